//! Grading a class with `raycast check --class`: submissions built and graded in one command,
//! the class's table, the platforms' formats (read by parsers that are not ours: Python's csv,
//! json and junitparser), points, a time budget, and shards merged into the report one run
//! makes.

// The renderers these tests grade are shell scripts and the cage they test is Unix's; on Windows
// check is run by CI's Wine job (.ci/windows), over raycast.exe itself.
#![cfg(unix)]

mod common;

use common::data_dir;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

fn conformance_dir() -> Option<PathBuf> {
    data_dir(
        "the class tests",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

/// A suite of the conformance suite's first `lines` lines, with its references and a POINTS
/// file giving `output2_01` three points.
fn suite(dir: &Path, conformance: &Path, lines: usize) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    let commands: Vec<String> = std::fs::read_to_string(conformance.join("COMMANDS.txt"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("raytracer -input scene2"))
        .take(lines)
        .map(String::from)
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), commands.join("\n") + "\n").unwrap();
    std::fs::write(
        suite.join("POINTS"),
        "# the first picture counts more\noutput2_01 3\n",
    )
    .unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    std::os::unix::fs::symlink(conformance.join("reference"), suite.join("reference")).unwrap();
    suite
}

/// A roster: each student a folder with a Makefile that makes `raytracer` from `raytracer.in`
/// (a script around raycast, with a fault planted where one is named), or fails to.
fn roster(dir: &Path, students: &[(&str, &str)]) -> PathBuf {
    let roster = dir.join("roster");
    let raycast = common::open_raycast();
    for (name, kind) in students {
        let folder = roster.join(name);
        std::fs::create_dir_all(&folder).unwrap();
        let script = match *kind {
            "correct" => format!("#!/bin/sh\nexec {raycast} \"$@\"\n"),
            "broken" => "this is not a script\n".to_string(),
            "slow" => format!("#!/bin/sh\nsleep 0.6\nexec {raycast} \"$@\"\n"),
            "snoop" => {
                "#!/bin/sh\ncat ../*/raytracer.in ../../*/*/raytracer.in >&2\nexit 1\n".to_string()
            }
            fault => format!("#!/bin/sh\nexec {raycast} -fault {fault} \"$@\"\n"),
        };
        std::fs::write(folder.join("raytracer.in"), script).unwrap();
        std::fs::write(
            folder.join("Makefile"),
            "raytracer: raytracer.in\n\tgrep -q '^#!' raytracer.in\n\tcp raytracer.in raytracer\n\tchmod +x raytracer\n",
        )
        .unwrap();
    }
    open_to_all(dir);
    roster
}

/// Opens `dir` and everything in it to every user (the renderers run as nobody under root).
fn open_to_all(dir: &Path) {
    let mode = |p: &Path| if p.is_dir() { 0o755 } else { 0o644 };
    for entry in walk(dir) {
        let _ = std::fs::set_permissions(&entry, std::fs::Permissions::from_mode(mode(&entry)));
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut found = vec![dir.to_path_buf()];
    if std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            found.extend(walk(&entry.path()));
        }
    }
    found
}

fn check(args: &[&str]) -> Output {
    Command::new(RAYCAST)
        .arg("check")
        .args(args)
        .args(["--allow-read", common::open_raycast_folder()])
        .output()
        .unwrap()
}

/// The class of `roster`, built with make, each `./raytracer` graded against `suite`, the
/// report in `report`.
fn grade_class(suite: &Path, roster: &Path, report: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        suite.to_str().unwrap(),
        "--class",
        roster.to_str().unwrap(),
        "--build",
        "make",
        "--renderer",
        "./raytracer",
        "--report",
        report.to_str().unwrap(),
    ];
    args.extend(extra);
    check(&args)
}

fn text(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr)
}

/// Runs Python on `program` with `args`; its stdout.
fn python(program: &str, args: &[&Path]) -> String {
    let output = Command::new("python3")
        .arg("-c")
        .arg(program)
        .args(args)
        .output()
        .expect("python3 reads the formats");
    assert!(output.status.success(), "{}", text(&output));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

#[test]
fn a_class_is_graded_in_one_command_with_its_table_and_formats() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 4);
    let roster = roster(
        dir.path(),
        &[
            ("alice", "correct"),
            ("bob", "pixel_corner"),
            ("carol", "ambient_missing"),
            ("dave", "broken"),
            ("eve", "snoop"),
        ],
    );
    let report = dir.path().join("report");
    let output = grade_class(&suite, &roster, &report, &[]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    // The terminal's table: one row a student, the verdict naming each one's fault.
    for row in [
        "alice          6/6          8/8",
        "bob            0/6          0/8",
        "carol",
        "dave           0/6          0/8",
    ] {
        assert!(out.contains(row), "no '{row}' in:\n{out}");
    }
    assert!(out.contains("pixel_corner / A2 0/6"), "{out}");
    assert!(out.contains("ambient_missing"), "{out}");
    assert!(out.contains("the build exited with status 2"), "{out}");
    // The CSV, read by Python's csv module.
    let rows = python(
        "import csv, sys\n\
         for r in csv.DictReader(open(sys.argv[1], newline='')):\n\
         \x20   print(r['student'], r['passed'], r['pictures'], r['points'], r['max_points'], r['A2 passed'], r['verdict'], r['report'])",
        &[&report.join("class.csv")],
    );
    let rows: Vec<&str> = rows.lines().collect();
    assert_eq!(rows.len(), 5, "{rows:?}");
    assert_eq!(rows[0], "alice 6 6 8 8 6  alice/index.html");
    assert_eq!(rows[1], "bob 0 6 0 8 0 pixel_corner bob/index.html");
    assert!(
        rows[2].starts_with("carol ") && rows[2].contains(" ambient_missing "),
        "{rows:?}"
    );
    assert_eq!(rows[3], "dave 0 6 0 8 0 build_failed dave/index.html");
    assert_eq!(rows[4], "eve 0 6 0 8 0 crash eve/index.html");

    let page = std::fs::read_to_string(report.join("class.html")).unwrap();
    assert!(
        page.contains("<a href=\"./bob/index.html\">bob</a>"),
        "{page}"
    );
    for student in ["alice", "bob", "carol", "dave", "eve"] {
        assert!(report.join(student).join("index.html").is_file());
    }
    // A student cannot read another's submission: eve's renderer said nothing of the others.
    let eve = std::fs::read_to_string(report.join("eve/summary.json")).unwrap();
    assert!(!eve.contains("-fault"), "{eve}");
    // The build's account is in the student's own summary.
    let dave = std::fs::read_to_string(report.join("dave/summary.json")).unwrap();
    assert!(dave.contains("\"ok\": false"), "{dave}");
    assert!(dave.contains("build_failed"), "{dave}");
    // And where a student and a teacher read: the build's own words (make's "Error 1") on
    // dave's page, in the class's table and at the top of every platform's file.
    let make_said = "Error 1";
    let dave_page = std::fs::read_to_string(report.join("dave/index.html")).unwrap();
    assert!(dave_page.contains("The build failed"), "{dave_page}");
    assert!(dave_page.contains(make_said), "{dave_page}");
    assert!(page.contains(make_said), "{page}");
    let tops = python(
        "import json, sys\n\
         import xml.etree.ElementTree as ET\n\
         g = json.load(open(sys.argv[1]))\n\
         p = json.load(open(sys.argv[2]))\n\
         suite = ET.parse(sys.argv[3]).getroot().find('testsuite')\n\
         print(repr(g['output']))\n\
         print(repr(p['message']))\n\
         print(repr(suite.find('system-out').text))",
        &[
            &report.join("dave/gradescope.json"),
            &report.join("dave/prairielearn.json"),
            &report.join("dave/junit.xml"),
        ],
    );
    for top in tops.lines() {
        assert!(
            top.contains("did not build") && top.contains(make_said),
            "a platform's top-level text leaves the build out: {top}"
        );
    }

    // Gradescope's results.json, field by field as its documentation lists them.
    let gradescope = python(
        "import json, sys\n\
         r = json.load(open(sys.argv[1]))\n\
         assert set(r) >= {'score', 'execution_time', 'tests'}, r.keys()\n\
         assert isinstance(r['execution_time'], int)\n\
         for t in r['tests']:\n\
         \x20   assert set(t) >= {'name', 'score', 'max_score', 'status', 'output', 'visibility'}, t\n\
         \x20   assert t['status'] in ('passed', 'failed') and t['visibility'] in ('visible', 'hidden', 'after_due_date', 'after_published')\n\
         \x20   assert 0 <= t['score'] <= t['max_score']\n\
         print(r['score'], sum(t['max_score'] for t in r['tests']), r['tests'][0]['status'], r['tests'][1]['status'])",
        &[&report.join("carol/gradescope.json")],
    );
    assert_eq!(gradescope.trim(), "5.0 8.0 passed failed");
    // Its top-level output opens with the count and then the verdict, what a student reads
    // first; each test says its explanation once.
    let bob = python(
        "import json, sys\n\
         r = json.load(open(sys.argv[1]))\n\
         lines = r['output'].splitlines()\n\
         print(lines[0])\n\
         print(lines[1].split(':')[0], 'pixel_corner' in lines[1])\n\
         for t in r['tests']:\n\
         \x20   first = t['output'].splitlines()[1:]\n\
         \x20   said = [l for l in t['output'].splitlines() if 'planted matches' in l]\n\
         \x20   assert len(said) <= 1, t['output']\n\
         \x20   words = t['output'].split('. ')\n\
         \x20   assert len(words) == len(set(words)), t['output']",
        &[&report.join("bob/gradescope.json")],
    );
    let bob: Vec<&str> = bob.lines().collect();
    assert_eq!(
        bob[0],
        "raycast check: 0 of 6 pictures pass (0 of 8 points)"
    );
    assert_eq!(bob[1], "verdict True");
    // PrairieLearn's external grader results, within its 1 MB, pictures as PNG data URLs.
    let prairielearn = python(
        "import json, sys, base64, os\n\
         assert os.path.getsize(sys.argv[1]) < 1_000_000\n\
         r = json.load(open(sys.argv[1]))\n\
         assert r['gradable'] is True and 0 <= r['score'] <= 1\n\
         images = 0\n\
         for t in r['tests']:\n\
         \x20   assert set(t) >= {'name', 'points', 'max_points', 'message', 'output'}, t\n\
         \x20   for i in t.get('images', []):\n\
         \x20       head, data = i['url'].split(',', 1)\n\
         \x20       assert head == 'data:image/png;base64' and base64.b64decode(data)[:8] == b'\\x89PNG\\r\\n\\x1a\\n'\n\
         \x20       images += 1\n\
         print(round(r['score'], 4), images > 0)",
        &[&report.join("bob/prairielearn.json")],
    );
    assert_eq!(prairielearn.trim(), "0.0 True");
    // JUnit XML, as junitparser reads it.
    let junit = python(
        "import sys\n\
         from junitparser import JUnitXml, Failure, Error\n\
         x = JUnitXml.fromfile(sys.argv[1])\n\
         for suite in x:\n\
         \x20   kinds = [type(r).__name__ for case in suite for r in case.result]\n\
         \x20   print(suite.tests, suite.failures, suite.errors, kinds.count('Failure'), kinds.count('Error'))",
        &[&report.join("dave/junit.xml")],
    );
    assert_eq!(junit.trim(), "6 0 6 0 6");
    // GitHub Classroom's autograding result.
    let classroom = python(
        "import json, sys\n\
         r = json.load(open(sys.argv[1]))\n\
         assert r['version'] == 1\n\
         for t in r['tests']:\n\
         \x20   assert set(t) >= {'name', 'status', 'score', 'message', 'test_code', 'duration'}\n\
         print(r['status'], r['max_score'], [t['status'] for t in r['tests']].count('pass'))",
        &[&report.join("alice/github-classroom.json")],
    );
    assert_eq!(classroom.trim(), "pass 8.0 6");
}

#[test]
fn with_vary_each_student_is_graded_on_scenes_of_their_own_that_a_teacher_can_make_again() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 3);
    let roster = roster(
        dir.path(),
        &[
            ("alice", "correct"),
            ("bob", "correct"),
            ("carol", "ambient_missing"),
        ],
    );
    let report = dir.path().join("report");
    let output = grade_class(&suite, &roster, &report, &["--vary", "11"]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    for row in [
        "alice          4/4",
        "bob            4/4",
        "carol          2/4",
    ] {
        assert!(out.contains(row), "no '{row}' in:\n{out}");
    }
    assert!(out.contains("ambient_missing"), "{out}");
    let summary = |student: &str| -> serde_json::Value {
        serde_json::from_str(
            &std::fs::read_to_string(report.join(student).join("summary.json")).unwrap(),
        )
        .unwrap()
    };
    let scenes = |folder: &Path| -> Vec<(std::ffi::OsString, Vec<u8>)> {
        let mut found: Vec<_> = std::fs::read_dir(folder)
            .unwrap()
            .flatten()
            .map(|e| (e.file_name(), std::fs::read(e.path()).unwrap()))
            .collect();
        found.sort();
        found
    };
    // Each student's seed comes from the class's and their name, and the scenes with it.
    let seed = |student: &str| summary(student)["varied"]["seed"].as_u64().unwrap();
    for student in ["alice", "bob", "carol"] {
        assert_eq!(seed(student), raycast::check::student_seed(11, student));
    }
    let alice = scenes(&report.join("alice/varied"));
    assert!(!alice.is_empty());
    assert_ne!(alice, scenes(&report.join("bob/varied")));
    // The teacher makes alice's scenes again with her seed, for one renderer.
    let again = dir.path().join("again");
    let output = check(&[
        suite.to_str().unwrap(),
        "--renderer",
        common::open_raycast(),
        "--vary",
        &seed("alice").to_string(),
        "--report",
        again.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    assert_eq!(scenes(&again.join("varied")), alice);
}

#[test]
fn a_budget_leaves_a_slow_student_partial_results() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 6);
    let roster = roster(dir.path(), &[("slow", "slow")]);
    let report = dir.path().join("report");
    let output = grade_class(
        &suite,
        &roster,
        &report,
        &["--budget", "1.5", "--jobs", "2"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    let summary = std::fs::read_to_string(report.join("slow/summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let images = summary["images"].as_array().unwrap();
    let statuses: Vec<(String, String)> = images
        .iter()
        .map(|i| {
            (
                i["status"].as_str().unwrap().to_string(),
                i["diagnoses"][0]["code"].as_str().unwrap_or("").to_string(),
            )
        })
        .collect();
    let passed = statuses.iter().filter(|(s, _)| s == "pass").count();
    let over = statuses.iter().filter(|(_, c)| c == "over_budget").count();
    assert!(passed >= 1 && over >= 1, "{statuses:?}");
    // Lines start in the suite's order: once one is over the budget, every later one is.
    let first_over = statuses
        .iter()
        .position(|(_, c)| c == "over_budget")
        .unwrap();
    assert!(
        statuses[first_over..]
            .iter()
            .all(|(_, c)| c == "over_budget"),
        "{statuses:?}"
    );
    // Each says which way the budget ended it, in plain seconds.
    for image in images
        .iter()
        .filter(|i| i["diagnoses"][0]["code"] == "over_budget")
    {
        let why = image["explanation"].as_str().unwrap();
        assert!(
            why.contains("budget of 1.5 s was spent before this line's turn")
                || why.contains("budget of 1.5 s ran out while this line ran"),
            "{why}"
        );
    }
    // The student's seconds are the clock's, not the sum of lines that ran side by side.
    let line_seconds: f64 = images.iter().map(|i| i["seconds"].as_f64().unwrap()).sum();
    let build_seconds = summary["build"]["seconds"].as_f64().unwrap();
    let csv_seconds: f64 = python(
        "import csv, sys\n\
         print(next(csv.DictReader(open(sys.argv[1], newline='')))['seconds'])",
        &[&report.join("class.csv")],
    )
    .trim()
    .parse()
    .unwrap();
    let clock = summary["seconds"].as_f64().unwrap();
    assert!(
        (csv_seconds - (build_seconds + clock)).abs() < 0.01,
        "{csv_seconds} {build_seconds} {clock}"
    );
    assert!(
        clock < line_seconds,
        "two lines ran side by side: {clock} s by the clock, {line_seconds} s added up"
    );
}

#[test]
fn shards_merge_into_the_report_one_run_makes() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 3);
    let roster = roster(
        dir.path(),
        &[
            ("ann", "correct"),
            ("ben", "pixel_corner"),
            ("cat", "channel_swap"),
        ],
    );
    let run = |report: &Path, shard: Option<&str>| {
        let mut args = vec![
            suite.to_str().unwrap(),
            "--class",
            roster.to_str().unwrap(),
            "--renderer",
            "./raytracer.in",
            "--report",
            report.to_str().unwrap(),
        ];
        if let Some(shard) = shard {
            args.extend(["--shard", shard]);
        }
        let output = check(&args);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    };
    for student in ["ann", "ben", "cat"] {
        let script = roster.join(student).join("raytracer.in");
        std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let whole = dir.path().join("whole");
    run(&whole, None);
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    run(&one, Some("1/2"));
    run(&two, Some("2/2"));
    let merged = dir.path().join("merged");
    let output = Command::new(RAYCAST)
        .args(["check", "merge"])
        .args([&merged, &one, &two])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    // The same files, the same contents apart from times.
    assert_same_report(&merged, &whole);
    // One renderer's lines in three shards, merged: the report one run makes.
    let renderer = roster.join("ben/raytracer.in");
    let run_lines = |report: &Path, shard: Option<&str>| {
        let mut args = vec![
            suite.to_str().unwrap(),
            "--renderer",
            renderer.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ];
        if let Some(shard) = shard {
            args.extend(["--shard", shard]);
        }
        check(&args)
    };
    let whole_lines = dir.path().join("whole-lines");
    run_lines(&whole_lines, None);
    let parts: Vec<PathBuf> = (1..=3)
        .map(|k| {
            let part = dir.path().join(format!("lines{k}"));
            run_lines(&part, Some(&format!("{k}/3")));
            part
        })
        .collect();
    let merged_lines = dir.path().join("merged-lines");
    let output = Command::new(RAYCAST)
        .args(["check", "merge"])
        .arg(&merged_lines)
        .args(&parts)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", text(&output));
    assert!(
        text(&output).contains("0 passed, 4 failed"),
        "{}",
        text(&output)
    );
    assert_same_report(&merged_lines, &whole_lines);
    // A shard given twice is refused.
    let output = Command::new(RAYCAST)
        .args(["check", "merge"])
        .args([&dir.path().join("again"), &one, &one])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output).contains("is in two shards"),
        "{}",
        text(&output)
    );
}

/// Asserts that two report folders hold the same files, the same pictures, and the same text
/// apart from times.
fn assert_same_report(merged: &Path, whole: &Path) {
    let without_times = |path: &Path| -> String {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        text.lines()
            .filter(|l| !l.contains("seconds") && !l.contains("duration") && !l.contains("time"))
            .map(|l| {
                // class.csv's seconds column (one assignment: the ninth), class.html's cells.
                if path.extension().is_some_and(|e| e == "csv") {
                    l.split(',').take(8).collect::<Vec<_>>().join(",")
                } else if l.contains("<td class=\"seconds\">") {
                    let mut parts = l.split("<td class=\"seconds\">");
                    let first = parts.next().unwrap_or("").to_string();
                    first
                        + &parts
                            .map(|part| part.split_once("</td>").map_or(part, |(_, rest)| rest))
                            .collect::<String>()
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let files = |root: &Path| -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = walk(root)
            .into_iter()
            .filter(|p| p.is_file())
            .map(|p| p.strip_prefix(root).unwrap().to_path_buf())
            .collect();
        files.sort();
        files
    };
    assert_eq!(files(merged), files(whole));
    for file in files(whole) {
        if file.extension().is_some_and(|e| e == "png") {
            assert_eq!(
                std::fs::read(merged.join(&file)).unwrap(),
                std::fs::read(whole.join(&file)).unwrap(),
                "{}",
                file.display()
            );
        } else {
            assert_eq!(
                without_times(&merged.join(&file)),
                without_times(&whole.join(&file)),
                "{}",
                file.display()
            );
        }
    }
}

#[test]
fn raycasts_own_references_are_made_once_and_kept_for_the_next_run() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // A suite without references: every picture graded against raycast's own render.
    let suite = dir.path().join("suite");
    std::fs::create_dir_all(suite.join("scenes")).unwrap();
    std::fs::copy(
        conformance.join("scenes/scene2_01_diffuse.txt"),
        suite.join("scenes/scene2_01_diffuse.txt"),
    )
    .unwrap();
    std::fs::write(
        suite.join("COMMANDS.txt"),
        "raytracer -input scene2_01_diffuse.txt -size 40 40 -output a.tga\n",
    )
    .unwrap();
    let cache = dir.path().join("cache");
    let run = || {
        let output = Command::new(RAYCAST)
            .args(["check", suite.to_str().unwrap(), "--renderer", RAYCAST])
            .env("RAYCAST_CACHE_DIR", &cache)
            .output()
            .unwrap();
        text(&output)
    };
    assert!(run().contains("pass   a"), "{}", run());
    let kept: Vec<PathBuf> = walk(&cache)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    assert_eq!(kept.len(), 1, "{kept:?}");
    // The next run reads the kept render: blackened, the picture fails against it.
    let black = image::RgbImage::new(40, 40);
    black.save(&kept[0]).unwrap();
    assert!(run().contains("FAIL   a"), "{}", run());
    // A changed scene is another key: rendered anew, it passes again.
    let scene = suite.join("scenes/scene2_01_diffuse.txt");
    let text_of_scene = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text_of_scene + "\n").unwrap();
    assert!(run().contains("pass   a"), "{}", run());
}

/// A platform's layout in a new folder: a two-line suite in `suite_in/suite`, and a
/// submission in `submission_in` whose renderer is raycast itself, as the student's program.
fn platform_layout(conformance: &Path, suite_in: &str, submission_in: &str) -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    let suite_folder = root.path().join(suite_in);
    std::fs::create_dir_all(&suite_folder).unwrap();
    suite(&suite_folder, conformance, 2);
    let submission = root.path().join(submission_in);
    std::fs::create_dir_all(&submission).unwrap();
    std::fs::copy(RAYCAST, submission.join("raytracer")).unwrap();
    open_to_all(root.path());
    std::fs::set_permissions(
        submission.join("raytracer"),
        std::fs::Permissions::from_mode(0o755),
    )
    .unwrap();
    root
}

#[test]
fn the_gradescope_example_grades_a_submission_laid_out_as_gradescope_lays_it_out() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let root = platform_layout(&conformance, "source", "submission");
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/examples/gradescope/run_autograder");
    let output = Command::new("bash")
        .arg(&script)
        .env("AUTOGRADER_ROOT", root.path())
        .env("RAYCAST", RAYCAST)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output));
    let results = root.path().join("results/results.json");
    let summary = python(
        "import json, sys\n\
         r = json.load(open(sys.argv[1]))\n\
         print(r['score'], len(r['tests']), all(t['status'] == 'passed' for t in r['tests']))",
        &[&results],
    );
    // Two pictures: output2_01 worth 3 points (the suite's POINTS), output2_02 one.
    assert_eq!(
        summary.trim(),
        "4.0 2 True",
        "{}",
        std::fs::read_to_string(root.path().join("check.log")).unwrap_or_default()
    );
}

#[test]
fn the_platform_examples_tell_a_submission_that_does_not_build_why() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/examples");
    for (script, root_variable, suite_in, submission_in, said) in [
        (
            "gradescope/run_autograder",
            "AUTOGRADER_ROOT",
            "source",
            "submission",
            "output",
        ),
        (
            "prairielearn/grade.sh",
            "GRADE_ROOT",
            "tests",
            "student",
            "message",
        ),
    ] {
        let root = platform_layout(&conformance, suite_in, submission_in);
        std::fs::write(
            root.path().join(submission_in).join("Makefile"),
            "all:\n\t@echo 'main.cpp:12: error: expected ; before }' >&2; exit 1\n",
        )
        .unwrap();
        let output = Command::new("bash")
            .arg(examples.join(script))
            .env(root_variable, root.path())
            .env("RAYCAST", RAYCAST)
            .output()
            .unwrap();
        assert!(output.status.success(), "{script}: {}", text(&output));
        let results = python(
            "import json, sys\n\
             r = json.load(open(sys.argv[1]))\n\
             print(r['score'], json.dumps(r[sys.argv[2]]))",
            &[&root.path().join("results/results.json"), Path::new(said)],
        );
        assert!(
            results.starts_with("0 \"The build failed")
                && results.contains("main.cpp:12: error: expected ; before }"),
            "{script}: {results}"
        );
    }
}

#[test]
fn class_usage_mistakes_are_one_clear_error() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let suite = conformance.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &[
                "check",
                suite,
                "--class",
                "/no/such/roster",
                "--renderer",
                "./r",
            ],
            "--class /no/such/roster: No such file or directory",
        ),
        (
            &["check", suite, "--renderer", "/bin/true", "--build", "make"],
            "--build builds a class's submissions: give --class DIR too",
        ),
        (
            &["check", suite, "--renderer", "/bin/true", "--shard", "3/2"],
            "--shard needs K/N with 1 <= K <= N (this run's share), found '3/2'",
        ),
        (
            &["check", "merge", "/tmp/raycast-merge-out"],
            "merge needs OUT and the shards' report folders",
        ),
        (
            &["check", "merge", "/tmp/raycast-merge-out", "/no/such/shard"],
            "/no/such/shard: no report of raycast check there",
        ),
    ];
    for (args, said) in cases {
        let output = Command::new(RAYCAST).args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(text(&output).contains(said), "{args:?}: {}", text(&output));
    }
    assert!(!Path::new("/tmp/raycast-merge-out").exists());
}

#[test]
fn the_prairielearn_example_grades_a_submission_laid_out_as_prairielearn_lays_it_out() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let root = platform_layout(&conformance, "tests", "student");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/examples/prairielearn/grade.sh");
    let output = Command::new("bash")
        .arg(&script)
        .env("GRADE_ROOT", root.path())
        .env("RAYCAST", RAYCAST)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output));
    let summary = python(
        "import json, sys\n\
         r = json.load(open(sys.argv[1]))\n\
         print(r['gradable'], r['score'], [t['points'] for t in r['tests']])",
        &[&root.path().join("results/results.json")],
    );
    // Two pictures, both passing: output2_01 worth 3 points (the suite's POINTS), output2_02 one.
    assert_eq!(summary.trim(), "True 1.0 [3.0, 1.0]");
}

#[test]
fn a_renderers_words_that_name_files_of_the_submission_are_found_inside_it() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 1);
    let roster = roster(dir.path(), &[("zoe", "correct")]);
    // `sh raytracer.in`: the interpreter from the PATH, the script inside the submission.
    let output = check(&[
        suite.to_str().unwrap(),
        "--class",
        roster.to_str().unwrap(),
        "--renderer",
        "sh raytracer.in",
    ]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    assert!(out.contains("zoe            1/1          3/3"), "{out}");
}

#[test]
fn hostile_and_broken_submission_names_are_data_and_never_end_the_class() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance, 2);
    let formula = "=HYPERLINK(\"example.invalid\";\"x\")";
    let names = [
        formula,
        "javascript:alert(1)",
        "class.csv",
        "eve\nmallory,9,9",
        "\u{1b}[2Kzed",
    ];
    let students: Vec<(&str, &str)> = names.iter().map(|n| (*n, "correct")).collect();
    let roster = roster(dir.path(), &students);
    // A name that is not UTF-8, a link to a folder, a plain file: each a row of its own.
    {
        use std::os::unix::ffi::OsStrExt;
        let odd = roster.join(std::ffi::OsStr::from_bytes(b"odd\xffname"));
        std::fs::rename(roster.join("javascript:alert(1)"), &odd).unwrap();
        std::fs::create_dir_all(roster.join("javascript:alert(1)")).unwrap();
        copy_dir(&odd, &roster.join("javascript:alert(1)"));
    }
    std::os::unix::fs::symlink(roster.join("class.csv"), roster.join("linked")).unwrap();
    std::fs::write(roster.join("notes.txt"), "not a submission\n").unwrap();
    open_to_all(dir.path());
    let report = dir.path().join("report");
    let output = grade_class(&suite, &roster, &report, &[]);
    let out = text(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    // The terminal shows every name, escaped, one row each: no escape reaches it raw.
    assert!(!out.contains('\u{1b}'), "{out:?}");
    assert!(out.contains("\\x1b[2Kzed"), "{out}");
    assert!(out.contains("eve\\nmallory,9,9"), "{out}");
    assert!(out.contains("odd\u{fffd}name"), "{out}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("linked") && l.contains("not graded: a symbolic link")),
        "{out}"
    );
    assert!(
        out.lines()
            .any(|l| l.starts_with("notes.txt") && l.contains("not graded: not a folder")),
        "{out}"
    );
    assert!(!report.join("notes.txt").exists() && !report.join("linked").exists());
    // class.csv: one row a student, no cell a formula, the class's own file intact.
    let rows = python(
        "import csv, sys\n\
         for r in csv.DictReader(open(sys.argv[1], newline='')):\n\
         \x20   print('|'.join([r['student'], r['passed'], r['pictures'], r['build'], r['report']]))",
        &[&report.join("class.csv")],
    );
    let rows: Vec<&str> = rows.lines().collect();
    assert_eq!(rows.len(), 8, "{rows:#?}");
    for row in &rows {
        assert!(!row.starts_with(['=', '+', '-', '@']), "{row}");
    }
    assert!(
        rows.iter()
            .any(|r| r.starts_with("'=HYPERLINK(") && r.contains("|2|2|built|")),
        "{rows:#?}"
    );
    assert!(
        rows.iter().any(|r| r.starts_with("class.csv|2|2|")
            && r.ends_with("student-class.csv/index.html")),
        "{rows:#?}"
    );
    assert!(
        rows.contains(
            &"notes.txt|0|2|not graded: not a folder: a submission is a folder of the roster|"
        ),
        "{rows:#?}"
    );
    assert!(
        report.join("student-class.csv/index.html").is_file(),
        "the student named class.csv has their own report"
    );
    assert!(
        std::fs::read_to_string(report.join("class.csv"))
            .unwrap()
            .starts_with("student,")
    );
    // class.html links each student to their own report, by a relative path, never a scheme.
    let page = std::fs::read_to_string(report.join("class.html")).unwrap();
    let hrefs: Vec<&str> = page
        .split("href=\"")
        .skip(1)
        .map(|rest| rest.split('"').next().unwrap())
        .collect();
    // The two not graded have no report to link to.
    assert_eq!(hrefs.len(), 6, "{hrefs:?}");
    for href in &hrefs {
        assert!(
            href.starts_with("./") && href.ends_with("/index.html") && !href[2..].contains(':'),
            "{href}"
        );
    }
    assert!(hrefs.contains(&"./javascript%3Aalert%281%29/index.html"));
    assert!(!page.contains('\u{1b}'));
}

/// Copies a folder of plain files and folders.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}
