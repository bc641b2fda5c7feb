use glam::{Mat3A, Vec3A};

/// A ray, with what every box and triangle test against it would otherwise recompute.
///
/// The direction need not be unit length: rays carried into a Transform's object space keep the
/// world's parameter t that way (SCENE_FORMAT.md §8).
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    pub origin: Vec3A,
    pub direction: Vec3A,
    /// 1/direction, kept finite (a zero component gives ±f32::MAX) so slab tests never make NaN.
    pub inv_direction: Vec3A,
    /// The watertight triangle test's frame, as one matrix: the axes permuted so that z is the
    /// direction's largest component, then sheared so that the direction becomes (0, 0, 1).
    pub(crate) to_ray_space: Mat3A,
}

impl Ray {
    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let inv = |d: f32| {
            let inv = 1.0 / d;
            if inv.is_finite() {
                inv
            } else {
                f32::MAX.copysign(d)
            }
        };
        let inv_direction = Vec3A::new(inv(direction.x), inv(direction.y), inv(direction.z));
        let kz = direction.abs().max_position();
        let kx = (kz + 1) % 3;
        let ky = (kx + 1) % 3;
        let dz = direction[kz];
        let unit = |axis: usize| Vec3A::AXES[axis];
        // Rows: x' = p[kx] - d[kx]/d[kz]·p[kz], y' likewise, z' = p[kz]/d[kz]. Entries of 0 and 1
        // keep those sums exact, so each vertex maps the same way for every triangle sharing it.
        let rows = [
            unit(kx) - (direction[kx] / dz) * unit(kz),
            unit(ky) - (direction[ky] / dz) * unit(kz),
            unit(kz) / dz,
        ];
        Ray {
            origin,
            direction,
            inv_direction,
            to_ray_space: Mat3A::from_cols(rows[0], rows[1], rows[2]).transpose(),
        }
    }

    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + t * self.direction
    }
}
