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
        let mut bvh = Self::from_binary(&super::build_binned::build(scene), scene);
        bvh.instances = super::instances::InstanceBvh::build(scene).map(Box::new);
        bvh.sdf = super::sdf::SdfBvh::build(scene).map(Box::new);
        bvh
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
        let instances = self.instances.as_ref().map_or(0, |i| i.memory_bytes());
        let sdf = self.sdf.as_ref().map_or(0, |s| s.memory_bytes());
        self.nodes.len() * size_of::<Node8>()
            + self.blocks.len() * size_of::<TriBlock>()
            + instances
            + sdf
    }

    /// The closest hit along `ray` before `t_max`, without assembling the surface (the
    /// scene's own primitives only, not its instances).
    #[inline]
    pub fn closest(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Closest> {
        simd::closest(self, scene, ray, t_max)
    }

    /// Nearest hit along `ray` before `t_max` (as [`Bvh::intersect`]).
    #[inline]
    pub fn intersect(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Hit> {
        let flat = self.closest(scene, ray, t_max);
        let mut t = flat.map_or(t_max, |c| c.1);
        let mut nearer = None;
        if let Some(instances) = &self.instances {
            if let Some(hit) = instances.intersect(scene, ray, t) {
                t = hit.t;
                nearer = Some(hit);
            }
        }
        if let Some(sdf) = &self.sdf {
            if let Some(hit) = sdf.intersect(scene, ray, t) {
                return Some(hit);
            }
        }
        if nearer.is_some() {
            return nearer;
        }
        let (id, t, u, v) = flat?;
        Some(surface::hit_at(scene, ray, id, t, u, v))
    }

    /// Whether anything blocks `ray` before `t_max` (as [`Bvh::occluded`]).
    #[inline]
    pub fn occluded(&self, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
        simd::occluded(self, scene, ray, t_max)
            || (self.instances.as_ref()).is_some_and(|i| i.occluded(scene, ray, t_max))
            || (self.sdf.as_ref()).is_some_and(|s| s.occluded(scene, ray, t_max))
    }
}
