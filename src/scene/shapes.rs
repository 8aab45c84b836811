//! The primitives a scene is made of: triangles (with their vertex normals and tangents) and
//! analytic spheres, below everything that intersects or shades them.

use glam::{Quat, Vec2, Vec3, Vec4};

/// A world-space triangle `v0, v1, v2`; front normal = normalize(cross(e1, e2)) with
/// `e1 = v1 - v0`, `e2 = v2 - v0`. The vertices are kept as given (not as edges) so that two
/// triangles sharing an edge share its end points bit for bit: the watertight intersection
/// test (src/math/geometry.rs) relies on that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub v0: Vec3,
    /// Second vertex.
    pub v1: Vec3,
    /// Third vertex.
    pub v2: Vec3,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// Index into `Scene::lights` when the triangle is emissive, else [`NO_LIGHT`].
    pub light: u32,
    /// Index into `Scene::shading_normals` of its vertex normals (smooth shading), or
    /// [`FLAT`].
    pub shading: u32,
}

impl Triangle {
    /// The triangle `a, b, c` of `material`, flat-shaded, not a light.
    pub fn new(a: Vec3, b: Vec3, c: Vec3, material: u32) -> Self {
        Self {
            v0: a,
            v1: b,
            v2: c,
            material,
            light: NO_LIGHT,
            shading: FLAT,
        }
    }
    /// The edge `v1 - v0`.
    pub fn e1(&self) -> Vec3 {
        self.v1 - self.v0
    }
    /// The edge `v2 - v0`.
    pub fn e2(&self) -> Vec3 {
        self.v2 - self.v0
    }
    /// Its area.
    pub fn area(&self) -> f32 {
        0.5 * self.e1().cross(self.e2()).length()
    }
    /// Unit front normal (zero for a degenerate triangle).
    pub fn normal(&self) -> Vec3 {
        self.e1().cross(self.e2()).normalize_or_zero()
    }
    /// The point with barycentric coordinates `(1 - u - v, u, v)`.
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        self.v0 + u * self.e1() + v * self.e2()
    }
}

/// An analytic sphere with outward normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (> 0).
    pub radius: f32,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// Index into `Scene::lights` when the sphere is emissive, else [`NO_LIGHT`].
    pub light: u32,
    /// The rotation from the sphere's object space, where Mitsuba's parameterisation (its uv
    /// and dp/du) is defined, to the world: the identity unless a Mitsuba `to_world` rotates
    /// it. Held at its GPU record's precision ([`Sphere::quantized_frame`]).
    pub frame: Quat,
}

impl Sphere {
    /// World direction `v` in the sphere's object space (its frame's inverse rotation).
    pub fn local(&self, v: Vec3) -> Vec3 {
        rotate(-self.frame.xyz(), self.frame.w, v)
    }
    /// Mitsuba's uv at the outward unit normal `n` (world): its parameterisation in the
    /// sphere's object space. Twin: `sphere_uv(sphere_local(s, n))` in
    /// `src/bvh/intersect.wgsl`.
    pub fn uv(&self, n: Vec3) -> Vec2 {
        crate::textures::uv::sphere(self.local(n))
    }
    /// The direction of Mitsuba's dp/du at the outward unit normal `n` (world): towards
    /// increasing azimuth about the object's z axis; zero at its poles.
    pub fn tangent(&self, n: Vec3) -> Vec3 {
        // Mitsuba's dp/du at the object's direction l, up to its scale (as
        // `math::geometry::sphere_tangent`, which imports this module).
        let l = self.local(n);
        self.world(Vec3::new(-l.y, l.x, 0.0))
    }
    /// Direction `v` of the sphere's object space in the world (its frame's rotation).
    pub fn world(&self, v: Vec3) -> Vec3 {
        rotate(self.frame.xyz(), self.frame.w, v)
    }
    /// `q` (a unit quaternion) rounded to four snorm16 (the GPU record's
    /// [`Sphere::frame_words`]), read back as the device does and normalised.
    pub fn quantized_frame(q: Quat) -> Quat {
        let w = frame_words(q);
        let half = |x: u32| f32::from(x as u16 as i16) / 32767.0;
        let c = |x: u32| half(x).max(-1.0);
        Quat::from_xyzw(c(w[0]), c(w[0] >> 16), c(w[1]), c(w[1] >> 16)).normalize()
    }
    /// The frame as the GPU record holds it: x, y then z, w as snorm16 pairs (WGSL's
    /// `pack2x16snorm`).
    pub fn frame_words(&self) -> [u32; 2] {
        frame_words(self.frame)
    }
}

/// `q`'s components as two words of two snorm16 each.
fn frame_words(q: Quat) -> [u32; 2] {
    let s = |x: f32| ((x.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    [s(q.x) | (s(q.y) << 16), s(q.z) | (s(q.w) << 16)]
}

/// `v` rotated by the unit quaternion `(u, w)`: `v + 2 u x (u x v + w v)` (the same
/// arithmetic as `sphere_rotate` in `src/bvh/intersect.wgsl`; exact for the identity).
fn rotate(u: Vec3, w: f32, v: Vec3) -> Vec3 {
    v + 2.0 * u.cross(u.cross(v) + w * v)
}

/// Marks a primitive that is not a light.
pub const NO_LIGHT: u32 = u32::MAX;

/// Marks a flat-shaded triangle ([`Triangle::shading`]): its shading normal is its
/// geometric normal.
pub const FLAT: u32 = u32::MAX;

/// The unit vertex normals of one smooth-shaded triangle, world space, at `v0, v1, v2`;
/// the shading normal at barycentric `(1 - u - v, u, v)` is their normalised interpolation
/// (see `geometry::shading_normal`).
pub type VertexNormals = [Vec3; 3];

/// The vertex tangents of one normal-mapped triangle, world space, at `v0, v1, v2` (glTF's
/// `TANGENT` or MikkTSpace's, `scene::tangents`). `xyz`: the tangent, along increasing u
/// (any length; zero: none, the triangle's own uv tangent is used). `w`: -1 where the
/// frame's second axis `n x t` is negated to point along increasing v (Mitsuba's
/// `FaceUVFlipped`), +1 otherwise: the axis along which a normal map's green is read. At
/// barycentric `(1 - u - v, u, v)` the frame interpolates them (`geometry::vertex_tangent`).
pub type VertexTangents = [Vec4; 3];
