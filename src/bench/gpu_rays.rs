//! The GPU ray benchmark (`gpu-photon bench SCENE --rays --backend gpu`): the ray sets of
//! [`super::rays`] traced on the device through the world's hierarchy, by the binary walk
//! (`walk_bvh` in src/bvh/intersect.wgsl) and by the four-wide one (`walk_wide`,
//! src/bvh/gpu_wide.rs): nearest hits for camera, gather and photon rays, the
//! first hit for shadow rays. One dispatch traces a whole set; it is timed from submission to
//! completion (wall clock: the device's throughput, all its cores), in rounds that alternate
//! the walks, and medians are reported. Both walks read the same leaves: the binary walk the
//! `nodes` binding a render uploads, the wide one its own buffer bound in its place.

use super::rays::{RayKind, RayRate, RaySet};
use crate::bvh::gpu_wide::WideTraversal;
use crate::error::{Error, Result};
use crate::integrators::gpu::buffers::{grid_2d, read_back, storage_buffer, wait};
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::pipelines::{feature_constants, pipeline_layout, shader_module_of};
use crate::integrators::gpu::run::GpuRun;
use crate::integrators::gpu::shaders::bench_source;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::time::Instant;

/// A walk of the device's hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// The renderer's: binary nodes, stackless (src/bvh/gpu_layout.rs).
    Binary,
    /// Four-wide nodes and a stack (src/bvh/gpu_wide.rs).
    Wide,
}

impl Walk {
    /// Both, the renderer's first.
    pub const ALL: [Walk; 2] = [Walk::Binary, Walk::Wide];

    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Walk::Binary => "gpu binary",
            Walk::Wide => "gpu wide",
        }
    }
}

/// A ray's nearest (or first) hit: the primitive id as in `Bvh::prim_ids`, and t.
pub type Answer = Option<(u32, f32)>;

/// One scene on the device with both layouts of its world hierarchy and the benchmark's
/// pipelines (per walk, nearest and first hit).
pub struct GpuRays {
    run: GpuRun,
    /// Group 0 per walk, its layout bound as `nodes`.
    groups: [wgpu::BindGroup; 2],
    /// Per walk, the nearest-hit pipeline, then the first-hit one.
    pipelines: [[wgpu::ComputePipeline; 2]; 2],
    /// Bytes of each layout's nodes (the frame included).
    pub node_bytes: [usize; 2],
}

impl GpuRays {
    /// Uploads `scene` as a render does and compiles the benchmark's pipelines. Fails for a
    /// scene with instances (the benchmark walks the world's hierarchy only) or one whose
    /// hierarchy the wide layout cannot hold.
    pub fn new(ctx: &GpuContext, scene: &Scene) -> Result<Self> {
        if !scene.instancing.is_empty() {
            return Err(Error::Gpu(
                "the GPU ray benchmark walks the world's hierarchy only: this scene has instances"
                    .into(),
            ));
        }
        let bvh = crate::bvh::gpu_sdf::world_bvh(scene);
        let wide = WideTraversal::of(&bvh)
            .ok_or_else(|| {
                Error::Gpu(
                    "the wide layout cannot hold this scene's hierarchy (no primitives, or deeper than its stack)"
                        .into(),
                )
            })?
            .bytes();
        let settings = RenderSettings {
            width: 1,
            height: 1,
            ..Default::default()
        };
        let run = GpuRun::new(ctx.clone(), scene, &settings, 0)?;
        let dev = &ctx.device;
        let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = shader_module_of(dev, "ray benchmark", bench_source());
        let layout = pipeline_layout(
            dev,
            "ray benchmark pipeline layout",
            &run.layouts,
            &run.layouts.gather,
        );
        let device_type = ctx.adapter.get_info().device_type;
        let base = feature_constants(scene, &ctx.shape, device_type, run.knn);
        let pipeline = |walk: Walk, any_hit: bool| {
            let mut constants = base.clone();
            constants.push(("WIDE_WALK", (walk == Walk::Wide) as u32 as f64));
            constants.push(("ANY_HIT", any_hit as u32 as f64));
            dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(match (walk, any_hit) {
                    (Walk::Binary, false) => "bench_rays binary nearest",
                    (Walk::Binary, true) => "bench_rays binary first",
                    (Walk::Wide, false) => "bench_rays wide nearest",
                    (Walk::Wide, true) => "bench_rays wide first",
                }),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("bench_rays"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            })
        };
        let pipelines = Walk::ALL.map(|w| [pipeline(w, false), pipeline(w, true)]);
        let wide_nodes = storage_buffer(
            dev,
            "ray benchmark wide nodes",
            &wide,
            wgpu::BufferUsages::empty(),
        );
        // The binary layout is the one the render uploaded (the frame and the nodes).
        let binary_bytes = (run.scene_buffers.buffer("nodes")).map_or(0, |b| b.size() as usize);
        let groups = [
            run.scene_buffers.bind_group.clone(),
            (run.scene_buffers).bind_group_with_nodes(dev, &run.layouts, &wide_nodes),
        ];
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!("ray benchmark pipeline: {e}")));
        }
        Ok(GpuRays {
            run,
            node_bytes: [binary_bytes, wide.len()],
            groups,
            pipelines,
        })
    }

    /// Traces `set` by `walk`: each ray's nearest hit (or, for shadow rays, the first found)
    /// as (primitive id as in `Bvh::prim_ids`, t), and the dispatch's wall-clock seconds.
    pub fn trace(&mut self, walk: Walk, set: &RaySet) -> Result<(Vec<Answer>, f64)> {
        let ctx = self.run.ctx.clone();
        let n = set.rays.len();
        let mut init = vec![[0f32; 4]; 3 * n.max(1)];
        for (i, (r, &t)) in set.rays.iter().zip(&set.t_max).enumerate() {
            init[i] = [r.origin.x, r.origin.y, r.origin.z, t];
            init[n + i] = [r.dir.x, r.dir.y, r.dir.z, 0.0];
        }
        let accum = self.run.accum_buffer(init.len() as u64 * 16);
        ctx.queue
            .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
        self.run.params.width = n as u32;
        ctx.queue.write_buffer(
            &self.run.scene_buffers.params,
            0,
            bytemuck::bytes_of(&self.run.params),
        );
        let (g, c) = (self.run.empty_map(false), self.run.empty_map(true));
        let bg = self.run.gather_bind_group([&g, &c], &accum);
        // The uploads finish before the clock starts.
        wait(&ctx)?;
        let any_hit = set.kind == RayKind::Shadow;
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("ray benchmark"),
            });
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ray benchmark"),
                timestamp_writes: None,
            });
            cp.set_pipeline(&self.pipelines[walk as usize][any_hit as usize]);
            cp.set_bind_group(0, &self.groups[walk as usize], &[0]);
            cp.set_bind_group(1, &bg, &[]);
            let (x, y) = grid_2d((n as u32).div_ceil(ctx.shape.wg_size));
            cp.dispatch_workgroups(x, y, 1);
        }
        let start = Instant::now();
        ctx.queue.submit([enc.finish()]);
        wait(&ctx)?;
        let seconds = start.elapsed().as_secs_f64();
        let out: Vec<[f32; 4]> = read_back(&ctx, &accum, accum.size())?;
        let hits = out[2 * n..3 * n]
            .iter()
            .map(|h| (h[1] == 1.0).then_some((h[2].to_bits(), h[0])))
            .collect();
        Ok((hits, seconds))
    }
}

/// Traces every set by both walks, `rounds` times (walks alternating within each round),
/// after one untimed round; `agree` counts the rays whose answer (the nearest primitive, or
/// occlusion) is the binary walk's.
pub fn measure(gpu: &mut GpuRays, sets: &[RaySet], rounds: usize) -> Result<Vec<RayRate>> {
    let mut out = Vec::new();
    for set in sets.iter().filter(|s| !s.rays.is_empty()) {
        let mut answers = Vec::new();
        for walk in Walk::ALL {
            let (hits, _) = gpu.trace(walk, set)?;
            let shadow = set.kind == RayKind::Shadow;
            answers.push(
                hits.iter()
                    .map(|h| h.map(|(id, _)| if shadow { 0 } else { id }))
                    .collect::<Vec<_>>(),
            );
        }
        let mut times = [Vec::new(), Vec::new()];
        for _ in 0..rounds.max(1) {
            for walk in Walk::ALL {
                times[walk as usize].push(gpu.trace(walk, set)?.1);
            }
        }
        for walk in Walk::ALL {
            let ts = &mut times[walk as usize];
            ts.sort_by(f64::total_cmp);
            let median = ts[ts.len() / 2];
            let mine = &answers[walk as usize];
            out.push(RayRate {
                tracer: walk.name().to_string(),
                kind: set.kind,
                rays: set.rays.len(),
                rays_per_s: set.rays.len() as f64 / median.max(1e-12),
                hits: mine.iter().filter(|a| a.is_some()).count(),
                agree: mine.iter().zip(&answers[0]).filter(|(a, b)| a == b).count(),
            });
        }
    }
    Ok(out)
}
