//! `raycast check` stops when it is asked to, in every phase: while raycast renders the
//! references, while the renderer runs, and while failing pictures are diagnosed by
//! simulation (the longest phase: a line whose picture no single fault explains is rendered
//! again dozens of times). Asked by SIGINT, SIGTERM or SIGHUP, it ends within a few seconds,
//! with a whole report that says what was not finished, and leaves nothing running.

// The renderers these tests grade are shell scripts and the cage they test is Unix's; on Windows
// check is run by CI's Wine job (.ci/windows), over raycast.exe itself.
#![cfg(unix)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// How long check may take to end once asked: far less than any phase these tests stop (each
/// lasts tens of seconds on an idle machine), with room for a busy one.
const STOPS_WITHIN: Duration = Duration::from_secs(8);

/// The deadline of a check whose lines take a few seconds to grade and several times as long
/// to diagnose.
const DEADLINE: Duration = Duration::from_secs(6);

/// A suite of assignment 7's scene, a line for each of `seeds`, `size` pixels square with 16
/// jittered samples a pixel and a Gaussian filter; a seed makes its line new to raycast's
/// cache of references. The first line's picture is `big0`.
fn suite(dir: &Path, later: &Path, size: u32, seeds: std::ops::Range<u32>) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    std::os::unix::fs::symlink(later.join("scenes"), suite.join("scenes")).unwrap();
    let lines: String = seeds
        .enumerate()
        .map(|(k, seed)| {
            format!(
                "raytracer -input scene7_02_checkerboard.txt -size {size} {size} -output \
                 big{k}.tga -jittered_samples 16 -gaussian_filter 0.6 -seed {seed}\n"
            )
        })
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), lines).unwrap();
    suite
}

/// A renderer that is raycast with its Gaussian filter's sigma three quarters of the line's:
/// no fault of check's library (alone, or two together) matches its pictures, so each is
/// diagnosed at length (every fault and pair screened, the closest made whole; seconds a line,
/// several times the line's render).
fn faulty_renderer(dir: &Path, token: &str) -> PathBuf {
    let script = dir.join(format!("{token}.sh"));
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\nn=$#; i=0\nwhile [ $i -lt $n ]; do a=$1; shift; [ \"$a\" = 0.6 ] && a=0.45; \
             set -- \"$@\" \"$a\"; i=$((i + 1)); done\nexec {} \"$@\"\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    script
}

/// Grades `suite` once with raycast with its colours' channels swapped as the renderer, so
/// that check's cache keeps the renders with several seeds that its failing pictures drawn by
/// chance are graded against (made while such a picture is graded, before any diagnosis): a
/// stop after the renderer has run then falls in the diagnosis. (On the checkerboard the swap
/// is the allowed answer of the cube's material: quick to grade.)
fn keep_the_seeded_renders(suite: &Path) {
    let cache = suite.with_file_name("cache");
    let output = Command::new(RAYCAST)
        .env("RAYCAST_CACHE_DIR", &cache)
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(format!("{} -fault channel_swap", common::open_raycast()))
        .args(["--allow-read", common::open_raycast_folder()])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&output.stdout);
    assert!(said.contains("big0"), "{said}");
    let kept = common::files_in(&cache);
    assert!(kept >= 8, "{kept} renders kept: {said}");
}

fn start_check(suite: &Path, renderer: &Path, report: &Path) -> Child {
    start_check_in(suite, renderer, report, &std::env::temp_dir())
}

/// `start_check`, check's scratch made in `temporary`.
fn start_check_in(suite: &Path, renderer: &Path, report: &Path, temporary: &Path) -> Child {
    Command::new(RAYCAST)
        .env("TMPDIR", temporary)
        // Nothing kept from another run: every render is made anew.
        .env("RAYCAST_CACHE_DIR", suite.with_file_name("cache"))
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(renderer)
        .args(["--report", report.to_str().unwrap(), "--jobs", "1"])
        .args(["--timeout", "120"])
        .args(["--allow-read", common::open_raycast_folder()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// The processes whose parent is `pid` and whose command line holds `word` and `token`.
fn children_with(pid: u32, word: &str, token: &str) -> usize {
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter(|entry| {
            let stat = std::fs::read_to_string(entry.path().join("stat")).unwrap_or_default();
            let parent = stat
                .rfind(')')
                .and_then(|at| stat[at + 1..].split_whitespace().nth(1))
                .and_then(|p| p.parse::<u32>().ok());
            let cmdline = std::fs::read(entry.path().join("cmdline")).unwrap_or_default();
            let cmdline = String::from_utf8_lossy(&cmdline);
            parent == Some(pid) && cmdline.contains(word) && cmdline.contains(token)
        })
        .count()
}

/// Waits until check's renderer (`token`) has run and ended (its line's supervisor came and
/// went; the cage's probe before the lines names no renderer): the diagnosis has begun.
fn wait_for_diagnosis(check: &mut Child, token: &str) {
    let start = Instant::now();
    let mut seen = false;
    loop {
        assert!(
            check.try_wait().unwrap().is_none(),
            "check ended before its diagnosis began"
        );
        let running = children_with(check.id(), "__supervise", token) > 0;
        if seen && !running {
            return;
        }
        seen |= running;
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the renderer never ran"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Sends `signal` and waits for check: its exit status and stdout, and how long it took.
fn stop(check: Child, signal: &str) -> (Option<i32>, String, Duration) {
    let sent = Instant::now();
    let status = Command::new("kill")
        .args(["-s", signal, &check.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let mut check = check;
    while check.try_wait().unwrap().is_none() {
        if sent.elapsed() > Duration::from_secs(200) {
            let _ = check.kill();
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let took = sent.elapsed();
    let output = check.wait_with_output().unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        took,
    )
}

#[test]
fn a_stop_during_diagnosis_ends_check_at_once_with_a_whole_report() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    for (k, signal) in ["INT", "TERM", "HUP"].into_iter().enumerate() {
        let dir = tempfile::tempdir().unwrap();
        let seed = 1 + k as u32;
        let suite = suite(dir.path(), &later, 240, seed..seed + 1);
        let renderer = faulty_renderer(dir.path(), "diagnosed-token");
        let report = dir.path().join("report");
        keep_the_seeded_renders(&suite);
        let mut check = start_check(&suite, &renderer, &report);
        wait_for_diagnosis(&mut check, "diagnosed-token");
        let (code, out, took) = stop(check, signal);
        assert!(
            took < STOPS_WITHIN,
            "SIG{signal}: check took {took:?} to end: {out}"
        );
        assert_eq!(code, Some(130), "SIG{signal}: {out}");
        assert!(
            out.contains("Diagnosis not finished: check was interrupted; from the pixels alone:"),
            "SIG{signal}: {out}"
        );
        let summary = common::summary_of(&report);
        assert_eq!(summary["partial"], true, "SIG{signal}");
        assert!(report.join("index.html").is_file());
        assert_eq!(
            common::left_running("diagnosed-token").len(),
            0,
            "SIG{signal}"
        );
    }
}

#[test]
fn a_stop_while_references_render_ends_check_at_once() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Many lines new to the cache: raycast renders their references for a long while first.
    let first = std::process::id() * 100;
    let suite = suite(dir.path(), &later, 400, first..first + 24);
    let renderer = faulty_renderer(dir.path(), "referenced-token");
    let report = dir.path().join("report");
    let check = start_check(&suite, &renderer, &report);
    std::thread::sleep(Duration::from_millis(800));
    let (code, out, took) = stop(check, "TERM");
    assert!(took < STOPS_WITHIN, "check took {took:?} to end: {out}");
    assert_eq!(code, Some(130), "{out}");
    assert!(out.contains("ERROR  big0: interrupted"), "{out}");
    assert!(out.contains("ERROR  big23: interrupted"), "{out}");
    assert_eq!(common::summary_of(&report)["partial"], true);
    assert_eq!(common::left_running("referenced-token").len(), 0);
}

#[test]
fn a_second_stop_ends_check_now_and_still_leaves_nothing_behind() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let temporary = dir.path().join("tmp");
    std::fs::create_dir(&temporary).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&temporary, std::fs::Permissions::from_mode(0o777)).unwrap();
    let suite = suite(dir.path(), &later, 240, 7..8);
    let renderer = faulty_renderer(dir.path(), "twice-token");
    let report = dir.path().join("report");
    keep_the_seeded_renders(&suite);
    let mut check = start_check_in(&suite, &renderer, &report, &temporary);
    wait_for_diagnosis(&mut check, "twice-token");
    let pid = check.id().to_string();
    let sent = Instant::now();
    for _ in 0..2 {
        assert!(
            Command::new("kill")
                .args(["-INT", &pid])
                .status()
                .unwrap()
                .success()
        );
    }
    let output = check.wait_with_output().unwrap();
    assert!(sent.elapsed() < STOPS_WITHIN, "{:?}", sent.elapsed());
    assert_eq!(output.status.code(), Some(130));
    let said = String::from_utf8_lossy(&output.stderr);
    // Ended at once, or (where the first stop was quicker than the second signal) as asked
    // the first time, with its report: either way nothing of it is left.
    assert!(
        said.contains("raycast: check: stopped at once; no report written")
            || report.join("summary.json").is_file(),
        "{said}"
    );
    let deadline = Instant::now() + Duration::from_secs(5);
    while !common::left_running("twice-token").is_empty() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(common::left_running("twice-token").len(), 0);
    let left: Vec<_> = std::fs::read_dir(&temporary)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(left.is_empty(), "scratch left behind: {left:?}");
}

#[test]
fn a_deadline_shorter_than_the_diagnoses_still_grades_and_reports_in_time() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &later, 240, 11..14);
    let renderer = faulty_renderer(dir.path(), "deadline-token");
    let report = dir.path().join("report");
    let start = Instant::now();
    let output = Command::new(RAYCAST)
        .env("RAYCAST_CACHE_DIR", dir.path().join("cache"))
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(&renderer)
        .args(["--report", report.to_str().unwrap(), "--jobs", "1"])
        .args(["--deadline", &DEADLINE.as_secs().to_string()])
        .args(["--allow-read", common::open_raycast_folder()])
        .output()
        .unwrap();
    let took = start.elapsed();
    let out = String::from_utf8_lossy(&output.stdout);
    // Its work stops before the deadline; the report is written in the time left.
    assert!(took < DEADLINE + STOPS_WITHIN / 4, "{took:?}: {out}");
    assert_eq!(output.status.code(), Some(1), "{out}");
    assert!(
        out.contains("check's --deadline came: the pictures not graded count as failed"),
        "{out}"
    );
    // What was diagnosed in part says so; what was not reached (on a busy machine, a line
    // itself) is over budget.
    assert!(
        out.contains("Diagnosis not finished: check's --deadline came; from the pixels alone:")
            || out.contains("over_budget: check's --deadline came before this line was graded"),
        "{out}"
    );
    assert_eq!(common::summary_of(&report)["partial"], true);
    assert!(report.join("gradescope.json").is_file());
    assert_eq!(common::left_running("deadline-token").len(), 0);
}

#[test]
fn every_line_is_graded_before_any_is_diagnosed() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &later, 160, 21..24);
    let renderer = faulty_renderer(dir.path(), "order-token");
    let report = dir.path().join("report");
    let mut check = start_check(&suite, &renderer, &report);
    // The renderers' phase is over once no line's supervisor has run for a second (lines follow
    // each other within milliseconds); had the first line been diagnosed before the next ran,
    // that second would fall in its diagnosis, with the other lines not yet run.
    let start = Instant::now();
    let (mut seen, mut quiet_since) = (false, None);
    loop {
        assert!(
            check.try_wait().unwrap().is_none(),
            "check ended before it was stopped"
        );
        let running = children_with(check.id(), "__supervise", "order-token") > 0;
        seen |= running;
        match (running, quiet_since) {
            (true, _) => quiet_since = None,
            (false, None) if seen => quiet_since = Some(Instant::now()),
            (false, Some(since)) if since.elapsed() > Duration::from_secs(1) => break,
            _ => {}
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the renderer never ran"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let (code, out, _) = stop(check, "INT");
    assert_eq!(code, Some(130), "{out}");
    for k in 0..3 {
        assert!(
            out.lines()
                .any(|l| l.starts_with(&format!("FAIL   big{k}, "))),
            "big{k} not graded: {out}"
        );
    }
    assert!(
        out.contains("Diagnosis not finished: check was interrupted; from the pixels alone:"),
        "{out}"
    );
}

/// A class of three students, each submitting the renderer of `faulty_renderer`, their folders
/// named with `token` (so their lines' supervisors can be found); open to every user, as the
/// renderers of a class run as an unprivileged one under root.
fn class_roster(dir: &Path, token: &str) -> (PathBuf, Vec<String>) {
    use std::os::unix::fs::PermissionsExt;
    let script = std::fs::read(faulty_renderer(dir, token)).unwrap();
    let roster = dir.join("roster");
    let names: Vec<String> = ["ann", "ben", "cat"]
        .iter()
        .map(|n| format!("{n}-{token}"))
        .collect();
    for name in &names {
        let folder = roster.join(name);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("raytracer"), &script).unwrap();
        std::fs::set_permissions(
            folder.join("raytracer"),
            std::fs::Permissions::from_mode(0o755),
        )
        .unwrap();
    }
    for open in [dir.to_path_buf(), roster.clone()]
        .into_iter()
        .chain(names.iter().map(|n| roster.join(n)))
    {
        std::fs::set_permissions(&open, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    (roster, names)
}

#[test]
fn a_stop_during_a_class_ends_it_at_once_with_every_student_in_its_table() {
    let Some(later) = common::later_dir("the stopping tests") else {
        return;
    };
    // The whole class, and the first of two shards (ann and cat).
    for (k, shard) in [None, Some("1/2")].into_iter().enumerate() {
        let dir = tempfile::tempdir().unwrap();
        let token = format!("classtoken{k}");
        let seed = 31 + k as u32;
        let suite = suite(dir.path(), &later, 240, seed..seed + 1);
        let (roster, names) = class_roster(dir.path(), &token);
        let report = dir.path().join("report");
        keep_the_seeded_renders(&suite);
        let mut command = Command::new(RAYCAST);
        command
            .env("RAYCAST_CACHE_DIR", suite.with_file_name("cache"))
            .args(["check", suite.to_str().unwrap(), "--class"])
            .arg(&roster)
            .args(["--renderer", "./raytracer", "--report"])
            .arg(&report)
            .args(["--jobs", "1", "--timeout", "120"])
            .args(["--allow-read", common::open_raycast_folder()])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        if let Some(shard) = shard {
            command.args(["--shard", shard]);
        }
        let mut check = command.spawn().unwrap();
        // The first student's line has run: their picture is being diagnosed.
        wait_for_diagnosis(&mut check, &token);
        let (code, out, took) = stop(check, "TERM");
        assert!(
            took < STOPS_WITHIN,
            "{shard:?}: took {took:?} to end: {out}"
        );
        assert_eq!(code, Some(130), "{shard:?}: {out}");
        assert!(
            out.contains("check was interrupted: the table is partial"),
            "{shard:?}: {out}"
        );
        let summary = common::summary_of(&report);
        assert_eq!(summary["partial"], true, "{shard:?}");
        let students = summary["students"].as_array().unwrap();
        let expected: Vec<&String> = match shard {
            None => names.iter().collect(),
            Some(_) => vec![&names[0], &names[2]],
        };
        let listed: Vec<&str> = students
            .iter()
            .map(|s| s["name"].as_str().unwrap())
            .collect();
        assert_eq!(listed, expected, "every student of the run has a row");
        // The first was graded, its diagnosis cut short; the rest were never reached.
        assert_eq!(students[0]["build"], "", "{shard:?}: {out}");
        assert_eq!(students[0]["pictures"], 1, "{shard:?}");
        let first = report.join(students[0]["report"].as_str().unwrap());
        assert!(
            std::fs::read_to_string(first.join("summary.json"))
                .unwrap()
                .contains("Diagnosis not finished: check was interrupted"),
            "{shard:?}"
        );
        for student in &students[1..] {
            assert_eq!(
                student["build"], "not graded: check was interrupted before this student's turn",
                "{shard:?}"
            );
        }
        assert!(report.join("class.html").is_file());
        assert!(report.join("class.csv").is_file());
        assert_eq!(common::left_running(&token).len(), 0, "{shard:?}");
    }
}
