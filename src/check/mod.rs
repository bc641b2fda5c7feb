//! `raycast check`: grades any renderer (a student's own) against a suite of the course's command
//! lines and reference images, and names the likely cause of each mismatch; `raycast diff`: the
//! same comparison for two image files.

pub mod diagnose;
mod report;
mod rule;
mod run;
mod suite;

use std::path::{Path, PathBuf};
use std::time::Duration;

use rayon::prelude::*;

pub use diagnose::Diagnosis;
pub use report::write_report;
pub use rule::{Comparison, Rule, compare};
pub use run::Ending;
pub use suite::{Line, Suite};

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
    /// The likely causes.
    pub diagnoses: Vec<Diagnosis>,
    /// What a student should look at.
    pub explanation: String,
    /// The renderer's image, when it could be read.
    pub actual: Option<Image>,
    /// The reference image, when there is one.
    pub reference: Option<Image>,
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
    let scratch = tempfile::tempdir().map_err(|e| format!("cannot make a scratch folder: {e}"))?;
    let scenes = scratch.path().join("scenes");
    run::copy_scenes(&suite.scenes, &scenes)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.max(1))
        .build()
        .map_err(|e| format!("cannot start {} threads: {e}", options.jobs))?;
    let ourselves =
        std::env::current_exe().map_err(|e| format!("cannot find raycast's own program: {e}"))?;
    let graded: Vec<Vec<Graded>> = pool.install(|| {
        suite
            .lines
            .par_iter()
            .enumerate()
            .map(|(number, line)| {
                let folder = scratch.path().join(format!("line{number}"));
                let graded = grade_line(options, &suite, line, &scenes, &folder, &ourselves);
                progress();
                graded
            })
            .collect()
    });
    Ok(graded.into_iter().flatten().collect())
}

/// Runs one line (and raycast on it, where the suite has no references) and grades its images.
fn grade_line(
    options: &CheckOptions,
    suite: &Suite,
    line: &Line,
    scenes: &Path,
    folder: &Path,
    ourselves: &Path,
) -> Vec<Graded> {
    let produce = |who: &str, program: &[String]| -> (Ending, PathBuf) {
        let work = folder.join(format!("{who}-work"));
        let out = folder.join(format!("{who}-out"));
        let prepared = run::work_folder(scenes, &work)
            .and_then(|()| std::fs::create_dir_all(&out).map_err(|e| e.to_string()));
        if let Err(e) = prepared {
            return (Ending::NotStarted(e), out);
        }
        let mut args = line.args.clone();
        for (at, name) in &line.outputs {
            args[*at] = out.join(file_name(name)).to_string_lossy().into_owned();
        }
        (run::run(program, &args, &work, options.timeout), out)
    };
    let (ending, out) = produce("renderer", &options.renderer);
    let reference_run = suite.references.is_none().then(|| {
        let program = [ourselves.to_string_lossy().into_owned()];
        produce("raycast", &program)
    });
    line.outputs
        .iter()
        .map(|(_, name)| {
            let image_name = suite::image_name(name);
            let reference = match (&suite.references, &reference_run) {
                (Some(folder), _) => read_image(&folder.join(format!("{image_name}.png"))),
                (None, Some((Ending::Success, out))) => read_image(&out.join(file_name(name))),
                (None, Some((ending, _))) => {
                    Err(format!("raycast itself could not render it: {ending:?}"))
                }
                (None, None) => Err("no reference".into()),
            };
            grade(
                options,
                line,
                &image_name,
                &ending,
                &out.join(file_name(name)),
                reference,
            )
        })
        .collect()
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
    name: &str,
    ending: &Ending,
    path: &Path,
    reference: Result<Image, String>,
) -> Graded {
    let error = |diagnoses: Vec<Diagnosis>, explanation: String, reference: Option<Image>| Graded {
        name: name.to_string(),
        command: line.command.clone(),
        status: Status::Error,
        bad_fraction: None,
        diagnoses,
        explanation,
        actual: None,
        reference,
    };
    let reference = match reference {
        Ok(image) => image,
        Err(why) => return error(vec![], format!("No reference image: {why}."), None),
    };
    if let Some(explanation) = failed_run(ending) {
        return error(vec![Diagnosis::CRASH], explanation, Some(reference));
    }
    let actual = match read_image(path) {
        Ok(image) => image,
        Err(why) => {
            return error(
                vec![Diagnosis::MISSING_OUTPUT],
                format!("{why}. {}", Diagnosis::MISSING_OUTPUT.explanation()),
                Some(reference),
            );
        }
    };
    let judgement = judge(&actual, &reference, options.rule);
    Graded {
        name: name.to_string(),
        command: line.command.clone(),
        status: if judgement.pass {
            Status::Pass
        } else {
            Status::Fail
        },
        bad_fraction: judgement.bad_fraction,
        explanation: diagnose::explain(&judgement.diagnoses),
        diagnoses: judgement.diagnoses,
        actual: Some(actual),
        reference: Some(reference),
    }
}

/// What went wrong with a run that did not end well, for the student; `None` for a success.
fn failed_run(ending: &Ending) -> Option<String> {
    match ending {
        Ending::Success => None,
        Ending::Failed { status, stderr } => {
            let how = match status {
                Some(code) => format!("exited with status {code}"),
                None => "was killed by a signal".to_string(),
            };
            let said = stderr.lines().next().unwrap_or("").trim();
            let said = if said.is_empty() {
                String::new()
            } else {
                format!(" It said: {said}")
            };
            Some(format!(
                "The renderer {how}.{said} {}",
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
    let size = std::fs::metadata(path)
        .map_err(|_| format!("There is no image '{}'", path.display()))?
        .len();
    if size > MAX_IMAGE_BYTES {
        return Err(format!(
            "The image is {size} bytes, far too big to be one of the course's"
        ));
    }
    let mut reader =
        image::ImageReader::open(path).map_err(|e| format!("The image cannot be opened: {e}"))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(crate::image_io::MAX_SIDE);
    limits.max_image_height = Some(crate::image_io::MAX_SIDE);
    limits.max_alloc = Some(1 << 30);
    reader.limits(limits);
    // TGA has no signature: the guess falls back on the extension.
    let reader = reader
        .with_guessed_format()
        .map_err(|e| format!("The image cannot be read: {e}"))?;
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

/// The one-line verdict of an image for the terminal.
pub fn verdict(graded: &Graded) -> String {
    let off = graded
        .bad_fraction
        .map(|f| format!(", {:.3}% of pixels off", 100.0 * f))
        .unwrap_or_default();
    match graded.status {
        Status::Pass => format!("pass   {}{off}", graded.name),
        Status::Fail | Status::Error => {
            let codes: Vec<&str> = graded.diagnoses.iter().map(|d| d.code()).collect();
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
                graded.explanation
            )
        }
    }
}

/// `summary.json`'s contents.
pub fn summary_json(graded: &[Graded]) -> serde_json::Value {
    let passed = graded.iter().filter(|g| g.status == Status::Pass).count();
    serde_json::json!({
        "passed": passed,
        "failed": graded.len() - passed,
        "images": graded.iter().map(|g| serde_json::json!({
            "name": g.name,
            "command": g.command,
            "status": g.status.code(),
            "bad_fraction": g.bad_fraction,
            "diagnoses": g.diagnoses.iter().map(|d| d.code()).collect::<Vec<_>>(),
            "explanation": g.explanation,
        })).collect::<Vec<_>>(),
    })
}
