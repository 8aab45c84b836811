//! The CPU backend's hierarchy: the binary SAH tree ([`Bvh`]) collapsed into nodes of up to
//! eight children whose boxes one SIMD test checks at once, with each leaf's triangles in
//! blocks of four tested together (the watertight test of `crate::math::geometry`, lane by lane
//! the same arithmetic). The instruction set is picked at run time ([`Isa`]): AVX-512, AVX2,
//! SSE2 or portable scalar code, one binary for all.
//!
//! Same hits as [`Bvh::intersect`] and [`Bvh::occluded`]: the closest hit (the first of
//! equal ones may differ, as the visiting order does), alpha-tested materials and spheres
//! included. A box test never misses what the binary one finds; a ray lying exactly in the
//! plane of a box face enters it here (the binary test's `0 * inf` rejects it).

use super::simd::{self, Isa};
use super::{surface, Bvh, Hit};
use crate::math::geometry::Ray;
use crate::scene::Scene;

/// Children per node.
pub const WIDTH: usize = 8;
/// Triangles per leaf block.
pub const BLOCK: usize = 4;
/// Marks a leaf in [`Node8::child`]: the rest is an index into [`WideBvh::leaves`].
pub const LEAF_BIT: u32 = 0x8000_0000;
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
    /// A node index, [`LEAF_BIT`] | a leaf index, or [`EMPTY`].
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

/// Four triangles, structure of arrays: `v0[axis][lane]` and so on; `n` is each triangle's
/// unnormalised normal `(v1 - v0) x (v2 - v0)` as `intersect_triangle` computes it. Unused
/// lanes are degenerate (all corners zero), which the test never hits.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriBlock {
    /// First corners.
    pub v0: [[f32; BLOCK]; 3],
    /// Second corners.
    pub v1: [[f32; BLOCK]; 3],
    /// Third corners.
    pub v2: [[f32; BLOCK]; 3],
    /// Unnormalised normals.
    pub n: [[f32; BLOCK]; 3],
    /// Triangle indices into `Scene::triangles` (unused lanes: `u32::MAX`).
    pub id: [u32; BLOCK],
}

/// A leaf: its triangle blocks and its spheres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Leaf {
    /// First block in [`WideBvh::blocks`].
    pub first_block: u32,
    /// Number of blocks.
    pub blocks: u32,
    /// First entry of [`WideBvh::spheres`].
    pub first_sphere: u32,
    /// Number of spheres.
    pub spheres: u32,
}

/// The 8-wide hierarchy.
#[derive(Clone, Debug)]
pub struct WideBvh {
    /// Nodes; node 0 is the root.
    pub nodes: Vec<Node8>,
    /// Leaves.
    pub leaves: Vec<Leaf>,
    /// Triangle blocks, each leaf's contiguous.
    pub blocks: Vec<TriBlock>,
    /// Sphere indices into `Scene::spheres`, each leaf's contiguous.
    pub spheres: Vec<u32>,
    /// Whether some material is alpha-tested (as [`Bvh::alpha`]).
    pub alpha: bool,
    /// The instruction set the walks use.
    pub isa: Isa,
}

/// The closest hit of a walk: primitive id (as in [`Bvh::prim_ids`]), `t` and a triangle's
/// barycentrics `u`, `v` (zero for a sphere).
pub type Closest = (u32, f32, f32, f32);

impl WideBvh {
    /// Builds the hierarchy over every triangle and sphere of `scene`, walked with the best
    /// instruction set this CPU has.
    pub fn build(scene: &Scene) -> Self {
        Self::from_binary(&Bvh::build_with(scene, super::build_wide::WIDE_COSTS), scene)
    }

    /// Collapses the binary hierarchy `bvh` of `scene`.
    pub fn from_binary(bvh: &Bvh, scene: &Scene) -> Self {
        super::build_wide::collapse(bvh, scene)
    }

    /// The same hierarchy walked with `isa` (which this CPU must have: see
    /// [`Isa::available`]; otherwise the best it has).
    pub fn with_isa(mut self, isa: Isa) -> Self {
        self.isa = if isa.available() { isa } else { Isa::detect() };
        self
    }

    /// Bytes the hierarchy takes (nodes, leaves, blocks, sphere lists).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.len() * size_of::<Node8>()
            + self.leaves.len() * size_of::<Leaf>()
            + self.blocks.len() * size_of::<TriBlock>()
            + self.spheres.len() * 4
    }

    /// The closest hit along `ray` before `t_max`, without assembling the surface.
    #[inline]
    pub fn closest(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Closest> {
        simd::closest(self, scene, ray, t_max)
    }

    /// Nearest hit along `ray` before `t_max` (as [`Bvh::intersect`]).
    #[inline]
    pub fn intersect(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (id, t, u, v) = self.closest(scene, ray, t_max)?;
        Some(surface::hit_at(scene, ray, id, t, u, v))
    }

    /// Whether anything blocks `ray` before `t_max` (as [`Bvh::occluded`]).
    #[inline]
    pub fn occluded(&self, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
        simd::occluded(self, scene, ray, t_max)
    }
}
