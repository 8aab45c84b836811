//! Bounded reads of the files a scene names (scene files, meshes, glTF buffers and images,
//! textures). Each must be a regular file and is read no further than the size its metadata
//! gives when opened, so a device (`/dev/zero`), a FIFO or a file that keeps growing cannot
//! make a read endless or its buffer unbounded. Text must be UTF-8; the first bad byte is
//! reported with its line.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// Most bytes reserved up front (a larger file grows its buffer as it is read).
const RESERVE_BYTES: u64 = 64 << 20;

/// The bytes of the regular file `path`, at most as many as its size when opened.
///
/// A path that is not a regular file (a directory, device or FIFO) is an
/// [`io::ErrorKind::InvalidInput`] error saying so; it is never opened, so a FIFO cannot
/// block.
pub fn regular_file(path: &Path) -> io::Result<Vec<u8>> {
    let not_regular = || io::Error::new(io::ErrorKind::InvalidInput, "not a regular file");
    if !std::fs::metadata(path)?.is_file() {
        return Err(not_regular());
    }
    let file = File::open(path)?;
    // Checked again on the open file: the path may have been replaced in between.
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    let len = meta.len();
    let mut bytes = Vec::with_capacity(len.min(RESERVE_BYTES) as usize);
    file.take(len).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Where text stops being UTF-8: its first invalid byte.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BadUtf8 {
    /// 1-based line of the byte.
    pub line: usize,
    /// 0-based offset of the byte in the file.
    pub offset: usize,
}

impl std::fmt::Display for BadUtf8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "invalid UTF-8 at byte {}", self.offset)
    }
}

/// `bytes` as UTF-8 text, or where the first invalid byte is.
pub fn utf8(bytes: Vec<u8>) -> Result<String, BadUtf8> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let before = &e.as_bytes()[..offset];
        BadUtf8 {
            line: 1 + before.iter().filter(|&&b| b == b'\n').count(),
            offset,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_utf8_is_located() {
        let bad = utf8(b"ab\ncd\n\xffe".to_vec()).unwrap_err();
        assert_eq!(bad, BadUtf8 { line: 3, offset: 6 });
        assert_eq!(bad.to_string(), "invalid UTF-8 at byte 6");
        assert_eq!(utf8(b"ok\n".to_vec()).unwrap(), "ok\n");
    }

    #[test]
    fn devices_and_directories_are_refused() {
        for path in ["/dev/zero", "/"] {
            let e = regular_file(Path::new(path)).unwrap_err();
            assert_eq!(e.to_string(), "not a regular file", "{path}");
        }
    }
}
