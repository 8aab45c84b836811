//! Oracle probes: run single kernels on chosen inputs so tests can compare them with the
//! Rust functions they mirror (the RNG, the grid build, the K-nearest estimate, the radiance
//! cache's build and lookup, the environment's lookup and sampling). The probe entry points
//! live in `probes.wgsl` beside this file, composed over the kernels' own libraries
//! (`gpu::shaders::probe_source`); the set-up is the render's own (`GpuRun`). Test code
//! only: no release build compiles it. Each test that uses probes declares `mod probes;`.
#![allow(dead_code)]

pub mod hit;
pub mod light;
pub mod media;
pub mod shading;

use gpu_photon::error::{Error, Result};
use gpu_photon::integrators::gpu::bindings::GATHER_GROUP;
use gpu_photon::integrators::gpu::buffers::{grid_2d, read_back};
use gpu_photon::integrators::gpu::codes::{STATS_LEN, WG_SIZE};
use gpu_photon::integrators::gpu::context::GpuContext;
use gpu_photon::integrators::gpu::pipelines::{pipeline_layout, shader_module_of};
use gpu_photon::integrators::gpu::recorder::Recorder;
use gpu_photon::integrators::gpu::run::GpuRun;
use gpu_photon::integrators::photon::Photon;
use gpu_photon::scene::Scene;
use gpu_photon::settings::{Filter, Mode, RenderSettings};

/// `(path_key, draw_u32, to_unit bits, pcg_hash(i))` for i < n, from WGSL, with the key's
/// stream `1 + i % 4` and dimension `i % 9`.
pub fn rng_values(ctx: &GpuContext, seed: u32, pass: u32, n: u32) -> Result<Vec<[u32; 4]>> {
    let scene = Scene::empty();
    let settings = RenderSettings {
        width: n,
        height: 1,
        seed,
        ..Default::default()
    };
    let run = GpuRun::new(ctx.clone(), &scene, &settings, pass)?;
    let accum = run.accum_buffer(n as u64 * 16);
    let out = dispatch_probe(&run, "probe_rng", &accum, n, None, &[])?;
    Ok(bytemuck::cast_slice::<[f32; 4], [u32; 4]>(&out).to_vec())
}

/// Builds the hash grid of `photons` on the device: returns `(cell_start, sorted photons)`.
pub fn build_grid(
    ctx: &GpuContext,
    photons: &[Photon],
    cell_size: f32,
    table_size: u32,
) -> Result<(Vec<u32>, Vec<Photon>)> {
    let scene = Scene::empty();
    let run = GpuRun::new(ctx.clone(), &scene, &RenderSettings::default(), 0)?;
    let map = run.upload_map(photons, cell_size, table_size, 1.0)?;
    let starts: Vec<u32> = read_back(ctx, &map.cell_start, 4 * (table_size as u64 + 1))?;
    let sorted: Vec<Photon> = read_back(
        ctx,
        &map.sorted,
        (photons.len().max(1) * std::mem::size_of::<Photon>()) as u64,
    )?;
    Ok((starts, sorted[..photons.len()].to_vec()))
}

/// The device's K-nearest estimate (f = 1) of `photons` at each query `(position, normal)`:
/// `(radiance, neighbour count)` per query, and the stats counters (bounds hit).
pub fn estimate(
    ctx: &GpuContext,
    photons: &[Photon],
    queries: &[([f32; 3], [f32; 3])],
    k: u32,
    radius: f32,
    cell_size: f32,
) -> Result<(Vec<([f32; 3], u32)>, Vec<u32>)> {
    let scene = Scene::empty();
    let n = queries.len() as u32;
    let settings = RenderSettings {
        width: n,
        height: 1,
        k,
        radius,
        ..Default::default()
    };
    let run = GpuRun::new(ctx.clone(), &scene, &settings, 0)?;
    let table =
        gpu_photon::integrators::gpu::grid::table_size_for(photons.len() as u32, ctx.max_binding);
    let map = run.upload_map(photons, cell_size, table, radius * radius)?;
    let mut init = vec![[0f32; 4]; 3 * queries.len()];
    for (i, (p, nrm)) in queries.iter().enumerate() {
        init[i] = [p[0], p[1], p[2], 0.0];
        init[queries.len() + i] = [nrm[0], nrm[1], nrm[2], 0.0];
    }
    let accum = case_buffer(&run, &init);
    let empty = run.empty_map(true);
    let bg = run.gather_bind_group([&map, &empty], &accum);
    let out = dispatch_probe(&run, "probe_knn", &accum, n, Some(&bg), &[])?;
    let stats: Vec<u32> = read_back(ctx, &run.scene_buffers.stats, (STATS_LEN * 4) as u64)?;
    Ok((
        out[2 * queries.len()..]
            .iter()
            .map(|v| ([v[0], v[1], v[2]], v[3] as u32))
            .collect(),
        stats,
    ))
}

/// The device's `cosine_hemisphere(normal, u1, u2)` (src/math/sampling.wgsl) for each
/// `(normal, [u1, u2])`.
pub fn cosine_hemisphere(
    ctx: &GpuContext,
    cases: &[([f32; 3], [f32; 2])],
) -> Result<Vec<[f32; 3]>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 3 * n];
    for (i, (nrm, u)) in cases.iter().enumerate() {
        init[i] = [nrm[0], nrm[1], nrm[2], 0.0];
        init[n + i] = [u[0], u[1], 0.0, 0.0];
    }
    let out = probe_cases(ctx, &Scene::empty(), "probe_cosine", &init, n)?;
    Ok(out[2 * n..2 * n + cases.len()]
        .iter()
        .map(|v| [v[0], v[1], v[2]])
        .collect())
}

/// One case of [`surface`]: the inputs of the surface-frame functions of
/// src/bvh/intersect.wgsl, src/bvh/shading_frame.wgsl and sampling.wgsl, and of material.wgsl's.
#[derive(Clone, Copy, Debug, Default)]
pub struct SurfaceCase {
    /// `phong_lobe`'s axis (and `sphere_uv`'s point).
    pub axis: [f32; 3],
    /// `phong_lobe`'s exponent.
    pub exponent: f32,
    /// `phong_lobe`'s two uniforms.
    pub u: [f32; 2],
    /// Geometric normal of the frame (ray's side).
    pub ng: [f32; 3],
    /// Shading normal of the frame.
    pub ns: [f32; 3],
    /// `normal_mapped`'s dp/du.
    pub dp_du: [f32; 3],
    /// Whether the tangent frame is mirrored.
    pub flipped: bool,
    /// `dielectric`'s and the Fresnel functions' index of refraction (and the bounce's).
    pub ior: f32,
    /// `photon_bounce`'s BSDF (a classic kind: Lambert, Phong, mirror, glass), packed as
    /// the scene buffers pack it (at most three words).
    pub material: gpu_photon::bsdfs::Bsdf,
    /// `photon_bounce`'s third uniform (the first two are `u`).
    pub u3: f32,
    /// A normal map's texel (in [0, 1]^3).
    pub c: [f32; 3],
    /// The ray's direction.
    pub d: [f32; 3],
    /// `bump_mapped`'s dp/dv (its dp/du is `dp_du`).
    pub dp_dv: [f32; 3],
    /// `bump_mapped`'s height gradient.
    pub grad: [f32; 2],
}

/// What the device gave for one [`SurfaceCase`].
#[derive(Clone, Copy, Debug)]
pub struct SurfaceProbe {
    /// `phong_lobe(axis, exponent, u1, u2)`.
    pub lobe: [f32; 3],
    /// `sphere_uv(axis)`.
    pub uv: [f32; 2],
    /// `reflection_leaks` and `refraction_leaks` of `d` in the frame (ng, ns).
    pub leaks: [bool; 2],
    /// `normal_mapped(ng, ns, dp_du, flipped, c, d)`.
    pub mapped: [f32; 3],
    /// `bump_mapped(ng, ns, (dp_du, dp_dv), grad, d)`.
    pub bumped: [f32; 3],
    /// `dielectric(d, ng, ns, ior)`: reflected direction, refracted direction (zero on total
    /// internal reflection) and reflectance (with the settings' Fresnel formula).
    pub dielectric: ([f32; 3], [f32; 3], f32),
    /// `fresnel_exact(c.x, 1, ior)`, `fresnel_exact(c.x, ior, 1)`, `fresnel_schlick(c.x, 1,
    /// ior)`, `fresnel_schlick(c.x, ior, 1)`.
    pub fresnel: [f32; 4],
    /// `reflect_dir(d, ns)`.
    pub reflected: [f32; 3],
    /// `phong_lobe_value(axis, -d, ns, exponent)`.
    pub lobe_value: f32,
    /// `photon_bounce`'s direction, kind (`codes::BOUNCE_*`) and weight.
    pub bounce: ([f32; 3], u32, [f32; 3]),
}

/// The device's Phong lobe, sphere uvs, leak tests, normal mapping and the classic materials'
/// functions (src/bsdfs/classic.wgsl) for each case (probe `probe_surface` in
/// tests/probes/probe_geometry.wgsl).
pub fn surface(ctx: &GpuContext, cases: &[SurfaceCase]) -> Result<Vec<SurfaceProbe>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 23 * n];
    let v = |a: [f32; 3]| [a[0], a[1], a[2], 0.0];
    for (i, c) in cases.iter().enumerate() {
        init[i] = [c.axis[0], c.axis[1], c.axis[2], c.exponent];
        init[n + i] = [c.u[0], c.u[1], c.flipped as u32 as f32, c.ior];
        use gpu_photon::bsdfs::BsdfKind;
        let mut w = gpu_photon::bsdfs::param::GpuWords::default();
        c.material.gpu_words(&mut w);
        w.words.resize(3, [0; 4]);
        for (k, slot) in [14, 15, 18].into_iter().enumerate() {
            init[slot * n + i] = w.words[k].map(f32::from_bits);
        }
        init[19 * n + i] = [f32::from_bits(c.material.code()), c.u3, 0.0, 0.0];
        init[20 * n + i] = v(c.dp_dv);
        init[21 * n + i] = [c.grad[0], c.grad[1], 0.0, 0.0];
        for (k, x) in [c.ng, c.ns, c.dp_du, c.c, c.d].into_iter().enumerate() {
            init[(2 + k) * n + i] = v(x);
        }
    }
    let out = probe_cases(ctx, &Scene::empty(), "probe_surface", &init, n)?;
    Ok((0..cases.len())
        .map(|i| {
            let at = |k: usize| out[k * n + i];
            let xyz = |v: [f32; 4]| [v[0], v[1], v[2]];
            let (m, g) = (at(8), at(10));
            SurfaceProbe {
                lobe: xyz(at(7)),
                uv: [m[0], m[1]],
                leaks: [m[2] != 0.0, m[3] != 0.0],
                mapped: xyz(at(9)),
                bumped: xyz(at(22)),
                dielectric: (xyz(g), xyz(at(11)), g[3]),
                fresnel: at(12),
                reflected: xyz(at(13)),
                lobe_value: at(13)[3],
                bounce: (xyz(at(16)), at(16)[3] as u32, xyz(at(17))),
            }
        })
        .collect())
}

/// The device's environment functions (src/lights/environment.wgsl) on `scene`'s
/// environment (its last light) for each `(direction, shading normal, uniforms)`: per case
/// `(radiance along the direction, env_pdf)` and the shadow-ray sample `(direction, pdf)`.
pub fn environment(
    ctx: &GpuContext,
    scene: &Scene,
    cases: &[([f32; 3], [f32; 3], [f32; 3])],
) -> Result<Vec<([f32; 4], [f32; 4])>> {
    let n = cases.len().max(1);
    let mut init = vec![[0f32; 4]; 5 * n];
    for (i, (d, ns, u)) in cases.iter().enumerate() {
        init[i] = [d[0], d[1], d[2], 0.0];
        init[n + i] = [ns[0], ns[1], ns[2], 0.0];
        init[2 * n + i] = [u[0], u[1], u[2], 0.0];
    }
    let out = probe_cases(ctx, scene, "probe_env", &init, n)?;
    Ok((0..cases.len())
        .map(|i| (out[3 * n + i], out[4 * n + i]))
        .collect())
}

/// What [`radiance_cache`] read back from the device.
#[derive(Clone, Debug)]
pub struct CacheProbe {
    /// The map's photons in the grid's order (the cache is parallel to them).
    pub sorted: Vec<Photon>,
    /// One entry per sorted photon: (value, 1) at a cache point, zero elsewhere.
    pub cache: Vec<[f32; 4]>,
    /// Per query: the lookup's value and the sorted index it read (`None`: no cache point).
    pub lookups: Vec<([f32; 3], Option<u32>)>,
    /// The stats counters (bounds hit) after the build and the lookups.
    pub stats: Vec<u32>,
}

/// Builds the radiance cache of `photons` (as the global map, with the render's own
/// `build_cache` pipeline: K = `k` nearest within `radius`, `k == 0` every photon within
/// it, `filter`) and looks it up at each query `(position, normal)`.
pub fn radiance_cache(
    ctx: &GpuContext,
    photons: &[Photon],
    queries: &[([f32; 3], [f32; 3])],
    (k, radius, cell_size, filter): (u32, f32, f32, Filter),
) -> Result<CacheProbe> {
    let scene = Scene::empty();
    let n = queries.len().max(1) as u32;
    let settings = RenderSettings {
        width: n,
        height: 1,
        k,
        radius,
        filter,
        mode: Mode::Gather,
        ..Default::default()
    };
    let mut run = GpuRun::new(ctx.clone(), &scene, &settings, 0)?;
    let table =
        gpu_photon::integrators::gpu::grid::table_size_for(photons.len() as u32, ctx.max_binding);
    let map = run.upload_map(photons, cell_size, table, radius * radius)?;
    let mut init = vec![[0f32; 4]; 3 * n as usize];
    for (i, (p, nrm)) in queries.iter().enumerate() {
        init[i] = [p[0], p[1], p[2], 0.0];
        init[n as usize + i] = [nrm[0], nrm[1], nrm[2], 0.0];
    }
    let accum = case_buffer(&run, &init);
    let empty = run.empty_map(true);
    let mut rec = Recorder::new(ctx.clone(), false);
    run.record_cache(&mut rec, [&map, &empty], &accum)?;
    rec.submit();
    let count = photons.len();
    let sorted: Vec<Photon> = read_back(
        ctx,
        &map.sorted,
        (count.max(1) * std::mem::size_of::<Photon>()) as u64,
    )?;
    let cache: Vec<[f32; 4]> = read_back(ctx, &run.cache[0], run.cache[0].size())?;
    let bg = run.gather_bind_group([&map, &empty], &accum);
    let out = dispatch_probe(&run, "probe_cache", &accum, n, Some(&bg), &[])?;
    let stats: Vec<u32> = read_back(ctx, &run.scene_buffers.stats, (STATS_LEN * 4) as u64)?;
    let lookups = out[2 * n as usize..2 * n as usize + queries.len()]
        .iter()
        .map(|v| ([v[0], v[1], v[2]], (v[3] >= 0.0).then_some(v[3] as u32)))
        .collect();
    Ok(CacheProbe {
        sorted: sorted[..count].to_vec(),
        cache: cache[..count].to_vec(),
        lookups,
        stats,
    })
}

/// A run over `scene` for `n` probe cases (an image of `n` x 1 pixels): the render's own
/// set-up.
pub fn case_run(ctx: &GpuContext, scene: &Scene, n: usize) -> Result<GpuRun> {
    let settings = RenderSettings {
        width: n as u32,
        height: 1,
        ..Default::default()
    };
    GpuRun::new(ctx.clone(), scene, &settings, 0)
}

/// The probes' buffer (`accum`) of `run`, holding `init`.
pub fn case_buffer(run: &GpuRun, init: &[[f32; 4]]) -> wgpu::Buffer {
    let accum = run.accum_buffer(init.len() as u64 * 16);
    run.ctx
        .queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(init));
    accum
}

/// Runs probe `entry` over `n` cases of `init` on a fresh run over `scene` (the WGSL
/// defaults of the override constants) and reads the buffer back.
pub fn probe_cases(
    ctx: &GpuContext,
    scene: &Scene,
    entry: &str,
    init: &[[f32; 4]],
    n: usize,
) -> Result<Vec<[f32; 4]>> {
    let run = case_run(ctx, scene, n)?;
    dispatch_probe(&run, entry, &case_buffer(&run, init), n as u32, None, &[])
}

/// Runs the probe entry point `entry` over `n` invocations (WG_SIZE-wide) with group 1 `bg`
/// (two absent maps and `accum` when `None`) and reads `accum` back. The pipeline is
/// specialised with `constants` (override constants by name; the WGSL defaults for the
/// others).
pub fn dispatch_probe(
    run: &GpuRun,
    entry: &str,
    accum: &wgpu::Buffer,
    n: u32,
    bg: Option<&wgpu::BindGroup>,
    constants: &[(&str, f64)],
) -> Result<Vec<[f32; 4]>> {
    debug_assert_eq!(GATHER_GROUP.group, 1);
    let dev = &run.ctx.device;
    let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = shader_module_of(dev, "probes", source());
    let layout = pipeline_layout(
        dev,
        "probe pipeline layout",
        &run.layouts,
        &run.layouts.gather,
    );
    let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&layout),
        module: &module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(Error::Gpu(format!("probe pipeline: {e}")));
    }
    let owned;
    let bg = match bg {
        Some(b) => b,
        None => {
            let (g, c) = (run.empty_map(false), run.empty_map(true));
            owned = run.gather_bind_group([&g, &c], accum);
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
        cp.set_bind_group(0, &run.scene_buffers.bind_group, &[0]);
        cp.set_bind_group(1, bg, &[]);
        let (x, y) = grid_2d(n.div_ceil(WG_SIZE));
        cp.dispatch_workgroups(x, y, 1);
    }
    run.ctx.queue.submit([enc.finish()]);
    read_back(&run.ctx, accum, accum.size())
}

/// The probes' composed module: the kernels' libraries, then `probes.wgsl`,
/// `probe_light.wgsl`, `probe_geometry.wgsl` and `probe_shading.wgsl`.
pub fn source() -> String {
    gpu_photon::integrators::gpu::shaders::probe_source(&[
        include_str!("probes.wgsl"),
        include_str!("probe_light.wgsl"),
        include_str!("probe_geometry.wgsl"),
        include_str!("probe_shading.wgsl"),
        include_str!("probe_bsdf.wgsl"),
    ])
}
