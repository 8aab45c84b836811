//! The scene builder's checks of geometry against its budgets ([`SceneBudgets`]): what an
//! importer is about to add ([`MeshCost`]: a shape, a mesh file, the instances of a glTF
//! mesh) is counted with what the scene holds and refused, with a located error, before any
//! of it is read or built.
//!
//! [`SceneBudgets`]: super::SceneBudgets

use super::builder::SceneBuilder;
use super::cost::{MeshCost, TRIANGLE_BYTES};
use super::locate::Locate;
use crate::error::Result;
use crate::textures::SceneTexture;

impl SceneBuilder {
    /// Fails when `adding`, `what` is about to be added (`this shape`, the instances of a
    /// mesh), would take the scene past its budgets ([`super::SceneBudgets::check_geometry`]): for
    /// an importer to call before it reads or builds what it counts.
    pub fn check_geometry(&self, adding: MeshCost, what: &str, at: &dyn Locate) -> Result<()> {
        let texels = self.textures.iter().map(SceneTexture::bytes).sum();
        (self.budgets).check_geometry(self.geometry(), texels, adding, what, at)
    }

    /// How many more flat triangles the scene's budgets have room for: a mesh file with
    /// more is refused as it is read, before its triangles are built.
    pub(crate) fn triangle_room(&self) -> u64 {
        let have = self.geometry();
        let texels: u64 = self.textures.iter().map(SceneTexture::bytes).sum();
        let bytes = (self.budgets.max_bytes)
            .saturating_sub(have.bytes())
            .saturating_sub(texels);
        let count = (self.budgets.max_triangles as u64).saturating_sub(have.triangles);
        count.min(bytes / TRIANGLE_BYTES)
    }

    /// Bytes the scene's budget ([`super::SceneBudgets::max_bytes`]) has room for beyond
    /// its geometry and texels (a medium's grid file is read against it).
    pub(crate) fn byte_room(&self) -> u64 {
        let texels: u64 = self.textures.iter().map(SceneTexture::bytes).sum();
        (self.budgets.max_bytes)
            .saturating_sub(self.geometry().bytes())
            .saturating_sub(texels)
    }

    /// The geometry the scene holds so far.
    pub(super) fn geometry(&self) -> MeshCost {
        let world = MeshCost {
            triangles: self.triangles.len() as u64,
            smooth: self.shading_normals.len() as u64,
            uvs: !self.uvs.is_empty(),
            tangents: !self.tangents.is_empty(),
            instances: 0,
        };
        world.and(self.instanced_geometry())
    }
}
