//! Every console example of the README and the book is run, and prints what the page says it
//! prints: an example that drifts from the program fails here, not in a reader's terminal.
//!
//! A ```console block is a session: `$ raycast ARGS` runs the program built with these tests
//! (its output is what it writes on stdout, then what it writes on stderr), `$ cat FILE` followed by the file's lines makes that file. Commands run in
//! a scratch folder that holds links to the course's scenes and meshes; a path starting with
//! `../shared/` names the course's data wherever it is. Times, rates, the number of threads and
//! the kernels the machine has are the only words compared loosely. An output excerpt that is not a session is
//! a ```text block.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// A console block: where it is, and its lines.
struct Session {
    place: String,
    lines: Vec<String>,
}

/// The ```console blocks of a Markdown text.
fn sessions(file: &Path, text: &str) -> Vec<Session> {
    let mut found = Vec::new();
    let mut open: Option<Session> = None;
    for (number, line) in text.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match (&mut open, fence) {
            (None, true) if line.trim() == "```console" => {
                open = Some(Session {
                    place: format!("{}:{}", file.display(), number + 1),
                    lines: Vec::new(),
                });
            }
            (Some(_), true) => found.extend(open.take()),
            (Some(session), false) => session.lines.push(line.to_string()),
            _ => {}
        }
    }
    found
}

/// The Markdown files whose examples are run: the README and every page of the book.
fn pages() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut pages = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// A line with what changes from run to run (times, rates, the machine's kernels) put as `_`.
fn steady(line: &str) -> String {
    let words: Vec<&str> = line.split_whitespace().collect();
    let mut out: Vec<String> = Vec::with_capacity(words.len());
    for (k, word) in words.iter().enumerate() {
        let next = words.get(k + 1).copied().unwrap_or("");
        let number = word.trim_start_matches('(').parse::<f64>().is_ok() || word.contains(':');
        let varies = (number
            && (next == "ms"
                || next == "M"
                || next.starts_with("thread")
                || next.starts_with("kernels")))
            || (k > 0 && next.starts_with("kernels"))
            || (line.trim_start().starts_with("total time") && k == 2)
            || (line.trim_start().starts_with("rays per second") && k == 3);
        out.push(if varies { "_".into() } else { word.to_string() });
    }
    out.join(" ")
}

/// The words of a command line, as a shell splits them.
fn words(command: &str) -> Vec<String> {
    shlex_split(command).unwrap_or_else(|| panic!("cannot split: {command}"))
}

/// A POSIX shell's split of a line: quotes and backslashes, no expansion.
fn shlex_split(line: &str) -> Option<Vec<String>> {
    let mut words = Vec::new();
    let mut word: Option<String> = None;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            ' ' | '\t' => words.extend(word.take()),
            '\'' => {
                let w = word.get_or_insert_with(String::new);
                loop {
                    match chars.next()? {
                        '\'' => break,
                        c => w.push(c),
                    }
                }
            }
            '"' => {
                let w = word.get_or_insert_with(String::new);
                loop {
                    match chars.next()? {
                        '"' => break,
                        '\\' => w.push(chars.next()?),
                        c => w.push(c),
                    }
                }
            }
            '\\' => word.get_or_insert_with(String::new).push(chars.next()?),
            c => word.get_or_insert_with(String::new).push(c),
        }
    }
    words.extend(word);
    Some(words)
}

/// A scratch folder with links to every scene and mesh of the course.
fn scratch(shared: &Path) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for folder in ["conformance/scenes", "later-assignments/scenes", "meshes"] {
        let Ok(entries) = std::fs::read_dir(shared.join(folder)) else {
            continue;
        };
        for entry in entries {
            let entry = entry.unwrap();
            let link = dir.path().join(entry.file_name());
            if !link.exists() {
                #[cfg(unix)]
                std::os::unix::fs::symlink(entry.path(), link).unwrap();
                #[cfg(not(unix))]
                std::fs::copy(entry.path(), link).unwrap();
            }
        }
    }
    dir
}

/// Runs one session; the differences from the page, if any.
fn run(session: &Session, shared: &Path) -> Result<(), String> {
    let dir = scratch(shared);
    let mut lines = session.lines.iter().peekable();
    let first = lines.peek().map(|l| l.as_str()).unwrap_or("");
    if !first.starts_with("$ ") {
        return Err(format!(
            "{}: a console block must start with a command ('$ ...'); an excerpt of output is \
             a ```text block",
            session.place
        ));
    }
    while let Some(line) = lines.next() {
        let command = line
            .strip_prefix("$ ")
            .ok_or_else(|| format!("{}: output before any command: {line}", session.place))?;
        let mut expected = Vec::new();
        while let Some(next) = lines.peek() {
            if next.starts_with("$ ") {
                break;
            }
            expected.push(lines.next().unwrap().clone());
        }
        let words = words(command);
        match words.first().map(String::as_str) {
            Some("cat") if words.len() == 2 => {
                let file = dir.path().join(&words[1]);
                let _ = std::fs::remove_file(&file);
                std::fs::write(&file, expected.join("\n") + "\n").unwrap();
            }
            Some("raycast") => {
                let args: Vec<String> = words[1..]
                    .iter()
                    .map(|w| match w.strip_prefix("../shared/") {
                        Some(rest) => shared.join(rest).display().to_string(),
                        None => w.clone(),
                    })
                    .collect();
                let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
                    .args(&args)
                    .current_dir(dir.path())
                    .output()
                    .unwrap();
                // As a terminal shows them: what it wrote on stdout, then on stderr.
                let shown = [output.stdout, output.stderr].concat();
                let actual: Vec<String> = String::from_utf8_lossy(&shown)
                    .lines()
                    .map(steady)
                    .collect();
                let expected: Vec<String> = expected.iter().map(|l| steady(l)).collect();
                if actual != expected {
                    return Err(format!(
                        "{}: `{command}` prints\n{}\nbut the page says\n{}",
                        session.place,
                        actual.join("\n"),
                        expected.join("\n")
                    ));
                }
            }
            _ => {
                return Err(format!(
                    "{}: `{command}`: a session runs `raycast` and `cat FILE` only",
                    session.place
                ));
            }
        }
    }
    Ok(())
}

#[test]
fn every_console_example_prints_what_its_page_says() {
    let Some(conformance) = common::data_dir(
        "the console examples of the README and the book",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    ) else {
        return;
    };
    let shared = conformance.parent().unwrap().to_path_buf();
    let mut failures = Vec::new();
    let mut ran = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        for session in sessions(&page, &text) {
            ran += 1;
            if let Err(why) = run(&session, &shared) {
                failures.push(why);
            }
        }
    }
    assert!(ran >= 3, "only {ran} console examples were found");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn loose_words_are_only_times_rates_and_kernels() {
    assert_eq!(
        steady(
            "raycast: render          52.91 ms  (1048576 rays on 1 thread, 19.82 M rays/s, avx kernels)"
        ),
        "raycast: render _ ms (1048576 rays on _ thread, _ M rays/s, _ kernels)"
    );
    assert_eq!(
        steady("  total time                 0:00:01"),
        "total time _"
    );
    assert_eq!(
        steady("  rays per second            54602.0"),
        "rays per second _"
    );
    // Counts are compared exactly.
    assert_eq!(
        steady("  total intersections        109650"),
        "total intersections 109650"
    );
    assert_eq!(
        steady("raycast: memory: geometry 5.90 MiB, acceleration 0.99 MiB (4062 BVH nodes)"),
        "raycast: memory: geometry 5.90 MiB, acceleration 0.99 MiB (4062 BVH nodes)"
    );
}
