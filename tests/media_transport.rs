//! Light transport through participating media (issue 24) on both backends, against closed
//! forms: Beer-Lambert through a slab bounded by index-matched (`null`) faces, single
//! scattering of a directional light in that slab seen head-on (by next-event estimation,
//! and by the volume photon map's beam estimate), and (CPU) the energy balance of photon
//! paths in a closed box filled with fog, single scattering from a point light and from a
//! constant environment against their integrals; the GPU's photon paths are the CPU's,
//! photon for photon (tests/media_gpu.rs). GPU tests skip without a device (CI has lavapipe).

mod common;
mod probes;

use glam::Vec3;
use gpu_photon::bvh::CpuBvh;
use gpu_photon::importers::load_str;
use gpu_photon::integrators::cpu::media::{self, transmittance};
use gpu_photon::integrators::cpu::photons::{trace_map, TraceContext};
use gpu_photon::integrators::plan::MapPlan;
use gpu_photon::lights::table::LightTable;
use gpu_photon::math::rng::{Rng, Stream};
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::settings::{Mode, RenderSettings};
use std::path::Path;

const D: f32 = 0.8;
const SIGMA_T: [f32; 3] = [0.5, 1.0, 2.0];
const ALBEDO: f32 = 0.6;
const G: f32 = 0.3;

/// A slab of fog `D` thick between z = 0 and z = -D (two `null` quads `half` wide whose
/// interior is the fog), a camera on the z axis looking down -z with a 1 degree field of
/// view, and a directional light of irradiance 1 travelling along -z.
fn slab(half: f32) -> Scene {
    slab_lit(
        half,
        "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nirradiance = [1, 1, 1]\n",
    )
}

/// The slab of [`slab`] lit by `light` (TOML) instead.
fn slab_lit(half: f32, light: &str) -> Scene {
    let (h, d) = (half, D);
    let text = format!(
        r#"
[camera]
eye = [0, 0, 5]
target = [0, 0, 0]
up = [0, 1, 0]
fov = 1.0
width = 4
height = 4

[media.fog]
sigma_t = [{}, {}, {}]
albedo = {ALBEDO}
g = {G}

[materials.boundary]
type = "null"

[[shapes]]
type = "quad"
corners = [[-{h}, -{h}, 0], [{h}, -{h}, 0], [{h}, {h}, 0], [-{h}, {h}, 0]]
material = "boundary"
interior = "fog"

[[shapes]]
type = "quad"
corners = [[-{h}, -{h}, -{d}], [-{h}, {h}, -{d}], [{h}, {h}, -{d}], [{h}, -{h}, -{d}]]
material = "boundary"
interior = "fog"

{light}
"#,
        SIGMA_T[0], SIGMA_T[1], SIGMA_T[2]
    );
    load_str(&text, "slab.toml", Path::new(".")).expect("the slab scene loads")
}

/// Henyey-Greenstein's density at cosine `c`.
fn hg(g: f64, c: f64) -> f64 {
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * c).powf(1.5))
}

/// Single-scattered radiance leaving the slab's lit face towards the light: the light
/// reaches depth s attenuated by exp(-sigma s), scatters back (cosine -1 between the
/// directions of travel), and returns attenuated as much again:
/// `E sigma_s p(-1) (1 - exp(-2 sigma D)) / (2 sigma)`.
fn single_scattering(c: usize) -> f64 {
    let s = SIGMA_T[c] as f64;
    ALBEDO as f64 * s * hg(G as f64, -1.0) * (1.0 - (-2.0 * s * D as f64).exp()) / (2.0 * s)
}

#[test]
fn transmittance_through_a_slab_is_beer_lambert() {
    let scene = slab(10.0);
    let bvh = CpuBvh::build(&scene);
    // A homogeneous medium's transmittance is exact: it draws none of these numbers.
    let mut rng = gpu_photon::math::rng::Rng::new(1, gpu_photon::math::rng::Stream::Camera, 0, 0);
    // From the camera's side, through both faces, to well beyond the slab.
    let tr = transmittance(
        &scene,
        &bvh,
        Vec3::new(0.1, -0.2, 2.0),
        Vec3::NEG_Z,
        6.0,
        scene.camera_medium,
        &mut rng,
    );
    for c in 0..3 {
        let want = (-(SIGMA_T[c] as f64) * D as f64).exp();
        let rel = (tr[c] as f64 - want).abs() / want;
        assert!(rel < 2e-6, "channel {c}: {} vs {want}", tr[c]);
    }
    // Slanted: the path in the slab is D / cos long.
    let dir = Vec3::new(0.6, 0.0, -0.8);
    let tr = transmittance(
        &scene,
        &bvh,
        Vec3::Z,
        dir,
        5.0,
        scene.camera_medium,
        &mut rng,
    );
    let want = (-(SIGMA_T[1] as f64) * D as f64 / 0.8).exp();
    assert!((tr[1] as f64 - want).abs() < 2e-6 * want, "{tr} vs {want}");
    // Stopping inside the slab: only the part travelled inside attenuates.
    let tr = transmittance(
        &scene,
        &bvh,
        Vec3::Z,
        Vec3::NEG_Z,
        1.3,
        scene.camera_medium,
        &mut rng,
    );
    let want = (-(SIGMA_T[2] as f64) * 0.3).exp();
    assert!((tr[2] as f64 - want).abs() < 2e-6 * want, "{tr} vs {want}");
}

/// The GPU's shadow walk (`shadow_transmittance`): the same cases, the same closed forms (to
/// 1e-5: the device's `exp`).
#[test]
fn transmittance_through_a_slab_is_beer_lambert_on_the_gpu() {
    let Some(ctx) = common::gpu() else { return };
    let scene = slab(10.0);
    let m = scene.camera_medium;
    let cases = [
        ([0.1, -0.2, 2.0], [0.0, 0.0, -1.0], 6.0, m),
        ([0.0, 0.0, 1.0], [0.6, 0.0, -0.8], 5.0, m),
        ([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], 1.3, m),
        ([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], 3.0e38, m),
    ];
    let got = probes::media::transmittance(&ctx, &scene, &cases).unwrap();
    let want = |c: usize, len: f64| (-(SIGMA_T[c] as f64) * len).exp();
    for c in 0..3 {
        for (case, len) in [(0, D as f64), (3, D as f64)] {
            let w = want(c, len);
            assert!(
                (got[case][c] as f64 - w).abs() < 1e-5 * w,
                "case {case} channel {c}: {} vs {w}",
                got[case][c]
            );
        }
    }
    let w = want(1, D as f64 / 0.8);
    assert!(
        (got[1][1] as f64 - w).abs() < 1e-5 * w,
        "{:?} vs {w}",
        got[1]
    );
    let w = want(2, 0.3);
    assert!(
        (got[2][2] as f64 - w).abs() < 1e-5 * w,
        "{:?} vs {w}",
        got[2]
    );
}

/// The mean of the render of `scene` with `s` on `backend` is the single-scattering closed
/// form within 1% per channel.
fn assert_single_scattering(scene: &Scene, s: &RenderSettings, backend: Backend) {
    let m = mean(scene, s, backend);
    for c in 0..3 {
        let want = single_scattering(c);
        assert!(
            (m[c] / want - 1.0).abs() < 0.01,
            "{backend:?} channel {c}: {} vs {want}",
            m[c]
        );
    }
}

/// The backends to check: the CPU, and the GPU where there is one.
fn backends() -> Vec<Backend> {
    match common::gpu() {
        Some(_) => vec![Backend::Cpu, Backend::Gpu],
        None => vec![Backend::Cpu],
    }
}

fn mean(scene: &Scene, s: &RenderSettings, backend: Backend) -> [f64; 3] {
    let (image, _) = render(scene, s, backend, Progress::default()).expect("renders");
    let mut m = [0.0f64; 3];
    for p in &image.pixels {
        for c in 0..3 {
            m[c] += p[c] as f64 / image.pixels.len() as f64;
        }
    }
    m
}

/// Next-event estimation alone (`direct-only` builds no photon map): every channel within
/// 1% of the closed form, on both backends.
#[test]
fn single_scattering_by_next_event_estimation_matches_the_closed_form() {
    let scene = slab(10.0);
    let s = RenderSettings {
        mode: Mode::DirectOnly,
        spp: 1024,
        ..scene.settings.clone()
    };
    for backend in backends() {
        assert_single_scattering(&scene, &s, backend);
    }
}

/// The volume photon map's beam estimate alone (`photon` mode, photon paths of one bounce,
/// so every volume photon is single scattering): within 1% with 4 million paths, whose own
/// noise here is about 0.3% (some 10^5 photons in each beam of radius 1; the slab is uniform
/// across, so the radius adds no bias). On the GPU beams of radius 0.6 (some 4 x 10^4
/// photons, noise about 0.5%): lavapipe's loop cut bounds the grid entries one invocation
/// reads (about 5 x 10^5), and a beam of radius 1 lists twice that.
#[test]
fn single_scattering_by_the_beam_estimate_matches_the_closed_form() {
    let scene = slab(4.0);
    let s = RenderSettings {
        mode: Mode::Photon,
        photons: 4_000_000,
        max_photon_bounces: 1,
        volume_radius: 1.0,
        pass_range: None,
        spp: 1,
        ..scene.settings.clone()
    };
    for backend in backends() {
        let radius = match backend {
            Backend::Cpu => 1.0,
            Backend::Gpu => 0.6,
        };
        let s = RenderSettings {
            volume_radius: radius,
            ..s.clone()
        };
        assert_single_scattering(&scene, &s, backend);
    }
}

/// A closed box of grey walls (albedo 0.5) with the camera inside and a light under its
/// ceiling, filled with fog of `albedo`.
fn fog_box(albedo: f32) -> Scene {
    let text = format!(
        r#"
[camera]
eye = [0, 0, 0.5]
target = [0, 0, 0]
up = [0, 1, 0]
fov = 60.0
width = 4
height = 4
medium = "fog"

[render]
max_photon_bounces = 64

[media.fog]
sigma_t = 1.0
albedo = {albedo}

[materials.wall]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]

[[shapes]]
type = "box"
min = [-1, -1, -1]
max = [1, 1, 1]
material = "wall"

[[shapes]]
type = "quad"
corners = [[-0.2, 0.95, -0.2], [0.2, 0.95, -0.2], [0.2, 0.95, 0.2], [-0.2, 0.95, 0.2]]
emission = [5, 5, 5]
"#
    );
    load_str(&text, "box.toml", Path::new(".")).expect("the fog box loads")
}

/// Where the photon paths' power goes, as fractions of the emitted power: (surfaces,
/// medium, escaped or cut).
fn balance(scene: &Scene) -> (f64, f64, f64) {
    let s = RenderSettings {
        photons: 200_000,
        ..scene.settings.clone()
    };
    let (bvh, lights) = (CpuBvh::build(scene), LightTable::new(scene));
    let plan = MapPlan::new(scene, &lights, &s);
    let ctx = TraceContext {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings: &s,
        pass: 0,
    };
    let global = plan.maps.iter().find(|m| m.budget.total() > 0).unwrap();
    let traced = trace_map(&ctx, global, plan.volume);
    assert!(
        !traced.volume.is_empty() || scene.media.iter().all(|m| m.albedo == Vec3::ZERO),
        "no volume photon stored"
    );
    let emitted = scene.total_power().x as f64;
    let e = traced.ends;
    (
        e.surface[0] / emitted,
        e.medium[0] / emitted,
        (e.escaped[0] + e.cut[0]) / emitted,
    )
}

/// Purely scattering fog loses nothing: the walls (and the light's own surface) absorb the
/// emitted power, to 0.1%. Fog of albedo 0.8 absorbs some: the medium and the walls together
/// absorb it all, and the medium's share is a real part of it.
#[test]
fn photon_power_is_conserved_in_a_fog_filled_box() {
    let (walls, medium, lost) = balance(&fog_box(1.0));
    assert_eq!(medium, 0.0, "a purely scattering medium absorbed {medium}");
    assert!((walls - 1.0).abs() < 1e-3, "walls absorbed {walls}");
    assert!(lost < 1e-4, "escaped or cut: {lost}");
    let (walls, medium, lost) = balance(&fog_box(0.8));
    assert!(
        (walls + medium - 1.0).abs() < 1e-3,
        "walls {walls} + medium {medium}"
    );
    assert!(medium > 0.2, "fog of albedo 0.8 absorbed only {medium}");
    assert!(lost < 1e-4, "escaped or cut: {lost}");
}

/// A sphere of purely absorbing fog (radius `R_FOG`, `sigma_t` 1) bounded by a `null`
/// surface, lit by `light` (TOML), nothing else; the camera outside it or (`camera_inside`)
/// in it.
fn absorbing_sphere(light: &str, camera_inside: bool) -> Scene {
    let (eye, medium) = match camera_inside {
        true => ("[0, 0, 0.5]", "medium = \"fog\""),
        false => ("[0, 0, 5]", ""),
    };
    let text = format!(
        r#"
[camera]
eye = {eye}
target = [0, 0, 0]
up = [0, 1, 0]
fov = 40.0
width = 4
height = 4
{medium}

[media.fog]
sigma_t = 1.0
albedo = 0.0

[materials.boundary]
type = "null"

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = {R_FOG}
material = "boundary"
interior = "fog"

{light}
"#
    );
    load_str(&text, "sphere.toml", Path::new(".")).expect("the fog sphere loads")
}

const R_FOG: f64 = 1.0;

/// Lights inside a bounded medium send their photons from it (issue 41): a point and a spot
/// light at the centre of a `null`-bounded sphere of absorbing fog (the camera outside) lose
/// `1 - exp(-sigma_t R)` of their power in it; a directional light, with the camera inside the
/// sphere, loses the chords' absorption over the sphere's disc,
/// `E pi (R^2 - (1 - (1 + 2 s R) exp(-2 s R)) / (2 s^2))`, and nothing before its photons
/// reach the sphere. Before, all three started in the camera's medium: no absorption at all
/// for the first two, absorption from the scene's edge on for the third. 200,000 photon paths:
/// within 0.006 (about five binomial standard deviations).
#[test]
fn photons_of_delta_lights_start_in_the_medium_around_them() {
    let shell = 1.0 - (-R_FOG).exp();
    let point = "[[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = [1, 1, 1]\n";
    let spot = "[[lights]]\ntype = \"spot\"\nposition = [0, 0, 0]\ndirection = [0, -1, 0.3]\n\
                intensity = [1, 1, 1]\nouter_angle = 40.0\n";
    for (kind, light) in [("point", point), ("spot", spot)] {
        let (_, medium, escaped) = balance(&absorbing_sphere(light, false));
        eprintln!("{kind}: medium {medium:.4}, escaped {escaped:.4}, expected {shell:.4}");
        assert!(
            (medium - shell).abs() < 6e-3,
            "{kind}: medium {medium}, expected {shell}"
        );
        assert!(
            (escaped - (1.0 - shell)).abs() < 6e-3,
            "{kind}: escaped {escaped}"
        );
    }
    let e = 2.0;
    let scene = absorbing_sphere(
        &format!("[[lights]]\ntype = \"directional\"\ndirection = [0.3, -1, 0.2]\nirradiance = [{e}, {e}, {e}]\n"),
        true,
    );
    let (_, medium, _) = balance(&scene);
    let (r, s) = (R_FOG, 1.0);
    let chords = r * r - (1.0 - (1.0 + 2.0 * s * r) * (-2.0 * s * r).exp()) / (2.0 * s * s);
    let expected = e * std::f64::consts::PI * chords / scene.total_power().x as f64;
    eprintln!("directional: medium {medium:.4}, expected {expected:.4}");
    assert!(
        (medium - expected).abs() < 6e-3,
        "directional: medium {medium}, expected {expected}"
    );
}

/// Single scattering from a point light beside a camera segment in fog (no surfaces):
/// the mean of `single_scattering`'s estimates (equiangular distances, which cancel the
/// light's inverse square) against the integral over the segment of
/// `sigma_s T(t) p(cos) I T(r) / r^2`, by quadrature in the angle the segment subtends at the
/// light; a finite segment and an endless one, per channel within four standard errors of
/// the estimate, which must be below 0.4% (the unbiased estimate of a wrong density fails).
#[test]
fn single_scattering_from_a_point_light_matches_the_integral() {
    let (intensity, y) = (2.0f32, Vec3::new(0.3, 0.4, -1.5));
    let text = format!(
        r#"
[camera]
eye = [0, 0, 5]
target = [0, 0, 0]
up = [0, 1, 0]
fov = 10.0
width = 4
height = 4
medium = "fog"

[media.fog]
sigma_t = [{}, {}, {}]
albedo = {ALBEDO}
g = {G}

[[lights]]
type = "point"
position = [{}, {}, {}]
intensity = [{intensity}, {intensity}, {intensity}]
"#,
        SIGMA_T[0], SIGMA_T[1], SIGMA_T[2], y.x, y.y, y.z
    );
    let scene = load_str(&text, "point.toml", Path::new(".")).expect("the scene loads");
    let (bvh, lights) = (CpuBvh::build(&scene), LightTable::new(&scene));
    let (o, d) = (
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.1, 0.0, -1.0).normalize(),
    );
    for t_seg in [4.0f32, f32::INFINITY] {
        let n = 200_000;
        let mut rng = Rng::new(5, Stream::Camera, 0, 0);
        let (mut est, mut sq) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            let l = media::single_scattering(&scene, &bvh, &lights, o, d, t_seg, 0, 1, &mut rng);
            for c in 0..3 {
                est[c] += l[c] as f64 / n as f64;
                sq[c] += (l[c] as f64).powi(2) / n as f64;
            }
        }
        // t = delta + dist tan(theta): dt / r^2 = d theta / dist.
        let (o, d, y) = (o.as_dvec3(), d.as_dvec3(), y.as_dvec3());
        let delta = (y - o).dot(d);
        let dist = ((y - o) - d * delta).length();
        let a = (-delta).atan2(dist);
        let b = if t_seg.is_finite() {
            (t_seg as f64 - delta).atan2(dist)
        } else {
            std::f64::consts::FRAC_PI_2
        };
        let steps = 200_000;
        for c in 0..3 {
            let s = SIGMA_T[c] as f64;
            let mut want = 0.0;
            for i in 0..steps {
                let theta = a + (b - a) * (i as f64 + 0.5) / steps as f64;
                let t = delta + dist * theta.tan();
                let x = o + d * t;
                let r = (y - x).length();
                let cos = (y - x).dot(d) / r;
                want += ALBEDO as f64
                    * s
                    * (-s * t).exp()
                    * hg(G as f64, cos)
                    * intensity as f64
                    * (-s * r).exp()
                    / dist
                    * (b - a)
                    / steps as f64;
            }
            // The estimate's own standard error: equiangular distances leave only the
            // transmittances and the phase function to vary.
            let se = ((sq[c] - est[c] * est[c]) / n as f64).sqrt();
            assert!(se < 0.004 * want, "standard error {se} of {want}");
            assert!(
                (est[c] - want).abs() < 4.0 * se,
                "t_seg {t_seg}, channel {c}: {} vs {want} (standard error {se})",
                est[c]
            );
        }
    }
}

/// Single scattering of a constant environment (radiance 1) in the slab seen head-on, by
/// next-event estimation alone (`direct-only`; the environment's direction drawn from the
/// phase function): the environment seen through the slab, `T(D)`, plus the integral over
/// depth t and the cosine mu of the light's direction of `sigma_s exp(-sigma t) 2 pi p(mu)
/// exp(-sigma s(t, mu))`, s the way out of the slab (t / mu up, (D - t) / -mu down), by
/// quadrature; per channel within 1%.
#[test]
fn single_scattering_of_an_environment_matches_the_integral() {
    let scene = slab_lit(10.0, "[environment]\nradiance = [1, 1, 1]\n");
    let s = RenderSettings {
        mode: Mode::DirectOnly,
        spp: 1024,
        ..scene.settings.clone()
    };
    let (n, d) = (2000, D as f64);
    let mut want = [0.0f64; 3];
    for c in 0..3 {
        let sigma = SIGMA_T[c] as f64;
        want[c] = (-sigma * d).exp();
        for i in 0..n {
            let t = (i as f64 + 0.5) / n as f64 * d;
            for j in 0..n {
                // mu: the cosine of the light's direction (towards where it comes from) with
                // +z; the camera looks along -z, so the scattering cosine is -mu.
                let mu = -1.0 + (j as f64 + 0.5) / n as f64 * 2.0;
                let out = if mu > 0.0 { t / mu } else { (d - t) / -mu };
                want[c] += ALBEDO as f64
                    * sigma
                    * (-sigma * t).exp()
                    * 2.0
                    * std::f64::consts::PI
                    * hg(G as f64, -mu)
                    * (-sigma * out).exp()
                    * (d / n as f64)
                    * (2.0 / n as f64);
            }
        }
    }
    for backend in backends() {
        let m = mean(&scene, &s, backend);
        for c in 0..3 {
            let w = want[c];
            assert!(
                (m[c] / w - 1.0).abs() < 0.01,
                "{backend:?} channel {c}: {} vs {w}",
                m[c]
            );
        }
    }
}
