//! The library's error type. Scene errors carry the file, line and field they are about.

use std::path::PathBuf;

/// Everything that can go wrong in the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file is malformed or describes something impossible.
    #[error("{file}:{line}: {field}: {message}")]
    Scene {
        file: String,
        line: usize,
        field: String,
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// An image could not be decoded or encoded.
    #[error("{}: {message}", path.display())]
    Image { path: PathBuf, message: String },
    /// A render setting is out of range (from the command line or the API).
    #[error("invalid setting {field}: {message}")]
    Setting {
        field: &'static str,
        message: String,
    },
    /// The GPU backend could not run.
    #[error("GPU backend: {0}")]
    Gpu(String),
}

/// Shorthand for results with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
