//! Rays, ray-primitive intersection and robust ray offsets.
//!
//! Twin: `shaders/common/intersect.wgsl`.

use crate::scene::{Sphere, Triangle};
use glam::Vec3;

/// A ray `origin + t * dir` with `dir` of unit length.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// Relative size of the offset that moves a new ray's origin off the surface it starts on.
pub const OFFSET_SCALE: f32 = 3.0e-5;
/// Absolute floor of that offset (scene units), so points at the origin move too.
pub const OFFSET_FLOOR: f32 = 1.0e-5;

/// Moves `p` off its surface (geometric normal `n`) to the side that `dir` leaves towards.
/// The offset grows with |p| so it stays above float rounding from scale 1e-3 to 1e4.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let eps = OFFSET_SCALE * (p.abs().max_element() + OFFSET_FLOOR);
    if dir.dot(n) >= 0.0 {
        p + n * eps
    } else {
        p - n * eps
    }
}

/// Möller-Trumbore: `(t, u, v)` of the hit with `t` in (0, t_max), or `None`.
#[inline]
pub fn intersect_triangle(tri: &Triangle, ray: &Ray, t_max: f32) -> Option<(f32, f32, f32)> {
    let p = ray.dir.cross(tri.e2);
    let det = tri.e1.dot(p);
    if det.abs() < 1e-30 {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - tri.v0;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(tri.e1);
    let v = ray.dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = tri.e2.dot(q) * inv;
    (t > 0.0 && t < t_max).then_some((t, u, v))
}

/// Nearest `t` in (0, t_max) where the ray meets the sphere, or `None`. Uses the
/// numerically stable form of the discriminant (Ray Tracing Gems, ch. 7).
#[inline]
pub fn intersect_sphere(s: &Sphere, ray: &Ray, t_max: f32) -> Option<f32> {
    let oc = ray.origin - s.center;
    let b = oc.dot(ray.dir);
    let perp = oc - b * ray.dir;
    let disc = s.radius * s.radius - perp.dot(perp);
    if disc < 0.0 {
        return None;
    }
    let c = oc.dot(oc) - s.radius * s.radius;
    let sq = disc.sqrt();
    // q has the sign of -b; t0 = c / q, t1 = q are the two roots.
    let q = if b > 0.0 { -b - sq } else { -b + sq };
    let (mut t0, mut t1) = (c / q, q);
    if q == 0.0 {
        t0 = 0.0;
        t1 = 0.0;
    }
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0 > 0.0 && t0 < t_max {
        Some(t0)
    } else if t1 > 0.0 && t1 < t_max {
        Some(t1)
    } else {
        None
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    pub fn of_triangle(t: &Triangle) -> Self {
        let (a, b, c) = (t.v0, t.v0 + t.e1, t.v0 + t.e2);
        Aabb {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }
    pub fn of_sphere(s: &Sphere) -> Self {
        Aabb {
            min: s.center - Vec3::splat(s.radius),
            max: s.center + Vec3::splat(s.radius),
        }
    }
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
    /// Half the surface area (the SAH only needs ratios).
    pub fn half_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.max - self.min;
        d.x * d.y + d.y * d.z + d.z * d.x
    }
    /// Slab test: whether the ray enters the box before `t_max`.
    #[inline]
    pub fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> bool {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let tmin = t0.min(t1).max_element().max(0.0);
        let tmax = t0.max(t1).min_element().min(t_max);
        tmin <= tmax
    }
}
