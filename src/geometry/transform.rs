//! Transforms: an object's placement in the world, and the way rays and normals cross it.

use glam::{Affine3A, DMat4, Mat3A, Vec3A};

use super::Ray;

/// An object placed in the world by a Transform: rays go in through the inverse matrix, normals
/// come out through its inverse transpose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// The Transform's matrix, nesting included: object points to world points.
    pub object_to_world: Affine3A,
    /// Its inverse, which carries rays into object space.
    pub world_to_object: Affine3A,
    /// The inverse's linear part transposed, which carries normals out to the world (their
    /// length is not kept).
    pub normal_to_world: Mat3A,
}

impl Transform {
    /// `matrix` maps object points to world points (column vectors); it must be invertible.
    /// Inverted in f64, so that the f32 inverse is as exact as f32 allows.
    pub fn new(matrix: DMat4) -> Self {
        let inverse = matrix.inverse();
        let world_to_object = Affine3A::from_mat4(inverse.as_mat4());
        Transform {
            object_to_world: Affine3A::from_mat4(matrix.as_mat4()),
            world_to_object,
            normal_to_world: world_to_object.matrix3.transpose(),
        }
    }

    /// The ray in object space. Its direction is not renormalised, so t means the same point in
    /// both spaces and no rescaling is needed (SCENE_FORMAT.md §8).
    #[inline(always)]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.world_to_object.transform_point3a(ray.origin),
            self.world_to_object.transform_vector3a(ray.direction),
        )
    }

    /// A world-space unit normal from an object-space normal of any length; zero if the normal
    /// has no direction. Scaled to a largest component of 1 first, so that tiny or huge normals
    /// (a tiny mesh under a large scale) neither underflow nor overflow on the way.
    #[inline]
    pub fn normal_to_world(&self, normal: Vec3A) -> Vec3A {
        unit_normal(self.normal_to_world * scaled_to_one(normal))
    }
}

/// `v` divided by its largest component, so that squaring it can neither underflow nor overflow.
#[inline]
fn scaled_to_one(v: Vec3A) -> Vec3A {
    v / v.abs().max_element()
}

/// A normal of any length made unit length; zero if it has no direction at all.
#[inline]
pub fn unit_normal(v: Vec3A) -> Vec3A {
    scaled_to_one(v).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Sphere, intersect_sphere};
    use glam::DVec3;

    #[test]
    fn t_stays_in_world_units_through_a_scale() {
        // A unit sphere scaled by 5 and moved to z = 20: a ray from the origin along +z (unit
        // direction) enters at world z = 15, so t = 15, though the object-space ray is shorter.
        let m = DMat4::from_translation(DVec3::new(0.0, 0.0, 20.0))
            * DMat4::from_scale(DVec3::splat(5.0));
        let transform = Transform::new(m);
        let world = Ray::new(Vec3A::ZERO, Vec3A::Z);
        let object = transform.ray_to_object(&world);
        assert_eq!(object.direction, Vec3A::new(0.0, 0.0, 0.2));
        let unit = Sphere {
            center: Vec3A::ZERO,
            radius: 1.0,
        };
        let t = intersect_sphere(&object, &unit, 0.0, f32::INFINITY).unwrap();
        assert!((t - 15.0).abs() < 1e-5, "t = {t}");
    }

    #[test]
    fn normals_go_through_the_inverse_transpose() {
        // Squash y by 0.2: the sphere's 45° normal (1,1,0)/√2 becomes (0.2, 1, 0) normalised
        // in the world, steeper than the plain matrix would make it.
        let transform = Transform::new(DMat4::from_scale(DVec3::new(1.0, 0.2, 1.0)));
        let n = transform.normal_to_world(Vec3A::new(1.0, 1.0, 0.0));
        let expected = Vec3A::new(0.2, 1.0, 0.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n} vs {expected}");
    }

    #[test]
    fn tiny_and_huge_normals_survive_the_trip() {
        // A mesh of 1e-9-sized triangles scaled up by 1e9: its raw normals are ~1e-18 long.
        let up = Transform::new(DMat4::from_scale(DVec3::splat(1e9)));
        assert_eq!(up.normal_to_world(Vec3A::new(0.0, 0.0, 1e-18)), Vec3A::Z);
        let down = Transform::new(DMat4::from_scale(DVec3::splat(1e-9)));
        assert_eq!(down.normal_to_world(Vec3A::new(0.0, 3e30, 0.0)), Vec3A::Y);
        assert_eq!(down.normal_to_world(Vec3A::ZERO), Vec3A::ZERO);
    }
}
