//! Errors a user can act on: every one names the file, and where it can, the line and column.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::parse::Span;

/// A problem at one place in an input file: `file:line:column: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    pub path: PathBuf,
    pub span: Span,
    pub message: String,
}

impl Diagnostic {
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
        path: PathBuf,
        source: std::io::Error,
    },
    /// An image that could not be written.
    #[error("{}: cannot write image: {message}", path.display())]
    Write { path: PathBuf, message: String },
    /// A request that cannot be met, found before any work is done.
    #[error("{0}")]
    Refused(String),
}
