//! `raycast check` stops when it is asked to, in every phase: while raycast renders the
//! references, while the renderer runs, and while failing pictures are diagnosed by
//! simulation (the longest phase: a line whose picture no single fault explains is rendered
//! again dozens of times). Asked by SIGINT, SIGTERM or SIGHUP, it ends within a few seconds,
//! with a whole report that says what was not finished, and leaves nothing running.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// How long check may take to end once asked: far less than any phase these tests stop (each
/// lasts tens of seconds on an idle machine), with room for a busy one.
const STOPS_WITHIN: Duration = Duration::from_secs(8);

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

/// A renderer that is raycast with a fault no single fault of check's library matches at
/// once, so its picture is diagnosed at length.
fn faulty_renderer(dir: &Path, token: &str) -> PathBuf {
    let script = dir.join(format!("{token}.sh"));
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\nexec {} \"$@\" -fault filter_radius\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    script
}

fn start_check(suite: &Path, renderer: &Path, report: &Path) -> Child {
    Command::new(RAYCAST)
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

/// The processes whose parent is `pid` and whose command line holds `word`.
fn children_with(pid: u32, word: &str) -> usize {
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
            parent == Some(pid) && String::from_utf8_lossy(&cmdline).contains(word)
        })
        .count()
}

/// Waits until check's renderer has run and ended (a line's supervisor came and went): the
/// diagnosis has begun.
fn wait_for_diagnosis(check: &mut Child) {
    let start = Instant::now();
    let mut seen = false;
    loop {
        assert!(
            check.try_wait().unwrap().is_none(),
            "check ended before its diagnosis began"
        );
        let running = children_with(check.id(), "__supervise") > 0;
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

/// The processes still carrying `token` (the renderer's script's name).
fn left_running(token: &str) -> usize {
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter(|entry| {
            let cmdline = std::fs::read(entry.path().join("cmdline")).unwrap_or_default();
            String::from_utf8_lossy(&cmdline).contains(token)
        })
        .count()
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
        let mut check = start_check(&suite, &renderer, &report);
        wait_for_diagnosis(&mut check);
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
        assert_eq!(left_running("diagnosed-token"), 0, "SIG{signal}");
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
    assert_eq!(left_running("referenced-token"), 0);
}
