//! Typed errors of the library. Every error knows whether it is the user's input (exit 2) or a failure (exit 1).

use std::path::{Path, PathBuf};

/// Result alias used across the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in scm.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad user input: names the file and the element at fault.
    #[error("{}: {element}: {message}", file.display())]
    Input {
        /// The file that holds the bad input.
        file: PathBuf,
        /// The element at fault (e.g. `<joint name="elbow">`, line 12).
        element: String,
        /// What is wrong with it.
        message: String,
    },
    /// An operating-system error while reading or writing a path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path being read or written.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A computation or an external program failed on input that passed validation.
    #[error("{context}: {message}")]
    Failed {
        /// What was being computed (e.g. `link "base": convex hull`).
        context: String,
        /// Why it failed.
        message: String,
    },
}

impl Error {
    /// A bad-input error for `file`, naming `element`.
    pub fn input(file: &Path, element: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Input {
            file: file.to_path_buf(),
            element: element.into(),
            message: message.into(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// The process exit code for this error: 2 for bad input, 1 for failures.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input { .. } => 2,
            Error::Io { .. } | Error::Failed { .. } => 1,
        }
    }
}
