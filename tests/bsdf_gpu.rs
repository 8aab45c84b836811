//! Oracle test of the BSDF library on the device (`src/bsdfs/*.wgsl` and the dispatch generated
//! from the list of kinds) against `src/bsdfs/`: the probe `tests/probes/probe_bsdf.wgsl` runs
//! every method of the interface (eval, pdf, the lobe's, sample, sample_lobe, diffuse_out,
//! store_weight, and the microfacet, Fresnel and erf helpers) on a few thousand (wi, wo, u)
//! cases over every kind of the list (a kind missing from [`bsdfs`] fails the test), each
//! material's BSDF as the scene buffers pack it, and each value is compared with the Rust
//! method on the same bits: relative error at most 1e-4, looser only for sampled quantities
//! where the sampler itself amplifies a few ulp of the device's sqrt/exp/log/sin/cos (near
//! grazing, in the erfinv tail of a Beckmann sample: see `tol_z`, `TOL_TAIL`,
//! `BECKMANN_FACTOR`) and for erf near 0 (`ERF_ABS`), and identical ok /
//! delta flags except within 1e-5 of a decision boundary (those samples are skipped).
//! Without a Vulkan adapter the test is skipped (CI fails instead, see common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::{Vec2, Vec3};
use gpu_photon::bsdfs::math::{erf, erfinv, mulsign, square_to_cosine_hemisphere};
use gpu_photon::bsdfs::BsdfKind;
use gpu_photon::bsdfs::{
    fresnel_conductor, fresnel_dielectric, Bsdf, Distribution, LobeSample, MetallicRoughness,
    Microfacet, Param, Plastic, Principled, PrincipledThin, Transport, KINDS,
};
use gpu_photon::integrators::gpu::GpuContext;
use gpu_photon::scene::{Material, Scene};
use std::collections::BTreeMap;

/// vec4 slots the probe writes per case (`BSDF_PROBE_OUT` in probe_bsdf.wgsl), after its six
/// input slots.
const SLOTS: usize = 12;
/// Input slots per case.
const INPUTS: usize = 6;
/// Seed of the cases.
const SEED: u64 = 0xb5df;
/// Cases per BSDF.
const PER_BSDF: usize = 1000;
/// Relative tolerance.
const TOL: f32 = 1e-4;
/// Near the horizon a direction's z comes from `1 - x^2 - y^2` (the cosine hemisphere, the
/// GGX visible normals, both lifting a point of the unit disk) and Fresnel's `1 - F`
/// cancels: an error of a few ulp of 1 in x, y (the device's sin/cos/sqrt) becomes
/// ~1e-7 / z^2 relative in z and in the pdf. The bound is 1e-4 down to z = 0.1 and grows as
/// 1e-6 / z^2 below (1e-2 at z = 0.01), for what a sampler gives (its wi, weight, pdf, the
/// visible normal and its density), z the smallest of |wo.z|, the sample's |wi.z| and the
/// lifted disk point's height. Values at given directions (eval, pdf, the lobe's, the
/// microfacet and Fresnel terms, diffuse_out, store_weight) are held to 1e-4, grazing or not.
fn tol_z(z: f32) -> f32 {
    TOL.max(GRAZING_ABS / (z * z))
}
const GRAZING_ABS: f32 = 1e-6;
/// Beckmann visible normals with `u[1]` or `u[2]` within 1e-3 of 0 or 1: erfinv's slope
/// `sqrt(pi)/2 exp(erfinv(x)^2)` in the tails (and D's `exp(-tan^2 / alpha^2)` after it)
/// amplify the device's few-ulp exp/log in the Newton steps ~10x.
const TOL_TAIL: f32 = 1e-3;
/// A Beckmann visible normal comes from a Newton inversion through erf, erfinv, exp and log
/// (GGX's is closed form): its m differs by up to ~2e-5 instead of ~1e-7, and a grazing
/// wo's small `wo . m` in the density turns that into `2e-5 / (wo . m)`; the grazing bound
/// of what a Beckmann sample gives is 10x `tol_z` (still 1e-4 above z = 0.32).
const BECKMANN_FACTOR: f32 = 10.0;
/// erf(x) is `1 - erfc` (the rational fit): its error is absolute, ~ulp(1), so near x = 0
/// the relative error of either side is large; compared to 1e-6 absolute.
const ERF_ABS: f32 = 1e-6;
/// The principled BSDF's samples weigh `eval / pdf` (Mitsuba's sampler), two values each
/// rounded like a sampled direction's: their bound is twice the sampler's (measured: 1.008e-4
/// at a transmission through a GGX normal from u[2] = 0.003, z = 0.11, against 1e-4).
const RATIO_FACTOR: f32 = 2.0;
/// Distance to a decision threshold within which the two sides may decide differently.
const BOUNDARY: f32 = 1e-5;

/// One case: directions, uniforms and the BSDF's index (its material's).
#[derive(Clone, Copy, Debug, Default)]
struct ProbeCase {
    wi: [f32; 3],
    bsdf: u32,
    wo: [f32; 3],
    radiance: u32,
    u: [f32; 3],
}

fn bsdfs() -> Vec<(&'static str, Bsdf)> {
    let (eta, k) = (Vec3::new(0.2, 0.92, 1.1), Vec3::new(3.9, 2.45, 2.14));
    let spec = Vec3::new(0.95, 0.9, 1.0);
    let cond = |mf| Bsdf::conductor(eta, k, spec, mf);
    let diel =
        |eta, mf| Bsdf::dielectric(eta, Vec3::new(0.9, 1.0, 0.95), Vec3::new(1.0, 0.8, 0.9), mf);
    let (kd, ks) = (Vec3::new(0.5, 0.3, 0.2), Vec3::new(1.0, 0.9, 0.8));
    let plastic = |nonlinear, mf| Bsdf::Plastic(Plastic::new(kd, ks, 1.5, nonlinear, mf));
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
    let principled = |f: &dyn Fn(&mut Principled)| {
        let mut p = Principled::new();
        p.base_color = Param::rgb(Vec3::new(0.7, 0.4, 0.2));
        f(&mut p);
        Bsdf::Principled(p)
    };
    let thin = |f: &dyn Fn(&mut PrincipledThin)| {
        let mut p = PrincipledThin::new();
        p.base_color = Param::rgb(Vec3::new(0.7, 0.4, 0.2));
        f(&mut p);
        Bsdf::PrincipledThin(p)
    };
    use Distribution::{Beckmann, Ggx};
    vec![
        ("diffuse", Bsdf::diffuse(Vec3::new(0.7, 0.5, 0.3))),
        (
            "phong",
            Bsdf::Phong(gpu_photon::bsdfs::phong::Phong::new(
                Vec3::new(0.4, 0.3, 0.2),
                Vec3::new(0.3, 0.4, 0.5),
                30.0,
            )),
        ),
        (
            "mirror",
            Bsdf::Mirror(gpu_photon::bsdfs::mirror::Mirror::new(Vec3::new(
                0.9, 0.8, 0.7,
            ))),
        ),
        ("conductor", cond(None)),
        (
            "roughconductor ggx iso",
            cond(Some(Microfacet::isotropic(Ggx, 0.3))),
        ),
        (
            "roughconductor ggx aniso",
            cond(Some(Microfacet::new(Ggx, 0.1, 0.4))),
        ),
        (
            "roughconductor beckmann iso",
            cond(Some(Microfacet::isotropic(Beckmann, 0.25))),
        ),
        (
            "roughconductor beckmann aniso",
            cond(Some(Microfacet::new(Beckmann, 0.5, 0.15))),
        ),
        ("dielectric", diel(1.5, None)),
        (
            "roughdielectric ggx",
            diel(1.5, Some(Microfacet::isotropic(Ggx, 0.2))),
        ),
        (
            "roughdielectric beckmann aniso",
            diel(1.33, Some(Microfacet::new(Beckmann, 0.3, 0.1))),
        ),
        (
            "roughdielectric ggx eta<1",
            diel(1.0 / 1.5, Some(Microfacet::isotropic(Ggx, 0.4))),
        ),
        (
            "thindielectric",
            Bsdf::thin_dielectric(1.5, Vec3::new(0.9, 1.0, 0.95), Vec3::new(1.0, 0.8, 0.9)),
        ),
        ("plastic", plastic(false, None)),
        ("plastic nonlinear", plastic(true, None)),
        (
            "roughplastic ggx",
            plastic(false, Some(Microfacet::isotropic(Ggx, 0.1))),
        ),
        (
            "roughplastic beckmann nonlinear",
            plastic(true, Some(Microfacet::isotropic(Beckmann, 0.3))),
        ),
        ("gltf dielectric", gltf(0.0, 0.5, 0.0)),
        ("gltf metal", gltf(1.0, 0.3, 0.0)),
        ("gltf mixed thin", gltf(0.4, 0.6, 0.7)),
        (
            "principled metal clearcoat sheen",
            principled(&|p| {
                p.metallic = Param::constant(0.6);
                p.roughness = Param::constant(0.3);
                p.clearcoat = Param::constant(0.8);
                p.clearcoat_gloss = Param::constant(0.5);
                p.sheen = Param::constant(0.7);
                p.sheen_tint = Param::constant(0.5);
                p.spec_tint = Param::constant(0.4);
            }),
        ),
        (
            "principled transmission aniso",
            principled(&|p| {
                p.spec_trans = Param::constant(0.7);
                p.roughness = Param::constant(0.2);
                p.anisotropic = Param::constant(0.6);
                p.clearcoat = Param::constant(0.3);
                p.eta = 1.45;
            }),
        ),
        (
            "principled two-sided",
            principled(&|p| {
                p.two_sided = true;
                p.roughness = Param::constant(0.4);
                p.metallic = Param::constant(0.3);
                p.sheen = Param::constant(0.5);
                p.clearcoat = Param::constant(0.5);
            }),
        ),
        (
            "principled flat",
            principled(&|p| {
                p.flatness = Param::constant(0.5);
                p.roughness = Param::constant(0.7);
                p.spec_trans = Param::constant(0.2);
                p.metallic = Param::constant(0.1);
            }),
        ),
        (
            "principledthin glossy sheen",
            thin(&|p| {
                p.spec_trans = Param::constant(0.6);
                p.diff_trans = Param::constant(0.8);
                p.roughness = Param::constant(0.3);
                p.anisotropic = Param::constant(0.5);
                p.eta = Param::constant(1.45);
                p.sheen = Param::constant(0.6);
                p.sheen_tint = Param::constant(0.5);
                p.spec_tint = Param::constant(0.4);
            }),
        ),
        (
            "principledthin diffuse flat",
            thin(&|p| {
                p.diff_trans = Param::constant(1.4);
                p.roughness = Param::constant(0.7);
                p.flatness = Param::constant(0.5);
            }),
        ),
    ]
}

fn microfacet_of(b: &Bsdf) -> Option<Microfacet> {
    match b {
        Bsdf::RoughConductor(c) => Some(c.microfacet()),
        Bsdf::RoughDielectric(d) => Some(d.microfacet()),
        Bsdf::Plastic(p) => p.microfacet,
        Bsdf::MetallicRoughness(g) => Some(g.microfacet()),
        Bsdf::Principled(p) => Some(p.microfacet()),
        Bsdf::PrincipledThin(p) => Some(p.microfacet()),
        _ => None,
    }
}

fn eta_of(b: &Bsdf) -> Option<f32> {
    match b {
        Bsdf::Glass(g) => Some(g.eta),
        Bsdf::RoughDielectric(d) => Some(d.eta),
        Bsdf::ThinDielectric(t) => Some(t.eta),
        Bsdf::Plastic(p) => Some(p.eta),
        Bsdf::Principled(p) => Some(p.eta),
        Bsdf::PrincipledThin(p) => Some(p.eta.float()),
        _ => None,
    }
}

/// A conductor's complex index.
fn conductor_of(b: &Bsdf) -> Option<(Vec3, Vec3)> {
    match b {
        Bsdf::Conductor(c) => Some((c.eta, c.k)),
        Bsdf::RoughConductor(c) => Some((c.eta, c.k)),
        _ => None,
    }
}

fn uniform_sphere(r: &mut TestRng) -> Vec3 {
    let z = r.range(-1.0, 1.0);
    let phi = r.range(0.0, std::f32::consts::TAU);
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// A direction within `max_z` of the horizon, either side.
fn grazing(r: &mut TestRng, max_z: f32) -> Vec3 {
    let z = r.range(-max_z, max_z);
    let phi = r.range(0.0, std::f32::consts::TAU);
    let s = (1.0 - z * z).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

fn transport(radiance: bool) -> Transport {
    if radiance {
        Transport::Radiance
    } else {
        Transport::Importance
    }
}

/// The cases of one BSDF: mostly uniform wo (a few at normal incidence or near grazing), wi
/// half the time the Rust lobe's (or whole BSDF's) sample so that glossy values are large.
fn cases_of(index: u32, b: &Bsdf, r: &mut TestRng) -> Vec<ProbeCase> {
    (0..PER_BSDF)
        .map(|i| {
            let radiance = i % 2 == 0;
            let wo = match i % 20 {
                0 => Vec3::new(0.0, 0.0, if i % 40 == 0 { 1.0 } else { -1.0 }),
                1 | 2 => grazing(r, 1e-2),
                _ => uniform_sphere(r),
            };
            let u = [r.f32(), r.f32(), r.f32()];
            let t = transport(radiance);
            let sampled = if i % 4 < 2 {
                b.sample_lobe(wo, u, t).or_else(|| b.sample(wo, u, t))
            } else {
                b.sample(wo, u, t)
            };
            let wi = match sampled {
                Some(s) if i % 2 == 1 || i % 3 == 0 => s.wi,
                _ => uniform_sphere(r),
            };
            ProbeCase {
                wi: wi.to_array(),
                bsdf: index,
                wo: wo.to_array(),
                radiance: radiance as u32,
                u,
            }
        })
        .collect()
}

/// Runs the probe over `cases` on a scene whose materials are `bsdfs` (packed as a render
/// packs them): each case's [`SLOTS`] outputs, in order.
fn run_probe(ctx: &GpuContext, bsdfs: &[Bsdf], cases: &[ProbeCase]) -> Vec<[f32; 4]> {
    let mut scene = Scene::empty();
    scene.materials = bsdfs.iter().map(|&b| Material::of(b)).collect();
    let n = cases.len();
    let mut init = vec![[0f32; 4]; (INPUTS + SLOTS) * n];
    for (i, c) in cases.iter().enumerate() {
        let b = &bsdfs[c.bsdf as usize];
        init[i] = [c.wi[0], c.wi[1], c.wi[2], f32::from_bits(c.bsdf)];
        init[n + i] = [c.wo[0], c.wo[1], c.wo[2], c.radiance as f32];
        init[2 * n + i] = [c.u[0], c.u[1], c.u[2], 0.0];
        let mf = microfacet_of(b).unwrap_or(Microfacet::isotropic(Distribution::Ggx, 0.3));
        let code = match mf.distribution {
            Distribution::Ggx => gpu_photon::bsdfs::microfacet::MF_GGX,
            Distribution::Beckmann => gpu_photon::bsdfs::microfacet::MF_BECKMANN,
        };
        init[3 * n + i] = [
            f32::from_bits(code),
            mf.alpha_u,
            mf.alpha_v,
            eta_of(b).unwrap_or(1.5),
        ];
        let (eta, k) = conductor_of(b).unwrap_or((Vec3::ONE, Vec3::ONE));
        init[4 * n + i] = [eta.x, eta.y, eta.z, 0.0];
        init[5 * n + i] = [k.x, k.y, k.z, 0.0];
    }
    let out = probes::probe_cases(ctx, &scene, "probe_bsdf", &init, n).unwrap();
    let mut per_case = Vec::with_capacity(n * SLOTS);
    for i in 0..n {
        per_case.extend((0..SLOTS).map(|k| out[(INPUTS + k) * n + i]));
    }
    per_case
}

/// Collects mismatches and the largest relative error per (kind, quantity).
struct Checker {
    errors: Vec<String>,
    worst: BTreeMap<(String, &'static str), f32>,
    skipped: usize,
    /// The current case's inputs, for the messages.
    inputs: String,
    /// Per kind: samples compared (both sides some), and nonzero eval values compared.
    coverage: BTreeMap<String, (usize, usize)>,
}

/// Vulkan lets a device flush subnormal results to zero (lavapipe does): a Phong lobe of a
/// high exponent far from its axis is 1e-40 in Rust and 0 on the device.
fn flush(x: f32) -> f32 {
    if x.abs() < f32::MIN_POSITIVE {
        0.0
    } else {
        x
    }
}

fn rel(a: f32, b: f32) -> f32 {
    let (a, b) = (flush(a), flush(b));
    if a == b {
        return 0.0;
    }
    if !a.is_finite() || !b.is_finite() {
        return f32::INFINITY;
    }
    (a - b).abs() / a.abs().max(b.abs())
}

fn rel3(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.map(flush), b.map(flush));
    if a == b {
        return 0.0;
    }
    if !a.is_finite() || !b.is_finite() {
        return f32::INFINITY;
    }
    (a - b).abs().max_element() / a.abs().max_element().max(b.abs().max_element())
}

impl Checker {
    fn note(
        &mut self,
        kind: &str,
        what: &'static str,
        case: usize,
        err: f32,
        tol: f32,
        detail: String,
    ) {
        let w = self.worst.entry((kind.to_string(), what)).or_insert(0.0);
        *w = w.max(err);
        if err.is_nan() || err > tol {
            self.errors.push(format!(
                "{kind} case {case} {what}: rel err {err:e} > {tol:e}: {detail} ({})",
                self.inputs
            ));
        }
    }

    fn f(&mut self, kind: &str, what: &'static str, case: usize, want: f32, got: f32, tol: f32) {
        self.note(
            kind,
            what,
            case,
            rel(want, got),
            tol,
            format!("rust {want:e} wgsl {got:e}"),
        );
    }

    fn v(&mut self, kind: &str, what: &'static str, case: usize, want: Vec3, got: Vec3, tol: f32) {
        self.note(
            kind,
            what,
            case,
            rel3(want, got),
            tol,
            format!("rust {want} wgsl {got}"),
        );
    }

    /// A sampled lobe: flags equal (unless `near` a decision boundary, then skipped), and
    /// when it is a sample, the same wi, weight and pdf.
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &mut self,
        kind: &str,
        what: &'static str,
        case: usize,
        want: Option<LobeSample>,
        got: &[[f32; 4]],
        tol: f32,
        near: bool,
    ) {
        let flags = got[1][3] as u32;
        let (ok, delta) = (flags & 1 != 0, flags & 2 != 0);
        let same = match want {
            None => !ok,
            Some(s) => ok && s.delta == delta,
        };
        if near {
            self.skipped += 1;
            return;
        }
        if !same {
            self.errors.push(format!(
                "{kind} case {case} {what}: flags rust {want:?} wgsl ok {ok} delta {delta} ({})",
                self.inputs
            ));
            return;
        }
        if let Some(s) = want {
            self.coverage.entry(kind.to_string()).or_default().0 += 1;
            let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
            self.v(kind, what, case, s.wi, v(got[0]), tol);
            self.v(kind, what, case, s.weight, v(got[1]), tol);
            self.f(kind, what, case, s.pdf, got[0][3], tol);
        }
    }
}

/// Whether a sampler's branch or validity decision for this case lies within BOUNDARY of
/// its threshold on the Rust side: `u[0]` against the Fresnel reflectance or the plastic's
/// coating probability, the sampled direction against the horizon, the density against 0.
fn near_boundary(b: &Bsdf, wo: Vec3, u: [f32; 3], samples: &[Option<LobeSample>]) -> bool {
    let close = |x: f32| x.abs() < BOUNDARY;
    for s in samples.iter().flatten() {
        if close(s.wi.z) || (!s.delta && close(s.pdf)) {
            return true;
        }
    }
    let wof = mulsign(wo, wo.z);
    match b {
        Bsdf::Glass(g) => close(u[0] - fresnel_dielectric(wo.z, g.eta).0),
        Bsdf::RoughDielectric(d) => {
            let (m, _) = d.microfacet().sample_visible(wof, Vec2::new(u[1], u[2]));
            close(u[0] - fresnel_dielectric(wo.dot(m), d.eta).0)
        }
        Bsdf::ThinDielectric(t) => {
            let r = fresnel_dielectric(wo.z.abs(), t.eta).0;
            close(u[0] - r * 2.0 / (1.0 + r))
        }
        Bsdf::Plastic(p) => {
            let t = p.transmittance(wo.z.abs());
            let ssw = p.specular_sampling_weight;
            let (ps, pd) = ((1.0 - t) * ssw, t * (1.0 - ssw));
            let prob = if ps + pd > 0.0 { ps / (ps + pd) } else { 0.0 };
            let reflected = p.microfacet.map(|mf| {
                gpu_photon::bsdfs::math::reflect(
                    wof,
                    mf.sample_visible(wof, Vec2::new(u[1], u[2])).0,
                )
            });
            close(u[0] - prob) || reflected.is_some_and(|w| close(w.z))
        }
        Bsdf::RoughConductor(c) => {
            let m = c.microfacet().sample_visible(wof, Vec2::new(u[1], u[2])).0;
            close(gpu_photon::bsdfs::math::reflect(wof, m).z)
        }
        Bsdf::Phong(p) => {
            // The choice between the lobe and the base.
            let (sd, ss) = (p.kd.get().element_sum(), p.ks.get().element_sum());
            close(u[0] - ss / (sd + ss))
        }
        Bsdf::MetallicRoughness(g) => {
            // sample: u[0] against the lobe probability, then (rescaled) against the
            // reflection probability at the visible normal; sample_lobe: u[0] against it.
            let p = g.front_lobe_probability(wof.z);
            let m = g.microfacet().sample_visible(wof, Vec2::new(u[1], u[2])).0;
            let r = g.reflect_probability(wof.dot(m));
            close(u[0] - p)
                || close(u[0] / p - r)
                || close(u[0] - r)
                || close(gpu_photon::bsdfs::math::reflect(wof, m).z)
        }
        Bsdf::Principled(p) => {
            // u[0] against the thresholds of both samplers; the reflected and refracted
            // directions against the horizon.
            let m = p.microfacet().sample_visible(wof, Vec2::new(u[1], u[2])).0;
            let (_, cos_t, _, eta_ti) = fresnel_dielectric(wo.dot(m), p.eta);
            let t = gpu_photon::bsdfs::math::refract(wo, m, cos_t, eta_ti);
            [false, true]
                .iter()
                .flat_map(|&lobe| p.sample_thresholds(wo, u, lobe))
                .any(|c| close(u[0] - c))
                || close(gpu_photon::bsdfs::math::reflect(wo, m).z)
                || close(t.z)
        }
        Bsdf::PrincipledThin(p) => {
            // u[0] against the thresholds of both samplers; the glossy directions (through
            // either distribution's visible normal) against the horizon.
            let u2 = Vec2::new(u[1], u[2]);
            let r = |mf: Microfacet| {
                gpu_photon::bsdfs::math::reflect(wof, mf.sample_visible(wof, u2).0)
            };
            [false, true]
                .iter()
                .flat_map(|&lobe| p.sample_thresholds(wo, lobe))
                .any(|c| close(u[0] - c))
                || close(r(p.microfacet()).z)
                || close(r(p.transmission_microfacet()).z)
        }
        _ => false,
    }
}

#[test]
fn wgsl_bsdfs_equal_rust_bsdfs() {
    let Some(ctx) = gpu() else { return };
    let named = bsdfs();
    let list: Vec<Bsdf> = named.iter().map(|(_, b)| *b).collect();
    let mut r = TestRng(SEED);
    let cases: Vec<ProbeCase> = list
        .iter()
        .enumerate()
        .flat_map(|(i, b)| cases_of(i as u32, b, &mut r))
        .collect();
    let out = run_probe(&ctx, &list, &cases);
    assert_eq!(out.len(), cases.len() * SLOTS);
    let mut ck = Checker {
        errors: Vec::new(),
        worst: BTreeMap::new(),
        skipped: 0,
        inputs: String::new(),
        coverage: BTreeMap::new(),
    };
    let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
    for (ci, c) in cases.iter().enumerate() {
        let (kind, b) = &named[c.bsdf as usize];
        let (wi, wo) = (Vec3::from(c.wi), Vec3::from(c.wo));
        let t = transport(c.radiance != 0);
        ck.inputs = format!("wi {wi} wo {wo} u {:?} {t:?}", c.u);
        let g = &out[ci * SLOTS..(ci + 1) * SLOTS];
        let tol = TOL;
        let beckmann =
            matches!(microfacet_of(b), Some(mf) if mf.distribution == Distribution::Beckmann);
        let tail = beckmann && c.u[1..].iter().any(|&x| !(1e-3..=1.0 - 1e-3).contains(&x));
        // The samplers warp (u[1], u[2]) to the unit disk and lift it: its height
        // sqrt(1 - r^2) is the cosine-hemisphere z and GGX's hemisphere projection.
        let r_disk = (2.0 * c.u[1] - 1.0).abs().max((2.0 * c.u[2] - 1.0).abs());
        let z = wo.z.abs().min((1.0 - r_disk * r_disk).max(0.0).sqrt());
        let factor = if beckmann { BECKMANN_FACTOR } else { 1.0 };
        let ratio = if matches!(b, Bsdf::Principled(_) | Bsdf::PrincipledThin(_)) {
            RATIO_FACTOR
        } else {
            1.0
        };
        let stol_mf =
            TOL.max(factor * GRAZING_ABS / (z * z))
                .max(if tail { TOL_TAIL } else { 0.0 });
        let value = b.eval(wi, wo, t);
        if value != Vec3::ZERO {
            ck.coverage.entry(kind.to_string()).or_default().1 += 1;
        }
        ck.v(kind, "eval", ci, value, v(g[0]), tol);
        ck.f(kind, "pdf", ci, b.pdf(wi, wo), g[0][3], tol);
        ck.v(kind, "eval_lobe", ci, b.eval_lobe(wi, wo, t), v(g[1]), tol);
        ck.f(kind, "pdf_lobe", ci, b.pdf_lobe(wi, wo), g[1][3], tol);
        let (s, sl) = (b.sample(wo, c.u, t), b.sample_lobe(wo, c.u, t));
        let near = near_boundary(b, wo, c.u, &[s, sl]);
        // A sample's own direction may be grazing: loosen as for eval.
        let stol = |s: Option<LobeSample>| match s {
            Some(s) => stol_mf.max(tol_z(s.wi.z.abs())) * ratio,
            None => stol_mf * ratio,
        };
        ck.sample(kind, "sample", ci, s, &g[2..4], stol(s), near);
        ck.sample(kind, "sample_lobe", ci, sl, &g[4..6], stol(sl), near);
        ck.v(kind, "diffuse_out", ci, b.diffuse_out(wo), v(g[6]), tol);
        ck.f(kind, "store_weight", ci, b.store_weight(wi), g[6][3], tol);
        if let Some(mf) = microfacet_of(b) {
            let h0 = (wi + wo).normalize();
            let h = mulsign(h0, h0.z);
            let wof = mulsign(wo, wo.z);
            if h.is_finite() {
                ck.f(kind, "mf_d", ci, mf.d(h), g[7][0], tol);
                ck.f(kind, "mf_smith_g1", ci, mf.smith_g1(wi, h), g[7][1], tol);
                ck.f(kind, "mf_g", ci, mf.g(wi, wo, h), g[7][2], tol);
                ck.f(
                    kind,
                    "mf_pdf_visible",
                    ci,
                    mf.pdf_visible(wof, h),
                    g[7][3],
                    tol,
                );
            }
            let (m, pdf) = mf.sample_visible(wof, Vec2::new(c.u[1], c.u[2]));
            ck.v(kind, "mf_sample_visible", ci, m, v(g[8]), stol_mf);
            ck.f(kind, "mf_sample_visible pdf", ci, pdf, g[8][3], stol_mf);
        }
        if let Some(eta) = eta_of(b) {
            let (f, ct, eit, eti) = fresnel_dielectric(wo.z, eta);
            ck.f(kind, "fresnel_dielectric F", ci, f, g[9][0], tol);
            ck.f(kind, "fresnel_dielectric cos_t", ci, ct, g[9][1], tol);
            ck.f(kind, "fresnel_dielectric eta_it", ci, eit, g[9][2], 0.0);
            ck.f(kind, "fresnel_dielectric eta_ti", ci, eti, g[9][3], 0.0);
        }
        if let Some((eta, k)) = conductor_of(b) {
            ck.v(
                kind,
                "fresnel_conductor",
                ci,
                fresnel_conductor(wo.z.abs(), eta, k),
                v(g[10]),
                tol,
            );
        }
        ck.f(
            kind,
            "erfinv",
            ci,
            erfinv(2.0 * c.u[0] - 1.0),
            g[10][3],
            TOL,
        );
        let (e_want, e_got) = (erf(4.0 * c.u[1] - 2.0), g[11][0]);
        let e_tol = if (e_want - e_got).abs() <= ERF_ABS {
            f32::INFINITY
        } else {
            TOL
        };
        ck.f(kind, "erf", ci, e_want, e_got, e_tol);
        let w = square_to_cosine_hemisphere(Vec2::new(c.u[1], c.u[2]));
        ck.v(
            kind,
            "square_to_cosine_hemisphere",
            ci,
            w,
            Vec3::new(g[11][1], g[11][2], g[11][3]),
            TOL,
        );
    }
    let mut by_kind: BTreeMap<&str, f32> = BTreeMap::new();
    for ((_, what), e) in &ck.worst {
        let w = by_kind.entry(what).or_insert(0.0);
        *w = w.max(*e);
    }
    eprintln!("largest relative error per quantity: {by_kind:#?}");
    eprintln!(
        "{} of {} cases' samples skipped (within {BOUNDARY:e} of a decision)",
        ck.skipped / 2,
        cases.len()
    );
    eprintln!(
        "per kind (samples compared, nonzero values compared): {:#?}",
        ck.coverage
    );
    for (kind, b) in &named {
        // Every kind's samplers and (but the delta-only kinds') values were exercised.
        let (samples, values) = ck.coverage.get(*kind).copied().unwrap_or_default();
        let want_values = if b.lobe_is_delta() && !b.has_diffuse() {
            0
        } else {
            PER_BSDF / 4
        };
        assert!(
            samples >= PER_BSDF / 2 && values >= want_values,
            "{kind}: {samples} samples, {values} values"
        );
    }
    if !ck.errors.is_empty() {
        let n = ck.errors.len();
        let shown: Vec<&String> = ck.errors.iter().take(40).collect();
        panic!("{n} mismatches between bsdf.wgsl and src/bsdf/:\n{shown:#?}");
    }
}

/// Every kind of the list that reflects anything has a case above: a new kind is checked by
/// this test without new test code, only a line of parameters.
#[test]
fn every_kind_has_cases() {
    let named = bsdfs();
    for (code, k) in KINDS.iter().enumerate() {
        if matches!(k.name, "Black" | "Null") {
            continue;
        }
        assert!(
            named.iter().any(|(_, b)| b.code() == code as u32),
            "kind {} has no case in bsdfs()",
            k.name
        );
    }
}

/// Every kind writes the words its entry of the list says (`load_bsdf` reads that many).
#[test]
fn every_kind_writes_its_words() {
    for (name, b) in bsdfs() {
        let mut w = gpu_photon::bsdfs::param::GpuWords::default();
        b.gpu_words(&mut w);
        assert_eq!(w.words.len(), KINDS[b.code() as usize].words, "{name}");
    }
}
