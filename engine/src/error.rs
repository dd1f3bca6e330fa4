//! The error type of the library: every variant says what failed and, where there is
//! one, which file.

use std::path::PathBuf;

/// Everything that can go wrong in Lumen that is not a bug.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said (part of the message, not a chained source,
        /// so that it is printed once).
        cause: std::io::Error,
    },
    /// A file was read but its content is wrong.
    #[error("{}: {message}", path.display())]
    BadFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// No GPU adapter matched the request.
    #[error("no usable GPU adapter: {0}")]
    NoAdapter(String),
    /// The GPU refused an operation (device creation, a pipeline, a lost device).
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The scene cannot be rendered as it is.
    #[error("scene: {0}")]
    Scene(String),
    /// An argument is out of range or malformed.
    #[error("{0}")]
    InvalidArgument(String),
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An [`Error::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, cause: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            cause,
        }
    }

    /// An [`Error::BadFile`] for `path`.
    pub fn bad_file(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::BadFile {
            path: path.into(),
            message: message.into(),
        }
    }
}
