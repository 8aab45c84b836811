//! A GPU pass records all its stages into one submission. Its phases are timed on the device
//! where the adapter has timestamp queries (lavapipe does), else reported as one "device
//! pass", or, when `timed_phases` asks (bench), each submitted and waited for on its own.
//! The three give the same pixels, and device times add up to no more than the wall time.
//! A bench pass with timestamps also times each kernel, within its phases.
//! Pipelines built for a progressive render (override KNN false) refuse a K-nearest pass.

mod common;

use common::gpu;
use gpu_photon::integrators::gpu::shaders::Kernel;
use gpu_photon::render::report::RenderReport;
use gpu_photon::settings::RenderSettings;

const PHASES: [&str; 4] = ["trace photons", "build grids", "build cache", "gather"];

fn pass(timestamps: bool, timed: bool) -> Option<(Vec<f32>, RenderReport, f64)> {
    let mut ctx = gpu()?;
    if timestamps && !ctx.timestamps {
        eprintln!("skipping: the adapter has no timestamp queries");
        return None;
    }
    ctx.timestamps = timestamps;
    let s = RenderSettings {
        width: 32,
        height: 32,
        spp: 4,
        photons: 20_000,
        timed_phases: timed,
        ..Default::default()
    };
    let (_, img, report, wall) = common::cornell_gpu_pass(ctx, &s);
    Some((img.pixels.concat(), report, wall))
}

fn names(r: &RenderReport) -> Vec<&'static str> {
    r.phases.iter().map(|p| p.0).collect()
}

#[test]
fn phases_are_timed_on_the_device_or_apart_and_change_no_pixel() {
    let Some((plain, r, _)) = pass(false, false) else {
        return;
    };
    assert_eq!(names(&r), ["device pass"]);
    let (split, r, _) = pass(false, true).unwrap();
    assert_eq!(names(&r), PHASES);
    assert!(split == plain, "separate submissions changed the image");
    let Some((stamped, r, wall)) = pass(true, false) else {
        return;
    };
    assert_eq!(names(&r), PHASES);
    assert!(stamped == plain, "timestamps changed the image");
    let device: f64 = r.phases.iter().map(|p| p.1.as_secs_f64()).sum();
    eprintln!("device phases {:?}, wall {wall:.3} s", r.phases);
    assert!(
        device > 0.0 && device <= wall,
        "device time {device} s against the pass's wall time {wall} s"
    );
    assert!(
        r.phases.iter().all(|p| p.1.as_nanos() > 0),
        "{:?}",
        r.phases
    );
}

#[test]
fn a_bench_pass_with_timestamps_times_each_kernel_within_its_phases() {
    let Some((plain, r, _)) = pass(false, false) else {
        return;
    };
    assert!(r.kernels.is_empty(), "{:?}", r.kernels);
    let (_, r, _) = pass(false, true).unwrap();
    assert!(r.kernels.is_empty(), "no timestamps, yet {:?}", r.kernels);
    let Some((timed, r, _)) = pass(true, true) else {
        return;
    };
    assert!(timed == plain, "kernel timestamps changed the image");
    eprintln!("phases {:?}\nkernels {:?}", r.phases, r.kernels);
    let kernels: Vec<&str> = r.kernels.iter().map(|k| k.0).collect();
    // Every entry point of the photon and grid modules but the volume grid's (a scene
    // without media builds none), and of the gather module all but the cache build that a
    // pass of this kind does not run (exactly one of the two) and the glass rounds (the
    // Cornell box has no glass; in a glass scene they are timed within `gather`).
    let (trace, grid) = (Kernel::TracePhotons, Kernel::BuildGrid);
    let volume = ["size_volume", "count_volume", "scatter_volume"];
    let grid = grid.entry_points().iter().filter(|e| !volume.contains(e));
    let maps = trace.entry_points().iter().chain(grid);
    let gather = Kernel::Gather.entry_points().iter();
    let builds = ["build_cache", "build_cache_fixed"];
    for want in maps.chain(gather.filter(|e| !builds.contains(e))) {
        assert!(kernels.contains(want), "{want} missing from {kernels:?}");
    }
    assert!(
        kernels.contains(&builds[0]) != kernels.contains(&builds[1]),
        "one cache kernel: {kernels:?}"
    );
    assert_eq!(kernels.len(), 12, "{kernels:?}");
    let secs =
        |v: &[(&str, std::time::Duration)]| -> f64 { v.iter().map(|k| k.1.as_secs_f64()).sum() };
    let (k, p) = (secs(&r.kernels), secs(&r.phases));
    assert!(
        k > 0.0 && k <= p + 1e-6,
        "kernels {k} s against phases {p} s"
    );
    // The gather phase is its one kernel.
    let of = |v: &[(&'static str, std::time::Duration)], n: &str| {
        v.iter().find(|x| x.0 == n).unwrap().1.as_secs_f64()
    };
    let (kg, pg) = (of(&r.kernels, "gather"), of(&r.phases, "gather"));
    assert!(
        kg <= pg + 1e-6 && kg >= 0.5 * pg,
        "gather kernel {kg} s, phase {pg} s"
    );
}

#[test]
fn progressive_pipelines_refuse_a_k_nearest_pass() {
    let Some(ctx) = gpu() else { return };
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = gpu_photon::importers::load(&root.join("scenes/cornell-box.toml")).unwrap();
    let s = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        photons: 1_000,
        pass_range: Some((0, 2)),
        ..Default::default()
    };
    let mut run = gpu_photon::integrators::gpu::run::GpuRun::new(ctx, &scene, &s, 0).unwrap();
    assert!(!run.knn);
    let accum = run.accum_buffer(8 * 8 * 16);
    let progress = gpu_photon::render::report::Progress::default();
    let mut report = RenderReport::default();
    // A progressive pass (k = 0) renders; the classic settings (k = 100) are refused.
    let pass = gpu_photon::render::progressive::pass_settings(&scene, &s, 0);
    assert_eq!(pass.k, 0);
    run.render_pass(&scene, &pass, 0, &accum, &progress, &mut report)
        .unwrap();
    let err = run
        .render_pass(&scene, &s, 0, &accum, &progress, &mut report)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "GPU backend: a K-nearest pass on pipelines built for a progressive render (fixed radii)"
    );
}

/// The glass rounds (`gather` dispatches of listed pixels) exist only for a scene whose camera paths may split at
/// glass or a thin dielectric (override `GLASS_SPLIT`), and so do their stacks: a scene
/// without gets a one-stack stand-in and dispatches no round.
#[test]
fn only_glass_scenes_get_the_glass_rounds() {
    let Some(ctx) = gpu() else { return };
    use gpu_photon::integrators::gpu::branches::stacks_bytes;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let s = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        photons: 1_000,
        ..Default::default()
    };
    for (file, glass) in [
        ("cornell-box.toml", false),
        ("cornell-caustics.toml", true),
        ("inside-glass.toml", true),
        ("glossy-sphere.toml", false),
    ] {
        let scene = gpu_photon::importers::load(&root.join("scenes").join(file)).unwrap();
        assert_eq!(
            gpu_photon::integrators::gpu::pipelines::glass_split(&scene),
            glass,
            "{file}"
        );
        let run =
            gpu_photon::integrators::gpu::run::GpuRun::new(ctx.clone(), &scene, &s, 0).unwrap();
        assert_eq!(run.pipelines.glass_rounds, glass, "{file}");
        let stacks = if glass { 8 * 8 } else { 1 };
        assert_eq!(run.branch_stacks.size(), stacks_bytes(stacks), "{file}");
    }
}

/// A second render in the process with the same scene and kinds of kernels takes the first
/// one's pipelines (`gpu::pipeline_cache`, on the shared device) and gives the same pixels;
/// a progressive pass (other override constants) compiles its own.
#[test]
fn a_later_render_reuses_the_pipelines_and_gives_the_same_pixels() {
    if gpu().is_none() {
        return;
    }
    use gpu_photon::render::report::Progress;
    use gpu_photon::render::session::{render, Backend};
    use gpu_photon::settings::Mode;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let scene = gpu_photon::importers::load(&path).unwrap();
    let s = RenderSettings {
        width: 16,
        height: 16,
        spp: 1,
        photons: 5_000,
        // A mode no other test here renders in: the first render compiles.
        mode: Mode::CausticOnly,
        ..Default::default()
    };
    let upload = |r: &RenderReport| names(r)[1];
    let (first, r1) = render(&scene, &s, Backend::Gpu, Progress::default()).unwrap();
    assert_eq!(upload(&r1), "upload + pipelines");
    let (second, r2) = render(&scene, &s, Backend::Gpu, Progress::default()).unwrap();
    assert_eq!(upload(&r2), "upload (pipelines reused)");
    assert_eq!(first.pixels, second.pixels);
    // A progressive pass (fixed radii: override KNN off), in a mode no other test here
    // renders progressively: its pipelines are not in the cache yet.
    let other = RenderSettings {
        pass_range: Some((0, 1)),
        ..s
    };
    let (_, r3) = render(&scene, &other, Backend::Gpu, Progress::default()).unwrap();
    assert_eq!(upload(&r3), "upload + pipelines");
}
