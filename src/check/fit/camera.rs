//! The camera, fitted: where each pixel's ray goes, as an offset of the film point, a scale of
//! the view per axis and a shear, for each way a ray is made from a point of the view (through a
//! plane, as the course does; by two turns, in either order; by a tangent per axis), the plane
//! first, the others in the order their course numbers draw the pictures. The fitted numbers name the
//! fault: half a pixel off is `pixel_corner`, a view w/(w-1) as wide `pixel_span_minus_one`, a
//! wider or narrower view `field_of_view` (with the angle or size it amounts to), axes of
//! other lengths or leaning `camera_basis`, rays not through a plane `equal_angle_rays`.

use super::minimise::{Start, minimise};
use crate::check::diagnose::object_bounds;
use crate::check::faults::{
    CameraFault, FAULTS, Fault, LineScene, Mapping, Plant, Planted, RayForm,
};
use crate::parse::description::Projection;
use crate::shade::Image;

// The numbers of a mapping, in order: the offset (x, y) in pixels, the scale (x, y), the shear.
/// Renders allowed for each stage of a form's search...
const EVALUATIONS: usize = 30;
/// ...and for all of a line's (each of a third of the rows: some three hundred renders' worth,
/// milliseconds each on the course's first assignments), shared among a pixel's samples: a
/// line of 16 samples a pixel costs its renders 16 times over...
const BUDGET: usize = 1000;
/// ...down to this many.
const LEAST_BUDGET: usize = 60;
/// The searches of a fit, in two orders: which numbers each stage searches, and whether by the
/// finer steps.
const ORDERS: [[(&[usize], bool); 3]; 2] = [
    [
        (&[0, 1], false),
        (&[2, 3, 4], false),
        (&[0, 1, 2, 3, 4], true),
    ],
    [
        (&[2, 3, 4], false),
        (&[0, 1], false),
        (&[0, 1, 2, 3, 4], true),
    ],
];
/// The first steps: half a pixel for the offsets, a twentieth for the scales and the shear...
const STEPS: [f64; 5] = [0.5, 0.5, 0.05, 0.05, 0.05];
/// ...and a fifth of those in the last stage.
const FINE: f64 = 0.2;
/// The round values each number is tried at, where it lands this close to one.
const ROUND: [&[f64]; 5] = [&[0.0, -0.5, 0.5], &[0.0, -0.5, 0.5], &[1.0], &[1.0], &[0.0]];
const WITHIN: [f64; 5] = [0.2, 0.2, 0.01, 0.01, 0.01];
/// An offset this long, in pixels, is a ray through a pixel's corner or edge.
const CORNER: f32 = 0.25;
/// A pixel is an object's where a channel is this far from the border's colour.
const BOUNDS_TOLERANCE: u8 = 8;
/// Two scales this close are one.
const SCALE_ROUND: f64 = 0.004;

/// A camera fitted to a student's pictures: its plant, and each way the fitted numbers can be
/// named (the faults, and the numbers that show each), the likeliest first.
#[derive(Debug, Clone)]
pub struct FittedCamera {
    pub plant: Planted,
    pub names: Vec<Named>,
}

/// Faults named from fitted numbers, with the numbers that show them.
pub type Named = (Vec<&'static Fault>, Vec<(&'static str, f64)>);

/// For each form a ray can be made in (only through a plane for an orthographic camera), the
/// mapping whose render is least `distance` from the student's pictures, where it is nearer than
/// the course's camera and differs from it. `distance` is called once per render.
pub fn fit_camera<E>(
    line: &LineScene,
    pictures: &[(&Image, &Image)],
    mut distance: impl FnMut(Plant) -> Result<f64, E>,
) -> Result<Vec<FittedCamera>, E> {
    let camera = line.scene.camera;
    let (angle, forms): (f32, &[RayForm]) = match line.description.camera.projection {
        Projection::Perspective { angle } => (
            angle.to_radians(),
            &[
                RayForm::Plane,
                RayForm::TangentPerAxis,
                RayForm::TurnedAngles,
                RayForm::TurnedOtherOrder,
            ],
        ),
        Projection::Orthographic { .. } => (0.0, &[RayForm::Plane]),
    };
    let plant = |form: RayForm, p: &[f64]| {
        Plant::one(Planted::Camera(CameraFault::Mapped(
            camera,
            angle,
            mapping(form, p),
        )))
    };
    let course_at = [0.0, 0.0, 1.0, 1.0, 0.0];
    let guess = estimate(pictures);
    let course = distance(plant(RayForm::Plane, &course_at))?;
    let mut fitted = Vec::new();
    let mut spent = 0;
    let samples = line.options.sampling.sampler.samples().max(1) as usize;
    let budget = (BUDGET / samples).max(LEAST_BUDGET);
    // The course's form first (most mistakes keep it: a scale, an offset, a lean), then the
    // others in the order their course numbers draw the pictures, nearest first: the budget is
    // shared, and the form the student wrote should not wait behind the others' searches.
    let mut ordered = Vec::with_capacity(forms.len());
    for &form in forms.iter().filter(|&&form| form != RayForm::Plane) {
        ordered.push((form, distance(plant(form, &course_at))?));
    }
    ordered.sort_by(|a, b| a.1.total_cmp(&b.1));
    let plane = forms
        .contains(&RayForm::Plane)
        .then_some((RayForm::Plane, course));
    for (form, _) in plane.into_iter().chain(ordered) {
        // Past the line's budget every render is as far as can be: the searches end at once.
        let mut measure = |p: &[f64]| {
            spent += 1;
            if spent > budget {
                Ok(f64::INFINITY)
            } else {
                distance(plant(form, p))
            }
        };
        // In stages, each a search of a few numbers (a search of all five at once settles on
        // the steps that edges make of a distance), in two orders (an offset can stand in for
        // part of a scale, and the reverse): the first to land nearest is kept.
        let mut best = (course_at.to_vec(), f64::INFINITY);
        let starts = guess.into_iter().chain([course_at]);
        let tries: Vec<([f64; 5], _)> = starts
            .enumerate()
            .flat_map(|(k, start)| {
                ORDERS
                    .iter()
                    .skip(k.min(1))
                    .map(move |order| (start, order))
            })
            .collect();
        for (start, order) in tries {
            if best.1 <= 0.0 {
                break;
            }
            let mut at = (start.to_vec(), f64::INFINITY);
            for &(free, fine) in order {
                if at.1 <= 0.0 {
                    break;
                }
                at = search(&mut measure, at, free, fine)?;
            }
            if at.1 < best.1 {
                best = at;
            }
        }
        // Each number taken for the round value it is close to, where the render is no
        // further from the picture for it; the others searched again around it.
        let (mut at, mut value) = best;
        let mut free: Vec<usize> = (0..at.len()).collect();
        for i in 0..at.len() {
            let Some(round) = ROUND[i]
                .iter()
                .copied()
                .find(|r| (at[i] - r).abs() <= WITHIN[i])
            else {
                continue;
            };
            let mut rounded = at.clone();
            rounded[i] = round;
            let v = if round == at[i] {
                value
            } else {
                measure(&rounded)?
            };
            if v <= value {
                (at, value) = (rounded, v);
                free.retain(|&f| f != i);
            }
        }
        if value > 0.0 && !free.is_empty() && free.len() < at.len() {
            (at, value) = search(&mut measure, (at, value), &free, true)?;
        }
        let found = mapping(form, &at);
        if value >= course || found == Mapping::course(RayForm::Plane) {
            continue;
        }
        fitted.push(FittedCamera {
            plant: Planted::Camera(CameraFault::Mapped(camera, angle, found)),
            names: names(line, found),
        });
        // A form that draws the pictures leaves nothing for another to explain.
        if value <= 0.0 {
            break;
        }
    }
    Ok(fitted)
}

/// The numbers `free` of `at` searched (the others held), by first steps a fifth as long where
/// `fine`; `at` kept where the search lands no nearer.
fn search<E>(
    measure: &mut impl FnMut(&[f64]) -> Result<f64, E>,
    (at, value): (Vec<f64>, f64),
    free: &[usize],
    fine: bool,
) -> Result<(Vec<f64>, f64), E> {
    let starts: Vec<Start> = free
        .iter()
        .map(|&i| Start {
            value: at[i],
            step: STEPS[i] * if fine { FINE } else { 1.0 },
        })
        .collect();
    let whole = |p: &[f64]| {
        let mut whole = at.clone();
        for (&i, &v) in free.iter().zip(p) {
            whole[i] = v;
        }
        whole
    };
    let least = minimise(&starts, EVALUATIONS, |p| measure(&whole(p)))?;
    Ok(if least.value < value {
        (whole(&least.at), least.value)
    } else {
        (at, value)
    })
}

/// Where the objects stand in the student's pictures against the references: the scale of
/// their box about the picture's centre and its offset, as a mapping's numbers (the view's
/// scale being the inverse of the objects'). A first guess for the search, from the first
/// picture whose boxes can be told.
fn estimate(pictures: &[(&Image, &Image)]) -> Option<[f64; 5]> {
    pictures.iter().find_map(|&(actual, reference)| {
        let seen = object_bounds(actual, BOUNDS_TOLERANCE)?;
        let wanted = object_bounds(reference, BOUNDS_TOLERANCE)?;
        let (width, height) = (f64::from(actual.width), f64::from(actual.height));
        let axis = |low: usize, high: usize, centre: f64, up: bool| {
            let (s, w) = (
                seen[high] - seen[low] + 1.0,
                wanted[high] - wanted[low] + 1.0,
            );
            let scale = w / s;
            // Where the box's middle lands, scaled back: what is left is the offset.
            let (sm, wm) = (
                (seen[low] + seen[high]) / 2.0 - centre,
                (wanted[low] + wanted[high]) / 2.0 - centre,
            );
            let offset = wm - sm * scale;
            (scale, if up { -offset } else { offset })
        };
        let (sx, ox) = axis(0, 2, width / 2.0 - 0.5, false);
        let (sy, oy) = axis(1, 3, height / 2.0 - 0.5, true);
        let plausible = |s: f64| (0.5..=2.0).contains(&s);
        (plausible(sx) && plausible(sy)).then_some([ox, oy, sx, sy, 0.0])
    })
}

fn mapping(form: RayForm, p: &[f64]) -> Mapping {
    Mapping {
        form,
        offset: [p[0] as f32, p[1] as f32],
        scale: [p[2] as f32, p[3] as f32],
        shear: p[4] as f32,
    }
}

fn fault(name: &str) -> &'static Fault {
    FAULTS
        .iter()
        .find(|f| f.name == name)
        .expect("a fault of the library")
}

/// What a teaching assistant would call the fitted mapping: the faults its numbers amount to,
/// each with the numbers that show it; two ways where the line cannot tell them apart (a
/// perspective view scaled alike on both axes is a wrong angle or a frame of another length).
fn names(line: &LineScene, found: Mapping) -> Vec<Named> {
    let (width, height) = (line.options.width as f32, line.options.height as f32);
    let near = |a: f32, b: f32| (a - b).abs() <= SCALE_ROUND as f32;
    let mut faults: Vec<&'static Fault> = Vec::new();
    let mut numbers: Vec<(&'static str, f64)> = Vec::new();
    if found.form != RayForm::Plane {
        faults.push(fault("equal_angle_rays"));
        numbers.push((
            match found.form {
                RayForm::TangentPerAxis => "form_tangent_per_axis",
                RayForm::TurnedOtherOrder => "form_turned_up_first",
                _ => "form_turned",
            },
            1.0,
        ));
    }
    // An offset of less than a quarter pixel is the fit's slack, not a corner.
    if found.offset.iter().any(|o| o.abs() >= CORNER) {
        faults.push(fault("pixel_corner"));
        numbers.push(("offset_x", f64::from(found.offset[0])));
        numbers.push(("offset_y", f64::from(found.offset[1])));
    }
    let [sx, sy] = found.scale;
    let leans = found.shear.abs() > SCALE_ROUND as f32;
    let span = |n: f32| if n > 1.0 { n / (n - 1.0) } else { 1.0 };
    let mut alternatives: Vec<Named> = Vec::new();
    if near(sx, 1.0) && near(sy, 1.0) && !leans {
        // Nothing of the view's size or lean.
    } else if near(sx, span(width)) && near(sy, span(height)) && !leans {
        faults.push(fault("pixel_span_minus_one"));
    } else if (near(sx, span(width)) || near(sx, 1.0))
        && (near(sy, span(height)) || near(sy, 1.0))
        && !leans
    {
        // One axis's pixels spread over its size - 1, the other's as the course's.
        faults.push(fault("pixel_span_minus_one"));
        numbers.push(("scale_x", f64::from(sx)));
        numbers.push(("scale_y", f64::from(sy)));
    } else if near(sx, sy) && !leans {
        let scale = f64::from(sx + sy) / 2.0;
        let basis = (fault("camera_basis"), ("scale", scale));
        // The view as wide as the student's: a perspective camera's angle, an orthographic
        // camera's size.
        let view = match line.description.camera.projection {
            Projection::Perspective { angle } => {
                let half = f64::from(angle).to_radians() / 2.0;
                ("angle", 2.0 * (scale * half.tan()).atan().to_degrees())
            }
            Projection::Orthographic { size } => ("size", scale * f64::from(size)),
        };
        let mut other = (faults.clone(), numbers.clone());
        other.0.push(basis.0);
        other.1.push(basis.1);
        alternatives.push(other);
        faults.push(fault("field_of_view"));
        numbers.push(view);
    } else {
        faults.push(fault("camera_basis"));
        numbers.push(("scale_x", f64::from(sx)));
        numbers.push(("scale_y", f64::from(sy)));
        if leans {
            numbers.push(("shear", f64::from(found.shear)));
        }
    }
    let mut all = vec![(faults, numbers)];
    all.extend(alternatives);
    all.retain(|(faults, _)| !faults.is_empty());
    all
}
