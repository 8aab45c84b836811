//! The radiance cache of final gathering on the CPU (rule: `plan::CACHE_STRIDE` and
//! `plan::CACHE_NORMAL_COS`): built once per pass from the global map, read where a gather
//! ray lands. Its points are the global photons chosen by identity; each holds the outgoing
//! radiance of a white Lambertian surface there, and a lookup returns the value of the
//! nearest point within the global radius whose normal matches the query's.

use crate::integrators::cpu::photon_map::{estimate_at, PhotonMap};
use crate::integrators::photon::{Photon, DEPTH_MASK};
use crate::integrators::plan::{CACHE_NORMAL_COS, CACHE_STRIDE};
use crate::settings::Filter;
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::num::NonZeroUsize;

/// Candidates a lookup asks the kd-tree for before it scans the whole radius (the nearest
/// point almost always passes the normal test; walls meeting at a corner are the exception).
pub const LOOKUP_FIRST: usize = 4;

/// Whether global photon `p` is a cache point (`(id + depth) % CACHE_STRIDE == 0`).
#[inline]
pub fn is_cache_point(p: &Photon) -> bool {
    p.id.wrapping_add(p.flags & DEPTH_MASK)
        .is_multiple_of(CACHE_STRIDE)
}

/// One cache point: where, which way its surface faces, its identity (for ties) and value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CachePoint {
    /// The photon's position.
    pub position: [f32; 3],
    /// The unit normal of the side the photon arrived on (unpacked from the photon).
    pub normal: Vec3,
    /// The photon's id (first tie-break).
    pub id: u32,
    /// The photon's flags (second tie-break).
    pub flags: u32,
    /// Outgoing radiance of a white Lambertian surface at the point.
    pub value: Vec3,
}

/// Cache points in a kd-tree over their positions (`tree` item `i` is `points[i]`).
pub struct RadianceCache {
    /// The points, in the order the tree indexes them (the global map's order).
    pub points: Vec<CachePoint>,
    tree: Option<ImmutableKdTree<f32, 3>>,
    /// Squared lookup radius (the global radius of the pass).
    radius2: f32,
}

impl RadianceCache {
    /// Builds the cache of `global` (rayon over the points): each point's value is the
    /// global map's estimate there with `k` nearest (0: every photon) within `radius`,
    /// `filter`, and BRDF 1/pi. Lookups search within `radius` too.
    pub fn build(global: &PhotonMap, k: u32, radius: f32, filter: Filter) -> Self {
        let r2 = radius * radius;
        let f = Vec3::splat(1.0 / PI);
        let points: Vec<CachePoint> = global
            .photons
            .par_iter()
            .filter(|p| is_cache_point(p))
            .map(|p| {
                let normal = p.normal();
                CachePoint {
                    position: p.position,
                    normal,
                    id: p.id,
                    flags: p.flags,
                    value: estimate_at(global, p.pos(), normal, k as usize, r2, filter, f),
                }
            })
            .collect();
        let positions: Vec<[f32; 3]> = points.iter().map(|p| p.position).collect();
        let tree = if positions.is_empty() {
            None
        } else {
            ImmutableKdTree::new_from_slice(&positions).ok()
        };
        RadianceCache {
            points,
            tree,
            radius2: r2,
        }
    }

    /// Number of cache points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Whether the cache holds no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The value of the nearest cache point to `x` within the lookup radius whose normal has
    /// a cosine of at least `CACHE_NORMAL_COS` with `n` (ties: lower id, then lower flags),
    /// or zero. Asks the tree for `LOOKUP_FIRST` candidates first; only when no candidate
    /// nearer than the farthest of them passes (so a farther or tied point could win) does
    /// it scan the whole radius.
    pub fn lookup(&self, x: Vec3, n: Vec3) -> Vec3 {
        let Some(tree) = &self.tree else {
            return Vec3::ZERO;
        };
        let q = x.to_array();
        let first = tree
            .query(&q)
            .nearest_n::<SquaredEuclidean<f32>>(NonZeroUsize::new(LOOKUP_FIRST).unwrap())
            .within(self.radius2)
            .execute();
        let farthest = first.iter().map(|r| r.distance).fold(0.0f32, f32::max);
        let complete = first.len() < LOOKUP_FIRST;
        let best = self.best(first.iter().map(|r| (r.distance, r.item as usize)), n);
        match best {
            // Exact when every point within the radius was found, or when the winner is
            // strictly nearer than the farthest candidate (nothing unseen can tie or beat it).
            Some((d2, i)) if complete || d2 < farthest => self.points[i].value,
            None if complete => Vec3::ZERO,
            _ => {
                let all = tree
                    .query(&q)
                    .within::<SquaredEuclidean<f32>>(self.radius2)
                    .unsorted()
                    .execute();
                self.best(all.iter().map(|r| (r.distance, r.item as usize)), n)
                    .map_or(Vec3::ZERO, |(_, i)| self.points[i].value)
            }
        }
    }

    /// The candidate `(squared distance, index)` that passes the normal test with the least
    /// (distance, id, flags).
    fn best(&self, found: impl Iterator<Item = (f32, usize)>, n: Vec3) -> Option<(f32, usize)> {
        found
            .filter(|&(_, i)| self.points[i].normal.dot(n) >= CACHE_NORMAL_COS)
            .min_by(|a, b| {
                let (pa, pb) = (&self.points[a.1], &self.points[b.1]);
                a.0.total_cmp(&b.0)
                    .then(pa.id.cmp(&pb.id))
                    .then(pa.flags.cmp(&pb.flags))
            })
    }
}
