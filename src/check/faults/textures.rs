//! Faults of assignment 6's solid textures: where a hit falls in texture space, and which
//! cube of the checkerboard it is in.

use glam::{DMat4, Vec3A};

use super::{Candidate, Fault, LineScene, Planted};
use crate::parse::description::{MaterialSpec, Pattern, TextureSpec};
use crate::scene::Texture;

/// How a student's tracer weighs a texture at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TextureFault {
    /// The checkerboard's cubes numbered by truncating toward zero, not by flooring: the
    /// cubes either side of each axis plane through the origin are one.
    CheckerTruncated,
    /// The cell per axis tested as C's `fmod(x, 2) < 1`, true for every negative coordinate.
    CheckerRemainder,
    /// The sum of the floors tested as C's `sum % 2 == 1`, which is −1 for a negative odd
    /// sum.
    CheckerOddRemainder,
    /// The texture's Transform ignored: the pattern laid over world space.
    MatrixIgnored,
    /// The inverse of the texture's Transform applied to the point.
    MatrixInverted,
    /// An allowed answer (check/choices.rs): the checkerboard's cube at the origin is the
    /// second material's.
    CheckerSwapped,
    /// An allowed answer: Noise's sum clamped to [0, 1], not mapped from [-1, 1].
    NoiseClamped,
    /// An allowed answer: Marble's sine clamped to [0, 1], not mapped from [-1, 1].
    MarbleClamped,
    /// An allowed answer: Marble's sine taken as its absolute value.
    MarbleAbsolute,
    /// The ambient term of a textured hit multiplied by one colour for the whole texture, not
    /// its materials' diffuse colours interpolated at the point: black (`None`), or its first
    /// material's (`Some(false)`) or second's (`Some(true)`).
    AmbientOfOneSide(Option<bool>),
    /// Noise's, Marble's and Wood's two materials exchanged: the first where the pattern is 1,
    /// the second where it is 0.
    BlendSwapped,
    /// Noise, Marble and Wood with other numbers than the file's.
    Constants {
        /// How many octaves more (or fewer) are summed.
        octaves: i32,
        /// What Marble's and Wood's frequency is multiplied by.
        frequency: f32,
        /// What Marble's and Wood's amplitude is multiplied by.
        amplitude: f32,
        /// The frequency of the first octave summed, each octave's weight its inverse: the
        /// noise is `octave_noise(s p) / s` (2: the octaves summed from the second).
        noise_scale: f32,
        /// Each octave's weight over the last's (the course's ½; 1: the octaves summed
        /// unweighed).
        octave_ratio: f32,
        /// The texture-space axis Marble's sine runs along (0: x, the course's; 1: y; 2: z),
        /// and Wood's rings' axis swapped with y likewise.
        axis: u8,
    },
}

/// `pattern` with its numbers changed as [`TextureFault::Constants`] says.
fn with_constants(pattern: Pattern, more: i32, frequency_by: f64, amplitude_by: f64) -> Pattern {
    let octaves_of = |octaves: u32| octaves.saturating_add_signed(more);
    match pattern {
        Pattern::Checkerboard => pattern,
        Pattern::Noise { octaves } => Pattern::Noise {
            octaves: octaves_of(octaves),
        },
        Pattern::Marble {
            octaves,
            frequency,
            amplitude,
        } => Pattern::Marble {
            octaves: octaves_of(octaves),
            frequency: frequency * frequency_by,
            amplitude: amplitude * amplitude_by,
        },
        Pattern::Wood {
            octaves,
            frequency,
            amplitude,
        } => Pattern::Wood {
            octaves: octaves_of(octaves),
            frequency: frequency * frequency_by,
            amplitude: amplitude * amplitude_by,
        },
    }
}

impl TextureFault {
    /// Where `point` (world space) falls between the texture's two materials.
    pub(super) fn weight(&self, texture: &Texture, point: Vec3A) -> f32 {
        let world = point.as_dvec3();
        match self {
            TextureFault::CheckerTruncated => match texture.pattern {
                Pattern::Checkerboard => {
                    let p = texture.to_texture.transform_point3(world);
                    let parity = p.x.trunc() + p.y.trunc() + p.z.trunc();
                    if parity.rem_euclid(2.0) == 0.0 {
                        0.0
                    } else {
                        1.0
                    }
                }
                _ => texture.weight(point),
            },
            TextureFault::CheckerRemainder | TextureFault::CheckerOddRemainder => {
                let Pattern::Checkerboard = texture.pattern else {
                    return texture.weight(point);
                };
                let p = texture.to_texture.transform_point3(world);
                // C's fmod and %: the remainder has the sign of the number divided.
                let odd = if *self == TextureFault::CheckerRemainder {
                    let first_half = |x: f64| f64::from(x % 2.0 < 1.0);
                    (first_half(p.x) + first_half(p.y) + first_half(p.z)) % 2.0 == 0.0
                } else {
                    (p.x.floor() + p.y.floor() + p.z.floor()) % 2.0 == 1.0
                };
                f32::from(u8::from(odd))
            }
            TextureFault::CheckerSwapped => match texture.pattern {
                Pattern::Checkerboard => 1.0 - texture.weight(point),
                _ => texture.weight(point),
            },
            TextureFault::NoiseClamped
            | TextureFault::MarbleClamped
            | TextureFault::MarbleAbsolute => {
                let p = texture.to_texture.transform_point3(world);
                let noise = |octaves| crate::scene::perlin::octave_noise(p.x, p.y, p.z, octaves);
                let weight = match (self, texture.pattern) {
                    (TextureFault::NoiseClamped, Pattern::Noise { octaves }) => noise(octaves),
                    (
                        TextureFault::MarbleClamped,
                        Pattern::Marble {
                            octaves,
                            frequency,
                            amplitude,
                        },
                    ) => (frequency * p.x + amplitude * noise(octaves)).sin(),
                    (
                        TextureFault::MarbleAbsolute,
                        Pattern::Marble {
                            octaves,
                            frequency,
                            amplitude,
                        },
                    ) => (frequency * p.x + amplitude * noise(octaves)).sin().abs(),
                    _ => return texture.weight(point),
                };
                weight.clamp(0.0, 1.0) as f32
            }
            TextureFault::Constants {
                octaves,
                frequency,
                amplitude,
                noise_scale,
                octave_ratio,
                axis,
            } => {
                let scale = f64::from(*noise_scale);
                let ratio = f64::from(*octave_ratio);
                // The pattern is handed the point with x and the axis swapped, and the noise
                // swaps them back: only the sine's (or the rings') axis moves.
                let swap = |q: glam::DVec3| match axis {
                    1 => glam::DVec3::new(q.y, q.x, q.z),
                    2 => glam::DVec3::new(q.z, q.y, q.x),
                    _ => q,
                };
                with_constants(
                    texture.pattern,
                    *octaves,
                    f64::from(*frequency),
                    f64::from(*amplitude),
                )
                .weight_with_noise(
                    swap(texture.to_texture.transform_point3(world)),
                    |q, octaves| {
                        let q = swap(q) * scale;
                        crate::scene::perlin::octave_noise_weighed(q.x, q.y, q.z, octaves, ratio)
                            / scale
                    },
                )
            }
            TextureFault::BlendSwapped => match texture.pattern {
                Pattern::Checkerboard => texture.weight(point),
                _ => 1.0 - texture.weight(point),
            },
            TextureFault::AmbientOfOneSide(_) => texture.weight(point),
            TextureFault::MatrixIgnored => texture.pattern.weight(world),
            TextureFault::MatrixInverted => texture
                .pattern
                .weight(texture.to_texture.inverse().transform_point3(world)),
        }
    }

    /// The colour ambient light is multiplied by on `surface`, where not its diffuse colour.
    pub(super) fn ambient_diffuse(&self, surface: &crate::scene::Surface<'_>) -> Option<Vec3A> {
        match *self {
            TextureFault::AmbientOfOneSide(side) if surface.is_textured() => {
                Some(side.map_or(Vec3A::ZERO, |second| surface.side_diffuse(second)))
            }
            _ => None,
        }
    }
}

/// The line's textures, when it shows shaded pictures.
fn textures(line: &LineScene) -> impl Iterator<Item = &TextureSpec> {
    let shown = line.has_image();
    line.description
        .materials
        .iter()
        .filter(move |_| shown)
        .filter_map(|m| match m {
            MaterialSpec::Texture(t) => Some(t),
            MaterialSpec::Phong(_) => None,
        })
}

pub(super) const CHECKER_TRUNCATION: Fault = Fault {
    name: "checker_truncation",
    assignment: 6,
    sentence: "My checkerboard numbers its cubes wrongly where a coordinate is negative (form \
               0: truncated toward zero, int(x), so the cubes either side of x = 0, y = 0 or \
               z = 0 have the same colour; 1: fmod(x, 2) < 1 per axis, true for every negative \
               x; 2: the sum of the floors tested with % 2 == 1, which is -1 for a negative odd \
               sum).",
    look_for: "The checkerboard's parity: floor(x) + floor(y) + floor(z) of the texture-space \
               point, taken modulo 2 as a number from 0 to 1; a cast to int rounds toward \
               zero, and C's fmod and % keep the sign of a negative number.",
    candidates: |line: &LineScene| {
        if textures(line).any(|t| t.pattern == Pattern::Checkerboard) {
            Candidate::forms(
                [
                    TextureFault::CheckerTruncated,
                    TextureFault::CheckerRemainder,
                    TextureFault::CheckerOddRemainder,
                ]
                .map(Planted::Texture),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const TEXTURE_TRANSFORM: Fault = Fault {
    name: "texture_transform",
    assignment: 6,
    sentence: "I place my textures with the wrong matrix (form 0: the texture's Transform \
               ignored; 1: its inverse applied).",
    look_for: "A texture's pattern is evaluated at the hit point (world space) multiplied by \
               the texture's own Transform matrix, as the handout says, not its inverse.",
    candidates: |line: &LineScene| {
        if textures(line).all(|t| t.to_texture == DMat4::IDENTITY) {
            return Vec::new();
        }
        Candidate::forms(
            [TextureFault::MatrixIgnored, TextureFault::MatrixInverted].map(Planted::Texture),
        )
    },
};

/// Whether the line shows a texture made of noise (Noise, Marble or Wood)...
fn shows_noise(line: &LineScene) -> bool {
    textures(line).any(|t| t.pattern != Pattern::Checkerboard)
}

/// ...and one with a frequency and an amplitude (Marble or Wood).
pub(crate) fn shows_veins(line: &LineScene) -> bool {
    textures(line).any(|t| matches!(t.pattern, Pattern::Marble { .. } | Pattern::Wood { .. }))
}

pub(super) const NOISE_CONSTANTS: Fault = Fault {
    name: "noise_constants",
    assignment: 6,
    sentence: "My Noise, Marble or Wood uses other numbers than the file gives (octaves: how \
               many more octaves are summed; frequency and amplitude: how many times the \
               file's; the first octave's frequency: 2 where the octaves are summed from the \
               second; the axis: Marble's sine along y (1) or z (2), not x).",
    look_for: "The texture's noise: the sum over exactly the file's number of octaves (octave i \
               at 2^i times the frequency and 1/2^i of the weight); Marble is sin(frequency·x + \
               amplitude·noise), Wood the same of the distance from the y axis, with the \
               file's frequency and amplitude.",
    candidates: |line: &LineScene| {
        if !shows_noise(line) {
            return Vec::new();
        }
        [-1, 1]
            .into_iter()
            .map(|more| {
                Candidate::with(
                    Planted::Texture(TextureFault::Constants {
                        octaves: more,
                        frequency: 1.0,
                        amplitude: 1.0,
                        noise_scale: 1.0,
                        octave_ratio: 0.5,
                        axis: 0,
                    }),
                    "octaves",
                    f64::from(more),
                )
            })
            .collect()
    },
};

pub(super) const TEXTURE_BLEND_SWAPPED: Fault = Fault {
    name: "texture_blend_swapped",
    assignment: 6,
    sentence: "My Noise, Marble or Wood puts its two materials the other way round: the first \
               material where the pattern's value is 1 and the second where it is 0 \
               (interpolated as N·first + (1 − N)·second).",
    look_for: "The interpolation of a noise texture: (1 − N)·first + N·second, N the pattern's \
               value mapped onto 0…1, so that the first material of the file shows where N is \
               0 (the checkerboard, whose parity the course leaves open, is not this).",
    candidates: |line: &LineScene| {
        if shows_noise(line) {
            vec![Candidate::plain(Planted::Texture(
                TextureFault::BlendSwapped,
            ))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const TEXTURE_AMBIENT: Fault = Fault {
    name: "texture_ambient",
    assignment: 6,
    sentence: "My ambient term asks a texture for one diffuse colour, not the colour at the hit \
               point (form 0: a texture's colour is black, so textured objects get no ambient \
               light; 1: its first material's colour everywhere; 2: its second's).",
    look_for: "The ambient term of a textured hit: ambient light times the diffuse colour of \
               the texture at that point, its two materials' diffuse colours interpolated by \
               the pattern's weight there (the handout's update of 11/2: accessors that take \
               the world-space point).",
    candidates: |line: &LineScene| {
        if textures(line).next().is_none() || line.description.ambient == glam::Vec3::ZERO {
            return Vec::new();
        }
        Candidate::forms(
            [None, Some(false), Some(true)]
                .map(|side| Planted::Texture(TextureFault::AmbientOfOneSide(side))),
        )
    },
};

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DVec3};

    use super::*;

    fn texture(pattern: Pattern, scale: f64) -> Texture {
        Texture {
            pattern,
            to_texture: DAffine3::from_scale(DVec3::splat(scale)),
            materials: [0, 1],
        }
    }

    #[test]
    fn truncated_cubes_and_misplaced_matrices_by_hand() {
        let checker = texture(Pattern::Checkerboard, 1.0);
        let p = Vec3A::new(-0.5, 0.5, 0.5);
        // floor: −1 + 0 + 0, odd; truncated: 0 + 0 + 0, even.
        assert_eq!(checker.weight(p), 1.0);
        assert_eq!(TextureFault::CheckerTruncated.weight(&checker, p), 0.0);
        // Scaled by 2, (0.75, 0.25, 0.25) is in texture cube (1, 0, 0): odd. Ignored, cube 0;
        // inverted, (0.375, 0.125, 0.125): cube 0.
        let small = texture(Pattern::Checkerboard, 2.0);
        let q = Vec3A::new(0.75, 0.25, 0.25);
        assert_eq!(small.weight(q), 1.0);
        assert_eq!(TextureFault::MatrixIgnored.weight(&small, q), 0.0);
        assert_eq!(TextureFault::MatrixInverted.weight(&small, q), 0.0);
        // Other patterns keep the course's weights under truncation.
        let noise = texture(Pattern::Noise { octaves: 3 }, 1.0);
        assert_eq!(
            TextureFault::CheckerTruncated.weight(&noise, p),
            noise.weight(p)
        );
    }

    #[test]
    fn other_constants_are_the_pattern_with_other_numbers() {
        let marble = |octaves, frequency, amplitude| {
            texture(
                Pattern::Marble {
                    octaves,
                    frequency,
                    amplitude,
                },
                2.0,
            )
        };
        let p = Vec3A::new(0.3, -0.7, 1.1);
        let course = marble(3, 2.0, 1.5);
        let same = TextureFault::Constants {
            octaves: 0,
            frequency: 1.0,
            amplitude: 1.0,
            noise_scale: 1.0,
            octave_ratio: 0.5,
            axis: 0,
        };
        assert_eq!(same.weight(&course, p), course.weight(p));
        let other = TextureFault::Constants {
            octaves: -1,
            frequency: 2.0,
            amplitude: 0.5,
            noise_scale: 1.0,
            octave_ratio: 0.5,
            axis: 0,
        };
        assert_eq!(other.weight(&course, p), marble(2, 4.0, 0.75).weight(p));
        // No fewer than no octaves.
        let noise = texture(Pattern::Noise { octaves: 0 }, 1.0);
        let fewer = TextureFault::Constants {
            octaves: -1,
            frequency: 1.0,
            amplitude: 1.0,
            noise_scale: 1.0,
            octave_ratio: 0.5,
            axis: 0,
        };
        assert_eq!(fewer.weight(&noise, p), noise.weight(p));
        // The sine along y: the course's formula with y in x's place, the noise where it was.
        let along_y = TextureFault::Constants {
            octaves: 0,
            frequency: 1.0,
            amplitude: 1.0,
            noise_scale: 1.0,
            octave_ratio: 0.5,
            axis: 1,
        };
        let q = course.to_texture.transform_point3(p.as_dvec3());
        let n = crate::scene::perlin::octave_noise(q.x, q.y, q.z, 3);
        let by_hand = 0.5 * ((2.0 * q.y + 1.5 * n).sin() + 1.0);
        assert!((f64::from(along_y.weight(&course, p)) - by_hand).abs() < 1e-6);
    }

    #[test]
    fn octaves_summed_from_the_second_are_the_noise_at_twice_the_point_halved() {
        let course = texture(
            Pattern::Marble {
                octaves: 4,
                frequency: 2.0,
                amplitude: 1.5,
            },
            2.0,
        );
        let from_second = TextureFault::Constants {
            octaves: 0,
            frequency: 1.0,
            amplitude: 1.0,
            noise_scale: 2.0,
            octave_ratio: 0.5,
            axis: 0,
        };
        for p in [Vec3A::new(0.3, -0.7, 1.1), Vec3A::new(-2.2, 0.4, 0.05)] {
            let q = course.to_texture.transform_point3(p.as_dvec3());
            let noise: f64 = (1..=4)
                .map(|i| {
                    let scale = f64::from(1u32 << i);
                    crate::scene::perlin::noise(q.x * scale, q.y * scale, q.z * scale) / scale
                })
                .sum();
            let by_hand = 0.5 * ((2.0 * q.x + 1.5 * noise).sin() + 1.0);
            let weight = from_second.weight(&course, p);
            assert!(
                (f64::from(weight) - by_hand).abs() < 1e-6,
                "{weight} {by_hand}"
            );
        }
    }
}
