//! The likely causes first. A renderer usually has one or two bugs, and a class shares its
//! commonest ones: the faults that explained pictures so far in this run (one student's lines,
//! or a whole class's) are tried first on the next line. Where one of them draws the student's
//! picture itself, nothing can match it better, and the faults that match it as well are those
//! whose render of the line is alike (to the rule) to that fault's: which they are depends on
//! the line and the fault, not on the student, so the first full search that finds them keeps
//! them (beside the renders, in the cache), and every later picture of that line that the fault
//! draws itself is named by comparing those alone, without searching again.

use std::sync::Mutex;

/// The faults that explained pictures in this run, with how many.
static EXPLAINED: Mutex<Vec<(&'static str, usize)>> = Mutex::new(Vec::new());

/// The faults that explained pictures so far, the commonest first.
pub fn faults() -> Vec<&'static str> {
    let mut explained = EXPLAINED.lock().unwrap_or_else(|e| e.into_inner()).clone();
    // Stable: among equals, the first to explain.
    explained.sort_by_key(|&(_, count)| std::cmp::Reverse(count));
    explained.into_iter().map(|(name, _)| name).collect()
}

/// `fault` explained a picture.
pub fn explained(fault: &'static str) {
    let mut explained = EXPLAINED.lock().unwrap_or_else(|e| e.into_inner());
    match explained.iter_mut().find(|(name, _)| *name == fault) {
        Some((_, count)) => *count += 1,
        None => explained.push((fault, 1)),
    }
}
