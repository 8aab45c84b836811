//! What a hit is: the surface the BVH walk found (its point, normals, material, light and
//! texture coordinates), the frame a ray sees there, and the two per-hit tests the walk
//! itself makes or needs: whether an alpha-tested surface lets the ray pass, and a
//! triangle's uv tangent for its normal map.
//!
//! Twins: `facing`, `alpha_passes`, `uv_tangent` and `trace_ray`'s hit in
//! `src/bvh/intersect.wgsl`.

use crate::bvh::hit::Hit;
use crate::bvh::SPHERE_BIT;
use crate::math::geometry::{
    inset, normal_mapped, shading_normal, sphere_tangent, triangle_tangent, vertex_tangent, Ray,
};
use crate::math::rng::{pcg_hash, to_unit};
use crate::scene::{Alpha, Scene, FLAT, NO_TEXTURE};
use glam::{Vec2, Vec3};

/// The hit on primitive `id` of `scene` at distance `t` along `ray` (a triangle's
/// barycentrics `u`, `v`: the weights of `v1`, `v2`), as the walk found it.
pub(crate) fn hit_at(scene: &Scene, ray: &Ray, id: u32, t: f32, u: f32, v: f32) -> Hit {
    let hit = geometric_hit(scene, ray, id, t, u, v);
    normal_map(scene, hit, ray.dir, || {
        tangent_at(scene, id, u, v, hit.normal)
    })
}

/// The hit on primitive `id` of `geometry` before any normal map: its point, normals,
/// material, light and uv (a sphere's uv only where `geometry` has textures).
pub(crate) fn geometric_hit(geometry: &Scene, ray: &Ray, id: u32, t: f32, u: f32, v: f32) -> Hit {
    let scene = geometry;
    if id & SPHERE_BIT == 0 {
        let tri = &scene.triangles[id as usize];
        let normal = tri.normal();
        let shading = match tri.shading {
            FLAT => normal,
            i => shading_normal(normal, &scene.shading_normals[i as usize], u, v),
        };
        let uv = match scene.uvs.get(id as usize) {
            Some(c) => (1.0 - u - v) * c[0] + u * c[1] + v * c[2],
            None => Vec2::ZERO,
        };
        Hit {
            t,
            // Barycentric position (closer to the plane than origin + t dir), inset
            // from the edges.
            position: inset(tri, tri.point(u, v)),
            normal,
            shading,
            material: tri.material,
            light: tri.light,
            uv,
        }
    } else {
        let s = &scene.spheres[(id & !SPHERE_BIT) as usize];
        let p = ray.origin + t * ray.dir;
        let n = (p - s.center).normalize_or_zero();
        let uv = if scene.textures.is_empty() {
            Vec2::ZERO
        } else {
            crate::textures::uv::sphere(n)
        };
        Hit {
            t,
            position: s.center + n * s.radius,
            normal: n,
            shading: n,
            material: s.material,
            light: s.light,
            uv,
        }
    }
}

/// The uv tangent a normal map reads at primitive `id` of `geometry` (geometric normal
/// `normal`) and whether its frame is flipped: a triangle's vertex tangents where it has them,
/// else its corner uvs' (none without uvs); a sphere's from Mitsuba's parameterisation.
pub(crate) fn tangent_at(geometry: &Scene, id: u32, u: f32, v: f32, normal: Vec3) -> (Vec3, bool) {
    if id & SPHERE_BIT == 0 {
        uv_tangent(geometry, id, u, v).unwrap_or((Vec3::ZERO, false))
    } else {
        (sphere_tangent(normal), false)
    }
}

/// `hit` with its shading normal perturbed by its material's normal map, if it has one
/// (`tangent`: the uv tangent there and whether its frame is flipped); `dir` the ray's.
pub(crate) fn normal_map(
    scene: &Scene,
    mut hit: Hit,
    dir: Vec3,
    tangent: impl FnOnce() -> (Vec3, bool),
) -> Hit {
    let normal_texture = scene.materials[hit.material as usize].normal_texture;
    if normal_texture != NO_TEXTURE {
        let (dp_du, flipped) = tangent();
        let c = scene.textures[normal_texture as usize].eval(hit.uv);
        hit.shading = normal_mapped(hit.normal, hit.shading, dp_du, flipped, c, dir);
    }
    hit
}

/// The uv tangent of triangle `id` of `scene` at barycentrics `(1 - u - v, u, v)` and
/// whether its frame is flipped, as a normal map reads it: the triangle's vertex tangents'
/// ([`vertex_tangent`]) where it has them and they do not vanish there, else its corner
/// uvs' ([`triangle_tangent`]); `None` without uvs or for a degenerate mapping (the normal
/// map then takes the shading normal's basis). Twin: `uv_tangent` in
/// `src/bvh/intersect.wgsl`.
pub fn uv_tangent(scene: &Scene, id: u32, u: f32, v: f32) -> Option<(Vec3, bool)> {
    let tri = &scene.triangles[id as usize];
    (scene.tangents.get(id as usize))
        .and_then(|t| vertex_tangent(t, u, v))
        .or_else(|| {
            let uvs = scene.uvs.get(id as usize);
            uvs.and_then(|c| triangle_tangent(tri.e1(), tri.e2(), c))
        })
}

/// The alpha test of primitive `id` hit at `t` along `ray` (a triangle's barycentrics `u`,
/// `v`): its material's [`Alpha`], the opacity there and the uniform a blend compares it
/// with (hashed from the primitive, `t` and the ray's direction, so the same ray always
/// makes the same choice); `None` for an opaque or emissive material.
pub fn alpha_test(
    scene: &Scene,
    id: u32,
    ray: &Ray,
    t: f32,
    u: f32,
    v: f32,
) -> Option<(Alpha, f32, f32)> {
    let (material, uv) = if id & SPHERE_BIT == 0 {
        let uv = match scene.uvs.get(id as usize) {
            Some(c) => (1.0 - u - v) * c[0] + u * c[1] + v * c[2],
            None => Vec2::ZERO,
        };
        (scene.triangles[id as usize].material, uv)
    } else {
        let s = &scene.spheres[(id & !SPHERE_BIT) as usize];
        let n = (ray.origin + t * ray.dir - s.center).normalize_or_zero();
        (s.material, crate::textures::uv::sphere(n))
    };
    let m = &scene.materials[material as usize];
    let alpha = m.alpha.filter(|_| !m.is_emissive())?;
    let mut key = pcg_hash(id ^ t.to_bits());
    for c in ray.dir.to_array() {
        key = pcg_hash(key ^ c.to_bits());
    }
    Some((alpha, alpha.opacity(&scene.textures, uv), to_unit(key)))
}

/// Whether `ray` passes primitive `id`, hit at `t` (a triangle's barycentrics `u`, `v`):
/// its material is alpha-tested, not emissive, and its opacity there does not stop the ray
/// ([`alpha_test`]). Twin: `alpha_passes` in `src/bvh/intersect.wgsl`.
pub fn alpha_passes(scene: &Scene, id: u32, ray: &Ray, t: f32, u: f32, v: f32) -> bool {
    alpha_test(scene, id, ray, t, u, v).is_some_and(|(a, opacity, r)| !a.stops(opacity, r))
}
