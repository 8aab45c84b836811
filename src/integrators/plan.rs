//! What a render needs, computed once from the scene and the settings before either backend
//! runs: which photon maps (and their budgets per light), and which terms a mode adds at a
//! diffuse or glossy hit. Both backends read this plan; neither re-derives it.

use crate::integrators::photon::{Budget, Photon};
use crate::lights::table::{specular_bounds, LightTable};
use crate::lights::{scalar_power, split_budget};
use crate::math::geometry::Aabb;
use crate::math::rng::Stream;
use crate::scene::Scene;
use crate::settings::{Mode, RenderSettings};

/// Pilot photons per light that estimate how often caustic emission hits the specular bounds.
pub const PILOT_PHOTONS: u32 = 4096;
/// Caustic attempts per light are capped at this multiple of its caustic photon count.
pub const MAX_AIM_FACTOR: f64 = 256.0;

/// The photon maps a render can build, in slot order: each backend keeps one slot per kind
/// (the GPU binds slot `i`'s buffers to the gather's `i`-th map bindings), so a new kind of
/// map is one more entry here, its rule in [`MapPlan::new`] and a slot in each backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// Photons stored at every hit with a diffuse part along paths traced from the lights
    /// (Russian roulette with the materials' coefficients): indirect light.
    Global = 0,
    /// L (S|G)+ D: photons emitted towards the bounds of the surfaces with a delta or glossy
    /// lobe, stored at the first diffuse hit after one or more such bounces.
    Caustic = 1,
}

impl MapKind {
    /// Every kind, in slot order.
    pub const ALL: [MapKind; 2] = [MapKind::Global, MapKind::Caustic];

    /// The random stream its paths draw from.
    pub fn stream(self) -> Stream {
        match self {
            MapKind::Global => Stream::Photon,
            MapKind::Caustic => Stream::Caustic,
        }
    }

    /// Its name in reports and device labels.
    pub fn name(self) -> &'static str {
        match self {
            MapKind::Global => "global",
            MapKind::Caustic => "caustic",
        }
    }

    /// Its search radius in a pass with settings `s` (`--radius`, `--caustic-radius`; a
    /// progressive render shrinks both per pass: `progressive::pass_settings`).
    pub fn radius(self, s: &RenderSettings) -> f32 {
        match self {
            MapKind::Global => s.radius,
            MapKind::Caustic => s.caustic_radius,
        }
    }

    /// Fraction of the storing area its photons are expected to cover: it sizes the map's
    /// first searches (the progressive first radius, the GPU grid's cells).
    pub fn area_fraction(self) -> f64 {
        match self {
            MapKind::Global => 1.0,
            MapKind::Caustic => CAUSTIC_AREA_FRACTION,
        }
    }
}

/// One photon map of a render: the paths it traces, which of their photons it keeps.
#[derive(Clone, Debug)]
pub struct MapSpec {
    /// What the map holds.
    pub kind: MapKind,
    /// Paths per light and their power.
    pub budget: Budget,
    /// The bounds its emissions aim at (emissions that miss them are not traced, and the
    /// budget's path power divides by every attempt); empty: no aim.
    pub aim: Vec<Aabb>,
    /// Which stored photons the map leaves out in this mode.
    pub filter: StoreFilter,
}

/// The volume photon map (participating media, issue 24): the photons that the global and
/// caustic maps' paths leave where they scatter in a medium, kept apart from the surface maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VolumeSpec {
    /// The global paths' L S+ V photons are left out: the caustic map's paths, aimed at the
    /// specular surfaces, carry them (volume caustics).
    pub drop_caustic: bool,
    /// The camera's beam estimate leaves out single scattering (photons of depth 0): next-event
    /// estimation from the lights does it where the mode adds direct light. Gather rays take
    /// every photon (their radiance is the whole in-scattered light).
    pub camera_skips_direct: bool,
}

/// The photon maps a render needs: only what the scene and mode use.
#[derive(Clone, Debug)]
pub struct MapPlan {
    /// The render mode the plan serves.
    pub mode: Mode,
    /// The maps, in [`MapKind`] slot order, at most one of each kind.
    pub maps: Vec<MapSpec>,
    /// The volume photon map, when the scene has a medium that scatters and some map's paths
    /// are traced.
    pub volume: Option<VolumeSpec>,
}

impl MapPlan {
    /// Plans the maps of a render of `scene` (its light tables `table`) with `s` (pilot
    /// photons included).
    ///
    /// - The global map: in every mode that estimates indirect light from photons, when the
    ///   scene has a light and some photon can stay in it (not in the direct mode when paths
    ///   end at their first bounce and no medium scatters).
    /// - The caustic map: in the modes that estimate caustics, when caustic photons are
    ///   asked for, photon paths may bounce and some surface has a delta or glossy lobe; its
    ///   attempts per light are the wanted photons divided by the fraction of pilot emissions
    ///   that hit those surfaces' bounds.
    /// - Which photons the global map drops ([`StoreFilter`]): `direct` drops direct
    ///   photons (shadow rays do that light); `photon` and `direct` drop L S+ D photons when
    ///   the caustic map carries them. `gather` keeps every photon: its radiance cache is the
    ///   whole outgoing light where gather rays land.
    pub fn new(scene: &Scene, table: &LightTable, s: &RenderSettings) -> Self {
        let uses_global = matches!(
            s.mode,
            Mode::Photon | Mode::Direct | Mode::Gather | Mode::GlobalOnly
        );
        let uses_caustic = matches!(
            s.mode,
            Mode::Photon | Mode::Direct | Mode::Gather | Mode::CausticOnly
        );
        // Paths of one bounce store only direct photons: none is a caustic, and the direct
        // mode drops them all from the global map (a Mitsuba file's max_depth 2), unless a
        // scattering medium keeps some.
        let scatters = scene.media.iter().any(|m| m.sigma_s().max_element() > 0.0);
        let one_bounce = s.max_photon_bounces <= 1;
        let uses_global = uses_global && !(one_bounce && s.mode == Mode::Direct && !scatters);
        let uses_caustic = uses_caustic && !one_bounce;
        let bounds = specular_bounds(scene);
        let caustic = (uses_caustic
            && s.caustic_photons > 0
            && !bounds.is_empty()
            && !scene.lights.is_empty())
        .then(|| {
            let powers: Vec<f64> = scene.lights.iter().map(|l| scalar_power(l.power)).collect();
            let wanted = split_budget(&powers, s.caustic_photons);
            let attempts = wanted
                .iter()
                .enumerate()
                .map(|(l, &n)| {
                    if n == 0 {
                        return 0;
                    }
                    let frac =
                        aim_fraction(scene, table, l, &bounds, s.seed).max(1.0 / MAX_AIM_FACTOR);
                    ((n as f64 / frac).ceil()).min(u32::MAX as f64 / 4.0) as u32
                })
                .collect();
            MapSpec {
                kind: MapKind::Caustic,
                budget: Budget::from_counts(scene, attempts),
                aim: bounds,
                filter: StoreFilter::default(),
            }
        });
        let global = (uses_global && !scene.lights.is_empty()).then(|| {
            let caustic_elsewhere = caustic.is_some();
            MapSpec {
                kind: MapKind::Global,
                budget: Budget::split(scene, s.photons),
                aim: vec![],
                filter: StoreFilter {
                    drop_direct: s.mode == Mode::Direct,
                    drop_caustic: caustic_elsewhere
                        && matches!(s.mode, Mode::Photon | Mode::Direct),
                },
            }
        });
        let volume = (scatters && scene.uses_media() && (global.is_some() || caustic.is_some()))
            .then_some(VolumeSpec {
                drop_caustic: caustic.is_some(),
                camera_skips_direct: Terms::of(s.mode).direct,
            });
        MapPlan {
            mode: s.mode,
            maps: global.into_iter().chain(caustic).collect(),
            volume,
        }
    }

    /// The map of kind `kind`, if the render builds one.
    pub fn map(&self, kind: MapKind) -> Option<&MapSpec> {
        self.maps.iter().find(|m| m.kind == kind)
    }

    /// Photon paths (or caustic attempts) of every map together.
    pub fn total_paths(&self) -> u64 {
        self.maps.iter().map(|m| m.budget.total() as u64).sum()
    }
}

/// Which photons of its paths a map leaves out. Both backends read this rule (the GPU as
/// drop flags).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StoreFilter {
    /// Drop photons stored at the first diffuse hit (depth 0).
    pub drop_direct: bool,
    /// Drop photons whose path was L S+ D (the caustic map carries those).
    pub drop_caustic: bool,
}

impl StoreFilter {
    /// Whether photon `p` stays in the map.
    pub fn keeps(self, p: &Photon) -> bool {
        !(self.drop_direct && p.depth() == 0) && !(self.drop_caustic && p.is_caustic())
    }
}

/// Fraction of light `l`'s emissions that enter `bounds`, from pilot photons (a
/// deterministic function of the scene and seed).
fn aim_fraction(scene: &Scene, table: &LightTable, l: usize, bounds: &[Aabb], seed: u32) -> f64 {
    use crate::math::rng::Rng;
    let hits = (0..PILOT_PHOTONS)
        .filter(|&i| {
            let mut rng = Rng::new(seed, Stream::Pilot, l as u32, i);
            let e = table.emit(
                scene,
                l,
                [rng.next(), rng.next(), rng.next(), rng.next(), rng.next()],
            );
            crate::lights::table::aims_at(bounds, e.origin, e.dir)
        })
        .count();
    hits as f64 / PILOT_PHOTONS as f64
}

/// Which terms a mode adds at a diffuse or glossy hit.
#[derive(Clone, Copy, Debug)]
pub struct Terms {
    /// Shadow rays: the kd part of area lights and the whole BRDF for delta lights (no ray
    /// sampled from a lobe can hit them).
    pub direct: bool,
    /// The glossy lobe for delta lights by shadow rays (always
    /// wanted unless a debug view).
    pub point_lobe: bool,
    /// A ray sampled from the glossy lobe (it sees area lights and everything else).
    pub lobe_ray: bool,
    /// Indirect diffuse light by one final-gather ray per camera sample that reads the
    /// radiance cache where it lands, instead of the global map's estimate at the hit.
    pub final_gather: bool,
}

impl Terms {
    /// The terms mode `mode` adds.
    pub fn of(mode: Mode) -> Self {
        match mode {
            Mode::Photon => Terms {
                direct: false,
                point_lobe: true,
                lobe_ray: true,
                final_gather: false,
            },
            Mode::Direct => Terms {
                direct: true,
                point_lobe: true,
                lobe_ray: true,
                final_gather: false,
            },
            Mode::Gather => Terms {
                direct: true,
                point_lobe: true,
                lobe_ray: true,
                final_gather: true,
            },
            Mode::DirectOnly => Terms {
                direct: true,
                point_lobe: true,
                lobe_ray: false,
                final_gather: false,
            },
            Mode::GlobalOnly | Mode::CausticOnly => Terms {
                direct: false,
                point_lobe: false,
                lobe_ray: false,
                final_gather: false,
            },
        }
    }
}

/// Radiance-cache points are the global photons whose `(id + depth) % CACHE_STRIDE == 0`
/// (`depth` = `flags & 0xff`): about one photon in four, chosen by identity so that both
/// backends cache the same photons whatever order their maps hold them in.
pub const CACHE_STRIDE: u32 = 4;
/// A cache point's value is the outgoing radiance of a white Lambertian surface there: the
/// global map's estimate at the photon (its position and normal; K nearest within the
/// global radius, or in progressive passes every photon within the pass's radius) with
/// BRDF 1/pi. A lookup at `x` with normal `n` returns the value of the nearest cache point
/// within the global radius whose normal has a cosine of at least this with `n` (ties by
/// photon id, then flags); when there is none (sparse points in dim regions), the global
/// map's estimate at `x` with normal `n` made as a point's value is. The caller multiplies
/// by its kd.
pub const CACHE_NORMAL_COS: f32 = 0.9;

/// Weight of the caustic-map estimate in camera sample `sample` of a pixel's `spp`, when the
/// estimate runs on one sample in `every` (decoupled rates, issue 10): the first
/// `ceil(spp / every)` samples run it (a prefix of the pixel's Sobol points, so they still
/// cover the pixel evenly), weighted `spp / ceil(spp / every)` so the pixel's mean is
/// unbiased; the others skip it (weight 0). `every` = 1: every sample, weight 1.
pub fn caustic_weight(spp: u32, every: u32, sample: u32) -> f32 {
    let runs = spp.div_ceil(every.max(1));
    if sample < runs {
        spp as f32 / runs as f32
    } else {
        0.0
    }
}

/// Fraction of the storing area the caustic photons are expected to cover
/// ([`MapKind::area_fraction`]).
pub const CAUSTIC_AREA_FRACTION: f64 = 0.05;

#[cfg(test)]
mod tests {
    use crate::integrators::plan::caustic_weight;

    #[test]
    fn caustic_weights_sum_to_the_sample_count() {
        for spp in [1, 2, 3, 4, 7, 16, 64, 100] {
            for every in [1, 2, 3, 4, 8, 200] {
                let w: Vec<f32> = (0..spp).map(|i| caustic_weight(spp, every, i)).collect();
                let runs = w.iter().filter(|&&x| x > 0.0).count() as u32;
                assert_eq!(runs, spp.div_ceil(every), "spp {spp} every {every}");
                // The estimating samples come first (a Sobol prefix).
                assert!(w[..runs as usize].iter().all(|&x| x > 0.0));
                let sum: f32 = w.iter().sum();
                assert!(
                    (sum - spp as f32).abs() < 1e-3 * spp as f32,
                    "{sum} vs {spp}"
                );
            }
            assert!((0..spp).all(|i| caustic_weight(spp, 1, i) == 1.0));
        }
    }
}
