//! Shading, fitted: where the student's objects stand where the course's do, each pixel's colour
//! is a sum of terms raycast knows at the hit (the ambient term, each light's diffuse and
//! specular terms with its shadow, and what mirrors and glass bring), so how the student's
//! colours depend on those terms can be found without a render per guess. The family: the
//! ambient term's weight, the power of each light's N·L, N·L clamped, taken whole (|N·L|) or as
//! it is (a light behind the surface takes its light away), and the normal's length as a
//! function over each object's surface (see [`crate::check::faults::normal_length`]). The
//! fitted numbers name the faults: an ambient weight of 0 is `ambient_missing`, one of the
//! number of lights `ambient_per_light`, a power of 2 `cosine_twice`, |N·L| `shade_back_abs`,
//! N·L as it is `diffuse_unclamped`, a normal of any other length `normal_length`; a number
//! that lands nowhere named names nothing.

use glam::Vec3A;

use super::camera::Named;
use super::minimise::{Start, minimise};
use crate::camera::pixel_to_screen;
use crate::check::faults::{
    Cosine, FAULTS, Fault, HitFault, LineScene, Planted, ShadingFault, length_from, normal_stretch,
};
use crate::geometry::Ray;
use crate::sample::Sampler;
use crate::scene::{
    HighlightBase, HighlightColour, HighlightForm, Illumination, Light, Surface, Texture,
};
use crate::shade::{Image, to_byte};
use crate::trace::{Scratch, Tracer, clearance, shadow_end, start_t};

/// How many numbers the family has: the ambient weight, the power of N·L, the normal's length's
/// a, b and c, and a point light's divisor's constant, linear and quadratic terms.
const NUMBERS: usize = 8;
/// The first steps of the search (the divisor's relative to the file's terms)...
const STEPS: [f64; NUMBERS] = [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5];
/// ...and the round values each is tried at once fitted (the ambient weight also at the number
/// of lights, the divisor's terms also at the file's three).
const ROUND: [&[f64]; NUMBERS] = [
    &[0.0, 1.0],
    &[1.0, 2.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
    &[0.0, 1.0],
];
/// The numbers of each stage of the pipeline: the shading's weights, the normal's length, a
/// point light's divisor.
const STAGES: [&[usize]; 3] = [&[0, 1], &[2, 3, 4], &[5, 6, 7]];
/// Evaluations of the model (not renders) for each search, for each number searched...
const EVALUATIONS: usize = 80;
/// ...and searches, each from where the last ended.
const RESTARTS: usize = 4;
/// The scales of H tried in each form of the highlights' family (1/2: the mean of L and V).
const HALF_SCALES: [f32; 2] = [1.0, 0.5];
/// At most this many pixels are weighed (evenly spread over the picture).
const MAX_PIXELS: usize = 6000;
/// A pixel's channel counts at most this many levels off: a pixel the family cannot draw (a
/// shadow's edge, a mirror's image) weighs no more than a few that it draws nearly.
const CAP: f64 = 24.0;
/// A channel within this many levels of the middle of the student's counts nothing: bytes
/// rounded to the nearest, not truncated as the course's, land there, and they are no mistake.
const SLACK: f64 = 1.0;
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
    stretch: Option<(f32, f32)>,
    surface: Surface<'a>,
    ambient: Vec3A,
    /// Each light that reaches the hit unshadowed, with its place among the scene's lights and
    /// the divisor the file's attenuation gives a point light there.
    lights: Vec<(usize, Illumination, Option<f32>)>,
    /// What mirrors and glass bring (the course's colour less the hit's own).
    rest: Vec3A,
}

/// The line's shading fitted to the student's shaded picture (`shaded`) and normals picture
/// (`normals`), each with the index of its slot: the plant, and the faults the numbers name,
/// where the fit removes more than `least_share` of the course's shading's difference from the
/// pictures and every number off the course's is named.
pub fn fit_shading(
    line: &LineScene,
    shaded: Option<&Image>,
    normals: Option<&Image>,
    least_share: f64,
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
    // The course's numbers; a point light's divisor is fitted where every point light has the
    // same attenuation (the course's terms then the file's).
    let terms: Vec<[f32; 3]> = scene
        .lights
        .iter()
        .filter_map(|light| match *light {
            Light::Point { attenuation, .. } => Some(attenuation),
            Light::Directional { .. } => None,
        })
        .collect();
    let shared = terms.first().filter(|t| terms.iter().all(|o| o == *t));
    let [c, l, q] = shared.map_or([1.0, 0.0, 0.0], |t| t.map(f64::from));
    let course: [f64; NUMBERS] = [1.0, 1.0, 1.0, 0.0, 0.0, c, l, q];
    let free: Vec<usize> = (0..if shared.is_some() { NUMBERS } else { 5 }).collect();
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
        let stretch = normal_stretch(hit.normal, transform);
        let clearance = clearance(point, ray.origin);
        let lights = scene
            .lights
            .iter()
            .enumerate()
            .filter_map(|(index, light)| Some((index, light.illuminate(point)?, light)))
            .filter(|(_, lit, _)| {
                let shadow = Ray::new(point, lit.to_light);
                !settings.shadows
                    || !scene.world.occluded(
                        &shadow,
                        start_t(clearance, lit.to_light, normal),
                        shadow_end(lit.distance),
                    )
            })
            .map(|(index, lit, light)| {
                let divisor = match *light {
                    Light::Point {
                        attenuation: [c, l, q],
                        ..
                    } => Some(c + l * lit.distance + q * lit.distance * lit.distance),
                    Light::Directional { .. } => None,
                };
                (index, lit, divisor)
            })
            .collect();
        let mut one = Seen {
            pixel,
            view: ray.direction,
            normal,
            stretch,
            ambient: scene.ambient * surface.diffuse(),
            surface,
            lights,
            rest: Vec3A::ZERO,
        };
        let colour = tracer.colour(&ray, Some(&hit), &mut scratch);
        let (highlight, count) = (HighlightForm::default(), scene.lights.len());
        one.rest = colour
            - shade(
                &one,
                &course,
                Cosine::Clamped,
                highlight,
                count,
                settings.specular,
            );
        seen.push(one);
    }
    if seen.is_empty() {
        return None;
    }
    let lights = scene.lights.len();
    let falloff = settings.specular;
    let cost_with = |numbers: &[f64], cosine: Cosine, highlight: HighlightForm| -> f64 {
        let mut sum = 0.0;
        for one in &seen {
            if let Some(shaded) = shaded {
                let colour = shade(one, numbers, cosine, highlight, lights, falloff);
                sum += levels_off(colour, shaded.pixels[one.pixel]);
            }
            if let Some(normals) = normals {
                let length = length(one, numbers);
                sum += levels_off((one.normal * length).abs(), normals.pixels[one.pixel]);
            }
        }
        sum / seen.len() as f64
    };
    let cost =
        |numbers: &[f64], cosine: Cosine| cost_with(numbers, cosine, HighlightForm::default());
    let course_cost = cost(&course, Cosine::Clamped);
    // N·L taken otherwise only where some light is behind a surface it would light.
    let behind = seen.iter().any(|one| {
        one.lights
            .iter()
            .any(|(_, light, _)| one.normal.dot(light.to_light) < 0.0)
    });
    // Each number's steps and round values: the divisor's in the file's terms' scale.
    let scale_of = |index: usize| match index {
        5..=7 => [c, l, q].into_iter().fold(0.0, f64::max).max(1e-3),
        _ => 1.0,
    };
    // The course's value first: a number that changes nothing is taken as the course's.
    let round_values = |index: usize| {
        let mut round: Vec<f64> = vec![course[index]];
        round.extend(ROUND[index]);
        match index {
            0 => round.push(lights as f64),
            5..=7 => round.extend([c, l, q]),
            _ => {}
        }
        round
    };
    // The numbers fitted with the highlight's form `highlight`: with each way of taking N·L.
    let search_numbers = |highlight: HighlightForm| {
        let cost = |numbers: &[f64], cosine: Cosine| cost_with(numbers, cosine, highlight);
        let mut best: Option<([f64; NUMBERS], Cosine, f64)> = None;
        for cosine in [Cosine::Clamped, Cosine::Absolute, Cosine::Signed]
            .into_iter()
            .filter(|&c| c == Cosine::Clamped || behind)
        {
            // Each stage's numbers alone first (the normal's length and a light's divisor trade
            // off against each other: searched together from the course's, they settle anywhere
            // along the valley between), the best of those, then every number from there.
            let search = |start: [f64; NUMBERS], searched: &[usize]| {
                search_from(start, searched, |numbers| cost(numbers, cosine), &scale_of)
            };
            let mut at = course;
            let mut value = f64::INFINITY;
            for stage in STAGES {
                let searched: Vec<usize> =
                    stage.iter().copied().filter(|i| free.contains(i)).collect();
                if searched.is_empty() {
                    continue;
                }
                let (there, cost_there) = search(course, &searched);
                if cost_there < value {
                    (at, value) = (there, cost_there);
                }
            }
            if value > 0.0 {
                let (there, cost_there) = search(at, &free);
                if cost_there < value {
                    (at, value) = (there, cost_there);
                }
            }
            // Every number at the round value nearest it at once, where that costs (almost)
            // nothing (numbers that trade off against each other may each sit off their round value
            // while the others do); then each number alone, again while any moves (one number may
            // round only once another has).
            let nearest: [f64; NUMBERS] = std::array::from_fn(|index| {
                round_values(index)
                    .into_iter()
                    .min_by(|a, b| (a - at[index]).abs().total_cmp(&(b - at[index]).abs()))
                    .unwrap_or(at[index])
            });
            // A round value is taken where the picture is (almost) as near as the search's least.
            let near_enough = value * (1.0 + ROUND_SHARE) + ROUND_LEVELS;
            let mut current = value;
            let there = cost(&nearest, cosine);
            if there <= near_enough {
                (at, current) = (nearest, there);
            }
            for _ in 0..at.len() {
                let mut moved = false;
                for index in 0..at.len() {
                    // The nearest of its round values (the course's first among equals).
                    let mut choice = (at[index], current);
                    for r in round_values(index) {
                        let mut tried = at;
                        tried[index] = r;
                        let there = cost(&tried, cosine);
                        if there <= near_enough && there < choice.1 {
                            choice = (r, there);
                        }
                    }
                    if choice.0 != at[index] {
                        at[index] = choice.0;
                        current = choice.1;
                        moved = true;
                    }
                }
                if !moved {
                    break;
                }
            }
            // A divisor a person writes whole (d², d, none, the file's terms reversed) where
            // the picture cannot tell it from the terms found, one by one, round as they are.
            if free.contains(&5) && [at[5], at[6], at[7]] != [c, l, q] {
                for whole in [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [q, l, c]] {
                    let mut tried = at;
                    tried[5..8].copy_from_slice(&whole);
                    let there = cost(&tried, cosine);
                    if there <= near_enough {
                        (at, current) = (tried, there);
                        break;
                    }
                }
            }
            let value = current;
            if best.is_none_or(|(_, _, v)| value < v) {
                best = Some((at, cosine, value));
            }
        }
        best
    };
    let (mut at, mut cosine, mut value) = search_numbers(HighlightForm::default())?;
    // The highlight's form: a highlight is a few pixels of a picture, too few to steer the
    // numbers' search, which may settle on numbers that draw it another way; so its family is
    // searched at the course's numbers and at those found, and the numbers again with each form
    // found.
    let mut highlight = HighlightForm::default();
    if shaded.is_some() && value > 0.0 {
        let mut forms: Vec<HighlightForm> = Vec::new();
        for (numbers, taken) in [(course, Cosine::Clamped), (at, cosine)] {
            let course_cost = cost(&numbers, taken);
            let (form, _) = fit_highlight(|form| cost_with(&numbers, taken, form), course_cost);
            if form != HighlightForm::default() && !forms.contains(&form) {
                forms.push(form);
            }
        }
        for form in forms {
            if let Some((there, taken, cost_there)) = search_numbers(form)
                && cost_there < value
            {
                (at, cosine, value, highlight) = (there, taken, cost_there, form);
            }
        }
    }
    let unchanged =
        at == course && cosine == Cosine::Clamped && highlight == HighlightForm::default();
    if value >= course_cost * (1.0 - least_share) || unchanged {
        return None;
    }
    name(at, cosine, highlight, lights, [c, l, q])
}

/// The member of the highlights' family that draws the picture nearest (by `cost`, the
/// course's costing `course`), with its cost; the course's unless another is nearer by more
/// than a round value's allowance. H's scale is searched once the rest of the form is chosen.
fn fit_highlight(cost: impl Fn(HighlightForm) -> f64, course: f64) -> (HighlightForm, f64) {
    let mut shapes = Vec::new();
    for view_along_ray in [false, true] {
        for base in [
            HighlightBase::Clamped,
            HighlightBase::Absolute,
            HighlightBase::Whole,
        ] {
            for ungated in [false, true] {
                let form = HighlightForm {
                    view_along_ray,
                    base,
                    ungated,
                    ..HighlightForm::default()
                };
                shapes.push(HighlightForm {
                    mirror: true,
                    ..form
                });
                for half_not_unit in [false, true] {
                    for half_scale in HALF_SCALES {
                        shapes.push(HighlightForm {
                            half_not_unit,
                            half_scale,
                            ..form
                        });
                    }
                }
            }
        }
    }
    // Each shape in each colour, the course's colour first.
    let mut forms: Vec<HighlightForm> = HighlightColour::ALL
        .into_iter()
        .flat_map(|colour| {
            shapes
                .iter()
                .map(move |&shape| HighlightForm { colour, ..shape })
        })
        .collect();
    // Last: where a vector that puts the highlight nowhere draws the same, the vector is named.
    let absent = HighlightForm {
        absent: true,
        ..HighlightForm::default()
    };
    forms.push(absent);
    // A form is taken only where it is nearer than the course's by more than the allowance
    // within which round values are taken: one that changes nothing is the course's.
    let enough = |value: f64| value < course - course * ROUND_SHARE - ROUND_LEVELS;
    let Some((mut form, mut value)) = forms
        .into_iter()
        .map(|form| (form, cost(form)))
        .filter(|&(_, value)| enough(value))
        .min_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return (HighlightForm::default(), course);
    };
    if !form.mirror && value > 0.0 {
        let start = [Start {
            value: f64::from(form.half_scale),
            step: 0.25,
        }];
        let scaled = |scale: f64| HighlightForm {
            half_scale: scale as f32,
            ..form
        };
        let Ok(least) = minimise(&start, EVALUATIONS, |x| {
            Ok::<_, std::convert::Infallible>(cost(scaled(x[0])))
        });
        // The round scale where it is as near.
        let near_enough = least.value * (1.0 + ROUND_SHARE) + ROUND_LEVELS;
        if least.value < value && (value > near_enough || !HALF_SCALES.contains(&form.half_scale)) {
            (form, value) = (scaled(least.at[0]), least.value);
        }
    }
    // An H scaled to nothing draws no highlight (but for an exponent of 0): where the absent
    // highlight is as near, it is the one named.
    if !form.absent && !form.mirror && form.half_scale.abs() < 1e-3 {
        let nothing = cost(absent);
        if nothing <= value * (1.0 + ROUND_SHARE) + ROUND_LEVELS {
            (form, value) = (absent, nothing);
        }
    }
    (form, value)
}

/// The least of `cost` over the numbers `searched` (the others as in `start`), by the simplex
/// searched again from where each search ends, by smaller steps (one search may settle short of
/// the least in a valley).
fn search_from(
    start: [f64; NUMBERS],
    searched: &[usize],
    cost: impl Fn(&[f64; NUMBERS]) -> f64,
    scale_of: &impl Fn(usize) -> f64,
) -> ([f64; NUMBERS], f64) {
    // `at` with the searched numbers set to `values`.
    let set = |at: [f64; NUMBERS], values: &[f64]| {
        let mut numbers = at;
        for (&index, &v) in searched.iter().zip(values) {
            numbers[index] = v;
        }
        numbers
    };
    let (mut at, mut value) = (start, cost(&start));
    for restart in 0..RESTARTS {
        let scale = 0.5f64.powi(restart as i32);
        let starts: Vec<Start> = searched
            .iter()
            .map(|&index| Start {
                value: at[index],
                step: STEPS[index] * scale * scale_of(index),
            })
            .collect();
        let evaluations = EVALUATIONS * searched.len();
        let least = match minimise(&starts, evaluations, |x| {
            Ok::<_, std::convert::Infallible>(cost(&set(at, x)))
        }) {
            Ok(least) => least,
            Err(never) => match never {},
        };
        let better = least.value < value - 1e-6;
        if least.value < value {
            at = set(at, &least.at);
            value = least.value;
        }
        if !better || value == 0.0 {
            break;
        }
    }
    (at, value)
}

/// The colour the family draws at `one` with `numbers` and the highlight's form (unclamped).
fn shade(
    one: &Seen<'_>,
    numbers: &[f64],
    cosine: Cosine,
    highlight: HighlightForm,
    lights: usize,
    falloff: crate::scene::SpecularFalloff,
) -> Vec3A {
    // (Point lights dimmed below, from the file's divisor.)
    let fault = weighed(numbers, cosine, false, highlight);
    let normal = one.normal * length(one, numbers);
    let mut colour = fault.ambient(one.ambient, lights) + one.rest;
    for &(index, lit, divisor) in &one.lights {
        // A point light as the student dims it: the file's divisor taken back, theirs applied.
        let light = match divisor {
            Some(course) => {
                let d = f64::from(lit.distance);
                let theirs = numbers[5] + numbers[6] * d + numbers[7] * d * d;
                Illumination {
                    colour: lit.colour * (f64::from(course) / theirs.max(1e-9)) as f32,
                    ..lit
                }
            }
            None => lit,
        };
        colour += fault.light(
            &|n, f, h| {
                one.surface
                    .shade(n, one.view, light.to_light, light.colour, f, h)
            },
            normal,
            (
                light.to_light,
                crate::trace::LightPlace { index, of: lights },
            ),
            falloff,
            crate::scene::Highlight::Course,
        );
    }
    colour
}

/// The shading the numbers say, as the fault library plants it.
/// (`divided`: with the numbers' own divisor for point lights.)
fn weighed(
    numbers: &[f64],
    cosine: Cosine,
    divided: bool,
    highlight: HighlightForm,
) -> ShadingFault {
    ShadingFault::Weighed {
        ambient: numbers[0] as f32,
        power: numbers[1] as f32,
        cosine,
        divisor: divided.then(|| [numbers[5], numbers[6], numbers[7]].map(|n| n as f32)),
        highlight,
    }
}

/// The normal's length at `one` with `numbers`.
fn length(one: &Seen<'_>, numbers: &[f64]) -> f32 {
    let numbers = [numbers[2], numbers[3], numbers[4]].map(|n| n as f32);
    length_from(numbers, one.stretch)
}

/// How many levels `colour` lands from the student's bytes, summed over the channels, each
/// less [`SLACK`] and at most [`CAP`].
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
                ((level - (f64::from(s) + 0.5)).abs() - SLACK).clamp(0.0, CAP)
            }
        })
        .sum()
}

/// The faults fitted numbers name, with the numbers that show them; none where a number off the
/// course's lands on no fault. `terms` are the file's attenuation (c, l, q).
fn name(
    at: [f64; NUMBERS],
    cosine: Cosine,
    highlight: HighlightForm,
    lights: usize,
    [c, l, q]: [f64; 3],
) -> Option<(Vec<Planted>, Named)> {
    let fault = |name: &str| FAULTS.iter().find(|f| f.name == name);
    let mut faults: Vec<&'static Fault> = Vec::new();
    let mut numbers: Vec<(&'static str, f64)> = Vec::new();
    let mut plants: Vec<Planted> = Vec::new();
    let [ambient, power, a, b, n, x, y, z] = at;
    let divided = [x, y, z] != [c, l, q];
    let highlighted = highlight != HighlightForm::default();
    let unclamped = cosine != Cosine::Clamped;
    if ambient != 1.0 || power != 1.0 || unclamped || divided || highlighted {
        if ambient == 0.0 {
            faults.push(fault("ambient_missing")?);
        } else if ambient == lights as f64 && lights > 1 {
            faults.push(fault("ambient_per_light")?);
        } else if ambient != 1.0 {
            return None;
        }
        if power == 2.0 {
            faults.push(fault("cosine_twice")?);
        } else if power != 1.0 {
            return None;
        }
        match cosine {
            Cosine::Clamped => {}
            Cosine::Absolute => faults.push(fault("shade_back_abs")?),
            Cosine::Signed => faults.push(fault("diffuse_unclamped")?),
        }
        if divided {
            faults.push(fault("attenuation")?);
            // The listed forms by their numbers; any other divisor by its terms.
            let forms = [[1.0, 0.0, 0.0], [c, l + q, 0.0], [q, l, c]];
            match forms.iter().position(|form| *form == [x, y, z]) {
                Some(form) => numbers.push(("form", form as f64)),
                None => numbers.extend([("divisor: constant", x), ("times d", y), ("times d²", z)]),
            }
        }
        if !highlight.absent && (highlight.ungated || highlight.base != HighlightBase::Clamped) {
            faults.push(fault("specular_unclamped")?);
            numbers.extend(
                highlight
                    .ungated
                    .then_some(("highlight where N·L < 0", 1.0)),
            );
            match highlight.base {
                HighlightBase::Clamped => {}
                HighlightBase::Absolute => numbers.push(("|N·H|", 1.0)),
                HighlightBase::Whole => numbers.push(("N·H unclamped", 1.0)),
            }
        }
        let course_half = HighlightForm {
            ungated: highlight.ungated,
            base: highlight.base,
            colour: highlight.colour,
            ..HighlightForm::default()
        };
        if let Some(form) = highlight.colour.form().filter(|_| !highlight.absent) {
            faults.push(fault("specular_colour")?);
            numbers.push(("form", form as f64));
        }
        if highlight.absent {
            faults.push(fault("specular_missing")?);
        } else if highlight != course_half {
            faults.push(fault("half_vector")?);
            let flags = [
                ("V along the ray", highlight.view_along_ray),
                ("Phong's R·V", highlight.mirror),
                ("H not unit", highlight.half_not_unit),
            ];
            numbers.extend(
                flags
                    .into_iter()
                    .filter(|f| f.1)
                    .map(|(what, _)| (what, 1.0)),
            );
            if highlight.half_scale != 1.0 {
                numbers.push(("H scaled by", f64::from(highlight.half_scale)));
            }
        }
        if ambient != 1.0 || power != 1.0 || unclamped {
            numbers.push(("ambient weight", ambient));
            numbers.push(("power of N·L", power));
        }
        plants.push(Planted::Shading(weighed(&at, cosine, divided, highlight)));
    }
    if [a, b, n] != [1.0, 0.0, 0.0] {
        faults.push(fault("normal_length")?);
        numbers.extend([
            ("normal's 1/|n|²: constant", a),
            ("times |Aᵀn|²", b),
            ("times (t·n)²", n),
        ]);
        plants.push(Planted::Hit(HitFault::NormalLength(
            [a, b, n].map(|n| n as f32),
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
        // 0.5 is level 127.5: a student's 120 is 7.0 below, 6.0 past the slack.
        assert!((levels_off(Vec3A::new(0.5, 0.2, 0.2), [120, 51, 51]) - 6.0).abs() < 1e-4);
        // Rounded where the course truncates: 0.5 is written 128 (and 0.2, 51.0, stays 51).
        assert_eq!(levels_off(Vec3A::new(0.5, 0.2, 0.2), [128, 51, 51]), 0.0);
        assert_eq!(levels_off(Vec3A::ONE, [0, 0, 0]), 3.0 * CAP);
    }

    #[test]
    fn numbers_land_on_names() {
        let named = |at: [f64; 5], cosine| {
            let at = [at[0], at[1], at[2], at[3], at[4], 1.0, 0.0, 0.0];
            name(at, cosine, HighlightForm::default(), 2, [1.0, 0.0, 0.0])
                .map(|(_, (faults, _))| faults.iter().map(|f| f.name).collect::<Vec<_>>())
        };
        assert_eq!(
            named([2.0, 1.0, 1.0, 0.0, 0.0], Cosine::Clamped),
            Some(vec!["ambient_per_light"])
        );
        assert_eq!(
            named([1.0, 2.0, 1.0, 0.0, 1.0], Cosine::Absolute),
            Some(vec!["cosine_twice", "shade_back_abs", "normal_length"])
        );
        assert_eq!(
            named([1.0, 1.0, 1.0, 0.0, 0.0], Cosine::Signed),
            Some(vec!["diffuse_unclamped"])
        );
        assert_eq!(named([0.7, 1.0, 1.0, 0.0, 0.0], Cosine::Clamped), None);
        assert_eq!(named([1.0, 1.5, 1.0, 0.0, 0.0], Cosine::Clamped), None);
    }

    #[test]
    fn highlight_forms_land_on_names() {
        let course = [1.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let named = |highlight: HighlightForm| {
            name(course, Cosine::Clamped, highlight, 1, [1.0, 0.0, 0.0]).map(
                |(_, (faults, numbers))| {
                    let faults: Vec<&str> = faults.iter().map(|f| f.name).collect();
                    (faults, numbers)
                },
            )
        };
        let form = HighlightForm::default();
        let absolute = HighlightForm {
            ungated: true,
            base: HighlightBase::Absolute,
            ..form
        };
        assert_eq!(
            named(absolute),
            Some((
                vec!["specular_unclamped"],
                vec![("highlight where N·L < 0", 1.0), ("|N·H|", 1.0)]
            ))
        );
        let halved = HighlightForm {
            half_not_unit: true,
            half_scale: 0.5,
            ..form
        };
        assert_eq!(
            named(halved),
            Some((
                vec!["half_vector"],
                vec![("H not unit", 1.0), ("H scaled by", 0.5)]
            ))
        );
        let both = HighlightForm {
            view_along_ray: true,
            mirror: true,
            ungated: true,
            ..form
        };
        assert_eq!(
            named(both).map(|(faults, _)| faults),
            Some(vec!["specular_unclamped", "half_vector"])
        );
        // No highlight at all, whatever else the form says: the term is missing, and nothing of
        // H or the clamp is named.
        let absent = HighlightForm {
            absent: true,
            ungated: true,
            ..form
        };
        assert_eq!(named(absent), Some((vec!["specular_missing"], Vec::new())));
        // White where the material's specular colour belongs, with H from the ray: both named.
        let white = HighlightForm {
            colour: HighlightColour::White,
            view_along_ray: true,
            ..form
        };
        assert_eq!(
            named(white),
            Some((
                vec!["specular_colour", "half_vector"],
                vec![("form", 1.0), ("V along the ray", 1.0)]
            ))
        );
    }

    #[test]
    fn a_picture_without_highlights_fits_the_absent_highlight() {
        // A picture without highlights: a member that draws none costs nothing, the others
        // what their highlights are worth.
        let cost = |form: HighlightForm| if form.absent { 0.0 } else { 10.0 };
        let (form, value) = fit_highlight(cost, 11.0);
        assert!(form.absent, "{form:?}");
        assert_eq!(value, 0.0);
    }
}
