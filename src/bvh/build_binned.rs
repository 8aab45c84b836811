//! The wide hierarchy's binary tree, built fast: binned SAH over [`BINS`] bins on all three
//! axes in one pass per node, the children's centroid bounds gathered while partitioning,
//! subtrees of more than [`PARALLEL`] primitives built on rayon's threads. Leaf costs count
//! blocks of four triangles (a block costs one test, as a node does), so leaves of up to
//! [`MAX_LEAF`] primitives stay whole where splitting them does not pay.
//!
//! The result has [`Bvh`]'s layout (depth-first, left child next), for
//! `build_wide::collapse`; the GPU's hierarchy keeps `Bvh::build_with`.

use super::wide_layout::BLOCK;
use super::{Bvh, BvhNode, MAX_DEPTH, SPHERE_BIT};
use crate::math::geometry::Aabb;
use crate::scene::Scene;
use glam::{Vec3, Vec4};

/// Bins per axis.
const BINS: usize = 32;
/// Most primitives in a leaf.
pub const MAX_LEAF: usize = 4 * BLOCK;
/// Subtrees above this size are built in parallel.
const PARALLEL: usize = 16 * 1024;
/// Depth up to which splits follow the SAH; past it, halves by index (the tree stays within
/// `MAX_DEPTH` for up to 2^26 primitives, `scene::MAX_TRIANGLES`).
const SAH_DEPTH: usize = MAX_DEPTH - 28;
/// Cost of a node step, in block tests (measured: 3 traces faster than 0.25 to 2, and
/// than 4 with larger leaves, on the 1M-triangle benchmark mesh).
const NODE_COST: f32 = 3.0;

/// One primitive's bounds (32 bytes, two SSE registers on x86): `min.w` holds its id's bits
/// plus [`ID_BIAS`] (a normal float, so that no arithmetic on the lane meets a denormal).
#[derive(Clone, Copy, Debug)]
struct Prim {
    min: Vec4,
    max: Vec4,
}

impl Prim {
    /// Twice the centroid (the binning needs only ratios), `w` zero: the id's bits in
    /// `min.w` are a normal float, but the difference of two of them is denormal, and
    /// arithmetic on a denormal lane stalls the whole vector instruction (a microcode
    /// assist: it made the 1M-triangle build 4x slower).
    #[inline(always)]
    fn c2(&self) -> Vec4 {
        Vec4::select(XYZ, self.min + self.max, Vec4::ZERO)
    }
    fn id(&self) -> u32 {
        self.min.w.to_bits() - ID_BIAS
    }
}

/// The lanes of a point.
const XYZ: glam::BVec4A = glam::BVec4A::from_array([true, true, true, false]);

/// Added to an id's bits in `Prim::min.w`: the smallest normal float's.
const ID_BIAS: u32 = 0x0080_0000;

/// Bounds and centroid bounds (doubled) of a range of primitives (`w` lanes meaningless).
#[derive(Clone, Copy, Debug)]
struct Extent {
    min: Vec4,
    max: Vec4,
    cmin: Vec4,
    cmax: Vec4,
}

impl Extent {
    const EMPTY: Extent = Extent {
        min: Vec4::INFINITY,
        max: Vec4::NEG_INFINITY,
        cmin: Vec4::INFINITY,
        cmax: Vec4::NEG_INFINITY,
    };
    #[inline(always)]
    fn grow(&mut self, p: &Prim) {
        self.min = self.min.min(p.min);
        self.max = self.max.max(p.max);
        let c = p.c2();
        self.cmin = self.cmin.min(c);
        self.cmax = self.cmax.max(c);
    }
    fn half_area(&self) -> f32 {
        half_area(self.min, self.max)
    }
}

/// Half the surface area of the box `lo..hi` (0 when empty).
#[inline(always)]
fn half_area(lo: Vec4, hi: Vec4) -> f32 {
    let d = (hi - lo).max(Vec4::ZERO);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The binary tree over every triangle and sphere of `scene` for the wide hierarchy.
pub fn build(scene: &Scene) -> Bvh {
    let boxes = (scene.triangles.iter().map(Aabb::of_triangle))
        .zip(0u32..)
        .chain((scene.spheres.iter().map(Aabb::of_sphere)).zip((0u32..).map(|i| i | SPHERE_BIT)));
    let prims: Vec<Prim> = boxes
        .map(|(b, id)| Prim {
            min: b.min.extend(f32::from_bits(id + ID_BIAS)),
            max: b.max.extend(0.0),
        })
        .collect();
    let alpha = scene.materials.iter().any(|m| m.alpha.is_some());
    if prims.is_empty() {
        return Bvh {
            alpha,
            ..Bvh::build(scene)
        };
    }
    let mut prims = prims;
    let mut extent = Extent::EMPTY;
    prims.iter().for_each(|p| extent.grow(p));
    let mut nodes = Vec::with_capacity(prims.len() / 2);
    subtree(&mut prims, 0, 1, extent, &mut nodes);
    Bvh {
        nodes,
        prim_ids: prims.iter().map(Prim::id).collect(),
        alpha,
    }
}

/// Appends the subtree over `prims` (at `offset` in the final order) to `out`, depth first.
fn subtree(prims: &mut [Prim], offset: usize, depth: usize, e: Extent, out: &mut Vec<BvhNode>) {
    let idx = out.len();
    out.push(BvhNode {
        bmin: e.min.truncate().to_array(),
        bmax: e.max.truncate().to_array(),
        left_first: offset as u32,
        count: prims.len() as u32,
    });
    if prims.len() <= 1 {
        return;
    }
    let split = match depth < SAH_DEPTH {
        true => sah_split(prims, &e),
        false => None,
    };
    let (mid, le, re) = match split {
        Some(s) => s,
        None if prims.len() <= MAX_LEAF && depth < SAH_DEPTH => return,
        None => halves(prims),
    };
    let (left, right) = prims.split_at_mut(mid);
    let right_index = if prims_len(left, right) > PARALLEL {
        let build = |p: &mut [Prim], off, e| {
            let mut v = Vec::with_capacity(p.len() / 2);
            subtree(p, off, depth + 1, e, &mut v);
            v
        };
        let (lv, rv) = rayon::join(
            || build(left, offset, le),
            || build(right, offset + mid, re),
        );
        append(out, lv);
        let r = out.len();
        append(out, rv);
        r
    } else {
        subtree(left, offset, depth + 1, le, out);
        let r = out.len();
        subtree(right, offset + mid, depth + 1, re, out);
        r
    };
    out[idx].left_first = right_index as u32;
    out[idx].count = 0;
}

fn prims_len(a: &[Prim], b: &[Prim]) -> usize {
    a.len() + b.len()
}

/// Appends a subtree built on its own, moving its interior nodes' child indices.
fn append(out: &mut Vec<BvhNode>, nodes: Vec<BvhNode>) {
    let base = out.len() as u32;
    out.extend(nodes.into_iter().map(|mut n| {
        if n.count == 0 {
            n.left_first += base;
        }
        n
    }));
}

/// Blocks of four a leaf of `n` primitives takes.
#[inline(always)]
fn blocks(n: usize) -> f32 {
    n.div_ceil(BLOCK) as f32
}

/// The binned SAH split of `prims` (reordered): the split position and both sides'
/// extents, or `None` when a leaf is cheaper or the centroids do not spread.
fn sah_split(prims: &mut [Prim], e: &Extent) -> Option<(usize, Extent, Extent)> {
    let extent = (e.cmax - e.cmin).truncate();
    let scale = Vec3::select(
        extent.cmpgt(Vec3::ZERO),
        Vec3::splat(BINS as f32 * (1.0 - f32::EPSILON)) / extent,
        Vec3::ZERO,
    );
    if scale == Vec3::ZERO || !scale.is_finite() {
        return None;
    }
    let (scale, cmin) = (scale.extend(0.0), e.cmin);
    let bin_of = |p: &Prim| -> [usize; 3] {
        let b = ((p.c2() - cmin) * scale).as_uvec4();
        [b.x as usize, b.y as usize, b.z as usize].map(|i| i.min(BINS - 1))
    };
    let mut lo = [[Vec4::INFINITY; BINS]; 3];
    let mut hi = [[Vec4::NEG_INFINITY; BINS]; 3];
    let mut count = [[0u32; BINS]; 3];
    for p in prims.iter() {
        let b = bin_of(p);
        for a in 0..3 {
            lo[a][b[a]] = lo[a][b[a]].min(p.min);
            hi[a][b[a]] = hi[a][b[a]].max(p.max);
            count[a][b[a]] += 1;
        }
    }
    let area = half_area;
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, first right bin)
    for a in 0..3 {
        if scale[a] == 0.0 {
            continue;
        }
        let mut right_cost = [0.0f32; BINS];
        let (mut l, mut h, mut n) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0usize);
        for i in (1..BINS).rev() {
            l = l.min(lo[a][i]);
            h = h.max(hi[a][i]);
            n += count[a][i] as usize;
            right_cost[i] = area(l, h) * blocks(n);
        }
        let (mut l, mut h, mut n) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0usize);
        for i in 0..BINS - 1 {
            l = l.min(lo[a][i]);
            h = h.max(hi[a][i]);
            n += count[a][i] as usize;
            if n == 0 || n == prims.len() {
                continue;
            }
            let cost = area(l, h) * blocks(n) + right_cost[i + 1];
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, a, i + 1));
            }
        }
    }
    let (cost, axis, split) = best?;
    let parent = e.half_area();
    if prims.len() <= MAX_LEAF && parent > 0.0 && NODE_COST + cost / parent >= blocks(prims.len()) {
        return None;
    }
    // Partition by the same bins, gathering both sides' extents.
    let (mut le, mut re) = (Extent::EMPTY, Extent::EMPTY);
    let mut i = 0;
    for j in 0..prims.len() {
        if bin_of(&prims[j])[axis] < split {
            le.grow(&prims[j]);
            prims.swap(i, j);
            i += 1;
        } else {
            re.grow(&prims[j]);
        }
    }
    Some((i, le, re))
}

/// Splits in two halves by index (past the SAH's depth, or when the centroids coincide).
fn halves(prims: &mut [Prim]) -> (usize, Extent, Extent) {
    let mid = prims.len() / 2;
    let (mut le, mut re) = (Extent::EMPTY, Extent::EMPTY);
    prims[..mid].iter().for_each(|p| le.grow(p));
    prims[mid..].iter().for_each(|p| re.grow(p));
    (mid, le, re)
}
