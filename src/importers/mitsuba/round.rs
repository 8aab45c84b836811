//! Mitsuba's `disk` and `cylinder`, which Mitsuba intersects exactly, as triangle meshes of
//! [`SEGMENTS`] facets around, with Mitsuba's texture coordinates (as Mitsuba 3.9.1 reports
//! them: `scripts/mitsuba_round_shapes.py`). The polygon's radius is widened so that its
//! area is the round shape's, so an emitter's power is Mitsuba's; its outline is within
//! 3e-4 of the radius of the circle's.

use crate::importers::mesh_file::MeshData;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Facets around a disk or cylinder.
pub(crate) const SEGMENTS: usize = 128;

/// The point at angle `phi` on the circle of radius `r` in z = 0.
fn around(r: f32, phi: f32) -> Vec3 {
    Vec3::new(r * phi.cos(), r * phi.sin(), 0.0)
}

/// Mitsuba's unit disk (radius 1 in z = 0, front +z) as a fan of [`SEGMENTS`] triangles of
/// total area pi; texture coordinates (r, phi / 2 pi) as `uv::disk` gives them, the seam's
/// last corner at 1 rather than 0 (the centre takes its triangle's middle angle).
pub(crate) fn disk() -> MeshData {
    let n = SEGMENTS as f32;
    let r = (TAU / (n * (TAU / n).sin())).sqrt();
    let (mut tris, mut uvs) = (Vec::new(), Vec::new());
    for i in 0..SEGMENTS {
        let (a, b) = (i as f32 / n, (i + 1) as f32 / n);
        tris.push([Vec3::ZERO, around(r, a * TAU), around(r, b * TAU)]);
        let mid = Vec2::new(0.0, 0.5 * (a + b));
        uvs.push([mid, Vec2::new(1.0, a), Vec2::new(1.0, b)]);
    }
    uv_mesh(tris, uvs)
}

/// The flat mesh `tris` with corner uvs `uvs` (the shapes' own meshes).
pub(super) fn uv_mesh(tris: Vec<[Vec3; 3]>, uvs: Vec<[Vec2; 3]>) -> MeshData {
    MeshData {
        tris,
        normals: None,
        uvs: Some(uvs),
        vertices: None,
        attributes: Vec::new(),
    }
}

/// Mitsuba's cylinder of radius 1 around z from 0 to 1 (no caps, front outward) as
/// [`SEGMENTS`] quads of total area 2 pi, smooth-shaded with radial normals; texture
/// coordinates (phi / 2 pi, z).
pub(crate) fn cylinder() -> MeshData {
    let n = SEGMENTS as f32;
    let r = PI / (n * (PI / n).sin());
    let (mut tris, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..SEGMENTS {
        let (a, b) = (i as f32 / n, (i + 1) as f32 / n);
        let (pa, pb) = (around(r, a * TAU), around(r, b * TAU));
        let (na, nb) = (around(1.0, a * TAU), around(1.0, b * TAU));
        let (qa, qb) = (pa + Vec3::Z, pb + Vec3::Z);
        tris.push([pa, pb, qb]);
        tris.push([pa, qb, qa]);
        normals.push([na, nb, nb]);
        normals.push([na, nb, na]);
        uvs.push([Vec2::new(a, 0.0), Vec2::new(b, 0.0), Vec2::new(b, 1.0)]);
        uvs.push([Vec2::new(a, 0.0), Vec2::new(b, 1.0), Vec2::new(a, 1.0)]);
    }
    MeshData {
        tris,
        normals: Some(normals),
        uvs: Some(uvs),
        vertices: None,
        attributes: Vec::new(),
    }
}

/// Mitsuba's placement of the unit cylinder between `p0` and `p1` with `radius`: p0, then
/// the frame of the axis (Mitsuba's `coordinate_system`, glam's `any_orthonormal_pair`),
/// then the scale; `None` when the axis has no length.
pub(crate) fn cylinder_frame(p0: Vec3, p1: Vec3, radius: f32) -> Option<Mat4> {
    let axis = p1 - p0;
    let length = axis.length();
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    let d = axis / length;
    let (s, t) = d.any_orthonormal_pair();
    let frame = Mat4::from_cols(s.extend(0.0), t.extend(0.0), d.extend(0.0), p0.extend(1.0));
    Some(frame * Mat4::from_scale(Vec3::new(radius, radius, length)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(m: &MeshData) -> f32 {
        m.tris
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .sum()
    }

    #[test]
    fn the_meshes_keep_the_round_shapes_areas_and_face_out() {
        let (d, c) = (disk(), cylinder());
        assert!((area(&d) - PI).abs() < 1e-5 * PI, "{}", area(&d));
        assert!((area(&c) - TAU).abs() < 1e-5 * TAU, "{}", area(&c));
        for t in &d.tris {
            assert!((t[1] - t[0]).cross(t[2] - t[0]).z > 0.0);
        }
        for t in &c.tris {
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            let out = (t[0] + t[1] + t[2]) / 3.0 * Vec3::new(1.0, 1.0, 0.0);
            assert!(n.dot(out) > 0.0);
            assert!(t.iter().all(|p| (p.truncate().length() - 1.0).abs() < 3e-4));
        }
    }

    #[test]
    fn a_cylinder_frame_maps_the_unit_cylinder_onto_its_axis() {
        let (p0, p1) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 1.0));
        let m = cylinder_frame(p0, p1, 0.5).unwrap();
        assert!(m.transform_point3(Vec3::ZERO).distance(p0) < 1e-6);
        assert!(m.transform_point3(Vec3::Z).distance(p1) < 1e-6);
        let rim = m.transform_point3(Vec3::X) - p0;
        assert!((rim.length() - 0.5).abs() < 1e-6 && rim.dot(p1 - p0).abs() < 1e-6);
        // The default axis keeps Mitsuba's frame: phi = 0 along +x.
        let unit = cylinder_frame(Vec3::ZERO, Vec3::Z, 1.0).unwrap();
        assert!(unit.abs_diff_eq(Mat4::IDENTITY, 1e-6));
        assert!(cylinder_frame(p0, p0, 1.0).is_none());
    }
}
