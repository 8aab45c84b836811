//! Oracle test of the shading interface on the device (src/bsdfs/shading.wgsl) against
//! src/bsdfs/shading.rs, through the probe `probe_shading` (tests/probes/probe_shading.wgsl,
//! `gpu::probe_shading`) on a scene built by the scene builder and uploaded as a render
//! uploads it: a sphere of every material kind (the classic ones, crate::bsdf's, a textured
//! Lambertian, plastic and glTF material, an anisotropic normal-mapped conductor, emitters
//! one- and two-sided with a texture) and a
//! floor cell of each on smooth triangles (shading normals off the face: the leak tests),
//! under a lat-long environment. Each ray's nearest hit on the device is read back and
//! shaded on both sides from the same bits: `bsdf_at` and every `surface_*` question (class, flags,
//! emission, store weight, diffuse albedo, value and estimate BRDF, the lobe's value and
//! density, a lobe sample and a delta bounce from the same random stream, a photon's bounce),
//! `power_heuristic` and `escape`. Classes, flags and bounce kinds are compared exactly (a
//! sampled decision only where it does not flip under a nudge of the ray or the uniforms,
//! `NUDGE`), values within `TOL` relative to `max(|value|, FLOOR)`, sampled directions
//! within `DIR_ABS`, sampled weights and densities within `TOL` or `GRAZING_ABS` over the
//! cosine. Without a Vulkan adapter the test is skipped (CI fails instead, see
//! common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::{Mat3, Vec2, Vec3};
use gpu_photon::bsdfs::interface::Bounce;
use gpu_photon::bsdfs::shading::{
    bsdf_at, escape, power_heuristic, DeltaEvent, SurfaceBsdf, SurfaceClass,
};
use gpu_photon::bsdfs::{
    Bsdf, BsdfKind, Channel, Distribution, MetallicRoughness, Microfacet, Param, Plastic,
};
use gpu_photon::integrators::gpu::codes::{
    class_code, BOUNCE_ABSORB, BOUNCE_DELTA, BOUNCE_DIFFUSE, BOUNCE_LOBE,
};
use gpu_photon::math::geometry::offset_origin;
use gpu_photon::math::rng::{path_key, Rng, Stream};
use gpu_photon::scene::{Material, MaterialId, Origin, Scene, SceneBuilder, Surface};
use gpu_photon::settings::RenderSettings;
use gpu_photon::textures::{pack_rgba8, Encoding, SceneTexture, Texture};
use probes::light::SceneProbes;
use probes::shading::{ShadedSurface, ShadingCase, SHADING_FLAGS};
use std::collections::BTreeMap;

/// Seed of the cases (and of the random streams the lobe sample and delta bounce draw).
const SEED: u64 = 0x5ad1;
/// Cases.
const CASES: usize = 3000;
/// Relative tolerance of a value (set from the measured worst case in the report line).
const TOL: f32 = 1e-4;
/// The environment's radiance along an escaping ray: a bilinear lat-long lookup at
/// `atan2` and `acos` of the direction, which lavapipe computes to a few 1e-6 (not a few
/// ulp), times the random map's steep slope (texel steps up to 1 over 1/8 of u).
const ENV_TOL: f32 = 1e-3;
/// Values are compared relative to at least this magnitude.
const FLOOR: f32 = 1e-3;
/// Sampled and bounced directions, and a delta bounce's new origin (relative to its
/// largest coordinate): crate::bsdf's samplers, which tests/bsdf_gpu.rs holds to 1e-4 (a
/// Beckmann visible normal comes from a Newton inversion through erf and erfinv and differs
/// by up to 2e-5; 1.4e-5 measured here).
const DIR_ABS: f32 = 1e-4;
/// A sampled weight or density is `f cos / pdf` or `pdf` at a drawn direction, which the
/// two sides give a few 1e-6 apart (up to 2e-5 for a Beckmann sample, see `DIR_ABS`): near
/// grazing, where the cosine is that small, the relative error is that over the cosine.
/// Held to `TOL.max(GRAZING_ABS / cos)`, cos the smaller of the ray's and the sample's
/// cosines with the shading normal.
const GRAZING_ABS: f32 = 2e-5;
/// A sampled decision (ok, the bounce's kind, reflect or refract, a leak) is compared only
/// where the host decides the same for the ray nudged by this (radians, two axes) and the
/// uniforms nudged by this: the device's few-ulp differences cannot flip it.
const NUDGE: f32 = 1e-4;

/// The floor's corner (x, y least) and height, and its cells' edge.
const FLOOR_MIN: Vec3 = Vec3::new(-3.0, -2.4, -0.6);
const CELL: f32 = 1.2;

fn at() -> Origin {
    Origin {
        file: "shading_gpu.rs".into(),
        line: 0,
        field: "scene".into(),
    }
}

fn texture(r: &mut TestRng, w: u32, h: u32) -> Texture {
    let texels = (0..w * h)
        .map(|_| pack_rgba8([0, 0, 0, 0].map(|_: u8| (r.f32() * 255.0) as u8)))
        .collect();
    Texture::from_rgba8("random", w, h, texels, Encoding::Raw).unwrap()
}

/// Every material kind on a 5 x 4 grid of spheres and on a floor of smooth triangles, under
/// a lat-long environment.
fn scene(r: &mut TestRng) -> Scene {
    let at = at();
    let mut b = SceneBuilder::new();
    b.camera(Vec3::new(0.0, -8.0, 4.0), Vec3::ZERO, Vec3::Z, 40.0, &at)
        .unwrap();
    let tex = b
        .add_texture(SceneTexture::Bitmap(texture(r, 6, 5)), &at)
        .unwrap();
    let turn = Mat3::from_rotation_y(0.4) * Mat3::from_rotation_x(0.7);
    b.set_environment(Vec3::splat(0.8), Some(texture(r, 8, 5)), turn, &at)
        .unwrap();
    let (eta, k) = (Vec3::new(0.2, 0.92, 1.1), Vec3::new(3.9, 2.45, 2.14));
    let cond = |microfacet| Bsdf::conductor(eta, k, Vec3::new(0.95, 0.9, 1.0), microfacet);
    let ggx = |a| Some(Microfacet::isotropic(Distribution::Ggx, a));
    let beckmann = Some(Microfacet::isotropic(Distribution::Beckmann, 0.3));
    let (kd, ks) = (Vec3::new(0.5, 0.3, 0.2), Vec3::new(1.0, 0.9, 0.8));
    let gltf = |metallic, roughness, transmission| {
        let (base, f0) = (Vec3::new(0.8, 0.45, 0.2), Vec3::new(0.04, 0.06, 0.03));
        Bsdf::MetallicRoughness(MetallicRoughness::new(
            base,
            metallic,
            roughness,
            f0,
            0.9,
            transmission,
        ))
    };
    let textured = |mut m: Material| {
        *m.bsdf.base_colour_mut().unwrap() = Param::texture(tex);
        m
    };
    // Every glTF parameter texture on one material: its channels as the importer reads them.
    let gltf_textured = |b: Bsdf| {
        let Bsdf::MetallicRoughness(g) = b else {
            unreachable!()
        };
        textured(Material::from_bsdf(Bsdf::MetallicRoughness(
            MetallicRoughness {
                metallic: g.metallic.times(tex, Channel::B),
                roughness: g.roughness.times(tex, Channel::G),
                transmission: g.transmission.times(tex, Channel::R),
                specular: g.specular.times(tex, Channel::A),
                f0: g.f0.times(tex, Channel::Rgb),
                ..g
            },
        )))
    };
    let materials = [
        Material::diffuse(Vec3::new(0.6, 0.5, 0.4)),
        textured(Material::diffuse(Vec3::splat(0.5))),
        Material::glossy(Vec3::splat(0.3), Vec3::new(0.5, 0.4, 0.3), 30.0),
        Material::glossy(Vec3::splat(0.5), Vec3::ZERO, 10.0),
        Material::mirror(Vec3::new(0.9, 0.8, 0.7)),
        Material::glass(1.5),
        Material::black(),
        Material::from_bsdf(cond(None)),
        Material::from_bsdf(cond(ggx(0.3))),
        Material::from_bsdf(Bsdf::dielectric(
            1.5,
            Vec3::new(0.9, 1.0, 0.95),
            Vec3::new(1.0, 0.8, 0.9),
            ggx(0.2),
        )),
        Material::from_bsdf(Bsdf::thin_dielectric(
            1.5,
            Vec3::new(0.9, 1.0, 0.95),
            Vec3::new(1.0, 0.8, 0.9),
        )),
        textured(Material::from_bsdf(Bsdf::Plastic(Plastic::new(
            kd, ks, 1.5, false, None,
        )))),
        Material::from_bsdf(Bsdf::Plastic(Plastic::new(kd, ks, 1.5, true, beckmann))),
        gltf_textured(gltf(0.4, 0.6, 0.7)),
        Material::from_bsdf(gltf(1.0, 0.3, 0.0)),
        Material::from_bsdf(gltf(0.0, 0.5, 0.0)),
        // One-sided (Mitsuba's bsdfs outside `twosided`): black from the back.
        Material {
            one_sided: true,
            ..Material::diffuse(Vec3::new(0.3, 0.6, 0.5))
        },
        Material {
            one_sided: true,
            ..textured(Material::from_bsdf(Bsdf::Plastic(Plastic::new(
                kd, ks, 1.5, true, beckmann,
            ))))
        },
    ];
    let mut ids: Vec<MaterialId> = materials
        .into_iter()
        .map(|m| b.add_material(None, m, &at).unwrap())
        .collect();
    // Blends (crate::bsdfs::blend): diffuse and mirror at a constant weight; a one-sided
    // plastic and glass by a texture's luminance, nested in a blend with a conductor.
    let half = b
        .add_blend(ids[0], ids[4], Param::constant(0.5), &at)
        .unwrap();
    let by_texture = Param {
        value: Vec3::ONE,
        texture: tex,
        channel: Channel::Luminance,
    };
    let textured_blend = b.add_blend(ids[17], ids[5], by_texture, &at).unwrap();
    let nested = b
        .add_blend(textured_blend, ids[8], Param::constant(0.3), &at)
        .unwrap();
    ids.extend([half, nested]);
    // A normal map that shadows grazing light (Mitsuba's use_shadowing_function), on an
    // anisotropic conductor: its frame's tangent (the hit's, made orthogonal to the
    // perturbed normal) turns every answer.
    let anisotropic = Some(Microfacet::new(Distribution::Ggx, 0.4, 0.15));
    let shadowed = Material {
        normal_texture: tex,
        normal_shadowing: true,
        ..Material::from_bsdf(cond(anisotropic))
    };
    ids.push(b.add_material(None, shadowed, &at).unwrap());
    // A floor of every material below the spheres, in cells of two smooth triangles whose
    // vertex normals lean up to 25 degrees off the face (the leak tests' cases).
    for (k, &id) in ids.iter().enumerate() {
        let (x, y) = (
            FLOOR_MIN.x + CELL * (k % 5) as f32,
            FLOOR_MIN.y + CELL * (k / 5) as f32,
        );
        let c = [(0.0, 0.0), (CELL, 0.0), (CELL, CELL), (0.0, CELL)]
            .map(|(dx, dy)| Vec3::new(x + dx, y + dy, FLOOR_MIN.z));
        let tris = vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]];
        let normals = (0..2)
            .map(|_| [0; 3].map(|_| (Vec3::Z + 0.45 * r.dir()).normalize()))
            .collect();
        let uv = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        let uvs = vec![[uv[0], uv[1], uv[2]], [uv[0], uv[2], uv[3]]];
        b.add_uv_mesh(tris, Some(normals), uvs, Surface::of(id), &at)
            .unwrap();
    }
    let mut surfaces: Vec<Surface> = ids.into_iter().map(Surface::of).collect();
    let black = b.add_material(None, Material::black(), &at).unwrap();
    surfaces.push(Surface {
        emission: Some(Vec3::new(2.0, 1.5, 1.0)),
        two_sided: Some(true),
        emission_texture: Some(tex),
        ..Surface::of(black)
    });
    surfaces.push(Surface::emitting(Vec3::new(1.0, 2.0, 3.0)));
    for (i, s) in surfaces.into_iter().enumerate() {
        let c = Vec3::new((i % 5) as f32 - 2.0, (i / 5) as f32 - 1.5, 0.0) * 1.2;
        b.add_sphere(c, 0.45, s, &at).unwrap();
    }
    b.finish(&at).unwrap()
}

/// Rays at random points of random spheres, or (a quarter) of the floor, from either side,
/// 0.5 to 4 away (some blocked by others);
/// `wo` the viewer (mostly `-dir`), `wi` uniform; an eighth of the rays leave the scene.
fn cases(scene: &Scene, r: &mut TestRng) -> Vec<ShadingCase> {
    (0..CASES)
        .map(|i| {
            let p = if i % 4 == 1 {
                let (w, h) = (5.0 * CELL, 4.0 * CELL);
                FLOOR_MIN + Vec3::new(r.range(0.0, w), r.range(0.0, h), 0.0)
            } else {
                let s = &scene.spheres[r.next_u64() as usize % scene.spheres.len()];
                s.center + s.radius * r.dir()
            };
            let origin = p + r.dir() * r.range(0.5, 4.0);
            let mut dir = (p - origin).normalize();
            if i % 8 == 7 {
                dir = r.dir();
            }
            let wo = if i % 3 == 0 { r.dir() } else { -dir };
            let pdfs = [r.f32(), [0.0, r.f32(), 10.0 * r.f32()][i % 3]];
            ShadingCase {
                origin,
                dir,
                t_max: 1e30,
                key: path_key(SEED as u32, Stream::Camera, 0, i as u32),
                wi: r.dir(),
                wo,
                u: [r.f32(), r.f32(), r.f32()],
                pdfs: if i % 17 == 0 { [0.0, 0.0] } else { pdfs },
            }
        })
        .collect()
}

fn stream(i: usize) -> Rng {
    Rng::new(SEED as u32, Stream::Camera, 0, i as u32)
}

/// Per quantity: (cases compared, worst relative error).
#[derive(Default)]
struct Errors(BTreeMap<&'static str, (usize, f32)>);

impl Errors {
    fn v(&mut self, what: &'static str, case: usize, got: Vec3, want: Vec3, tol: f32, floor: f32) {
        let e = (got - want).abs().max_element() / want.abs().max_element().max(floor);
        let s = self.0.entry(what).or_default();
        s.0 += 1;
        s.1 = s.1.max(e);
        assert!(
            e <= tol,
            "case {case}: {what}: device {got} vs host {want} (relative error {e})"
        );
    }
    fn f(&mut self, what: &'static str, case: usize, got: f32, want: f32) {
        self.v(what, case, Vec3::splat(got), Vec3::splat(want), TOL, FLOOR);
    }
}

fn bounce_code(b: &Bounce) -> (u32, Vec3, Vec3) {
    match *b {
        Bounce::Absorb => (BOUNCE_ABSORB, Vec3::ZERO, Vec3::ZERO),
        Bounce::Diffuse { dir, weight } => (BOUNCE_DIFFUSE, dir, weight),
        Bounce::Specular { dir, weight, delta } => {
            let k = if delta { BOUNCE_DELTA } else { BOUNCE_LOBE };
            (k, dir, weight)
        }
    }
}

/// The tolerance of a value sampled along `dir` for a ray along `d` (`GRAZING_ABS`).
fn grazing(d: Vec3, dir: Vec3, ns: Vec3) -> f32 {
    let cos = d.dot(ns).abs().min(dir.dot(ns).abs());
    TOL.max(GRAZING_ABS / cos)
}

/// `d` and `d` turned by `NUDGE` about two axes across it, both ways.
fn nudged(d: Vec3) -> Vec<Vec3> {
    let (t, b) = gpu_photon::math::sampling::basis(d);
    let mut out = vec![d];
    for a in [t, b] {
        for s in [-NUDGE, NUDGE] {
            out.push((d + s * a).normalize());
        }
    }
    out
}

/// Whether `decide` gives the same for every nudge of `d`.
fn stable<T: PartialEq>(d: Vec3, decide: impl Fn(Vec3) -> T) -> bool {
    let first = decide(d);
    nudged(d).into_iter().all(|n| decide(n) == first)
}

/// The host's delta bounce as the device makes it (one draw chooses at a dielectric):
/// (direction, not leaking, throughput).
fn host_delta(s: &SurfaceBsdf, probe: &ShadedSurface, d: Vec3, i: usize) -> (Vec3, bool, Vec3) {
    let hit = &probe.hit;
    let f = hit.facing(d);
    match s.delta(d, hit, &f, RenderSettings::default().fresnel) {
        DeltaEvent::Reflect { dir, weight } => (dir, !f.reflection_leaks(dir), weight),
        DeltaEvent::Split(g) => {
            let reflects = stream(i).next() < g.reflectance;
            let dir = match (reflects, g.refracted) {
                (false, Some(t)) => t,
                _ => g.reflected,
            };
            let leaks = if reflects {
                f.reflection_leaks(dir)
            } else {
                f.refraction_leaks(dir)
            };
            // Radiance mode: a refracted camera path carries (n_i/n_t)^2, as the CPU's chain
            // does (`Dielectric::refracted_radiance`).
            let weight = match reflects || g.refracted.is_none() {
                true => Vec3::ONE,
                false => Vec3::splat(g.refracted_radiance()),
            };
            (dir, !leaks, weight)
        }
    }
}

#[test]
fn wgsl_shading_equals_rust_shading() {
    let Some(ctx) = gpu() else { return };
    let mut r = TestRng(SEED);
    let scene = scene(&mut r);
    let cases = cases(&scene, &mut r);
    let mut probes = SceneProbes::new(&ctx, &scene, &RenderSettings::default()).unwrap();
    let got = probes.shading(&cases).unwrap();
    let fresnel = RenderSettings::default().fresnel;
    let mut errs = Errors::default();
    let mut classes = BTreeMap::new();
    let mut bounces = BTreeMap::new();
    let (mut skipped, mut samples, mut deltas, mut backs, mut blends) = (0, 0, 0, 0, 0);
    for (i, (c, p)) in cases.iter().zip(&got).enumerate() {
        errs.v("escape", i, p.escape, escape(&scene, c.dir), ENV_TOL, FLOOR);
        let ph = power_heuristic(c.pdfs[0], c.pdfs[1]);
        errs.f("power_heuristic", i, p.power_heuristic, ph);
        let Some(g) = &p.surface else { continue };
        let hit = g.hit;
        let s = bsdf_at(&scene, &hit, c.dir);
        let f = hit.facing(c.dir);
        assert_eq!(g.class, class_code(s.class()), "case {i}: class");
        *classes.entry(format!("{:?}", s.class())).or_insert(0) += 1;
        blends += usize::from(scene.materials[hit.material as usize].blend.is_some());
        backs += usize::from(
            scene.materials[hit.material as usize].one_sided && c.dir.dot(hit.normal) >= 0.0,
        );
        let flags = [
            s.bsdf().splits(),
            s.has_lobe(),
            s.lobe_takes_point_lights(),
            s.lobe_is_glossy(),
            s.stores_photons(),
        ];
        for (k, (name, want)) in SHADING_FLAGS.iter().zip(flags).enumerate() {
            assert_eq!(g.flags >> k & 1 == 1, want, "case {i}: {name}");
        }
        let (wi, wo) = (c.wi, c.wo);
        errs.v(
            "emitted front",
            i,
            g.emitted[0],
            s.emitted(true),
            TOL,
            FLOOR,
        );
        errs.v(
            "emitted back",
            i,
            g.emitted[1],
            s.emitted(false),
            TOL,
            FLOOR,
        );
        let sw = s.store_weight(wi).unwrap_or(1.0);
        errs.f("store_weight", i, g.store_weight, sw);
        errs.f("pdf_lobe", i, g.pdf_lobe, s.pdf_lobe(wi, wo, f.ns));
        let albedo = s.diffuse_albedo(wo);
        errs.v("diffuse_albedo", i, g.diffuse_albedo, albedo, TOL, FLOOR);
        let fd = s.eval_diffuse(wi, wo);
        errs.v("eval_diffuse", i, g.eval_diffuse, fd, TOL, FLOOR);
        let est = s.estimate_brdf(wo);
        errs.v("estimate_brdf", i, g.estimate_brdf, est, TOL, FLOOR);
        let lobe = s.eval_lobe(wi, wo, f.ns);
        errs.v("eval_lobe", i, g.eval_lobe, lobe, TOL, FLOOR);

        // The lobe sample, where its outcome does not flip under a nudge of the ray.
        let sample = |d: Vec3| s.sample_lobe(d, &hit.facing(d), &mut stream(i));
        if stable(c.dir, |d| sample(d).is_some()) {
            let want = sample(c.dir);
            assert_eq!(
                g.sample_lobe.is_some(),
                want.is_some(),
                "case {i}: sample_lobe ok"
            );
            if let (Some((dir, weight, pdf)), Some(w)) = (g.sample_lobe, want) {
                samples += 1;
                errs.v("sample_lobe dir", i, dir, w.dir, DIR_ABS, 1.0);
                let tol = grazing(c.dir, w.dir, f.ns);
                errs.v("sample_lobe weight", i, weight, w.weight, tol, FLOOR);
                let (p, wp) = (Vec3::splat(pdf), Vec3::splat(w.pdf));
                errs.v("sample_lobe pdf", i, p, wp, tol, FLOOR);
            }
        } else {
            skipped += 1;
        }

        // The delta bounce of a delta surface.
        assert_eq!(
            g.delta.is_some(),
            s.class() == SurfaceClass::Delta,
            "case {i}: delta"
        );
        if let Some((dir, ok, t, o)) = g.delta {
            let decide = |d: Vec3| {
                let (dir, ok, _) = host_delta(&s, g, d, i);
                (dir.dot(hit.normal) > 0.0, ok)
            };
            if stable(c.dir, decide) {
                deltas += 1;
                let (want_dir, want_ok, want_t) = host_delta(&s, g, c.dir, i);
                assert_eq!(ok, want_ok, "case {i}: surface_delta's leak test");
                errs.v("delta dir", i, dir, want_dir, DIR_ABS, 1.0);
                errs.v("delta throughput", i, t, want_t, TOL, FLOOR);
                let want_o = offset_origin(hit.position, hit.normal, want_dir);
                let scale = hit.position.abs().max_element().max(1.0);
                errs.v("delta origin", i, o, want_o, DIR_ABS, scale);
            } else {
                skipped += 1;
            }
        }

        // The photon's bounce, where its kind does not flip under a nudge of the ray or of
        // the uniforms.
        let bounce = |d: Vec3, u: [f32; 3]| bounce_code(&s.photon_bounce(d, &hit, fresnel, u));
        let u_nudged = (0..3).flat_map(|k| {
            [-NUDGE, NUDGE].map(|e| {
                let mut u = c.u;
                u[k] = (u[k] + e).clamp(0.0, 1.0 - f32::EPSILON);
                u
            })
        });
        let kind = bounce(c.dir, c.u).0;
        let steady = stable(c.dir, |d| bounce(d, c.u).0 == kind)
            && u_nudged.into_iter().all(|u| bounce(c.dir, u).0 == kind);
        if steady {
            let (want_kind, want_dir, want_w) = bounce(c.dir, c.u);
            let (dir, got_kind, w) = g.bounce;
            assert_eq!(got_kind, want_kind, "case {i}: photon bounce kind");
            *bounces.entry(want_kind).or_insert(0) += 1;
            // An absorbed photon's direction and weight mean nothing (the device keeps the
            // direction it rejected).
            if want_kind != BOUNCE_ABSORB {
                errs.v("bounce dir", i, dir, want_dir, DIR_ABS, 1.0);
                let tol = grazing(c.dir, want_dir, f.ns);
                errs.v("bounce weight", i, w, want_w, tol, FLOOR);
            }
        } else {
            skipped += 1;
        }
    }
    for (what, (n, e)) in &errs.0 {
        eprintln!("{what}: {n} cases, worst relative error {e:.2e}");
    }
    eprintln!(
        "classes {classes:?}, bounce kinds {bounces:?}, lobe samples {samples}, delta bounces \
         {deltas}, decisions skipped near a threshold {skipped}, one-sided backs {backs}, blends {blends}"
    );
    // Every class but Null (no null surface here), every bounce kind, and most decisions
    // compared.
    assert_eq!(classes.len(), 3, "{classes:?}");
    assert_eq!(bounces.len(), 4, "{bounces:?}");
    assert!(
        samples > CASES / 5 && deltas > CASES / 20,
        "{samples} {deltas}"
    );
    assert!(skipped < CASES / 50, "{skipped} decisions near a threshold");
    // One-sided materials were seen from the back (black on both sides) in enough cases.
    assert!(backs > CASES / 200, "{backs} one-sided backs");
    assert!(blends > CASES / 100, "{blends} blends");
}
