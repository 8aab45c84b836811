//! Mitsuba 3's `sdfgrid` shape (3.9.1, `src/shapes/sdfgrid.cpp`): a signed distance
//! function sampled on the vertices of a grid spanning the unit cube of its object space,
//! read from a one-channel `.vol` file (`crate::media::grid`'s format: `res` values per axis,
//! x fastest, so `res - 1` cells per axis). Between the vertices it is trilinear; the surface
//! is its zero set.
//!
//! As Mitsuba: the cells whose eight corners are neither all positive nor all negative are
//! its primitives, each bounded by its tight box (Hansson-Söderlund and Akenine-Möller 2023:
//! the corners at zero and the zero crossings of the edges); a ray is intersected with a
//! cell by the cubic its trilinear function is along the ray (Hansson-Söderlund, Evans and
//! Akenine-Möller 2022), solved as Marmitt et al. 2004 (the derivative's roots split the
//! segment, then regula falsi to 1e-5); the geometric normal is the trilinear gradient of
//! the cell that holds the point, the shading normal (`normals` `smooth`, the default) the
//! gradients of the eight cells around the nearest vertex, normalised and blended
//! trilinearly; texture coordinates are zero. It is never a light. Mitsuba's 3.9.1 mixes the
//! axes of a grid whose resolutions differ (it reads the tensor's z extent as x's); the
//! grids here are read per axis, which is the same for the cubic grids its scenes use.

use crate::math::geometry::Aabb;
use crate::media::grid::{Filter, VolumeGrid};
use glam::{Affine3A, IVec3, Mat3, UVec3, Vec3};
use std::sync::Arc;

/// One occupied cell: its integer corner and its tight box in object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdfCell {
    /// The cell's lowest vertex (x, y, z).
    pub corner: UVec3,
    /// The box around the surface in the cell (object space).
    pub bounds: Aabb,
}

/// A grid's values and its occupied cells, shared by every placement of it.
#[derive(Clone, Debug, PartialEq)]
pub struct SdfData {
    /// The values at the vertices (one channel).
    pub grid: VolumeGrid,
    /// The cells the surface passes through, in x-fastest order.
    pub cells: Vec<SdfCell>,
}

/// An `sdfgrid` placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct SdfGrid {
    /// The grid and its cells.
    pub data: Arc<SdfData>,
    /// Object (the unit cube) to world.
    pub to_world: Affine3A,
    /// World to object.
    pub to_object: Affine3A,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// Mitsuba's `normals`: `smooth` (true) or `analytic`.
    pub smooth: bool,
}

impl SdfData {
    /// The grid of `grid` (one channel, at least 2 values per axis) and its occupied cells;
    /// an error message when it has none or the wrong shape.
    pub fn new(grid: VolumeGrid) -> Result<Self, String> {
        if grid.channels != 1 {
            return Err(format!("{} channels, an sdfgrid has 1", grid.channels));
        }
        if grid.res.iter().any(|&r| r < 2) {
            let [x, y, z] = grid.res;
            return Err(format!(
                "{x}x{y}x{z} values: an sdfgrid needs 2 or more per axis"
            ));
        }
        let mut data = SdfData {
            grid,
            cells: Vec::new(),
        };
        let [rx, ry, rz] = data.grid.res;
        for z in 0..rz - 1 {
            for y in 0..ry - 1 {
                for x in 0..rx - 1 {
                    let corner = UVec3::new(x, y, z);
                    if let Some(bounds) = data.tight_box(corner) {
                        data.cells.push(SdfCell { corner, bounds });
                    }
                }
            }
        }
        if data.cells.is_empty() {
            return Err("no cell holds a surface (every value has the same sign)".into());
        }
        Ok(data)
    }

    /// The value at vertex `v` (in range).
    fn value(&self, v: UVec3) -> f32 {
        let [rx, ry, _] = self.grid.res;
        self.grid.data[((v.z * ry + v.y) * rx + v.x) as usize]
    }

    /// The eight corner values of the cell at `c`, corner `i` at `c + (i & 1, i >> 1 & 1,
    /// i >> 2 & 1)`.
    pub fn corners(&self, c: UVec3) -> [f32; 8] {
        std::array::from_fn(|i| {
            let i = i as u32;
            self.value(c + UVec3::new(i & 1, (i >> 1) & 1, (i >> 2) & 1))
        })
    }

    /// Vertices per axis minus one: the cells per axis, as floats.
    fn cells_per_axis(&self) -> Vec3 {
        UVec3::from(self.grid.res).as_vec3() - 1.0
    }

    /// The size of a cell in object space.
    fn cell_size(&self) -> Vec3 {
        self.cells_per_axis().recip()
    }

    /// Mitsuba's `compute_tight_bbox`: `None` for a cell without surface, else the box (in
    /// object space) of its corners at zero and its edges' zero crossings.
    fn tight_box(&self, c: UVec3) -> Option<Aabb> {
        let f = self.corners(c);
        if f.iter().all(|&v| v > 0.0) || f.iter().all(|&v| v < 0.0) {
            return None;
        }
        let pos = |i: usize| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2 & 1) as f32);
        let zero = |i: usize| f[i] == 0.0;
        // A side is at the cell's face where a corner on that face is zero, else collapsed
        // to the far face (to grow from the crossings below).
        let mut lo = Vec3::ONE;
        let mut hi = Vec3::ZERO;
        for i in 0..8 {
            if zero(i) {
                let p = pos(i);
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        for a in 0..8usize {
            for axis in 0..3 {
                if a & (1 << axis) != 0 {
                    continue;
                }
                let b = a | (1 << axis);
                if f[a] * f[b] <= 0.0 && f[a] != f[b] {
                    let p = pos(a) + f[a] / (f[a] - f[b]) * (pos(b) - pos(a));
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            }
        }
        let h = self.cell_size();
        let c = c.as_vec3();
        Some(Aabb {
            min: (lo + c) * h,
            max: (hi + c) * h,
        })
    }

    /// The trilinear value at `p` of the unit cube, as Mitsuba's texture lookup gives it
    /// (`rescale_point`, then drjit's linear filter, indices clamped to the grid).
    pub fn value_at(&self, p: Vec3) -> f32 {
        let res = UVec3::from(self.grid.res).as_vec3();
        let inv = res.recip();
        let q = p * (1.0 - inv) + inv / 2.0;
        self.grid.lookup(q, Filter::Trilinear).x
    }

    /// Mitsuba's `voxel_grad`: the gradient at `p` of the trilinear function of cell `v`
    /// (differences across the cell through `p`, in object units).
    pub fn cell_gradient(&self, p: Vec3, v: IVec3) -> Vec3 {
        let h = self.cell_size();
        let p0 = v.as_vec3() * h;
        let diff = |axis: usize| {
            let (mut hi, mut lo) = (p, p);
            hi[axis] = p0[axis] + h[axis];
            lo[axis] = p0[axis];
            (self.value_at(hi) - self.value_at(lo)) / h[axis]
        };
        Vec3::new(diff(0), diff(1), diff(2))
    }

    /// Mitsuba's `sdf_grad`: the gradient at `p` of the cell that holds it (object space).
    pub fn gradient(&self, p: Vec3) -> Vec3 {
        // Mitsuba's Point3i(p * resolution): truncation towards zero.
        let v = (p * self.cells_per_axis()).as_ivec3();
        self.cell_gradient(p, v)
    }

    /// Mitsuba's `smooth_sh`: the unit gradients of the eight cells around the vertex nearest
    /// `p` (those at a negative index left out), blended trilinearly by `p`'s place between
    /// their centres (object space, not normalised).
    pub fn smooth_normal(&self, p: Vec3) -> Vec3 {
        let scaled = p * self.cells_per_axis();
        let v000 = scaled.round().as_ivec3() - IVec3::ONE;
        let corner = |i: i32| v000 + IVec3::new(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        let valid: [bool; 8] = std::array::from_fn(|i| corner(i as i32).cmpge(IVec3::ZERO).all());
        let n: [Vec3; 8] = std::array::from_fn(|i| {
            if valid[i] {
                self.cell_gradient(p, corner(i as i32)).normalize()
            } else {
                Vec3::ZERO
            }
        });
        let mut w = scaled - (v000 + IVec3::ONE).as_vec3() + 0.5;
        // An axis along which every cell on one side is left out takes the other side.
        let none =
            |bit: i32, side: i32| (0..8).all(|i| (i >> bit) & 1 != side || !valid[i as usize]);
        for axis in 0..3 {
            if none(axis as i32, 0) {
                w[axis] = 1.0;
            }
            if none(axis as i32, 1) {
                w[axis] = 0.0;
            }
        }
        let (u, v, t) = (w.x, w.y, w.z);
        (1.0 - t) * ((1.0 - v) * ((1.0 - u) * n[0] + u * n[1]) + v * ((1.0 - u) * n[2] + u * n[3]))
            + t * ((1.0 - v) * ((1.0 - u) * n[4] + u * n[5]) + v * ((1.0 - u) * n[6] + u * n[7]))
    }

    /// Mitsuba's cell intersection: the first zero of the trilinear function of `cell` along
    /// the object-space ray `origin + t dir` (`dir` need not be unit) with `0 <= t <=
    /// t_max`, or `None`.
    pub fn intersect_cell(
        &self,
        cell: &SdfCell,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
    ) -> Option<f32> {
        let h = self.cell_size();
        let c = cell.corner.as_vec3();
        let (t_beg, t_end) = slab(c * h, (c + 1.0) * h, origin, dir)?;
        let t_beg = t_beg.max(0.0);
        if t_beg >= t_end {
            return None;
        }
        // The ray in the cell's unit cube.
        let scale = self.cells_per_axis();
        let o = (origin + t_beg * dir) * scale - c;
        let d = dir * scale;
        let s = self.corners(cell.corner);
        let (s000, s100, s010, s110) = (s[0], s[1], s[2], s[3]);
        let (s001, s101, s011, s111) = (s[4], s[5], s[6], s[7]);
        let a = s101 - s001;
        let k0 = s000;
        let k1 = s100 - s000;
        let k2 = s010 - s000;
        let k3 = s110 - s010 - k1;
        let k4 = k0 - s001;
        let k5 = k1 - a;
        let k6 = k2 - (s011 - s001);
        let k7 = k3 - (s111 - s011 - a);
        let m0 = o.x * o.y;
        let m1 = d.x * d.y;
        let m2 = o.x * d.y + o.y * d.x;
        let m3 = k5 * o.z - k1;
        let m4 = k6 * o.z - k2;
        let m5 = k7 * o.z - k3;
        let c0 = (k4 * o.z - k0) + (o.x * m3 + (o.y * m4 + m0 * m5));
        let c1 = (d.x * m3 + d.y * m4) + m2 * m5 + d.z * (k4 + (k5 * o.x + (k6 * o.y + k7 * m0)));
        let c2 = m1 * m5 + d.z * (k5 * d.x + (k6 * d.y + k7 * m2));
        let c3 = k7 * m1 * d.z;
        let t = solve_cubic(0.0, t_end - t_beg, [c0, c1, c2, c3])?;
        let t = t_beg + t;
        (t >= 0.0 && t <= t_max).then_some(t)
    }
}

/// Mitsuba's `BoundingBox::ray_intersect`: the entry and exit distances of the ray through
/// the box `lo..hi`, `None` when it misses.
fn slab(lo: Vec3, hi: Vec3, o: Vec3, d: Vec3) -> Option<(f32, f32)> {
    let inside = o.cmpgt(lo) | o.cmplt(hi);
    if !(d.cmpne(Vec3::ZERO) | inside).all() {
        return None;
    }
    let rcp = d.recip();
    let (t1, t2) = ((lo - o) * rcp, (hi - o) * rcp);
    let (near, far) = (t1.min(t2).max_element(), t1.max(t2).min_element());
    (far >= near).then_some((near, far))
}

/// Mitsuba's `math::solve_quadratic`: whether `a x^2 + b x + c` has real roots, and
/// them in order (a linear equation's twice).
fn solve_quadratic(a: f32, b: f32, c: f32) -> (bool, f32, f32) {
    let linear = a == 0.0;
    let valid_linear = linear && b != 0.0;
    let mut x0 = -c / b;
    let mut x1 = x0;
    let discrim = b * b - 4.0 * a * c;
    let valid_quadratic = !linear && discrim >= 0.0;
    if valid_quadratic {
        let temp = -0.5 * (b + discrim.sqrt().copysign(b));
        let (p, q) = (temp / a, c / temp);
        (x0, x1) = (p.min(q), p.max(q));
    }
    (valid_linear || valid_quadratic, x0, x1)
}

/// The regula falsi's steps at most (Mitsuba's `sdf_solve_cubic`; the WGSL twin's too).
pub const CUBIC_STEPS: u32 = 51;
/// The bracket's width at which it stops.
pub const CUBIC_TOLERANCE: f32 = 1e-5;

/// Mitsuba's `sdf_solve_cubic`: the first zero in `t_beg..t_end` of minus the cubic of
/// coefficients `c` (constant first), bracketed between the derivative's roots and refined
/// by regula falsi to 1e-5 (at most 51 steps).
fn solve_cubic(t_beg: f32, t_end: f32, c: [f32; 4]) -> Option<f32> {
    let [c0, c1, c2, c3] = c;
    let f = |t: f32| -(((c3 * t + c2) * t + c1) * t + c0);
    let (has_roots, r0, r1) = solve_quadratic(3.0 * c3, 2.0 * c2, c1);
    let (mut near, mut far) = (t_beg, t_end);
    if has_roots && near <= r0 && r0 <= far {
        if f(t_beg) * f(r0) <= 0.0 {
            far = r0;
        } else {
            near = r0;
        }
    }
    if has_roots && near <= r1 && r1 <= far {
        if f(near) * f(r1) <= 0.0 {
            far = r1;
        } else {
            near = r1;
        }
    }
    let (mut f_near, mut f_far) = (f(near), f(far));
    if f_near * f_far > 0.0 || (f_near * f_far).is_nan() {
        return None;
    }
    let mut t = 0.0;
    for _ in 0..CUBIC_STEPS {
        t = near + (far - near) * (-f_near / (f_far - f_near));
        let f_t = f(t);
        if f_t * f_near <= 0.0 {
            (far, f_far) = (t, f_t);
        } else if f_t * f_near > 0.0 {
            (near, f_near) = (t, f_t);
        }
        if (near - far).abs() < CUBIC_TOLERANCE {
            break;
        }
    }
    Some(t)
}

impl SdfGrid {
    /// `data` placed by `to_world` (affine and invertible: the caller checks), of `material`.
    pub fn new(data: Arc<SdfData>, to_world: Affine3A, material: u32, smooth: bool) -> Self {
        SdfGrid {
            data,
            to_world,
            to_object: to_world.inverse(),
            material,
            smooth,
        }
    }

    /// The same grid placed by `m` after its own `to_world` (an instance's placement).
    pub fn placed(&self, m: Affine3A) -> Self {
        Self::new(
            self.data.clone(),
            m * self.to_world,
            self.material,
            self.smooth,
        )
    }

    /// The matrix normals are carried to the world by (the inverse transpose).
    fn normal_matrix(&self) -> Mat3 {
        Mat3::from(self.to_object.matrix3).transpose()
    }

    /// The world box around occupied cell `i`.
    pub fn cell_world_box(&self, i: usize) -> Aabb {
        let b = self.data.cells[i].bounds;
        let corner = |k: usize| {
            let pick = |axis: usize| {
                if k >> axis & 1 == 0 {
                    b.min[axis]
                } else {
                    b.max[axis]
                }
            };
            Vec3::new(pick(0), pick(1), pick(2))
        };
        (0..8).fold(Aabb::EMPTY, |a, k| {
            a.grow(self.to_world.transform_point3(corner(k)))
        })
    }

    /// The world box around every occupied cell.
    pub fn world_box(&self) -> Aabb {
        (0..self.data.cells.len()).fold(Aabb::EMPTY, |a, i| a.union(self.cell_world_box(i)))
    }

    /// The distance along the world ray `origin + t dir` to the surface in occupied cell `i`
    /// (tested against its tight box first, as Embree does), up to `t_max`.
    pub fn intersect_cell(&self, i: usize, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
        let o = self.to_object.transform_point3(origin);
        let d = self.to_object.transform_vector3(dir);
        let cell = &self.data.cells[i];
        let b = cell.bounds;
        if !b.hit(o, d.recip(), t_max) {
            return None;
        }
        self.data.intersect_cell(cell, o, d, t_max)
    }

    /// The surface at world point `p` found by a ray: the point (carried to the object
    /// space and back, as Mitsuba does), the unit geometric normal and the unit shading
    /// normal (world space).
    pub fn surface_at(&self, p: Vec3) -> (Vec3, Vec3, Vec3) {
        let local = self.to_object.transform_point3(p);
        let nm = self.normal_matrix();
        let normal = (nm * self.data.gradient(local)).normalize_or_zero();
        let shading = if self.smooth {
            (nm * self.data.smooth_normal(local)).normalize_or_zero()
        } else {
            normal
        };
        (self.to_world.transform_point3(local), normal, shading)
    }

    /// An estimate of the surface's area in the world (it sizes photon search radii only): a
    /// plane crosses 3/2 cells per cell face of area on average over its orientations.
    pub fn area_estimate(&self) -> f32 {
        let h = self.data.cell_size();
        let cell_volume = h.x * h.y * h.z * self.to_world.matrix3.determinant().abs();
        let side = cell_volume.cbrt();
        self.data.cells.len() as f32 * side * side / 1.5
    }
}
