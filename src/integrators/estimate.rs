//! The radiance estimate from the K nearest photons (Jensen): kernel weights and the
//! normalisation of each filter. Backend-neutral; twin: `kernel_weight`, `kernel_norm` and `estimate` in
//! `src/integrators/gpu/gather.wgsl`.

use crate::integrators::photon::Photon;
use crate::settings::Filter;
use glam::Vec3;
use std::f32::consts::PI;

/// Photons a radiance search may read, on either backend: past it the CPU narrows the
/// search (`cpu::density`) and the GPU cuts it and counts it (`MAX_VISITS` in
/// src/integrators/estimate.wgsl, lower still on lavapipe, whose loop budget bounds it first).
pub const SEARCH_VISIT_BOUND: u32 = 16_384;

/// Integer cell coordinates of `p` in a uniform grid of cells of side `cell_size` (the GPU's
/// photon grid, twin: src/integrators/gpu/grid.wgsl; the CPU's density tables, `cpu::density`).
pub fn cell_of(p: [f32; 3], cell_size: f32) -> [i32; 3] {
    p.map(|c| (c / cell_size).floor() as i32)
}

/// Hash-table slot of cell `c` (`table_size` a power of two).
pub fn cell_hash(c: [i32; 3], table_size: u32) -> u32 {
    use crate::math::rng::pcg_hash;
    let h = pcg_hash(c[0] as u32 ^ pcg_hash(c[1] as u32 ^ pcg_hash(c[2] as u32)));
    h & (table_size - 1)
}

/// Photons on a surface whose normal is within 60 degrees of the estimate's (cos > 0.5) are
/// on the same surface; beyond 120 degrees (cos < -0.5) they are on its other side.
pub const FACING_COS: f32 = 0.5;

/// Whether photon `p` lends light to an estimate at `x` on a surface with unit normal `ns`
/// facing the viewer. It must have arrived from the front. A photon of the same surface
/// counts; one of the other side (a wall's back, a closed sphere's inside) does not. A
/// photon of a surface meeting this one at an edge stands in for the part of the disc the
/// edge cuts off when the two surfaces face each other (a concave corner: each lies in front
/// of the other) or both face outwards (a convex edge: each lies behind the other); never
/// across the solid, when one lies in front of the other and not the other way round (the
/// inside of a closed box's wall next to a point on its outer top face).
#[inline]
pub fn photon_faces(p: &Photon, x: Vec3, ns: Vec3) -> bool {
    faces(Vec3::from(p.dir), || p.normal(), p.pos(), x, ns)
}

/// [`photon_faces`] of a photon travelling along `dir`, stored at `pos` with the unit normal
/// `normal()` (read only when the direction passes; the CPU's photon grid keeps it unpacked).
#[inline]
pub fn faces(dir: Vec3, normal: impl FnOnce() -> Vec3, pos: Vec3, x: Vec3, ns: Vec3) -> bool {
    if dir.dot(ns) >= 0.0 {
        return false;
    }
    let np = normal();
    let c = np.dot(ns);
    if c > FACING_COS {
        return true;
    }
    if c < -FACING_COS {
        return false;
    }
    ((pos - x).dot(ns) > 0.0) == ((x - pos).dot(np) > 0.0)
}

/// Jensen's cone-filter constant k (weights fall to 0 at distance k r).
pub const CONE_K: f32 = 1.0;
/// `1 / CONE_K`: the cone's weight is `1 - (d / r) / k`.
pub const INV_CONE_K: f32 = 1.0 / CONE_K;
/// The cone's area normalisation factor `1 - 2 / (3 k)` (its kernel integrates to that times
/// pi r^2), computed once in f32 for both backends.
pub const CONE_NORM: f32 = 1.0 - 2.0 / (3.0 * CONE_K);

/// Kernel weight of a photon at squared distance `d2` inside radius^2 `r2`.
#[inline]
pub fn kernel_weight(filter: Filter, d2: f32, r2: f32) -> f32 {
    match filter {
        Filter::Disc => 1.0,
        Filter::Cone => (1.0 - (d2 / r2).sqrt() * INV_CONE_K).max(0.0),
        Filter::Epanechnikov => (1.0 - d2 / r2).max(0.0),
    }
}

/// The area normalisation `1 / integral of the kernel over the disc of radius^2 r2`.
#[inline]
pub fn kernel_norm(filter: Filter, r2: f32) -> f32 {
    match filter {
        Filter::Disc => 1.0 / (PI * r2),
        Filter::Cone => 1.0 / (CONE_NORM * PI * r2),
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
/// Only photons that [`photon_faces`] the surface at `x` count.
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
    x: Vec3,
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
        if Some(i) == skip || !photon_faces(p, x, ns) {
            continue;
        }
        sum += f(-Vec3::from(p.dir)) * Vec3::from(p.power) * kernel_weight(filter, d2, r2);
    }
    sum * kernel_norm(filter, r2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The side test on the cases it separates, around the edge x = 0.5, y = 1 of a box
    /// (query on the top face, y = 1, or on the floor of a room, y = 0).
    #[test]
    fn photons_count_on_their_own_side_of_edges_and_walls() {
        let photon = |pos: [f32; 3], dir: Vec3, n: Vec3| {
            Photon::new(Vec3::from(pos), Vec3::ONE, dir.normalize(), n, 0, 0, false)
        };
        let down = Vec3::new(0.1, -1.0, 0.2);
        let x = Vec3::new(0.49, 1.0, 0.0);
        let cases = [
            // Same surface, lit from above.
            (
                "same surface",
                photon([0.45, 1.0, 0.01], down, Vec3::Y),
                x,
                Vec3::Y,
                true,
            ),
            // Arrived from behind the surface.
            (
                "from behind",
                photon([0.45, 1.0, 0.01], -down, Vec3::Y),
                x,
                Vec3::Y,
                false,
            ),
            // The underside of the top (closed box lit from inside).
            (
                "other side",
                photon([0.45, 1.0, 0.01], Vec3::new(0.1, 1.0, 0.0), Vec3::Y),
                x,
                Vec3::Y,
                false,
            ),
            // Inside of the +x wall, seen from the outer top face: across the solid.
            (
                "across the edge",
                photon([0.5, 0.99, 0.0], Vec3::new(1.0, -0.3, 0.0), Vec3::X),
                x,
                Vec3::Y,
                false,
            ),
            // Outer side of the +x wall, seen from the outer top face: a convex edge.
            (
                "convex edge",
                photon([0.5, 0.99, 0.0], Vec3::new(-1.0, -0.3, 0.0), Vec3::X),
                x,
                Vec3::Y,
                true,
            ),
            // A room's +x wall seen from its floor: a concave corner.
            (
                "concave corner",
                photon([0.5, 0.01, 0.0], Vec3::new(1.0, -0.3, 0.0), Vec3::X),
                Vec3::new(0.49, 0.0, 0.0),
                Vec3::Y,
                true,
            ),
            // The floor seen from the outer side of the wall: across the solid again.
            (
                "across, reversed",
                photon([0.49, 0.0, 0.0], Vec3::new(-0.1, -1.0, 0.2), Vec3::Y),
                Vec3::new(0.5, 0.01, 0.0),
                Vec3::X,
                false,
            ),
        ];
        for (name, p, x, ns, want) in cases {
            assert_eq!(photon_faces(&p, x, ns), want, "{name}");
        }
    }

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
