//! A ray-surface intersection as the walks return it: below the scene and the BSDFs, which
//! read it (its twin is `Hit` in `src/bvh/intersect.wgsl`).

use crate::math::geometry::Facing;
use glam::{Vec2, Vec3};

/// A ray-surface intersection.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// The hit point.
    pub position: Vec3,
    /// Unit geometric front normal of the primitive (not flipped towards the ray).
    pub normal: Vec3,
    /// Unit shading normal, on the side of `normal`: the interpolated vertex normals of a
    /// smooth triangle, else `normal` itself; then perturbed by the material's normal map
    /// when it has one (`crate::math::geometry::normal_mapped`).
    pub shading: Vec3,
    /// Index of the primitive's material in `Scene::materials`.
    pub material: u32,
    /// Index of the primitive's light in `Scene::lights`, or `scene::NO_LIGHT`.
    pub light: u32,
    /// Texture coordinates: a triangle's interpolated corner uvs (`Scene::uvs`), a sphere's
    /// Mitsuba parameterisation; zero when the scene has no textures.
    pub uv: Vec2,
    /// Unit tangent of the shading frame before any normal map (Mitsuba's `sh_frame.s`): the
    /// surface's `dp/du` made orthogonal to the unperturbed shading normal (a triangle's uv
    /// tangent, or its first edge without uvs; a sphere's azimuth direction); zero where it
    /// vanishes. A bump map's frame has its own (`crate::math::geometry::bump_tangent`). The BSDF's frame is `crate::bsdfs::interface::Frame::new(shading, tangent)`.
    pub tangent: Vec3,
}

impl Hit {
    /// The normals turned towards a ray along `d` that arrives from the front when
    /// `d . normal < 0` (see [`Facing`]).
    #[inline]
    pub fn facing(&self, d: Vec3) -> Facing {
        Facing::new(self.normal, self.shading, d.dot(self.normal) < 0.0)
    }
}
