//! Oracle probes of participating media (issue 24): the free-flight and Henyey-Greenstein
//! samplers on chosen random numbers (`probe_medium` in shaders/probes.wgsl) and one pass's
//! photon tracing read back (surface maps and volume photons), for tests/media_gpu.rs to
//! compare with their Rust twins.

use super::buffers::read_back;
use super::context::GpuContext;
use super::probe::dispatch_probe;
use super::recorder::Recorder;
use super::run::GpuRun;
use crate::error::Result;
use crate::photon::Photon;
use crate::report::RenderReport;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// One case of [`medium_samplers`]: the free flight's `(u_channel, u, t_max)` and the
/// phase function's travel direction and `(u1, u2)`.
#[derive(Clone, Copy, Debug)]
pub struct MediumCase {
    /// `Medium::sample_flight`'s channel choice.
    pub u_channel: f32,
    /// Its distance draw.
    pub u: f32,
    /// The surface's distance (a miss: any value beyond every flight, e.g. 3e38).
    pub t_max: f32,
    /// The direction travelled before scattering (unit).
    pub dir: [f32; 3],
    /// `HenyeyGreenstein::sample`'s two numbers.
    pub u_phase: [f32; 2],
}

/// What the device's samplers gave for one [`MediumCase`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumSample {
    /// The flight's distance.
    pub t: f32,
    /// Whether it ended in the medium.
    pub in_medium: bool,
    /// Its weight.
    pub weight: [f32; 3],
    /// The scattered direction.
    pub scattered: [f32; 3],
}

/// The device's `sample_flight` and `hg_sample` (shaders/common/medium.wgsl) with `scene`'s
/// first medium, per case.
pub fn medium_samplers(
    ctx: &GpuContext,
    scene: &Scene,
    cases: &[MediumCase],
) -> Result<Vec<MediumSample>> {
    let n = cases.len().max(1);
    let settings = RenderSettings {
        width: n as u32,
        height: 1,
        ..Default::default()
    };
    let run = GpuRun::new(ctx.clone(), scene, &settings, 0)?;
    let mut init = vec![[0f32; 4]; 4 * n];
    for (i, c) in cases.iter().enumerate() {
        init[i] = [c.u_channel, c.u, c.t_max, c.u_phase[0]];
        init[n + i] = [c.dir[0], c.dir[1], c.dir[2], c.u_phase[1]];
    }
    let accum = run.accum_buffer(init.len() as u64 * 16);
    ctx.queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
    let out = dispatch_probe(&run, "probe_medium", &accum, n as u32, None)?;
    Ok((0..cases.len())
        .map(|i| {
            let (f, h) = (out[2 * n + i], out[3 * n + i]);
            MediumSample {
                t: f[3],
                in_medium: h[3] == 1.0,
                weight: [f[0], f[1], f[2]],
                scattered: [h[0], h[1], h[2]],
            }
        })
        .collect())
}

/// The photons one pass traced on the device (`GpuRun::record_maps`, pass index `pass`):
/// each map's surface photons in [`crate::plan::MapKind`] slot order (as traced, before the
/// grid's sort) and the volume photons, each list in the device's order.
#[derive(Clone, Debug, Default)]
pub struct TracedPhotons {
    /// Surface photons per map slot.
    pub surface: [Vec<Photon>; 2],
    /// Volume photons of every map's paths.
    pub volume: Vec<Photon>,
}

/// Traces one pass's photon maps of `scene` with `s` on the device and reads them back.
pub fn trace_photons(
    ctx: &GpuContext,
    scene: &Scene,
    s: &RenderSettings,
    pass: u32,
) -> Result<TracedPhotons> {
    let mut run = GpuRun::new(ctx.clone(), scene, s, pass)?;
    run.configure_pass(scene, s, pass);
    let mut rec = Recorder::new(ctx.clone(), false);
    let mut report = RenderReport::default();
    let maps = run.record_maps(scene, s, &mut rec, &mut report)?;
    rec.submit();
    ctx.check()?;
    let photons =
        |buf: &wgpu::Buffer, count: &wgpu::Buffer, capacity: u32| -> Result<Vec<Photon>> {
            let n: Vec<u32> = read_back(ctx, count, 4)?;
            let n = n[0].min(capacity) as usize;
            let all: Vec<Photon> = read_back(ctx, buf, buf.size())?;
            Ok(all[..n].to_vec())
        };
    let mut out = TracedPhotons::default();
    for (slot, m) in maps.iter().enumerate() {
        if m.params.paths > 0 {
            out.surface[slot] = photons(&m.photons, &m.counters, m.params.capacity)?;
        }
    }
    out.volume = photons(&run.volume.photons, &run.volume.count, run.volume.capacity)?;
    Ok(out)
}
