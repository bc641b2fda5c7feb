//! Errors a user can act on: every one names the file, and where it can, the line and column.

use std::fmt;
use std::path::{Path, PathBuf};

/// A place in a text file, both counted from 1; columns count characters, not bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Span {
    /// From 1.
    pub line: u32,
    /// From 1, in characters.
    pub column: u32,
}

impl Span {
    /// The place at `line` and `column`, both counted from 1.
    pub fn new(line: u32, column: u32) -> Self {
        Span { line, column }
    }
}

/// A problem at one place in an input file: `file:line:column: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// The file as messages name it: as the user gave it, or where a mesh was found.
    pub path: PathBuf,
    /// Where in the file: line and column, both from 1.
    pub span: Span,
    /// What is wrong, without the place: usually "expected …, found …".
    pub message: String,
}

impl Diagnostic {
    /// A diagnostic with a message of any form; [`Diagnostic::expected`] is the usual one.
    pub fn new(path: &Path, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            path: path.to_path_buf(),
            span,
            message: message.into(),
        }
    }

    /// The usual form: what the reader wanted at that place, and what it found there.
    pub fn expected(path: &Path, span: Span, expected: &str, found: &str) -> Self {
        Diagnostic::new(path, span, format!("expected {expected}, found {found}"))
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // A description built in code has no lines: its messages name the item instead.
        if self.span.line == 0 {
            return write!(f, "{}: {}", self.path.display(), self.message);
        }
        write!(
            f,
            "{}:{}:{}: {}",
            self.path.display(),
            self.span.line,
            self.span.column,
            self.message
        )
    }
}

impl std::error::Error for Diagnostic {}

/// Everything that can stop a render.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A malformed scene or mesh file, or a value it may not hold.
    #[error("{0}")]
    Input(#[from] Diagnostic),
    /// A file that could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// What could not be read, as messages name it.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// An image that could not be written.
    #[error("{}: cannot write image: {message}", path.display())]
    Write {
        /// Where the image was going, as messages name it.
        path: PathBuf,
        /// Why it could not be written, in words fit for the user.
        message: String,
    },
    /// A request that cannot be met, found before any work is done.
    #[error("{0}")]
    Refused(String),
    /// The preview could not be served (its port taken, say).
    #[error("raycast: preview: {0}")]
    Preview(String),
}
