//! Reading a scene file from disk, shared by every importer: the whole file (a regular file,
//! read up to its size by [`crate::importers::read`]), with an unreadable one reported as [`Error::Io`]
//! naming it and text that is not UTF-8 as [`Error::Scene`] at its first bad byte, and the
//! directory its relative references (meshes, buffers) resolve against.

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

/// The text of `path`; failure to read is [`Error::Io`] naming the file, invalid UTF-8 an
/// [`Error::Scene`] at the line of the first bad byte (field `text`).
pub(crate) fn read_text(path: &Path) -> Result<String> {
    crate::importers::read::utf8(read_bytes(path)?).map_err(|bad| Error::Scene {
        file: path.display().to_string(),
        line: bad.line,
        field: "text".into(),
        message: bad.to_string(),
    })
}

/// The bytes of `path`; failure is [`Error::Io`] naming the file.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    crate::importers::read::regular_file(path).map_err(|source| io_error(path, source))
}

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}
