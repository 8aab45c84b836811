//! The GPU render: scene upload, the pipelines (created once), and the passes recorded per
//! photon map (trace, then the grid build) and per camera sample (gather).

use super::context::GpuContext;
use super::grid::{cell_size_for, table_size_for};
use super::shaders::Kernel;
use super::types::*;
use crate::bvh::{Bvh, BvhNode};
use crate::error::{Error, Result};
use crate::film::Image;
use crate::light::LightTable;
use crate::photon::{Budget, Photon};
use crate::plan::MapPlan;
use crate::report::{Progress, RenderReport};
use crate::rng::Stream;
use crate::scene::Scene;
use crate::settings::{FresnelMode, RenderSettings};
use bytemuck::Pod;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Largest K the gather kernel's heap holds (`MAX_HEAP` in shaders/gather.wgsl).
pub const MAX_HEAP: u32 = 256;
/// Indices of the stats buffer (`STAT_*` in shaders/common/types.wgsl).
pub const STAT_PHOTON_OVERFLOW: usize = 0;
pub const STAT_LOOP_BUDGET: usize = 1;
pub const STAT_GATHER_TRUNCATED: usize = 2;
const STATS_LEN: usize = 4;
/// Drop flags of a map's grid (`DROP_*` in shaders/common/grid.wgsl).
const DROP_DIRECT: u32 = 1;
const DROP_CAUSTIC: u32 = 2;

fn storage_buffer<T: Pod>(
    dev: &wgpu::Device,
    label: &str,
    data: &[T],
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(data).to_vec();
    if bytes.is_empty() {
        bytes.resize(256, 0); // bindings may not be empty: one zeroed element of any struct
    }
    dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage: wgpu::BufferUsages::STORAGE | extra,
    })
}

fn empty_buffer(
    dev: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(64),
        usage,
        mapped_at_creation: false,
    })
}

fn layout_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    dynamic: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: dynamic,
            min_binding_size: None,
        },
        count: None,
    }
}

const RO: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };
const RW: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: false };

/// The scene group's binding of the per-sample parameters (`params` in
/// shaders/common/scene.wgsl), bound with a dynamic offset PARAMS_STRIDE apart.
pub const PARAMS_BINDING: u32 = 8;

/// The bind-group layouts, declared once: group 0 (scene) for every kernel, group 1 for the
/// map-building kernels or for the gather.
///
/// No binding is a uniform buffer, on purpose: lavapipe (Mesa 22.3) inlines uniform values
/// into the shader and compiles a new copy of the pipeline, never freed, each time a bind
/// group holding a uniform buffer is bound: about 2.3 MB and 23 ms per gather dispatch.
/// Read-only storage buffers carry the parameters instead.
pub struct Layouts {
    pub scene: wgpu::BindGroupLayout,
    pub map: wgpu::BindGroupLayout,
    pub gather: wgpu::BindGroupLayout,
}

impl Layouts {
    pub fn new(dev: &wgpu::Device) -> Self {
        // `dynamic`: the binding that takes a dynamic offset, if any.
        let mk = |label: &str, tys: &[wgpu::BufferBindingType], dynamic: Option<u32>| {
            let entries: Vec<_> = tys
                .iter()
                .enumerate()
                .map(|(i, &t)| layout_entry(i as u32, t, dynamic == Some(i as u32)))
                .collect();
            dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
        };
        Layouts {
            scene: mk(
                "scene layout",
                &[RO, RO, RO, RO, RO, RO, RO, RO, RO, RW],
                Some(PARAMS_BINDING),
            ),
            map: mk("photon map layout", &[RW, RW, RW, RW, RW, RW, RO], None),
            gather: mk("gather layout", &[RO, RO, RO, RO, RO, RO, RW], None),
        }
    }
}

/// Bind-group entries 0, 1, ... each binding a whole buffer.
fn whole_entries<'b>(
    buffers: impl Iterator<Item = &'b wgpu::Buffer>,
) -> Vec<wgpu::BindGroupEntry<'b>> {
    buffers
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect()
}

fn bind_group(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries = whole_entries(buffers.iter().copied());
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// Per-lane loop budget on a CPU device (lavapipe): 65,535 iterations per 8-lane SIMD group
/// (`LOOP_BUDGET` in shaders/common/scene.wgsl explains the bound).
pub const CPU_DEVICE_LOOP_BUDGET: u32 = 8000;
/// Loop budget on devices without lavapipe's cut: a guard against runaway loops only.
pub const GPU_DEVICE_LOOP_BUDGET: u32 = 1_000_000;

/// Scene features and the device's loop budget as pipeline-overridable constants.
pub fn feature_constants(scene: &Scene, device_type: wgpu::DeviceType) -> Vec<(&'static str, f64)> {
    let budget = if device_type == wgpu::DeviceType::Cpu {
        CPU_DEVICE_LOOP_BUDGET
    } else {
        GPU_DEVICE_LOOP_BUDGET
    };
    vec![
        ("LOOP_BUDGET", budget as f64),
        ("HAS_GLASS", scene.has_glass() as u32 as f64),
        ("HAS_SPHERES", (!scene.spheres.is_empty()) as u32 as f64),
        ("HAS_POINT_LIGHTS", scene.has_point_lights() as u32 as f64),
    ]
}

/// The compute pipelines of a render, each created once.
pub struct Pipelines {
    pub trace_photons: wgpu::ComputePipeline,
    pub count_cells: wgpu::ComputePipeline,
    pub scan_blocks: wgpu::ComputePipeline,
    pub scan_sums: wgpu::ComputePipeline,
    pub add_offsets: wgpu::ComputePipeline,
    pub scatter: wgpu::ComputePipeline,
    pub gather: wgpu::ComputePipeline,
}

impl Pipelines {
    pub fn new(ctx: &GpuContext, layouts: &Layouts, constants: &[(&str, f64)]) -> Result<Self> {
        let dev = &ctx.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = |k: Kernel| {
            dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(k.name()),
                source: wgpu::ShaderSource::Wgsl(k.source().into()),
            })
        };
        let map_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("photon map pipeline layout"),
            bind_group_layouts: &[Some(&layouts.scene), Some(&layouts.map)],
            immediate_size: 0,
        });
        let gather_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gather pipeline layout"),
            bind_group_layouts: &[Some(&layouts.scene), Some(&layouts.gather)],
            immediate_size: 0,
        });
        let pipeline = |m: &wgpu::ShaderModule, layout: &wgpu::PipelineLayout, entry: &str| {
            dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                module: m,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    zero_initialize_workgroup_memory: true,
                },
                cache: None,
            })
        };
        let trace = module(Kernel::TracePhotons);
        let grid = module(Kernel::BuildGrid);
        let gather = module(Kernel::Gather);
        let p = Pipelines {
            trace_photons: pipeline(&trace, &map_layout, "trace_photons"),
            count_cells: pipeline(&grid, &map_layout, "count_cells"),
            scan_blocks: pipeline(&grid, &map_layout, "scan_blocks"),
            scan_sums: pipeline(&grid, &map_layout, "scan_sums"),
            add_offsets: pipeline(&grid, &map_layout, "add_offsets"),
            scatter: pipeline(&grid, &map_layout, "scatter"),
            gather: pipeline(&gather, &gather_layout, "gather"),
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("pipeline creation failed: {e}")));
        }
        Ok(p)
    }
}

/// The scene in device buffers, with the group-0 bind group.
pub struct SceneBuffers {
    pub params: wgpu::Buffer,
    /// The lights with their photon budgets (rewritten per pass).
    pub lights: wgpu::Buffer,
    pub stats: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

impl SceneBuffers {
    pub fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        scene: &Scene,
        bvh: &Bvh,
        table: &LightTable,
        lights: &[GpuLight],
        bounds: &[GpuAabb],
        params: &GpuParams,
        samples: u32,
    ) -> Self {
        let dev = &ctx.device;
        let none = wgpu::BufferUsages::empty();
        let tris: Vec<GpuTriangle> = scene.triangles.iter().map(GpuTriangle::from).collect();
        let spheres: Vec<GpuSphere> = scene.spheres.iter().map(GpuSphere::from).collect();
        let mats: Vec<GpuMaterial> = scene.materials.iter().map(GpuMaterial::from).collect();
        let nodes: &[BvhNode] = &bvh.nodes;
        let buffers = [
            storage_buffer(dev, "triangles", &tris, none),
            storage_buffer(dev, "spheres", &spheres, none),
            storage_buffer(dev, "bvh nodes", nodes, none),
            storage_buffer(dev, "bvh prim ids", &bvh.prim_ids, none),
            storage_buffer(dev, "materials", &mats, none),
            storage_buffer(dev, "lights", lights, wgpu::BufferUsages::COPY_DST),
            storage_buffer(dev, "light cdf", &table.tri_cdf, none),
            storage_buffer(dev, "specular bounds", bounds, none),
        ];
        // One PARAMS_STRIDE slot per camera sample: a pass's gathers are all recorded into
        // one submission, each dispatch reading its sample's slot (dynamic offset).
        let params_buf = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: PARAMS_STRIDE * samples.max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&params_buf, 0, bytemuck::bytes_of(params));
        let stats = storage_buffer(
            dev,
            "stats",
            &[0u32; STATS_LEN],
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let mut entries = whole_entries(buffers.iter());
        entries.push(wgpu::BindGroupEntry {
            binding: 8,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &params_buf,
                offset: 0,
                size: std::num::NonZeroU64::new(std::mem::size_of::<GpuParams>() as u64),
            }),
        });
        entries.push(wgpu::BindGroupEntry {
            binding: 9,
            resource: stats.as_entire_binding(),
        });
        let bind_group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene bind group"),
            layout: &layouts.scene,
            entries: &entries,
        });
        SceneBuffers {
            lights: buffers[5].clone(),
            params: params_buf,
            stats,
            bind_group,
        }
    }
}

/// One photon map on the device: the traced photons, the hash grid and its parameters.
pub struct MapBuffers {
    pub params: GpuMapParams,
    pub photons: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    pub cell_count: wgpu::Buffer,
    pub cell_start: wgpu::Buffer,
    pub sorted: wgpu::Buffer,
    pub params_buf: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

impl MapBuffers {
    pub fn new(ctx: &GpuContext, layouts: &Layouts, label: &str, params: GpuMapParams) -> Self {
        let dev = &ctx.device;
        let rw = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let photon_bytes = params.capacity as u64 * std::mem::size_of::<Photon>() as u64;
        let t = params.table_size as u64;
        let photons = empty_buffer(dev, &format!("{label} photons"), photon_bytes, rw);
        let counters = empty_buffer(dev, &format!("{label} counters"), 16, rw);
        let cell_count = empty_buffer(dev, &format!("{label} cell counts"), 4 * t, rw);
        let cell_start = empty_buffer(dev, &format!("{label} cell starts"), 4 * (t + 1), rw);
        let sorted = empty_buffer(dev, &format!("{label} sorted photons"), photon_bytes, rw);
        let block_sums = empty_buffer(dev, &format!("{label} block sums"), 4 * t.div_ceil(256), rw);
        let params_buf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label} map params")),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = bind_group(
            dev,
            &format!("{label} map bind group"),
            &layouts.map,
            &[
                &photons,
                &counters,
                &cell_count,
                &cell_start,
                &sorted,
                &block_sums,
                &params_buf,
            ],
        );
        MapBuffers {
            params,
            photons,
            counters,
            cell_count,
            cell_start,
            sorted,
            params_buf,
            bind_group,
        }
    }

    /// Records tracing this map's photons (when `trace`) and building its grid (when
    /// `grid`) into `enc`.
    pub fn record_build(
        &self,
        enc: &mut wgpu::CommandEncoder,
        p: &Pipelines,
        scene_bg: &wgpu::BindGroup,
        trace: bool,
        grid: bool,
    ) {
        if trace {
            enc.clear_buffer(&self.counters, 0, None);
        }
        if grid {
            enc.clear_buffer(&self.cell_count, 0, None);
        }
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("build photon map"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, scene_bg, &[0]);
        pass.set_bind_group(1, &self.bind_group, &[]);
        let cap = self.params.capacity;
        let t = self.params.table_size;
        let trace_stage = [(&p.trace_photons, self.params.paths, 64)];
        let grid_stages = [
            (&p.count_cells, cap, 64),
            (&p.scan_blocks, t, 256),
            (&p.scan_sums, 256, 256),
            (&p.add_offsets, t, 64),
            (&p.scatter, cap, 64),
        ];
        let stages = if trace { &trace_stage[..] } else { &[] };
        let grid_stages = if grid { &grid_stages[..] } else { &[] };
        for &(pipeline, n, wg) in stages.iter().chain(grid_stages) {
            pass.set_pipeline(pipeline);
            let (x, y) = grid_2d(n.div_ceil(wg));
            pass.dispatch_workgroups(x, y, 1);
        }
    }
}

/// Parameters of an absent map (`paths == 0`: the gather skips it).
pub const EMPTY_MAP: GpuMapParams = GpuMapParams {
    stream: 0,
    paths: 0,
    capacity: 1,
    table_size: 256,
    cell_size: 1.0,
    is_caustic: 0,
    drop_flags: 0,
    radius2: 0.0,
};

/// Distance between the per-sample parameter slots (the largest storage-buffer offset
/// alignment an adapter may require; checked against the adapter's limit).
pub const PARAMS_STRIDE: u64 = 256;

/// Most batches one pass is split into (and the stride of batch indices in the RNG's pass).
pub const MAX_BATCHES: u32 = 64;

/// Settings of batch `b` of `n`: an equal share of the photon paths (the remainder spread
/// over the first batches).
pub fn batch_settings(s: &RenderSettings, b: u32, n: u32) -> RenderSettings {
    let share = |total: u32| total / n + u32::from(b < total % n);
    RenderSettings {
        photons: share(s.photons).max(1),
        caustic_photons: share(s.caustic_photons),
        ..s.clone()
    }
}

/// Photons the map's kernels stored (the reports' counts).
fn report_count(r: &RenderReport, m: &MapBuffers) -> usize {
    if m.params.is_caustic != 0 {
        r.caustic_stored
    } else {
        r.global_stored
    }
}

/// Splits a workgroup count over x and y so that x stays within the 65,535 limit.
pub fn grid_2d(groups: u32) -> (u32, u32) {
    let groups = groups.max(1);
    let x = groups.min(65_535);
    (x, groups.div_ceil(x))
}

/// The lights with the plan's global and caustic photon budgets filled in.
fn budgeted_lights(scene: &Scene, table: &LightTable, plan: &MapPlan) -> Vec<GpuLight> {
    let mut lights = lights(scene, table);
    if let Some(b) = &plan.global {
        fill_budget(&mut lights, b, false);
    }
    if let Some((b, _)) = &plan.caustic {
        fill_budget(&mut lights, b, true);
    }
    lights
}

fn fill_budget(lights: &mut [GpuLight], b: &Budget, caustic: bool) {
    for (l, g) in lights.iter_mut().enumerate() {
        if caustic {
            (g.caustic_offset, g.caustic_count, g.caustic_power) =
                (b.offsets[l], b.counts[l], b.path_power[l].to_array());
        } else {
            (g.global_offset, g.global_count, g.global_power) =
                (b.offsets[l], b.counts[l], b.path_power[l].to_array());
        }
    }
}

/// `Params` of a render (`sample` set per gather dispatch).
pub fn gpu_params(scene: &Scene, s: &RenderSettings, pass: u32, n_bounds: u32) -> GpuParams {
    let terms = crate::plan::Terms::of(s.mode);
    let c = &scene.camera;
    GpuParams {
        eye: c.eye.to_array(),
        width: s.width,
        forward: c.forward.to_array(),
        height: s.height,
        right: c.right.to_array(),
        spp: s.spp,
        up: c.up.to_array(),
        sample: 0,
        seed: s.seed,
        pass_index: pass,
        k: s.k,
        filter_kind: match s.filter {
            crate::settings::Filter::Disc => 0,
            crate::settings::Filter::Cone => 1,
            crate::settings::Filter::Epanechnikov => 2,
        },
        mode: s.mode as u32,
        max_depth: s.max_depth,
        max_photon_bounces: s.max_photon_bounces,
        shadow_samples: s.shadow_samples,
        fresnel: (s.fresnel == FresnelMode::Schlick) as u32,
        n_lights: scene.lights.len() as u32,
        n_bounds,
        n_triangles: scene.triangles.len() as u32,
        terms: terms.direct as u32 | (terms.point_lobe as u32) << 1 | (terms.lobe_ray as u32) << 2,
        ..Default::default()
    }
}

/// Reads a buffer back to the host.
pub fn read_back<T: Pod>(ctx: &GpuContext, src: &wgpu::Buffer, bytes: u64) -> Result<Vec<T>> {
    let dev = &ctx.device;
    let staging = empty_buffer(
        dev,
        "readback",
        bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, bytes);
    ctx.queue.submit([enc.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |_| {});
    dev.poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Gpu(format!("waiting for the device: {e}")))?;
    ctx.check()?;
    let data = {
        let view = staging
            .get_mapped_range(..bytes)
            .map_err(|e| Error::Gpu(format!("mapping the read-back buffer: {e:?}")))?;
        bytemuck::cast_slice(&view).to_vec()
    };
    staging.unmap();
    staging.destroy();
    Ok(data)
}

/// Everything one render (or one probe) sets up on the device, once.
pub struct GpuRun<'a> {
    pub ctx: &'a GpuContext,
    pub layouts: Layouts,
    pub scene_buffers: SceneBuffers,
    pub pipelines: Pipelines,
    pub params: GpuParams,
    pub plan: MapPlan,
    /// Maps of earlier passes, reused when a pass needs buffers of the same sizes (so
    /// memory stays flat over passes).
    pub map_cache: Vec<MapBuffers>,
}

impl<'a> GpuRun<'a> {
    /// Re-plans the photon budgets for settings `s` and pass index `pass` (the RNG's pass),
    /// rewriting the lights and parameters on the device; pipelines and geometry stay.
    pub fn configure_pass(&mut self, scene: &Scene, s: &RenderSettings, pass: u32) {
        let table = LightTable::new(scene);
        let plan = MapPlan::new(scene, s);
        let lights = budgeted_lights(scene, &table, &plan);
        self.params = gpu_params(scene, s, pass, self.params.n_bounds);
        if !lights.is_empty() {
            self.ctx.queue.write_buffer(
                &self.scene_buffers.lights,
                0,
                bytemuck::cast_slice(&lights),
            );
        }
        self.ctx.queue.write_buffer(
            &self.scene_buffers.params,
            0,
            bytemuck::bytes_of(&self.params),
        );
        self.plan = plan;
    }

    /// Uploads the scene and creates the pipelines, specialised to the scene's features.
    pub fn new(ctx: &'a GpuContext, scene: &Scene, s: &RenderSettings, pass: u32) -> Result<Self> {
        let bvh = Bvh::build(scene);
        let table = LightTable::new(scene);
        let plan = MapPlan::new(scene, s);
        let lights = budgeted_lights(scene, &table, &plan);
        let bounds: Vec<GpuAabb> = plan
            .caustic
            .as_ref()
            .map(|(_, b)| {
                b.iter()
                    .map(|a| GpuAabb {
                        bmin: a.min.to_array(),
                        bmax: a.max.to_array(),
                        ..Default::default()
                    })
                    .collect()
            })
            .unwrap_or_default();
        let params = gpu_params(scene, s, pass, bounds.len() as u32);
        let layouts = Layouts::new(&ctx.device);
        let scene_buffers = SceneBuffers::new(
            ctx, &layouts, scene, &bvh, &table, &lights, &bounds, &params, s.spp,
        );
        let pipelines = Pipelines::new(
            ctx,
            &layouts,
            &feature_constants(scene, ctx.adapter.get_info().device_type),
        )?;
        Ok(GpuRun {
            ctx,
            layouts,
            scene_buffers,
            pipelines,
            params,
            plan,
            map_cache: Vec::new(),
        })
    }

    /// A zeroed read-write buffer for the image (or probe results).
    pub fn accum_buffer(&self, bytes: u64) -> wgpu::Buffer {
        empty_buffer(
            &self.ctx.device,
            "image accumulator",
            bytes,
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
        )
    }

    /// An absent map (`paths == 0`), bound where a mode or scene has none.
    pub fn empty_map(&self, caustic: bool) -> MapBuffers {
        let p = GpuMapParams {
            table_size: 256,
            cell_size: 1.0,
            capacity: 1,
            is_caustic: caustic as u32,
            ..Default::default()
        };
        MapBuffers::new(
            self.ctx,
            &self.layouts,
            if caustic {
                "caustic (absent)"
            } else {
                "global (absent)"
            },
            p,
        )
    }

    /// Uploads `photons` as a map and builds its grid (no tracing).
    pub fn upload_map(
        &self,
        photons: &[Photon],
        cell_size: f32,
        table_size: u32,
        radius2: f32,
    ) -> Result<MapBuffers> {
        let n = photons.len() as u32;
        let map = MapBuffers::new(
            self.ctx,
            &self.layouts,
            "uploaded",
            super::probe::probe_map_params(n, cell_size, table_size, radius2),
        );
        if n > 0 {
            self.ctx
                .queue
                .write_buffer(&map.photons, 0, bytemuck::cast_slice(photons));
        }
        self.ctx
            .queue
            .write_buffer(&map.counters, 0, bytemuck::bytes_of(&[n, 0, 0, 0]));
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("grid build"),
            });
        map.record_build(
            &mut enc,
            &self.pipelines,
            &self.scene_buffers.bind_group,
            false,
            true,
        );
        self.ctx.queue.submit([enc.finish()]);
        self.ctx.check()?;
        Ok(map)
    }

    /// Runs the gather module's entry point `entry` over `n` invocations (64-wide) and reads
    /// `accum` back.
    pub fn dispatch_probe(
        &self,
        entry: &str,
        accum: &wgpu::Buffer,
        n: u32,
        bg: Option<&wgpu::BindGroup>,
    ) -> Result<Vec<[f32; 4]>> {
        let dev = &self.ctx.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("probe"),
            source: wgpu::ShaderSource::Wgsl(Kernel::Gather.source().into()),
        });
        let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("probe pipeline layout"),
            bind_group_layouts: &[Some(&self.layouts.scene), Some(&self.layouts.gather)],
            immediate_size: 0,
        });
        let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("probe pipeline: {e}")));
        }
        let owned;
        let bg = match bg {
            Some(b) => b,
            None => {
                let (g, c) = (self.empty_map(false), self.empty_map(true));
                owned = bind_group_for_gather(self.ctx, &self.layouts, &g, &c, accum);
                &owned
            }
        };
        let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("probe"),
        });
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("probe"),
                timestamp_writes: None,
            });
            cp.set_pipeline(&pipeline);
            cp.set_bind_group(0, &self.scene_buffers.bind_group, &[0]);
            cp.set_bind_group(1, bg, &[]);
            let (x, y) = grid_2d(n.div_ceil(64));
            cp.dispatch_workgroups(x, y, 1);
        }
        self.ctx.queue.submit([enc.finish()]);
        read_back(self.ctx, accum, accum.size())
    }
}

/// The gather kernel's group 1 over two maps and the accumulator.
pub fn bind_group_for_gather(
    ctx: &GpuContext,
    layouts: &Layouts,
    global: &MapBuffers,
    caustic: &MapBuffers,
    accum: &wgpu::Buffer,
) -> wgpu::BindGroup {
    bind_group(
        &ctx.device,
        "gather bind group",
        &layouts.gather,
        &[
            &global.sorted,
            &global.cell_start,
            &global.params_buf,
            &caustic.sorted,
            &caustic.cell_start,
            &caustic.params_buf,
            accum,
        ],
    )
}

/// Renders `scene` with one photon pass on the GPU.
pub fn render(
    scene: &Scene,
    s: &RenderSettings,
    pass: u32,
    progress: &Progress,
) -> Result<(Image, RenderReport)> {
    let mut image = None;
    let report = render_passes(scene, &[(pass, s.clone())], progress, |img| {
        image = Some(img.clone());
        crate::progressive::Flow::Continue
    })?;
    Ok((
        image.unwrap_or_else(|| Image::new(s.width, s.height)),
        report,
    ))
}

/// The RNG pass of batch `b` of pass `pass`: batch 0 is the pass itself (as on the CPU).
pub fn batch_pass(pass: u32, b: u32) -> u32 {
    pass ^ (b << 24)
}

/// Renders each `(pass index, settings)` in turn on one device with pipelines created once,
/// handing every pass's image to `on_pass` (which may stop the sequence).
pub fn render_passes(
    scene: &Scene,
    passes: &[(u32, RenderSettings)],
    progress: &Progress,
    mut on_pass: impl FnMut(&Image) -> crate::progressive::Flow,
) -> Result<RenderReport> {
    let Some((first_pass, s)) = passes.first() else {
        return Ok(RenderReport::default());
    };
    if s.k > MAX_HEAP {
        return Err(Error::Setting {
            field: "k",
            message: format!("{} exceeds the GPU backend's limit of {MAX_HEAP}", s.k),
        });
    }
    let mut report = RenderReport::default();
    let t = Instant::now();
    let ctx = GpuContext::new()?;
    let accum_bytes = s.width as u64 * s.height as u64 * 16;
    if accum_bytes > ctx.max_binding {
        return Err(Error::Gpu(format!(
            "a {}x{} image needs {accum_bytes} bytes in one binding; the limit is {} (use --backend cpu)",
            s.width, s.height, ctx.max_binding
        )));
    }
    report.backend = ctx.describe();
    report.phase("open device", t);
    let t = Instant::now();
    let mut run = GpuRun::new(&ctx, scene, s, *first_pass)?;
    report.phase("upload + pipelines", t);
    let accum = run.accum_buffer(accum_bytes);
    for (pass, sp) in passes {
        let image = run.render_pass(scene, sp, *pass, &accum, progress, &mut report)?;
        if on_pass(&image) == crate::progressive::Flow::Stop {
            break;
        }
    }
    report.gpu_stats = read_back(&ctx, &run.scene_buffers.stats, (STATS_LEN * 4) as u64)?;
    Ok(report)
}

impl GpuRun<'_> {
    /// One pass: photon maps (in batches when one storage binding cannot hold them), then
    /// every camera sample gathered into `accum`; returns the pass's image.
    ///
    /// Batch b traces paths of its own (RNG pass `batch_pass(pass, b)`), builds its grid and
    /// gathers every camera sample; the image is the mean of the batches. The batch count
    /// grows until no map overflows (decided by the first batch, so it is deterministic).
    pub fn render_pass(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        pass: u32,
        accum: &wgpu::Buffer,
        progress: &Progress,
        report: &mut RenderReport,
    ) -> Result<Image> {
        let ctx = self.ctx;
        let accum_bytes = accum.size();
        let phases_before = report.phases.len();
        let mut batches = 1u32;
        'attempt: loop {
            ctx.queue
                .write_buffer(accum, 0, &vec![0u8; accum_bytes as usize]);
            for b in 0..batches {
                let sb = batch_settings(s, b, batches);
                self.configure_pass(scene, &sb, batch_pass(pass, b));
                let (global, caustic) = self.trace_maps(scene, &sb, report)?;
                let overflow = [&global, &caustic]
                    .iter()
                    .map(|m| report_count(report, m).div_ceil(m.params.capacity.max(1) as usize))
                    .max()
                    .unwrap_or(1);
                if overflow > 1 && b == 0 && batches < MAX_BATCHES {
                    batches = (batches * overflow as u32 + batches / 4 + 1).min(MAX_BATCHES);
                    report.phases.truncate(phases_before);
                    ctx.queue
                        .write_buffer(&self.scene_buffers.stats, 0, &[0u8; STATS_LEN * 4]);
                    continue 'attempt;
                }
                let t = Instant::now();
                let gather_bg = bind_group_for_gather(ctx, &self.layouts, &global, &caustic, accum);
                let bar = progress.bar(s.spp as u64, "gather");
                let (wx, wy) = (s.width.div_ceil(8), s.height.div_ceil(8));
                // Every sample's parameters, then all the sample layers in one submission.
                let mut slots = vec![0u8; (PARAMS_STRIDE * s.spp as u64) as usize];
                for sample in 0..s.spp {
                    let p = GpuParams {
                        sample,
                        ..self.params
                    };
                    let at = (PARAMS_STRIDE * sample as u64) as usize;
                    slots[at..at + std::mem::size_of::<GpuParams>()]
                        .copy_from_slice(bytemuck::bytes_of(&p));
                }
                ctx.queue
                    .write_buffer(&self.scene_buffers.params, 0, &slots);
                let mut enc = ctx
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("gather"),
                    });
                {
                    let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("gather"),
                        timestamp_writes: None,
                    });
                    cp.set_pipeline(&self.pipelines.gather);
                    cp.set_bind_group(1, &gather_bg, &[]);
                    for sample in 0..s.spp {
                        cp.set_bind_group(
                            0,
                            &self.scene_buffers.bind_group,
                            &[(PARAMS_STRIDE * sample as u64) as u32],
                        );
                        cp.dispatch_workgroups(wx, wy, 1);
                    }
                }
                ctx.queue.submit([enc.finish()]);
                ctx.device
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| Error::Gpu(format!("waiting for the device: {e}")))?;
                bar.inc(s.spp as u64);
                bar.finish_and_clear();
                report.phase("gather", t);
                drop(gather_bg);
                self.map_cache.push(global);
                self.map_cache.push(caustic);
            }
            break;
        }
        report.batches = report.batches.max(batches);
        let px: Vec<[f32; 4]> = read_back(ctx, accum, accum_bytes)?;
        let mut image = Image::new(s.width, s.height);
        let scale = 1.0 / batches as f32;
        for (dst, src) in image.pixels.iter_mut().zip(&px) {
            *dst = [src[0] * scale, src[1] * scale, src[2] * scale];
        }
        Ok(image)
    }
}

impl GpuRun<'_> {
    /// Traces the photon maps the plan asks for and builds their grids on the device.
    /// A map with parameters `p`: a cached one of the same sizes (its parameters rewritten)
    /// or a new one.
    fn take_map(&mut self, p: GpuMapParams, label: &str) -> MapBuffers {
        let same = |m: &MapBuffers| {
            m.params.capacity == p.capacity
                && m.params.table_size == p.table_size
                && m.params.is_caustic == p.is_caustic
        };
        match self.map_cache.iter().position(same) {
            Some(i) => {
                let mut m = self.map_cache.swap_remove(i);
                self.ctx
                    .queue
                    .write_buffer(&m.params_buf, 0, bytemuck::bytes_of(&p));
                m.params = p;
                m
            }
            None => MapBuffers::new(self.ctx, &self.layouts, label, p),
        }
    }

    pub fn trace_maps(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        report: &mut RenderReport,
    ) -> Result<(MapBuffers, MapBuffers)> {
        let mut t = Instant::now();
        let ctx = self.ctx;
        let plan = self.plan.clone();
        let photon_size = std::mem::size_of::<Photon>() as u64;
        let max_photons = (ctx.max_binding / photon_size) as u32;
        let area = scene.storing_area();
        // A map's grid parameters; fixed-radius passes (k = 0) use cells of the radius.
        let params = |caustic: bool,
                      paths: u32,
                      capacity: u32,
                      expected: u32,
                      radius: f32,
                      concentration: f32,
                      drop_flags: u32| GpuMapParams {
            stream: if caustic {
                Stream::Caustic
            } else {
                Stream::Photon
            } as u32,
            paths,
            capacity,
            table_size: table_size_for(expected, ctx.max_binding),
            cell_size: cell_size_for(radius, s.k, expected, area, concentration),
            is_caustic: caustic as u32,
            drop_flags,
            radius2: radius * radius,
        };
        let mut global = match &plan.global {
            Some(b) => {
                let paths = b.total();
                let capacity =
                    (paths as u64 * s.max_photon_bounces as u64).min(max_photons as u64) as u32;
                let filter = plan.global_filter();
                let drop = if filter.drop_direct { DROP_DIRECT } else { 0 }
                    | if filter.drop_caustic { DROP_CAUSTIC } else { 0 };
                let p = params(
                    false,
                    paths,
                    capacity,
                    paths.saturating_mul(3),
                    s.radius,
                    1.0,
                    drop,
                );
                self.take_map(p, "global")
            }
            None => self.take_map(EMPTY_MAP, "global (absent)"),
        };
        let mut caustic = match &plan.caustic {
            Some((b, _)) => {
                let paths = b.total();
                let p = params(
                    true,
                    paths,
                    paths.min(max_photons),
                    s.caustic_photons,
                    s.caustic_radius,
                    0.05,
                    0,
                );
                self.take_map(p, "caustic")
            }
            None => self.take_map(
                GpuMapParams {
                    is_caustic: 1,
                    ..EMPTY_MAP
                },
                "caustic (absent)",
            ),
        };
        // Two submissions, each waited for, so the phases can be timed apart.
        for (trace, grid, name) in [(true, false, "trace photons"), (false, true, "build grids")] {
            let mut enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(name) });
            for m in [&global, &caustic] {
                if m.params.paths > 0 {
                    m.record_build(
                        &mut enc,
                        &self.pipelines,
                        &self.scene_buffers.bind_group,
                        trace,
                        grid,
                    );
                }
            }
            ctx.queue.submit([enc.finish()]);
            ctx.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Gpu(format!("waiting for the device: {e}")))?;
            ctx.check()?;
            report.phase(name, t);
            t = Instant::now();
            if trace {
                let gc: Vec<u32> = read_back(ctx, &global.counters, 16)?;
                let cc: Vec<u32> = read_back(ctx, &caustic.counters, 16)?;
                report.global_stored = gc[0] as usize;
                report.caustic_stored = cc[0] as usize;
                // Size the grid's cells from the photons actually stored (an open scene stores
                // far fewer per path than a closed one; too small cells would make sparse
                // searches run out of cells and be cut).
                for (m, stored, concentration) in
                    [(&mut global, gc[0], 1.0f32), (&mut caustic, cc[0], 0.05)]
                {
                    if m.params.paths == 0 {
                        continue;
                    }
                    let cell = cell_size_for(
                        m.params.radius2.sqrt(),
                        s.k,
                        stored.min(m.params.capacity),
                        area,
                        concentration,
                    );
                    if cell != m.params.cell_size {
                        m.params.cell_size = cell;
                        ctx.queue
                            .write_buffer(&m.params_buf, 0, bytemuck::bytes_of(&m.params));
                    }
                }
                t = Instant::now();
            }
        }
        Ok((global, caustic))
    }
}
