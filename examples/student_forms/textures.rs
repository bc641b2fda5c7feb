//! Textures' weights as the forms write them.

use raycast::Vec3A;
use raycast::glam::DVec3;
use raycast::parse::description::Pattern;
use raycast::scene::Texture;
use raycast::scene::perlin::{noise as perlin_noise, octave_noise};

/// Where `point` falls between a texture's materials, Marble's frequency in turns.
pub(crate) fn marble_in_turns(texture: &Texture, point: Vec3A) -> f32 {
    marble_with(texture, point, |p, frequency| {
        std::f64::consts::TAU * frequency * p.x
    })
}

/// Where `point` falls between a texture's materials, Marble's stripes running across y, not x.
pub(crate) fn marble_along_y(texture: &Texture, point: Vec3A) -> f32 {
    marble_with(texture, point, |p, frequency| frequency * p.y)
}

/// Where `point` falls between a Marble's materials with the sine's phase (before the noise)
/// the student's `phase` of the texture's point and the file's frequency.
fn marble_with(texture: &Texture, point: Vec3A, phase: impl Fn(DVec3, f64) -> f64) -> f32 {
    let Pattern::Marble {
        octaves,
        frequency,
        amplitude,
    } = texture.pattern
    else {
        return texture.weight(point);
    };
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    let noise = octave_noise(p.x, p.y, p.z, octaves);
    (0.5 * ((phase(p, frequency) + amplitude * noise).sin() + 1.0)) as f32
}

/// Where `point` falls between a texture's materials, its noise summed from the second octave:
/// `noise(2^i p) / 2^i` for i = 1 to octaves.
pub(crate) fn noise_from_second_octave(texture: &Texture, point: Vec3A) -> f32 {
    with_noise(texture, point, |p, octaves| {
        (1..=octaves)
            .map(|i| {
                let scale = f64::from(1u32 << i);
                perlin_noise(p.x * scale, p.y * scale, p.z * scale) / scale
            })
            .sum()
    })
}

/// Where `point` falls between a texture's materials, its octaves summed unweighed:
/// `noise(2^i p)` for i = 0 to octaves - 1.
pub(crate) fn noise_octaves_unweighed(texture: &Texture, point: Vec3A) -> f32 {
    with_noise(texture, point, |p, octaves| {
        (0..octaves)
            .map(|i| {
                let scale = f64::from(1u32 << i);
                perlin_noise(p.x * scale, p.y * scale, p.z * scale)
            })
            .sum()
    })
}

/// Where `point` falls between a texture's materials, with `noise(p, octaves)` the student's
/// sum of octaves at the texture's point p.
fn with_noise(texture: &Texture, point: Vec3A, noise: impl Fn(DVec3, u32) -> f64) -> f32 {
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    let weight = match texture.pattern {
        Pattern::Checkerboard => return texture.weight(point),
        Pattern::Noise { octaves } => 0.5 * (noise(p, octaves) + 1.0),
        Pattern::Marble {
            octaves,
            frequency,
            amplitude,
        } => 0.5 * ((frequency * p.x + amplitude * noise(p, octaves)).sin() + 1.0),
        Pattern::Wood {
            octaves,
            frequency,
            amplitude,
        } => {
            let radius = (p.x * p.x + p.z * p.z).sqrt();
            let ring = 0.5 * ((frequency * radius + amplitude * noise(p, octaves)).sin() + 1.0);
            ring * ring * ring
        }
    };
    weight.clamp(0.0, 1.0) as f32
}

/// Where `point` falls between a texture's materials, its noise and marble sine taken as the
/// weight itself, not mapped from [-1, 1] onto [0, 1] by (1 + x) / 2 (clamped as a weight is).
pub(crate) fn noise_unmapped(texture: &Texture, point: Vec3A) -> f32 {
    match noise_or_sine(texture, point) {
        Some(value) => value.clamp(0.0, 1.0) as f32,
        None => texture.weight(point),
    }
}

/// Noise's sum, or Marble's sine, at `point`, before it is mapped onto a weight; `None` for
/// the other textures.
fn noise_or_sine(texture: &Texture, point: Vec3A) -> Option<f64> {
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    match texture.pattern {
        Pattern::Noise { octaves } => Some(octave_noise(p.x, p.y, p.z, octaves)),
        Pattern::Marble {
            octaves,
            frequency,
            amplitude,
        } => Some((frequency * p.x + amplitude * octave_noise(p.x, p.y, p.z, octaves)).sin()),
        _ => None,
    }
}

/// The weight of the second material, the student's `N * first + (1 - N) * second` read as
/// the course's `(1 - w) * first + w * second`: w = (1 - N) with N mapped onto 0…1 as the
/// course maps it.
pub(crate) fn noise_blended_the_other_way(texture: &Texture, point: Vec3A) -> f32 {
    match noise_or_sine(texture, point) {
        Some(value) => (1.0 - (value + 1.0) / 2.0) as f32,
        None => texture.weight(point),
    }
}

/// A checkerboard whose cell along each axis is `cell(x)` (1 or 0), their parities added.
pub(crate) fn checker(texture: &Texture, point: Vec3A, cell: impl Fn(f64) -> f64) -> f32 {
    let Pattern::Checkerboard = texture.pattern else {
        return texture.weight(point);
    };
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    // Cell (0, 0, 0) gives 1 on each axis, and the course's weight 0 there.
    let ones = cell(p.x) + cell(p.y) + cell(p.z);
    (1.0 - ones.rem_euclid(2.0)) as f32
}
