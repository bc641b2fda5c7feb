//! Pictures that depend on chance (assignment 7's random and jittered samples): a correct
//! tracer with another random generator passes them all, and the library's sampling and
//! filter faults still fail and are named.

// The renderers here are shell scripts.
#![cfg(unix)]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Command;

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// The later assignments' lines whose samples fall by chance and that are cheap to render.
const LINES: &[&str] = &[
    "samples7_01c.tga",
    "samples7_01d.tga",
    "samples7_01a_low_res.tga",
    "output7_01a_low_res.tga",
    "output7_01b_low_res.tga",
    "output7_01c_low_res.tga",
    "output7_01h_low_res.tga",
    "output7_01i_low_res.tga",
];

/// check's terminal table for raycast with `extra` arguments as the renderer, over [`LINES`].
fn check(dir: &Path, later: &Path, extra: &str) -> Vec<String> {
    let suite = dir.join("suite");
    if !suite.exists() {
        std::fs::create_dir_all(&suite).unwrap();
        std::os::unix::fs::symlink(later.join("scenes"), suite.join("scenes")).unwrap();
        let commands = std::fs::read_to_string(later.join("COMMANDS.txt")).unwrap();
        let lines: Vec<&str> = commands
            .lines()
            .filter(|l| !l.starts_with('#') && LINES.iter().any(|name| l.contains(name)))
            .collect();
        assert_eq!(lines.len(), LINES.len(), "{lines:?}");
        std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    }
    let renderer = dir.join(format!("renderer{}", extra.len()));
    std::fs::write(
        &renderer,
        format!(
            "#!/bin/sh\nexec {} \"$@\" {extra}\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&renderer, std::fs::Permissions::from_mode(0o755)).unwrap();
    let output = Command::new(RAYCAST)
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(&renderer)
        .args(["--allow-read", common::open_raycast_folder()])
        .env("RAYCAST_CACHE_DIR", dir.join("cache"))
        .output()
        .unwrap();
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter(|l| l.starts_with("pass") || l.starts_with("FAIL") || l.starts_with("ERROR"))
        .map(String::from)
        .collect()
}

#[test]
fn another_random_generator_passes_every_picture_drawn_by_chance() {
    let Some(later) = common::later_dir("the pictures drawn by chance") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    for seed in ["1", "424242"] {
        let table = check(dir.path(), &later, &format!("-seed {seed}"));
        assert_eq!(table.len(), LINES.len(), "{}", table.join("\n"));
        assert!(
            table.iter().all(|l| l.starts_with("pass")),
            "-seed {seed}:\n{}",
            table.join("\n")
        );
    }
}

/// The files of check's cache in `dir`.
fn kept(dir: &Path) -> usize {
    common::files_in(&dir.join("cache"))
}

#[test]
fn raycasts_own_pictures_pass_without_the_other_seeds_being_rendered() {
    let Some(later) = common::later_dir("the pictures drawn by chance") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let table = check(dir.path(), &later, "");
    assert!(
        table.len() == LINES.len() && table.iter().all(|l| l.starts_with("pass")),
        "{}",
        table.join("\n")
    );
    // raycast's own render of each line, one file a picture, and nothing else: a picture that
    // passes against a draw of the spread is within the spread.
    let own = kept(dir.path());
    assert!(
        (LINES.len()..=2 * LINES.len()).contains(&own),
        "{own} files kept"
    );
    // Another generator's traced pictures are graded against the spread: its seven other draws
    // (the samples pictures against their structure).
    let table = check(dir.path(), &later, "-seed 1");
    assert!(
        table.iter().all(|l| l.starts_with("pass")),
        "{}",
        table.join("\n")
    );
    let traced = LINES.iter().filter(|l| l.starts_with("output")).count();
    assert_eq!(kept(dir.path()), own + 7 * traced);
}

#[test]
fn sampling_and_filter_faults_still_fail_and_are_named() {
    let Some(later) = common::later_dir("the pictures drawn by chance") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Jittered samples anywhere in the pixel: two fall in one cell of the grid.
    let table = check(dir.path(), &later, "-fault jitter_whole_pixel");
    let samples = table
        .iter()
        .find(|l| l.contains("samples7_01c,"))
        .unwrap_or_else(|| panic!("{}", table.join("\n")));
    assert!(
        samples.starts_with("FAIL") && samples.contains(": jitter_whole_pixel"),
        "{samples}"
    );
    // The filter's weights wrong: every filtered picture's mean moves.
    let table = check(dir.path(), &later, "-fault filter_weights");
    for name in [
        "output7_01b_low_res",
        "output7_01c_low_res",
        "output7_01h_low_res",
    ] {
        let line = table
            .iter()
            .find(|l| l.contains(&format!("{name},")))
            .unwrap_or_else(|| panic!("{name}: {}", table.join("\n")));
        assert!(
            line.starts_with("FAIL") && line.contains(": filter_weights"),
            "{line}"
        );
    }
}
