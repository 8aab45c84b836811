//! Smooth vertex normals for a mesh file that has none, computed from its faces as Mitsuba 3
//! computes them for an `obj` or `ply` shape without `face_normals` (3.9.1's
//! `Mesh::recompute_vertex_normals`; `scripts/mitsuba_conformance_probe.py`): after
//! `to_world`, each face adds its unit normal to each of its corners' vertices, weighted by
//! the corner's interior angle (Thuermer and Wuethrich, "Computing vertex normals from
//! polygonal facets", JGT 1998); each vertex's sum is then normalised. A vertex is one of the
//! file's vertices: a PLY `vertex`, an OBJ corner's `v` with its `vt` (Mitsuba keeps corners
//! with different texture coordinates apart, so a uv seam is a crease).

use crate::scene::VertexNormals;
use glam::{DVec3, Vec3};

/// Angle-weighted vertex normals of `tris`, whose corners are the vertices `ids`: one set per
/// triangle, unit length. A vertex whose faces' normals cancel (or are all degenerate) takes
/// its triangle's own face normal (+z for a degenerate triangle), so every normal is valid.
pub(crate) fn from_faces(tris: &[[Vec3; 3]], ids: &[[u32; 3]]) -> Vec<VertexNormals> {
    let count = ids
        .iter()
        .flatten()
        .map(|&i| i as usize + 1)
        .max()
        .unwrap_or(0);
    let mut sums = vec![DVec3::ZERO; count];
    let faces: Vec<DVec3> = tris.iter().map(face_normal).collect();
    for ((t, ids), n) in tris.iter().zip(ids).zip(&faces) {
        if *n == DVec3::ZERO {
            continue;
        }
        let p = t.map(|v| v.as_dvec3());
        for k in 0..3 {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            let angle = unit_angle(a.normalize_or_zero(), b.normalize_or_zero());
            if angle.is_finite() {
                sums[ids[k] as usize] += *n * angle;
            }
        }
    }
    ids.iter()
        .zip(&faces)
        .map(|(ids, face)| {
            ids.map(|i| {
                let n = sums[i as usize].normalize_or_zero();
                let n = if n == DVec3::ZERO { *face } else { n };
                if n == DVec3::ZERO {
                    Vec3::Z
                } else {
                    n.as_vec3()
                }
            })
        })
        .collect()
}

/// The unit normal of triangle `t` (its winding's), or zero when it is degenerate.
fn face_normal(t: &[Vec3; 3]) -> DVec3 {
    let p = t.map(|v| v.as_dvec3());
    (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
}

/// The angle between unit vectors `a` and `b`, accurate near 0 and pi (Mitsuba's
/// `unit_angle`).
fn unit_angle(a: DVec3, b: DVec3) -> f64 {
    if a.dot(b) < 0.0 {
        std::f64::consts::PI - 2.0 * ((a + b).length() / 2.0).min(1.0).asin()
    } else {
        2.0 * ((a - b).length() / 2.0).min(1.0).asin()
    }
}
