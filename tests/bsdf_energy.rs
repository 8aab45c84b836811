//! Energy and symmetry of the BSDFs: white furnaces (the albedo, the integral of f |cos|, is
//! at most 1 and, for the lossless cases, close to 1), the albedo by sampling equal to the
//! albedo by quadrature of `eval`, reciprocity of the reflective kinds, the eta^2 rule of
//! dielectric transmission, two-sidedness, and the diffuse + lobe split.

use glam::Vec3;
use gpu_photon::bsdfs::BsdfKind;
use gpu_photon::bsdfs::{
    Bsdf, Distribution, Microfacet, Param, Plastic, Principled, PrincipledThin, Transport,
};
use std::f32::consts::PI;

mod common;

use common::TestRng;

fn wo_at(deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn ggx(a: f32) -> Option<Microfacet> {
    Some(Microfacet::isotropic(Distribution::Ggx, a))
}

fn beckmann(au: f32, av: f32) -> Option<Microfacet> {
    Some(Microfacet::new(Distribution::Beckmann, au, av))
}

/// White versions of every kind.
fn white() -> Vec<(&'static str, Bsdf)> {
    let one = Vec3::ONE;
    let mirror = |microfacet| Bsdf::conductor(Vec3::ZERO, one, one, microfacet);
    let glass = |microfacet| Bsdf::dielectric(1.5, one, one, microfacet);
    vec![
        ("diffuse", Bsdf::diffuse(one)),
        ("mirror", mirror(None)),
        ("rough mirror ggx", mirror(ggx(0.4))),
        ("rough mirror beckmann aniso", mirror(beckmann(0.2, 0.6))),
        ("glass", glass(None)),
        ("rough glass ggx", glass(ggx(0.3))),
        ("rough glass beckmann aniso", glass(beckmann(0.1, 0.4))),
        ("thin", Bsdf::thin_dielectric(1.5, one, one)),
        (
            "plastic",
            Bsdf::Plastic(Plastic::new(one, one, 1.5, false, None)),
        ),
        (
            "plastic nonlinear",
            Bsdf::Plastic(Plastic::new(one, one, 1.5, true, None)),
        ),
        (
            "rough plastic",
            Bsdf::Plastic(Plastic::new(one, one, 1.5, false, ggx(0.3))),
        ),
    ]
}

/// Albedo by sampling: mean and standard error of the weight's first channel.
fn albedo_sampled(b: &Bsdf, wo: Vec3, transport: Transport, n: usize, seed: u64) -> (f32, f32) {
    let mut rng = TestRng(seed);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u = [rng.f32(), rng.f32(), rng.f32()];
        let w = b
            .sample(wo, u, transport)
            .map_or(0.0, |s| s.weight.x as f64);
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean as f32, (var / n as f64).sqrt() as f32)
}

/// Albedo by quadrature of `eval_cos` over the sphere (midpoint rule in theta, phi).
fn albedo_quadrature(b: &Bsdf, wo: Vec3, transport: Transport) -> f32 {
    let (nt, np) = (600, 240);
    let mut sum = 0.0f64;
    for i in 0..nt {
        let t = (i as f32 + 0.5) / nt as f32 * PI;
        for j in 0..np {
            let p = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
            let wi = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
            sum += (b.eval_cos(wi, wo, transport).x * t.sin()) as f64;
        }
    }
    (sum * (PI / nt as f32) as f64 * (2.0 * PI / np as f32) as f64) as f32
}

#[test]
fn white_furnace_never_gains() {
    for (name, b) in white() {
        for deg in [0.0, 30.0, 60.0, 85.0] {
            for wo in [wo_at(deg, 20.0), -wo_at(deg, 20.0)] {
                let (a, err) = albedo_sampled(&b, wo, Transport::Importance, 40_000, 11);
                assert!(
                    a <= 1.0 + 4.0 * err + 2e-3,
                    "{name} wo {wo}: albedo {a} +- {err}"
                );
                assert!(a > 0.3, "{name} wo {wo}: albedo {a}");
            }
        }
    }
}

#[test]
fn sampled_albedo_matches_quadrature() {
    for (name, b) in white() {
        if b.lobe_is_delta() && !b.has_diffuse() {
            continue;
        }
        for wo in [wo_at(20.0, 10.0), wo_at(65.0, 100.0), -wo_at(40.0, 200.0)] {
            let q = albedo_quadrature(&b, wo, Transport::Importance);
            // The delta coating of the smooth plastic is no part of the quadrature.
            let delta = if b.lobe_is_delta() {
                b.sample_lobe(wo, [0.0; 3], Transport::Importance)
                    .unwrap()
                    .weight
                    .x
            } else {
                0.0
            };
            let (a, err) = albedo_sampled(&b, wo, Transport::Importance, 60_000, 5);
            assert!(
                (a - (q + delta)).abs() < 4.0 * err + 3e-3,
                "{name} wo {wo}: sampled {a} +- {err}, quadrature {q} + delta {delta}"
            );
        }
    }
}

#[test]
fn lossless_limits() {
    let one = Vec3::ONE;
    // A perfect mirror (F = 1) with little roughness loses almost nothing to shadowing;
    // more roughness loses more.
    let mut last = 1.0;
    for a in [0.02, 0.2, 0.5, 1.0] {
        let b = Bsdf::conductor(Vec3::ZERO, one, one, ggx(a));
        let (e, err) = albedo_sampled(&b, wo_at(45.0, 0.0), Transport::Radiance, 40_000, 3);
        if a < 0.05 {
            assert!(e > 0.995, "alpha {a}: {e}");
        }
        assert!(e < last + 3.0 * err, "alpha {a}: {e} after {last}");
        last = e;
    }
    // A slightly rough glass: R + T close to 1 from either side (importance: no eta^2).
    for mf in [ggx(0.02), beckmann(0.02, 0.03)] {
        let b = Bsdf::dielectric(1.5, one, one, mf);
        for wo in [wo_at(30.0, 0.0), -wo_at(30.0, 0.0), wo_at(70.0, 40.0)] {
            let (e, _) = albedo_sampled(&b, wo, Transport::Importance, 20_000, 9);
            assert!(e > 0.99 && e < 1.003, "{mf:?} wo {wo}: {e}");
        }
    }
    // Smooth glass and the thin sheet: every importance sample carries exactly 1; radiance
    // entering the glass is scaled by 1/eta^2 on transmission.
    let glass = Bsdf::dielectric(1.5, one, one, None);
    let thin = Bsdf::thin_dielectric(1.5, one, one);
    for u0 in [0.0, 0.03, 0.5, 0.99] {
        for b in [glass, thin] {
            let s = b
                .sample(wo_at(30.0, 0.0), [u0, 0.5, 0.5], Transport::Importance)
                .unwrap();
            assert!(s.delta && (s.weight - one).abs().max_element() < 1e-6);
        }
        let s = glass
            .sample(wo_at(30.0, 0.0), [u0, 0.5, 0.5], Transport::Radiance)
            .unwrap();
        let expect = if s.wi.z > 0.0 { 1.0 } else { 1.0 / 2.25 };
        assert!((s.weight.x - expect).abs() < 1e-6, "u0 {u0}: {s:?}");
    }
}

fn reflective() -> Vec<Bsdf> {
    let c = |mf| {
        Bsdf::conductor(
            Vec3::new(0.2, 0.9, 1.5),
            Vec3::new(3.9, 2.4, 1.6),
            Vec3::new(0.9, 0.8, 0.7),
            mf,
        )
    };
    vec![
        Bsdf::diffuse(Vec3::new(0.8, 0.5, 0.2)),
        c(ggx(0.3)),
        c(beckmann(0.1, 0.5)),
        Bsdf::Plastic(Plastic::new(
            Vec3::new(0.6, 0.3, 0.1),
            Vec3::splat(0.9),
            1.5,
            true,
            None,
        )),
        Bsdf::Plastic(Plastic::new(
            Vec3::new(0.6, 0.3, 0.1),
            Vec3::ONE,
            1.6,
            false,
            beckmann(0.25, 0.25),
        )),
    ]
}

fn close3(a: Vec3, b: Vec3, rel: f32) -> bool {
    (a - b).abs().max_element() <= rel * a.abs().max(b.abs()).max_element() + 1e-7
}

#[test]
fn reflective_kinds_are_reciprocal_and_two_sided() {
    let mut rng = TestRng(77);
    let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    for b in reflective() {
        let mut nonzero = 0;
        for _ in 0..2000 {
            let (mut wi, mut wo) = (rng.dir(), rng.dir());
            wi.z = wi.z.abs();
            wo.z = wo.z.abs();
            let f = b.eval(wi, wo, Transport::Radiance);
            nonzero += (f.max_element() > 0.0) as usize;
            assert!(
                close3(f, b.eval(wo, wi, Transport::Radiance), 2e-4),
                "{b:?} {wi} {wo}"
            );
            assert!(close3(
                f,
                b.eval(flip(wi), flip(wo), Transport::Radiance),
                1e-6
            ));
            assert!((b.pdf(wi, wo) - b.pdf(flip(wi), flip(wo))).abs() <= 1e-6 * b.pdf(wi, wo));
            assert_eq!(b.eval(flip(wi), wo, Transport::Radiance), Vec3::ZERO);
            assert_eq!(b.pdf(flip(wi), wo), 0.0);
        }
        assert!(nonzero > 1000, "{b:?}");
        if let Some(s) = b.sample(-wo_at(30.0, 10.0), [0.7, 0.3, 0.6], Transport::Radiance) {
            assert!(s.wi.z < 0.0, "{b:?}: {s:?}");
        }
    }
}

#[test]
fn dielectric_transmission_follows_the_eta2_rule() {
    let mut rng = TestRng(99);
    for mf in [ggx(0.3), beckmann(0.2, 0.5)] {
        let b = Bsdf::dielectric(1.5, Vec3::ONE, Vec3::ONE, mf);
        let n = |w: Vec3| if w.z < 0.0 { 1.5f32 } else { 1.0 };
        let mut checked = 0;
        for _ in 0..4000 {
            let (wi, wo) = (rng.dir(), rng.dir());
            // Grazing outside is the critical angle inside, where 1 - F is too sensitive to
            // compare f32 values computed from either end.
            if wi.z.abs().min(wo.z.abs()) < 0.05 {
                continue;
            }
            let rad = b.eval(wi, wo, Transport::Radiance);
            let rad_rev = b.eval(wo, wi, Transport::Radiance);
            // Importance is the adjoint of radiance: f*(wi, wo) = f(wo, wi).
            let imp = b.eval(wi, wo, Transport::Importance);
            assert!(
                close3(imp, rad_rev, 2e-3),
                "{mf:?} {wi} {wo}: {imp} vs {rad_rev}"
            );
            // f(wi, wo) / n(wo)^2 = f(wo, wi) / n(wi)^2.
            assert!(
                close3(rad / (n(wo) * n(wo)), rad_rev / (n(wi) * n(wi)), 2e-3),
                "{wi} {wo}"
            );
            if wi.z * wo.z < 0.0 && rad.x > 1e-3 {
                checked += 1;
                let ratio = rad.x / imp.x;
                assert!(
                    (ratio - (n(wo) / n(wi)).powi(2)).abs() < 1e-4,
                    "{wi} {wo} ratio {ratio}"
                );
            }
        }
        assert!(checked > 100, "{checked}");
    }
}

#[test]
fn diffuse_plus_lobe_is_the_whole() {
    let mut rng = TestRng(5);
    let mut all = reflective();
    all.extend(white().into_iter().map(|(_, b)| b));
    for b in all {
        for _ in 0..500 {
            let (wi, wo) = (rng.dir(), rng.dir());
            for t in [Transport::Radiance, Transport::Importance] {
                let same = wi.z * wo.z > 0.0;
                let fd = if same {
                    b.diffuse_out(wo) * b.store_weight(wi) / PI
                } else {
                    Vec3::ZERO
                };
                let sum = fd + b.eval_lobe(wi, wo, t);
                assert!(close3(b.eval(wi, wo, t), sum, 1e-5), "{b:?} {wi} {wo}");
            }
        }
        assert_eq!(
            b.has_diffuse(),
            matches!(b, Bsdf::Diffuse(_) | Bsdf::Plastic(_))
        );
        if !b.has_diffuse() {
            assert_eq!(b.diffuse_out(wo_at(30.0, 0.0)), Vec3::ZERO);
            assert_eq!(b.store_weight(wo_at(30.0, 0.0)), 0.0);
        }
        if !b.has_lobe() {
            assert!(b
                .sample_lobe(wo_at(30.0, 0.0), [0.5; 3], Transport::Radiance)
                .is_none());
        } else if b.lobe_is_delta() {
            let s = b
                .sample_lobe(wo_at(30.0, 0.0), [0.5; 3], Transport::Radiance)
                .unwrap();
            assert!(s.delta && s.pdf == 0.0);
            assert_eq!(
                b.eval_lobe(s.wi, wo_at(30.0, 0.0), Transport::Radiance),
                Vec3::ZERO
            );
        }
    }
}

#[test]
fn samplers_stay_finite() {
    // Grazing and normal incidence, extreme uniforms: no NaN, no negative weight or pdf.
    let mut rng = TestRng(123);
    let mut all = reflective();
    all.extend(white().into_iter().map(|(_, b)| b));
    let us = [0.0, 1e-7, 0.5, 0.999_999_9];
    for b in all {
        for i in 0..3000 {
            let mut wo = if i < 40 {
                Vec3::new(0.0, 0.0, 1.0)
            } else {
                rng.dir()
            };
            if i % 3 == 0 {
                // Nearly grazing.
                wo = Vec3::new(wo.x, wo.y, wo.z.signum() * 1e-4).normalize();
            }
            let u = if i < 64 {
                [us[i % 4], us[(i / 4) % 4], us[(i / 16) % 4]]
            } else {
                [rng.f32(), rng.f32(), rng.f32()]
            };
            for t in [Transport::Radiance, Transport::Importance] {
                for s in [b.sample(wo, u, t), b.sample_lobe(wo, u, t)]
                    .into_iter()
                    .flatten()
                {
                    let ok = s.wi.is_finite()
                        && (s.wi.length() - 1.0).abs() < 1e-3
                        && s.weight.is_finite()
                        && s.weight.min_element() >= 0.0
                        && s.pdf.is_finite()
                        && s.pdf >= 0.0;
                    assert!(ok, "{b:?} wo {wo} u {u:?}: {s:?}");
                }
                let wi = rng.dir();
                let (f, p) = (b.eval(wi, wo, t), b.pdf(wi, wo));
                assert!(f.is_finite() && f.min_element() >= 0.0 && p.is_finite() && p >= 0.0);
            }
        }
    }
}

/// White principled materials: (name, kind, whether it conserves energy). The metal and the
/// transmissive dielectric do (a GGX interface); Disney's diffuse with its retro-reflection,
/// sheen and clearcoat does not (its `(1 - Fo/2)(1 - Fi/2)` does not subtract the specular
/// reflection, and the retro-reflection grows towards grazing), in Mitsuba as here.
fn white_principled() -> Vec<(&'static str, Bsdf, bool)> {
    let make = |f: &dyn Fn(&mut Principled)| {
        let mut p = Principled::new();
        p.base_color = Param::rgb(Vec3::ONE);
        f(&mut p);
        Bsdf::Principled(p)
    };
    let c = Param::constant;
    vec![
        (
            "metal",
            make(&|p| {
                p.metallic = c(1.0);
                p.roughness = c(0.4);
            }),
            true,
        ),
        (
            "aniso metal",
            make(&|p| {
                p.metallic = c(1.0);
                p.roughness = c(0.45);
                p.anisotropic = c(0.5);
            }),
            true,
        ),
        (
            "glass",
            make(&|p| {
                p.spec_trans = c(1.0);
                p.roughness = c(0.4);
                p.eta = 1.5;
            }),
            true,
        ),
        (
            "disney",
            make(&|p| {
                p.roughness = c(0.7);
                p.sheen = c(1.0);
                p.clearcoat = c(1.0);
                p.clearcoat_gloss = c(0.5);
                p.spec_trans = c(0.3);
                p.flatness = c(0.3);
            }),
            false,
        ),
    ]
}

/// The principled BSDF's furnace: the energy-conserving cases reflect (and transmit) at most
/// what arrives and, away from grazing, nearly all of it; every case's albedo by Mitsuba's
/// sampler equals the quadrature of its eval, and so does the photon mapper's split (the
/// diffuse part by quadrature plus the lobe part by `sample_lobe`); the non-conserving Disney
/// mix stays below 1.25 (measured: 1.00 at normal incidence, 1.06 at 60 degrees, 1.20 at 85).
#[test]
fn principled_furnace() {
    for (name, b, conserving) in white_principled() {
        for deg in [0.0, 30.0, 60.0, 85.0] {
            for wo in [wo_at(deg, 20.0), -wo_at(deg, 20.0)] {
                let (a, err) = albedo_sampled(&b, wo, Transport::Importance, 40_000, 11);
                let q = albedo_quadrature(&b, wo, Transport::Importance);
                assert!(
                    (a - q).abs() < 4.0 * err + 3e-3,
                    "{name} wo {wo}: sampled {a} +- {err}, quadrature {q}"
                );
                if conserving {
                    assert!(a <= 1.0 + 4.0 * err + 2e-3, "{name} wo {wo}: albedo {a}");
                }
                // The metal is black from inside (Mitsuba's is one interface).
                let lit = wo.z > 0.0 || name == "glass" || name == "disney";
                // From inside, the Disney mix transmits and reflects only its spec_trans 0.3.
                let least = match (conserving, deg < 70.0, wo.z > 0.0) {
                    (true, true, _) => 0.85,
                    (false, _, false) => 0.15,
                    _ => 0.3,
                };
                if lit {
                    assert!(a > least, "{name} wo {wo}: albedo {a}");
                } else {
                    assert_eq!(a, 0.0, "{name} wo {wo}");
                }
                assert!(a < 1.25, "{name} wo {wo}: albedo {a}");
                assert_split(name, &b, wo, q, err);
            }
        }
    }
}

/// The thin principled BSDF's furnace (white): all glossy (`spec_trans` 1: a GGX reflection
/// and an unbent GGX transmission, `F + (1 - F)` less what masking loses) and all diffuse
/// transmission (`diff_trans` 2: Lambertian, exactly 1) conserve energy; the Disney mix with
/// sheen does not (as `principled_furnace`'s), below 1.25. Every case's albedo by Mitsuba's
/// sampler equals the quadrature of its eval, the photon mapper's split (diffuse part by
/// quadrature, lobe part by `sample_lobe`) equals it too, and the sheet is the same from both
/// sides (eval at mirrored directions, and the sampled albedo, bit for bit).
#[test]
fn principled_thin_furnace() {
    let make = |f: &dyn Fn(&mut PrincipledThin)| {
        let mut p = PrincipledThin::new();
        p.base_color = Param::rgb(Vec3::ONE);
        f(&mut p);
        Bsdf::PrincipledThin(p)
    };
    let c = Param::constant;
    let cases = [
        (
            "glossy",
            make(&|p| {
                // Transmission GGX alpha (0.625 * 0.55)^2 = 0.12: a sharper lobe at 85 degrees
                // outruns albedo_quadrature's grid (roughness 0.4 reads 0.729 where a 4x finer
                // grid and sampling read 0.699).
                p.spec_trans = c(1.0);
                p.roughness = c(0.55);
            }),
            Some(0.85),
        ),
        (
            "diffuse transmission",
            make(&|p| p.diff_trans = c(2.0)),
            Some(0.999),
        ),
        (
            "disney",
            make(&|p| {
                p.roughness = c(0.7);
                p.sheen = c(1.0);
                p.spec_trans = c(0.3);
                p.diff_trans = c(0.8);
                p.flatness = c(0.3);
                p.anisotropic = c(0.4);
            }),
            None,
        ),
    ];
    for (name, b, least) in cases {
        for deg in [0.0, 30.0, 60.0, 85.0] {
            let wo = wo_at(deg, 20.0);
            let (a, err) = albedo_sampled(&b, wo, Transport::Radiance, 40_000, 11);
            let q = albedo_quadrature(&b, wo, Transport::Radiance);
            assert!(
                (a - q).abs() < 4.0 * err + 3e-3,
                "{name} wo {wo}: sampled {a} +- {err}, quadrature {q}"
            );
            assert_eq!(
                (a, err),
                albedo_sampled(&b, -wo, Transport::Radiance, 40_000, 11),
                "{name}: the back differs"
            );
            let mut rng = TestRng(5);
            for _ in 0..100 {
                let wi = wo_at(rng.range(0.0, 180.0), rng.range(0.0, 360.0));
                assert_eq!(
                    b.eval(wi, wo, Transport::Radiance),
                    b.eval(-wi, -wo, Transport::Radiance)
                );
            }
            match least {
                Some(least) => {
                    assert!(a <= 1.0 + 4.0 * err + 2e-3, "{name} wo {wo}: albedo {a}");
                    if deg < 70.0 {
                        assert!(a > least, "{name} wo {wo}: albedo {a}");
                    }
                }
                None => assert!(a > 0.3 && a < 1.25, "{name} wo {wo}: albedo {a}"),
            }
            assert_split(name, &b, wo, q, err);
        }
    }
}

/// Photons at a thin principled sheet (`photon_bounce_at`, the photon tracer's scattering on
/// both backends' host side): from either face, the mean weight is the BSDF's albedo by
/// quadrature, and the part that continues through the sheet (towards the far side, the
/// sheet's medium unchanged, no refraction) is the quadrature over the far hemisphere; a
/// diffuse bounce stays on the near side. Four standard errors plus the quadrature's 3e-3.
#[test]
fn principled_thin_photon_bounce() {
    use gpu_photon::bsdfs::shading::{photon_bounce_at, Bounce};
    use gpu_photon::scene::Material;
    use gpu_photon::settings::FresnelMode;
    let mut k = PrincipledThin::new();
    k.base_color = Param::rgb(Vec3::new(0.9, 0.6, 0.3));
    k.roughness = Param::constant(0.6);
    k.spec_trans = Param::constant(0.4);
    k.diff_trans = Param::constant(0.8);
    k.sheen = Param::constant(0.5);
    k.eta = Param::constant(1.4);
    let (b, m) = (Bsdf::PrincipledThin(k), Material::of(k));
    // The albedo of the far side's hemisphere (`far`) or the whole sphere, by quadrature.
    let quadrature = |wo: Vec3, far: bool| {
        let (nt, np) = (600, 240);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let t = (i as f32 + 0.5) / nt as f32 * PI;
            for j in 0..np {
                let p = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let wi = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                if !far || wi.z * wo.z < 0.0 {
                    sum += (b.eval_cos(wi, wo, Transport::Importance).x * t.sin()) as f64;
                }
            }
        }
        sum * (PI / nt as f32) as f64 * (2.0 * PI / np as f32) as f64
    };
    for deg in [0.0f32, 40.0, 75.0] {
        for side in [1.0f32, -1.0] {
            let wo = wo_at(deg, 0.0) * side;
            let (d, n) = (-wo, Vec3::Z);
            let mut rng = TestRng(17);
            let count = 200_000;
            let (mut all, mut all2, mut through) = (0.0f64, 0.0f64, 0.0f64);
            for _ in 0..count {
                let u = [rng.f32(), rng.f32(), rng.f32()];
                let (dir, w) = match photon_bounce_at(&m, d, n, n, FresnelMode::Exact, u) {
                    Bounce::Absorb => continue,
                    Bounce::Diffuse { dir, weight } => {
                        assert!(dir.z * wo.z > 0.0, "a diffuse bounce through the sheet");
                        (dir, weight.x as f64)
                    }
                    Bounce::Specular { dir, weight, delta } => {
                        assert!(!delta);
                        (dir, weight.x as f64)
                    }
                };
                all += w;
                all2 += w * w;
                if dir.z * wo.z < 0.0 {
                    through += w;
                }
            }
            let mean = all / count as f64;
            let se = ((all2 / count as f64 - mean * mean) / count as f64).sqrt();
            let (q, q_far) = (quadrature(wo, false), quadrature(wo, true));
            let through = through / count as f64;
            assert!(
                (mean - q).abs() < 4.0 * se + 3e-3,
                "wo {wo}: photons keep {mean} +- {se}, the albedo is {q}"
            );
            assert!(
                (through - q_far).abs() < 4.0 * se + 3e-3,
                "wo {wo}: {through} passes the sheet, the far side's albedo is {q_far}"
            );
            assert!(q_far > 0.2, "wo {wo}: transmits {q_far}");
        }
    }
}

/// The photon mapper's split of `b` at `wo`: its diffuse part by quadrature plus its lobe part
/// by its own sampler equals the whole albedo `q` (sampled with standard error `err`).
#[track_caller]
fn assert_split(name: &str, b: &Bsdf, wo: Vec3, q: f32, err: f32) {
    let diffuse = split_diffuse_quadrature(b, wo);
    let mut rng = TestRng(3);
    let n = 40_000;
    let lobe: f64 = (0..n)
        .filter_map(|_| {
            let u = [rng.f32(), rng.f32(), rng.f32()];
            b.sample_lobe(wo, u, Transport::Importance)
        })
        .map(|s| s.weight.x as f64)
        .sum();
    let split = diffuse + (lobe / n as f64) as f32;
    assert!(
        (split - q).abs() < 4.0 * err + 5e-3,
        "{name} wo {wo}: diffuse {diffuse} + lobe = {split}, whole {q}"
    );
}

/// The diffuse part's albedo `diffuse_out(wo)` times the cosine-weighted mean of
/// `store_weight(wi)` over the hemisphere of `wo`, by quadrature.
fn split_diffuse_quadrature(b: &Bsdf, wo: Vec3) -> f32 {
    let n = 2000;
    let mut mean = 0.0f64;
    for i in 0..n {
        // cos theta_i = sqrt(u) makes the cosine weight uniform in u.
        let u = (i as f64 + 0.5) / n as f64;
        let wi = Vec3::new((1.0 - u).sqrt() as f32, 0.0, u.sqrt() as f32);
        mean += b.store_weight(if wo.z > 0.0 { wi } else { -wi }) as f64;
    }
    b.diffuse_out(wo).x * (mean / n as f64) as f32
}
