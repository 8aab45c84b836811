//! Wavefront OBJ meshes (`type = "mesh"`), read with tobj and fed to the [`SceneBuilder`].
//!
//! Shading is flat, so only vertex positions and faces are used: texture coordinates,
//! normals, materials, points and lines are ignored. Polygons are triangulated as fans
//! `(v0, v1, v2), (v0, v2, v3), ...`, keeping the file's winding, so a face's front normal is
//! `cross(v1 - v0, v2 - v0)`.

use glam::Vec3;
use std::io::BufReader;
use std::path::Path;

/// Loads the triangles of the OBJ file at `path` (in the file's coordinates).
///
/// Errors are messages naming the resolved path: the file cannot be read, it does not parse,
/// a face refers to a missing vertex, a vertex is not finite, or there are no triangles.
pub(crate) fn load_triangles(path: &Path) -> Result<Vec<[Vec3; 3]>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read mesh {}: {e}", path.display()))?;
    match parse_triangles(&text) {
        Ok(tris) if tris.is_empty() => {
            Err(format!("{}: the mesh has no triangles", path.display()))
        }
        result => result.map_err(|e| format!("{}: {e}", path.display())),
    }
}

/// Parses OBJ `text` into triangles; see [`load_triangles`].
fn parse_triangles(text: &str) -> Result<Vec<[Vec3; 3]>, String> {
    let positions_only = strip_attributes(text);
    let mut reader = BufReader::new(positions_only.as_bytes());
    // Single index, triangulated (fans), points and lines ignored. Material libraries are
    // never opened: materials come from the scene file.
    let no_mtl = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let (models, _) = tobj::load_obj_buf(&mut reader, &tobj::GPU_LOAD_OPTIONS, no_mtl)
        .map_err(|e| format!("OBJ parse error: {e}"))?;

    let mut triangles = Vec::new();
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
        for face in mesh.indices.chunks_exact(3) {
            triangles.push([vertex(face[0])?, vertex(face[1])?, vertex(face[2])?]);
        }
    }
    Ok(triangles)
}

/// Keeps only what flat shading needs: drops `vt`/`vn` records and reduces each face
/// corner `v/vt/vn` to `v`, so that tobj never indexes texture coordinates or normals
/// (whose out-of-range indices it does not guard against overflow).
fn strip_attributes(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt") | Some("vn") | Some("vp") => continue,
            Some("f") => {
                out.push('f');
                for corner in words {
                    out.push(' ');
                    out.push_str(corner.split('/').next().unwrap_or(corner));
                }
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}
