//! Oracle test of the classic materials' device functions (src/bsdfs/classic.wgsl)
//! against src/bsdfs/classic.rs, through the probe `probe_surface` (tests/probes/probe_geometry.wgsl,
//! `gpu::probes::surface`): `reflect_dir`, `fresnel_exact` and `fresnel_schlick` entering and
//! leaving (total internal reflection included), `dielectric` on smooth frames (the render's
//! default Fresnel formula, exact), `phong_lobe_value` (exponents 0 to 10^4) and
//! `photon_bounce` of diffuse, glossy, mirror and glass materials (every outcome: absorbed,
//! diffuse, the glossy lobe, delta, and a direction leaking below the geometric surface).
//! Tolerances: `DIR_ABS`, `VALUE_ABS`, `LOBE_REL` (a glossy bounce's direction as
//! tests/intersect_gpu.rs bounds `phong_lobe` near its axis, its weight, which holds that
//! direction's cosine, ten times that); outcomes exactly, where the host is not
//! within `KNIFE` of a decision (a uniform against a probability, a cosine against 0, the
//! critical angle).
//! Without a Vulkan adapter the test is skipped (CI fails instead, see common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::Vec3;
use gpu_photon::bsdfs::fresnel::{dielectric_shading, fresnel_exact, fresnel_schlick, reflect};
use gpu_photon::bsdfs::phong::phong_lobe_value;
use gpu_photon::bsdfs::shading::{photon_bounce_at, Bounce};
use gpu_photon::bsdfs::Bsdf;
use gpu_photon::integrators::gpu::codes::{
    BOUNCE_ABSORB, BOUNCE_DELTA, BOUNCE_DIFFUSE, BOUNCE_LOBE,
};
use gpu_photon::math::geometry::Facing;
use gpu_photon::scene::Material;
use gpu_photon::settings::FresnelMode;
use probes::{surface, SurfaceCase, SurfaceProbe};

/// Directions: a normalisation or a square root and a few products (measured worst on
/// lavapipe in the report line); the glossy lobe's `phong_lobe` near its axis is looser
/// (tests/intersect_gpu.rs: `2e-5 + 4e-7 / sin`), which `lobe_tol` adds.
const DIR_ABS: f32 = 1e-5;
/// Reflectances and weights (relative for weights): pow's and sqrt's last bits.
const VALUE_ABS: f32 = 1e-5;
/// The Phong lobe's value, relative per unit of exponent: pow's relative error on the
/// cosine, times the exponent.
const LOBE_REL: f32 = 1e-6;
/// Decisions closer than this to their threshold on the host are not compared.
const KNIFE: f32 = 1e-4;

/// The classic kinds, by index (the cases cycle through them).
fn classic(k: usize, kd: Vec3, ks: Vec3, exponent: f32, ior: f32) -> Bsdf {
    match k {
        0 => Material::diffuse(kd).bsdf,
        1 => Material::glossy(kd, ks, exponent).bsdf,
        2 => Material::mirror(ks).bsdf,
        _ => Material::glass(ior).bsdf,
    }
}

fn cases(r: &mut TestRng) -> Vec<SurfaceCase> {
    (0..3000)
        .map(|i| {
            let ng = r.dir();
            let ns = if i % 5 == 0 {
                ng
            } else {
                (ng + 0.3 * r.dir()).normalize()
            };
            // Rays mostly arriving from the front, some from behind (leaving glass).
            let d = if i % 3 == 0 {
                r.dir()
            } else {
                (-ng + 0.8 * r.dir()).normalize()
            };
            let kd = Vec3::new(r.f32(), r.f32(), r.f32()) * 0.5;
            let ks = Vec3::new(r.f32(), r.f32(), r.f32()) * 0.45;
            let exponent = [0.0, 1.0, 20.0, 1e4][i % 4] * r.f32();
            let ior = [1.5, 1.33, 2.4, r.range(1.0, 3.0)][i % 4];
            SurfaceCase {
                axis: r.dir().to_array(),
                exponent,
                u: [r.f32(), r.f32()],
                ng: ng.to_array(),
                ns: ns.to_array(),
                c: [r.f32(), 0.0, 0.0],
                d: d.to_array(),
                ior,
                material: classic(i % 7 % 4, kd, ks, exponent, ior),
                u3: r.f32(),
                ..Default::default()
            }
        })
        .collect()
}

fn dir_close(what: &str, got: [f32; 3], want: Vec3, tol: f32) -> f32 {
    let e = (Vec3::from(got) - want).abs().max_element();
    assert!(e <= tol, "{what}: {got:?} vs {want} (error {e})");
    e
}

/// The host's bounce as (kind code, direction, weight) and how near a decision it was made.
fn host_bounce(c: &SurfaceCase) -> ((u32, Vec3, Vec3), f32) {
    let m = Material::of(c.material);
    let (kd, ks) = match c.material {
        Bsdf::Diffuse(d) => (d.reflectance.get(), Vec3::ZERO),
        Bsdf::Phong(p) => (p.kd.get(), p.ks.get()),
        Bsdf::Mirror(r) => (Vec3::ZERO, r.reflectance.get()),
        _ => (Vec3::ZERO, Vec3::ZERO),
    };
    let (d, ng, ns) = (Vec3::from(c.d), Vec3::from(c.ng), Vec3::from(c.ns));
    let u = [c.u[0], c.u[1], c.u3];
    let b = photon_bounce_at(&m, d, ng, ns, FresnelMode::Exact, u);
    let out = match b {
        Bounce::Absorb => (BOUNCE_ABSORB, Vec3::ZERO, Vec3::ZERO),
        Bounce::Diffuse { dir, weight } => (BOUNCE_DIFFUSE, dir, weight),
        Bounce::Specular { dir, weight, delta } => {
            let k = if delta { BOUNCE_DELTA } else { BOUNCE_LOBE };
            (k, dir, weight)
        }
    };
    // The roulette's thresholds, and the signs the outcome's direction was tested by.
    let f = Facing::new(ng, ns, d.dot(ng) < 0.0);
    let total = (kd + ks).max_element();
    let (sd, ss) = (kd.element_sum(), ks.element_sum());
    let pd = total * sd / (sd + ss);
    // The lobe's and the dielectric's directions are kept by sign tests against the normals.
    let signs = |dirs: &[Vec3]| {
        dirs.iter()
            .map(|v| v.dot(f.ns).abs().min(v.dot(f.ng).abs()))
            .fold(f32::INFINITY, f32::min)
    };
    let near = match c.material {
        Bsdf::Diffuse(_) => (u[0] - pd).abs().min((u[0] - total).abs()),
        Bsdf::Phong(_) => {
            let lobe =
                gpu_photon::math::sampling::phong_lobe(reflect(d, f.ns), c.exponent, u[1], u[2]);
            (u[0] - pd)
                .abs()
                .min((u[0] - total).abs())
                .min(signs(&[lobe]))
        }
        Bsdf::Mirror(_) => (u[0] - ks.max_element()).abs(),
        _ => {
            let g = dielectric_shading(d, ng, ns, c.ior, FresnelMode::Exact);
            let dirs = [g.reflected, g.refracted.unwrap_or(g.reflected)];
            (u[0] - g.reflectance).abs().min(signs(&dirs))
        }
    };
    (out, near)
}

fn check(i: usize, c: &SurfaceCase, g: &SurfaceProbe, worst: &mut [f32; 3]) -> bool {
    let (ng, ns, d, x) = (Vec3::from(c.ng), Vec3::from(c.ns), Vec3::from(c.d), c.c[0]);
    let want = [
        fresnel_exact(x, 1.0, c.ior),
        fresnel_exact(x, c.ior, 1.0),
        fresnel_schlick(x, 1.0, c.ior),
        fresnel_schlick(x, c.ior, 1.0),
    ];
    // Leaving the dense side, total internal reflection begins at sin = 1 / ior: a step.
    let critical = ((1.0 - x * x).sqrt() * c.ior - 1.0).abs() < KNIFE;
    for k in 0..4 {
        let e = (g.fresnel[k] - want[k]).abs();
        assert!(
            (k % 2 == 1 && critical) || e <= VALUE_ABS,
            "case {i}: fresnel {k}: {:?} vs {want:?}",
            g.fresnel
        );
    }
    let e = dir_close(
        &format!("case {i}: reflect_dir"),
        g.reflected,
        reflect(d, ns),
        DIR_ABS,
    );
    worst[0] = worst[0].max(e);
    let v = phong_lobe_value(Vec3::from(c.axis), -d, ns, c.exponent);
    let tol = LOBE_REL * (1.0 + c.exponent) * v.max(1.0);
    assert!(
        (g.lobe_value - v).abs() <= tol,
        "case {i}: phong_lobe_value {} vs {v}",
        g.lobe_value
    );
    let h = dielectric_shading(d, ng, ns, c.ior, FresnelMode::Exact);
    let nn = if d.dot(ng) < 0.0 { ns } else { -ns };
    let eta = if d.dot(ng) < 0.0 { 1.0 / c.ior } else { c.ior };
    let cos_i = (-d.dot(nn)).clamp(0.0, 1.0);
    let total = (eta * eta * (1.0 - cos_i * cos_i) - 1.0).abs() < KNIFE;
    let mut tir = false;
    if !total && d.dot(ng).abs() > KNIFE {
        let (reflected, refracted, reflectance) = g.dielectric;
        dir_close(
            &format!("case {i}: reflected"),
            reflected,
            h.reflected,
            DIR_ABS,
        );
        assert!(
            (reflectance - h.reflectance).abs() <= VALUE_ABS,
            "case {i}: reflectance"
        );
        match h.refracted {
            None => {
                tir = true;
                assert_eq!(refracted, [0.0; 3], "case {i}: total internal reflection");
            }
            Some(t) => {
                let e = dir_close(&format!("case {i}: refracted"), refracted, t, DIR_ABS);
                worst[1] = worst[1].max(e);
            }
        }
    }
    tir
}

#[test]
fn classic_materials_equal_the_hosts() {
    let Some(ctx) = gpu() else { return };
    let mut r = TestRng(0x3a7e);
    let cases = cases(&mut r);
    let got = surface(&ctx, &cases).unwrap();
    let (mut worst, mut tir, mut near, mut kinds) = ([0f32; 3], 0, 0, [0usize; 4]);
    for (i, (c, g)) in cases.iter().zip(&got).enumerate() {
        tir += check(i, c, g, &mut worst) as usize;
        let ((kind, dir, weight), margin) = host_bounce(c);
        if margin < KNIFE {
            near += 1;
            continue;
        }
        let (gdir, gkind, gweight) = g.bounce;
        assert_eq!(gkind, kind, "case {i} {c:?}: photon_bounce's outcome");
        kinds[kind as usize] += 1;
        if kind == BOUNCE_ABSORB {
            // An absorbed photon's direction and weight are not read.
            continue;
        }
        // The lobe's direction: phong_lobe near its axis (tests/intersect_gpu.rs).
        let sin = dir
            .cross(reflect(Vec3::from(c.d), Vec3::from(c.ns)))
            .length();
        let tol = if kind == BOUNCE_LOBE {
            2e-5 + 4e-7 / sin.max(1e-6)
        } else {
            DIR_ABS
        };
        dir_close(&format!("case {i}: bounce direction"), gdir, dir, tol);
        let e = ((Vec3::from(gweight) - weight).abs() / (weight.abs() + 1e-30)).max_element();
        assert!(
            e <= VALUE_ABS.max(tol * 10.0),
            "case {i}: bounce weight {gweight:?} vs {weight}"
        );
        worst[2] = worst[2].max(e);
    }
    eprintln!(
        "{} cases: {tir} totally reflected, bounces absorbed / diffuse / lobe / delta {kinds:?} \
         ({near} near a decision skipped); worst reflect_dir {:e}, refracted {:e}, bounce \
         weight {:e} relative",
        cases.len(),
        worst[0],
        worst[1],
        worst[2]
    );
    assert!(
        tir > 50 && kinds.iter().all(|&k| k > 100),
        "{tir} {kinds:?}"
    );
}
