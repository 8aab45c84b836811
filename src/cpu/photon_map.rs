//! A photon map: photons in a kd-tree (kiddo) for K-nearest-neighbour queries.

use crate::photon::Photon;
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
