//! A command given as one argument (`--renderer CMD`, `--build CMD`), split into words as the
//! system's own shell would: POSIX rules on Linux and macOS (quotes and backslashes, no
//! expansion), Windows' rules on Windows, where backslashes are path separators
//! (`--renderer "C:\Users\me\x64\Release\raytracer.exe"` keeps them).

/// The words of `command`, or `None` where its quotes are unbalanced (or, on Unix, it ends in
/// a backslash).
pub fn split(command: &str) -> Option<Vec<String>> {
    if cfg!(windows) {
        split_windows(command)
    } else {
        shlex::split(command)
    }
}

/// Windows' rules (those of `CommandLineToArgvW`): words are split at spaces and tabs outside
/// double quotes; a backslash is itself unless backslashes run up to a double quote, where
/// each pair is one backslash and an odd one makes the quote a plain character.
fn split_windows(command: &str) -> Option<Vec<String>> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut quoted = false;
    let mut chars = command.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' => {
                let mut backslashes = 1;
                while chars.peek() == Some(&'\\') {
                    chars.next();
                    backslashes += 1;
                }
                in_word = true;
                if chars.peek() == Some(&'"') {
                    word.extend(std::iter::repeat_n('\\', backslashes / 2));
                    if backslashes % 2 == 1 {
                        chars.next();
                        word.push('"');
                    }
                } else {
                    word.extend(std::iter::repeat_n('\\', backslashes));
                }
            }
            '"' => {
                in_word = true;
                quoted = !quoted;
            }
            ' ' | '\t' if !quoted => {
                if in_word {
                    words.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            c => {
                in_word = true;
                word.push(c);
            }
        }
    }
    if quoted {
        return None;
    }
    if in_word {
        words.push(word);
    }
    Some(words)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_paths_keep_their_backslashes_and_spaces() {
        assert_eq!(
            split_windows(r#""C:\Users\A Student\x64\Release\raytracer.exe" -v"#),
            Some(vec![
                r"C:\Users\A Student\x64\Release\raytracer.exe".to_string(),
                "-v".to_string()
            ])
        );
        assert_eq!(
            split_windows(r"D:\course\raytracer.exe"),
            Some(vec![r"D:\course\raytracer.exe".to_string()])
        );
    }

    #[test]
    fn windows_quotes_and_escaped_quotes() {
        assert_eq!(
            split_windows(r#"a "b c" d\"e f\\"g h""#),
            Some(vec![
                "a".to_string(),
                "b c".to_string(),
                "d\"e".to_string(),
                r"f\g h".to_string()
            ])
        );
        assert_eq!(split_windows(r#"a "b"#), None);
        assert_eq!(split_windows("  "), Some(vec![]));
        assert_eq!(split_windows(r#""""#), Some(vec![String::new()]));
    }

    #[test]
    fn unix_rules_elsewhere() {
        if !cfg!(windows) {
            assert_eq!(
                split("python3 'my tracer.py'"),
                Some(vec!["python3".to_string(), "my tracer.py".to_string()])
            );
        }
    }
}
