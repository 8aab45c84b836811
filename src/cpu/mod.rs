//! The CPU backend: rayon over photon paths and image rows, kiddo kd-trees for the K nearest
//! photons. It is the fallback and the reference the GPU backend is tested against.

pub mod gather;
pub mod photon_map;
pub mod photons;

use crate::bvh::Bvh;
use crate::film::Image;
use crate::light::LightTable;
use crate::photon::Photon;
use crate::plan::MapPlan;
use crate::plan::Terms;
use crate::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use gather::Gatherer;
use photon_map::PhotonMap;
use photons::TraceContext;
use rayon::prelude::*;
use std::time::Instant;

/// Renders `scene` with one photon pass (`pass`) on the CPU.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    pass: u32,
    progress: &Progress,
) -> (Image, RenderReport) {
    let mut report = RenderReport::default();
    let t = Instant::now();
    let bvh = Bvh::build(scene);
    let lights = LightTable::new(scene);
    report.phase("build BVH", t);

    let plan = MapPlan::new(scene, settings);
    let ctx = TraceContext {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings,
        pass,
    };
    let t = Instant::now();
    let global = plan.global.as_ref().map(|budget| {
        let photons = photons::trace_photons(&ctx, budget);
        report.global_stored = photons.len();
        let kept: Vec<Photon> = photons
            .into_iter()
            .filter(|p| plan.keep_in_global(p))
            .collect();
        kept
    });
    let caustic = plan.caustic.as_ref().map(|(budget, bounds)| {
        let photons = photons::trace_caustic_photons(&ctx, budget, bounds);
        report.caustic_stored = photons.len();
        photons
    });
    report.phase("trace photons", t);

    let t = Instant::now();
    let global = global.map(PhotonMap::build);
    let caustic = caustic.map(PhotonMap::build);
    report.phase("build kd-trees", t);

    let t = Instant::now();
    let g = Gatherer {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings,
        global: global.as_ref(),
        caustic: caustic.as_ref(),
        terms: Terms::of(settings.mode),
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
    (image, report)
}
