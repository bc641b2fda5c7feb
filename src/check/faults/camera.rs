//! Faults of the camera: where each pixel's ray goes through, and the ray itself.

use glam::Vec3A;

use super::{Candidate, Fault, LineScene, Planted};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::parse::description::Projection;

/// How a student's camera makes its rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraFault {
    /// Rays through a corner of each pixel: (0, 0) the lower left, (1, 1) the upper right.
    Corner(u8, u8),
    /// Pixels spread over width - 1 and height - 1: the first and last pixel's rays through the
    /// view's edges.
    SpanMinusOne,
    /// Rows counted from the other end.
    FlipVertical,
    /// Columns counted from the other end.
    FlipHorizontal,
    /// A square picture's x and y exchanged, in the way of this [`Exchange`].
    Transposed(Exchange),
    /// Another camera: a wrong field of view, or a frame made another way.
    Other(Camera),
    /// Rays at equal angles across the field of view rather than through an image plane.
    EqualAngles(Camera, f32),
    /// The camera a fit found for a student's pictures: the scene's camera, the full angle of
    /// its view in radians (0 for an orthographic one), and how pixels map onto rays.
    Mapped(Camera, f32, Mapping),
    /// The scene's camera with every ray, of a pixel's centre or of a sample, through the point
    /// of the view this far from the course's (in shares of the view's width and height): not
    /// a fault, an allowed answer's render (a ray's last digits).
    Nudged(Camera, [f32; 2]),
}

/// How a student's camera maps pixels onto rays, as a fit finds it: each pixel's film point
/// moved by an offset, the view scaled per axis and sheared about its centre (an axis of
/// another length, or leaning), and the ray made through a plane, by two turns, or by a tangent
/// per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapping {
    /// How the ray is made from a point of the view.
    pub form: RayForm,
    /// Added to each pixel's centre, in pixels (right, up).
    pub offset: [f32; 2],
    /// The view's width and height, as shares of the course's.
    pub scale: [f32; 2],
    /// How far the screen's x leans per unit of its y.
    pub shear: f32,
}

impl Mapping {
    /// The course's mapping, in `form`.
    pub fn course(form: RayForm) -> Mapping {
        Mapping {
            form,
            offset: [0.0; 2],
            scale: [1.0; 2],
            shear: 0.0,
        }
    }
}

/// How a perspective ray is made from a point (x, y) of the view, each in [-½, ½].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayForm {
    /// Through the point of an image plane: the course's.
    Plane,
    /// Turned by x·angle about the up axis, then by y·angle about the horizontal one.
    TurnedAngles,
    /// Turned by y·angle about the horizontal axis, then by x·angle about the up one.
    TurnedOtherOrder,
    /// direction + tan(x·angle)·horizontal + tan(y·angle)·up.
    TangentPerAxis,
}

/// How a square picture's x and y are exchanged: which of the course's pixels pixel (i, j)
/// shows, in a picture of side n.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exchange {
    /// (j, i): mirrored across the diagonal from the lower left.
    Transpose,
    /// (n − 1 − j, n − 1 − i): mirrored across the other diagonal.
    OtherDiagonal,
    /// (j, n − 1 − i): turned a quarter turn one way.
    QuarterTurn,
    /// (n − 1 − j, i): turned a quarter turn the other way.
    OtherQuarterTurn,
}

impl Exchange {
    /// Which of the course's pixels pixel (i, j) of a picture of side `n` shows.
    fn source(self, i: u32, j: u32, n: u32) -> (u32, u32) {
        match self {
            Exchange::Transpose => (j, i),
            Exchange::OtherDiagonal => (n - 1 - j, n - 1 - i),
            Exchange::QuarterTurn => (j, n - 1 - i),
            Exchange::OtherQuarterTurn => (n - 1 - j, i),
        }
    }
}

impl CameraFault {
    /// The pixel whose point is used for pixel (i, j).
    pub(super) fn pixel(&self, i: u32, j: u32, width: u32, height: u32) -> (u32, u32) {
        match *self {
            CameraFault::FlipVertical => (i, height - 1 - j),
            CameraFault::FlipHorizontal => (width - 1 - i, j),
            CameraFault::Transposed(exchange) if width == height => exchange.source(i, j, width),
            _ => (i, j),
        }
    }

    /// The point of the image pixel (i, j) samples, where it is not its centre.
    pub(super) fn film_point(&self, i: u32, j: u32, width: u32, height: u32) -> Option<(f32, f32)> {
        match *self {
            CameraFault::Corner(x, y) => Some((i as f32 + f32::from(x), j as f32 + f32::from(y))),
            CameraFault::SpanMinusOne => {
                let spread = |k: u32, n: u32| {
                    if n > 1 {
                        k as f32 * n as f32 / (n - 1) as f32
                    } else {
                        0.5
                    }
                };
                Some((spread(i, width), spread(j, height)))
            }
            CameraFault::Mapped(_, _, mapping) => Some((
                i as f32 + 0.5 + mapping.offset[0],
                j as f32 + 0.5 + mapping.offset[1],
            )),
            _ => None,
        }
    }

    /// The ray through (u, v) of the view, where it is not the scene camera's.
    pub(super) fn ray(&self, u: f32, v: f32) -> Option<Ray> {
        match *self {
            CameraFault::Other(camera) => Some(camera.ray(u, v)),
            CameraFault::Nudged(camera, [du, dv]) => Some(camera.ray(u + du, v + dv)),
            CameraFault::EqualAngles(camera, angle) => {
                let (direction, horizontal, up) = camera.frame();
                let (a, b) = ((u - 0.5) * angle, (v - 0.5) * angle);
                // Turned by a about the up axis, then by b about the horizontal one.
                let turned = direction * (a.cos() * b.cos())
                    + horizontal * (a.sin() * b.cos())
                    + up * b.sin();
                Some(Ray::new(camera.center(), turned))
            }
            CameraFault::Mapped(camera, angle, mapping) => {
                let (x, y) = (u - 0.5, v - 0.5);
                let (x, y) = (
                    mapping.scale[0] * x + mapping.shear * y,
                    mapping.scale[1] * y,
                );
                let (direction, horizontal, up) = camera.frame();
                Some(match mapping.form {
                    RayForm::Plane => camera.ray(0.5 + x, 0.5 + y),
                    RayForm::TurnedAngles => {
                        let (a, b) = (x * angle, y * angle);
                        let turned = direction * (a.cos() * b.cos())
                            + horizontal * (a.sin() * b.cos())
                            + up * b.sin();
                        Ray::new(camera.center(), turned)
                    }
                    RayForm::TurnedOtherOrder => {
                        let (a, b) = (x * angle, y * angle);
                        let turned = direction * (a.cos() * b.cos())
                            + horizontal * a.sin()
                            + up * (a.cos() * b.sin());
                        Ray::new(camera.center(), turned)
                    }
                    RayForm::TangentPerAxis => Ray::new(
                        camera.center(),
                        direction + horizontal * (x * angle).tan() + up * (y * angle).tan(),
                    ),
                })
            }
            _ => None,
        }
    }
}

/// The perspective camera's angle, in degrees, where the line's camera is one.
fn perspective_angle(line: &LineScene) -> Option<f32> {
    match line.description.camera.projection {
        Projection::Perspective { angle } => Some(angle),
        Projection::Orthographic { .. } => None,
    }
}

/// The scene's camera with its field of view `degrees` wide.
fn with_angle(line: &LineScene, degrees: f32) -> Camera {
    let camera = line.scene.camera;
    let (direction, horizontal, up) = camera.frame();
    Camera::from_frame(
        camera.center(),
        direction,
        horizontal,
        up,
        Projection::Perspective { angle: degrees },
    )
}

fn corners(_: &LineScene) -> Vec<Candidate> {
    [(0, 0), (1, 0), (0, 1), (1, 1)]
        .into_iter()
        .map(|(x, y)| {
            // The corner as a student names it: 0 lower left, 1 lower right, 2 upper left,
            // 3 upper right.
            let corner = f64::from(x + 2 * y);
            Candidate::with(Planted::Camera(CameraFault::Corner(x, y)), "corner", corner)
        })
        .collect()
}

pub(super) const PIXEL_CORNER: Fault = Fault {
    name: "pixel_corner",
    assignment: 1,
    sentence: "My rays go through a corner of each pixel, not its centre.",
    look_for: "Where a pixel's screen coordinates are computed: a pixel's ray goes through \
               (i + 0.5) / width and (j + 0.5) / height, not i / width and j / height.",
    candidates: corners,
};

pub(super) const PIXEL_SPAN_MINUS_ONE: Fault = Fault {
    name: "pixel_span_minus_one",
    assignment: 1,
    sentence: "I spread my pixels over width - 1, so the first and last rays go through the \
               edges of the view.",
    look_for: "The mapping from pixel to screen: i / (width - 1) puts the last pixel on the \
               view's edge; use (i + 0.5) / width.",
    candidates: |_| vec![Candidate::plain(Planted::Camera(CameraFault::SpanMinusOne))],
};

pub(super) const FLIP_VERTICAL: Fault = Fault {
    name: "flip_vertical",
    assignment: 1,
    sentence: "My picture is upside down: I count rows from the top where the camera counts \
               from the bottom.",
    look_for: "Where rows are written: the image's row 0 is its top, the screen's y = 0 its \
               bottom, so row j is screen y = height - 1 - j (or the up vector is reversed).",
    candidates: |_| vec![Candidate::plain(Planted::Camera(CameraFault::FlipVertical))],
};

pub(super) const FLIP_HORIZONTAL: Fault = Fault {
    name: "flip_horizontal",
    assignment: 1,
    sentence: "My picture is mirrored left to right.",
    look_for: "The camera's horizontal vector: direction × up, in that order, and the sign of \
               the screen's x coordinate.",
    candidates: |_| {
        vec![Candidate::plain(Planted::Camera(
            CameraFault::FlipHorizontal,
        ))]
    },
};

pub(super) const PIXELS_TRANSPOSED: Fault = Fault {
    name: "pixels_transposed",
    assignment: 1,
    sentence: "My square picture has its x and y exchanged: pixel (i, j) shows what the \
               camera's pixel (j, i) sees (form 0: the loops' or SetPixel's arguments swapped), \
               or the same with rows or columns counted from the other end (form 1: mirrored \
               across the other diagonal; forms 2 and 3: turned a quarter turn).",
    look_for: "Where the pixel loop makes a ray and writes its colour: the ray of column i and \
               row j (from the bottom) goes to SetPixel(i, j), x first; check both loops' \
               bounds and the order of the arguments.",
    candidates: |line: &LineScene| {
        if line.options.width != line.options.height || line.options.width < 2 {
            return Vec::new();
        }
        Candidate::forms(
            [
                Exchange::Transpose,
                Exchange::OtherDiagonal,
                Exchange::QuarterTurn,
                Exchange::OtherQuarterTurn,
            ]
            .map(|exchange| Planted::Camera(CameraFault::Transposed(exchange))),
        )
    },
};

/// The angles students' formulas make of the file's `angle`, each with its name, and then a
/// search for the angle that fits best is left to the caller's fitting.
fn field_of_view(line: &LineScene) -> Vec<Candidate> {
    let Some(angle) = perspective_angle(line) else {
        return Vec::new();
    };
    let radians = f64::from(angle).to_radians();
    let formulas = [
        // tan(angle) for tan(angle / 2): the angle used whole.
        2.0 * radians,
        // tan(angle / 4): halved twice.
        radians / 2.0,
        // The angle's degrees taken for radians (no conversion), folded into a view.
        2.0 * (f64::from(angle) / 2.0).tan().abs().atan(),
        // asin(tan(angle / 2)) where atan was meant, or the reverse.
        2.0 * (radians / 2.0).tan().min(1.0).asin(),
        2.0 * (radians / 2.0).sin().atan(),
    ];
    formulas
        .into_iter()
        .map(|full| full.to_degrees() as f32)
        .filter(|&degrees| degrees > 0.0 && degrees < 179.9 && (degrees - angle).abs() > 0.01)
        .map(|degrees| {
            Candidate::with(
                Planted::Camera(CameraFault::Other(with_angle(line, degrees))),
                "angle",
                f64::from(degrees),
            )
        })
        .collect()
}

pub(super) const FIELD_OF_VIEW: Fault = Fault {
    name: "field_of_view",
    assignment: 2,
    sentence: "My camera sees a wider or narrower view than the file says: a perspective \
               camera's angle, or an orthographic camera's size.",
    look_for: "The perspective camera's screen: at distance 1 it is 2·tan(angle / 2) wide, \
               with the angle converted from degrees to radians once; the orthographic \
               camera's square is `size` wide, from the centre − size / 2 to + size / 2.",
    candidates: field_of_view,
};

fn equal_angles(line: &LineScene) -> Vec<Candidate> {
    let Some(angle) = perspective_angle(line) else {
        return Vec::new();
    };
    let camera = line.scene.camera;
    vec![Candidate::plain(Planted::Camera(CameraFault::EqualAngles(
        camera,
        f64::from(angle).to_radians() as f32,
    )))]
}

pub(super) const EQUAL_ANGLE_RAYS: Fault = Fault {
    name: "equal_angle_rays",
    assignment: 2,
    sentence: "My perspective rays step by equal angles across the view instead of going through \
               evenly spaced points of a screen.",
    look_for: "How a perspective ray is made: direction + x·horizontal + y·up through points \
               evenly spaced on the screen, not rotations by equal angles.",
    candidates: equal_angles,
};

/// The frames students make of the file's up: not made perpendicular to the direction (then
/// normalised or not), and the horizontal vector not normalised either. (The parser keeps the
/// direction normalised, so a direction's own length cannot be told here.)
fn camera_basis(line: &LineScene) -> Vec<Candidate> {
    let spec = line.description.camera;
    let raw_up = Vec3A::from(spec.up);
    let direction = Vec3A::from(spec.direction).normalize();
    let horizontal = direction.cross(raw_up).normalize();
    let frames = [
        (horizontal, raw_up.normalize()),
        (horizontal, raw_up),
        (direction.cross(raw_up), raw_up),
    ];
    let (_, _, course_up) = line.scene.camera.frame();
    let mut candidates = Vec::new();
    let mut seen = vec![(horizontal, course_up)];
    for (k, (horizontal, up)) in frames.into_iter().enumerate() {
        let same = |(h, u): &(Vec3A, Vec3A)| {
            (*h - horizontal).abs().max_element() < 1e-6 && (*u - up).abs().max_element() < 1e-6
        };
        if seen.iter().any(same) {
            continue;
        }
        seen.push((horizontal, up));
        let center = line.scene.camera.center();
        let camera = Camera::from_frame(center, direction, horizontal, up, spec.projection);
        candidates.push(Candidate::with(
            Planted::Camera(CameraFault::Other(camera)),
            "frame",
            k as f64,
        ));
    }
    candidates
}

pub(super) const CAMERA_BASIS: Fault = Fault {
    name: "camera_basis",
    assignment: 1,
    sentence: "My camera's up vector is used as given: not made perpendicular to the direction, \
               or not normalised.",
    look_for: "The camera's frame: horizontal = normalize(direction × up), then up' = \
               horizontal × direction; use up', not the file's up.",
    candidates: camera_basis,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_exchange_of_x_and_y_is_its_own_map_of_the_square() {
        let all = [
            Exchange::Transpose,
            Exchange::OtherDiagonal,
            Exchange::QuarterTurn,
            Exchange::OtherQuarterTurn,
        ];
        let n = 3;
        let maps: Vec<Vec<(u32, u32)>> = all
            .iter()
            .map(|e| {
                (0..n)
                    .flat_map(|j| (0..n).map(move |i| e.source(i, j, n)))
                    .collect()
            })
            .collect();
        for (map, exchange) in maps.iter().zip(all) {
            // Every pixel of the square shown once.
            let mut sorted = map.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), 9, "{exchange:?}");
        }
        for (a, first) in maps.iter().enumerate() {
            assert!(maps[a + 1..].iter().all(|other| other != first));
        }
        // By hand, in a picture of side 3: the lower-right pixel (2, 0) shows the upper
        // left (0, 2) across the diagonal, and itself across the other; a quarter turn one
        // way shows (0, 0) there, the other way (2, 2).
        assert_eq!(Exchange::Transpose.source(2, 0, n), (0, 2));
        assert_eq!(Exchange::OtherDiagonal.source(2, 0, n), (2, 0));
        assert_eq!(Exchange::QuarterTurn.source(2, 0, n), (0, 0));
        assert_eq!(Exchange::OtherQuarterTurn.source(2, 0, n), (2, 2));
        // Two quarter turns the same way: the half turn.
        let twice = |i, j| {
            let (i, j) = Exchange::QuarterTurn.source(i, j, n);
            Exchange::QuarterTurn.source(i, j, n)
        };
        assert_eq!(twice(0, 0), (2, 2));
        assert_eq!(twice(2, 1), (0, 1));
    }
}
