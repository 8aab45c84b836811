//! Renders on the CPU backend measured against the independent reference images in
//! `tests/data/` (Mitsuba 3 path tracer, 16,384 spp; their scenes and conventions: `scenes/README.md`),
//! against the analytic image of the point-light plane, and a smoke render of every scene.
//!
//! On failure the rendered image and |render - reference| are written to
//! `target/test-output/` for inspection.
//!
//! The glTF importer's tests (`gltf.rs`) are in this test binary too: they compare the glTF
//! Cornell box with the TOML one at its default settings, the image the reference test
//! renders, and both read it from [`cornell_box_default_render`] (one render, not two).

#[path = "../common/mod.rs"]
mod common;
mod gltf;

use glam::DVec3;
use gpu_photon::importers::load;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::{diff, DiffStats};
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{LightShape, Scene};
use gpu_photon::settings::{Mode, RenderSettings};
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn load_scene(name: &str) -> Scene {
    let path = root().join("scenes").join(name);
    load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn reference(name: &str) -> Image {
    let path = root().join("tests/data").join(name);
    Image::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn render_cpu(scene: &Scene, settings: &RenderSettings) -> Image {
    let (img, _) = render(scene, settings, Backend::Cpu, Progress::default()).expect("CPU render");
    assert_eq!((img.width, img.height), (settings.width, settings.height));
    img
}

/// `scenes/cornell-box.toml` rendered on the CPU at its default settings (what
/// `gpu-photon render` renders with no flags), once per test binary: the reference test
/// below and `gltf.rs`'s TOML twin both compare this image (the render is deterministic, so
/// sharing it changes nothing but the time).
fn cornell_box_default_render() -> &'static Image {
    static IMAGE: std::sync::OnceLock<Image> = std::sync::OnceLock::new();
    IMAGE.get_or_init(|| {
        let scene = load_scene("cornell-box.toml");
        render_cpu(&scene, &scene.settings.as_default_render())
    })
}

/// Writes `img` and |img - reference| to `target/test-output/NAME.exr` and `NAME-error.exr`.
fn save_for_inspection(name: &str, img: &Image, reference: Option<&Image>) -> PathBuf {
    let dir = root().join("target/test-output");
    std::fs::create_dir_all(&dir).expect("create target/test-output");
    let out = dir.join(format!("{name}.exr"));
    img.write(&out, 0.0).expect("write rendered image");
    if let Some(r) = reference {
        img.abs_diff(r)
            .write(&dir.join(format!("{name}-error.exr")), 0.0)
            .expect("write error image");
    }
    out
}

/// Asserts every `(ok, message)` check, saving the images first when any fails.
#[track_caller]
fn check_all(name: &str, img: &Image, reference: Option<&Image>, checks: &[(bool, String)]) {
    let failed: Vec<&str> = checks
        .iter()
        .filter(|c| !c.0)
        .map(|c| c.1.as_str())
        .collect();
    if !failed.is_empty() {
        let out = save_for_inspection(name, img, reference);
        panic!(
            "{name}: {} (images in {})",
            failed.join("; "),
            out.parent().unwrap().display()
        );
    }
}

fn ratio_ok(d: &DiffStats, lo: f64, hi: f64) -> bool {
    d.mean_ratio.iter().all(|r| (lo..=hi).contains(r))
}

// ---------------------------------------------------------------------------------------------
// Cornell box vs the path-traced reference
// ---------------------------------------------------------------------------------------------

#[test]
fn cornell_box_default_settings_match_reference() {
    let scene = load_scene("cornell-box.toml");
    // What `gpu-photon render` renders with no flags is what the reference is compared with.
    let settings = scene.settings.as_default_render();
    assert_eq!(settings.pass_range, Some((0, 4)));
    assert_eq!(
        (settings.width, settings.height, settings.mode),
        (256, 256, Mode::Gather)
    );
    let img = cornell_box_default_render();
    let reference = reference("cornell-diffuse.exr");
    let d = diff(img, &reference, 16).expect("same size");
    eprintln!("cornell-box: {d:?}");
    check_all(
        "cornell-box",
        &img,
        Some(&reference),
        &[
            (
                img.non_finite() == 0,
                format!("{} non-finite pixels", img.non_finite()),
            ),
            // Bias: the mean of 65,536 pixels has negligible noise (block RMSE ~0.003 against
            // reference means of 0.34, 0.23, 0.068), so a 2% band only admits the estimator's
            // own bias (measured 0.998). Indirect light is 14-23% of the image (the
            // direct-only view measures 0.77, 0.80, 0.86 of the reference), so a 10% error in
            // the photon map's estimate, a wrong light power or BRDF normalisation shows.
            (
                ratio_ok(&d, 0.98, 1.02),
                format!("mean ratio {:?} outside 0.98..1.02", d.mean_ratio),
            ),
            // Per-pixel RMSE is dominated by area-light sampling and the gather ray at the
            // scene's 4 passes of 32 spp (measured 0.0039 with Sobol samples; the
            // reference's own is 0.0014). 0.0058 is issue 10's target (Mitsuba's error at
            // 1,024 spp).
            (d.rmse < 0.0058, format!("RMSE {} >= 0.0058", d.rmse)),
            // 16x16 block means keep bias and lose most noise (measured 0.00096 in `gather`):
            // a shifted or blurred shadow, a colour-bleeding error, or the photon map's
            // blotches show here (`direct` mode, which reads the global map at every sample,
            // measures 0.0028 and fails this bound).
            (
                d.block_rmse < 0.002,
                format!("block RMSE {} >= 0.002", d.block_rmse),
            ),
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Point light over a plane: the analytic image
// ---------------------------------------------------------------------------------------------

const EYE: DVec3 = DVec3::new(0.0, 3.0, 3.0);
const FOV_Y_DEG: f64 = 45.0;
const LIGHT: DVec3 = DVec3::new(0.25, 1.0, -0.25);
const INTENSITY: [f64; 3] = [12.0, 10.0, 8.0];
const ALBEDO: f64 = 0.8;

/// The reference convention (README): direction through raster (px, py), row 0 at the top.
fn camera_dir(px: f64, py: f64, w: f64, h: f64) -> DVec3 {
    let forward = (DVec3::ZERO - EYE).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    let t = (FOV_Y_DEG.to_radians() / 2.0).tan();
    (forward + (2.0 * px / w - 1.0) * t * (w / h) * right + (1.0 - 2.0 * py / h) * t * up)
        .normalize()
}

/// Where the ray through raster (px, py) meets the plane y = 0.
fn plane_point(px: f64, py: f64) -> DVec3 {
    let d = camera_dir(px, py, 256.0, 256.0);
    assert!(d.y < 0.0, "every pixel looks down at the plane");
    EYE + d * (-EYE.y / d.y)
}

/// Exact radiance of the plane at `x` (Lambertian, direct light only: nothing else to bounce
/// from; `common::point_lit_plane_radiance`).
fn analytic(x: DVec3) -> [f64; 3] {
    common::point_lit_plane_radiance(ALBEDO, INTENSITY, LIGHT, x)
}

/// The scene file must be the scene the constants above describe.
fn check_point_light_scene(scene: &Scene) {
    let c = &scene.camera;
    assert!((c.eye.as_dvec3() - EYE).length() < 1e-6);
    assert!((c.forward.as_dvec3() - (-EYE).normalize()).length() < 1e-6);
    assert!((c.up.length() as f64 - (FOV_Y_DEG.to_radians() / 2.0).tan()).abs() < 1e-6);
    assert_eq!(scene.lights.len(), 1);
    let LightShape::Point(gpu_photon::lights::point::Point {
        position,
        intensity,
    }) = scene.lights[0].shape
    else {
        panic!("a point light")
    };
    assert!((position.as_dvec3() - LIGHT).length() < 1e-6);
    assert!((intensity.as_dvec3() - DVec3::from(INTENSITY)).length() < 1e-6);
    assert!(scene
        .materials
        .iter()
        .any(|m| m
            .bsdf
            .base_colour()
            .is_some_and(|kd| (kd.get().as_dvec3() - DVec3::splat(ALBEDO)).length() < 1e-6)));
}

#[test]
fn point_light_reference_is_the_analytic_image() {
    // Checks our reading of the conventions (camera, row 0 at the top, radiance units)
    // against the reference file: at pixel centres the box-filtered reference equals the
    // point value up to second order in the pixel footprint (~1e-4 relative here) plus its
    // noise (4e-5 absolute), so 1% is a loose bound; a mirrored row or column order, a
    // wrong fov or a missing 1/pi would be off by far more (the light is off-centre).
    let reference = reference("point-light-plane.exr");
    assert_eq!((reference.width, reference.height), (256, 256));
    let scene = load_scene("point-light-plane.toml");
    check_point_light_scene(&scene);
    let mut worst = 0.0f64;
    for (x, y) in [
        (128u32, 128u32),
        (140, 100),
        (10, 10),
        (245, 12),
        (20, 240),
        (250, 250),
        (64, 190),
        (200, 70),
    ] {
        let p = plane_point(x as f64 + 0.5, y as f64 + 0.5);
        let want = analytic(p);
        let got = reference.pixels[(y * 256 + x) as usize];
        // The library's camera agrees with the convention too.
        let lib = scene
            .camera
            .direction(x as f32 + 0.5, y as f32 + 0.5, 256, 256)
            .as_dvec3();
        assert!((lib - camera_dir(x as f64 + 0.5, y as f64 + 0.5, 256.0, 256.0)).length() < 1e-5);
        for c in 0..3 {
            let rel = (got[c] as f64 - want[c]).abs() / want[c];
            worst = worst.max(rel);
            assert!(
                rel < 0.01,
                "pixel ({x}, {y}) channel {c}: reference {} vs analytic {}",
                got[c],
                want[c]
            );
        }
        // A flipped image reads a different value there (so the check can fail).
        let flipped = analytic(plane_point(x as f64 + 0.5, 256.0 - (y as f64 + 0.5)));
        if (flipped[0] - want[0]).abs() / want[0] < 0.02 {
            continue;
        }
        assert!((got[0] as f64 - flipped[0]).abs() / flipped[0] > 0.02);
    }
    eprintln!(
        "point-light reference vs analytic at pixel centres: worst relative error {worst:.2e}"
    );
}

/// The noise model of a photon-mode image of the plane, per pixel: the expected number of
/// photons `n` landing on the pixel's footprint (the quadrilateral of its projected corners,
/// area `a`) for `paths` paths from the point light, whose photon density on the plane is
/// paths / (4 pi) * h / r^3 per unit area.
///
/// To first order a pixel's estimate is (albedo / pi) * (photon power) * count / a, so a sum of
/// pixels with weights 1 / a over Poisson counts has relative variance
/// `sum(n / a^2) / sum(n / a)^2`. (The K-nearest estimate spreads each photon's power over
/// the pixels around it, which smooths these weights and only lowers the variance.)
fn pixel_photons(paths: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::with_capacity(256 * 256);
    for y in 0..256 {
        for x in 0..256 {
            let (x, y) = (x as f64, y as f64);
            let q = [
                plane_point(x, y),
                plane_point(x + 1.0, y),
                plane_point(x + 1.0, y + 1.0),
                plane_point(x, y + 1.0),
            ];
            let a = 0.5 * ((q[2] - q[0]).cross(q[3] - q[1])).length();
            let r = (LIGHT - plane_point(x + 0.5, y + 0.5)).length();
            v.push((
                paths / (4.0 * std::f64::consts::PI) * LIGHT.y / r.powi(3) * a,
                a,
            ));
        }
    }
    v
}

/// Relative standard deviation of the sum of the pixels `idx` under the model above, and
/// the expected number of photons they see.
fn relative_sd(model: &[(f64, f64)], idx: impl Iterator<Item = usize>) -> (f64, f64) {
    let (mut var, mut sum, mut n) = (0.0, 0.0, 0.0);
    for i in idx {
        let (ni, a) = model[i];
        var += ni / (a * a);
        sum += ni / a;
        n += ni;
    }
    (var.sqrt() / sum, n)
}

#[test]
fn point_light_plane_photon_mode_matches_analytic_reference() {
    let scene = load_scene("point-light-plane.toml");
    check_point_light_scene(&scene);
    assert_eq!(scene.settings.mode, Mode::Photon);
    let reference = reference("point-light-plane.exr");
    let all = |b: u32, bx: u32, by: u32| {
        (by * b..(by + 1) * b)
            .flat_map(move |y| (bx * b..(bx + 1) * b).map(move |x| (y * 256 + x) as usize))
    };
    // The scene's settings (K = 100, radius 0.25, disc filter) with its 200k photon paths,
    // where the far plane has fewer than K photons within the radius (the estimate then uses
    // the whole disc), and with 4M paths, where the noise is low enough to see a 1% bias.
    // Few camera samples: the error is the photon map's, which more samples per pixel do not
    // reduce (neighbouring samples share photons; measured block RMSE 0.0147 with 1M paths
    // at 1, 4 and 16 spp alike).
    for (paths, spp) in [(200_000u32, 4u32), (4_000_000, 1)] {
        let settings = RenderSettings {
            spp,
            photons: paths,
            ..scene.settings.clone()
        };
        let img = render_cpu(&scene, &settings);
        let d = diff(&img, &reference, 16).expect("same size");
        let model = pixel_photons(paths as f64);
        let (sd_image, n_view) = relative_sd(&model, 0..256 * 256);
        eprintln!("point-light-plane, {paths} paths: {d:?}; image mean relative sd {sd_image:.4} ({n_view:.0} photons in view)");

        // Bias allowance: the disc kernel averages the radiance over radius r_K, and the
        // peak's curvature, L ~ (1 + rho^2)^(-3/2), makes that -0.75 r_K^2 relative under the
        // light: -0.2% at 200k paths (r_K = 0.045 there), -0.01% at 4M; elsewhere less. The
        // K/(K-1) correction is exact for a locally uniform density. 0.3% covers both.
        let bias = 0.003;
        let mean_tol = 4.0 * sd_image + bias;

        // Block means: each within 4.5 sd of its own photon count (4.5, not 4: 256 blocks are
        // tested, and P(|z| > 4.5) x 256 = 0.2%), plus the bias allowance.
        let b = 16u32;
        let mut worst_z = 0.0f64;
        let mut fails = Vec::new();
        for by in 0..256 / b {
            for bx in 0..256 / b {
                let (sd, n) = relative_sd(&model, all(b, bx, by));
                let tol = 4.5 * sd + bias;
                let (mut s, mut r) = ([0.0f64; 3], [0.0f64; 3]);
                for i in all(b, bx, by) {
                    for c in 0..3 {
                        s[c] += img.pixels[i][c] as f64;
                        r[c] += reference.pixels[i][c] as f64;
                    }
                }
                for c in 0..3 {
                    let rel = s[c] / r[c] - 1.0;
                    worst_z = worst_z.max(rel.abs() / sd);
                    if rel.abs() > tol {
                        fails.push(format!(
                            "block ({bx},{by}) ch {c}: {rel:+.4} beyond {tol:.4} ({n:.0} photons)"
                        ));
                    }
                }
            }
        }
        eprintln!("point-light-plane, {paths} paths: worst block |rel. error| / sd = {worst_z:.2}");
        check_all(
            &format!("point-light-plane-{paths}"),
            &img,
            Some(&reference),
            &[
                (
                    img.non_finite() == 0,
                    format!("{} non-finite pixels", img.non_finite()),
                ),
                (
                    ratio_ok(&d, 0.98, 1.02),
                    format!("mean ratio {:?} outside 0.98..1.02", d.mean_ratio),
                ),
                // The tight form of the same: 4 sd of the image mean + the bias allowance,
                // 0.7% at 4M paths (sd 0.1%; seeds 1, 2, 3 measure 0.9982, 1.0014, 0.9996).
                // This render scaled by 1.01, as without the K/(K-1) correction, fails it.
                (
                    d.mean_ratio.iter().all(|r| (r - 1.0).abs() <= mean_tol),
                    format!("mean ratio {:?} beyond 1 +- {mean_tol:.4}", d.mean_ratio),
                ),
                (
                    fails.is_empty(),
                    format!("{} blocks off: {}", fails.len(), fails.join(", ")),
                ),
            ],
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Every scene renders
// ---------------------------------------------------------------------------------------------

#[test]
fn every_scene_renders_tiny_without_nan_in_every_mode() {
    let mut names: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .expect("scenes/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 2, "scenes/*.toml: {names:?}");
    for path in &names {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let scene = load(path).unwrap_or_else(|e| panic!("{e}"));
        // A scene the renderers refuse as unsupported (the media scenes until issue 24's
        // transport lands) is skipped, saying so; it joins once a one-pixel render passes.
        let probe = RenderSettings {
            width: 1,
            height: 1,
            spp: 1,
            passes: 0,
            photons: 1,
            caustic_photons: 0,
            ..scene.settings.clone()
        };
        if let Err(gpu_photon::Error::Unsupported(why)) =
            render(&scene, &probe, Backend::Cpu, Progress::default())
        {
            eprintln!("{name}: skipped: {why}");
            continue;
        }
        for mode in [
            Mode::Photon,
            Mode::Direct,
            Mode::DirectOnly,
            Mode::GlobalOnly,
            Mode::CausticOnly,
        ] {
            let settings = RenderSettings {
                width: 32,
                height: 24,
                spp: 1,
                photons: 20_000,
                caustic_photons: 20_000,
                mode,
                ..scene.settings.clone()
            };
            let img = render_cpu(&scene, &settings);
            let mean = img.mean();
            let tag = format!("{name}-{}", mode.name());
            // Every view but the caustic one must show light (all scenes are lit, and a
            // photon or shadow ray reaches some visible surface); the caustic view is dark
            // without a mirror or glass surface (apart from visible emitters).
            let lit = mode != Mode::CausticOnly;
            check_all(
                &tag,
                &img,
                None,
                &[
                    (
                        img.non_finite() == 0,
                        format!("{} non-finite pixels", img.non_finite()),
                    ),
                    (
                        img.pixels.iter().flatten().all(|&c| c >= 0.0),
                        "negative radiance".into(),
                    ),
                    (
                        !lit || mean.iter().all(|&m| m > 0.0),
                        format!("mean {mean:?} is zero"),
                    ),
                ],
            );
        }
    }
}

/// RMS over the channels of the pixels at least 2 from the border of `a - b` (a gaussian
/// filter of radius 2 reaches past the image there, where Mitsuba draws no samples).
fn inner_rms(a: &Image, b: &Image) -> f64 {
    let (w, h) = (a.width as usize, a.height as usize);
    let (mut sum, mut n) = (0.0, 0usize);
    for y in 2..h - 2 {
        for x in 2..w - 2 {
            let (p, q) = (a.pixels[y * w + x], b.pixels[y * w + x]);
            for c in 0..3 {
                sum += (p[c] as f64 - q[c] as f64).powi(2);
                n += 1;
            }
        }
    }
    (sum / n as f64).sqrt()
}

/// `scenes/mitsuba/filter.xml` (32 x 32: emissive bars before a wall they light, through
/// Mitsuba's gaussian filter) against its Mitsuba 3.9.1 reference `tests/data/filter.exr`
/// (two halves of 16,384 spp by `scripts/filter_reference.py`; its own noise 0.00179 RMS, from the llvm_ad_rgb variant, whose filter is exact).
/// Two seeds of ours give our own noise; unbiased, the RMS difference of their mean from the
/// reference is the root sum of squares of the two noises: allowed 1.25x that. The same
/// film with a box filter must miss by more than 3x (the edges are as wide as the filter).
#[test]
fn a_gaussian_film_renders_as_mitsubas_image_of_the_same_scene() {
    const REFERENCE_NOISE: f64 = 0.00179;
    let path = root().join("scenes/mitsuba/filter.xml");
    let reference = reference("filter.exr");
    let text = std::fs::read_to_string(&path).unwrap();
    let gaussian = r#"<rfilter type="gaussian"><float name="stddev" value="0.5"/></rfilter>"#;
    assert!(text.contains(gaussian));
    let mut misses = Vec::new();
    for rfilter in [gaussian, r#"<rfilter type="box"/>"#] {
        let xml = text.replace(gaussian, rfilter);
        let scene = gpu_photon::importers::mitsuba::import(
            &xml,
            "filter.xml",
            &root().join("scenes/mitsuba"),
        )
        .unwrap_or_else(|e| panic!("{e}"))
        .scene;
        let s = RenderSettings {
            spp: 64,
            ..scene.settings.as_default_render()
        };
        let [a, b] = [1, 2].map(|seed| render_cpu(&scene, &RenderSettings { seed, ..s.clone() }));
        let mut mean = a.clone();
        for (m, q) in mean.pixels.iter_mut().zip(&b.pixels) {
            for c in 0..3 {
                m[c] = 0.5 * (m[c] + q[c]);
            }
        }
        let ours = 0.5 * inner_rms(&a, &b);
        let expected = (ours * ours + REFERENCE_NOISE * REFERENCE_NOISE).sqrt();
        let miss = inner_rms(&mean, &reference);
        eprintln!(
            "{rfilter}: RMS {miss:.5} against the reference, {expected:.5} expected from the noise"
        );
        misses.push((miss, expected));
    }
    let ((gauss, expected), (boxed, _)) = (misses[0], misses[1]);
    assert!(
        gauss <= 1.25 * expected,
        "gaussian film: RMS {gauss} vs noise {expected}"
    );
    assert!(
        boxed > 3.0 * expected,
        "box film: RMS {boxed} is within the noise {expected}"
    );
}
