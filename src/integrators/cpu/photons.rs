//! Photon tracing on the CPU (twin: `src/integrators/gpu/trace_photons.wgsl`): one path per index, keyed
//! by (seed, stream, pass, index) so the result does not depend on thread scheduling.

use crate::bsdfs::interface::Bounce;
use crate::bsdfs::shading::{bsdf_at, SurfaceClass};
use crate::bvh::CpuBvh;
use crate::integrators::cpu::media::{medium_after, photon_medium, MAX_CROSSINGS};
use crate::integrators::photon::{power_ends, Budget, Photon};
use crate::integrators::plan::VolumeSpec;
use crate::lights::table::{aims_at, LightTable};
use crate::math::geometry::{offset_origin, Ray};
use crate::math::rng::{Rng, Stream};
use crate::media::NO_MEDIUM;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::Vec3;
use rayon::prelude::*;

/// What one photon pass needs.
pub struct TraceContext<'a> {
    /// The scene traced.
    pub scene: &'a Scene,
    /// Its BVH.
    pub bvh: &'a CpuBvh,
    /// Its lights' sampling tables.
    pub lights: &'a LightTable,
    /// The pass's settings (seed, bounces, Fresnel mode).
    pub settings: &'a RenderSettings,
    /// The RNG's pass index.
    pub pass: u32,
}

/// The photons of one map's paths: those stored on surfaces, and those stored where the
/// paths scattered in a medium (for the volume map; empty without media); and where the
/// paths' power went (the energy balance `tests/media_transport.rs` checks).
#[derive(Debug, Default)]
pub struct Traced {
    /// Surface photons, in path-index order.
    pub surface: Vec<Photon>,
    /// Volume photons, in path-index order.
    pub volume: Vec<Photon>,
    /// Power of the paths that ended, by where they ended (W per channel, in f64).
    pub ends: PathEnds,
}

/// Power of the ended photon paths of a [`Traced`], by how each ended. A path's power at its
/// end is what Russian roulette let it carry, so in expectation each sum is the power the
/// surfaces or media absorbed (or that left the scene).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PathEnds {
    /// Absorbed at a surface (Russian roulette, a black surface, a light's own surface).
    pub surface: [f64; 3],
    /// Absorbed in a medium (Russian roulette on a scattering event's weight).
    pub medium: [f64; 3],
    /// Left the scene.
    pub escaped: [f64; 3],
    /// Cut off: by `max_photon_bounces`, the boundary-crossing bound, or a power that is not
    /// finite and positive; caustic paths that end at their first diffuse or medium event.
    pub cut: [f64; 3],
}

impl PathEnds {
    fn add(sum: &mut [f64; 3], power: Vec3) {
        for (s, p) in sum.iter_mut().zip(power.to_array()) {
            if p.is_finite() {
                *s += p as f64;
            }
        }
    }
    fn merge(&mut self, o: &PathEnds) {
        for (a, b) in [
            (&mut self.surface, &o.surface),
            (&mut self.medium, &o.medium),
            (&mut self.escaped, &o.escaped),
            (&mut self.cut, &o.cut),
        ] {
            for c in 0..3 {
                a[c] += b[c];
            }
        }
    }
}

impl Traced {
    fn append(mut self, mut other: Traced) -> Traced {
        self.surface.append(&mut other.surface);
        self.volume.append(&mut other.volume);
        self.ends.merge(&other.ends);
        self
    }
}

/// Traces the global photon paths `0..budget.total()`; stores a photon at every diffuse or
/// glossy hit, in path-index order.
pub fn trace_photons(ctx: &TraceContext, budget: &Budget) -> Vec<Photon> {
    trace_paths(ctx, budget, Stream::Photon, None, None).surface
}

/// Traces caustic paths `0..budget.total()` aimed at `bounds`: emissions that miss the
/// bounds are rejected (the budget's path power already divides by all attempts), paths
/// whose first hit is not specular are dropped, and each remaining path stores one photon
/// at its first diffuse hit after one or more specular bounces.
pub fn trace_caustic_photons(
    ctx: &TraceContext,
    budget: &Budget,
    bounds: &[crate::math::geometry::Aabb],
) -> Vec<Photon> {
    trace_paths(ctx, budget, Stream::Caustic, Some(bounds), None).surface
}

/// Traces the paths of map `spec` (`trace_photons` or, aimed, `trace_caustic_photons`);
/// with `volume` (the plan's volume map) they also store volume photons.
pub fn trace_map(
    ctx: &TraceContext,
    spec: &crate::integrators::plan::MapSpec,
    volume: Option<VolumeSpec>,
) -> Traced {
    let aim = (!spec.aim.is_empty()).then_some(&spec.aim[..]);
    trace_paths(ctx, &spec.budget, spec.kind.stream(), aim, volume)
}

/// Every path of `budget` in parallel; the photons in path-index order (rayon's fold and
/// reduce keep the order of an indexed range).
fn trace_paths(
    ctx: &TraceContext,
    budget: &Budget,
    stream: Stream,
    aim: Option<&[crate::math::geometry::Aabb]>,
    volume: Option<VolumeSpec>,
) -> Traced {
    (0..budget.total())
        .into_par_iter()
        .fold(Traced::default, |mut out, i| {
            trace_path(ctx, budget, stream, i, aim, volume, &mut out);
            out
        })
        .reduce(Traced::default, Traced::append)
}

/// One photon path. With `aim` (a caustic path) only L S+ D (and L S+ V) is stored. In a
/// medium each segment samples a free flight (`Medium::sample_flight`): an event in the
/// medium stores a volume photon (with `volume`), then the path goes on by the phase
/// function with Russian roulette on the flight's weight (the albedo, for a grey medium),
/// and counts as a bounce; index-matched boundaries only change the medium.
#[allow(clippy::too_many_arguments)]
fn trace_path(
    ctx: &TraceContext,
    budget: &Budget,
    stream: Stream,
    i: u32,
    aim: Option<&[crate::math::geometry::Aabb]>,
    volume: Option<VolumeSpec>,
    out: &mut Traced,
) {
    let s = ctx.settings;
    let scene = ctx.scene;
    let mut rng = Rng::new(s.seed, stream, ctx.pass, i);
    let l = budget.light_of(i);
    let e = ctx.lights.emit(
        scene,
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
    // NO_MEDIUM in a scene without media (vacuum interfaces, no camera medium).
    let mut medium = photon_medium(scene, ctx.bvh, l, &e, ray.origin);
    let mut all_specular = true;
    let mut depth = 0;
    let mut crossings = 0;
    while depth < s.max_photon_bounces {
        let hit = ctx.bvh.intersect(scene, &ray, f32::INFINITY);
        if medium != NO_MEDIUM {
            let m = &scene.media[medium as usize];
            let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            let flight = m.flight(ray.origin, ray.dir, t_max, &mut rng);
            if flight.in_medium {
                let x = ray.origin + ray.dir * flight.t;
                let scattered = power * flight.weight;
                let caustic = depth > 0 && all_specular;
                if let Some(v) = volume {
                    // A caustic path keeps only L S+ V; the global paths leave those to it.
                    let keep = match aim {
                        Some(_) => caustic,
                        None => !(caustic && v.drop_caustic),
                    };
                    if keep && scattered.max_element() > 0.0 {
                        out.volume.push(Photon::in_medium(
                            x, scattered, ray.dir, medium, i, depth, caustic,
                        ));
                    }
                }
                if aim.is_some() {
                    return PathEnds::add(&mut out.ends.cut, power);
                }
                // Absorption by Russian roulette on the scattering weight.
                let q = flight.weight.max_element().min(1.0);
                if !(rng.next() < q) {
                    return PathEnds::add(&mut out.ends.medium, power);
                }
                power = scattered / q;
                let dir = m.phase.sample(ray.dir, rng.next(), rng.next());
                ray = Ray { origin: x, dir };
                all_specular = false;
                depth += 1;
                if power_ends(power) {
                    return PathEnds::add(&mut out.ends.cut, power);
                }
                continue;
            }
            power *= flight.weight;
        }
        let Some(hit) = hit else {
            return PathEnds::add(&mut out.ends.escaped, power);
        };
        let bsdf = bsdf_at(scene, &hit, ray.dir);
        if bsdf.class() == SurfaceClass::Null {
            // An index-matched boundary: straight on, in the medium behind it.
            crossings += 1;
            if crossings > MAX_CROSSINGS {
                return PathEnds::add(&mut out.ends.cut, power);
            }
            medium = medium_after(scene, &hit, medium, ray.dir);
            ray.origin = offset_origin(hit.position, hit.normal, ray.dir);
            continue;
        }
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
                out.surface.push(Photon::new(
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
            Bounce::Absorb => return PathEnds::add(&mut out.ends.surface, power),
            Bounce::Diffuse { .. } if aim.is_some() => {
                return PathEnds::add(&mut out.ends.cut, power)
            }
            Bounce::Diffuse { dir, weight } => {
                all_specular = false;
                (dir, weight)
            }
            // Delta and glossy lobes alike: the photon-mapping split traces every lobe
            // from the camera, so light arriving over any of them is a caustic.
            Bounce::Specular { dir, weight, .. } => (dir, weight),
        };
        power *= weight;
        if power_ends(power) {
            return PathEnds::add(&mut out.ends.cut, power);
        }
        // A thin sheet passed in a scene with media is a null event (Mitsuba's volpath): no
        // bounce, not a caustic's specular event (shadow rays cross it: L-thin-D is direct).
        let crossed = dir.dot(hit.normal) * ray.dir.dot(hit.normal) > 0.0;
        let null_pass = crossed && bsdf.passes_null() && scene.has_media_transport();
        medium = medium_after(scene, &hit, medium, dir);
        ray = Ray {
            origin: offset_origin(hit.position, hit.normal, dir),
            dir,
        };
        if !null_pass {
            depth += 1;
        }
    }
    PathEnds::add(&mut out.ends.cut, power);
}
