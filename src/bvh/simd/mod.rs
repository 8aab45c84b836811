//! The wide hierarchy's walks, written once over a [`Kernel`] (a node's eight box tests and a
//! block's four triangle tests) and compiled for each instruction set; [`Isa`] picks one at
//! run time.
//!
//! Per ray: the slab test's planes are chosen by the direction's signs (no min/max of the
//! two distances), with `1 / d` kept finite (`+-f32::MAX` where `d` is zero) so that a box
//! face through the origin gives 0, never `0 * inf`; the exit distance is widened by
//! `BOX_SLACK` as in [`crate::math::geometry::Aabb::hit`]. The triangle test is
//! [`crate::math::geometry::intersect_triangle`]'s arithmetic, operation for operation.

mod scalar;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use super::isa::Isa;
use super::wide_layout::{leaf_blocks, Closest, TriBlock, WideBvh, EMPTY, LEAF_BIT};
use super::{alpha_passes, SPHERE_BIT};
use crate::math::geometry::{intersect_sphere, Ray, Shear};
use crate::scene::Scene;
use std::mem::MaybeUninit;

/// What a walk needs of a ray, computed once.
#[derive(Clone, Copy, Debug)]
pub(super) struct Prepared {
    /// Origin.
    pub o: [f32; 3],
    /// `1 / d`, finite.
    pub inv: [f32; 3],
    /// Row of `Node8::bounds` the ray enters each slab by (the lower plane where `d >= 0`).
    pub near_row: [usize; 3],
    /// Row it leaves each slab by.
    pub far_row: [usize; 3],
    /// Shear axes `[kx, ky, kz]` of the triangle test.
    pub k: [usize; 3],
    /// The shear.
    pub s: [f32; 2],
    /// Direction.
    pub d: [f32; 3],
}

impl Prepared {
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        let i = glam::Vec3A::ONE / glam::Vec3A::from(ray.dir);
        let finite = glam::Vec3A::select(i.is_finite_mask(), i, glam::Vec3A::MAX.copysign(i));
        let inv = finite.to_array();
        let (mut near_row, mut far_row) = ([0; 3], [0; 3]);
        for a in 0..3 {
            let neg = inv[a].is_sign_negative() as usize;
            near_row[a] = a + 3 * neg;
            far_row[a] = a + 3 * (1 - neg);
        }
        let (k, s) = Shear::new(ray.dir).axes();
        Prepared {
            o: ray.origin.to_array(),
            inv,
            near_row,
            far_row,
            k,
            s: s.to_array(),
            d: ray.dir.to_array(),
        }
    }
}

/// The lanes of a block the ray hits before `t_max`, with what `intersect_triangle` returns
/// for them: `t`, and `u = e1 / det`, `v = e2 / det`. Left uninitialised until a block test
/// writes the lanes it hits: zeroing its 64 bytes per leaf made LLVM emit a 512-bit store in
/// the AVX-512 walks, and on Intel cores any 512-bit instruction slows the vector units around
/// it (the Cornell box's shadow rays ran 25% slower than with the AVX2 kernel).
#[derive(Clone, Copy, Debug)]
pub(super) struct TriHits {
    pub t: [f32; 4],
    pub e1: [f32; 4],
    pub e2: [f32; 4],
    pub det: [f32; 4],
}

impl TriHits {
    /// The first floats of the rows `t`, `e1`, `e2` and `det` of `*h`, which may be
    /// uninitialised (no reference to it is made): the block tests write through them.
    #[inline(always)]
    pub(super) unsafe fn rows(h: *mut TriHits) -> [*mut f32; 4] {
        use std::ptr::addr_of_mut;
        [
            addr_of_mut!((*h).t).cast(),
            addr_of_mut!((*h).e1).cast(),
            addr_of_mut!((*h).e2).cast(),
            addr_of_mut!((*h).det).cast(),
        ]
    }

    /// `t`, `e1`, `e2` and `det` of `lane`, which the last block test wrote (a lane of its
    /// mask).
    #[inline(always)]
    unsafe fn lane(h: *mut TriHits, lane: usize) -> (f32, f32, f32, f32) {
        let [t, e1, e2, det] = Self::rows(h).map(|row| row.add(lane).read());
        (t, e1, e2, det)
    }
}

/// A node test and a block test for one instruction set.
pub(super) trait Kernel {
    /// The ray, splatted into registers.
    type Ray: Copy;
    /// Splats `p`.
    unsafe fn ray(p: &Prepared) -> Self::Ray;
    /// The children of `node` whose boxes the ray enters before `t_max`, compacted into
    /// `near` (entry distance) and `child`; returns how many.
    unsafe fn node(
        node: &super::wide_layout::Node8,
        r: &Self::Ray,
        t_max: f32,
        near: &mut [f32; 8],
        child: &mut [u32; 8],
    ) -> usize;
    /// Asks for the cache lines `at..at + bytes` before they are read (a no-op where the
    /// kernel has no prefetch).
    #[inline(always)]
    unsafe fn prefetch(_at: *const u8, _bytes: usize) {}
    /// The lanes of `block` hit in (0, t_max) as a bit mask; writes (at least) those lanes
    /// of `*out`.
    unsafe fn block(
        block: &super::wide_layout::TriBlock,
        r: &Self::Ray,
        t_max: f32,
        out: *mut TriHits,
    ) -> u32;
}

/// Stack entries: up to seven deferred children per level of a tree at most
/// `super::MAX_DEPTH` deep.
const STACK: usize = 7 * super::MAX_DEPTH + 8;

/// What a walk does at a leaf.
trait Visit {
    /// Tests the leaf of `blocks` against the ray up to `t_max`; returns a new `t_max` on
    /// a hit (negative stops the walk).
    unsafe fn leaf(&mut self, blocks: &[TriBlock], t_max: f32) -> Option<f32>;
}

/// Visits the leaves whose boxes the ray enters, nearest box first (`NEAR_FIRST`), or
/// farthest first: an any-hit walk from a surface finds a blocker sooner away from the
/// surface it leaves (1M-triangle benchmark mesh: 0.78 of Embree's rays/s against 0.6-0.66;
/// the 32-triangle Cornell box loses 5% by it).
#[inline(always)]
unsafe fn walk<K: Kernel, const NEAR_FIRST: bool>(
    bvh: &WideBvh,
    r: &K::Ray,
    t_max: f32,
    visit: &mut impl Visit,
) {
    let mut t_max = t_max;
    let mut stack_node = [MaybeUninit::<u32>::uninit(); STACK];
    let mut stack_t = [MaybeUninit::<f32>::uninit(); STACK];
    let mut sp = 0usize;
    let mut near = [0.0f32; 8];
    let mut child = [0u32; 8];
    let mut cur = 0u32;
    loop {
        if cur & LEAF_BIT == 0 {
            let node = bvh.nodes.get_unchecked(cur as usize);
            let k = K::node(node, r, t_max, &mut near, &mut child);
            if k == 1 {
                cur = child[0];
                continue;
            }
            if k == 2 {
                // The common case: defer one child.
                let far = ((near[0] <= near[1]) == NEAR_FIRST) as usize;
                defer::<K>(bvh, child[far]);
                if sp < STACK {
                    stack_node[sp].write(child[far]);
                    stack_t[sp].write(near[far]);
                    sp += 1;
                }
                cur = child[1 - far];
                continue;
            }
            if k > 2 {
                // Sort by entry distance, farthest first; push all but the nearest.
                for i in 1..k {
                    let (t, c) = (near[i], child[i]);
                    let mut j = i;
                    while j > 0 && (near[j - 1] < t) == NEAR_FIRST {
                        near[j] = near[j - 1];
                        child[j] = child[j - 1];
                        j -= 1;
                    }
                    near[j] = t;
                    child[j] = c;
                }
                for i in 0..k - 1 {
                    defer::<K>(bvh, child[i]);
                    if sp < STACK {
                        stack_node[sp].write(child[i]);
                        stack_t[sp].write(near[i]);
                        sp += 1;
                    }
                }
                cur = child[k - 1];
                continue;
            }
        } else if cur != EMPTY {
            // A ray whose slab tests turn NaN (an origin or box at infinity: a photon from
            // the disc of a scene with a vertex near f32::MAX) may enter an empty slot: only a
            // real leaf's blocks are read, and only within the block list.
            let (first, count) = leaf_blocks(cur);
            if let Some(blocks) = bvh.blocks.get(first..first + count) {
                match visit.leaf(blocks, t_max) {
                    Some(t) if t < 0.0 => return,
                    Some(t) => t_max = t,
                    None => {}
                }
            }
        }
        loop {
            if sp == 0 {
                return;
            }
            sp -= 1;
            if stack_t[sp].assume_init() <= t_max {
                cur = stack_node[sp].assume_init();
                break;
            }
        }
    }
}

/// A deferred child is likely visited: starts its loads now.
#[inline(always)]
unsafe fn defer<K: Kernel>(bvh: &WideBvh, c: u32) {
    if c & LEAF_BIT == 0 {
        let at = bvh.nodes.as_ptr().add(c as usize) as *const u8;
        K::prefetch(at, std::mem::size_of::<super::wide_layout::Node8>());
    } else if let Some(b) = bvh.blocks.get(leaf_blocks(c).0) {
        // The first block (a leaf's further blocks follow it in memory); an empty slot's
        // reference names none.
        K::prefetch(
            b as *const TriBlock as *const u8,
            std::mem::size_of::<TriBlock>(),
        );
    }
}

/// The ray and hierarchy a leaf test reads.
struct LeafTest<'a, K: Kernel> {
    bvh: &'a WideBvh,
    scene: &'a Scene,
    ray: &'a Ray,
    r: K::Ray,
}

impl<K: Kernel> LeafTest<'_, K> {
    /// Whether the alpha test lets the ray through primitive `id` hit at `t` (`u`, `v`).
    #[inline(always)]
    fn passes(&self, id: u32, t: f32, u: f32, v: f32) -> bool {
        self.bvh.alpha && alpha_passes(self.scene, id, self.ray, t, u, v)
    }
}

/// The closest-hit walk's leaf test.
struct ClosestVisit<'a, K: Kernel> {
    test: LeafTest<'a, K>,
    best: Option<Closest>,
}

impl<K: Kernel> Visit for ClosestVisit<'_, K> {
    #[inline(always)]
    unsafe fn leaf(&mut self, blocks: &[TriBlock], t_max: f32) -> Option<f32> {
        let mut hits = MaybeUninit::<TriHits>::uninit();
        let h = hits.as_mut_ptr();
        let mut t_lim = t_max;
        let mut found = false;
        for b in blocks {
            let mut m = K::block(b, &self.test.r, t_lim, h);
            while m != 0 {
                // The nearest lane, the first of equal ones.
                let mut lane = m.trailing_zeros() as usize;
                let mut rest = m & (m - 1);
                while rest != 0 {
                    let j = rest.trailing_zeros() as usize;
                    if TriHits::lane(h, j).0 < TriHits::lane(h, lane).0 {
                        lane = j;
                    }
                    rest &= rest - 1;
                }
                let (t, e1, e2, det) = TriHits::lane(h, lane);
                let id = b.id[lane];
                let (u, v) = (e1 / det, e2 / det);
                if self.test.passes(id, t, u, v) {
                    m &= !(1 << lane);
                    continue;
                }
                self.best = Some((id, t, u, v));
                t_lim = t;
                found = true;
                break;
            }
            let mut spheres = b.sphere_lanes();
            while spheres != 0 {
                let id = b.id[spheres.trailing_zeros() as usize];
                spheres &= spheres - 1;
                let sphere = &self.test.scene.spheres[(id & !SPHERE_BIT) as usize];
                if let Some(t) = intersect_sphere(sphere, self.test.ray, t_lim) {
                    if !self.test.passes(id, t, 0.0, 0.0) {
                        self.best = Some((id, t, 0.0, 0.0));
                        t_lim = t;
                        found = true;
                    }
                }
            }
        }
        found.then_some(t_lim)
    }
}

/// The any-hit walk's leaf test.
struct OccludedVisit<'a, K: Kernel> {
    test: LeafTest<'a, K>,
    hit: bool,
}

impl<K: Kernel> Visit for OccludedVisit<'_, K> {
    #[inline(always)]
    unsafe fn leaf(&mut self, blocks: &[TriBlock], t_max: f32) -> Option<f32> {
        let mut hits = MaybeUninit::<TriHits>::uninit();
        let h = hits.as_mut_ptr();
        for b in blocks {
            let mut m = K::block(b, &self.test.r, t_max, h);
            while m != 0 {
                let lane = m.trailing_zeros() as usize;
                m &= m - 1;
                let (t, e1, e2, det) = TriHits::lane(h, lane);
                let (u, v) = (e1 / det, e2 / det);
                if !self.test.passes(b.id[lane], t, u, v) {
                    self.hit = true;
                    return Some(-1.0);
                }
            }
            let mut spheres = b.sphere_lanes();
            while spheres != 0 {
                let id = b.id[spheres.trailing_zeros() as usize];
                spheres &= spheres - 1;
                let sphere = &self.test.scene.spheres[(id & !SPHERE_BIT) as usize];
                if let Some(t) = intersect_sphere(sphere, self.test.ray, t_max) {
                    if !self.test.passes(id, t, 0.0, 0.0) {
                        self.hit = true;
                        return Some(-1.0);
                    }
                }
            }
        }
        None
    }
}

/// The closest hit, walked with kernel `K`.
#[inline(always)]
unsafe fn closest_with<K: Kernel>(
    bvh: &WideBvh,
    scene: &Scene,
    ray: &Ray,
    t_max: f32,
) -> Option<Closest> {
    let r = K::ray(&Prepared::new(ray));
    let test = LeafTest::<K> { bvh, scene, ray, r };
    let mut v = ClosestVisit { test, best: None };
    walk::<K, true>(bvh, &r, t_max, &mut v);
    v.best
}

/// Whether anything blocks the ray, walked with kernel `K`.
#[inline(always)]
unsafe fn occluded_with<K: Kernel>(bvh: &WideBvh, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
    let r = K::ray(&Prepared::new(ray));
    let test = LeafTest::<K> { bvh, scene, ray, r };
    let mut v = OccludedVisit { test, hit: false };
    walk::<K, false>(bvh, &r, t_max, &mut v);
    v.hit
}

/// Entry points compiled for one instruction set.
macro_rules! entry_points {
    ($closest:ident, $occluded:ident, $kernel:ty, $($feature:tt)*) => {
        $($feature)*
        pub(super) unsafe fn $closest(
            bvh: &crate::bvh::wide_layout::WideBvh,
            scene: &crate::scene::Scene,
            ray: &crate::math::geometry::Ray,
            t_max: f32,
        ) -> Option<crate::bvh::wide_layout::Closest> {
            crate::bvh::simd::closest_with::<$kernel>(bvh, scene, ray, t_max)
        }
        $($feature)*
        pub(super) unsafe fn $occluded(
            bvh: &crate::bvh::wide_layout::WideBvh,
            scene: &crate::scene::Scene,
            ray: &crate::math::geometry::Ray,
            t_max: f32,
        ) -> bool {
            crate::bvh::simd::occluded_with::<$kernel>(bvh, scene, ray, t_max)
        }
    };
}
use entry_points;

/// The closest hit on `bvh` with its instruction set.
#[inline]
pub(super) fn closest(bvh: &WideBvh, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Closest> {
    // SAFETY: `bvh.isa` is only ever set to an instruction set this CPU has
    // (`WideBvh::with_isa`, `Isa::detect`); the walks index only what the build made.
    unsafe {
        match bvh.isa {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => x86::closest_avx512(bvh, scene, ray, t_max),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => x86::closest_avx2(bvh, scene, ray, t_max),
            #[cfg(target_arch = "x86_64")]
            Isa::Sse2 => x86::closest_sse2(bvh, scene, ray, t_max),
            _ => scalar::closest_scalar(bvh, scene, ray, t_max),
        }
    }
}

/// Whether anything on `bvh` blocks the ray, with its instruction set.
#[inline]
pub(super) fn occluded(bvh: &WideBvh, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
    // SAFETY: as in `closest`.
    unsafe {
        match bvh.isa {
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => x86::occluded_avx512(bvh, scene, ray, t_max),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => x86::occluded_avx2(bvh, scene, ray, t_max),
            #[cfg(target_arch = "x86_64")]
            Isa::Sse2 => x86::occluded_sse2(bvh, scene, ray, t_max),
            _ => scalar::occluded_scalar(bvh, scene, ray, t_max),
        }
    }
}
