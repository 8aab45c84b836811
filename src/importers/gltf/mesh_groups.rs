//! Meshes placed by several node instances are stored once and instanced
//! (`crate::scene::instances`): a mesh named at two or more distinct places (node and world
//! matrix; copies at one place are left out, `instances.rs`) whose primitives' materials
//! neither emit nor are alpha-blended or masked (instancing refuses both) becomes a shape
//! group in its own space, built the first time a node names it, and each node places it
//! by its world matrix. Any other mesh is a copy per node, as before; so is a node whose
//! matrix is singular (its copy is flat and invisible). The budget counts an instanced
//! mesh's geometry once and each of its placements as an instance.

use super::{Importer, MAX_DEPTH, MAX_NODE_INSTANCES};
use crate::error::Result;
use crate::scene::locate::Part;
use crate::scene::MeshId;
use glam::Mat4;
use std::collections::{HashMap, HashSet};
use std::hash::{DefaultHasher, Hash, Hasher};

/// What the importer knows of its meshes' instancing.
#[derive(Default)]
pub(super) struct MeshGroups {
    /// Distinct places (node and world matrix) each mesh is named at.
    uses: HashMap<usize, u64>,
    /// The group of each instanced mesh built so far (`None`: it could not be one).
    groups: HashMap<usize, Option<MeshId>>,
}

impl Importer<'_> {
    /// Counts the distinct places each mesh of `scene` is named at (stops past
    /// [`MAX_NODE_INSTANCES`] node instances or [`MAX_DEPTH`] levels: the traversal refuses
    /// those).
    pub(super) fn count_mesh_uses(&mut self, scene: &gltf::Scene) {
        fn walk(
            node: &gltf::Node,
            parent: Mat4,
            depth: usize,
            visits: &mut usize,
            places: &mut HashSet<u64>,
            uses: &mut HashMap<usize, u64>,
        ) {
            *visits += 1;
            if depth > MAX_DEPTH || *visits > MAX_NODE_INSTANCES {
                return;
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if let Some(mesh) = node.mesh() {
                let mut h = DefaultHasher::new();
                (node.index(), world.to_cols_array().map(f32::to_bits)).hash(&mut h);
                if places.insert(h.finish()) {
                    *uses.entry(mesh.index()).or_default() += 1;
                }
            }
            for child in node.children() {
                walk(&child, world, depth + 1, visits, places, uses);
            }
        }
        let (mut visits, mut places) = (0, HashSet::new());
        for node in scene.nodes() {
            let uses = &mut self.mesh_groups.uses;
            walk(&node, Mat4::IDENTITY, 0, &mut visits, &mut places, uses);
        }
    }

    /// Whether `mesh` is instanced: named at two or more places, and no primitive's material
    /// emits or is alpha-tested.
    pub(super) fn instanced(&self, mesh: &gltf::Mesh) -> bool {
        let opaque = |p: gltf::Primitive| {
            let m = p.material();
            m.emissive_factor() == [0.0; 3]
                && m.emissive_texture().is_none()
                && m.alpha_mode() == gltf::material::AlphaMode::Opaque
        };
        self.mesh_groups
            .uses
            .get(&mesh.index())
            .is_some_and(|&n| n >= 2)
            && mesh.primitives().all(opaque)
    }

    /// Places `mesh` at `world` as an instance of its group (built the first time); false
    /// when it is not instanced, or cannot be here (then the node gets a copy).
    pub(super) fn place_instance(&mut self, mesh: &gltf::Mesh, world: Mat4) -> Result<bool> {
        if !self.instanced(mesh) {
            return Ok(false);
        }
        let field = format!("meshes[{}]", mesh.index());
        let group = match self.mesh_groups.groups.get(&mesh.index()) {
            Some(&g) => g,
            None => {
                let at = |_: Part, m: String| self.cx.err(&field, m);
                self.b.begin_shape_group(&at)?;
                // A primitive the group refuses is built again as a copy, which reports
                // whatever is wrong with it.
                let built = (mesh.primitives())
                    .try_for_each(|p| self.primitive(mesh, &p, Mat4::IDENTITY))
                    .is_ok();
                let id = self.b.end_shape_group();
                let g = built.then_some(id);
                self.mesh_groups.groups.insert(mesh.index(), g);
                g
            }
        };
        let Some(group) = group else {
            return Ok(false);
        };
        if crate::scene::Instance::new(world, group.0).is_none() {
            return Ok(false);
        }
        let at = |_: Part, m: String| self.cx.err(&field, m);
        self.b.add_instance(group, world, &at)?;
        Ok(true)
    }
}
