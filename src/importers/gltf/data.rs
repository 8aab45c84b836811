//! The binary data of a glTF file: its buffers (the GLB `BIN` chunk, base64 `data:` URIs or
//! files next to the glTF file), the accessors the importer reads (positions, normals,
//! texture coordinates and indices) and the encoded bytes of images. Every problem is a
//! message; the caller names the file and item.

use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::Accessor;
use std::path::Path;

/// The data of every buffer of `doc`, in order. Each buffer's size (the BIN chunk's, a file's
/// on disk, its declared `byteLength` for a `data:` URI) is added up before it is read: past
/// `budget` bytes (the scene's, `SceneBudgets::max_bytes`), however often the same file or
/// chunk is named, the buffer that passes it is an error.
pub(crate) fn load_buffers(
    doc: &gltf::Document,
    blob: Option<&[u8]>,
    base_dir: &Path,
    budget: u64,
) -> Result<Vec<Vec<u8>>, (String, String)> {
    let mut out = Vec::new();
    let mut total = 0u64;
    for buffer in doc.buffers() {
        let field = format!("buffers[{}]", buffer.index());
        let fail = |m: String| (field.clone(), m);
        let size = match buffer.source() {
            Source::Bin => blob.map_or(0, |b| b.len() as u64),
            Source::Uri(uri) if uri.starts_with("data:") => buffer.length() as u64,
            Source::Uri(uri) => std::fs::metadata(base_dir.join(uri)).map_or(0, |m| m.len()),
        };
        total = total.saturating_add(size);
        if total > budget {
            return Err(fail(format!(
                "the buffers so far take {total} bytes, more than the scene's budget of \
                 {budget} bytes"
            )));
        }
        let data = match buffer.source() {
            Source::Bin => blob
                .map(<[u8]>::to_vec)
                .ok_or_else(|| fail("refers to the GLB BIN chunk, which is missing".into()))?,
            Source::Uri(uri) if uri.starts_with("data:") => data_uri(uri).map_err(fail)?,
            Source::Uri(uri) => {
                let path = base_dir.join(uri);
                crate::importers::read::regular_file(&path)
                    // The uri as written (the message names the scene file and line already).
                    .map_err(|e| fail(format!("cannot read buffer `{uri}`: {e}")))?
            }
        };
        if data.len() < buffer.length() {
            let (n, m) = (data.len(), buffer.length());
            return Err(fail(format!("truncated: {n} bytes of {m}")));
        }
        out.push(data);
    }
    Ok(out)
}

/// The bytes of a base64 `data:` URI.
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (head, body) = uri.split_once(',').unwrap_or((uri, ""));
    if !head.ends_with(";base64") {
        return Err("a data URI must be base64".into());
    }
    base64(body)
}

/// The encoded bytes of `image` (a PNG or JPEG file, as the caller decodes them): a
/// `data:` URI, a file relative to `base_dir` (its name returned too, for messages), or a
/// bufferView, checked against its buffer.
pub(crate) fn image_bytes(
    image: &gltf::Image,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<(Vec<u8>, Option<std::path::PathBuf>), String> {
    match image.source() {
        gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
            Ok((data_uri(uri)?, None))
        }
        gltf::image::Source::Uri { uri, .. } => {
            let path = base_dir.join(uri);
            let bytes = crate::importers::read::regular_file(&path)
                .map_err(|e| format!("cannot read image {}: {e}", path.display()))?;
            Ok((bytes, Some(path)))
        }
        gltf::image::Source::View { view, .. } => {
            let data = buffers
                .get(view.buffer().index())
                .ok_or("refers to a missing buffer")?;
            let end = view.offset().checked_add(view.length());
            match end.and_then(|end| data.get(view.offset()..end)) {
                Some(bytes) => Ok((bytes.to_vec(), None)),
                None => Err(format!(
                    "bufferView {} runs past the end of its buffer",
                    view.index()
                )),
            }
        }
    }
}

/// Decodes standard base64 (padding optional, whitespace not allowed).
fn base64(text: &str) -> Result<Vec<u8>, String> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' | b'-' => Some(62),
        b'/' | b'_' => Some(63),
        _ => None,
    };
    let text = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0);
    for &c in text {
        let v = value(c).ok_or_else(|| format!("invalid base64 character {:?}", c as char))?;
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}

/// The bytes of each element of `accessor`, `size` bytes apiece, checked against its view
/// and buffer.
fn elements<'d>(
    accessor: &Accessor,
    buffers: &'d [Vec<u8>],
    size: usize,
) -> Result<Vec<&'d [u8]>, String> {
    let (data, start, stride) = placed(accessor, buffers, size)?;
    let count = accessor.count();
    Ok((0..count)
        .map(|i| &data[start + i * stride..start + i * stride + size])
        .collect())
}

/// Whether `accessor`'s elements (of its own size) are all in its view and buffer, so that
/// its count can be believed before its data is read.
pub(super) fn fits(accessor: &Accessor, buffers: &[Vec<u8>]) -> bool {
    placed(accessor, buffers, accessor.size()).is_ok()
}

/// `accessor`'s buffer, its first element's offset and the stride between elements of `size`
/// bytes, once every element is checked to lie in its view and the view in its buffer.
fn placed<'d>(
    accessor: &Accessor,
    buffers: &'d [Vec<u8>],
    size: usize,
) -> Result<(&'d [u8], usize, usize), String> {
    if accessor.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let Some(view) = accessor.view() else {
        return Err("has no bufferView".into());
    };
    let data = buffers
        .get(view.buffer().index())
        .ok_or("refers to a missing buffer")?;
    let stride = view.stride().unwrap_or(size).max(size);
    let count = accessor.count();
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > data.len()) {
        return Err(format!(
            "bufferView {} runs past the end of its buffer",
            view.index()
        ));
    }
    let needed = match count {
        0 => Some(0),
        n => (n - 1)
            .checked_mul(stride)
            .and_then(|s| s.checked_add(size))
            .and_then(|s| s.checked_add(accessor.offset())),
    };
    if needed.is_none_or(|n| n > view.length()) {
        return Err(format!(
            "{count} elements run past the end of bufferView {}",
            view.index()
        ));
    }
    Ok((data, view.offset() + accessor.offset(), stride))
}

/// The `POSITION` accessor's points: VEC3 of FLOAT, all finite.
pub(crate) fn read_positions(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
) -> Result<Vec<glam::Vec3>, String> {
    read_vec3(accessor, buffers, "POSITION", false)
}

/// The `NORMAL` accessor's vectors: VEC3 of FLOAT, all finite and non-zero.
pub(crate) fn read_normals(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
) -> Result<Vec<glam::Vec3>, String> {
    read_vec3(accessor, buffers, "NORMAL", true)
}

/// The VEC3-of-FLOAT attribute `name`, all finite (and non-zero with `nonzero`).
fn read_vec3(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    name: &str,
    nonzero: bool,
) -> Result<Vec<glam::Vec3>, String> {
    if accessor.dimensions() != Dimensions::Vec3 || accessor.data_type() != DataType::F32 {
        return Err(format!(
            "{name} must be VEC3 of FLOAT, not {:?} of {:?}",
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    // Sized from the elements, which are checked against the view: never the bare count.
    let elements = elements(accessor, buffers, 12)?;
    let mut points = Vec::with_capacity(elements.len());
    for e in elements {
        let f = |i: usize| f32::from_le_bytes([e[i], e[i + 1], e[i + 2], e[i + 3]]);
        let p = glam::Vec3::new(f(0), f(4), f(8));
        if !p.is_finite() {
            return Err(format!("{name} {} is not finite", points.len()));
        }
        if nonzero && p == glam::Vec3::ZERO {
            return Err(format!("{name} {} is zero", points.len()));
        }
        points.push(p);
    }
    Ok(points)
}

/// The `TANGENT` accessor's tangents: VEC4 of FLOAT, all finite (`w`, the bitangent's
/// sign, is read by its sign).
pub(crate) fn read_tangents(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
) -> Result<Vec<glam::Vec4>, String> {
    if accessor.dimensions() != Dimensions::Vec4 || accessor.data_type() != DataType::F32 {
        return Err(format!(
            "TANGENT must be VEC4 of FLOAT, not {:?} of {:?}",
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    let elements = elements(accessor, buffers, 16)?;
    let mut tangents = Vec::with_capacity(elements.len());
    for e in elements {
        let f = |i: usize| f32::from_le_bytes([e[i], e[i + 1], e[i + 2], e[i + 3]]);
        let t = glam::Vec4::new(f(0), f(4), f(8), f(12));
        if !t.is_finite() {
            return Err(format!("TANGENT {} is not finite", tangents.len()));
        }
        tangents.push(t);
    }
    Ok(tangents)
}

/// The texture coordinates of a `TEXCOORD_n` accessor (`name`): VEC2 of FLOAT, or of
/// normalized UNSIGNED_BYTE or UNSIGNED_SHORT (x / 255, x / 65535), as glTF allows; all
/// finite.
pub(crate) fn read_uvs(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    name: &str,
) -> Result<Vec<glam::Vec2>, String> {
    let (dims, ty) = (accessor.dimensions(), accessor.data_type());
    let size = match (dims, ty, accessor.normalized()) {
        (Dimensions::Vec2, DataType::F32, _) => 4,
        (Dimensions::Vec2, DataType::U16, true) => 2,
        (Dimensions::Vec2, DataType::U8, true) => 1,
        _ => {
            let normalized = if accessor.normalized() {
                "normalized "
            } else {
                ""
            };
            return Err(format!(
                "{name} must be VEC2 of FLOAT, or of normalized U8 or U16, not {dims:?} of \
                 {normalized}{ty:?}"
            ));
        }
    };
    let elements = elements(accessor, buffers, 2 * size)?;
    let mut uvs = Vec::with_capacity(elements.len());
    for e in elements {
        let c = |i: usize| match size {
            4 => f32::from_le_bytes([e[4 * i], e[4 * i + 1], e[4 * i + 2], e[4 * i + 3]]),
            2 => u16::from_le_bytes([e[2 * i], e[2 * i + 1]]) as f32 / 65535.0,
            _ => e[i] as f32 / 255.0,
        };
        let uv = glam::Vec2::new(c(0), c(1));
        if !uv.is_finite() {
            return Err(format!("{name} {} is not finite", uvs.len()));
        }
        uvs.push(uv);
    }
    Ok(uvs)
}

/// The indices of an `indices` accessor: SCALAR of UNSIGNED_BYTE, _SHORT or _INT.
pub(crate) fn read_indices(accessor: &Accessor, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    let size = match accessor.data_type() {
        DataType::U8 => 1,
        DataType::U16 => 2,
        DataType::U32 => 4,
        other => return Err(format!("indices must be unsigned integers, not {other:?}")),
    };
    if accessor.dimensions() != Dimensions::Scalar {
        let dims = accessor.dimensions();
        return Err(format!("indices must be SCALAR, not {dims:?}"));
    }
    let elements = elements(accessor, buffers, size)?;
    Ok(elements
        .iter()
        .map(|e| match size {
            1 => e[0] as u32,
            2 => u16::from_le_bytes([e[0], e[1]]) as u32,
            _ => u32::from_le_bytes([e[0], e[1], e[2], e[3]]),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_decodes() {
        assert_eq!(
            crate::importers::gltf::data::base64("aGVsbG8=").unwrap(),
            b"hello"
        );
        assert_eq!(
            crate::importers::gltf::data::base64("AAECAw").unwrap(),
            [0, 1, 2, 3]
        );
        assert!(crate::importers::gltf::data::base64("a b").is_err());
    }
}
