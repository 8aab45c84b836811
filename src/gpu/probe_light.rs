//! Oracle probes of the lights and of ray intersection (shaders/probe_light.wgsl,
//! shaders/probe_geometry.wgsl): emission, shadow-ray samples, the owner of a photon path,
//! the end of a spent path, one primitive's intersection test and the BVH walk, on chosen
//! inputs, for tests/light_gpu.rs and tests/intersect_gpu.rs to compare with their Rust
//! twins (`LightTable::emit` and `sample`, `Budget::light_of`, `photon::power_ends`,
//! `geometry::intersect_triangle` and `intersect_sphere`, `Bvh::intersect` and `occluded`).

use super::context::GpuContext;
use super::probe::dispatch_probe;
use super::run::GpuRun;
use crate::error::Result;
use crate::photon::Budget;
use crate::plan::MapKind;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// One case of [`lights`]: a light and the random numbers and shading point it is used with.
#[derive(Clone, Copy, Debug)]
pub struct LightCase {
    /// The light's index in the scene.
    pub light: u32,
    /// `LightTable::emit`'s five numbers; `sample`'s three are `u[0], u[3], u[4]`.
    pub u: [f32; 5],
    /// The shading point of the shadow-ray sample.
    pub x: [f32; 3],
    /// Its shading normal.
    pub ns: [f32; 3],
}

/// What the device's `emit` and `sample_light` gave for one [`LightCase`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightProbe {
    /// The emission's origin.
    pub origin: [f32; 3],
    /// Its direction.
    pub dir: [f32; 3],
    /// Its surface normal (zero for the lights without a surface).
    pub normal: [f32; 3],
    /// Its factor on the photon's power.
    pub scale: [f32; 3],
    /// The triangle `pick_triangle` chose for `u[0]` (a triangle light only).
    pub triangle: Option<u32>,
    /// The shadow-ray sample's point.
    pub point: [f32; 3],
    /// Its weight.
    pub weight: [f32; 3],
    /// Whether it is distant (a directional light's or the environment's).
    pub distant: bool,
    /// Its solid-angle density (area lights and the environment; 0 for the delta lights).
    pub pdf: f32,
}

fn xyz(v: [f32; 4]) -> [f32; 3] {
    [v[0], v[1], v[2]]
}

/// A run over `scene` whose parameters say `n` invocations.
fn probe_run(ctx: &GpuContext, scene: &Scene, s: &RenderSettings, n: usize) -> Result<GpuRun> {
    let settings = RenderSettings {
        width: n.max(1) as u32,
        height: 1,
        ..s.clone()
    };
    GpuRun::new(ctx.clone(), scene, &settings, 0)
}

/// The device's `emit` and `sample_light` (shaders/common/light.wgsl) on `scene`'s lights,
/// per case.
pub fn lights(ctx: &GpuContext, scene: &Scene, cases: &[LightCase]) -> Result<Vec<LightProbe>> {
    let n = cases.len().max(1);
    let run = probe_run(ctx, scene, &RenderSettings::default(), n)?;
    let mut init = vec![[0f32; 4]; 9 * n];
    for (i, c) in cases.iter().enumerate() {
        init[i] = [c.u[0], c.u[1], c.u[2], f32::from_bits(c.light)];
        init[n + i] = [c.x[0], c.x[1], c.x[2], c.u[3]];
        init[2 * n + i] = [c.ns[0], c.ns[1], c.ns[2], c.u[4]];
    }
    let accum = run.accum_buffer(init.len() as u64 * 16);
    ctx.queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
    let out = dispatch_probe(&run, "probe_light", &accum, n as u32, None)?;
    let at = |k: usize, i: usize| out[k * n + i];
    Ok((0..cases.len())
        .map(|i| LightProbe {
            origin: xyz(at(3, i)),
            triangle: (at(3, i)[3] >= 0.0).then_some(at(3, i)[3] as u32),
            dir: xyz(at(4, i)),
            normal: xyz(at(5, i)),
            scale: xyz(at(6, i)),
            point: xyz(at(7, i)),
            pdf: at(7, i)[3],
            weight: xyz(at(8, i)),
            distant: at(8, i)[3] == 1.0,
        })
        .collect())
}

/// What [`paths`] read back: the budgets the run planned and what the device made of them.
#[derive(Clone, Debug)]
pub struct PathsProbe {
    /// The planned budget of the global and the caustic map (`None`: not planned).
    pub budgets: [Option<Budget>; 2],
    /// Per path index: `light_of(i, false)` and `light_of(i, true)`.
    pub owners: Vec<[u32; 2]>,
    /// Per power given: `power_ends(power)`.
    pub ends: Vec<bool>,
}

/// The device's `light_of` (shaders/common/light.wgsl) for every path index below the larger
/// of the two maps' totals (as a render of `scene` with `s` plans them) and `powers.len()`,
/// and its `power_ends` (shaders/common/photon.wgsl) for each of `powers`.
pub fn paths(
    ctx: &GpuContext,
    scene: &Scene,
    s: &RenderSettings,
    powers: &[[f32; 3]],
) -> Result<PathsProbe> {
    // The plan does not depend on the image's size: plan on the host to size the run.
    let table = crate::light::LightTable::new(scene);
    let plan = crate::plan::MapPlan::new(scene, &table, s);
    let total = plan
        .maps
        .iter()
        .map(|m| m.budget.total())
        .max()
        .unwrap_or(0) as usize;
    let n = total.max(powers.len()).max(1);
    let run = probe_run(ctx, scene, s, n)?;
    let budget = |k| run.plan.map(k).map(|m| m.budget.clone());
    let budgets = [budget(MapKind::Global), budget(MapKind::Caustic)];
    let mut init = vec![[0f32; 4]; 2 * n];
    for (i, p) in powers.iter().enumerate() {
        init[i] = [p[0], p[1], p[2], 0.0];
    }
    let accum = run.accum_buffer(init.len() as u64 * 16);
    ctx.queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
    let out = dispatch_probe(&run, "probe_paths", &accum, n as u32, None)?;
    Ok(PathsProbe {
        budgets,
        owners: (0..total.min(n))
            .map(|i| [out[n + i][0] as u32, out[n + i][1] as u32])
            .collect(),
        ends: (0..powers.len()).map(|i| out[n + i][2] == 1.0).collect(),
    })
}

/// One ray of [`intersect`].
#[derive(Clone, Copy, Debug)]
pub struct RayCase {
    /// Its origin.
    pub origin: [f32; 3],
    /// Its unit direction.
    pub dir: [f32; 3],
    /// Hits count in (0, t_max).
    pub t_max: f32,
    /// The primitive tested alone: a triangle's index, `SPHERE_BIT | ` a sphere's, or
    /// `u32::MAX` for none.
    pub primitive: u32,
}

/// What the device's intersection gave for one [`RayCase`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntersectProbe {
    /// The primitive's own test: `(t, u, v)` of a triangle's hit (u, v the weights of v1,
    /// v2), `(t, 0, 0)` of a sphere's; `None` for a miss (or no primitive).
    pub primitive: Option<[f32; 3]>,
    /// The BVH walk's nearest hit: `(t, material, light)`.
    pub nearest: Option<(f32, u32, Option<u32>)>,
    /// Its position and geometric normal (zero for a miss).
    pub position: [f32; 3],
    /// The hit's geometric normal.
    pub normal: [f32; 3],
    /// Whether the any-hit walk found a hit.
    pub occluded: bool,
}

/// The device's `intersect_triangle`, `intersect_sphere` and `trace_ray` (nearest and any
/// hit; shaders/common/intersect.wgsl) over `scene` for each ray.
pub fn intersect(ctx: &GpuContext, scene: &Scene, rays: &[RayCase]) -> Result<Vec<IntersectProbe>> {
    let n = rays.len().max(1);
    let run = probe_run(ctx, scene, &RenderSettings::default(), n)?;
    let mut init = vec![[0f32; 4]; 7 * n];
    for (i, r) in rays.iter().enumerate() {
        init[i] = [r.origin[0], r.origin[1], r.origin[2], r.t_max];
        init[n + i] = [r.dir[0], r.dir[1], r.dir[2], f32::from_bits(r.primitive)];
    }
    let accum = run.accum_buffer(init.len() as u64 * 16);
    ctx.queue
        .write_buffer(&accum, 0, bytemuck::cast_slice(&init));
    let out = dispatch_probe(&run, "probe_intersect", &accum, n as u32, None)?;
    let at = |k: usize, i: usize| out[k * n + i];
    Ok((0..rays.len())
        .map(|i| {
            let (p, h) = (at(2, i), at(3, i));
            IntersectProbe {
                primitive: (p[0] >= 0.0).then_some(xyz(p)),
                nearest: (h[1] == 1.0).then_some((
                    h[0],
                    h[2] as u32,
                    (h[3] >= 0.0).then_some(h[3] as u32),
                )),
                position: xyz(at(4, i)),
                normal: xyz(at(5, i)),
                occluded: at(6, i)[0] == 1.0,
            }
        })
        .collect())
}
