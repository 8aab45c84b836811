//! Vertex normals as the scene builder takes them: checked and normalised, and the test that
//! keeps a triangle whose normals all lie along its face normal flat (no normals stored).

use crate::scene::VertexNormals;
use glam::Vec3;

/// Vertex normals within this cosine of a triangle's face normal (0.1 degrees) shade it flat.
pub const FLAT_COS: f32 = 0.999_998_5;

/// Whether unit vertex normals `n` all lie along the face normal `ng` (or all against it):
/// smooth shading would give the flat normal.
pub(crate) fn is_flat(ng: Vec3, n: &VertexNormals) -> bool {
    n.iter().all(|v| v.dot(ng) >= FLAT_COS) || n.iter().all(|v| v.dot(ng) <= -FLAT_COS)
}

/// `normals`, one set per triangle of `count`, each normalised; an error message when the
/// count differs or a normal is zero or not finite.
pub(crate) fn unit_normals(
    mut normals: Vec<VertexNormals>,
    count: usize,
) -> Result<Vec<VertexNormals>, String> {
    if normals.len() != count {
        let n = normals.len();
        return Err(format!("{n} sets of vertex normals for {count} triangles"));
    }
    for (i, set) in normals.iter_mut().enumerate() {
        for n in set.iter_mut() {
            let unit = n.normalize_or_zero();
            if !n.is_finite() || unit == Vec3::ZERO {
                return Err(format!(
                    "vertex normal {n} of triangle {i} is zero or not finite"
                ));
            }
            *n = unit;
        }
    }
    Ok(normals)
}
