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

thread_local! {
    /// Whether a panic on this thread is being contained by [`contain_panics`], so the
    /// panic hook stays quiet.
    static CONTAINING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, turning a panic inside it into `Err` with the panic's message. For calls into
/// third-party parsers whose malformed-input paths may panic: the caller turns the message
/// into its usual one-line error. The panic prints nothing (a process-wide hook, installed
/// once, stays quiet for panics contained here and defers to the previous hook otherwise).
pub fn contain_panics<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !CONTAINING.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    let was = CONTAINING.with(|c| c.replace(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    CONTAINING.with(|c| c.set(was));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".into())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_contained_panic_is_an_error_with_its_message() {
        let v: Vec<u32> = Vec::new();
        let index = v.len() + 3;
        let e = contain_panics(|| v[index]).expect_err("panics");
        assert!(e.contains("index out of bounds"), "{e}");
        assert_eq!(contain_panics(|| 7).ok(), Some(7));
        // Nested: the outer guard still contains after an inner one returns.
        let outer = contain_panics(|| {
            let _ = contain_panics(|| 1);
            panic!("outer")
        });
        assert_eq!(outer.err().as_deref(), Some("outer"));
    }
}
