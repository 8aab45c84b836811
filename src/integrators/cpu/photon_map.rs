//! A photon map: photons in a kd-tree (kiddo) for K-nearest-neighbour queries, and for a
//! map built for one radius a hashed grid for its fixed-radius estimates; the radiance
//! estimate from them (read by the camera pass and the radiance cache).

use crate::integrators::cpu::density::{DensityTable, NARROWED_K};
use crate::integrators::cpu::point_grid::PointGrid;
use crate::integrators::estimate;
use crate::integrators::photon::Photon;
use crate::settings::Filter;
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

/// What a fixed-radius estimate reads of a photon besides its position: its direction,
/// unpacked normal and power.
#[derive(Clone, Copy, Debug)]
struct GridPhoton {
    dir: Vec3,
    normal: Vec3,
    power: Vec3,
}

/// Photons and a kd-tree over their positions (`tree` item `i` is `photons[i]`).
pub struct PhotonMap {
    /// The photons, in the order the tree indexes them.
    pub photons: Vec<Photon>,
    /// Built on first use for a map with a grid (only K-nearest searches read it).
    tree: OnceLock<Option<ImmutableKdTree<f32, 3>>>,
    /// Fixed-radius searches of at most the radius a bounded map was built for (cells of
    /// that radius).
    grid: Option<PointGrid<GridPhoton>>,
    /// Bounds the work of fixed-radius searches ([`PhotonMap::build_bounded`]).
    density: Option<DensityTable>,
    /// Fixed-radius searches narrowed so far.
    narrowed: AtomicU64,
}

/// A kd-tree over `points`, none when there are none.
fn kd_tree(points: &[[f32; 3]]) -> Option<ImmutableKdTree<f32, 3>> {
    if points.is_empty() {
        None
    } else {
        ImmutableKdTree::new_from_slice(points).ok()
    }
}

impl PhotonMap {
    /// Builds the map over `photons`. Its fixed-radius searches read every photon within
    /// their radius, however many.
    pub fn build(photons: Vec<Photon>) -> Self {
        Self::build_with(photons, None)
    }

    /// Builds the map over `photons` for fixed-radius searches of at most `radius`, each of
    /// which reads a bounded number of photons (`crate::integrators::cpu::density`): a smaller radius
    /// where the first holds too many, or the [`NARROWED_K`] nearest where no radius helps.
    pub fn build_bounded(photons: Vec<Photon>, radius: f32) -> Self {
        Self::build_with(photons, Some(radius))
    }

    /// The kd-tree, and for searches of at most `radius` if given the density table and the
    /// grid (the tree then waits for a K-nearest search), over one list of the positions.
    fn build_with(photons: Vec<Photon>, radius: Option<f32>) -> Self {
        let points: Vec<[f32; 3]> = photons.iter().map(|p| p.position).collect();
        let grid = radius.filter(|r| *r > 0.0 && r.is_finite()).map(|r| {
            PointGrid::build(&points, r, |i| {
                let p = &photons[i];
                GridPhoton {
                    dir: Vec3::from(p.dir),
                    normal: p.normal(),
                    power: Vec3::from(p.power),
                }
            })
        });
        let tree = OnceLock::new();
        if grid.is_none() {
            let _ = tree.set(kd_tree(&points));
        }
        PhotonMap {
            density: radius.and_then(|r| DensityTable::build(&points, r)),
            photons,
            tree,
            grid,
            narrowed: AtomicU64::new(0),
        }
    }

    /// The kd-tree (built now if it was left for later).
    fn tree(&self) -> Option<&ImmutableKdTree<f32, 3>> {
        self.tree
            .get_or_init(|| {
                let points: Vec<[f32; 3]> = self.photons.iter().map(|p| p.position).collect();
                kd_tree(&points)
            })
            .as_ref()
    }

    /// Fixed-radius searches narrowed so far (a smaller radius or the nearest photons).
    pub fn narrowed(&self) -> u64 {
        self.narrowed.load(Ordering::Relaxed)
    }

    /// The squared radius a fixed-radius search at `x` of `r2` reads (counted when
    /// narrowed), or `None` where it must read the [`NARROWED_K`] nearest instead.
    fn search_radius2(&self, x: [f32; 3], r2: f32) -> Option<f32> {
        let Some(table) = &self.density else {
            return Some(r2);
        };
        let chosen = table.radius2_at(x, r2);
        if chosen != Some(r2) {
            self.narrowed.fetch_add(1, Ordering::Relaxed);
        }
        chosen
    }

    /// Number of photons.
    pub fn len(&self) -> usize {
        self.photons.len()
    }
    /// Whether the map holds no photon.
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Every photon within squared distance `r2` of `x`, as `(squared distance, photon)`.
    pub fn within<'a>(&'a self, x: [f32; 3], r2: f32, out: &mut Vec<(f32, &'a Photon)>) {
        out.clear();
        let Some(tree) = self.tree() else { return };
        let found = tree
            .query(&x)
            .within::<SquaredEuclidean<f32>>(r2)
            .unsorted()
            .execute();
        out.extend(
            found
                .into_iter()
                .map(|r| (r.distance, &self.photons[r.item as usize])),
        );
    }

    /// The up to `k` nearest photons within squared distance `max_r2` of `x`, as
    /// `(squared distance, photon)`, nearest first, written into `out`.
    pub fn nearest<'a>(
        &'a self,
        x: [f32; 3],
        k: usize,
        max_r2: f32,
        out: &mut Vec<(f32, &'a Photon)>,
    ) {
        out.clear();
        let (Some(tree), Some(k)) = (self.tree(), NonZeroUsize::new(k)) else {
            return;
        };
        let found = tree
            .query(&x)
            .nearest_n::<SquaredEuclidean<f32>>(k)
            .within(max_r2)
            .execute();
        out.extend(
            found
                .into_iter()
                .map(|r| (r.distance, &self.photons[r.item as usize])),
        );
    }
}

/// The radiance estimate from `map` at `x` with a Lambertian BRDF `kd / pi`: the K nearest
/// within `max_r2`, or with `k == 0` (progressive passes) every photon within `max_r2` (a
/// bounded map's narrower radius where that holds more than a search may read).
pub fn estimate_at(
    map: &PhotonMap,
    x: Vec3,
    ns: Vec3,
    k: usize,
    max_r2: f32,
    filter: Filter,
    f: Vec3,
) -> Vec3 {
    let mut found = Vec::with_capacity(k.max(16));
    if k == 0 {
        let Some(r2) = map.search_radius2(x.to_array(), max_r2) else {
            map.nearest(x.to_array(), NARROWED_K, max_r2, &mut found);
            return estimate::radiance(&found, NARROWED_K, max_r2, filter, x, ns, |_| f);
        };
        if let Some(grid) = map.grid.as_ref().filter(|g| r2 <= g.cell().powi(2)) {
            return grid_radiance(grid, r2, filter, x, ns, f);
        }
        map.within(x.to_array(), r2, &mut found);
        return estimate::radiance(&found, usize::MAX, r2, filter, x, ns, |_| f);
    }
    map.nearest(x.to_array(), k, max_r2, &mut found);
    estimate::radiance(&found, k, max_r2, filter, x, ns, |_| f)
}

/// `estimate::radiance` over every photon within `r2` of `x` (no K: the whole disc), read
/// from the grid: the same photons and terms, summed in the grid's order.
fn grid_radiance(
    grid: &PointGrid<GridPhoton>,
    r2: f32,
    filter: Filter,
    x: Vec3,
    ns: Vec3,
    f: Vec3,
) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut found = false;
    grid.search(x.to_array(), r2, |p, d2| {
        found = true;
        let q = &p.data;
        let pos = Vec3::from(p.position);
        if estimate::faces(q.dir, || q.normal, pos, x, ns) {
            sum += f * q.power * estimate::kernel_weight(filter, d2, r2);
        }
    });
    if !found {
        return Vec3::ZERO;
    }
    sum * estimate::kernel_norm(filter, r2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::cpu::point_grid::tests::uniform;

    /// A map built for a radius estimates from its grid what the kd-tree's fixed-radius
    /// search gives (the same photons, summed in another order), for every filter and for
    /// radii up to the one it was built for.
    #[test]
    fn grid_estimates_equal_the_kd_tree_estimates() {
        let mut next = uniform(11);
        let photons: Vec<Photon> = (0..20_000)
            .map(|i| {
                // The floor y = 0 and the wall x = 0 of a room, lit from above and the side.
                let (pos, n) = if i % 3 == 0 {
                    (Vec3::new(0.0, next(), next()), Vec3::X)
                } else {
                    (Vec3::new(next(), 0.0, next()), Vec3::Y)
                };
                let dir = (Vec3::new(next(), next(), next()) - 0.5 - n).normalize();
                let power = Vec3::new(next(), next(), next());
                Photon::new(pos, power, dir, n, i, i % 3, false)
            })
            .collect();
        let r = 0.1f32;
        let grid = PhotonMap::build_bounded(photons.clone(), r);
        let tree = PhotonMap::build(photons);
        let f = Vec3::new(0.2, 0.3, 0.4);
        for q in 0..300 {
            let (x, ns) = match q % 3 {
                0 => (Vec3::new(0.0, next(), next()), Vec3::X),
                1 => (Vec3::new(next(), 0.0, next()), Vec3::Y),
                _ => (Vec3::new(next() * 0.05, 0.0, next()), Vec3::Y),
            };
            let filter = [Filter::Cone, Filter::Disc, Filter::Epanechnikov][q % 3];
            let r2 = (r * [1.0, 0.5, 0.999][q / 3 % 3]).powi(2);
            let a = estimate_at(&grid, x, ns, 0, r2, filter, f);
            let b = estimate_at(&tree, x, ns, 0, r2, filter, f);
            assert!(b.max_element() > 0.0, "query {q}");
            assert!(
                (a - b).abs().max_element() <= 1e-5 * b.max_element(),
                "query {q}: grid {a} != kd-tree {b}"
            );
        }
    }
}
