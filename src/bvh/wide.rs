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

use super::isa::Isa;
use super::simd;
pub use super::wide_layout::*;
use super::{surface, Bvh, Hit};
use crate::math::geometry::Ray;
use crate::scene::Scene;

impl WideBvh {
    /// Builds the hierarchy over every triangle and sphere of `scene`, walked with the best
    /// instruction set this CPU has.
    pub fn build(scene: &Scene) -> Self {
        Self::from_binary(&super::build_binned::build(scene), scene)
    }

    /// Collapses the binary hierarchy `bvh` of `scene` (whose leaves hold at most
    /// `MAX_LEAF_BLOCKS * BLOCK` primitives each: larger ones are split by index).
    pub fn from_binary(bvh: &Bvh, scene: &Scene) -> Self {
        super::build_wide::collapse(bvh, scene)
    }

    /// The same hierarchy walked with `isa` (which this CPU must have: see
    /// [`Isa::available`]; otherwise the best it has).
    pub fn with_isa(mut self, isa: Isa) -> Self {
        self.isa = if isa.available() { isa } else { Isa::detect() };
        self
    }

    /// Bytes the hierarchy takes (nodes and blocks).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.len() * size_of::<Node8>() + self.blocks.len() * size_of::<TriBlock>()
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
