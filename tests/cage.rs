//! `raycast check` against hostile renderers: each one tries to forge its grade, hang the check,
//! escape, exhaust memory or disk, write or read outside its folders. For each: the grade is
//! right (a forger never passes), check ends within its deadline, nothing the renderer started
//! is left running, a canary folder and the suite are unchanged, and the cause is named.

// The cage these tests break into is Linux's (namespaces, Landlock, its own root); the other
// systems' cages are tested by their own module's tests and, for Windows, CI's Wine job.
#![cfg(target_os = "linux")]

mod common;

use common::{data_dir, left_running};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn conformance_dir() -> Option<PathBuf> {
    data_dir(
        "the cage tests",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// The line's time limit in these tests, in seconds.
const TIMEOUT: u64 = 4;

/// A hostile renderer's world: a one-line suite with its own reference, a folder of scripts
/// any user may run, and a canary folder any user may write to (so only the cage keeps a
/// renderer out of it).
struct World {
    _dir: tempfile::TempDir,
    suite: PathBuf,
    reference: PathBuf,
    scripts: PathBuf,
    canary: PathBuf,
    report: PathBuf,
}

impl World {
    fn new(conformance: &Path) -> World {
        World::in_folder(conformance, tempfile::tempdir().unwrap())
    }

    /// The world laid out in `dir`, a new folder (opened to every user).
    fn in_folder(conformance: &Path, dir: tempfile::TempDir) -> World {
        std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        let suite = dir.path().join("suite");
        std::fs::create_dir_all(suite.join("reference")).unwrap();
        std::fs::write(
            suite.join("COMMANDS.txt"),
            "raytracer -input scene2_01_diffuse.txt -size 200 200 -output output2_01.tga\n",
        )
        .unwrap();
        let reference = suite.join("reference/output2_01.png");
        std::fs::copy(conformance.join("reference/output2_01.png"), &reference).unwrap();
        std::os::unix::fs::symlink(conformance.join("scenes"), suite.join("scenes")).unwrap();
        let scripts = dir.path().join("scripts");
        let canary = dir.path().join("canary");
        for folder in [&scripts, &canary] {
            std::fs::create_dir_all(folder).unwrap();
        }
        std::fs::set_permissions(&canary, std::fs::Permissions::from_mode(0o777)).unwrap();
        let canary_file = canary.join("kept.txt");
        std::fs::write(&canary_file, "untouched").unwrap();
        std::fs::set_permissions(&canary_file, std::fs::Permissions::from_mode(0o666)).unwrap();
        World {
            report: dir.path().join("report"),
            _dir: dir,
            suite,
            reference,
            scripts,
            canary,
        }
    }

    /// A renderer: a bash script; `$7` is the picture's path, `"$@"` the line.
    fn renderer(&self, name: &str, body: &str) -> String {
        let path = self.scripts.join(name);
        std::fs::write(&path, format!("#!/usr/bin/env bash\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path.to_str().unwrap().to_string()
    }

    /// The suite's and the canary's files and their contents.
    fn state(&self) -> Vec<(PathBuf, Vec<u8>)> {
        let mut files = Vec::new();
        for root in [&self.suite.join("reference"), &self.canary] {
            let mut entries: Vec<PathBuf> = std::fs::read_dir(root)
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            entries.sort();
            for path in entries {
                let bytes = std::fs::read(&path).unwrap_or_default();
                files.push((path, bytes));
            }
        }
        files.push((
            self.suite.join("COMMANDS.txt"),
            std::fs::read(self.suite.join("COMMANDS.txt")).unwrap(),
        ));
        files
    }

    /// `raycast check` with `renderer`, which must end within the deadline; its stdout, and
    /// the check's exit status. Asserts that the suite and the canary are unchanged and that
    /// no process carrying `token` in its command line is left.
    fn check(&self, renderer: &str, extra: &[&str], token: &str) -> (String, Option<i32>) {
        self.check_by(false, renderer, extra, token)
    }

    /// [`World::check`], run by an ordinary user (user 65534, through `setpriv`) where `ordinary`
    /// and the tests run as root.
    fn check_by(
        &self,
        ordinary: bool,
        renderer: &str,
        extra: &[&str],
        token: &str,
    ) -> (String, Option<i32>) {
        let before = self.state();
        let start = Instant::now();
        let mut command = if ordinary {
            let mut setpriv = Command::new("setpriv");
            setpriv
                .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
                .arg(common::open_raycast());
            setpriv
        } else {
            Command::new(RAYCAST)
        };
        let mut child = command
            .args([
                "check",
                self.suite.to_str().unwrap(),
                "--renderer",
                renderer,
            ])
            .args(["--timeout", &TIMEOUT.to_string()])
            .args(["--report", self.report.to_str().unwrap()])
            // Those that render in the end run raycast, which they may read.
            .args(["--allow-read", common::open_raycast_folder()])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // A line's own --timeout in `extra` (the last given counts) moves the deadline with it.
        let timeout = extra
            .windows(2)
            .filter(|pair| pair[0] == "--timeout")
            .filter_map(|pair| pair[1].parse::<u64>().ok())
            .next_back()
            .unwrap_or(TIMEOUT);
        let deadline = Duration::from_secs(timeout + 6);
        while child.try_wait().unwrap().is_none() {
            if start.elapsed() > deadline {
                let _ = child.kill();
                panic!("check still running after {deadline:?} with {renderer}");
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let output: Output = child.wait_with_output().unwrap();
        let out = String::from_utf8_lossy(&output.stdout).into_owned()
            + &String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            self.state(),
            before,
            "the suite or the canary changed: {out}"
        );
        assert_eq!(left_running(token), Vec::<String>::new(), "{out}");
        (out, output.status.code())
    }
}

/// A line of raycast's own render, for renderers that do their harm and then render.
fn render() -> String {
    format!("exec {} \"$@\"", common::open_raycast())
}

fn world() -> Option<World> {
    Some(World::new(&conformance_dir()?))
}

fn assert_graded(out: &str, expected: &str) {
    assert!(out.contains(expected), "expected '{expected}' in:\n{out}");
}

#[test]
fn a_forger_never_passes() {
    let Some(w) = world() else { return };
    let reference = w.reference.display();
    // Copies the reference it knows the path of.
    let copier = w.renderer("copier.sh", &format!("cp '{reference}' \"$7\""));
    let (out, code) = w.check(&copier, &[], "copier.sh");
    assert_eq!(code, Some(1), "{out}");
    assert_graded(&out, "ERROR  output2_01: crash");
    // Not there at all in the renderer's own root; refused by Landlock where it has none.
    assert!(
        out.contains("No such file") || out.contains("cannot open"),
        "{out}"
    );
    // Finds the suite in check's command line, through /proc.
    let finder = w.renderer(
        "finder.sh",
        "for c in /proc/[0-9]*/cmdline; do
           suite=$(tr '\\0' '\\n' < $c 2>/dev/null | grep -A1 '^check$' | tail -1)
           [ -n \"$suite\" ] && cp \"$suite/reference/output2_01.png\" \"$7\" && exit 0
         done",
    );
    let (out, _) = w.check(&finder, &[], "finder.sh");
    assert!(!out.contains("pass   output2_01"), "{out}");
    // Links its output to the reference.
    let linker = w.renderer("linker.sh", &format!("ln -s '{reference}' \"$7\""));
    let (out, _) = w.check(&linker, &[], "linker.sh");
    assert_graded(
        &out,
        "ERROR  output2_01: unreadable_output: The image is a symbolic link",
    );
    // Blackens the reference, then writes black.
    let black = w.scripts.join("black.txt");
    std::fs::write(
        &black,
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 1 }
         Background { color 0 0 0 ambientLight 0 0 0 }
         Group { numObjects 0 }",
    )
    .unwrap();
    let blackener = w.renderer(
        "blackener.sh",
        &format!(
            "{raycast} -input '{}' -size 200 200 -output '{reference}'
             exec {raycast} -input '{}' -size 200 200 -output \"$7\"",
            black.display(),
            black.display(),
            raycast = common::open_raycast(),
        ),
    );
    let (out, _) = w.check(
        &blackener,
        &["--allow-read", w.scripts.to_str().unwrap()],
        "blackener.sh",
    );
    assert_graded(&out, "FAIL   output2_01");
    // Empties its copy of the scene and writes black, in a suite without references: the
    // reference, raycast's own render, was made before from the suite's scene.
    std::fs::remove_file(&w.reference).unwrap();
    let emptier = w.renderer(
        "emptier.sh",
        &format!(
            "rm -f scene2_01_diffuse.txt; cp '{}' scene2_01_diffuse.txt
             exec {raycast} -input scene2_01_diffuse.txt -size 200 200 -output \"$7\"",
            black.display(),
            raycast = common::open_raycast(),
        ),
    );
    let (out, _) = w.check(
        &emptier,
        &["--allow-read", w.scripts.to_str().unwrap()],
        "emptier.sh",
    );
    assert_graded(&out, "FAIL   output2_01");
}

#[test]
fn nothing_the_renderer_starts_outlives_its_line() {
    let Some(w) = world() else { return };
    let cases = [
        ("lingerer", "(exec -a lingerer-token sleep 30) &\n"),
        (
            "setsid",
            "setsid bash -c 'exec -a setsid-token sleep 30' < /dev/null > /dev/null 2>&1 &\n",
        ),
        (
            "daemon",
            "(setsid bash -c 'exec -a daemon-token sleep 30' &) ; sleep 0.2\n",
        ),
        (
            "crowd",
            "for i in $(seq 200); do (exec -a crowd-token sleep 30) & done\n",
        ),
        (
            "stderr-holder",
            "setsid bash -c 'exec -a holder-token sleep 30' < /dev/null > /dev/null &\n",
        ),
    ];
    for (name, prelude) in cases {
        let token = format!("{name}-token");
        let renderer = w.renderer(&format!("{name}.sh"), &format!("{prelude}{}", render()));
        let start = Instant::now();
        let (out, code) = w.check(&renderer, &[], &token);
        assert_eq!(code, Some(0), "{name}: {out}");
        assert!(
            start.elapsed() < Duration::from_secs(TIMEOUT),
            "{name}: took {:?}",
            start.elapsed()
        );
    }
}

#[test]
fn hangs_end_at_the_deadline_with_their_cause() {
    let Some(w) = world() else { return };
    let cases = [
        ("sleeper", "exec -a sleeper-token sleep 100\n"),
        (
            "stubborn",
            "trap '' TERM INT HUP; (exec -a stubborn-token sleep 100); sleep 100\n",
        ),
        ("spinner", "while :; do :; done # spinner-token\n"),
    ];
    for (name, body) in cases {
        let renderer = w.renderer(&format!("{name}.sh"), body);
        let (out, code) = w.check(&renderer, &[], &format!("{name}-token"));
        assert_eq!(code, Some(1), "{out}");
        assert_graded(
            &out,
            "ERROR  output2_01: timed_out: The renderer did not finish within 4 s",
        );
    }
    // One that stops its supervisor (or anything it can find) cannot freeze check.
    let stopper = w.renderer(
        "stopper.sh",
        "for p in /proc/[0-9]*; do kill -STOP ${p#/proc/} 2>/dev/null; done; exec -a stopper-token sleep 100",
    );
    let (out, _) = w.check(&stopper, &[], "stopper-token");
    assert_graded(&out, "ERROR  output2_01: timed_out");
    // Nor can it kill check.
    let killer = w.renderer(
        "killer.sh",
        &format!(
            "for p in /proc/[0-9]*; do kill -KILL ${{p#/proc/}} 2>/dev/null; done; {}",
            render()
        ),
    );
    let (out, code) = w.check(&killer, &[], "killer.sh");
    assert!(out.contains("output2_01"), "{out}");
    assert!(code == Some(0) || code == Some(1), "{code:?}: {out}");
}

#[test]
fn pictures_that_are_not_pictures_get_their_cause() {
    let Some(w) = world() else { return };
    let fifo = w.renderer("fifo.sh", "mkfifo \"$7\"");
    let (out, _) = w.check(&fifo, &[], "fifo.sh");
    assert_graded(
        &out,
        "ERROR  output2_01: unreadable_output: The image is not a plain file",
    );
    let png = w.renderer(
        "png.sh",
        &format!(
            "{} \"${{@:1:6}}\" \"$7.png\" && mv \"$7.png\" \"$7\"",
            common::open_raycast()
        ),
    );
    let (out, _) = w.check(&png, &[], "png.sh");
    assert_graded(
        &out,
        "ERROR  output2_01: wrong_format: The file is named .tga but holds a PNG picture",
    );
    let cut = w.renderer(
        "cut.sh",
        &format!(
            "{} \"$@\" && truncate -s 5000 \"$7\"",
            common::open_raycast()
        ),
    );
    let (out, _) = w.check(&cut, &[], "cut.sh");
    assert_graded(&out, "ERROR  output2_01: unreadable_output");
    // A PNG whose header says 18000x18000: refused by its header, never decoded.
    let giant = w.scripts.join("giant.png");
    std::fs::write(&giant, png_header(18000, 18000)).unwrap();
    let liar = w.renderer(
        "liar.sh",
        &format!("cp '{}' \"$7.png\"; mv \"$7.png\" \"$7\"", giant.display()),
    );
    let (out, _) = w.check(
        &liar,
        &["--allow-read", w.scripts.to_str().unwrap()],
        "liar.sh",
    );
    assert_graded(&out, "wrong_format");
    let liar = w.renderer("liar2.sh", &format!("cp '{}' \"$7\"", giant.display()));
    let suite_png = w.suite.join("COMMANDS.txt");
    std::fs::write(
        &suite_png,
        "raytracer -input scene2_01_diffuse.txt -size 200 200 -output output2_01.png\n",
    )
    .unwrap();
    let (out, _) = w.check(
        &liar,
        &["--allow-read", w.scripts.to_str().unwrap()],
        "liar2.sh",
    );
    assert_graded(
        &out,
        "FAIL   output2_01: size: The picture is 18000x18000; its reference is 200x200",
    );
}

/// A PNG signature and header chunk for a picture of `width` x `height` (no pixels).
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut chunk = b"IHDR".to_vec();
    chunk.extend(width.to_be_bytes());
    chunk.extend(height.to_be_bytes());
    chunk.extend([8, 2, 0, 0, 0]);
    let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    // The header, a few bytes of pixel data, and the end.
    for chunk in [chunk, b"IDAT\x78\x9c\x03\x00".to_vec(), b"IEND".to_vec()] {
        bytes.extend((chunk.len() as u32 - 4).to_be_bytes());
        bytes.extend(&chunk);
        bytes.extend(crc32(&chunk).to_be_bytes());
    }
    bytes
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[test]
fn limits_hold_and_name_their_cause() {
    let Some(w) = world() else { return };
    // Memory: raycast itself under 16 MiB of address space.
    let (out, _) = w.check(RAYCAST, &["--memory", "16M"], "no-token-memory");
    assert!(
        out.contains("ERROR  output2_01: out_of_memory")
            || out.contains("ERROR  output2_01: crash"),
        "{out}"
    );
    // A file past the size limit: one byte written 300 MiB in, so that the limit is met at once
    // however slowly the machine writes (writing 300 MB could outlast the line's deadline on a
    // busy machine, and be named timed_out).
    let filler = w.renderer(
        "filler.sh",
        "dd if=/dev/zero of=\"$7\" bs=1 count=1 seek=300M 2>/dev/null",
    );
    let (out, _) = w.check(&filler, &[], "filler.sh");
    assert_graded(&out, "ERROR  output2_01: output_too_large");
    // A crash by a signal, named.
    let segv = w.renderer("segv.sh", "kill -SEGV $$");
    let (out, _) = w.check(&segv, &[], "segv.sh");
    assert_graded(
        &out,
        "ERROR  output2_01: crash: The renderer was killed by SIGSEGV (a segmentation fault",
    );
    // A fork bomb ends with its line.
    let bomb = w.renderer(
        "bomb.sh",
        "for i in $(seq 2000); do (exec -a bomb-token sleep 30) & done; wait",
    );
    let (out, _) = w.check(&bomb, &[], "bomb-token");
    assert!(out.contains("ERROR  output2_01"), "{out}");
}

#[test]
fn nothing_is_written_or_read_outside_its_folders() {
    let Some(w) = world() else { return };
    let canary = w.canary.display();
    let secret = w.canary.join("kept.txt");
    let writer = w.renderer(
        "writer.sh",
        &format!(
            "echo x > '{canary}/new.txt'; echo x >> '{}'; ln -s '{}' link; echo x >> link
             echo x > /tmp/raycast-cage-escape-$$; echo x > ~/raycast-cage-escape
             echo \"HOME=$HOME TMPDIR=$TMPDIR\" >&2
             {}",
            secret.display(),
            secret.display(),
            render()
        ),
    );
    let (out, code) = w.check(&writer, &[], "writer.sh");
    assert_eq!(code, Some(0), "{out}");
    assert!(!Path::new(&format!("{canary}/new.txt")).exists());
    let leaked: Vec<_> = std::fs::read_dir("/tmp")
        .unwrap()
        .flatten()
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with("raycast-cage-escape")
        })
        .collect();
    assert!(leaked.is_empty(), "{leaked:?}");
    // Another submission's file (readable by any user) cannot be read.
    let reader = w.renderer(
        "reader.sh",
        &format!("cat '{}' >&2; exit 3", secret.display()),
    );
    let (out, _) = w.check(&reader, &[], "reader.sh");
    assert!(!out.contains("untouched"), "{out}");
    let summary = std::fs::read_to_string(w.report.join("summary.json")).unwrap();
    assert!(!summary.contains("untouched"), "{summary}");
    // No network: a listener on loopback hears nothing.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let caller = w.renderer(
        "caller.sh",
        &format!(
            "exec 3<>/dev/tcp/127.0.0.1/{port} && echo hello >&3; {}",
            render()
        ),
    );
    w.check(&caller, &[], "caller.sh");
    assert!(
        listener.accept().is_err(),
        "the renderer reached the network"
    );
}

#[test]
fn the_report_is_whole_and_says_how_the_renderer_was_caged() {
    let Some(w) = world() else { return };
    let (out, code) = w.check(RAYCAST, &[], "no-token-report");
    assert_eq!(code, Some(0), "{out}");
    let summary: serde_json::Value = common::summary_of(&w.report);
    assert_eq!(summary["partial"], false);
    let cage = &summary["cage"];
    for key in ["user", "landlock", "network_namespace", "subreaper"] {
        assert!(!cage[key].is_null(), "no cage.{key} in {summary}");
    }
    if rustix_is_root() {
        assert_eq!(cage["user"], "uid 65534", "{summary}");
    }
    // Two checks into one report folder: the report is one run's or the other's, whole.
    let black = w.renderer("black2.sh", "exit 1");
    let first = std::thread::spawn({
        let (suite, report) = (w.suite.clone(), w.report.clone());
        move || {
            for _ in 0..5 {
                Command::new(RAYCAST)
                    .args(["check", suite.to_str().unwrap(), "--renderer", RAYCAST])
                    .args(["--report", report.to_str().unwrap()])
                    .output()
                    .unwrap();
            }
        }
    });
    for _ in 0..5 {
        Command::new(RAYCAST)
            .args(["check", w.suite.to_str().unwrap(), "--renderer", &black])
            .args(["--report", w.report.to_str().unwrap()])
            .output()
            .unwrap();
        let summary = std::fs::read_to_string(w.report.join("summary.json")).unwrap();
        let page = std::fs::read_to_string(w.report.join("index.html")).unwrap();
        let passed = summary.contains("\"passed\": 1");
        assert_eq!(
            page.contains("1 passed, 0 failed"),
            passed,
            "{summary}\n{page}"
        );
    }
    first.join().unwrap();
    // A folder that holds other files is not taken for a report.
    let not_a_report = w.scripts.clone();
    let output = Command::new(RAYCAST)
        .args(["check", w.suite.to_str().unwrap(), "--renderer", RAYCAST])
        .args(["--report", not_a_report.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("is not a report of raycast's"));
}

/// Interrupts `check` (SIGINT, as Ctrl-C does), which must end within 5 seconds: its output.
fn interrupted(mut check: std::process::Child) -> Output {
    let start = Instant::now();
    Command::new("kill")
        .args(["-INT", &check.id().to_string()])
        .status()
        .unwrap();
    while check.try_wait().unwrap().is_none() {
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "check did not end on SIGINT"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    check.wait_with_output().unwrap()
}

#[test]
fn an_interrupted_check_ends_its_renderers_and_reports_what_it_graded() {
    let Some(w) = world() else { return };
    let sleeper = w.renderer("interrupted.sh", "exec -a interrupted-token sleep 100");
    let child = Command::new(RAYCAST)
        .args(["check", w.suite.to_str().unwrap(), "--renderer", &sleeper])
        .args(["--timeout", "60", "--report", w.report.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(800));
    assert!(!left_running("interrupted-token").is_empty());
    let output = interrupted(child);
    let out = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(130), "{out}");
    assert!(out.contains("ERROR  output2_01: interrupted"), "{out}");
    assert_eq!(left_running("interrupted-token"), Vec::<String>::new());
    let summary = std::fs::read_to_string(w.report.join("summary.json")).unwrap();
    assert!(summary.contains("\"partial\": true"), "{summary}");
}

#[test]
fn the_next_line_is_made_ready_while_one_runs_and_given_up_unrun_when_check_stops() {
    let Some(w) = world() else { return };
    // Two lines, one at a time: the second's cage is built while the first's renderer runs.
    let commands = w.suite.join("COMMANDS.txt");
    let line = std::fs::read_to_string(&commands).unwrap();
    std::fs::write(&commands, format!("{line}\n{line}\n")).unwrap();
    let sleeper = w.renderer("readied.sh", "exec -a readied-token sleep 100");
    let child = Command::new(RAYCAST)
        .args(["check", w.suite.to_str().unwrap(), "--renderer", &sleeper])
        .args(["--jobs", "1", "--timeout", "60"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The first line's renderer runs, and a supervisor holds the second's cage, its renderer
    // not started.
    let held = || {
        left_running("readied.sh")
            .into_iter()
            .filter(|c| c.contains("__supervise") && c.contains("\"held\":true"))
            .count()
    };
    let start = Instant::now();
    while left_running("readied-token").len() != 1 || held() < 2 {
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "no line held ready while the first ran: {:?}",
            left_running("readied.sh")
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = interrupted(child);
    let out = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(130), "{out}");
    assert!(out.contains("ERROR  output2_01: interrupted"), "{out}");
    assert!(out.contains("ERROR  output2_01#2: interrupted"), "{out}");
    // The held supervisor heard its line given up, took its cage down and ended.
    assert_eq!(left_running("readied.sh"), Vec::<String>::new());
    assert_eq!(left_running("readied-token"), Vec::<String>::new());
}

#[test]
fn check_run_by_an_ordinary_user_cages_the_renderer_too() {
    let Some(w) = world() else { return };
    if !rustix_is_root() {
        // Already an ordinary user: the other tests ran as one.
        return;
    }
    std::fs::set_permissions(
        w.report.parent().unwrap(),
        std::fs::Permissions::from_mode(0o777),
    )
    .unwrap();
    let setpriv = ["--reuid=65534", "--regid=65534", "--clear-groups"];
    let lingerer = w.renderer(
        "user-lingerer.sh",
        &format!(
            "(setsid bash -c 'exec -a user-token sleep 30' &); {}",
            render()
        ),
    );
    let output = Command::new("setpriv")
        .args(setpriv)
        .args([
            common::open_raycast(),
            "check",
            w.suite.to_str().unwrap(),
            "--renderer",
            &lingerer,
        ])
        .args(["--report", w.report.to_str().unwrap()])
        .args(["--allow-read", common::open_raycast_folder()])
        .output();
    let Ok(output) = output else {
        panic!("setpriv is needed to run check as an ordinary user");
    };
    let out = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{out}");
    let summary = std::fs::read_to_string(w.report.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"user\": \"check's own user\""),
        "{summary}"
    );
    // Its own user namespace gives it the rest of the cage: its own root and namespaces.
    let cage = &common::summary_of(&w.report)["cage"];
    for held in [
        "own_root",
        "pid_namespace",
        "ipc_namespace",
        "network_namespace",
    ] {
        assert_eq!(cage[held], true, "{held}: {cage}");
    }
    assert_eq!(left_running("user-token"), Vec::<String>::new());
}

fn rustix_is_root() -> bool {
    std::fs::read_to_string("/proc/self/status")
        .map(|s| {
            s.lines()
                .any(|l| l.starts_with("Uid:") && l.split_whitespace().nth(2) == Some("0"))
        })
        .unwrap_or(false)
}

#[test]
fn a_suite_past_its_bounds_is_one_error_before_anything_runs() {
    let Some(w) = world() else { return };
    let commands = w.suite.join("COMMANDS.txt");
    let outputs: String = (0..9).map(|k| format!(" -output o{k}.tga")).collect();
    std::fs::write(&commands, format!("raytracer -input a.txt{outputs}\n")).unwrap();
    let output = Command::new(RAYCAST)
        .args(["check", w.suite.to_str().unwrap(), "--renderer", RAYCAST])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(
        said.contains("a line writes 9 pictures, more than the 8 a line may"),
        "{said}"
    );
    std::fs::write(&commands, "raytracer -output a.tga\n".repeat(100_000)).unwrap();
    let output = Command::new(RAYCAST)
        .args(["check", w.suite.to_str().unwrap(), "--renderer", RAYCAST])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(
        said.contains("COMMANDS.txt: more than 1 MiB: not a suite's list of command lines"),
        "{said}"
    );
}

#[test]
fn folders_the_renderer_locks_are_still_removed() {
    let Some(w) = world() else { return };
    // Its scratch in a folder of the test's, so that what is left there can be seen; check
    // runs as an ordinary user where the test is root (root removes anything anyway).
    let tmp = w.report.parent().unwrap().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    std::fs::set_permissions(
        w.report.parent().unwrap(),
        std::fs::Permissions::from_mode(0o777),
    )
    .unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o777)).unwrap();
    let locker = w.renderer(
        "locker.sh",
        &format!(
            "mkdir -p locked/inner && touch locked/inner/x && chmod 000 locked/inner locked\n{}",
            render()
        ),
    );
    let mut command = if rustix_is_root() {
        let mut command = Command::new("setpriv");
        command.args([
            "--reuid=65534",
            "--regid=65534",
            "--clear-groups",
            common::open_raycast(),
        ]);
        command
    } else {
        Command::new(RAYCAST)
    };
    let output = command
        .args(["check", w.suite.to_str().unwrap(), "--renderer", &locker])
        .args(["--allow-read", common::open_raycast_folder()])
        .env("TMPDIR", &tmp)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{out}");
    assert!(!out.contains("could not be removed"), "{out}");
    let left: Vec<_> = std::fs::read_dir(&tmp)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_renderer_never_runs_as_root_even_from_a_closed_folder() {
    let Some(w) = world() else { return };
    if !rustix_is_root() {
        return;
    }
    // A student's tracer in a home folder of mode 700, as `sudo raycast check` finds it.
    let home = w.scripts.join("home");
    std::fs::create_dir_all(home.join("tracer/data")).unwrap();
    std::fs::write(home.join("tracer/data/table.txt"), "beside the program\n").unwrap();
    let tracer = home.join("tracer/raytracer");
    std::fs::write(
        &tracer,
        format!(
            "#!/usr/bin/env bash\necho \"uid $(id -u), $(cat \"$(dirname \"$0\")/data/table.txt\")\" >&2\nexec {} \"$@\"\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&tracer, std::fs::Permissions::from_mode(0o700)).unwrap();
    std::fs::set_permissions(&home, std::fs::Permissions::from_mode(0o700)).unwrap();
    let (out, code) = w.check(tracer.to_str().unwrap(), &[], "no-token-closed");
    assert_eq!(code, Some(0), "{out}");
    let summary: serde_json::Value = common::summary_of(&w.report);
    assert_eq!(summary["cage"]["user"], "uid 65534", "{summary}");
    let stderr = summary["images"][0]["stderr"].as_str().unwrap();
    assert!(stderr.contains("uid 65534, beside the program"), "{stderr}");
    assert!(
        summary["cage"]["note"]
            .as_str()
            .unwrap()
            .contains("from copies of what that user could not reach"),
        "{summary}"
    );
    // What cannot be copied is refused before any line runs: never run as root instead.
    let crowded = home.join("crowded");
    std::fs::create_dir_all(&crowded).unwrap();
    for k in 0..20_001 {
        std::fs::write(crowded.join(k.to_string()), "").unwrap();
    }
    let output = Command::new(RAYCAST)
        .args([
            "check",
            w.suite.to_str().unwrap(),
            "--renderer",
            common::open_raycast(),
        ])
        .args(["--allow-read", crowded.to_str().unwrap()])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{said}");
    assert!(
        said.contains("never runs a renderer as root")
            && said.contains(&crowded.display().to_string())
            && said.contains("chmod o+rx"),
        "{said}"
    );
    assert!(output.stdout.is_empty());
}

#[test]
fn a_suite_in_a_folder_renderers_may_read_is_hidden_or_refused() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    if !rustix_is_root() {
        return;
    }
    // A suite under /opt, which every renderer may read as a system folder.
    let w = World::in_folder(
        &conformance,
        tempfile::Builder::new()
            .prefix("raycast-suite-")
            .tempdir_in("/opt")
            .unwrap(),
    );
    // It hands in the reference it can read as its own picture.
    let copier = w.renderer(
        "copier.sh",
        &format!("cat '{}' > \"$7\"", w.reference.display()),
    );
    let (suite, report) = (&w.suite, &w.report);
    let run = |extra: &[&str]| {
        Command::new(RAYCAST)
            .args(["check", suite.to_str().unwrap(), "--renderer"])
            .arg(&copier)
            .args(["--report", report.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap()
    };
    let first = run(&[]);
    let said = String::from_utf8_lossy(&first.stderr);
    if first.status.code() == Some(2) {
        // No root of its own on this machine: Landlock alone would let it read /opt.
        assert!(
            said.contains("the suite lies under /opt, which every renderer may read")
                && said.contains("--no-cage"),
            "{said}"
        );
        assert!(first.stdout.is_empty() && !report.exists());
    } else {
        // In a root of its own the suite is hidden, even under /opt (an empty folder no one
        // may open lies over it): graded, and the copier has nothing to copy.
        let out = String::from_utf8_lossy(&first.stdout);
        assert_eq!(first.status.code(), Some(1), "{out}{said}");
        assert!(out.contains("ERROR  output2_01: crash"), "{out}");
        assert!(
            out.contains("suite/reference/output2_01.png: Permission denied"),
            "{out}"
        );
        assert_eq!(common::summary_of(report)["cage"]["own_root"], true);
    }
    // Told --no-cage, it grades, says so once, and every report records it.
    let graded = run(&["--no-cage"]);
    let said = String::from_utf8_lossy(&graded.stderr);
    assert!(said.contains("raycast: check: --no-cage: "), "{said}");
    assert_eq!(common::summary_of(report)["cage"]["no_cage"], true);
    let gradescope = std::fs::read_to_string(report.join("gradescope.json")).unwrap();
    assert!(
        gradescope.contains("graded with --no-cage"),
        "{gradescope:.600}"
    );
}

/// The System V shared memory segments of the machine, as `ipcs -m` lists them.
fn shared_memory_segments() -> Vec<String> {
    let listed = Command::new("ipcs")
        .arg("-m")
        .output()
        .expect("ipcs (util-linux) lists the machine's shared memory");
    String::from_utf8_lossy(&listed.stdout)
        .lines()
        .filter(|l| l.starts_with("0x"))
        .map(String::from)
        .collect()
}

#[test]
fn no_side_door_reaches_outside_the_line() {
    let Some(w) = world() else { return };
    let python = Path::new("/usr/bin/python3");
    assert!(python.exists(), "these tests need /usr/bin/python3");
    // System V shared memory: each line sees none but its own, and none outlives it.
    let before = shared_memory_segments();
    let sharer = w.renderer(
        "sharer.sh",
        &format!(
            "ipcs -m | grep -q '^0x' && {{ echo 'saw a segment of another line'; exit 1; }}
             ipcmk -M 4096 > /dev/null || exit 1
             {}",
            render()
        ),
    );
    for _ in 0..2 {
        let (out, code) = w.check(&sharer, &[], "sharer.sh");
        assert_eq!(code, Some(0), "{out}");
    }
    assert_eq!(shared_memory_segments(), before);
    // A listener outside, reached by its socket's path (as D-Bus, docker.sock or an X server
    // would be): never reached.
    let sockets = tempfile::tempdir().unwrap();
    std::fs::set_permissions(sockets.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    let path = sockets.path().join("listener.sock");
    let listener = std::os::unix::net::UnixListener::bind(&path).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o777)).unwrap();
    listener.set_nonblocking(true).unwrap();
    let caller = w.renderer(
        "caller.sh",
        &format!(
            "/usr/bin/python3 -c 'import socket, sys
s = socket.socket(socket.AF_UNIX)
s.connect(sys.argv[1])
s.sendall(b\"a line of the suite\")' '{}' && {{ echo 'reached the listener'; exit 1; }}
             {}",
            path.display(),
            render()
        ),
    );
    let (out, code) = w.check(&caller, &[], "caller.sh");
    assert_eq!(code, Some(0), "{out}");
    assert!(
        listener.accept().is_err(),
        "the listener heard the renderer"
    );
    // /tmp and /dev/shm are the line's own: written there, found nowhere else.
    let marker = format!("raycast-marker-{}", std::process::id());
    let temporary = w.renderer(
        "temporary.sh",
        &format!(
            "echo x > /tmp/{marker} && echo x > /dev/shm/{marker} || exit 1
             {}",
            render()
        ),
    );
    let (out, code) = w.check(&temporary, &[], "temporary.sh");
    assert_eq!(code, Some(0), "{out}");
    for folder in ["/tmp", "/dev/shm"] {
        assert!(!Path::new(folder).join(&marker).exists(), "{folder}: {out}");
    }
    assert_eq!(
        common::summary_of(&w.report)["cage"]["own_root"],
        true,
        "the lines ran in a root of their own"
    );
    // The kernel's keyrings, which no namespace separates: no key can be made to leave there
    // for another line of the same user.
    let keeper = w.renderer(
        "keeper.sh",
        &format!(
            "/usr/bin/python3 -c 'import ctypes, platform
libc = ctypes.CDLL(None, use_errno=True)
add_key = {{\"x86_64\": 248, \"aarch64\": 217}}[platform.machine()]
made = libc.syscall(add_key, b\"user\", b\"a picture\", b\"pixels\", 6, ctypes.c_int(-4))
raise SystemExit(1 if made >= 0 else 0)' || {{ echo 'made a key in the user keyring'; exit 1; }}
             {}",
            render()
        ),
    );
    let (out, code) = w.check(&keeper, &[], "keeper.sh");
    assert_eq!(code, Some(0), "{out}");
    assert_eq!(
        common::summary_of(&w.report)["cage"]["keyrings_closed"],
        true,
        "{out}"
    );
}

#[test]
fn a_bomb_that_reforks_as_it_is_killed_ends_with_its_line() {
    let Some(w) = world() else { return };
    let bomb = w.renderer(
        "refork.sh",
        &format!(
            "for i in $(seq 60); do
               ( while :; do (exec -a refork-token sleep 30) & wait; done ) &
             done
             sleep 0.3
             {}",
            render()
        ),
    );
    // w.check asserts that no process carrying the token is left.
    let (out, code) = w.check(&bomb, &[], "refork-token");
    assert_eq!(code, Some(0), "{out}");
    assert_eq!(common::summary_of(&w.report)["cage"]["pid_namespace"], true);
}

#[test]
fn a_line_writes_no_more_than_its_disk_and_leaves_nothing() {
    let Some(w) = world() else { return };
    // 16 MiB: 16 MiB of bytes and 256 files and folders in all, whatever the folder.
    let filler = w.renderer(
        "filler.sh",
        "dd if=/dev/zero of=fill bs=1M count=64 2>/dev/null
         echo \"wrote $(stat -c %s fill) bytes\"
         rm fill
         for i in $(seq 1000); do mkdir -p /tmp/d$i 2>/dev/null || break; done
         echo \"made $((i - 1)) folders\"
         exit 1",
    );
    let (out, code) = w.check(&filler, &["--disk", "16M"], "filler.sh");
    assert_eq!(code, Some(1), "{out}");
    let number_after = |word: &str| -> u64 {
        let at = out
            .find(word)
            .unwrap_or_else(|| panic!("no '{word}' in {out}"))
            + word.len();
        out[at..]
            .split_whitespace()
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no number after '{word}' in {out}"))
    };
    assert!(number_after("wrote ") <= 16 << 20, "{out}");
    assert!(number_after("made ") < 256, "{out}");
    let usage = Command::new(RAYCAST)
        .args(["check", "suite", "--renderer", "r", "--disk", "1T0"])
        .output()
        .unwrap();
    assert_eq!(
        String::from_utf8_lossy(&usage.stderr).lines().next(),
        Some("raycast: --disk needs a size such as 1G or 256M (at least 16M), found '1T0'")
    );
}

#[test]
fn a_careless_renderer_is_told_the_cage_kept_it_from_its_files() {
    let Some(w) = world() else { return };
    // CMake's layout: the program in build/bin reads the data beside the sources, found from
    // its own place. Its project is its own to read: it passes.
    let project = w.scripts.join("tracer");
    std::fs::create_dir_all(project.join("build/bin")).unwrap();
    std::fs::create_dir_all(project.join("data")).unwrap();
    std::fs::write(project.join("CMakeLists.txt"), "project(tracer)\n").unwrap();
    std::fs::write(project.join("data/sky.txt"), "blue\n").unwrap();
    let program = project.join("build/bin/tracer.sh");
    std::fs::write(
        &program,
        format!(
            "#!/usr/bin/env bash\ngrep -q blue \"$(dirname \"$0\")/../../data/sky.txt\" || exit 1\n{}\n",
            render()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
    let (out, code) = w.check(program.to_str().unwrap(), &[], "tracer.sh");
    assert_eq!(code, Some(0), "{out}");
    // One that reads a file outside its project: the cage is named, with the fix.
    let outside = w.canary.join("kept.txt");
    let reader = w.renderer(
        "reader.sh",
        &format!(
            "cat '{}' > /dev/null || exit 1\n{}",
            outside.display(),
            render()
        ),
    );
    let (out, code) = w.check(&reader, &[], "reader.sh");
    assert_eq!(code, Some(1), "{out}");
    assert_graded(
        &out,
        &format!(
            "ERROR  output2_01: cage_refused: The renderer exited with status 1. It said: cat: {}",
            outside.display()
        ),
    );
    assert_graded(
        &out,
        &format!(
            "by hand it can read it, under check it cannot. If it needs it, give check \
             --allow-read {}.",
            w.canary.display()
        ),
    );
    assert!(!out.contains("run the same command line by hand"), "{out}");
    // Given the --allow-read it was told, it passes.
    let (out, code) = w.check(
        &reader,
        &["--allow-read", w.canary.to_str().unwrap()],
        "reader.sh",
    );
    assert_eq!(code, Some(0), "{out}");
}

#[test]
fn the_side_doors_stay_closed_when_an_ordinary_user_runs_check() {
    let Some(w) = world() else { return };
    if !rustix_is_root() {
        // Already an ordinary user: the other tests ran as one.
        return;
    }
    // The report is written by the ordinary user.
    std::fs::set_permissions(
        w.report.parent().unwrap(),
        std::fs::Permissions::from_mode(0o777),
    )
    .unwrap();
    let before = shared_memory_segments();
    let sharer = w.renderer(
        "user-sharer.sh",
        &format!(
            "ipcs -m | grep -q '^0x' && {{ echo 'saw a segment of another line'; exit 1; }}
             ipcmk -M 4096 > /dev/null || exit 1
             echo x > /tmp/user-marker && echo x > /dev/shm/user-marker || exit 1
             {}",
            render()
        ),
    );
    for _ in 0..2 {
        let (out, code) = w.check_by(true, &sharer, &[], "user-sharer.sh");
        assert_eq!(code, Some(0), "{out}");
    }
    assert_eq!(shared_memory_segments(), before);
    for folder in ["/tmp", "/dev/shm"] {
        assert!(!Path::new(folder).join("user-marker").exists(), "{folder}");
    }
    let bomb = w.renderer(
        "user-refork.sh",
        &format!(
            "for i in $(seq 40); do
               ( while :; do (exec -a user-refork-token sleep 30) & wait; done ) &
             done
             sleep 0.3
             {}",
            render()
        ),
    );
    let (out, code) = w.check_by(true, &bomb, &[], "user-refork-token");
    assert_eq!(code, Some(0), "{out}");
    let filler = w.renderer(
        "user-filler.sh",
        "dd if=/dev/zero of=fill bs=1M count=64 2>/dev/null
         echo \"wrote $(stat -c %s fill) bytes\"
         exit 1",
    );
    let (out, code) = w.check_by(true, &filler, &["--disk", "16M"], "user-filler.sh");
    assert_eq!(code, Some(1), "{out}");
    let wrote: u64 = out
        .split("wrote ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{out}"));
    assert!(wrote <= 16 << 20, "{out}");
    let cage = &common::summary_of(&w.report)["cage"];
    assert_eq!(cage["user"], "check's own user", "{cage}");
    assert_eq!(cage["own_root"], true, "{cage}");
}

#[test]
fn a_lines_memory_and_process_count_are_its_own() {
    // A line's memory and processes are counted over all its processes, and apart from every
    // other line's, where the kernel gives check a control group for it (here, as root); an
    // ordinary user without a delegated subtree has none.
    if !rustix_is_root() || !common::line_groups_can_be_made() {
        eprintln!("skipped: check gets no control group for a line here (not root, or no cgroup)");
        return;
    }
    let Some(w) = world() else { return };
    // Four processes of 300 MiB each under --memory 1G: each is within the limit alone, not
    // together. The kernel ends one; the renderer fails, and the cause is the line's memory.
    let hungry = w.renderer(
        "hungry.sh",
        &format!(
            // Each tail holds its 300 MiB until the reader behind it wakes, so that all four
            // hold theirs at once however busy the machine.
            "set -o pipefail\n\
             for i in 1 2 3 4; do\n\
               head -c 300M /dev/zero | tail -c 300M | (sleep 3; cat >/dev/null) &\n\
             done\n\
             for p in $(jobs -p); do wait $p || exit 1; done\n{}",
            render()
        ),
    );
    // However slowly a busy machine pipes the four 300 MiB, the kernel's end of one comes
    // before the line's time (CI once took over 4 s to get there).
    let (out, _) = w.check(&hungry, &["--memory", "1G", "--timeout", "30"], "hungry.sh");
    assert_graded(
        &out,
        "ERROR  output2_01: out_of_memory: The renderer exited with status 1: its processes \
         together outgrew the line's memory (1 GiB), and the kernel ended one.",
    );
    let summary = common::summary_of(&w.report);
    assert_eq!(summary["cage"]["line_group"], true, "{summary}");
    assert_eq!(summary["cage"]["memory_ran_out"], true, "{summary}");
    // Two lines at once, 200 children each: as user nobody they shared one count of 256 (the
    // second line's forks failed); each line's group counts its own.
    let two = w.suite.join("COMMANDS.txt");
    let one = std::fs::read_to_string(&two).unwrap();
    std::fs::write(
        &two,
        format!("{one}{}", one.replace("output2_01", "again2_01")),
    )
    .unwrap();
    std::fs::copy(&w.reference, w.suite.join("reference/again2_01.png")).unwrap();
    let kids = w.renderer(
        "kids.sh",
        &format!("for i in $(seq 200); do sleep 2 & done\nwait\n{}", render()),
    );
    let (out, _) = w.check(&kids, &["--jobs", "2"], "kids.sh");
    assert_graded(&out, "2 passed, 0 failed");
}

/// A renderer kept in the machine's shared memory (a class copied there with
/// `TMPDIR=/dev/shm`) is bound into its own root like one kept anywhere else: /dev is made
/// anew there, not bound whole.
#[test]
fn a_renderer_kept_in_shared_memory_runs_from_there() {
    let Some(w) = world() else { return };
    let Ok(folder) = tempfile::tempdir_in("/dev/shm") else {
        return;
    };
    std::fs::set_permissions(folder.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(folder.path().join("table.txt"), "beside the program\n").unwrap();
    let tracer = folder.path().join("raytracer");
    std::fs::write(
        &tracer,
        format!(
            "#!/usr/bin/env bash\necho \"$(cat \"$(dirname \"$0\")/table.txt\")\" >&2\nexec {} \"$@\"\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&tracer, std::fs::Permissions::from_mode(0o755)).unwrap();
    let (out, code) = w.check(tracer.to_str().unwrap(), &[], "no-token-shared-memory");
    assert_eq!(code, Some(0), "{out}");
    let summary: serde_json::Value = common::summary_of(&w.report);
    let stderr = summary["images"][0]["stderr"].as_str().unwrap();
    assert!(stderr.contains("beside the program"), "{stderr}");
}
