//! Rays, with the reciprocals the box tests need and the frame the triangle test needs.

use glam::{Mat3A, Vec3A};

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

    /// The watertight triangle test's frame, as one matrix: the axes permuted so that z is the
    /// direction's largest component, then sheared so that the direction becomes (0, 0, 1).
    /// Worked out only for rays that reach triangles, since most rays of a big scene never do.
    pub fn to_ray_space(&self) -> Mat3A {
        let direction = self.direction;
        let a = direction.abs();
        // Rows: x' = p[kx] - d[kx]/d[kz]·p[kz], y' likewise, z' = p[kz]/d[kz], with kz the
        // direction's largest axis. Entries of 0 and 1 keep those sums exact, so each vertex maps
        // the same way for every triangle sharing it.
        let (x, y, z) = (direction.x, direction.y, direction.z);
        let rows = if a.z >= a.x && a.z >= a.y {
            [
                Vec3A::new(1.0, 0.0, -x / z),
                Vec3A::new(0.0, 1.0, -y / z),
                Vec3A::new(0.0, 0.0, 1.0 / z),
            ]
        } else if a.y >= a.x {
            [
                Vec3A::new(0.0, -z / y, 1.0),
                Vec3A::new(1.0, -x / y, 0.0),
                Vec3A::new(0.0, 1.0 / y, 0.0),
            ]
        } else {
            [
                Vec3A::new(-y / x, 1.0, 0.0),
                Vec3A::new(-z / x, 0.0, 1.0),
                Vec3A::new(1.0 / x, 0.0, 0.0),
            ]
        };
        Mat3A::from_cols(rows[0], rows[1], rows[2]).transpose()
    }

    /// The point at parameter `t`: origin + t·direction.
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + t * self.direction
    }
}
