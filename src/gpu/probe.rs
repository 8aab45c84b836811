//! Oracle probes: run single kernels on chosen inputs so tests can compare them with the
//! Rust functions they mirror (the RNG, the grid build, the K-nearest estimate).

use super::context::GpuContext;
use super::render::{bind_group_for_gather, read_back, GpuRun};
use super::types::GpuMapParams;
use crate::error::Result;
use crate::photon::Photon;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// `(path_key, draw_u32, to_unit bits, pcg_hash(i))` for i < n, from WGSL, with the key's
/// stream `1 + i % 4` and dimension `i % 9`.
pub fn rng_values(ctx: &GpuContext, seed: u32, pass: u32, n: u32) -> Result<Vec<[u32; 4]>> {
    let scene = crate::scene::Scene::empty();
    let settings = RenderSettings {
        width: n,
        height: 1,
        seed,
        ..Default::default()
    };
    let run = GpuRun::new(ctx, &scene, &settings, pass)?;
    let accum = run.accum_buffer(n as u64 * 16);
    let out = run.dispatch_probe("probe_rng", &accum, n, None)?;
    Ok(bytemuck::cast_slice::<[f32; 4], [u32; 4]>(&out).to_vec())
}

/// Builds the hash grid of `photons` on the device: returns `(cell_start, sorted photons)`.
pub fn build_grid(
    ctx: &GpuContext,
    photons: &[Photon],
    cell_size: f32,
    table_size: u32,
) -> Result<(Vec<u32>, Vec<Photon>)> {
    let scene = crate::scene::Scene::empty();
    let run = GpuRun::new(ctx, &scene, &RenderSettings::default(), 0)?;
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
    let run = GpuRun::new(ctx, &scene, &settings, 0)?;
    let map = run.upload_map(
        photons,
        cell_size,
        super::grid::table_size_for(photons.len() as u32, ctx.max_binding),
        radius * radius,
    )?;
    let mut init = vec![[0f32; 4]; 3 * queries.len()];
    for (i, (p, nrm)) in queries.iter().enumerate() {
        init[i] = [p[0], p[1], p[2], 0.0];
        init[queries.len() + i] = [nrm[0], nrm[1], nrm[2], 0.0];
    }
    let accum = run.accum_buffer(init.len() as u64 * 16);
    ctx.queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
    let empty = run.empty_map(true);
    let bg = bind_group_for_gather(ctx, &run.layouts, &map, &empty, &accum);
    let out = run.dispatch_probe("probe_knn", &accum, n, Some(&bg))?;
    let stats: Vec<u32> = read_back(ctx, &run.scene_buffers.stats, 16)?;
    Ok((
        out[2 * queries.len()..]
            .iter()
            .map(|v| ([v[0], v[1], v[2]], v[3] as u32))
            .collect(),
        stats,
    ))
}

/// Map parameters of a probe map.
pub fn probe_map_params(n: u32, cell_size: f32, table_size: u32, radius2: f32) -> GpuMapParams {
    GpuMapParams {
        stream: 0,
        paths: n.max(1),
        capacity: n.max(1),
        table_size,
        cell_size,
        is_caustic: 0,
        drop_flags: 0,
        radius2,
    }
}
