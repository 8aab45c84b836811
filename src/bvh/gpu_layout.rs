//! The BVH as the GPU walks it (`trace_ray` in src/bvh/intersect.wgsl): the hierarchy
//! of src/bvh/mod.rs, built with [`GPU_COSTS`], copied into the two arrays a traversal step reads.
//!
//! - `nodes`: a [`GpuBvhFrame`], then every node once per child order (left child first,
//!   then right child first), each copy numbered in its own depth-first preorder. A node is
//!   one 16-byte word: its box on the frame's grid (16 bits per bound, rounded outwards, so
//!   decoding is exact integer-to-float arithmetic) and one link. In preorder an interior
//!   node's first child is the next node, and so is whatever follows a leaf; so an interior
//!   node keeps only where its subtree ends (taken when its box is missed) and a leaf only its
//!   primitives (first entry and count).
//! - `leaf_prims`: each leaf entry's primitive in leaf order, a triangle with its vertices, so
//!   a leaf step loads one 48-byte record instead of an index and then the triangle.
//!
//! On lavapipe every load of a storage buffer at a lane-dependent index is a loop over the
//! SIMD group's lanes with a bounds check per lane, so a step's cost is its loads: one word
//! per node, where full-precision boxes and two links took two.
//! Twins: `BvhFrame`, `TraversalNode` and `LeafPrim` in src/integrators/gpu/types.wgsl.

use crate::bvh::{BuildCosts, Bvh, SPHERE_BIT};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// The SAH costs of the GPU's hierarchy: a node step loads one 16-byte word, a triangle test
/// three, and on lavapipe loads set the cost (a step a third of a test, where the CPU's costs
/// weigh them alike).
pub const GPU_COSTS: BuildCosts = BuildCosts {
    node_step: NODE_STEP_COST,
    max_leaf: GPU_MAX_LEAF,
};
const NODE_STEP_COST: f32 = 1.0 / 3.0;
const GPU_MAX_LEAF: usize = 2;

/// Bits of a leaf's `link` below its primitive count: its first leaf entry lies below
/// `1 << LEAF_COUNT_SHIFT`, the count (at least 1) above it; an interior node's link (the
/// node after its subtree) has count bits 0.
pub const LEAF_COUNT_SHIFT: u32 = 28;
/// Largest grid coordinate of a quantised bound (16 bits).
const GRID_MAX: i64 = 0xffff;
/// Frame bases and grid coordinates stay below this magnitude, so that `base + q` converts
/// to f32 exactly.
const EXACT_INT: i64 = 1 << 24;

/// 16-byte words per [`GpuTraversalNode`] (the shader reads `nodes` as words).
pub const NODE_WORDS: u32 = (std::mem::size_of::<GpuTraversalNode>() / 16) as u32;
/// 16-byte words of the [`GpuBvhFrame`] before the nodes.
pub const FRAME_WORDS: u32 = (std::mem::size_of::<GpuBvhFrame>() / 16) as u32;
/// 16-byte words per [`GpuLeafPrim`].
pub const LEAF_PRIM_WORDS: u32 = (std::mem::size_of::<GpuLeafPrim>() / 16) as u32;
const _: () = assert!(std::mem::size_of::<GpuTraversalNode>().is_multiple_of(16));
const _: () = assert!(std::mem::size_of::<GpuBvhFrame>().is_multiple_of(16));
const _: () = assert!(std::mem::size_of::<GpuLeafPrim>().is_multiple_of(16));

/// Twin of WGSL `BvhFrame`: the grid of the quantised boxes. Grid coordinate `q` on axis
/// `a` is the point `(base[a] + q) * step[a]`, computed exactly in f32 (`step` is a power of
/// two and `|base + q| < 2^24`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBvhFrame {
    /// Grid origin, in steps.
    pub base: [i32; 3],
    /// Nodes per copy (the traversal ends at this index).
    pub nodes: u32,
    /// Grid spacing per axis, a power of two.
    pub step: [f32; 3],
    /// The word where the next level starts (`super::gpu_instances`): in the world
    /// hierarchy's frame the instances' top level (0: no instances), in the top level's the
    /// instance records.
    pub next: u32,
}

/// Twin of WGSL `TraversalNode`: one node of one copy. `qx`, `qy`, `qz` hold the box's lower
/// grid coordinate in the low 16 bits and its upper one in the high 16 bits.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTraversalNode {
    /// Box on x.
    pub qx: u32,
    /// Box on y.
    pub qy: u32,
    /// Box on z.
    pub qz: u32,
    /// Interior: the node after its subtree in this copy's preorder (the copy's node count
    /// after the last). Leaf: `first | count << LEAF_COUNT_SHIFT`.
    pub link: u32,
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

/// The traversal's node array: the frame's words, then each copy's nodes.
#[derive(Clone, Debug)]
pub struct TraversalLayout {
    /// The grid.
    pub frame: GpuBvhFrame,
    /// Left-first copy (preorder), then the right-first copy.
    pub nodes: Vec<GpuTraversalNode>,
    /// Copy index of each `Bvh` node: `position[c][i]` is node i's index in copy c.
    pub position: [Vec<u32>; 2],
}

impl TraversalLayout {
    /// The bytes of the `nodes` binding: the frame, then the nodes.
    pub fn bytes(&self) -> Vec<u8> {
        let mut out = bytemuck::bytes_of(&self.frame).to_vec();
        out.extend_from_slice(bytemuck::cast_slice(&self.nodes));
        out
    }

    /// The box of copy node `n`, decoded as the shader does.
    pub fn bounds(&self, n: &GpuTraversalNode) -> ([f32; 3], [f32; 3]) {
        let f = &self.frame;
        let at = |a: usize, q: u32| (f.base[a] + q as i32) as f32 * f.step[a];
        let words = [n.qx, n.qy, n.qz];
        let lo = std::array::from_fn(|a| at(a, words[a] & 0xffff));
        let hi = std::array::from_fn(|a| at(a, words[a] >> 16));
        (lo, hi)
    }
}

/// The grid on one axis for bounds within [lo, hi]: (base, step exponent), or None where no
/// exact power-of-two grid of 16-bit coordinates covers them.
fn axis_grid(lo: f32, hi: f32) -> Option<(i64, i32)> {
    let (lo, hi) = (lo as f64, hi as f64);
    if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
        return Some((0, 0));
    }
    // Normal steps only (lavapipe may flush subnormal results to zero).
    // The bounds are checked in f64 before the casts: a flat negative range at a tiny step
    // (`lo = hi = -1`, step 2^-100) saturated both to i64::MIN, whose abs() wrapped, and the
    // grid decoded every bound as 0 (a ground plane's box moved to y = 0).
    let exact = EXACT_INT as f64;
    for e in -100..=100 {
        let step = 2f64.powi(e);
        let base = (lo / step).floor();
        let top = (hi / step).ceil();
        if top - base <= GRID_MAX as f64
            && base.abs() < exact - GRID_MAX as f64
            && top.abs() < exact
        {
            return Some((base as i64, e));
        }
    }
    None
}

/// The grid of a hierarchy's quantised boxes, spanning its root's box: per axis the base
/// and the step's exponent (`axis_grid`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxGrid([(i64, i32); 3]);

impl BoxGrid {
    /// The grid of the hierarchy whose root is `root`; None where no exact grid covers it.
    pub(crate) fn of(root: &crate::bvh::BvhNode) -> Option<Self> {
        let grid = [0, 1, 2].map(|a| axis_grid(root.bmin[a], root.bmax[a]));
        Some(BoxGrid([grid[0]?, grid[1]?, grid[2]?]))
    }

    /// Its frame, for a copy of `nodes` nodes.
    pub(crate) fn frame(&self, nodes: u32) -> GpuBvhFrame {
        GpuBvhFrame {
            base: self.0.map(|g| g.0 as i32),
            nodes,
            step: self.0.map(|g| 2f32.powi(g.1)),
            next: 0,
        }
    }

    /// Outward-rounded grid coordinates of a node's box, lower in the low 16 bits and upper
    /// in the high 16 (zero for a non-finite one: only the placeholder of a scene without
    /// primitives, which is never walked).
    pub(crate) fn quantise(&self, b: &crate::bvh::BvhNode) -> [u32; 3] {
        std::array::from_fn(|a| {
            let (base, e) = self.0[a];
            let (lo, hi) = (b.bmin[a] as f64, b.bmax[a] as f64);
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return 0;
            }
            let step = 2f64.powi(e);
            let q = |v: i64| (v - base).clamp(0, GRID_MAX) as u32;
            q((lo / step).floor() as i64) | q((hi / step).ceil() as i64) << 16
        })
    }
}

/// The traversal layout of `bvh`. None when it does not fit: 2^28 nodes or leaf entries
/// (where a storage binding runs out long before), a leaf of 16 primitives (which the build
/// never makes), or a scene wider than 65,535 x 2^100 (about 8e34) or farther out than
/// 2^124 (only coordinates beyond about 1e34 come near either).
pub fn traversal_nodes(bvh: &Bvh) -> Option<TraversalLayout> {
    let limit = 1usize << LEAF_COUNT_SHIFT;
    let counts_fit = bvh
        .nodes
        .iter()
        .all(|n| n.count < 1 << (32 - LEAF_COUNT_SHIFT));
    if bvh.nodes.len() >= limit || bvh.prim_ids.len() >= limit || !counts_fit {
        return None;
    }
    let n = bvh.nodes.len();
    let grid = BoxGrid::of(&bvh.nodes[0])?;
    let frame = grid.frame(n as u32);
    let mut nodes: Vec<GpuTraversalNode> = Vec::with_capacity(2 * n);
    let mut position = [vec![0u32; n], vec![0u32; n]];
    for (copy, right_first) in [false, true].into_iter().enumerate() {
        let offset = nodes.len();
        let start = &mut position[copy];
        // Preorder; an interior node's link, the end of its subtree, is patched in once its
        // children are placed (the placeholder root of a scene without primitives has none).
        let mut todo = vec![(0usize, false)];
        while let Some((i, done)) = todo.pop() {
            let b = &bvh.nodes[i];
            if done {
                nodes[offset + start[i] as usize].link = (nodes.len() - offset) as u32;
                continue;
            }
            start[i] = (nodes.len() - offset) as u32;
            let [qx, qy, qz] = grid.quantise(b);
            let link = if b.count > 0 {
                b.left_first | b.count << LEAF_COUNT_SHIFT
            } else {
                0
            };
            nodes.push(GpuTraversalNode { qx, qy, qz, link });
            if b.count == 0 {
                todo.push((i, true));
                if !bvh.prim_ids.is_empty() {
                    let (l, r) = (i + 1, b.left_first as usize);
                    let (first, second) = if right_first { (r, l) } else { (l, r) };
                    todo.push((second, false));
                    todo.push((first, false));
                }
            }
        }
    }
    Some(TraversalLayout {
        frame,
        nodes,
        position,
    })
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
    fn leaves_hold_their_triangles() {
        // Quads (two triangles each) and two analytic spheres.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-caustics.toml");
        let scene = crate::importers::load(std::path::Path::new(path)).expect("scene");
        assert!(!scene.spheres.is_empty() && !scene.triangles.is_empty());
        let bvh = Bvh::build(&scene);
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

    #[test]
    fn grids_are_exact_and_cover_their_range() {
        for (lo, hi) in [
            (-1.0f32, 1.0),
            (1000.0, 1000.001),
            (-3.0e7, 5.0),
            (0.0, 0.0),
            (2.5e-3, 2.5e-3),
            (-1.0, -1.0),
            (-2.5e-3, -2.5e-3),
        ] {
            let (base, e) = axis_grid(lo, hi).expect("a grid");
            let step = 2f64.powi(e);
            assert!(base as f64 * step <= lo as f64, "{lo}");
            assert!((base + GRID_MAX) as f64 * step >= hi as f64, "{hi}");
            assert!(base.abs() + GRID_MAX < EXACT_INT);
        }
        assert!(axis_grid(-1.0e38, 1.0e38).is_none());
    }
}
