//! Wavefront OBJ meshes (`type = "mesh"`), read with tobj and fed to the [`SceneBuilder`].
//!
//! Vertex positions, faces and vertex normals (`vn`, named by face corners `v//vn` or
//! `v/vt/vn`) are used: texture coordinates, materials, points and lines are ignored. The
//! mesh has normals (smooth shading) when every face corner names one; otherwise they are
//! all ignored (flat). Polygons are triangulated as fans `(v0, v1, v2), (v0, v2, v3), ...`,
//! keeping the file's winding, so a face's front normal is `cross(v1 - v0, v2 - v0)`.
//!
//! [`SceneBuilder`]: super::SceneBuilder

use super::VertexNormals;
use glam::Vec3;
use std::io::BufReader;
use std::path::Path;

/// The triangles of an OBJ file and, when every corner names one, their vertex normals (as
/// the file gives them, not normalised).
pub(crate) type ObjTriangles = (Vec<[Vec3; 3]>, Option<Vec<VertexNormals>>);

/// Loads the triangles of the OBJ file at `path` (in the file's coordinates).
///
/// Errors are messages naming the resolved path: the file cannot be read, it does not parse,
/// a face refers to a missing vertex or normal, a vertex is not finite, a normal (`vn`) is
/// zero or not finite, or there are no triangles.
pub(crate) fn load_triangles(path: &Path) -> Result<ObjTriangles, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read mesh {}: {e}", path.display()))?;
    match parse_triangles(&text) {
        Ok((tris, _)) if tris.is_empty() => {
            Err(format!("{}: the mesh has no triangles", path.display()))
        }
        result => result.map_err(|e| format!("{}: {e}", path.display())),
    }
}

/// Parses OBJ `text` into triangles; see [`load_triangles`].
fn parse_triangles(text: &str) -> Result<ObjTriangles, String> {
    let kept = strip_attributes(text)?;
    let mut reader = BufReader::new(kept.as_bytes());
    // Single index, triangulated (fans), points and lines ignored. Material libraries are
    // never opened: materials come from the scene file.
    let no_mtl = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let (models, _) = tobj::load_obj_buf(&mut reader, &tobj::GPU_LOAD_OPTIONS, no_mtl)
        .map_err(|e| format!("OBJ parse error: {e}"))?;

    let mut triangles = Vec::new();
    let mut normals = Vec::new();
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
            triangles.push([vertex(face[0])?, vertex(face[1])?, vertex(face[2])?]);
            if kept.has_normals {
                normals.push([normal(face[0])?, normal(face[1])?, normal(face[2])?]);
            }
        }
    }
    Ok((triangles, kept.has_normals.then_some(normals)))
}

/// OBJ text reduced to what the mesh needs, and whether it keeps normals.
struct Kept {
    text: String,
    has_normals: bool,
}

impl Kept {
    fn as_bytes(&self) -> &[u8] {
        self.text.as_bytes()
    }
}

/// Keeps only positions, faces and (when every face corner names one) normals: drops
/// `vt`/`vp` records and reduces each face corner `v/vt/vn` to `v//vn` (or `v`), so that tobj
/// never indexes texture coordinates; a normal index is checked against the `vn` records
/// first (tobj does not guard an out-of-range index against overflow).
fn strip_attributes(text: &str) -> Result<Kept, String> {
    let n_normals = text
        .lines()
        .filter(|l| l.split_whitespace().next() == Some("vn"))
        .count() as i64;
    let corners = || {
        text.lines()
            .filter(|l| l.split_whitespace().next() == Some("f"))
            .flat_map(|l| l.split_whitespace().skip(1))
    };
    let has_normals =
        n_normals > 0 && corners().all(|c| c.split('/').nth(2).is_some_and(|n| !n.is_empty()));
    let mut out = String::with_capacity(text.len());
    let mut seen = 0i64; // `vn` records so far: a corner may name only those
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt") | Some("vp") => continue,
            Some("vn") if !has_normals => continue,
            Some("vn") => {
                seen += 1;
                out.push_str(line);
            }
            Some("f") => {
                out.push('f');
                for corner in words {
                    out.push(' ');
                    let mut parts = corner.split('/');
                    out.push_str(parts.next().unwrap_or(corner));
                    if has_normals {
                        let n = parts.nth(1).unwrap_or("");
                        let valid = n.parse::<i64>().is_ok_and(|i| i != 0 && i.abs() <= seen);
                        if !valid {
                            return Err(format!(
                                "OBJ face corner `{corner}`: normal index out of range \
                                 ({seen} vn records before it)"
                            ));
                        }
                        out.push_str("//");
                        out.push_str(n);
                    }
                }
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    Ok(Kept {
        text: out,
        has_normals,
    })
}
