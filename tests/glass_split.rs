//! The glass rule of the camera path, the same on both backends (issue 25): below
//! `GLASS_SPLIT_DEPTH` a glass hit traces the reflected ray weighted by the Fresnel
//! reflectance R and the refracted one by 1 - R, deeper one of them chosen with probability
//! R. Scene: a glass slab (ior 1.5, 0.2 thick) filling the view, a uniform emitter of
//! radiance L = 1 behind it and an environment of radiance E = 0.5 everywhere else. Near
//! normal incidence a pixel sees `T L + (1 - T) E` with the slab's transmittance
//! `T = (1 - R)^2 / (1 - R^2)`, R = 0.04 (its internal reflections summed).
//! Split, every path with up to three glass hits is exact, so the image is nearly noise
//! free (the first random choice weighs R^2 (1 - R) ~ 0.0015); taking one branch per hit, a
//! camera sample is L or E and a pixel of 4 samples has a standard deviation near
//! `sqrt(T (1 - T) / 4) (L - E) = 0.067`.

mod common;

use gpu_photon::bsdfs::shading::GLASS_SPLIT_DEPTH;
use gpu_photon::importers::load_str;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;
use std::path::Path;

const SLAB: &str = r#"
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 20
width = 16
height = 16

[render]
mode = "direct"
spp = 4
photons = 2000
caustic_photons = 2000

[environment]
radiance = [0.5, 0.5, 0.5]

[materials.crown]
type = "glass"
ior = 1.5

[[shapes]]
type = "box"
min = [-1, -1, -0.1]
max = [1, 1, 0.1]
material = "crown"

# The emitter behind the slab, facing it (+z).
[[shapes]]
type = "quad"
corners = [[-2, -2, -1], [2, -2, -1], [2, 2, -1], [-2, 2, -1]]
emission = [1, 1, 1]
"#;

fn slab() -> Scene {
    load_str(SLAB, "slab.toml", Path::new(".")).unwrap()
}

fn image(scene: &Scene, seed: u32, backend: Backend) -> Image {
    let s = RenderSettings {
        seed,
        pass_range: None,
        ..scene.settings.clone()
    };
    render(scene, &s, backend, Progress::default()).unwrap().0
}

/// The slab's value near normal incidence: `T L + (1 - T) E`.
fn expected() -> f64 {
    let r = 0.04f64;
    let t = (1.0 - r) * (1.0 - r) / (1.0 - r * r);
    t + (1.0 - t) * 0.5
}

fn mean(img: &Image) -> f64 {
    let sum: f64 = img
        .pixels
        .iter()
        .flat_map(|p| p.iter().map(|&c| c as f64))
        .sum();
    sum / (3 * img.pixels.len()) as f64
}

/// The split on a backend: the slab's mean within 0.3% of the analytic value (rays are at
/// most 7 degrees off the normal, where R grows by under 1e-4), and two seeds' images
/// within 0.005 RMSE of each other (one branch per hit: about 0.09).
fn check_split(what: &str, a: &Image, b: &Image) {
    assert_eq!(a.non_finite(), 0, "{what}");
    let m = mean(a);
    assert!(
        (m / expected() - 1.0).abs() < 3e-3,
        "{what}: slab mean {m:.5}, expected {:.5}",
        expected()
    );
    let noise = diff(a, b, 4).unwrap().rmse;
    eprintln!(
        "{what}: mean {m:.5} (expected {:.5}), seed-to-seed rmse {noise:.6}",
        expected()
    );
    assert!(
        noise < 5e-3,
        "{what}: seeds 1 and 2 differ by rmse {noise:.5}: glass hits are not split"
    );
}

#[test]
fn the_cpu_splits_glass_hits() {
    assert_eq!(GLASS_SPLIT_DEPTH, 3);
    let scene = slab();
    check_split(
        "cpu",
        &image(&scene, 1, Backend::Cpu),
        &image(&scene, 2, Backend::Cpu),
    );
}

/// The GPU splits as the CPU does (the branch left waits on its pixel's stack for a later
/// round of `gather`, `gpu::branches`) and draws
/// the same random numbers for the same paths: the same seed gives the CPU's image up to
/// float rounding.
#[test]
fn the_gpu_splits_glass_hits_as_the_cpu_does() {
    let Some(_ctx) = common::gpu() else { return };
    let scene = slab();
    let gpu1 = image(&scene, 1, Backend::Gpu);
    check_split("gpu", &gpu1, &image(&scene, 2, Backend::Gpu));
    let same = diff(&gpu1, &image(&scene, 1, Backend::Cpu), 4).unwrap();
    eprintln!("same seed: gpu-cpu rmse {:.7}", same.rmse);
    assert!(
        same.rmse < 1e-4,
        "same seed: GPU and CPU differ by rmse {:.6}",
        same.rmse
    );
}

/// Where the glass branch stacks would exceed what they may take (one storage binding), the
/// gather runs in bands of rows, each band's stacks reused by the next: the same image, bit
/// for bit, as in one band (here three bands of one tile of rows each).
#[test]
fn gpu_bands_of_rows_give_the_same_image() {
    use gpu_photon::integrators::gpu::branches::stacks_bytes;
    use gpu_photon::integrators::gpu::run::GpuRun;
    use gpu_photon::render::report::RenderReport;
    let Some(ctx) = common::gpu() else { return };
    let scene = slab();
    let s = RenderSettings {
        seed: 1,
        width: 24,
        height: 24,
        pass_range: None,
        ..scene.settings.clone()
    };
    let tile = ctx.shape.gather_tile;
    let render_with = |stack_bytes| {
        let mut run = GpuRun::with_stack_bytes(ctx.clone(), &scene, &s, 0, stack_bytes).unwrap();
        let accum = run.accum_buffer(16 * s.width as u64 * s.height as u64);
        let mut report = RenderReport::default();
        let quiet = Progress::default();
        let img = run
            .render_pass(&scene, &s, 0, &accum, &quiet, &mut report)
            .unwrap();
        (img, run.band_rows)
    };
    let (one, rows) = render_with(u64::MAX);
    assert_eq!(rows, s.height);
    let (banded, rows) = render_with(stacks_bytes(s.width as u64 * tile as u64));
    assert_eq!(rows, tile);
    assert!(rows < s.height, "tile {tile}: one band");
    assert!(one.pixels == banded.pixels, "the bands changed the image");
    assert!(mean(&one) > 0.5, "the slab is lit");
}
