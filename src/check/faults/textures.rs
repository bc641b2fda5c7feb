//! Faults of assignment 6's solid textures: where a hit falls in texture space, and which
//! cube of the checkerboard it is in.

use glam::{DMat4, Vec3A};

use super::{Candidate, Fault, LineScene, Planted};
use crate::parse::description::{MaterialSpec, Pattern, TextureSpec};
use crate::scene::Texture;

/// How a student's tracer weighs a texture at a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureFault {
    /// The checkerboard's cubes numbered by truncating toward zero, not by flooring: the
    /// cubes either side of each axis plane through the origin are one.
    CheckerTruncated,
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
            TextureFault::MatrixIgnored => texture.pattern.weight(world),
            TextureFault::MatrixInverted => texture
                .pattern
                .weight(texture.to_texture.inverse().transform_point3(world)),
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
    sentence: "My checkerboard numbers its cubes by truncating the coordinates toward zero \
               (int(x)), so the cubes either side of x = 0, y = 0 or z = 0 have the same colour.",
    look_for: "The checkerboard's parity: floor(x) + floor(y) + floor(z) of the texture-space \
               point; a cast to int rounds toward zero, which is not floor for negative values.",
    candidates: |line: &LineScene| {
        if textures(line).any(|t| t.pattern == Pattern::Checkerboard) {
            vec![Candidate::plain(Planted::Texture(
                TextureFault::CheckerTruncated,
            ))]
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
}
