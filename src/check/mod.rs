//! `raycast check`: grades any renderer (a student's own) against a suite of the course's command
//! lines and reference images, and names the likely cause of each mismatch; `raycast diff`: the
//! same comparison for two image files.

mod cache;
mod cage;
mod chance;
pub mod choices;
pub mod class;
pub mod diagnose;
mod diagnosis;
mod envelope;
mod failure;
pub mod faults;
mod finding;
mod fit;
pub mod formats;
mod guard;
mod likely;
pub mod merge;
pub(crate) mod modes;
mod output;
mod picture;
mod progress;
mod project;
mod references;
mod refused;
mod report;
mod rule;
mod run;
mod samples_picture;
mod scratch;
mod screen;
mod simulate;
mod suite;
pub(crate) mod untrusted;
mod vary;
mod verdict;

use failure::{OWN_MESSAGE_ADVICE, how_it_ended};
use references::References;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use crate::render::StopFlag;
use std::time::Duration;

use rayon::prelude::*;

pub use cage::{Confinement, Ending, Limits, Ran, SUPERVISE, supervise};
pub use diagnose::Diagnosis;
pub use finding::Finding;
pub use output::{MAX_IMAGE_BYTES, read_image};
pub use progress::{Progress, Snapshot};
pub use report::{Pictures, Staging, write_report};
pub use rule::{Comparison, Rule, compare};
pub use scratch::{Scratch, remove_all_now as remove_scratch_now};
pub use simulate::FaultMatch;
pub use simulate::{Located, Place};
pub use suite::{Line, PictureKind, Suite};
pub use untrusted::visible;
pub use vary::{Variation, VariedSuite, student_seed};
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
    /// The renderer's resource limits.
    pub limits: Limits,
    /// What the renderer may read besides the system's files and its own program's folder
    /// (`--allow-read`).
    pub readable: Vec<PathBuf>,
    /// This run's share of the suite's lines (`--shard K/N`): those whose place, counted from
    /// 0, is K - 1 modulo N.
    pub shard: Option<(usize, usize)>,
    /// The most time the renderer's lines may take together (`--budget`, without `--class`:
    /// a class's budget is each student's); the lines left when it is spent are not run.
    pub budget: Option<Duration>,
    /// The whole run's time (`--deadline`: a platform's hard limit). The caller sets the stop
    /// flag out of time before it ends, leaving time for the report; check then stops as it
    /// does when asked, the lines not reached and the diagnoses cut short said to be so.
    pub deadline: Option<Duration>,
    /// Grade even where no wall keeps the renderer from the references (`--no-cage`): for a
    /// student's own renderer on their own machine, never strangers'. Every report says so.
    pub no_cage: bool,
    /// Whether the programs graded are other people's (a class): where the cage cannot keep a
    /// renderer's reads (Windows), they are graded only with `--no-cage`.
    pub others: bool,
    /// `--vary SEED`: every line's scene varied within bounds that keep what it tests, and
    /// graded against raycast's render of the varied scene (in a class, each student's own
    /// variation, from the seed and their name).
    pub vary: Option<u64>,
    /// While check grades a varied copy (`suite`): the variation, and the suite it was made
    /// from (hidden from renderers as the copy is, and the folder whose wall must hold).
    pub varied: Option<Variation>,
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
            limits: Limits::default(),
            readable: Vec::new(),
            shard: None,
            budget: None,
            deadline: None,
            no_cage: false,
            others: false,
            vary: None,
            varied: None,
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
    /// It is drawn by chance (random or jittered samples): graded against the spread of
    /// raycast's renders with several seeds, or by a samples picture's structure.
    pub by_chance: bool,
    /// What kind of picture it is (the option that names it).
    pub picture: PictureKind,
    /// For a failing picture: raycast's account (`-inspect`) of the pixel where it differs
    /// most from the reference.
    pub worst_pixel: Option<WorstPixel>,
    /// The report's files of its pictures, once written (its pixels are dropped then).
    pub pictures: Pictures,
    /// What a pass is worth (the suite's `POINTS`; one by default).
    pub points: f64,
    /// The suite's line that makes it (its number, from 0) and which of the line's pictures
    /// it is.
    pub line: (usize, usize),
    /// Where the verdict took the first of its findings from (it puts first the fault that
    /// explains the most pictures), so that shards' findings can be put back in the order
    /// simulation found them.
    pub moved_from: Option<usize>,
    /// Where a failing picture no fault explains differs: the material or light its
    /// difference lies on, where one holds it.
    pub located: Option<Located>,
    /// A picture that differs from raycast's answer to a question the course leaves open, and
    /// passes because the course allows the tracer's (or leaves it free).
    pub accepted: Option<choices::Acceptance>,
}

impl Graded {
    /// Picture `k` of `line`, named `name`, before anything is known of it: an error without a
    /// cause, worth one point.
    fn blank(line: &Line, k: usize, name: &str) -> Graded {
        Graded {
            name: name.to_string(),
            command: line.command.clone(),
            status: Status::Error,
            bad_fraction: None,
            findings: Vec::new(),
            explanation: String::new(),
            actual: None,
            reference: None,
            stderr: String::new(),
            seconds: 0.0,
            against_raycast: false,
            by_chance: false,
            picture: line.picture_kind(k),
            worst_pixel: None,
            pictures: Pictures::default(),
            points: 1.0,
            line: (line.number, k),
            moved_from: None,
            located: None,
            accepted: None,
        }
    }
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
    let comparison = compare(actual, reference, rule.tolerance);
    judged(actual, reference, comparison, rule)
}

/// [`judge`], where a picture drawn by chance is graded by its rule (`chance`: the spread of
/// raycast's seeded renders, or the samples picture's structure) instead of against the one
/// `reference` (which its guesses from the pixels still use). `Err` where that rule could not
/// be made (raycast could not render the line's draws, or check was stopped first).
fn judge_by(
    actual: &Image,
    reference: &Image,
    chance: Option<&references::ChanceRule>,
    rule: Rule,
) -> Result<Judgement, String> {
    let plain = || compare(actual, reference, rule.tolerance);
    let comparison = match chance {
        None => plain(),
        Some(chance) => match plain().filter(|c| chance.plain_pass_suffices() && rule.passes(c)) {
            Some(passed) => Some(passed),
            None => match chance.rule()? {
                Some(by_chance) => by_chance.compare(actual, rule.tolerance),
                None => plain(),
            },
        },
    };
    Ok(judged(actual, reference, comparison, rule))
}

/// The judgement of `actual` by its `comparison` (`None`: another size than `reference`'s).
fn judged(
    actual: &Image,
    reference: &Image,
    comparison: Option<Comparison>,
    rule: Rule,
) -> Judgement {
    let Some(comparison) = comparison else {
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

/// A run of `check`: every picture graded, and the cage the renderer ran in.
#[derive(Debug)]
pub struct Checked {
    /// Every picture of the suite, in its order.
    pub graded: Vec<Graded>,
    /// The cage's mechanisms, as the first line's supervisor found them.
    pub confinement: Option<Confinement>,
    /// What check did to run the renderer as an unprivileged user when it ran as root (what it
    /// copied where that user could reach it), if anything.
    pub cage_note: Option<String>,
    /// What of its scratch check could not remove, if anything.
    pub cleanup: Option<String>,
    /// Graded with `--no-cage`: without a wall known to hold.
    pub no_cage: bool,
    /// Whether check was interrupted: some lines did not run (their pictures are errors).
    pub partial: bool,
    /// The report being built, its pictures written, when one was asked for.
    pub staging: Option<Staging>,
    /// How the submission's build went, in a class (`class::Built::json`).
    pub build: Option<serde_json::Value>,
    /// How long its lines took by the clock, from the first's start to the last's end (they
    /// run side by side: not the sum of their times).
    pub seconds: f64,
    /// The variation of the scenes it was graded on (`--vary`), if any.
    pub variation: Option<Variation>,
}

impl Checked {
    /// Adds what of check's scratch could not be removed to what the run warns of.
    pub fn left_behind(&mut self, left: String) {
        self.cleanup = Some(match self.cleanup.take() {
            Some(earlier) => format!("{earlier}; {left}"),
            None => left,
        });
    }
}

/// A suite made ready to grade renderers against, once for all of them: read, fingerprinted,
/// its references read and raycast's own rendered, before any renderer's code runs (nothing a
/// renderer does to the suite's files can change what it is graded against).
pub struct Prepared {
    suite: Suite,
    references: Vec<References>,
    fingerprint: guard::Fingerprint,
    pool: rayon::ThreadPool,
}

impl Prepared {
    /// The suite.
    pub fn suite(&self) -> &Suite {
        &self.suite
    }
}

/// Reads the options' suite and makes its references, on `options.jobs` threads; once `stop`
/// is set, the references not yet rendered say so.
pub fn prepare(options: &CheckOptions, stop: &'static StopFlag) -> Result<Prepared, String> {
    let mut suite = Suite::read(&options.suite)?;
    // Before any renderer's code runs: a wall must hold, or the user said --no-cage.
    let root = cage::is_root();
    if !options.no_cage {
        let original = options.varied.as_ref().map_or(&options.suite, |v| &v.from);
        cage::Wall::find(original, root).holds(options.others)?;
    }
    if let Some((k, n)) = options.shard {
        suite.lines = std::mem::take(&mut suite.lines)
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k - 1)
            .map(|(_, line)| line)
            .collect();
    }
    let fingerprint = guard::Fingerprint::of(&options.suite)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.max(1))
        .build()
        .map_err(|e| format!("cannot start {} threads: {e}", options.jobs))?;
    let references: Vec<References> = pool.install(|| {
        suite
            .lines
            .par_iter()
            .with_max_len(1)
            .map(|line| references::of(&suite, line, stop))
            .collect()
    });
    Ok(Prepared {
        suite,
        references,
        fingerprint,
        pool,
    })
}

/// One renderer to grade.
pub struct Renderer<'a> {
    /// Its command: the executable (resolved), then its own arguments.
    pub command: &'a [String],
    /// What it may read besides the system's files.
    pub readable: &'a [PathBuf],
    /// The most time its lines may take together; the lines left when it is spent are not run.
    pub budget: Option<Duration>,
}

/// What `raycast check cache` says of the renders kept between runs; with `clear`, empties it
/// first.
pub fn cache_command(clear: bool) -> Result<String, String> {
    let limit = cache::limit()?;
    let Some(folder) = cache::folder() else {
        return Ok("RAYCAST_CACHE_DIR=off: no render is kept between runs".into());
    };
    let mib = |bytes: u64| bytes as f64 / f64::from(1 << 20);
    if clear {
        let (pictures, bytes) = cache::usage();
        cache::trim(0);
        let (left, _) = cache::usage();
        if left > 0 {
            return Err(format!(
                "cannot remove {left} of the {pictures} pictures kept in {}",
                folder.display()
            ));
        }
        return Ok(format!(
            "removed {pictures} pictures ({:.1} MiB) from {}",
            mib(bytes),
            folder.display()
        ));
    }
    let (pictures, bytes) = cache::usage();
    Ok(format!(
        "{pictures} pictures kept in {}: {:.1} MiB of at most {:.1} MiB (RAYCAST_CACHE_SIZE)",
        folder.display(),
        mib(bytes),
        mib(limit)
    ))
}

/// Checks `RAYCAST_CACHE_SIZE` before a run, which trims the cache to it at its end.
pub fn cache_limit() -> Result<u64, String> {
    cache::limit()
}

/// Keeps the renders kept between runs within `limit` bytes, the least recently used removed
/// first.
pub fn trim_cache(limit: u64) {
    cache::trim(limit);
}

/// Runs every line of the suite with the renderer, each in its cage, and grades every image it
/// should write, counting in `progress` the lines graded and diagnosed; once `stop` is set (check was
/// interrupted), the lines running end and no other starts. The error is a usage or suite
/// problem.
pub fn check(
    options: &CheckOptions,
    progress: &Progress,
    stop: &'static StopFlag,
) -> Result<Checked, String> {
    let executable = run::check_program(&options.renderer)?;
    let mut command = options.renderer.clone();
    command[0] = executable.display().to_string();
    // A word naming a file or folder here (`python3 tracer.py`) names it from the renderer's
    // own folder too, which is each line's: made absolute.
    for word in command.iter_mut().skip(1) {
        if Path::new(word.as_str()).is_relative()
            && let Ok(absolute) = std::fs::canonicalize(word.as_str())
        {
            *word = absolute.display().to_string();
        }
    }
    let readable = submission(
        &options.renderer,
        &executable,
        &options.readable,
        &options.suite,
    )?;
    // Never as root: what the unprivileged user cannot reach is run from an open copy.
    let copies = Scratch::new()?;
    let (command, readable, copied) = match cage::unprivileged_user(&readable) {
        Some(Err(_)) => {
            let staged = cage::stage(&command, &readable, copies.path())?;
            (staged.command, staged.readable, staged.note)
        }
        _ => (command, readable, None),
    };
    // Made before the lines run: a report folder that cannot be one is an error at once.
    let staging = options.report.as_deref().map(Staging::new).transpose()?;
    let varied = options
        .vary
        .map(|seed| VariedSuite::make(&options.suite, seed))
        .transpose()?;
    let varied_options = varied.as_ref().map(|varied| varied.options(options));
    let options = varied_options.as_ref().unwrap_or(options);
    let prepared = prepare(options, stop)?;
    let renderer = Renderer {
        command: &command,
        readable: &readable,
        budget: options.budget,
    };
    let mut checked = grade_renderer(&prepared, options, &renderer, staging, progress, stop)?;
    checked.cage_note = copied;
    if let Some(Err(left)) = varied.map(VariedSuite::remove) {
        checked.left_behind(left);
    }
    Ok(checked)
}

/// Grades one renderer against a prepared suite (see [`check`]); its pictures go into
/// `staging`, the report being built, where there is one.
pub fn grade_renderer(
    prepared: &Prepared,
    options: &CheckOptions,
    renderer: &Renderer,
    staging: Option<Staging>,
    progress: &Progress,
    stop: &'static StopFlag,
) -> Result<Checked, String> {
    let suite = &prepared.suite;
    if let (Some(variation), Some(staging)) = (&options.varied, &staging) {
        variation.copy_scenes(&options.suite.join("scenes"), staging.path())?;
    }
    // A renderer never runs as root (check() runs it from open copies where it must).
    let (user, cage_note) = match cage::unprivileged_user(renderer.readable) {
        None => (None, None),
        Some(Ok(user)) => (Some(user), None),
        Some(Err(why)) => {
            return Err(format!(
                "check runs as root, and never runs a renderer as root; the user it runs \
                 renderers as cannot reach what the renderer needs: {why}. Run check as an \
                 ordinary user, or open the path to other users (chmod o+rx on it and on each \
                 folder above it)"
            ));
        }
    };
    let scratch = Scratch::for_lines()?;
    if user.is_some() {
        // Passed through by the renderer's user to its own line's folders, never listed.
        modes::set_mode(scratch.path(), 0o711)
            .map_err(|e| format!("cannot open the scratch folder to the renderer: {e}"))?;
    }
    let started = std::time::Instant::now();
    let hidden = hidden_from_renderers(options);
    let caged = Caged {
        command: renderer.command,
        readable: renderer.readable,
        hidden: &hidden,
        user,
        stop,
        budget: renderer.budget.map(|b| (started, b)),
    };
    // Every line is run and graded first, then the failing ones diagnosed: a deadline or a
    // budget that comes during the diagnoses leaves every line graded.
    let keep_pictures = |graded: &mut Vec<Graded>| match &staging {
        Some(staging) => staging.keep_pictures(graded, options.rule.tolerance),
        // Nothing needs the pixels once the line is graded.
        None => graded.iter_mut().for_each(|g| {
            g.actual = None;
            g.reference = None;
        }),
    };
    let folder = |number: usize| scratch.path().join(format!("line{number}"));
    let grade_one = |number: usize, ran: (Ran, PathBuf)| {
        let (line, references) = (&suite.lines[number], &prepared.references[number]);
        let (mut graded, confinement) = grade_ran(
            options,
            &caged,
            suite,
            line,
            references.clone(),
            &folder(number),
            ran,
        );
        // Graded from memory from here on. Where it cannot be removed now, the scratch's
        // removal at the end tries again and says so.
        let _ = scratch::remove_inside(&folder(number));
        // A line with nothing to diagnose is done.
        if !graded.iter().any(|g| g.status == Status::Fail) {
            keep_pictures(&mut graded);
        }
        progress.graded();
        (std::sync::Mutex::new(graded), confinement)
    };
    // A line's pictures are graded on a thread of their own while the next lines run: the
    // renderers keep the jobs' threads, and check's own work fills the time they leave. A line
    // drawn by chance may need raycast's renders of the line to be graded: it is graded where
    // it ran, before the next line starts, so that those renders never share the machine with
    // a renderer being timed.
    let graded = std::thread::scope(|scope| {
        let (ran_lines, to_grade) = std::sync::mpsc::channel::<(usize, (Ran, PathBuf))>();
        let grader = scope.spawn(move || {
            to_grade
                .into_iter()
                .map(|(number, ran)| (number, grade_one(number, ran)))
                .collect::<Vec<_>>()
        });
        let ready = |number: usize| {
            let line = &suite.lines[number];
            ready_line(options, &caged, suite, line, &folder(number))
        };
        let start = |line: ReadyLine| start_line(options, &caged, line);
        let mut graded = lines_in_suite_order(
            &prepared.pool,
            suite.lines.len(),
            ready,
            start,
            |number, line| {
                let ran = finish_line(options, &caged, line);
                let by_chance = prepared.references[number].iter().any(|r| r.2.is_some());
                if by_chance {
                    return Some(grade_one(number, ran));
                }
                // The grader lives as long as this scope's lines, unless it panicked, which its
                // join says.
                let _ = ran_lines.send((number, ran));
                None
            },
        );
        drop(ran_lines);
        let in_the_grader = grader
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        for (number, line) in in_the_grader {
            graded[number] = Some(line);
        }
        graded
    });
    let graded: Vec<_> = graded
        .into_iter()
        .map(|line| line.expect("each line is graded where it ran or by the grader"))
        .collect();
    let lines: Vec<Vec<Graded>> = graded
        .iter()
        .map(|(g, _)| std::mem::take(&mut *g.lock().unwrap_or_else(|e| e.into_inner())))
        .collect();
    let order = diagnosis::diagnosis_order(&lines);
    let lines: Vec<std::sync::Mutex<Vec<Graded>>> =
        lines.into_iter().map(std::sync::Mutex::new).collect();
    progress.diagnosing(order.len());
    let spent = || {
        caged
            .budget
            .and_then(|(start, budget)| (start.elapsed() >= budget).then_some(budget))
    };
    // Each line's diagnosis tries the run's likely faults as they are when it begins, kept:
    // a line left with pictures no fault explains is looked at again below.
    let likely_before = in_suite_order(&prepared.pool, order.len(), |k| {
        let number = order[k];
        let mut graded = lines[number].lock().unwrap_or_else(|e| e.into_inner());
        let likely = likely::faults();
        let line = &suite.lines[number];
        let remembered =
            diagnosis::diagnose_line(options, suite, line, &mut graded, stop, spent(), &likely);
        let unexplained = graded
            .iter()
            .any(|g| g.status == Status::Fail && diagnosis::unexplained(g));
        if !unexplained {
            keep_pictures(&mut graded);
        }
        progress.diagnosed();
        // A record of an earlier run tried that run's likely pairs: which, it does not say.
        unexplained.then(|| if remembered { Vec::new() } else { likely })
    });
    // The likely pairs once more, with the likely faults of every line: a pair that explained
    // a line diagnosed late is tried on the lines diagnosed before it.
    let likely_now = likely::faults();
    in_suite_order(&prepared.pool, order.len(), |k| {
        let Some(before) = &likely_before[k] else {
            return;
        };
        let number = order[k];
        let mut graded = lines[number].lock().unwrap_or_else(|e| e.into_inner());
        if !stop.is_set() && spent().is_none() {
            let line = &suite.lines[number];
            let likely = (&before[..], &likely_now[..]);
            diagnosis::pair_again(options, suite, line, &mut graded, stop, likely);
        }
        keep_pictures(&mut graded);
    });
    let graded: Vec<(Vec<Graded>, Option<Confinement>)> = lines
        .into_iter()
        .zip(graded)
        .map(|(line, (_, confinement))| {
            (
                line.into_inner().unwrap_or_else(|e| e.into_inner()),
                confinement,
            )
        })
        .collect();
    let confinement = graded.iter().find_map(|(_, c)| c.clone());
    let mut graded: Vec<Graded> = graded.into_iter().flat_map(|(g, _)| g).collect();
    unique_names(&mut graded);
    let changed = guard::Fingerprint::of(&options.suite)
        .map(|after| prepared.fingerprint.changed(&after))
        .unwrap_or_else(|why| vec![PathBuf::from(why)]);
    if !changed.is_empty() {
        void(&mut graded, &changed);
    }
    let cleanup = scratch.remove().err();
    Ok(Checked {
        graded,
        confinement,
        cage_note,
        cleanup,
        no_cage: options.no_cage,
        partial: stop.is_set(),
        staging,
        build: None,
        seconds: started.elapsed().as_secs_f64(),
        variation: options.varied.clone(),
    })
}

/// Runs `task` on every index below `count` on the pool's workers, each taking the next index
/// as it comes free: lines start in the suite's order (a budget spent leaves the last lines
/// unrun, never ones in the middle), and lines that differ in time a hundredfold share the
/// workers evenly. The results in index order.
fn in_suite_order<T: Send>(
    pool: &rayon::ThreadPool,
    count: usize,
    task: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::Mutex::new(Vec::with_capacity(count));
    pool.scope(|scope| {
        for _ in 0..pool.current_num_threads().min(count) {
            scope.spawn(|_| {
                loop {
                    let number = next.fetch_add(1, Ordering::Relaxed);
                    if number >= count {
                        break;
                    }
                    let result = task(number);
                    done.lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((number, result));
                }
            });
        }
    });
    let mut done = done.into_inner().unwrap_or_else(|e| e.into_inner());
    done.sort_by_key(|&(number, _)| number);
    done.into_iter().map(|(_, result)| result).collect()
}

/// The check of a submission that did not build: every picture an error that says why.
pub fn not_built(prepared: &Prepared, why: &str, staging: Option<Staging>) -> Checked {
    let explanation = format!("{why}. {}", Diagnosis::BUILD_FAILED.explanation());
    let mut graded: Vec<Graded> = prepared
        .suite
        .lines
        .iter()
        .flat_map(|line| {
            let explanation = explanation.clone();
            line.outputs.iter().enumerate().map(move |(k, (_, name))| {
                let image_name = suite::image_name(name);
                Graded {
                    points: prepared.suite.points(&image_name),
                    findings: vec![Finding::Diagnosis(Diagnosis::BUILD_FAILED)],
                    explanation: explanation.clone(),
                    ..Graded::blank(line, k, &image_name)
                }
            })
        })
        .collect();
    unique_names(&mut graded);
    Checked {
        graded,
        confinement: None,
        cage_note: None,
        cleanup: None,
        no_cage: false,
        partial: false,
        staging,
        build: None,
        seconds: 0.0,
        variation: None,
    }
}

/// What the renderer may read: its program and every word of its command that names a file
/// or folder (a script, a data folder), and a script's interpreter, each with its own project's
/// folders (`project.rs`) unless they hold the suite (whose references a renderer must not
/// read), and what `--allow-read` adds.
fn submission(
    renderer: &[String],
    executable: &Path,
    allowed: &[PathBuf],
    suite: &Path,
) -> Result<Vec<PathBuf>, String> {
    let suite = std::fs::canonicalize(suite).unwrap_or_else(|_| suite.to_path_buf());
    let mut readable: Vec<PathBuf> = Vec::new();
    let named = renderer
        .iter()
        .skip(1)
        .map(PathBuf::from)
        .filter(|p| p.exists());
    let programs: Vec<PathBuf> = std::iter::once(executable.to_path_buf())
        .chain(named)
        .map(|p| std::path::absolute(&p).unwrap_or(p))
        .collect();
    // A script brings its interpreter's (a virtual environment's python, say) too.
    let interpreters: Vec<PathBuf> = programs
        .iter()
        .filter_map(|p| project::interpreter(p))
        .collect();
    for path in programs.iter().chain(&interpreters) {
        for folder in project::own_folders(path, &suite) {
            if !readable.contains(&folder) {
                readable.push(folder);
            }
        }
        // A program whose own folder holds the suite: the program alone.
        let alone = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if alone.parent().is_some_and(|f| suite.starts_with(f)) && !readable.contains(&alone) {
            readable.push(alone);
        }
    }
    for path in allowed {
        if suite.starts_with(path) {
            return Err(format!(
                "--allow-read {} holds the suite: the renderer could read its references",
                path.display()
            ));
        }
        readable.push(path.clone());
    }
    Ok(readable)
}

/// How every line's renderer is run: its command (the program resolved), what it may read,
/// the user it runs as, and the flag that ends the run.
struct Caged<'a> {
    command: &'a [String],
    readable: &'a [PathBuf],
    /// What the renderer must not see even where it may read: the suite.
    hidden: &'a [PathBuf],
    user: Option<(u32, u32)>,
    stop: &'static StopFlag,
    /// When the renderer's lines began, and the time they may take together.
    budget: Option<(std::time::Instant, Duration)>,
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

/// The folders no renderer may see, even inside a folder it may read: the suite's.
pub(crate) fn hidden_from_renderers(options: &CheckOptions) -> Vec<PathBuf> {
    std::iter::once(&options.suite)
        .chain(options.varied.as_ref().map(|v| &v.from))
        .filter_map(|suite| std::fs::canonicalize(suite).ok())
        .collect()
}

/// A line made ready in its folder (whose `out` its pictures go to), or ended before it could
/// be: how.
type ReadyLine = (Result<cage::Readied, Ran>, PathBuf);

/// A line whose renderer runs, or that ended before it could start: how.
type StartedLine = (Result<cage::Running, Ran>, PathBuf);

/// How a line ended that never started.
fn unstarted(ending: Ending) -> Ran {
    Ran {
        ending,
        stderr: String::new(),
        seconds: 0.0,
        confinement: None,
    }
}

/// Why a line may not start now: check was stopped, or the budget is spent.
fn not_now(caged: &Caged) -> Option<Ending> {
    let spent = caged
        .budget
        .filter(|(start, budget)| start.elapsed() >= *budget);
    if caged.stop.is_set() {
        Some(Ending::stopped(caged.stop))
    } else {
        spent.map(|(_, budget)| Ending::OverBudget(budget))
    }
}

/// Makes one line ready in `folder` while the line before it runs: its files copied, its
/// supervisor building its cage.
fn ready_line(
    options: &CheckOptions,
    caged: &Caged,
    suite: &Suite,
    line: &Line,
    folder: &Path,
) -> ReadyLine {
    if let Some(ending) = not_now(caged) {
        return (Err(unstarted(ending)), folder.join("out"));
    }
    let files = run::line_files(line, &suite.scenes);
    match run::prepare(&suite.scenes, &files, folder, caged.user) {
        Err(why) => (Err(unstarted(Ending::NotStarted(why))), folder.join("out")),
        Ok((work, out)) => {
            let mut args = line.args.clone();
            for (at, name) in &line.outputs {
                args[*at] = out.join(file_name(name)).to_string_lossy().into_owned();
            }
            if !options.keep_preview_options {
                args = suite::without_preview_options(&args);
            }
            let request = cage::Request {
                command: caged.command.iter().cloned().chain(args).collect(),
                work,
                outputs: out.clone(),
                readable: caged.readable.to_vec(),
                hidden: caged.hidden.to_vec(),
                root: Some(folder.join("root")),
                work_kept: false,
                limit: options.timeout,
                limits: options.limits,
                user: caged.user,
                held: false,
            };
            (Ok(cage::ready(&request)), out)
        }
    }
}

/// Starts a readied line's renderer, with the time it may take: --timeout, or what is left of
/// the budget where that is less. A line whose turn comes after check was stopped or the budget
/// spent is given up unstarted.
fn start_line(options: &CheckOptions, caged: &Caged, (readied, out): ReadyLine) -> StartedLine {
    let readied = match readied {
        Ok(readied) => readied,
        Err(ran) => return (Err(ran), out),
    };
    if let Some(ending) = not_now(caged) {
        readied.cancel();
        return (Err(unstarted(ending)), out);
    }
    let left = caged
        .budget
        .map(|(start, budget)| budget.saturating_sub(start.elapsed()));
    let limit = left.map_or(options.timeout, |left| left.min(options.timeout));
    (Ok(readied.start(limit)), out)
}

/// How a started line ran, and the folder its pictures are in.
fn finish_line(
    options: &CheckOptions,
    caged: &Caged,
    (running, out): StartedLine,
) -> (Ran, PathBuf) {
    match running {
        Err(ran) => (ran, out),
        Ok(running) => {
            let mut ran = running.wait(caged.stop);
            // Stopped at the budget's end rather than at --timeout: the budget is the cause.
            if let (Ending::TimedOut(after), Some((_, budget))) = (&ran.ending, caged.budget)
                && *after < options.timeout
            {
                ran.ending = Ending::BudgetRanOut {
                    budget,
                    after: *after,
                };
            }
            (ran, out)
        }
    }
}

/// Runs every line on the pool's workers, as [`in_suite_order`] does, each worker making its
/// next line ready (`ready`: files copied, cage built) while its current line's renderer runs,
/// so that a line's turn costs its renderer's time and little more. `done` takes each line's
/// number and how it ran.
fn lines_in_suite_order<Ready, Started, T: Send>(
    pool: &rayon::ThreadPool,
    count: usize,
    ready: impl Fn(usize) -> Ready + Sync,
    start: impl Fn(Ready) -> Started + Sync,
    done: impl Fn(usize, Started) -> T + Sync,
) -> Vec<T> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let claim = || {
        let number = next.fetch_add(1, Ordering::Relaxed);
        (number < count).then(|| (number, ready(number)))
    };
    let finished = std::sync::Mutex::new(Vec::with_capacity(count));
    pool.scope(|scope| {
        for _ in 0..pool.current_num_threads().min(count) {
            scope.spawn(|_| {
                let mut current = claim();
                while let Some((number, line)) = current {
                    let running = start(line);
                    current = claim();
                    let result = done(number, running);
                    finished
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((number, result));
                }
            });
        }
    });
    let mut finished = finished.into_inner().unwrap_or_else(|e| e.into_inner());
    finished.sort_by_key(|&(number, _)| number);
    finished.into_iter().map(|(_, result)| result).collect()
}

/// A line's pictures graded, each against its reference (read before any renderer ran), from
/// how its renderer ran and the folder its pictures are in; with the cage the line's
/// supervisor found.
fn grade_ran(
    options: &CheckOptions,
    caged: &Caged,
    suite: &Suite,
    line: &Line,
    references: References,
    folder: &Path,
    (ran, out): (Ran, PathBuf),
) -> (Vec<Graded>, Option<Confinement>) {
    let ran = Ran {
        stderr: without_scratch(&ran.stderr, folder),
        ..ran
    };
    let mut graded: Vec<Graded> = line
        .outputs
        .iter()
        .zip(references)
        .enumerate()
        .map(|(k, ((_, name), (reference, own_render, spread)))| {
            let image_name = suite::image_name(name);
            let mut graded = picture::grade(
                options,
                suite.picture_alone_after_crash,
                line,
                k,
                &image_name,
                &ran,
                &out.join(file_name(name)),
                (reference, spread.as_ref()),
            );
            graded.against_raycast = own_render;
            graded.by_chance = spread.is_some();
            graded.points = suite.points(&image_name);
            graded
        })
        .collect();
    let reach = refused::Reach {
        readable: caged.readable,
        hidden: caged.hidden,
        line: folder,
        program: Path::new(caged.command.first().map_or("", String::as_str)),
    };
    blame_the_cage(&mut graded, &ran.stderr, &reach);
    (graded, ran.confinement)
}

/// Where a picture is missing because the renderer was kept from a file of its own (its words
/// say so), the cause is the cage, not the renderer, and the fix an `--allow-read`: never
/// "run it by hand", which works.
fn blame_the_cage(graded: &mut [Graded], said: &str, reach: &refused::Reach) {
    let by_the_cage = |g: &Graded| {
        g.status == Status::Error
            && g.findings.iter().any(|f| {
                matches!(f, Finding::Diagnosis(d) if *d == Diagnosis::CRASH || *d == Diagnosis::MISSING_OUTPUT)
            })
    };
    if !graded.iter().any(by_the_cage) {
        return;
    }
    let Some(advice) = refused::cage_refused(said, reach) else {
        return;
    };
    for g in graded.iter_mut().filter(|g| by_the_cage(g)) {
        let generic = [
            Diagnosis::CRASH.explanation(),
            Diagnosis::MISSING_OUTPUT.explanation(),
            OWN_MESSAGE_ADVICE,
        ];
        let mut explanation = g.explanation.clone();
        for words in generic {
            if let Some(kept) = explanation.strip_suffix(words) {
                explanation = kept.trim_end().to_string();
            }
        }
        g.findings = vec![Finding::Diagnosis(Diagnosis::CAGE_REFUSED)];
        g.explanation = format!("{explanation} {advice}");
    }
}

/// What a renderer printed, with the line's scratch paths (gone once check ends) as the
/// command line names them: `out/picture.tga` and `work/scene.txt` as `picture.tga` and
/// `scene.txt`.
fn without_scratch(stderr: &str, folder: &Path) -> String {
    let folder = folder.display().to_string();
    stderr
        .replace(&format!("{folder}/out/"), "")
        .replace(&format!("{folder}/work/"), "")
        .replace(&folder, "(the line's folder)")
}

fn file_name(name: &str) -> String {
    Path::new(name)
        .file_name()
        .map_or_else(|| name.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The one-line verdict of an image for the terminal.
pub fn verdict(graded: &Graded) -> String {
    let against = match (graded.against_raycast, graded.by_chance) {
        (_, true) => " against the spread of raycast's renders with several seeds",
        (true, false) => " against raycast's render",
        (false, false) => "",
    };
    let off = graded
        .bad_fraction
        .map(|f| format!(", {:.3}% of pixels off{against}", 100.0 * f))
        .unwrap_or_default();
    match (graded.status, &graded.accepted) {
        (Status::Pass, Some(choices::Acceptance::Answer(_, answer))) => {
            format!("pass   {}{off}: allowed: {}", graded.name, answer.said)
        }
        (Status::Pass, Some(choices::Acceptance::Answers([(_, first), (_, second)]))) => {
            format!(
                "pass   {}{off}: allowed: {}; and {}",
                graded.name, first.said, second.said
            )
        }
        (Status::Pass, Some(choices::Acceptance::Informational(_))) => {
            format!("info   {}{off}: {}", graded.name, graded.explanation)
        }
        (Status::Pass, None) => format!("pass   {}{off}", graded.name),
        (Status::Fail | Status::Error, _) => {
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

/// `summary.json`'s contents: raycast's version and the rule, whether the run was cut short
/// (`partial`) and the cage the renderer ran in (`cage`), the counts, the renderer's
/// verdict (`{fault, lines}`, biggest group first), and for each image its status, the share
/// of pixels off, its causes (`diagnoses`, the one the verdict names first), what to look at,
/// the renderer's last words on stderr and its time for the line, and for a failing picture
/// the pixel where it differs most with raycast's account of it (`worst_pixel`).
pub fn summary_json(checked: &Checked, groups: &[Group], rule: Rule) -> serde_json::Value {
    let graded = &checked.graded;
    let passed = graded.iter().filter(|g| g.status == Status::Pass).count();
    let mut cage = checked
        .confinement
        .as_ref()
        .map_or(serde_json::json!({}), Confinement::json);
    cage["note"] = serde_json::json!(checked.cage_note);
    cage["no_cage"] = serde_json::json!(checked.no_cage);
    cage["cleanup"] = serde_json::json!(checked.cleanup);
    serde_json::json!({
        "raycast": env!("CARGO_PKG_VERSION"),
        "rule": { "tolerance": rule.tolerance, "max_bad": rule.max_bad },
        "partial": checked.partial,
        "seconds": checked.seconds,
        "cage": cage,
        "build": checked.build,
        "varied": checked.variation.as_ref().map(Variation::json),
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
            "reference": match (g.against_raycast, g.by_chance) {
                (_, true) => "raycast_seeds",
                (true, false) => "raycast",
                (false, false) => "suite",
            },
            "stderr": untrusted::tail(&g.stderr),
            "seconds": g.seconds,
            "points": g.points,
            "line": g.line.0,
            "output": g.line.1,
            "picture": g.picture.option(),
            "pictures": {
                "actual": g.pictures.actual,
                "reference": g.pictures.reference,
                "diff": g.pictures.diff,
            },
            "verdict_moved_from": g.moved_from,
            "where": g.located.as_ref().map(Located::json),
            "accepted": g.accepted.as_ref().map(choices::Acceptance::json),
            "worst_pixel": g.worst_pixel.as_ref().map(|w| serde_json::json!({
                "x": w.x, "y": w.y, "difference": w.difference, "ray_tree": w.ray_tree,
            })),
        })).collect::<Vec<_>>(),
    })
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
