//! Reading a scene file from disk, shared by every importer: the whole file, with an
//! unreadable one reported as [`Error::Io`] naming it, and the directory its relative
//! references (meshes, buffers) resolve against.

use crate::error::{Error, Result};
use std::path::Path;

/// The directory relative paths inside `path` resolve against: its parent, or `.` for a bare
/// file name.
pub(crate) fn base_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// The text of `path` (UTF-8); failure is [`Error::Io`] naming the file.
pub(crate) fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|source| io_error(path, source))
}

/// The bytes of `path`; failure is [`Error::Io`] naming the file.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| io_error(path, source))
}

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}
