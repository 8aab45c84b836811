//! The compute pipelines of a render, each created once, specialised to the scene's features
//! and the device's loop budget through WGSL override constants.

use crate::error::{Error, Result};
use crate::integrators::gpu::bindings::Layouts;
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::shaders::{parse_and_validate, Kernel};
use crate::integrators::gpu::shape::KernelShape;
use crate::integrators::gpu::specialise::specialise;
use crate::scene::Scene;

/// Per-lane loop budget on a CPU device (lavapipe): 65,535 iterations per 8-lane SIMD group
/// (`LOOP_BUDGET` in src/integrators/gpu/scene.wgsl explains the bound; it is also the WGSL
/// default, which the probes use).
pub const CPU_DEVICE_LOOP_BUDGET: u32 = 8000;
/// Loop budget on devices without lavapipe's cut: a guard against runaway loops only.
pub const GPU_DEVICE_LOOP_BUDGET: u32 = 1_000_000;

/// Scene features, the kernel shape (`shape`: widths and the loop guard), the device's loop
/// budget and whether any pass may run K-nearest estimates (`knn`: false for a progressive
/// render) as pipeline-overridable constants.
pub fn feature_constants(
    scene: &Scene,
    shape: &KernelShape,
    device_type: wgpu::DeviceType,
    knn: bool,
) -> Vec<(&'static str, f64)> {
    let budget = if device_type == wgpu::DeviceType::Cpu {
        CPU_DEVICE_LOOP_BUDGET
    } else {
        GPU_DEVICE_LOOP_BUDGET
    };
    let mut constants = shape.overrides();
    constants.push(("LOOP_BUDGET", budget as f64));
    constants.extend(scene_features(scene, knn));
    constants
}

/// The scene features whose code in the kernels also checks the scene's data (a primitive's
/// kind, a material's texture or alpha mode, a BSDF's or light's kind, a medium's grid), so
/// that a kernel compiled with one on renders a scene without it as the scene's own kernel
/// does, only slower: the BSDF and light kind flags and the presence flags below, for scenes
/// with primitives. Not shareable: `HAS_ENVIRONMENT` (the last light is then read as the
/// environment), `HAS_MEDIA` (null surfaces pass rays), `HAS_UVS` (the tangent's fallback),
/// `GLASS_SPLIT` (its branch stacks), `KNN` and the rest.
pub fn shareable_features() -> Vec<&'static str> {
    let mut out = vec![
        "HAS_SPHERES",
        "HAS_SDF_GRIDS",
        "HAS_INSTANCES",
        "HAS_SMOOTH",
        "HAS_TEXTURES",
        "HAS_NORMAL_MAPS",
        "HAS_BUMP_MAPS",
        "HAS_ALPHA",
        "HAS_HETERO_MEDIA",
        "HAS_LINEAR_SPOTS",
    ];
    out.extend(crate::bsdfs::gpu::kind_flags().iter().map(String::as_str));
    out.extend(crate::lights::gpu::kind_flags().iter().map(String::as_str));
    out
}

/// `constants` with each shareable feature of `floor` ([`shareable_features`]) raised to at
/// least its value there; the others as they are.
pub fn with_floor(
    mut constants: Vec<(&'static str, f64)>,
    floor: &[(&'static str, f64)],
) -> Vec<(&'static str, f64)> {
    let shareable = shareable_features();
    for (name, value) in &mut constants {
        if !shareable.contains(name) {
            continue;
        }
        if let Some((_, f)) = floor.iter().find(|(n, _)| n == name) {
            *value = value.max(*f);
        }
    }
    constants
}

/// The scene's features (and `knn`, whether any pass may run K-nearest estimates) as the
/// pipeline-overridable constants a render's pipelines, and the probes on its scene, are
/// specialised with.
pub fn scene_features(scene: &Scene, knn: bool) -> Vec<(&'static str, f64)> {
    // One flag per kind of BSDF: the dispatch compiles the kinds the scene has.
    let kinds = crate::bsdfs::gpu::kind_flags()
        .iter()
        .enumerate()
        .map(|(code, flag)| {
            let has = scene.materials.iter().any(|m| m.bsdf.code() == code as u32);
            (flag.as_str(), has as u32 as f64)
        });
    // A mesh of the scene's instances counts as its own geometry (uploaded after it).
    let meshes = |f: fn(&Scene) -> bool| f(scene) || scene.instancing.meshes.iter().any(f);
    let mut features = vec![
        (
            "HAS_SPHERES",
            meshes(|s| !s.spheres.is_empty()) as u32 as f64,
        ),
        ("HAS_INSTANCES", !scene.instancing.is_empty() as u32 as f64),
        ("HAS_SDF_GRIDS", !scene.sdf_grids.is_empty() as u32 as f64),
        // Some light is a delta light (LightKind::is_delta): the gather's shadow rays for them.
        ("HAS_POINT_LIGHTS", scene.has_delta_lights() as u32 as f64),
        ("HAS_SMOOTH", meshes(Scene::has_smooth) as u32 as f64),
        (
            "HAS_ENVIRONMENT",
            scene.environment().is_some() as u32 as f64,
        ),
        ("HAS_TEXTURES", !scene.textures.is_empty() as u32 as f64),
        (
            "HAS_NORMAL_MAPS",
            scene
                .materials
                .iter()
                .any(|m| m.normal_texture != crate::scene::NO_TEXTURE) as u32 as f64,
        ),
        (
            "HAS_BUMP_MAPS",
            scene.materials.iter().any(|m| m.bump.is_some()) as u32 as f64,
        ),
        ("HAS_UVS", meshes(|s| !s.uvs.is_empty()) as u32 as f64),
        (
            "HAS_TANGENTS",
            meshes(|s| !s.tangents.is_empty()) as u32 as f64,
        ),
        (
            "HAS_ALPHA",
            scene.materials.iter().any(|m| m.alpha.is_some()) as u32 as f64,
        ),
        ("KNN", knn as u32 as f64),
        ("HAS_MEDIA", scene.has_media_transport() as u32 as f64),
        (
            "HAS_HETERO_MEDIA",
            scene.media.iter().any(|m| !m.is_homogeneous()) as u32 as f64,
        ),
        ("GLASS_SPLIT", glass_split(scene) as u32 as f64),
    ];
    features.extend(kinds);
    // One flag per kind of light, and the kinds' own constants.
    features.extend(crate::lights::gpu::overrides(&scene.lights));
    features
}

/// Whether a camera path may split at a dielectric (glass, or a thin dielectric sheet):
/// only then do the gather's glass branch stacks and rounds exist (`GLASS_SPLIT`).
pub fn glass_split(scene: &Scene) -> bool {
    use crate::bsdfs::BsdfKind;
    scene.materials.iter().any(|m| m.bsdf.splits())
}

/// The compute pipelines of a render, each created once.
#[derive(Clone)]
pub struct Pipelines {
    /// `trace_photons` (src/integrators/gpu/trace_photons.wgsl).
    pub trace_photons: wgpu::ComputePipeline,
    /// `size_grid` (src/integrators/gpu/build_grid.wgsl).
    pub size_grid: wgpu::ComputePipeline,
    /// `count_cells` (src/integrators/gpu/build_grid.wgsl).
    pub count_cells: wgpu::ComputePipeline,
    /// `scan_blocks` (src/integrators/gpu/build_grid.wgsl).
    pub scan_blocks: wgpu::ComputePipeline,
    /// `scan_sums` (src/integrators/gpu/build_grid.wgsl).
    pub scan_sums: wgpu::ComputePipeline,
    /// `add_offsets` (src/integrators/gpu/build_grid.wgsl).
    pub add_offsets: wgpu::ComputePipeline,
    /// `scatter` (src/integrators/gpu/build_grid.wgsl).
    pub scatter: wgpu::ComputePipeline,
    /// `scatter_rest` (src/integrators/gpu/build_grid.wgsl).
    pub scatter_rest: wgpu::ComputePipeline,
    /// `size_volume` (src/integrators/gpu/volume_grid.wgsl).
    pub size_volume: wgpu::ComputePipeline,
    /// `count_volume` (src/integrators/gpu/volume_grid.wgsl).
    pub count_volume: wgpu::ComputePipeline,
    /// `scatter_volume` (src/integrators/gpu/volume_grid.wgsl).
    pub scatter_volume: wgpu::ComputePipeline,
    /// `gather` (src/integrators/gpu/gather.wgsl).
    pub gather: wgpu::ComputePipeline,
    /// Whether `gather` is also dispatched for rounds of glass branches (`GLASS_SPLIT`).
    pub glass_rounds: bool,
    /// The radiance cache's build: only for a render in mode gather.
    pub radiance_cache: Option<CachePipelines>,
    /// The kernel shape they were compiled with (the host's dispatch sizes follow it).
    pub shape: KernelShape,
}

/// The radiance cache's build (src/integrators/gpu/cache_build.wgsl and cache_fixed.wgsl).
#[derive(Clone)]
pub struct CachePipelines {
    /// `list_cache_points`.
    pub list: wgpu::ComputePipeline,
    /// `size_cache_build`.
    pub size: wgpu::ComputePipeline,
    /// `build_cache`, the K-nearest values: only on pipelines with K-nearest estimates.
    pub knn: Option<wgpu::ComputePipeline>,
    /// `build_cache_fixed`, the fixed-radius values.
    pub fixed: wgpu::ComputePipeline,
}

/// A shader module of composed WGSL `source` (a kernel's, or a test's oracle probes').
pub fn shader_module_of(dev: &wgpu::Device, label: &str, source: String) -> wgpu::ShaderModule {
    dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// A kernel family's composed WGSL, parsed and validated once by naga; each entry point gets
/// a module of its own, specialised to the render's constants (`gpu::specialise`).
struct Family {
    label: &'static str,
    source: String,
    /// `None` when naga rejects the source: wgpu then reports the error on the WGSL itself.
    parsed: Option<(naga::Module, naga::valid::ModuleInfo)>,
}

impl Family {
    fn new(label: &'static str, source: String) -> Self {
        let parsed = parse_and_validate(&source).ok();
        Family {
            label,
            source,
            parsed,
        }
    }

    /// The module of entry point `entry` and the override constants its pipeline takes:
    /// specialised, those sizing workgroup arrays; else the whole WGSL and all of
    /// `constants` (a module naga cannot specialise is left for wgpu to compile or report).
    fn entry<'c>(
        &self,
        dev: &wgpu::Device,
        entry: &str,
        constants: &[(&'c str, f64)],
    ) -> (wgpu::ShaderModule, Vec<(&'c str, f64)>) {
        let specialised = self
            .parsed
            .as_ref()
            .and_then(|(module, info)| specialise(module, info, entry, constants).ok());
        match specialised {
            Some((module, kept)) => {
                let label = format!("{} ({entry})", self.label);
                let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&label),
                    source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
                });
                (module, kept)
            }
            None => (
                shader_module_of(dev, self.label, self.source.clone()),
                constants.to_vec(),
            ),
        }
    }
}

/// The pipeline layout of groups 0 (scene) and 1 (`group1`).
pub fn pipeline_layout(
    dev: &wgpu::Device,
    label: &str,
    layouts: &Layouts,
    group1: &wgpu::BindGroupLayout,
) -> wgpu::PipelineLayout {
    dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(&layouts.scene), Some(group1)],
        immediate_size: 0,
    })
}

impl Pipelines {
    /// Compiles every kernel's pipelines with the override constants `constants` (the
    /// radiance cache's build only when `final_gather`, its K-nearest kernel only when `knn`,
    /// the constants' `KNN`); a shader or layout error is returned, not raised.
    pub fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        constants: &[(&str, f64)],
        final_gather: bool,
        knn: bool,
    ) -> Result<Self> {
        let dev = &ctx.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let map_layout = pipeline_layout(dev, "photon map pipeline layout", layouts, &layouts.map);
        let gather_layout =
            pipeline_layout(dev, "gather pipeline layout", layouts, &layouts.gather);
        let pipeline = |family: &Family, layout: &wgpu::PipelineLayout, entry: &str| {
            let (module, constants) = family.entry(dev, entry, constants);
            // build_cache clears what it reads of its 14 KB of workgroup memory itself.
            let zero = entry != "build_cache";
            dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    zero_initialize_workgroup_memory: zero,
                },
                cache: None,
            })
        };
        let split = constants
            .iter()
            .any(|&(n, v)| n == "GLASS_SPLIT" && v != 0.0);
        let family = |k: Kernel| Family::new(k.name(), k.source());
        let trace = family(Kernel::TracePhotons);
        let grid = family(Kernel::BuildGrid);
        let gather = match crate::integrators::gpu::faults::injected() {
            Some(crate::integrators::gpu::faults::Fault::Shader) => {
                Family::new("gather (malformed)", malformed_source())
            }
            _ => family(Kernel::Gather),
        };
        let p = Pipelines {
            trace_photons: pipeline(&trace, &map_layout, "trace_photons"),
            size_grid: pipeline(&grid, &map_layout, "size_grid"),
            count_cells: pipeline(&grid, &map_layout, "count_cells"),
            scan_blocks: pipeline(&grid, &map_layout, "scan_blocks"),
            scan_sums: pipeline(&grid, &map_layout, "scan_sums"),
            add_offsets: pipeline(&grid, &map_layout, "add_offsets"),
            scatter: pipeline(&grid, &map_layout, "scatter"),
            scatter_rest: pipeline(&grid, &map_layout, "scatter_rest"),
            size_volume: pipeline(&grid, &map_layout, "size_volume"),
            count_volume: pipeline(&grid, &map_layout, "count_volume"),
            scatter_volume: pipeline(&grid, &map_layout, "scatter_volume"),
            gather: pipeline(&gather, &gather_layout, "gather"),
            glass_rounds: split,
            radiance_cache: final_gather.then(|| CachePipelines {
                list: pipeline(&gather, &gather_layout, "list_cache_points"),
                size: pipeline(&gather, &gather_layout, "size_cache_build"),
                knn: knn.then(|| pipeline(&gather, &gather_layout, "build_cache")),
                fixed: pipeline(&gather, &gather_layout, "build_cache_fixed"),
            }),
            shape: ctx.shape,
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            let e = crate::integrators::gpu::faults::describe(&e);
            return Err(Error::Gpu(format!("pipeline creation failed: {e}")));
        }
        Ok(p)
    }
}

/// The gather kernel cut short and ended by a stray token (an injected shader fault,
/// `gpu::faults`): a parse error.
fn malformed_source() -> String {
    let source = Kernel::Gather.source();
    let mut half = source.len() / 2;
    while !source.is_char_boundary(half) {
        half -= 1;
    }
    // A token no WGSL parses after the cut: the half alone may end between two whole
    // functions and parse, failing only later at the missing entry point.
    format!("{}\n@@ malformed", &source[..half])
}
