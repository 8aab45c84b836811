//! The volume photon map on the CPU (issue 24) and its beam radiance estimate (Jarosz,
//! Zwicker and Jensen 2008): photons stored where paths scattered in a medium, each a sphere
//! of the pass's radius r, and one query per camera segment for every photon whose sphere
//! the segment passes through.
//!
//! The map hashes a uniform grid of cells of side at least 2 r (unbounded: fog around an open scene
//! spreads photons far). A photon is listed in every cell its sphere's box overlaps (at most
//! 8). A query walks the cells the segment crosses inside the photons' bounds (3D DDA, at
//! most [`MAX_STEPS`]) and, in each, takes the listed photons whose nearest point on the ray
//! lies in the part of the segment inside that cell: that point is within r of the photon,
//! so the photon is listed there, and it lies in exactly one cell, so each photon counts
//! once.

use crate::integrators::photon::{BeamPhotons, Photon};
use crate::media::{Medium, Transmittances, POINT_RADIUS_FACTOR};
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::f32::consts::PI;

/// Most cells one beam query walks (bounds its work on a segment through photons spread
/// over a huge region; the cells past it are not read).
pub const MAX_STEPS: usize = 1 << 16;
/// Photons a grid cell is sized to hold at the mean density (see [`VolumeMap::build`]).
pub const PHOTONS_PER_CELL: f32 = 16.0;
// A point query finds every photon within R of its point in the cells its own box of half-width
// r overlaps (at most 2 an axis: cells are at least 2 r wide) only while R <= 2 r.
const _: () = assert!(POINT_RADIUS_FACTOR <= 2.0);

/// Marks an empty slot of the cell table.
const EMPTY: u64 = u64::MAX;

/// The cell of point `x` in a grid of cells of edge `cell` from corner `lo` (the device's
/// `volume_cell` in src/integrators/gpu/grid.wgsl).
#[inline]
pub fn volume_cell(x: Vec3, lo: Vec3, cell: f32) -> IVec3 {
    ((x - lo) / cell).floor().as_ivec3()
}

/// Volume photons in a hashed grid of photon lists.
pub struct VolumeMap {
    /// The photons.
    pub photons: Vec<Photon>,
    /// The radius of every photon's sphere.
    pub radius: f32,
    lo: Vec3,
    hi: Vec3,
    cell: f32,
    /// Open-addressed table of the non-empty cells: (key, first ref, end ref).
    table: Vec<(u64, u32, u32)>,
    /// Photon indices, grouped by cell.
    refs: Vec<u32>,
}

/// A cell's key: its coordinates, 21 bits each (offset by 2^20).
fn key(c: IVec3) -> u64 {
    let f = |v: i32| ((v + (1 << 20)) as u64) & 0x1f_ffff;
    f(c.x) | f(c.y) << 21 | f(c.z) << 42
}

fn hash(k: u64) -> usize {
    (k.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 20) as usize
}

impl VolumeMap {
    /// Builds the grid over `photons`, each a sphere of `radius`.
    pub fn build(photons: Vec<Photon>, radius: f32) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in &photons {
            lo = lo.min(p.pos());
            hi = hi.max(p.pos());
        }
        if photons.is_empty() {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        let (lo, hi) = (lo - Vec3::splat(radius), hi + Vec3::splat(radius));
        // Cells of at least 2 r, larger where photons are sparse: a query pays one table
        // probe per cell it crosses and one test per photon listed, so cells of about
        // `PHOTONS_PER_CELL` photons (at the mean density over the bounds), up to 8 r;
        // and few enough that every coordinate fits its 21 bits.
        let density = photons.len() as f32 / (hi - lo).element_product().max(1e-30);
        let sparse = (PHOTONS_PER_CELL / density.max(1e-30))
            .cbrt()
            .min(8.0 * radius);
        let cell = (2.0 * radius)
            .max(sparse)
            .max((hi - lo).max_element() / 1.0e6);
        let mut map = VolumeMap {
            photons,
            radius,
            lo,
            hi,
            cell,
            table: vec![],
            refs: vec![],
        };
        let mut pairs: Vec<(u64, u32)> = (0..map.photons.len())
            .into_par_iter()
            .fold(Vec::new, |mut out, i| {
                map.cells_of(i, |k| out.push((k, i as u32)));
                out
            })
            .reduce(Vec::new, |mut a, mut b| {
                a.append(&mut b);
                a
            });
        pairs.par_sort_unstable();
        let cells = pairs.chunk_by(|a, b| a.0 == b.0).count();
        map.table = vec![(EMPTY, 0, 0); (2 * cells).next_power_of_two().max(2)];
        let mask = map.table.len() - 1;
        let mut start = 0;
        for run in pairs.chunk_by(|a, b| a.0 == b.0) {
            let mut slot = hash(run[0].0) & mask;
            while map.table[slot].0 != EMPTY {
                slot = (slot + 1) & mask;
            }
            map.table[slot] = (run[0].0, start, start + run.len() as u32);
            start += run.len() as u32;
        }
        map.refs = pairs.into_iter().map(|(_, i)| i).collect();
        map
    }

    /// Number of photons.
    pub fn len(&self) -> usize {
        self.photons.len()
    }
    /// Whether the map holds no photon.
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    fn cell_coords(&self, x: Vec3) -> IVec3 {
        volume_cell(x, self.lo, self.cell)
    }

    /// The photons listed in cell `c`.
    fn list(&self, c: IVec3) -> &[u32] {
        let (k, mask) = (key(c), self.table.len() - 1);
        let mut slot = hash(k) & mask;
        loop {
            let (sk, a, b) = self.table[slot];
            if sk == k {
                return &self.refs[a as usize..b as usize];
            }
            if sk == EMPTY {
                return &[];
            }
            slot = (slot + 1) & mask;
        }
    }

    /// Calls `f` with the key of every cell photon `i`'s sphere's box overlaps.
    fn cells_of(&self, i: usize, mut f: impl FnMut(u64)) {
        let p = self.photons[i].pos();
        let (a, b) = (
            self.cell_coords(p - self.radius),
            self.cell_coords(p + self.radius),
        );
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                for x in a.x..=b.x {
                    f(key(IVec3::new(x, y, z)));
                }
            }
        }
    }

    /// The volume radiance estimate at the point `x` for light leaving towards `wo` (unit), in
    /// medium `medium` (index `medium_index`): the sum over that medium's photons within
    /// `R = POINT_RADIUS_FACTOR r` of `x` of `p(cos) power / (4/3 pi R^3)` (`cos` between the
    /// photon's travel and `wo`), which estimates `sigma_s` times the in-scattered radiance
    /// there. A photon within `R <= 2 r` of `x` is listed in a cell that `x`'s own box of
    /// half-width `r` overlaps (the two boxes overlap), so the query reads those cells only (at
    /// most 2 an axis), and counts a photon in one of them alone: the corner of the cells both
    /// boxes overlap, componentwise the larger of the two boxes' lowest cells.
    pub fn point(&self, x: Vec3, wo: Vec3, medium: &Medium, medium_index: u32) -> Vec3 {
        if self.photons.is_empty() || x.cmplt(self.lo).any() || x.cmpgt(self.hi).any() {
            return Vec3::ZERO;
        }
        let r = POINT_RADIUS_FACTOR * self.radius;
        let (a, b) = (
            self.cell_coords(x - self.radius),
            self.cell_coords(x + self.radius),
        );
        let mut sum = Vec3::ZERO;
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                for cx in a.x..=b.x {
                    let c = IVec3::new(cx, y, z);
                    for &i in self.list(c) {
                        let p = &self.photons[i as usize];
                        let (q, medium_of) = (p.pos(), p.normal);
                        if medium_of != medium_index
                            || (q - x).length_squared() >= r * r
                            || self.cell_coords(q - self.radius).max(a) != c
                        {
                            continue;
                        }
                        sum += medium.phase.eval(Vec3::from(p.dir).dot(wo)) * Vec3::from(p.power);
                    }
                }
            }
        }
        sum * (3.0 / (4.0 * PI * r * r * r))
    }

    /// Where the ray from `o` along unit `d` leaves the photons' bounds (0 where it never
    /// meets them).
    pub fn exit(&self, o: Vec3, d: Vec3) -> f32 {
        if self.photons.is_empty() {
            return 0.0;
        }
        let inv = d.recip();
        let (ta, tb) = ((self.lo - o) * inv, (self.hi - o) * inv);
        ta.max(tb).min_element().max(0.0)
    }

    /// The beam radiance estimate along the segment from `o` along unit `d`, `t_max` long
    /// (infinite allowed), in medium `medium` (index `medium_index`): the sum over photons of
    /// that medium whose sphere the segment passes through, each at its nearest point t on
    /// the ray, of `T(t) p(cos) power / (pi r^2)` (a disc kernel across the ray; `cos`
    /// between the photon's travel and the way to the camera, `-d`), over the photons
    /// `which` keeps. For a homogeneous medium (its exact transmittance);
    /// [`Self::beam_through`] takes any.
    pub fn beam(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        medium: &Medium,
        medium_index: u32,
        which: BeamPhotons,
    ) -> Vec3 {
        let tr = Transmittances::Exact(medium.sigma_t);
        self.beam_through((o, d, t_max), (medium, medium_index), which, &tr)
    }

    /// [`Self::beam`] of the segment `(o, d, t_max)` in `(medium, medium_index)`, with the
    /// transmittance from `o` to each photon's nearest point read from `tr` (a heterogeneous
    /// medium's: [`Medium::transmittances`]).
    pub fn beam_through(
        &self,
        (o, d, t_max): (Vec3, Vec3, f32),
        (medium, medium_index): (&Medium, u32),
        which: BeamPhotons,
        tr: &Transmittances,
    ) -> Vec3 {
        if self.photons.is_empty() {
            return Vec3::ZERO;
        }
        // Clip the segment to the photons' bounds (slab test).
        let inv = d.recip();
        let (ta, tb) = ((self.lo - o) * inv, (self.hi - o) * inv);
        let t0 = ta.min(tb).max_element().max(0.0);
        let t1 = ta.max(tb).min_element().min(t_max);
        if !(t0 < t1) {
            return Vec3::ZERO;
        }
        let r2 = self.radius * self.radius;
        let norm = 1.0 / (PI * r2);
        let mut sum = Vec3::ZERO;
        // 3D DDA from the entry point.
        let mut c = self.cell_coords(o + d * t0);
        let step = IVec3::new(sign(d.x), sign(d.y), sign(d.z));
        let next_boundary = |c: IVec3, axis: usize| -> f32 {
            if step[axis] == 0 {
                return f32::INFINITY;
            }
            let edge = self.lo[axis] + (c[axis] + (step[axis] > 0) as i32) as f32 * self.cell;
            (edge - o[axis]) * inv[axis]
        };
        let mut t_next = Vec3::new(
            next_boundary(c, 0),
            next_boundary(c, 1),
            next_boundary(c, 2),
        );
        let t_delta = (self.cell * inv).abs();
        let mut t_enter = t0;
        for _ in 0..MAX_STEPS {
            let axis = if t_next.x <= t_next.y && t_next.x <= t_next.z {
                0
            } else if t_next.y <= t_next.z {
                1
            } else {
                2
            };
            let t_exit = t_next[axis].min(t1);
            for &i in self.list(c) {
                let p = &self.photons[i as usize];
                if p.normal != medium_index || !which.keeps(p) {
                    continue;
                }
                let to = p.pos() - o;
                let t = to.dot(d);
                // The photon's nearest point on the ray must lie in this cell's part.
                if t < t_enter || t >= t_exit || t < t0 || t >= t1 {
                    continue;
                }
                if (to - d * t).length_squared() >= r2 {
                    continue;
                }
                let phase = medium.phase.eval(Vec3::from(p.dir).dot(-d));
                sum += tr.at(t) * phase * Vec3::from(p.power);
            }
            if t_exit >= t1 {
                break;
            }
            t_enter = t_exit;
            c[axis] += step[axis];
            t_next[axis] += t_delta[axis];
        }
        sum * norm
    }
}

fn sign(x: f32) -> i32 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::{Rng, Stream};
    use crate::media::phase::HenyeyGreenstein;

    /// Photons spread uniformly through a unit cube, each of power `phi`, in a clear
    /// isotropic medium: the point estimate inside is `n phi / (4 pi)` per unit volume, and
    /// the beam estimate along a segment of length L inside is L times that (within the
    /// noise of the photons counted: about 7,000 per point query, 30,000 per beam), with
    /// photons of another medium and depth-0 photons (`BeamPhotons::SkipDirect`) left out,
    /// or all but the caustic ones (`BeamPhotons::Caustic`).
    #[test]
    fn point_and_beam_estimates_match_a_uniform_density() {
        let (n, r, phi) = (200_000u32, 0.2f32, 1e-3f32);
        let mut rng = Rng::new(7, Stream::Photon, 0, 0);
        let photons: Vec<Photon> = (0..n)
            .map(|i| {
                let p = Vec3::new(rng.next(), rng.next(), rng.next());
                let dir = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, 1.0).normalize();
                // Every tenth photon in medium 1; every other one of depth 0.
                Photon::in_medium(
                    p,
                    Vec3::splat(phi),
                    dir,
                    (i % 10 == 9) as u32,
                    i,
                    i % 2,
                    i % 3 == 0,
                )
            })
            .collect();
        let map = VolumeMap::build(photons, r);
        let m = Medium {
            sigma_t: Vec3::ZERO,
            albedo: Vec3::ONE,
            phase: HenyeyGreenstein { g: 0.0 },
            kind: crate::media::MediumKind::Homogeneous,
        };
        let density = 0.9 * n as f32 * phi / (4.0 * PI);
        let mut mean = 0.0;
        for i in 0..16 {
            let x = Vec3::new(0.3 + 0.025 * i as f32, 0.5, 0.45 + 0.01 * i as f32);
            mean += map.point(x, Vec3::Z, &m, 0).x / 16.0;
        }
        assert!(
            (mean / density - 1.0).abs() < 0.02,
            "point {mean} vs {density}"
        );
        // A segment from inside to inside, 0.5 long, not starting at a cell boundary.
        let (o, d) = (
            Vec3::new(0.25, 0.3, 0.5),
            Vec3::new(1.0, 1.0, 0.3).normalize(),
        );
        let beam = map.beam(o, d, 0.5, &m, 0, BeamPhotons::All).x;
        assert!((beam / (0.5 * density) - 1.0).abs() < 0.02, "beam {beam}");
        let direct_left_out = map.beam(o, d, 0.5, &m, 0, BeamPhotons::SkipDirect).x;
        // Of medium 0's photons (i mod 10 in 0..9), those with odd i are of depth 1: 4 in 9.
        let want = 0.5 * density * 4.0 / 9.0;
        assert!(
            (direct_left_out / want - 1.0).abs() < 0.03,
            "{direct_left_out} vs {want}"
        );
        // A third of them are caustic (L S+ V) photons.
        let caustic = map.beam(o, d, 0.5, &m, 0, BeamPhotons::Caustic).x;
        let want = 0.5 * density / 3.0;
        assert!((caustic / want - 1.0).abs() < 0.04, "{caustic} vs {want}");
        // Outside the photons' bounds: nothing.
        assert_eq!(map.point(Vec3::splat(2.0), Vec3::Z, &m, 0), Vec3::ZERO);
    }
}
