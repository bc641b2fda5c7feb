//! `raycast check --vary SEED`: graded on scenes nobody has seen. raycast passes its varied
//! scenes on both suites; a renderer that memorised the course's pictures (it renders the
//! original scenes whatever it is given) passes the course and fails every varied picture but
//! the filter's weights, which do not depend on the scene; the same seed makes the same scenes, kept in the
//! report.

// The renderers are shell scripts, graded in Unix's cage.
#![cfg(unix)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn check(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raycast"))
        .arg("check")
        .args(args)
        .args(["--allow-read", common::open_raycast_folder()])
        .output()
        .unwrap()
}

fn text(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr)
}

/// A suite of the command lines of `data` whose scene names start with one of `scenes`.
fn suite(dir: &Path, data: &Path, scenes: &[&str]) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    let commands: Vec<String> = std::fs::read_to_string(data.join("COMMANDS.txt"))
        .unwrap()
        .lines()
        .filter(|l| {
            scenes
                .iter()
                .any(|s| l.starts_with(&format!("raytracer -input {s}")))
        })
        .map(String::from)
        .collect();
    assert!(!commands.is_empty());
    std::fs::write(suite.join("COMMANDS.txt"), commands.join("\n") + "\n").unwrap();
    std::os::unix::fs::symlink(data.join("scenes"), suite.join("scenes")).unwrap();
    std::os::unix::fs::symlink(data.join("reference"), suite.join("reference")).unwrap();
    suite
}

/// A renderer that ships the course's scenes in its own folder and renders those, whatever
/// scene it is given: the pictures it prints are the course's.
fn memoriser(dir: &Path, data: &Path) -> String {
    let own = dir.join("memoriser");
    let memory = own.join("memory");
    std::fs::create_dir_all(&memory).unwrap();
    for entry in std::fs::read_dir(data.join("scenes")).unwrap().flatten() {
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), memory.join(entry.file_name())).unwrap();
        }
    }
    let program = own.join("raytracer");
    std::fs::write(
        &program,
        format!(
            "#!/usr/bin/env bash\nhere=$(dirname \"$0\")\nargs=()\n\
             while [ $# -gt 0 ]; do\n\
             if [ \"$1\" = -input ]; then args+=(-input \"$here/memory/$(basename \"$2\")\"); shift 2\n\
             else args+=(\"$1\"); shift; fi\ndone\nexec {} \"${{args[@]}}\"\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
    for folder in [dir, &own, &memory] {
        std::fs::set_permissions(folder, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    program.display().to_string()
}

fn summary(report: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap()).unwrap()
}

/// The files of `folder` and their bytes.
fn files(folder: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut found: Vec<(PathBuf, Vec<u8>)> = std::fs::read_dir(folder)
        .unwrap()
        .flatten()
        .map(|e| {
            (
                PathBuf::from(e.file_name()),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    found.sort();
    found
}

fn graded_on_varied_scenes(data: &Path, scenes: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), data, scenes);
    let suite = suite.to_str().unwrap();
    let raycast = common::open_raycast();
    let report = |name: &str| dir.path().join(name);
    // The suite graded with `renderer` on the scenes of `seed`, its report in `name`.
    let graded = |renderer: &str, seed: &str, name: &str| {
        check(&[
            suite,
            "--renderer",
            renderer,
            "--vary",
            seed,
            "--report",
            report(name).to_str().unwrap(),
        ])
    };

    // raycast passes its own varied scenes; the report keeps them and says how they were made.
    let once = graded(raycast, "7", "once");
    assert!(once.status.success(), "{}", text(&once));
    assert!(
        text(&once).contains("graded on varied scenes (--vary 7): "),
        "{}",
        text(&once)
    );
    let said = summary(&report("once"));
    assert_eq!(said["varied"]["seed"], 7, "{said}");
    let varied = report("once").join("varied");
    let kept = files(&varied);
    assert_eq!(
        said["varied"]["scenes"].as_array().unwrap().len(),
        kept.len()
    );
    assert!(!kept.is_empty());
    for (name, bytes) in &kept {
        let original = std::fs::read(data.join("scenes").join(name)).unwrap();
        assert_ne!(&original, bytes, "{} is not varied", name.display());
    }
    let page = std::fs::read_to_string(report("once").join("index.html")).unwrap();
    assert!(page.contains("Graded on varied scenes (--vary 7)"));
    assert!(page.contains(&format!("href=\"varied/{}\"", kept[0].0.display())));

    // The same seed, the same scenes; another seed, others.
    let again = graded(raycast, "7", "again");
    assert!(again.status.success(), "{}", text(&again));
    assert_eq!(files(&report("again").join("varied")), kept);
    let other = graded(raycast, "8", "other");
    assert!(other.status.success(), "{}", text(&other));
    assert_ne!(files(&report("other").join("varied")), kept);

    // The memoriser passes the course's scenes and fails the varied ones, but for the
    // pictures that do not depend on the scene (the filter's weights) and those shown, not
    // graded (the grid's colours are the student's to choose).
    let memoriser = memoriser(dir.path(), data);
    let course = check(&[suite, "--renderer", &memoriser]);
    assert!(course.status.success(), "{}", text(&course));
    let caught = graded(&memoriser, "7", "caught");
    assert_eq!(caught.status.code(), Some(1), "{}", text(&caught));
    for image in summary(&report("caught"))["images"].as_array().unwrap() {
        let scene_free = image["picture"] == "-render_filter";
        let shown = image["accepted"]["informational"].is_string();
        let expected = if scene_free || shown { "pass" } else { "fail" };
        assert_eq!(image["status"], expected, "{image}");
        if expected == "fail" {
            // Named for what it is: the original scene's picture.
            assert_eq!(image["diagnoses"][0]["code"], "unvaried", "{image}");
            assert_eq!(image["diagnoses"].as_array().unwrap().len(), 1, "{image}");
        }
    }
}

#[test]
fn a_renderer_that_memorised_the_course_fails_varied_scenes_that_raycast_passes() {
    if let Some(conformance) = common::data_dir(
        "the --vary tests on assignments 1 and 2",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    ) {
        graded_on_varied_scenes(
            &conformance,
            &[
                "scene1_01",
                "scene1_05",
                "scene2_01",
                "scene2_07",
                "scene2_14",
            ],
        );
    }
}

#[test]
fn varied_later_assignments_keep_their_shadows_grids_textures_and_samples() {
    if let Some(later) = common::later_dir("the --vary tests on assignments 3 to 7") {
        graded_on_varied_scenes(
            &later,
            &[
                "scene3_09",
                "scene4_01",
                "scene4_08",
                "scene5_02",
                "scene6_13",
                "scene7_01",
            ],
        );
    }
}

#[test]
fn a_seed_that_is_not_a_whole_number_is_a_usage_error() {
    let output = check(&["suite", "--renderer", "true", "--vary", "x7"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output).contains(
            "--vary needs a seed, a whole number from 0 to 18446744073709551615, found 'x7'"
        ),
        "{}",
        text(&output)
    );
}

#[test]
fn shards_of_a_varied_run_merge_with_their_scenes_and_refuse_another_seed() {
    let Some(conformance) = common::data_dir(
        "the --vary tests on assignments 1 and 2",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    ) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(
        dir.path(),
        &conformance,
        &["scene2_01", "scene2_02", "scene2_03"],
    );
    let shard = |k: &str, seed: &str| {
        let report = dir.path().join(format!("shard{k}-{seed}"));
        let output = check(&[
            suite.to_str().unwrap(),
            "--renderer",
            common::open_raycast(),
            "--vary",
            seed,
            "--shard",
            &format!("{k}/2"),
            "--report",
            report.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{}", text(&output));
        report.to_str().unwrap().to_string()
    };
    let (first, second) = (shard("1", "5"), shard("2", "5"));
    let merged = dir.path().join("merged");
    let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["check", "merge", merged.to_str().unwrap(), &first, &second])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output));
    assert_eq!(summary(&merged)["varied"]["seed"], 5);
    assert_eq!(
        files(&merged.join("varied")),
        files(&Path::new(&first).join("varied"))
    );
    let other = shard("2", "6");
    let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args([
            "check",
            "merge",
            dir.path().join("mixed").to_str().unwrap(),
            &first,
            &other,
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", text(&output));
    assert!(
        text(&output).contains("graded on other scenes (--vary) than the shards before it"),
        "{}",
        text(&output)
    );
}
