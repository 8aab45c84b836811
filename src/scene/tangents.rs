//! Vertex tangents for normal maps: the builder's entry for meshes that carry them, and
//! MikkTSpace's tangents (the `mikktspace` crate, the algorithm glTF and Blender use) for
//! meshes that do not. The convention is [`VertexTangents`]'.

use crate::error::Result;
use crate::scene::builder::{SceneBuilder, Surface};
use crate::scene::locate::{Locate, Part};
use crate::scene::{VertexNormals, VertexTangents};
use glam::{Vec2, Vec3, Vec4};

impl SceneBuilder {
    /// [`add_uv_mesh`](Self::add_uv_mesh) with vertex tangents for each triangle's corners
    /// (`tangents` parallel to `tris`, in [`VertexTangents`]' convention; a `w` is read by
    /// its sign; non-finite values are an error).
    pub fn add_tangent_mesh(
        &mut self,
        tris: Vec<[Vec3; 3]>,
        normals: Option<Vec<VertexNormals>>,
        uvs: Vec<[Vec2; 3]>,
        tangents: Vec<VertexTangents>,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        if tangents.len() != tris.len() || tangents.iter().flatten().any(|t| !t.is_finite()) {
            let message = "vertex tangents must be finite, one set per triangle";
            return Err(at.error(Part::Geometry, message.into()));
        }
        let cost = super::MeshCost::mesh(tris.len() as u64, normals.is_some(), true, true);
        self.check_geometry(cost, "this shape", at)?;
        let first = self.triangles.len();
        self.add_uv_mesh(tris, normals, uvs, surface, at)?;
        self.tangents.resize(first, VertexTangents::default());
        let sign = |t: Vec4| t.truncate().extend(if t.w < 0.0 { -1.0 } else { 1.0 });
        self.tangents
            .extend(tangents.into_iter().map(|c| c.map(sign)));
        Ok(())
    }
}

/// MikkTSpace's tangents of a mesh given per triangle corner (positions, unit normals, uvs,
/// parallel), in [`VertexTangents`]' convention: MikkTSpace's bitangent `w (n x t)` points
/// along increasing v, so its `w` is ours. `None` when MikkTSpace refuses the mesh.
pub fn mikktspace(
    points: &[[Vec3; 3]],
    normals: &[VertexNormals],
    uvs: &[[Vec2; 3]],
) -> Option<Vec<VertexTangents>> {
    let mut mesh = Corners {
        points,
        normals,
        uvs,
        out: vec![VertexTangents::default(); points.len()],
    };
    let n = points.len().min(normals.len()).min(uvs.len());
    (n == points.len() && mikktspace::generate_tangents(&mut mesh)).then_some(mesh.out)
}

/// A mesh as MikkTSpace reads it: faces of three corners.
struct Corners<'a> {
    points: &'a [[Vec3; 3]],
    normals: &'a [VertexNormals],
    uvs: &'a [[Vec2; 3]],
    out: Vec<VertexTangents>,
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.points.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.points[face][vert].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[face][vert].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[face][vert].to_array()
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.out[face][vert] = Vec4::from_array(tangent);
    }
}

#[cfg(test)]
mod tests {
    use crate::math::geometry::triangle_tangent;
    use crate::scene::tangents::mikktspace;
    use glam::{Vec2, Vec3};

    /// On a plane MikkTSpace's frame is each triangle's uv frame: the same tangent direction,
    /// and its sign says what `triangle_tangent`'s `flipped` says, for either winding of the
    /// uvs (a mirrored mapping included).
    #[test]
    fn planar_tangents_match_the_uv_frame() {
        let p = [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        for mirror in [false, true] {
            // glTF's convention (v down the image) and its mirror image in u.
            let u = |x: f32| if mirror { 1.0 - x } else { x };
            let uv = [
                Vec2::new(u(0.0), 0.0),
                Vec2::new(u(0.0), 1.0),
                Vec2::new(u(1.0), 1.0),
                Vec2::new(u(1.0), 0.0),
            ];
            let corners = [[0, 1, 2], [0, 2, 3]];
            let points: Vec<[Vec3; 3]> = corners.iter().map(|c| c.map(|i| p[i])).collect();
            let uvs: Vec<[Vec2; 3]> = corners.iter().map(|c| c.map(|i| uv[i])).collect();
            let normals = vec![[Vec3::Z; 3]; 2];
            let t = mikktspace(&points, &normals, &uvs).expect("a valid mesh");
            for (f, tri) in points.iter().enumerate() {
                let (dp_du, flipped) =
                    triangle_tangent(tri[1] - tri[0], tri[2] - tri[0], &uvs[f]).unwrap();
                for c in t[f] {
                    let dir = c.truncate().normalize();
                    assert!(dir.dot(dp_du.normalize()) > 0.9999, "{dir} vs {dp_du}");
                    assert_eq!(c.w < 0.0, flipped, "mirror {mirror}: w {}", c.w);
                }
            }
        }
    }
}
