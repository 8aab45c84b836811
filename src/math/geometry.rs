//! Rays, ray-primitive intersection and robust ray offsets.
//!
//! Twins: `src/bvh/intersect.wgsl`, and `src/bvh/shading_frame.wgsl` for the shading frame
//! (`shading_normal` to `bump_tangent`, `Facing` and its leak tests).

use crate::scene::shapes::{Sphere, Triangle, VertexNormals};
use glam::{Vec2, Vec3};

/// 1 + 2 gamma(3), gamma(n) = n u / (1 - n u) with u = 2^-24: the relative error bound of
/// the slab test's exit distance.
pub const BOX_SLACK: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON / 2.0) / (1.0 - 3.0 * f32::EPSILON / 2.0);

/// A ray `origin + t * dir` with `dir` of unit length.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Unit direction.
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

/// Moves a point of triangle `tri` towards the triangle's centroid by the ray-offset distance
/// (at most half way). A hit on an edge or vertex (or rounded just past it) would otherwise
/// start its next ray on the plane of the face that meets it there, which then cannot stop
/// it (a hit needs t > 0): light would leak out of closed corners.
#[inline]
pub fn inset(tri: &Triangle, p: Vec3) -> Vec3 {
    let to_c = (tri.v0 + tri.v1 + tri.v2) / 3.0 - p;
    let len = to_c.length();
    if len == 0.0 {
        return p;
    }
    let eps = OFFSET_SCALE * (p.abs().max_element() + OFFSET_FLOOR);
    p + to_c * (eps / len).min(0.5)
}

/// The shading normal at barycentric `(1 - u - v, u, v)` of a smooth triangle with unit
/// geometric normal `ng` and vertex normals `n`: their normalised interpolation, negated
/// when it points against `ng` (vertex normals wound the other way round), and `ng` itself
/// where the interpolation vanishes. Twin: `shading_normal` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn shading_normal(ng: Vec3, n: &VertexNormals, u: f32, v: f32) -> Vec3 {
    let ns = ((1.0 - u - v) * n[0] + u * n[1] + v * n[2]).normalize_or_zero();
    if ns == Vec3::ZERO {
        ng
    } else if ns.dot(ng) < 0.0 {
        -ns
    } else {
        ns
    }
}

/// The tangent of a triangle's uv parameterisation (Mitsuba's `dp_du` up to its positive
/// scale `1 / |det|`, the sign included) and whether the parameterisation is flipped
/// (`det < 0` for the corner uvs' determinant, Mitsuba's `FaceUVFlipped`); `None` for a
/// degenerate mapping (`det == 0`). `e1`, `e2`: the edges from corner 0 to corners 1 and 2.
/// Twin: `triangle_tangent` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn triangle_tangent(e1: Vec3, e2: Vec3, uv: &[Vec2; 3]) -> Option<(Vec3, bool)> {
    let (d0, d1) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d0.x * d1.y - d0.y * d1.x;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let dp_du = (d1.y * e1 - d0.y * e2) * det.signum();
    Some((dp_du, det < 0.0))
}

/// A triangle's uv partials `(dp_du, dp_dv)` (Mitsuba's, from its corner uvs `uv`; both zero
/// for a degenerate mapping, as Mitsuba's `inv_det` is). `e1`, `e2`: the edges from corner 0
/// to corners 1 and 2. Twin: `uv_jacobian` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn uv_jacobian(e1: Vec3, e2: Vec3, uv: &[Vec2; 3]) -> (Vec3, Vec3) {
    let (d0, d1) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d0.x * d1.y - d0.y * d1.x;
    let inv = if det != 0.0 { 1.0 / det } else { 0.0 };
    ((d1.y * e1 - d0.y * e2) * inv, (d0.x * e2 - d1.x * e1) * inv)
}

/// The uv tangent at barycentric `(1 - u - v, u, v)` of a triangle with vertex tangents
/// ([`crate::scene::shapes::VertexTangents`]): the interpolated tangent and whether the frame is
/// flipped (the interpolated `w` is negative), as [`triangle_tangent`] gives them; `None`
/// where the interpolated tangent vanishes. Twin: `vertex_tangent` in
/// `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn vertex_tangent(
    t: &crate::scene::shapes::VertexTangents,
    u: f32,
    v: f32,
) -> Option<(Vec3, bool)> {
    let m = (1.0 - u - v) * t[0] + u * t[1] + v * t[2];
    let dir = m.truncate();
    (dir != Vec3::ZERO && dir.is_finite()).then_some((dir, m.w < 0.0))
}

/// `tangent` made orthogonal to unit `n` and normalised (Gram-Schmidt), or `None` where that
/// vanishes or is not finite. Twin: `orthogonal_tangent` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn orthogonal_tangent(n: Vec3, tangent: Vec3) -> Option<Vec3> {
    let s = tangent - n * n.dot(tangent);
    let l2 = s.length_squared();
    (l2 > 0.0 && l2.is_finite()).then(|| s / l2.sqrt())
}

/// The unit tangent of a hit's shading frame (Mitsuba 3.9.1's `sh_frame.s`, from
/// `initialize_sh_frame`) at unit shading normal `ns`: the surface's uv tangent `dp_du`, or
/// `fallback` where that is zero, made orthogonal to `ns` and normalised; zero where that
/// vanishes. Twin: `shading_tangent` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn shading_tangent(ns: Vec3, dp_du: Vec3, fallback: Vec3) -> Vec3 {
    let t = if dp_du == Vec3::ZERO { fallback } else { dp_du };
    orthogonal_tangent(ns, t).unwrap_or(Vec3::ZERO)
}

/// The tangent of Mitsuba's sphere parameterisation at outward unit normal `n` (`dp_du` up
/// to its positive scale, `(-y, x, 0)`: towards increasing azimuth); zero at the poles.
#[inline]
pub fn sphere_tangent(n: Vec3) -> Vec3 {
    Vec3::new(-n.y, n.x, 0.0)
}

/// The uv partials `(dp_du, dp_dv)` of Mitsuba's sphere parameterisation at outward unit
/// normal `n` of a sphere of radius `r`: `2 pi r` times [`sphere_tangent`] and `pi r` times
/// the polar direction `(z cos phi, z sin phi, -sin theta)`, `pi r x` at the poles. Twin:
/// `sphere_partials` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn sphere_partials(n: Vec3, r: f32) -> (Vec3, Vec3) {
    let rd = (n.x * n.x + n.y * n.y).sqrt();
    let polar = if rd == 0.0 {
        Vec3::X
    } else {
        Vec3::new(n.z * (n.x / rd), n.z * (n.y / rd), -rd)
    };
    let pi = std::f32::consts::PI;
    (2.0 * pi * r * sphere_tangent(n), pi * r * polar)
}

/// Mitsuba 3's `normalmap` (src/bsdfs/normalmap.cpp, with `flip_invalid_normals`): the
/// shading normal that texel `c` (linear rgb) gives at a hit with front normal `ng`, unit
/// shading normal `ns` (on the side of `ng`), uv tangent `dp_du` (zero when the hit has no
/// usable parameterisation), `flipped` parameterisation, for a ray along unit `d`.
///
/// The frame is Mitsuba's `sh_frame` after `finalize_surface_interaction`: `s` is `dp_du`
/// made orthogonal to `ns` and normalised, `t = ns x s`, negated when `flipped`; where `s`
/// vanishes (degenerate uvs, a mesh without uvs, a sphere's poles) `(s, t)` is the
/// orthonormal basis `crate::math::sampling::basis(ns)` (Mitsuba's `coordinate_system`, the same
/// construction). The texel's normal is `m = 2 c - 1` in that frame; when the incident
/// direction `wi = -d` has `(wi . ns) (wi . m) <= 0`, `m` becomes `(-m.x, -m.y, m.z)`. The
/// result is normalised and, like [`shading_normal`], turned to the side of `ng` (and `ns`
/// itself where it vanishes). Twin: `normal_mapped` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn normal_mapped(ng: Vec3, ns: Vec3, dp_du: Vec3, flipped: bool, c: Vec3, d: Vec3) -> Vec3 {
    let s = dp_du - ns * ns.dot(dp_du);
    let (s, t) = if s.length_squared() > 0.0 && s.is_finite() {
        let s = s.normalize();
        let t = ns.cross(s);
        (s, if flipped { -t } else { t })
    } else {
        crate::math::sampling::basis(ns)
    };
    let m = 2.0 * c - Vec3::ONE;
    let wi = -d;
    let world = |m: Vec3| s * m.x + t * m.y + ns * m.z;
    let m = if wi.dot(ns) * wi.dot(world(m)) <= 0.0 {
        Vec3::new(-m.x, -m.y, m.z)
    } else {
        m
    };
    let n = world(m).normalize_or_zero();
    if n == Vec3::ZERO {
        ns
    } else if n.dot(ng) < 0.0 {
        -n
    } else {
        n
    }
}

/// Mitsuba 3's `bumpmap` (src/bsdfs/bumpmap.cpp, with `flip_invalid_normals`): the shading
/// normal that the height gradient `grad` (the texture's `eval_1_grad` times `scale`) gives at
/// a hit with front normal `ng`, unit shading normal `ns` (on the side of `ng`), uv partials
/// `dp_du`, `dp_dv` (Mitsuba's, scale included), for a ray along unit `d`.
///
/// The partials are made tangent to `ns` and lifted by the gradient (`dp_du + ns (grad.x -
/// ns . dp_du)`, likewise for v); their normalised cross product, turned to the side of `ng`,
/// is the bumped normal. When the incident direction `wi = -d` has `(wi . ns) (wi . n) <= 0`,
/// `n` is reflected about `ns` (Mitsuba's `(-n.x, -n.y, n.z)` in the shading frame). Like
/// [`normal_mapped`], the result is on the side of `ng`, and `ns` where the cross product
/// vanishes against the partials' lengths (degenerate uvs; Mitsuba's is noise or NaN there). Twin: `bump_mapped` in `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn bump_mapped(ng: Vec3, ns: Vec3, dp_du: Vec3, dp_dv: Vec3, grad: Vec2, d: Vec3) -> Vec3 {
    let du = dp_du + ns * (grad.x - ns.dot(dp_du));
    let dv = dp_dv + ns * (grad.y - ns.dot(dp_dv));
    let c = du.cross(dv);
    // Partials that vanish or are parallel (a degenerate mapping) leave rounding noise.
    let crossed = c.length_squared() > 1e-12 * du.length_squared() * dv.length_squared();
    if !crossed {
        return ns;
    }
    let n = c.normalize();
    let n = if n.dot(ng) < 0.0 { -n } else { n };
    let wi = -d;
    let n = if wi.dot(ns) * wi.dot(n) <= 0.0 {
        2.0 * ns.dot(n) * ns - n
    } else {
        n
    };
    let n = n.normalize_or_zero();
    if n == Vec3::ZERO {
        ns
    } else if n.dot(ng) < 0.0 {
        -n
    } else {
        n
    }
}

/// The tangent of Mitsuba 3.9.1's bumped frame (`bumpmap.cpp`'s `frame`): with `n` the bumped
/// normal [`bump_mapped`] gave, written in the unperturbed shading frame (unit normal `ns`,
/// unit tangent `s` orthogonal to it, or zero for the basis `crate::math::sampling::basis(ns)`
/// as the BSDF frame takes it; `t = ns x s`) as `n'`, Mitsuba orthogonalises the world `dp_du` *as if it
/// were local* against `n'` (`s' = normalize(dp_du - n' (n' . dp_du))`); `s'` taken back to
/// world space is the tangent here. Only a nested anisotropic BSDF sees it (an isotropic one
/// reads the normal alone); `s` itself where `s'` vanishes. Twin: `bump_tangent` in
/// `src/bvh/shading_frame.wgsl`.
#[inline]
pub fn bump_tangent(ns: Vec3, s: Vec3, dp_du: Vec3, n: Vec3) -> Vec3 {
    let s = if s == Vec3::ZERO {
        crate::math::sampling::basis(ns).0
    } else {
        s
    };
    let t = ns.cross(s);
    let local = Vec3::new(n.dot(s), n.dot(t), n.dot(ns));
    match orthogonal_tangent(local, dp_du) {
        Some(l) => s * l.x + t * l.y + ns * l.z,
        None => s,
    }
}

/// The facing frame of a hit for a ray travelling along `d`: the geometric normal `ng` and
/// the shading normal `ns` turned to the side the ray arrives from (`d . ng < 0` keeps them),
/// and whether the shading normal differs from the geometric one (a smooth triangle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facing {
    /// Geometric normal on the ray's side: sidedness, ray offsets, light leaks.
    pub ng: Vec3,
    /// Shading normal on the same side as `ng`: BSDF evaluation and sampling.
    pub ns: Vec3,
    /// `ns != ng`: only then can a direction be on opposite sides of the two.
    pub interpolated: bool,
}

impl Facing {
    /// The frame for front normal `ng`, shading normal `ns` (same side as `ng`), a ray along
    /// `d`; `front` chooses the side: `d . ng < 0` (or `<= 0`, as the caller's rule is).
    #[inline]
    pub fn new(ng: Vec3, ns: Vec3, front: bool) -> Self {
        let s = if front { 1.0 } else { -1.0 };
        Facing {
            ng: s * ng,
            ns: s * ns,
            interpolated: ns != ng,
        }
    }
    /// Whether `dir`, leaving the surface on the ray's side (a reflection), lies below the
    /// geometric surface: on a smooth triangle it carries nothing (no light leaks through the
    /// terminator). Always false on a flat surface, whose callers test the same cosine.
    #[inline]
    pub fn reflection_leaks(&self, dir: Vec3) -> bool {
        self.interpolated && dir.dot(self.ng) <= 0.0
    }
    /// Whether `dir`, meant to cross the surface (a refraction), stays on the ray's side of
    /// the geometric surface; always false on a flat surface.
    #[inline]
    pub fn refraction_leaks(&self, dir: Vec3) -> bool {
        self.interpolated && dir.dot(self.ng) >= 0.0
    }
}

/// Per-ray constants of the watertight ray-triangle test (Woop, Benthin and Wald, "Watertight
/// Ray/Triangle Intersection", JCGT 2013): the axis `kz` where the direction is largest, and
/// the shear that maps the ray onto the z axis (only its x and y parts are needed here).
#[derive(Clone, Copy, Debug)]
pub struct Shear {
    kx: usize,
    ky: usize,
    kz: usize,
    s: Vec2,
}

impl Shear {
    /// The shear and axis permutation that map `dir` onto +z.
    pub fn new(dir: Vec3) -> Self {
        let a = dir.abs();
        let kz = if a.x > a.y && a.x > a.z {
            0
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        Shear {
            kx,
            ky,
            kz,
            s: Vec2::new(dir[kx] / dir[kz], dir[ky] / dir[kz]),
        }
    }

    /// The axes `[kx, ky, kz]` (`kz` where the direction is largest) and the shear
    /// `(d[kx] / d[kz], d[ky] / d[kz])`, for tests that project many vertices at once.
    pub fn axes(&self) -> ([usize; 3], Vec2) {
        ([self.kx, self.ky, self.kz], self.s)
    }

    /// A vertex relative to the ray's origin, projected along the ray (sheared x and y).
    #[inline]
    fn project(&self, v: Vec3, origin: Vec3) -> Vec2 {
        let p = v - origin;
        Vec2::new(
            p[self.kx] - self.s.x * p[self.kz],
            p[self.ky] - self.s.y * p[self.kz],
        )
    }
}

/// `p.x q.y - p.y q.x`. The two triangles sharing an edge get exactly opposite values (one
/// of them sees a point on the edge as inside, whatever the rounding): Rust never fuses a
/// multiply and an add, products commute exactly and rounding is symmetric, so
/// `edge_function(q, p) == -edge_function(p, q)` up to the sign of a zero (which no test
/// reads). The WGSL twin orders the end points canonically instead: a shader compiler may
/// fuse.
#[inline]
pub fn edge_function(p: Vec2, q: Vec2) -> f32 {
    p.x * q.y - p.y * q.x
}

/// Watertight ray-triangle test: `(t, u, v)` of the hit with `t` in (0, t_max), where `u` and
/// `v` weight `v1` and `v2`, or `None`. A ray through a shared edge or vertex hits at least
/// one of the triangles that share it; a degenerate triangle is never hit.
#[inline]
pub fn intersect_triangle(
    tri: &Triangle,
    ray: &Ray,
    shear: &Shear,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    let a = shear.project(tri.v0, ray.origin);
    let b = shear.project(tri.v1, ray.origin);
    let c = shear.project(tri.v2, ray.origin);
    let e0 = edge_function(c, b);
    let e1 = edge_function(a, c);
    let e2 = edge_function(b, a);
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    // The distance from the plane equation in world space, not from the sheared frame: a ray
    // starting on the plane gets t = 0 exactly wherever the plane is axis-aligned.
    let n = tri.e1().cross(tri.e2());
    let t = (tri.v0 - ray.origin).dot(n) / ray.dir.dot(n);
    (t > 0.0 && t < t_max).then(|| (t, e1 / det, e2 / det))
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
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (the identity of `union` and `grow`).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    /// The bounds of a triangle.
    pub fn of_triangle(t: &Triangle) -> Self {
        let (a, b, c) = (t.v0, t.v1, t.v2);
        Aabb {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }
    /// The bounds of a sphere.
    pub fn of_sphere(s: &Sphere) -> Self {
        Aabb {
            min: s.center - Vec3::splat(s.radius),
            max: s.center + Vec3::splat(s.radius),
        }
    }
    /// The smallest box holding both boxes.
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    /// The smallest box holding this box and point `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    /// The box's centre.
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    /// Whether the box holds no point.
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
    /// Slab test: whether the ray enters the box before `t_max`. The exit distance is
    /// widened by [`BOX_SLACK`] so that rounding never rejects a ray that grazes the box
    /// (pbrt-v4's robust bounds test), e.g. along an edge of a flat box.
    #[inline]
    pub fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> bool {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let tmin = t0.min(t1).max_element().max(0.0);
        let tmax = (t0.max(t1).min_element() * BOX_SLACK).min(t_max);
        tmin <= tmax
    }
}
