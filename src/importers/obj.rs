//! Wavefront OBJ meshes (`type = "mesh"`), read with tobj and fed to the [`SceneBuilder`].
//!
//! Vertex positions, faces, vertex normals (`vn`, named by face corners `v//vn` or
//! `v/vt/vn`) and texture coordinates (`vt`, named by corners `v/vt` or `v/vt/vn`) are used:
//! materials, points and lines are ignored. The mesh has normals (smooth shading) when every
//! face corner names one; otherwise they are all ignored (flat). It has texture coordinates
//! when any corner names a `vt`; a corner that names none then gets uv (0, 0). The uvs are
//! the file's `(u, v)` (a missing `v` is 0), v flipped to `1 - v` when the caller asks
//! (Mitsuba's `flip_tex_coords`, applied to each `vt` record as its `obj.cpp` does, so a
//! corner without one stays (0, 0); see `mesh_file.rs`). Polygons are triangulated as fans
//! `(v0, v1, v2), (v0, v2, v3), ...`, keeping the file's winding, so a face's front normal is
//! `cross(v1 - v0, v2 - v0)`.
//!
//! [`SceneBuilder`]: crate::scene::SceneBuilder

use crate::scene::VertexNormals;
use glam::{Vec2, Vec3};
use std::io::BufReader;
use std::path::Path;

/// The triangles of an OBJ file, their vertex normals when every corner names one (as the
/// file gives them, not normalised) and their texture coordinates when any corner names one
/// (v flipped when asked).
pub(crate) struct ObjTriangles {
    /// The triangles, in the file's winding.
    pub tris: Vec<[Vec3; 3]>,
    /// The corners' normals, parallel to `tris`.
    pub normals: Option<Vec<VertexNormals>>,
    /// The corners' `vt` coordinates, parallel to `tris`.
    pub uvs: Option<Vec<[Vec2; 3]>>,
    /// The corners' vertices (tobj's single index: one per `v`, or per `v//vn` pair when
    /// the mesh has normals), parallel to `tris`.
    pub vertices: Vec<[u32; 3]>,
}

/// Loads the triangles of the OBJ file at `path` (in the file's coordinates).
///
/// Errors are messages naming the resolved path and, for a malformed record, its line
/// (`PATH:LINE: message`): the file cannot be read, a record does not parse, a face refers
/// to a missing vertex or normal, a vertex is not finite, a normal (`vn`) is zero or not
/// finite, a `vt` is malformed or not finite, a corner names a missing `vt`, or there are no
/// triangles (at the file's last line), or more than `room` (at the face that passes it).
pub(crate) fn load_triangles(path: &Path, flip_v: bool, room: u64) -> Result<ObjTriangles, String> {
    let bytes = crate::importers::read::regular_file(path)
        .map_err(|e| format!("cannot read mesh {}: {e}", path.display()))?;
    let text = crate::importers::read::utf8(bytes)
        .map_err(|bad| format!("{}:{}: {bad}", path.display(), bad.line))?;
    match parse_triangles(&text, flip_v, room) {
        Ok(obj) if obj.tris.is_empty() => Err(format!(
            "{}:{}: the mesh has no triangles",
            path.display(),
            text.lines().count().max(1)
        )),
        Ok(obj) => Ok(obj),
        Err((0, e)) => Err(format!("{}: {e}", path.display())),
        Err((line, e)) => Err(format!("{}:{line}: {e}", path.display())),
    }
}

/// Parses OBJ `text` into triangles; see [`load_triangles`]. Errors carry the 1-based line
/// of the record (0: none).
fn parse_triangles(text: &str, flip_v: bool, room: u64) -> Result<ObjTriangles, (usize, String)> {
    let kept = strip_attributes(text, flip_v, room)?;
    let mut reader = BufReader::new(kept.as_bytes());
    // Single index, triangulated (fans), points and lines ignored. Material libraries are
    // never opened: materials come from the scene file.
    let no_mtl = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let (models, _) = tobj::load_obj_buf(&mut reader, &tobj::GPU_LOAD_OPTIONS, no_mtl)
        .map_err(|e| (0, format!("OBJ parse error: {e}")))?;

    let mut triangles = Vec::new();
    let mut normals = Vec::new();
    let mut vertices = Vec::new();
    // One model (the grouping records are stripped); offsets keep indices apart if not.
    let mut first = 0u32;
    for model in &models {
        let mesh = &model.mesh;
        let vertex = |i: u32| -> Result<Vec3, String> {
            let i = i as usize;
            let p = mesh
                .positions
                .get(3 * i..3 * i + 3)
                .ok_or_else(|| "OBJ face refers to a missing vertex".to_string())?;
            let p = Vec3::new(p[0], p[1], p[2]);
            if !p.is_finite() {
                return Err(format!("OBJ vertex {p} is not finite"));
            }
            Ok(p)
        };
        let normal = |i: u32| -> Result<Vec3, String> {
            let i = i as usize;
            let n = mesh
                .normals
                .get(3 * i..3 * i + 3)
                .ok_or_else(|| "OBJ face refers to a missing normal (vn)".to_string())?;
            let n = Vec3::new(n[0], n[1], n[2]);
            if !n.is_finite() || n == Vec3::ZERO {
                return Err(format!("OBJ normal (vn) {n} is zero or not finite"));
            }
            Ok(n)
        };
        for face in mesh.indices.chunks_exact(3) {
            let v = |k: usize| vertex(face[k]).map_err(|e| (0, e));
            triangles.push([v(0)?, v(1)?, v(2)?]);
            vertices.push([face[0], face[1], face[2]].map(|i| first.saturating_add(i)));
            if kept.has_normals {
                let n = |k: usize| normal(face[k]).map_err(|e| (0, e));
                normals.push([n(0)?, n(1)?, n(2)?]);
            }
        }
        first = first.saturating_add((mesh.positions.len() / 3) as u32);
    }
    let uvs = match kept.uvs {
        None => None,
        Some(uvs) if uvs.len() == triangles.len() => Some(uvs),
        Some(uvs) => {
            return Err((
                0,
                format!(
                    "OBJ texture coordinates: {} triangles with vt corners, {} triangles read",
                    uvs.len(),
                    triangles.len()
                ),
            ))
        }
    };
    Ok(ObjTriangles {
        tris: triangles,
        normals: kept.has_normals.then_some(normals),
        uvs,
        vertices,
    })
}

/// OBJ text reduced to what the mesh needs, whether it keeps normals, and the texture
/// coordinates of the triangles its faces make (fans, as tobj makes them), if any.
struct Kept {
    text: String,
    has_normals: bool,
    uvs: Option<Vec<[Vec2; 3]>>,
}

impl Kept {
    fn as_bytes(&self) -> &[u8] {
        self.text.as_bytes()
    }
}

/// Keeps only positions, faces and (when every face corner names one) normals: drops
/// `vt`/`vp` records and everything tobj would only name or group (`o`, `g`, `s`, `usemtl`,
/// `mtllib`, `l`, `p`), and reduces each face corner `v/vt/vn` to `v//vn` (or `v`), so that
/// tobj never indexes texture coordinates. Every kept record is checked here first, with its
/// line (tobj's errors have none, and it does not guard an index against overflow): a `v`
/// has three finite numbers, a used `vn` three numbers neither all zero nor infinite, a face
/// three or more corners whose indices name existing records (a normal, or a negative
/// index, one before it). The `vt` records named by the corners are read here instead (v
/// flipped when `flip_v`), checked the same way. The faces' triangles are counted as they
/// come: past `room`, the face that passes it is an error (before tobj builds them).
fn strip_attributes(text: &str, flip_v: bool, room: u64) -> Result<Kept, (usize, String)> {
    let records = |kind: &'static str| {
        text.lines()
            .filter(move |l| l.split_whitespace().next() == Some(kind))
    };
    let n_normals = records("vn").count() as i64;
    let n_positions = records("v").count() as i64;
    let corners = || records("f").flat_map(|l| l.split_whitespace().skip(1));
    let has_normals =
        n_normals > 0 && corners().all(|c| c.split('/').nth(2).is_some_and(|n| !n.is_empty()));
    let mut out = String::with_capacity(text.len());
    let has_uvs = corners().any(|c| c.split('/').nth(1).is_some_and(|t| !t.is_empty()));
    let mut seen = 0i64; // `vn` records so far: a corner may name only those
    let mut positions = 0i64; // `v` records so far: a negative index counts back from here
    let mut vts: Vec<Vec2> = Vec::new();
    let mut uvs = Vec::new();
    let mut triangles = 0u64;
    for (i, line) in text.lines().enumerate() {
        let at = |e: String| (i + 1, e);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt") if has_uvs => {
                let uv = parse_vt(line).map_err(at)?;
                vts.push(if flip_v {
                    Vec2::new(uv.x, 1.0 - uv.y)
                } else {
                    uv
                });
                continue;
            }
            Some("v") => {
                let p = three_numbers(line).map_err(at)?;
                if !p.is_finite() {
                    return Err(at(format!("OBJ vertex {p} is not finite")));
                }
                positions += 1;
                keep_three(&mut out, line);
            }
            Some("vn") if has_normals => {
                let n = three_numbers(line).map_err(at)?;
                if !n.is_finite() || n == Vec3::ZERO {
                    return Err(at(format!("OBJ normal (vn) {n} is zero or not finite")));
                }
                seen += 1;
                keep_three(&mut out, line);
            }
            Some("f") => {
                out.push('f');
                let mut face_uvs = Vec::new();
                let mut count = 0;
                for corner in words {
                    count += 1;
                    if has_uvs {
                        face_uvs.push(corner_uv(corner, &vts).map_err(at)?);
                    }
                    out.push(' ');
                    let mut parts = corner.split('/');
                    let v = parts.next().unwrap_or(corner);
                    let valid = v
                        .parse::<i64>()
                        .is_ok_and(|i| counts_back(i, positions) || (1..=n_positions).contains(&i));
                    if !valid || corner.split('/').count() > 3 {
                        return Err(at(format!(
                            "OBJ face corner `{corner}`: vertex index out of range or \
                             malformed ({positions} v records before it, {n_positions} in all)"
                        )));
                    }
                    out.push_str(v);
                    if has_normals {
                        let n = parts.nth(1).unwrap_or("");
                        let valid = n
                            .parse::<i64>()
                            .is_ok_and(|i| counts_back(i, seen) || (1..=seen).contains(&i));
                        if !valid {
                            return Err(at(format!(
                                "OBJ face corner `{corner}`: normal index out of range \
                                 ({seen} vn records before it)"
                            )));
                        }
                        out.push_str("//");
                        out.push_str(n);
                    }
                }
                if count < 3 {
                    let message = format!("OBJ face has {count} corners; a face needs 3 or more");
                    return Err(at(message));
                }
                triangles += count - 2;
                if triangles > room {
                    return Err(at(format!(
                        "the faces so far make {triangles} triangles, more than the {room} the \
                         scene's budget has room for"
                    )));
                }
                for k in 2..face_uvs.len() {
                    uvs.push([face_uvs[0], face_uvs[k - 1], face_uvs[k]]);
                }
            }
            _ => continue,
        }
        out.push('\n');
    }
    Ok(Kept {
        text: out,
        has_normals,
        uvs: has_uvs.then_some(uvs),
    })
}

/// Appends a checked `v` or `vn` record with only its keyword and first three numbers
/// (tobj would parse a `w` or colours after them, and fail on a malformed one).
fn keep_three(out: &mut String, line: &str) {
    for word in line.split_whitespace().take(4) {
        out.push_str(word);
        out.push(' ');
    }
}

/// The first three numbers after a `v` or `vn` record's keyword (a `v`'s `w` and vertex
/// colours are ignored).
fn three_numbers(line: &str) -> Result<Vec3, String> {
    let mut xyz = [0.0f32; 3];
    let mut words = line.split_whitespace().skip(1);
    for x in &mut xyz {
        let w = words
            .next()
            .ok_or_else(|| format!("OBJ record `{line}` has fewer than 3 numbers"))?;
        *x = w
            .parse()
            .map_err(|_| format!("OBJ record `{line}`: `{w}` is not a number"))?;
    }
    Ok(Vec3::from_array(xyz))
}

/// The `(u, v)` of a `vt u [v [w]]` record (`v` 0 when absent), finite.
fn parse_vt(line: &str) -> Result<Vec2, String> {
    let mut uv = [0.0f32; 2];
    let mut words = line.split_whitespace().skip(1);
    for (i, x) in uv.iter_mut().enumerate() {
        match words.next() {
            None if i == 1 => break,
            None => return Err(format!("OBJ texture coordinate `{line}` has no u")),
            Some(w) => {
                *x = w.parse().map_err(|_| {
                    format!("OBJ texture coordinate `{line}`: `{w}` is not a number")
                })?
            }
        }
    }
    let uv = Vec2::from_array(uv);
    if !uv.is_finite() {
        return Err(format!("OBJ texture coordinate (vt) {uv} is not finite"));
    }
    Ok(uv)
}

/// Whether `i` is a negative index naming one of the `records` before it (-1 the last).
/// i64::MIN is not: its magnitude does not fit an i64 (negating it overflowed here once).
fn counts_back(i: i64, records: i64) -> bool {
    i < 0 && i.unsigned_abs() <= records.unsigned_abs()
}

/// The uv a face corner names (`v/vt`, `v/vt/vn`; negative indices count back from the last
/// `vt` so far), or (0, 0) for a corner that names none.
fn corner_uv(corner: &str, vts: &[Vec2]) -> Result<Vec2, String> {
    let t = corner.split('/').nth(1).unwrap_or("");
    if t.is_empty() {
        return Ok(Vec2::ZERO);
    }
    let n = vts.len() as i64;
    let index = t
        .parse::<i64>()
        .ok()
        .and_then(|i| match i {
            1.. if i <= n => Some(i - 1),
            _ if counts_back(i, n) => Some(n + i),
            _ => None,
        })
        .ok_or_else(|| {
            format!(
                "OBJ face corner `{corner}`: texture coordinate index out of range \
                 ({n} vt records before it)"
            )
        })?;
    Ok(vts[index as usize])
}
