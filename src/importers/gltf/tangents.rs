//! The vertex tangents of a normal-mapped glTF primitive, as the specification asks: its
//! `TANGENT` attribute (xyz the tangent, w the sign of its bitangent `w (n x t)`, which
//! points to the top of the normal map's image), MikkTSpace's tangents where it has none,
//! and without `NORMAL` each triangle's own uv frame (the supplied tangents MUST then be
//! ignored), its bitangent negated where the mapping mirrors, as MikkTSpace's. Returned per
//! world-space corner, in [`crate::scene::VertexTangents`]' convention.

use crate::importers::gltf::data;
use crate::scene::tangents::mikktspace;
use crate::scene::VertexTangents;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// What a primitive's tangents are computed from: its vertices (object space) and the
/// corners of its triangles, in the file's winding.
pub(crate) struct Vertices<'a> {
    /// `POSITION`.
    pub points: &'a [Vec3],
    /// `NORMAL`, as many as the points.
    pub normals: &'a [Vec3],
    /// The normal texture's `TEXCOORD_n`, as many as the points.
    pub uvs: &'a [Vec2],
    /// Each triangle's vertex indices, checked against the points.
    pub corners: &'a [[u32; 3]],
}

/// The tangents of `primitive`'s triangles for a material with a normal texture, placed by
/// `world` (corners swapped as the triangles are where it mirrors).
pub(crate) fn primitive_tangents(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    v: &Vertices,
    world: Mat4,
) -> Result<Vec<VertexTangents>, String> {
    let corner = |c: &[u32; 3]| c.map(|i| i as usize);
    // In the file's convention (glTF's w: the bitangent points to the image's top).
    let local: Vec<VertexTangents> = match primitive.get(&gltf::Semantic::Tangents) {
        Some(a) => {
            let t = data::read_tangents(&a, buffers)?;
            if t.len() != v.points.len() {
                let n = v.points.len();
                return Err(format!("{} TANGENTs for {n} POSITIONs", t.len()));
            }
            v.corners.iter().map(|c| corner(c).map(|i| t[i])).collect()
        }
        None => {
            let of = |a: &[Vec3]| -> Vec<[Vec3; 3]> {
                v.corners.iter().map(|c| corner(c).map(|i| a[i])).collect()
            };
            let uvs: Vec<[Vec2; 3]> = v
                .corners
                .iter()
                .map(|c| corner(c).map(|i| v.uvs[i]))
                .collect();
            // MikkTSpace's w points its bitangent along increasing v: down the image.
            let m = mikktspace(&of(v.points), &of(v.normals), &uvs).unwrap_or_default();
            m.into_iter()
                .map(|c| c.map(|t| t.truncate().extend(-t.w)))
                .collect()
        }
    };
    let linear = Mat3::from_mat4(world);
    let mirrored = world.determinant() < 0.0;
    // Ours: w (n x t) along increasing v, the image's bottom; a mirror reverses the cross
    // product's orientation.
    let sign = if mirrored { 1.0 } else { -1.0 };
    let place = |t: Vec4| (linear * t.truncate()).extend(sign * t.w);
    Ok(local
        .into_iter()
        .map(|c| {
            let c = c.map(place);
            if mirrored {
                [c[0], c[2], c[1]]
            } else {
                c
            }
        })
        .collect())
}

/// The tangents of triangles without `NORMAL` (world-space corners `tris`, uvs `uvs`): each
/// triangle's own uv tangent at its three corners, `w` -1 where its mapping mirrors
/// (`geometry::triangle_tangent`; zero for a degenerate one). The scene's frame from corner
/// uvs is Mitsuba's, never flipped; glTF's flips as MikkTSpace does.
pub(crate) fn face_tangents(tris: &[[Vec3; 3]], uvs: &[[Vec2; 3]]) -> Vec<VertexTangents> {
    use crate::math::geometry::triangle_tangent;
    (tris.iter().zip(uvs))
        .map(
            |(p, uv)| match triangle_tangent(p[1] - p[0], p[2] - p[0], uv) {
                Some((t, flipped)) => [t.extend(if flipped { -1.0 } else { 1.0 }); 3],
                None => [Vec4::ZERO; 3],
            },
        )
        .collect()
}
