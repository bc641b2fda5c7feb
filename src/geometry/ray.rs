use glam::Vec3A;

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
    /// The watertight triangle test's frame: the axes permuted so that z is the direction's
    /// largest component, and the shear that maps the direction onto that z axis.
    pub(crate) axes: [usize; 3],
    pub(crate) shear: Vec3A,
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
        let shear = Vec3A::new(-direction[kx] / dz, -direction[ky] / dz, 1.0 / dz);
        Ray {
            origin,
            direction,
            inv_direction,
            axes: [kx, ky, kz],
            shear,
        }
    }

    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + t * self.direction
    }
}
