//! The geometry of a glTF scene's node instances, counted before any is built. A node is
//! instanced once per reference on each path from the scene's root list: a root list that
//! names one mesh node 1,000 times costs 1,000 copies of its mesh, and so does a DAG of
//! shared children. Each node's subtree is counted once (memoised), so the count is linear in
//! the file however many instances it unfolds to, and the total is checked against the
//! scene's budgets ([`SceneBuilder::check_geometry`](crate::scene::SceneBuilder::check_geometry))
//! with a located error before the first triangle is read.
//!
//! An instance at the very place of an earlier instance of the same node (a node named twice
//! in one list, as glTF's `uniqueItems` forbids, or shared by parents at the same place) is
//! a coincident copy: its mesh and light are left out, with one warning per node. Such
//! copies would render as the one (twice its light) at the cost of every ray testing each:
//! 100,000 of a quad took 30 s at 8x8 pixels. The budget still counts them, as references.

use super::{data, Importer, MAX_DEPTH};
use crate::error::Result;
use crate::scene::locate::Part;
use crate::scene::MeshCost;
use glam::Mat4;
use gltf::mesh::Mode;
use gltf::Semantic;
use std::collections::{HashMap, HashSet};
use std::hash::{DefaultHasher, Hash, Hasher};

/// A subtree's geometry and its node instances (itself included).
type Subtree = (MeshCost, u64);

/// The places of the node instances built so far (a 64-bit hash of the node and its world
/// matrix's bits each, 8 bytes per instance), and the nodes warned about a copy.
#[derive(Default)]
pub(super) struct Placed {
    places: HashSet<u64>,
    warned: HashSet<usize>,
}

impl Importer<'_> {
    /// Fails when every instance of `scene`'s nodes together would take the scene past its
    /// budgets; the error is on the scene's `nodes`, naming the triangles, the bytes and the
    /// instances. A node nested deeper than [`MAX_DEPTH`] (a cycle) is the traversal's error.
    pub(super) fn check_instances(&self, scene: &gltf::Scene) -> Result<()> {
        let (mut memo, mut meshes) = (HashMap::new(), HashMap::new());
        let (mut total, mut instances) = (MeshCost::default(), 0u64);
        for node in scene.nodes() {
            let (cost, count) = self.subtree(&node, 0, &mut memo, &mut meshes)?;
            total = total.and(cost);
            instances = instances.saturating_add(count);
        }
        for cost in meshes.values() {
            total = total.and(*cost);
        }
        let field = format!("scenes[{}].nodes", scene.index());
        let what = format!("its {instances} node instances");
        let at = |_: Part, m: String| self.cx.err(&field, m);
        self.b.check_geometry(total, &what, &at)
    }

    /// Whether this instance of `node`, at `world`, is the first there (always, for a node
    /// without a mesh or a light); a later one is a copy, warned about once per node (its
    /// children are still instances of their own).
    pub(super) fn first_at(&mut self, node: &gltf::Node, world: Mat4) -> bool {
        if node.mesh().is_none() && node.light().is_none() {
            return true;
        }
        let mut h = DefaultHasher::new();
        (node.index(), world.to_cols_array().map(f32::to_bits)).hash(&mut h);
        if self.placed.places.insert(h.finish()) {
            return true;
        }
        if self.placed.warned.insert(node.index()) {
            crate::warning::warn(format!(
                "{}: nodes[{}]: instanced again at the place of an earlier instance (named \
                 twice in one list, or by parents at the same place); the copies are left out",
                self.cx.file,
                node.index()
            ));
        }
        false
    }

    /// What one copy of `mesh` adds to the scene.
    fn mesh_cost(&self, mesh: &gltf::Mesh) -> MeshCost {
        (mesh.primitives()).fold(MeshCost::default(), |c, p| {
            c.and(primitive_cost(&p, &self.buffers))
        })
    }

    /// The geometry and instance count of `node` and its descendants.
    fn subtree(
        &self,
        node: &gltf::Node,
        depth: usize,
        memo: &mut HashMap<usize, Subtree>,
        meshes: &mut HashMap<usize, MeshCost>,
    ) -> Result<Subtree> {
        if let Some(&known) = memo.get(&node.index()) {
            return Ok(known);
        }
        if depth > MAX_DEPTH {
            let message = format!("nodes nested deeper than {MAX_DEPTH} (a cycle?)");
            return Err(self.cx.err(&format!("nodes[{}]", node.index()), message));
        }
        // An instanced mesh (`mesh_groups.rs`) costs an instance here, its geometry once in
        // `check_instances`.
        let mut cost = match node.mesh() {
            Some(m) if self.instanced(&m) => {
                meshes
                    .entry(m.index())
                    .or_insert_with(|| self.mesh_cost(&m));
                MeshCost {
                    instances: 1,
                    ..MeshCost::default()
                }
            }
            Some(m) => self.mesh_cost(&m),
            None => MeshCost::default(),
        };
        let mut count = 1u64;
        for child in node.children() {
            let (c, n) = self.subtree(&child, depth + 1, memo, meshes)?;
            cost = cost.and(c);
            count = count.saturating_add(n);
        }
        memo.insert(node.index(), (cost, count));
        Ok((cost, count))
    }
}

/// What one instance of `primitive` adds to the scene, from its accessors' counts (read
/// before any of their data): its triangles by its mode and index count (else vertex count),
/// smooth with a `NORMAL`, with uvs with a `TEXCOORD_n`, with tangents for a normal texture.
/// An accessor whose count runs past its data counts nothing: reading it is the error.
fn primitive_cost(primitive: &gltf::Primitive, buffers: &[Vec<u8>]) -> MeshCost {
    let count = |a: gltf::Accessor| {
        if data::fits(&a, buffers) {
            a.count()
        } else {
            0
        }
    };
    let corners = match primitive.indices() {
        Some(indices) => count(indices),
        None => primitive.get(&Semantic::Positions).map_or(0, count),
    } as u64;
    let triangles = match primitive.mode() {
        Mode::Triangles => corners / 3,
        Mode::TriangleStrip | Mode::TriangleFan => corners.saturating_sub(2),
        _ => 0,
    };
    let normals = primitive.get(&Semantic::Normals).is_some();
    let uvs = primitive
        .attributes()
        .any(|(semantic, _)| matches!(semantic, Semantic::TexCoords(_)));
    let tangents = normals && uvs && primitive.material().normal_texture().is_some();
    MeshCost::mesh(triangles, normals, uvs, tangents)
}
