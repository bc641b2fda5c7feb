//! What a line's run that did not end well says to a student: its cause, how it ended (a
//! signal's name and meaning), the renderer's last words, and why a picture is missing.

use std::time::Duration;

use super::{Diagnosis, Ending, Limits, PictureKind, Ran};

/// Why a picture is missing, named as the command line names it (`-depth depth.tga`, never the
/// scratch path the renderer was given): where the renderer said something, its own words
/// are the likely reason; else where to look.
pub(super) fn missing_output(kind: PictureKind, file: &str, stderr: &str) -> String {
    let option = kind.option();
    let what = format!("The renderer ended without writing the picture of {option} {file}.");
    let words = said(stderr);
    if words.is_empty() {
        format!(
            "{what} Check that the file name after {option} is taken from the command line and \
             that the file is written before the program exits."
        )
    } else {
        format!("{what}{words} {OWN_MESSAGE_ADVICE}")
    }
}

/// The advice where a renderer's own message is the likely reason a picture is missing.
pub(super) const OWN_MESSAGE_ADVICE: &str = "Its own message is the likely reason: fix what it names (a \
     scene it cannot read, an option it does not know), then run the line by hand.";

/// How much of the renderer's last words an explanation quotes.
pub(super) const SAID_CHARS: usize = 300;

/// The renderer's last words on stderr, for a message: " It said: ..." (up to three lines), or
/// nothing.
pub(super) fn said(stderr: &str) -> String {
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    if lines.is_empty() {
        return String::new();
    }
    let last = lines[lines.len().saturating_sub(3)..].join(" / ");
    // A sentence, not a log: a progress bar redrawn with \r is one line of kilobytes.
    let count = last.chars().count();
    let last = if count > SAID_CHARS {
        let end: String = last.chars().skip(count - SAID_CHARS).collect();
        format!("…{end}")
    } else {
        last
    };
    format!(" It said: {last}")
}

/// What went wrong with a run that did not end well, its cause and what to tell the student;
/// `None` for a success.
pub(super) fn failed_run(ran: &Ran, limits: &Limits) -> Option<(Diagnosis, String)> {
    let likely_out_of_memory = || {
        ALLOCATION_FAILED
            .iter()
            .any(|marker| ran.stderr.contains(marker))
    };
    // The kernel's own count, where the line had a memory group of its own.
    let killed_for_memory = ran.confinement.as_ref().is_some_and(|c| c.memory_ran_out);
    let (cause, what) = match &ran.ending {
        Ending::Success => return None,
        Ending::Failed { .. } | Ending::Signaled { .. } if killed_for_memory => (
            Diagnosis::OUT_OF_MEMORY,
            format!(
                "The renderer {}: its processes together outgrew the line's memory ({}), and \
                 the kernel ended one.",
                how_it_ended(&ran.ending),
                bytes(limits.memory)
            ),
        ),
        Ending::Failed { .. } | Ending::Signaled { .. } if likely_out_of_memory() => (
            Diagnosis::OUT_OF_MEMORY,
            format!(
                "The renderer {}, most likely out of memory (its limit is {}).",
                how_it_ended(&ran.ending),
                bytes(limits.memory)
            ),
        ),
        Ending::Signaled { signal: SIGXFSZ }
        | Ending::Failed {
            status: SHELL_SIGXFSZ,
        } => (
            Diagnosis::OUTPUT_TOO_LARGE,
            format!(
                "The renderer was stopped by SIGXFSZ: it wrote past the size limit of {} a \
                 file.",
                bytes(limits.file_size)
            ),
        ),
        Ending::Failed { .. } | Ending::Signaled { .. } => (
            Diagnosis::CRASH,
            format!("The renderer {}.", how_it_ended(&ran.ending)),
        ),
        Ending::TimedOut(limit) => (
            Diagnosis::TIMED_OUT,
            format!(
                "The renderer did not finish within {} s and was stopped.",
                seconds(*limit)
            ),
        ),
        Ending::Interrupted => (
            Diagnosis::INTERRUPTED,
            "check was interrupted before this line ended.".to_string(),
        ),
        Ending::DeadlineCame => (
            Diagnosis::OVER_BUDGET,
            "check's --deadline came before this line was graded: it counts as failed.".to_string(),
        ),
        Ending::OverBudget(budget) => (
            Diagnosis::OVER_BUDGET,
            format!(
                "The renderer's time budget of {} s was spent before this line's turn: it was \
                 not run.",
                seconds(*budget)
            ),
        ),
        Ending::BudgetRanOut { budget, after } => (
            Diagnosis::OVER_BUDGET,
            format!(
                "The renderer's time budget of {} s ran out while this line ran: it was \
                 stopped after {} s.",
                seconds(*budget),
                seconds(*after)
            ),
        ),
        Ending::NotStarted(why) => (
            Diagnosis::CRASH,
            format!("The renderer could not be started: {why}."),
        ),
    };
    Some((
        cause,
        format!("{what}{} {}", said(&ran.stderr), cause.explanation()),
    ))
}

/// What programs print when an allocation fails: Rust, C++, Python, Java, C's perror.
pub(super) const ALLOCATION_FAILED: &[&str] = &[
    "memory allocation of",
    "std::bad_alloc",
    "MemoryError",
    "OutOfMemoryError",
    "Cannot allocate memory",
    "out of memory",
];

/// The signal a process gets for writing past RLIMIT_FSIZE.
pub(super) const SIGXFSZ: i32 = 25;

/// A script's exit status when a command of it was killed by SIGXFSZ (a shell's 128 + N).
pub(super) const SHELL_SIGXFSZ: i32 = 128 + SIGXFSZ;

/// "exited with status 3", "was killed by SIGSEGV (a segmentation fault: ...)".
pub(super) fn how_it_ended(ending: &Ending) -> String {
    match ending {
        Ending::Failed { status } => format!("exited with status {status}"),
        Ending::Signaled { signal } => format!("was killed by {}", signal_name(*signal)),
        _ => "ended".to_string(),
    }
}

/// A signal's name and what it usually means, for a student.
pub(super) fn signal_name(signal: i32) -> String {
    let (name, meaning) = match signal {
        4 => ("SIGILL", "an illegal instruction"),
        6 => (
            "SIGABRT",
            "an abort: a failed assertion or an uncaught exception",
        ),
        7 => ("SIGBUS", "a bus error"),
        8 => (
            "SIGFPE",
            "an arithmetic error, such as an integer division by zero",
        ),
        9 => ("SIGKILL", "killed from outside"),
        11 => (
            "SIGSEGV",
            "a segmentation fault: a bad pointer or an index out of bounds",
        ),
        15 => ("SIGTERM", "asked to stop"),
        24 => ("SIGXCPU", "its CPU time ran out"),
        25 => ("SIGXFSZ", "a file past the size limit"),
        _ => return format!("signal {signal}"),
    };
    format!("{name} ({meaning})")
}

/// A time as a person reads it: `30`, `29.9`, never `29.989`.
pub(super) fn seconds(time: Duration) -> String {
    let tenths = (time.as_secs_f64() * 10.0).round() / 10.0;
    if tenths.fract() == 0.0 {
        format!("{tenths:.0}")
    } else {
        format!("{tenths:.1}")
    }
}

/// `4 GiB`, `256 MiB`, as limits are given.
pub(super) fn bytes(n: u64) -> String {
    if n >= 1 << 30 && n.is_multiple_of(1 << 30) {
        format!("{} GiB", n >> 30)
    } else {
        format!("{} MiB", n >> 20)
    }
}
