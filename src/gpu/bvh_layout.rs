//! The BVH as the GPU walks it (`trace_ray` in shaders/common/intersect.wgsl): the shared
//! hierarchy of src/bvh.rs, copied into the two arrays one traversal step reads.
//!
//! - `nodes`: every node once per child order (left-first order, then right-first), each with
//!   its escape link in that order ([`Bvh::links`]) and its first entry and primitive count
//!   packed into one word. A step loads one 32-byte node and nothing else.
//! - `leaf_prims`: each leaf entry's primitive in leaf order, a triangle with its vertices, so
//!   a leaf step loads one 48-byte record instead of an index and then the triangle.
//!
//! On lavapipe every load of a storage buffer at a lane-dependent index is a loop over the
//! SIMD group's lanes with a bounds check per lane: fewer, wider loads per step make the
//! traversal about a fifth faster on the 500,000-triangle scene (images unchanged).
//! Twins: `TraversalNode` and `LeafPrim` in shaders/common/types.wgsl.

use crate::bvh::{Bvh, SPHERE_BIT};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// Bits of `first_count` below the primitive count: the first entry (interior node: right
/// child) lies below `1 << LEAF_COUNT_SHIFT`, the count above it.
pub const LEAF_COUNT_SHIFT: u32 = 28;

/// 16-byte words per [`GpuTraversalNode`] (the shader reads `nodes` as words).
pub const NODE_WORDS: u32 = (std::mem::size_of::<GpuTraversalNode>() / 16) as u32;
/// 16-byte words per [`GpuLeafPrim`].
pub const LEAF_PRIM_WORDS: u32 = (std::mem::size_of::<GpuLeafPrim>() / 16) as u32;
const _: () = assert!(std::mem::size_of::<GpuTraversalNode>().is_multiple_of(16));
const _: () = assert!(std::mem::size_of::<GpuLeafPrim>().is_multiple_of(16));

/// Twin of WGSL `TraversalNode`: one node of the GPU's traversal in one child order.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTraversalNode {
    /// Lower corner of the node's bounds.
    pub bmin: [f32; 3],
    /// `left_first | count << LEAF_COUNT_SHIFT` (see [`crate::bvh::BvhNode`]).
    pub first_count: u32,
    /// Upper corner of the node's bounds.
    pub bmax: [f32; 3],
    /// The node after this one's subtree in this copy's order, or `NO_NODE`.
    pub skip: u32,
}

/// Twin of WGSL `LeafPrim`: one leaf entry: its primitive id (as in `Bvh::prim_ids`) and, for
/// a triangle, its vertices (zero for a sphere, which the shader reads from `spheres`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLeafPrim {
    /// First vertex.
    pub v0: [f32; 3],
    /// The primitive id: a triangle index, or a sphere index with `SPHERE_BIT`.
    pub id: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// Padding.
    pub _pad1: u32,
}

/// The traversal nodes: `bvh.nodes.len()` in left-first order, then as many in right-first
/// order. None when the hierarchy does not fit the packed word (2^28 nodes or leaf entries,
/// where a storage binding runs out long before, or a leaf of 16 primitives, which the build
/// never makes).
pub fn traversal_nodes(bvh: &Bvh) -> Option<Vec<GpuTraversalNode>> {
    let limit = 1usize << LEAF_COUNT_SHIFT;
    let counts_fit = bvh
        .nodes
        .iter()
        .all(|n| n.count < 1 << (32 - LEAF_COUNT_SHIFT));
    if bvh.nodes.len() >= limit || bvh.prim_ids.len() >= limit || !counts_fit {
        return None;
    }
    let links = bvh.links();
    let mut out = Vec::with_capacity(2 * bvh.nodes.len());
    for order in 0..2 {
        out.extend(bvh.nodes.iter().zip(&links).map(|(n, l)| GpuTraversalNode {
            bmin: n.bmin,
            first_count: n.left_first | n.count << LEAF_COUNT_SHIFT,
            bmax: n.bmax,
            skip: l[order],
        }));
    }
    Some(out)
}

/// One record per entry of `bvh.prim_ids`, in that order (one placeholder when there is
/// none: a binding cannot be empty).
pub fn leaf_prims(bvh: &Bvh, scene: &Scene) -> Vec<GpuLeafPrim> {
    let mut out: Vec<GpuLeafPrim> = bvh
        .prim_ids
        .iter()
        .map(|&id| {
            if id & SPHERE_BIT != 0 {
                return GpuLeafPrim {
                    id,
                    ..GpuLeafPrim::default()
                };
            }
            let t = &scene.triangles[id as usize];
            GpuLeafPrim {
                v0: t.v0.to_array(),
                id,
                v1: t.v1.to_array(),
                v2: t.v2.to_array(),
                ..GpuLeafPrim::default()
            }
        })
        .collect();
    if out.is_empty() {
        out.push(GpuLeafPrim::default());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_copy_holds_the_nodes_their_links_and_the_leaves_their_triangles() {
        // Quads (two triangles each) and two analytic spheres.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-caustics.toml");
        let scene = crate::scene::load(std::path::Path::new(path)).expect("scene");
        assert!(!scene.spheres.is_empty() && !scene.triangles.is_empty());
        let bvh = Bvh::build(&scene);
        let nodes = traversal_nodes(&bvh).expect("small enough");
        let links = bvh.links();
        let n = bvh.nodes.len();
        assert_eq!(nodes.len(), 2 * n);
        for (i, b) in bvh.nodes.iter().enumerate() {
            for order in 0..2 {
                let t = nodes[order * n + i];
                assert_eq!((t.bmin, t.bmax), (b.bmin, b.bmax));
                assert_eq!(t.first_count & ((1 << LEAF_COUNT_SHIFT) - 1), b.left_first);
                assert_eq!(t.first_count >> LEAF_COUNT_SHIFT, b.count);
                assert_eq!(t.skip, links[i][order]);
            }
        }
        let prims = leaf_prims(&bvh, &scene);
        assert_eq!(prims.len(), bvh.prim_ids.len());
        for (p, &id) in prims.iter().zip(&bvh.prim_ids) {
            assert_eq!(p.id, id);
            if id & SPHERE_BIT == 0 {
                let t = &scene.triangles[id as usize];
                assert_eq!([p.v0, p.v1, p.v2], [t.v0, t.v1, t.v2].map(|v| v.to_array()));
            }
        }
    }
}
