//! Shading, fitted: where the student's objects stand where the course's do, each pixel's colour
//! is a sum of terms raycast knows at the hit (the ambient term, each light's diffuse and
//! specular terms with its shadow, and what mirrors and glass bring), so how the student's
//! colours depend on those terms can be found without a render per guess. The family: the
//! ambient term's weight, the power of each light's N·L, N·L clamped or taken whole (|N·L|), and
//! the normal's length as a function over each object's surface (see
//! [`crate::check::faults::normal_length`]). The fitted numbers name the faults: an ambient
//! weight of 0 is `ambient_missing`, one of the number of lights `ambient_per_light`, a power of
//! 2 `cosine_twice`, |N·L| `shade_back_abs`, a normal of any other length `normal_length`; a
//! number that lands nowhere named names nothing.

use glam::Vec3A;

use super::camera::Named;
use super::minimise::{Start, minimise};
use crate::camera::pixel_to_screen;
use crate::check::faults::{
    FAULTS, Fault, HitFault, LineScene, Planted, ShadingFault, length_from, normal_stretch,
};
use crate::geometry::Ray;
use crate::sample::Sampler;
use crate::scene::{Illumination, Surface, Texture};
use crate::shade::{Image, to_byte};
use crate::trace::{Scratch, Tracer, clearance, shadow_end, start_t};

/// The family's numbers, in order: the ambient weight, the power of N·L, and the normal's
/// length's a, b and c; the course's values...
const COURSE: [f64; 5] = [1.0, 1.0, 1.0, 0.0, 0.0];
/// ...the first steps of the search...
const STEPS: [f64; 5] = [0.5, 0.5, 0.5, 0.5, 0.5];
/// ...and the round values each is tried at once fitted (the ambient weight also at the number
/// of lights).
const ROUND: [&[f64]; 5] = [
    &[0.0, 1.0],
    &[1.0, 2.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
];
/// Evaluations of the model (not renders) for each search...
const EVALUATIONS: usize = 400;
/// ...and searches, each from where the last ended.
const RESTARTS: usize = 4;
/// At most this many pixels are weighed (evenly spread over the picture).
const MAX_PIXELS: usize = 6000;
/// A pixel's channel counts at most this many levels off: a pixel the family cannot draw (a
/// shadow's edge, a mirror's image) weighs no more than a few that it draws nearly.
const CAP: f64 = 24.0;
/// A round value is taken where the fit is worse by at most this share there...
const ROUND_SHARE: f64 = 0.02;
/// ...or by this many levels a pixel.
const ROUND_LEVELS: f64 = 0.05;

/// What the fit knows of one pixel: the hit as the course finds it, and what its colour is
/// made of there.
struct Seen<'a> {
    /// Its index in the picture.
    pixel: usize,
    /// The ray's direction.
    view: Vec3A,
    /// The course's unit normal, turned toward the ray.
    normal: Vec3A,
    /// The length of the normal's direction on its object, for the family's a, b and c.
    stretch: f32,
    along: f32,
    surface: Surface<'a>,
    ambient: Vec3A,
    /// Each light that reaches the hit unshadowed.
    lights: Vec<Illumination>,
    /// What mirrors and glass bring (the course's colour less the hit's own).
    rest: Vec3A,
}

/// The line's shading fitted to the student's shaded picture (`shaded`) and normals picture
/// (`normals`), each with the index of its slot: the plant, and the faults the numbers name,
/// where the fit is nearer than the course's shading and every number off the course's is
/// named.
pub fn fit_shading(
    line: &LineScene,
    shaded: Option<&Image>,
    normals: Option<&Image>,
) -> Option<(Vec<Planted>, Named)> {
    let options = &line.options;
    let settings = options.trace;
    // One ray through each pixel's centre, as the course's lines without samples make.
    if options.sampling.sampler != Sampler::Uniform(1)
        || settings.visualize_grid
        || (shaded.is_none() && normals.is_none())
    {
        return None;
    }
    let scene = &line.scene;
    let (width, height) = (options.width, options.height);
    let pixels = (width * height) as usize;
    let every = pixels.div_ceil(MAX_PIXELS).max(1);
    let tracer = Tracer::new(scene, settings);
    let mut scratch = Scratch::default();
    let mut seen: Vec<Seen<'_>> = Vec::new();
    for pixel in (0..pixels).step_by(every) {
        let (i, row) = (pixel as u32 % width, pixel as u32 / width);
        let (u, v) = pixel_to_screen(i, height - 1 - row, width, height);
        let ray = scene.camera.ray(u, v);
        let t_min = scene.camera.t_min();
        let Some(hit) = scene.world.intersect(&ray, t_min) else {
            continue;
        };
        let inside = ray.direction.dot(hit.normal) > 0.0;
        if inside && !settings.shade_back {
            continue;
        }
        let point = ray.at(hit.t);
        let mut surface = Surface::unweighed(&scene.materials, hit.material);
        surface.weigh(point, Texture::weight);
        let normal = if inside { -hit.normal } else { hit.normal };
        let transform = scene.world.normal_origin(&ray, t_min).and_then(|(_, t)| t);
        let (stretch, along) = normal_stretch(hit.normal, transform);
        let clearance = clearance(point, ray.origin);
        let lights = scene
            .lights
            .iter()
            .filter_map(|light| light.illuminate(point))
            .filter(|light| {
                let shadow = Ray::new(point, light.to_light);
                !settings.shadows
                    || !scene.world.occluded(
                        &shadow,
                        start_t(clearance, light.to_light, normal),
                        shadow_end(light.distance),
                    )
            })
            .collect();
        let mut one = Seen {
            pixel,
            view: ray.direction,
            normal,
            stretch,
            along,
            ambient: scene.ambient * surface.diffuse(),
            surface,
            lights,
            rest: Vec3A::ZERO,
        };
        let course = tracer.colour(&ray, Some(&hit), &mut scratch);
        one.rest = course - shade(&one, &COURSE, false, scene.lights.len(), settings.specular);
        seen.push(one);
    }
    if seen.is_empty() {
        return None;
    }
    let lights = scene.lights.len();
    let falloff = settings.specular;
    let cost = |numbers: &[f64], absolute: bool| -> f64 {
        let mut sum = 0.0;
        for one in &seen {
            if let Some(shaded) = shaded {
                let colour = shade(one, numbers, absolute, lights, falloff);
                sum += levels_off(colour, shaded.pixels[one.pixel]);
            }
            if let Some(normals) = normals {
                let length = length(one, numbers);
                sum += levels_off((one.normal * length).abs(), normals.pixels[one.pixel]);
            }
        }
        sum / seen.len() as f64
    };
    let course = cost(&COURSE, false);
    // |N·L| only where some light is behind a surface it would light.
    let behind = seen.iter().any(|one| {
        one.lights
            .iter()
            .any(|light| one.normal.dot(light.to_light) < 0.0)
    });
    let mut best: Option<([f64; 5], bool, f64)> = None;
    for absolute in [false, true].into_iter().filter(|&a| !a || behind) {
        // Searched again from where each search ends, by smaller steps: the simplex of one
        // search may settle short of the least in a valley.
        let mut at: [f64; 5] = COURSE;
        let mut value = f64::INFINITY;
        for restart in 0..RESTARTS {
            let scale = 0.5f64.powi(restart as i32);
            let starts: Vec<Start> = at
                .iter()
                .zip(STEPS)
                .map(|(&value, step)| Start {
                    value,
                    step: step * scale,
                })
                .collect();
            let least = minimise::<()>(&starts, EVALUATIONS, |at| Ok(cost(at, absolute))).ok()?;
            let better = least.value < value - 1e-6;
            if least.value < value {
                at = least.at.try_into().ok()?;
                value = least.value;
            }
            if !better || value == 0.0 {
                break;
            }
        }
        // Every number at the round value nearest it at once, where that costs (almost)
        // nothing (numbers that trade off against each other may each sit off their round value
        // while the others do); then each number alone, again while any moves (one number may
        // round only once another has).
        let nearest: [f64; 5] = std::array::from_fn(|index| {
            round_values(index, lights)
                .into_iter()
                .min_by(|a, b| (a - at[index]).abs().total_cmp(&(b - at[index]).abs()))
                .unwrap_or(at[index])
        });
        let there = cost(&nearest, absolute);
        if there <= value * (1.0 + ROUND_SHARE) + ROUND_LEVELS {
            at = nearest;
            value = there.min(value);
        }
        for _ in 0..at.len() {
            let mut moved = false;
            for index in 0..at.len() {
                for r in round_values(index, lights)
                    .into_iter()
                    .filter(|&r| r != at[index])
                {
                    let mut tried = at;
                    tried[index] = r;
                    let there = cost(&tried, absolute);
                    if there <= value * (1.0 + ROUND_SHARE) + ROUND_LEVELS {
                        at = tried;
                        value = there.min(value);
                        moved = true;
                        break;
                    }
                }
            }
            if !moved {
                break;
            }
        }
        if best.is_none_or(|(_, _, v)| value < v) {
            best = Some((at, absolute, value));
        }
    }
    let (at, absolute, value) = best?;
    if value >= course || (at == COURSE && !absolute) {
        return None;
    }
    name(at, absolute, lights)
}

/// The round values number `index` is tried at.
fn round_values(index: usize, lights: usize) -> Vec<f64> {
    let mut round = ROUND[index].to_vec();
    if index == 0 {
        round.push(lights as f64);
    }
    round
}

/// The colour the family draws at `one` with `numbers` (unclamped).
fn shade(
    one: &Seen<'_>,
    numbers: &[f64],
    absolute: bool,
    lights: usize,
    falloff: crate::scene::SpecularFalloff,
) -> Vec3A {
    let fault = weighed(numbers, absolute);
    let normal = one.normal * length(one, numbers);
    let mut colour = fault.ambient(one.ambient, lights) + one.rest;
    for light in &one.lights {
        colour += fault.light(
            &|n, f, h| {
                one.surface
                    .shade(n, one.view, light.to_light, light.colour, f, h)
            },
            normal,
            light.to_light,
            falloff,
            crate::scene::Highlight::Course,
        );
    }
    colour
}

/// The shading the numbers say, as the fault library plants it.
fn weighed(numbers: &[f64], absolute: bool) -> ShadingFault {
    ShadingFault::Weighed {
        ambient: numbers[0] as f32,
        power: numbers[1] as f32,
        absolute,
    }
}

/// The normal's length at `one` with `numbers`.
fn length(one: &Seen<'_>, numbers: &[f64]) -> f32 {
    let numbers = [numbers[2], numbers[3], numbers[4]].map(|n| n as f32);
    length_from(numbers, one.stretch, one.along)
}

/// How many levels `colour` lands from the student's bytes, summed over the channels, each at
/// most [`CAP`].
fn levels_off(colour: Vec3A, student: [u8; 3]) -> f64 {
    colour
        .to_array()
        .iter()
        .zip(student)
        .map(|(&c, s)| {
            if to_byte(c) == s {
                0.0
            } else {
                let level = f64::from(c.clamp(0.0, 1.0)) * 255.0;
                (level - (f64::from(s) + 0.5)).abs().min(CAP)
            }
        })
        .sum()
}

/// The faults fitted numbers name, with the numbers that show them; none where a number off the
/// course's lands on no fault.
fn name(at: [f64; 5], absolute: bool, lights: usize) -> Option<(Vec<Planted>, Named)> {
    let fault = |name: &str| FAULTS.iter().find(|f| f.name == name);
    let mut faults: Vec<&'static Fault> = Vec::new();
    let mut numbers: Vec<(&'static str, f64)> = Vec::new();
    let mut plants: Vec<Planted> = Vec::new();
    let [ambient, power, a, b, c] = at;
    if ambient != 1.0 || power != 1.0 || absolute {
        if ambient == 0.0 {
            faults.push(fault("ambient_missing")?);
        } else if ambient == lights as f64 {
            faults.push(fault("ambient_per_light")?);
        } else if ambient != 1.0 {
            return None;
        }
        if power == 2.0 {
            faults.push(fault("cosine_twice")?);
        } else if power != 1.0 {
            return None;
        }
        if absolute {
            faults.push(fault("shade_back_abs")?);
        }
        numbers.push(("ambient weight", ambient));
        numbers.push(("power of N·L", power));
        plants.push(Planted::Shading(weighed(&at, absolute)));
    }
    if [a, b, c] != [COURSE[2], COURSE[3], COURSE[4]] {
        faults.push(fault("normal_length")?);
        numbers.extend([
            ("normal's 1/|n|²: constant", a),
            ("times |Aᵀn|²", b),
            ("times (t·n)²", c),
        ]);
        plants.push(Planted::Hit(HitFault::NormalLength(
            [a, b, c].map(|n| n as f32),
        )));
    }
    Some((plants, (faults, numbers)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_off_counts_from_the_middle_of_the_students_level() {
        assert_eq!(levels_off(Vec3A::splat(0.2), [51, 51, 51]), 0.0);
        // 0.5 is level 127.5: a student's 120 is 7.0 below.
        assert!((levels_off(Vec3A::new(0.5, 0.2, 0.2), [120, 51, 51]) - 7.0).abs() < 1e-4);
        assert_eq!(levels_off(Vec3A::ONE, [0, 0, 0]), 3.0 * CAP);
    }

    #[test]
    fn numbers_land_on_names() {
        let named = |at, absolute| {
            name(at, absolute, 2)
                .map(|(_, (faults, _))| faults.iter().map(|f| f.name).collect::<Vec<_>>())
        };
        assert_eq!(
            named([2.0, 1.0, 1.0, 0.0, 0.0], false),
            Some(vec!["ambient_per_light"])
        );
        assert_eq!(
            named([1.0, 2.0, 1.0, 0.0, 1.0], true),
            Some(vec!["cosine_twice", "shade_back_abs", "normal_length"])
        );
        assert_eq!(named([0.7, 1.0, 1.0, 0.0, 0.0], false), None);
        assert_eq!(named([1.0, 1.5, 1.0, 0.0, 0.0], false), None);
    }
}
