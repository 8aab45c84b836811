//! Shader composition: each kernel family is its own file beside this one, preceded by the
//! prelude of shared constants generated from Rust (`codes::wgsl_prelude`) and the WGSL
//! libraries that live beside their Rust twins (`src/math/`, `src/bsdfs/`, `src/lights/`, ...)
//! in a fixed order. No text substitution inside a kernel; scene features
//! reach WGSL as pipeline-overridable constants.

use crate::integrators::gpu::codes::wgsl_prelude;

/// The compute kernel families (WGSL modules) of the GPU backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// `trace_photons.wgsl`: photon paths into a map's photon buffer.
    TracePhotons,
    /// `build_grid.wgsl`: the counting sort that builds a map's hash grid, with
    /// `volume_grid.wgsl` (the volume map's).
    BuildGrid,
    /// `gather.wgsl`: the camera pass and the radiance estimate, with
    /// `volume_estimate.wgsl` (the volume map's estimates),
    /// `media_camera.wgsl` (segments through media),
    /// `glass_branches.wgsl` (the camera path's deferred glass branches),
    /// `gather_ray.wgsl` (the final-gather ray),
    /// `radiance_cache.wgsl` (the final gather's cache lookup), `cache_build.wgsl`
    /// and `cache_fixed.wgsl` (its build) and the Sobol library
    /// (`crate::math::sobol::wgsl_library`).
    Gather,
}

const TYPES: &str = include_str!("types.wgsl");
const PHOTON: &str = include_str!("photon.wgsl");
const RNG: &str = include_str!("../../math/rng.wgsl");
const SAMPLING: &str = include_str!("../../math/sampling.wgsl");
const SCENE: &str = include_str!("scene.wgsl");
const INTERSECT: &str = include_str!("../../bvh/intersect.wgsl");
const SHADING_FRAME: &str = include_str!("../../bvh/shading_frame.wgsl");
const INSTANCES: &str = include_str!("../../bvh/instances.wgsl");
const SDF_GRID: &str = include_str!("../../scene/sdf_grid.wgsl");
const TEXTURE: &str = include_str!("../../textures/texture.wgsl");
const MEDIUM: &str = include_str!("../../media/medium.wgsl");
const HETEROGENEOUS: &str = include_str!("../../media/heterogeneous.wgsl");
const GRID: &str = include_str!("grid.wgsl");
const MAP: &str = include_str!("map.wgsl");
const ESTIMATE: &str = include_str!("../estimate.wgsl");
const SOBOL: &str = include_str!("../../math/sobol.wgsl");
const CAMERA: &str = include_str!("../../camera/camera.wgsl");
const TRACE_PHOTONS: &str = include_str!("trace_photons.wgsl");
const BUILD_GRID: &str = include_str!("build_grid.wgsl");
const VOLUME_GRID: &str = include_str!("volume_grid.wgsl");
const VOLUME_ESTIMATE: &str = include_str!("volume_estimate.wgsl");
const MEDIA_CAMERA: &str = include_str!("media_camera.wgsl");
const RADIANCE_CACHE: &str = include_str!("radiance_cache.wgsl");
const CACHE_BUILD: &str = include_str!("cache_build.wgsl");
const CACHE_FIXED: &str = include_str!("cache_fixed.wgsl");
const GLASS_BRANCHES: &str = include_str!("glass_branches.wgsl");
const GATHER: &str = include_str!("gather.wgsl");
const GATHER_RAY: &str = include_str!("gather_ray.wgsl");
const GPU_WIDE: &str = include_str!("../../bvh/gpu_wide.wgsl");
const BENCH_RAYS: &str = include_str!("../../bench/gpu_rays.wgsl");

/// The WGSL files outside `src/bsdfs/` and `src/lights/` the kernels compose, by their paths
/// under `src/` ([`wgsl_files`] adds the BSDFs' and the lights').
const WGSL_FILES: [(&str, &str); 30] = [
    ("integrators/gpu/types.wgsl", TYPES),
    ("integrators/gpu/photon.wgsl", PHOTON),
    ("math/rng.wgsl", RNG),
    ("math/sampling.wgsl", SAMPLING),
    ("integrators/gpu/scene.wgsl", SCENE),
    ("bvh/intersect.wgsl", INTERSECT),
    ("bvh/shading_frame.wgsl", SHADING_FRAME),
    ("bvh/instances.wgsl", INSTANCES),
    ("scene/sdf_grid.wgsl", SDF_GRID),
    // Composed by `gpu::textures::wgsl_library()` (behind its generated constants).
    ("textures/texture.wgsl", TEXTURE),
    ("media/medium.wgsl", MEDIUM),
    ("media/heterogeneous.wgsl", HETEROGENEOUS),
    ("integrators/gpu/grid.wgsl", GRID),
    ("integrators/gpu/map.wgsl", MAP),
    ("integrators/estimate.wgsl", ESTIMATE),
    // Composed by `crate::math::sobol::wgsl_library()` (behind its generated direction table).
    ("math/sobol.wgsl", SOBOL),
    // Composed by `crate::camera::pixel_filter::wgsl_library()` (behind its generated polynomials).
    ("camera/camera.wgsl", CAMERA),
    ("integrators/gpu/trace_photons.wgsl", TRACE_PHOTONS),
    ("integrators/gpu/build_grid.wgsl", BUILD_GRID),
    ("integrators/gpu/volume_grid.wgsl", VOLUME_GRID),
    ("integrators/gpu/volume_estimate.wgsl", VOLUME_ESTIMATE),
    ("integrators/gpu/media_camera.wgsl", MEDIA_CAMERA),
    ("integrators/gpu/radiance_cache.wgsl", RADIANCE_CACHE),
    ("integrators/gpu/cache_build.wgsl", CACHE_BUILD),
    ("integrators/gpu/cache_fixed.wgsl", CACHE_FIXED),
    ("integrators/gpu/glass_branches.wgsl", GLASS_BRANCHES),
    ("integrators/gpu/gather_ray.wgsl", GATHER_RAY),
    ("integrators/gpu/gather.wgsl", GATHER),
    // The ray benchmark's module only (`bench_source`): the four-wide walk, its kernel.
    ("bvh/gpu_wide.wgsl", GPU_WIDE),
    ("bench/gpu_rays.wgsl", BENCH_RAYS),
];

/// Every WGSL file the kernels compose, by its path under `src/` (for tests that read them).
pub fn wgsl_files() -> Vec<(String, &'static str)> {
    let mut out: Vec<(String, &'static str)> = WGSL_FILES
        .iter()
        .map(|&(p, t)| (p.to_string(), t))
        .collect();
    out.extend(crate::bsdfs::gpu::wgsl_files());
    out.extend(crate::lights::gpu::wgsl_files());
    out
}

impl Kernel {
    /// Every kernel family.
    pub const ALL: [Kernel; 3] = [Kernel::TracePhotons, Kernel::BuildGrid, Kernel::Gather];

    /// The module's name (its WGSL file's stem; the shader module's label).
    pub fn name(self) -> &'static str {
        match self {
            Kernel::TracePhotons => "trace_photons",
            Kernel::BuildGrid => "build_grid",
            Kernel::Gather => "gather",
        }
    }

    /// The entry points the host creates pipelines for.
    pub fn entry_points(self) -> &'static [&'static str] {
        match self {
            Kernel::TracePhotons => &["trace_photons"],
            Kernel::BuildGrid => &[
                "size_grid",
                "count_cells",
                "scan_blocks",
                "scan_sums",
                "add_offsets",
                "scatter",
                "scatter_rest",
                "size_volume",
                "count_volume",
                "scatter_volume",
            ],
            Kernel::Gather => &[
                "gather",
                "list_cache_points",
                "size_cache_build",
                "build_cache",
                "build_cache_fixed",
            ],
        }
    }

    /// The composed WGSL source of this kernel's module: prelude, libraries, own files.
    pub fn source(self) -> String {
        // The gather kernel draws Sobol points (camera jitter, first-hit light and gather
        // samples): the library with its generated direction table, after rng.wgsl.
        let sobol = crate::math::sobol::wgsl_library();
        // The camera ray: the pixel filter's jitter and the thin lens.
        let camera = crate::camera::pixel_filter::wgsl_library();
        let own: &[&str] = match self {
            Kernel::TracePhotons => &[MAP, TRACE_PHOTONS],
            Kernel::BuildGrid => &[MAP, BUILD_GRID, VOLUME_GRID],
            Kernel::Gather => &[
                &sobol,
                &camera,
                ESTIMATE,
                VOLUME_ESTIMATE,
                MEDIA_CAMERA,
                RADIANCE_CACHE,
                CACHE_BUILD,
                CACHE_FIXED,
                GLASS_BRANCHES,
                GATHER_RAY,
                GATHER,
            ],
        };
        compose(own)
    }
}

/// The prelude and the libraries every kernel composes, then `own`.
fn compose(own: &[&str]) -> String {
    let prelude = wgsl_prelude();
    // The BSDFs (every kind's file, the shading interface and their generated dispatch) and
    // the textures (texture.wgsl with its constants): every kernel declares their bindings.
    let bsdfs = crate::bsdfs::gpu::wgsl_library();
    let lights = crate::lights::gpu::wgsl_library();
    let textures = crate::integrators::gpu::textures::wgsl_library();
    let libs: &[&str] = &[
        &prelude,
        TYPES,
        PHOTON,
        RNG,
        SAMPLING,
        SCENE,
        INTERSECT,
        SHADING_FRAME,
        INSTANCES,
        SDF_GRID,
        &lights,
        &bsdfs,
        &textures,
        MEDIUM,
        HETEROGENEOUS,
        GRID,
    ];
    libs.iter()
        .chain(own)
        .copied()
        .collect::<Vec<_>>()
        .join("\n")
}

/// A module of oracle probes (tests/probes/, test code only): the libraries, the gather
/// group's estimates and media functions (the probes bind that group, whose branch stacks
/// glass_branches.wgsl declares), then the probes' own WGSL `own`.
pub fn probe_source(own: &[&str]) -> String {
    let mut all = vec![
        ESTIMATE,
        VOLUME_ESTIMATE,
        MEDIA_CAMERA,
        RADIANCE_CACHE,
        GLASS_BRANCHES,
    ];
    all.extend_from_slice(own);
    compose(&all)
}

/// The ray benchmark's module (src/bench/gpu_rays.rs): the libraries, the four-wide walk
/// (src/bvh/gpu_wide.wgsl) and the benchmark's kernel.
pub fn bench_source() -> String {
    compose(&[GPU_WIDE, BENCH_RAYS])
}

/// Parses and validates a composed module with naga (no GPU needed).
pub fn validate(source: &str) -> Result<naga::Module, String> {
    parse_and_validate(source).map(|(module, _)| module)
}

/// [`validate`], keeping naga's analysis of the module (what `gpu::specialise` needs).
pub fn parse_and_validate(source: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok((module, info))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ray_benchmark_parses_and_validates() {
        if let Err(e) = validate(&bench_source()) {
            panic!("bench_rays: {e}");
        }
    }

    #[test]
    fn every_kernel_parses_and_validates() {
        for k in Kernel::ALL {
            if let Err(e) = validate(&k.source()) {
                panic!("{}: {e}", k.name());
            }
        }
    }
}
