//! Every link in the README and in docs/ leads somewhere: a file of the repository (and, with
//! a `#fragment`, a heading in it), or a public URL.

use std::path::{Path, PathBuf};

/// The anchors GitHub makes of a Markdown file's headings.
fn anchors(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.starts_with('#'))
        .map(|l| {
            l.trim_start_matches('#')
                .trim()
                .to_lowercase()
                .chars()
                .filter_map(|c| match c {
                    ' ' => Some('-'),
                    c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                    _ => None,
                })
                .collect()
        })
        .collect()
}

/// The targets of the `[text](target)` links of a Markdown text, outside code blocks.
fn links(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            found.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    found
}

#[test]
fn every_link_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for link in links(&text) {
            checked += 1;
            if link.starts_with("https://") || link.starts_with("http://") {
                continue;
            }
            let (path, fragment) = match link.split_once('#') {
                Some((path, fragment)) => (path, Some(fragment)),
                None => (link.as_str(), None),
            };
            let target = if path.is_empty() {
                file.clone()
            } else {
                file.parent().unwrap().join(path)
            };
            if !target.exists() {
                broken.push(format!("{}: {link}: no such file", file.display()));
                continue;
            }
            if let Some(fragment) = fragment {
                let text = std::fs::read_to_string(&target).unwrap_or_default();
                if !anchors(&text).iter().any(|a| a == fragment) {
                    broken.push(format!("{}: {link}: no such heading", file.display()));
                }
            }
        }
    }
    assert!(checked > 30, "only {checked} links found");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// The book's pages, as its table of contents (docs/SUMMARY.md) lists them.
fn summary_pages(root: &Path) -> Vec<String> {
    let summary = std::fs::read_to_string(root.join("docs/SUMMARY.md")).unwrap();
    links(&summary)
        .into_iter()
        .map(|l| l.split('#').next().unwrap().to_string())
        .collect()
}

#[test]
fn every_page_of_the_book_is_in_its_contents_and_reachable_from_the_readme() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let listed = summary_pages(root);
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.extension().is_some_and(|e| e == "md")
            && name != "SUMMARY.md"
            && !listed.contains(&name)
        {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "pages the book's contents leave out: {missing:?}"
    );
    // The README, the front door, links every page.
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let linked: Vec<String> = links(&readme)
        .into_iter()
        .map(|l| l.split('#').next().unwrap().to_string())
        .collect();
    let unlinked: Vec<&String> = listed
        .iter()
        .filter(|page| !linked.contains(&format!("docs/{page}")))
        .collect();
    assert!(
        unlinked.is_empty(),
        "pages the README does not link: {unlinked:?}"
    );
    // And stays a front door: one screen or two, not a manual.
    let lines = readme.lines().count();
    assert!(
        lines <= 130,
        "the README is {lines} lines: move the detail into the book"
    );
}
