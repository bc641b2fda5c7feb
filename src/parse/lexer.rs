//! Splits scene text into whitespace-separated words, each with the line and column it starts at.
//!
//! The course's format has no comments and no punctuation of its own: braces are words like any
//! other, so a lexer only has to find the words and remember where they were.

use crate::error::Span;

/// One word of the text and where it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token<'a> {
    /// The word itself: never empty, and free of ASCII whitespace.
    pub text: &'a str,
    /// Where the word's first character is.
    pub span: Span,
}

/// Walks a text word by word, counting lines and columns on the way; a clone looks ahead.
#[derive(Clone)]
pub struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line: u32,
    column: u32,
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `text`.
    pub fn new(text: &'a str) -> Self {
        Lexer {
            text,
            pos: 0,
            line: 1,
            column: 1,
        }
    }

    /// Where the text ends: what a "found end of file" message points at.
    pub fn end(&mut self) -> Span {
        while self.next_token().is_some() {}
        Span::new(self.line, self.column)
    }

    /// The next word, or `None` once the text is used up.
    pub fn next_token(&mut self) -> Option<Token<'a>> {
        let bytes = self.text.as_bytes();
        while let Some(&b) = bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
                self.column = 1;
            } else {
                self.column += 1;
            }
            self.pos += 1;
        }
        if self.pos == bytes.len() {
            return None;
        }
        let start = self.pos;
        let span = Span::new(self.line, self.column);
        while let Some(&b) = bytes.get(self.pos) {
            if b.is_ascii_whitespace() {
                break;
            }
            // UTF-8 continuation bytes do not start a character.
            if b & 0xC0 != 0x80 {
                self.column += 1;
            }
            self.pos += 1;
        }
        Some(Token {
            text: &self.text[start..self.pos],
            span,
        })
    }
}

/// Where the first byte that is not UTF-8 sits, for the error that refuses such a file.
pub fn invalid_utf8_span(bytes: &[u8], valid_up_to: usize) -> Span {
    let before = &bytes[..valid_up_to];
    let line = before.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    Span::new(line, column_after(&before[line_start..]))
}

/// The column, counted from 1 in characters, just after `line_prefix` (UTF-8 bytes from the
/// start of a line; continuation bytes do not start a character).
pub(crate) fn column_after(line_prefix: &[u8]) -> u32 {
    line_prefix.iter().filter(|&&b| b & 0xC0 != 0x80).count() as u32 + 1
}

/// How a token is shown in a message: quoted, shortened, with control characters escaped.
pub fn describe(text: &str) -> String {
    const LIMIT: usize = 40;
    let mut shown: String = text.chars().take(LIMIT).collect();
    if shown.len() < text.len() {
        shown.push('…');
    }
    format!("'{}'", shown.escape_debug())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<(String, u32, u32)> {
        let mut lexer = Lexer::new(text);
        std::iter::from_fn(|| lexer.next_token())
            .map(|t| (t.text.to_string(), t.span.line, t.span.column))
            .collect()
    }

    #[test]
    fn tokens_carry_line_and_column() {
        assert_eq!(
            words("Group {\n\tnumObjects 1\r\n  Sphere{ }"),
            vec![
                ("Group".into(), 1, 1),
                ("{".into(), 1, 7),
                ("numObjects".into(), 2, 2),
                ("1".into(), 2, 13),
                ("Sphere{".into(), 3, 3),
                ("}".into(), 3, 11),
            ]
        );
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        assert_eq!(words("é x")[1], ("x".into(), 1, 3));
    }

    #[test]
    fn end_points_past_the_last_character() {
        let mut lexer = Lexer::new("a\nbc \n");
        assert_eq!(lexer.end(), Span::new(3, 1));
        let mut lexer = Lexer::new("a\nbc");
        assert_eq!(lexer.end(), Span::new(2, 3));
    }

    #[test]
    fn invalid_utf8_is_located() {
        // Owned bytes: rustc refuses from_utf8 on a literal it can see is invalid.
        let bytes = b"ab\ncd\xffe".to_vec();
        let err = std::str::from_utf8(&bytes).unwrap_err();
        assert_eq!(
            invalid_utf8_span(&bytes, err.valid_up_to()),
            Span::new(2, 3)
        );
    }

    #[test]
    fn long_and_odd_tokens_are_shortened_and_escaped() {
        assert_eq!(describe("a\u{7}b"), "'a\\u{7}b'");
        assert_eq!(describe(&"x".repeat(50)), format!("'{}…'", "x".repeat(40)));
    }
}
