//! The CPU renderer of a session: the BVH, the light table and the photon plan (with its
//! pilot photons) built once per render, then each pass traces its photons, builds its
//! kd-trees (and in `gather` mode the radiance cache over the global map) and gathers every
//! pixel.

use crate::bvh::CpuBvh;
use crate::error::Result;
use crate::integrators::cpu::cache::RadianceCache;
use crate::integrators::cpu::gather::Gatherer;
use crate::integrators::cpu::photon_map::PhotonMap;
use crate::integrators::cpu::photons::{trace_map, TraceContext};
use crate::integrators::cpu::volume_map::VolumeMap;
use crate::integrators::photon::Photon;
use crate::integrators::plan::{MapPlan, Terms};
use crate::lights::table::LightTable;
use crate::render::adaptive;
use crate::render::film::Image;
use crate::render::report::{PassRenderer, Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use rayon::prelude::*;
use std::time::Instant;

/// Renders passes of one scene on the CPU; what does not change from pass to pass is built
/// once in `new`.
pub struct CpuRenderer<'s> {
    scene: &'s Scene,
    bvh: CpuBvh,
    lights: LightTable,
    /// Built from the render's settings: a pass's settings differ only in `k` and the radii,
    /// which the plan does not read.
    plan: MapPlan,
    report: RenderReport,
    /// The render's settings (a pass's come from them, `progressive::pass_settings`).
    settings: RenderSettings,
    /// Adaptive sampling's camera samples per pixel, from pass 0's pilots
    /// (`crate::render::adaptive`), once the first pass has them.
    counts: Option<Vec<u32>>,
}

/// A pass's photon maps, its volume map and radiance cache, as the plan asks for them.
struct PassMaps {
    global: Option<PhotonMap>,
    caustic: Option<PhotonMap>,
    volume: Option<VolumeMap>,
    cache: Option<RadianceCache>,
}

impl<'s> CpuRenderer<'s> {
    /// Builds the BVH, the light table and the photon plan of `scene` for a render with
    /// `settings`.
    pub fn new(scene: &'s Scene, settings: &RenderSettings) -> Result<Self> {
        let mut report = RenderReport {
            backend: format!("cpu ({} threads)", rayon::current_num_threads()),
            ..Default::default()
        };
        let t = Instant::now();
        let bvh = CpuBvh::build(scene);
        let lights = LightTable::new(scene);
        report.phase("build BVH", t);
        let plan = MapPlan::new(scene, &lights, settings);
        Ok(CpuRenderer {
            scene,
            bvh,
            lights,
            plan,
            report,
            settings: settings.clone(),
            counts: None,
        })
    }
}

impl CpuRenderer<'_> {
    /// Traces pass `pass`'s photons and builds its maps (and in `gather` mode the radiance
    /// cache over the global map).
    fn maps(&self, pass: u32, settings: &RenderSettings, report: &mut RenderReport) -> PassMaps {
        let (scene, plan) = (self.scene, &self.plan);
        let ctx = TraceContext {
            scene,
            bvh: &self.bvh,
            lights: &self.lights,
            settings,
            pass,
        };
        // One slot per map kind (crate::integrators::plan::MapKind), built as the plan lists them.
        let t = Instant::now();
        let mut traced: [Option<Vec<Photon>>; 2] = Default::default();
        let mut volume_photons = Vec::new();
        for spec in &plan.maps {
            let photons = trace_map(&ctx, spec, plan.volume);
            *report.stored_mut(spec.kind) = photons.surface.len();
            let kept = photons.surface.into_iter().filter(|p| spec.filter.keeps(p));
            traced[spec.kind as usize] = Some(kept.collect());
            volume_photons.extend(photons.volume);
        }
        report.volume_stored = volume_photons.len();
        report.phase("trace photons", t);

        let t = Instant::now();
        // Fixed-radius passes bound each search's work by the map's density table.
        let radii = [settings.radius, settings.caustic_radius];
        let mut built = traced.into_iter().zip(radii).map(|(p, r)| {
            p.map(|p| match settings.k {
                0 => PhotonMap::build_bounded(p, r),
                _ => PhotonMap::build(p),
            })
        });
        let (global, caustic) = (built.next().flatten(), built.next().flatten());
        report.phase("build kd-trees", t);
        let volume = plan.volume.map(|_| {
            let t = Instant::now();
            let map = VolumeMap::build(volume_photons, settings.volume_radius);
            report.phase("build volume grid", t);
            map
        });
        let cache = match (&global, Terms::of(plan.mode).final_gather) {
            (Some(global), true) => {
                let t = Instant::now();
                let cache =
                    RadianceCache::build(global, settings.k, settings.radius, settings.filter);
                report.phase("build cache", t);
                Some(cache)
            }
            _ => None,
        };
        PassMaps {
            global,
            caustic,
            volume,
            cache,
        }
    }

    /// The camera pass's reader of `maps` with `settings`.
    fn gatherer<'a>(&'a self, settings: &'a RenderSettings, maps: &'a PassMaps) -> Gatherer<'a> {
        Gatherer {
            scene: self.scene,
            bvh: &self.bvh,
            lights: &self.lights,
            settings,
            global: maps.global.as_ref(),
            caustic: maps.caustic.as_ref(),
            terms: Terms::of(self.plan.mode),
            cache: maps.cache.as_ref(),
            volume: maps.volume.as_ref(),
            volume_spec: self.plan.volume,
            media: self.scene.has_media_transport(),
        }
    }

    /// Adaptive sampling's counts (`crate::render::adaptive`): two pilot images of pass 0 over
    /// pass 0's maps (`maps` when this pass is pass 0, else traced again here, so that a
    /// range of passes rendered on its own gets the counts of the whole render).
    fn adaptive_counts(&self, pass: u32, maps: &PassMaps, report: &mut RenderReport) -> Vec<u32> {
        let settings = self.pass_zero();
        let zero;
        let maps = if pass == 0 {
            maps
        } else {
            zero = self.maps(0, &settings, &mut RenderReport::default());
            &zero
        };
        let t = Instant::now();
        let pilot = |half: u32| {
            let s = RenderSettings {
                spp: adaptive::PILOT_SPP,
                seed: adaptive::pilot_seed(settings.seed, half),
                adaptive: 1,
                ..settings.clone()
            };
            let g = self.gatherer(&s, maps);
            rows(&s, None, |x, y| g.pixel(x, y, 0))
        };
        let counts = adaptive::sample_counts(&pilot(0), &pilot(1), settings.spp, settings.adaptive);
        report.phase("adaptive pilot", t);
        counts
    }

    /// Pass 0's settings (those of the render when it is one classic pass), `adaptive`
    /// resolved.
    fn pass_zero(&self) -> RenderSettings {
        let s = match self.settings.pass_range {
            Some(_) => crate::render::progressive::pass_settings(self.scene, &self.settings, 0),
            None => self.settings.clone(),
        };
        RenderSettings {
            adaptive: adaptive::resolve(&s),
            ..s
        }
    }
}

impl PassRenderer for CpuRenderer<'_> {
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image> {
        let settings = &RenderSettings {
            adaptive: adaptive::resolve(settings),
            ..settings.clone()
        };
        let mut report = RenderReport::default();
        let maps = self.maps(pass, settings, &mut report);
        if settings.adaptive > 1 && self.counts.is_none() {
            self.counts = Some(self.adaptive_counts(pass, &maps, &mut report));
        }
        let g = self.gatherer(settings, &maps);
        let t = Instant::now();
        let bar = progress.bar(settings.height as u64, "gather");
        let image = rows(settings, Some(&bar), |x, y| match &self.counts {
            Some(n) => g.pixel_samples(x, y, pass, n[(y * settings.width + x) as usize]),
            None => g.pixel(x, y, pass),
        });
        bar.finish_and_clear();
        report.phase("gather", t);
        report.narrowed = [&maps.global, &maps.caustic]
            .iter()
            .filter_map(|m| m.as_ref().map(PhotonMap::narrowed))
            .sum();
        self.report.absorb(&report);
        Ok(image)
    }

    fn report(&mut self) -> Result<RenderReport> {
        Ok(self.report.clone())
    }
}

/// The image of `s`'s size whose pixel (x, y) is `pixel(x, y)`, rows in parallel, `bar`
/// advanced by one a row.
fn rows(
    s: &RenderSettings,
    bar: Option<&indicatif::ProgressBar>,
    pixel: impl Fn(u32, u32) -> glam::Vec3 + Sync,
) -> Image {
    let mut image = Image::new(s.width, s.height);
    image
        .pixels
        .par_chunks_mut(s.width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, px) in row.iter_mut().enumerate() {
                *px = pixel(x as u32, y as u32).to_array();
            }
            if let Some(bar) = bar {
                bar.inc(1);
            }
        });
    image
}
