//! The GPU backend's renderer: opens the device, checks its limits, uploads the scene and
//! creates the pipelines once per render, then renders pass after pass
//! (`report::PassRenderer`).

use crate::error::{Error, Result};
use crate::integrators::gpu::buffers::read_back;
use crate::integrators::gpu::codes::{MAX_HEAP, STATS_LEN};
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::faults::{injected, Fault};
use crate::integrators::gpu::run::GpuRun;
use crate::integrators::gpu::shape::{AdapterFacts, KernelShape};
use crate::render::film::Image;
use crate::render::report::PassRenderer;
use crate::render::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::time::Instant;

/// A render on the GPU: the device, the scene's buffers, the pipelines and the image
/// accumulator, built once; then one `pass` per photon pass.
pub struct GpuRenderer<'s> {
    scene: &'s Scene,
    run: GpuRun,
    accum: wgpu::Buffer,
    /// Phases and counts of the passes so far, as recorded.
    report: RenderReport,
}

/// Fails when `k` exceeds the gather heap.
fn check_k(s: &RenderSettings) -> Result<()> {
    if s.k > MAX_HEAP {
        return Err(Error::Setting {
            field: "k",
            message: format!("{} exceeds the GPU backend's limit of {MAX_HEAP}", s.k),
        });
    }
    Ok(())
}

/// What in `scene` the GPU backend cannot render yet, as the refusal's message; `None` when
/// it renders all of it: every scene the CPU renders today. The one place a kind the device
/// lacks would be refused, rather than rendered wrong.
pub fn unsupported(_scene: &Scene) -> Option<String> {
    None
}

impl<'s> GpuRenderer<'s> {
    /// Opens the device, checks that the image fits one storage binding, uploads `scene` and
    /// creates every pipeline, for a render with `settings`. A scene the GPU cannot render
    /// ([`unsupported`]) is an [`Error::Unsupported`].
    pub fn new(scene: &'s Scene, settings: &RenderSettings) -> Result<Self> {
        let t = Instant::now();
        let ctx = GpuContext::shared()?;
        Self::build(ctx, t, scene, settings)
    }

    /// [`GpuRenderer::new`] on the device of `ctx` rather than the process's shared one: a
    /// context per thread renders side by side (lavapipe compiles a device's kernels on that
    /// device's own queue thread, one at a time).
    pub fn on_context(
        ctx: GpuContext,
        scene: &'s Scene,
        settings: &RenderSettings,
    ) -> Result<Self> {
        Self::build(ctx, Instant::now(), scene, settings)
    }

    /// The renderer on `ctx`, whose opening began at `t` (the report's first phase).
    fn build(
        mut ctx: GpuContext,
        t: Instant,
        scene: &'s Scene,
        settings: &RenderSettings,
    ) -> Result<Self> {
        if let Some(why) = unsupported(scene) {
            return Err(Error::Unsupported(why));
        }
        let s = settings;
        let mut report = RenderReport::default();
        // The shared device outlives this render: GPU_PHOTON_KERNEL_SHAPE is read per render.
        ctx.shape = KernelShape::from_env(&AdapterFacts::of(&ctx.adapter)).map_err(Error::Gpu)?;
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
        let run = GpuRun::new(ctx, scene, s, 0)?;
        report.phase(
            match run.reused_pipelines {
                true => "upload (pipelines reused)",
                false => "upload + pipelines",
            },
            t,
        );
        let accum = accumulator(&run, accum_bytes)?;
        Ok(GpuRenderer {
            scene,
            run,
            accum,
            report,
        })
    }
}

/// The image accumulator of `bytes`, its allocation failure (out of memory, over a limit)
/// an error. An injected `oom` (`gpu::faults`) asks for one byte over the largest buffer.
fn accumulator(run: &GpuRun, bytes: u64) -> Result<wgpu::Buffer> {
    let dev = &run.ctx.device;
    let size = match injected() {
        Some(Fault::OutOfMemory) => dev.limits().max_buffer_size + 1,
        _ => bytes,
    };
    let oom = dev.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let invalid = dev.push_error_scope(wgpu::ErrorFilter::Validation);
    let accum = run.accum_buffer(size);
    let invalid = pollster::block_on(invalid.pop());
    match pollster::block_on(oom.pop()).or(invalid) {
        Some(e) => Err(Error::Gpu(format!(
            "could not allocate the image accumulator ({size} bytes): {}",
            crate::integrators::gpu::faults::describe(&e)
        ))),
        None => Ok(accum),
    }
}

impl PassRenderer for GpuRenderer<'_> {
    /// Renders pass `pass` with `settings` (k at most MAX_HEAP, the image size of `new`).
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image> {
        check_k(settings)?;
        // A device lost since the last pass: an error here, before wgpu is asked for buffers.
        self.run.ctx.check()?;
        self.run.render_pass(
            self.scene,
            settings,
            pass,
            &self.accum,
            progress,
            &mut self.report,
        )
    }

    /// The passes' phases (same names summed), counts and the bound counters read back.
    fn report(&mut self) -> Result<RenderReport> {
        let mut out = RenderReport {
            backend: self.report.backend.clone(),
            ..Default::default()
        };
        out.absorb(&self.report);
        let stats = &self.run.scene_buffers.stats;
        out.gpu_stats = read_back(&self.run.ctx, stats, (STATS_LEN * 4) as u64)?;
        Ok(out)
    }
}
