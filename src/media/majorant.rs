//! The majorant grid of a heterogeneous medium (issue 41): the extinction volume's box cut
//! into a coarse grid of cells, each holding a bound on the extinction anywhere in it (every
//! channel, times `scale`), walked along a ray by a 3D DDA. Tracking then draws tentative
//! collisions from each cell's own majorant, so empty space costs one cell step instead of
//! many null collisions, and a dense corner does not slow the rest.
//!
//! A cell's bound is the largest voxel value in the block of voxels that can reach it: the
//! cell's box mapped into the grid (its eight corners through `to_local`), widened by one
//! voxel for the trilinear filter and clamped to the grid as lookups are, so it holds for any
//! transform and filter.

use crate::media::grid::{Volume, VolumeKind};
use glam::{IVec3, UVec3, Vec3};

/// Voxels per cell along the grid's longest axis, about (a cell of 4 holds 6 after widening).
pub const VOXELS_PER_CELL: u32 = 4;

/// Most cells per axis.
pub const MAX_CELLS: u32 = 64;

/// Per-cell extinction bounds over a volume's box.
#[derive(Clone, Debug, PartialEq)]
pub struct MajorantGrid {
    lo: Vec3,
    size: Vec3,
    res: UVec3,
    cells: Vec<f32>,
}

impl MajorantGrid {
    /// The grid of `scale` times `sigma_t`'s bounds (one cell for a constant volume).
    pub fn new(sigma_t: &Volume, scale: f32) -> MajorantGrid {
        let (lo, hi) = (sigma_t.lo, sigma_t.hi);
        let VolumeKind::Grid { grid, to_local, .. } = &sigma_t.kind else {
            return MajorantGrid {
                lo,
                size: hi - lo,
                res: UVec3::ONE,
                cells: vec![scale * sigma_t.max()],
            };
        };
        let longest = grid.res.iter().copied().max().unwrap_or(1);
        let n = longest.div_ceil(VOXELS_PER_CELL).clamp(1, MAX_CELLS);
        let res = UVec3::splat(n);
        let size = (hi - lo) / n as f32;
        let voxels = IVec3::new(grid.res[0] as i32, grid.res[1] as i32, grid.res[2] as i32);
        let channels = grid.channels as usize;
        let mut cells = Vec::with_capacity((n * n * n) as usize);
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let c0 = lo + size * Vec3::new(x as f32, y as f32, z as f32);
                    // The cell's box in the grid's unit cube, then in voxel centres.
                    let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
                    for k in 0..8 {
                        let corner =
                            Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, (k >> 2) as f32);
                        let p = to_local.transform_point3(c0 + size * corner);
                        (a, b) = (a.min(p), b.max(p));
                    }
                    let res_f = voxels.as_vec3();
                    let first =
                        ((a * res_f - 0.5).floor().as_ivec3()).clamp(IVec3::ZERO, voxels - 1);
                    let last =
                        ((b * res_f - 0.5).floor().as_ivec3() + 1).clamp(IVec3::ZERO, voxels - 1);
                    let mut m = 0.0f32;
                    for vz in first.z..=last.z {
                        for vy in first.y..=last.y {
                            let row = ((vz * voxels.y + vy) * voxels.x) as usize;
                            let from = (row + first.x as usize) * channels;
                            let to = (row + last.x as usize + 1) * channels;
                            m = grid.data[from..to].iter().copied().fold(m, f32::max);
                        }
                    }
                    cells.push(scale * m);
                }
            }
        }
        MajorantGrid {
            lo,
            size,
            res,
            cells,
        }
    }

    /// How many cells it has.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Its layout for the device (`media/gpu.rs`): the lower corner, a cell's size, the
    /// cells per axis and the bounds, x fastest.
    pub fn parts(&self) -> (Vec3, Vec3, UVec3, &[f32]) {
        (self.lo, self.size, self.res, &self.cells)
    }

    /// Calls `f(ta, tb, majorant)` for each cell the ray from `o` along unit `d` crosses
    /// within `[t0, t1)` (inside the box), in order, until `f` returns false.
    pub fn walk(
        &self,
        o: Vec3,
        d: Vec3,
        t0: f32,
        t1: f32,
        mut f: impl FnMut(f32, f32, f32) -> bool,
    ) {
        let n = self.res.as_ivec3();
        if self.cells.len() == 1 {
            f(t0, t1, self.cells[0]);
            return;
        }
        let p = o + d * t0;
        let mut c = ((p - self.lo) / self.size)
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, n - 1);
        let step = IVec3::new(sign(d.x), sign(d.y), sign(d.z));
        let inv = d.recip();
        let boundary = |c: IVec3, axis: usize| match step[axis] {
            0 => f32::INFINITY,
            s => {
                let edge = self.lo[axis] + (c[axis] + (s > 0) as i32) as f32 * self.size[axis];
                (edge - o[axis]) * inv[axis]
            }
        };
        let mut t_next = Vec3::new(boundary(c, 0), boundary(c, 1), boundary(c, 2));
        let t_delta = (self.size * inv).abs();
        let mut ta = t0;
        // A ray crosses at most one cell per axis step.
        for _ in 0..(n.x + n.y + n.z) {
            let axis = match (
                t_next.x <= t_next.y,
                t_next.x <= t_next.z,
                t_next.y <= t_next.z,
            ) {
                (true, true, _) => 0,
                (_, _, true) => 1,
                _ => 2,
            };
            let tb = t_next[axis].min(t1);
            let i = ((c.z * n.y + c.y) * n.x + c.x) as usize;
            if tb > ta && !f(ta, tb, self.cells[i]) {
                return;
            }
            if tb >= t1 {
                return;
            }
            ta = ta.max(tb);
            c[axis] += step[axis];
            if c[axis] < 0 || c[axis] >= n[axis] {
                return;
            }
            t_next[axis] += t_delta[axis];
        }
    }
}

fn sign(x: f32) -> i32 {
    match x {
        x if x > 0.0 => 1,
        x if x < 0.0 => -1,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::{Rng, Stream};
    use crate::media::grid::{Filter, VolumeGrid};
    use glam::Affine3A;
    use std::sync::Arc;

    /// A 16^3 grid of pseudo-random sparse values, scaled, rotated and moved: along random
    /// rays the walk's cells tile the span without gaps or overlaps, and every cell's majorant
    /// bounds the extinction at points drawn in its part (both filters).
    #[test]
    fn cells_tile_the_ray_and_bound_the_density() {
        let mut rng = Rng::new(5, Stream::Photon, 0, 0);
        let data: Vec<f32> = (0..16 * 16 * 16 * 3)
            .map(|_| match rng.next() < 0.2 {
                true => rng.next() * 4.0,
                false => 0.0,
            })
            .collect();
        let grid = Arc::new(VolumeGrid {
            res: [16, 16, 16],
            channels: 3,
            bbox: [Vec3::ZERO, Vec3::ONE],
            data,
        });
        let to_world = Affine3A::from_translation(Vec3::new(0.3, -1.0, 2.0))
            * Affine3A::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7)
            * Affine3A::from_scale(Vec3::new(2.0, 1.0, 1.5));
        for filter in [Filter::Trilinear, Filter::Nearest] {
            let kind = VolumeKind::Grid {
                grid: grid.clone(),
                to_local: to_world.inverse(),
                filter,
            };
            let v = Volume::new(kind, to_world.inverse());
            let m = MajorantGrid::new(&v, 1.5);
            assert_eq!(m.res, UVec3::splat(4));
            let centre = 0.5 * (v.lo + v.hi);
            for _ in 0..300 {
                let dir =
                    Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
                let o = centre - dir * 4.0 + Vec3::new(rng.next(), rng.next(), rng.next()) - 0.5;
                let inv = dir.recip();
                let (a, b) = ((v.lo - o) * inv, (v.hi - o) * inv);
                let (t0, t1) = (a.min(b).max_element().max(0.0), a.max(b).min_element());
                if t0 >= t1 {
                    continue;
                }
                let mut end = t0;
                m.walk(o, dir, t0, t1, |ta, tb, mu| {
                    assert!((ta - end).abs() < 1e-4, "gap: {end} to {ta}");
                    end = tb;
                    for k in 0..8 {
                        let s = ta + (tb - ta) * (k as f32 + 0.5) / 8.0;
                        let x = o + dir * s;
                        let sigma = 1.5 * v.eval(x).max_element();
                        assert!(sigma <= mu * (1.0 + 1e-5), "{sigma} > {mu} at {x}");
                    }
                    true
                });
                assert!((end - t1).abs() < 1e-4, "ends at {end}, not {t1}");
            }
        }
    }
}
