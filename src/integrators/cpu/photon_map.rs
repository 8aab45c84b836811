//! A photon map: photons in a kd-tree (kiddo) for K-nearest-neighbour queries, and the
//! radiance estimate from it (read by the camera pass and the radiance cache).

use crate::integrators::cpu::density::{DensityTable, NARROWED_K};
use crate::integrators::estimate;
use crate::integrators::photon::Photon;
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicU64, Ordering};

/// Photons and a kd-tree over their positions (`tree` item `i` is `photons[i]`).
pub struct PhotonMap {
    /// The photons, in the order the tree indexes them.
    pub photons: Vec<Photon>,
    tree: Option<ImmutableKdTree<f32, 3>>,
    /// Bounds the work of fixed-radius searches ([`PhotonMap::build_bounded`]).
    density: Option<DensityTable>,
    /// Fixed-radius searches narrowed so far.
    narrowed: AtomicU64,
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

    /// The kd-tree, and the density table for searches of at most `radius` if given, over
    /// one list of the photons' positions.
    fn build_with(photons: Vec<Photon>, radius: Option<f32>) -> Self {
        let points: Vec<[f32; 3]> = photons.iter().map(|p| p.position).collect();
        let tree = if points.is_empty() {
            None
        } else {
            ImmutableKdTree::new_from_slice(&points).ok()
        };
        PhotonMap {
            density: radius.and_then(|r| DensityTable::build(&points, r)),
            photons,
            tree,
            narrowed: AtomicU64::new(0),
        }
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
        let Some(tree) = &self.tree else { return };
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
        let (Some(tree), Some(k)) = (&self.tree, NonZeroUsize::new(k)) else {
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
    filter: crate::settings::Filter,
    f: Vec3,
) -> Vec3 {
    let mut found = Vec::with_capacity(k.max(16));
    if k == 0 {
        let Some(r2) = map.search_radius2(x.to_array(), max_r2) else {
            map.nearest(x.to_array(), NARROWED_K, max_r2, &mut found);
            return estimate::radiance(&found, NARROWED_K, max_r2, filter, x, ns, |_| f);
        };
        map.within(x.to_array(), r2, &mut found);
        return estimate::radiance(&found, usize::MAX, r2, filter, x, ns, |_| f);
    }
    map.nearest(x.to_array(), k, max_r2, &mut found);
    estimate::radiance(&found, k, max_r2, filter, x, ns, |_| f)
}
