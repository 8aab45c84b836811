//! A photon map: photons in a kd-tree (kiddo) for K-nearest-neighbour queries, and the
//! radiance estimate from it (read by the camera pass and the radiance cache).

use crate::estimate;
use crate::photon::Photon;
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZeroUsize;

/// Photons and a kd-tree over their positions (`tree` item `i` is `photons[i]`).
pub struct PhotonMap {
    /// The photons, in the order the tree indexes them.
    pub photons: Vec<Photon>,
    tree: Option<ImmutableKdTree<f32, 3>>,
}

impl PhotonMap {
    /// Builds the map over `photons`.
    pub fn build(photons: Vec<Photon>) -> Self {
        let points: Vec<[f32; 3]> = photons.iter().map(|p| p.position).collect();
        let tree = if points.is_empty() {
            None
        } else {
            ImmutableKdTree::new_from_slice(&points).ok()
        };
        PhotonMap { photons, tree }
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
/// within `max_r2`, or with `k == 0` (progressive passes) every photon within `max_r2`.
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
        map.within(x.to_array(), max_r2, &mut found);
        return estimate::radiance(&found, usize::MAX, max_r2, filter, x, ns, |_| f);
    }
    map.nearest(x.to_array(), k, max_r2, &mut found);
    estimate::radiance(&found, k, max_r2, filter, x, ns, |_| f)
}
