//! `raycast check SUITE --renderer CMD ...` and `raycast diff A B [--out FILE]`.

use std::ffi::OsString;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use crate::check::class::ClassOptions;
use crate::check::{self, CheckOptions, Rule};
use crate::image_io::{self, ImageFormat};

/// The usage of the two subcommands.
pub const CHECK_USAGE: &str = "\
usage: raycast check SUITE --renderer CMD [--report DIR] [--tolerance LEVELS]
                     [--max-bad FRACTION] [--jobs N] [--timeout SECONDS] [--budget SECONDS]
                     [--deadline SECONDS] [--shard K/N] [--memory SIZE] [--disk SIZE]
                     [--allow-read PATH]... [--vary SEED]
                     [--keep-preview-options] [--no-cage]
       raycast check SUITE --class ROSTER --renderer CMD [--build CMD] [--build-timeout S]
                     [the options above]
       raycast check merge OUT DIR...
       raycast check cache [clear]
       raycast diff IMAGE REFERENCE [--out DIFF.png] [--tolerance LEVELS] [--max-bad FRACTION]

check runs every line of SUITE/COMMANDS.txt ('raytracer ARGS') as 'CMD ARGS' in a scratch
folder with copies of the files the line reads, and compares each image with its reference,
SUITE/reference/NAME.png or SUITE/reference/*/NAME.png (or, where the suite has none, with
raycast's own render of the same line). It names the likely cause of each mismatch, and with
--report writes DIR/summary.json, DIR/index.html and the grades for Gradescope
(gradescope.json), PrairieLearn (prairielearn.json), JUnit readers (junit.xml) and GitHub
Classroom (github-classroom.json), each picture worth the points SUITE/POINTS gives it (one by
default). CMD is the renderer's command, one argument split into words as the system's shell splits
them (POSIX quotes and backslashes, no expansion; on Windows, double quotes, backslashes kept):
--renderer \"python3 'my tracer.py'\". -gui,
-tessellation and -gouraud, which only drive the course's OpenGL preview, are dropped from the
lines (--keep-preview-options passes them on). Lines run --jobs at a time (default: one a
core), each handed out as a worker comes free; --shard K/N runs every Nth line from the Kth.
Each line's renderer runs caged (docs/check.md, \"The cage\"): as user nobody when check runs as
root, in a root of its own (the system's folders, its own program's folder and --allow-read
paths, read-only; its work and output folders and a private /tmp on --disk bytes, default 1G,
gone with the line), under Landlock, in network, IPC and PID namespaces of its own, with
--memory of address space a process (default 4G), files of at most 256 MiB, and everything it
started ended with it. Ctrl-C ends the renderers and writes what was graded,
marked partial (exit 130). Where nothing would keep the renderer from the references (no
Landlock, or a suite under a system folder such as /opt), check refuses to grade; --no-cage
grades anyway, for your own renderer on your own machine, and every report says so. --budget
bounds the renderer's lines and their diagnoses together (a platform's time limit): lines
start in the suite's order, those left when it is spent are not run, and every line is graded
before any is diagnosed. --deadline bounds the whole run,
diagnoses included (a platform's hard limit): check stops its work 5% before it (at least 1 s)
and writes its report with what it graded, as when Ctrl-C stops it, but exits 1, not 130.
--vary SEED grades on scenes nobody has seen: every line's scene is changed within bounds that
keep what the line tests (the camera orbits its subject by 1 to 3 degrees, directional lights
turn by 2 to 5, the colours of lights, background and materials are scaled by 0.8 to 1 a
channel), and each picture is compared with raycast's render of its varied scene; the report
keeps the varied scenes (DIR/varied/), and the same SEED makes them again. A renderer that prints
pictures it has memorised fails. In a class, each student gets a variation of their own, from
SEED and their name (their report gives it as the SEED that makes it again).
--class grades each folder of ROSTER as one student's submission: copied, built with --build
in its folder (caged, --build-timeout seconds, default 120), its renderer (CMD's first word
taken inside the submission) graded; the class's table on the terminal and in DIR/class.csv
and DIR/class.html, each student's report in DIR/STUDENT/; --budget is each student's.
--shard K/N grades every Nth student from the Kth; merge joins the shards' report folders
into the one report a single run makes. raycast's renders of the suite's lines, and of the
faults check simulates, are kept in RAYCAST_CACHE_DIR (default ~/.cache/raycast; off keeps
none), trimmed to RAYCAST_CACHE_SIZE (default 1G) after each run; 'check cache' shows it,
'check cache clear' empties it. Without a terminal, stderr hears every 5 s how far check is.
An image passes when at most FRACTION of its pixels (default 0.001) are off by more than
LEVELS (default 2). Exit status: 0 all pass (for a class: graded), 1 some fail, 2 a usage or
suite error.";

fn say(mut to: impl Write, text: &str) {
    let _ = writeln!(to, "{text}");
}

fn refuse(message: &str) -> ExitCode {
    super::refuse_with_hint(message, "raycast check -help")
}

/// The value after an option, or a message.
fn value(
    args: &mut impl Iterator<Item = OsString>,
    flag: &str,
    what: &str,
) -> Result<String, String> {
    match args.next().map(|a| a.to_string_lossy().into_owned()) {
        Some(v) => Ok(v),
        None => Err(format!(
            "{flag} needs {what}, found the end of the command line"
        )),
    }
}

fn number<T: std::str::FromStr>(text: &str, flag: &str, what: &str) -> Result<T, String> {
    text.parse()
        .map_err(|_| format!("{flag} needs {what}, found '{text}'"))
}

/// The shared grading options: `--tolerance` and `--max-bad`.
fn grading(flag: &str, text: &str, rule: &mut Rule) -> Result<(), String> {
    match flag {
        "--tolerance" => rule.tolerance = number(text, flag, "a number of levels from 0 to 255")?,
        _ => {
            let f: f64 = number(text, flag, "a fraction from 0 to 1")?;
            if !(0.0..=1.0).contains(&f) {
                return Err(format!(
                    "--max-bad needs a fraction from 0 to 1, found '{text}'"
                ));
            }
            rule.max_bad = f;
        }
    }
    Ok(())
}

/// A size in bytes: a number with K, M or G (powers of 1024) after it; at least 16 MiB.
fn size(text: &str) -> Option<u64> {
    let (number, unit) = text.split_at(text.find(|c: char| !c.is_ascii_digit())?);
    let shift = match unit {
        "K" | "k" => 10,
        "M" | "m" => 20,
        "G" | "g" => 30,
        _ => return None,
    };
    let bytes = number.parse::<u64>().ok()?.checked_shl(shift)?;
    (bytes >> shift == number.parse::<u64>().ok()? && bytes >= 16 << 20).then_some(bytes)
}

/// `K/N`, 1 <= K <= N.
fn shard(text: &str) -> Option<(usize, usize)> {
    let (k, n) = text.split_once('/')?;
    let (k, n): (usize, usize) = (k.parse().ok()?, n.parse().ok()?);
    (1..=n).contains(&k).then_some((k, n))
}

/// A number of seconds above 0, for `flag`.
fn seconds(text: &str, flag: &str) -> Result<Duration, String> {
    let s: f64 = number(text, flag, "a number of seconds above 0")?;
    if !(s > 0.0 && s.is_finite()) {
        return Err(format!(
            "{flag} needs a number of seconds above 0, found '{text}'"
        ));
    }
    Ok(Duration::from_secs_f64(s))
}

/// Reads `check`'s command line; `None` for `-help`. The class's options come with it when
/// `--class` is given.
fn parse_check_args(
    args: Vec<OsString>,
) -> Result<Option<(CheckOptions, Option<ClassOptions>)>, String> {
    let mut args = args.into_iter();
    let mut suite = None;
    let mut options = CheckOptions::new(PathBuf::new(), Vec::new());
    let mut class = ClassOptions {
        roster: PathBuf::new(),
        build: None,
        build_timeout: Duration::from_secs(120),
        budget: None,
        shard: None,
    };
    let mut roster = None;
    while let Some(arg) = args.next() {
        let text = arg.to_string_lossy().into_owned();
        match text.as_str() {
            "--renderer" => {
                let command = value(&mut args, "--renderer", "the renderer's command")?;
                options.renderer = super::words::split(&command).ok_or_else(|| {
                    format!("--renderer: unbalanced quotes or a trailing backslash in '{command}'")
                })?;
            }
            "--report" => options.report = Some(value(&mut args, "--report", "a folder")?.into()),
            "--tolerance" | "--max-bad" => {
                let v = value(&mut args, &text, "a number")?;
                grading(&text, &v, &mut options.rule)?;
            }
            "--jobs" => {
                let v = value(&mut args, "--jobs", "a number of jobs")?;
                options.jobs = number(&v, "--jobs", "a number of jobs from 1 to 1024")?;
                if !(1..=1024).contains(&options.jobs) {
                    return Err(format!(
                        "--jobs needs a number of jobs from 1 to 1024, found '{v}'"
                    ));
                }
            }
            "--timeout" => {
                let v = value(&mut args, "--timeout", "a number of seconds")?;
                let s: f64 = number(&v, "--timeout", "a number of seconds above 0")?;
                if !(s > 0.0 && s <= 86_400.0) {
                    return Err(format!(
                        "--timeout needs a number of seconds above 0, found '{v}'"
                    ));
                }
                options.timeout = Duration::from_secs_f64(s);
            }
            "--keep-preview-options" => options.keep_preview_options = true,
            "--vary" => {
                let v = value(&mut args, "--vary", "a seed")?;
                options.vary = Some(number(
                    &v,
                    "--vary",
                    "a seed, a whole number from 0 to 18446744073709551615",
                )?);
            }
            "--no-cage" => options.no_cage = true,
            "--class" => roster = Some(PathBuf::from(value(&mut args, "--class", "a folder")?)),
            "--build" => {
                let command = value(&mut args, "--build", "the build's command")?;
                class.build = Some(
                    super::words::split(&command)
                        .filter(|words| !words.is_empty())
                        .ok_or_else(|| {
                            format!("--build: no command, or unbalanced quotes in '{command}'")
                        })?,
                );
            }
            "--build-timeout" => {
                let v = value(&mut args, "--build-timeout", "a number of seconds")?;
                class.build_timeout = seconds(&v, "--build-timeout")?;
            }
            "--budget" => {
                let v = value(&mut args, "--budget", "a number of seconds")?;
                class.budget = Some(seconds(&v, "--budget")?);
            }
            "--deadline" => {
                let v = value(&mut args, "--deadline", "a number of seconds")?;
                options.deadline = Some(seconds(&v, "--deadline")?);
            }
            "--shard" => {
                let v = value(&mut args, "--shard", "K/N")?;
                options.shard = Some(shard(&v).ok_or_else(|| {
                    format!("--shard needs K/N with 1 <= K <= N (this run's share), found '{v}'")
                })?);
            }
            "--memory" => {
                let v = value(&mut args, "--memory", "a size such as 4G or 512M")?;
                options.limits.memory = size(&v).ok_or_else(|| {
                    format!("--memory needs a size such as 4G or 512M (at least 16M), found '{v}'")
                })?;
            }
            "--disk" => {
                let v = value(&mut args, "--disk", "a size such as 1G or 256M")?;
                options.limits.disk = size(&v).ok_or_else(|| {
                    format!("--disk needs a size such as 1G or 256M (at least 16M), found '{v}'")
                })?;
                options.limits.files = check::Limits::files_for(options.limits.disk);
            }
            "--allow-read" => {
                let v = value(&mut args, "--allow-read", "a file or folder")?;
                let path =
                    std::fs::canonicalize(&v).map_err(|e| format!("--allow-read: '{v}': {e}"))?;
                options.readable.push(path);
            }
            "-help" | "--help" | "-h" => return Ok(None),
            _ if text.starts_with('-') => {
                return Err(format!("check: unknown option '{text}'"));
            }
            _ if suite.is_none() => suite = Some(PathBuf::from(&text)),
            _ => {
                return Err(format!(
                    "check: unexpected argument '{text}' (one SUITE only)"
                ));
            }
        }
    }
    let Some(suite) = suite else {
        return Err("check needs a SUITE folder (with COMMANDS.txt and scenes/)".into());
    };
    if options.renderer.is_empty() {
        return Err("check needs --renderer CMD: which renderer should be graded?".into());
    }
    options.suite = suite;
    let Some(roster) = roster else {
        if class.build.is_some() {
            return Err("--build builds a class's submissions: give --class DIR too".into());
        }
        // One renderer's budget: its lines together, as a student's in a class.
        options.budget = class.budget;
        return Ok(Some((options, None)));
    };
    class.roster = roster;
    // A class is sharded by students; its every student runs every line.
    class.shard = options.shard.take();
    Ok(Some((options, Some(class))))
}

/// `raycast check ...` (arguments after `check`).
pub fn run_check(args: Vec<OsString>) -> ExitCode {
    if args.first().is_some_and(|a| a == "merge") {
        let words: Vec<String> = args[1..]
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        return super::class::run_merge(&words);
    }
    if args.first().is_some_and(|a| a == "cache") {
        let clear = match &args[1..] {
            [] => false,
            [word] if word == "clear" => true,
            _ => return refuse("check cache takes nothing, or 'clear'"),
        };
        return match check::cache_command(clear) {
            Ok(said) => {
                say(std::io::stdout(), &said);
                ExitCode::SUCCESS
            }
            Err(message) => {
                say(
                    std::io::stderr(),
                    &format!("raycast: check cache: {message}"),
                );
                ExitCode::from(1)
            }
        };
    }
    let cache_limit = match check::cache_limit() {
        Ok(limit) => limit,
        Err(message) => {
            say(std::io::stderr(), &format!("raycast: check: {message}"));
            return ExitCode::from(2);
        }
    };
    let options = match parse_check_args(args) {
        Ok(Some((options, class))) if options.no_cage => {
            say(
                std::io::stderr(),
                "raycast: check: --no-cage: renderers are graded without a wall known to keep \
                 them from the references; for your own renderer on your own machine only",
            );
            match class {
                Some(class) => {
                    let status = super::class::run_class(options, class);
                    check::trim_cache(cache_limit);
                    return status;
                }
                None => options,
            }
        }
        Ok(Some((options, Some(class)))) => {
            let status = super::class::run_class(options, class);
            check::trim_cache(cache_limit);
            return status;
        }
        Ok(Some((options, None))) => options,
        Ok(None) => {
            say(std::io::stdout(), CHECK_USAGE);
            return ExitCode::SUCCESS;
        }
        Err(message) => return refuse(&message),
    };
    let lines = check::Suite::read(&options.suite).map_or(0, |suite| suite.lines.len());
    let progress = std::sync::Arc::new(check::Progress::new(lines));
    let watcher = super::progress::Watcher::start(progress.clone());
    let stop = super::grades::stop_on_signals();
    super::grades::stop_at_deadline(stop, options.deadline);
    let checked = check::check(&options, &progress, stop);
    watcher.finish();
    let mut checked = match checked {
        Ok(checked) => checked,
        Err(message) => {
            say(std::io::stderr(), &format!("raycast: check: {message}"));
            return ExitCode::from(2);
        }
    };
    check::trim_cache(cache_limit);
    // The cage is reported in summary.json; the terminal hears of it only where part is missing.
    if let Some(confinement) = checked.confinement.as_ref().filter(|c| !c.is_whole()) {
        say(
            std::io::stderr(),
            &format!("raycast: check: warning: {}", confinement.summary()),
        );
    }
    for note in [&checked.cage_note, &checked.cleanup].into_iter().flatten() {
        say(
            std::io::stderr(),
            &format!("raycast: check: warning: {note}"),
        );
    }
    let previewing = check::preview_lines(&options);
    if previewing > 0 && !options.keep_preview_options {
        say(
            std::io::stderr(),
            &format!(
                "raycast: check: -gui, -tessellation and -gouraud were left out of {previewing} \
                 line{}: they only drive the course's OpenGL preview, and the image is the same \
                 (--keep-preview-options passes them on)",
                if previewing == 1 { "" } else { "s" }
            ),
        );
    }
    let groups = check::renderer_verdict(&mut checked.graded);
    let graded = &checked.graded;
    let mut out = std::io::stdout().lock();
    if let Some(variation) = &checked.variation {
        let _ = writeln!(out, "{}", variation.sentence());
    }
    let failed = super::grades::print_grades(&mut out, &groups, graded);
    if let Some(dir) = &options.report {
        if let Err(message) = check::write_report(&mut checked, &groups, options.rule) {
            say(
                std::io::stderr(),
                &format!("raycast: check: cannot write the report: {message}"),
            );
            return ExitCode::from(2);
        }
        let _ = writeln!(out, "report: {}", dir.join("index.html").display());
    }
    if checked.partial && stop.is_out_of_time() {
        let _ = writeln!(
            out,
            "check's --deadline came: the pictures not graded count as failed"
        );
        return ExitCode::from(1);
    }
    if checked.partial {
        let _ = writeln!(
            out,
            "check was interrupted: the pictures not graded count as failed"
        );
        return ExitCode::from(130);
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// `diff`'s command line: the two images, `--out`, and the rule.
struct DiffArgs {
    files: Vec<PathBuf>,
    out_file: Option<PathBuf>,
    rule: Rule,
}

fn parse_diff_args(args: Vec<OsString>) -> Result<DiffArgs, String> {
    let mut args = args.into_iter();
    let mut parsed = DiffArgs {
        files: Vec::new(),
        out_file: None,
        rule: Rule::COURSE,
    };
    while let Some(arg) = args.next() {
        let text = arg.to_string_lossy().into_owned();
        match text.as_str() {
            "--out" => {
                parsed.out_file = Some(PathBuf::from(value(&mut args, "--out", "an image file")?))
            }
            "--tolerance" | "--max-bad" => {
                let v = value(&mut args, &text, "a number")?;
                grading(&text, &v, &mut parsed.rule)?;
            }
            _ if text.starts_with('-') && text.len() > 1 => {
                return Err(format!("diff: unknown option '{text}'"));
            }
            _ => parsed.files.push(PathBuf::from(text)),
        }
    }
    Ok(parsed)
}

/// `raycast diff A B ...` (arguments after `diff`).
pub fn run_diff(args: Vec<OsString>) -> ExitCode {
    let DiffArgs {
        files,
        out_file,
        rule,
    } = match parse_diff_args(args) {
        Ok(parsed) => parsed,
        Err(message) => return refuse(&message),
    };
    let [actual, reference] = files.as_slice() else {
        return refuse("diff needs two images: yours, then the reference");
    };
    let read = |path: &PathBuf| check::read_image(path);
    let (a, r) = match (read(actual), read(reference)) {
        (Ok(a), Ok(r)) => (a, r),
        (Err(e), _) | (_, Err(e)) => {
            say(std::io::stderr(), &format!("raycast: diff: {e}"));
            return ExitCode::from(2);
        }
    };
    let tolerance = rule.tolerance;
    let judgement = check::judge(&a, &r, rule);
    let mut out = std::io::stdout().lock();
    let Some(bad_fraction) = judgement.bad_fraction else {
        let _ = writeln!(
            out,
            "FAIL: sizes differ ({}x{} against {}x{}): size: {}",
            a.width,
            a.height,
            r.width,
            r.height,
            check::Diagnosis::SIZE.explanation()
        );
        return ExitCode::from(1);
    };
    if let Some(path) = &out_file {
        let format = ImageFormat::from_path(path).unwrap_or(ImageFormat::Png);
        let heat = check::diagnose::heat_map(&a, &r, tolerance);
        if let Err(e) = std::fs::write(path, image_io::encode(&heat, format)) {
            say(
                std::io::stderr(),
                &format!("raycast: diff: {}: {e}", path.display()),
            );
            return ExitCode::from(2);
        }
    }
    let percent = 100.0 * bad_fraction;
    if judgement.pass {
        let _ = writeln!(
            out,
            "pass: {percent:.3}% of pixels off by more than {tolerance} levels"
        );
        return ExitCode::SUCCESS;
    }
    let codes: Vec<&str> = judgement.diagnoses.iter().map(|d| d.code()).collect();
    let _ = writeln!(
        out,
        "FAIL: {percent:.3}% of pixels off by more than {tolerance} levels: {}: {}",
        codes.join(", "),
        check::diagnose::explain(&judgement.diagnoses)
    );
    ExitCode::from(1)
}
