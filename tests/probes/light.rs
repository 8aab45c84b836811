//! Oracle probes of the lights and of ray intersection (tests/probes/probe_light.wgsl,
//! tests/probes/probe_geometry.wgsl) on one uploaded scene ([`SceneProbes`], its pipelines compiled
//! once): emission, shadow-ray samples, the owner of a photon path, the end of a spent path,
//! one primitive's intersection test and the BVH walk, on chosen inputs, for tests/light_gpu.rs and tests/intersect_gpu.rs to compare with their Rust
//! twins (`LightTable::emit` and `sample`, `Budget::light_of`, `photon::power_ends`,
//! `geometry::intersect_triangle` and `intersect_sphere`, `Bvh::intersect` and `occluded`).

use super::{case_buffer, dispatch_probe};
use gpu_photon::error::Result;
use gpu_photon::integrators::gpu::context::GpuContext;
use gpu_photon::integrators::gpu::pipelines::scene_features;
use gpu_photon::integrators::gpu::run::GpuRun;
use gpu_photon::integrators::photon::Budget;
use gpu_photon::integrators::plan::MapKind;
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;

/// One case of [`SceneProbes::lights`]: a light, and the random numbers and shading point
/// it is used with.
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
    /// Whether `aims_at` sends it towards the caustic map's bounds (the run's plan's).
    pub aims: bool,
    /// The triangle `pick_triangle` chose for `u[0]` (a triangle light only).
    pub triangle: Option<u32>,
    /// The shadow-ray sample's point.
    pub point: [f32; 3],
    /// Its weight.
    pub weight: [f32; 3],
    /// Whether it is distant (a directional light's or the environment's).
    pub distant: bool,
    /// Whether the light is a delta light (`is_delta_light`: point, spot, directional).
    pub delta: bool,
    /// Its solid-angle density (area lights and the environment; 0 for the delta lights).
    pub pdf: f32,
}

fn xyz(v: [f32; 4]) -> [f32; 3] {
    [v[0], v[1], v[2]]
}

/// What [`SceneProbes::paths`] read back: the budgets the run planned and what the device made of them.
#[derive(Clone, Debug)]
pub struct PathsProbe {
    /// The planned budget of the global and the caustic map (`None`: not planned).
    pub budgets: [Option<Budget>; 2],
    /// Per path index: `light_of(i, false)` and `light_of(i, true)`.
    pub owners: Vec<[u32; 2]>,
    /// Per power given: `power_ends(power)`.
    pub ends: Vec<bool>,
}

/// One scene on the device, uploaded as a render uploads it, for the probes of this module
/// and `probe_hit`: their pipelines are specialised with the scene's features, as a
/// render's are (`pipelines::scene_features`).
pub struct SceneProbes {
    run: GpuRun,
    features: Vec<(&'static str, f64)>,
}

impl SceneProbes {
    /// Uploads `scene` with the photon budgets `s` plans (see [`SceneProbes::paths`]).
    pub fn new(ctx: &GpuContext, scene: &Scene, s: &RenderSettings) -> Result<Self> {
        let run = GpuRun::new(ctx.clone(), scene, s, 0)?;
        let features = scene_features(scene, run.knn);
        Ok(SceneProbes { run, features })
    }

    /// Runs probe `entry` over `n` invocations on `init` (the parameters' width set to `n`)
    /// and reads the buffer back.
    pub fn dispatch(&mut self, entry: &str, init: &[[f32; 4]], n: usize) -> Result<Vec<[f32; 4]>> {
        let run = &mut self.run;
        run.params.width = n as u32;
        run.ctx.queue.write_buffer(
            &run.scene_buffers.params,
            0,
            bytemuck::bytes_of(&run.params),
        );
        let accum = case_buffer(run, init);
        dispatch_probe(run, entry, &accum, n as u32, None, &self.features)
    }

    /// The device's `emit` and `sample_light` (src/lights/light.wgsl) on the scene's
    /// lights, per case.
    pub fn lights(&mut self, cases: &[LightCase]) -> Result<Vec<LightProbe>> {
        let n = cases.len().max(1);
        let mut init = vec![[0f32; 4]; 9 * n];
        for (i, c) in cases.iter().enumerate() {
            init[i] = [c.u[0], c.u[1], c.u[2], f32::from_bits(c.light)];
            init[n + i] = [c.x[0], c.x[1], c.x[2], c.u[3]];
            init[2 * n + i] = [c.ns[0], c.ns[1], c.ns[2], c.u[4]];
        }
        let out = self.dispatch("probe_light", &init, n)?;
        let at = |k: usize, i: usize| out[k * n + i];
        Ok((0..cases.len())
            .map(|i| LightProbe {
                origin: xyz(at(3, i)),
                triangle: (at(3, i)[3] >= 0.0).then_some(at(3, i)[3] as u32),
                dir: xyz(at(4, i)),
                normal: xyz(at(5, i)),
                aims: at(5, i)[3] == 1.0,
                scale: xyz(at(6, i)),
                delta: at(6, i)[3] == 1.0,
                point: xyz(at(7, i)),
                pdf: at(7, i)[3],
                weight: xyz(at(8, i)),
                distant: at(8, i)[3] == 1.0,
            })
            .collect())
    }

    /// The device's `light_of` (src/lights/light.wgsl) for every path index below the
    /// larger of the two maps' totals (as the settings given to [`SceneProbes::new`] plan
    /// them), and its `power_ends` (src/integrators/gpu/photon.wgsl) for each of `powers`.
    pub fn paths(&mut self, powers: &[[f32; 3]]) -> Result<PathsProbe> {
        let budget = |k| self.run.plan.map(k).map(|m| m.budget.clone());
        let budgets = [budget(MapKind::Global), budget(MapKind::Caustic)];
        let total = budgets
            .iter()
            .flatten()
            .map(Budget::total)
            .max()
            .unwrap_or(0) as usize;
        let n = total.max(powers.len()).max(1);
        let mut init = vec![[0f32; 4]; 2 * n];
        for (i, p) in powers.iter().enumerate() {
            init[i] = [p[0], p[1], p[2], 0.0];
        }
        let out = self.dispatch("probe_paths", &init, n)?;
        Ok(PathsProbe {
            budgets,
            owners: (0..total)
                .map(|i| [out[n + i][0] as u32, out[n + i][1] as u32])
                .collect(),
            ends: (0..powers.len()).map(|i| out[n + i][2] == 1.0).collect(),
        })
    }

    /// The device's `intersect_triangle`, `intersect_sphere` and `trace_ray` (nearest and
    /// any hit; src/bvh/intersect.wgsl) over the scene for each ray.
    pub fn intersect(&mut self, rays: &[RayCase]) -> Result<Vec<IntersectProbe>> {
        let n = rays.len().max(1);
        let mut init = vec![[0f32; 4]; 7 * n];
        for (i, r) in rays.iter().enumerate() {
            init[i] = [r.origin[0], r.origin[1], r.origin[2], r.t_max];
            init[n + i] = [r.dir[0], r.dir[1], r.dir[2], f32::from_bits(r.primitive)];
        }
        let out = self.dispatch("probe_intersect", &init, n)?;
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
                    shading: [at(6, i)[1], at(6, i)[2], at(6, i)[3]],
                    occluded: at(6, i)[0] == 1.0,
                }
            })
            .collect())
    }
}

/// One ray of [`SceneProbes::intersect`].
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

impl RayCase {
    /// The host's ray.
    pub fn ray(&self) -> gpu_photon::math::geometry::Ray {
        gpu_photon::math::geometry::Ray {
            origin: glam::Vec3::from_array(self.origin),
            dir: glam::Vec3::from_array(self.dir),
        }
    }
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
    /// Its shading normal.
    pub shading: [f32; 3],
    /// Whether the any-hit walk found a hit.
    pub occluded: bool,
}
