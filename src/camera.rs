//! Cameras: where the ray through each point of the image starts and where it goes.

use glam::Vec3A;

use crate::geometry::Ray;
use crate::parse::description::{CameraSpec, Projection};

/// A camera ready to cast rays: its unit frame, worked out once, and its projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    center: Vec3A,
    direction: Vec3A,
    /// Screen x, to the right in the image.
    horizontal: Vec3A,
    /// Screen y, up in the image: perpendicular to both others even if the file's up is not.
    up: Vec3A,
    projection: Projection,
    /// The perspective camera's screen width at distance 1: 2·tan(angle/2).
    screen: f32,
}

impl Camera {
    /// The course's frame: `direction` normalised, horizontal = normalize(direction × up), and
    /// up' = horizontal × direction (the file's up need be neither unit nor perpendicular).
    pub fn new(spec: &CameraSpec) -> Camera {
        let direction = Vec3A::from(spec.direction).normalize();
        let horizontal = direction.cross(spec.up.into()).normalize();
        let up = horizontal.cross(direction);
        Camera {
            center: spec.center.into(),
            direction,
            horizontal,
            up,
            projection: spec.projection,
            screen: screen_width(spec.projection),
        }
    }

    /// A camera of a frame given whole, unit or not and perpendicular or not: how a student's
    /// code may have made it (check's faults build cameras this way).
    pub fn from_frame(
        center: Vec3A,
        direction: Vec3A,
        horizontal: Vec3A,
        up: Vec3A,
        projection: Projection,
    ) -> Camera {
        Camera {
            center,
            direction,
            horizontal,
            up,
            projection,
            screen: screen_width(projection),
        }
    }

    /// The unit frame: direction, horizontal (screen x) and up (screen y).
    pub fn frame(&self) -> (Vec3A, Vec3A, Vec3A) {
        (self.direction, self.horizontal, self.up)
    }

    /// Where the rays start: the orthographic camera's centre, the perspective camera's eye.
    pub fn center(&self) -> Vec3A {
        self.center
    }

    /// Orthographic or perspective, with the size or angle of the view.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// The ray through (u, v) of the camera's square view, both in [0, 1], v upward. Its
    /// direction is not always unit length: distances along it are `t * direction.length()`.
    #[inline]
    pub fn ray(&self, u: f32, v: f32) -> Ray {
        let (x, y) = (u - 0.5, v - 0.5);
        match self.projection {
            Projection::Orthographic { size } => Ray::new(
                self.center + (x * size) * self.horizontal + (y * size) * self.up,
                self.direction,
            ),
            Projection::Perspective { .. } => {
                let screen = self.screen;
                // Not normalised: t then counts in lengths of this vector, which orders hits just
                // the same, and the depth picture multiplies it back into a distance. Normalising
                // every ray chained a square root and a division into the reciprocal that the box
                // tests need: a third of the cost of a ray that hits nothing.
                let direction =
                    self.direction + (x * screen) * self.horizontal + (y * screen) * self.up;
                Ray::new(self.center, direction)
            }
        }
    }

    /// The orthographic camera sees what lies behind its centre too; the perspective camera
    /// sees only what is in front of its eye.
    pub fn t_min(&self) -> f32 {
        match self.projection {
            Projection::Orthographic { .. } => f32::NEG_INFINITY,
            Projection::Perspective { .. } => 0.0,
        }
    }
}

/// How camera rays are made: the seam where a render may make them as a student's tracer would
/// (check's fault library). The defaults are the course's; a render picks its variant once, and
/// the course's own ([`crate::render::Exact`]) compiles to the plain calls.
pub trait CameraSeam: Copy + Send + Sync {
    /// The point of the camera's square view that pixel (i, j) (from the lower left) samples.
    #[inline(always)]
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        pixel_to_screen(i, j, width, height)
    }

    /// The point of the view at (x, y) of the image, in pixels from its lower-left corner (a
    /// sample's position).
    #[inline(always)]
    fn film_to_screen(&self, x: f32, y: f32, width: u32, height: u32) -> (f32, f32) {
        film_to_screen(x, y, width, height)
    }

    /// The ray through (u, v) of the view.
    #[inline(always)]
    fn ray(&self, camera: &Camera, u: f32, v: f32) -> Ray {
        camera.ray(u, v)
    }
}

impl CameraSeam for crate::variant::Exact {}

/// The perspective camera's screen width at distance 1, 2·tan(angle/2); 0 for orthographic.
fn screen_width(projection: Projection) -> f32 {
    match projection {
        // Degrees to radians in f64, as the course's scenes were always converted.
        Projection::Perspective { angle } => {
            2.0 * (0.5 * f64::from(angle).to_radians() as f32).tan()
        }
        Projection::Orthographic { .. } => 0.0,
    }
}

/// The point of the camera's square view that pixel (i, j) samples: its centre, with i from the
/// left and j from the bottom. The square spans the image's longer side; the shorter is cropped.
#[inline]
pub fn pixel_to_screen(i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
    film_to_screen(i as f32 + 0.5, j as f32 + 0.5, width, height)
}

/// The point of the camera's square view at (x, y) of the image, in pixels from its lower-left
/// corner (a pixel's centre is at i + ½, j + ½).
#[inline]
pub fn film_to_screen(x: f32, y: f32, width: u32, height: u32) -> (f32, f32) {
    let side = width.max(height) as f32;
    let u = (x - width as f32 / 2.0) / side + 0.5;
    let v = (y - height as f32 / 2.0) / side + 0.5;
    (u, v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn spec(projection: Projection) -> CameraSpec {
        CameraSpec {
            center: Vec3::new(0.0, 0.0, 10.0),
            direction: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::new(0.0, 2.0, 0.5),
            projection,
        }
    }

    fn close(a: Vec3A, b: Vec3A) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_the_size() {
        let camera = Camera::new(&spec(Projection::Orthographic { size: 4.0 }));
        let centre = camera.ray(0.5, 0.5);
        assert!(close(centre.origin, Vec3A::new(0.0, 0.0, 10.0)));
        assert!(close(centre.direction, -Vec3A::Z));
        // The file's up is not perpendicular: only its component across the view counts.
        let top_right = camera.ray(1.0, 1.0);
        assert!(close(top_right.origin, Vec3A::new(2.0, 2.0, 10.0)));
        assert!(close(top_right.direction, -Vec3A::Z));
        assert_eq!(camera.t_min(), f32::NEG_INFINITY);
    }

    #[test]
    fn perspective_angle_is_the_full_field_of_view() {
        let camera = Camera::new(&spec(Projection::Perspective { angle: 90.0 }));
        assert!(close(camera.ray(0.5, 0.5).direction, -Vec3A::Z));
        // At the left edge the ray is 45° off the axis: tan(45°) = 1.
        let left = camera.ray(0.0, 0.5);
        assert!(close(left.direction, Vec3A::new(-1.0, 0.0, -1.0)));
        assert!(close(left.origin, Vec3A::new(0.0, 0.0, 10.0)));
        let bottom = camera.ray(0.5, 0.0);
        assert!(close(bottom.direction, Vec3A::new(0.0, -1.0, -1.0)));
        assert_eq!(camera.t_min(), 0.0);
    }

    #[test]
    fn pixels_are_sampled_at_their_centres_from_the_bottom_left() {
        let check = |(i, j, w, h): (u32, u32, u32, u32), (u, v): (f32, f32)| {
            let got = pixel_to_screen(i, j, w, h);
            assert!(
                (got.0 - u).abs() < 1e-6 && (got.1 - v).abs() < 1e-6,
                "{got:?} vs {u}, {v}"
            );
        };
        check((0, 0, 200, 200), (0.0025, 0.0025));
        check((199, 199, 200, 200), (0.9975, 0.9975));
        // A wide image: the square spans the width, top and bottom are cropped.
        check((0, 0, 4, 2), (0.125, 0.375));
        check((3, 1, 4, 2), (0.875, 0.625));
    }
}
