//! What renderers print and what submissions are named is data, never control: the one home of
//! how such text is made safe to show (on a terminal, in a line of a table, in a page) and how
//! much of it is kept.

/// How many lines of a renderer's output a report keeps for a picture.
pub const TAIL_LINES: usize = 20;

/// How many characters of a renderer's output a report keeps for a picture: a progress bar
/// redrawn with `\r` is one line of tens of kilobytes.
pub const TAIL_CHARS: usize = 2000;

/// `text` with every control character, escape and invisible reordering mark written out as
/// a visible escape (`\n`, `\x1b`, `\u{202e}`): a terminal shows it and obeys none of it, and
/// it stays on one line.
pub fn visible(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => {
                out.push_str(&format!("\\x{:02x}", c as u32));
            }
            c if is_hidden(c) => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// Characters a terminal or a page acts on or hides rather than shows: C1 controls (`\u{9b}` is
/// a terminal's CSI), bidirectional overrides and isolates (which reorder what follows), and
/// the line and paragraph separators.
fn is_hidden(c: char) -> bool {
    matches!(c as u32, 0x80..=0x9f | 0x202a..=0x202e | 0x2066..=0x2069 | 0x2028 | 0x2029 | 0x200e | 0x200f | 0x061c)
}

/// Text made safe to stand in HTML, in an element or an attribute.
pub fn html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The end of what a renderer printed, as a report keeps it: its last [`TAIL_LINES`] lines, at
/// most [`TAIL_CHARS`] characters of them, with a note where more was cut.
pub fn tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let kept = lines[lines.len().saturating_sub(TAIL_LINES)..].join("\n");
    let count = kept.chars().count();
    if count <= TAIL_CHARS {
        return kept;
    }
    let cut: String = kept.chars().skip(count - TAIL_CHARS).collect();
    format!(
        "[cut: the last {TAIL_CHARS} of {} characters]\n{cut}",
        text.chars().count()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_is_escaped_for_a_page() {
        assert_eq!(
            html("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
    }

    #[test]
    fn escapes_are_shown_not_obeyed() {
        // Erase the line, set the title, write the clipboard (OSC 52), a C1 CSI, a reversal.
        let hostile =
            "\x1b[2K\r0 failed\x1b]0;title\x07\x1b]52;c;cm0gLXJm\x07\u{9b}31m\u{202e}txt.exe\n";
        assert_eq!(
            visible(hostile),
            "\\x1b[2K\\r0 failed\\x1b]0;title\\x07\\x1b]52;c;cm0gLXJm\\x07\\u{9b}31m\\u{202e}txt.exe\\n"
        );
        assert_eq!(visible("plain text, é ü 漢"), "plain text, é ü 漢");
    }

    #[test]
    fn a_tail_keeps_the_last_lines_and_characters_and_says_what_it_cut() {
        let many: String = (0..50).map(|k| format!("line {k}\n")).collect();
        let kept = tail(&many);
        assert!(
            kept.starts_with("line 30\n") && kept.ends_with("line 49"),
            "{kept}"
        );
        // A progress bar redrawn with \r: one line of 64 KiB.
        let bar = "\r 50% [=====     ]".repeat(4000);
        let kept = tail(&bar);
        assert!(kept.starts_with(&format!(
            "[cut: the last {TAIL_CHARS} of {} characters]\n",
            bar.chars().count()
        )));
        assert_eq!(kept.lines().nth(1).unwrap().chars().count(), TAIL_CHARS);
        assert_eq!(tail("short"), "short");
    }
}
