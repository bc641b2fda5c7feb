//! `raycast check SUITE --class DIR ...`: a class graded in one command, its table on the
//! terminal and, with `--report`, in `class.csv` and `class.html` beside each student's report.

use std::io::Write;
use std::process::ExitCode;
use std::sync::atomic::Ordering;

use crate::check::class::{self, ClassOptions, table};
use crate::check::{self, CheckOptions, Staging};

fn fail(message: &str) -> ExitCode {
    eprintln!("raycast: check: {message}");
    ExitCode::from(2)
}

/// Grades every student of `class.roster`; exit status 0 once the class is graded (whatever
/// the grades), 130 when interrupted, 2 for a usage or suite problem.
pub fn run_class(options: CheckOptions, class: ClassOptions) -> ExitCode {
    let students = match class::students(&class.roster, class.shard) {
        Ok(students) => students,
        Err(message) => return fail(&message),
    };
    let staging = match options.report.as_deref().map(Staging::new).transpose() {
        Ok(staging) => staging,
        Err(message) => return fail(&message),
    };
    let prepared = match check::prepare(&options) {
        Ok(prepared) => prepared,
        Err(message) => return fail(&message),
    };
    let scratch = match tempfile::tempdir() {
        Ok(scratch) => scratch,
        Err(e) => return fail(&format!("cannot make a scratch folder: {e}")),
    };
    {
        use std::os::unix::fs::PermissionsExt;
        // Passed through by the renderers' user to each student's copy, never listed.
        let opened =
            std::fs::set_permissions(scratch.path(), std::fs::Permissions::from_mode(0o711));
        if let Err(e) = opened {
            return fail(&format!("cannot open the scratch folder: {e}"));
        }
    }
    let stop = super::check::stop_on_signals();
    let lines = prepared.suite().lines.len() as u64;
    let bar = std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| {
        let bar = indicatif::ProgressBar::new(lines * students.len() as u64);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "grading {msg} {wide_bar} {pos}/{len} command lines, {elapsed} elapsed",
        ) {
            bar.set_style(style);
        }
        bar
    });
    let advance = || {
        if let Some(bar) = &bar {
            bar.inc(1);
        }
    };
    let mut rows = Vec::new();
    for student in &students {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        if let Some(bar) = &bar {
            bar.set_message(student.0.clone());
        }
        let report = staging.as_ref().map(|s| s.path().join(&student.0));
        let graded = class::grade_student(
            &prepared,
            &options,
            &class,
            student,
            scratch.path(),
            report.as_deref(),
            &advance,
            &stop,
        );
        match graded {
            Ok(graded) => rows.push(table::Row::of(&graded.name, &graded.summary)),
            Err(message) => return fail(&format!("{}: {message}", student.0)),
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let partial = stop.load(Ordering::Relaxed);
    let mut out = std::io::stdout().lock();
    let _ = write!(out, "{}", table::terminal(&rows));
    if let Some(staging) = staging {
        let dir = staging.path().to_path_buf();
        let files = [
            ("class.csv", table::csv(&rows)),
            ("class.html", table::html(&rows, partial)),
            (
                "summary.json",
                serde_json::to_string_pretty(&table::json(&rows, partial)).unwrap_or_default()
                    + "\n",
            ),
        ];
        for (name, text) in files {
            if let Err(e) = std::fs::write(dir.join(name), text) {
                return fail(&format!(
                    "cannot write the report: {}: {e}",
                    dir.join(name).display()
                ));
            }
        }
        if let Err(message) = staging.place() {
            return fail(&format!("cannot write the report: {message}"));
        }
        if let Some(place) = &options.report {
            let _ = writeln!(out, "report: {}", place.join("class.html").display());
        }
    }
    if partial {
        let _ = writeln!(out, "check was interrupted: the table is partial");
        return ExitCode::from(130);
    }
    ExitCode::SUCCESS
}
