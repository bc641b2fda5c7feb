//! The likely cause of a picture's difference from its reference, named by a stable code and
//! explained for a student.
//!
//! Every decision comes from the pixels alone, never from file names. Each picture's background
//! is estimated as the most common colour along its border (scenes frame their objects, so the
//! border is nearly all background). Causes are tried from the whole-picture ones (a flip, a
//! channel swap, a shift, a colour curve: one mistake that moves every pixel), each of which is
//! reported alone when it fits, to the local ones (the background, regions, cracks, depths),
//! which may appear together and each take out the pixels they explain, and last the outline
//! causes, for what is left along the reference's edges.
//!
//! A cause is one file: its [`Diagnosis`] (code, report rank, explanation), its test on the
//! pictures, and the unit tests that plant it. Adding one is that file and one line in
//! `WHOLE_PICTURE`, `LOCAL` or `OUTLINE`.

mod background;
mod cracks;
mod curve;
mod depth;
#[cfg(test)]
mod fixtures;
mod heat_map;
mod outline;
mod pair;
mod pixels;
mod regions;
mod whole;

pub use heat_map::heat_map;

use super::rule::{Rule, compare};
use crate::shade::Image;
use pair::Pair;

/// A kind of mistake, as `raycast check` reports it: a stable snake_case code and one or two
/// sentences telling a student where in their code to look.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Diagnosis {
    code: &'static str,
    /// Where it is listed among the causes of one picture: the most specific first.
    rank: u8,
    explanation: &'static str,
}

impl Diagnosis {
    const fn new(code: &'static str, rank: u8, explanation: &'static str) -> Diagnosis {
        Diagnosis {
            code,
            rank,
            explanation,
        }
    }

    /// The stable snake_case code, as reports and scripts see it.
    pub fn code(self) -> &'static str {
        self.code
    }

    /// One or two sentences telling a student where in their code to look.
    pub fn explanation(self) -> &'static str {
        self.explanation
    }

    /// Whether it is a fact of the run (a crash, no picture, the wrong size) rather than a
    /// guess from the pixels.
    pub fn is_fact(self) -> bool {
        Diagnosis::FACTS.contains(&self)
    }

    /// Every diagnosis `check` can name: those its caller decides, then those of the lists.
    pub fn all() -> impl Iterator<Item = Diagnosis> {
        let found = WHOLE_PICTURE.iter().map(|&(d, _)| d);
        let local = LOCAL.iter().map(|&(d, _)| d);
        let outline = OUTLINE.iter().map(|&(d, _)| d);
        let mut seen = Vec::new();
        Diagnosis::FACTS
            .into_iter()
            .chain(found)
            .chain(local)
            .chain(outline)
            .chain([Diagnosis::UNKNOWN])
            .filter(move |d| {
                let new = !seen.contains(d);
                seen.push(*d);
                new
            })
    }
}

// Decided by the caller (a run that failed, an image that is missing) or by no cause fitting.
impl Diagnosis {
    /// The facts of a run, as opposed to guesses from its pixels.
    const FACTS: [Diagnosis; 15] = [
        Diagnosis::CRASH,
        Diagnosis::CAGE_REFUSED,
        Diagnosis::TIMED_OUT,
        Diagnosis::OUT_OF_MEMORY,
        Diagnosis::OUTPUT_TOO_LARGE,
        Diagnosis::INTERRUPTED,
        Diagnosis::OVER_BUDGET,
        Diagnosis::BUILD_FAILED,
        Diagnosis::CRASH_AT_EXIT,
        Diagnosis::MISSING_OUTPUT,
        Diagnosis::UNREADABLE_OUTPUT,
        Diagnosis::WRONG_FORMAT,
        Diagnosis::SIZE,
        Diagnosis::SUITE_TAMPERED,
        Diagnosis::UNVARIED,
    ];

    /// The renderer crashed, or exited with an error.
    pub const CRASH: Diagnosis = Diagnosis::new(
        "crash",
        8,
        "The renderer crashed or reported an error before writing its picture: run the same \
        command line by hand and read its message.",
    );

    /// The renderer failed because the cage kept it from a file of its own (data, a library)
    /// outside what it may read: it works by hand.
    pub const CAGE_REFUSED: Diagnosis = Diagnosis::new(
        "cage_refused",
        8,
        "The cage that check runs renderers in kept the renderer from a file it reads, outside \
        the system's folders, its own project's folders and the --allow-read paths: by hand it \
        works. Give check --allow-read with the folder that holds it.",
    );

    /// The renderer wrote its whole picture, then crashed or failed on its way out.
    pub const CRASH_AT_EXIT: Diagnosis = Diagnosis::new(
        "crash_at_exit",
        8,
        "The renderer wrote its whole picture and then crashed or failed on its way out: look \
        at what runs after the picture is saved (destructors and clean-up code: a double free, \
        a delete of memory not owned, an object freed twice by two owners).",
    );

    /// The renderer outlasted the line's time limit.
    pub const TIMED_OUT: Diagnosis = Diagnosis::new(
        "timed_out",
        8,
        "The renderer did not finish in time: look for a loop that never ends (a ray that \
        keeps hitting the surface it leaves, a grid walk that never steps out), or time the \
        line by hand.",
    );

    /// The renderer ran out of the memory it may use (said as likely where the kernel gave
    /// no count).
    pub const OUT_OF_MEMORY: Diagnosis = Diagnosis::new(
        "out_of_memory",
        8,
        "The renderer most likely ran out of memory: look for an allocation per ray or per \
        pixel that is never freed, or a structure that grows with every step.",
    );

    /// The renderer wrote a file past the size limit.
    pub const OUTPUT_TOO_LARGE: Diagnosis = Diagnosis::new(
        "output_too_large",
        8,
        "The renderer wrote a file far larger than any picture of the course: check the \
        width and height it writes, and that it writes each pixel once.",
    );

    /// The renderer's time budget ran out before the line ran.
    pub const OVER_BUDGET: Diagnosis = Diagnosis::new(
        "over_budget",
        8,
        "The renderer's lines together took longer than its time budget: make the slow \
        lines faster (an acceleration structure, fewer rays), then run check again.",
    );

    /// The submission did not build, so its renderer was not run.
    pub const BUILD_FAILED: Diagnosis = Diagnosis::new(
        "build_failed",
        8,
        "The submission did not build, so no line was run: read the build's output at the top of \
        the report, and build it by hand the same way.",
    );

    /// check was interrupted before the line ended.
    pub const INTERRUPTED: Diagnosis = Diagnosis::new(
        "interrupted",
        8,
        "check was interrupted before this line was graded: run it again.",
    );

    /// The renderer wrote no picture.
    pub const MISSING_OUTPUT: Diagnosis = Diagnosis::new(
        "missing_output",
        8,
        "The renderer finished but wrote no picture where the command line asked: check that \
        the file name after the picture's option is taken from the command line and that the \
        file is written before the program exits.",
    );

    /// The renderer's picture is there, but is not a picture raycast can read.
    pub const UNREADABLE_OUTPUT: Diagnosis = Diagnosis::new(
        "unreadable_output",
        8,
        "The renderer wrote a file that is not a readable picture: check the file's header \
        and that every pixel is written (a file cut short, or written as text, reads as this).",
    );

    /// The picture is in another format than its name says.
    pub const WRONG_FORMAT: Diagnosis = Diagnosis::new(
        "wrong_format",
        8,
        "The picture is in another format than its file name says (the course's .tga is \
        uncompressed TGA, .ppm is binary PPM): write the format the name asks for.",
    );

    /// The suite's files changed while the renderer ran: the grade is void.
    pub const SUITE_TAMPERED: Diagnosis = Diagnosis::new(
        "suite_tampered",
        8,
        "The suite's files changed while the renderer ran, so no grade of this run counts \
        (a renderer must only read the scenes and write its pictures).",
    );

    /// Graded on varied scenes (`--vary`), the picture is the original scene's.
    pub const UNVARIED: Diagnosis = Diagnosis::new(
        "unvaried",
        8,
        "The picture is the original scene's, not that of the varied scene the renderer was \
        given (--vary): it did not render the scene file named after -input (a scene path \
        written into the program, a scene read from elsewhere, or pictures kept and printed).",
    );

    /// The picture's width or height differs from the reference's.
    pub const SIZE: Diagnosis = Diagnosis::new(
        "size",
        8,
        "The picture has the wrong size: the width and height must come from -size \
        (width first, then height).",
    );

    /// No known mistake explains the difference.
    pub const UNKNOWN: Diagnosis = Diagnosis::new(
        "unknown",
        8,
        "The picture differs in a way no known mistake explains: compare it with the \
        reference and the heat map by eye.",
    );
}

/// A whole-picture test: whether undoing one mistake makes the whole picture match.
type WholePictureTest = fn(&Pair, Budget) -> bool;
/// A local test: takes the pixels it explains out of `unexplained`, and names what it found (its
/// own diagnosis, or a related one the pixels show it to be).
type LocalTest = fn(&Pair, &mut [bool]) -> Option<Diagnosis>;
/// An outline test, on the differing pixels no local cause explained.
type OutlineTest = fn(&Pair, &[usize]) -> bool;

/// Tried in order; the first that fits is the only cause reported.
const WHOLE_PICTURE: &[(Diagnosis, WholePictureTest)] = &[
    (Diagnosis::FLIPPED_VERTICAL, whole::flipped_vertical),
    (Diagnosis::FLIPPED_HORIZONTAL, whole::flipped_horizontal),
    (Diagnosis::TRANSPOSED, whole::transposed),
    (Diagnosis::CHANNEL_SWAP, whole::channel_swap),
    (Diagnosis::SHIFT, whole::shifted),
    (Diagnosis::GAMMA, curve::gamma),
    (Diagnosis::COLOUR_SCALE, curve::colour_scale),
];

/// Each tried in turn on what the ones before it left unexplained.
const LOCAL: &[(Diagnosis, LocalTest)] = &[
    (Diagnosis::BACKGROUND, background::wrong_background),
    (Diagnosis::OBJECT_SPACE_T, depth::object_space_t),
    (Diagnosis::CRACKS, cracks::cracks),
    (Diagnosis::MISSING_OBJECT, regions::missing_object),
    (Diagnosis::EXTRA_OBJECT, regions::extra_object),
    (Diagnosis::BACK_FACES, regions::back_faces),
];

/// Tried in order on what is left along the outlines; the first that fits is reported.
const OUTLINE: &[(Diagnosis, OutlineTest)] = &[
    (Diagnosis::HALF_PIXEL, outline::half_pixel),
    (Diagnosis::SILHOUETTE, outline::silhouette),
];

/// What a whole-picture cause must achieve: how many pixels differ as the picture is, and the
/// rule's share.
#[derive(Debug, Clone, Copy)]
struct Budget {
    plain_bad: f64,
    max_bad: f64,
}

/// The explanations of `diagnoses`, in order, as one paragraph; empty when there are none.
pub fn explain(diagnoses: &[Diagnosis]) -> String {
    diagnoses
        .iter()
        .map(|d| d.explanation())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The likely causes of the difference, decided from the pixels alone, in a fixed order from
/// the most specific; empty when the pictures pass `rule`. A whole-picture cause comes alone;
/// `size` comes alone when the sizes differ; `unknown` when nothing fits.
pub fn diagnose(actual: &Image, reference: &Image, rule: Rule) -> Vec<Diagnosis> {
    let Some(comparison) = compare(actual, reference, rule.tolerance) else {
        return vec![Diagnosis::SIZE];
    };
    if comparison.differing == 0 || rule.passes(&comparison) {
        return Vec::new();
    }
    let pair = Pair::new(actual, reference, rule.tolerance);
    let budget = Budget {
        plain_bad: comparison.bad_fraction,
        max_bad: rule.max_bad,
    };
    if let Some(&(whole, _)) = WHOLE_PICTURE.iter().find(|(_, fits)| fits(&pair, budget)) {
        return vec![whole];
    }
    let mut unexplained = comparison.mask;
    let mut found: Vec<Diagnosis> = LOCAL
        .iter()
        .filter_map(|(_, test)| test(&pair, &mut unexplained))
        .collect();
    found.dedup();
    let residual: Vec<usize> = (0..unexplained.len()).filter(|&i| unexplained[i]).collect();
    // What is left may be too little to fail on its own: then it needs no cause.
    if residual.len() as f64 > rule.max_bad * unexplained.len() as f64
        && let Some(&(outline, _)) = OUTLINE.iter().find(|(_, fits)| fits(&pair, &residual))
    {
        found.push(outline);
    }
    if found.is_empty() {
        found.push(Diagnosis::UNKNOWN);
    }
    found.sort_by_key(|diagnosis| diagnosis.rank);
    found
}

/// Whether the objects stand elsewhere in `actual` than in `reference`: more pixels than `rule`
/// allows show the background in one picture and an object in the other (each picture's
/// background its border's colour). Never for a reference without a background to tell by.
pub fn silhouette_moved(actual: &Image, reference: &Image, rule: Rule) -> bool {
    if compare(actual, reference, rule.tolerance).is_none() {
        return false;
    }
    let pair = Pair::new(actual, reference, rule.tolerance);
    if !pair.reference_has_background {
        return false;
    }
    let moved = (0..pair.actual.len())
        .filter(|&i| pair.reference_shows_background[i] != pair.actual_shows_background(i))
        .count();
    moved as f64 > rule.max_bad * pair.actual.len() as f64
}

/// The box that holds a picture's objects: the least and greatest column and row (rows from the
/// top) of the pixels that are not its background (its border's colour); `None` where the
/// picture shows nothing but background.
pub fn object_bounds(image: &Image, tolerance: u8) -> Option<[f64; 4]> {
    let (width, height) = (image.width as usize, image.height as usize);
    if image.pixels.len() != width * height {
        return None;
    }
    let background = pixels::border_mode(&image.pixels, width, height);
    let mut bounds: Option<[f64; 4]> = None;
    for (index, &colour) in image.pixels.iter().enumerate() {
        if crate::check::rule::channel_difference(colour, background) <= tolerance {
            continue;
        }
        let (x, y) = ((index % width) as f64, (index / width) as f64);
        let b = bounds.get_or_insert([x, y, x, y]);
        *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    bounds
}

#[cfg(test)]
mod tests {
    use super::fixtures::*;
    use super::*;

    #[test]
    fn codes_are_distinct_snake_case_with_explanations() {
        let codes: Vec<&str> = Diagnosis::all().map(|d| d.code()).collect();
        assert_eq!(codes.len(), 31);
        for (i, code) in codes.iter().enumerate() {
            assert!(
                code.chars().all(|c| c.is_ascii_lowercase() || c == '_'),
                "{code}"
            );
            assert!(!codes[..i].contains(code), "{code} twice");
        }
        assert!(Diagnosis::all().all(|d| d.explanation().ends_with('.')));
        assert_eq!(
            Diagnosis::HALF_PIXEL.explanation(),
            "Every edge is off by about half a pixel: the camera rays go through pixel corners \
             instead of centres; sample at (i + 0.5, j + 0.5)."
        );
    }

    #[test]
    fn explain_joins_the_explanations_in_order() {
        assert_eq!(explain(&[]), "");
        let both = explain(&[Diagnosis::CRACKS, Diagnosis::BACKGROUND]);
        let expected = format!(
            "{} {}",
            Diagnosis::CRACKS.explanation(),
            Diagnosis::BACKGROUND.explanation()
        );
        assert_eq!(both, expected);
    }

    #[test]
    fn identical_pictures_pass_with_no_diagnosis() {
        let reference = reference();
        let actual = reference.clone();
        let comparison = compare(&actual, &reference, TOLERANCE).expect("same size");
        assert_eq!((comparison.differing, comparison.worst), (0, 0));
        assert!(RULE.passes(&comparison));
        assert!(diagnose(&actual, &reference, RULE).is_empty());
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
        assert_eq!(diagnose(&cropped, &reference, RULE), [Diagnosis::SIZE]);
    }

    #[test]
    fn random_noise_is_unknown() {
        let mut noise = Noise(12345);
        let random = map_pixels(&reference(), |_| [noise.byte(), noise.byte(), noise.byte()]);
        assert_diagnosed(&random, &[Diagnosis::UNKNOWN]);
    }

    #[test]
    fn small_noise_everywhere_is_unknown() {
        let mut noise = Noise(777);
        let noisy = map_pixels(&reference(), |colour| {
            colour.map(|level| level.saturating_add(noise.byte() % 21).saturating_sub(10))
        });
        assert_diagnosed(&noisy, &[Diagnosis::UNKNOWN]);
    }

    #[test]
    fn missing_object_and_back_faces_together() {
        let both = render(Scene {
            triangle: false,
            black_lower_disc: true,
            ..Scene::default()
        });
        assert_diagnosed(&both, &[Diagnosis::BACK_FACES, Diagnosis::MISSING_OBJECT]);
    }

    #[test]
    fn wrong_background_and_missing_object_together() {
        let both = render(Scene {
            background: [0, 0, 0],
            triangle: false,
            ..Scene::default()
        });
        assert_diagnosed(&both, &[Diagnosis::MISSING_OBJECT, Diagnosis::BACKGROUND]);
    }
}
