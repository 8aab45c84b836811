//! Environment lights (`scene::Environment`, `crate::environment`): the furnace (a diffuse
//! sphere under a constant environment reads albedo x L, the background L), the photons'
//! flux, the image distribution's sampler against its pdf (chi-square), CPU = GPU on an image
//! environment, and the command line's `--env` and no-light error.

use glam::{Mat3, Vec3};
use gpu_photon::integrators::photon::Budget;
use gpu_photon::lights::environment::sampling::{self as env, EnvDistribution};
use gpu_photon::lights::table::LightTable;
use gpu_photon::render::film::Image;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{Environment, Material, Origin, Scene, SceneBuilder, Surface};
use gpu_photon::settings::{Mode, RenderSettings};
use gpu_photon::textures::Texture;
use std::f64::consts::PI;

mod common;
mod probes;

const ALBEDO: f32 = 0.5;
const L: Vec3 = Vec3::new(1.0, 0.5, 0.25);

fn at() -> Origin {
    Origin {
        file: "test".into(),
        line: 1,
        field: "scene".into(),
    }
}

/// An 8 x 4 sky: a bright texel (the sun) and a blue-to-grey gradient, linear floats.
fn sky() -> Texture {
    let (w, h) = (8u32, 4u32);
    let mut data = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let t = y as f32 / (h - 1) as f32;
            let mut c = [0.3 + 0.4 * t, 0.4 + 0.3 * t, 1.0 - 0.5 * t];
            if (x, y) == (2, 1) {
                c = [40.0, 36.0, 30.0];
            }
            data.extend_from_slice(&c);
        }
    }
    Texture::from_float("sky", w, h, data, 3).unwrap()
}

/// A unit sphere of albedo [`ALBEDO`] at the origin under `environment` (constant [`L`], or
/// the [`sky`] rotated 30 degrees about y), the camera 4 units away on +z.
fn sphere_scene(image: bool) -> Scene {
    let mut b = SceneBuilder::new();
    b.camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 40.0, &at())
        .unwrap();
    let m = b
        .add_material(None, Material::diffuse(Vec3::splat(ALBEDO)), &at())
        .unwrap();
    b.add_sphere(Vec3::ZERO, 1.0, Surface::of(m), &at())
        .unwrap();
    if image {
        let rot = Mat3::from_rotation_y(30f32.to_radians());
        b.set_environment(Vec3::splat(0.5), Some(sky()), rot, &at())
            .unwrap();
    } else {
        b.set_environment(L, None, Mat3::IDENTITY, &at()).unwrap();
    }
    b.finish(&at()).unwrap()
}

fn settings(s: &Scene, size: u32, spp: u32, mode: Mode) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        spp,
        mode,
        ..s.settings.clone()
    }
}

/// Pixels whose four corners' rays all hit the sphere (`true`) or all miss it (`false`);
/// others (the silhouette) are left out.
fn coverage(s: &Scene, size: u32) -> Vec<Option<bool>> {
    let cam = &s.camera;
    let hits = |x: f32, y: f32| {
        let d = cam.direction(x, y, size, size);
        // |eye + t d| = 1 has a root: (e.d)^2 - (e.e - 1) >= 0.
        let e = cam.eye;
        e.dot(d).powi(2) - (e.dot(e) - 1.0) >= 0.0
    };
    let mut out = Vec::new();
    for y in 0..size {
        for x in 0..size {
            let (x, y) = (x as f32, y as f32);
            let c = [
                hits(x, y),
                hits(x + 1.0, y),
                hits(x, y + 1.0),
                hits(x + 1.0, y + 1.0),
            ];
            out.push(match c {
                [true, true, true, true] => Some(true),
                [false, false, false, false] => Some(false),
                _ => None,
            });
        }
    }
    out
}

fn px(img: &Image, i: usize) -> Vec3 {
    Vec3::from(img.pixels[i])
}

/// Every pixel on the sphere within `tol` (relative) of albedo x L, every background pixel
/// L exactly; returns the mean over the sphere.
fn check_furnace(img: &Image, s: &Scene, tol: f32, what: &str) -> Vec3 {
    let cover = coverage(s, img.width);
    let (mut sum, mut n) = (Vec3::ZERO, 0);
    let want = ALBEDO * L;
    for (i, c) in cover.iter().enumerate() {
        let p = px(img, i);
        match c {
            Some(true) => {
                let err = ((p - want) / want).abs().max_element();
                assert!(err <= tol, "{what}: pixel {i} reads {p}, want {want}");
                sum += p;
                n += 1;
            }
            Some(false) => assert_eq!(p, L, "{what}: background pixel {i}"),
            None => {}
        }
    }
    assert!(n > 100, "{what}: only {n} pixels on the sphere");
    sum / n as f32
}

/// Shadow rays cosine-sample the constant environment about the normal: a Lambertian
/// sphere's estimate is exact, and every pixel reads albedo x L (0.5% asked; f32 rounding).
#[test]
fn furnace_cpu() {
    let s = sphere_scene(false);
    for mode in [Mode::Gather, Mode::Direct] {
        let st = settings(&s, 32, 1, mode);
        let (img, _) = render(&s, &st, Backend::Cpu, Progress::default()).unwrap();
        check_furnace(&img, &s, 0.005, &format!("cpu {mode:?}"));
    }
}

/// Photon mode estimates the same light from the environment's photons alone (their disc,
/// directions and power): the sphere's mean within 2%, each pixel within 50% (K-nearest
/// noise).
#[test]
fn furnace_by_photons_cpu() {
    let s = sphere_scene(false);
    let st = RenderSettings {
        photons: 400_000,
        ..settings(&s, 24, 1, Mode::Photon)
    };
    let (img, _) = render(&s, &st, Backend::Cpu, Progress::default()).unwrap();
    let mean = check_furnace(&img, &s, 0.5, "cpu photons");
    eprintln!("photon furnace mean {mean}");
    let err = ((mean - ALBEDO * L) / (ALBEDO * L)).abs().max_element();
    assert!(err < 0.02, "photon furnace mean {mean} vs {}", ALBEDO * L);
}

#[test]
fn furnace_gpu() {
    if common::gpu().is_none() {
        return;
    }
    let s = sphere_scene(false);
    let st = settings(&s, 32, 1, Mode::Gather);
    let (img, _) = render(&s, &st, Backend::Gpu, Progress::default()).unwrap();
    check_furnace(&img, &s, 0.005, "gpu gather");
    let st = RenderSettings {
        photons: 400_000,
        ..settings(&s, 24, 1, Mode::Photon)
    };
    let (img, _) = render(&s, &st, Backend::Gpu, Progress::default()).unwrap();
    let mean = check_furnace(&img, &s, 0.5, "gpu photons");
    let err = ((mean - ALBEDO * L) / (ALBEDO * L)).abs().max_element();
    assert!(
        err < 0.02,
        "gpu photon furnace mean {mean} vs {}",
        ALBEDO * L
    );
}

/// Emits `n` photons of the environment (the scene's last light): per photon its power
/// (path power x scale) and whether its ray meets the unit sphere at the origin.
fn emitted(s: &Scene, n: u32) -> Vec<(Vec3, bool)> {
    let table = LightTable::new(s);
    let l = s.lights.len() - 1;
    let budget = Budget::split(s, n);
    let mut rng = common::TestRng(7);
    (0..n)
        .map(|_| {
            let u = [rng.f32(), rng.f32(), rng.f32(), rng.f32(), rng.f32()];
            let e = table.emit(s, l, u);
            let b = e.origin.dot(e.dir);
            let hits = b * b - (e.origin.length_squared() - 1.0) >= 0.0 && b < 0.0;
            (budget.path_power[l] * e.scale, hits)
        })
        .collect()
}

/// Mean and standard error of `xs`.
fn mean_err(xs: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = xs.clone().count() as f64;
    let m = xs.clone().sum::<f64>() / n;
    let v = xs.map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (v / n).sqrt())
}

/// The photons carry the environment's flux through the disc, pi R^2 times the radiance's
/// integral over directions (4 pi^2 R^2 L for a constant one), and the unit sphere inside
/// receives its share, 4 pi^2 L for a constant L (the integral of pi L over its area):
/// within 4 standard errors of the count.
#[test]
fn photons_carry_the_analytic_flux() {
    let n = 200_000;
    let s = sphere_scene(false);
    let (_, r) = s.bounding_sphere();
    let total = 4.0 * PI * PI * (r as f64).powi(2) * L.x as f64;
    let photons = emitted(&s, n);
    let sum: f64 = photons.iter().map(|p| p.0.x as f64).sum();
    assert!((sum / total - 1.0).abs() < 1e-4, "emitted {sum} vs {total}");
    let onto = photons.iter().map(|p| if p.1 { p.0.x as f64 } else { 0.0 });
    let (m, e) = mean_err(onto);
    let want = 4.0 * PI * PI * L.x as f64;
    let got = m * n as f64;
    assert!(
        (got - want).abs() < 4.0 * e * n as f64,
        "onto the sphere {got} vs {want} (+- {})",
        e * n as f64
    );

    // An image: the power is pi R^2 times the integral of the radiance (the image's
    // luminance drives the directions, each photon carries L / pdf).
    let s = sphere_scene(true);
    let power = s.lights.last().unwrap().power;
    let integral = sky_integral(0.5);
    let want = integral * (std::f64::consts::PI * (r as f64).powi(2));
    assert!(
        (power.as_dvec3() / want - 1.0).abs().max_element() < 5e-3,
        "power {power} vs {want}"
    );
    let photons = emitted(&s, n);
    for c in 0..3 {
        let (m, e) = mean_err(photons.iter().map(|p| p.0[c] as f64));
        let (got, err) = (m * n as f64, e * n as f64);
        assert!(
            (got - want[c]).abs() < 4.0 * err + 5e-3 * want[c],
            "channel {c}: {got} vs {} +- {err}",
            want[c]
        );
        let onto = photons
            .iter()
            .map(|p| if p.1 { p.0[c] as f64 } else { 0.0 });
        let (m, e) = mean_err(onto);
        let (got, err) = (m * n as f64, e * n as f64);
        // The unit sphere's share of the flux through a disc of radius R is 1 / R^2.
        let want = want[c] / (r as f64).powi(2);
        assert!(
            (got - want).abs() < 4.0 * err + 5e-3 * want,
            "onto, channel {c}: {got} vs {want} +- {err}"
        );
    }
}

/// The integral over directions of `scale` x the sky's bilinear lookup, by a fine midpoint
/// rule in (u, v) of Mitsuba's lat-long map (dw = 2 pi^2 sin(pi v) du dv).
fn sky_integral(scale: f64) -> glam::DVec3 {
    let t = sky();
    let (nu, nv) = (400, 200);
    let mut sum = glam::DVec3::ZERO;
    for j in 0..nv {
        let v = (j as f64 + 0.5) / nv as f64;
        for i in 0..nu {
            let u = (i as f64 + 0.5) / nu as f64;
            let c = gpu_photon::lights::environment::latlong_lookup(
                &t,
                glam::Vec2::new(u as f32, v as f32),
            );
            sum += c.as_dvec3() * (PI * v).sin();
        }
    }
    sum * (2.0 * PI * PI * scale / (nu * nv) as f64)
}

/// Standard normal upper tail.
fn normal_q(z: f64) -> f64 {
    // Abramowitz and Stegun 7.1.26 on erfc(z / sqrt 2).
    let x = z.abs() / 2f64.sqrt();
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let erfc = poly * (-x * x).exp();
    if z >= 0.0 {
        0.5 * erfc
    } else {
        1.0 - 0.5 * erfc
    }
}

/// The image distribution's directions against its own pdf: chi-square over 16 x 32 bins of
/// (theta, phi) in world space (expected counts by a 6 x 6 midpoint rule of the pdf per bin),
/// bins expecting < 5 pooled; p-value by Wilson-Hilferty, > 1e-3. The sampled pdf equals
/// `direction_pdf` at the sampled direction.
#[test]
fn envmap_sampling_matches_its_pdf() {
    const NT: usize = 16;
    const NP: usize = 32;
    const SUB: usize = 6;
    let samples = 400_000usize;
    let s = sphere_scene(true);
    let e = *s.environment().unwrap();
    let dist = env::distribution(&e, &s.textures).unwrap();
    let bin = |d: Vec3| {
        let t = (d.y as f64).clamp(-1.0, 1.0).acos() / PI * NT as f64;
        let mut p = (d.z as f64).atan2(d.x as f64);
        if p < 0.0 {
            p += 2.0 * PI;
        }
        let p = p / (2.0 * PI) * NP as f64;
        (t as usize).min(NT - 1) * NP + (p as usize).min(NP - 1)
    };
    let mut rng = common::TestRng(11);
    let mut observed = vec![0.0f64; NT * NP];
    let ns = Vec3::Y;
    for _ in 0..samples {
        let u = [rng.f32(), rng.f32(), rng.f32()];
        let (d, pdf) = env::sample_direction(&e, Some(&dist), ns, u);
        let back = env::direction_pdf(&e, Some(&dist), ns, d);
        // (Near the poles f32's acos of y loses the density's sin(theta).)
        assert!(
            d.y.abs() > 0.9998 || (pdf - back).abs() <= 2e-3 * pdf.max(back) + 1e-6,
            "pdf {pdf} vs {back} at {d}"
        );
        observed[bin(d)] += 1.0;
    }
    let mut expected = vec![0.0f64; NT * NP];
    let (dt, dp) = (PI / NT as f64, 2.0 * PI / NP as f64);
    for i in 0..NT {
        for j in 0..NP {
            let mut sum = 0.0;
            for a in 0..SUB {
                for b in 0..SUB {
                    let t = (i as f64 + (a as f64 + 0.5) / SUB as f64) * dt;
                    let p = (j as f64 + (b as f64 + 0.5) / SUB as f64) * dp;
                    let d = Vec3::new(
                        (t.sin() * p.cos()) as f32,
                        t.cos() as f32,
                        (t.sin() * p.sin()) as f32,
                    );
                    sum += env::direction_pdf(&e, Some(&dist), ns, d) as f64 * t.sin();
                }
            }
            expected[i * NP + j] = sum / (SUB * SUB) as f64 * dt * dp * samples as f64;
        }
    }
    let total: f64 = expected.iter().sum();
    assert!(
        (total / samples as f64 - 1.0).abs() < 0.01,
        "the pdf integrates to {}",
        total / samples as f64
    );
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut chi2, mut dof, mut pe, mut po) = (0.0, 0usize, 0.0, 0.0);
    for k in order {
        if expected[k] < 5.0 {
            pe += expected[k];
            po += observed[k];
            if pe < 5.0 {
                continue;
            }
            chi2 += (po - pe) * (po - pe) / pe;
            (pe, po) = (0.0, 0.0);
        } else {
            chi2 += (observed[k] - expected[k]).powi(2) / expected[k];
        }
        dof += 1;
    }
    let k = (dof - 1) as f64;
    let z = ((chi2 / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    let p = normal_q(z);
    assert!(p > 1e-3, "chi2 {chi2:.1} over {k} dof: p = {p:.2e}");
}

/// The distribution is Mitsuba's: luminance x sin(theta) on the (W + 1) x H grid, u
/// shifted by half a texel; its uv density integrates to one and peaks at the sun.
#[test]
fn envmap_distribution_is_luminance_times_sin_theta() {
    let t = sky();
    let d = EnvDistribution::new(&t);
    assert_eq!(
        (d.width, d.height, d.grid.len(), d.cdf.len()),
        (8, 4, 9 * 4, 8 * 3)
    );
    let sun = gpu_photon::lights::environment::luminance(Vec3::new(40.0, 36.0, 30.0));
    let want = sun * (std::f32::consts::PI / 3.0).sin();
    assert!((d.grid[9 + 2] - want).abs() < 1e-4 * want);
    assert_eq!(d.grid[9 + 8], d.grid[9], "column W repeats column 0");
    // The sun's texel centre, u = 2.5 / 8, v = 1 / 3, has the largest density.
    let peak = d.pdf_uv(glam::Vec2::new(2.5 / 8.0, 1.0 / 3.0));
    assert!((peak - d.grid[11] / d.integral).abs() < 1e-3 * peak);
    let n = 400;
    let mut sum = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let uv = glam::Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            sum += d.pdf_uv(uv) as f64;
        }
    }
    assert!(
        (sum / (n * n) as f64 - 1.0).abs() < 1e-3,
        "uv density integrates to {}",
        sum / (n * n) as f64
    );
    // Mitsuba's uv <-> direction: +y is v = 0, -z is u = 0, +x is u = 1/4.
    let uv = gpu_photon::lights::environment::latlong_uv(Vec3::X);
    assert!((uv - glam::Vec2::new(0.25, 0.5)).abs().max_element() < 1e-6);
    let d = gpu_photon::lights::environment::latlong_dir(glam::Vec2::new(0.0, 0.5));
    assert!((d - Vec3::NEG_Z).abs().max_element() < 1e-6);
}

/// The GPU renders an image environment as the CPU does: the whole image, mean and per
/// 4 x 4 block, within 5 standard errors of the CPU's own spread over two seeds (gather mode;
/// the background, seen directly, to f32 rounding).
#[test]
fn gpu_renders_an_envmap_as_the_cpu_does() {
    if common::gpu().is_none() {
        return;
    }
    let s = sphere_scene(true);
    let st = settings(&s, 16, 16, Mode::Gather);
    let (cpu, _) = render(&s, &st, Backend::Cpu, Progress::default()).unwrap();
    let other = RenderSettings {
        seed: st.seed + 1,
        ..st.clone()
    };
    let (cpu2, _) = render(&s, &other, Backend::Cpu, Progress::default()).unwrap();
    let (gpu, _) = render(&s, &st, Backend::Gpu, Progress::default()).unwrap();
    let cover = coverage(&s, 16);
    for (i, c) in cover.iter().enumerate() {
        if *c == Some(false) {
            let (a, b) = (px(&cpu, i), px(&gpu, i));
            assert!(
                (a - b).abs().max_element() <= 1e-4 * a.max_element().max(1.0),
                "background {i}: cpu {a} gpu {b}"
            );
        }
    }
    // Blocks: the seed-to-seed difference sets the noise of one render's block mean.
    for by in 0..4 {
        for bx in 0..4 {
            let block = |img: &Image| {
                let mut sum = Vec3::ZERO;
                for y in 0..4 {
                    for x in 0..4 {
                        sum += px(img, (by * 4 + y) * 16 + bx * 4 + x);
                    }
                }
                sum / 16.0
            };
            let (a, a2, g) = (block(&cpu), block(&cpu2), block(&gpu));
            let noise = (a - a2).abs().max_element() / std::f32::consts::SQRT_2;
            let tol = 5.0 * noise + 0.01 * a.max_element();
            assert!(
                (a - g).abs().max_element() <= tol,
                "block ({bx}, {by}): cpu {a} gpu {g} (seed noise {noise})"
            );
        }
    }
}

/// The device's environment functions equal the Rust ones on the same inputs: the image
/// lookup and its pdf at 300 directions (away from the poles), within the Rust values'
/// range over directions 3e-4 rad around (lavapipe's atan2 and acos differ from Rust's by up to
/// ~1e-4 rad, within Vulkan's 4096 ulp, and the sky's steep sun turns that into 1e-3 of
/// radiance) plus 1e-4 relative; and the shadow-ray sample (direction and pdf) from 300
/// uniform triples to 2e-4.
#[test]
fn device_environment_equals_rust() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let s = sphere_scene(true);
    let e = *s.environment().unwrap();
    let dist = env::distribution(&e, &s.textures).unwrap();
    let mut rng = common::TestRng(5);
    let mut cases = Vec::new();
    while cases.len() < 300 {
        let d = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let ns = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        if !(0.1..=1.0).contains(&d.length()) || ns.length() < 0.1 || d.normalize().y.abs() > 0.99 {
            continue;
        }
        let u = [rng.f32(), rng.f32(), rng.f32()];
        cases.push((d.normalize(), ns.normalize(), u));
    }
    let input: Vec<_> = cases
        .iter()
        .map(|(d, ns, u)| (d.to_array(), ns.to_array(), *u))
        .collect();
    let out = probes::environment(&ctx, &s, &input).unwrap();
    // [lookup r, g, b, pdf] at d and at eight directions 3e-4 rad around it.
    let rust = |d: Vec3, ns: Vec3| {
        let l = e.eval(&s.textures, d);
        [l.x, l.y, l.z, env::direction_pdf(&e, Some(&dist), ns, d)]
    };
    let close = |a: f32, b: f32| (a - b).abs() <= 2e-4 * a.abs().max(b.abs()) + 1e-6;
    let mut bad = Vec::new();
    for ((d, ns, u), (look, sample)) in cases.iter().zip(&out) {
        let (t, b) = gpu_photon::math::sampling::basis(*d);
        let ring = [t, -t, b, -b, t + b, t - b, b - t, -t - b];
        let around = ring.map(|a| rust((*d + 3e-4 * a.normalize()).normalize(), *ns));
        let centre = rust(*d, *ns);
        let within = (0..4).all(|c| {
            let lo = around.iter().map(|v| v[c]).fold(centre[c], f32::min);
            let hi = around.iter().map(|v| v[c]).fold(centre[c], f32::max);
            let slack = 1e-4 * hi.abs() + 1e-6;
            look[c] >= lo - slack && look[c] <= hi + slack
        });
        let (sd, sp) = env::sample_direction(&e, Some(&dist), *ns, *u);
        let sampled = (0..3).all(|c| (sd[c] - sample[c]).abs() < 2e-4)
            && (sd.y.abs() > 0.999 || close(sp, sample[3]));
        if !(within && sampled) {
            bad.push(format!(
                "{d} {u:?}: rust {centre:?} {sd} {sp}, device {look:?} {sample:?}"
            ));
        }
    }
    assert!(
        bad.is_empty(),
        "{} of 300 differ, e.g. {}",
        bad.len(),
        bad[0]
    );
}

/// A scene with no light and no environment is an error that says so; `--env R,G,B` lights
/// it (and `--env-scale` scales it), and the camera sees the radiance given.
#[test]
fn no_light_is_an_error_and_env_lights_the_scene() {
    let dir = std::env::temp_dir().join(format!("gpu-photon-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("dark.toml");
    std::fs::write(
        &scene,
        "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n\n\
         [materials.grey]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"grey\"\n",
    )
    .unwrap();
    let out = dir.join("dark.exr");
    let run = common::bin()
        .args(["render", "--backend", "cpu", "-o"])
        .arg(&out)
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    let want = format!(
        "{}: the scene has no light (add one, or give --env)",
        scene.display()
    );
    assert!(stderr.contains(&want), "stderr: {stderr}");
    assert!(!out.exists());
    let run = common::bin()
        .args([
            "render",
            "--backend",
            "cpu",
            "--spp",
            "1",
            "--env",
            "0.5,1,2",
            "--env-scale",
            "2",
            "-o",
        ])
        .arg(&out)
        .arg(&scene)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let img = Image::read(&out).unwrap();
    // The corner pixel sees the environment.
    assert_eq!(Vec3::from(img.pixels[0]), Vec3::new(1.0, 2.0, 4.0));
    // An image: the same rays see twice the radiance with --env-scale 2.
    let sky =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/envlight-sky.exr");
    let corner = |scale: &str| {
        let run = common::bin()
            .args([
                "render",
                "--backend",
                "cpu",
                "--spp",
                "1",
                "--env-scale",
                scale,
                "--env",
            ])
            .arg(&sky)
            .arg("-o")
            .arg(&out)
            .arg(&scene)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        Vec3::from(Image::read(&out).unwrap().pixels[0])
    };
    let (one, two) = (corner("1"), corner("2"));
    assert!(
        one.min_element() > 0.0 && (two - 2.0 * one).abs().max_element() < 1e-6 * two.max_element(),
        "{one} {two}"
    );
    // A malformed value names the flag.
    let run = common::bin()
        .args(["render", "--env", "1,2", "-o"])
        .arg(&out)
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr
            .contains("invalid setting env: 1,2: expected R,G,B (three numbers) or an image file"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The scene formats: TOML `[environment]` and Mitsuba's `constant` give the same light.
#[test]
fn toml_and_mitsuba_constant_environments() {
    let toml = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\n\n\
                [environment]\nradiance = [1, 0.5, 0.25]\n";
    let s = gpu_photon::importers::load_str(toml, "env.toml", std::path::Path::new(".")).unwrap();
    assert_eq!(s.environment(), Some(&Environment::constant(L)));
    let xml = r#"<scene version="3.0.0">
        <sensor type="perspective"><float name="fov" value="40"/></sensor>
        <emitter type="constant"><rgb name="radiance" value="1, 0.5, 0.25"/></emitter>
    </scene>"#;
    let dir = std::env::temp_dir().join(format!("gpu-photon-envxml-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("env.xml");
    std::fs::write(&path, xml).unwrap();
    let m = gpu_photon::importers::load(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(m.environment(), Some(&Environment::constant(L)));
    let both = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\n\n\
                [environment]\nradiance = [1, 1, 1]\nfilename = \"sky.exr\"\n";
    let e = gpu_photon::importers::load_str(both, "env.toml", std::path::Path::new("."))
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "env.toml:8: environment.filename: give `radiance` or `filename`, not both"
    );
    let missing = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\n\n\
                   [environment]\nfilename = \"no-such-sky.exr\"\nscale = 2\n";
    let e = gpu_photon::importers::load_str(missing, "env.toml", std::path::Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("env.toml:7: environment.filename: "), "{e}");
    let negative = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\n\n\
                    [environment]\nradiance = [1, -1, 1]\n";
    let e = gpu_photon::importers::load_str(negative, "env.toml", std::path::Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("env.toml:7: environment.radiance: "), "{e}");
}

/// `scenes/mitsuba/envlight.xml` (a diffuse and a glass sphere on a plane under a sky with a
/// sun, `envmap` rotated by `to_world`), our default render on the CPU against its Mitsuba
/// 3.9.1 reference `tests/data/envlight.exr` (two halves of 2,048 spp, seeds 1 and 2, by
/// `scripts/envlight_reference.py`; its own 16x16-block noise 0.00033): every channel's mean
/// within 1%, 16x16-block RMSE at most 0.003 (measured: 0.9991, 0.9998, 1.0000; 0.0017).
#[test]
fn envlight_default_render_matches_the_mitsuba_reference() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = gpu_photon::importers::load(&root.join("scenes/mitsuba/envlight.xml")).unwrap();
    let s = scene.settings.as_default_render();
    let (img, _) = render(&scene, &s, Backend::Cpu, Progress::default()).unwrap();
    let reference = Image::read(&root.join("tests/data/envlight.exr")).unwrap();
    let d = gpu_photon::render::image_diff::diff(&img, &reference, 16).unwrap();
    eprintln!("envlight, default render vs Mitsuba: {d:?}");
    for (c, r) in d.mean_ratio.iter().enumerate() {
        assert!((r - 1.0).abs() < 0.01, "channel {c}: mean ratio {r}");
    }
    assert!(d.block_rmse <= 0.003, "block RMSE {}", d.block_rmse);
}

/// A lone ground quad at y = -1 under a constant environment: every pixel reads albedo x L
/// (the plane sees the whole upper hemisphere) or L, on both backends. The GPU's traversal
/// grid once decoded a flat box at y = -1 as y = 0 (`gpu::bvh_layout::axis_grid`), and its
/// camera rays missed the quad's near half.
#[test]
fn a_ground_plane_under_the_sky_on_both_backends() {
    let toml = "[camera]\neye = [0, 0.6, 3.4]\ntarget = [0, -0.5, 0]\nfov = 40\n\
                width = 32\nheight = 32\n\n\
                [materials.grey]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n\
                [[shapes]]\ntype = \"quad\"\nmaterial = \"grey\"\n\
                corners = [[-2.5, -1, 2.5], [2.5, -1, 2.5], [2.5, -1, -2.5], [-2.5, -1, -2.5]]\n\n\
                [environment]\nradiance = [1, 0.5, 0.25]\n";
    let s =
        gpu_photon::importers::load_str(toml, "ground.toml", std::path::Path::new(".")).unwrap();
    let st = settings(&s, 32, 1, Mode::DirectOnly);
    let mut counts = Vec::new();
    for b in [Backend::Cpu, Backend::Gpu] {
        if b == Backend::Gpu && common::gpu().is_none() {
            continue;
        }
        let (img, _) = render(&s, &st, b, Progress::default()).unwrap();
        let mut ground = Vec::new();
        for (i, p) in img.pixels.iter().enumerate() {
            let p = Vec3::from(*p);
            let on = (p - ALBEDO * L).abs().max_element() < 1e-5;
            assert!(
                on || (p - L).abs().max_element() < 1e-6,
                "{b:?}: pixel {i} {p}"
            );
            if on {
                ground.push(i);
            }
        }
        counts.push(ground);
    }
    // The quad fills the lower 18 rows but for its far corners' edges (578 pixels); the GPU
    // with the fault saw 465 of them.
    assert!(
        counts[0].len() > 18 * 32,
        "{} ground pixels",
        counts[0].len()
    );
    if let Some(gpu) = counts.get(1) {
        assert_eq!(gpu, &counts[0], "the GPU sees the ground at other pixels");
    }
}

/// Mitsuba's environments: a missing or unreadable `filename` and a second environment are
/// errors located at their line and parameter.
#[test]
fn mitsuba_environment_errors_are_located() {
    let dir = std::env::temp_dir().join(format!("gpu-photon-envbad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        (
            r#"<emitter type="envmap"><float name="scale" value="2"/></emitter>"#,
            ":3: emitter[0].filename: missing",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="nope.exr"/></emitter>"#,
            ":3: emitter[0].filename: ",
        ),
        (
            r#"<emitter type="constant"/>
  <emitter type="constant"><rgb name="radiance" value="2"/></emitter>"#,
            ":4: emitter[1].radiance: the scene has one environment",
        ),
    ];
    for (i, (emitter, want)) in cases.iter().enumerate() {
        let path = dir.join(format!("bad{i}.xml"));
        let xml = format!(
            "<scene version=\"3.0.0\">\n  <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n  {emitter}\n</scene>\n"
        );
        std::fs::write(&path, xml).unwrap();
        let e = gpu_photon::importers::load(&path).unwrap_err().to_string();
        assert!(e.contains(want), "case {i}: {e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `scenes/mitsuba/envlight.xml` (an image environment over glass, a diffuse sphere and a
/// ground plane) at 32 x 32, one pass: the GPU's image is no farther from a second CPU seed
/// than the first CPU seed is (per pixel and 8x8 blocks; `common::within_seed_noise`).
#[test]
fn gpu_renders_the_envlight_scene_as_the_cpu_does() {
    if common::gpu().is_none() {
        return;
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = gpu_photon::importers::load(&root.join("scenes/mitsuba/envlight.xml")).unwrap();
    let s = RenderSettings {
        photons: 50_000,
        caustic_photons: 50_000,
        ..settings(&scene, 32, 16, Mode::Gather)
    };
    let (d, noise) = common::gpu_and_seed_diffs(&scene, &s);
    eprintln!("envlight 32x32: gpu vs cpu seed 2 {d:?}, cpu seeds {noise:?}");
    let (pixels, blocks) = common::within_seed_noise(&d, &noise, 1e-4);
    assert!(pixels && blocks, "gpu {d:?} vs seeds {noise:?}");
}

#[test]
fn a_gltf_without_lights_is_lit_by_a_white_environment() {
    // One triangle, no light: as in most Khronos sample models.
    let json = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"scene":0,"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]}"#;
    let scene = gpu_photon::importers::gltf::load_slice(
        json.as_bytes(),
        "t.gltf",
        std::path::Path::new("."),
        None,
    )
    .unwrap();
    assert_eq!(scene.lights.len(), 1);
    let env = scene.environment().expect("an environment");
    assert_eq!(
        env.radiance,
        gpu_photon::importers::gltf::DEFAULT_ENVIRONMENT
    );
    assert_eq!(env.texture, gpu_photon::scene::NO_TEXTURE);
    // The command line renders it and says how it is lit.
    let dir = common::scratch("gltf-no-light");
    let (file, out) = (dir.join("t.gltf"), dir.join("t.exr"));
    std::fs::write(&file, json).unwrap();
    let run = common::bin()
        .args([
            "render",
            "--backend",
            "cpu",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
        ])
        .args(["--passes", "1", "-q", "-o"])
        .arg(&out)
        .arg(&file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let want = format!(
        "warning: {}: no light in the scene: lit by a uniform white environment of radiance 1 \
         (as model viewers light a model; --env replaces it)",
        file.display()
    );
    assert!(stderr.contains(&want), "{stderr}");
    let image = gpu_photon::render::film::Image::read(&out).unwrap();
    assert!(image.mean().iter().all(|m| *m > 0.0 && m.is_finite()));
}
