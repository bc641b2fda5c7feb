//! The camera's forms: the frame, the pixel's place on the screen, the ray through it.

use raycast::Vec3A;
use raycast::camera::{Camera, CameraSeam, film_to_screen};
use raycast::geometry::Ray;
use raycast::parse::description::Projection;

use crate::Form;

impl Form {
    /// The student's frame: direction, horizontal and up, each as their code makes it.
    fn frame(&self, camera: &Camera) -> (Vec3A, Vec3A, Vec3A) {
        let (direction, horizontal, up) = camera.frame();
        match *self {
            Form::UpOrthogonalNotNormalised(file_up) => (
                direction,
                horizontal,
                file_up - file_up.dot(direction) * direction,
            ),
            Form::HorizontalNotNormalised(file_up) => {
                let long = direction.cross(file_up);
                (direction, long, long.normalize().cross(direction))
            }
            Form::RawDirection(raw) => (raw, horizontal, up),
            Form::HorizontalReversed => (direction, -horizontal, up),
            _ => (direction, horizontal, up),
        }
    }
}

impl CameraSeam for Form {
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        match self {
            Form::LeftEdge => film_to_screen(i as f32, j as f32 + 0.5, width, height),
            Form::RowsFromTheTop => {
                film_to_screen(i as f32 + 0.5, (height - 1 - j) as f32 + 0.5, width, height)
            }
            Form::ColumnsOverWidthMinusOne => {
                let across = width as f32 / (width.max(2) - 1) as f32;
                film_to_screen(i as f32 * across, j as f32 + 0.5, width, height)
            }
            Form::CentredEdgeToEdge => {
                let centred = |k: u32, n: u32| match n {
                    1 => 0.0,
                    _ => 2.0 * k as f32 / (n - 1) as f32 - 1.0,
                };
                // Back from [-1, 1] to the film's pixels, 0 to the width.
                let film = |k: u32, n: u32| (centred(k, n) + 1.0) / 2.0 * n as f32;
                film_to_screen(film(i, width), film(j, height), width, height)
            }
            Form::FarCorner => film_to_screen(i as f32 + 1.0, j as f32 + 1.0, width, height),
            Form::LoopsSwapped => film_to_screen(j as f32 + 0.5, i as f32 + 0.5, width, height),
            Form::LoopsSwappedFromTheTop => {
                film_to_screen((height - 1 - j) as f32 + 0.5, i as f32 + 0.5, width, height)
            }
            Form::VFromTheTop | Form::UMirrored => {
                let (u, v) = film_to_screen(i as f32 + 0.5, j as f32 + 0.5, width, height);
                match self {
                    Form::VFromTheTop => (u, 1.0 - v),
                    _ => (1.0 - u, v),
                }
            }
            _ => film_to_screen(i as f32 + 0.5, j as f32 + 0.5, width, height),
        }
    }

    fn ray(&self, camera: &Camera, u: f32, v: f32) -> Ray {
        let (x, y) = (u - 0.5, v - 0.5);
        let (direction, horizontal, up) = self.frame(camera);
        match (camera.projection(), self) {
            (Projection::Perspective { angle }, Form::DoublePrecision) => {
                let (x, y) = (f64::from(u) - 0.5, f64::from(v) - 0.5);
                let screen = 2.0 * (f64::from(angle).to_radians() / 2.0).tan();
                let through = direction.as_dvec3()
                    + (x * screen) * horizontal.as_dvec3()
                    + (y * screen) * up.as_dvec3();
                Ray::new(camera.center(), Vec3A::from(through.normalize().as_vec3()))
            }
            (Projection::Perspective { angle }, Form::SphericalRays) => {
                let angle = angle.to_radians();
                let (ax, ay) = (x * angle, y * angle);
                let tilted = ay.cos() * direction + ay.sin() * up;
                let through = ax.cos() * tilted + ax.sin() * horizontal;
                Ray::new(camera.center(), through)
            }
            (Projection::Perspective { angle }, Form::TangentPerAxis) => {
                let angle = angle.to_radians();
                let through = direction + (x * angle).tan() * horizontal + (y * angle).tan() * up;
                Ray::new(camera.center(), through)
            }
            (Projection::Perspective { angle }, _) => {
                let screen = match self {
                    Form::ScreenAsWideAsTheAngle => angle.to_radians(),
                    _ => 2.0 * (angle.to_radians() / 2.0).tan(),
                };
                let through = direction + (x * screen) * horizontal + (y * screen) * up;
                Ray::new(camera.center(), through)
            }
            (Projection::Orthographic { size }, Form::OrthographicHalfSize) => Ray::new(
                camera.center() + (x * 2.0 * size) * horizontal + (y * 2.0 * size) * up,
                direction.normalize(),
            ),
            (Projection::Orthographic { size }, _) => Ray::new(
                camera.center() + (x * size) * horizontal + (y * size) * up,
                direction.normalize(),
            ),
        }
    }
}
