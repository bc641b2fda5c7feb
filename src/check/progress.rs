//! How far a check has come, counted as it goes: lines graded, then failing lines diagnosed
//! (every line is graded before any is diagnosed). Whoever shows it (a bar on a terminal, a
//! line every few seconds in a log) reads a [`Snapshot`].

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The counts, shared by the workers that grade and diagnose.
#[derive(Debug)]
pub struct Progress {
    lines: usize,
    graded: AtomicUsize,
    to_diagnose: AtomicUsize,
    diagnosed: AtomicUsize,
    started: Instant,
    /// When the last line of the suite was graded (a class's student's), where the diagnoses
    /// began: they are timed from there.
    diagnoses_began: Mutex<Option<(Instant, usize)>>,
    /// Whose renderer is graded, in a class.
    whose: Mutex<String>,
}

/// The counts at one moment.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Lines to grade, in all.
    pub lines: usize,
    /// Lines graded.
    pub graded: usize,
    /// Lines with a failing picture to diagnose, found so far.
    pub to_diagnose: usize,
    /// Lines diagnosed.
    pub diagnosed: usize,
    /// Since the check began.
    pub elapsed: Duration,
    /// The time left, estimated from the pace so far; `None` before there is a pace.
    pub left: Option<Duration>,
    /// Whose renderer is graded, in a class; empty otherwise.
    pub whose: String,
}

impl Progress {
    /// A check of `lines` lines (for a class, every student's).
    pub fn new(lines: usize) -> Progress {
        Progress {
            lines,
            graded: AtomicUsize::new(0),
            to_diagnose: AtomicUsize::new(0),
            diagnosed: AtomicUsize::new(0),
            started: Instant::now(),
            diagnoses_began: Mutex::new(None),
            whose: Mutex::new(String::new()),
        }
    }

    /// A line was run and graded.
    pub fn graded(&self) {
        self.graded.fetch_add(1, Ordering::Relaxed);
    }

    /// Every line of a renderer is graded; `lines` of them are to be diagnosed.
    pub fn diagnosing(&self, lines: usize) {
        self.to_diagnose.fetch_add(lines, Ordering::Relaxed);
        let mut began = self
            .diagnoses_began
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        *began = Some((Instant::now(), self.diagnosed.load(Ordering::Relaxed)));
    }

    /// A line was diagnosed.
    pub fn diagnosed(&self) {
        self.diagnosed.fetch_add(1, Ordering::Relaxed);
    }

    /// A class's next student.
    pub fn grading(&self, whose: &str) {
        *self.whose.lock().unwrap_or_else(|e| e.into_inner()) = whose.to_string();
    }

    /// The counts now.
    pub fn snapshot(&self) -> Snapshot {
        let graded = self.graded.load(Ordering::Relaxed);
        let to_diagnose = self.to_diagnose.load(Ordering::Relaxed);
        let diagnosed = self.diagnosed.load(Ordering::Relaxed);
        let elapsed = self.started.elapsed();
        let began = *self
            .diagnoses_began
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        let left = match began {
            // Diagnosing: at the pace of the diagnoses since they began.
            Some((at, before)) if graded >= self.lines && diagnosed > before => {
                let pace = at.elapsed().as_secs_f64() / (diagnosed - before) as f64;
                Some(Duration::from_secs_f64(
                    pace * to_diagnose.saturating_sub(diagnosed) as f64,
                ))
            }
            Some(_) if graded >= self.lines => None,
            // Grading: at the pace of the lines so far, diagnoses to come not counted.
            _ if graded > 0 => {
                let pace = elapsed.as_secs_f64() / graded as f64;
                Some(Duration::from_secs_f64(
                    pace * self.lines.saturating_sub(graded) as f64,
                ))
            }
            _ => None,
        };
        Snapshot {
            lines: self.lines,
            graded,
            to_diagnose,
            diagnosed,
            elapsed,
            left,
            whose: self.whose.lock().unwrap_or_else(|e| e.into_inner()).clone(),
        }
    }
}

impl Snapshot {
    /// One line of text: "40/168 lines graded, 3/12 diagnosed, 1m 05s, about 2m 10s left".
    pub fn said(&self) -> String {
        let mut said = format!("{}/{} lines graded", self.graded, self.lines);
        if self.to_diagnose > 0 {
            said += &format!(", {}/{} diagnosed", self.diagnosed, self.to_diagnose);
        }
        said += &format!(", {}", minutes(self.elapsed));
        if let Some(left) = self.left {
            said += &format!(", about {} left", minutes(left));
        }
        if !self.whose.is_empty() {
            said += &format!(" ({})", self.whose);
        }
        said
    }
}

/// "45s", "3m 05s", "1h 02m".
fn minutes(duration: Duration) -> String {
    let seconds = duration.as_secs();
    match seconds {
        0..60 => format!("{seconds}s"),
        60..3600 => format!("{}m {:02}s", seconds / 60, seconds % 60),
        _ => format!("{}h {:02}m", seconds / 3600, seconds / 60 % 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_snapshot_counts_and_says_what_is_done() {
        let progress = Progress::new(4);
        assert_eq!(progress.snapshot().left, None);
        progress.graded();
        progress.graded();
        let snapshot = progress.snapshot();
        assert_eq!((snapshot.graded, snapshot.diagnosed), (2, 0));
        assert!(snapshot.left.is_some(), "a pace once a line is graded");
        assert!(snapshot.said().starts_with("2/4 lines graded, "));
        progress.graded();
        progress.graded();
        progress.diagnosing(3);
        progress.diagnosed();
        progress.grading("ada");
        let said = progress.snapshot().said();
        assert!(
            said.starts_with("4/4 lines graded, 1/3 diagnosed, "),
            "{said}"
        );
        assert!(said.ends_with(" left (ada)"), "{said}");
    }

    #[test]
    fn durations_read_as_a_person_says_them() {
        assert_eq!(minutes(Duration::from_secs(45)), "45s");
        assert_eq!(minutes(Duration::from_secs(185)), "3m 05s");
        assert_eq!(minutes(Duration::from_secs(3720)), "1h 02m");
    }
}
