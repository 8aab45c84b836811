//! A bound on the work of a fixed-radius photon search: photon counts per hashed grid cell
//! twice the search radius wide, so that the eight cells around a query hold every photon
//! within the radius. Their sum bounds what a kd-tree radius query reads. Where it exceeds
//! [`VISIT_BOUND`], finer levels (cells halving, down to [`LEVELS`]) find the largest radius
//! `r / 2^j` whose cells hold at most [`NARROWED_BOUND`], and the search reads that smaller
//! disc instead: the same fixed-radius estimate with a narrower kernel, unbiased where the
//! density is locally uniform, as the first radius is (`photon_map::estimate_at`). The
//! tables only decide how a search runs: a hash collision or a photon on a cell's edge
//! changes the radius chosen, never what a search of that radius finds.

use crate::integrators::estimate::{cell_hash, cell_of};

/// Photons a fixed-radius search may read (the eight cells' count) before it is narrowed:
/// the bound both backends share. The point-lit plane (`scenes/point-light-plane.toml`), the
/// example scene whose photons are densest against its first radius (about 10^3 times),
/// stays below it.
pub const VISIT_BOUND: u32 = crate::integrators::estimate::SEARCH_VISIT_BOUND;

/// What the cells of a narrowed search hold at most: a few hundred photons within its
/// radius on a surface, about as many as an ordinary search reads, so the narrowed estimate
/// blurs no more than the scene's radius was meant to (a narrower bound leaves more noise,
/// a wider one more blur where light changes fast, as under a point light).
pub const NARROWED_BOUND: u32 = 1_024;

/// Finer levels at most: the narrowest radius is `r / 2^(LEVELS - 1)`, a disc 4^-(LEVELS-1)
/// of the first's area.
pub const LEVELS: usize = 14;

/// Photons a search reads where even the finest level's cells hold more than
/// [`NARROWED_BOUND`] (photons stacked on one point): Jensen's K-nearest estimate with this K.
pub const NARROWED_K: usize = 1_024;

/// Photon counts per hashed cell of one side.
struct Level {
    cell: f32,
    size: u32,
    counts: Vec<u16>,
}

impl Level {
    fn build(positions: &[[f32; 3]], cell: f32) -> Self {
        let size = positions.len().max(256).next_power_of_two().min(1 << 30);
        let mut l = Level {
            cell,
            size: size as u32,
            counts: vec![0; size],
        };
        for &p in positions {
            let slot = l.slot(cell_of(p, cell));
            l.counts[slot] = l.counts[slot].saturating_add(1);
        }
        l
    }

    fn slot(&self, c: [i32; 3]) -> usize {
        cell_hash(c, self.size) as usize
    }

    /// The counts of the eight cells that hold every point within half a cell of `x`.
    fn bound(&self, x: [f32; 3]) -> u32 {
        // Per axis: x's cell and the neighbour on the side of x's nearer edge.
        let axis = |c: f32| {
            let s = c / self.cell;
            let i = s.floor() as i32;
            if s - s.floor() < 0.5 {
                [i - 1, i]
            } else {
                [i, i + 1]
            }
        };
        let [ax, ay, az] = x.map(axis);
        let mut sum = 0u32;
        for cx in ax {
            for cy in ay {
                for cz in az {
                    sum += u32::from(self.counts[self.slot([cx, cy, cz])]);
                }
            }
        }
        sum
    }
}

/// Photon counts per hashed cell at cell sides `2 r`, `r`, `r / 2`, ...: a level is built
/// only where the one above has a cell that could make a search read more than the bound.
pub struct DensityTable {
    levels: Vec<Level>,
}

impl DensityTable {
    /// Counts `positions` for searches of radius at most `radius`: `None` for a radius that is
    /// not positive and finite.
    pub fn build(positions: &[[f32; 3]], radius: f32) -> Option<Self> {
        let mut cell = 2.0 * radius;
        if !(cell > 0.0 && cell.is_finite()) {
            return None;
        }
        let mut levels = vec![Level::build(positions, cell)];
        // Eight cells can sum past a bound only if one holds an eighth of it.
        let crowded = |l: &Level, bound: u32| l.counts.iter().any(|&c| u32::from(c) * 8 > bound);
        let mut bound = VISIT_BOUND;
        while levels.len() < LEVELS && crowded(levels.last().unwrap(), bound) {
            bound = NARROWED_BOUND;
            cell *= 0.5;
            levels.push(Level::build(positions, cell));
        }
        Some(DensityTable { levels })
    }

    /// The squared radius a search at `x` of squared radius `r2` reads: `r2` itself where
    /// the cells around `x` hold at most [`VISIT_BOUND`] photons, else the largest
    /// `r2 / 4^j` whose finer cells hold at most [`NARROWED_BOUND`]; `None` where no level does (the search then reads
    /// the nearest photons). `r2` itself where the table cannot tell: `x` not finite, or a
    /// wider search than the table was built for.
    pub fn radius2_at(&self, x: [f32; 3], r2: f32) -> Option<f32> {
        let first = self.levels[0].cell;
        if r2.is_nan() || 4.0 * r2 > first * first || !x.iter().all(|c| c.is_finite()) {
            return Some(r2);
        }
        if self.levels[0].bound(x) <= VISIT_BOUND {
            return Some(r2);
        }
        let mut r2 = r2;
        for level in &self.levels[1..] {
            r2 = r2.min(0.25 * level.cell * level.cell);
            if level.bound(x) <= NARROWED_BOUND {
                return Some(r2);
            }
        }
        None
    }

    /// How many levels were built (1: no cell was crowded).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::pcg_hash;

    fn points(n: usize, seed: u32, lo: [f32; 3], size: [f32; 3]) -> Vec<[f32; 3]> {
        let mut s = seed;
        let mut next = || {
            s = pcg_hash(s);
            s as f32 / u32::MAX as f32
        };
        (0..n)
            .map(|_| [0, 1, 2].map(|a| lo[a] + next() * size[a]))
            .collect()
    }

    fn inside(pts: &[[f32; 3]], x: [f32; 3], r2: f32) -> u32 {
        pts.iter()
            .filter(|p| (0..3).map(|a| (p[a] - x[a]).powi(2)).sum::<f32>() < r2 * 0.999)
            .count() as u32
    }

    #[test]
    fn sparse_searches_keep_their_radius_and_dense_ones_read_at_most_the_bound() {
        // A plane of sparse photons with a dense patch (100,000 in 0.02 x 0.02).
        let mut pts = points(20_000, 7, [-1.0, 0.0, -1.0], [2.0, 0.0, 2.0]);
        pts.extend(points(100_000, 8, [0.3, 0.0, 0.3], [0.02, 0.0, 0.02]));
        let r = 0.05f32;
        let t = DensityTable::build(&pts, r).unwrap();
        assert!(t.levels() > 1);
        let queries = points(400, 9, [-1.0, 0.0, -1.0], [2.0, 0.0, 2.0]);
        let patch = points(100, 10, [0.3, 0.0, 0.3], [0.02, 0.0, 0.02]);
        let mut narrowed = 0;
        for x in queries.into_iter().chain(patch) {
            let r2 = t.radius2_at(x, r * r).unwrap();
            // A search of the radius chosen reads at most the bound: the visit bound, or the
            // narrowed bound where the radius was narrowed.
            if r2 < r * r {
                narrowed += 1;
                assert!(inside(&pts, x, r2) <= NARROWED_BOUND, "{x:?}");
            } else {
                assert_eq!(r2, r * r);
                assert!(inside(&pts, x, r2) <= VISIT_BOUND, "{x:?}");
            }
        }
        assert!(narrowed >= 100, "{narrowed}");
        // A wider search than the table was built for, or a NaN position: left as asked.
        assert_eq!(t.radius2_at([0.0; 3], 4.0 * r * r), Some(4.0 * r * r));
        assert_eq!(t.radius2_at([f32::NAN; 3], r * r), Some(r * r));
        // Photons stacked on one point: no level helps.
        let stack = vec![[0.5f32, 0.5, 0.5]; 20_000];
        let t = DensityTable::build(&stack, r).unwrap();
        assert_eq!(t.levels(), LEVELS);
        assert_eq!(t.radius2_at([0.5, 0.5, 0.5], r * r), None);
        assert!(DensityTable::build(&pts, f32::NAN).is_none());
        // Nothing crowded: one level.
        assert_eq!(DensityTable::build(&pts[..20_000], r).unwrap().levels(), 1);
    }
}
