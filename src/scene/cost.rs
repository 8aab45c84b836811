//! What geometry costs a scene, counted before it is built: its triangles and the bytes the
//! finished [`Scene`](super::Scene) keeps for them. Importers describe what they are about to
//! add (one shape, or a mesh times the instances that name it) and the builder checks it
//! against the scene's budgets (`geometry_budget.rs`) before anything of it is allocated.

use super::{Triangle, VertexNormals, VertexTangents};
use glam::Vec2;
use std::mem::size_of;

/// Bytes per triangle of [`Scene::triangles`](super::Scene::triangles).
pub const TRIANGLE_BYTES: u64 = size_of::<Triangle>() as u64;
/// Bytes per smooth-shaded triangle of [`Scene::shading_normals`](super::Scene::shading_normals).
pub const NORMALS_BYTES: u64 = size_of::<VertexNormals>() as u64;
/// Bytes per triangle of [`Scene::uvs`](super::Scene::uvs), which covers every triangle once any
/// has texture coordinates.
pub const UVS_BYTES: u64 = size_of::<[Vec2; 3]>() as u64;
/// Bytes per triangle of [`Scene::tangents`](super::Scene::tangents), likewise.
pub const TANGENTS_BYTES: u64 = size_of::<VertexTangents>() as u64;

/// Bytes per instance of a mesh (its two affine maps and the mesh's index; the instancing
/// module asserts it is its `Instance`'s size).
pub const INSTANCE_BYTES: u64 = 144;

/// Geometry as the scene will hold it: how many triangles, how many of them smooth-shaded,
/// and whether any has texture coordinates or vertex tangents (the scene then keeps them for
/// all its triangles). Counts saturate rather than wrap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshCost {
    /// Triangles.
    pub triangles: u64,
    /// Of them, those with vertex normals.
    pub smooth: u64,
    /// Whether texture coordinates come with them.
    pub uvs: bool,
    /// Whether vertex tangents come with them.
    pub tangents: bool,
    /// Instances of meshes stored once (the scene's instancing): each costs
    /// [`INSTANCE_BYTES`], not its mesh's triangles.
    pub instances: u64,
}

impl MeshCost {
    /// `triangles` triangles, all with vertex normals when `normals`, with texture
    /// coordinates and tangents when asked.
    pub fn mesh(triangles: u64, normals: bool, uvs: bool, tangents: bool) -> Self {
        MeshCost {
            triangles,
            smooth: if normals { triangles } else { 0 },
            uvs,
            tangents,
            instances: 0,
        }
    }

    /// This and `other` together.
    pub fn and(self, other: MeshCost) -> Self {
        MeshCost {
            triangles: self.triangles.saturating_add(other.triangles),
            smooth: self.smooth.saturating_add(other.smooth),
            uvs: self.uvs || other.uvs,
            tangents: self.tangents || other.tangents,
            instances: self.instances.saturating_add(other.instances),
        }
    }

    /// `n` copies of this (a mesh named by `n` instances).
    pub fn times(self, n: u64) -> Self {
        MeshCost {
            triangles: self.triangles.saturating_mul(n),
            smooth: self.smooth.saturating_mul(n),
            instances: self.instances.saturating_mul(n),
            ..self
        }
    }

    /// The bytes a scene of this geometry holds for it.
    pub fn bytes(&self) -> u64 {
        let per_triangle = TRIANGLE_BYTES
            + if self.uvs { UVS_BYTES } else { 0 }
            + if self.tangents { TANGENTS_BYTES } else { 0 };
        let all = self.triangles.saturating_mul(per_triangle);
        let instances = self.instances.saturating_mul(INSTANCE_BYTES);
        (all.saturating_add(self.smooth.saturating_mul(NORMALS_BYTES))).saturating_add(instances)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_count_what_the_scene_keeps() {
        assert_eq!(
            (TRIANGLE_BYTES, NORMALS_BYTES, UVS_BYTES, TANGENTS_BYTES),
            (48, 36, 24, 48)
        );
        let smooth = MeshCost::mesh(10, true, false, false);
        assert_eq!(smooth.bytes(), 10 * (48 + 36));
        // Texture coordinates and tangents of one mesh are kept for every triangle.
        let flat = MeshCost::mesh(5, false, false, false);
        let textured = MeshCost::mesh(1, false, true, true);
        assert_eq!(flat.and(textured).bytes(), 6 * (48 + 24 + 48));
        // 1,000 instances of a 77,792-triangle smooth mesh; and counts that saturate.
        assert_eq!(
            MeshCost::mesh(77_792, true, false, false)
                .times(1000)
                .bytes(),
            77_792_000 * 84
        );
        assert_eq!(
            MeshCost::mesh(u64::MAX, true, true, true).times(3).bytes(),
            u64::MAX
        );
    }
}
