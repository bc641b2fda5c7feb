//! `raycast check` and `raycast diff` as a student meets them: a clean run over the course's 44
//! images passes; renderers that crash, hang, write nothing or write garbage fail image by image
//! and never fail the check itself; faults planted in raycast's own images, the way a student's
//! code would make them, get their diagnosis; the report holds what it says, and works in a
//! real browser.

// The renderers these tests grade are shell scripts and the cage they test is Unix's; on Windows
// check is run by CI's Wine job (.ci/windows), over raycast.exe itself.
#![cfg(unix)]

mod common;

use common::data_dir;
use std::io::Write as _;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn conformance_dir() -> Option<PathBuf> {
    data_dir(
        "the check tests on the course's images",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

fn raycast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(args)
        .args(renderers_may_run_raycast(args))
        .output()
        .unwrap()
}

/// The test renderers are scripts that end by running raycast: for `check`, its folder is made
/// readable to them (the cage lets a renderer read only its own folder and the system's).
fn renderers_may_run_raycast(args: &[&str]) -> Vec<String> {
    let raycast = Path::new(common::open_raycast());
    if args.first() == Some(&"check") && args.contains(&"--renderer") {
        vec![
            "--allow-read".into(),
            raycast.parent().unwrap().display().to_string(),
        ]
    } else {
        Vec::new()
    }
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// A renderer: a bash script in `dir`, made executable.
fn script(dir: &Path, name: &str, body: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, format!("#!/usr/bin/env bash\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_str().unwrap().to_string()
}

/// A small suite: the first `lines` command lines of the course's assignments 1 and 2.
fn small_suite(dir: &Path, conformance: &Path, lines: usize) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    let commands: Vec<String> = std::fs::read_to_string(conformance.join("COMMANDS.txt"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("raytracer "))
        .take(lines)
        .map(String::from)
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), commands.join("\n") + "\n").unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    std::os::unix::fs::symlink(conformance.join("reference"), suite.join("reference")).unwrap();
    suite
}

#[test]
fn a_clean_run_over_the_courses_images_passes() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let output = raycast(&[
        "check",
        conformance.to_str().unwrap(),
        "--renderer",
        common::open_raycast(),
    ]);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    assert!(out.ends_with("44 passed, 0 failed\n"), "{out}");
    assert_eq!(out.lines().filter(|l| l.starts_with("pass ")).count(), 44);
}

#[test]
fn broken_renderers_fail_their_images_not_the_check() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = small_suite(dir.path(), &conformance, 3);
    let suite = suite.to_str().unwrap();
    let cases = [
        (
            "crash.sh",
            "echo 'segmentation fault' >&2; exit 3",
            "crash",
            "exited with status 3",
        ),
        (
            "nothing.sh",
            "exit 0",
            "missing_output",
            "The renderer ended without writing the picture of -normals normals2_03.tga. \
             Check that the file name after -normals is taken from the command line",
        ),
        // An assignment-2 tracer that does not know a keyword says so and writes nothing: its
        // own words are the reason, not the file name.
        (
            "unknown.sh",
            "echo 'Unknown token PhongMaterial' >&2; exit 0",
            "missing_output",
            "The renderer ended without writing the picture of -output output2_01.tga. It \
             said: Unknown token PhongMaterial Its own message is the likely reason",
        ),
        // What it says of its scratch paths (gone once check ends) is said as the command
        // line names them.
        (
            "scratch.sh",
            "for a in \"$@\"; do case $a in */out/*) echo \"cannot write $a\" >&2;; esac; done; exit 4",
            "crash",
            "It said: cannot write output2_01.tga",
        ),
        (
            "hang.sh",
            "sleep 30",
            "timed_out",
            "did not finish within 0.5 s",
        ),
        (
            "garbage.sh",
            "while [ $# -gt 0 ]; do case $1 in -output|-normals|-depth) echo hello > \"$2\";; esac; shift; done",
            "unreadable_output",
            "not a readable image",
        ),
    ];
    // A process of the test's own, outside the renderer's group: stopping a hung renderer must
    // not touch it (an earlier `kill -KILL -PID` was read by procps as a signal to every process).
    let mut bystander = Command::new("sleep").arg("60").spawn().unwrap();
    for (name, body, code, said) in cases {
        let renderer = script(dir.path(), name, body);
        let started = std::time::Instant::now();
        let output = raycast(&["check", suite, "--renderer", &renderer, "--timeout", "0.5"]);
        let out = stdout(&output);
        assert_eq!(
            output.status.code(),
            Some(1),
            "{name}: {out}{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let verdicts: Vec<&str> = out.lines().filter(|l| l.starts_with("ERROR")).collect();
        assert!(!verdicts.is_empty(), "{name}: {out}");
        for line in &verdicts {
            assert!(line.contains(&format!(": {code}: ")), "{name}: {line}");
        }
        assert!(out.contains(said), "{name}: {out}");
        assert!(!out.contains("/out/"), "{name} shows a scratch path: {out}");
        if name == "unknown.sh" {
            assert!(!out.contains("taken from the command line"), "{out}");
        }
        // Three lines of the course, four images.
        assert_eq!(out.lines().last().unwrap(), "0 passed, 4 failed", "{name}");
        // A hang costs its time limit, not the renderer's half minute.
        assert!(
            started.elapsed().as_secs() < 20,
            "{name} took {:?}",
            started.elapsed()
        );
    }
    assert!(
        bystander.try_wait().unwrap().is_none(),
        "the time-out killed a bystander"
    );
    let _ = bystander.kill();
    let _ = bystander.wait();
    // The suite is never written into.
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("suite"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["COMMANDS.txt", "reference", "scenes"]);
}

#[test]
fn usage_and_suite_errors_exit_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let output = raycast(&["check", dir.path().to_str().unwrap(), "--renderer", "true"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("COMMANDS.txt: cannot read"));
    let output = raycast(&["check", dir.path().to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    let output = raycast(&["check", "x", "--renderer", "true", "--jobs", "0"]);
    assert_eq!(output.status.code(), Some(2));
    let output = raycast(&["diff", "only-one.png"]);
    assert_eq!(output.status.code(), Some(2));
}

/// Renders a course line with raycast (extra words added), returns the image.
fn render(conformance: &Path, line: &str, extra: &[&str], dir: &Path) -> image::RgbImage {
    let out = dir.join("render.png");
    let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
    let at = args.iter().position(|a| a == "-output").unwrap();
    args[at + 1] = out.to_str().unwrap().into();
    args.extend(extra.iter().map(|s| s.to_string()));
    let status = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(&args)
        .current_dir(conformance.join("scenes"))
        .status()
        .unwrap();
    assert!(status.success());
    image::open(&out).unwrap().to_rgb8()
}

/// `raycast diff` of two images: its verdict line.
fn diff(dir: &Path, actual: &image::RgbImage, reference: &image::RgbImage) -> String {
    let (a, r) = (dir.join("a.png"), dir.join("r.png"));
    actual.save(&a).unwrap();
    reference.save(&r).unwrap();
    stdout(&raycast(&[
        "diff",
        a.to_str().unwrap(),
        r.to_str().unwrap(),
    ]))
}

#[test]
fn planted_faults_get_their_diagnosis() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let line = "raytracer -input scene2_06_plane.txt -size 200 200 -output output2_06.tga";
    let reference = render(&conformance, line, &[], d);
    let planted = |actual: image::RgbImage| diff(d, &actual, &reference);
    let codes = |verdict: &str| -> Vec<String> {
        // "FAIL: 12.3% of pixels off by more than 2 levels: code, code: explanation"
        verdict
            .split(": ")
            .nth(2)
            .unwrap_or("")
            .split(", ")
            .map(String::from)
            .collect()
    };
    assert!(planted(reference.clone()).starts_with("pass"));
    let flipped = image::imageops::flip_vertical(&reference);
    assert_eq!(codes(&planted(flipped)), ["flip_vertical"]);
    let mirrored = image::imageops::flip_horizontal(&reference);
    assert_eq!(codes(&planted(mirrored)), ["flip_horizontal"]);
    let mut swapped = reference.clone();
    for p in swapped.pixels_mut() {
        p.0.swap(0, 2);
    }
    assert_eq!(codes(&planted(swapped)), ["channel_swap"]);
    let mut dim = reference.clone();
    for p in dim.pixels_mut() {
        p.0 = p.0.map(|c| (f32::from(c) * 0.6) as u8);
    }
    assert!(codes(&planted(dim)).contains(&"colour_scale".to_string()));
    let mut shifted = reference.clone();
    for y in 0..200 {
        for x in 0..200 {
            *shifted.get_pixel_mut(x, y) = *reference.get_pixel(x.saturating_sub(2), y);
        }
    }
    assert_eq!(codes(&planted(shifted)), ["shift"]);
    // Back faces black: the course's scene2_05 (inside a sphere) without -shade_back.
    let inside =
        "raytracer -input scene2_05_inside_sphere.txt -size 200 200 -output output2_05.tga";
    let shaded = render(&conformance, inside, &["-shade_back"], d);
    let black = render(&conformance, inside, &[], d);
    assert!(codes(&diff(d, &black, &shaded)).contains(&"back_faces".to_string()));
}

#[test]
fn the_report_holds_what_it_says_and_works_in_a_browser() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = small_suite(dir.path(), &conformance, 4);
    // raycast itself, except that it crashes on scene2_02.
    let raycast_bin = common::open_raycast();
    let renderer = script(
        dir.path(),
        "mostly_raycast.sh",
        &format!("if [[ \"$*\" == *scene2_02* ]]; then exit 1; fi\nexec {raycast_bin} \"$@\""),
    );
    let report = dir.path().join("report");
    let output = raycast(&[
        "check",
        suite.to_str().unwrap(),
        "--renderer",
        &renderer,
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", stdout(&output));
    let summary: serde_json::Value = common::summary_of(&report);
    assert_eq!(summary["passed"], 5);
    assert_eq!(summary["failed"], 1);
    let images = summary["images"].as_array().unwrap();
    assert_eq!(images.len(), 6);
    for image in images {
        assert!(
            image["command"]
                .as_str()
                .unwrap()
                .starts_with("raytracer -input")
        );
        if image["name"] == "output2_02" {
            assert_eq!(image["status"], "error");
            assert_eq!(image["diagnoses"][0]["code"], "crash");
            assert_eq!(image["diagnoses"][0]["kind"], "run");
            assert!(
                image["explanation"]
                    .as_str()
                    .unwrap()
                    .contains("exited with status 1")
            );
        } else {
            assert_eq!(image["status"], "pass");
            assert!(image["bad_fraction"].as_f64().unwrap() <= 0.001);
        }
    }
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(page.contains("5 passed, 1 failed"));
    // Failures first.
    assert!(page.find("output2_02").unwrap() < page.find("output2_01").unwrap());
    browser_self_test(&report);
}

/// Opens the report in headless Chromium with `?selftest`: every picture must load, the wipe
/// must move and no script may fail. Chromium is required in CI (`.ci/run` installs it).
fn browser_self_test(report: &Path) {
    let browser = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|b| {
            Command::new(b)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        });
    let Some(browser) = browser else {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI needs Chromium for the report test"
        );
        let _ = writeln!(
            std::io::stderr(),
            "skipped: the report's browser test (no Chromium; apt-get install chromium)"
        );
        return;
    };
    let url = format!("file://{}?selftest", report.join("index.html").display());
    // A profile of its own (two browsers sharing one wait on each other's lock), and a time
    // limit: a browser that hangs fails the test instead of stalling the whole run.
    let profile = tempfile::tempdir().unwrap();
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-dev-shm-usage",
            "--allow-file-access-from-files",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(["--dump-dom", &url])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Read as it comes, so that a long page never fills the pipe and stalls the browser.
    let read = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let out = read(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
    );
    let err = read(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
    );
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > std::time::Duration::from_secs(90) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{browser} did not finish the report's self-test within 90 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let output = std::process::Output {
        status: child.wait().unwrap(),
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    };
    let dom = String::from_utf8_lossy(&output.stdout);
    let result = dom
        .split("<pre id=\"selftest\"")
        .nth(1)
        .and_then(|rest| rest.split_once('>'))
        .map(|(_, rest)| rest.split("</pre>").next().unwrap_or(""))
        .unwrap_or("(no self-test result)");
    assert!(
        result.starts_with("ok ("),
        "the report's self-test in {browser}: {result}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let _ = writeln!(std::io::stderr(), "report in {browser}: {result}");
}

/// A one-line suite of the course's line `line`, in `dir`.
fn one_line_suite(dir: &Path, conformance: &Path, line: &str) -> PathBuf {
    let suite = dir.join("one");
    std::fs::create_dir_all(&suite).unwrap();
    std::fs::write(suite.join("COMMANDS.txt"), format!("{line}\n")).unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    std::os::unix::fs::symlink(conformance.join("reference"), suite.join("reference")).unwrap();
    suite
}

#[test]
fn faults_a_students_renderer_makes_get_their_diagnosis() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let raycast_bin = common::open_raycast();
    let shared = tempfile::tempdir().unwrap();
    let squashed = shared.path().join("squashed.txt");
    let scene = std::fs::read_to_string(conformance.join("scenes/scene2_16_t_scale.txt")).unwrap();
    std::fs::write(&squashed, object_space_t(&scene)).unwrap();
    let object_space = format!(
        "exec RAYCAST -input {} \"${{@:3}}\"",
        squashed.to_str().unwrap()
    );
    // A student's picture fixed up after the render, as a script of its own: raycast renders
    // the line to a PPM, then Python rewrites its pixels and writes the TGA the line asks for
    // (uncompressed, its rows from the bottom, each pixel blue, green, red).
    let rewritten = |change: &str| {
        format!(
            "RAYCAST -input \"$2\" -size $4 $5 -output picture.ppm || exit 1\n\
             python3 - picture.ppm \"$7\" <<'PY'\n\
             import sys\n\
             data = open(sys.argv[1], 'rb').read()\n\
             _, width, height, _ = data.split(maxsplit=3)\n\
             w, h = int(width), int(height)\n\
             pixels = data[-w * h * 3:]\n\
             rows = [bytearray(pixels[k * w * 3:(k + 1) * w * 3]) for k in range(h)]\n\
             {change}\n\
             header = bytes([0, 0, 2] + [0] * 9) + w.to_bytes(2, 'little') + h.to_bytes(2, 'little') + bytes([24, 0])\n\
             bgr = [bytes(row[k + 2 - c] for k in range(0, len(row), 3) for c in range(3)) for row in reversed(rows)]\n\
             open(sys.argv[2], 'wb').write(header + b''.join(bgr))\n\
             PY"
        )
    };
    let flipped = rewritten("rows.reverse()");
    let swapped = rewritten("for row in rows:\n    row[0::3], row[2::3] = row[2::3], row[0::3]");
    // (the renderer's fault, as a script around raycast; the course line; the code expected)
    let cases = [
        (
            // Rays through pixel corners instead of centres: the orthographic camera moved by
            // half a pixel (size 5 over 200 pixels) down and to the left.
            "sed 's/center 0 0 10/center -0.0125 -0.0125 10/' scene2_01_diffuse.txt > moved.txt\n\
             exec RAYCAST -input moved.txt \"${@:3}\"",
            "raytracer -input scene2_01_diffuse.txt -size 200 200 -output output2_01.tga",
            "pixel_corner",
        ),
        (
            // Triangles dropped while reading the mesh: every fifth face.
            "awk '/^f/{n++; if (n % 5 == 0) next} {print}' bunny_200.obj > dropped.obj\n\
             rm bunny_200.obj && mv dropped.obj bunny_200.obj\nexec RAYCAST \"$@\"",
            "raytracer -input scene2_09_bunny_200.txt -size 200 200 -output output2_09.tga",
            "missing_object",
        ),
        (
            // Back faces left black: -shade_back ignored.
            "args=(); for a in \"$@\"; do [ \"$a\" = -shade_back ] || args+=(\"$a\"); done\n\
             exec RAYCAST \"${args[@]}\"",
            "raytracer -input scene2_05_inside_sphere.txt -size 200 200 -output output2_05.tga -shade_back",
            "shade_back_ignored",
        ),
        (
            // t measured in object space under a scaling Transform (see `object_space_t`).
            object_space.as_str(),
            "raytracer -input scene2_16_t_scale.txt -size 200 200 -output output2_16.tga -depth 2 7 depth2_16.tga",
            "object_space_t",
        ),
        (
            // The ambient term left out: as if the scene had none.
            "sed -E 's/ambientLight [0-9. ]+/ambientLight 0 0 0 /' scene2_02_ambient.txt > dark.txt\n\
             exec RAYCAST -input dark.txt \"${@:3}\"",
            "raytracer -input scene2_02_ambient.txt -size 200 200 -output output2_02.tga",
            "ambient_missing",
        ),
        (
            // The ambient term added in the loop over the scene's three lights: three times over.
            "sed -E 's/ambientLight 0.2 0.2 0.2/ambientLight 0.6 0.6 0.6/' scene2_03_colored_lights.txt > bright.txt\n\
             exec RAYCAST -input bright.txt \"${@:3}\"",
            "raytracer -input scene2_03_colored_lights.txt -size 200 200 -output output2_03.tga",
            "ambient_per_light",
        ),
        (
            // tan(angle) where tan(angle / 2) is meant: the view twice as wide.
            "sed 's/angle 30/angle 60/' scene2_04_perspective.txt > wide.txt\n\
             exec RAYCAST -input wide.txt \"${@:3}\"",
            "raytracer -input scene2_04_perspective.txt -size 200 200 -output output2_04.tga",
            "field_of_view",
        ),
        (
            // Pixels spread over width - 1: i / 199 across the view, as if it were 200/199 as
            // wide.
            "sed 's/size 5/size 5.025125628/' scene2_01_diffuse.txt > spread.txt\n\
             exec RAYCAST -input spread.txt \"${@:3}\"",
            "raytracer -input scene2_01_diffuse.txt -size 200 200 -output output2_01.tga",
            "pixel_span_minus_one",
        ),
        (
            // Rows written bottom first.
            flipped.as_str(),
            "raytracer -input scene2_07_sphere_triangles.txt -size 200 200 -output output2_07.tga",
            "flip_vertical",
        ),
        (
            // Red and blue written in each other's place.
            swapped.as_str(),
            "raytracer -input scene2_03_colored_lights.txt -size 200 200 -output output2_03.tga",
            "channel_swap",
        ),
        (
            // Back faces shaded whether -shade_back is given or not.
            "exec RAYCAST \"$@\" -shade_back",
            "raytracer -input scene2_05_inside_sphere.txt -size 200 200 -output output2_05_no_back.tga",
            "back_faces_lit",
        ),
    ];
    for (k, (body, line, code)) in cases.into_iter().enumerate() {
        let dir = tempfile::tempdir().unwrap();
        let suite = one_line_suite(dir.path(), &conformance, line);
        let renderer = script(
            dir.path(),
            &format!("r{k}.sh"),
            &body.replace("RAYCAST", raycast_bin),
        );
        // The squashed scene lies outside the renderer's folder: read by leave.
        let output = raycast(&[
            "check",
            suite.to_str().unwrap(),
            "--renderer",
            &renderer,
            "--allow-read",
            shared.path().to_str().unwrap(),
        ]);
        let out = stdout(&output);
        assert_eq!(output.status.code(), Some(1), "{line}: {out}");
        // The line's last picture carries the fault (its depth picture, where it has one).
        let verdict = out
            .lines()
            .rfind(|l| l.starts_with("FAIL"))
            .unwrap_or_else(|| panic!("{line}: no picture fails: {out}"));
        println!("{verdict}");
        assert!(
            verdict.contains(&format!(": {code}")) || verdict.contains(&format!(", {code}")),
            "{line}: {verdict}"
        );
    }
}

/// The course's scene2_16 as a renderer that measures t in object space draws its depth: a hit
/// under `Scale s` reports its t divided by s (the object ray's direction, 1/s long, normalized),
/// and hits are compared by those t. Under the scene's orthographic camera at z = 5 looking down
/// -z, that is what squashing each scaled object along z draws: z' = 5 - 5/s + z/s makes
/// t' = 5 - z' = t/s, over the same pixels. (The shaded picture differs besides, through the
/// squashed normals; the depth picture is exact.)
fn object_space_t(scene: &str) -> String {
    let mut out = String::new();
    let mut block: Vec<&str> = Vec::new();
    let mut depth = 0;
    for line in scene.lines() {
        if block.is_empty() && line.trim() != "Transform {" {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        block.push(line);
        depth += line.matches('{').count() as i32 - line.matches('}').count() as i32;
        if depth > 0 {
            continue;
        }
        let scale: f64 = block
            .iter()
            .find_map(|l| l.trim().strip_prefix("Scale"))
            .and_then(|rest| rest.split_whitespace().next())
            .unwrap()
            .parse()
            .unwrap();
        out.push_str(&format!(
            "Transform {{\nTranslate 0 0 {}\nScale 1 1 {}\n",
            5.0 - 5.0 / scale,
            1.0 / scale
        ));
        for l in block.drain(..) {
            out.push_str(l);
            out.push('\n');
        }
        out.push_str("}\n");
    }
    out
}

#[test]
fn a_suite_without_references_is_graded_against_raycasts_own_renders() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = dir.path().join("later");
    std::fs::create_dir_all(&suite).unwrap();
    std::fs::write(
        suite.join("COMMANDS.txt"),
        "raytracer -input scene2_06_plane.txt -size 64 64 -output a.tga -shade_back\n",
    )
    .unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    let suite = suite.to_str().unwrap();
    let report = dir.path().join("report");
    let output = raycast(&[
        "check",
        suite,
        "--renderer",
        common::open_raycast(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert!(
        stdout(&output).starts_with(
            "pass   a, 0.000% of pixels off against raycast's render\n1 passed, 0 failed\n"
        ),
        "{}",
        stdout(&output)
    );
    // The page says so too, beside the picture and under the reference.
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        page.contains("the reference is raycast's own render of it")
            && page.contains("<figcaption>reference: raycast's render</figcaption>"),
        "{page}"
    );
    // A renderer that ignores -size fails against raycast's render of the line.
    let renderer = script(
        dir.path(),
        "fixed_size.sh",
        &format!(
            "exec {} -input \"$2\" -size 32 32 \"${{@:6}}\"",
            common::open_raycast()
        ),
    );
    let output = raycast(&["check", suite, "--renderer", &renderer]);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(1), "{out}");
    assert!(
        out.lines().any(|l| l.starts_with("FAIL   a: size: ")),
        "{out}"
    );
}

#[test]
fn a_renderer_that_cannot_run_is_one_error_before_any_line() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = small_suite(dir.path(), &conformance, 3);
    let suite = suite.to_str().unwrap();
    let refused = |renderer: &str| {
        let output = raycast(&["check", suite, "--renderer", renderer]);
        assert_eq!(output.status.code(), Some(2), "{renderer}");
        assert!(output.stdout.is_empty(), "nothing ran for {renderer}");
        String::from_utf8_lossy(&output.stderr).trim().to_string()
    };
    let missing = dir.path().join("missing.sh");
    assert_eq!(
        refused(missing.to_str().unwrap()),
        format!(
            "raycast: check: --renderer: '{}' cannot be run: No such file or directory (os error 2)",
            missing.display()
        )
    );
    assert_eq!(
        refused("no-such-tracer-anywhere --fast"),
        "raycast: check: --renderer: 'no-such-tracer-anywhere' is not a program on PATH (give \
         its path, such as ./no-such-tracer-anywhere)"
    );
    let plain = dir.path().join("plain.py");
    std::fs::write(&plain, "print('hi')\n").unwrap();
    assert_eq!(
        refused(plain.to_str().unwrap()),
        format!(
            "raycast: check: --renderer: '{0}' is not executable (chmod +x it, or name its \
             interpreter: --renderer \"python3 {0}\")",
            plain.display()
        )
    );
    // A command that does not split: a usage error, said first.
    assert_eq!(
        refused("'unbalanced").lines().next().unwrap(),
        "raycast: --renderer: unbalanced quotes or a trailing backslash in ''unbalanced'"
    );
}

#[test]
fn renderer_words_split_as_a_shell_splits_them_and_preview_options_are_left_out() {
    let Some(later) = common::later_dir("check's suite of preview lines") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // A renderer in a folder with a space, given with an argument of its own, that dies as a
    // student's tracer does where there is no display when asked for the OpenGL preview.
    let folder = dir.path().join("my tracer");
    std::fs::create_dir_all(&folder).unwrap();
    let renderer = script(
        &folder,
        "render.sh",
        &format!(
            "[ \"$1\" = 'with space' ] || exit 3; shift
             for a in \"$@\"; do case $a in -gui|-tessellation|-gouraud) echo 'cannot open display' >&2; exit 1;; esac; done
             exec {} \"$@\"",
            common::open_raycast()
        ),
    );
    let suite = dir.path().join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    std::fs::write(
        suite.join("COMMANDS.txt"),
        "raytracer -input scene3_08_sphere.txt -size 40 40 -output a.tga -gui -tessellation 10 5 -gouraud\n\
         raytracer -input scene3_01_cube_orthographic.txt -size 40 40 -output b.tga\n",
    )
    .unwrap();
    std::os::unix::fs::symlink(later.join("scenes"), suite.join("scenes")).unwrap();
    let suite = suite.to_str().unwrap();
    let command = format!("'{renderer}' with\\ space");
    let output = raycast(&["check", suite, "--renderer", &command]);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(
        String::from_utf8_lossy(&output.stderr),
        "raycast: check: -gui, -tessellation and -gouraud were left out of 1 line: they only \
         drive the course's OpenGL preview, and the image is the same (--keep-preview-options \
         passes them on)\n"
    );
    let output = raycast(&[
        "check",
        suite,
        "--renderer",
        &command,
        "--keep-preview-options",
    ]);
    assert_eq!(output.status.code(), Some(1));
    let out = stdout(&output);
    assert!(out.contains("ERROR  a: crash"), "{out}");
    assert!(out.contains("cannot open display"), "{out}");
    assert!(output.stderr.is_empty());
}

#[test]
fn jobs_take_lines_one_at_a_time() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = dir.path().join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    // Twenty slow lines, then twenty quick ones. Two workers that each took a fixed half would run
    // the slow lines one after another; handed out one at a time, they run two at once.
    let lines: Vec<String> = (0..40)
        .map(|k| {
            let name = if k < 20 {
                format!("slow{k}")
            } else {
                format!("quick{k}")
            };
            format!("raytracer -input scene2_06_plane.txt -size 8 8 -output {name}.tga")
        })
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    let report = dir.path().join("report");
    let renderer = script(
        dir.path(),
        "timed.sh",
        &format!(
            "name=$(basename \"$7\" .tga)
             echo \"start $name $(date +%s%N)\" >&2
             case $name in slow*) sleep 0.2;; esac
             echo \"end $name $(date +%s%N)\" >&2
             exec {raycast} \"$@\"",
            raycast = common::open_raycast()
        ),
    );
    let output = raycast(&[
        "check",
        suite.to_str().unwrap(),
        "--renderer",
        &renderer,
        "--jobs",
        "2",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    // The renderer's log, from what it said on stderr (the cage lets it write nothing else).
    let summary: serde_json::Value = common::summary_of(&report);
    let text: String = summary["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|image| format!("{}\n", image["stderr"].as_str().unwrap()))
        .collect();
    let time = |event: &str, name: &str| -> u128 {
        text.lines()
            .find_map(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                (w.len() == 3 && w[0] == event && w[1] == name).then(|| w[2].parse().unwrap())
            })
            .unwrap_or_else(|| panic!("no {event} of {name} in the log:\n{text}"))
    };
    let slow: Vec<(u128, u128)> = (0..20)
        .map(|k| {
            (
                time("start", &format!("slow{k}")),
                time("end", &format!("slow{k}")),
            )
        })
        .collect();
    let overlapping = (0..20)
        .flat_map(|a| (a + 1..20).map(move |b| (a, b)))
        .filter(|&(a, b)| slow[a].0 < slow[b].1 && slow[b].0 < slow[a].1)
        .count();
    assert!(
        overlapping >= 2,
        "slow lines ran two at once {overlapping} times:\n{text}"
    );
}

#[test]
fn the_report_shows_raycasts_ray_tree_where_a_picture_differs_most() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let line = "raytracer -input scene2_04_perspective.txt -size 200 200 -output output2_04.tga";
    let suite = one_line_suite(dir.path(), &conformance, line);
    let renderer = script(
        dir.path(),
        "flipped.sh",
        &format!(
            "exec {} \"$@\" -fault flip_horizontal",
            common::open_raycast()
        ),
    );
    let report = dir.path().join("report");
    let output = raycast(&[
        "check",
        suite.to_str().unwrap(),
        "--renderer",
        &renderer,
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", stdout(&output));
    let summary: serde_json::Value = common::summary_of(&report);
    let worst = &summary["images"][0]["worst_pixel"];
    let (x, y) = (worst["x"].as_u64().unwrap(), worst["y"].as_u64().unwrap());
    // What `raycast -inspect X Y` prints for the line, word for word.
    let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
    args.extend(["-inspect".into(), x.to_string(), y.to_string()]);
    let at = args.iter().position(|a| a == "-output").unwrap();
    args[at + 1] = dir.path().join("own.tga").to_str().unwrap().into();
    let inspect = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(&args)
        .current_dir(conformance.join("scenes"))
        .output()
        .unwrap();
    assert_eq!(
        worst["ray_tree"].as_str().unwrap(),
        stdout(&inspect).trim_end()
    );
    assert!(worst["difference"].as_u64().unwrap() > 2);
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(page.contains(&format!("what raycast traced at pixel ({x}, {y})")));
}

/// A suite of one line of the course's assignment 2 with a writable copy of its reference.
fn suite_with_own_reference(dir: &Path, conformance: &Path) -> PathBuf {
    let suite = dir.join("own");
    std::fs::create_dir_all(suite.join("reference")).unwrap();
    std::fs::write(
        suite.join("COMMANDS.txt"),
        "raytracer -input scene2_01_diffuse.txt -size 200 200 -output output2_01.tga\n",
    )
    .unwrap();
    std::fs::copy(
        conformance.join("reference/output2_01.png"),
        suite.join("reference/output2_01.png"),
    )
    .unwrap();
    std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
    suite
}

/// `raycast check SUITE --renderer R --timeout 10`, which must end within 20 s.
fn check_within(suite: &Path, renderer: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["check", suite.to_str().unwrap(), "--renderer", renderer])
        .args(["--timeout", "10"])
        .args(renderers_may_run_raycast(&["check", "--renderer"]))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > std::time::Duration::from_secs(20) {
            let _ = child.kill();
            panic!("check still running after 20 s with {renderer}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn a_hostile_renderer_cannot_forge_its_grade_or_hang_the_check() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite_with_own_reference(dir.path(), &conformance);
    let reference = suite.join("reference/output2_01.png");
    // Its output a link to the reference: not read through the link.
    let linker = script(
        dir.path(),
        "linker.sh",
        &format!("ln -s '{}' \"$7\"", reference.display()),
    );
    let output = check_within(&suite, &linker);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(1), "{out}");
    assert!(
        out.contains("ERROR  output2_01: unreadable_output: The image is a symbolic link"),
        "{out}"
    );
    // Its output a FIFO: refused at once, not waited on.
    let fifo = script(dir.path(), "fifo.sh", "mkfifo \"$7\"");
    let output = check_within(&suite, &fifo);
    let out = stdout(&output);
    assert!(out.contains("The image is not a plain file"), "{out}");
    // It blackens the suite's reference, then writes black: the reference was read before it
    // ran, so black fails.
    let black_scene = dir.path().join("black.txt");
    std::fs::write(
        &black_scene,
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 1 }
         Background { color 0 0 0 ambientLight 0 0 0 }
         Group { numObjects 0 }",
    )
    .unwrap();
    let blackener = script(
        dir.path(),
        "blackener.sh",
        &format!(
            "{raycast} -input '{black}' -size 200 200 -output '{reference}'
             exec {raycast} -input '{black}' -size 200 200 -output \"$7\"",
            raycast = common::open_raycast(),
            black = black_scene.display(),
            reference = reference.display()
        ),
    );
    let before = std::fs::read(&reference).unwrap();
    let output = check_within(&suite, &blackener);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(1), "{out}");
    // The cage keeps it from writing the suite (Landlock, or another user); where neither is
    // to be had, the suite's fingerprint voids the run (tested in the check module).
    assert_eq!(std::fs::read(&reference).unwrap(), before, "{out}");
    assert!(!out.contains("pass "), "{out}");
    std::fs::copy(conformance.join("reference/output2_01.png"), &reference).unwrap();
    // It leaves a child holding stderr open and exits: check ends on time, and the child with
    // it.
    let marker = dir.path().join("still-running");
    let lingerer = script(
        dir.path(),
        "lingerer.sh",
        &format!(
            "(sleep 3; touch '{}') &
             exec {} \"$@\"",
            marker.display(),
            common::open_raycast()
        ),
    );
    let start = std::time::Instant::now();
    let output = check_within(&suite, &lingerer);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert!(start.elapsed() < std::time::Duration::from_secs(3));
    std::thread::sleep(std::time::Duration::from_millis(3500));
    assert!(
        !marker.exists(),
        "the renderer's child ran on after the check"
    );
}

#[test]
fn a_script_named_from_checks_folder_is_found_from_each_lines_folder() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite_with_own_reference(dir.path(), &conformance);
    std::fs::write(
        dir.path().join("my tracer.sh"),
        format!("exec {} \"$@\"\n", common::open_raycast()),
    )
    .unwrap();
    // `bash 'my tracer.sh'`, named from the folder check runs in; each line runs in its own.
    let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["check", suite.to_str().unwrap()])
        .args(["--renderer", "bash 'my tracer.sh'"])
        .args(renderers_may_run_raycast(&["check", "--renderer"]))
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert!(
        stdout(&output).contains("pass   output2_01"),
        "{}",
        stdout(&output)
    );
}

#[test]
fn what_a_renderer_prints_reaches_people_as_data_and_within_the_platforms_sizes() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = small_suite(dir.path(), &conformance, 3);
    // A progress bar redrawn with \r (one line of about 90 KB), then: erase the terminal's
    // line and forge a count, write its clipboard (OSC 52), ring its bell.
    let renderer = script(
        dir.path(),
        "flood.sh",
        "for i in $(seq 3000); do printf '\\r%5d%% [=========           ]' $i >&2; done
         printf '\\n\\033[2K\\r0 passed, 4 failed\\033]52;c;cm0gLXJm\\a\\n' >&2
         exit 1",
    );
    let report = dir.path().join("report");
    let output = raycast(&[
        "check",
        suite.to_str().unwrap(),
        "--renderer",
        &renderer,
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        !output.stdout.contains(&0x1b) && !output.stdout.contains(&0x07),
        "a raw escape reached the terminal: {}",
        stdout(&output)
    );
    let out = stdout(&output);
    assert!(
        out.contains("\\x1b[2K\\r0 passed, 4 failed\\x1b]52;"),
        "{out}"
    );
    // The only count is check's own.
    assert_eq!(
        out.lines()
            .filter(|l| l.starts_with("0 passed"))
            .collect::<Vec<_>>(),
        ["0 passed, 4 failed"]
    );
    // The report keeps the end of what it printed, cut and saying so, once a line.
    let summary: serde_json::Value = common::summary_of(&report);
    for image in summary["images"].as_array().unwrap() {
        let kept = image["stderr"].as_str().unwrap();
        assert!(kept.starts_with("[cut: the last 2000 of "), "{kept:.80}");
        assert!(kept.chars().count() < 2100);
    }
    // Text: a few kilobytes a picture, not 60 KB each.
    for file in ["gradescope.json", "junit.xml"] {
        let size = std::fs::metadata(report.join(file)).unwrap().len();
        assert!(size < 40_000, "{file}: {size} bytes");
    }
    // PrairieLearn's holds the references' pictures too, within its 1 MB.
    let size = std::fs::metadata(report.join("prairielearn.json"))
        .unwrap()
        .len();
    assert!(size < 1_000_000, "prairielearn.json: {size} bytes");
    let gradescope = std::fs::read_to_string(report.join("gradescope.json")).unwrap();
    // Line 3 writes two pictures: its second points to its first for what the renderer said.
    assert!(
        gradescope.contains("The renderer's output for this line is under output2_03."),
        "{gradescope:.2000}"
    );
}

#[test]
fn a_picture_written_before_a_crash_is_compared_and_the_crash_blamed_on_the_exit() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = small_suite(dir.path(), &conformance, 1);
    let suite = suite.to_str().unwrap();
    // The right picture, then an abort on the way out (a double free in a destructor).
    let aborts = script(
        dir.path(),
        "aborts.sh",
        &format!(
            "{} \"$@\" || exit 9\necho 'free(): double free detected in tcache 2' >&2\nkill -ABRT $$",
            common::open_raycast()
        ),
    );
    let report = dir.path().join("report");
    let output = raycast(&[
        "check",
        suite,
        "--renderer",
        &aborts,
        "--report",
        report.to_str().unwrap(),
    ]);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(1), "{out}");
    assert!(
        out.contains(
            "ERROR  output2_01, 0.000% of pixels off: crash_at_exit: Your picture matches the \
             reference (0.000% of pixels off); then the renderer was killed by SIGABRT"
        ),
        "{out}"
    );
    assert!(out.contains("double free detected"), "{out}");
    assert!(out.contains("destructors and clean-up code"), "{out}");
    assert!(!out.contains("before writing its picture"), "{out}");
    // The picture it wrote is in the report beside the reference.
    let summary: serde_json::Value = common::summary_of(&report);
    assert!(
        summary["images"][0]["pictures"]["actual"].is_string(),
        "{summary}"
    );
    // A crash that leaves the picture cut short says so.
    let cut = script(
        dir.path(),
        "cut.sh",
        &format!(
            "{} \"$@\" || exit 9\ntruncate -s 5000 \"$7\"\nexit 3",
            common::open_raycast()
        ),
    );
    let out = stdout(&raycast(&["check", suite, "--renderer", &cut]));
    assert!(
        out.contains("ERROR  output2_01: crash: The renderer exited with status 3 while its picture was being written: the file it left is cut short"),
        "{out}"
    );
    // A suite that grades the picture alone passes it, and still tells of the crash.
    std::fs::write(
        Path::new(suite).join("GRADING"),
        "# this class grades pictures\ncrash_at_exit picture\n",
    )
    .unwrap();
    let output = raycast(&["check", suite, "--renderer", &aborts]);
    let out = stdout(&output);
    assert_eq!(output.status.code(), Some(0), "{out}");
    assert!(out.contains("1 passed, 0 failed"), "{out}");
    let reported = raycast(&[
        "check",
        suite,
        "--renderer",
        &aborts,
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(reported.status.code(), Some(0));
    let summary: serde_json::Value = common::summary_of(&report);
    let explanation = summary["images"][0]["explanation"].as_str().unwrap();
    assert!(
        explanation.starts_with(
            "Your picture matches the reference (0.000% of pixels off); then the renderer was \
             killed by SIGABRT"
        ) && explanation.contains("which this suite does not grade (it grades the picture alone)"),
        "{explanation}"
    );
    std::fs::write(Path::new(suite).join("GRADING"), "crash_at_exit maybe\n").unwrap();
    let output = raycast(&["check", suite, "--renderer", &aborts]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&output.stderr).contains(
            "GRADING line 1: expected 'crash_at_exit picture' or 'crash_at_exit line', found \
             'crash_at_exit maybe'"
        ),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}
