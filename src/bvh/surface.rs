//! What a hit is: the surface the BVH walk found (its point, normals, material, light and
//! texture coordinates), the frame a ray sees there, and the two per-hit tests the walk
//! itself makes or needs: whether an alpha-tested surface lets the ray pass, and a
//! triangle's uv tangent for its normal map.
//!
//! Twins: `alpha_passes` and `trace_ray`'s hit (its tangent included) in
//! `src/bvh/intersect.wgsl`, `facing` and `uv_tangent` in `src/bvh/shading_frame.wgsl`.

use crate::bvh::hit::Hit;
use crate::bvh::SPHERE_BIT;
use crate::math::geometry::{
    bump_mapped, bump_tangent, inset, normal_mapped, shading_normal, shading_tangent,
    sphere_partials, triangle_tangent, uv_jacobian, vertex_tangent, Ray,
};
use crate::math::rng::{pcg_hash, to_unit};
use crate::scene::{Alpha, Scene, FLAT, NO_TEXTURE};
use glam::{Vec2, Vec3};

/// The hit on primitive `id` of `scene` at distance `t` along `ray` (a triangle's
/// barycentrics `u`, `v`: the weights of `v1`, `v2`), as the walk found it.
pub(crate) fn hit_at(scene: &Scene, ray: &Ray, id: u32, t: f32, u: f32, v: f32) -> Hit {
    let hit = geometric_hit(scene, ray, id, t, u, v);
    let tangent = tangent_at(scene, id, u, v, hit.normal);
    let fallback = tangent_fallback(scene, id, hit.normal);
    let partials = || uv_partials(scene, id, hit.normal);
    shading_frame(scene, hit, ray.dir, tangent, fallback, partials)
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
            tangent: Vec3::ZERO,
        }
    } else {
        let s = &scene.spheres[(id & !SPHERE_BIT) as usize];
        let p = ray.origin + t * ray.dir;
        let n = (p - s.center).normalize_or_zero();
        let uv = if scene.textures.is_empty() {
            Vec2::ZERO
        } else {
            s.uv(n)
        };
        Hit {
            t,
            position: s.center + n * s.radius,
            normal: n,
            shading: n,
            material: s.material,
            light: s.light,
            uv,
            tangent: Vec3::ZERO,
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
        let s = &geometry.spheres[(id & !SPHERE_BIT) as usize];
        (s.tangent(normal), false)
    }
}

/// Without a uv tangent at primitive `id` of `geometry` (geometric normal `normal`),
/// Mitsuba's: a triangle's first edge in a scene without uvs, the geometric normal's basis for
/// a degenerate mapping; none on a sphere's poles.
pub(crate) fn tangent_fallback(geometry: &Scene, id: u32, normal: Vec3) -> Vec3 {
    match id & SPHERE_BIT {
        0 if geometry.uvs.is_empty() => geometry.triangles[id as usize].e1(),
        0 => crate::math::sampling::basis(normal).0,
        _ => Vec3::ZERO,
    }
}

/// Mitsuba's uv partials `(dp_du, dp_dv)` of primitive `id` of `geometry` (geometric normal
/// `normal`), as its `bumpmap` reads them: a triangle's corner uvs' Jacobian (zero for a
/// degenerate mapping), its edges without uvs; a sphere's parameterisation
/// ([`sphere_partials`]) in its object frame, turned to the world.
pub(crate) fn uv_partials(geometry: &Scene, id: u32, normal: Vec3) -> (Vec3, Vec3) {
    if id & SPHERE_BIT == 0 {
        let tri = &geometry.triangles[id as usize];
        match geometry.uvs.get(id as usize) {
            Some(c) => uv_jacobian(tri.e1(), tri.e2(), c),
            None => (tri.e1(), tri.e2()),
        }
    } else {
        // In the sphere's object space, where Mitsuba's parameterisation is defined.
        let s = &geometry.spheres[(id & !SPHERE_BIT) as usize];
        let (du, dv) = sphere_partials(s.local(normal), s.radius);
        (s.world(du), s.world(dv))
    }
}

/// `hit` with its shading frame: the tangent from the uv tangent `tangent` (dp/du and whether
/// its frame is flipped) or `fallback` made orthogonal to the shading normal, then the shading
/// normal perturbed by its material's normal map or bump map, if it has one; `dir` the ray's,
/// `partials` the hit's uv partials (read by a bump map only).
pub(crate) fn shading_frame(
    scene: &Scene,
    mut hit: Hit,
    dir: Vec3,
    (dp_du, flipped): (Vec3, bool),
    fallback: Vec3,
    partials: impl FnOnce() -> (Vec3, Vec3),
) -> Hit {
    hit.tangent = shading_tangent(hit.shading, dp_du, fallback);
    let m = &scene.materials[hit.material as usize];
    if m.normal_texture != NO_TEXTURE {
        let texture = &scene.textures[m.normal_texture as usize];
        hit.shading = match m.bump {
            None => {
                let c = texture.eval(hit.uv);
                normal_mapped(hit.normal, hit.shading, dp_du, flipped, c, dir)
            }
            Some(scale) => {
                let (pu, pv) = partials();
                let grad = scale * texture.eval_grad(hit.uv);
                let n = bump_mapped(hit.normal, hit.shading, pu, pv, grad, dir);
                hit.tangent = bump_tangent(hit.shading, hit.tangent, pu, n);
                n
            }
        };
    }
    hit
}

/// The uv tangent of triangle `id` of `scene` at barycentrics `(1 - u - v, u, v)` and
/// whether its frame is flipped, as a normal map reads it: the triangle's vertex tangents'
/// ([`vertex_tangent`], flipped by their `w`) where it has them and they do not vanish there,
/// else its corner uvs' ([`triangle_tangent`], never flipped, as in Mitsuba 3.9.1); `None`
/// without uvs or for a degenerate mapping (the normal map then takes the shading normal's
/// basis). Twin: `uv_tangent` in
/// `src/bvh/shading_frame.wgsl`.
pub fn uv_tangent(scene: &Scene, id: u32, u: f32, v: f32) -> Option<(Vec3, bool)> {
    let tri = &scene.triangles[id as usize];
    (scene.tangents.get(id as usize))
        .and_then(|t| vertex_tangent(t, u, v))
        .or_else(|| {
            // Mitsuba 3.9.1's frame from corner uvs is never flipped (`initialize_sh_frame`:
            // t = n x s), which the suite's normal-mapped references follow.
            let uvs = scene.uvs.get(id as usize);
            let t = uvs.and_then(|c| triangle_tangent(tri.e1(), tri.e2(), c));
            t.map(|(t, _)| (t, false))
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
        (s.material, s.uv(n))
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
