//! Grading a class: every folder of a roster is one student's submission. Each is copied into
//! scratch, built with `--build` (caged like a renderer, with a time limit of its own), and its
//! renderer graded against the suite, prepared once for the whole class; its report goes to
//! `REPORT/STUDENT/`, and the class's table to `REPORT/class.{csv,html}` and the terminal.

pub mod table;

use crate::render::StopFlag;
use std::path::{Path, PathBuf};
use std::time::Duration;

use super::cage::{self, Ending, Ran, Request};
use super::vary::{VariedSuite, student_seed};
use super::{CheckOptions, Checked, Prepared, Renderer, Staging, grade_renderer};

/// How a class is graded, beside the check's own options.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassOptions {
    /// The roster: one folder a student.
    pub roster: PathBuf,
    /// The command that builds a submission, run in its folder (`make`), split into words.
    pub build: Option<Vec<String>>,
    /// How long a build may take.
    pub build_timeout: Duration,
    /// How long a student's lines may take together (`--budget`).
    pub budget: Option<Duration>,
    /// This run's share of the class (`--shard K/N`): the students whose place in name order,
    /// counted from 0, is K - 1 modulo N.
    pub shard: Option<(usize, usize)>,
}

/// A student's build: how it ended, what it said, how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Built {
    /// Whether it ended with status 0.
    pub ok: bool,
    /// How it ended, in a sentence.
    pub ending: String,
    /// The end of what it printed.
    pub output: String,
    /// Wall-clock seconds.
    pub seconds: f64,
}

impl Built {
    fn of(ran: &Ran) -> Built {
        let ending = match &ran.ending {
            Ending::Success => "built".to_string(),
            Ending::Failed { .. } | Ending::Signaled { .. } => {
                format!("the build {}", super::how_it_ended(&ran.ending))
            }
            Ending::TimedOut(limit) => {
                format!("the build did not finish within {} s", limit.as_secs_f64())
            }
            Ending::Interrupted => "check was interrupted during the build".to_string(),
            Ending::DeadlineCame => "check's --deadline came during the build".to_string(),
            Ending::OverBudget(_) | Ending::BudgetRanOut { .. } => {
                "the build was not run".to_string()
            }
            Ending::NotStarted(why) => format!("the build could not be started: {why}"),
        };
        Built {
            ok: ran.ending == Ending::Success,
            ending,
            output: super::untrusted::tail(&ran.stderr),
            seconds: ran.seconds,
        }
    }

    /// As `summary.json` writes it.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "ok": self.ok,
            "ending": self.ending,
            "output": self.output,
            "seconds": self.seconds,
        })
    }
}

/// The students of a roster, by name (the entry's, shown lossily where it is not UTF-8; two
/// that read alike are told apart by `#2`, `#3`), in name order, this shard's only. Every entry
/// but hidden ones is a student: one that is not a folder (a link, a file) is refused in its own
/// row by [`grade_student`], never left out without a word.
pub fn students(
    roster: &Path,
    shard: Option<(usize, usize)>,
) -> Result<Vec<(String, PathBuf)>, String> {
    let entries =
        std::fs::read_dir(roster).map_err(|e| format!("--class {}: {e}", roster.display()))?;
    let mut students: Vec<(String, PathBuf)> = entries
        .filter_map(Result::ok)
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path()))
        .filter(|(name, _)| !name.starts_with('.'))
        .collect();
    students.sort();
    let mut seen: Vec<(String, usize)> = Vec::new();
    for (name, _) in students.iter_mut() {
        match seen.iter_mut().find(|(n, _)| n == name) {
            Some((_, count)) => {
                *count += 1;
                *name = format!("{name}#{count}");
            }
            None => seen.push((name.clone(), 1)),
        }
    }
    if students.is_empty() {
        return Err(format!(
            "--class {}: no submissions (one folder a student)",
            roster.display()
        ));
    }
    if let Some((k, n)) = shard {
        students = students
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k - 1)
            .map(|(_, s)| s)
            .collect();
    }
    Ok(students)
}

/// The files a class's report holds beside the students' folders.
pub const CLASS_FILES: [&str; 3] = ["class.csv", "class.html", "summary.json"];

/// The folder of a student's report in the class's: their name, unless it is a file of the
/// class's report itself (a submission named `class.csv`), which gets `student-` before it.
pub fn report_folder(name: &str) -> String {
    if CLASS_FILES.contains(&name) || name.starts_with("student-") {
        format!("student-{name}")
    } else {
        name.to_string()
    }
}

/// One student graded: their name, the check of their renderer (its report written, when one
/// was asked for), their build.
#[derive(Debug)]
pub struct Graded {
    /// The submission folder's name.
    pub name: String,
    /// Their pictures, graded.
    pub checked: Checked,
    /// Their build, when `--build` was given.
    pub built: Option<Built>,
    /// Their `summary.json`.
    pub summary: serde_json::Value,
}

/// Grades one student: copies the submission into `scratch`, builds it, grades its renderer
/// (`renderer`, its first word relative to the submission when it holds a `/`), and writes
/// their report into `report` (a folder of the class's report being built) when there is one.
/// The suite is the class's, `shared`; where there is none (`--vary`), the student's own: the
/// suite varied by the seed and their name, prepared for them.
#[allow(clippy::too_many_arguments)]
pub fn grade_student(
    shared: Option<&Prepared>,
    options: &CheckOptions,
    class: &ClassOptions,
    (name, folder): &(String, PathBuf),
    scratch: &Path,
    report: Option<&Path>,
    progress: &super::Progress,
    stop: &'static StopFlag,
) -> Result<Graded, String> {
    // A link could name any folder of the machine (copied, it would be the renderer's to
    // read): only a folder of the roster itself is a submission.
    match std::fs::symlink_metadata(folder) {
        Ok(kind) if kind.is_dir() => {}
        Ok(kind) if kind.is_symlink() => {
            return Err(
                "a symbolic link, not a folder: put the submission's folder itself in the roster"
                    .to_string(),
            );
        }
        Ok(_) => return Err("not a folder: a submission is a folder of the roster".to_string()),
        Err(e) => return Err(format!("cannot read it: {e}")),
    }
    let varied = match (shared, options.vary) {
        (None, Some(seed)) => Some(VariedSuite::make(&options.suite, student_seed(seed, name))?),
        _ => None,
    };
    let varied_options = varied.as_ref().map(|varied| varied.options(options));
    let options = varied_options.as_ref().unwrap_or(options);
    let own;
    let prepared = match shared {
        Some(prepared) => prepared,
        None => {
            own = super::prepare(options, stop)?;
            &own
        }
    };
    let copy = scratch.join(report_folder(name));
    super::modes::copy_tree(folder, &copy).map_err(|e| format!("cannot copy it: {e}"))?;
    for private in [".home", ".tmp"] {
        std::fs::create_dir_all(copy.join(private)).map_err(|e| e.to_string())?;
    }
    let readable: Vec<PathBuf> = std::iter::once(copy.clone())
        .chain(options.readable.iter().cloned())
        .collect();
    // Never as root: a class whose --allow-read paths the renderers' user cannot reach is
    // refused student by student, each row saying why.
    let user = match cage::unprivileged_user(&readable) {
        Some(Ok(user)) => {
            own_tree(&copy, user).map_err(|e| format!("{}: {e}", copy.display()))?;
            Some(user)
        }
        Some(Err(why)) => {
            return Err(format!(
                "check runs as root and never runs a renderer as root, and the user it runs \
                 them as cannot reach {why}: open it to other users, or run check as an \
                 ordinary user"
            ));
        }
        None => None,
    };
    // The build's own root is mounted on a folder beside the copy, never in it.
    let build_root = tempfile::tempdir_in(scratch).map_err(|e| e.to_string())?;
    let built = class.build.as_ref().map(|build| {
        let mut command = build.clone();
        command[0] = in_submission(&command[0], &copy);
        let request = Request {
            command,
            work: copy.clone(),
            outputs: copy.clone(),
            readable: readable.clone(),
            hidden: super::hidden_from_renderers(options),
            root: Some(build_root.path().to_path_buf()),
            work_kept: true,
            limit: class.build_timeout,
            limits: options.limits,
            user,
            held: false,
        };
        Built::of(&cage::run(&request, stop))
    });
    let mut command = options.renderer.clone();
    command[0] = in_submission(&command[0], &copy);
    // A word naming a file or folder of the submission (`python3 tracer.py`) names it from
    // each line's own folder too: made absolute, inside the copy.
    for word in command.iter_mut().skip(1) {
        let inside = copy.join(word.as_str());
        if Path::new(word.as_str()).is_relative() && inside.exists() {
            *word = inside.display().to_string();
        }
    }
    let staging = report.map(Staging::new).transpose()?;
    let renderer = Renderer {
        command: &command,
        readable: &readable,
        budget: class.budget,
    };
    let unbuilt = built.as_ref().filter(|b| !b.ok).map(|b| b.ending.clone());
    let mut checked = match unbuilt {
        // A submission that did not build is not run: each picture says so.
        Some(why) => super::not_built(prepared, &why, staging),
        None => grade_renderer(prepared, options, &renderer, staging, progress, stop)?,
    };
    checked.build = built.as_ref().map(Built::json);
    // A class of hundreds keeps one submission's copy at a time. Where it cannot be removed
    // now, the class's scratch is removed at the end, and says so.
    drop(build_root);
    let _ = super::scratch::remove_inside(&copy);
    if let Some(Err(left)) = varied.map(VariedSuite::remove) {
        checked.left_behind(left);
    }
    let groups = super::renderer_verdict(&mut checked.graded);
    let summary = super::summary_json(&checked, &groups, options.rule);
    if checked.staging.is_some() {
        super::write_report(&mut checked, &groups, options.rule)?;
    }
    if stop.is_set() {
        checked.partial = true;
    }
    Ok(Graded {
        name: name.clone(),
        checked,
        built,
        summary,
    })
}

/// A renderer or build command's first word: a path (it holds a `/`) is taken inside the
/// submission; a bare name is left for the PATH.
fn in_submission(word: &str, submission: &Path) -> String {
    if word.contains('/') && Path::new(word).is_relative() {
        submission.join(word).display().to_string()
    } else {
        word.to_string()
    }
}

/// Gives the folder `root` and everything in it to `user`.
fn own_tree(root: &Path, (uid, gid): (u32, u32)) -> std::io::Result<()> {
    super::modes::give(root, (uid, gid))?;
    if std::fs::symlink_metadata(root)?.is_dir() {
        for entry in std::fs::read_dir(root)? {
            own_tree(&entry?.path(), (uid, gid))?;
        }
    }
    Ok(())
}
