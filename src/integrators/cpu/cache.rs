//! The radiance cache of final gathering on the CPU (rule: `plan::CACHE_STRIDE` and
//! `plan::CACHE_NORMAL_COS`): built once per pass from the global map, read where a gather
//! ray lands. Its points are the global photons chosen by identity; each holds the outgoing
//! radiance of a white Lambertian surface there, and a lookup returns the value of the
//! nearest point within the global radius whose normal matches the query's, found in a
//! hashed grid of cells of that radius (`point_grid`), or none (the gather ray then reads
//! the global map there itself).

use crate::integrators::cpu::photon_map::{estimate_at, PhotonMap};
use crate::integrators::cpu::point_grid::{GridPoint, PointGrid};
use crate::integrators::photon::{Photon, DEPTH_MASK};
use crate::integrators::plan::{CACHE_NORMAL_COS, CACHE_STRIDE};
use crate::settings::Filter;
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

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

/// What a lookup reads of a cache point besides its position: its normal, its value, and
/// its index in `RadianceCache::points` (for ties).
#[derive(Clone, Copy, Debug)]
struct Entry {
    normal: Vec3,
    value: Vec3,
    index: u32,
}

/// Cache points in a hashed grid over their positions.
pub struct RadianceCache {
    /// The points, in the global map's order.
    pub points: Vec<CachePoint>,
    /// Cells of the lookup radius (none where the radius is not positive and
    /// finite: no lookup then finds a point).
    grid: Option<PointGrid<Entry>>,
    /// Squared lookup radius (the global radius of the pass).
    radius2: f32,
}

impl RadianceCache {
    /// Builds the cache of `global` (rayon over the points, in a grid's order so that
    /// neighbouring estimates read neighbouring photons): each point's value is the global
    /// map's estimate there with `k` nearest (0: every photon) within `radius`, `filter`,
    /// and BRDF 1/pi. Lookups search within `radius` too.
    pub fn build(global: &PhotonMap, k: u32, radius: f32, filter: Filter) -> Self {
        let r2 = radius * radius;
        let f = Vec3::splat(1.0 / PI);
        let chosen: Vec<&Photon> = global
            .photons
            .iter()
            .filter(|p| is_cache_point(p))
            .collect();
        let positions: Vec<[f32; 3]> = chosen.iter().map(|p| p.position).collect();
        let usable = radius > 0.0 && radius.is_finite();
        // Every point once: a grid's order, then any point the grid left out.
        let mut order: Vec<u32> = match usable {
            true => PointGrid::build(&positions, radius, |_| ()).index,
            false => Vec::new(),
        };
        if order.len() != chosen.len() {
            let mut listed = vec![false; chosen.len()];
            order.iter().for_each(|&i| listed[i as usize] = true);
            order.extend((0..chosen.len() as u32).filter(|&i| !listed[i as usize]));
        }
        let values: Vec<Vec3> = order
            .par_iter()
            .map(|&i| {
                let p = chosen[i as usize];
                estimate_at(global, p.pos(), p.normal(), k as usize, r2, filter, f)
            })
            .collect();
        let mut points: Vec<CachePoint> = chosen
            .iter()
            .map(|p| CachePoint {
                position: p.position,
                normal: p.normal(),
                id: p.id,
                flags: p.flags,
                value: Vec3::ZERO,
            })
            .collect();
        for (&i, v) in order.iter().zip(values) {
            points[i as usize].value = v;
        }
        let grid = usable.then(|| lookup_grid(&points, radius));
        RadianceCache {
            points,
            grid,
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
    /// or `None` (the caller then estimates from the global map). The grid's search goes out
    /// ring by ring from `x`'s cell, skipping the cells farther than the best point so far.
    pub fn lookup(&self, x: Vec3, n: Vec3) -> Option<Vec3> {
        let grid = self.grid.as_ref()?;
        let key = |e: &Entry| {
            let p = &self.points[e.index as usize];
            (p.id, p.flags)
        };
        let x = x.to_array();
        let mut best: Option<&GridPoint<Entry>> = None;
        grid.nearest(x, self.radius2, |run, mut bound| {
            for p in &grid.points[run] {
                let d2 = p.distance2(x);
                if d2 > bound || p.data.normal.dot(n) < CACHE_NORMAL_COS {
                    continue;
                }
                // Not farther than the best: nearer, or tied and first by identity.
                if best.is_none_or(|b| d2 < bound || key(&p.data) < key(&b.data)) {
                    best = Some(p);
                    bound = d2;
                }
            }
            bound
        });
        best.map(|p| p.data.value)
    }
}

/// A grid over `points` for lookups within `radius`, in cells of that radius (on the Cornell
/// box's default render, about ten points to an occupied cell, these were faster than cells
/// of half the radius: fewer rows of cells read, each a run of memory).
fn lookup_grid(points: &[CachePoint], radius: f32) -> PointGrid<Entry> {
    let positions: Vec<[f32; 3]> = points.iter().map(|p| p.position).collect();
    PointGrid::build(&positions, radius, |i| Entry {
        normal: points[i].normal,
        value: points[i].value,
        index: i as u32,
    })
}
