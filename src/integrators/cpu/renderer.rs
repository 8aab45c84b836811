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
        })
    }
}

impl PassRenderer for CpuRenderer<'_> {
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image> {
        let (scene, plan) = (self.scene, &self.plan);
        let mut report = RenderReport::default();
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

        let terms = Terms::of(plan.mode);
        let cache = match (&global, terms.final_gather) {
            (Some(global), true) => {
                let t = Instant::now();
                let cache =
                    RadianceCache::build(global, settings.k, settings.radius, settings.filter);
                report.phase("build cache", t);
                Some(cache)
            }
            _ => None,
        };

        let t = Instant::now();
        let g = Gatherer {
            scene,
            bvh: &self.bvh,
            lights: &self.lights,
            settings,
            global: global.as_ref(),
            caustic: caustic.as_ref(),
            terms,
            cache: cache.as_ref(),
            volume: volume.as_ref(),
            volume_spec: plan.volume,
            media: scene.has_media_transport(),
        };
        let mut image = Image::new(settings.width, settings.height);
        let bar = progress.bar(settings.height as u64, "gather");
        image
            .pixels
            .par_chunks_mut(settings.width as usize)
            .enumerate()
            .for_each(|(y, row)| {
                for (x, px) in row.iter_mut().enumerate() {
                    *px = g.pixel(x as u32, y as u32, pass).to_array();
                }
                bar.inc(1);
            });
        bar.finish_and_clear();
        report.phase("gather", t);
        report.narrowed = [&global, &caustic]
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
