//! Oracle probes of participating media (issue 24): the free-flight and Henyey-Greenstein
//! samplers on chosen random numbers with the interface, photon-filter, cache-point and
//! volume-cell rules on chosen inputs (`probe_medium` in tests/probes/probes.wgsl), one pass's
//! photon tracing read back (surface maps and volume photons), the volume grid's build over
//! uploaded photons, its beam estimate and the shadow walk's transmittance, for
//! tests/media_gpu.rs to compare with their Rust twins.

use super::{case_buffer, dispatch_probe, probe_cases};
use gpu_photon::error::Result;
use gpu_photon::integrators::gpu::buffers::read_back;
use gpu_photon::integrators::gpu::context::GpuContext;
use gpu_photon::integrators::gpu::recorder::Recorder;
use gpu_photon::integrators::gpu::run::GpuRun;
use gpu_photon::integrators::gpu::volume::VolumeBuffers;
use gpu_photon::integrators::photon::{BeamPhotons, Photon};
use gpu_photon::render::report::RenderReport;
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;

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
    /// The cosine `HenyeyGreenstein::eval` is asked at.
    pub cos: f32,
    /// `MediumInterface::after`'s interface (interior, exterior), the medium the ray was in
    /// and the surface's normal (the ray leaves along `dir`).
    pub interface: ([u32; 2], u32, [f32; 3]),
    /// A photon's flags and id, and a map's `MapParams.drop_flags` (`keep_photon`,
    /// `is_cache_point`).
    pub photon: (u32, u32, u32),
    /// A point, a grid's corner and its cell edge (`volume_cell`).
    pub cell: ([f32; 3], [f32; 3], f32),
    /// A material of the scene (`medium_after` at a hit of it with the interface's normal,
    /// current medium and `dir`) and a light of the scene (`light_medium` of an emission
    /// along `dir` with that normal).
    pub material_light: (u32, u32),
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
    /// `hg_eval(g, cos)`.
    pub density: f32,
    /// `medium_interface_after` of the case's interface.
    pub after: u32,
    /// `keep_photon(flags, drop)`.
    pub keep: bool,
    /// `is_cache_point(flags, id)`.
    pub cache_point: bool,
    /// `volume_cell(x, lo, cell)`.
    pub cell: [i32; 3],
    /// `medium_after` at a hit of the case's material.
    pub medium_after: u32,
    /// `light_medium` of the case's light.
    pub light_medium: u32,
}

/// The device's `sample_flight`, `hg_sample`, `hg_eval`, `medium_interface_after`,
/// `medium_after` and `light_medium` (src/media/medium.wgsl) with `scene`'s first
/// medium, materials and lights, and `keep_photon`, `is_cache_point` and `volume_cell`
/// (src/integrators/gpu/grid.wgsl), per case.
pub fn medium_samplers(
    ctx: &GpuContext,
    scene: &Scene,
    cases: &[MediumCase],
) -> Result<Vec<MediumSample>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 12 * n];
    for (i, c) in cases.iter().enumerate() {
        init[i] = [c.u_channel, c.u, c.t_max, c.u_phase[0]];
        init[n + i] = [c.dir[0], c.dir[1], c.dir[2], c.u_phase[1]];
        let ([inside, outside], current, nrm) = c.interface;
        let bits = [inside, outside, current].map(f32::from_bits);
        init[4 * n + i] = [c.cos, bits[0], bits[1], bits[2]];
        init[5 * n + i] = [nrm[0], nrm[1], nrm[2], 0.0];
        let (flags, id, drop) = c.photon;
        let (material, light) = c.material_light;
        init[7 * n + i] = [flags, drop, id, light].map(f32::from_bits);
        let (x, lo, cell) = c.cell;
        init[8 * n + i] = [x[0], x[1], x[2], cell];
        init[9 * n + i] = [lo[0], lo[1], lo[2], f32::from_bits(material)];
    }
    let out = probe_cases(ctx, scene, "probe_medium", &init, n)?;
    Ok((0..cases.len())
        .map(|i| {
            let (f, h) = (out[2 * n + i], out[3 * n + i]);
            MediumSample {
                t: f[3],
                in_medium: h[3] == 1.0,
                weight: [f[0], f[1], f[2]],
                scattered: [h[0], h[1], h[2]],
                density: out[6 * n + i][0],
                after: out[6 * n + i][1].to_bits(),
                keep: out[10 * n + i][0] == 1.0,
                cache_point: out[10 * n + i][1] == 1.0,
                medium_after: out[10 * n + i][2].to_bits(),
                light_medium: out[10 * n + i][3].to_bits(),
                cell: [0, 1, 2].map(|k| out[11 * n + i][k].to_bits() as i32),
            }
        })
        .collect())
}

/// The photons one pass traced on the device (`GpuRun::record_maps`, pass index `pass`):
/// each map's surface photons in [`gpu_photon::integrators::plan::MapKind`] slot order (as traced, before the
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

/// The volume grid the device built over uploaded photons ([`volume_grid`]).
#[derive(Clone, Debug)]
pub struct VolumeGridProbe {
    /// The grid's corner (the photons' bounds less r).
    pub lo: [f32; 3],
    /// Its cell edge.
    pub cell: f32,
    /// The far corner (bounds plus r).
    pub hi: [f32; 3],
    /// Hash-table slots.
    pub table_size: u32,
    /// Each slot's first entry; `[table_size]` = all entries.
    pub cell_start: Vec<u32>,
    /// The entries in slot order: (photon index, cell coordinates).
    pub entries: Vec<(u32, [i32; 3])>,
}

/// A run over `scene` with the volume map's grid built over `photons` (spheres of
/// `radius`) on the device, as a render's pass builds it.
fn run_with_volume(
    ctx: &GpuContext,
    scene: &Scene,
    photons: &[Photon],
    radius: f32,
    width: u32,
) -> Result<GpuRun> {
    let settings = RenderSettings {
        width,
        height: 1,
        ..Default::default()
    };
    run_with_volume_settings(ctx, scene, photons, radius, &settings)
}

/// [`run_with_volume`] with the render settings `settings` (its width the cases').
fn run_with_volume_settings(
    ctx: &GpuContext,
    scene: &Scene,
    photons: &[Photon],
    radius: f32,
    settings: &RenderSettings,
) -> Result<GpuRun> {
    let mut run = GpuRun::new(ctx.clone(), scene, settings, 0)?;
    run.volume = VolumeBuffers::new(ctx, &run.layouts, photons.len() as u32);
    let n = photons.len() as u32;
    if n > 0 {
        ctx.queue
            .write_buffer(&run.volume.photons, 0, bytemuck::cast_slice(photons));
    }
    ctx.queue
        .write_buffer(&run.volume.count, 0, bytemuck::cast_slice(&[n, 0, 0, 0]));
    let mut rec = Recorder::new(ctx.clone(), false);
    let scene_bg = &run.scene_buffers.bind_group;
    run.volume
        .record_grid(&run.ctx, &mut rec, &run.pipelines, scene_bg, radius);
    rec.submit();
    ctx.check()?;
    Ok(run)
}

/// Builds the volume grid over `photons` (spheres of `radius`) on the device and reads it
/// back.
pub fn volume_grid(ctx: &GpuContext, photons: &[Photon], radius: f32) -> Result<VolumeGridProbe> {
    let run = run_with_volume(ctx, &Scene::empty(), photons, radius, 1)?;
    let g: Vec<[f32; 4]> = read_back(ctx, &run.volume.grid, 48)?;
    let table_size = g[2][0].to_bits();
    let cell_start: Vec<u32> =
        read_back(ctx, &run.volume.map.cell_start, 4 * (table_size as u64 + 1))?;
    let total = cell_start[table_size as usize] as usize;
    let raw: Vec<[u32; 4]> = read_back(ctx, &run.volume.map.sorted, run.volume.map.sorted.size())?;
    Ok(VolumeGridProbe {
        lo: [g[0][0], g[0][1], g[0][2]],
        cell: g[0][3],
        hi: [g[1][0], g[1][1], g[1][2]],
        table_size,
        cell_start,
        entries: raw[..total]
            .iter()
            .map(|e| (e[0], [e[1] as i32, e[2] as i32, e[3] as i32]))
            .collect(),
    })
}

/// One beam query: the segment's origin, unit direction and length, the medium (an index of
/// the scene's) and which photons count.
#[derive(Clone, Copy, Debug)]
pub struct BeamQuery {
    /// Origin.
    pub o: [f32; 3],
    /// Unit direction.
    pub d: [f32; 3],
    /// Length (3e38 or more: endless).
    pub t_max: f32,
    /// The medium the segment runs in.
    pub medium: u32,
    /// Which photons count.
    pub photons: BeamPhotons,
    /// The beam is the segment's part beyond this distance (0: all of it); a heterogeneous
    /// medium's transmittance is the whole segment's walk on the stream
    /// `(seed, Photon, 0, i)`, read from there on (`Transmittances::split`).
    pub z: f32,
}

/// The device's beam estimate (`beam` in src/integrators/gpu/volume_estimate.wgsl) over `photons` (spheres
/// of `radius`) with `scene`'s media, per query.
pub fn beam(
    ctx: &GpuContext,
    scene: &Scene,
    photons: &[Photon],
    radius: f32,
    queries: &[BeamQuery],
) -> Result<Vec<[f32; 3]>> {
    let n = queries.len().max(1);
    let run = run_with_volume(ctx, scene, photons, radius, n as u32)?;
    let mut init = vec![[0f32; 4]; 4 * n];
    for (i, q) in queries.iter().enumerate() {
        init[i] = [q.o[0], q.o[1], q.o[2], q.t_max];
        init[n + i] = [q.d[0], q.d[1], q.d[2], f32::from_bits(q.medium)];
        init[2 * n + i] = [q.photons as u32 as f32, q.z, 0.0, 0.0];
    }
    let out = dispatch_probe(
        &run,
        "probe_beam",
        &case_buffer(&run, &init),
        n as u32,
        None,
        &[],
    )?;
    Ok((0..queries.len())
        .map(|i| [out[3 * n + i][0], out[3 * n + i][1], out[3 * n + i][2]])
        .collect())
}

/// The device's shadow walk (`shadow_transmittance`) through `scene` per case (origin,
/// unit direction, length, 3e38 or more for endless; the medium it starts in).
pub fn transmittance(
    ctx: &GpuContext,
    scene: &Scene,
    cases: &[([f32; 3], [f32; 3], f32, u32)],
) -> Result<Vec<[f32; 3]>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 3 * n];
    for (i, (o, d, t, m)) in cases.iter().enumerate() {
        init[i] = [o[0], o[1], o[2], *t];
        init[n + i] = [d[0], d[1], d[2], f32::from_bits(*m)];
    }
    let out = probe_cases(ctx, scene, "probe_transmittance", &init, n)?;
    Ok((0..cases.len())
        .map(|i| [out[2 * n + i][0], out[2 * n + i][1], out[2 * n + i][2]])
        .collect())
}

/// One case of [`hetero`]: a ray's origin, unit direction and length, and the seed of its
/// random-number streams.
#[derive(Clone, Copy, Debug)]
pub struct HeteroCase {
    /// The origin (also where the extinction and scattering are looked up).
    pub o: [f32; 3],
    /// The unit direction.
    pub d: [f32; 3],
    /// The segment's length (a surface's distance).
    pub t: f32,
    /// The seed: transmittance on `(seed, Photon, 0, i)`, the flight on `(seed, Caustic, 0, i)`.
    pub seed: u32,
}

/// What the device gave for one [`HeteroCase`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeteroSample {
    /// `hetero_sigma_t_at(o)`.
    pub sigma_t: [f32; 3],
    /// `hetero_sigma_s_at(o)`.
    pub sigma_s: [f32; 3],
    /// `hetero_transmittance` over the segment.
    pub transmittance: [f32; 3],
    /// `hetero_sample_flight`'s weight, distance and whether it ended in the medium.
    pub flight: ([f32; 3], f32, bool),
    /// The majorant walk over the segment's span: cells visited, the sum of majorant times
    /// length, whether it ran out.
    pub walk: (u32, f32, bool),
}

/// The device's heterogeneous-medium functions (src/media/heterogeneous.wgsl) on `scene`'s
/// medium 0, which must be heterogeneous, per case (`probe_hetero`).
pub fn hetero(ctx: &GpuContext, scene: &Scene, cases: &[HeteroCase]) -> Result<Vec<HeteroSample>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 7 * n];
    for (i, c) in cases.iter().enumerate() {
        init[i] = [c.o[0], c.o[1], c.o[2], c.t];
        init[n + i] = [c.d[0], c.d[1], c.d[2], f32::from_bits(c.seed)];
    }
    let out = probe_cases(ctx, scene, "probe_hetero", &init, n)?;
    let v3 = |v: [f32; 4]| [v[0], v[1], v[2]];
    Ok((0..cases.len())
        .map(|i| {
            let (f, w) = (out[5 * n + i], out[6 * n + i]);
            HeteroSample {
                sigma_t: v3(out[2 * n + i]),
                sigma_s: v3(out[3 * n + i]),
                transmittance: v3(out[4 * n + i]),
                flight: (v3(f), f[3], w[0] == 1.0),
                walk: (w[1] as u32, w[2], w[3] == 1.0),
            }
        })
        .collect())
}

/// What the device gave for one camera segment of [`segments`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentSample {
    /// `single_scattering` on the stream `(seed, Photon, 0, i)`.
    pub single: [f32; 3],
    /// `gathered_in_medium` on `(seed, Caustic, 0, i)`.
    pub gathered: [f32; 3],
}

/// The device's camera-segment estimates (`probe_segment`: `single_scattering`,
/// `gathered_in_medium`) in `scene`'s medium 0 over the volume map of `photons` (spheres of
/// `radius`), with `settings` (seed, shadow samples), per case (origin, unit direction,
/// length: 3e38 or more for endless).
pub fn segments(
    ctx: &GpuContext,
    scene: &Scene,
    settings: &RenderSettings,
    photons: &[Photon],
    radius: f32,
    cases: &[([f32; 3], [f32; 3], f32)],
) -> Result<Vec<SegmentSample>> {
    let n = cases.len().max(1);
    let s = RenderSettings {
        width: n as u32,
        height: 1,
        ..settings.clone()
    };
    let run = run_with_volume_settings(ctx, scene, photons, radius, &s)?;
    let mut init = vec![[0f32; 4]; 4 * n];
    for (i, (o, d, t)) in cases.iter().enumerate() {
        init[i] = [o[0], o[1], o[2], *t];
        init[n + i] = [d[0], d[1], d[2], 0.0];
    }
    let out = dispatch_probe(
        &run,
        "probe_segment",
        &case_buffer(&run, &init),
        n as u32,
        None,
        &[],
    )?;
    let v3 = |v: [f32; 4]| [v[0], v[1], v[2]];
    Ok((0..cases.len())
        .map(|i| SegmentSample {
            single: v3(out[2 * n + i]),
            gathered: v3(out[3 * n + i]),
        })
        .collect())
}
