//! Oracle test of a hit's surface on the device (src/bvh/intersect.wgsl and
//! src/bvh/shading_frame.wgsl) against src/math/geometry.rs and src/bvh/surface.rs, through
//! the probe `probe_hit`
//! (tests/probes/probe_geometry.wgsl, `gpu::probe_hit`) on scenes built by the scene builder and
//! uploaded as a render uploads them (pipelines specialised with their features):
//! `shading_normal` (smooth triangles, vertex normals that cancel at a point or point
//! against the face), `triangle_tangent` (flipped and degenerate uv mappings),
//! `vertex_tangent` (tangents that cancel at a point), `uv_tangent` (vertex tangents, the
//! corner uvs' fallback, triangles without uvs or tangents), `alpha_passes` (a masked
//! texture's alpha, a blend of a texture's luminance, a constant blend, an alpha-tested
//! sphere, an emitter whose alpha is ignored) and `facing` at the nearest hit (its normal
//! mapped, or bump mapped through `uv_jacobian`, `sphere_partials`, `texture_grad` and
//! `bump_mapped`), from both
//! sides, on a scene with vertex tangents, one with uvs but none, and a flat one; and each
//! ray's `offset_origin` and `pack_normal` (the two functions photon paths checked before).
//! Tolerances: `UNIT_ABS` on normals, `TANGENT_ULPS` on tangents, `SHADING_ABS` and
//! `MAPPED_ABS` on the hit's frame, `OFFSET_ULPS` and `PACK_STEPS`; booleans exactly (outside `ALPHA_MARGIN` of a decision).
//! Without a Vulkan adapter the test is skipped (CI fails instead, see common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::{Vec2, Vec3, Vec4};
use gpu_photon::bvh::{alpha_passes, alpha_test, uv_tangent, Bvh, SPHERE_BIT};
use gpu_photon::integrators::photon::pack_normal;
use gpu_photon::math::geometry::{
    offset_origin, shading_normal, triangle_tangent, vertex_tangent, Ray,
};
use gpu_photon::scene::{
    Alpha, AlphaMode, Material, Origin, Scene, SceneBuilder, Surface, FLAT, NO_TEXTURE,
};
use gpu_photon::settings::RenderSettings;
use gpu_photon::textures::{pack_rgba8, Encoding, SceneTexture, Texture};
use probes::hit::{HitCase, HitProbe};
use probes::light::SceneProbes;

/// Unit normals: the same normalisation of the same sum on both sides, a few roundings
/// (measured worst on lavapipe in the report line).
const UNIT_ABS: f32 = 2e-6;
/// Tangents: differences of products (`d1.y e1 - d0.y e2`, the barycentric sum), which the
/// device may contract into fused multiply-adds: within this many ulp of the sum of the
/// terms' magnitudes.
const TANGENT_ULPS: f32 = 8.0;
/// The hit's frame: the device's barycentrics differ from the host's by up to 1e-6
/// (tests/intersect_gpu.rs), which moves an interpolated normal by about that times the
/// spread of the vertex normals.
const SHADING_ABS: f32 = 1e-5;
/// A normal-mapped frame also reads the map at the hit's uv (bilinear: the texels' slope
/// times the uv's difference) and goes through `normal_mapped` (tests/intersect_gpu.rs holds
/// it to 1e-4).
const MAPPED_ABS: f32 = 1e-4;
/// The shading frame's tangent: `dp/du` made orthogonal to a shading normal that the device
/// gives within `SHADING_ABS`, normalised (a tangent short against the normal's component
/// magnifies that).
const TANGENT_ABS: f32 = 1e-4;
/// `offset_origin`: `p +- n eps` with the same `eps`, which the device may fuse into one
/// multiply-add: a rounding or two of the origin's largest coordinate.
const OFFSET_ULPS: f32 = 2.0;
/// `pack_normal`: each 16-bit half of the word may be one step apart (the octahedral
/// projection divides by the L1 norm, a rounding the device may do differently).
const PACK_STEPS: u32 = 1;
/// An alpha decision within this of its threshold (the opacity against a mask's cutoff or a
/// blend's uniform) is not compared: the opacity is read at a uv the device may round
/// differently (bilinear, so a uv difference of 1e-6 moves it by less than 1e-5 here).
const ALPHA_MARGIN: f32 = 1e-4;

fn at() -> Origin {
    Origin {
        file: "hit_gpu.rs".into(),
        line: 0,
        field: "scene".into(),
    }
}

/// A `w` x `h` raw 8-bit texture of pseudo-random texels.
fn texture(r: &mut TestRng, w: u32, h: u32) -> SceneTexture {
    let texels = (0..w * h)
        .map(|_| pack_rgba8([0, 0, 0, 0].map(|_: u8| (r.f32() * 255.0) as u8)))
        .collect();
    SceneTexture::Bitmap(Texture::from_rgba8("random", w, h, texels, Encoding::Raw).unwrap())
}

/// A wavy 3 x 3 patch of quads at height `z0` (6 triangles a row), with vertex normals
/// tilted from the face, uvs over [0, 1]^2 and per-corner tangents along u.
#[allow(clippy::type_complexity)]
fn patch(
    z0: f32,
    r: &mut TestRng,
) -> (
    Vec<[Vec3; 3]>,
    Vec<[Vec3; 3]>,
    Vec<[Vec2; 3]>,
    Vec<[Vec4; 3]>,
) {
    let p = |i: usize, j: usize| {
        let (x, y) = (i as f32 - 1.5, j as f32 - 1.5);
        Vec3::new(x, y, z0 + 0.2 * (x * 1.3).sin() * (y * 0.7).cos())
    };
    let uv = |i: usize, j: usize| Vec2::new(i as f32 / 3.0, j as f32 / 3.0);
    let (mut tris, mut normals, mut uvs, mut tangents) = (vec![], vec![], vec![], vec![]);
    for i in 0..3 {
        for j in 0..3 {
            for c in [[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]] {
                let k = c.map(|(a, b)| (i + a, j + b));
                tris.push(k.map(|(a, b)| p(a, b)));
                normals.push(k.map(|_| (Vec3::Z + 0.5 * r.dir()).normalize()));
                uvs.push(k.map(|(a, b)| uv(a, b)));
                let w = if r.f32() < 0.3 { -1.0 } else { 1.0 };
                tangents.push(k.map(|_| (Vec3::X + 0.3 * r.dir()).extend(w)));
            }
        }
    }
    (tris, normals, uvs, tangents)
}

/// The edge cases of the per-triangle functions, each one triangle at height `z`: vertex
/// normals that cancel at barycentrics (0.5, 0) and ones that point against the face;
/// tangents that cancel there; degenerate (one point, collinear) and flipped uvs.
#[allow(clippy::type_complexity)]
fn edge_cases(
    z: f32,
) -> (
    Vec<[Vec3; 3]>,
    Vec<[Vec3; 3]>,
    Vec<[Vec2; 3]>,
    Vec<[Vec4; 3]>,
) {
    let tri = |k: f32| {
        let o = Vec3::new(3.0 + 1.2 * k, -1.0, z);
        [o, o + Vec3::X, o + Vec3::Y]
    };
    let against = (-Vec3::Z + 0.5 * Vec3::X).normalize();
    let normals = [
        [Vec3::X, -Vec3::X, Vec3::Z],
        [against, -Vec3::Z, (-Vec3::Z + 0.5 * Vec3::Y).normalize()],
        [Vec3::Z, Vec3::X, Vec3::Y],
        [Vec3::Z, Vec3::Y, Vec3::X],
    ];
    let uvs = [
        [Vec2::splat(0.25); 3],
        [Vec2::ZERO, Vec2::new(0.5, 0.25), Vec2::new(1.0, 0.5)],
        [Vec2::ZERO, Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0)],
        [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)],
    ];
    let tangents = [
        [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(-1.0, 0.0, 0.0, 1.0),
            Vec4::Y,
        ],
        [Vec4::new(0.0, 1.0, 0.0, -1.0); 3],
        [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(-1.0, 0.0, 0.0, -1.0),
            Vec4::Z,
        ],
        [Vec4::new(0.0, 0.0, 0.0, 1.0); 3],
    ];
    (
        (0..4).map(|k| tri(k as f32)).collect(),
        normals.to_vec(),
        uvs.to_vec(),
        tangents.to_vec(),
    )
}

/// The scenes: `tangents` one with vertex tangents (and triangles with uvs but without
/// them), else one with uvs only; each with normal-mapped, alpha-tested, emissive and plain
/// surfaces, a flat floor without uvs and spheres. `flat`: only the floor and a sphere.
fn scene(kind: &str, r: &mut TestRng) -> Scene {
    let at = at();
    let mut b = SceneBuilder::new();
    b.camera(Vec3::new(0.0, -6.0, 4.0), Vec3::ZERO, Vec3::Z, 40.0, &at)
        .unwrap();
    let plain = b
        .add_material(None, Material::diffuse(Vec3::splat(0.5)), &at)
        .unwrap();
    let floor =
        [[-6.0, -6.0], [6.0, -6.0], [6.0, 6.0], [-6.0, 6.0]].map(|[x, y]| Vec3::new(x, y, -1.5));
    b.add_quad(floor, Surface::of(plain), &at).unwrap();
    b.add_sphere(Vec3::new(-3.5, 2.5, 0.0), 0.7, Surface::of(plain), &at)
        .unwrap();
    if kind == "flat" {
        return b.finish(&at).unwrap();
    }
    let normal_map = b.add_texture(texture(r, 5, 4), &at).unwrap();
    let alpha_map = b.add_texture(texture(r, 7, 3), &at).unwrap();
    let mapped = Material {
        normal_texture: normal_map,
        ..Material::diffuse(Vec3::splat(0.6))
    };
    let alpha = |mode, factor, texture, luminance| Material {
        alpha: Some(Alpha {
            mode,
            factor,
            texture,
            luminance,
        }),
        ..Material::diffuse(Vec3::splat(0.4))
    };
    let mapped = b.add_material(None, mapped, &at).unwrap();
    // The same texture as a bump map's heights (Mitsuba's bumpmap).
    let bumped = Material {
        normal_texture: normal_map,
        bump: Some(0.3),
        ..Material::diffuse(Vec3::splat(0.6))
    };
    let bumped = b.add_material(None, bumped, &at).unwrap();
    let mask = alpha(AlphaMode::Mask(0.5), 1.0, alpha_map, false);
    let mask = b.add_material(None, mask, &at).unwrap();
    let blend = alpha(AlphaMode::Blend, 0.9, alpha_map, true);
    let blend = b.add_material(None, blend, &at).unwrap();
    let constant = alpha(AlphaMode::Blend, 0.4, NO_TEXTURE, false);
    let constant = b.add_material(None, constant, &at).unwrap();
    let tangents = kind == "tangents";
    let add = |b: &mut SceneBuilder, m, mesh: (Vec<_>, Vec<_>, Vec<_>, Vec<_>)| {
        let (tris, normals, uvs, t) = mesh;
        let s = Surface::of(m);
        if tangents {
            b.add_tangent_mesh(tris, Some(normals), uvs, t, s, &at)
        } else {
            b.add_uv_mesh(tris, Some(normals), uvs, s, &at)
        }
        .unwrap()
    };
    add(&mut b, mapped, patch(0.0, r));
    add(&mut b, mask, patch(1.0, r));
    add(&mut b, blend, patch(2.0, r));
    add(&mut b, mapped, edge_cases(0.0));
    add(&mut b, bumped, patch(3.2, r));
    add(&mut b, bumped, edge_cases(-0.7));
    // Uvs but no tangents (zero tangents in a scene that has them).
    let (tris, normals, uvs, _) = patch(-0.8, r);
    b.add_uv_mesh(tris, Some(normals), uvs, Surface::of(mapped), &at)
        .unwrap();
    // Turned: its uv (the blend's alpha) and tangent are its object space's.
    let turned = glam::Quat::from_axis_angle(Vec3::new(0.3, -0.8, 0.5).normalize(), 1.1);
    b.add_oriented_sphere(
        Vec3::new(3.0, 2.5, 0.5),
        0.6,
        turned,
        Surface::of(blend),
        &at,
    )
    .unwrap();
    b.add_sphere(Vec3::new(-3.5, -2.5, 0.5), 0.6, Surface::of(constant), &at)
        .unwrap();
    b.add_sphere(Vec3::new(0.0, -3.5, 0.5), 0.6, Surface::of(bumped), &at)
        .unwrap();
    let lit = Surface {
        emission: Some(Vec3::ONE),
        ..Surface::of(mask)
    };
    let quad =
        [[3.0, -3.0], [4.0, -3.0], [4.0, -2.0], [3.0, -2.0]].map(|[x, y]| Vec3::new(x, y, 2.5));
    b.add_quad(quad, lit, &at).unwrap();
    b.finish(&at).unwrap()
}

/// Cases on every primitive: triangles at their corners, edge midpoints, centroid and
/// random barycentrics, spheres at random points; each seen from a random point on either
/// side.
fn cases(scene: &Scene, r: &mut TestRng) -> Vec<HitCase> {
    let mut out = Vec::new();
    let mut push = |p: Vec3, id: u32, bc: [f32; 2], ng: Vec3, r: &mut TestRng| {
        let o = p + r.dir() * r.range(0.5, 3.0);
        let d = (p - o).normalize();
        out.push(HitCase {
            origin: o.to_array(),
            dir: d.to_array(),
            t_max: 3.0e38,
            primitive: id,
            t: (p - o).length(),
            bc,
            ng: ng.to_array(),
        });
    };
    for (id, t) in scene.triangles.iter().enumerate() {
        let mut bcs = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [0.0, 0.5],
            [0.5, 0.5],
            [1.0 / 3.0, 1.0 / 3.0],
        ];
        for _ in 0..8 {
            let (u, v) = (r.f32(), r.f32());
            bcs.push(if u + v > 1.0 {
                [1.0 - u, 1.0 - v]
            } else {
                [u, v]
            });
        }
        for bc in bcs {
            push(t.point(bc[0], bc[1]), id as u32, bc, t.normal(), r);
        }
    }
    for (k, s) in scene.spheres.iter().enumerate() {
        for _ in 0..40 {
            let n = r.dir();
            push(
                s.center + s.radius * n,
                SPHERE_BIT | k as u32,
                [0.3, 0.3],
                n,
                r,
            );
        }
    }
    out
}

fn close(got: [f32; 3], want: Vec3, tol: f32) -> f32 {
    let e = (Vec3::from(got) - want).abs().max_element();
    assert!(e <= tol, "{got:?} vs {want} (error {e}, bound {tol})");
    e
}

/// A tangent from the device, `(xyz, w)`, against the host's `Some((t, flipped))` or `None`
/// (`none_w`: the device's `w` for none, where it has one), `scale` the magnitude of the
/// sum's terms; returns the error in ulp of `scale`.
fn tangent(
    what: &str,
    got: [f32; 4],
    want: Option<(Vec3, bool)>,
    none_w: Option<f32>,
    scale: f32,
) -> f32 {
    match want {
        None => {
            assert_eq!(Vec3::from_slice(&got), Vec3::ZERO, "{what}");
            assert!(none_w.is_none_or(|w| got[3] == w), "{what}: {got:?}");
            0.0
        }
        Some((t, flipped)) => {
            assert_eq!(got[3], flipped as u32 as f32, "{what}: flipped");
            let tol = TANGENT_ULPS * f32::EPSILON * scale;
            let e = (Vec3::from_slice(&got) - t).abs().max_element();
            assert!(e <= tol, "{what}: {got:?} vs {t} (error {e}, bound {tol})");
            e / (f32::EPSILON * scale)
        }
    }
}

/// How far the host's alpha decision is from its threshold (infinite when not alpha-tested).
fn alpha_margin(scene: &Scene, id: u32, ray: &Ray, t: f32, [u, v]: [f32; 2]) -> f32 {
    match alpha_test(scene, id, ray, t, u, v) {
        None => f32::INFINITY,
        Some((a, opacity, r)) => match a.mode {
            AlphaMode::Mask(cutoff) => (opacity - cutoff).abs(),
            AlphaMode::Blend => (r - opacity).abs(),
        },
    }
}

/// Compares every case of `scene`; returns the report's counts and worst errors.
fn check(kind: &str, scene: &Scene, cases: &[HitCase], got: &[HitProbe]) -> String {
    let bvh = Bvh::build(scene);
    let (mut smooth, mut passes, mut near, mut frames, mut worst) = (0, [0, 0], 0, 0, [0f32; 5]);
    let mut fallbacks = [0; 3];
    let (mut packed_exact, mut bumped) = (0, 0);
    for (i, (c, g)) in cases.iter().zip(got).enumerate() {
        let ctx = format!("{kind} case {i} {c:?}");
        let ray = Ray {
            origin: Vec3::from(c.origin),
            dir: Vec3::from(c.dir),
        };
        let [u, v] = c.bc;
        let id = c.primitive;
        if id & SPHERE_BIT == 0 {
            let tri = &scene.triangles[id as usize];
            let ng = Vec3::from(c.ng);
            match (g.shading, tri.shading) {
                (None, FLAT) => {}
                (Some(s), k) if k != FLAT => {
                    let n = &scene.shading_normals[k as usize];
                    let want = shading_normal(ng, n, u, v);
                    let sum = (1.0 - u - v) * n[0] + u * n[1] + v * n[2];
                    fallbacks[0] += (sum == Vec3::ZERO) as usize;
                    worst[0] = worst[0].max(close(s, want, UNIT_ABS));
                    smooth += 1;
                }
                (s, k) => panic!("{ctx}: shading {s:?}, host's triangle {k}"),
            }
            let (e1, e2) = (tri.e1(), tri.e2());
            match (g.triangle_tangent, scene.uvs.get(id as usize)) {
                (Some(t), Some(uvs)) => {
                    let want = triangle_tangent(e1, e2, uvs);
                    let (d0, d1) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
                    let scale =
                        d1.y.abs() * e1.abs().max_element() + d0.y.abs() * e2.abs().max_element();
                    tangent(
                        &format!("{ctx}: triangle_tangent"),
                        t,
                        want,
                        Some(-1.0),
                        scale,
                    );
                    fallbacks[1] += want.is_none() as usize;
                }
                (t, uvs) => assert!(t.is_none() && uvs.is_none(), "{ctx}: {t:?} {uvs:?}"),
            }
            match (g.vertex_tangent, scene.tangents.get(id as usize)) {
                (Some(t), Some(ts)) => {
                    let want = vertex_tangent(ts, u, v);
                    let scale = ts.iter().map(|t| t.truncate().abs().max_element()).sum();
                    let e = tangent(&format!("{ctx}: vertex_tangent"), t, want, None, scale);
                    worst[3] = worst[3].max(e);
                    fallbacks[2] += want.is_none() as usize;
                }
                (t, ts) => assert!(t.is_none() && ts.is_none(), "{ctx}: {t:?} {ts:?}"),
            }
            if let Some(t) = g.uv_tangent {
                let want = uv_tangent(scene, id, u, v);
                let ts = scene.tangents.get(id as usize);
                let from_vertices = ts.is_some_and(|ts| vertex_tangent(ts, u, v).is_some());
                let scale = match (from_vertices, ts) {
                    (true, Some(ts)) => ts.iter().map(|t| t.truncate().abs().max_element()).sum(),
                    _ => 2.0 * e1.abs().max_element().max(e2.abs().max_element()),
                };
                let e = tangent(&format!("{ctx}: uv_tangent"), t, want, Some(-1.0), scale);
                worst[3] = worst[3].max(e);
            } else {
                assert!(scene.uvs.is_empty(), "{ctx}: no uv_tangent");
            }
        }
        // A ray's offset origin (off the knife edge of its side test) and packed direction.
        let ng = Vec3::from(c.ng);
        if ray.dir.dot(ng).abs() > 1e-6 {
            let want = offset_origin(ray.origin, ng, ray.dir);
            let tol = OFFSET_ULPS * f32::EPSILON * ray.origin.abs().max_element();
            close(g.offset, want, tol);
        }
        let want = pack_normal(ray.dir);
        let halves = |w: u32| [w & 0xffff, w >> 16];
        let (a, b) = (halves(g.packed), halves(want));
        assert!(
            (0..2).all(|k| a[k].abs_diff(b[k]) <= PACK_STEPS),
            "{ctx}: pack_normal {:#x} vs {want:#x}",
            g.packed
        );
        packed_exact += (g.packed == want) as usize;
        if alpha_margin(scene, id, &ray, c.t, c.bc) > ALPHA_MARGIN {
            let want = alpha_passes(scene, id, &ray, c.t, u, v);
            assert_eq!(g.passes, want, "{ctx}: alpha_passes");
            passes[want as usize] += 1;
        } else {
            near += 1;
        }
        // The frame at the nearest hit, where the ray does not graze a corner or an edge
        // (two primitives at one t: either may be the nearest).
        let interior = id & SPHERE_BIT != 0 || u.min(v).min(1.0 - u - v) > 0.02;
        let hit = bvh.intersect(scene, &ray, c.t_max);
        if !interior || ray.dir.dot(hit.map_or(Vec3::Z, |h| h.normal)).abs() < 1e-3 {
            continue;
        }
        assert_eq!(g.material, hit.map(|h| h.material), "{ctx}: nearest hit");
        let Some(h) = hit else { continue };
        let f = h.facing(ray.dir);
        let (ng, ns, interpolated) = g.facing;
        assert_eq!(interpolated, f.interpolated, "{ctx}: facing.interpolated");
        close(ng, f.ng, UNIT_ABS);
        let m = &scene.materials[h.material as usize];
        let mapped = m.normal_texture != NO_TEXTURE;
        bumped += m.bump.is_some() as usize;
        let e = close(ns, f.ns, if mapped { MAPPED_ABS } else { SHADING_ABS });
        worst[1 + mapped as usize] = worst[1 + mapped as usize].max(e);
        // The shading frame's tangent (Mitsuba's sh_frame.s, before the normal map): dp/du,
        // the first edge without uvs or the normal's basis for a degenerate mapping, made
        // orthogonal to the shading normal.
        let e = close(g.tangent, h.tangent, TANGENT_ABS);
        worst[4] = worst[4].max(e);
        frames += 1;
    }
    let report = format!(
        "{kind}: {} cases, {smooth} smooth ({} vanish: ng), {} degenerate uv maps, {} \
         vanishing vertex tangents, alpha passes {} / stops {} ({near} near the threshold \
         skipped), {frames} frames ({bumped} bump-mapped); worst shading normal {:e}, frame ns \
         {:e} (normal- or bump-mapped {:e}), tangents {} ulp, frame tangents {:e}, {packed_exact} packed directions bit \
         for bit",
        cases.len(),
        fallbacks[0],
        fallbacks[1],
        fallbacks[2],
        passes[1],
        passes[0],
        worst[0],
        worst[1],
        worst[2],
        worst[3],
        worst[4]
    );
    assert!(
        kind == "flat" || bumped > 50,
        "{kind}: {bumped} bump-mapped frames"
    );
    report
}

#[test]
fn device_hit_surfaces_equal_the_hosts() {
    let Some(ctx) = gpu() else { return };
    let mut r = TestRng(0x4117);
    let mut report = Vec::new();
    for kind in ["tangents", "uvs", "flat"] {
        let scene = scene(kind, &mut r);
        assert_eq!(scene.tangents.is_empty(), kind != "tangents");
        let cases = cases(&scene, &mut r);
        let mut probes = SceneProbes::new(&ctx, &scene, &RenderSettings::default()).unwrap();
        let got = probes.hits(&cases).unwrap();
        report.push(check(kind, &scene, &cases, &got));
    }
    eprintln!("{}", report.join("\n"));
}
