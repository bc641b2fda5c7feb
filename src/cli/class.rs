//! `raycast check SUITE --class DIR ...`: a class graded in one command, its table on the
//! terminal and, with `--report`, in `class.csv` and `class.html` beside each student's report.

use std::io::Write;
use std::process::ExitCode;

use crate::check::class::{self, ClassOptions, table};
use crate::check::{self, CheckOptions, Staging};

fn fail(message: &str) -> ExitCode {
    eprintln!("raycast: check: {message}");
    ExitCode::from(2)
}

/// `raycast check merge OUT DIR...`: the reports of shards (`--shard K/N`) of a class, or of
/// one renderer's lines, joined into the report one run makes.
pub fn run_merge(args: &[String]) -> ExitCode {
    let Some((out, shards)) = args.split_first().filter(|(_, shards)| !shards.is_empty()) else {
        return fail(
            "merge needs OUT and the shards' report folders: raycast check merge OUT DIR...",
        );
    };
    let staging = match Staging::new(std::path::Path::new(out)) {
        Ok(staging) => staging,
        Err(message) => return fail(&message),
    };
    if !check::merge::is_class(std::path::Path::new(&shards[0])) {
        // The shards of one renderer's lines.
        let shards: Vec<std::path::PathBuf> = shards.iter().map(std::path::PathBuf::from).collect();
        let (mut checked, groups, rule) = match check::merge::merge(staging, &shards) {
            Ok(merged) => merged,
            Err(message) => return fail(&message),
        };
        let mut out_text = std::io::stdout().lock();
        super::grades::print_grades(&mut out_text, &groups, &checked.graded);
        return match check::write_report(&mut checked, &groups, rule) {
            Ok(()) => {
                let _ = writeln!(
                    out_text,
                    "report: {}",
                    std::path::Path::new(out).join("index.html").display()
                );
                ExitCode::SUCCESS
            }
            Err(message) => fail(&format!("cannot write the report: {message}")),
        };
    }
    let mut rows = Vec::new();
    let mut partial = false;
    for shard in shards {
        let shard = std::path::Path::new(shard);
        let summary = std::fs::read_to_string(shard.join("summary.json"))
            .ok()
            .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok());
        let Some(summary) = summary.filter(|s| s["class"] == true) else {
            return fail(&format!(
                "{}: not the report of a class (no summary.json of a --class run)",
                shard.display()
            ));
        };
        partial |= summary["partial"] == true;
        for student in summary["students"].as_array().into_iter().flatten() {
            let Some(name) = student["name"].as_str() else {
                continue;
            };
            let folder = student["report"].as_str().unwrap_or(name);
            if folder.is_empty() {
                // Not graded: a row, and no report of their own.
                rows.push(table::Row::of_class_summary(student));
                continue;
            }
            let target = staging.path().join(folder);
            if target.exists() {
                return fail(&format!(
                    "{name} is in two shards ({} is one): were they made with the same roster?",
                    shard.display()
                ));
            }
            let own = std::fs::read_to_string(shard.join(folder).join("summary.json"))
                .ok()
                .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok());
            let Some(own) = own else {
                // A student who could not be graded has a row and no report.
                rows.push(table::Row::of_class_summary(student));
                continue;
            };
            if let Err(e) = check::modes::copy_tree(&shard.join(folder), &target) {
                return fail(&e);
            }
            rows.push(table::Row::of(name, folder, &own));
        }
    }
    rows.sort_by(|a, b| a.name.cmp(&b.name));
    let mut out_text = std::io::stdout().lock();
    let _ = write!(out_text, "{}", table::terminal(&rows));
    match finish(staging, &rows, partial) {
        Ok(()) => {
            let _ = writeln!(
                out_text,
                "report: {}",
                std::path::Path::new(out).join("class.html").display()
            );
            ExitCode::SUCCESS
        }
        Err(message) => fail(&format!("cannot write the report: {message}")),
    }
}

/// Writes the class's files beside the students' reports, and puts the report in its place.
fn finish(staging: Staging, rows: &[table::Row], partial: bool) -> Result<(), String> {
    let dir = staging.path().to_path_buf();
    let files = [
        ("class.csv", table::csv(rows)),
        ("class.html", table::html(rows, partial)),
        (
            "summary.json",
            serde_json::to_string_pretty(&table::json(rows, partial)).unwrap_or_default() + "\n",
        ),
    ];
    for (name, text) in files {
        std::fs::write(dir.join(name), text)
            .map_err(|e| format!("{}: {e}", dir.join(name).display()))?;
    }
    staging.place()
}

/// Why a student's row is empty when check stopped before their turn.
fn not_reached(stop: &crate::render::StopFlag) -> &'static str {
    if stop.is_out_of_time() {
        "not graded: check's --deadline came before this student's turn"
    } else {
        "not graded: check was interrupted before this student's turn"
    }
}

/// Grades every student of `class.roster`; exit status 0 once the class is graded (whatever
/// the grades), 130 when interrupted, 2 for a usage or suite problem.
pub fn run_class(mut options: CheckOptions, class: ClassOptions) -> ExitCode {
    options.others = true;
    let students = match class::students(&class.roster, class.shard) {
        Ok(students) => students,
        Err(message) => return fail(&message),
    };
    let staging = match options.report.as_deref().map(Staging::new).transpose() {
        Ok(staging) => staging,
        Err(message) => return fail(&message),
    };
    // Heard from the start: a stop while the references render ends those too.
    let stop = super::grades::stop_on_signals();
    super::grades::stop_at_deadline(stop, options.deadline);
    let suite = match check::Suite::read(&options.suite) {
        Ok(suite) => suite,
        Err(message) => return fail(&message),
    };
    // Prepared once for the class; with --vary each student has scenes, and so references,
    // of their own.
    let shared = match options.vary {
        Some(_) => None,
        None => match check::prepare(&options, stop) {
            Ok(prepared) => Some(prepared),
            Err(message) => return fail(&message),
        },
    };
    let scratch = match check::Scratch::new() {
        Ok(scratch) => scratch,
        Err(message) => return fail(&message),
    };
    {
        // Passed through by the renderers' user to each student's copy, never listed.
        let opened = check::modes::set_mode(scratch.path(), 0o711);
        if let Err(e) = opened {
            return fail(&format!("cannot open the scratch folder: {e}"));
        }
    }
    let lines = suite.lines.len();
    let (pictures, max_points) = suite.pictures_and_points();
    let progress = std::sync::Arc::new(check::Progress::new(lines * students.len()));
    let watcher = super::progress::Watcher::start(progress.clone());
    let mut rows = Vec::new();
    for student in &students {
        if stop.is_set() {
            // The table is the whole roster: a student check did not reach says why.
            rows.push(table::Row::refused(
                &student.0,
                not_reached(stop),
                pictures,
                max_points,
            ));
            continue;
        }
        progress.grading(&student.0);
        let folder = class::report_folder(&student.0);
        let report = staging.as_ref().map(|s| s.path().join(&folder));
        let graded = class::grade_student(
            shared.as_ref(),
            &options,
            &class,
            student,
            scratch.path(),
            report.as_deref(),
            &progress,
            stop,
        );
        match graded {
            Ok(graded) => rows.push(table::Row::of(&graded.name, &folder, &graded.summary)),
            // One student's submission never ends the class: it is their row, with the reason.
            Err(why) => {
                if let Some(report) = &report {
                    let _ = std::fs::remove_dir_all(report);
                }
                rows.push(table::Row::refused(
                    &student.0,
                    &format!("not graded: {why}"),
                    pictures,
                    max_points,
                ));
            }
        }
    }
    watcher.finish();
    if let Err(message) = scratch.remove() {
        eprintln!("raycast: check: warning: {message}");
    }
    let partial = stop.is_set();
    let mut out = std::io::stdout().lock();
    let _ = write!(out, "{}", table::terminal(&rows));
    if let Some(staging) = staging {
        if let Err(message) = finish(staging, &rows, partial) {
            return fail(&format!("cannot write the report: {message}"));
        }
        if let Some(place) = &options.report {
            let _ = writeln!(out, "report: {}", place.join("class.html").display());
        }
    }
    if partial && stop.is_out_of_time() {
        // Graded as far as time allowed: the class's grades stand, partial.
        let _ = writeln!(out, "check's --deadline came: the table is partial");
        return ExitCode::SUCCESS;
    }
    if partial {
        let _ = writeln!(out, "check was interrupted: the table is partial");
        return ExitCode::from(130);
    }
    ExitCode::SUCCESS
}
