//! The portable kernel: one lane at a time, the same arithmetic as the SIMD ones (the
//! fallback off x86-64, and their reference in tests).

use super::{entry_points, Kernel, Prepared, TriHits};
use crate::bvh::wide_layout::{Node8, TriBlock, BLOCK, WIDTH};
use crate::math::geometry::BOX_SLACK;

/// The portable kernel.
pub(super) struct Scalar;

impl Kernel for Scalar {
    type Ray = Prepared;

    #[inline(always)]
    unsafe fn ray(p: &Prepared) -> Prepared {
        *p
    }

    #[inline(always)]
    unsafe fn node(
        node: &Node8,
        r: &Prepared,
        t_max: f32,
        near: &mut [f32; 8],
        child: &mut [u32; 8],
    ) -> usize {
        let mut k = 0;
        for i in 0..WIDTH {
            let t = |row: usize, a: usize| (node.bounds[row][i] - r.o[a]) * r.inv[a];
            let n = |a: usize| t(r.near_row[a], a);
            let f = |a: usize| t(r.far_row[a], a);
            let tn = n(0).max(n(1)).max(n(2).max(0.0));
            let tf = (f(0).min(f(1)).min(f(2)) * BOX_SLACK).min(t_max);
            if tn <= tf {
                near[k] = tn;
                child[k] = node.child[i];
                k += 1;
            }
        }
        k
    }

    #[inline(always)]
    unsafe fn block(b: &TriBlock, r: &Prepared, t_max: f32, out: *mut TriHits) -> u32 {
        let [kx, ky, kz] = r.k;
        let mut mask = 0;
        for i in 0..BLOCK {
            let proj = |v: &[[f32; BLOCK]; 3]| {
                let (px, py, pz) = (v[kx][i] - r.o[kx], v[ky][i] - r.o[ky], v[kz][i] - r.o[kz]);
                (px - r.s[0] * pz, py - r.s[1] * pz)
            };
            let (a, bb, c) = (proj(&b.v0), proj(&b.v1), proj(&b.v2));
            let edge = |p: (f32, f32), q: (f32, f32)| p.0 * q.1 - p.1 * q.0;
            let (e0, e1, e2) = (edge(c, bb), edge(a, c), edge(bb, a));
            if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
                continue;
            }
            let det = e0 + e1 + e2;
            if det == 0.0 {
                continue;
            }
            let n = [b.n[0][i], b.n[1][i], b.n[2][i]];
            let num = (b.v0[0][i] - r.o[0]) * n[0]
                + (b.v0[1][i] - r.o[1]) * n[1]
                + (b.v0[2][i] - r.o[2]) * n[2];
            let den = r.d[0] * n[0] + r.d[1] * n[1] + r.d[2] * n[2];
            let t = num / den;
            if t > 0.0 && t < t_max {
                mask |= 1 << i;
                for (row, v) in TriHits::rows(out).into_iter().zip([t, e1, e2, det]) {
                    row.add(i).write(v);
                }
            }
        }
        mask
    }
}

entry_points!(closest_scalar, occluded_scalar, Scalar,);
