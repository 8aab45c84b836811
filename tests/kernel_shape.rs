//! The kernel shape chosen per adapter (src/integrators/gpu/shape.rs): lavapipe keeps today's widths and
//! loop guard (so its images stay byte for byte what they were), a 32- or 64-wide adapter gets
//! wider workgroups and cache builds, the cache build's workgroup memory is what Rust thinks,
//! and four example scenes rendered on lavapipe with the shape a 32-wide adapter gets (forced
//! by GPU_PHOTON_KERNEL_SHAPE) agree with the default shape's within seed noise. A context's
//! feature floor (shared kernels) renders as a scene's own kernels do.
//!
//! The simulated shape keeps the loop guard ON: lavapipe needs it (it ends loops silently after
//! 65,535 iterations), so this test simulates the widths only, not a guard-free device; that
//! the guard-free kernels compile is checked by creating their pipelines.

mod common;

use common::gpu;
use gpu_photon::integrators::gpu::bindings::Layouts;
use gpu_photon::integrators::gpu::pipelines::{feature_constants, Pipelines};
use gpu_photon::integrators::gpu::shaders::{validate, Kernel};
use gpu_photon::integrators::gpu::shape::{
    cache_build_bytes, AdapterFacts, KernelShape, SHAPE_ENV,
};
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::settings::RenderSettings;

fn facts(subgroup_max: u32, cpu: bool, workgroup_storage: u32) -> AdapterFacts {
    AdapterFacts {
        subgroup_max,
        cpu,
        workgroup_storage,
        invocations: 1024,
    }
}

/// Lavapipe (8-lane SIMD groups, a CPU adapter, 32 KiB of workgroup memory) gets exactly the
/// constants the kernels had before shapes existed: workgroups of 64, 8x8 gather tiles, 8
/// cache lanes, the loop guard on. (Byte identity of its images with the code before shapes
/// was measured by hand: docs/measurements.md.)
#[test]
fn lavapipe_keeps_todays_constants() {
    let want = KernelShape {
        subgroup: 8,
        wg_size: 64,
        gather_tile: 8,
        cache_lanes: 8,
        loop_guard: true,
    };
    assert_eq!(KernelShape::for_adapter(&facts(8, true, 32 << 10)), want);
    assert_eq!(KernelShape::DEFAULT, want);
    // An adapter reporting no subgroup size gets the default widths.
    assert_eq!(KernelShape::for_adapter(&facts(0, true, 16 << 10)), want);
    let lavapipe = KernelShape::parse("lavapipe", &facts(32, false, 48 << 10)).unwrap();
    assert_eq!(lavapipe, want);
}

#[test]
fn hardware_adapters_get_their_width_and_no_guard() {
    // NVIDIA: 32-wide warps, 48 KiB of workgroup memory.
    let nvidia = KernelShape::for_adapter(&facts(32, false, 48 << 10));
    assert_eq!(
        nvidia,
        KernelShape {
            subgroup: 32,
            wg_size: 128,
            gather_tile: 8,
            cache_lanes: 32,
            loop_guard: false,
        }
    );
    assert_eq!(
        KernelShape::parse("nvidia", &facts(32, false, 48 << 10)).unwrap(),
        nvidia
    );
    // AMD wave64.
    let amd = KernelShape::for_adapter(&facts(64, false, 64 << 10));
    assert_eq!(
        (amd.wg_size, amd.cache_lanes, amd.loop_guard),
        (256, 64, false)
    );
    // A software adapter of any width keeps the guard.
    assert!(KernelShape::for_adapter(&facts(16, true, 32 << 10)).loop_guard);
    // With only 16 KiB of workgroup memory, 32 cache lanes do not fit: 16.
    assert!(cache_build_bytes(32) > 16 << 10 && cache_build_bytes(16) <= 16 << 10);
    assert_eq!(
        KernelShape::for_adapter(&facts(32, false, 16 << 10)).cache_lanes,
        16
    );
}

#[test]
fn forced_shapes_parse_and_keep_the_adapters_guard_unless_told() {
    let lavapipe = facts(8, true, 32 << 10);
    let s = KernelShape::parse("subgroup:32", &lavapipe).unwrap();
    assert_eq!((s.wg_size, s.cache_lanes, s.loop_guard), (128, 32, true));
    let s =
        KernelShape::parse("subgroup:32, guard:off, wg:64, tile:16, lanes:4", &lavapipe).unwrap();
    assert_eq!(
        s,
        KernelShape {
            subgroup: 32,
            wg_size: 64,
            gather_tile: 16,
            cache_lanes: 4,
            loop_guard: false,
        }
    );
    let e = KernelShape::parse("subgroup:32,tile:32", &lavapipe).unwrap_err();
    assert_eq!(
        e,
        "GPU_PHOTON_KERNEL_SHAPE=\"subgroup:32,tile:32\": tile:32 needs 1024 invocations"
    );
}

/// `cache_build_bytes` lists every workgroup variable of the gather module (all of them are
/// the cache build's) at its size, for 8 and 32 lanes: the module is parsed with
/// CACHE_LANES as a constant and its workgroup globals laid out by naga.
#[test]
fn cache_build_workgroup_memory_is_what_rust_computes() {
    let source = Kernel::Gather.source();
    let decl = format!(
        "override CACHE_LANES: u32 = {}u;",
        KernelShape::DEFAULT.cache_lanes
    );
    assert!(source.contains(&decl), "the prelude declares {decl}");
    for lanes in [8u32, 32] {
        let fixed = source.replace(&decl, &format!("const CACHE_LANES: u32 = {lanes}u;"));
        let module = validate(&fixed).unwrap_or_else(|e| panic!("{lanes} lanes: {e}"));
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let bytes: u32 = module
            .global_variables
            .iter()
            .filter(|(_, g)| g.space == naga::AddressSpace::WorkGroup)
            .map(|(_, g)| layouter[g.ty].size.div_ceil(16) * 16)
            .sum();
        assert_eq!(bytes, cache_build_bytes(lanes), "{lanes} lanes");
    }
}

fn settings(scene: &gpu_photon::scene::Scene, seed: u32) -> RenderSettings {
    common::example_settings(scene, 32, seed)
}

/// On lavapipe: the guard-free NVIDIA shape compiles every pipeline; then four example scenes
/// rendered with the simulated 32-wide shape (`subgroup:32`: workgroups of 128, 32 cache
/// lanes, the guard still on) is as close to the default shape's render at another seed as
/// two default renders are (common::within_seed_noise), and at the same seed far closer: the
/// widths change no random number, only the order photons land in and float summation order
/// (on lavapipe the images came out identical: the estimates sum in fixed point). The host's
/// dispatch sizes follow the shape, so an override the pipelines ignored would trace half
/// the paths here and fail.
/// One test, so that setting the environment variable races no other render.
#[test]
fn a_32_wide_shape_renders_the_same_images() {
    let Some(ctx) = gpu() else { return };
    let scene =
        gpu_photon::importers::load(std::path::Path::new("scenes/cornell-box.toml")).unwrap();
    let mut guard_free = ctx.clone();
    guard_free.shape = KernelShape::parse("nvidia", &AdapterFacts::of(&ctx.adapter)).unwrap();
    assert!(!guard_free.shape.loop_guard);
    let layouts = Layouts::new(&guard_free.device);
    let constants = feature_constants(
        &scene,
        &guard_free.shape,
        guard_free.adapter.get_info().device_type,
        true,
    );
    if let Err(e) = Pipelines::new(&guard_free, &layouts, &constants, true, true) {
        panic!("the guard-free 32-wide shape does not compile: {e}");
    }
    drop((guard_free, ctx));

    let run = |scene: &_, seed| {
        render(
            scene,
            &settings(scene, seed),
            Backend::Gpu,
            Progress::default(),
        )
        .unwrap()
        .0
    };
    let mut failures = Vec::new();
    // One scene per kernel family the widths touch (CI time: tests/gpu_images.rs renders
    // every example scene): the radiance cache's build (cornell-box, mode gather), the
    // caustic map (cornell-caustics), the glossy lobe (glossy-sphere) and mode photon's
    // K-nearest gather (point-light-plane).
    let wanted = [
        "cornell-box",
        "cornell-caustics",
        "glossy-sphere",
        "point-light-plane",
    ];
    let paths = common::example_scenes_without_media()
        .into_iter()
        .filter(|p| {
            wanted
                .iter()
                .any(|w| p.file_stem().is_some_and(|s| s == *w))
        })
        .collect::<Vec<_>>();
    assert_eq!(paths.len(), wanted.len(), "{paths:?}");
    for path in paths {
        let scene = gpu_photon::importers::load(&path).unwrap();
        std::env::remove_var(SHAPE_ENV);
        let (d1, d2) = (run(&scene, 1), run(&scene, 2));
        std::env::set_var(SHAPE_ENV, "subgroup:32");
        let wide1 = run(&scene, 1);
        std::env::remove_var(SHAPE_ENV);
        assert_eq!(wide1.non_finite(), 0, "{}: NaN or infinity", path.display());
        let noise = diff(&d1, &d2, 8).unwrap();
        let cross = diff(&wide1, &d2, 8).unwrap();
        let same = diff(&wide1, &d1, 8).unwrap();
        let line = format!(
            "{}: rmse wide1-default2 {:.5} vs default1-default2 {:.5}; block {:.5} vs {:.5}; \
             same seed {:.2e}",
            path.display(),
            cross.rmse,
            noise.rmse,
            cross.block_rmse,
            noise.block_rmse,
            same.rmse
        );
        eprintln!("{line}");
        let (pixels, blocks) = common::within_seed_noise(&cross, &noise, 1e-6);
        if !(pixels && blocks) || same.rmse > SAME_SEED_FRACTION * noise.rmse {
            failures.push(line);
        }
    }
    assert!(
        failures.is_empty(),
        "the 32-wide shape disagrees:\n{}",
        failures.join("\n")
    );
}

/// Largest same-seed difference of the two shapes, as a fraction of the seed noise.
const SAME_SEED_FRACTION: f64 = 0.25;

/// A context's feature floor (`GpuContext::with_feature_floor`, which the Mitsuba suite uses
/// to share kernels among scenes) changes the kernels, not the images: the Cornell box
/// rendered with five shareable features it lacks on (the suite shares all) is as close to
/// its own kernels' render at another seed as two of those are, and at the same seed far
/// closer (`SAME_SEED_FRACTION`).
#[test]
fn a_feature_floor_renders_the_same_images() {
    use gpu_photon::integrators::gpu::pipelines::{shareable_features, with_floor};
    use gpu_photon::integrators::gpu::GpuRenderer;
    use gpu_photon::render::session::PassRenderer;
    let Some(ctx) = gpu() else { return };
    let scene =
        gpu_photon::importers::load(std::path::Path::new("scenes/cornell-box.toml")).unwrap();
    // A few shareable features the scene lacks, each guarding code the scene's data then
    // skips; cheap ones (with textures and a BSDF kind more, lavapipe took 100 s to compile).
    let lacks = [
        "HAS_SMOOTH",
        "HAS_ALPHA",
        "HAS_SDF_GRIDS",
        "HAS_INSTANCES",
        "HAS_LIGHT_POINT",
    ];
    assert!(lacks.iter().all(|f| shareable_features().contains(f)));
    let floor: Vec<(&'static str, f64)> = lacks.iter().map(|&f| (f, 1.0)).collect();
    let floored = ctx.with_feature_floor(&floor);
    let device_type = ctx.adapter.get_info().device_type;
    let own = feature_constants(&scene, &ctx.shape, device_type, true);
    assert_ne!(
        with_floor(own.clone(), &floored.feature_floor),
        own,
        "the floor changes no kernel"
    );
    let run = |ctx: &gpu_photon::integrators::gpu::GpuContext, seed| {
        let s = settings(&scene, seed);
        let mut r = GpuRenderer::on_context(ctx.clone(), &scene, &s).unwrap();
        r.pass(0, &s, &Progress { enabled: false }).unwrap()
    };
    let (d1, d2, f1) = (run(&ctx, 1), run(&ctx, 2), run(&floored, 1));
    assert_eq!(f1.non_finite(), 0);
    let noise = diff(&d1, &d2, 8).unwrap();
    let cross = diff(&f1, &d2, 8).unwrap();
    let same = diff(&f1, &d1, 8).unwrap();
    eprintln!(
        "floor1-own2 {:.5} vs own1-own2 {:.5}; same seed {:.2e}",
        cross.rmse, noise.rmse, same.rmse
    );
    let (pixels, blocks) = common::within_seed_noise(&cross, &noise, 1e-6);
    assert!(pixels && blocks && same.rmse <= SAME_SEED_FRACTION * noise.rmse);
}
