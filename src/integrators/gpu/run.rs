//! What one render (or one probe) sets up on the device once: layouts, the scene's buffers,
//! the pipelines, and the current pass's parameters and plan; plus the buffers a pass binds
//! (the image accumulator, absent maps, uploaded maps) and the gather's group 1.

use crate::error::Result;
use crate::integrators::gpu::bindings::{bind_group, Layouts, GATHER_GROUP, MAP_SLOTS};
use crate::integrators::gpu::branches::{band_rows, stack_buffer, BRANCH_LISTS};
use crate::integrators::gpu::buffers::{cache_buffers, empty_buffer};
use crate::integrators::gpu::codes::SCAN_BLOCK;
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::host::{budgeted_lights, gpu_params};
use crate::integrators::gpu::maps::{probe_map_params, MapBuffers};
use crate::integrators::gpu::pipeline_cache::{self, PipelineKey};
use crate::integrators::gpu::pipelines::{feature_constants, glass_split, with_floor, Pipelines};
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::scene_buffers::SceneBuffers;
use crate::integrators::gpu::types::{GpuAabb, GpuMapParams, GpuParams};
use crate::integrators::gpu::volume::{volume_capacity, VolumeBuffers};
use crate::integrators::photon::Photon;
use crate::integrators::plan::MapPlan;
use crate::lights::table::LightTable;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// Everything one render (or one probe) sets up on the device, once.
pub struct GpuRun {
    /// The device (a handle: clones share it).
    pub ctx: GpuContext,
    /// The bind-group layouts.
    pub layouts: Layouts,
    /// The scene's buffers and group 0.
    pub scene_buffers: SceneBuffers,
    /// Every render pipeline, created once.
    pub pipelines: Pipelines,
    /// The pipelines came from an earlier render in this process (`gpu::pipeline_cache`).
    pub reused_pipelines: bool,
    /// The current pass's parameters (slot 0; the gather writes one slot per sample).
    pub params: GpuParams,
    /// The current pass's plan.
    pub plan: MapPlan,
    /// The scene's light sampling tables, built once (each pass re-plans from them).
    pub table: LightTable,
    /// Maps of earlier passes, reused when a pass needs buffers of the same sizes (so
    /// memory stays flat over passes).
    pub map_cache: Vec<MapBuffers>,
    /// The radiance cache (`cache`, one vec4 per global photon slot) and the list of its
    /// points (`cache_list`), grown by `GpuRun::ensure_cache` (stand-ins outside mode gather).
    pub cache: [wgpu::Buffer; 3],
    /// The pipelines run K-nearest estimates (override `KNN`); false for a progressive
    /// render, whose passes must then all have `k == 0`.
    pub knn: bool,
    /// The volume photons every map's paths store (a placeholder without a volume map);
    /// grown by `GpuRun::plan_maps` when a pass needs more.
    pub volume: VolumeBuffers,
    /// The camera paths' glass branch stacks (`gpu::branches`): one per pixel of a band of
    /// `band_rows` rows of `width` pixels, a stand-in without `GLASS_SPLIT`.
    pub branch_stacks: wgpu::Buffer,
    /// Rows per band of the gather, and the image width the stacks were made for.
    pub band_rows: u32,
    /// The width the stacks were made for.
    pub band_width: u32,
    /// Parameter slots the scene's `params` buffer has (one per sample and band).
    pub param_slots: u32,
    /// The most bytes the branch stacks may take: one storage binding (less in tests of
    /// the bands).
    pub stack_bytes: u64,
}

impl GpuRun {
    /// Uploads the scene and creates the pipelines, specialised to the scene's features;
    /// `s` and `pass` give the first parameters and plan (each pass re-plans).
    pub fn new(ctx: GpuContext, scene: &Scene, s: &RenderSettings, pass: u32) -> Result<Self> {
        let stack_bytes = ctx.max_binding;
        Self::with_stack_bytes(ctx, scene, s, pass, stack_bytes)
    }

    /// [`GpuRun::new`] with the glass branch stacks limited to `stack_bytes` (the gather runs
    /// in bands of rows whose stacks fit).
    pub fn with_stack_bytes(
        ctx: GpuContext,
        scene: &Scene,
        s: &RenderSettings,
        pass: u32,
        stack_bytes: u64,
    ) -> Result<Self> {
        // A progressive render's passes all use fixed radii (`progressive::pass_settings`).
        let knn = s.pass_range.is_none();
        let constants = with_floor(
            feature_constants(scene, &ctx.shape, ctx.adapter.get_info().device_type, knn),
            &ctx.feature_floor,
        );
        let final_gather = crate::integrators::plan::Terms::of(s.mode).final_gather;
        let key = PipelineKey::new(&constants, final_gather, knn);
        let cached = pipeline_cache::get(&ctx, &key);
        let layouts = match &cached {
            Some((layouts, _)) => layouts.clone(),
            None => Layouts::new(&ctx.device),
        };
        let compiled = cached.is_none();
        // The pipelines compile (synchronously, on lavapipe) on a second thread while this one
        // builds the BVH and uploads the scene: neither needs the other.
        let (pipelines, scene_side) = std::thread::scope(|threads| {
            let compile = threads.spawn(|| match cached {
                Some((_, pipelines)) => Ok(pipelines),
                None => Pipelines::new(&ctx, &layouts, &constants, final_gather, knn),
            });
            let slots = Self::bands(&ctx, scene, s, stack_bytes).2;
            let scene_side = Self::upload_scene(&ctx, &layouts, scene, s, pass, slots);
            let pipelines = compile
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (pipelines, scene_side)
        });
        let pipelines = pipelines?;
        if compiled {
            pipeline_cache::put(&ctx, key, layouts.clone(), pipelines.clone());
        }
        let (plan, table, params, scene_buffers) = scene_side?;
        let (split, rows, slots) = Self::bands(&ctx, scene, s, stack_bytes);
        let branch_stacks = stack_buffer(&ctx.device, s.width, rows, split);
        let cache = cache_buffers(&ctx.device, 1);
        let volume = VolumeBuffers::new(
            &ctx,
            &layouts,
            volume_capacity(&plan, s.max_photon_bounces, ctx.max_photons()),
        );
        Ok(GpuRun {
            volume,
            ctx,
            layouts,
            scene_buffers,
            pipelines,
            reused_pipelines: !compiled,
            params,
            plan,
            table,
            map_cache: Vec::new(),
            cache,
            knn,
            branch_stacks,
            band_rows: rows,
            band_width: s.width,
            param_slots: slots,
            stack_bytes,
        })
    }

    /// Makes the glass branch stacks fit a pass of `s` (a pass may differ from the first in
    /// its size); fails when its samples and bands need more parameter slots than the
    /// render made room for.
    pub fn ensure_bands(&mut self, scene: &Scene, s: &RenderSettings) -> Result<()> {
        let (split, rows, slots) = Self::bands(&self.ctx, scene, s, self.stack_bytes);
        if slots > self.param_slots {
            return Err(crate::error::Error::Gpu(format!(
                "a pass of {} samples in {} bands needs {slots} parameter slots; the render made room for {}",
                s.spp,
                slots / s.spp.max(1),
                self.param_slots
            )));
        }
        if split && (s.width, rows) != (self.band_width, self.band_rows) {
            self.branch_stacks = stack_buffer(&self.ctx.device, s.width, rows, split);
        }
        (self.band_width, self.band_rows) = (s.width, rows);
        Ok(())
    }

    /// Whether the scene splits camera paths at glass, the gather's rows per band (the whole
    /// image but where the glass branch stacks would exceed `stack_bytes`) and the
    /// parameter slots a pass of `s` needs (one per sample and band, and with glass one per
    /// sample's dispatch: the gather and its rounds).
    fn bands(
        ctx: &GpuContext,
        scene: &Scene,
        s: &RenderSettings,
        stack_bytes: u64,
    ) -> (bool, u32, u32) {
        let split = glass_split(scene);
        if !split {
            return (false, s.height.max(1), s.spp.max(1));
        }
        let rows = band_rows(s.width, s.height, ctx.shape.gather_tile, stack_bytes);
        let dispatches = s.spp.max(1) * BRANCH_LISTS;
        (true, rows, dispatches * s.height.div_ceil(rows).max(1))
    }

    /// Re-plans the photon budgets for settings `s` and pass index `pass` (the RNG's pass),
    /// rewriting the lights and parameters on the device; pipelines and geometry stay.
    pub fn configure_pass(&mut self, scene: &Scene, s: &RenderSettings, pass: u32) {
        let plan = MapPlan::new(scene, &self.table, s);
        let lights = budgeted_lights(scene, &self.table, &plan);
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

    /// A read-write buffer for the image (or probe results).
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

    /// The pass's plan and parameters, and the scene's buffers (its BVH built for the GPU's
    /// walk).
    fn upload_scene(
        ctx: &GpuContext,
        layouts: &Layouts,
        scene: &Scene,
        s: &RenderSettings,
        pass: u32,
        slots: u32,
    ) -> Result<(MapPlan, LightTable, GpuParams, SceneBuffers)> {
        let bvh = crate::bvh::gpu_sdf::world_bvh(scene);
        let table = LightTable::new(scene);
        let plan = MapPlan::new(scene, &table, s);
        let lights = budgeted_lights(scene, &table, &plan);
        let bounds: Vec<GpuAabb> = plan
            .map(crate::integrators::plan::MapKind::Caustic)
            .map(|spec| {
                spec.aim
                    .iter()
                    .map(|a| GpuAabb {
                        bmin: a.min.to_array(),
                        bmax: a.max.to_array(),
                        ..Default::default()
                    })
                    .collect()
            })
            .unwrap_or_default();
        let params = gpu_params(scene, s, pass, bounds.len() as u32);
        let buffers = SceneBuffers::new(
            ctx, layouts, scene, &bvh, &table, &lights, &bounds, &params, slots,
        )?;
        Ok((plan, table, params, buffers))
    }

    /// An absent map (`paths == 0`), bound where a mode or scene has none.
    pub fn empty_map(&self, caustic: bool) -> MapBuffers {
        let p = GpuMapParams {
            table_size: SCAN_BLOCK,
            cell_size: 1.0,
            capacity: 1,
            is_caustic: caustic as u32,
            ..Default::default()
        };
        let label = if caustic {
            "caustic (absent)"
        } else {
            "global (absent)"
        };
        MapBuffers::new(&self.ctx, &self.layouts, label, p, self.volume.bindings())
    }

    /// Uploads `photons` as a map and builds its grid (no tracing).
    pub fn upload_map(
        &self,
        photons: &[Photon],
        cell_size: f32,
        table_size: u32,
        radius2: f32,
    ) -> Result<MapBuffers> {
        let ctx = &self.ctx;
        let n = photons.len() as u32;
        let params = probe_map_params(n, cell_size, table_size, radius2);
        let map = MapBuffers::new(
            ctx,
            &self.layouts,
            "uploaded",
            params,
            self.volume.bindings(),
        );
        if n > 0 {
            ctx.queue
                .write_buffer(&map.photons, 0, bytemuck::cast_slice(photons));
        }
        ctx.queue
            .write_buffer(&map.counters, 0, bytemuck::bytes_of(&[n, 0, 0, 0]));
        let mut rec = Recorder::new(ctx.clone(), false);
        let scene_bg = &self.scene_buffers.bind_group;
        map.record_grid(&mut rec, &self.pipelines, scene_bg);
        rec.submit();
        ctx.check()?;
        Ok(map)
    }

    /// The gather kernel's group 1 over the maps (by [`crate::integrators::plan::MapKind`] slot), the
    /// accumulator, the radiance cache and the glass branch stacks.
    pub fn gather_bind_group(
        &self,
        maps: [&MapBuffers; 2],
        accum: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let mut entries = Vec::new();
        for (m, [photons, cells, params]) in maps.into_iter().zip(MAP_SLOTS) {
            entries.push((photons, m.sorted.as_entire_binding()));
            entries.push((cells, m.cell_start.as_entire_binding()));
            entries.push((params, m.params_buf.as_entire_binding()));
        }
        entries.extend([
            ("accum", accum.as_entire_binding()),
            ("cache", self.cache[0].as_entire_binding()),
            ("cache_list", self.cache[1].as_entire_binding()),
            ("v_photons", self.volume.photons.as_entire_binding()),
            ("v_refs", self.volume.map.sorted.as_entire_binding()),
            ("v_cells", self.volume.map.cell_start.as_entire_binding()),
            ("v_grid", self.volume.grid.as_entire_binding()),
            ("branch_stacks", self.branch_stacks.as_entire_binding()),
        ]);
        bind_group(
            &self.ctx.device,
            "gather bind group",
            &self.layouts.gather,
            &GATHER_GROUP,
            entries,
        )
    }
}
