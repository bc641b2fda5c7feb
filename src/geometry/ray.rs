//! Rays, with the reciprocals the box tests need and the frame the triangle test needs.

use glam::Vec3A;

/// A ray, with what every box test against it would otherwise recompute.
///
/// The direction need not be unit length: rays carried into a Transform's object space keep the
/// world's parameter t that way (SCENE_FORMAT.md §8).
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// Where the ray starts: the point at t = 0.
    pub origin: Vec3A,
    /// The way the ray goes, of any length: t counts in lengths of it.
    pub direction: Vec3A,
    /// 1/direction, kept finite (a zero component gives ±f32::MAX) so slab tests never make NaN.
    pub inv_direction: Vec3A,
}

impl Ray {
    /// A ray from `origin` along `direction`, with its reciprocal worked out once.
    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let inv = Vec3A::ONE / direction;
        let inv_direction = Vec3A::select(
            inv.is_finite_mask(),
            inv,
            Vec3A::splat(f32::MAX).copysign(direction),
        );
        Ray {
            origin,
            direction,
            inv_direction,
        }
    }

    /// The watertight triangle test's frame: the axes permuted so that z is the direction's
    /// largest component, then sheared so that the direction becomes (0, 0, 1). Worked out only
    /// for rays that reach triangles, since most rays of a big scene never do.
    #[inline]
    pub fn to_ray_space(&self) -> RayFrame {
        let direction = self.direction;
        let a = direction.abs();
        let (x, y, z) = (direction.x, direction.y, direction.z);
        // x and y follow z in cyclic order, so that the frame keeps its handedness.
        if a.z >= a.x && a.z >= a.y {
            RayFrame {
                axes: [0, 1, 2],
                shear: [-x / z, -y / z, 1.0 / z],
            }
        } else if a.y >= a.x {
            RayFrame {
                axes: [2, 0, 1],
                shear: [-z / y, -x / y, 1.0 / y],
            }
        } else {
            RayFrame {
                axes: [1, 2, 0],
                shear: [-y / x, -z / x, 1.0 / x],
            }
        }
    }

    /// The point at parameter `t`: origin + t·direction.
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + t * self.direction
    }
}

/// A ray's frame for the watertight triangle test ([`Ray::to_ray_space`]): a point p, taken
/// relative to the ray's origin, goes to `(p[kx] + sx·p[kz], p[ky] + sy·p[kz], sz·p[kz])`,
/// where the ray runs along +z from the origin.
///
/// A shear with two products and two sums a vertex, where a full matrix would take nine and
/// six; the entries a matrix would hold are 0 and 1, whose products and sums are exact, so the
/// two give the same values. Each vertex maps the same way for every triangle sharing it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayFrame {
    /// `[kx, ky, kz]`: the axes that become x, y and z.
    pub axes: [usize; 3],
    /// `[sx, sy, sz]`.
    pub shear: [f32; 3],
}

impl RayFrame {
    /// `relative` (a point less the ray's origin) in the ray's frame.
    #[inline(always)]
    pub fn apply(&self, relative: Vec3A) -> [f32; 3] {
        let [kx, ky, kz] = self.axes;
        let [sx, sy, sz] = self.shear;
        let p = relative.to_array();
        [p[kx] + sx * p[kz], p[ky] + sy * p[kz], sz * p[kz]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat3A;
    use proptest::prelude::*;

    /// The frame as the whole matrix: rows of the permutation's 0s and 1s beside the shear.
    fn as_matrix(frame: &RayFrame) -> Mat3A {
        let [kx, ky, kz] = frame.axes;
        let [sx, sy, sz] = frame.shear;
        let row = |k: usize, s: f32, one: bool| {
            let mut r = [0.0; 3];
            if one {
                r[k] = 1.0;
            }
            r[kz] = s;
            Vec3A::from(r)
        };
        Mat3A::from_cols(row(kx, sx, true), row(ky, sy, true), row(kz, sz, false)).transpose()
    }

    fn coordinate() -> impl Strategy<Value = f32> {
        prop_oneof![-1e3f32..1e3, Just(0.0), Just(-0.0), Just(1.0)]
    }

    proptest! {
        /// Two products and two sums a vertex give what the full matrix gives (equal as
        /// numbers: only the sign of a zero may differ), and the ray itself runs along +z
        /// (to rounding: the shear's quotients are rounded).
        #[test]
        fn the_shear_maps_as_the_matrix_does(
            d in prop::array::uniform3(coordinate()),
            p in prop::array::uniform3(coordinate()),
        ) {
            let direction = Vec3A::from(d);
            prop_assume!(direction.abs().max_element() > 0.0);
            let frame = Ray::new(Vec3A::ZERO, direction).to_ray_space();
            let sheared = frame.apply(Vec3A::from(p));
            let full = as_matrix(&frame) * Vec3A::from(p);
            prop_assert_eq!(Vec3A::from(sheared), full);
            let along = frame.apply(direction);
            let scale = direction.abs().max_element();
            prop_assert!(along[0].abs() <= 1e-6 * scale && along[1].abs() <= 1e-6 * scale);
            prop_assert!((along[2] - 1.0).abs() <= 1e-6);
        }
    }

    #[test]
    fn the_frame_keeps_its_handedness() {
        for direction in [Vec3A::X, Vec3A::Y, Vec3A::Z, -Vec3A::Y] {
            let frame = Ray::new(Vec3A::ZERO, direction).to_ray_space();
            // A cyclic order of the axes: an even permutation, so no mirror.
            let [kx, ky, kz] = frame.axes;
            assert_eq!((ky, kz), ((kx + 1) % 3, (kx + 2) % 3), "{direction}");
        }
    }
}
