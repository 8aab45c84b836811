//! The wide BVH's memory layout: 8-child nodes, leaf references, 4-primitive blocks, and the
//! hierarchy that holds them (`wide.rs` builds and walks it).

use super::isa::Isa;

/// Children per node.
pub const WIDTH: usize = 8;
/// Triangles per leaf block.
pub const BLOCK: usize = 4;
/// Marks a leaf in [`Node8::child`]: bits 0..27 are its first block in
/// [`WideBvh::blocks`], bits 27..31 its number of blocks less one.
pub const LEAF_BIT: u32 = 0x8000_0000;
/// Where a leaf reference keeps its block count.
pub const LEAF_COUNT_SHIFT: u32 = 27;
/// Most blocks in a leaf.
pub const MAX_LEAF_BLOCKS: usize = 16;
/// The id of an unused lane of a block.
pub const NO_PRIM: u32 = 0x7fff_ffff;
/// An unused child slot (its box is empty: `min = +inf`, `max = -inf`, which no ray enters).
pub const EMPTY: u32 = u32::MAX;
/// Row of [`Node8::bounds`] holding the children's lower x; +3 for the upper.
pub const MIN_X: usize = 0;

/// One node: its children's boxes as rows (min x, y, z, max x, y, z) of eight lanes, then
/// their references. 224 bytes, aligned for 256-bit loads.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node8 {
    /// `bounds[axis][lane]` lower corners (rows 0..3), `bounds[3 + axis][lane]` upper ones.
    pub bounds: [[f32; WIDTH]; 6],
    /// A node index, a leaf reference ([`LEAF_BIT`]), or [`EMPTY`].
    pub child: [u32; WIDTH],
}

impl Node8 {
    /// A node with no children.
    pub const EMPTY: Node8 = Node8 {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [EMPTY; WIDTH],
    };
}

/// Four primitives, structure of arrays: triangles' corners `v0[axis][lane]` and so on,
/// `n` each triangle's unnormalised normal `(v1 - v0) x (v2 - v0)` as `intersect_triangle`
/// computes it. A sphere's lane has its id (with `SPHERE_BIT`) and degenerate corners (all
/// zero), as has an unused lane (id [`NO_PRIM`]): the triangle test never hits them.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriBlock {
    /// First corners.
    pub v0: [[f32; BLOCK]; 3],
    /// Second corners.
    pub v1: [[f32; BLOCK]; 3],
    /// Third corners.
    pub v2: [[f32; BLOCK]; 3],
    /// Primitive ids as in `Bvh::prim_ids`, or [`NO_PRIM`] (before the normals: a ray
    /// that misses every lane reads the first 160 bytes only).
    pub id: [u32; BLOCK],
    /// Unnormalised normals.
    pub n: [[f32; BLOCK]; 3],
}

impl TriBlock {
    /// The lanes holding spheres, as a bit mask.
    #[inline(always)]
    pub fn sphere_lanes(&self) -> u32 {
        let mut m = 0;
        for (i, id) in self.id.iter().enumerate() {
            m |= (id >> 31) << i;
        }
        m
    }
}

/// The blocks of leaf reference `child`: (first, count).
#[inline(always)]
pub fn leaf_blocks(child: u32) -> (usize, usize) {
    let first = child & ((1 << LEAF_COUNT_SHIFT) - 1);
    let count = ((child & !LEAF_BIT) >> LEAF_COUNT_SHIFT) + 1;
    (first as usize, count as usize)
}

/// The 8-wide hierarchy.
#[derive(Clone, Debug)]
pub struct WideBvh {
    /// Nodes; node 0 is the root.
    pub nodes: Vec<Node8>,
    /// Primitive blocks, each leaf's contiguous.
    pub blocks: Vec<TriBlock>,
    /// Whether some material is alpha-tested (as `Bvh::alpha`).
    pub alpha: bool,
    /// The instruction set the walks use.
    pub isa: Isa,
    /// The scene's instances (`super::instances`); `None` in a scene without them.
    pub instances: Option<Box<super::instances::InstanceBvh>>,
    /// The scene's SDF grids (`super::sdf`); `None` in a scene without them.
    pub sdf: Option<Box<super::sdf::SdfBvh>>,
}

/// The closest hit of a walk: primitive id (as in `Bvh::prim_ids`), `t` and a triangle's
/// barycentrics `u`, `v` (zero for a sphere).
pub type Closest = (u32, f32, f32, f32);
