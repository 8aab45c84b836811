//! Hard cases, each rendered on both backends (the CPU always, the GPU when `common::gpu()`
//! finds an adapter): white furnaces with analytic answers (a point light in a diffuse sphere,
//! and an emitting, reflecting sphere with lossless mirror and glass objects inside),
//! the point-light plane against its analytic image, total internal reflection, grazing
//! light, light leaks out of sealed objects, scale invariance, and degenerate input.
//!
//! Every render is scanned for NaN and infinity (`both` asserts `non_finite() == 0`) and for
//! the GPU's bound counters (photon overflow, loop budget, truncated searches), which leave a
//! GPU image incomplete. Each tolerance is stated, with its reason, where it is asserted.
//!
//! Where a case found a defect (light leaks through edges, corners and walls, a panic, a GPU
//! validation error, GPU search truncation), its test says what was measured before the fix.
//!
//! Budget: tiny images (32 x 32, 4 spp or fewer); the whole file takes about 40 s in release
//! on 2 cores with lavapipe (most of it GPU renders).

mod common;

use gpu_photon::importers::{load, load_str};
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{LightShape, Scene};
use gpu_photon::settings::{Mode, RenderSettings};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// Whether the GPU backend can run (asked once; `common::gpu()` panics under CI without one).
fn gpu_available() -> bool {
    static AVAILABLE: OnceLock<bool> = OnceLock::new();
    *AVAILABLE.get_or_init(|| common::gpu().is_some())
}

fn scene(text: &str) -> Scene {
    load_str(
        text,
        "hard_cases.toml",
        Path::new(env!("CARGO_MANIFEST_DIR")),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Renders on the CPU and, when there is an adapter, on the GPU. Every image is checked for
/// size and NaN/inf. GPU bound counters: photon overflow (dropped photons) is never allowed;
/// the loop budget and truncated searches cut single camera samples short, and at most 0.2%
/// of the samples may hit them (at most -0.2% on a mean).
fn both(scene: &Scene, s: &RenderSettings) -> Vec<(Backend, Image)> {
    render_both(scene, s, 0.002)
}

/// `both` for images whose expected value is exactly 0: there a cut sample changes nothing,
/// so any number of truncated searches is allowed (still printed).
fn both_any_bounds(scene: &Scene, s: &RenderSettings) -> Vec<(Backend, Image)> {
    render_both(scene, s, f64::INFINITY)
}

fn render_both(scene: &Scene, s: &RenderSettings, max_cut: f64) -> Vec<(Backend, Image)> {
    let mut out = Vec::new();
    for backend in [Backend::Cpu, Backend::Gpu] {
        if backend == Backend::Gpu && !gpu_available() {
            continue;
        }
        let t = std::time::Instant::now();
        let (img, report) = render(scene, s, backend, Progress::default())
            .unwrap_or_else(|e| panic!("{backend:?} render failed: {e}"));
        eprintln!(
            "  {backend:?} render {:.2} s ({} GPU batches)",
            t.elapsed().as_secs_f64(),
            report.batches
        );
        assert_eq!((img.width, img.height), (s.width, s.height));
        assert_eq!(
            img.non_finite(),
            0,
            "{backend:?}: {} NaN/inf pixels",
            img.non_finite()
        );
        let samples = (s.width * s.height * s.spp) as f64;
        if let [overflow, budget, truncated, ..] = report.gpu_stats[..] {
            eprintln!(
                "  GPU bounds: overflow {overflow}, loop budget {budget}, truncated {truncated}"
            );
            assert_eq!(overflow, 0, "GPU photon overflow");
            assert!(
                (budget + truncated) as f64 <= max_cut * samples,
                "GPU loop budget {budget} / truncated {truncated} of {samples} samples"
            );
        }
        out.push((backend, img));
    }
    out
}

/// Settings for the small renders here: 32x32, 4 spp, K = 100 and a global radius of 0.1
/// (the GPU's grid cells are at least radius / 5: with K = 256, or radius 0.25 in maps of a
/// million photons, its gather runs out of its loop budget), long photon paths.
fn small(mode: Mode, photons: u32) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 32,
        spp: 4,
        photons,
        caustic_photons: photons / 4,
        k: 100,
        radius: 0.1,
        mode,
        max_photon_bounces: 64,
        max_depth: 64,
        ..RenderSettings::default()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Largest per-channel relative difference of two means.
fn rel3(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| rel(a[c], b[c])).fold(0.0, f64::max)
}

fn max_pixel(img: &Image) -> f32 {
    img.pixels
        .iter()
        .flatten()
        .fold(0.0f32, |m, &v| m.max(v.abs()))
}

/// Worst relative deviation from `want` of any pixel and of any 8x8 block mean, per channel.
fn uniformity(img: &Image, want: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let (mut px, mut blk) = ([0.0f64; 3], [0.0f64; 3]);
    for p in &img.pixels {
        for c in 0..3 {
            px[c] = px[c].max(rel(p[c] as f64, want[c]));
        }
    }
    for by in 0..img.height / 8 {
        for bx in 0..img.width / 8 {
            let mut sum = [0.0f64; 3];
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let p = img.pixels[(y * img.width + x) as usize];
                    for c in 0..3 {
                        sum[c] += p[c] as f64 / 64.0;
                    }
                }
            }
            for c in 0..3 {
                blk[c] = blk[c].max(rel(sum[c], want[c]));
            }
        }
    }
    (px, blk)
}

/// A camera block for the TOML scenes below.
fn camera(eye: [f64; 3], target: [f64; 3], fov: f64) -> String {
    format!("[camera]\neye = {eye:?}\ntarget = {target:?}\nup = [0.0, 1.0, 0.0]\nfov = {fov:?}\n")
}

// ---------------------------------------------------------------------------------------------
// 1. White furnaces
// ---------------------------------------------------------------------------------------------

const ALBEDO: [f64; 3] = [0.5, 0.4, 0.6];
const INTENSITY: [f64; 3] = [1.0, 2.0, 0.5];

/// A diffuse sphere of radius 1 (albedo `ALBEDO`) around a point light (`INTENSITY`) at its
/// centre, with the camera at the centre too (point lights are invisible).
fn point_furnace(extra: &str) -> Scene {
    scene(&format!(
        "{}
[materials.wall]
type = \"diffuse\"
albedo = {ALBEDO:?}
[materials.glass]
type = \"glass\"
ior = 1.5
[[shapes]]
type = \"sphere\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"wall\"
[[lights]]
type = \"point\"
position = [0.0, 0.0, 0.0]
intensity = {INTENSITY:?}
{extra}",
        camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], 120.0)
    ))
}

/// The exact radiance of the point furnace's wall with photon paths cut after `bounces`
/// stored photons: the light at the centre gives every wall point E0 = I / R^2 (P = 4 pi I
/// over 4 pi R^2), and inside a sphere a Lambertian wall sends its reflected light uniformly
/// over the whole wall, so bounce d adds a^d E0: L = a / pi * E0 * (1 - a^N) / (1 - a).
fn point_furnace_radiance(bounces: i32) -> [f64; 3] {
    [0, 1, 2].map(|c| {
        let a = ALBEDO[c];
        a / PI * INTENSITY[c] * (1.0 - a.powi(bounces)) / (1.0 - a)
    })
}

#[test]
fn white_furnace_point_light_at_the_centre() {
    // A point light at the centre of a closed diffuse sphere, camera at the centre: the wall is
    // uniform at L = a I / (pi R^2 (1 - a)) per channel, L (1 - a^N) with photon paths cut
    // after N stored photons (N = 64: a^64 < 1e-14 for a <= 0.6; N = 2 and 3 check the cut
    // itself, in `photon` mode and in `direct` mode where shadow rays stand for depth 0).
    // Mean: within 1% (the brief's bound). Noise: the mean gathers 4096 K-nearest discs of
    // K = 100 photons from ~1.25M stored photons; six seeds of the photon-mode render
    // measured a standard deviation of 0.25% (largest deviation 0.48%), `direct` mode 0.12%
    // (half of the light comes from noiseless shadow rays).
    // 8x8 block means: within 5% of L. The field is uniform, so every block's expectation is
    // L; a block averages 256 estimates (~0.8% noise; measured worst 2.5% over 48 block
    // channels); a hole or a hot spot as large as a block fails.
    let sc = point_furnace("");
    for (mode, bounces) in [
        (Mode::Photon, 64),
        (Mode::Direct, 64),
        (Mode::Photon, 2),
        (Mode::Direct, 3),
    ] {
        let s = RenderSettings {
            max_photon_bounces: bounces as u32,
            ..small(mode, 500_000)
        };
        let want = point_furnace_radiance(bounces);
        for (b, img) in both(&sc, &s) {
            let m = img.mean();
            eprintln!(
                "point furnace {mode:?} N={bounces} {b:?}: mean {m:?} want {want:?} (rel {:.4})",
                rel3(m, want)
            );
            assert!(
                rel3(m, want) < 0.01,
                "{b:?} {mode:?} N={bounces}: mean {m:?}, analytic {want:?}"
            );
            let (px, blk) = uniformity(&img, want);
            eprintln!("  worst pixel {px:.3?}, worst 8x8 block {blk:.3?}");
            assert!(
                blk.iter().all(|&d| d < 0.05),
                "{b:?} {mode:?}: an 8x8 block is off by {blk:?}"
            );
        }
    }
}

const LE: [f64; 3] = [1.0, 0.5, 2.0];

/// A sphere of radius 1 that both emits `LE` (two-sided) and reflects diffusely (`ALBEDO`):
/// inside it the radiance is L = Le / (1 - a) everywhere and in every direction, so any
/// lossless object (a mirror of reflectance 1, glass) placed inside changes nothing: every
/// pixel's expected value is L, even where the camera sees the object.
fn emissive_furnace(cam: &str, extra: &str) -> Scene {
    scene(&format!(
        "{cam}
[materials.wall]
type = \"diffuse\"
albedo = {ALBEDO:?}
[materials.mirror]
type = \"mirror\"
reflectance = [1.0, 1.0, 1.0]
[materials.glass]
type = \"glass\"
ior = 1.5
[[shapes]]
type = \"sphere\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"wall\"
emission = {LE:?}
two_sided = true
{extra}"
    ))
}

fn emissive_furnace_radiance() -> [f64; 3] {
    [0, 1, 2].map(|c| LE[c] / (1.0 - ALBEDO[c]))
}

fn sphere(center: [f64; 3], radius: f64, material: &str) -> String {
    format!("[[shapes]]\ntype = \"sphere\"\ncenter = {center:?}\nradius = {radius:?}\nmaterial = \"{material}\"\n")
}

#[test]
fn white_furnace_lossless_objects_change_nothing() {
    // A point light at the centre cannot carry this test: a mirror or glass object there
    // shadows part of the wall and throws a caustic elsewhere, so the image changes where the
    // camera looks, and conservation only fixes the total over the whole wall. In the
    // emitting furnace the radiance field is uniform and isotropic, so a lossless object
    // (mirror of reflectance 1, glass with exact Fresnel) leaves every pixel at L exactly,
    // including the pixels that see the objects.
    // Mean: within 1% of L (the brief's bound). Noise: six seeds at these settings measured a
    // standard deviation of ~0.17% (largest deviation 0.57%), with and without the objects;
    // the emission Le, half of L or more, is noiseless.
    // 8x8 block means: within 5% (as in the point furnace; measured worst 1.8%).
    let cam = camera([0.2, 0.1, 0.3], [0.0, 0.0, -1.0], 120.0);
    let want = emissive_furnace_radiance();
    let objects = [
        sphere([0.35, -0.1, -0.45], 0.2, "mirror"),
        sphere([-0.35, 0.15, -0.4], 0.2, "glass"),
        // Nested glass: a sphere inside a glass sphere (each surface an air-glass interface).
        sphere([0.0, -0.35, -0.5], 0.2, "glass"),
        sphere([0.02, -0.36, -0.52], 0.1, "glass"),
    ];
    let cases = [
        ("empty", String::new()),
        (
            "a mirror sphere, a glass sphere and nested glass spheres",
            objects.concat(),
        ),
    ];
    for (name, extra) in &cases {
        let sc = emissive_furnace(&cam, extra);
        for mode in [Mode::Photon, Mode::Direct] {
            let s = small(mode, 250_000);
            for (b, img) in both(&sc, &s) {
                let m = img.mean();
                eprintln!(
                    "emissive furnace, {name}, {mode:?} {b:?}: mean {m:?} want {want:?} (rel {:.4})",
                    rel3(m, want)
                );
                assert!(
                    rel3(m, want) < 0.01,
                    "{name} {mode:?} {b:?}: mean {m:?}, want {want:?}"
                );
                let (px, blk) = uniformity(&img, want);
                eprintln!("  worst pixel {px:.3?}, worst 8x8 block {blk:.3?}");
                assert!(
                    blk.iter().all(|&d| d < 0.05),
                    "{name} {mode:?} {b:?}: an 8x8 block is off by {blk:?}"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. The point-light plane against its analytic image
// ---------------------------------------------------------------------------------------------

/// The exact mean of the point-light plane's image at `w` x `h` (the scene's own quad, 10
/// units to each side): `common::point_lit_plane_mean` with the scene's light and camera.
fn analytic_plane_mean(scene: &Scene, albedo: f64, w: u32, h: u32) -> [f64; 3] {
    let LightShape::Point(gpu_photon::lights::point::Point {
        position,
        intensity,
    }) = scene.lights[0].shape
    else {
        panic!("a point light")
    };
    let intensity = intensity.as_dvec3().to_array();
    common::point_lit_plane_mean(
        &scene.camera,
        albedo,
        intensity,
        position.as_dvec3(),
        10.0,
        w,
        h,
    )
}

#[test]
fn point_light_plane_mean_within_one_percent_of_analytic() {
    // The scene file's plane and light (its own K = 100, radius 0.1 here) at 32 x 32, 4 spp,
    // 1M paths, photon mode: the image mean within 1% of the exact one (the reference test
    // allows 2% at 256 x 256). Noise: 4096 camera samples, each a K = 100 estimate (10%
    // relative) from mostly disjoint photon sets, give ~0.16% on the mean; the disc kernel's
    // bias under the light is -0.75 r_K^2 (r_K ~ 0.02 there: -0.03%); where fewer than K
    // photons lie within the radius the whole disc is used, which is unbiased. Two more CPU
    // seeds measure the noise: their spread must stay under a quarter of the tolerance, or
    // the 1% test would not mean much.
    let sc =
        load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-light-plane.toml")).unwrap();
    let s = small(Mode::Photon, 1_000_000);
    let want = analytic_plane_mean(&sc, 0.8, s.width, s.height);
    for (b, img) in both(&sc, &s) {
        let m = img.mean();
        eprintln!(
            "plane {b:?}: mean {m:?} analytic {want:?} (rel {:.4})",
            rel3(m, want)
        );
        assert!(rel3(m, want) < 0.01, "{b:?}: mean {m:?}, analytic {want:?}");
    }
    let seeds: Vec<[f64; 3]> = [2, 3]
        .iter()
        .map(|&seed| {
            let s = RenderSettings { seed, ..s.clone() };
            let (img, _) = render(&sc, &s, Backend::Cpu, Progress::default()).unwrap();
            assert_eq!(img.non_finite(), 0);
            img.mean()
        })
        .collect();
    let spread = rel3(seeds[0], seeds[1]);
    eprintln!(
        "plane CPU seeds 2, 3: rel {:.4}, {:.4} (spread {spread:.4})",
        rel3(seeds[0], want),
        rel3(seeds[1], want)
    );
    assert!(spread < 0.0025, "seeds 2 and 3 differ by {spread}");
    for m in &seeds {
        assert!(
            rel3(*m, want) < 0.01,
            "CPU seed: mean {m:?}, analytic {want:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Total internal reflection, nested glass, the camera inside glass
// ---------------------------------------------------------------------------------------------

const IOR: f64 = 1.5;

/// Fraction of pixel (x, y)'s square (of a `size` x `size` image, fov 90) whose directions
/// satisfy `free(sx, sy)` (image-plane coordinates in [-1, 1]), on a 16 x 16 grid.
fn pixel_fraction(x: u32, y: u32, size: u32, free: impl Fn(f64, f64) -> bool) -> f64 {
    let n = 16;
    let mut k = 0;
    for j in 0..n {
        for i in 0..n {
            let px = x as f64 + (i as f64 + 0.5) / n as f64;
            let py = y as f64 + (j as f64 + 0.5) / n as f64;
            let sx = 2.0 * px / size as f64 - 1.0;
            let sy = 1.0 - 2.0 * py / size as f64;
            k += free(sx, sy) as u32;
        }
    }
    k as f64 / (n * n) as f64
}

/// Checks an image of the emitting furnace seen through glass where some directions are
/// trapped by total internal reflection: `frac[i]` is the fraction of pixel i whose camera
/// rays can leave the glass. Trapped pixels must be exactly 0 (a trapped ray never reaches
/// anything that emits); pixels that are wholly free see the furnace's L times IOR^2 (the
/// camera is in the glass: radiance over n^2 is what a path conserves, Mitsuba's
/// radiance-mode transmission); the image mean is that times the mean free fraction.
fn check_trapped_image(name: &str, img: &Image, frac: &[f64], mean_tol: f64) {
    let want = emissive_furnace_radiance().map(|l| l * IOR * IOR);
    let (mut free_sum, mut free_n, mut dark_n) = ([0.0f64; 3], 0usize, 0usize);
    for (p, &f) in img.pixels.iter().zip(frac) {
        if f == 0.0 {
            dark_n += 1;
            assert!(
                p.iter().all(|&v| v == 0.0),
                "{name}: a trapped pixel is {p:?} (must be exactly 0)"
            );
        } else if f == 1.0 {
            free_n += 1;
            for c in 0..3 {
                free_sum[c] += p[c] as f64;
            }
        }
    }
    assert!(
        dark_n >= 32 && free_n >= 32,
        "{name}: {dark_n} dark, {free_n} free pixels"
    );
    let free_mean = free_sum.map(|v| v / free_n as f64);
    let f_mean = frac.iter().sum::<f64>() / frac.len() as f64;
    let want_mean = want.map(|l| l * f_mean);
    let m = img.mean();
    eprintln!(
        "{name}: {dark_n} trapped pixels all 0; free pixels mean {free_mean:?} (want {want:?}, rel {:.4}); image mean {m:?} want {want_mean:?} (rel {:.4})",
        rel3(free_mean, want),
        rel3(m, want_mean)
    );
    // Free pixels: the furnace's L within 2% (photon noise of a few hundred pixels' estimates,
    // while the emission, half of L or more, is noiseless; measured 0.27-0.35%).
    assert!(
        rel3(free_mean, want) < 0.02,
        "{name}: free pixels {free_mean:?}, want {want:?}"
    );
    // The whole image: the same noise plus the boundary pixels, where the Fresnel chain of
    // rays just inside the critical angle (R -> 1) is cut at max_depth (measured -0.6% for
    // the cube, +0.7% for the sphere; `mean_tol` is 2% and 3%).
    assert!(
        rel3(m, want_mean) < mean_tol,
        "{name}: mean {m:?}, want {want_mean:?}"
    );
}

#[test]
fn total_internal_reflection_camera_inside_a_glass_cube() {
    // The camera at the centre of a glass cube (ior 1.5) looking along -z with a 90 degree
    // field of view. A ray leaves through the front face iff |d_z| > cos(theta_c) =
    // sqrt(1 - 1/n^2), i.e. sx^2 + sy^2 < 1 / (n^2 - 1) = 0.8 in image-plane coordinates;
    // in this field of view it meets the side faces beyond the critical angle (that needs
    // sx^2 > (n^2 - 1)(1 + sy^2) >= 1.25), and a cube preserves |d_x|, |d_y|, |d_z| under
    // reflection, so every other ray is trapped for ever (the diagonal directions of a glass
    // cube). The cube sits in the emitting furnace, where it changes nothing outside itself.
    let cam = camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], 90.0);
    let sc = emissive_furnace(
        &cam,
        "[[shapes]]\ntype = \"box\"\nmin = [-0.2, -0.2, -0.2]\nmax = [0.2, 0.2, 0.2]\nmaterial = \"glass\"\n",
    );
    let s = small(Mode::Photon, 150_000);
    let limit = 1.0 / (IOR * IOR - 1.0);
    let frac: Vec<f64> = (0..s.width * s.height)
        .map(|i| {
            pixel_fraction(i % s.width, i / s.width, s.width, |sx, sy| {
                sx * sx + sy * sy < limit
            })
        })
        .collect();
    for (b, img) in both(&sc, &s) {
        check_trapped_image(&format!("glass cube {b:?}"), &img, &frac, 0.02);
    }
}

#[test]
fn total_internal_reflection_camera_inside_a_glass_sphere() {
    // Centred: every camera ray leaves the sphere at normal incidence, reflecting R = 0.04
    // back through the centre each time, so in the furnace every pixel sees L (T + R T +
    // ...) times IOR^2 (radiance in the glass); the mean must be that within 1% as for the
    // furnace itself (measured 0.14-0.16%).
    let want = emissive_furnace_radiance().map(|l| l * IOR * IOR);
    let eye = [0.2, 0.1, 0.3];
    let sc = emissive_furnace(
        &camera(eye, [0.0, 0.0, -1.0], 90.0),
        &sphere(eye, 0.3, "glass"),
    );
    for (b, img) in both(&sc, &small(Mode::Photon, 150_000)) {
        let m = img.mean();
        eprintln!(
            "camera inside glass sphere (centred) {b:?}: mean {m:?} want {want:?} (rel {:.4})",
            rel3(m, want)
        );
        assert!(rel3(m, want) < 0.01, "{b:?}: mean {m:?}, want {want:?}");
    }
    // Off-centre, at p = (0.45, 0, 0) from the centre of a sphere of radius 0.5, looking
    // along (1, 0, -1): a chord keeps its angle of incidence at every reflection, with
    // sin(theta) = |p x d| / R, so rays with |p x d| > R / n are trapped for ever (a
    // whispering gallery: the left part of the image, towards -z); rays closer to +x leave.
    // max_depth 24 keeps the trapped rays' chains short on the GPU (R^24 is small except
    // within a fraction of a degree of the critical angle, in the boundary pixels).
    let (r, p) = (0.5, glam::DVec3::new(0.45, 0.0, 0.0));
    let sc = emissive_furnace(
        &camera(p.to_array(), [1.45, 0.0, -1.0], 90.0),
        &sphere([0.0, 0.0, 0.0], r, "glass"),
    );
    let s = RenderSettings {
        max_depth: 24,
        ..small(Mode::Photon, 150_000)
    };
    let cam = sc.camera;
    let frac: Vec<f64> = (0..s.width * s.height)
        .map(|i| {
            pixel_fraction(i % s.width, i / s.width, s.width, |sx, sy| {
                let d =
                    (cam.forward.as_dvec3() + sx * cam.right.as_dvec3() + sy * cam.up.as_dvec3())
                        .normalize();
                p.cross(d).length() < r / IOR
            })
        })
        .collect();
    for (b, img) in both(&sc, &s) {
        check_trapped_image(&format!("glass sphere off-centre {b:?}"), &img, &frac, 0.03);
    }
}

#[test]
fn total_internal_reflection_point_light_inside_a_glass_cube() {
    use glam::Vec3;
    use gpu_photon::bsdfs::fresnel::dielectric;
    use gpu_photon::settings::FresnelMode;

    // At and around the critical angle the split stays finite, unit and a probability.
    let n = Vec3::Z;
    let crit = (1.0 / IOR).asin();
    for dtheta in [-1e-3, -1e-6, 0.0, 1e-6, 1e-3, 0.5] {
        let t = (crit + dtheta).min(std::f64::consts::FRAC_PI_2);
        // Leaving the glass: travelling along +z (with the outward normal +z).
        let d = Vec3::new(t.sin() as f32, 0.0, t.cos() as f32).normalize();
        for mode in [FresnelMode::Exact, FresnelMode::Schlick] {
            let g = dielectric(d, n, IOR as f32, mode);
            assert!(
                (0.0..=1.0).contains(&g.reflectance),
                "{dtheta}: R = {}",
                g.reflectance
            );
            assert!((g.reflected.length() - 1.0).abs() < 1e-5 && g.reflected.z < 0.0);
            if let Some(r) = g.refracted {
                assert!(
                    r.is_finite() && (r.length() - 1.0).abs() < 1e-5 && r.z >= 0.0,
                    "{r}"
                );
            }
            if dtheta > 1e-5 {
                assert!(
                    g.refracted.is_none() && g.reflectance == 1.0,
                    "{dtheta}: no TIR"
                );
            }
            if dtheta < -1e-5 {
                assert!(
                    g.refracted.is_some(),
                    "{dtheta}: TIR before the critical angle"
                );
            }
        }
    }

    // A point light at the centre of a glass cube: a direction escapes iff one of |d_i| >
    // c = sqrt(1 - 1/n^2) (reflections in a cube only flip signs, so the other directions are
    // trapped for ever); the caps |d_i| > c cannot overlap (2 c^2 > 1), so the escaping
    // fraction is 6 * 2 pi (1 - c) / (4 pi) = 3 (1 - c) = 0.7639 for n = 1.5, and every
    // escaping path's first diffuse hit (on the furnace wall) carries its whole power.
    let sc = point_furnace(
        "[[shapes]]\ntype = \"box\"\nmin = [-0.2, -0.2, -0.2]\nmax = [0.2, 0.2, 0.2]\nmaterial = \"glass\"\n",
    );
    let paths = 200_000u32;
    let settings = RenderSettings {
        photons: paths,
        max_photon_bounces: 64,
        ..RenderSettings::default()
    };
    let (_, photons) = common::trace_global(&sc, &settings);
    let mut first: std::collections::HashMap<u32, &gpu_photon::integrators::photon::Photon> =
        Default::default();
    for p in &photons {
        let e = first.entry(p.id).or_insert(p);
        if p.depth() < e.depth() {
            *e = p;
        }
    }
    let power: [f64; 3] = [0, 1, 2].map(|c| first.values().map(|p| p.power[c] as f64).sum());
    let total = sc.total_power();
    let c = (1.0 - 1.0 / (IOR * IOR)).sqrt();
    let want = 3.0 * (1.0 - c);
    // Binomial noise of the escaping count: sd = sqrt(p (1 - p) / N) = 0.095% absolute.
    let sd = (want * (1.0 - want) / paths as f64).sqrt();
    for ch in 0..3 {
        let got = power[ch] / total[ch] as f64;
        eprintln!("glass cube around a point light, channel {ch}: escaping power {got:.5} of the emitted, analytic {want:.5} (sd {sd:.5})");
        // 4.5 sd: a wrong critical angle (or refraction where TIR must reflect) moves this
        // by far more (n = 1.45 instead of 1.5 gives 0.828; measured 0.76445 = +0.55 sd).
        assert!(
            (got - want).abs() < 4.5 * sd,
            "channel {ch}: {got} vs {want}"
        );
    }
    assert!(first.values().all(|p| p.is_caustic() && p.depth() >= 1));

    // The render of that furnace on both backends: finite, and the GPU no farther from a
    // second CPU seed than the first CPU seed is (gpu_images' statistic, with its 1.3 slack
    // for the GPU's stochastic Fresnel choice at glass).
    // Photon paths trapped in the cube end after max_photon_bounces: 16 here (64 above)
    // keeps the GPU's trace short.
    let mut s = RenderSettings {
        max_photon_bounces: 16,
        ..small(Mode::Photon, 150_000)
    };
    s.width = 24;
    s.height = 24;
    let sc = Scene {
        camera: gpu_photon::camera::Camera::look_at(
            Vec3::new(0.0, 0.3, 0.7),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::Y,
            90.0,
        )
        .unwrap(),
        ..sc
    };
    let runs = both(&sc, &s);
    let (cpu2, _) = render(
        &sc,
        &RenderSettings {
            seed: 2,
            ..s.clone()
        },
        Backend::Cpu,
        Progress::default(),
    )
    .unwrap();
    assert_eq!(cpu2.non_finite(), 0);
    let noise = diff(&runs[0].1, &cpu2, 8).unwrap();
    for (b, img) in &runs {
        let d = diff(img, &cpu2, 8).unwrap();
        eprintln!("glass cube furnace {b:?}: mean {:?}; rmse vs CPU seed 2 {:.4} (CPU seeds: {:.4}), block rmse {:.4} ({:.4})", img.mean(), d.rmse, noise.rmse, d.block_rmse, noise.block_rmse);
        let (pixels, blocks) = common::within_seed_noise(&d, &noise, 0.0);
        assert!(pixels && blocks, "{b:?}: {d:?} vs {noise:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Grazing incidence
// ---------------------------------------------------------------------------------------------

/// A 2 x 2 diffuse quad at y = 0 (albedo 0.8, front up), seen from above, with `lights`.
fn grazing_scene(lights: &str) -> Scene {
    scene(&format!(
        "{}
[materials.white]
type = \"diffuse\"
albedo = [0.8, 0.8, 0.8]
[[shapes]]
type = \"quad\"
corners = [[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]]
material = \"white\"
{lights}",
        camera([0.0, 2.5, 1.0], [0.0, 0.0, 0.0], 70.0)
    ))
}

fn point_light(position: [f64; 3], intensity: f64) -> String {
    format!("[[lights]]\ntype = \"point\"\nposition = {position:?}\nintensity = [{intensity:?}, {intensity:?}, {intensity:?}]\n")
}

#[test]
fn grazing_light_in_the_plane_of_a_quad_gives_no_light() {
    // cos(theta) = 0 at every point of the quad for a light in its plane, so the exact image
    // is 0; a light just below the plane lights only the back face, which the camera above
    // does not see (a photon arriving from behind does not count). Each case must render
    // exactly 0 in every mode: any positive pixel is light that came from nowhere.
    let cases = [
        (
            "in the plane, beyond the edge",
            point_light([0.0, 0.0, -1.5], 1.0),
        ),
        (
            "in the plane, over the quad",
            point_light([0.3, 0.0, 0.2], 1.0),
        ),
        ("1e-4 below the plane", point_light([0.3, -1e-4, 0.2], 1.0)),
    ];
    for (name, light) in &cases {
        let sc = grazing_scene(light);
        for mode in [Mode::Photon, Mode::Direct, Mode::DirectOnly] {
            let s = RenderSettings {
                spp: 1,
                ..small(mode, 20_000)
            };
            for (b, img) in both_any_bounds(&sc, &s) {
                eprintln!(
                    "grazing, light {name}, {mode:?} {b:?}: max pixel {}",
                    max_pixel(&img)
                );
                assert_eq!(
                    max_pixel(&img),
                    0.0,
                    "light {name}, {mode:?} {b:?}: not black"
                );
            }
        }
    }
}

/// The exact mean of the grazing scene's image for a point light of intensity 1 at `light`:
/// L = albedo / pi * h / r^3 on the quad (`common::point_lit_plane_mean`).
fn analytic_grazing_mean(sc: &Scene, light: glam::DVec3, w: u32, h: u32) -> f64 {
    common::point_lit_plane_mean(&sc.camera, 0.8, [1.0; 3], light, 1.0, w, h)[0]
}

#[test]
fn nearly_grazing_light_matches_the_analytic_irradiance() {
    // A light at height h = 1e-4 and h = 0.01, 0.2 beyond the quad's near edge: cos(theta) =
    // h / r is at most 5e-4 and 0.05. `direct-only` (shadow rays, no photons) must give the
    // analytic image mean within 2.5%: its only error is the pixel integration of 16 samples
    // per pixel. With Sobol jitter (issue 10): -1.50% at both heights, both backends alike.
    // The bound was 1%, set on the 4x4 stratified jitter's -0.19% at this seed; that sampler
    // measured -0.2% to -3.3% over seeds 1..8 (Sobol: +0.1% to -3.3%, i.e. the old seed was
    // lucky, the error's spread did not grow). All samplers average about -1.5%: a small
    // systematic offset of the analytic mean or the renderer, not of the sampler.
    for h in [1e-4, 0.01] {
        let pos = glam::DVec3::new(0.0, h, -1.2);
        let sc = grazing_scene(&point_light(pos.to_array(), 1.0));
        let s = RenderSettings {
            spp: 16,
            ..small(Mode::DirectOnly, 1000)
        };
        let want = analytic_grazing_mean(&sc, pos, s.width, s.height);
        for (b, img) in both(&sc, &s) {
            let m = img.mean();
            eprintln!(
                "grazing h = {h}, direct-only {b:?}: mean {:.6e} analytic {want:.6e} (rel {:+.4})",
                m[0],
                m[0] / want - 1.0
            );
            assert!(
                m.iter().all(|&v| rel(v, want) < 0.025),
                "h = {h} {b:?}: {m:?} vs {want}"
            );
        }
    }
    // Photon mode at h = 0.01: 0.7% of the photons reach the quad, all at grazing angles
    // (7k of 1M paths: 1.2% noise on the mean), and the disc estimate loses the part of its
    // disc that lies beyond the quad's near edge, where the light is brightest: a low bias of
    // a few percent (measured -4.2% and -5.1% at seeds 1 and 2, both backends alike). 10%
    // bounds both; a lost or doubled grazing photon would be far outside.
    let pos = glam::DVec3::new(0.0, 0.01, -1.2);
    let sc = grazing_scene(&point_light(pos.to_array(), 1.0));
    let s = small(Mode::Photon, 1_000_000);
    let want = analytic_grazing_mean(&sc, pos, s.width, s.height);
    for (b, img) in both(&sc, &s) {
        let m = img.mean();
        eprintln!(
            "grazing h = 0.01, photon {b:?}: mean {:.6e} analytic {want:.6e} (rel {:+.4})",
            m[0],
            m[0] / want - 1.0
        );
        assert!(
            m.iter().all(|&v| rel(v, want) < 0.1),
            "photon mode {b:?}: {m:?} vs {want}"
        );
    }
}

#[test]
fn gpu_sparse_photon_map_matches_the_cpu() {
    // The nearly grazing scene in photon mode: only 0.7% of the paths store a photon. With
    // the same seed both backends trace the same photons, so when the GPU's searches are
    // complete the means agree to ~1e-6 (see the furnace tests); 0.5% allows for a few cut
    // samples. The GPU used to size its hash grid for 3 photons per path: its cells were far
    // too small for this sparse map, 1060 of 4096 searches were truncated and the GPU mean
    // was 2.3% below the CPU's (0.977 at seeds 1 and 2). Since the grid is sized from the
    // photons actually stored: no truncation, GPU / CPU = 1.0000.
    let pos = glam::DVec3::new(0.0, 0.01, -1.2);
    let sc = grazing_scene(&point_light(pos.to_array(), 1.0));
    let s = small(Mode::Photon, 1_000_000);
    let runs = both(&sc, &s);
    if let [(_, cpu), (_, gpu)] = &runs[..] {
        let (c, g) = (cpu.mean()[0], gpu.mean()[0]);
        eprintln!("sparse map: GPU / CPU = {:.4}", g / c);
        assert!(rel(g, c) < 0.005, "GPU mean {g} vs CPU {c}");
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Light leaks
// ---------------------------------------------------------------------------------------------

/// Six separate quads closing the box [-0.5, 0.5] x [0.2, 1.2] x [-0.5, 0.5] (diffuse 0.8,
/// some facing in and some out), over a ground quad at y = 0, with `light` inside; the camera
/// looks at three faces and the ground from outside.
fn sealed_box(light: &str) -> Scene {
    let (a, b, y0, y1) = (-0.5, 0.5, 0.2, 1.2);
    let quads = [
        // Bottom (facing down), top (facing up).
        [[a, y0, a], [b, y0, a], [b, y0, b], [a, y0, b]],
        [[a, y1, a], [a, y1, b], [b, y1, b], [b, y1, a]],
        // -x (facing in), +x (facing out).
        [[a, y0, a], [a, y0, b], [a, y1, b], [a, y1, a]],
        [[b, y0, a], [b, y1, a], [b, y1, b], [b, y0, b]],
        // -z (facing out), +z (facing in).
        [[a, y0, a], [a, y1, a], [b, y1, a], [b, y0, a]],
        [[a, y0, b], [b, y0, b], [b, y1, b], [a, y1, b]],
    ];
    let mut text = camera([1.6, 1.9, 2.2], [0.0, 0.5, 0.0], 60.0);
    text += "[materials.white]\ntype = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]\n";
    text += "[[shapes]]\ntype = \"quad\"\ncorners = [[-3.0, 0.0, 3.0], [3.0, 0.0, 3.0], [3.0, 0.0, -3.0], [-3.0, 0.0, -3.0]]\nmaterial = \"white\"\n";
    for q in quads {
        text += &format!("[[shapes]]\ntype = \"quad\"\ncorners = {q:?}\nmaterial = \"white\"\n");
    }
    scene(&(text + light))
}

/// The lights of the outer-face test: the centre, and 1e-3 from a corner.
const BOX_LIGHTS: [(&str, [f64; 3]); 2] = [
    ("centre", [0.0, 0.7, 0.0]),
    ("1e-3 from a corner", [0.499, 1.199, 0.499]),
];

/// Whether any of a grid of rays through pixel (x, y) (plus its corners) hits the box.
fn pixel_sees_box(sc: &Scene, x: u32, y: u32, w: u32, h: u32) -> bool {
    let cam = sc.camera;
    let (lo, hi) = (
        glam::DVec3::new(-0.5, 0.2, -0.5),
        glam::DVec3::new(0.5, 1.2, 0.5),
    );
    let eye = cam.eye.as_dvec3();
    (0..=4).any(|j| {
        (0..=4).any(|i| {
            let (px, py) = (x as f64 + i as f64 / 4.0, y as f64 + j as f64 / 4.0);
            let sx = (2.0 * px / w as f64 - 1.0) * (w as f64 / h as f64);
            let sy = 1.0 - 2.0 * py / h as f64;
            let d = cam.forward.as_dvec3() + sx * cam.right.as_dvec3() + sy * cam.up.as_dvec3();
            let (t0, t1) = ((lo - eye) / d, (hi - eye) / d);
            // A margin of 1e-3 in t (the box is ~2.7 away) counts grazing rays as hits.
            t0.min(t1).max_element() <= t0.max(t1).min_element() + 1e-3
        })
    })
}

/// Nothing may get out of a closed box with light `pos` inside: (1) every photon the CPU
/// traces is stored on the box (within 1e-4 of its surface: positions are the rays' hit
/// points), so none slips through an edge or a corner; (2) in both modes the ground and
/// everything else the camera sees beside the box is exactly 0 on both backends; (3)
/// `direct-only` (shadow rays alone) is exactly 0 everywhere, the box's outer faces
/// included. (The outer faces in the main modes: `sealed_box_outer_faces_are_black`.)
fn check_nothing_escapes_the_box(name: &str, pos: [f64; 3]) {
    let sc = sealed_box(&point_light(pos, 1.0));
    let settings = RenderSettings {
        photons: 100_000,
        max_photon_bounces: 64,
        ..RenderSettings::default()
    };
    let (_, photons) = common::trace_global(&sc, &settings);
    let off_box = |p: &&gpu_photon::integrators::photon::Photon| {
        let q = p.pos();
        let inside = q.x.abs() <= 0.5001 && q.z.abs() <= 0.5001 && q.y >= 0.1999 && q.y <= 1.2001;
        let on_wall = q.x.abs() >= 0.4999 || q.z.abs() >= 0.4999 || q.y <= 0.2001 || q.y >= 1.1999;
        !(inside && on_wall)
    };
    let outside: Vec<_> = photons.iter().filter(off_box).collect();
    eprintln!(
        "sealed box, light {name}: {} photons stored, {} off the box",
        photons.len(),
        outside.len()
    );
    for p in outside.iter().take(3) {
        eprintln!(
            "   off the box: {:?} depth {} dir {:?}",
            p.pos(),
            p.depth(),
            p.dir
        );
    }

    let mut failures = Vec::new();
    for mode in [Mode::Photon, Mode::Direct, Mode::DirectOnly] {
        let s = RenderSettings {
            spp: 2,
            ..small(mode, 50_000)
        };
        for (b, img) in both_any_bounds(&sc, &s) {
            let (mut lit_off_box, mut lit_box) = (0, 0);
            for (i, p) in img.pixels.iter().enumerate() {
                if p.iter().any(|&v| v != 0.0) {
                    if pixel_sees_box(
                        &sc,
                        i as u32 % s.width,
                        i as u32 / s.width,
                        s.width,
                        s.height,
                    ) {
                        lit_box += 1;
                    } else {
                        lit_off_box += 1;
                    }
                }
            }
            eprintln!("  {mode:?} {b:?}: {lit_off_box} lit pixels off the box, {lit_box} on its outer faces (max {})", max_pixel(&img));
            if lit_off_box > 0 {
                failures.push(format!(
                    "{mode:?} {b:?}: {lit_off_box} pixels lit beside the box"
                ));
            }
            if mode == Mode::DirectOnly && lit_box > 0 {
                failures.push(format!("{b:?}: a shadow ray leaked ({lit_box} pixels)"));
            }
        }
    }
    assert!(
        photons.len() > 100_000,
        "light {name}: only {} photons stored",
        photons.len()
    );
    assert!(
        outside.is_empty(),
        "light {name}: {} of {} photons stored off the box",
        outside.len(),
        photons.len()
    );
    assert!(failures.is_empty(), "light {name}: {}", failures.join("; "));
}

#[test]
fn sealed_box_lets_no_photon_or_shadow_ray_out() {
    check_nothing_escapes_the_box("at the centre", [0.0, 0.7, 0.0]);
    check_nothing_escapes_the_box("1e-3 from a corner", [0.499, 1.199, 0.499]);
    check_nothing_escapes_the_box("1e-4 above the floor of the box", [0.1, 0.2001, 0.1]);
    // 5e-5 inside the +x face: the shadow rays of point lights used to stop end_eps =
    // 4 * 3e-5 * (0.9 + 1e-5) = 1.08e-4 short of the light, so this face never shadowed it
    // (140 of 1024 ground pixels lit, max 0.238, on both backends); they now run all the way.
    check_nothing_escapes_the_box("5e-5 from the +x face", [0.49995, 0.9, 0.0]);
}

#[test]
fn sealed_box_with_the_light_1e5_from_a_corner() {
    // The light is a point inside the box, so every emitted ray must hit a wall, and every
    // shadow ray from outside must meet one. Three bugs made this fail; each is fixed:
    //
    // 1. Measured (CPU, 100k paths, Möller-Trumbore): 34 of 499,855
    // photons are stored on the ground outside, some at depth 0. They leave along the
    // diagonal (shared) edge of a face's two triangles: the light lies on the plane of the
    // +z face's diagonal, so rays with d_x ~ d_y hit that face on its diagonal, 1.5e-5 away,
    // where f32 rounding puts the hit outside both triangles (in f64, u = 0.0000000 for one
    // and v = -0.0000000 for the other). Fixed by the watertight test (src/math/geometry.rs).
    // 2. In `direct-only` 292 of 1024 ground pixels were lit
    // (max 0.139, both backends): a shadow ray starts at the receiver's offset origin
    // (moved 3e-5 * max|coordinate|, up to 9e-5 on this ground) but keeps the direction
    // aimed from the un-offset point, so it passes the light by up to that much, here
    // outside the box's corner; re-aiming from the offset origin leaves 1 of 1519 such rays
    // unoccluded instead of 897 (measured with the library's Bvh::occluded). Shadow rays are
    // now aimed from their origin. Renders (50k paths, 32x32, 2 spp) had ground pixels lit
    // in photon mode 26 (CPU) / 24 (GPU), in `direct` 301 / 299.
    // 3. With both fixed, 21 of 500,306 photons still escaped (14 / 20 ground pixels lit):
    // hit points on the box's edges (rounded onto, or 6e-8 past, the plane of the adjacent
    // face) started their next ray on that plane, where the face cannot stop it (a hit needs
    // t > 0). Hit points on triangles are now moved towards the centroid by the ray offset
    // (geometry::inset); 0 escape.
    check_nothing_escapes_the_box("1e-5 from a corner", [0.49999, 1.19999, 0.49999]);
}

#[test]
fn sealed_box_outer_faces_are_black() {
    // The outer faces of a closed box with the light inside must be exactly 0 in both modes.
    // Measured before the fix (CPU and GPU alike, light at the centre, 100k paths, 32x32,
    // 2 spp): 19 pixels
    // along the box's edges lit, up to 0.49 (photon mode) and 0.47 (direct mode), against
    // 0.8/pi * 4 = 1.0 from direct light alone on the nearest inner wall. Mechanism (CPU
    // photons): the 100 nearest photons of a point on the outer top face 0.01 from the +x
    // edge (r_K = 0.016) include photons stored on the inner side of the +x wall; 14 of them
    // travel downwards (indirect photons, depth 1 to 22), so they pass the "not from behind"
    // test of the top face's outer side, which compares the photon's direction with the
    // shading normal only, not with the surface the photon was stored on. Photons now carry
    // the normal of the side they arrived on, and an estimate does not take photons from
    // across the solid (estimate::photon_faces): 0 pixels lit.
    for (name, pos) in BOX_LIGHTS {
        let sc = sealed_box(&point_light(pos, 1.0));
        for mode in [Mode::Photon, Mode::Direct] {
            let s = RenderSettings {
                spp: 2,
                ..small(mode, 100_000)
            };
            for (b, img) in both_any_bounds(&sc, &s) {
                let lit = img
                    .pixels
                    .iter()
                    .filter(|p| p.iter().any(|&v| v != 0.0))
                    .count();
                eprintln!(
                    "sealed box, light {name}, {mode:?} {b:?}: {lit} lit pixels, max {}",
                    max_pixel(&img)
                );
                assert_eq!(
                    lit,
                    0,
                    "light {name}, {mode:?} {b:?}: {lit} pixels lit outside the box (max {})",
                    max_pixel(&img)
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Scale invariance
// ---------------------------------------------------------------------------------------------

/// A small room at scale `s`: a floor, a back wall and a red left wall (quads), a turned
/// diffuse block, a glass sphere, a mirror quad, an area light (radiance unchanged: its power
/// scales with its area, s^2) and a point light (intensity scaled by s^2), so that every
/// radiance, hence the image, is the same at every scale. `extra` is appended unscaled.
fn room(s: f64, extra: &str) -> Scene {
    let p = |v: [f64; 3]| format!("[{:?}, {:?}, {:?}]", v[0] * s, v[1] * s, v[2] * s);
    let quad = |c: [[f64; 3]; 4], m: &str| {
        format!(
            "[[shapes]]\ntype = \"quad\"\ncorners = [{}, {}, {}, {}]\nmaterial = \"{m}\"\n",
            p(c[0]),
            p(c[1]),
            p(c[2]),
            p(c[3])
        )
    };
    let mut t = format!(
        "[camera]\neye = {}\ntarget = {}\nfov = 45.0\n",
        p([0.0, 0.6, 2.4]),
        p([0.0, 0.2, 0.0])
    );
    t += "[materials.white]\ntype = \"diffuse\"\nalbedo = [0.7, 0.7, 0.7]\n";
    t += "[materials.red]\ntype = \"diffuse\"\nalbedo = [0.6, 0.1, 0.1]\n";
    t += "[materials.glass]\ntype = \"glass\"\nior = 1.5\n";
    t += "[materials.mirror]\ntype = \"mirror\"\nreflectance = [0.9, 0.9, 0.9]\n";
    t += &quad(
        [
            [-1.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 0.0, -1.0],
            [-1.0, 0.0, -1.0],
        ],
        "white",
    );
    t += &quad(
        [
            [-1.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [1.0, 1.4, -1.0],
            [-1.0, 1.4, -1.0],
        ],
        "white",
    );
    t += &quad(
        [
            [-1.0, 0.0, -1.0],
            [-1.0, 1.4, -1.0],
            [-1.0, 1.4, 1.0],
            [-1.0, 0.0, 1.0],
        ],
        "red",
    );
    t += &quad(
        [
            [0.95, 0.1, -0.6],
            [0.95, 0.1, 0.2],
            [0.95, 0.9, 0.2],
            [0.95, 0.9, -0.6],
        ],
        "mirror",
    );
    t += &format!(
        "[[shapes]]\ntype = \"box\"\nmin = {}\nmax = {}\nrotate_y = 20.0\nmaterial = \"white\"\n",
        p([-0.7, 0.0, -0.7]),
        p([-0.25, 0.55, -0.25])
    );
    t += &format!(
        "[[shapes]]\ntype = \"sphere\"\ncenter = {}\nradius = {:?}\nmaterial = \"glass\"\n",
        p([0.35, 0.3, 0.1]),
        0.3 * s
    );
    t += &format!(
        "[[shapes]]\ntype = \"quad\"\ncorners = [{}, {}, {}, {}]\nemission = [6.0, 5.0, 4.0]\n",
        p([-0.2, 1.3, -0.2]),
        p([0.2, 1.3, -0.2]),
        p([0.2, 1.3, 0.2]),
        p([-0.2, 1.3, 0.2])
    );
    let i = [0.4 * s * s, 0.35 * s * s, 0.3 * s * s];
    t += &format!(
        "[[lights]]\ntype = \"point\"\nposition = {}\nintensity = {i:?}\n",
        p([0.4, 1.0, 0.7])
    );
    scene(&(t + extra))
}

fn room_settings(mode: Mode, s: f64, seed: u32) -> RenderSettings {
    RenderSettings {
        radius: (0.1 * s) as f32,
        caustic_radius: (0.05 * s) as f32,
        seed,
        max_photon_bounces: 16,
        max_depth: 12,
        ..small(mode, 60_000)
    }
}

/// Standard deviation of the mean of `a - b` per channel, from the spread of its sixteen
/// 8 x 8 block means (blocks are far wider than a photon search, so nearly independent).
fn mean_diff_sd(a: &Image, b: &Image) -> [f64; 3] {
    let mut blocks = Vec::new();
    for by in 0..a.height / 8 {
        for bx in 0..a.width / 8 {
            let mut sum = [0.0f64; 3];
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let i = (y * a.width + x) as usize;
                    for c in 0..3 {
                        sum[c] += (a.pixels[i][c] - b.pixels[i][c]) as f64 / 64.0;
                    }
                }
            }
            blocks.push(sum);
        }
    }
    let n = blocks.len() as f64;
    [0, 1, 2].map(|c| {
        let m = blocks.iter().map(|b| b[c]).sum::<f64>() / n;
        let var = blocks.iter().map(|b| (b[c] - m).powi(2)).sum::<f64>() / (n - 1.0);
        (var / n).sqrt()
    })
}

/// The room at scale 1 on each backend (seed 1) and on the CPU at seed 2, per mode: the
/// reference of the scale and degenerate-input tests (rendered once).
struct RoomRefs {
    /// (mode, backend, seed 1 image), and the CPU seed 2 image per mode.
    seed1: Vec<(Mode, Backend, Image)>,
    seed2: Vec<(Mode, Image)>,
}

fn room_refs() -> &'static RoomRefs {
    static REFS: OnceLock<RoomRefs> = OnceLock::new();
    REFS.get_or_init(|| {
        let sc = room(1.0, "");
        let mut r = RoomRefs {
            seed1: vec![],
            seed2: vec![],
        };
        for mode in [Mode::Photon, Mode::Direct] {
            for (b, img) in both(&sc, &room_settings(mode, 1.0, 1)) {
                r.seed1.push((mode, b, img));
            }
            let s2 = both(&sc, &room_settings(mode, 1.0, 2)).swap_remove(0).1;
            r.seed2.push((mode, s2));
        }
        r
    })
}

/// Checks `img` (mode, backend, seed 1) against the room's scale-1 render: the means agree
/// within 4 standard deviations of the seed-to-seed difference (measured from the two CPU
/// seeds' block means; a render of another seed would pass this with ~99.99%), and the
/// per-pixel RMSE is no larger than 1.3 x that between the two seeds (gpu_images' statistic:
/// an independent render of the same image gives 1.0; acne, a shifted shadow or lost light
/// give more).
fn check_like_room(what: &str, mode: Mode, b: Backend, img: &Image) {
    let refs = room_refs();
    let base = &refs
        .seed1
        .iter()
        .find(|r| r.0 == mode && r.1 == b)
        .unwrap()
        .2;
    let cpu1 = &refs
        .seed1
        .iter()
        .find(|r| r.0 == mode && r.1 == Backend::Cpu)
        .unwrap()
        .2;
    let cpu2 = &refs.seed2.iter().find(|r| r.0 == mode).unwrap().1;
    let sd = mean_diff_sd(cpu1, cpu2);
    let (m, mb) = (img.mean(), base.mean());
    let noise = diff(cpu2, cpu1, 8).unwrap();
    let d = diff(img, base, 8).unwrap();
    let z: [f64; 3] = [0, 1, 2].map(|c| (m[c] - mb[c]).abs() / sd[c]);
    eprintln!(
        "{what} {mode:?} {b:?}: mean {m:.5?} vs {mb:.5?} at scale 1 (|diff| / sd = {z:.2?}, sd {sd:?}); rmse {:.5} (seeds: {:.5})",
        d.rmse, noise.rmse
    );
    assert!(
        z.iter().all(|&z| z < 4.0),
        "{what} {mode:?} {b:?}: mean {m:?} vs {mb:?}, sd {sd:?}"
    );
    assert!(
        common::within_seed_noise(&d, &noise, 0.0).0,
        "{what} {mode:?} {b:?}: rmse {} vs seeds' {}",
        d.rmse,
        noise.rmse
    );
}

#[test]
fn scale_1e_minus_3_and_1e4_render_the_same_image() {
    for s in [1e-3, 1e4] {
        let sc = room(s, "");
        for mode in [Mode::Photon, Mode::Direct] {
            for (b, img) in both(&sc, &room_settings(mode, s, 1)) {
                check_like_room(&format!("room at scale {s:e}"), mode, b, &img);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 7. Degenerate input
// ---------------------------------------------------------------------------------------------

#[test]
fn zero_area_and_sliver_triangles_change_nothing() {
    // Zero-area triangles (a point, a collinear triple) are never hit; slivers (1e-6 wide,
    // and a needle with a 1e-7 edge) almost never: the room must render as without them
    // (same statistic as the scale test), with no NaN.
    let tri = |v: [[f64; 3]; 3]| {
        format!("[[shapes]]\ntype = \"triangle\"\nvertices = {v:?}\nmaterial = \"white\"\n")
    };
    let extra = [
        tri([[0.1, 0.5, 0.0], [0.1, 0.5, 0.0], [0.1, 0.5, 0.0]]),
        tri([[-0.5, 0.2, 0.3], [0.0, 0.4, 0.3], [0.5, 0.6, 0.3]]),
        tri([[-0.8, 0.3, 0.5], [0.8, 0.3, 0.5], [0.0, 0.300001, 0.5]]),
        tri([[-0.3, 0.0, 0.5], [0.3, 0.0, 0.5], [0.0, 0.0, 0.5000001]]),
        tri([[0.0, 0.7, 0.0], [0.0, 0.7, 1e-7], [0.5, 0.2, 0.0]]),
    ]
    .concat();
    let sc = room(1.0, &extra);
    assert_eq!(sc.triangles.len(), room(1.0, "").triangles.len() + 5);
    for mode in [Mode::Photon, Mode::Direct] {
        for (b, img) in both(&sc, &room_settings(mode, 1.0, 1)) {
            check_like_room("room with degenerate triangles", mode, b, &img);
        }
    }
}

#[test]
fn zero_radius_sphere_and_zero_area_light_are_scene_errors() {
    let cam = camera([0.0, 0.0, 3.0], [0.0, 0.0, 0.0], 40.0);
    let body = "[materials.white]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n[[shapes]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\n";
    for (radius, line_of_value) in [("0.0", true), ("-1.0", true)] {
        let text = format!("{cam}{body}radius = {radius}\nmaterial = \"white\"\n");
        let err = load_str(&text, "hard_cases.toml", Path::new("."))
            .expect_err("radius <= 0 must be an error");
        let shown = err.to_string();
        eprintln!("radius {radius}: {shown}");
        let line = text.lines().position(|l| l.starts_with("radius")).unwrap() + 1;
        assert!(line_of_value);
        assert_eq!(
            shown,
            format!("hard_cases.toml:{line}: shapes[0].radius: must be positive")
        );
    }
    // An emitting triangle of zero area would have zero power: an error too.
    let text = format!("{cam}[[shapes]]\ntype = \"triangle\"\nvertices = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]\nemission = [1.0, 1.0, 1.0]\n");
    let shown = load_str(&text, "hard_cases.toml", Path::new("."))
        .expect_err("zero-area light")
        .to_string();
    eprintln!("zero-area light: {shown}");
    assert!(
        shown.starts_with("hard_cases.toml:")
            && shown.contains("shapes[0].vertices")
            && shown.contains("zero-area light"),
        "{shown}"
    );
}

/// A point light inside a closed diffuse sphere over a ground plane, seen from outside.
/// Returns, per (mode, backend), the number of lit ground pixels, of lit pixels on the
/// sphere, and the brightest pixel on the sphere.
fn light_in_sphere(modes: &[Mode]) -> Vec<(Mode, Backend, usize, usize, f32)> {
    let text = format!(
        "{}
[materials.white]
type = \"diffuse\"
albedo = [0.8, 0.8, 0.8]
[[shapes]]
type = \"quad\"
corners = [[-3.0, 0.0, 3.0], [3.0, 0.0, 3.0], [3.0, 0.0, -3.0], [-3.0, 0.0, -3.0]]
material = \"white\"
[[shapes]]
type = \"sphere\"
center = [0.0, 0.8, 0.0]
radius = 0.5
material = \"white\"
{}",
        camera([1.5, 1.8, 2.4], [0.0, 0.6, 0.0], 60.0),
        point_light([0.1, 0.9, -0.05], 1.0)
    );
    let sc = scene(&text);
    let cam = sc.camera;
    let mut out = Vec::new();
    for &mode in modes {
        let s = RenderSettings {
            spp: 2,
            ..small(mode, 100_000)
        };
        for (b, img) in both_any_bounds(&sc, &s) {
            let (mut ground, mut sphere_lit, mut sphere_max) = (0, 0, 0.0f32);
            for (i, p) in img.pixels.iter().enumerate() {
                let (x, y) = (i as u32 % s.width, i as u32 / s.width);
                // Whether any ray through the pixel's corners or centre meets the sphere.
                let hits = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)]
                    .iter()
                    .any(|&(dx, dy)| {
                        let d = cam
                            .direction(x as f32 + dx, y as f32 + dy, s.width, s.height)
                            .as_dvec3();
                        let oc = cam.eye.as_dvec3() - glam::DVec3::new(0.0, 0.8, 0.0);
                        let b = oc.dot(d);
                        b * b - (oc.length_squared() - 0.25) > -1e-3
                    });
                if p.iter().any(|&v| v != 0.0) {
                    if hits {
                        sphere_lit += 1;
                        sphere_max = sphere_max.max(p[0].max(p[1]).max(p[2]));
                    } else {
                        ground += 1;
                    }
                }
            }
            eprintln!("light in a sphere, {mode:?} {b:?}: {ground} ground pixels lit, {sphere_lit} sphere pixels lit (max {sphere_max})");
            out.push((mode, b, ground, sphere_lit, sphere_max));
        }
    }
    out
}

#[test]
fn light_inside_a_closed_sphere_lights_nothing_outside() {
    // Nothing gets out of the sphere: the ground must be exactly 0 in every mode, and with
    // shadow rays alone (`direct-only`) the sphere's outside too. (The photon-map estimate on
    // the sphere's outside: `light_inside_a_closed_sphere_outer_surface_is_black`.)
    for (mode, b, ground, sphere_lit, _) in
        light_in_sphere(&[Mode::Photon, Mode::Direct, Mode::DirectOnly])
    {
        assert_eq!(ground, 0, "{mode:?} {b:?}: light got out of the sphere");
        if mode == Mode::DirectOnly {
            assert_eq!(sphere_lit, 0, "{b:?}: a shadow ray went through the sphere");
        }
    }
}

#[test]
fn light_inside_a_closed_sphere_outer_surface_is_black() {
    // Measured before photons carried their surface's normal (100k paths, 32x32, 2 spp): one
    // pixel of the sphere's outside lit, 0.022 (CPU) / 0.016 (GPU) in photon mode and
    // 0.018 / 0.016 in direct mode, against ~1 inside (inner photons at grazing incidence
    // passed the direction test). Now the inner photons' normals face inwards: 0.
    for (mode, b, _, sphere_lit, max) in light_in_sphere(&[Mode::Photon, Mode::Direct]) {
        assert_eq!(
            sphere_lit, 0,
            "{mode:?} {b:?}: the outside of the sphere is lit (max {max})"
        );
    }
}

#[test]
fn coincident_quads_render_between_their_materials() {
    // Two quads at the same place (white and red, one of them with reversed winding) under a
    // point light: no NaN, and each channel's mean lies between those of the white-only and
    // red-only renders (whichever surface a ray or photon hits, both are Lambertian with
    // albedos in that range), within 4 seed-to-seed standard deviations.
    let quad = |corners: &str, m: &str| {
        format!("[[shapes]]\ntype = \"quad\"\ncorners = {corners}\nmaterial = \"{m}\"\n")
    };
    let up = "[[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]]";
    let down = "[[-1.0, 0.0, 1.0], [-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0]]";
    let wall = quad(
        "[[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 1.5, -1.0], [-1.0, 1.5, -1.0]]",
        "white",
    );
    let make = |shapes: &str| {
        scene(&format!(
            "{}[materials.white]\ntype = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]\n[materials.red]\ntype = \"diffuse\"\nalbedo = [0.7, 0.1, 0.1]\n{wall}{shapes}{}",
            camera([0.0, 1.6, 2.2], [0.0, 0.2, 0.0], 60.0),
            point_light([0.2, 0.9, 0.1], 1.0)
        ))
    };
    let white = make(&quad(up, "white"));
    let red = make(&quad(up, "red"));
    let both_quads = make(&(quad(up, "white") + &quad(down, "red")));
    for mode in [Mode::Photon, Mode::Direct] {
        let s = RenderSettings {
            spp: 2,
            ..small(mode, 50_000)
        };
        let w = both(&white, &s);
        let r = both(&red, &s);
        let w2 = render(
            &white,
            &RenderSettings {
                seed: 2,
                ..s.clone()
            },
            Backend::Cpu,
            Progress::default(),
        )
        .unwrap()
        .0;
        let sd = mean_diff_sd(&w[0].1, &w2);
        for (i, (b, img)) in both(&both_quads, &s).into_iter().enumerate() {
            let (m, mw, mr) = (img.mean(), w[i].1.mean(), r[i].1.mean());
            eprintln!("coincident quads {mode:?} {b:?}: mean {m:.4?}, white only {mw:.4?}, red only {mr:.4?} (sd {sd:?})");
            for c in 0..3 {
                let (lo, hi) = (mw[c].min(mr[c]), mw[c].max(mr[c]));
                assert!(
                    m[c] >= lo - 4.0 * sd[c] && m[c] <= hi + 4.0 * sd[c],
                    "{mode:?} {b:?} channel {c}: {} outside [{lo}, {hi}]",
                    m[c]
                );
            }
        }
    }
}

/// Renders `text` in every mode on each of `backends` (the GPU only where there is one) and
/// asserts the image is black (and finite).
fn check_black(name: &str, text: &str, backends: &[Backend]) {
    let sc = scene(text);
    for mode in [
        Mode::Photon,
        Mode::Direct,
        Mode::DirectOnly,
        Mode::GlobalOnly,
        Mode::CausticOnly,
    ] {
        let s = RenderSettings {
            width: 8,
            height: 8,
            spp: 1,
            ..small(mode, 1000)
        };
        for &b in backends {
            if b == Backend::Gpu && !gpu_available() {
                continue;
            }
            let (img, _) = render(&sc, &s, b, Progress::default())
                .unwrap_or_else(|e| panic!("{name} {mode:?} {b:?}: render failed: {e}"));
            assert_eq!(img.non_finite(), 0, "{name} {mode:?} {b:?}: NaN/inf");
            assert_eq!(max_pixel(&img), 0.0, "{name} {mode:?} {b:?}: not black");
        }
    }
    eprintln!("{name}: black in every mode on {backends:?}");
}

/// The camera looks through the cube [-1, 1]^3.
fn empty_camera() -> String {
    camera([0.0, 0.0, 3.0], [0.0, 0.0, 0.0], 40.0)
}

const QUAD_AND_GLASS: &str = "[materials.white]\ntype = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]\n[materials.glass]\ntype = \"glass\"\nior = 1.5\n[[shapes]]\ntype = \"quad\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]\nmaterial = \"white\"\n[[shapes]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 1.0]\nradius = 0.5\nmaterial = \"glass\"\n";

#[test]
fn empty_scenes_render_black() {
    // No shapes and no lights; shapes but no lights; a light but no shapes (point lights
    // are invisible and there is nothing to light): black in every mode on both backends.
    // The camera looks through the cube [-1, 1]^3, where the empty scene's placeholder BVH
    // node lies: until Bvh::walk skipped it, the CPU panicked there (index out of bounds in
    // src/bvh/mod.rs; in photon mode a point light's photons anywhere did it too), and the GPU
    // failed on any scene without lights (wgpu validation error: the lights buffer bound
    // with 64 bytes where the shader's `array<Light>` needs 96).
    let cam = empty_camera();
    let both_backends = [Backend::Cpu, Backend::Gpu];
    check_black("nothing at all", &cam, &both_backends);
    check_black(
        "shapes, no lights",
        &format!("{cam}{QUAD_AND_GLASS}"),
        &both_backends,
    );
    check_black(
        "a point light, no shapes",
        &format!("{cam}{}", point_light([0.0, 0.0, 1.0], 1.0)),
        &both_backends,
    );
}
