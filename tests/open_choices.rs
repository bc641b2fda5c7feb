//! check fails no correct tracer on a question the course leaves open: raycast rendered with
//! each allowed answer (`-choose NAME`) passes every line of the later assignments that the
//! answer changes, and the report says which answer it took; a picture the course leaves free
//! (Wood) is informational, never failed; a fault is still a fault.

// The renderers are raycast itself, started through its path; the suites link the course's
// scenes.
#![cfg(unix)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use raycast::check::choices::{Acceptance, answers};

/// The later assignments' lines that the open questions reach, at sizes that render in
/// moments: Gaussian and box filters, a checkerboard filtered with a box, Noise and Marble, a
/// glass sphere's shadow.
const LINES: &[&str] = &[
    "raytracer -input scene7_01_sphere_triangle.txt -size 9 9 -render_filter filter7_01c.tga 20 -gaussian_filter 0.5",
    "raytracer -input scene7_01_sphere_triangle.txt -size 9 9 -render_filter filter7_01a.tga 20 -box_filter 0.5",
    "raytracer -input scene7_02_checkerboard.txt -size 45 45 -output output7_02d.tga -uniform_samples 16 -box_filter 0.5",
    "raytracer -input scene7_02_checkerboard.txt -size 45 45 -output output7_02c.tga -uniform_samples 9 -gaussian_filter 0.6",
    "raytracer -input scene6_15_marble_cubes.txt -size 60 60 -output output6_15.tga",
    "raytracer -input scene6_17_marble_vase.txt -size 60 60 -output output6_17a.tga -grid 15 30 15 -bounces 1 -shadows",
    "raytracer -input scene4_08_transparent_sphere_1.1.txt -size 50 50 -output output4_08.tga -shadows -bounces 5 -weight 0.01 -shade_back",
];

fn suite(dir: &Path, later: &Path, lines: &[&str]) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    std::os::unix::fs::symlink(later.join("scenes"), suite.join("scenes")).unwrap();
    suite
}

fn check(suite: &Path, renderer: &str, report: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["check", suite.to_str().unwrap(), "--renderer", renderer])
        .args(["--report", report.to_str().unwrap(), "--jobs", "2"])
        .output()
        .unwrap()
}

#[test]
fn every_allowed_answer_passes_the_lines_it_changes_and_says_so() {
    let Some(later) = common::later_dir("the open questions' suite") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &later, LINES);
    let raycast = common::open_raycast();
    let mut named = Vec::new();
    for (choice, answer) in answers() {
        let report = dir.path().join(answer.name);
        let output = check(
            &suite,
            &format!("{raycast} -choose {}", answer.name),
            &report,
        );
        let out = String::from_utf8_lossy(&output.stdout);
        assert_eq!(output.status.code(), Some(0), "{}:\n{out}", answer.name);
        assert!(
            out.contains(&format!("{} passed, 0 failed", LINES.len())),
            "{}:\n{out}",
            answer.name
        );
        // Found by rendering: where the answer changes a picture past the tolerance, it is
        // named there, with its question, in summary.json.
        if out.contains(&format!("allowed: {}", answer.said)) {
            named.push(answer.name);
        }
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap())
                .unwrap();
        let accepted: Vec<&serde_json::Value> = summary["images"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|image| !image["accepted"].is_null())
            .collect();
        for image in accepted {
            assert_eq!(image["status"], "pass");
            assert_eq!(image["accepted"]["choice"], choice.name);
            assert_eq!(image["accepted"]["answer"], answer.name);
            assert_eq!(
                Acceptance::from_json(&image["accepted"]),
                Some(Acceptance::Answer(choice, answer))
            );
        }
    }
    // A box whose edges are out (a sample lies on the edge only where the grid of samples meets
    // it exactly), a fixed epsilon in the allowed range, a hit exactly at the light's distance
    // and the course's -weight where a line gives none change no picture of these lines past
    // the tolerance; every other answer changes some.
    assert_eq!(
        named,
        [
            "gaussian_uncut",
            "box_closed",
            "checker_swapped",
            "noise_clamped",
            "marble_clamped",
            "marble_absolute",
            "shadows_through_each_surface",
            "shadows_through_each_object",
            "shadows_through_by_distance"
        ]
    );
}

#[test]
fn a_picture_the_course_leaves_free_is_informational_and_a_fault_is_still_a_fault() {
    let Some(later) = common::later_dir("the open questions' suite") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(
        dir.path(),
        &later,
        &[
            "raytracer -input scene6_16_wood_cubes.txt -size 60 60 -output output6_16.tga",
            "raytracer -input scene7_02_checkerboard.txt -size 45 45 -output output7_02.tga",
        ],
    );
    let raycast = common::open_raycast();
    // The texture's Transform ignored changes the Wood (free-form: informational) and the
    // checkerboard (fixed by the course: a fault, named).
    let output = check(
        &suite,
        &format!("{raycast} -fault texture_transform"),
        &dir.path().join("report"),
    );
    let out = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{out}");
    assert!(
        out.contains(
            "info   output6_16, 50.611% of pixels off against raycast's render: Informational: \
             The course leaves Wood free-form (extra credit), so a picture with Wood is shown, \
             not graded."
        ),
        "{out}"
    );
    assert!(out.contains("FAIL   output7_02"), "{out}");
    assert!(out.contains("texture_transform"), "{out}");
    assert!(
        out.contains("1 passed (1 informational), 1 failed"),
        "{out}"
    );
}

#[test]
fn an_unknown_answer_is_refused_with_the_list() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("x.txt"),
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n\
         Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }\n\
         Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }\n",
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["-input", "x.txt", "-size", "8", "8", "-output", "x.tga"])
        .args(["-choose", "gaussian_sharp"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let names: Vec<&str> = answers().map(|(_, a)| a.name).collect();
    assert_eq!(
        String::from_utf8_lossy(&output.stderr),
        format!(
            "raycast: -choose: unknown answer 'gaussian_sharp' (one of {})\n",
            names.join(", ")
        )
    );
    assert_ne!(output.status.code(), Some(0));
    assert!(!dir.path().join("x.tga").exists());
}

#[test]
fn a_suite_pins_a_question_to_one_answer() {
    let Some(later) = common::later_dir("the open questions' suite") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let gaussian = &LINES[..1];
    let suite = suite(dir.path(), &later, gaussian);
    let raycast = common::open_raycast();
    let uncut = format!("{raycast} -choose gaussian_uncut");
    let run = |renderer: &str, name: &str| {
        let output = check(&suite, renderer, &dir.path().join(name));
        (
            output.status.code(),
            String::from_utf8_lossy(&output.stdout).into_owned(),
            String::from_utf8_lossy(&output.stderr).into_owned(),
        )
    };
    // Pinned to raycast's answer: the other fails.
    std::fs::write(
        suite.join("CHOICES"),
        "# this class cuts\ngaussian_cut raycast\n",
    )
    .unwrap();
    let (code, out, _) = run(&uncut, "a");
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("FAIL   filter7_01c"), "{out}");
    assert_eq!(run(raycast, "b").0, Some(0));
    // Pinned to the other: its render is the reference, raycast's own fails.
    std::fs::write(suite.join("CHOICES"), "gaussian_cut gaussian_uncut\n").unwrap();
    let (code, out, _) = run(&uncut, "c");
    assert_eq!(code, Some(0), "{out}");
    assert!(
        out.contains("pass   filter7_01c, 0.000% of pixels off"),
        "{out}"
    );
    assert_eq!(run(raycast, "d").0, Some(1));
    // What a teacher mistypes is named.
    std::fs::write(suite.join("CHOICES"), "gaussian_cut sharp\n").unwrap();
    let (code, _, said) = run(raycast, "e");
    assert_eq!(code, Some(2));
    assert!(
        said.contains(
            "CHOICES line 1: 'sharp' is no answer to gaussian_cut (raycast, gaussian_uncut)"
        ),
        "{said}"
    );
    std::fs::write(suite.join("CHOICES"), "wood rings\n").unwrap();
    let (_, _, said) = run(raycast, "f");
    assert!(
        said.contains("CHOICES line 1: 'wood' has no answers to pin"),
        "{said}"
    );
}

/// A tracer that answers two open questions otherwise at once (a scene of Noise and Marble,
/// each clamped to [0, 1]: the student form `noise_unmapped`, not the library's code) passes,
/// and the report names both answers.
#[test]
fn two_questions_answered_otherwise_together_pass_and_are_both_named() {
    let Some(later) = common::later_dir("the open questions' suite") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let lines = &LINES[4..6];
    let suite = suite(dir.path(), &later, lines);
    let report = dir.path().join("report");
    let renderer = format!("{} noise_unmapped", common::open_example("student_forms"));
    let output = check(&suite, &renderer, &report);
    let out = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{out}");
    let both = "allowed: your Noise clamps its sum to [0, 1]; and your Marble clamps its sine to \
                [0, 1]";
    assert_eq!(out.matches(both).count(), 2, "{out}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap())
            .unwrap();
    for image in summary["images"].as_array().unwrap() {
        assert_eq!(image["status"], "pass");
        assert_eq!(image["accepted"]["answer"], "noise_clamped");
        assert_eq!(image["accepted"]["also"]["answer"], "marble_clamped");
        let read = Acceptance::from_json(&image["accepted"]).unwrap();
        assert!(matches!(read, Acceptance::Answers(_)), "{read:?}");
    }
}
