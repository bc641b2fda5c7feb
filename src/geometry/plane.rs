//! Infinite planes and the ray-plane test.

use glam::Vec3A;

use super::Ray;

/// The points P with P · normal = offset; `normal` is unit length and is the front side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit length, toward the front side.
    pub normal: Vec3A,
    /// The plane's signed distance from the origin along `normal`.
    pub offset: f32,
}

/// The t in [t_min, t_max] where the ray meets the plane, from either side; `None` for a ray
/// parallel to it. The direction need not be unit length.
#[inline(always)]
pub fn intersect_plane(ray: &Ray, plane: &Plane, t_min: f32, t_max: f32) -> Option<f32> {
    let t = (plane.offset - plane.normal.dot(ray.origin)) / plane.normal.dot(ray.direction);
    // A ray parallel to the plane gives ±inf or NaN; -inf would pass an orthographic t_min.
    (t >= t_min && t <= t_max && t.is_finite()).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meets_the_floor_from_above_and_below() {
        let floor = Plane {
            normal: Vec3A::Y,
            offset: -2.0,
        };
        let down = Ray::new(Vec3A::new(0.0, 3.0, 0.0), Vec3A::new(0.0, -0.5, 0.0));
        assert_eq!(
            intersect_plane(&down, &floor, 0.0, f32::INFINITY),
            Some(10.0)
        );
        let up = Ray::new(Vec3A::new(0.0, -4.0, 0.0), Vec3A::Y);
        assert_eq!(intersect_plane(&up, &floor, 0.0, f32::INFINITY), Some(2.0));
        let parallel = Ray::new(Vec3A::ZERO, Vec3A::X);
        assert_eq!(
            intersect_plane(&parallel, &floor, f32::NEG_INFINITY, f32::INFINITY),
            None
        );
    }
}
