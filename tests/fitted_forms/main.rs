//! Mistakes written in forms of their own (the example `student_forms`, not the fault library's
//! code): check fits the camera, the depth range and the shading to the student's pictures and
//! names the fault from where the fit lands, on every picture the mistake changes.

// The renderers here are shell scripts around the example.
#![cfg(unix)]

#[path = "../common/mod.rs"]
mod common;

mod camera;
mod pictures;
mod rays;
mod shading;
mod textures_and_samples;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

fn conformance_dir() -> Option<PathBuf> {
    common::data_dir(
        "the fitted forms",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

/// check's report of the example's `form` on the conformance lines of `scenes`: each failing
/// picture's line of the terminal's table.
fn failing(form: &str, scenes: &[&str]) -> Vec<String> {
    failing_in(
        &conformance_dir().expect("the conformance suite"),
        form,
        scenes,
    )
}

/// [`failing`] on the lines of the suite in `conformance` that name any of `scenes` (a scene
/// file, or an output's file name).
fn failing_in(conformance: &Path, form: &str, scenes: &[&str]) -> Vec<String> {
    let out = checked_in(conformance, form, scenes);
    let failing: Vec<String> = out
        .lines()
        .filter(|l| l.starts_with("FAIL"))
        .map(String::from)
        .collect();
    assert!(!failing.is_empty(), "{form}: nothing failed\n{out}");
    failing
}

/// check's terminal report of the example's `form` on the lines of the suite in `conformance`
/// that name any of `scenes`.
fn checked_in(conformance: &Path, form: &str, scenes: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let suite = dir.path().join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    for folder in ["scenes", "reference"] {
        std::os::unix::fs::symlink(conformance.join(folder), suite.join(folder)).unwrap();
    }
    let commands = std::fs::read_to_string(conformance.join("COMMANDS.txt")).unwrap();
    let lines: Vec<&str> = commands
        .lines()
        .filter(|line| line.starts_with("raytracer "))
        .filter(|line| scenes.iter().any(|s| line.contains(&format!(" {s}"))))
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    let example = common::open_example("student_forms");
    let renderer = dir.path().join(form);
    std::fs::write(
        &renderer,
        format!("#!/bin/sh\nexec {example} {form} \"$@\"\n"),
    )
    .unwrap();
    std::fs::set_permissions(&renderer, std::fs::Permissions::from_mode(0o755)).unwrap();
    let output = Command::new(RAYCAST)
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(&renderer)
        .args([
            "--allow-read",
            Path::new(&example).parent().unwrap().to_str().unwrap(),
        ])
        .env("RAYCAST_CACHE_DIR", dir.path().join("cache"))
        .output()
        .unwrap();
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Every failing picture names `fault` first, alone.
fn all_named(form: &str, scenes: &[&str], fault: &str) -> Vec<String> {
    named_in(&failing(form, scenes), form, fault)
}

/// Every line of `failing` names `fault` first, alone.
fn named_in(failing: &[String], form: &str, fault: &str) -> Vec<String> {
    let failing = failing.to_vec();
    for line in &failing {
        assert!(
            // Graded against the staff's image, or raycast's render where there is none, or
            // the spread of its renders where the picture is drawn by chance.
            [
                "% of pixels off",
                "against raycast's render",
                "with several seeds"
            ]
            .iter()
            .any(|graded| line
                .contains(&format!("{graded}: {fault}: raycast's render"))
                || line.contains(&format!("{graded}: {fault}, "))),
            "{form}: {line}\n{}",
            failing.join("\n")
        );
    }
    failing
}

/// Each failing picture of `form` on the later assignments' lines that name any of `scenes`
/// names `fault` first, alone, with `numbers` (a part of its line); returns how many failed.
fn later_named(form: &str, scenes: &[&str], fault: &str, numbers: &str) -> usize {
    let later =
        common::later_dir("the fitted forms of assignments 4 to 7").expect("the later assignments");
    let failing = failing_in(&later, form, scenes);
    let failing = named_in(&failing, form, fault);
    assert!(
        failing.iter().all(|l| l.contains(numbers)),
        "{form}: {}",
        failing.join("\n")
    );
    failing.len()
}

/// Each failing picture of `form` on the conformance lines that name any of `scenes` names
/// `fault` first (alone, or with those the line cannot tell from it), with `numbers` (a part
/// of its line); returns how many failed.
fn conformance_named(form: &str, scenes: &[&str], fault: &str, numbers: &str) -> usize {
    let failing = named_in(&failing(form, scenes), form, fault);
    assert!(
        failing.iter().all(|l| l.contains(numbers)),
        "{form}: {}",
        failing.join("\n")
    );
    failing.len()
}
