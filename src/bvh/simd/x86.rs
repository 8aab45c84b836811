//! The x86-64 kernels: a node's eight box tests in two SSE2 halves, one AVX2 register, or
//! AVX-512's mask compare and compress; a block's four triangle tests in SSE registers
//! (VEX- or EVEX-encoded inside the wider kernels' functions).
//!
//! Every helper is `#[inline(always)]` without target features of its own: it is only ever
//! inlined into the entry points at the end, whose `#[target_feature]` its intrinsics then
//! run under (LLVM declines to inline a `#[target_feature]` helper as large as a node test).

use super::{entry_points, Kernel, Prepared, TriHits};
use crate::bvh::wide_layout::{Node8, TriBlock};
use crate::math::geometry::BOX_SLACK;
use std::arch::x86_64::*;

/// A ray splatted for the triangle test.
#[derive(Clone, Copy)]
pub(super) struct TriRay {
    /// World origin x, y, z.
    o: [__m128; 3],
    /// Origin along the shear axes kx, ky, kz.
    ok: [__m128; 3],
    /// Shear.
    s: [__m128; 2],
    /// Direction x, y, z.
    d: [__m128; 3],
    /// Shear axes.
    k: [usize; 3],
}

#[inline(always)]
unsafe fn tri_ray(p: &Prepared) -> TriRay {
    let [kx, ky, kz] = p.k;
    TriRay {
        o: p.o.map(|v| _mm_set1_ps(v)),
        ok: [kx, ky, kz].map(|a| _mm_set1_ps(p.o[a])),
        s: p.s.map(|v| _mm_set1_ps(v)),
        d: p.d.map(|v| _mm_set1_ps(v)),
        k: p.k,
    }
}

/// `intersect_triangle` on four lanes: the mask of lanes hit in (0, t_max).
#[inline(always)]
unsafe fn block4(b: &TriBlock, r: &TriRay, t_max: f32, out: *mut TriHits) -> u32 {
    let ld = |row: &[f32; 4]| _mm_load_ps(row.as_ptr());
    let [kx, ky, kz] = r.k;
    let proj = |v: &[[f32; 4]; 3]| {
        let px = _mm_sub_ps(ld(&v[kx]), r.ok[0]);
        let py = _mm_sub_ps(ld(&v[ky]), r.ok[1]);
        let pz = _mm_sub_ps(ld(&v[kz]), r.ok[2]);
        (
            _mm_sub_ps(px, _mm_mul_ps(r.s[0], pz)),
            _mm_sub_ps(py, _mm_mul_ps(r.s[1], pz)),
        )
    };
    let (a, bb, c) = (proj(&b.v0), proj(&b.v1), proj(&b.v2));
    let edge = |p: (__m128, __m128), q: (__m128, __m128)| {
        _mm_sub_ps(_mm_mul_ps(p.0, q.1), _mm_mul_ps(p.1, q.0))
    };
    let (e0, e1, e2) = (edge(c, bb), edge(a, c), edge(bb, a));
    let zero = _mm_setzero_ps();
    let neg = _mm_or_ps(
        _mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)),
        _mm_cmplt_ps(e2, zero),
    );
    let pos = _mm_or_ps(
        _mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)),
        _mm_cmpgt_ps(e2, zero),
    );
    let det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
    let inside = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_cmpneq_ps(det, zero));
    if _mm_movemask_ps(inside) == 0 {
        return 0;
    }
    let n = [ld(&b.n[0]), ld(&b.n[1]), ld(&b.n[2])];
    let rel = |a: usize| _mm_sub_ps(ld(&b.v0[a]), r.o[a]);
    let num = _mm_add_ps(
        _mm_add_ps(_mm_mul_ps(rel(0), n[0]), _mm_mul_ps(rel(1), n[1])),
        _mm_mul_ps(rel(2), n[2]),
    );
    let den = _mm_add_ps(
        _mm_add_ps(_mm_mul_ps(r.d[0], n[0]), _mm_mul_ps(r.d[1], n[1])),
        _mm_mul_ps(r.d[2], n[2]),
    );
    let t = _mm_div_ps(num, den);
    let ok = _mm_and_ps(
        inside,
        _mm_and_ps(_mm_cmpgt_ps(t, zero), _mm_cmplt_ps(t, _mm_set1_ps(t_max))),
    );
    let mask = _mm_movemask_ps(ok) as u32;
    if mask != 0 {
        for (row, v) in TriHits::rows(out).into_iter().zip([t, e1, e2, det]) {
            _mm_storeu_ps(row, v);
        }
    }
    mask
}

/// Prefetches the cache lines of `at..at + bytes` (at most four).
#[inline(always)]
unsafe fn prefetch(at: *const u8, bytes: usize) {
    for line in 0..4 {
        if line * 64 < bytes {
            _mm_prefetch::<_MM_HINT_T0>(at.add(line * 64) as *const i8);
        }
    }
}

/// Compacts the lanes of `mask` into `near` and `child`.
#[inline(always)]
fn compact(
    mask: u32,
    tn: &[f32; 8],
    node: &Node8,
    near: &mut [f32; 8],
    child: &mut [u32; 8],
) -> usize {
    let (mut m, mut k) = (mask, 0);
    while m != 0 {
        let i = m.trailing_zeros() as usize;
        near[k] = tn[i];
        child[k] = node.child[i];
        k += 1;
        m &= m - 1;
    }
    k
}

/// What every x86 kernel does alike: prefetch, and the block test in SSE registers.
macro_rules! x86_kernel_methods {
    ($ray:ty) => {
        #[inline(always)]
        unsafe fn prefetch(at: *const u8, bytes: usize) {
            prefetch(at, bytes)
        }

        #[inline(always)]
        unsafe fn block(b: &TriBlock, r: &$ray, t_max: f32, out: *mut TriHits) -> u32 {
            block4(b, &r.tri, t_max, out)
        }
    };
}

/// Two 4-lane halves per node.
pub(super) struct Sse2;

/// A ray splatted into registers of lanes `V` for the box tests.
#[derive(Clone, Copy)]
pub(super) struct RayN<V> {
    o: [V; 3],
    inv: [V; 3],
    near_row: [usize; 3],
    far_row: [usize; 3],
    tri: TriRay,
}

/// The ray `p` with its origin and inverse direction splatted by `splat`.
#[inline(always)]
unsafe fn ray_n<V>(p: &Prepared, splat: impl Fn(f32) -> V) -> RayN<V> {
    RayN {
        o: p.o.map(&splat),
        inv: p.inv.map(&splat),
        near_row: p.near_row,
        far_row: p.far_row,
        tri: tri_ray(p),
    }
}

/// A ray splatted into 4-lane registers.
pub(super) type Ray4 = RayN<__m128>;
/// A ray splatted into 8-lane registers.
pub(super) type Ray8 = RayN<__m256>;

impl Kernel for Sse2 {
    type Ray = Ray4;

    #[inline(always)]
    unsafe fn ray(p: &Prepared) -> Ray4 {
        ray_n(p, |v| _mm_set1_ps(v))
    }

    #[inline(always)]
    unsafe fn node(
        node: &Node8,
        r: &Ray4,
        t_max: f32,
        near: &mut [f32; 8],
        child: &mut [u32; 8],
    ) -> usize {
        let mut tn = [0.0f32; 8];
        let mut mask = 0u32;
        for h in 0..2 {
            let t = |row: usize, a: usize| {
                let b = _mm_loadu_ps(node.bounds[row].as_ptr().add(4 * h));
                _mm_mul_ps(_mm_sub_ps(b, r.o[a]), r.inv[a])
            };
            let n = |a: usize| t(r.near_row[a], a);
            let f = |a: usize| t(r.far_row[a], a);
            let tnear = _mm_max_ps(_mm_max_ps(n(0), n(1)), _mm_max_ps(n(2), _mm_setzero_ps()));
            let tfar = _mm_min_ps(
                _mm_mul_ps(
                    _mm_min_ps(_mm_min_ps(f(0), f(1)), f(2)),
                    _mm_set1_ps(BOX_SLACK),
                ),
                _mm_set1_ps(t_max),
            );
            mask |= (_mm_movemask_ps(_mm_cmple_ps(tnear, tfar)) as u32) << (4 * h);
            _mm_storeu_ps(tn.as_mut_ptr().add(4 * h), tnear);
        }
        compact(mask, &tn, node, near, child)
    }

    x86_kernel_methods!(Ray4);
}

/// Entry and exit distances of the eight boxes of `node` (always inlined into the AVX2
/// and AVX-512 node tests, whose target features its intrinsics then run under).
#[inline(always)]
unsafe fn slabs8(node: &Node8, r: &Ray8, t_max: f32) -> (__m256, __m256) {
    let t = |row: usize, a: usize| {
        let b = _mm256_load_ps(node.bounds[row].as_ptr());
        _mm256_mul_ps(_mm256_sub_ps(b, r.o[a]), r.inv[a])
    };
    let n = |a: usize| t(r.near_row[a], a);
    let f = |a: usize| t(r.far_row[a], a);
    let tnear = _mm256_max_ps(
        _mm256_max_ps(n(0), n(1)),
        _mm256_max_ps(n(2), _mm256_setzero_ps()),
    );
    let tfar = _mm256_min_ps(
        _mm256_mul_ps(
            _mm256_min_ps(_mm256_min_ps(f(0), f(1)), f(2)),
            _mm256_set1_ps(BOX_SLACK),
        ),
        _mm256_set1_ps(t_max),
    );
    (tnear, tfar)
}

#[inline(always)]
unsafe fn node_avx2(
    node: &Node8,
    r: &Ray8,
    t_max: f32,
    near: &mut [f32; 8],
    child: &mut [u32; 8],
) -> usize {
    let (tnear, tfar) = slabs8(node, r, t_max);
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tnear, tfar)) as u32;
    if mask == 0 {
        return 0;
    }
    let mut tn = [0.0f32; 8];
    _mm256_storeu_ps(tn.as_mut_ptr(), tnear);
    compact(mask, &tn, node, near, child)
}

#[inline(always)]
unsafe fn node_avx512(
    node: &Node8,
    r: &Ray8,
    t_max: f32,
    near: &mut [f32; 8],
    child: &mut [u32; 8],
) -> usize {
    let (tnear, tfar) = slabs8(node, r, t_max);
    let mask = _mm256_cmp_ps_mask::<_CMP_LE_OQ>(tnear, tfar);
    if mask == 0 {
        return 0;
    }
    // Compress in registers (a compress straight to memory is slow on some CPUs).
    let kids = _mm256_load_si256(node.child.as_ptr() as *const __m256i);
    _mm256_storeu_ps(near.as_mut_ptr(), _mm256_maskz_compress_ps(mask, tnear));
    _mm256_storeu_si256(
        child.as_mut_ptr() as *mut __m256i,
        _mm256_maskz_compress_epi32(mask, kids),
    );
    mask.count_ones() as usize
}

/// One 8-lane register per node: AVX2's movemask (`MASKS` false) or AVX-512's mask compare
/// and compress.
pub(super) struct Lanes8<const MASKS: bool>;

impl<const MASKS: bool> Kernel for Lanes8<MASKS> {
    type Ray = Ray8;

    #[inline(always)]
    unsafe fn ray(p: &Prepared) -> Ray8 {
        ray_n(p, |v| _mm256_set1_ps(v))
    }

    #[inline(always)]
    unsafe fn node(
        node: &Node8,
        r: &Ray8,
        t_max: f32,
        near: &mut [f32; 8],
        child: &mut [u32; 8],
    ) -> usize {
        match MASKS {
            true => node_avx512(node, r, t_max, near, child),
            false => node_avx2(node, r, t_max, near, child),
        }
    }

    x86_kernel_methods!(Ray8);
}

entry_points!(closest_sse2, occluded_sse2, Sse2,);
entry_points!(closest_avx2, occluded_avx2, Lanes8<false>, #[target_feature(enable = "avx2")]);
entry_points!(
    closest_avx512,
    occluded_avx512,
    Lanes8<true>,
    #[target_feature(enable = "avx512f,avx512vl,avx2")]
);
