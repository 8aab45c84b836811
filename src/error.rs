//! The library's error type. Scene errors carry the file, line and field they are about.
//! What an error echoes of the user's input (a file's name, a field path, an id or a value
//! quoted in the message) is written with its control characters escaped
//! ([`crate::escape`]), so every message is one line of plain text.

use crate::escape::escape;
use std::path::{Path, PathBuf};

/// Everything that can go wrong in the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file is malformed or describes something impossible.
    #[error("{}:{line}: {}: {}", escape(.file), escape(.field), escape(.message))]
    Scene {
        /// The file, as given to the loader.
        file: String,
        /// 1-based line of the offending value (of its table for a missing key).
        line: usize,
        /// Field path, e.g. `shapes[3].radius`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", shown(.path))]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// An image could not be decoded or encoded.
    #[error("{}: {}", shown(.path), escape(.message))]
    Image {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A render setting is out of range (from the command line or the API).
    #[error("invalid setting {field}: {}", escape(.message))]
    Setting {
        /// The setting, by its command-line flag (`spp`, `shadow-samples`).
        field: &'static str,
        /// What is wrong (for a value out of range, the range of `settings::SETTINGS`).
        message: String,
    },
    /// A scene with no light and no environment (it would render black).
    #[error("{}: the scene has no light (add one, or give --env)", shown(.file))]
    NoLight {
        /// The scene file.
        file: PathBuf,
    },
    /// A scene uses what the chosen backend cannot render yet (media on the GPU backend).
    #[error("{}", escape(.0))]
    Unsupported(String),
    /// Two images that must have the same size do not.
    #[error("{0}")]
    Sizes(String),
    /// The render would need more memory than this machine has available (`budget`).
    #[error("{0}")]
    Memory(String),
    /// The GPU backend could not run.
    #[error("GPU backend: {0}")]
    Gpu(String),
}

/// A path as messages show it: displayed, its control characters escaped.
fn shown(path: &Path) -> String {
    escape(&path.display().to_string()).into_owned()
}

/// Shorthand for results with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
