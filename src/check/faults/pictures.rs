//! Faults of the pictures: colours to bytes, and the depth and normals pictures.

use glam::Vec3A;

use super::{Candidate, Fault, LineScene, Planted};
use crate::accel::Hit;

/// How a student's tracer writes its pictures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PictureFault {
    /// The depth picture's grey over another range of distances (near, far).
    DepthRange(f32, f32),
    /// Red and blue exchanged.
    ChannelSwap,
    /// Colours past 1 (or below 0) wrap around a byte instead of clamping.
    Wrap,
    /// The depth picture's grey not clamped to [0, 1] before the byte, so it wraps: past
    /// both ends, or clamped at one end only and wrapping past the other.
    DepthWrap(Unclamped),
    /// The depth and normals pictures show the scene's background where nothing is hit.
    Background,
    /// The normals picture shows the signed normal (negative components clamped to 0).
    SignedNormals,
    /// The normals picture shows (n + 1) / 2.
    HalvedNormals,
}

/// Which ends of the depth picture's range a student's grey wraps past.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Unclamped {
    /// Both: no clamp at all.
    Both,
    /// Past the near end (the grey clamped at 0 alone, `max(grey, 0)`).
    Near,
    /// Past the far end (the grey clamped at 1 alone, `min(grey, 1)`).
    Far,
}

/// A student's byte: the value times 255, truncated, wrapping around 256.
fn wrapped(value: f32) -> u8 {
    ((value * 255.0) as i64).rem_euclid(256) as u8
}

impl PictureFault {
    pub(super) fn bytes(&self, colour: Vec3A) -> Option<[u8; 3]> {
        match self {
            PictureFault::Wrap => Some([wrapped(colour.x), wrapped(colour.y), wrapped(colour.z)]),
            _ => None,
        }
    }

    /// The bytes as written, after they are made.
    pub(super) fn rearrange(&self, [red, green, blue]: [u8; 3]) -> [u8; 3] {
        match self {
            PictureFault::ChannelSwap => [blue, green, red],
            _ => [red, green, blue],
        }
    }

    pub(super) fn normal_colour(&self, hit: &Hit) -> Option<Vec3A> {
        match self {
            PictureFault::SignedNormals => Some(hit.normal.max(Vec3A::ZERO)),
            PictureFault::HalvedNormals => Some((hit.normal + Vec3A::ONE) * 0.5),
            _ => None,
        }
    }

    pub(super) fn depth_grey(&self, t: f32, t_near: f32, t_far: f32) -> Option<f32> {
        match self {
            // Left unclamped: the byte then wraps (to_byte clamps, a student's cast does not),
            // which the caller's byte conversion shows as a value outside [0, 1]: fold it here.
            PictureFault::DepthRange(near, far) => Some(crate::shade::depth_grey(t, *near, *far)),
            PictureFault::DepthWrap(unclamped) => {
                let grey = (t_far - t) / (t_far - t_near);
                let grey = match unclamped {
                    Unclamped::Both => grey,
                    Unclamped::Near => grey.max(0.0),
                    Unclamped::Far => grey.min(1.0),
                };
                Some(f32::from(wrapped(grey)) / 255.0 + 0.5 / 255.0)
            }
            _ => None,
        }
    }

    pub(super) fn picture_miss(&self, background: [u8; 3]) -> Option<[u8; 3]> {
        match self {
            PictureFault::Background => Some(background),
            _ => None,
        }
    }
}

fn only(fault: PictureFault) -> Vec<Candidate> {
    vec![Candidate::plain(Planted::Picture(fault))]
}

pub(super) const CHANNEL_SWAP: Fault = Fault {
    name: "channel_swap",
    assignment: 1,
    sentence: "I write red and blue in each other's place.",
    look_for: "The byte order of the picture file: a TGA stores each pixel as blue, green, red.",
    candidates: |_| only(PictureFault::ChannelSwap),
};

pub(super) const NO_CLAMP: Fault = Fault {
    name: "no_clamp",
    assignment: 2,
    sentence: "Colours brighter than 1 wrap around to dark instead of staying white.",
    look_for: "The conversion to bytes: clamp each channel to [0, 1] (or the byte to [0, 255]) \
               before the cast; a cast alone wraps past 255.",
    candidates: |line: &LineScene| {
        if line.has_image() {
            only(PictureFault::Wrap)
        } else {
            Vec::new()
        }
    },
};

pub(super) const DEPTH_CLAMP: Fault = Fault {
    name: "depth_clamp",
    assignment: 2,
    sentence: "My depth picture is not clamped: what is nearer than TMIN or farther than TMAX \
               wraps around (form 0), or it is clamped at one end only, and what is nearer than \
               TMIN (form 1) or farther than TMAX (form 2) wraps.",
    look_for: "The depth picture's grey, (TMAX - t) / (TMAX - TMIN): clamp it to [0, 1], so that \
               nearer is white and farther is black.",
    candidates: |line: &LineScene| {
        if line.options.depth.is_some() {
            Candidate::forms(
                [Unclamped::Both, Unclamped::Near, Unclamped::Far]
                    .map(|ends| Planted::Picture(PictureFault::DepthWrap(ends))),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const PICTURE_BACKGROUND: Fault = Fault {
    name: "picture_background",
    assignment: 2,
    sentence: "My depth and normals pictures show the scene's background where nothing is hit.",
    look_for: "The depth and normals pictures are black where a ray hits nothing; the \
               background colour belongs to the shaded picture only.",
    candidates: |line: &LineScene| {
        if line.has_depth_or_normals() {
            only(PictureFault::Background)
        } else {
            Vec::new()
        }
    },
};

pub(super) const NORMALS_SIGNED: Fault = Fault {
    name: "normals_signed",
    assignment: 2,
    sentence: "My normals picture shows the normal's signed components, not their absolute \
               values.",
    look_for: "The normals picture's colour is (|x|, |y|, |z|) of the unit normal.",
    candidates: |line: &LineScene| {
        if line.options.normals.is_some() {
            vec![
                Candidate::with(
                    Planted::Picture(PictureFault::SignedNormals),
                    "mapping",
                    0.0,
                ),
                Candidate::with(
                    Planted::Picture(PictureFault::HalvedNormals),
                    "mapping",
                    1.0,
                ),
            ]
        } else {
            Vec::new()
        }
    },
};

/// The nearest and farthest distance the line's camera rays hit (through pixel centres).
fn hit_range(line: &LineScene) -> Option<(f32, f32)> {
    let (width, height) = (line.options.width, line.options.height);
    let camera = &line.scene.camera;
    let mut range: Option<(f32, f32)> = None;
    for j in 0..height {
        for i in 0..width {
            let (u, v) = crate::camera::pixel_to_screen(i, j, width, height);
            let ray = camera.ray(u, v);
            if let Some(hit) = line.scene.world.intersect(&ray, camera.t_min()) {
                let distance = hit.t * ray.direction.length();
                range = Some(match range {
                    None => (distance, distance),
                    Some((near, far)) => (near.min(distance), far.max(distance)),
                });
            }
        }
    }
    range.filter(|(near, far)| far > near)
}

pub(super) const DEPTH_RANGE: Fault = Fault {
    name: "depth_range",
    assignment: 2,
    sentence: "My depth picture is normalised by the distances the picture itself holds (or from \
               the nearest hit), not by -depth's TMIN and TMAX.",
    look_for: "The depth picture's grey: (TMAX - t) / (TMAX - TMIN) with the TMIN and TMAX of the \
               command line, the same for every picture.",
    candidates: |line: &LineScene| {
        let (Some((_, far, _)), Some((near_hit, far_hit))) = (&line.options.depth, hit_range(line))
        else {
            return Vec::new();
        };
        vec![
            Candidate::with(
                Planted::Picture(PictureFault::DepthRange(near_hit, far_hit)),
                "near",
                f64::from(near_hit),
            ),
            Candidate::with(
                Planted::Picture(PictureFault::DepthRange(near_hit, *far)),
                "near",
                f64::from(near_hit),
            ),
        ]
    },
};
