//! How a picture differs from its reference, a heat map of the difference, and the likely cause,
//! named by a stable code and explained for a student.
//!
//! Every decision comes from the pixels alone, never from file names. Each picture's background
//! is estimated as the most common colour along its border (scenes frame their objects, so the
//! border is nearly all background). Causes are tried from the global ones (a flip, a channel
//! swap, a shift, a colour curve: one mistake that moves every pixel), each of which is reported
//! alone when it fits, to the local ones (the background, regions, cracks, outlines), which may
//! appear together.

use std::cmp::Reverse;
use std::collections::HashMap;
use std::ops::{Range, RangeInclusive};

use crate::shade::Image;

/// A stable code for each kind of mistake, as `raycast check` reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Diagnosis {
    /// The renderer crashed, timed out or exited with an error (the caller decides this one).
    Crash,
    /// The renderer wrote no picture (the caller decides this one).
    MissingOutput,
    /// The picture's width or height differs from the reference's.
    Size,
    /// The picture is upside down.
    FlippedVertical,
    /// The picture is mirrored left to right.
    FlippedHorizontal,
    /// Red and blue are exchanged.
    ChannelSwap,
    /// Every object colour is the reference's times one factor.
    ColourScale,
    /// The whole picture is moved by a few whole pixels.
    Shift,
    /// Every outline is off by about half a pixel.
    HalfPixel,
    /// Regions inside objects are black in one picture and shaded in the other.
    BackFaces,
    /// Only the background colour is wrong.
    Background,
    /// Isolated pixels inside objects show the background.
    Cracks,
    /// Pixels along outlines differ, each within a pixel of an edge, with no half-pixel pattern.
    Silhouette,
    /// An object of the reference is missing.
    MissingObject,
    /// An object that the reference lacks is drawn.
    ExtraObject,
    /// The colours follow a power curve of the reference's.
    Gamma,
    /// In a depth picture, some objects' depths are off by factors of their own while others
    /// match: the hit's t was measured in an object's space, under a scaling Transform.
    ObjectSpaceT,
    /// No known mistake explains the difference.
    Unknown,
}

impl Diagnosis {
    /// Every diagnosis, in declaration order.
    pub const ALL: [Diagnosis; 18] = [
        Diagnosis::Crash,
        Diagnosis::MissingOutput,
        Diagnosis::Size,
        Diagnosis::FlippedVertical,
        Diagnosis::FlippedHorizontal,
        Diagnosis::ChannelSwap,
        Diagnosis::ColourScale,
        Diagnosis::Shift,
        Diagnosis::HalfPixel,
        Diagnosis::BackFaces,
        Diagnosis::Background,
        Diagnosis::Cracks,
        Diagnosis::Silhouette,
        Diagnosis::MissingObject,
        Diagnosis::ExtraObject,
        Diagnosis::Gamma,
        Diagnosis::ObjectSpaceT,
        Diagnosis::Unknown,
    ];

    /// The stable snake_case code, as reports and scripts see it.
    pub fn code(self) -> &'static str {
        match self {
            Diagnosis::Crash => "crash",
            Diagnosis::MissingOutput => "missing_output",
            Diagnosis::Size => "size",
            Diagnosis::FlippedVertical => "flipped_vertical",
            Diagnosis::FlippedHorizontal => "flipped_horizontal",
            Diagnosis::ChannelSwap => "channel_swap",
            Diagnosis::ColourScale => "colour_scale",
            Diagnosis::Shift => "shift",
            Diagnosis::HalfPixel => "half_pixel",
            Diagnosis::BackFaces => "back_faces",
            Diagnosis::Background => "background",
            Diagnosis::Cracks => "cracks",
            Diagnosis::Silhouette => "silhouette",
            Diagnosis::MissingObject => "missing_object",
            Diagnosis::ExtraObject => "extra_object",
            Diagnosis::Gamma => "gamma",
            Diagnosis::ObjectSpaceT => "object_space_t",
            Diagnosis::Unknown => "unknown",
        }
    }

    /// One or two sentences telling a student where in their code to look.
    pub fn explanation(self) -> &'static str {
        match self {
            Diagnosis::Crash => {
                "The renderer crashed, timed out or reported an error before writing its \
                 picture: run the same command line by hand and read its message."
            }
            Diagnosis::MissingOutput => {
                "The renderer finished but wrote no picture where -output asked: check that the \
                 output file name is taken from the command line and the file is written."
            }
            Diagnosis::Size => {
                "The picture has the wrong size: the width and height must come from -size \
                 (width first, then height)."
            }
            Diagnosis::FlippedVertical => {
                "The picture is upside down: image rows run from the top, while the camera's \
                 screen y runs up, so row j is screen y = height - 1 - j (or the up vector is \
                 reversed)."
            }
            Diagnosis::FlippedHorizontal => {
                "The picture is mirrored left to right: check the camera's horizontal vector \
                 (direction × up, in that order) and the sign of the screen x coordinate."
            }
            Diagnosis::ChannelSwap => {
                "Red and blue are swapped: the colour channels are written in the wrong order \
                 (a TGA file stores blue, green, red)."
            }
            Diagnosis::ColourScale => {
                "Every colour is off by the same factor: check the ambient term (missing or \
                 added twice) and that each light's colour multiplies its diffuse term."
            }
            Diagnosis::Shift => {
                "The whole picture is moved by whole pixels: check the mapping from pixel \
                 indices to screen coordinates for an off-by-one (the image's corner or size)."
            }
            Diagnosis::HalfPixel => {
                "Every edge is off by about half a pixel: the camera rays go through pixel \
                 corners instead of centres; sample at (i + 0.5, j + 0.5)."
            }
            Diagnosis::BackFaces => {
                "Regions inside objects are black in one picture and shaded in the other: check \
                 how back faces are shaded (the normal turned toward the viewer, -shade_back) \
                 and the sign of the normal."
            }
            Diagnosis::Background => {
                "Only the background differs: rays that hit nothing must take the scene's \
                 background colour, unshaded."
            }
            Diagnosis::Cracks => {
                "Isolated pixels inside objects show the background: rays slip between \
                 triangles where they meet; make the triangle test inclusive at its edges \
                 (barycentric coordinates >= 0, not > 0)."
            }
            Diagnosis::Silhouette => {
                "Pixels along object outlines differ: check the intersection tests' epsilon and \
                 tmin handling, the objects' exact size, and where within each pixel the rays are \
                 sampled."
            }
            Diagnosis::MissingObject => {
                "An object of the reference is missing: check that every object of the scene is \
                 parsed and intersected (groups, transforms, and the nearest-hit test with tmin)."
            }
            Diagnosis::ExtraObject => {
                "Something is drawn that the reference does not show: check the nearest-hit \
                 comparison, tmin (hits behind the eye) and the transforms' inverses."
            }
            Diagnosis::Gamma => {
                "The colours follow a power curve of the reference's: apply no gamma correction \
                 or sRGB conversion; write the linear colour, clamped, times 255."
            }
            Diagnosis::ObjectSpaceT => {
                "Some objects' depths are off by factors of their own while others match: t is \
                 measured in the object's space under a scaling Transform. Keep the transformed \
                 ray's direction unnormalized, so that its t is the world ray's t (or convert t \
                 back), and compare hits by world t."
            }
            Diagnosis::Unknown => {
                "The picture differs in a way no known mistake explains: compare it with the \
                 reference and the heat map by eye."
            }
        }
    }
}

/// The explanations of `diagnoses`, in order, as one paragraph; empty when there are none.
pub fn explain(diagnoses: &[Diagnosis]) -> String {
    diagnoses
        .iter()
        .map(|d| d.explanation())
        .collect::<Vec<_>>()
        .join(" ")
}

/// How two pictures of the same size differ.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// In pixels.
    pub width: u32,
    /// In pixels.
    pub height: u32,
    /// How many pixels have a channel off by more than the tolerance.
    pub differing: usize,
    /// `differing` over the number of pixels (0 for an empty picture).
    pub bad_fraction: f64,
    /// The largest difference of any channel of any pixel, in levels.
    pub worst: u8,
    /// Per pixel, in the pictures' order (rows top first): whether it differs.
    pub mask: Vec<bool>,
}

/// Compares `actual` with `reference` pixel by pixel: a pixel differs when any channel is off by
/// more than `tolerance` levels. `None` when the sizes differ (or a picture's pixels do not fill
/// its size).
pub fn compare(actual: &Image, reference: &Image, tolerance: u8) -> Option<Comparison> {
    if !same_shape(actual, reference) {
        return None;
    }
    let mut worst = 0_u8;
    let mask: Vec<bool> = actual
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(&got, &want)| {
            let difference = channel_difference(got, want);
            worst = worst.max(difference);
            difference > tolerance
        })
        .collect();
    let differing = mask.iter().filter(|&&differs| differs).count();
    let bad_fraction = if mask.is_empty() {
        0.0
    } else {
        differing as f64 / mask.len() as f64
    };
    Some(Comparison {
        width: reference.width,
        height: reference.height,
        differing,
        bad_fraction,
        worst,
        mask,
    })
}

/// The conformance rule: at most `max_bad` of the pixels differ.
pub fn passes(comparison: &Comparison, max_bad: f64) -> bool {
    comparison.bad_fraction <= max_bad
}

/// A picture of the difference, the reference's size: pixels within `tolerance` are dim grey
/// copies of the reference (black where it is black), so the scene stays recognisable; the others
/// ramp from dark red through red and yellow to white with their largest channel difference.
/// Where `actual` has no pixel (a picture of another size), the difference counts as the largest.
pub fn heat_map(actual: &Image, reference: &Image, tolerance: u8) -> Image {
    let (width, height) = (reference.width as usize, reference.height as usize);
    let (actual_width, actual_height) = (actual.width as usize, actual.height as usize);
    let mut pixels = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let want = reference
                .pixels
                .get(y * width + x)
                .copied()
                .unwrap_or_default();
            let got = if x < actual_width && y < actual_height {
                actual.pixels.get(y * actual_width + x).copied()
            } else {
                None
            };
            let difference = got.map_or(u8::MAX, |got| channel_difference(got, want));
            pixels.push(if difference <= tolerance {
                dimmed(want)
            } else {
                heat(difference)
            });
        }
    }
    Image {
        width: reference.width,
        height: reference.height,
        pixels,
    }
}

/// The likely causes of the difference, decided from the pixels alone, in a fixed order from
/// the most specific; empty when the pictures match. A global cause (`flipped_vertical`,
/// `flipped_horizontal`, `channel_swap`, `shift`, `colour_scale`, `gamma`) comes alone; `size`
/// comes alone when the sizes differ; `unknown` when the pictures do not match and nothing fits.
pub fn diagnose(actual: &Image, reference: &Image, tolerance: u8, max_bad: f64) -> Vec<Diagnosis> {
    let Some(comparison) = compare(actual, reference, tolerance) else {
        return vec![Diagnosis::Size];
    };
    if comparison.differing == 0 || passes(&comparison, max_bad) {
        return Vec::new();
    }
    let pair = Pair::new(actual, reference, tolerance);
    if let Some(global) = pair.global_cause(comparison.bad_fraction, max_bad) {
        return vec![global];
    }
    pair.local_causes(comparison.mask, max_bad)
}

// Global causes. A transform undoing the mistake must leave at most this fraction of pixels off
// (or `max_bad`, if larger: a student's flipped picture may differ slightly besides)...
const GLOBAL_SLACK: f64 = 0.005;
// ...and must leave this many times fewer pixels off than the picture as it is, so that a small
// local difference in a symmetric or plain picture is not taken for a flip or a shift.
const GLOBAL_GAIN: f64 = 4.0;
// The largest whole-pixel shift tried along each axis.
const MAX_SHIFT: isize = 3;

// Colour curves (scale and gamma), fitted on the reference's object pixels. Darker channel
// levels are left out of the fit: they carry too little precision for a ratio.
const FIT_MIN_LEVEL: u8 = 20;
const FIT_MIN_SAMPLES: usize = 20;
// The share of object pixels the curve must predict, and how much better than the identity.
const FIT_SHARE: f64 = 0.95;
const FIT_GAIN: f64 = 0.1;
// A fitted factor or exponent this close to 1 is no curve at all.
const NEAR_ONE: f64 = 0.04;
const SCALE_RANGE: RangeInclusive<f64> = 0.2..=5.0;
const GAMMA_RANGE: RangeInclusive<f64> = 0.3..=3.0;

// Background: the reference must show enough of it, nearly all of it must differ, and the
// actual picture must show mostly one colour there instead.
const BACKGROUND_MIN_PIXELS: usize = 20;
const BACKGROUND_WRONG_SHARE: f64 = 0.9;
const BACKGROUND_UNIFORM_SHARE: f64 = 0.8;

// A colour is clearly not the background when a channel is this many levels off it (or the
// tolerance, if larger): noise around the background must not read as an object.
const CLEAR_MARGIN: u8 = 24;

// Regions (missing and extra objects, back faces): at least this many pixels, with a pixel whose
// eight neighbours all belong (a one- or two-pixel strip along an outline is not an object)...
const REGION_MIN_PIXELS: usize = 20;
// ...and smooth in the actual picture, as shading is and noise is not: this share of the
// region's neighbouring pairs within this many levels.
const COHERENT_STEP: u8 = 24;
const COHERENT_SHARE: f64 = 0.7;

// Depth per object: the reference's surfaces are split where neighbouring levels jump by more
// than this; a surface counts when it has this many pixels, and a surface is kept, or fitted by
// a map, when this share of its pixels agree. Two maps agree within this many levels.
const SURFACE_STEP: u8 = 8;
const SURFACE_MIN_PIXELS: usize = 50;
const SURFACE_SHARE: f64 = 0.9;
const MAP_AGREEMENT: f64 = 8.0;
// How far, in pixels, a surface's steep rim reaches beyond it.
const RIM_WIDTH: usize = 2;

// Cracks: clusters of at most this many pixels, at least this many pixels in all, and this share
// of what differs.
const CRACK_CLUSTER: usize = 2;
const CRACK_MIN_PIXELS: usize = 3;
const CRACK_SHARE: f64 = 0.8;

// Outlines: this share of what is left must lie within a pixel of the reference's edges.
const EDGE_SHARE: f64 = 0.98;
// Half a pixel: this share of what differs must be nearer one half-pixel shift of the reference
// than the reference itself, and what differs must be at least this share of the edge pixels
// (a half-pixel mistake moves outlines everywhere; jitter moves a few).
const HALF_PIXEL_CONSISTENT: f64 = 0.8;
const HALF_PIXEL_COVERAGE: f64 = 0.05;

// Neighbours as (dx, dy), y down.
const SIDE_STEPS: [(isize, isize); 4] = [(0, -1), (-1, 0), (1, 0), (0, 1)];
const ALL_STEPS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// The two pictures (of one size) and what the heuristics share.
struct Pair<'a> {
    actual: &'a [[u8; 3]],
    reference: &'a [[u8; 3]],
    width: usize,
    height: usize,
    tolerance: u8,
    reference_background: [u8; 3],
    actual_background: [u8; 3],
    /// Whether the reference's border is mostly one flat colour, a background.
    reference_has_background: bool,
    /// Per pixel: the reference shows its background there.
    reference_shows_background: Vec<bool>,
}

/// A colour curve that may map the reference's levels to the actual picture's.
#[derive(Debug, Clone, Copy)]
enum Curve {
    /// actual = reference × k, clamped.
    Scale,
    /// actual = 255 (reference / 255)^g.
    Gamma,
}

impl Curve {
    /// The parameter one channel suggests, where the channel can say.
    fn sample(self, reference: u8, actual: u8) -> Option<f64> {
        let (want, got) = (f64::from(reference), f64::from(actual));
        match self {
            // A clamped channel only bounds k from below.
            Curve::Scale if reference > FIT_MIN_LEVEL && actual < u8::MAX => Some(got / want),
            // Both levels strictly inside (0, 255), where the logarithms are finite and nonzero.
            Curve::Gamma
                if (FIT_MIN_LEVEL + 1..u8::MAX - FIT_MIN_LEVEL).contains(&reference)
                    && (1..u8::MAX).contains(&actual) =>
            {
                Some((got / 255.0).ln() / (want / 255.0).ln())
            }
            _ => None,
        }
    }

    fn range(self) -> RangeInclusive<f64> {
        match self {
            Curve::Scale => SCALE_RANGE,
            Curve::Gamma => GAMMA_RANGE,
        }
    }

    fn predict(self, parameter: f64, level: f64) -> f64 {
        match self {
            Curve::Scale => (level * parameter).min(255.0),
            Curve::Gamma => 255.0 * (level / 255.0).powf(parameter),
        }
    }
}

/// An affine change of levels, clamped, as a depth picture's levels change when one object's t is
/// scaled.
#[derive(Debug, Clone, Copy)]
struct LevelMap {
    slope: f64,
    offset: f64,
}

impl LevelMap {
    fn apply(self, level: f64) -> f64 {
        (self.slope * level + self.offset).clamp(0.0, 255.0)
    }

    /// Whether the two maps send every level to about the same place.
    fn agrees(&self, other: &LevelMap) -> bool {
        [0.0, 128.0, 255.0]
            .iter()
            .all(|&level| (self.apply(level) - other.apply(level)).abs() <= MAP_AGREEMENT)
    }
}

/// What a region of differing pixels shows.
#[derive(Debug, Clone, Copy)]
enum RegionKind {
    /// The actual picture shows its background where the reference shows an object.
    Missing,
    /// The reference shows its background where the actual picture shows an object.
    Extra,
    /// Black on one side, shaded on the other, and background on neither.
    BackFace,
}

impl<'a> Pair<'a> {
    fn new(actual: &'a Image, reference: &'a Image, tolerance: u8) -> Pair<'a> {
        let (width, height) = (reference.width as usize, reference.height as usize);
        let reference_background = border_mode(&reference.pixels, width, height);
        let actual_background = border_mode(&actual.pixels, width, height);
        // A picture taken from inside an object (the course's scene2_05) has no background:
        // its border is shaded, not one flat colour.
        let reference_has_background = border_share(
            &reference.pixels,
            width,
            height,
            reference_background,
            tolerance,
        ) >= 0.5;
        let reference_shows_background = reference
            .pixels
            .iter()
            .map(|&colour| {
                reference_has_background
                    && channel_difference(colour, reference_background) <= tolerance
            })
            .collect();
        Pair {
            actual: &actual.pixels,
            reference: &reference.pixels,
            width,
            height,
            tolerance,
            reference_background,
            actual_background,
            reference_has_background,
            reference_shows_background,
        }
    }

    /// The one mistake that, undone, makes the whole picture match.
    fn global_cause(&self, plain_bad: f64, max_bad: f64) -> Option<Diagnosis> {
        let (width, height) = (self.width, self.height);
        let actual = self.actual;
        let (all_x, all_y) = (0..width, 0..height);
        if self.fits_undone(plain_bad, max_bad, &all_x, &all_y, |x, y| {
            actual[(height - 1 - y) * width + x]
        }) {
            return Some(Diagnosis::FlippedVertical);
        }
        if self.fits_undone(plain_bad, max_bad, &all_x, &all_y, |x, y| {
            actual[y * width + (width - 1 - x)]
        }) {
            return Some(Diagnosis::FlippedHorizontal);
        }
        if self.fits_undone(plain_bad, max_bad, &all_x, &all_y, |x, y| {
            let [red, green, blue] = actual[y * width + x];
            [blue, green, red]
        }) {
            return Some(Diagnosis::ChannelSwap);
        }
        if self.fits_shifted(plain_bad, max_bad) {
            return Some(Diagnosis::Shift);
        }
        let objects: Vec<usize> = (0..self.reference.len())
            .filter(|&i| !self.reference_shows_background[i])
            .collect();
        let scale = self.curve_fit(&objects, Curve::Scale);
        let gamma = self.curve_fit(&objects, Curve::Gamma);
        match (scale, gamma) {
            (_, Some(gamma)) if scale.is_none_or(|scale| gamma > scale) => Some(Diagnosis::Gamma),
            (Some(_), _) => Some(Diagnosis::ColourScale),
            _ => None,
        }
    }

    /// Whether the actual picture, read through `undone` over the reference's pixels `xs` × `ys`,
    /// matches there, and by far better than as it is.
    fn fits_undone(
        &self,
        plain_bad: f64,
        max_bad: f64,
        xs: &Range<usize>,
        ys: &Range<usize>,
        undone: impl Fn(usize, usize) -> [u8; 3],
    ) -> bool {
        let overlap = xs.len() * ys.len();
        if overlap == 0 {
            return false;
        }
        let ceiling = max_bad.max(GLOBAL_SLACK);
        let allowed_fraction = ceiling.min(plain_bad / GLOBAL_GAIN);
        let allowed = (allowed_fraction * overlap as f64).floor() as usize;
        let mut bad = 0;
        for y in ys.clone() {
            for x in xs.clone() {
                if channel_difference(undone(x, y), self.reference[y * self.width + x])
                    > self.tolerance
                {
                    bad += 1;
                    // Most candidates fail within a few pixels: stop there.
                    if bad > allowed {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Whether the actual picture moved by a few whole pixels matches the reference where the two
    /// overlap (the strip uncovered by the move is ignored).
    fn fits_shifted(&self, plain_bad: f64, max_bad: f64) -> bool {
        let (width, actual) = (self.width, self.actual);
        (-MAX_SHIFT..=MAX_SHIFT)
            .flat_map(|dy| (-MAX_SHIFT..=MAX_SHIFT).map(move |dx| (dx, dy)))
            .filter(|&shift| shift != (0, 0))
            .any(|(dx, dy)| {
                let xs = overlap(width, dx);
                let ys = overlap(self.height, dy);
                self.fits_undone(plain_bad, max_bad, &xs, &ys, |x, y| {
                    actual[y.wrapping_add_signed(dy) * width + x.wrapping_add_signed(dx)]
                })
            })
    }

    /// The share of `objects` that `curve`, fitted on them, predicts, when the fit is a real
    /// curve (not the identity) that predicts nearly all of them and many more than match as is.
    fn curve_fit(&self, objects: &[usize], curve: Curve) -> Option<f64> {
        if objects.len() < FIT_MIN_SAMPLES {
            return None;
        }
        let mut samples: Vec<f64> = objects
            .iter()
            .flat_map(|&i| {
                let (want, got) = (self.reference[i], self.actual[i]);
                (0..3).filter_map(move |c| curve.sample(want[c], got[c]))
            })
            .collect();
        if samples.len() < FIT_MIN_SAMPLES {
            return None;
        }
        // The median: a few pixels that differ for another reason do not move it.
        let middle = samples.len() / 2;
        let parameter = *samples.select_nth_unstable_by(middle, f64::total_cmp).1;
        if !curve.range().contains(&parameter) || (parameter - 1.0).abs() < NEAR_ONE {
            return None;
        }
        let predicted: [f64; 256] =
            std::array::from_fn(|level| curve.predict(parameter, level as f64));
        // The reference's own rounding (a level either way) and the tolerance, plus a level for
        // the student's rounding.
        let slack = f64::from(self.tolerance) + 1.0;
        let mut fitting = 0;
        let mut matching = 0;
        for &i in objects {
            let (want, got) = (self.reference[i], self.actual[i]);
            let fits = want.iter().zip(got).all(|(&want, got)| {
                let low = predicted[usize::from(want.saturating_sub(1))] - slack;
                let high = predicted[usize::from(want.saturating_add(1))] + slack;
                (low..=high).contains(&f64::from(got))
            });
            fitting += usize::from(fits);
            matching += usize::from(channel_difference(got, want) <= self.tolerance);
        }
        let total = objects.len() as f64;
        let fit_share = fitting as f64 / total;
        let match_share = matching as f64 / total;
        (fit_share >= FIT_SHARE && fit_share - match_share >= FIT_GAIN).then_some(fit_share)
    }

    /// The local causes of the pixels in `unexplained`, which each cause found takes out.
    fn local_causes(&self, mut unexplained: Vec<bool>, max_bad: f64) -> Vec<Diagnosis> {
        let mut found = Vec::new();
        if let Some(flat) = self.wrong_background(&mut unexplained) {
            // A background is one flat colour. Where the reference's "background" is shaded
            // (inside a sphere, it is the sphere's inside) and the image shows one colour there
            // instead, those are back faces drawn black (or flat).
            found.push(if flat {
                Diagnosis::Background
            } else {
                Diagnosis::BackFaces
            });
        }
        if self.depths_per_object(&mut unexplained) {
            found.push(Diagnosis::ObjectSpaceT);
        }
        if self.cracks(&mut unexplained) {
            found.push(Diagnosis::Cracks);
        }
        let kinds = [
            (RegionKind::Missing, Diagnosis::MissingObject),
            (RegionKind::Extra, Diagnosis::ExtraObject),
            (RegionKind::BackFace, Diagnosis::BackFaces),
        ];
        for (kind, diagnosis) in kinds {
            if self.regions_of(kind, &mut unexplained) {
                // Seen from inside an object, "missing" black parts are its back faces.
                let inside = !self.reference_has_background && self.actual_background == [0; 3];
                found.push(if diagnosis == Diagnosis::MissingObject && inside {
                    Diagnosis::BackFaces
                } else {
                    diagnosis
                });
            }
        }
        found.dedup();
        let residual: Vec<usize> = (0..unexplained.len()).filter(|&i| unexplained[i]).collect();
        // What is left may be too little to fail on its own: then it needs no cause.
        let significant = residual.len() as f64 > max_bad * unexplained.len() as f64;
        found.extend(if significant {
            self.outline_cause(&residual)
        } else {
            None
        });
        if found.is_empty() {
            found.push(Diagnosis::Unknown);
        }
        found.sort_by_key(|&diagnosis| report_rank(diagnosis));
        found
    }

    /// Whether the background is wrong nearly everywhere it shows, one colour instead; then
    /// takes those pixels out of `unexplained`, and says whether the reference was flat there.
    fn wrong_background(&self, unexplained: &mut [bool]) -> Option<bool> {
        let background: Vec<usize> = (0..self.reference.len())
            .filter(|&i| self.reference_shows_background[i])
            .collect();
        if background.len() < BACKGROUND_MIN_PIXELS {
            return None;
        }
        let wrong: Vec<usize> = background
            .iter()
            .copied()
            .filter(|&i| unexplained[i])
            .collect();
        if (wrong.len() as f64) < BACKGROUND_WRONG_SHARE * background.len() as f64 {
            return None;
        }
        let shown = most_common(wrong.iter().map(|&i| self.actual[i]))?;
        let uniform = wrong
            .iter()
            .filter(|&&i| channel_difference(self.actual[i], shown) <= self.tolerance)
            .count();
        if (uniform as f64) < BACKGROUND_UNIFORM_SHARE * wrong.len() as f64 {
            return None;
        }
        for &i in &wrong {
            unexplained[i] = false;
        }
        let reference = most_common(wrong.iter().map(|&i| self.reference[i]))?;
        let flat = wrong
            .iter()
            .filter(|&&i| channel_difference(self.reference[i], reference) <= self.tolerance)
            .count();
        Some(flat as f64 >= BACKGROUND_UNIFORM_SHARE * wrong.len() as f64)
    }

    /// Whether the pictures are depth pictures (grey) in which some of the reference's surfaces
    /// are drawn with depths of their own (an affine change of levels, possibly clamped), and
    /// they are not all changed alike; takes those surfaces out of `unexplained`.
    fn depths_per_object(&self, unexplained: &mut [bool]) -> bool {
        let grey = |colour: &[u8; 3]| colour[0] == colour[1] && colour[1] == colour[2];
        if !self.reference.iter().all(grey) || !self.actual.iter().all(grey) {
            return false;
        }
        let mut kept = 0;
        let mut changed: Vec<(Vec<usize>, LevelMap)> = Vec::new();
        for surface in self.surfaces() {
            if surface.len() < SURFACE_MIN_PIXELS {
                continue;
            }
            let matching = surface
                .iter()
                .filter(|&&i| {
                    channel_difference(self.actual[i], self.reference[i]) <= self.tolerance
                })
                .count();
            if matching as f64 >= SURFACE_SHARE * surface.len() as f64 {
                kept += 1;
            } else if let Some(map) = self.level_map(&surface) {
                changed.push((surface, map));
            }
        }
        let distinct = changed
            .iter()
            .any(|(_, map)| changed.iter().any(|(_, other)| !map.agrees(other)));
        if changed.is_empty() || (kept == 0 && !distinct) {
            return false;
        }
        let mut explained = vec![false; unexplained.len()];
        for i in changed.into_iter().flat_map(|(surface, _)| surface) {
            explained[i] = true;
        }
        // A sphere's rim is too steep to join its surface: its few pixels go with the surface
        // they border.
        for _ in 0..RIM_WIDTH {
            let rim: Vec<usize> = (0..explained.len())
                .filter(|&i| {
                    !explained[i]
                        && !self.reference_shows_background[i]
                        && neighbours(self.width, self.height, i, &ALL_STEPS).any(|n| explained[n])
                })
                .collect();
            for i in rim {
                explained[i] = true;
            }
        }
        for (unexplained, explained) in unexplained.iter_mut().zip(explained) {
            *unexplained &= !explained;
        }
        true
    }

    /// The reference's object pixels split into smooth surfaces: 4-connected, each step between
    /// neighbours within `SURFACE_STEP` levels, so a jump in depth separates two objects.
    fn surfaces(&self) -> Vec<Vec<usize>> {
        let mut seen = self.reference_shows_background.clone();
        let mut found = Vec::new();
        let mut stack = Vec::new();
        for start in 0..self.reference.len() {
            if seen[start] {
                continue;
            }
            seen[start] = true;
            stack.push(start);
            let mut surface = Vec::new();
            while let Some(index) = stack.pop() {
                surface.push(index);
                for next in neighbours(self.width, self.height, index, &SIDE_STEPS) {
                    let step = channel_difference(self.reference[index], self.reference[next]);
                    if !seen[next] && step <= SURFACE_STEP {
                        seen[next] = true;
                        stack.push(next);
                    }
                }
            }
            found.push(surface);
        }
        found
    }

    /// The affine map of levels, clamped to 0..=255, that takes the reference's `surface` to
    /// the actual picture's, fitted by least squares on the levels left unclamped; `None` when
    /// it fails to predict nearly all of the surface, or when the surface went to the background
    /// (a missing object, not a moved one).
    fn level_map(&self, surface: &[usize]) -> Option<LevelMap> {
        let level = |pixels: &[[u8; 3]], i: usize| f64::from(pixels[i][0]);
        let gone = surface
            .iter()
            .filter(|&&i| self.actual_shows_background(i))
            .count();
        if gone as f64 >= SURFACE_SHARE * surface.len() as f64 {
            return None;
        }
        let inside: Vec<(f64, f64)> = surface
            .iter()
            .map(|&i| (level(self.reference, i), level(self.actual, i)))
            .filter(|&(_, got)| got > 0.0 && got < 255.0)
            .collect();
        let map = if inside.len() >= FIT_MIN_SAMPLES {
            let n = inside.len() as f64;
            let (sum_x, sum_y) = inside
                .iter()
                .fold((0.0, 0.0), |(sx, sy), &(x, y)| (sx + x, sy + y));
            let (mean_x, mean_y) = (sum_x / n, sum_y / n);
            let (mut sxx, mut sxy) = (0.0, 0.0);
            for &(x, y) in &inside {
                sxx += (x - mean_x) * (x - mean_x);
                sxy += (x - mean_x) * (y - mean_y);
            }
            // A surface of one level fixes no slope: take its levels as moved by an offset.
            let slope = if sxx > 0.0 { sxy / sxx } else { 1.0 };
            LevelMap {
                slope,
                offset: mean_y - slope * mean_x,
            }
        } else {
            // Clamped throughout: the whole surface moved past the near or the far plane.
            let got = level(self.actual, surface[0]);
            LevelMap {
                slope: 0.0,
                offset: got,
            }
        };
        let slack = f64::from(self.tolerance) + 2.0;
        let fitting = surface
            .iter()
            .filter(|&&i| {
                (map.apply(level(self.reference, i)) - level(self.actual, i)).abs() <= slack
            })
            .count();
        (fitting as f64 >= SURFACE_SHARE * surface.len() as f64).then_some(map)
    }

    /// Whether what differs is mostly tiny clusters inside objects that show the background;
    /// takes them out of `unexplained`.
    fn cracks(&self, unexplained: &mut [bool]) -> bool {
        let differing = unexplained.iter().filter(|&&differs| differs).count();
        let cracks: Vec<usize> = regions(unexplained, self.width, self.height)
            .into_iter()
            .filter(|region| {
                region.len() <= CRACK_CLUSTER && region.iter().all(|&i| self.is_crack(i))
            })
            .flatten()
            .collect();
        if cracks.len() < CRACK_MIN_PIXELS || (cracks.len() as f64) < CRACK_SHARE * differing as f64
        {
            return false;
        }
        for &i in &cracks {
            unexplained[i] = false;
        }
        true
    }

    /// Whether the actual picture shows its background at `index` while the reference shows an
    /// object there and all around it (inside the object, not on its outline).
    fn is_crack(&self, index: usize) -> bool {
        self.actual_shows_background(index)
            && self.reference_clearly_object(index)
            && neighbours(self.width, self.height, index, &SIDE_STEPS)
                .all(|next| self.reference_clearly_object(next))
    }

    /// Whether `unexplained` holds a sizeable, smooth region of `kind`; takes every such region
    /// out of `unexplained`.
    fn regions_of(&self, kind: RegionKind, unexplained: &mut [bool]) -> bool {
        let member: Vec<bool> = (0..unexplained.len())
            .map(|i| unexplained[i] && self.is_of_kind(kind, i))
            .collect();
        let mut any = false;
        for region in regions(&member, self.width, self.height) {
            if self.has_interior(&region, &member) && self.is_coherent(&region, &member) {
                any = true;
                for &i in &region {
                    unexplained[i] = false;
                }
            }
        }
        any
    }

    fn is_of_kind(&self, kind: RegionKind, index: usize) -> bool {
        let (got, want) = (self.actual[index], self.reference[index]);
        match kind {
            RegionKind::Missing => {
                self.actual_shows_background(index) && self.reference_clearly_object(index)
            }
            RegionKind::Extra => {
                self.reference_shows_background[index] && self.actual_clearly_object(index)
            }
            RegionKind::BackFace => {
                let black_here = self.is_black(got)
                    && !self.actual_shows_background(index)
                    && self.reference_clearly_object(index)
                    && self.is_coloured(want);
                let black_there = self.is_black(want)
                    && !self.reference_shows_background[index]
                    && self.actual_clearly_object(index)
                    && self.is_coloured(got);
                black_here || black_there
            }
        }
    }

    /// Big enough, with a pixel whose eight neighbours all belong to the region.
    fn has_interior(&self, region: &[usize], member: &[bool]) -> bool {
        region.len() >= REGION_MIN_PIXELS
            && region.iter().any(|&i| {
                neighbours(self.width, self.height, i, &ALL_STEPS)
                    .filter(|&next| member[next])
                    .count()
                    == ALL_STEPS.len()
            })
    }

    /// Smooth in the actual picture: most neighbouring pairs within the region are close.
    fn is_coherent(&self, region: &[usize], member: &[bool]) -> bool {
        let (mut pairs, mut smooth) = (0_usize, 0_usize);
        for &i in region {
            let (x, y) = (i % self.width, i / self.width);
            let right = (x + 1 < self.width).then_some(i + 1);
            let below = (y + 1 < self.height).then_some(i + self.width);
            for next in [right, below]
                .into_iter()
                .flatten()
                .filter(|&next| member[next])
            {
                pairs += 1;
                let step = channel_difference(self.actual[i], self.actual[next]);
                smooth += usize::from(step <= COHERENT_STEP);
            }
        }
        pairs > 0 && smooth as f64 >= COHERENT_SHARE * pairs as f64
    }

    /// `half_pixel` or `silhouette` when the `residual` pixels lie along the reference's edges.
    fn outline_cause(&self, residual: &[usize]) -> Option<Diagnosis> {
        let (width, height) = (self.width, self.height);
        let edge: Vec<bool> = (0..self.reference.len())
            .map(|i| {
                neighbours(width, height, i, &SIDE_STEPS).any(|next| {
                    channel_difference(self.reference[i], self.reference[next]) > self.tolerance
                })
            })
            .collect();
        let edge_count = edge.iter().filter(|&&is_edge| is_edge).count();
        let near_edge = residual
            .iter()
            .filter(|&&i| edge[i] || neighbours(width, height, i, &ALL_STEPS).any(|n| edge[n]))
            .count();
        if (near_edge as f64) < EDGE_SHARE * residual.len() as f64 {
            return None;
        }
        Some(if self.is_half_pixel(residual, edge_count) {
            Diagnosis::HalfPixel
        } else {
            Diagnosis::Silhouette
        })
    }

    /// Whether the `residual` pixels are systematically nearer the reference resampled half a
    /// pixel off, in one direction, than the reference itself. Which corner a student's rays go
    /// through depends on the direction of their rows and columns, so every direction is tried.
    fn is_half_pixel(&self, residual: &[usize], edge_count: usize) -> bool {
        if (residual.len() as f64) < HALF_PIXEL_COVERAGE * edge_count as f64 {
            return false;
        }
        let consistent = ALL_STEPS
            .iter()
            .map(|&(dx, dy)| {
                residual
                    .iter()
                    .filter(|&&i| {
                        let got = self.actual[i];
                        let shifted = self.half_pixel_reference(i, dx, dy);
                        let unshifted = self.reference[i].map(f64::from);
                        distance(got, shifted) + 0.5 < distance(got, unshifted)
                    })
                    .count()
            })
            .max()
            .unwrap_or(0);
        consistent as f64 >= HALF_PIXEL_CONSISTENT * residual.len() as f64
    }

    /// The reference bilinearly resampled half a pixel from `index` toward (dx, dy): the mean of
    /// the pixel and its neighbours that way (clamped at the picture's sides).
    fn half_pixel_reference(&self, index: usize, dx: isize, dy: isize) -> [f64; 3] {
        let (x, y) = (index % self.width, index / self.width);
        let toward = |at: usize, step: isize, length: usize| {
            at.checked_add_signed(step)
                .filter(|&next| next < length)
                .unwrap_or(at)
        };
        let xs = [x, toward(x, dx, self.width)];
        let ys = [y, toward(y, dy, self.height)];
        let mut sum = [0.0_f64; 3];
        for &sample_y in &ys {
            for &sample_x in &xs {
                let colour = self.reference[sample_y * self.width + sample_x];
                for (total, level) in sum.iter_mut().zip(colour) {
                    *total += f64::from(level);
                }
            }
        }
        sum.map(|total| total / 4.0)
    }

    fn actual_shows_background(&self, index: usize) -> bool {
        channel_difference(self.actual[index], self.actual_background) <= self.tolerance
    }

    fn reference_clearly_object(&self, index: usize) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        channel_difference(self.reference[index], self.reference_background) > margin
    }

    /// Clearly neither picture's background: a student's object must not be their background
    /// colour nor the reference's.
    fn actual_clearly_object(&self, index: usize) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        let colour = self.actual[index];
        channel_difference(colour, self.actual_background) > margin
            && channel_difference(colour, self.reference_background) > margin
    }

    fn is_black(&self, colour: [u8; 3]) -> bool {
        colour.iter().all(|&level| level <= self.tolerance)
    }

    fn is_coloured(&self, colour: [u8; 3]) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        colour.iter().any(|&level| level > margin)
    }
}

/// The order in which local causes are reported: the most specific first.
fn report_rank(diagnosis: Diagnosis) -> u8 {
    match diagnosis {
        Diagnosis::Cracks => 0,
        Diagnosis::BackFaces => 1,
        Diagnosis::MissingObject => 2,
        Diagnosis::ExtraObject => 3,
        Diagnosis::Background => 4,
        Diagnosis::ObjectSpaceT => 5,
        Diagnosis::HalfPixel => 6,
        Diagnosis::Silhouette => 7,
        _ => 8,
    }
}

fn same_shape(actual: &Image, reference: &Image) -> bool {
    let pixel_count = reference.width as usize * reference.height as usize;
    actual.width == reference.width
        && actual.height == reference.height
        && actual.pixels.len() == pixel_count
        && reference.pixels.len() == pixel_count
}

/// The largest difference of any channel.
fn channel_difference(a: [u8; 3], b: [u8; 3]) -> u8 {
    a[0].abs_diff(b[0])
        .max(a[1].abs_diff(b[1]))
        .max(a[2].abs_diff(b[2]))
}

/// The sum of the channels' differences.
fn distance(colour: [u8; 3], to: [f64; 3]) -> f64 {
    colour
        .iter()
        .zip(to)
        .map(|(&level, target)| (f64::from(level) - target).abs())
        .sum()
}

/// The reference's pixels off `length` where a picture moved by `offset` still covers them.
fn overlap(length: usize, offset: isize) -> Range<usize> {
    let uncovered = offset.unsigned_abs().min(length);
    if offset >= 0 {
        0..length - uncovered
    } else {
        uncovered..length
    }
}

/// The colours along a picture's border (empty for a picture without pixels).
fn border(pixels: &[[u8; 3]], width: usize, height: usize) -> Vec<[u8; 3]> {
    if width == 0 || height == 0 || pixels.len() < width * height {
        return Vec::new();
    }
    let top = &pixels[..width];
    let bottom = &pixels[(height - 1) * width..height * width];
    let sides = (0..height).flat_map(|y| [pixels[y * width], pixels[y * width + width - 1]]);
    top.iter().chain(bottom).copied().chain(sides).collect()
}

/// The most common colour along a picture's border: its background.
fn border_mode(pixels: &[[u8; 3]], width: usize, height: usize) -> [u8; 3] {
    most_common(border(pixels, width, height).into_iter()).unwrap_or_default()
}

/// The share of the border's pixels within `tolerance` of `colour`.
fn border_share(
    pixels: &[[u8; 3]],
    width: usize,
    height: usize,
    colour: [u8; 3],
    tolerance: u8,
) -> f64 {
    let border = border(pixels, width, height);
    if border.is_empty() {
        return 0.0;
    }
    let near = border
        .iter()
        .filter(|&&c| channel_difference(c, colour) <= tolerance)
        .count();
    near as f64 / border.len() as f64
}

/// The most frequent colour (the least, by value, among equals, so that the answer does not
/// depend on hashing); `None` when there are none.
fn most_common(colours: impl Iterator<Item = [u8; 3]>) -> Option<[u8; 3]> {
    let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
    for colour in colours {
        *counts.entry(colour).or_insert(0) += 1;
    }
    counts
        .into_iter()
        .max_by_key(|&(colour, count)| (count, Reverse(colour)))
        .map(|(colour, _)| colour)
}

/// The pixels `steps` away from `index` that lie inside the picture.
fn neighbours(
    width: usize,
    height: usize,
    index: usize,
    steps: &'static [(isize, isize)],
) -> impl Iterator<Item = usize> {
    let (x, y) = (index % width, index / width);
    steps.iter().filter_map(move |&(dx, dy)| {
        let next_x = x.checked_add_signed(dx).filter(|&next| next < width)?;
        let next_y = y.checked_add_signed(dy).filter(|&next| next < height)?;
        Some(next_y * width + next_x)
    })
}

/// The 8-connected regions of the pixels in `member`, each as its pixels' indices.
fn regions(member: &[bool], width: usize, height: usize) -> Vec<Vec<usize>> {
    let mut seen = vec![false; member.len()];
    let mut found = Vec::new();
    let mut stack = Vec::new();
    for (start, &is_member) in member.iter().enumerate() {
        if !is_member || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut region = Vec::new();
        while let Some(index) = stack.pop() {
            region.push(index);
            for next in neighbours(width, height, index, &ALL_STEPS) {
                if member[next] && !seen[next] {
                    seen[next] = true;
                    stack.push(next);
                }
            }
        }
        found.push(region);
    }
    found
}

/// A matching pixel in the heat map: the reference's brightness, dimmed to a quarter, in grey.
fn dimmed([red, green, blue]: [u8; 3]) -> [u8; 3] {
    let luma = (299 * u32::from(red) + 587 * u32::from(green) + 114 * u32::from(blue)) / 1000;
    [(luma / 4) as u8; 3]
}

/// A differing pixel in the heat map, in three equal stages: dark red to red, red to yellow,
/// yellow to white. Even the smallest difference (128 of red) stands out from the dimmed grey.
fn heat(difference: u8) -> [u8; 3] {
    let step = 3 * u32::from(difference);
    match step {
        0..255 => [(128 + step / 2) as u8, 0, 0],
        255..510 => [255, (step - 255) as u8, 0],
        _ => [255, 255, (step - 510).min(255) as u8],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIDTH: u32 = 64;
    const HEIGHT: u32 = 48;
    const GREY: [u8; 3] = [127, 127, 127];
    const TOLERANCE: u8 = 2;
    const MAX_BAD: f64 = 0.001;

    const RED: [u8; 3] = [220, 40, 30];
    const GREEN: [u8; 3] = [40, 200, 60];
    const BLUE: [u8; 3] = [50, 70, 230];
    const YELLOW: [u8; 3] = [230, 220, 40];
    /// Centre x, centre y, radius.
    const DISC: (f64, f64, f64) = (16.3, 15.6, 9.7);
    const TRIANGLE: [(f64, f64); 3] = [(30.4, 44.2), (46.1, 26.3), (58.3, 43.6)];

    /// What the synthetic renderer draws, and where within each pixel it samples.
    #[derive(Debug, Clone, Copy)]
    struct Scene {
        /// The sample point within a pixel: (0.5, 0.5) is its centre, (0, 0) its top left corner.
        offset: (f64, f64),
        background: [u8; 3],
        triangle: bool,
        square: bool,
        black_lower_disc: bool,
    }

    impl Default for Scene {
        fn default() -> Self {
            Scene {
                offset: (0.5, 0.5),
                background: GREY,
                triangle: true,
                square: false,
                black_lower_disc: false,
            }
        }
    }

    /// A gradient across the picture, so that channels vary (but by at most the tolerance from
    /// one pixel to the next, so that only outlines are edges).
    fn shade(base: [u8; 3], x: f64, y: f64) -> [u8; 3] {
        let factor = 0.55 + 0.25 * x / f64::from(WIDTH) + 0.2 * y / f64::from(HEIGHT);
        base.map(|level| (f64::from(level) * factor) as u8)
    }

    fn inside_triangle(x: f64, y: f64) -> bool {
        let side = |(ax, ay): (f64, f64), (bx, by): (f64, f64)| {
            (bx - ax) * (y - ay) - (by - ay) * (x - ax)
        };
        let [a, b, c] = TRIANGLE;
        let sides = [side(a, b), side(b, c), side(c, a)];
        sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0)
    }

    /// A grey picture with a red disc, a green rectangle and a blue triangle, analytically, one
    /// sample per pixel.
    fn render(scene: Scene) -> Image {
        let (cx, cy, radius) = DISC;
        let mut pixels = Vec::new();
        for row in 0..HEIGHT {
            for column in 0..WIDTH {
                let x = f64::from(column) + scene.offset.0;
                let y = f64::from(row) + scene.offset.1;
                let colour = if (x - cx) * (x - cx) + (y - cy) * (y - cy) <= radius * radius {
                    if scene.black_lower_disc && y > cy {
                        [0, 0, 0]
                    } else {
                        shade(RED, x, y)
                    }
                } else if (34.2..57.6).contains(&x) && (5.3..20.8).contains(&y) {
                    shade(GREEN, x, y)
                } else if scene.triangle && inside_triangle(x, y) {
                    shade(BLUE, x, y)
                } else if scene.square && (4.0..10.0).contains(&x) && (32.0..38.0).contains(&y) {
                    shade(YELLOW, x, y)
                } else {
                    scene.background
                };
                pixels.push(colour);
            }
        }
        Image {
            width: WIDTH,
            height: HEIGHT,
            pixels,
        }
    }

    fn reference() -> Image {
        render(Scene::default())
    }

    fn map_pixels(image: &Image, mut change: impl FnMut([u8; 3]) -> [u8; 3]) -> Image {
        Image {
            width: image.width,
            height: image.height,
            pixels: image.pixels.iter().map(|&colour| change(colour)).collect(),
        }
    }

    fn rearranged(image: &Image, source: impl Fn(usize, usize) -> (usize, usize)) -> Image {
        let (width, height) = (image.width as usize, image.height as usize);
        let mut pixels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                let (from_x, from_y) = source(x, y);
                pixels.push(image.pixels[from_y * width + from_x]);
            }
        }
        Image {
            width: image.width,
            height: image.height,
            pixels,
        }
    }

    /// A deterministic byte stream (a 64-bit LCG's top byte).
    struct Noise(u64);

    impl Noise {
        fn byte(&mut self) -> u8 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 56) as u8
        }
    }

    /// The planted fault fails the conformance rule and gets exactly `expected`.
    fn assert_diagnosed(actual: &Image, expected: &[Diagnosis]) {
        let reference = reference();
        let comparison = compare(actual, &reference, TOLERANCE).expect("the sizes agree");
        assert!(
            !passes(&comparison, MAX_BAD),
            "the planted fault must fail; {} pixels differ",
            comparison.differing
        );
        assert_eq!(diagnose(actual, &reference, TOLERANCE, MAX_BAD), expected);
    }

    #[test]
    fn codes_are_distinct_snake_case_with_explanations() {
        let codes: Vec<&str> = Diagnosis::ALL.iter().map(|d| d.code()).collect();
        for (i, code) in codes.iter().enumerate() {
            assert!(
                code.chars().all(|c| c.is_ascii_lowercase() || c == '_'),
                "{code}"
            );
            assert!(!codes[..i].contains(code), "{code} twice");
        }
        assert!(
            Diagnosis::ALL
                .iter()
                .all(|d| d.explanation().ends_with('.'))
        );
        assert_eq!(
            Diagnosis::HalfPixel.explanation(),
            "Every edge is off by about half a pixel: the camera rays go through pixel corners \
             instead of centres; sample at (i + 0.5, j + 0.5)."
        );
    }

    #[test]
    fn explain_joins_the_explanations_in_order() {
        assert_eq!(explain(&[]), "");
        let both = explain(&[Diagnosis::Cracks, Diagnosis::Background]);
        let expected = format!(
            "{} {}",
            Diagnosis::Cracks.explanation(),
            Diagnosis::Background.explanation()
        );
        assert_eq!(both, expected);
    }

    #[test]
    fn compare_counts_channels_beyond_the_tolerance() {
        let reference = Image {
            width: 3,
            height: 2,
            pixels: vec![
                [10, 10, 10],
                [10, 10, 10],
                [10, 10, 10],
                [0, 0, 0],
                [0, 0, 0],
                [9; 3],
            ],
        };
        let actual = Image {
            width: 3,
            height: 2,
            // Equal; off by exactly the tolerance; off by one more in blue; off by 200 in red;
            // equal; off by the tolerance in every channel.
            pixels: vec![
                [10, 10, 10],
                [12, 8, 10],
                [10, 10, 13],
                [200, 0, 0],
                [0, 0, 0],
                [7; 3],
            ],
        };
        let comparison = compare(&actual, &reference, 2).expect("same size");
        assert_eq!((comparison.width, comparison.height), (3, 2));
        assert_eq!(comparison.differing, 2);
        assert_eq!(comparison.worst, 200);
        assert_eq!(comparison.mask, [false, false, true, true, false, false]);
        assert!((comparison.bad_fraction - 2.0 / 6.0).abs() < 1e-12);
        assert!(passes(&comparison, 0.34));
        assert!(!passes(&comparison, 0.3));
        let strict = compare(&actual, &reference, 0).expect("same size");
        assert_eq!(strict.differing, 4);

        let narrower = Image {
            width: 2,
            height: 3,
            pixels: reference.pixels.clone(),
        };
        assert!(compare(&narrower, &reference, 2).is_none());
        assert_eq!(diagnose(&narrower, &reference, 2, 0.001), [Diagnosis::Size]);
    }

    #[test]
    fn heat_map_dims_matches_and_ramps_differences() {
        let reference = Image {
            width: 4,
            height: 1,
            pixels: vec![[0, 0, 0], [200, 100, 40], [100, 100, 100], [0, 0, 0]],
        };
        let actual = Image {
            width: 4,
            height: 1,
            pixels: vec![[0, 0, 0], [201, 100, 40], [100, 110, 100], [255, 255, 255]],
        };
        let map = heat_map(&actual, &reference, 2);
        assert_eq!((map.width, map.height, map.pixels.len()), (4, 1, 4));
        assert_eq!(map.pixels[0], [0, 0, 0], "equal black stays black");
        let [r, g, b] = map.pixels[1];
        let grey = r == g && g == b && (1..64).contains(&r);
        assert!(grey, "a match is a dim grey: {:?}", map.pixels[1]);
        let [r, g, b] = map.pixels[2];
        assert!(
            r >= 128 && g == 0 && b == 0,
            "a small difference is red: {:?}",
            map.pixels[2]
        );
        assert_eq!(
            map.pixels[3],
            [255, 255, 255],
            "the largest difference is white"
        );

        let smaller = Image {
            width: 1,
            height: 1,
            pixels: vec![[0, 0, 0]],
        };
        let map = heat_map(&smaller, &reference, 2);
        assert_eq!(map.pixels.len(), 4);
        assert_eq!(
            map.pixels[1],
            [255, 255, 255],
            "no pixel counts as the largest difference"
        );
    }

    #[test]
    fn identical_pictures_pass_with_no_diagnosis() {
        let reference = reference();
        let actual = reference.clone();
        let comparison = compare(&actual, &reference, TOLERANCE).expect("same size");
        assert_eq!((comparison.differing, comparison.worst), (0, 0));
        assert!(passes(&comparison, MAX_BAD));
        assert!(diagnose(&actual, &reference, TOLERANCE, MAX_BAD).is_empty());
    }

    #[test]
    fn wrong_size() {
        let reference = reference();
        let pixels = reference.pixels[..(WIDTH as usize - 1) * HEIGHT as usize].to_vec();
        let cropped = Image {
            width: WIDTH - 1,
            height: HEIGHT,
            pixels,
        };
        assert_eq!(
            diagnose(&cropped, &reference, TOLERANCE, MAX_BAD),
            [Diagnosis::Size]
        );
    }

    #[test]
    fn flipped_vertically() {
        let flipped = rearranged(&reference(), |x, y| (x, HEIGHT as usize - 1 - y));
        assert_diagnosed(&flipped, &[Diagnosis::FlippedVertical]);
    }

    #[test]
    fn flipped_horizontally() {
        let flipped = rearranged(&reference(), |x, y| (WIDTH as usize - 1 - x, y));
        assert_diagnosed(&flipped, &[Diagnosis::FlippedHorizontal]);
    }

    #[test]
    fn channels_swapped() {
        let swapped = map_pixels(&reference(), |[r, g, b]| [b, g, r]);
        assert_diagnosed(&swapped, &[Diagnosis::ChannelSwap]);
    }

    #[test]
    fn colours_halved_everywhere() {
        let halved = map_pixels(&reference(), |colour| {
            colour.map(|level| (f64::from(level) * 0.5).round() as u8)
        });
        assert_diagnosed(&halved, &[Diagnosis::ColourScale]);
    }

    #[test]
    fn object_colours_brightened_and_clamped() {
        let brighter = map_pixels(&reference(), |colour| {
            if colour == GREY {
                colour
            } else {
                colour.map(|level| (f64::from(level) * 1.6).round().min(255.0) as u8)
            }
        });
        assert_diagnosed(&brighter, &[Diagnosis::ColourScale]);
    }

    #[test]
    fn gamma_applied() {
        let curved = map_pixels(&reference(), |colour| {
            colour.map(|level| (255.0 * (f64::from(level) / 255.0).powf(2.2)).round() as u8)
        });
        assert_diagnosed(&curved, &[Diagnosis::Gamma]);
    }

    #[test]
    fn shifted_two_pixels_right() {
        let shifted = render(Scene {
            offset: (2.5, 0.5),
            ..Scene::default()
        });
        assert_diagnosed(&shifted, &[Diagnosis::Shift]);
    }

    #[test]
    fn shifted_one_pixel_up() {
        let shifted = render(Scene {
            offset: (0.5, -0.5),
            ..Scene::default()
        });
        assert_diagnosed(&shifted, &[Diagnosis::Shift]);
    }

    #[test]
    fn sampled_at_pixel_corners() {
        let corners = render(Scene {
            offset: (0.0, 0.0),
            ..Scene::default()
        });
        assert_diagnosed(&corners, &[Diagnosis::HalfPixel]);
    }

    #[test]
    fn background_black() {
        let black = render(Scene {
            background: [0, 0, 0],
            ..Scene::default()
        });
        assert_diagnosed(&black, &[Diagnosis::Background]);
    }

    #[test]
    fn half_the_disc_black() {
        let back_faces = render(Scene {
            black_lower_disc: true,
            ..Scene::default()
        });
        assert_diagnosed(&back_faces, &[Diagnosis::BackFaces]);
    }

    #[test]
    fn background_showing_through_the_rectangle() {
        let mut cracked = reference();
        for k in (0..20).step_by(3) {
            let (x, y) = (36 + k, 7 + k * 12 / 20);
            cracked.pixels[y * WIDTH as usize + x] = GREY;
        }
        assert_diagnosed(&cracked, &[Diagnosis::Cracks]);
    }

    #[test]
    fn triangle_missing() {
        let missing = render(Scene {
            triangle: false,
            ..Scene::default()
        });
        assert_diagnosed(&missing, &[Diagnosis::MissingObject]);
    }

    #[test]
    fn square_added() {
        let extra = render(Scene {
            square: true,
            ..Scene::default()
        });
        assert_diagnosed(&extra, &[Diagnosis::ExtraObject]);
    }

    #[test]
    fn a_few_outline_pixels_jittered() {
        // Each edge pixel with the first neighbour (right, left, below, above) it differs from.
        const FIRST_DIFFERENT: [(isize, isize); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
        let reference = reference();
        let (width, height) = (WIDTH as usize, HEIGHT as usize);
        let edges: Vec<(usize, usize)> = (0..width * height)
            .filter_map(|i| {
                neighbours(width, height, i, &FIRST_DIFFERENT)
                    .find(|&j| channel_difference(reference.pixels[i], reference.pixels[j]) > 2)
                    .map(|j| (i, j))
            })
            .collect();
        let mut jittered = reference.clone();
        for &(i, j) in edges.iter().step_by(40) {
            jittered.pixels[i] = reference.pixels[j];
        }
        assert_diagnosed(&jittered, &[Diagnosis::Silhouette]);
    }

    #[test]
    fn random_noise_is_unknown() {
        let mut noise = Noise(12345);
        let random = map_pixels(&reference(), |_| [noise.byte(), noise.byte(), noise.byte()]);
        assert_diagnosed(&random, &[Diagnosis::Unknown]);
    }

    #[test]
    fn small_noise_everywhere_is_unknown() {
        let mut noise = Noise(777);
        let noisy = map_pixels(&reference(), |colour| {
            colour.map(|level| level.saturating_add(noise.byte() % 21).saturating_sub(10))
        });
        assert_diagnosed(&noisy, &[Diagnosis::Unknown]);
    }

    #[test]
    fn missing_object_and_back_faces_together() {
        let both = render(Scene {
            triangle: false,
            black_lower_disc: true,
            ..Scene::default()
        });
        assert_diagnosed(&both, &[Diagnosis::BackFaces, Diagnosis::MissingObject]);
    }

    #[test]
    fn wrong_background_and_missing_object_together() {
        let both = render(Scene {
            background: [0, 0, 0],
            triangle: false,
            ..Scene::default()
        });
        assert_diagnosed(&both, &[Diagnosis::MissingObject, Diagnosis::Background]);
    }

    /// A depth picture (grey, nearer is brighter, black background) of two spheres seen along
    /// the view axis, each at depth `centre` with radius `radius`, with the far sphere's depths
    /// divided by `far_divisor` (1: drawn right), and `near` to `far` mapped to 255 to 0.
    fn depth_picture(far_divisor: f64, near_divisor: f64) -> Image {
        let (near, far) = (2.0, 7.0);
        let spheres = [
            ((20.0, 22.0), 14.0, 5.0, near_divisor),
            ((46.0, 24.0), 12.0, 4.0, far_divisor),
        ];
        let mut pixels = Vec::new();
        for row in 0..HEIGHT {
            for column in 0..WIDTH {
                let (x, y) = (f64::from(column) + 0.5, f64::from(row) + 0.5);
                let mut nearest = f64::INFINITY;
                for ((cx, cy), radius, centre, divisor) in spheres {
                    let r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (radius * radius);
                    if r2 <= 1.0 {
                        nearest = nearest.min((centre - (1.0 - r2).sqrt()) / divisor);
                    }
                }
                let level = if nearest.is_finite() {
                    (255.0 * ((far - nearest) / (far - near)).clamp(0.0, 1.0)) as u8
                } else {
                    0
                };
                pixels.push([level; 3]);
            }
        }
        Image {
            width: WIDTH,
            height: HEIGHT,
            pixels,
        }
    }

    #[test]
    fn depths_off_per_object_are_object_space_t() {
        let reference = depth_picture(1.0, 1.0);
        let diagnosed = |actual: &Image| diagnose(actual, &reference, TOLERANCE, MAX_BAD);
        assert!(diagnosed(&reference).is_empty());
        // One sphere under `Scale 2`, the other untransformed.
        assert_eq!(
            diagnosed(&depth_picture(2.0, 1.0)),
            [Diagnosis::ObjectSpaceT]
        );
        // Two spheres scaled differently, neither drawn right.
        assert_eq!(
            diagnosed(&depth_picture(1.25, 0.8)),
            [Diagnosis::ObjectSpaceT]
        );
        // Every depth off alike (a wrong near plane, say) is not one object's t.
        assert!(!diagnosed(&depth_picture(1.25, 1.25)).contains(&Diagnosis::ObjectSpaceT));
        // Colour pictures are not depth pictures.
        let coloured = map_pixels(&depth_picture(2.0, 1.0), |[l, _, _]| [l, l / 2, 0]);
        let coloured_reference = map_pixels(&reference, |[l, _, _]| [l, l / 2, 0]);
        assert!(
            !diagnose(&coloured, &coloured_reference, TOLERANCE, MAX_BAD)
                .contains(&Diagnosis::ObjectSpaceT)
        );
    }
}
