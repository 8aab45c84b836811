//! Spot and directional lights against their analytic images and powers, on both backends:
//! a directional light on a diffuse plane (radiance rho/pi E cos theta), a spot above a
//! plane (on-axis radiance, black outside the cone, the falloff across its edge), the power
//! their photons carry, CPU-GPU agreement, and their import from glTF (candela, lux) and
//! Mitsuba XML. Errors of malformed lights are in tests/scene_errors.rs (TOML) and here.

mod common;

use glam::{DVec3, Vec3};
use gpu_photon::camera::Camera;
use gpu_photon::importers::mitsuba::import;
use gpu_photon::importers::{load, load_str};
use gpu_photon::lights::spot::{SpotCone, SpotFalloff};
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{LightShape, Scene};
use gpu_photon::settings::{Mode, RenderSettings};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scene(text: &str) -> Scene {
    load_str(text, "test.toml", root()).unwrap_or_else(|e| panic!("{e}"))
}

/// The backends to test: the CPU, and the GPU when there is one (always under CI).
fn backends() -> Vec<Backend> {
    let mut b = vec![Backend::Cpu];
    if common::gpu().is_some() {
        b.push(Backend::Gpu);
    }
    b
}

/// Renders on `backend`; on the GPU, no photon overflows and at most 0.2% of the samples
/// cut short by the loop budget or a truncated search (as in tests/hard_cases.rs).
fn run(s: &Scene, settings: &RenderSettings, backend: Backend) -> Image {
    let (img, report) = render(s, settings, backend, Progress::default())
        .unwrap_or_else(|e| panic!("{backend:?}: {e}"));
    assert_eq!(img.non_finite(), 0, "{backend:?}: NaN or infinity");
    if let [overflow, budget, truncated, ..] = report.gpu_stats[..] {
        let samples = (settings.width * settings.height * settings.spp) as f64;
        assert_eq!(overflow, 0, "GPU photon overflow");
        assert!(
            (budget + truncated) as f64 <= 0.002 * samples,
            "GPU loop budget {budget} / truncated {truncated} of {samples} samples"
        );
    }
    img
}

fn small(mode: Mode, photons: u32, size: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        spp,
        photons,
        caustic_photons: 0,
        k: 100,
        radius: 0.5,
        mode,
        ..RenderSettings::default()
    }
}

/// The point of the plane y = 0 seen through image point (x, y) (pixels, continuous).
fn on_plane(cam: &Camera, w: u32, h: u32, x: f64, y: f64) -> Option<DVec3> {
    let sx = (2.0 * x / w as f64 - 1.0) * (w as f64 / h as f64);
    let sy = 1.0 - 2.0 * y / h as f64;
    let d =
        (cam.forward.as_dvec3() + sx * cam.right.as_dvec3() + sy * cam.up.as_dvec3()).normalize();
    let eye = cam.eye.as_dvec3();
    (d.y < 0.0).then(|| eye + d * (-eye.y / d.y))
}

// ---------------------------------------------------------------------------------------------
// A directional light on a plane
// ---------------------------------------------------------------------------------------------

const ALBEDO: f64 = 0.8;

/// A 20 x 20 white plane at y = 0 seen from (0, 3, 3), lit by a directional light.
fn sun_plane(direction: [f32; 3], irradiance: [f32; 3]) -> Scene {
    scene(&format!(
        r#"[camera]
eye = [0.0, 3.0, 3.0]
target = [0.0, 0.0, 0.0]
fov = 45.0
[materials.white]
type = "diffuse"
albedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]
[[shapes]]
type = "quad"
corners = [[-10.0, 0.0, 10.0], [10.0, 0.0, 10.0], [10.0, 0.0, -10.0], [-10.0, 0.0, -10.0]]
material = "white"
[[lights]]
type = "directional"
direction = {direction:?}
irradiance = {irradiance:?}
"#
    ))
}

#[test]
fn directional_light_on_a_plane_is_rho_over_pi_e_cos_theta() {
    let (dir, e) = ([0.3f32, -1.0, 0.2], [3.0f32, 2.0, 1.0]);
    let s = sun_plane(dir, e);
    let cos = 1.0 / Vec3::from(dir).length() as f64;
    let want = e.map(|e| ALBEDO / PI * e as f64 * cos);
    // Power: E pi R^2, R the scene's bounding radius (the plane's half-diagonal, grown 0.1%).
    let (_, r) = s.bounding_sphere();
    assert!((r as f64 - 200f64.sqrt() * 1.001).abs() < 1e-3);
    for c in 0..3 {
        let p = e[c] as f64 * PI * (r as f64).powi(2);
        assert!((s.lights[0].power[c] as f64 - p).abs() < 1e-5 * p);
    }
    for backend in backends() {
        // Direct mode: shadow rays only (one plane: nothing to bounce from), every pixel the
        // exact value up to float rounding; 1% allowed.
        let img = run(&s, &small(Mode::Direct, 20_000, 24, 1), backend);
        let worst = img
            .pixels
            .iter()
            .flat_map(|p| (0..3).map(move |c| (p[c] as f64 - want[c]).abs() / want[c]))
            .fold(0.0, f64::max);
        eprintln!("direct {backend:?}: worst pixel rel. error {worst:.2e}");
        assert!(worst < 0.01, "{backend:?}: a pixel {worst} off {want:?}");
        // Photon mode: the image mean from the density estimate. The irradiance is uniform,
        // so the disc kernel has no bias; the noise of the mean is that of the photon count M
        // in the region the camera sees (~ a 6 x 9 trapezoid, 54 of the plane's 400 m^2):
        // of the 1e6 photons, a fraction 400 cos / (pi R^2) = 0.61 hits the plane, so M ~ 8e4
        // and 1/sqrt(M) = 0.35%. Bound: 4 sigma = 1.5%.
        let img = run(&s, &small(Mode::Photon, 1_000_000, 24, 2), backend);
        let m = img.mean();
        let rel = (0..3)
            .map(|c| (m[c] - want[c]).abs() / want[c])
            .fold(0.0, f64::max);
        eprintln!("photon {backend:?}: mean {m:?} analytic {want:?} (rel {rel:.4})");
        assert!(
            rel < 0.015,
            "{backend:?}: photon-mode mean {m:?}, analytic {want:?}"
        );
    }
}

#[test]
fn directional_shadow_rays_reach_occluders_however_far() {
    // A 2 x 2 plane seen from straight above, lit straight down; a quad 1000 units up hides
    // its x < 0 half. Direct mode: that half exactly black, the other rho/pi E.
    let s = scene(&format!(
        r#"[camera]
eye = [0.0, 3.0, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 30.0
[materials.white]
type = "diffuse"
albedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]
[[shapes]]
type = "quad"
corners = [[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]]
material = "white"
[[shapes]]
type = "quad"
corners = [[-5.0, 1000.0, 5.0], [0.0, 1000.0, 5.0], [0.0, 1000.0, -5.0], [-5.0, 1000.0, -5.0]]
material = "white"
[[lights]]
type = "directional"
direction = [0.0, -1.0, 0.0]
irradiance = [1.0, 1.0, 1.0]
"#
    ));
    let want = (ALBEDO / PI) as f32;
    let size = 16;
    for backend in backends() {
        let img = run(&s, &small(Mode::Direct, 1000, size, 1), backend);
        for y in 0..size {
            for x in 0..size {
                let got = img.pixels[(y * size + x) as usize][0];
                // Columns wholly left of x = 0 are shadowed, wholly right lit.
                if x < size / 2 - 1 {
                    assert_eq!(got, 0.0, "{backend:?}: ({x}, {y}) not shadowed");
                } else if x > size / 2 {
                    assert!(
                        (got - want).abs() < 1e-4 * want,
                        "{backend:?}: ({x}, {y}) {got}"
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// A spot above a plane
// ---------------------------------------------------------------------------------------------

const SPOT_H: f64 = 1.0;
const INNER: f32 = 20.0;
const OUTER: f32 = 30.0;

/// A 2.4 x 2.4 white plane at y = 0 seen from straight above (so each pixel is a square of
/// the plane; the view is 2 x 2), lit by the `[[lights]]` table `light`.
fn plane_under(light: &str) -> Scene {
    scene(&format!(
        r#"[camera]
eye = [0.0, 3.0, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 36.869898
[materials.white]
type = "diffuse"
albedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]
[[shapes]]
type = "quad"
corners = [[-1.2, 0.0, 1.2], [1.2, 0.0, 1.2], [1.2, 0.0, -1.2], [-1.2, 0.0, -1.2]]
material = "white"
[[lights]]
{light}"#
    ))
}

/// [`plane_under`] a spot at height 1 pointing straight down.
fn spot_plane(falloff: SpotFalloff) -> Scene {
    let falloff = falloff.name();
    plane_under(&format!(
        r#"type = "spot"
position = [0.0, {SPOT_H}, 0.0]
target = [0.0, 0.0, 0.0]
intensity = [12.0, 10.0, 8.0]
inner_angle = {INNER}
outer_angle = {OUTER}
falloff = "{falloff}"
"#
    ))
}

/// The spot falloff at cosine `cd` for half-angles `inner`, `outer` (degrees), written out
/// from the KHR_lights_punctual reference code (f64).
fn gltf_att(cd: f64, inner: f64, outer: f64) -> f64 {
    let (ci, co) = (inner.to_radians().cos(), outer.to_radians().cos());
    let scale = 1.0 / (ci - co).max(0.001);
    let offset = -co * scale;
    (cd * scale + offset).clamp(0.0, 1.0).powi(2)
}

/// The falloff of Mitsuba 3's `spot` (`falloff_curve` in its spot.cpp), written out in f64:
/// 1 inside `inner`, `(outer - theta) / (outer - inner)` between, 0 outside `outer`.
fn linear_att(cd: f64, inner: f64, outer: f64) -> f64 {
    let theta = cd.clamp(-1.0, 1.0).acos().to_degrees();
    match theta {
        t if t <= inner => 1.0,
        t if t < outer => (outer - t) / (outer - inner),
        _ => 0.0,
    }
}

/// The falloff `f` at cosine `cd` (degrees `inner`, `outer`).
fn att(f: SpotFalloff, cd: f64, inner: f64, outer: f64) -> f64 {
    match f {
        SpotFalloff::Gltf => gltf_att(cd, inner, outer),
        SpotFalloff::LinearAngle => linear_att(cd, inner, outer),
    }
}

/// Radiance at x on the plane under the spot, per W/sr: rho/pi att(h/d) h/d^3.
fn spot_radiance(f: SpotFalloff, x: DVec3) -> f64 {
    let d = (DVec3::new(0.0, SPOT_H, 0.0) - x).length();
    let att = att(f, SPOT_H / d, INNER as f64, OUTER as f64);
    ALBEDO / PI * att * SPOT_H / d.powi(3)
}

#[test]
fn spot_on_a_plane_matches_its_falloff_and_is_black_outside_the_cone() {
    for f in SpotFalloff::ALL {
        spot_on_a_plane(f);
    }
}

fn spot_on_a_plane(f: SpotFalloff) {
    let s = spot_plane(f);
    let LightShape::Spot(gpu_photon::lights::spot::Spot { intensity, .. }) = s.lights[0].shape
    else {
        panic!("a spot")
    };
    let size = 40;
    let outer_r = SPOT_H * (OUTER as f64).to_radians().tan();
    // Per pixel: the analytic mean radiance per W/sr (a 16 x 16 grid over its square of the
    // plane) and the distance of its nearest grid point from the axis.
    let n = 16;
    let mut exact = Vec::new();
    for py in 0..size {
        for px in 0..size {
            let (mut want, mut nearest) = (0.0, f64::INFINITY);
            for j in 0..n {
                for i in 0..n {
                    let x = px as f64 + (i as f64 + 0.5) / n as f64;
                    let y = py as f64 + (j as f64 + 0.5) / n as f64;
                    let p = on_plane(&s.camera, size, size, x, y).unwrap();
                    want += spot_radiance(f, p) / (n * n) as f64;
                    nearest = nearest.min(DVec3::new(p.x, 0.0, p.z).length());
                }
            }
            exact.push((want, nearest));
        }
    }
    let scale = intensity.to_array().map(|i| i as f64);
    let peak = spot_radiance(f, DVec3::ZERO);
    let mean_want = exact.iter().map(|e| e.0).sum::<f64>() / exact.len() as f64;
    for backend in backends() {
        let img = run(&s, &small(Mode::Direct, 10_000, size, 64), backend);
        let (mut axis, mut edge, mut black) = (0.0f64, 0.0f64, 0);
        for (i, &(want, nearest)) in exact.iter().enumerate() {
            let got = img.pixels[i];
            // Wholly outside the outer cone (with a margin of a grid step): exactly 0.
            if nearest > outer_r + 0.01 {
                assert_eq!(got, [0.0; 3], "{backend:?}: pixel {i} lit");
                black += 1;
                continue;
            }
            for c in 0..3 {
                let err = (got[c] as f64 / scale[c] - want).abs() / peak;
                if nearest < 0.3 {
                    axis = axis.max(err);
                } else {
                    edge = edge.max(err);
                }
            }
        }
        eprintln!(
            "spot {f:?} {backend:?}: {black} black pixels; worst error / on-axis radiance: inside \
             {axis:.2e}, across the edge {edge:.2e}"
        );
        assert!(
            black > size * size / 2,
            "{backend:?}: only {black} black pixels"
        );
        // Inside the inner cone the image is smooth: 1% of the on-axis radiance. Across the
        // ramp the pixel's 64 jittered (Sobol) samples estimate its mean over a steep
        // profile: 0.5% of the on-axis radiance (measured 0.06%; a falloff linear in the
        // cosine instead of quadratic is off by up to 25% of it).
        assert!(axis < 0.01, "{backend:?}: inside the cone {axis}");
        assert!(edge < 0.005, "{backend:?}: across the cone edge {edge}");

        // Photon mode: the image mean from the spot's photons. All 100k land in view, at
        // N / (Omega h^2) = 190k per m^2 on the axis (Omega = 0.53 sr), so r_K (K = 100) is
        // 0.013 there. Noise: 1/sqrt(N) = 0.32% from the photon count, and ~1700 mostly
        // disjoint K = 100 estimates (10% each) add 0.25%: 0.4% in all; bound 1.6% (4
        // sigma). Bias: where fewer than K photons lie within the radius (the ramp's dim
        // outer end) the disc averages a profile convex there, by ~r^2/8 of its Laplacian:
        // with r = 0.1 that was measured at +0.7%, so the radius here is 0.03 (0.06%).
        let rel = photon_mean_error(&s, backend, size, scale, mean_want);
        eprintln!("spot photon {f:?} {backend:?}: mean rel. error {rel:.4}");
        assert!(rel < 0.016, "{backend:?}: photon-mode mean off by {rel}");
    }
}

/// The worst channel's relative error of the image mean of `s` rendered in photon mode
/// (100k photons, K = 100 within 0.03, 4 spp) on `backend`, over `scale` per channel, from
/// `want`.
fn photon_mean_error(s: &Scene, backend: Backend, size: u32, scale: [f64; 3], want: f64) -> f64 {
    let st = RenderSettings {
        k: 100,
        radius: 0.03,
        ..small(Mode::Photon, 100_000, size, 4)
    };
    let m = run(s, &st, backend).mean();
    (0..3)
        .map(|c| (m[c] / scale[c] - want).abs() / want)
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------------
// The power photons carry
// ---------------------------------------------------------------------------------------------

/// `2 pi ∫ att(c) dc` of falloff `f` over cosines `lo..hi` by the midpoint rule (f64).
fn falloff_integral(f: SpotFalloff, inner: f64, outer: f64, lo: f64, hi: f64) -> f64 {
    let n = 1_000_000;
    let sum: f64 = (0..n)
        .map(|i| {
            att(
                f,
                lo + (hi - lo) * (i as f64 + 0.5) / n as f64,
                inner,
                outer,
            )
        })
        .sum();
    2.0 * PI * sum * (hi - lo) / n as f64
}

#[test]
fn spot_photons_carry_its_power_and_follow_its_falloff() {
    for f in SpotFalloff::ALL {
        spot_photons(f);
    }
}

/// A spot inside a closed grey box (every photon's first hit is a wall): half-angles
/// `inner`, `outer`, falloff `falloff`, more keys of its table in `extra`.
fn spot_box(inner: f64, outer: f64, falloff: &str, extra: &str) -> Scene {
    scene(&format!(
        r#"[camera]
eye = [0.0, 0.0, 0.5]
target = [0.0, 0.0, 0.0]
fov = 40.0
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[shapes]]
type = "box"
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
material = "grey"
[[lights]]
type = "spot"
position = [0.1, 0.2, -0.1]
direction = [1.0, -2.0, 0.5]
intensity = [3.0, 2.0, 1.0]
inner_angle = {inner}
outer_angle = {outer}
falloff = "{falloff}"
{extra}"#
    ))
}

fn spot_photons(f: SpotFalloff) {
    // A spot inside a closed box: every photon's first hit is a wall, so the depth-0 photons
    // carry the emitted power, which must be I times the falloff's integral over the sphere.
    let s = spot_box(15.0, 40.0, f.name(), "");
    let omega = falloff_integral(f, 15.0, 40.0, -1.0, 1.0);
    let LightShape::Spot(gpu_photon::lights::spot::Spot {
        position,
        direction,
        intensity,
        cone,
        ..
    }) = s.lights[0].shape
    else {
        panic!("a spot")
    };
    for c in 0..3 {
        let want = intensity[c] as f64 * omega;
        let rel = (s.lights[0].power[c] as f64 - want).abs() / want;
        assert!(
            rel < 1e-5,
            "power {} vs I x integral {want}",
            s.lights[0].power[c]
        );
    }
    let st = RenderSettings {
        photons: 200_000,
        ..RenderSettings::default()
    };
    let (_, photons) = common::trace_global(&s, &st);
    let first: Vec<_> = photons.iter().filter(|p| p.depth() == 0).collect();
    assert!(first.len() as f64 > 200_000.0 * (1.0 - 1e-4));
    let mut sum = [0.0f64; 3];
    // Histogram of the cosine to the axis over 8 bins of [cos_outer, 1].
    let bins = 8;
    let mut hist = vec![0.0f64; bins];
    let co = cone.cos_outer as f64;
    for p in &first {
        for c in 0..3 {
            sum[c] += p.power[c] as f64;
        }
        let cd = (p.pos() - position).normalize().dot(direction) as f64;
        assert!(cd > co - 1e-4, "a photon outside the outer cone (cos {cd})");
        let b = (((cd - co) / (1.0 - co)) * bins as f64) as usize;
        hist[b.min(bins - 1)] += 1.0 / first.len() as f64;
    }
    for c in 0..3 {
        let want = intensity[c] as f64 * omega;
        let rel = (sum[c] - want).abs() / want;
        eprintln!(
            "channel {c}: photons carry {:.5} W of {want:.5} W (rel {rel:.1e})",
            sum[c]
        );
        assert!(
            rel < 1e-4,
            "channel {c}: photons carry {} W, want {want}",
            sum[c]
        );
    }
    // Each bin holds its share p of the falloff's integral, within 5 binomial sigmas
    // sqrt(p (1 - p) / n).
    for (b, h) in hist.iter().enumerate() {
        let lo = co + (1.0 - co) * b as f64 / bins as f64;
        let hi = co + (1.0 - co) * (b + 1) as f64 / bins as f64;
        let p = falloff_integral(f, 15.0, 40.0, lo, hi) / omega;
        let sigma = (p * (1.0 - p) / first.len() as f64).sqrt();
        eprintln!("bin {b}: {h:.5} of the photons, {p:.5} of the falloff (sigma {sigma:.1e})");
        assert!((h - p).abs() < 5.0 * sigma + 1e-5, "bin {b}: {h} vs {p}");
    }
}

#[test]
fn directional_photons_deliver_e_times_the_projected_area() {
    // A 2 x 2 quad facing up, lit along (0.6, -0.8, 0): it intercepts E A cos = 3.2 E.
    // The photons start on a disc of radius R, a fraction 3.2 / (pi R^2) ~ 0.51 of them hits
    // the quad; binomial noise on 200000 photons: 0.22%. Bound 1%.
    let s = scene(
        r#"[camera]
eye = [0.0, 3.0, 3.0]
target = [0.0, 0.0, 0.0]
fov = 40.0
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[shapes]]
type = "quad"
corners = [[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]]
material = "grey"
[[lights]]
type = "directional"
direction = [0.6, -0.8, 0.0]
irradiance = [2.0, 1.0, 0.5]
"#,
    );
    let st = RenderSettings {
        photons: 200_000,
        ..RenderSettings::default()
    };
    let (_, photons) = common::trace_global(&s, &st);
    let mut sum = [0.0f64; 3];
    for p in photons.iter().filter(|p| p.depth() == 0) {
        // Each arrived travelling along the light.
        for c in 0..3 {
            sum[c] += p.power[c] as f64;
        }
    }
    for (c, e) in [2.0, 1.0, 0.5].iter().enumerate() {
        let want = e * 4.0 * 0.8;
        let rel = (sum[c] - want).abs() / want;
        eprintln!(
            "channel {c}: {:.5} W on the quad, E A cos = {want} (rel {rel:.4})",
            sum[c]
        );
        assert!(rel < 0.01, "channel {c}: {} W, want {want}", sum[c]);
    }
}

// ---------------------------------------------------------------------------------------------
// CPU and GPU agree
// ---------------------------------------------------------------------------------------------

#[test]
fn backends_agree_on_a_spot_and_a_directional_light() {
    let Some(_) = common::gpu() else { return };
    let s = load(&root().join("scenes/spot-light.toml")).unwrap();
    let at = |seed, backend| {
        let st = RenderSettings {
            width: 32,
            height: 32,
            spp: 4,
            photons: 40_000,
            mode: Mode::Photon,
            seed,
            ..s.settings.clone()
        };
        run(&s, &st, backend)
    };
    let (cpu1, cpu2, gpu1) = (
        at(1, Backend::Cpu),
        at(2, Backend::Cpu),
        at(1, Backend::Gpu),
    );
    let noise = diff(&cpu1, &cpu2, 8).unwrap();
    let cross = diff(&gpu1, &cpu2, 8).unwrap();
    let same = diff(&gpu1, &cpu1, 8).unwrap();
    eprintln!(
        "rmse gpu1-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}; same seed {:.5}",
        cross.rmse, noise.rmse, cross.block_rmse, noise.block_rmse, same.rmse
    );
    let (pixels, blocks) = common::within_seed_noise(&cross, &noise, 1e-6);
    assert!(pixels && blocks, "GPU farther from CPU than CPU seeds are");
    // No glass: same seed, same numbers, so the images differ far below the noise.
    assert!(
        same.rmse < 0.01 * noise.rmse,
        "same seed differs: {}",
        same.rmse
    );
}

// ---------------------------------------------------------------------------------------------
// Import: glTF and Mitsuba
// ---------------------------------------------------------------------------------------------

fn write(name: &str, text: &str) -> PathBuf {
    let dir = root().join("target/test-output/lights");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A glTF scene: a triangle, a camera, a spot of 683 x 3 cd pointing down (the node turned
/// -90 degrees about x) and a directional light of 683 x 2 lux along the node's -Z.
fn gltf_lights(spot: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_lights_punctual"],
"scenes": [{{"nodes": [0, 1, 2, 3]}}],
"nodes": [{{"camera": 0, "translation": [0, 1, 3]}}, {{"mesh": 0}},
  {{"translation": [0, 2, 0], "rotation": [-0.70710677, 0, 0, 0.70710677], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
  {{"extensions": {{"KHR_lights_punctual": {{"light": 1}}}}}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "znear": 0.1}}}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}}],
"bufferViews": [{{"buffer": 0, "byteLength": 36}}],
"buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,AACAvwAAAAAAAIC/AACAPwAAAAAAAIC/AAAAAAAAAAAAAIA/"}}],
"extensions": {{"KHR_lights_punctual": {{"lights": [
  {{"name": "Spot", "type": "spot", "color": [1, 0.5, 0.25], "intensity": 2049, {spot}}},
  {{"name": "Sun", "type": "directional", "color": [1, 1, 0.5], "intensity": 1366}}]}}}}}}"#
    )
}

#[test]
fn gltf_spot_and_directional_lights_load_in_watts() {
    let spot = r#""spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}"#;
    let s = load(&write("lights.gltf", &gltf_lights(spot))).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.lights.len(), 2);
    let LightShape::Spot(gpu_photon::lights::spot::Spot {
        position,
        direction,
        intensity,
        cone,
        ..
    }) = s.lights[0].shape
    else {
        panic!("a spot: {:?}", s.lights[0])
    };
    // 2049 cd / 683 = 3 W/sr, times the colour.
    assert!((intensity - Vec3::new(3.0, 1.5, 0.75)).abs().max_element() < 1e-5);
    assert!((position - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
    assert!(
        (direction - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6,
        "{direction}"
    );
    assert!((cone.cos_inner - 0.2f32.cos()).abs() < 1e-6);
    assert!((cone.cos_outer - 0.5f32.cos()).abs() < 1e-6);
    let omega = SpotCone::solid_angle(&cone) as f32;
    assert!((s.lights[0].power - intensity * omega).abs().max_element() < 1e-5);
    let LightShape::Directional(gpu_photon::lights::directional::Directional {
        direction,
        irradiance,
    }) = s.lights[1].shape
    else {
        panic!("directional: {:?}", s.lights[1])
    };
    // 1366 lux / 683 = 2 W/m^2, times the colour; an unrotated node shines along -Z.
    assert!((irradiance - Vec3::new(2.0, 2.0, 1.0)).abs().max_element() < 1e-5);
    assert_eq!(direction, Vec3::NEG_Z);
    // The default cone: inner 0, outer pi/4.
    let s = load(&write("default-spot.gltf", &gltf_lights(r#""spot": {}"#))).unwrap();
    let LightShape::Spot(gpu_photon::lights::spot::Spot { cone, .. }) = s.lights[0].shape else {
        panic!("a spot")
    };
    assert_eq!(cone.cos_inner, 1.0);
    assert!((cone.cos_outer - std::f32::consts::FRAC_PI_4.cos()).abs() < 1e-6);
}

const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 3.5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
<shape type="rectangle"/>
"#;

fn mitsuba(body: &str) -> Result<gpu_photon::importers::mitsuba::Imported, gpu_photon::Error> {
    let text = format!("<scene version=\"3.0.0\">{SENSOR}{body}\n</scene>\n");
    import(&text, "t.xml", root())
}

#[test]
fn mitsuba_spot_and_directional_emitters_load() {
    let im = mitsuba(
        r#"<emitter type="spot"><rgb name="intensity" value="4, 3, 2"/><float name="cutoff_angle" value="30"/>
<float name="beam_width" value="10"/>
<transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform></emitter>
<emitter type="directional"><vector name="direction" value="0, -2, 0"/><rgb name="irradiance" value="5"/></emitter>
<emitter type="spot"><rgb name="intensity" value="1"/></emitter>"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let s = &im.scene;
    let LightShape::Spot(gpu_photon::lights::spot::Spot {
        position,
        direction,
        intensity,
        cone,
        ..
    }) = s.lights[0].shape
    else {
        panic!("a spot")
    };
    assert!((position - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
    assert!((direction - Vec3::NEG_Y).length() < 1e-6, "{direction}");
    assert_eq!(intensity, Vec3::new(4.0, 3.0, 2.0));
    let linear = SpotFalloff::LinearAngle;
    assert_eq!(cone, SpotCone::with_profile(10.0, 30.0, linear));
    let LightShape::Directional(gpu_photon::lights::directional::Directional {
        direction,
        irradiance,
    }) = s.lights[1].shape
    else {
        panic!("directional")
    };
    assert_eq!((direction, irradiance), (Vec3::NEG_Y, Vec3::splat(5.0)));
    // Mitsuba's defaults: cutoff 20 degrees, beam width 3/4 of it, along +Z from the origin.
    let LightShape::Spot(gpu_photon::lights::spot::Spot {
        direction, cone, ..
    }) = s.lights[2].shape
    else {
        panic!("a spot")
    };
    assert_eq!(
        (direction, cone),
        (Vec3::Z, SpotCone::with_profile(15.0, 20.0, linear))
    );
    // Mitsuba's falloff is ours: nothing approximated, no warning.
    assert!(im.warnings.is_empty(), "{:?}", im.warnings);
}

#[test]
fn bad_lights_give_file_line_field_messages() {
    let cases = [
        (
            r#"<emitter type="spot"><rgb name="intensity" value="1"/>
<float name="cutoff_angle" value="100"/></emitter>"#,
            "t.xml:5: emitter[0].cutoff_angle: must be in (0, 90] degrees (got 100)",
        ),
        (
            r#"<emitter type="spot"><rgb name="intensity" value="1"/><float name="cutoff_angle" value="0"/></emitter>"#,
            "t.xml:4: emitter[0].cutoff_angle: must be in (0, 90] degrees (got 0)",
        ),
        (
            r#"<emitter type="spot"><rgb name="intensity" value="1"/><float name="cutoff_angle" value="30"/>
<float name="beam_width" value="40"/></emitter>"#,
            "t.xml:5: emitter[0].beam_width: must be in [0, outer angle 30] degrees (got 40)",
        ),
        (
            r#"<emitter type="spot"><rgb name="intensity" value="-1"/></emitter>"#,
            "t.xml:4: emitter[0].intensity: components must be >= 0",
        ),
        (
            r#"<emitter type="spot"><rgb name="intensity" value="1"/><texture name="texture" type="bitmap"/></emitter>"#,
            "t.xml:4: emitter[0].texture.filename: missing",
        ),
        (
            r#"<emitter type="spot"><rgb name="intensity" value="1"/><float name="cutoff_angle" value="90"/>
<texture name="texture" type="checkerboard"/></emitter>"#,
            "t.xml:4: emitter[0].cutoff_angle: must be under 90 degrees with a texture (got 90)",
        ),
        (
            r#"<emitter type="projector"><transform name="to_world"><scale value="2"/></transform></emitter>"#,
            "t.xml:4: emitter[0].to_world: must be a rotation and translation (no scale or shear)",
        ),
        (
            r#"<emitter type="projector"><float name="fov" value="180"/></emitter>"#,
            "t.xml:4: emitter[0].fov: must be in (0, 180) degrees",
        ),
        (
            r#"<emitter type="projector">
<rgb name="irradiance" value="-1"/></emitter>"#,
            "t.xml:5: emitter[0].irradiance: components must be >= 0",
        ),
        (
            r#"<emitter type="projector"><rgb name="irradiance" value="1"/>
<float name="scale" value="-2"/></emitter>"#,
            "t.xml:5: emitter[0].scale: components must be >= 0",
        ),
        (
            r#"<emitter type="projector"><float name="gamma" value="2"/></emitter>"#,
            "t.xml:4: emitter[0].gamma: unsupported parameter of `projector`",
        ),
        (
            r#"<emitter type="directional"><rgb name="irradiance" value="1"/>
<vector name="direction" value="0, 0, 0"/></emitter>"#,
            "t.xml:5: emitter[0].direction: must not be zero",
        ),
        (
            r#"<emitter type="directional"><vector name="direction" value="0, 0, 1"/></emitter>"#,
            "t.xml:4: emitter[0].irradiance: missing",
        ),
        (
            r#"<emitter type="directional"><rgb name="irradiance" value="1"/><vector name="direction" value="0, 0, 1"/>
<transform name="to_world"><translate x="1"/></transform></emitter>"#,
            "t.xml:4: emitter[0]: give `direction` or `to_world`, not both",
        ),
    ];
    for (body, want) in cases {
        match mitsuba(body) {
            Ok(_) => panic!("loaded: {body}"),
            Err(e) => assert_eq!(e.to_string(), want),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Projected images: projectors and spots with a texture
// ---------------------------------------------------------------------------------------------

/// The image the projector and projecting-spot tests use (Mitsuba's suite's, 8-bit sRGB).
const CARROT: &str = "tests/data/mitsuba-suite/common/textures/carrot.png";

/// A projector's or a projecting spot's frame as the scene file's `lookat` makes it (f64,
/// written out from scenes/README.md): local x, y, z.
fn lookat_frame(dir: DVec3, up: DVec3) -> [DVec3; 3] {
    let z = dir.normalize();
    let x = up.cross(z).normalize();
    [x, z.cross(x), z]
}

/// The image-plane coordinates `(a, b)` in [-1, 1] of `v` (from a projector of frame `f` and
/// half-extent tangents `tx`, `ty`), and `v`'s depth along the axis.
fn plane_coords(f: &[DVec3; 3], tx: f64, ty: f64, v: DVec3) -> (f64, f64, f64) {
    let z = v.dot(f[2]);
    (v.dot(f[0]) / (z * tx), v.dot(f[1]) / (z * ty), z)
}

/// A projector above the plane y = 0 ([`plane_under`]), tilted 20 degrees, with a
/// constant irradiance and a 50-degree horizontal field of view.
const PROJ_POS: [f64; 3] = [0.1, 1.2, -0.1];
const PROJ_DIR: [f64; 3] = [0.0, -1.0, 0.364];
const PROJ_FOV: f64 = 50.0;

fn projector_plane() -> Scene {
    let [px, py, pz] = PROJ_POS;
    let [dx, dy, dz] = PROJ_DIR;
    plane_under(&format!(
        r#"type = "projector"
position = [{px}, {py}, {pz}]
direction = [{dx}, {dy}, {dz}]
up = [1.0, 0.0, 0.0]
fov = {PROJ_FOV}
irradiance = [3.0, 2.0, 1.0]
"#
    ))
}

/// Radiance per unit irradiance at `x` on the plane under [`projector_plane`]'s projector,
/// and whether `x` is inside its image: Mitsuba's `pi E |v| / z^3` times the receiver's
/// cosine `h / |v|` times `albedo / pi`, that is `albedo E h / z^3`.
fn projector_radiance(x: DVec3) -> (f64, bool) {
    let p = DVec3::from_array(PROJ_POS);
    let f = lookat_frame(DVec3::from_array(PROJ_DIR), DVec3::X);
    let t = (PROJ_FOV / 2.0).to_radians().tan();
    let (a, b, z) = plane_coords(&f, t, t, x - p);
    let inside = z > 0.0 && a.abs() <= 1.0 && b.abs() <= 1.0;
    (ALBEDO * p.y / z.powi(3), inside)
}

#[test]
fn projector_on_a_plane_is_albedo_e_h_over_z_cubed_inside_its_image() {
    let s = projector_plane();
    let size = 40;
    let n = 8;
    // Per pixel: the analytic mean over the midpoints of an 8 x 8 grid, and how many of the
    // 9 x 9 grid points from corner to corner are inside the image (pixels with some inside
    // and some outside lie across its edge: not compared).
    let at = |x: f64, y: f64| projector_radiance(on_plane(&s.camera, size, size, x, y).unwrap());
    let mut exact = Vec::new();
    for py in 0..size {
        for px in 0..size {
            let (x0, y0) = (px as f64, py as f64);
            let mut sum = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let (l, ok) = at(
                        x0 + (i as f64 + 0.5) / n as f64,
                        y0 + (j as f64 + 0.5) / n as f64,
                    );
                    sum += if ok { l } else { 0.0 };
                }
            }
            let inside = (0..=n)
                .flat_map(|j| (0..=n).map(move |i| (i, j)))
                .filter(|&(i, j)| at(x0 + i as f64 / n as f64, y0 + j as f64 / n as f64).1)
                .count() as u32;
            exact.push((sum / (n * n) as f64, inside));
        }
    }
    let e = [3.0, 2.0, 1.0];
    let mean_want = exact.iter().map(|e| e.0).sum::<f64>() / exact.len() as f64;
    for backend in backends() {
        let img = run(&s, &small(Mode::Direct, 10_000, size, 64), backend);
        let (mut worst, mut lit, mut dark) = (0.0f64, 0, 0);
        for (i, &(want, inside)) in exact.iter().enumerate() {
            let got = img.pixels[i];
            if inside == 0 {
                assert_eq!(
                    got, [0.0; 3],
                    "{backend:?}: pixel {i} outside the image is lit"
                );
                dark += 1;
            } else if inside == (n + 1) * (n + 1) {
                for c in 0..3 {
                    worst = worst.max((got[c] as f64 / e[c] - want).abs() / want);
                }
                lit += 1;
            }
        }
        eprintln!("projector {backend:?}: {lit} pixels inside, {dark} outside; worst rel. error {worst:.2e}");
        assert!(
            lit > 300 && dark > 300,
            "{backend:?}: {lit} inside, {dark} outside"
        );
        // The radiance varies smoothly (1 / z^3) within a pixel: its 64 jittered samples
        // estimate the pixel's mean closely (measured 7.7e-5 on both backends); a projector
        // without the 1 / cos^3 law is off by 20% at the image's corners.
        assert!(worst < 1e-3, "{backend:?}: worst relative error {worst}");

        // Photon mode: the image mean from the projector's photons, uniform over its image
        // plane: ~0.4% noise as for the spot above (100k photons, K = 100), bound 1.6%
        // (measured 0.23% on both backends).
        let rel = photon_mean_error(&s, backend, size, e, mean_want);
        eprintln!("projector photon {backend:?}: mean rel. error {rel:.4}");
        assert!(rel < 0.016, "{backend:?}: photon-mode mean off by {rel}");
    }
}

/// `texture`'s mean over the uv rectangle `[u0, u1] x [v0, v1]` by the midpoints of an
/// `n x n` grid (f64).
fn image_mean(t: &gpu_photon::textures::SceneTexture, [u0, u1, v0, v1]: [f64; 4], n: u32) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for j in 0..n {
        for i in 0..n {
            let u = u0 + (u1 - u0) * (i as f64 + 0.5) / n as f64;
            let v = v0 + (v1 - v0) * (j as f64 + 0.5) / n as f64;
            sum += t.eval(glam::Vec2::new(u as f32, v as f32)).as_dvec3();
        }
    }
    sum / (n * n) as f64
}

#[test]
fn projector_photons_carry_pi_e_a_and_follow_its_image() {
    // A projector 1 above the floor, looking straight down, projecting the carrot: every
    // photon lands on the floor at depth 0 (the image spans 1.15 x 0.92 of its 2.4 x 2.4).
    // Their power in each of 8 x 8 bins of the image is pi E (A / 64) times the image's mean
    // over the bin, and in all pi E A times its mean (within 5 standard errors).
    let image = Path::new(env!("CARGO_MANIFEST_DIR")).join(CARROT);
    let s = plane_under(&format!(
        r#"type = "projector"
position = [0.0, 1.0, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 60.0
irradiance = [1.0, 2.0, 3.0]
scale = 0.5
filename = "{}"
"#,
        image.display()
    ));
    let LightShape::Projector(p) = s.lights[0].shape else {
        panic!("a projector")
    };
    let tex = &s.textures[p.texture.expect("an image") as usize];
    let gpu_photon::textures::SceneTexture::Bitmap(b) = tex else {
        panic!("a bitmap")
    };
    let aspect = b.width as f64 / b.height as f64;
    let tx = 30f64.to_radians().tan();
    let ty = tx / aspect;
    let e = DVec3::new(0.5, 1.0, 1.5);
    let area = 4.0 * tx * ty;
    let want_total = e * PI * area * image_mean(tex, [0.0, 1.0, 0.0, 1.0], 1000);
    let power = DVec3::from_array(s.lights[0].power.to_array().map(f64::from));
    assert!(
        ((power - want_total) / want_total).abs().max_element() < 2e-3,
        "power {power} vs pi E A mean {want_total}"
    );
    let f = lookat_frame(DVec3::NEG_Y, DVec3::NEG_Z);
    let bins = 8;
    let (got, dark) = binned_first_hits(&s, bins * bins, |x| {
        let (a, b, _) = plane_coords(&f, tx, ty, x - DVec3::Y);
        let (u, v) = (0.5 - 0.5 * a, 0.5 - 0.5 * b);
        assert!(
            (-1e-4..=1.0 + 1e-4).contains(&u) && (-1e-4..=1.0 + 1e-4).contains(&v),
            "a photon outside the image: uv ({u}, {v})"
        );
        ((v * bins as f64) as usize).min(bins - 1) * bins
            + ((u * bins as f64) as usize).min(bins - 1)
    });
    let mut want: Vec<DVec3> = (0..bins * bins)
        .map(|k| {
            let (i, j) = ((k % bins) as f64, (k / bins) as f64);
            let r = [i, i + 1.0, j, j + 1.0].map(|x| x / bins as f64);
            e * PI * area / (bins * bins) as f64 * image_mean(tex, r, 128)
        })
        .collect();
    want.push(want_total);
    assert_bins_match(&got, &want, "projector image");
    assert!(dark < 1e-3, "{dark} of the photons carry nothing");
}

#[test]
fn projector_photons_go_where_its_image_is_lit() {
    // A 64 x 32 slide, black but for a 4 x 3 block of texels: a uniform projector would
    // waste 99% of its photons on black; these pass the lit block but for the uniform tenth
    // (`distribution::UNIFORM`) and the block's bilinear rim, and carry its power (pi E A
    // times the image's mean, within 5 standard errors).
    let dir = common::scratch("slide");
    let path = dir.join("slide.png");
    let mut img = image::RgbImage::new(64, 32);
    for (x, y) in (40..44).flat_map(|x| (10..13).map(move |y| (x, y))) {
        img.put_pixel(x, y, image::Rgb([200, 100, 50]));
    }
    img.save(&path).unwrap();
    let s = plane_under(&format!(
        "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n\
         up = [0.0, 0.0, -1.0]\nfov = 60.0\nfilename = \"{}\"\n",
        path.display()
    ));
    let LightShape::Projector(p) = s.lights[0].shape else {
        panic!("a projector")
    };
    let tex = &s.textures[p.texture.expect("an image") as usize];
    let tx = 30f64.to_radians().tan();
    let want = PI * 4.0 * tx * tx / 2.0 * image_mean(tex, [0.0, 1.0, 0.0, 1.0], 2048);
    let (got, dark) = binned_first_hits(&s, 1, |_| 0);
    eprintln!(
        "slide: photons carry {:.6} W, pi E A mean {want:.6} W; {dark:.4} carry nothing",
        got[0].0
    );
    assert_bins_match(&got, &[want, want], "slide");
    let uniform = gpu_photon::lights::projector::distribution::UNIFORM;
    // Measured 14.2%: the uniform tenth on black (9.9%) and the dark parts of the cells
    // around the block that its bilinear edge reaches (4.3%); a uniform projector's: 99%.
    assert!(dark < uniform + 0.06, "{dark} of the photons carry nothing");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn projecting_spot_photons_carry_its_textured_power_by_the_image() {
    // A spot projecting the carrot inside a closed box: every photon's first hit is a wall.
    // The power in each of 4 x 4 bins of the image's uv must be I times the integral of
    // falloff x texel over the directions that see that bin (quadrature over the cone, f64).
    let image = Path::new(env!("CARGO_MANIFEST_DIR")).join(CARROT);
    let (inner, outer): (f64, f64) = (10.0, 35.0);
    let extra = format!("up = [0.0, 0.0, 1.0]\nfilename = \"{}\"\n", image.display());
    let s = spot_box(inner, outer, "linear-angle", &extra);
    let LightShape::Spot(spot) = s.lights[0].shape else {
        panic!("a spot")
    };
    let tex = &s.textures[spot.projection.expect("a projection").texture as usize];
    let f = lookat_frame(DVec3::new(1.0, -2.0, 0.5), DVec3::Z);
    let tan_outer = outer.to_radians().tan();
    let bins = 4;
    let bin_of = |local: DVec3| {
        let (u, v) = (
            0.5 + 0.5 * local.x / (local.z * tan_outer),
            0.5 + 0.5 * local.y / (local.z * tan_outer),
        );
        ((v * bins as f64) as usize).min(bins - 1) * bins
            + ((u * bins as f64) as usize).min(bins - 1)
    };
    // The quadrature: theta by 600 midpoints over [0, outer], phi by 1200.
    let intensity = DVec3::new(3.0, 2.0, 1.0);
    let mut want = vec![DVec3::ZERO; bins * bins];
    let (nt, np) = (600, 1200);
    let dt = outer.to_radians() / nt as f64;
    for i in 0..nt {
        let theta = (i as f64 + 0.5) * dt;
        let att = linear_att(theta.cos(), inner, outer);
        let dphi = 2.0 * PI / np as f64;
        for j in 0..np {
            let phi = (j as f64 + 0.5) * dphi;
            let local = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let uv = glam::Vec2::new(
                (0.5 + 0.5 * local.x / (local.z * tan_outer)) as f32,
                (0.5 + 0.5 * local.y / (local.z * tan_outer)) as f32,
            );
            let texel = tex.eval(uv).as_dvec3();
            want[bin_of(local)] += intensity * att * texel * theta.sin() * dt * dphi;
        }
    }
    let want_total: DVec3 = want.iter().sum();
    let power = DVec3::from_array(s.lights[0].power.to_array().map(f64::from));
    eprintln!("projecting spot: power {power}, quadrature {want_total}");
    // The light's power takes the image's mean over a 64 x 64 grid of the photons' own
    // draws: measured 2e-5 from the quadrature here; bound 1e-3.
    assert!(((power - want_total) / want_total).abs().max_element() < 1e-3);
    let (got, _) = binned_first_hits(&s, bins * bins, |x| {
        let w = (x - DVec3::new(0.1, 0.2, -0.1)).normalize();
        bin_of(DVec3::new(w.dot(f[0]), w.dot(f[1]), w.dot(f[2])))
    });
    want.push(want_total);
    assert_bins_match(&got, &want, "projecting spot");
}

/// The power of 200,000 global photon paths of `s` (traced on the CPU, every path's first
/// hit stored at depth 0) summed in `bins` bins by where that hit lies (`bin`), with each
/// sum's standard error from the photons' own spread (all paths are draws; one landing in
/// another bin adds 0); then the total over all bins, with its own; and the fraction of the
/// first hits that carry no power.
fn binned_first_hits(
    s: &Scene,
    bins: usize,
    bin: impl Fn(DVec3) -> usize,
) -> (Vec<(DVec3, DVec3)>, f64) {
    let n = 200_000;
    let st = RenderSettings {
        photons: n,
        ..RenderSettings::default()
    };
    let (_, photons) = common::trace_global(s, &st);
    let first: Vec<_> = photons.iter().filter(|p| p.depth() == 0).collect();
    assert!(
        first.len() as f64 > n as f64 * (1.0 - 1e-4),
        "{} first hits",
        first.len()
    );
    let (mut sum, mut sq) = (vec![DVec3::ZERO; bins + 1], vec![DVec3::ZERO; bins + 1]);
    for ph in &first {
        let pw = DVec3::from_array(ph.power.map(f64::from));
        for k in [bin(ph.pos().as_dvec3()), bins] {
            sum[k] += pw;
            sq[k] += pw * pw;
        }
    }
    let sigma = |k: usize| {
        (sq[k] - sum[k] * sum[k] / n as f64)
            .max(DVec3::ZERO)
            .powf(0.5)
    };
    let dark = first.iter().filter(|p| p.power == [0.0; 3]).count() as f64 / first.len() as f64;
    ((0..=bins).map(|k| (sum[k], sigma(k))).collect(), dark)
}

/// Each bin's power (`got`: sum, standard error) within 5 standard errors (plus 1e-4 of the
/// total, for bins the image leaves black) of `want`; the last is the total.
fn assert_bins_match(got: &[(DVec3, DVec3)], want: &[DVec3], what: &str) {
    let total = want[want.len() - 1];
    for (k, (&(sum, sigma), w)) in got.iter().zip(want).enumerate() {
        eprintln!("{what} bin {k}: photons {sum:.5}, expected {w:.5} (sigma {sigma:.5})");
        for c in 0..3 {
            assert!(
                (sum[c] - w[c]).abs() <= 5.0 * sigma[c] + 1e-4 * total[c],
                "{what} bin {k} channel {c}: photons {} vs expected {} (sigma {})",
                sum[c],
                w[c],
                sigma[c]
            );
        }
    }
}

#[test]
fn bad_projected_lights_in_toml_give_file_line_field_messages() {
    let head =
        "[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov = 40.0\n[[lights]]\n";
    let cases = [
        (
            "type = \"spot\"\nposition = [0.0, 1.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nouter_angle = 30.0\nup = [0.0, 0.0, 1.0]\n",
            "t.toml:11: lights[0].up: only with `filename` (the projected image's frame)",
        ),
        (
            "type = \"spot\"\nposition = [0.0, 1.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nouter_angle = 30.0\nfilename = \"carrot.png\"\nup = [0.0, 0.0, 1.0]\n",
            "t.toml:11: lights[0].filename: ",
        ),
        (
            "type = \"spot\"\nposition = [0.0, 1.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nouter_angle = 30.0\nfilename = \"x.png\"\nup = [0.0, 2.0, 0.0]\n",
            "t.toml:12: lights[0].up: must not be zero or parallel to the direction",
        ),
        (
            "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\n",
            "t.toml:5: lights[0].fov: missing field `fov`",
        ),
        (
            "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nfov = 0.0\n",
            "t.toml:10: lights[0].fov: must be in (0, 180) degrees (got 0)",
        ),
        (
            "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nfov = 30.0\n",
            "t.toml:5: lights[0].up: the default up (+y) is parallel to the direction: give `up`",
        ),
        (
            "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nfov = 30.0\nirradiance = [1.0, -1.0, 1.0]\n",
            "t.toml:11: lights[0].irradiance: ",
        ),
        (
            "type = \"projector\"\nposition = [0.0, 1.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nfov = 30.0\nintensity = [1.0, 1.0, 1.0]\n",
            "t.toml:11: lights[0].intensity: `intensity` does not apply to type \"projector\"",
        ),
    ];
    for (body, want) in cases {
        match load_str(&format!("{head}{body}"), "t.toml", root()) {
            Ok(_) => panic!("loaded: {body}"),
            Err(e) => assert!(e.to_string().starts_with(want), "{e}\nwant: {want}"),
        }
    }
}
