//! Spheres and the ray-sphere test.

use glam::Vec3A;

use super::{Aabb, Ray};

/// A sphere in its own space: the world's, or its Transform's object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// The centre, in the sphere's own space.
    pub center: Vec3A,
    /// Above 0.
    pub radius: f32,
}

impl Sphere {
    /// The box around the sphere, in its own space.
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.center - self.radius,
            max: self.center + self.radius,
        }
    }

    /// The outward unit normal at a point on the sphere.
    pub fn normal_at(&self, point: Vec3A) -> Vec3A {
        (point - self.center) / self.radius
    }
}

/// The nearest t in [t_min, t_max] where the ray meets the sphere; from inside that is the far
/// side. The direction need not be unit length.
#[inline(always)]
pub fn intersect_sphere(ray: &Ray, sphere: &Sphere, t_min: f32, t_max: f32) -> Option<f32> {
    let (near, far) = sphere_roots(ray, sphere)?;
    if near >= t_min && near <= t_max {
        Some(near)
    } else if far >= t_min && far <= t_max {
        Some(far)
    } else {
        None
    }
}

/// Both t where the ray's line meets the sphere, the nearer first; none where it passes by.
#[inline(always)]
pub fn sphere_roots(ray: &Ray, sphere: &Sphere) -> Option<(f32, f32)> {
    let oc = ray.origin - sphere.center;
    let d = ray.direction;
    let a = d.length_squared();
    let half_b = oc.dot(d);
    // The discriminant from the distance between the centre and the ray's closest point to it
    // loses far less precision than b² - ac when the sphere is small and far away.
    let closest = oc - (half_b / a) * d;
    let r2 = sphere.radius * sphere.radius;
    let discriminant = a * (r2 - closest.length_squared());
    if discriminant < 0.0 {
        return None;
    }
    let q = -(half_b + half_b.signum() * discriminant.sqrt());
    let c = oc.length_squared() - r2;
    let (t0, t1) = (c / q, q / a);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_at(z: f32) -> Sphere {
        Sphere {
            center: Vec3A::new(0.0, 0.0, z),
            radius: 1.0,
        }
    }

    #[test]
    fn hits_the_near_side_from_outside() {
        let ray = Ray::new(Vec3A::ZERO, Vec3A::Z);
        assert_eq!(
            intersect_sphere(&ray, &unit_at(10.0), 0.0, f32::INFINITY),
            Some(9.0)
        );
    }

    #[test]
    fn hits_the_far_side_from_inside() {
        let ray = Ray::new(Vec3A::ZERO, Vec3A::Z);
        assert_eq!(
            intersect_sphere(&ray, &unit_at(0.5), 0.0, f32::INFINITY),
            Some(1.5)
        );
        // With t_min = -inf (orthographic camera), the side behind the origin counts.
        assert_eq!(
            intersect_sphere(&ray, &unit_at(0.5), f32::NEG_INFINITY, f32::INFINITY),
            Some(-0.5)
        );
    }

    #[test]
    fn keeps_t_for_non_unit_directions() {
        let ray = Ray::new(Vec3A::ZERO, Vec3A::Z * 0.25);
        assert_eq!(
            intersect_sphere(&ray, &unit_at(10.0), 0.0, f32::INFINITY),
            Some(36.0)
        );
    }

    #[test]
    fn misses_beside_and_behind() {
        let beside = Ray::new(Vec3A::new(1.5, 0.0, 0.0), Vec3A::Z);
        assert_eq!(
            intersect_sphere(&beside, &unit_at(10.0), 0.0, f32::INFINITY),
            None
        );
        let behind = Ray::new(Vec3A::ZERO, -Vec3A::Z);
        assert_eq!(
            intersect_sphere(&behind, &unit_at(10.0), 0.0, f32::INFINITY),
            None
        );
    }

    #[test]
    fn a_ray_from_the_centre_meets_both_sides() {
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), Vec3A::X);
        assert_eq!(
            intersect_sphere(&ray, &unit_at(10.0), f32::NEG_INFINITY, f32::INFINITY),
            Some(-1.0)
        );
    }
}
