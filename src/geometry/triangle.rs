//! The watertight ray-triangle test, and the triangle's front-side normal.

use glam::{Vec3, Vec3A};

use super::{Ray, RayFrame};

/// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013, as in pbrt-v4).
///
/// The vertices are moved into a frame where the ray runs along +z from the origin; the 2-D edge
/// functions there are computed the same way for both triangles that share an edge, so a ray
/// through that edge or a shared vertex never slips between them. Either side of the triangle
/// is hit; a zero-area triangle never is. Returns t with t_min <= t <= t_max (a hit at exactly
/// t_max is a tie, which the caller settles).
#[inline(always)]
pub fn intersect_triangle(ray: &Ray, v: &[Vec3; 3], t_min: f32, t_max: f32) -> Option<f32> {
    intersect_triangle_in(&ray.to_ray_space(), ray, v, t_min, t_max)
}

/// [`intersect_triangle`] with the ray's frame ([`Ray::to_ray_space`]) already worked out.
#[inline(always)]
pub(crate) fn intersect_triangle_in(
    frame: &RayFrame,
    ray: &Ray,
    v: &[Vec3; 3],
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let [p0x, p0y, p0z] = frame.apply(Vec3A::from(v[0]) - ray.origin);
    let [p1x, p1y, p1z] = frame.apply(Vec3A::from(v[1]) - ray.origin);
    let [p2x, p2y, p2z] = frame.apply(Vec3A::from(v[2]) - ray.origin);

    let mut e0 = p1x * p2y - p1y * p2x;
    let mut e1 = p2x * p0y - p2y * p0x;
    let mut e2 = p0x * p1y - p0y * p1x;
    // On an edge in f32, the sign is decided again in f64 so that neighbours agree.
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let d = |a: f32, b: f32, c: f32, e: f32| (a as f64 * b as f64 - c as f64 * e as f64) as f32;
        e0 = d(p1x, p2y, p1y, p2x);
        e1 = d(p2x, p0y, p2y, p0x);
        e2 = d(p0x, p1y, p0y, p1x);
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    let t = (e0 * p0z + e1 * p1z + e2 * p2z) / det;
    (t >= t_min && t <= t_max).then_some(t)
}

/// The side counter-clockwise vertices are seen from: (v1 - v0) × (v2 - v0), not normalised.
#[inline]
pub fn triangle_normal(v: &[Vec3; 3]) -> Vec3A {
    let (a, b, c) = (Vec3A::from(v[0]), Vec3A::from(v[1]), Vec3A::from(v[2]));
    (b - a).cross(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray::new(Vec3A::from(o), Vec3A::from(d))
    }

    #[test]
    fn hits_from_both_sides_at_the_right_distance() {
        let front = ray([0.25, 0.25, 5.0], [0.0, 0.0, -1.0]);
        assert_eq!(
            intersect_triangle(&front, &TRI, 0.0, f32::INFINITY),
            Some(5.0)
        );
        let back = ray([0.25, 0.25, -2.0], [0.0, 0.0, 2.0]);
        assert_eq!(
            intersect_triangle(&back, &TRI, 0.0, f32::INFINITY),
            Some(1.0)
        );
    }

    #[test]
    fn misses_outside_and_outside_the_t_range() {
        let outside = ray([0.75, 0.75, 5.0], [0.0, 0.0, -1.0]);
        assert_eq!(intersect_triangle(&outside, &TRI, 0.0, f32::INFINITY), None);
        let inside = ray([0.25, 0.25, 5.0], [0.0, 0.0, -1.0]);
        assert_eq!(intersect_triangle(&inside, &TRI, 0.0, 4.0), None);
        assert_eq!(intersect_triangle(&inside, &TRI, 5.5, 9.0), None);
        // Behind the origin counts only when t_min allows it, as for the orthographic camera.
        let away = ray([0.25, 0.25, 5.0], [0.0, 0.0, 1.0]);
        assert_eq!(intersect_triangle(&away, &TRI, 0.0, f32::INFINITY), None);
        assert_eq!(
            intersect_triangle(&away, &TRI, f32::NEG_INFINITY, f32::INFINITY),
            Some(-5.0)
        );
    }

    #[test]
    fn zero_area_triangles_are_never_hit() {
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let r = ray([1.0, 0.0, 1.0], [0.0, 0.0, -1.0]);
        assert_eq!(
            intersect_triangle(&r, &flat, f32::NEG_INFINITY, f32::INFINITY),
            None
        );
    }

    #[test]
    fn a_shared_edge_is_hit_by_exactly_one_side_or_both() {
        // Two triangles of a square split along its diagonal; rays along the diagonal.
        let a = [Vec3::ZERO, Vec3::X, Vec3::ONE.with_z(0.0)];
        let b = [Vec3::ZERO, Vec3::ONE.with_z(0.0), Vec3::Y];
        for i in 1..100 {
            let x = i as f32 / 100.0;
            let r = ray([x, x, 1.0], [0.0, 0.0, -1.0]);
            let hits = [&a, &b]
                .iter()
                .filter(|t| intersect_triangle(&r, t, 0.0, f32::INFINITY).is_some())
                .count();
            assert!(hits >= 1, "ray at {x} slipped between the triangles");
        }
    }

    #[test]
    fn non_unit_directions_keep_the_ray_parameter() {
        let r = ray([0.25, 0.25, 5.0], [0.0, 0.0, -0.5]);
        assert_eq!(intersect_triangle(&r, &TRI, 0.0, f32::INFINITY), Some(10.0));
    }

    #[test]
    fn normal_faces_the_counter_clockwise_side() {
        assert_eq!(triangle_normal(&TRI), Vec3A::Z);
    }
}
