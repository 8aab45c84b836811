//! The radiance estimate from the K nearest photons (Jensen): kernel weights and the
//! normalisation of each filter. Backend-neutral; twin: `shaders/common/estimate.wgsl`.

use crate::photon::Photon;
use crate::settings::Filter;
use glam::Vec3;
use std::f32::consts::PI;

/// Jensen's cone-filter constant k (weights fall to 0 at distance k r).
pub const CONE_K: f32 = 1.0;

/// Kernel weight of a photon at squared distance `d2` inside radius^2 `r2`.
#[inline]
pub fn kernel_weight(filter: Filter, d2: f32, r2: f32) -> f32 {
    match filter {
        Filter::Disc => 1.0,
        Filter::Cone => (1.0 - (d2 / r2).sqrt() / CONE_K).max(0.0),
        Filter::Epanechnikov => (1.0 - d2 / r2).max(0.0),
    }
}

/// The area normalisation `1 / integral of the kernel over the disc of radius^2 r2`.
#[inline]
pub fn kernel_norm(filter: Filter, r2: f32) -> f32 {
    match filter {
        Filter::Disc => 1.0 / (PI * r2),
        Filter::Cone => 1.0 / ((1.0 - 2.0 / (3.0 * CONE_K)) * PI * r2),
        Filter::Epanechnikov => 2.0 / (PI * r2),
    }
}

/// The radius^2 of the estimate: the K-th neighbour's when K were found, else the search
/// radius^2 (fewer than K photons inside it means the whole disc was searched).
#[inline]
pub fn estimate_r2(found: usize, k: usize, farthest_d2: f32, max_r2: f32) -> f32 {
    if found >= k {
        farthest_d2.max(1e-30)
    } else {
        max_r2
    }
}

/// Reflected radiance towards the viewer from photons `(d2, photon)` around a point with unit
/// normal `ns` (facing the viewer), for a BRDF `f` evaluated per incident direction.
/// Photons that arrived from behind the surface are ignored.
///
/// When K photons were found, the K-th lies on the boundary of the disc it defines and is
/// left out: the K-nearest density estimate `K / (pi r_K^2)` is biased high by K / (K - 1)
/// (for uniformly distributed photons `E[1 / r_K^2] = pi density / (K - 1)`), while
/// `(K - 1) / (pi r_K^2)` is unbiased. The cone and Epanechnikov kernels give that photon
/// zero weight anyway.
pub fn radiance(
    neighbours: &[(f32, &Photon)],
    k: usize,
    max_r2: f32,
    filter: Filter,
    ns: Vec3,
    f: impl Fn(Vec3) -> Vec3,
) -> Vec3 {
    if neighbours.is_empty() {
        return Vec3::ZERO;
    }
    let farthest = neighbours.iter().map(|n| n.0).fold(0.0f32, f32::max);
    let r2 = estimate_r2(neighbours.len(), k, farthest, max_r2);
    let skip = if neighbours.len() >= k {
        neighbours.iter().position(|n| n.0 == farthest)
    } else {
        None
    };
    let mut sum = Vec3::ZERO;
    for (i, &(d2, p)) in neighbours.iter().enumerate() {
        let dir = Vec3::from(p.dir);
        if Some(i) == skip {
            continue;
        }
        if dir.dot(ns) >= 0.0 {
            continue;
        }
        sum += f(-dir) * Vec3::from(p.power) * kernel_weight(filter, d2, r2);
    }
    sum * kernel_norm(filter, r2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each kernel integrates to 1 over its disc (midpoint rule in the radius).
    #[test]
    fn kernels_are_normalised() {
        for filter in [Filter::Disc, Filter::Cone, Filter::Epanechnikov] {
            let r2 = 0.7f32;
            let r = r2.sqrt();
            let n = 20_000;
            let mut integral = 0.0f64;
            for i in 0..n {
                let rho = (i as f32 + 0.5) / n as f32 * r;
                integral +=
                    (kernel_weight(filter, rho * rho, r2) * 2.0 * PI * rho * (r / n as f32)) as f64;
            }
            let total = integral * kernel_norm(filter, r2) as f64;
            assert!((total - 1.0).abs() < 1e-3, "{filter:?}: {total}");
        }
    }
}
