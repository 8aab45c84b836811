//! Mitsuba's `serialized` meshes: the compressed binary format Mitsuba 3.9 reads
//! (`src/shapes/serialized.cpp`), versions 3 and 4.
//!
//! A file is one or more meshes, each a 4-byte header (`u16` format id `0x041C`, `u16`
//! version) and a zlib stream holding, little endian: a `u32` flag word (`0x1` normals,
//! `0x2` texture coordinates, `0x8` vertex colours, `0x2000` double precision), in version 4
//! the shape's NUL-terminated name, `u64` vertex and triangle counts, the vertex positions,
//! then the normals, texture coordinates and colours the flags announce (3, 2, 3 values per
//! vertex, `f32` or `f64`), then 3 `u32` vertex indices per triangle. The file ends in a
//! dictionary: the meshes' file offsets (`u64` in version 4, `u32` in version 3) and their
//! `u32` count, by which `shape_index` finds its mesh.
//!
//! Every problem is an error naming the file and where: a byte offset in the file for the
//! header and dictionary; for the rest, the byte where the mesh's zlib stream starts and the
//! offset in its decompressed data; and the field. The file must be a regular file (read whole, as PLY files
//! are). The counts are checked against the scene's budget before any
//! array is allocated, and the arrays grow only as their data arrives, so a hostile count
//! or a truncated file never allocates more than the file holds.

use crate::importers::mesh_file::MeshData;
use crate::importers::read::regular_file;
use crate::scene::cost::TRIANGLE_BYTES;
use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};
use std::io::{ErrorKind, Read};
use std::path::Path;

/// The format id of a serialized mesh's header.
const FORMAT_ID: u16 = 0x041C;
/// Flag: the vertices have normals.
const HAS_NORMALS: u32 = 0x0001;
/// Flag: the vertices have texture coordinates.
const HAS_TEXCOORDS: u32 = 0x0002;
/// Flag: the vertices have colours (read past, as Mitsuba does).
const HAS_COLORS: u32 = 0x0008;
/// Flag: the values are `f64` (else `f32`).
const DOUBLE_PRECISION: u32 = 0x2000;
/// The longest shape name read (Mitsuba's is unbounded; this bounds a hostile stream).
const MAX_NAME: u64 = 1 << 16;
/// Values read per chunk: arrays grow by this much as their data arrives.
const CHUNK: usize = 1 << 14;
/// Bytes a vertex may take while read (position, normal, uv), counted against the budget.
const VERTEX_BYTES: u64 = 32;

/// Reads mesh `shape_index` of the serialized file at `path`, in the file's coordinates:
/// its triangles, and the normals and texture coordinates it has (per corner), with the
/// vertex ids for normals computed from the faces. At most `room` triangles (and vertices
/// that fit in their bytes) are accepted. Errors name `path`.
pub(crate) fn read_serialized(
    path: &Path,
    shape_index: u32,
    room: u64,
) -> Result<MeshData, String> {
    let name = path.display();
    let bytes = regular_file(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let size = bytes.len() as u64;
    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
    if bytes.len() < 4 {
        return Err(format!(
            "{name}: byte {size}: the file ends in its 4-byte header"
        ));
    }
    let format = u16_at(0);
    if format != FORMAT_ID {
        return Err(format!(
            "{name}: byte 0: not a Mitsuba serialized mesh (format id 0x{format:04X}, \
             expected 0x{FORMAT_ID:04X})"
        ));
    }
    let version = u16_at(2);
    if version != 3 && version != 4 {
        return Err(format!(
            "{name}: byte 2: unsupported serialized version {version} (Mitsuba 3 reads 3 and 4)"
        ));
    }
    // The stream of mesh `shape_index` starts after its own 4-byte header.
    let start = if shape_index == 0 {
        4
    } else {
        let (at, offset) =
            dictionary_entry(&bytes, version, shape_index).map_err(|m| format!("{name}: {m}"))?;
        let start = offset.checked_add(4).filter(|s| *s <= size);
        start.ok_or_else(|| {
            format!(
                "{name}: byte {at}: the dictionary's offset of mesh {shape_index} ({offset}) is \
                 past the file's end ({size} bytes)"
            )
        })?
    };
    let mut stream = Stream {
        inner: ZlibDecoder::new(&bytes[start as usize..]),
        pos: 0,
    };
    read_mesh(&mut stream, version, room).map_err(|(at, field, what)| {
        format!(
            "{name}: byte {start} (mesh {shape_index}'s zlib stream), decompressed byte {at}: \
             {field}: {what}"
        )
    })
}

/// Where mesh `index`'s entry is in the dictionary at the end of the file `bytes`, and the
/// file offset it holds. The dictionary's `u32` count is last, before it the offsets (`u64`
/// in version 4, `u32` in version 3).
fn dictionary_entry(bytes: &[u8], version: u16, index: u32) -> Result<(u64, u64), String> {
    let size = bytes.len();
    if size < 8 {
        return Err(format!(
            "byte 0: a file of {size} bytes has no mesh dictionary"
        ));
    }
    let count = u32::from_le_bytes(bytes[size - 4..].try_into().unwrap());
    if index >= count {
        return Err(format!(
            "byte {}: shape_index {index} is out of range: the file's dictionary counts {count} \
             meshes",
            size - 4
        ));
    }
    let width: usize = if version == 4 { 8 } else { 4 };
    let back = (width as u64) * u64::from(count - index) + 4;
    let Some(at) = (size as u64).checked_sub(back).map(|a| a as usize) else {
        return Err(format!(
            "byte {}: the dictionary's {count} meshes do not fit in the file ({size} bytes)",
            size - 4
        ));
    };
    let mut offset = [0u8; 8];
    offset[..width].copy_from_slice(&bytes[at..at + width]);
    Ok((at as u64, u64::from_le_bytes(offset)))
}

/// A decompressing reader that counts the bytes it has given.
struct Stream<R> {
    inner: ZlibDecoder<R>,
    pos: u64,
}

/// A problem in a mesh's stream: where (a byte of the decompressed data), the field and
/// what.
type Problem = (u64, &'static str, String);

impl<R: Read> Stream<R> {
    /// Fills `buf`, or says why not (the stream ends, bad zlib data) for `field`.
    fn fill(&mut self, buf: &mut [u8], field: &'static str) -> Result<(), Problem> {
        let mut done = 0;
        while done < buf.len() {
            match self.inner.read(&mut buf[done..]) {
                Ok(0) => {
                    let what = "the compressed stream ends here".into();
                    return Err((self.pos, field, what));
                }
                Ok(n) => {
                    done += n;
                    self.pos += n as u64;
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err((self.pos, field, format!("bad zlib data: {e}"))),
            }
        }
        Ok(())
    }

    fn u32(&mut self, field: &'static str) -> Result<u32, Problem> {
        let mut b = [0u8; 4];
        self.fill(&mut b, field)?;
        Ok(u32::from_le_bytes(b))
    }

    fn u64(&mut self, field: &'static str) -> Result<u64, Problem> {
        let mut b = [0u8; 8];
        self.fill(&mut b, field)?;
        Ok(u64::from_le_bytes(b))
    }

    /// `count` values (`f64` when `double`, else `f32`) as `f32`, the array grown as they
    /// arrive.
    fn floats(
        &mut self,
        count: u64,
        double: bool,
        field: &'static str,
    ) -> Result<Vec<f32>, Problem> {
        let width = if double { 8 } else { 4 };
        let mut out = Vec::with_capacity((count as usize).min(CHUNK));
        let mut buf = vec![0u8; CHUNK * width];
        let mut left = count as usize;
        while left > 0 {
            let n = left.min(CHUNK);
            self.fill(&mut buf[..n * width], field)?;
            if double {
                let values = buf[..n * 8].chunks_exact(8);
                out.extend(values.map(|b| f64::from_le_bytes(b.try_into().unwrap()) as f32));
            } else {
                let values = buf[..n * 4].chunks_exact(4);
                out.extend(values.map(|b| f32::from_le_bytes(b.try_into().unwrap())));
            }
            left -= n;
        }
        Ok(out)
    }

    /// `count` `u32`s, the array grown as they arrive.
    fn indices(&mut self, count: u64, field: &'static str) -> Result<Vec<u32>, Problem> {
        let mut out = Vec::with_capacity((count as usize).min(CHUNK));
        let mut buf = vec![0u8; CHUNK * 4];
        let mut left = count as usize;
        while left > 0 {
            let n = left.min(CHUNK);
            self.fill(&mut buf[..n * 4], field)?;
            let values = buf[..n * 4].chunks_exact(4);
            out.extend(values.map(|b| u32::from_le_bytes(b.try_into().unwrap())));
            left -= n;
        }
        Ok(out)
    }
}

/// Reads one mesh's decompressed data (after its header) into per-corner arrays.
fn read_mesh<R: Read>(s: &mut Stream<R>, version: u16, room: u64) -> Result<MeshData, Problem> {
    let flags = s.u32("flags")?;
    if version == 4 {
        // The shape's name, NUL-terminated: not used.
        let at = s.pos;
        let mut b = [0u8; 1];
        loop {
            s.fill(&mut b, "name")?;
            if b[0] == 0 {
                break;
            }
            if s.pos - at > MAX_NAME {
                return Err((at, "name", format!("longer than {MAX_NAME} bytes")));
            }
        }
    }
    let counts_at = s.pos;
    let vertex_count = s.u64("vertex_count")?;
    let face_count = s.u64("face_count")?;
    if face_count > room {
        let message =
            format!("{face_count} triangles, more than the {room} the scene's budget has room for");
        return Err((counts_at + 8, "face_count", message));
    }
    if face_count == 0 {
        return Err((
            counts_at + 8,
            "face_count",
            "the mesh has no triangles".into(),
        ));
    }
    if vertex_count > room.saturating_mul(TRIANGLE_BYTES) / VERTEX_BYTES
        || vertex_count > u64::from(u32::MAX)
    {
        let message = format!(
            "{vertex_count} vertices, more than the scene's budget has room for ({room} \
             triangles' bytes)"
        );
        return Err((counts_at, "vertex_count", message));
    }
    let double = flags & DOUBLE_PRECISION != 0;
    let width = if double { 8 } else { 4 };
    // Reads `dim` values a vertex of `field`; the first vertex that fails `ok` is an error
    // at its own byte.
    let vectors = |s: &mut Stream<R>, dim: u64, field: &'static str, ok: fn(&[f32]) -> bool| {
        let at = s.pos;
        let values = s.floats(vertex_count * dim, double, field)?;
        match values.chunks_exact(dim as usize).position(|v| !ok(v)) {
            None => Ok(values),
            Some(i) => {
                let v = &values[i * dim as usize..][..dim as usize];
                let what = format!(
                    "vertex {i}: {v:?} is not {}",
                    if dim == 3 && field == "normals" {
                        "a finite, non-zero normal"
                    } else {
                        "finite"
                    }
                );
                Err((at + i as u64 * dim * width, field, what))
            }
        }
    };
    let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
    let positions = vectors(s, 3, "positions", finite)?;
    let positions: Vec<Vec3> = positions.chunks_exact(3).map(Vec3::from_slice).collect();
    let normals = if flags & HAS_NORMALS != 0 {
        let ok = |v: &[f32]| v.iter().all(|x| x.is_finite()) && v.iter().any(|x| *x != 0.0);
        let ns = vectors(s, 3, "normals", ok)?;
        Some(ns.chunks_exact(3).map(Vec3::from_slice).collect::<Vec<_>>())
    } else {
        None
    };
    let uvs = if flags & HAS_TEXCOORDS != 0 {
        let uvs = vectors(s, 2, "texcoords", finite)?;
        Some(
            uvs.chunks_exact(2)
                .map(Vec2::from_slice)
                .collect::<Vec<_>>(),
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        // Mitsuba 3.9 reads past the colours; so do we (in chunks, nothing kept).
        let mut left = vertex_count * 3;
        while left > 0 {
            let n = left.min(CHUNK as u64);
            s.floats(n, double, "colors")?;
            left -= n;
        }
    }
    let faces_at = s.pos;
    let faces = s.indices(face_count * 3, "faces")?;
    let faces: Vec<[u32; 3]> = faces.chunks_exact(3).map(|f| [f[0], f[1], f[2]]).collect();
    let bad = |f: &[u32; 3]| f.iter().any(|&v| u64::from(v) >= vertex_count);
    if let Some(i) = faces.iter().position(bad) {
        let message = format!(
            "triangle {i}: vertex indices {:?}, not all below the vertex count {vertex_count}",
            faces[i]
        );
        return Err((faces_at + 12 * i as u64, "faces", message));
    }
    let corners = |f: &[u32; 3]| f.map(|v| v as usize);
    Ok(MeshData {
        tris: faces
            .iter()
            .map(|f| corners(f).map(|v| positions[v]))
            .collect(),
        normals: normals.map(|ns| faces.iter().map(|f| corners(f).map(|v| ns[v])).collect()),
        uvs: uvs.map(|uvs| faces.iter().map(|f| corners(f).map(|v| uvs[v])).collect()),
        vertices: Some(faces),
        attributes: Vec::new(),
    })
}
