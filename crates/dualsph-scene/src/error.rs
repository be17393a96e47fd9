//! The one error type of the crate.

use std::path::{Path, PathBuf};

/// Everything that can go wrong loading a scene. Each variant renders as one message that names
/// the file (and, for syntax problems, the line and column).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read scene file: {source}", path.display())]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The text is not a well-formed scene (syntax, unknown or missing field, wrong type,
    /// unknown plugin). `line` and `col` are 1-based and point at the start of the problem.
    #[error("{}:{line}:{col}: {message}", path.display())]
    Parse {
        /// The scene file (as given to the parser; used for messages only).
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
        /// What was found and what was expected.
        message: String,
    },
    /// The scene parsed but a value is meaningless (see [`crate::Scene::validate`]).
    #[error("{}: invalid value for `{field}`: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// Path of the offending value, e.g. `particles[1].spacing`, `domain.max`,
        /// `plugins[2] (Gravity)`.
        field: String,
        /// Why it is invalid.
        message: String,
    },
}

impl SceneError {
    /// Converts ron's error into [`SceneError::Parse`], positioned at the start of its span
    /// moved past any whitespace (ron sometimes reports the position before the blank that
    /// precedes the offending token).
    pub(crate) fn from_ron(path: &Path, text: &str, e: ron::error::SpannedError) -> Self {
        SceneError::parse_at(
            path,
            text,
            e.span.start.line,
            e.span.start.col,
            e.code.to_string(),
        )
    }

    /// [`SceneError::Parse`] at (`line`, `col`) moved past any whitespace.
    pub(crate) fn parse_at(
        path: &Path,
        text: &str,
        line: usize,
        col: usize,
        message: String,
    ) -> Self {
        let (line, col) = skip_blanks(text, line, col);
        SceneError::Parse {
            path: path.to_path_buf(),
            line,
            col,
            message,
        }
    }
}

/// The first non-whitespace position at or after (`line`, `col`) (1-based, columns in
/// characters); the input position itself when only whitespace follows or it is out of range.
fn skip_blanks(text: &str, line: usize, col: usize) -> (usize, usize) {
    let (mut l, mut c) = (1, 1);
    for ch in text.chars() {
        if (l, c) >= (line, col) && !ch.is_whitespace() {
            return (l, c);
        }
        if ch == '\n' {
            (l, c) = (l + 1, 1);
        } else {
            c += 1;
        }
    }
    (line, col)
}

/// A validation failure before the file path is attached.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Problem {
    pub field: String,
    pub message: String,
}

impl Problem {
    pub(crate) fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Problem {
            field: field.into(),
            message: message.into(),
        }
    }

    pub(crate) fn into_error(self, path: &Path) -> SceneError {
        SceneError::Invalid {
            path: path.to_path_buf(),
            field: self.field,
            message: self.message,
        }
    }
}
