//! PLY meshes (`type = "mesh"` with a `.ply` file, and the Mitsuba importer's `ply` shapes),
//! read with the `ply-rs-bw` crate: ASCII and binary (little and big endian).
//!
//! The `vertex` element gives the positions (`x`, `y`, `z`, float or double) and, when all
//! three are present, vertex normals (`nx`, `ny`, `nz`), which [`PlyMesh`] keeps as given
//! (`mesh_file.rs` checks them and makes the mesh smooth-shaded), and, when a pair is present,
//! texture coordinates: the first of [`UV_NAMES`] (`u v`, `texture_u texture_v`, `s t`,
//! `texture_s texture_t`; float or double, finite), as Mitsuba 3's `ply.cpp` names them, kept
//! as given (Mitsuba's PLY default `flip_tex_coords = false`). The `face` element's `vertex_indices` (or
//! `vertex_index`) lists, of any integer type, are polygons triangulated as fans
//! `(v0, v1, v2), (v0, v2, v3), ...` keeping the file's winding, as OBJ faces are: a face's
//! front normal is `cross(v1 - v0, v2 - v0)`. Other elements and properties are ignored.

pub mod attributes;
pub mod place;

use crate::error::Result;
use crate::importers::ply::attributes::{field, groups, PlyAttribute};
use crate::importers::ply::place::{element_line, row_place, size, Place};
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{
    DefaultElement, ElementDef, Encoding, Header, Property, PropertyType, ScalarType,
};
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// A triangle mesh read from a PLY file, in the file's coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// Vertex positions, all finite.
    pub positions: Vec<Vec3>,
    /// Triangles as indices into `positions` (polygons fan-triangulated), never empty.
    pub triangles: Vec<[u32; 3]>,
    /// Vertex normals as the file gives them (not normalised), one per position, when the
    /// `vertex` element has `nx`, `ny` and `nz`.
    pub normals: Option<Vec<Vec3>>,
    /// Texture coordinates as the file gives them, one per position, when the `vertex`
    /// element has a pair of `UV_NAMES`.
    pub uvs: Option<Vec<Vec2>>,
    /// The custom attributes ([`attributes`]): a `vertex_` one's rows per position, a
    /// `face_` one's per triangle (a polygon's triangles each get its row).
    pub attributes: Vec<PlyAttribute>,
}

/// The `vertex` property pairs read as texture coordinates, the first present winning.
pub const UV_NAMES: [[&str; 2]; 4] = [
    ["u", "v"],
    ["texture_u", "texture_v"],
    ["s", "t"],
    ["texture_s", "texture_t"],
];

impl PlyMesh {
    /// The triangles' corner positions, in the order of [`PlyMesh::triangles`].
    pub fn triangle_positions(&self) -> Vec<[Vec3; 3]> {
        let at = |i: u32| self.positions[i as usize];
        self.triangles
            .iter()
            .map(|t| [at(t[0]), at(t[1]), at(t[2])])
            .collect()
    }
}

/// Why a PLY file could not be read or used; shown as `FILE:LINE: what` for a problem in
/// the header or an ASCII row, `FILE: byte N: what` for one in a binary row, or `FILE: what`
/// when the file cannot be read.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {message}", path.display(), shown_place(*line, *byte))]
pub struct PlyError {
    /// The file.
    pub path: PathBuf,
    /// The 1-based line of the header entry or ASCII row at fault.
    pub line: Option<usize>,
    /// The 0-based offset of the binary row at fault (or of the payload's end, when it ends
    /// too early).
    pub byte: Option<usize>,
    /// What is wrong with it.
    pub message: String,
}

/// `:LINE`, `: byte N` or nothing.
fn shown_place(line: Option<usize>, byte: Option<usize>) -> String {
    match (line, byte) {
        (Some(l), _) => format!(":{l}"),
        (None, Some(b)) => format!(": byte {b}"),
        (None, None) => String::new(),
    }
}

/// Reads the PLY file at `path` (see the module documentation for what is used).
///
/// Errors: the file cannot be read or is not valid PLY (a bad header, a truncated or
/// malformed payload), the `vertex` or `face` element or a property is missing or of the
/// wrong type, a face has fewer than 3 vertices or refers to a missing vertex, a position
/// or texture coordinate is not finite, or there are no faces.
pub fn read_ply(path: &Path) -> Result<PlyMesh, PlyError> {
    read_ply_within(path, u64::MAX)
}

/// [`read_ply`], refusing a mesh of more than `room` triangles (what the scene's budget has
/// room for) before they are built: elements whose rows would take the parser more than
/// `room` triangles' bytes at the header line of the one that passes it, before the payload
/// is parsed, and polygons that triangulate to more triangles at the row that passes it.
pub(crate) fn read_ply_within(path: &Path, room: u64) -> Result<PlyMesh, PlyError> {
    let at = |place: Option<Place>, message: String| PlyError {
        path: path.to_path_buf(),
        line: match place {
            Some(Place::Line(l)) => Some(l),
            _ => None,
        },
        byte: match place {
            Some(Place::Byte(b)) => Some(b),
            _ => None,
        },
        message,
    };
    let bytes = crate::importers::read::regular_file(path)
        .map_err(|e| at(None, format!("cannot read: {e}")))?;
    let head_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .map_or(bytes.len(), |p| p + 10);
    if let Err(bad) = crate::importers::read::utf8(bytes[..head_end].to_vec()) {
        let message = format!("not a valid PLY file: the header has {bad}");
        return Err(at(Some(Place::Line(bad.line)), message));
    }
    let mut reader = Reader::new(Cursor::new(&bytes[..]));
    let parser = Parser::<DefaultElement>::new();
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| header_error(path, &e, &bytes))?;
    let (head, rest) = bytes.split_at(reader.get_ref().position() as usize);
    if matches!(header.encoding, Encoding::Ascii) {
        if let Err(bad) = crate::importers::read::utf8(bytes.to_vec()) {
            let message = format!("not a valid PLY file: {bad}");
            return Err(at(Some(Place::Line(bad.line)), message));
        }
    }
    check_counts(&header, head, rest)
        .map_err(|(line, message)| at(Some(Place::Line(line)), message))?;
    check_parse_room(
        &header,
        head,
        room.saturating_mul(crate::scene::cost::TRIANGLE_BYTES),
    )
    .map_err(|(line, message)| at(Some(Place::Line(line)), message))?;
    let elements = &header.elements;
    let line_of = |name: &str| Some(Place::Line(element_line(head, name)));
    let fail = |message: String| at(line_of("vertex"), message);
    let vertex_def = elements
        .get("vertex")
        .ok_or_else(|| fail("no `vertex` element".into()))?;
    for name in ["x", "y", "z"] {
        check_float(vertex_def, name).map_err(fail)?;
    }
    let has_normals = ["nx", "ny", "nz"]
        .iter()
        .all(|n| vertex_def.properties.contains_key(*n));
    if has_normals {
        for name in ["nx", "ny", "nz"] {
            check_float(vertex_def, name).map_err(fail)?;
        }
    }
    let uv_names = UV_NAMES
        .into_iter()
        .find(|pair| pair.iter().all(|n| vertex_def.properties.contains_key(*n)));
    for name in uv_names.iter().flatten() {
        check_float(vertex_def, name).map_err(fail)?;
    }
    let mut reserved = vec!["x", "y", "z", "nx", "ny", "nz", "u", "v"];
    reserved.extend(uv_names.iter().flatten());
    let vertex_groups = groups("vertex", vertex_def, &reserved);
    let fail = |message: String| at(line_of("face"), message);
    let face_def = elements
        .get("face")
        .ok_or_else(|| fail("no `face` element: the mesh has no triangles".into()))?;
    let list = ["vertex_indices", "vertex_index"]
        .into_iter()
        .find(|n| face_def.properties.contains_key(*n))
        .ok_or_else(|| fail("the `face` element has no `vertex_indices` list".into()))?;
    match &face_def.properties[list].data_type {
        PropertyType::List(count, item) if is_integer(count) && is_integer(item) => {}
        other => {
            return Err(fail(format!(
                "face property `{list}` is {}; expected a list of integers",
                type_name(other)
            )))
        }
    }

    let face_groups = groups("face", face_def, &[list]);
    // A binary payload has no lines: the parser's line is then the header's last.
    let ascii = matches!(header.encoding, Encoding::Ascii);
    let payload = parser.read_payload(&mut reader, &header).map_err(|e| {
        let mut e = invalid(path, &e, ascii);
        // A binary payload fails only by ending early: at the file's end.
        e.byte = (!ascii).then_some(bytes.len());
        e
    })?;
    let row = |name: &str, i: usize, message: String| {
        at(row_place(&header, head, rest, name, i), message)
    };

    let empty = Vec::new();
    let vertices = payload.get("vertex").unwrap_or(&empty);
    let faces = payload.get("face").unwrap_or(&empty);
    let mut positions = Vec::with_capacity(vertices.len());
    let mut normals = Vec::with_capacity(if has_normals { vertices.len() } else { 0 });
    let mut uvs = Vec::with_capacity(uv_names.map_or(0, |_| vertices.len()));
    let new = |(name, fields): &(String, Vec<String>)| PlyAttribute {
        name: name.clone(),
        dim: fields.len(),
        values: Vec::new(),
    };
    let mut attributes: Vec<PlyAttribute> = vertex_groups.iter().map(new).collect();
    for (i, v) in vertices.iter().enumerate() {
        let fail = |message: String| row("vertex", i, message);
        for (a, (_, fields)) in attributes.iter_mut().zip(&vertex_groups) {
            for name in fields {
                a.values
                    .push(field(v, name).map_err(|m| fail(format!("vertex {i}: {m}")))?);
            }
        }
        let p = vec3(v, ["x", "y", "z"]).map_err(fail)?;
        if !p.is_finite() {
            return Err(fail(format!("vertex {i} is not finite: {p}")));
        }
        positions.push(p);
        if has_normals {
            let n = vec3(v, ["nx", "ny", "nz"]).map_err(fail)?;
            if !n.is_finite() || n == Vec3::ZERO {
                return Err(fail(format!(
                    "vertex {i}: the normal (nx, ny, nz) {n} is zero or not finite"
                )));
            }
            normals.push(n);
        }
        if let Some([a, b]) = uv_names {
            let uv = vec3(v, [a, b, a]).map_err(fail)?.truncate();
            if !uv.is_finite() {
                return Err(fail(format!(
                    "vertex {i}: the texture coordinate ({a}, {b}) {uv} is not finite"
                )));
            }
            uvs.push(uv);
        }
    }
    let mut triangles = Vec::with_capacity(faces.len());
    let mut face_attributes: Vec<PlyAttribute> = face_groups.iter().map(new).collect();
    for (f, face) in faces.iter().enumerate() {
        let fail = |message: String| row("face", f, message);
        let mut rows = Vec::with_capacity(face_groups.len());
        for (_, fields) in &face_groups {
            let values: Result<Vec<f32>, String> = fields.iter().map(|n| field(face, n)).collect();
            rows.push(values.map_err(|m| fail(format!("face {f}: {m}")))?);
        }
        let indices = indices(face.get(list)).map_err(fail)?;
        if indices.len() < 3 {
            return Err(fail(format!(
                "face {f} has {} vertices; a face needs at least 3",
                indices.len()
            )));
        }
        let mut corner = Vec::with_capacity(indices.len());
        for i in indices {
            match u32::try_from(i) {
                Ok(u) if (u as usize) < positions.len() => corner.push(u),
                _ => {
                    return Err(fail(format!(
                        "face {f} refers to vertex {i}; the mesh has {} vertices",
                        positions.len()
                    )))
                }
            }
        }
        if (triangles.len() + corner.len() - 2) as u64 > room {
            return Err(fail(format!(
                "the faces so far make {} triangles, more than the {room} the scene's budget \
                 has room for",
                triangles.len() + corner.len() - 2
            )));
        }
        for k in 1..corner.len() - 1 {
            triangles.push([corner[0], corner[k], corner[k + 1]]);
            for (a, values) in face_attributes.iter_mut().zip(&rows) {
                a.values.extend(values);
            }
        }
    }
    if triangles.is_empty() {
        return Err(at(line_of("face"), "the mesh has no triangles".into()));
    }
    Ok(PlyMesh {
        positions,
        triangles,
        normals: has_normals.then_some(normals),
        uvs: uv_names.map(|_| uvs),
        attributes: attributes.into_iter().chain(face_attributes).collect(),
    })
}

/// A header the parser refused, as a [`PlyError`] with a line: the parser's, else (it read
/// past a mangled `end_header` into binary data, or the file ended) the line of the first
/// byte that is not UTF-8, or the file's last line.
fn header_error(path: &Path, e: &ParseError, bytes: &[u8]) -> PlyError {
    let mut error = invalid(path, e, true);
    if error.line.is_none() {
        let end = 1 + bytes.iter().filter(|&&b| b == b'\n').count();
        error.line = Some(match crate::importers::read::utf8(bytes.to_vec()) {
            Err(bad) => {
                error.message = format!("not a valid PLY file: the header has {bad}");
                bad.line
            }
            Ok(_) => end,
        });
    }
    error
}

/// A parser error as a one-line [`PlyError`] (the parser's first line, without its
/// `Line N:` prefix; the line is kept when `has_lines`).
fn invalid(path: &Path, e: &ParseError, has_lines: bool) -> PlyError {
    let shown = e.to_string();
    let mut lines = shown.lines();
    let first = lines.next().unwrap_or_default();
    let mut what = match first.split_once(": ") {
        Some((prefix, rest)) if prefix.starts_with("Line ") => rest,
        _ => first,
    }
    .trim_end_matches('.')
    .to_string();
    // The parser's causes, without debug dumps or its grammar's expected tokens.
    for cause in lines.filter_map(|l| l.trim().strip_prefix("Error: ")) {
        let cause = cause.split(": expected one of").next().unwrap_or_default();
        if !cause.contains('{') {
            what = format!("{what}: {}", cause.trim_end_matches('.'));
        }
    }
    PlyError {
        path: path.to_path_buf(),
        line: e.line().filter(|_| has_lines),
        byte: None,
        message: format!("not a valid PLY file: {what}"),
    }
}

/// Checks every binary element's row count against the bytes that follow the header
/// (`rest`), before the parser reads (and allocates) rows: a row takes at least the size of
/// its scalars and list counts, and is counted as at least a byte, so that a row of nothing
/// cannot be read 2^32 times. (An ASCII row is a line: the parser stops at the end of the
/// file, naming its line.) Problems are the (line in `head`, the header) of the element.
fn check_counts(header: &Header, head: &[u8], rest: &[u8]) -> Result<(), (usize, String)> {
    if matches!(header.encoding, Encoding::Ascii) {
        return Ok(());
    }
    let mut bytes = 0usize;
    for e in header.elements.values() {
        let row = e.properties.values().map(|p| match &p.data_type {
            PropertyType::Scalar(s) | PropertyType::List(s, _) => size(s),
        });
        let row = row.sum::<usize>().max(1);
        bytes = bytes.saturating_add(e.count.saturating_mul(row));
        let (name, count) = (&e.name, e.count);
        if bytes > rest.len() {
            let line = element_line(head, name);
            let message = format!(
                "element `{name}` has {count} rows: with the elements before it they need at \
                 least {bytes} bytes, but only {} bytes follow the header",
                rest.len()
            );
            return Err((line, message));
        }
    }
    Ok(())
}

/// Bytes the parser takes per row, and per property of a row: it keeps each row as a map of
/// its properties (measured: 450 bytes a vertex of three floats, 38 times the binary row).
const PARSED_ROW_BYTES: u64 = 128;
/// See [`PARSED_ROW_BYTES`].
const PARSED_PROPERTY_BYTES: u64 = 96;

/// Checks that the parser's rows fit in `room` bytes (what the scene's budget has room for)
/// before the payload is read: else the element that passes it, at its header line.
fn check_parse_room(header: &Header, head: &[u8], room: u64) -> Result<(), (usize, String)> {
    let mut bytes = 0u64;
    for e in header.elements.values() {
        let row = PARSED_ROW_BYTES + PARSED_PROPERTY_BYTES * e.properties.len() as u64;
        bytes = bytes.saturating_add((e.count as u64).saturating_mul(row));
        if bytes > room {
            let (name, count) = (&e.name, e.count);
            let message = format!(
                "element `{name}` has {count} rows: read, the elements so far take about {}, \
                 more than the {} the scene's budget has room for",
                crate::render::memory::size(bytes),
                crate::render::memory::size(room)
            );
            return Err((element_line(head, name), message));
        }
    }
    Ok(())
}

/// Checks that `element` has the scalar float or double property `name`.
fn check_float(element: &ElementDef, name: &str) -> Result<(), String> {
    match element.properties.get(name).map(|p| &p.data_type) {
        None => Err(format!("{} property `{name}` is missing", element.name)),
        Some(PropertyType::Scalar(ScalarType::Float | ScalarType::Double)) => Ok(()),
        Some(other) => Err(format!(
            "{} property `{name}` is {}; expected float or double",
            element.name,
            type_name(other)
        )),
    }
}

/// The three float or double properties `names` of vertex `v`.
fn vec3(v: &DefaultElement, names: [&str; 3]) -> Result<Vec3, String> {
    let mut out = [0.0f32; 3];
    for (o, name) in out.iter_mut().zip(names) {
        *o = match v.get(name) {
            Some(Property::Float(x)) => *x,
            Some(Property::Double(x)) => *x as f32,
            _ => return Err(format!("vertex property `{name}` is not a float or double")),
        };
    }
    Ok(Vec3::from_array(out))
}

/// The vertex indices of a face's index list, widened.
fn indices(list: Option<&Property>) -> Result<Vec<i64>, String> {
    fn wide<T: Copy + Into<i64>>(v: &[T]) -> Vec<i64> {
        v.iter().map(|&x| x.into()).collect()
    }
    Ok(match list {
        Some(Property::ListChar(v)) => wide(v),
        Some(Property::ListUChar(v)) => wide(v),
        Some(Property::ListShort(v)) => wide(v),
        Some(Property::ListUShort(v)) => wide(v),
        Some(Property::ListInt(v)) => wide(v),
        Some(Property::ListUInt(v)) => wide(v),
        _ => return Err("a face's vertex index list is not a list of integers".into()),
    })
}

fn is_integer(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

/// A property type as a PLY header writes it (`float`, `list uchar int`).
fn type_name(t: &PropertyType) -> String {
    let scalar = |s: &ScalarType| match s {
        ScalarType::Char => "char",
        ScalarType::UChar => "uchar",
        ScalarType::Short => "short",
        ScalarType::UShort => "ushort",
        ScalarType::Int => "int",
        ScalarType::UInt => "uint",
        ScalarType::Float => "float",
        ScalarType::Double => "double",
    };
    match t {
        PropertyType::Scalar(s) => scalar(s).to_string(),
        PropertyType::List(c, s) => format!("list {} {}", scalar(c), scalar(s)),
    }
}
