//! A hashed uniform grid over points for the CPU's fixed-radius searches (the photon map's
//! fixed-radius estimate, the radiance cache's lookup). A cell's table slot is linear in its
//! coordinates, `x + y A + z B` modulo the table's size, so a row of cells along x is a run
//! of consecutive slots, and the points, sorted by slot, lie in one run of memory for the
//! whole row. A search visits the rows its ball overlaps (each slot once, however many
//! cells share it) and tests every point in them; cells sharing a slot only add
//! candidates, which the distance test rejects. The squared distance is
//! `dx*dx + dy*dy + dz*dz` in that order, as the brute-force oracles of the tests compute
//! it, so a search finds exactly the points a test of every point finds.

use rayon::prelude::*;

/// Cells a search may overlap per axis: a ball of radius at most the cell's side, padded
/// against rounding, overlaps at most four.
const MAX_SPAN: usize = 4;

/// Slot steps of a cell's y and z coordinates (odd, far apart modulo every table size).
const STEP_Y: u32 = 0x9e37_79b1;
const STEP_Z: u32 = 0x85eb_ca77;

/// A point of a grid with what its searches read of it, side by side in memory.
#[derive(Clone, Copy, Debug)]
pub struct GridPoint<T> {
    /// Where it is.
    pub position: [f32; 3],
    /// What the caller keeps with it.
    pub data: T,
}

impl<T> GridPoint<T> {
    /// Squared distance to `x`: `dx*dx + dy*dy + dz*dz`, in that order (as the tests' brute
    /// force computes it).
    #[inline]
    pub fn distance2(&self, x: [f32; 3]) -> f32 {
        let p = self.position;
        let (dx, dy, dz) = (p[0] - x[0], p[1] - x[1], p[2] - x[2]);
        dx * dx + dy * dy + dz * dz
    }
}

/// Points in hashed cells of one side (see the module's doc).
pub struct PointGrid<T> {
    /// The cell's side.
    cell: f32,
    /// Table slots minus one (a power of two minus one).
    mask: u32,
    /// Slot `s` holds sorted points `starts[s] .. starts[s + 1]`.
    starts: Vec<u32>,
    /// The sorted points.
    pub points: Vec<GridPoint<T>>,
    /// Index of each sorted point in the slice the grid was built from.
    pub index: Vec<u32>,
}

/// The cell coordinate of `c` along one axis.
#[inline]
fn cell_coord(c: f32, cell: f32) -> i32 {
    (c / cell).floor() as i32
}

/// The table slot of cell `c` before the mask (CPU-only; the GPU's grid has its own hash).
#[inline]
fn slot_of(c: [i32; 3]) -> u32 {
    (c[0] as u32)
        .wrapping_add((c[1] as u32).wrapping_mul(STEP_Y))
        .wrapping_add((c[2] as u32).wrapping_mul(STEP_Z))
}

/// Rings of cells whose gaps a nearest-point search computes before it starts (a search of
/// the cell's radius reaches two).
const NEAR_RINGS: usize = 2;

/// Up to this many slot runs per search (16 rows, each split in two where it wraps).
const MAX_RUNS: usize = 2 * MAX_SPAN * MAX_SPAN;

impl<T: Copy + Send + Sync> PointGrid<T> {
    /// Sorts `points` into cells of side `cell` (positive and finite), point `i` with
    /// `data(i)`. Points that are not finite are left out of every search.
    pub fn build(points: &[[f32; 3]], cell: f32, data: impl Fn(usize) -> T + Sync) -> Self {
        debug_assert!(cell > 0.0 && cell.is_finite());
        let cells: Vec<Option<u32>> = points
            .par_iter()
            .map(|p| {
                p.iter()
                    .all(|c| c.is_finite())
                    .then(|| slot_of(p.map(|c| cell_coord(c, cell))))
            })
            .collect();
        // About two slots per occupied cell (counted in a table of a slot per point), so
        // collisions stay rare and the table small.
        let count = |mask: u32| {
            let mut hit = vec![false; mask as usize + 1];
            cells
                .iter()
                .flatten()
                .for_each(|&c| hit[(c & mask) as usize] = true);
            hit.iter().filter(|&&h| h).count()
        };
        let first = points.len().max(256).next_power_of_two().min(1 << 28);
        let size = (2 * count(first as u32 - 1))
            .clamp(256, first)
            .next_power_of_two();
        let mask = size as u32 - 1;
        let slots: Vec<u32> = cells
            .iter()
            .map(|c| c.map_or(u32::MAX, |c| c & mask))
            .collect();
        let mut starts = vec![0u32; size + 1];
        for &s in &slots {
            if s != u32::MAX {
                starts[s as usize + 1] += 1;
            }
        }
        for s in 0..size {
            starts[s + 1] += starts[s];
        }
        let n = starts[size] as usize;
        let mut next = starts.clone();
        let mut index = vec![0u32; n];
        for (i, &s) in slots.iter().enumerate() {
            if s != u32::MAX {
                index[next[s as usize] as usize] = i as u32;
                next[s as usize] += 1;
            }
        }
        let points = index
            .par_iter()
            .map(|&i| GridPoint {
                position: points[i as usize],
                data: data(i as usize),
            })
            .collect();
        PointGrid {
            cell,
            mask,
            points,
            starts,
            index,
        }
    }

    /// The cell side searches are sized by.
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Number of points in the grid.
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// Whether the grid holds no point.
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The slot runs `(first, last)` of `count` cells along x from cell `c` (one run, or two
    /// where the slots wrap around the table).
    #[inline]
    fn row_runs(&self, c: [i32; 3], count: u32, runs: &mut [(u32, u32)], n: &mut usize) {
        let first = slot_of(c) & self.mask;
        let last = first + count - 1;
        if last <= self.mask {
            runs[*n] = (first, last);
            *n += 1;
        } else {
            runs[*n] = (first, self.mask);
            runs[*n + 1] = (0, last - self.mask - 1);
            *n += 2;
        }
    }

    /// Calls `visit(p, d2)` for every point `p` within squared distance `r2` of `x`
    /// (`d2 <= r2`) exactly once, in the grid's order; `r2` at most the cell's side squared
    /// (a wider search is cut to it).
    #[inline]
    pub fn search<'a>(
        &'a self,
        x: [f32; 3],
        r2: f32,
        mut visit: impl FnMut(&'a GridPoint<T>, f32),
    ) {
        if self.index.is_empty() || r2.is_nan() || r2 < 0.0 || !x.iter().all(|c| c.is_finite()) {
            return;
        }
        let r2 = r2.min(self.cell * self.cell);
        // The cells of the ball's bounding box, padded so that rounding never drops one.
        let reach = r2.sqrt() * 1.00001 + 1e-30;
        let mut lo = [0i32; 3];
        let mut n = [0usize; 3];
        // Per axis, the squared gap from x to each overlapped cell (0 for x's own).
        let mut gaps = [[0.0f32; MAX_SPAN]; 3];
        for a in 0..3 {
            lo[a] = cell_coord(x[a] - reach, self.cell);
            let hi = cell_coord(x[a] + reach, self.cell);
            n[a] = ((i64::from(hi) - i64::from(lo[a]) + 1).max(0) as usize).min(MAX_SPAN);
            for (k, gap) in gaps[a].iter_mut().enumerate().take(n[a]) {
                let c0 = lo[a].wrapping_add(k as i32) as f32 * self.cell;
                let g = (c0 - x[a]).max(x[a] - (c0 + self.cell)).max(0.0);
                *gap = g * g;
            }
        }
        let mut runs = [(0u32, 0u32); MAX_RUNS];
        let mut n_runs = 0;
        for k in 0..n[2] {
            for j in 0..n[1] {
                let gyz = gaps[1][j] + gaps[2][k];
                // The row's cells near enough: a contiguous range (the gap is convex).
                let near = |i: &usize| gaps[0][*i] + gyz <= r2;
                let Some(i0) = (0..n[0]).find(near) else {
                    continue;
                };
                let i1 = (0..n[0]).rev().find(near).unwrap_or(i0);
                let c = [
                    lo[0].wrapping_add(i0 as i32),
                    lo[1].wrapping_add(j as i32),
                    lo[2].wrapping_add(k as i32),
                ];
                self.row_runs(c, (i1 - i0 + 1) as u32, &mut runs, &mut n_runs);
            }
        }
        // Each slot once: rows whose runs overlap (cells sharing slots) are merged.
        let runs = &mut runs[..n_runs];
        runs.sort_unstable_by_key(|r| r.0);
        let mut m = 0;
        while m < runs.len() {
            let (first, mut last) = runs[m];
            m += 1;
            while m < runs.len() && runs[m].0 <= last + 1 {
                last = last.max(runs[m].1);
                m += 1;
            }
            self.visit_run(first, last, x, r2, &mut visit);
        }
    }

    /// For a nearest-point search: calls `scan(points, bound)` for runs `points` of sorted
    /// points (indices into [`PointGrid::points`]) that hold every point within squared
    /// distance `bound` of `x` of a row of cells, ring of cells by ring outwards from `x`'s
    /// own, where `bound` starts at `r2` (any radius) and is what the last `scan` returned
    /// (at most what it was: the caller's nearest point so far; the caller tests the
    /// points). It stops after the ring beyond which every point lies farther than `bound`.
    /// Every point within the final `bound` is in a run (a point whose slot another cell
    /// shares may be in two).
    #[inline]
    pub fn nearest(
        &self,
        x: [f32; 3],
        r2: f32,
        mut scan: impl FnMut(std::ops::Range<usize>, f32) -> f32,
    ) {
        if self.index.is_empty() || r2.is_nan() || r2 < 0.0 || !x.iter().all(|c| c.is_finite()) {
            return;
        }
        let home = x.map(|c| cell_coord(c, self.cell));
        // Squared gap from x to cell `home + o` along axis `a`.
        let gap_at = |a: usize, o: i32| {
            let c0 = home[a].wrapping_add(o) as f32 * self.cell;
            let g = (c0 - x[a]).max(x[a] - (c0 + self.cell)).max(0.0);
            g * g
        };
        // The gaps of the nearest rings, computed once (the rows ask for each many times).
        let mut near = [[0.0f32; 2 * NEAR_RINGS + 1]; 3];
        for (a, gaps) in near.iter_mut().enumerate() {
            for (k, g) in gaps.iter_mut().enumerate() {
                *g = gap_at(a, k as i32 - NEAR_RINGS as i32);
            }
        }
        let gap = |a: usize, o: i32| match near[a].get((o + NEAR_RINGS as i32) as usize) {
            Some(&g) => g,
            None => gap_at(a, o),
        };
        let rings = ((r2.sqrt() * 1.00001 + 1e-30) / self.cell).ceil() as i32;
        let mut bound = r2;
        let mut runs = [(0u32, 0u32); 2];
        for s in 0..=rings {
            // Every point outside rings 0..s lies at least this far (squared) from x.
            if s > 0 {
                let inner = (0..3)
                    .map(|a| gap(a, -s).min(gap(a, s)))
                    .fold(f32::MAX, f32::min);
                if inner > bound {
                    return;
                }
            }
            for dz in -s..=s {
                let gz = gap(2, dz);
                for dy in -s..=s {
                    let gyz = gz + gap(1, dy);
                    if gyz > bound {
                        continue;
                    }
                    let b2 = bound;
                    let row = |from: i32, to: i32| {
                        let from = (from..=to).find(|&dx| gyz + gap(0, dx) <= b2)?;
                        let to = (from..=to).rev().find(|&dx| gyz + gap(0, dx) <= b2)?;
                        Some((from, to))
                    };
                    // The ring's cells of this row: all of it on the ring's faces in y and
                    // z, else its two ends.
                    let spans = if dz.abs() == s || dy.abs() == s {
                        [row(-s, s), None]
                    } else {
                        [row(-s, -s), row(s, s)]
                    };
                    for (from, to) in spans.into_iter().flatten() {
                        let c = [
                            home[0].wrapping_add(from),
                            home[1].wrapping_add(dy),
                            home[2].wrapping_add(dz),
                        ];
                        let mut n = 0;
                        self.row_runs(c, (to - from + 1) as u32, &mut runs, &mut n);
                        for &(first, last) in &runs[..n] {
                            let (a, b) = (
                                self.starts[first as usize] as usize,
                                self.starts[last as usize + 1] as usize,
                            );
                            if a < b {
                                bound = scan(a..b, bound);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Calls `visit(j, d2)` for the points of slots `first..=last` within squared distance
    /// `r2` of `x`.
    #[inline]
    fn visit_run<'a>(
        &'a self,
        first: u32,
        last: u32,
        x: [f32; 3],
        r2: f32,
        visit: &mut impl FnMut(&'a GridPoint<T>, f32),
    ) {
        let (a, b) = (
            self.starts[first as usize] as usize,
            self.starts[last as usize + 1] as usize,
        );
        for p in &self.points[a..b] {
            let d2 = p.distance2(x);
            if d2 <= r2 {
                visit(p, d2);
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::rng::pcg_hash;

    /// Uniform numbers in [0, 1] from `seed` (the tests' points).
    pub(crate) fn uniform(seed: u32) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = pcg_hash(s);
            s as f32 / u32::MAX as f32
        }
    }

    /// Every search finds exactly the points a test of every point finds, on clustered
    /// points, radii up to the cell's side and queries on, near and off the points.
    #[test]
    fn searches_find_what_brute_force_finds() {
        let mut next = uniform(3);
        let mut pts: Vec<[f32; 3]> = (0..5000)
            .map(|_| [next() * 2.0 - 1.0, next() * 0.1, next() * 2.0 - 1.0])
            .collect();
        pts.extend((0..3000).map(|_| [0.3 + next() * 0.01, 0.05, -0.2 + next() * 0.01]));
        pts.push([f32::NAN, 0.0, 0.0]);
        let cell = 0.07;
        let g = PointGrid::build(&pts, cell, |i| i as u32);
        assert_eq!(g.len(), pts.len() - 1);
        for q in 0..600 {
            let x = if q % 3 == 0 {
                pts[q * 7 % 8000]
            } else {
                [next() * 2.4 - 1.2, next() * 0.2 - 0.05, next() * 2.4 - 1.2]
            };
            let r = cell * [1.0, 0.5, 0.01, 0.999][q % 4];
            let mut got: Vec<(u32, f32)> = Vec::new();
            g.search(x, r * r, |p, d2| got.push((p.data, d2)));
            got.sort_by_key(|e| e.0);
            let want: Vec<(u32, f32)> = pts
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let (dx, dy, dz) = (p[0] - x[0], p[1] - x[1], p[2] - x[2]);
                    (i as u32, dx * dx + dy * dy + dz * dz)
                })
                .filter(|e| e.1 <= r * r)
                .collect();
            assert_eq!(got, want, "query {q} at {x:?}, r {r}");
        }
    }

    /// A nearest-point search over cells finer than its radius finds the brute-force
    /// nearest point (ties by index), or none where no point is within the radius.
    #[test]
    fn nearest_finds_the_brute_force_nearest() {
        let mut next = uniform(5);
        let pts: Vec<[f32; 3]> = (0..4000).map(|_| [next(), next() * 0.05, next()]).collect();
        let r = 0.06f32;
        for cell in [r, r / 2.0, r / 3.0] {
            let g = PointGrid::build(&pts, cell, |i| i as u32);
            let (mut found, mut none) = (0, 0);
            for q in 0..500 {
                let x = [next() * 1.2 - 0.1, next() * 0.2 - 0.05, next() * 1.2 - 0.1];
                let mut best = (r * r, u32::MAX);
                g.nearest(x, r * r, |run, bound| {
                    for p in &g.points[run] {
                        let d2 = p.distance2(x);
                        if d2 <= bound && (d2, p.data) < best {
                            best = (d2, p.data);
                        }
                    }
                    best.0
                });
                let want = pts
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        let (dx, dy, dz) = (p[0] - x[0], p[1] - x[1], p[2] - x[2]);
                        (dx * dx + dy * dy + dz * dz, i as u32)
                    })
                    .filter(|e| e.0 <= r * r)
                    .min_by(|a, b| a.partial_cmp(b).unwrap());
                let got = Some(best).filter(|b| b.1 != u32::MAX);
                assert_eq!(got, want, "query {q} at {x:?}, cell {cell}");
                if want.is_some() {
                    found += 1
                } else {
                    none += 1
                }
            }
            assert!(found > 200 && none > 20, "{found} found, {none} none");
        }
    }
}
