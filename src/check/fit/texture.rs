//! Marble and Wood, fitted from the pixels: where the objects stand in place, a textured pixel's
//! colour lies between the colours its two materials would give it, so the student's weight
//! there can be read off the picture; and the course's formula, sin(frequency·u + amplitude·
//! noise), can be searched for the frequency, amplitude and octaves that give those weights
//! without a render per guess. A render's distance from the picture swings with every stripe
//! (a frequency 1% off puts the stripes of a large object out of phase); the weights do not.

use glam::Vec3A;

use super::camera::Named;
use crate::camera::pixel_to_screen;
use crate::check::faults::{FAULTS, LineScene, Planted, TextureFault};
use crate::parse::description::Pattern;
use crate::sample::Sampler;
use crate::scene::perlin::octave_noise_weighed;
use crate::scene::{Material, Surface};
use crate::shade::Image;
use crate::trace::{Scratch, TraceSeam, Tracer};

/// At most this many pixels are read (evenly spread over the picture).
const MAX_PIXELS: usize = 3000;
/// A pixel's two materials must differ by this much (in a channel's 0…1) for its weight to be
/// read.
const APART: f32 = 0.1;
/// The noises tried: how many octaves more than the file's, the first octave's frequency (its
/// weight the frequency's inverse), and each octave's weight over the last's: the file's, one
/// octave fewer and one more, the octaves summed from the second, and summed unweighed.
const NOISES: [(i32, f64, f64); 5] = [
    (0, 1.0, 0.5),
    (-1, 1.0, 0.5),
    (1, 1.0, 0.5),
    (0, 2.0, 0.5),
    (0, 1.0, 1.0),
];
/// The frequency's and amplitude's factors searched, evenly in their logarithm...
const RANGE: (f64, f64) = (0.1, 10.0);
/// ...at this many points for the frequency (a step of a quarter of a percent)...
const FREQUENCY_STEPS: usize = 1900;
/// ...and this many for the amplitude.
const AMPLITUDE_STEPS: usize = 200;
/// A fit must bring the weights this much nearer than the file's numbers do (a mean of the
/// weight's 0…1).
const GAIN: f64 = 0.02;
/// A factor is taken at a round value where the weights are no further for it than this share.
const ROUND_SHARE: f64 = 0.02;

/// A pixel the fit reads: the student's weight there, and what the formula takes.
struct Read {
    /// The student's weight of the second material.
    weight: f64,
    /// Along what the sine runs, times the file's frequency, for each axis Marble's sine may
    /// be written along: texture space's x (the course's), y or z; Wood's distance from its
    /// y axis, the same for all three.
    phase: [f64; 3],
    /// The file's amplitude.
    amplitude: f64,
    /// The noise in each of the ways of [`NOISES`].
    noise: [f64; NOISES.len()],
}

/// Weighs every texture at `0` or `1`: the colour of a pixel as each of its materials alone
/// would give it.
#[derive(Debug, Clone, Copy)]
struct Forced(f32);

impl TraceSeam for Forced {
    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        surface.weigh(point, |_, _| self.0);
    }
}

/// The line's Marble and Wood fitted to the student's shaded picture: the plant and the fault
/// its numbers name, where they bring the picture's weights nearer than the file's numbers.
pub fn fit_texture(line: &LineScene, shaded: &Image) -> Option<(Planted, Named)> {
    let options = &line.options;
    if options.sampling.sampler != Sampler::Uniform(1) || options.trace.visualize_grid {
        return None;
    }
    let read = read_weights(line, shaded);
    if read.is_empty() {
        return None;
    }
    let off_along = |axis: usize, octaves: usize, frequency: f64, amplitude: f64| {
        read.iter()
            .map(|r| {
                let w = 0.5
                    * ((frequency * r.phase[axis] + amplitude * r.amplitude * r.noise[octaves])
                        .sin()
                        + 1.0);
                (w - r.weight).abs()
            })
            .sum::<f64>()
            / read.len() as f64
    };
    let course = off_along(0, 0, 1.0, 1.0);
    let factor = |steps: usize, i: usize| {
        (RANGE.0.ln() + (RANGE.1.ln() - RANGE.0.ln()) * i as f64 / (steps - 1) as f64).exp()
    };
    let mut best = (0usize, 0usize, 1.0, 1.0, course);
    // Along x with every noise; along y and z (a sine written along another axis) with the
    // file's noise alone.
    let searches = (0..NOISES.len())
        .map(|octaves| (0, octaves))
        .chain([(1, 0), (2, 0)]);
    for (axis, octaves) in searches {
        let off = |octaves: usize, frequency: f64, amplitude: f64| {
            off_along(axis, octaves, frequency, amplitude)
        };
        // The frequency first (the stripes' spacing), then the amplitude (how far the noise
        // bends them) at that frequency, then the frequency again at that amplitude.
        let mut frequency = 1.0;
        let mut amplitude = 1.0;
        for _ in 0..2 {
            frequency = least(
                (0..FREQUENCY_STEPS).map(|i| factor(FREQUENCY_STEPS, i)),
                |f| off(octaves, f, amplitude),
            );
            amplitude = least(
                (0..AMPLITUDE_STEPS)
                    .map(|i| factor(AMPLITUDE_STEPS, i))
                    .chain([1.0]),
                |a| off(octaves, frequency, a),
            );
        }
        // The amplitude's coarse step (2%) refined around its best, a tenth of a percent.
        let step = (RANGE.1 / RANGE.0).ln() / (AMPLITUDE_STEPS - 1) as f64;
        let around = amplitude;
        amplitude = least(
            (-20..=20).map(|k| around * (step * f64::from(k) / 20.0).exp()),
            |a| off(octaves, frequency, a),
        );
        let value = off(octaves, frequency, amplitude);
        if value < best.4 {
            best = (axis, octaves, frequency, amplitude, value);
        }
    }
    let (axis, octaves, mut frequency, mut amplitude, value) = best;
    let off = |octaves: usize, frequency: f64, amplitude: f64| {
        off_along(axis, octaves, frequency, amplitude)
    };
    if value > course - GAIN {
        return None;
    }
    // Each factor as a person would write it, where the weights are as near for it.
    let near = |o: usize, f: f64, a: f64| off(o, f, a) <= value * (1.0 + ROUND_SHARE) + 1e-4;
    if let Some(round) = rounded(frequency).find(|&f| near(octaves, f, amplitude)) {
        frequency = round;
    }
    if let Some(round) = rounded(amplitude).find(|&a| near(octaves, frequency, a)) {
        amplitude = round;
    }
    let fault = FAULTS.iter().find(|f| f.name == "noise_constants")?;
    let (more, noise_scale, octave_ratio) = NOISES[octaves];
    let mut numbers = Vec::new();
    if more != 0 {
        numbers.push(("octaves", f64::from(more)));
    }
    if noise_scale != 1.0 {
        numbers.push(("first octave's frequency", noise_scale));
    }
    if octave_ratio != 0.5 {
        numbers.push(("each octave's weight over the last's", octave_ratio));
    }
    if frequency != 1.0 {
        numbers.push(("frequency", frequency));
    }
    if amplitude != 1.0 {
        numbers.push(("amplitude", amplitude));
    }
    if axis != 0 {
        numbers.push(("axis", axis as f64));
    }
    if numbers.is_empty() {
        return None;
    }
    let plant = Planted::Texture(TextureFault::Constants {
        octaves: more,
        frequency: frequency as f32,
        amplitude: amplitude as f32,
        noise_scale: noise_scale as f32,
        octave_ratio: octave_ratio as f32,
        axis: axis as u8,
    });
    Some((plant, (vec![fault], numbers)))
}

/// The value of `values` where `f` is least (1 where there is none).
fn least(values: impl Iterator<Item = f64>, f: impl Fn(f64) -> f64) -> f64 {
    values
        .map(|x| (x, f(x)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(1.0, |(x, _)| x)
}

/// The values near `x` a person would write, roundest first: 1, a multiple of π, a fraction of
/// small numbers, two or three significant digits.
fn rounded(x: f64) -> impl Iterator<Item = f64> {
    let pi = std::f64::consts::PI;
    let fraction = |of: f64| {
        (1..=8u32).find_map(move |d| {
            let n = (x / of * f64::from(d)).round();
            let close = n > 0.0 && (n * of / f64::from(d) / x - 1.0).abs() <= 0.01;
            close.then(|| n * of / f64::from(d))
        })
    };
    let significant = move |digits: i32| {
        let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
        (x * scale).round() / scale
    };
    [Some(1.0), fraction(1.0), fraction(pi)]
        .into_iter()
        .flatten()
        .chain([2, 3].map(significant))
}

/// The weight the student's picture gives each textured pixel the fit can read.
fn read_weights(line: &LineScene, shaded: &Image) -> Vec<Read> {
    let options = &line.options;
    let scene = &line.scene;
    let (width, height) = (options.width, options.height);
    if (shaded.width, shaded.height) != (width, height) {
        return Vec::new();
    }
    let pixels = (width * height) as usize;
    let every = pixels.div_ceil(MAX_PIXELS).max(1);
    let first = Tracer::with_variant(scene, options.trace, Forced(0.0));
    let second = Tracer::with_variant(scene, options.trace, Forced(1.0));
    let mut scratch = Scratch::default();
    let mut read = Vec::new();
    for pixel in (0..pixels).step_by(every) {
        let (i, row) = (pixel as u32 % width, pixel as u32 / width);
        let (u, v) = pixel_to_screen(i, height - 1 - row, width, height);
        let ray = scene.camera.ray(u, v);
        let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) else {
            continue;
        };
        let Material::Texture(texture) = scene.materials.get(hit.material) else {
            continue;
        };
        let p = texture
            .to_texture
            .transform_point3(ray.at(hit.t).as_dvec3());
        let (octaves, frequency, amplitude, along) = match texture.pattern {
            Pattern::Marble {
                octaves,
                frequency,
                amplitude,
            } => (octaves, frequency, amplitude, [p.x, p.y, p.z]),
            Pattern::Wood {
                octaves,
                frequency,
                amplitude,
            } => (
                octaves,
                frequency,
                amplitude,
                [(p.x * p.x + p.z * p.z).sqrt(); 3],
            ),
            Pattern::Checkerboard | Pattern::Noise { .. } => continue,
        };
        let a = first.colour(&ray, Some(&hit), &mut scratch);
        let b = second.colour(&ray, Some(&hit), &mut scratch);
        // Unclamped colours only: past 1 a channel no longer says the weight.
        let inside = |c: Vec3A| c.min_element() >= 0.0 && c.max_element() <= 1.0;
        let apart = b - a;
        if !inside(a) || !inside(b) || apart.abs().max_element() < APART {
            continue;
        }
        let student = Vec3A::from(shaded.pixels[pixel].map(|c| (f32::from(c) + 0.5) / 255.0));
        let weight = ((student - a).dot(apart) / apart.length_squared()).clamp(0.0, 1.0);
        read.push(Read {
            weight: f64::from(weight),
            phase: along.map(|a| frequency * a),
            amplitude,
            noise: NOISES.map(|(more, scale, ratio)| {
                let q = p * scale;
                let octaves = octaves.saturating_add_signed(more);
                octave_noise_weighed(q.x, q.y, q.z, octaves, ratio) / scale
            }),
        });
    }
    read
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_values_a_person_writes() {
        let first = |x: f64| rounded(x).next().unwrap();
        assert_eq!(first(1.001), 1.0);
        // 19/3 is tried before 2π: the weights choose between them.
        let near: Vec<f64> = rounded(std::f64::consts::TAU * 0.99998).collect();
        assert!((near[1] - 19.0 / 3.0).abs() < 1e-12, "{near:?}");
        assert!((near[2] - std::f64::consts::TAU).abs() < 1e-12, "{near:?}");
        let third = rounded(1.3335).find(|&r| r != 1.0).unwrap();
        assert!((third - 4.0 / 3.0).abs() < 1e-12);
    }
}
