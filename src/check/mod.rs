//! `raycast check`: grades any renderer (a student's own) against a suite of the course's command
//! lines and reference images, and names the likely cause of each mismatch; `raycast diff`: the
//! same comparison for two image files.

pub mod diagnose;
pub mod faults;
mod finding;
mod guard;
mod report;
mod rule;
mod run;
mod simulate;
mod suite;
mod verdict;

use std::path::{Path, PathBuf};
use std::time::Duration;

use rayon::prelude::*;

pub use diagnose::Diagnosis;
pub use finding::Finding;
pub use report::write_report;
pub use rule::{Comparison, Rule, compare};
pub use run::{Ending, Ran};
pub use simulate::FaultMatch;
pub use suite::{Line, PictureKind, Suite};
pub use verdict::{
    Group, entries as verdict_entries, lines as verdict_lines, verdict as renderer_verdict,
};

use crate::shade::Image;

/// How `check` runs and grades.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckOptions {
    /// The suite's folder.
    pub suite: PathBuf,
    /// The renderer's command: the executable, then any arguments of its own.
    pub renderer: Vec<String>,
    /// Where to write `summary.json` and `index.html`, if anywhere.
    pub report: Option<PathBuf>,
    /// When an image passes.
    pub rule: Rule,
    /// How many command lines run at once.
    pub jobs: usize,
    /// How long one command line may run.
    pub timeout: Duration,
    /// Pass `-gui`, `-tessellation` and `-gouraud` on to the renderer (dropped by default).
    pub keep_preview_options: bool,
}

impl CheckOptions {
    /// The conformance tests' rule (2 levels, 0.1 % of pixels), one job a core, 60 s a line.
    pub fn new(suite: PathBuf, renderer: Vec<String>) -> CheckOptions {
        CheckOptions {
            suite,
            renderer,
            report: None,
            rule: Rule::COURSE,
            jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
            timeout: Duration::from_secs(60),
            keep_preview_options: false,
        }
    }
}

/// An image's grade.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Within the tolerance.
    Pass,
    /// Made, but too different.
    Fail,
    /// Not made: the renderer crashed, hung, or wrote no image.
    Error,
}

impl Status {
    /// As `summary.json` writes it.
    pub fn code(self) -> &'static str {
        match self {
            Status::Pass => "pass",
            Status::Fail => "fail",
            Status::Error => "error",
        }
    }
}

/// One image of the suite, graded.
#[derive(Debug, Clone, PartialEq)]
pub struct Graded {
    /// The image's file name without its extension.
    pub name: String,
    /// The command line that makes it.
    pub command: String,
    /// Pass, fail or error.
    pub status: Status,
    /// The share of pixels off by more than the tolerance, when both images could be read.
    pub bad_fraction: Option<f64>,
    /// The causes named: the faults whose render matches the picture, or what the run or the
    /// pixels show.
    pub findings: Vec<Finding>,
    /// What a student should look at.
    pub explanation: String,
    /// The renderer's image, when it could be read.
    pub actual: Option<Image>,
    /// The reference image, when there is one.
    pub reference: Option<Image>,
    /// The end of what the renderer said on stderr while making it.
    pub stderr: String,
    /// How long the renderer took over the line, in seconds.
    pub seconds: f64,
    /// The suite has no reference for it: it is graded against raycast's render of the line.
    pub against_raycast: bool,
    /// What kind of picture it is (the option that names it).
    pub picture: PictureKind,
    /// For a failing picture: raycast's account (`-inspect`) of the pixel where it differs
    /// most from the reference.
    pub worst_pixel: Option<WorstPixel>,
}

/// The pixel where a failing picture differs most from its reference, and what raycast's
/// tracer did there.
#[derive(Debug, Clone, PartialEq)]
pub struct WorstPixel {
    /// Counted as `-inspect` counts them: x from the left, y from the bottom.
    pub x: u32,
    /// From the bottom.
    pub y: u32,
    /// The largest difference of a channel there, in levels.
    pub difference: u8,
    /// `-inspect X Y` of the line, as raycast prints it.
    pub ray_tree: String,
}

/// The pixel where `actual` differs most from `reference` (the largest difference of a channel;
/// among equals, the one nearest the image's centre), as `-inspect` counts pixels, and the
/// difference; `None` when the sizes differ or nothing differs.
pub fn worst_pixel(actual: &Image, reference: &Image) -> Option<(u32, u32, u8)> {
    if (actual.width, actual.height) != (reference.width, reference.height) {
        return None;
    }
    let (w, h) = (actual.width, actual.height);
    let centre_distance = |k: usize| {
        let (x, row) = ((k as u32 % w) as f64 + 0.5, (k as u32 / w) as f64 + 0.5);
        (x - f64::from(w) / 2.0).powi(2) + (row - f64::from(h) / 2.0).powi(2)
    };
    let (k, difference) = actual
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, r)| {
            a.iter()
                .zip(r)
                .map(|(p, q)| p.abs_diff(*q))
                .max()
                .unwrap_or(0)
        })
        .enumerate()
        .filter(|&(_, d)| d > 0)
        .min_by(|&(i, d), &(j, e)| {
            e.cmp(&d)
                .then(centre_distance(i).total_cmp(&centre_distance(j)))
        })?;
    let (x, row) = (k as u32 % w, k as u32 / w);
    Some((x, h - 1 - row, difference))
}

/// What the rule says of one picture against its reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    /// Whether the picture passes.
    pub pass: bool,
    /// The share of pixels off by more than the tolerance; `None` when the sizes differ.
    pub bad_fraction: Option<f64>,
    /// The likely causes of a failure (empty for a pass).
    pub diagnoses: Vec<Diagnosis>,
}

/// Compares `actual` with `reference` by `rule`, and diagnoses a failure: the one decision of
/// pass or fail, for `check` and `diff` alike.
pub fn judge(actual: &Image, reference: &Image, rule: Rule) -> Judgement {
    let Some(comparison) = compare(actual, reference, rule.tolerance) else {
        return Judgement {
            pass: false,
            bad_fraction: None,
            diagnoses: vec![Diagnosis::SIZE],
        };
    };
    let pass = rule.passes(&comparison);
    Judgement {
        pass,
        bad_fraction: Some(comparison.bad_fraction),
        diagnoses: if pass {
            Vec::new()
        } else {
            diagnose::diagnose(actual, reference, rule)
        },
    }
}

/// The largest image file `check` reads: anything bigger is not a picture of the course.
const MAX_IMAGE_BYTES: u64 = 256 << 20;

/// Runs every line of the suite with the renderer and grades every image it should write.
/// `progress` is called once a line has run. The error is a usage or suite problem.
pub fn check(options: &CheckOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Graded>, String> {
    let suite = Suite::read(&options.suite)?;
    run::check_program(&options.renderer)?;
    let fingerprint = guard::Fingerprint::of(&options.suite)?;
    let scratch = tempfile::tempdir().map_err(|e| format!("cannot make a scratch folder: {e}"))?;
    let scenes = scratch.path().join("scenes");
    run::copy_scenes(&suite.scenes, &scenes)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.max(1))
        .build()
        .map_err(|e| format!("cannot start {} threads: {e}", options.jobs))?;
    // Every reference read, and raycast's own made, before any of the renderer's code runs:
    // nothing it does to the suite's files can change what it is graded against.
    let references: Vec<References> = pool.install(|| {
        suite
            .lines
            .par_iter()
            .with_max_len(1)
            .map(|line| references_of(&suite, line))
            .collect()
    });
    let graded: Vec<Vec<Graded>> = pool.install(|| {
        suite
            .lines
            .par_iter()
            .zip(references)
            // One line a task: lines differ in time a hundredfold, and a worker that runs out
            // takes the next line, not half of another's.
            .with_max_len(1)
            .enumerate()
            .map(|(number, (line, references))| {
                let folder = scratch.path().join(format!("line{number}"));
                let graded = grade_line(options, &suite, line, references, &scenes, &folder);
                progress();
                graded
            })
            .collect()
    });
    let mut graded: Vec<Graded> = graded.into_iter().flatten().collect();
    unique_names(&mut graded);
    let changed = guard::Fingerprint::of(&options.suite)
        .map(|after| fingerprint.changed(&after))
        .unwrap_or_else(|why| vec![PathBuf::from(why)]);
    if !changed.is_empty() {
        void(&mut graded, &changed);
    }
    Ok(graded)
}

/// A renderer changed the suite's files while it ran: every grade of the run is void, each
/// picture an error that names the files.
fn void(graded: &mut [Graded], changed: &[PathBuf]) {
    let files: Vec<String> = changed
        .iter()
        .take(10)
        .map(|p| p.display().to_string())
        .collect();
    let more = changed.len().saturating_sub(files.len());
    let explanation = format!(
        "{} Changed: {}{}.",
        Diagnosis::SUITE_TAMPERED.explanation(),
        files.join(", "),
        if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        }
    );
    for g in graded.iter_mut() {
        g.status = Status::Error;
        g.bad_fraction = None;
        g.findings = vec![Finding::Diagnosis(Diagnosis::SUITE_TAMPERED)];
        g.explanation = explanation.clone();
        g.worst_pixel = None;
    }
}

/// How many lines of the options' suite name a preview option.
pub fn preview_lines(options: &CheckOptions) -> usize {
    Suite::read(&options.suite)
        .map(|suite| {
            suite
                .lines
                .iter()
                .filter(|l| l.has_preview_options())
                .count()
        })
        .unwrap_or(0)
}

/// Several lines may write an image of the same name (the course's A3 lines write output3_08
/// four times): the second and later are named `NAME#2`, `NAME#3`, so a report tells them apart.
fn unique_names(graded: &mut [Graded]) {
    let mut seen: Vec<(String, usize)> = Vec::new();
    for g in graded.iter_mut() {
        match seen.iter_mut().find(|(name, _)| *name == g.name) {
            Some((_, count)) => {
                *count += 1;
                g.name = format!("{}#{count}", g.name);
            }
            None => seen.push((g.name.clone(), 1)),
        }
    }
}

/// A line's references, one for each image it writes: the suite's, or raycast's own render of
/// the line (`true`) where the suite has none.
type References = Vec<(Result<Image, String>, bool)>;

/// Reads the references of `line`'s images, rendering the line with raycast for those the suite
/// lacks (once for all of them).
fn references_of(suite: &Suite, line: &Line) -> References {
    let own = std::sync::OnceLock::new();
    line.outputs
        .iter()
        .enumerate()
        .map(
            |(k, (_, name))| match suite.reference(&suite::image_name(name)) {
                Some(path) => (read_image(&path), false),
                None => {
                    let pictures =
                        own.get_or_init(|| simulate::course_pictures(line, &suite.scenes));
                    let picture = match pictures {
                        Ok(pictures) => pictures
                            .get(k)
                            .cloned()
                            .ok_or_else(|| "raycast made no such picture".to_string()),
                        Err(why) => Err(format!("raycast itself could not render it: {why}")),
                    };
                    (picture, true)
                }
            },
        )
        .collect()
}

/// Runs one line and grades its images, each against its reference (read before any renderer
/// ran).
fn grade_line(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    references: References,
    scenes: &Path,
    folder: &Path,
) -> Vec<Graded> {
    let produce = |who: &str, program: &[String]| -> (Ran, PathBuf) {
        let work = folder.join(format!("{who}-work"));
        let out = folder.join(format!("{who}-out"));
        let prepared = run::work_folder(scenes, &work)
            .and_then(|()| std::fs::create_dir_all(&out).map_err(|e| e.to_string()));
        if let Err(e) = prepared {
            let ran = Ran {
                ending: Ending::NotStarted(e),
                stderr: String::new(),
                seconds: 0.0,
            };
            return (ran, out);
        }
        let mut args = line.args.clone();
        for (at, name) in &line.outputs {
            args[*at] = out.join(file_name(name)).to_string_lossy().into_owned();
        }
        if !options.keep_preview_options {
            args = suite::without_preview_options(&args);
        }
        (run::run(program, &args, &work, options.timeout), out)
    };
    let (ran, out) = produce("renderer", &options.renderer);
    let mut graded: Vec<Graded> = line
        .outputs
        .iter()
        .zip(references)
        .enumerate()
        .map(|(k, ((_, name), (reference, own_render)))| {
            let image_name = suite::image_name(name);
            let mut graded = grade(
                options,
                line,
                k,
                &image_name,
                &ran,
                &out.join(file_name(name)),
                reference,
            );
            graded.against_raycast = own_render;
            graded
        })
        .collect();
    explain_by_simulation(options, suite, line, &mut graded);
    for g in graded.iter_mut().filter(|g| g.status == Status::Fail) {
        let (Some(actual), Some(reference)) = (&g.actual, &g.reference) else {
            continue;
        };
        let Some((x, y, difference)) = worst_pixel(actual, reference) else {
            continue;
        };
        if let Ok(ray_tree) = simulate::ray_tree(line, &suite.scenes, (x, y)) {
            g.worst_pixel = Some(WorstPixel {
                x,
                y,
                difference,
                ray_tree,
            });
        }
    }
    graded
}

/// Names the faults whose render of the line matches each failing picture; where none does,
/// the pixels' guesses stay, said to be guesses.
fn explain_by_simulation(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    graded: &mut [Graded],
) {
    let failing: Vec<(usize, &Image)> = graded
        .iter()
        .enumerate()
        .filter(|(_, g)| g.status == Status::Fail)
        .filter_map(|(k, g)| g.actual.as_ref().map(|actual| (k, actual)))
        .collect();
    if failing.is_empty() {
        return;
    }
    let indices: Vec<usize> = failing.iter().map(|&(k, _)| k).collect();
    let Ok(simulated) = simulate::simulate(line, &suite.scenes, &failing, options.rule) else {
        // A line raycast cannot render itself leaves the guesses as they are.
        return;
    };
    for (k, result) in indices.into_iter().zip(simulated) {
        if result.matches.is_empty() {
            continue;
        }
        let g = &mut graded[k];
        g.findings = result.matches.into_iter().map(Finding::Fault).collect();
        g.explanation = finding::explain(&g.findings, g.picture);
    }
}

fn file_name(name: &str) -> String {
    Path::new(name)
        .file_name()
        .map_or_else(|| name.to_string(), |n| n.to_string_lossy().into_owned())
}

/// Grades one image from how its run ended and what it left.
fn grade(
    options: &CheckOptions,
    line: &Line,
    index: usize,
    name: &str,
    ran: &Ran,
    path: &Path,
    reference: Result<Image, String>,
) -> Graded {
    let graded = |status, findings: Vec<Finding>, explanation: String| Graded {
        name: name.to_string(),
        command: line.command.clone(),
        status,
        bad_fraction: None,
        findings,
        explanation,
        actual: None,
        reference: None,
        stderr: ran.stderr.clone(),
        seconds: ran.seconds,
        against_raycast: false,
        picture: line.picture_kind(index),
        worst_pixel: None,
    };
    let reference = match reference {
        Ok(image) => image,
        Err(why) => {
            return graded(Status::Error, vec![], format!("No reference image: {why}."));
        }
    };
    if let Some(explanation) = failed_run(ran) {
        return Graded {
            reference: Some(reference),
            ..graded(
                Status::Error,
                vec![Finding::Diagnosis(Diagnosis::CRASH)],
                explanation,
            )
        };
    }
    let actual = match read_output(path) {
        Ok(image) => image,
        Err(why) => {
            let explanation = format!(
                "{why}. {}{}",
                Diagnosis::MISSING_OUTPUT.explanation(),
                said(&ran.stderr)
            );
            return Graded {
                reference: Some(reference),
                ..graded(
                    Status::Error,
                    vec![Finding::Diagnosis(Diagnosis::MISSING_OUTPUT)],
                    explanation,
                )
            };
        }
    };
    let judgement = judge(&actual, &reference, options.rule);
    let findings: Vec<Finding> = judgement
        .diagnoses
        .into_iter()
        .map(Finding::Diagnosis)
        .collect();
    Graded {
        status: if judgement.pass {
            Status::Pass
        } else {
            Status::Fail
        },
        bad_fraction: judgement.bad_fraction,
        explanation: finding::explain(&findings, line.picture_kind(index)),
        findings,
        actual: Some(actual),
        reference: Some(reference),
        ..graded(Status::Pass, vec![], String::new())
    }
}

/// The renderer's last words on stderr, for a message: " It said: ..." (up to three lines), or
/// nothing.
fn said(stderr: &str) -> String {
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    if lines.is_empty() {
        return String::new();
    }
    let last = &lines[lines.len().saturating_sub(3)..];
    format!(" It said: {}", last.join(" / "))
}

/// What went wrong with a run that did not end well, for the student; `None` for a success.
fn failed_run(ran: &Ran) -> Option<String> {
    match &ran.ending {
        Ending::Success => None,
        Ending::Failed { status } => {
            let how = match status {
                Some(code) => format!("exited with status {code}"),
                None => "was killed by a signal".to_string(),
            };
            Some(format!(
                "The renderer {how}.{} {}",
                said(&ran.stderr),
                Diagnosis::CRASH.explanation()
            ))
        }
        Ending::TimedOut(limit) => Some(format!(
            "The renderer did not finish within {} s and was stopped.",
            limit.as_secs_f64()
        )),
        Ending::NotStarted(why) => Some(format!("The renderer could not be started: {why}.")),
    }
}

/// Reads an image a renderer wrote, whatever it is: refused when missing, too big, or not a
/// picture in a format raycast reads (TGA, PPM, PNG).
pub fn read_image(path: &Path) -> Result<Image, String> {
    read_picture(path, true)
}

/// [`read_image`] of what a renderer wrote: refused if it is a symbolic link (which a renderer
/// could point at the reference).
pub fn read_output(path: &Path) -> Result<Image, String> {
    read_picture(path, false)
}

fn read_picture(path: &Path, follow_links: bool) -> Result<Image, String> {
    let file = open_plain(path, follow_links)?;
    let size = file
        .metadata()
        .map_err(|e| format!("The image cannot be read: {e}"))?
        .len();
    if size > MAX_IMAGE_BYTES {
        return Err(format!(
            "The image is {size} bytes, far too big to be one of the course's"
        ));
    }
    let mut reader = image::ImageReader::new(std::io::BufReader::new(file));
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(crate::image_io::MAX_SIDE);
    limits.max_image_height = Some(crate::image_io::MAX_SIDE);
    limits.max_alloc = Some(1 << 30);
    reader.limits(limits);
    // TGA has no signature: the guess falls back on the extension.
    let mut reader = reader
        .with_guessed_format()
        .map_err(|e| format!("The image cannot be read: {e}"))?;
    if reader.format().is_none()
        && let Ok(format) = image::ImageFormat::from_path(path)
    {
        reader.set_format(format);
    }
    let decoded = reader
        .decode()
        .map_err(|e| format!("The file is not a readable image: {e}"))?
        .to_rgb8();
    Ok(Image {
        width: decoded.width(),
        height: decoded.height(),
        pixels: decoded.pixels().map(|p| p.0).collect(),
    })
}

/// Opens `path` for reading only if it is a plain file, without blocking on a FIFO (which
/// would hang the check); unless `follow_links`, not through a symbolic link either.
fn open_plain(path: &Path, follow_links: bool) -> Result<std::fs::File, String> {
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let mut flags = rustix::fs::OFlags::NONBLOCK;
        if !follow_links {
            flags |= rustix::fs::OFlags::NOFOLLOW;
        }
        open.custom_flags(flags.bits() as i32);
    }
    let kind = std::fs::symlink_metadata(path).map(|m| m.file_type());
    if !follow_links && kind.as_ref().is_ok_and(|k| k.is_symlink()) {
        return Err("The image is a symbolic link: raycast reads only plain files".into());
    }
    let file = open.open(path).map_err(|e| match kind {
        Ok(_) => format!("The image cannot be opened: {e}"),
        Err(_) => format!("There is no image '{}'", path.display()),
    })?;
    let is_file = file.metadata().map(|m| m.is_file()).unwrap_or(false);
    if !is_file {
        return Err(
            "The image is not a plain file (a FIFO, a folder or a device): raycast reads only \
             plain files"
                .into(),
        );
    }
    Ok(file)
}

/// The one-line verdict of an image for the terminal.
pub fn verdict(graded: &Graded) -> String {
    let against = if graded.against_raycast {
        " against raycast's render"
    } else {
        ""
    };
    let off = graded
        .bad_fraction
        .map(|f| format!(", {:.3}% of pixels off{against}", 100.0 * f))
        .unwrap_or_default();
    match graded.status {
        Status::Pass => format!("pass   {}{off}", graded.name),
        Status::Fail | Status::Error => {
            let codes: Vec<String> = graded.findings.iter().map(Finding::code).collect();
            let codes = if codes.is_empty() {
                "unknown".to_string()
            } else {
                codes.join(", ")
            };
            format!(
                "{}  {}{off}: {codes}: {}",
                if graded.status == Status::Fail {
                    "FAIL "
                } else {
                    "ERROR"
                },
                graded.name,
                finding::headline(&graded.findings, &graded.explanation)
            )
        }
    }
}

/// `summary.json`'s contents: raycast's version and the rule, the counts, the renderer's
/// verdict (`{fault, lines}`, biggest group first), and for each image its status, the share
/// of pixels off, its causes (`diagnoses`, the one the verdict names first), what to look at,
/// the renderer's last words on stderr and its time for the line, and for a failing picture
/// the pixel where it differs most with raycast's account of it (`worst_pixel`).
pub fn summary_json(graded: &[Graded], groups: &[Group], rule: Rule) -> serde_json::Value {
    let passed = graded.iter().filter(|g| g.status == Status::Pass).count();
    serde_json::json!({
        "raycast": env!("CARGO_PKG_VERSION"),
        "rule": { "tolerance": rule.tolerance, "max_bad": rule.max_bad },
        "passed": passed,
        "failed": graded.len() - passed,
        "verdict": verdict::json(groups),
        "images": graded.iter().map(|g| serde_json::json!({
            "name": g.name,
            "command": g.command,
            "status": g.status.code(),
            "bad_fraction": g.bad_fraction,
            "diagnoses": g.findings.iter().map(Finding::json).collect::<Vec<_>>(),
            "explanation": g.explanation,
            "reference": if g.against_raycast { "raycast" } else { "suite" },
            "stderr": last_lines(&g.stderr, 20),
            "seconds": g.seconds,
            "worst_pixel": g.worst_pixel.as_ref().map(|w| serde_json::json!({
                "x": w.x, "y": w.y, "difference": w.difference, "ray_tree": w.ray_tree,
            })),
        })).collect::<Vec<_>>(),
    })
}

/// The last `n` lines of `text`.
pub(crate) fn last_lines(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, pixels: Vec<[u8; 3]>) -> Image {
        Image {
            width,
            height,
            pixels,
        }
    }

    #[test]
    fn the_worst_pixel_is_the_largest_difference_nearest_the_centre() {
        let reference = image(4, 3, vec![[0; 3]; 12]);
        let mut actual = reference.clone();
        assert_eq!(worst_pixel(&actual, &reference), None);
        // Two pixels 9 levels off: (0, 0) in the top-left corner and (2, 1) in the middle row;
        // the middle one wins. Rows are stored top first; -inspect counts y from the bottom.
        actual.pixels[0] = [0, 9, 0];
        actual.pixels[4 + 2] = [9, 0, 0];
        actual.pixels[11] = [0, 0, 5];
        assert_eq!(worst_pixel(&actual, &reference), Some((2, 1, 9)));
        // A larger difference anywhere beats them: (3, 0) bottom-right, stored last.
        actual.pixels[11] = [0, 0, 200];
        assert_eq!(worst_pixel(&actual, &reference), Some((3, 0, 200)));
        // Sizes that differ have no pixel to compare.
        assert_eq!(worst_pixel(&image(2, 2, vec![[0; 3]; 4]), &reference), None);
    }
}
