//! Chi-square goodness-of-fit of every BSDF sampler against its density, as Mitsuba's own
//! tests do: sampled directions are binned on a (theta, phi) grid over the whole sphere (theta
//! rather than cos theta so that the narrow transmitted lobes near the poles still span several
//! bins), expected counts come from integrating the pdf over each bin numerically, bins expecting
//! fewer than 5 are pooled, and delta or failed samples form one extra bin (expected: the
//! missing mass 1 - integral of the pdf). A fixed seed, p-value threshold 1e-3. Every
//! non-delta sample also checks `weight == eval |cos| / pdf` and `pdf == pdf(wi)`.

use glam::Vec3;
use gpu_photon::bsdfs::BsdfKind;
use gpu_photon::bsdfs::{
    Bsdf, Distribution, LobeSample, MetallicRoughness, Microfacet, Param, Plastic, Principled,
    PrincipledThin, Transport,
};
use std::f64::consts::PI;

const N_THETA: usize = 48;
const N_PHI: usize = 64;
const SAMPLES: usize = 200_000;
const SUB: usize = 8;

mod common;

use common::TestRng;

fn ln_gamma(x: f64) -> f64 {
    // Lanczos approximation (g = 7, n = 9).
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Upper regularised incomplete gamma Q(a, x): the chi-square p-value is Q(dof/2, chi2/2).
fn gamma_q(a: f64, x: f64) -> f64 {
    if x < a + 1.0 {
        let (mut sum, mut term, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - ln_gamma(a)).exp()
    } else {
        // Lentz's continued fraction.
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - ln_gamma(a)).exp() * h
    }
}

fn dir(theta: f64, phi: f64) -> Vec3 {
    let s = theta.sin();
    Vec3::new(
        (s * phi.cos()) as f32,
        (s * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

fn bin_of(w: Vec3) -> usize {
    let c = ((w.z as f64).clamp(-1.0, 1.0).acos() / PI * N_THETA as f64) as usize;
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let p = (phi / (2.0 * PI) * N_PHI as f64) as usize;
    c.min(N_THETA - 1) * N_PHI + p.min(N_PHI - 1)
}

/// Runs the chi-square test and the weight checks for one sampler; panics with a message.
fn chi2(
    name: &str,
    check_weights: bool,
    sample: impl Fn([f32; 3]) -> Option<LobeSample>,
    pdf: impl Fn(Vec3) -> f32,
    eval_cos: impl Fn(Vec3) -> Vec3,
) {
    let mut rng = TestRng(0x5EED ^ (name.len() as u64 * 7919));
    let mut observed = vec![0.0f64; N_THETA * N_PHI + 1];
    let mut weight_errors = 0;
    let mut worst = String::new();
    for _ in 0..SAMPLES {
        let u = [rng.f32(), rng.f32(), rng.f32()];
        match sample(u) {
            Some(s) if !s.delta => {
                observed[bin_of(s.wi)] += 1.0;
                let p = pdf(s.wi);
                let expect = eval_cos(s.wi) / p;
                let tol = 2e-3 * expect.max_element().max(s.weight.max_element()) + 1e-6;
                let bad_w = (s.weight - expect).abs().max_element() > tol;
                let bad_p = (s.pdf - p).abs() > 2e-3 * p.max(s.pdf) + 1e-6;
                if check_weights && (bad_w || bad_p || !s.weight.is_finite()) {
                    weight_errors += 1;
                    worst = format!(
                        "wi {} weight {} vs {expect}, pdf {} vs {p}",
                        s.wi, s.weight, s.pdf
                    );
                }
            }
            _ => observed[N_THETA * N_PHI] += 1.0,
        }
    }
    assert!(
        weight_errors <= SAMPLES / 10_000,
        "{name}: {weight_errors} bad weights, e.g. {worst}"
    );
    // Expected counts: midpoint rule with SUB x SUB points per bin.
    let mut expected = vec![0.0f64; N_THETA * N_PHI + 1];
    let (dt, dp) = (PI / N_THETA as f64, 2.0 * PI / N_PHI as f64);
    let mut total = 0.0;
    for i in 0..N_THETA {
        for j in 0..N_PHI {
            let mut sum = 0.0;
            for a in 0..SUB {
                for b in 0..SUB {
                    let t = (i as f64 + (a as f64 + 0.5) / SUB as f64) * dt;
                    let p = (j as f64 + (b as f64 + 0.5) / SUB as f64) * dp;
                    sum += pdf(dir(t, p)) as f64 * t.sin();
                }
            }
            let e = sum / (SUB * SUB) as f64 * dt * dp * SAMPLES as f64;
            expected[i * N_PHI + j] = e;
            total += e;
        }
    }
    assert!(
        total <= SAMPLES as f64 * 1.01,
        "{name}: the pdf integrates to {}",
        total / SAMPLES as f64
    );
    expected[N_THETA * N_PHI] = (SAMPLES as f64 - total).max(0.0);
    // Pool the bins expecting < 5, smallest first, as Mitsuba's chi2 test.
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].partial_cmp(&expected[b]).unwrap());
    let (mut chi2, mut dof, mut pool_e, mut pool_o) = (0.0, 0i64, 0.0, 0.0);
    for &k in &order {
        if expected[k] == 0.0 && observed[k] > 0.0 && k != N_THETA * N_PHI {
            // Samples where the pdf says none can be: allow only rounding at bin edges.
            assert!(
                observed[k] <= 3.0,
                "{name}: {} samples in bin {k} of zero density",
                observed[k]
            );
        }
        if expected[k] < 5.0 {
            pool_e += expected[k];
            pool_o += observed[k];
            if pool_e >= 5.0 {
                chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
                dof += 1;
                pool_e = 0.0;
                pool_o = 0.0;
            }
        } else {
            chi2 += (observed[k] - expected[k]).powi(2) / expected[k];
            dof += 1;
        }
    }
    if pool_e > 0.0 {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e.max(5.0);
        dof += 1;
    }
    let p = gamma_q((dof - 1).max(1) as f64 / 2.0, chi2 / 2.0);
    if std::env::var_os("BSDF_CHI2_VERBOSE").is_some() {
        eprintln!(
            "{name}: chi2 {chi2:.1}, {} dof, p = {p:.3}, missing mass {:.4}",
            dof - 1,
            1.0 - total / SAMPLES as f64
        );
    }
    assert!(
        p > 1e-3,
        "{name}: chi2 {chi2:.1} with {} dof, p = {p:.2e}",
        dof - 1
    );
}

/// Tests `sample` against `pdf`, and `sample_lobe` against `pdf_lobe` where it differs.
fn check(name: &str, b: &Bsdf, wo: Vec3, transport: Transport) {
    chi2(
        &format!("{name} sample wo {wo}"),
        true,
        |u| b.sample(wo, u, transport),
        |wi| b.pdf(wi, wo),
        |wi| b.eval_cos(wi, wo, transport),
    );
    if b.has_diffuse() && b.has_lobe() && !b.lobe_is_delta() {
        chi2(
            &format!("{name} sample_lobe wo {wo}"),
            true,
            |u| b.sample_lobe(wo, u, transport),
            |wi| b.pdf_lobe(wi, wo),
            |wi| b.eval_lobe(wi, wo, transport) * wi.z.abs(),
        );
    }
}

fn wo_at(deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

const ANGLES: [f32; 3] = [10.0, 45.0, 75.0];

fn roughness() -> Vec<(&'static str, Microfacet)> {
    let mut v = Vec::new();
    for (n, d) in [
        ("ggx", Distribution::Ggx),
        ("beckmann", Distribution::Beckmann),
    ] {
        v.push((n, Microfacet::isotropic(d, 0.3)));
        v.push((n, Microfacet::new(d, 0.15, 0.5)));
    }
    v
}

#[test]
fn chi2_diffuse() {
    let b = Bsdf::diffuse(Vec3::new(0.8, 0.5, 0.2));
    check("diffuse", &b, wo_at(30.0, 10.0), Transport::Radiance);
    check("diffuse back", &b, -wo_at(30.0, 10.0), Transport::Radiance);
}

#[test]
fn chi2_rough_conductor() {
    for (name, mf) in roughness() {
        let b = Bsdf::conductor(
            Vec3::new(0.2, 0.9, 1.5),
            Vec3::new(3.9, 2.4, 1.6),
            Vec3::ONE,
            Some(mf),
        );
        for deg in ANGLES {
            check(
                &format!("conductor {name} {mf:?}"),
                &b,
                wo_at(deg, 30.0),
                Transport::Radiance,
            );
        }
        check(
            &format!("conductor back {name}"),
            &b,
            -wo_at(40.0, 70.0),
            Transport::Radiance,
        );
    }
}

#[test]
fn chi2_rough_dielectric() {
    for (name, mf) in roughness() {
        let b = Bsdf::dielectric(1.5, Vec3::ONE, Vec3::ONE, Some(mf));
        for deg in ANGLES {
            let wo = wo_at(deg, 30.0);
            check(
                &format!("dielectric {name} {mf:?} outside"),
                &b,
                wo,
                Transport::Radiance,
            );
            let inside = Vec3::new(wo.x, wo.y, -wo.z);
            check(
                &format!("dielectric {name} {mf:?} inside"),
                &b,
                inside,
                Transport::Importance,
            );
        }
    }
}

#[test]
fn chi2_plastic() {
    for d in [Distribution::Ggx, Distribution::Beckmann] {
        let p = Plastic::new(
            Vec3::new(0.6, 0.3, 0.1),
            Vec3::ONE,
            1.5,
            false,
            Some(Microfacet::isotropic(d, 0.3)),
        );
        for deg in ANGLES {
            check(
                &format!("roughplastic {d:?}"),
                &Bsdf::Plastic(p),
                wo_at(deg, 30.0),
                Transport::Radiance,
            );
        }
    }
    let p = Plastic::new(Vec3::new(0.6, 0.3, 0.1), Vec3::ONE, 1.5, true, None);
    for deg in ANGLES {
        check(
            "plastic",
            &Bsdf::Plastic(p),
            wo_at(deg, 30.0),
            Transport::Radiance,
        );
    }
}

/// glTF metallic-roughness materials: a dielectric, a metal, a mix with thin transmission
/// (both lobes and the diffuse base), and a viewer below the surface.
#[test]
fn chi2_metallic_roughness() {
    let g = |metallic, roughness, transmission| {
        let (base, f0) = (Vec3::new(0.8, 0.5, 0.2), Vec3::new(0.04, 0.05, 0.03));
        Bsdf::MetallicRoughness(MetallicRoughness::new(
            base,
            metallic,
            roughness,
            f0,
            1.0,
            transmission,
        ))
    };
    for (name, b) in [
        ("dielectric", g(0.0, 0.5, 0.0)),
        ("metal", g(1.0, 0.4, 0.0)),
        ("mixed thin", g(0.3, 0.6, 0.5)),
    ] {
        for deg in ANGLES {
            check(name, &b, wo_at(deg, 30.0), Transport::Radiance);
        }
        check(name, &b, -wo_at(40.0, 70.0), Transport::Importance);
    }
}

/// Mitsuba's principled BSDF: a dielectric with clearcoat and sheen, an anisotropic metal,
/// a transmissive one seen from both sides (the viewer inside too), a flat one; `sample`
/// against `pdf` and `sample_lobe` (the traced part) against `pdf_lobe`.
#[test]
fn chi2_principled() {
    let make = |f: &dyn Fn(&mut Principled)| {
        let mut p = Principled::new();
        p.base_color = Param::rgb(Vec3::new(0.8, 0.5, 0.2));
        f(&mut p);
        Bsdf::Principled(p)
    };
    let c = Param::constant;
    let cases = [
        (
            "principled coat sheen",
            make(&|p| {
                p.roughness = c(0.4);
                p.clearcoat = c(0.8);
                p.clearcoat_gloss = c(0.3);
                p.sheen = c(0.6);
                p.spec_tint = c(0.5);
            }),
            false,
        ),
        (
            "principled aniso metal",
            make(&|p| {
                p.metallic = c(0.8);
                p.roughness = c(0.35);
                p.anisotropic = c(0.7);
            }),
            false,
        ),
        (
            "principled transmission",
            make(&|p| {
                p.spec_trans = c(0.8);
                p.roughness = c(0.3);
                p.clearcoat = c(0.4);
                p.eta = 1.45;
            }),
            true,
        ),
        (
            "principled two-sided",
            make(&|p| {
                p.two_sided = true;
                p.roughness = c(0.4);
                p.sheen = c(0.5);
                p.clearcoat = c(0.5);
            }),
            true,
        ),
        (
            "principled flat",
            make(&|p| {
                p.flatness = c(0.7);
                p.roughness = c(0.8);
                p.spec_trans = c(0.3);
            }),
            true,
        ),
    ];
    for (name, b, inside) in cases {
        for deg in ANGLES {
            check(name, &b, wo_at(deg, 30.0), Transport::Radiance);
        }
        if inside {
            check(name, &b, -wo_at(40.0, 70.0), Transport::Importance);
            check(name, &b, -wo_at(10.0, 20.0), Transport::Radiance);
        }
    }
}

/// Mitsuba's thin principled BSDF: glossy reflection and transmission (anisotropic, with
/// sheen), nearly all glossy, and diffuse only (no `spec_trans`, flat), each seen from both
/// sides; `sample` against `pdf` and `sample_lobe` against `pdf_lobe`.
#[test]
fn chi2_principled_thin() {
    let make = |f: &dyn Fn(&mut PrincipledThin)| {
        let mut p = PrincipledThin::new();
        p.base_color = Param::rgb(Vec3::new(0.8, 0.5, 0.2));
        f(&mut p);
        Bsdf::PrincipledThin(p)
    };
    let c = Param::constant;
    let cases = [
        (
            "principledthin glossy sheen",
            make(&|p| {
                p.spec_trans = c(0.5);
                p.diff_trans = c(0.6);
                p.roughness = c(0.4);
                p.anisotropic = c(0.6);
                p.sheen = c(0.6);
                p.spec_tint = c(0.5);
                p.eta = c(1.45);
            }),
        ),
        (
            "principledthin glossy",
            make(&|p| {
                // Transmission GGX alpha (0.625 * 0.55)^2 = 0.12: sharper lobes than the
                // bins' numerical integration resolves at 75 degrees.
                p.spec_trans = c(0.9);
                p.roughness = c(0.55);
                p.eta = c(1.5);
            }),
        ),
        (
            "principledthin diffuse flat",
            make(&|p| {
                p.diff_trans = c(1.2);
                p.flatness = c(0.6);
                p.roughness = c(0.7);
            }),
        ),
    ];
    for (name, b) in cases {
        for deg in ANGLES {
            check(name, &b, wo_at(deg, 30.0), Transport::Radiance);
        }
        check(name, &b, -wo_at(40.0, 70.0), Transport::Importance);
        check(name, &b, -wo_at(10.0, 20.0), Transport::Radiance);
    }
}

#[test]
fn chi2_catches_a_wrong_pdf() {
    // The test must be able to fail: a GGX sampler judged by the Beckmann density.
    let ggx = Bsdf::conductor(
        Vec3::ZERO,
        Vec3::ONE,
        Vec3::ONE,
        Some(Microfacet::isotropic(Distribution::Ggx, 0.3)),
    );
    let beckmann = Bsdf::conductor(
        Vec3::ZERO,
        Vec3::ONE,
        Vec3::ONE,
        Some(Microfacet::isotropic(Distribution::Beckmann, 0.3)),
    );
    let wo = wo_at(45.0, 0.0);
    let r = std::panic::catch_unwind(|| {
        chi2(
            "wrong pdf",
            false,
            |u| ggx.sample(wo, u, Transport::Radiance),
            |wi| beckmann.pdf(wi, wo),
            |wi| beckmann.eval_cos(wi, wo, Transport::Radiance),
        )
    });
    let msg = r.expect_err("the chi-square test accepted a wrong density");
    let msg = msg.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(
        msg.contains("chi2") || msg.contains("zero density"),
        "{msg}"
    );
}
