//! Photon tracing on the CPU (twin: `shaders/trace_photons.wgsl`): one path per index, keyed
//! by (seed, stream, pass, index) so the result does not depend on thread scheduling.

use crate::bvh::Bvh;
use crate::geometry::{offset_origin, Ray};
use crate::light::{aims_at, LightTable};
use crate::material::Bounce;
use crate::photon::{Budget, Photon};
use crate::rng::{Rng, Stream};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use crate::shading::bsdf_at;
use glam::Vec3;
use rayon::prelude::*;

/// What one photon pass needs.
pub struct TraceContext<'a> {
    /// The scene traced.
    pub scene: &'a Scene,
    /// Its BVH.
    pub bvh: &'a Bvh,
    /// Its lights' sampling tables.
    pub lights: &'a LightTable,
    /// The pass's settings (seed, bounces, Fresnel mode).
    pub settings: &'a RenderSettings,
    /// The RNG's pass index.
    pub pass: u32,
}

/// Traces the global photon paths `0..budget.total()`; stores a photon at every diffuse or
/// glossy hit, in path-index order.
pub fn trace_photons(ctx: &TraceContext, budget: &Budget) -> Vec<Photon> {
    trace_paths(ctx, budget, Stream::Photon, None)
}

/// Traces caustic paths `0..budget.total()` aimed at `bounds`: emissions that miss the
/// bounds are rejected (the budget's path power already divides by all attempts), paths
/// whose first hit is not specular are dropped, and each remaining path stores one photon
/// at its first diffuse hit after one or more specular bounces.
pub fn trace_caustic_photons(
    ctx: &TraceContext,
    budget: &Budget,
    bounds: &[crate::geometry::Aabb],
) -> Vec<Photon> {
    trace_paths(ctx, budget, Stream::Caustic, Some(bounds))
}

/// Traces the paths of map `spec` (`trace_photons` or, aimed, `trace_caustic_photons`).
pub fn trace_map(ctx: &TraceContext, spec: &crate::plan::MapSpec) -> Vec<Photon> {
    let aim = (!spec.aim.is_empty()).then_some(&spec.aim[..]);
    trace_paths(ctx, &spec.budget, spec.kind.stream(), aim)
}

/// Every path of `budget` in parallel; the photons in path-index order (rayon's fold and
/// reduce keep the order of an indexed range).
fn trace_paths(
    ctx: &TraceContext,
    budget: &Budget,
    stream: Stream,
    aim: Option<&[crate::geometry::Aabb]>,
) -> Vec<Photon> {
    (0..budget.total())
        .into_par_iter()
        .fold(Vec::new, |mut out, i| {
            trace_path(ctx, budget, stream, i, aim, &mut out);
            out
        })
        .reduce(Vec::new, |mut a, mut b| {
            a.append(&mut b);
            a
        })
}

/// One photon path. With `aim` (a caustic path) only L S+ D is stored.
fn trace_path(
    ctx: &TraceContext,
    budget: &Budget,
    stream: Stream,
    i: u32,
    aim: Option<&[crate::geometry::Aabb]>,
    out: &mut Vec<Photon>,
) {
    let s = ctx.settings;
    let mut rng = Rng::new(s.seed, stream, ctx.pass, i);
    let l = budget.light_of(i);
    let e = ctx.lights.emit(
        ctx.scene,
        l,
        [rng.next(), rng.next(), rng.next(), rng.next(), rng.next()],
    );
    if let Some(bounds) = aim {
        if !aims_at(bounds, e.origin, e.dir) {
            return;
        }
    }
    let mut power = budget.path_power[l] * e.scale;
    let mut ray = Ray {
        origin: if e.normal == Vec3::ZERO {
            e.origin
        } else {
            offset_origin(e.origin, e.normal, e.dir)
        },
        dir: e.dir,
    };
    let mut all_specular = true;
    for depth in 0..s.max_photon_bounces {
        let Some(hit) = ctx.bvh.intersect(ctx.scene, &ray, f32::INFINITY) else {
            return;
        };
        let bsdf = bsdf_at(ctx.scene, &hit);
        if bsdf.stores_photons() {
            let caustic = depth > 0 && all_specular;
            // The caustic map keeps only L (S|G)+ D photons: its paths end at the first
            // diffuse bounce.
            if aim.is_none() || caustic {
                // A plastic's base sees the light its coating lets through.
                let stored = match bsdf.store_weight(-ray.dir) {
                    Some(w) => power * w,
                    None => power,
                };
                out.push(Photon::new(
                    hit.position,
                    stored,
                    ray.dir,
                    hit.normal,
                    i,
                    depth,
                    caustic,
                ));
            }
        }
        let u = [rng.next(), rng.next(), rng.next()];
        let bounce = bsdf.photon_bounce(ray.dir, &hit, s.fresnel, u);
        let (dir, weight) = match bounce {
            Bounce::Absorb => return,
            Bounce::Diffuse { .. } if aim.is_some() => return,
            Bounce::Diffuse { dir, weight } => {
                all_specular = false;
                (dir, weight)
            }
            // Delta and glossy lobes alike: the photon-mapping split traces every lobe
            // from the camera, so light arriving over any of them is a caustic.
            Bounce::Specular { dir, weight, .. } => (dir, weight),
        };
        power *= weight;
        if !(power.max_element() > 0.0) || !power.is_finite() {
            return;
        }
        ray = Ray {
            origin: offset_origin(hit.position, hit.normal, dir),
            dir,
        };
    }
}
