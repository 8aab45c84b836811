//! glTF's metallic-roughness BSDF (`gpu_photon::bsdfs::MetallicRoughness`) against the
//! specification's Appendix B written out here on its own: the lobes equal it pointwise, the
//! diffuse part's albedo towards every viewer equals the specification's (whose
//! `1 - max F(wo . h)` weight our split replaces by its cosine-weighted mean), sampling
//! agrees with quadrature, and the `S(mu)` table agrees with a brute-force integral.

use glam::Vec3;
use gpu_photon::bsdfs::BsdfKind;
use gpu_photon::bsdfs::{
    schlick_mean, Bsdf, Distribution, MetallicRoughness, Microfacet, Transport,
};
use std::f32::consts::PI;

mod common;

fn wo_at(deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn unit_vector(r: &mut common::TestRng) -> Vec3 {
    let z = 2.0 * r.f32() - 1.0;
    let phi = 2.0 * PI * r.f32();
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

fn materials() -> Vec<(&'static str, MetallicRoughness)> {
    let g = |base: Vec3, metallic, roughness, f0: Vec3, f90, transmission| {
        MetallicRoughness::new(base, metallic, roughness, f0, f90, transmission)
    };
    let orange = Vec3::new(0.9, 0.5, 0.1);
    vec![
        (
            "plastic-like",
            g(orange, 0.0, 0.5, Vec3::splat(0.04), 1.0, 0.0),
        ),
        (
            "gold-like metal",
            g(
                Vec3::new(1.0, 0.78, 0.34),
                1.0,
                0.3,
                Vec3::splat(0.04),
                1.0,
                0.0,
            ),
        ),
        (
            "half metal",
            g(orange, 0.5, 0.7, Vec3::splat(0.04), 1.0, 0.0),
        ),
        (
            "coloured specular",
            g(orange, 0.0, 0.4, Vec3::new(0.08, 0.02, 0.05), 0.6, 0.0),
        ),
        (
            "thin transmission",
            g(
                Vec3::new(0.7, 0.9, 0.8),
                0.0,
                0.35,
                Vec3::splat(0.04),
                1.0,
                0.8,
            ),
        ),
    ]
}

/// Appendix B (with KHR_materials_specular and a thin-walled transmission), transcribed:
/// f(wi, wo) for `wo.z > 0`, the base's Fresnel weight at `wo . h` as the specification has it.
fn appendix_b(g: &MetallicRoughness, wi: Vec3, wo: Vec3) -> Vec3 {
    let mf = Microfacet::isotropic(Distribution::Ggx, g.roughness.float() * g.roughness.float());
    let through = wi.z < 0.0;
    let wr = if through {
        Vec3::new(wi.x, wi.y, -wi.z)
    } else {
        wi
    };
    if wr.z <= 0.0 || wo.z <= 0.0 {
        return Vec3::ZERO;
    }
    let h = (wr + wo).normalize();
    let c = wo.dot(h);
    let k = (1.0 - c).clamp(0.0, 1.0).powi(5);
    let spec = mf.d(h) * mf.smith_g1(wr, h) * mf.smith_g1(wo, h) / (4.0 * wr.z * wo.z);
    let fd = g.f0.get() + (Vec3::splat(g.f90) - g.f0.get()) * k;
    let fm = g.base.get() + (Vec3::ONE - g.base.get()) * k;
    let rest = 1.0 - fd.max_element();
    let (m, t) = (g.metallic.float(), g.transmission.float());
    if through {
        return (1.0 - m) * rest * t * g.base.get() * spec;
    }
    let dielectric = fd * spec + rest * (1.0 - t) * g.base.get() / PI;
    dielectric * (1.0 - m) + fm * spec * m
}

/// The integral over the sphere of `f(wi) |wi.z|` (midpoint rule in theta, phi).
fn quadrature(f: impl Fn(Vec3) -> Vec3) -> Vec3 {
    let (nt, np) = (500, 200);
    let mut sum = [0.0f64; 3];
    for i in 0..nt {
        let t = (i as f32 + 0.5) / nt as f32 * PI;
        for j in 0..np {
            let p = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
            let wi = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
            let v = f(wi) * (wi.z.abs() * t.sin());
            for (s, v) in sum.iter_mut().zip(v.to_array()) {
                *s += v as f64;
            }
        }
    }
    let w = (PI / nt as f32) as f64 * (2.0 * PI / np as f32) as f64;
    Vec3::new(
        (sum[0] * w) as f32,
        (sum[1] * w) as f32,
        (sum[2] * w) as f32,
    )
}

#[test]
fn lobes_equal_appendix_b_and_the_diffuse_albedo_is_its_own() {
    let mut r = common::TestRng(7);
    for (name, g) in materials() {
        let b = Bsdf::MetallicRoughness(g);
        // Pointwise: our lobes are the specification's minus its base term.
        for _ in 0..2000 {
            let wo = unit_vector(&mut r);
            let wi = unit_vector(&mut r);
            let wo = if wo.z < 0.0 { -wo } else { wo };
            let mut want = appendix_b(&g, wi, wo);
            if wi.z > 0.0 {
                let c = wo.dot((wi + wo).normalize());
                let fmax = (g.f0.get() + (Vec3::splat(g.f90) - g.f0.get()) * (1.0 - c).powi(5))
                    .max_element();
                want -= (1.0 - g.metallic.float())
                    * (1.0 - g.transmission.float())
                    * (1.0 - fmax)
                    * g.base.get()
                    / PI;
            }
            let got = b.eval_lobe(wi, wo, Transport::Radiance);
            let tol = 1e-4 * want.max_element().max(1.0);
            assert!(
                (got - want).abs().max_element() <= tol,
                "{name}: wi {wi} wo {wo}: {got} vs {want}"
            );
        }
        // The diffuse part's albedo: the specification's, towards every viewer.
        for deg in [0.0, 30.0, 60.0, 80.0, 88.0] {
            let wo = wo_at(deg, 40.0);
            let want = quadrature(|wi| appendix_b(&g, wi, wo))
                - quadrature(|wi| b.eval_lobe(wi, wo, Transport::Radiance));
            let got = quadrature(|wi| b.eval(wi, wo, Transport::Radiance))
                - quadrature(|wi| b.eval_lobe(wi, wo, Transport::Radiance));
            assert!(
                (got - want).abs().max_element() < 2e-3 * want.max_element().max(0.05),
                "{name} at {deg} degrees: diffuse albedo {got} vs the specification's {want}"
            );
        }
    }
}

#[test]
fn sampled_albedo_matches_quadrature() {
    let mut r = common::TestRng(21);
    for (name, g) in materials() {
        let b = Bsdf::MetallicRoughness(g);
        for wo in [wo_at(15.0, 10.0), wo_at(70.0, 100.0), -wo_at(45.0, 200.0)] {
            let q = quadrature(|wi| b.eval(wi, wo, Transport::Radiance));
            let n = 80_000;
            let (mut s, mut s2) = (Vec3::ZERO, Vec3::ZERO);
            for _ in 0..n {
                let u = [r.f32(), r.f32(), r.f32()];
                let w = b
                    .sample(wo, u, Transport::Radiance)
                    .map_or(Vec3::ZERO, |s| s.weight);
                assert!(
                    w.is_finite() && w.min_element() >= 0.0,
                    "{name}: weight {w}"
                );
                s += w;
                s2 += w * w;
            }
            let mean = s / n as f32;
            let err = ((s2 / n as f32 - mean * mean).max(Vec3::ZERO) / n as f32)
                .max_element()
                .sqrt();
            assert!(
                (mean - q).abs().max_element() < 4.0 * err + 3e-3,
                "{name} wo {wo}: sampled {mean} +- {err}, quadrature {q}"
            );
        }
    }
}

#[test]
fn schlick_mean_table_is_the_integral() {
    // S(mu) by brute force: the cosine-weighted mean of (1 - wo . h)^5 over the hemisphere.
    for mu in [0.0f32, 0.13, 0.5, 0.77, 1.0] {
        let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let s = quadrature(|wi| {
            if wi.z <= 0.0 || (wi + wo).length_squared() == 0.0 {
                return Vec3::ZERO;
            }
            Vec3::splat((1.0 - wo.dot((wi + wo).normalize())).max(0.0).powi(5) / PI)
        })
        .x;
        let got = schlick_mean(mu);
        assert!((got - s).abs() < 2e-4, "S({mu}) = {got}, brute force {s}");
    }
    assert!(schlick_mean(1.0) < 1e-3 && schlick_mean(0.0) > 0.01);
}
