//! The scene builder's calls for instancing (`instances.rs`): recording a shape group into
//! a mesh, placing it, and what both cost the budgets.

use super::builder::{MaterialId, SceneBuilder};
use super::instances::{GroupStash, Instance, MeshId};
use super::locate::{Locate, Part};
use super::Scene;
use crate::error::Result;
use glam::{Mat4, Vec2, Vec3};

impl SceneBuilder {
    /// Starts a shape group: the shapes added until [`Self::end_shape_group`] make one mesh,
    /// in its object space, that instances place. Groups do not nest (an error on
    /// [`Part::Geometry`]).
    pub fn begin_shape_group(&mut self, at: &dyn Locate) -> Result<()> {
        if self.group.is_some() {
            let message = "a shape group inside a shape group (Mitsuba refuses nested groups)";
            return Err(at.error(Part::Geometry, message.into()));
        }
        let mut stash = GroupStash::default();
        self.swap_stash(&mut stash);
        self.group = Some(stash);
        Ok(())
    }

    /// Ends the shape group begun last and returns its mesh (which may be empty).
    pub fn end_shape_group(&mut self) -> MeshId {
        let Some(mut stash) = self.group.take() else {
            return MeshId(u32::MAX);
        };
        self.swap_stash(&mut stash);
        let mut mesh = Scene::empty();
        if !stash.uvs.is_empty() {
            stash.uvs.resize(stash.triangles.len(), [Vec2::ZERO; 3]);
        }
        if !stash.tangents.is_empty() {
            stash
                .tangents
                .resize(stash.triangles.len(), Default::default());
        }
        (
            mesh.triangles,
            mesh.shading_normals,
            mesh.uvs,
            mesh.tangents,
            mesh.spheres,
            mesh.sdf_grids,
        ) = (
            stash.triangles,
            stash.shading_normals,
            stash.uvs,
            stash.tangents,
            stash.spheres,
            stash.sdf_grids,
        );
        self.instancing.meshes.push(mesh);
        MeshId(self.instancing.meshes.len() as u32 - 1)
    }

    /// Whether material `m` may be in a shape group: it neither emits (Mitsuba refuses
    /// emitters in groups) nor is alpha-tested (the instances' walk makes no alpha test).
    pub fn instanceable(&self, m: MaterialId) -> bool {
        let material = &self.materials[m.index() as usize];
        !material.is_emissive() && material.alpha.is_none()
    }

    /// Whether a shape group is being recorded (its shapes may not emit).
    pub fn in_shape_group(&self) -> bool {
        self.group.is_some()
    }

    /// Places `mesh` by `to_world` (affine, finite, invertible; errors on
    /// [`Part::Geometry`]), counted by the budgets as one instance, not as its triangles.
    pub fn add_instance(&mut self, mesh: MeshId, to_world: Mat4, at: &dyn Locate) -> Result<()> {
        if mesh.0 as usize >= self.instancing.meshes.len() {
            return Err(at.error(
                Part::Geometry,
                "an instance of an unknown shape group".into(),
            ));
        }
        let cost = super::MeshCost {
            instances: 1,
            ..Default::default()
        };
        self.check_geometry(cost, "this instance", at)?;
        let Some(instance) = Instance::new(to_world, mesh.0) else {
            let message = "an instance's to_world must be a finite, invertible affine transform";
            return Err(at.error(Part::Geometry, message.into()));
        };
        // SDF grids are placed in the world, one copy per instance sharing the values.
        let grids = &self.instancing.meshes[mesh.0 as usize].sdf_grids;
        let placed = grids.iter().map(|g| g.placed(instance.to_world));
        self.sdf_grids.extend(placed.collect::<Vec<_>>());
        self.instancing.instances.push(instance);
        Ok(())
    }

    /// The bounding box of the world's primitives and the instances added so far.
    pub(crate) fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let flat = super::bounds_of(&self.triangles, &self.spheres);
        super::join_bounds(flat, self.instancing.bounds())
    }

    fn swap_stash(&mut self, s: &mut GroupStash) {
        std::mem::swap(&mut self.triangles, &mut s.triangles);
        std::mem::swap(&mut self.shading_normals, &mut s.shading_normals);
        std::mem::swap(&mut self.uvs, &mut s.uvs);
        std::mem::swap(&mut self.tangents, &mut s.tangents);
        std::mem::swap(&mut self.spheres, &mut s.spheres);
        std::mem::swap(&mut self.sdf_grids, &mut s.sdf_grids);
    }

    /// The geometry set aside by a group being recorded and held by the meshes and
    /// instances so far (for the budgets).
    pub(super) fn instanced_geometry(&self) -> super::MeshCost {
        let mut cost = super::MeshCost {
            instances: self.instancing.instances.len() as u64,
            ..Default::default()
        };
        let mut add = |tris: usize, smooth: usize, uvs: bool, tangents: bool| {
            cost = cost.and(super::MeshCost {
                triangles: tris as u64,
                smooth: smooth as u64,
                uvs,
                tangents,
                instances: 0,
            });
        };
        if let Some(s) = &self.group {
            add(
                s.triangles.len(),
                s.shading_normals.len(),
                !s.uvs.is_empty(),
                !s.tangents.is_empty(),
            );
        }
        for m in &self.instancing.meshes {
            add(
                m.triangles.len(),
                m.shading_normals.len(),
                !m.uvs.is_empty(),
                !m.tangents.is_empty(),
            );
        }
        cost
    }
}
