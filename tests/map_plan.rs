//! The map plan builds only maps that can hold a photon the render reads: at one photon
//! bounce (a Mitsuba file's `max_depth` 2) the direct mode drops every photon, so neither map
//! is traced. Checked by tracing the maps a two-bounce plan would build with one-bounce paths.

use gpu_photon::bvh::CpuBvh;
use gpu_photon::importers::load;
use gpu_photon::integrators::cpu::photons::{trace_map, TraceContext};
use gpu_photon::integrators::plan::{MapKind, MapPlan};
use gpu_photon::lights::table::LightTable;
use gpu_photon::scene::Scene;
use gpu_photon::settings::{Mode, RenderSettings};
use std::path::Path;

fn settings(scene: &Scene, mode: Mode, bounces: u32) -> RenderSettings {
    RenderSettings {
        mode,
        max_photon_bounces: bounces,
        photons: 20_000,
        caustic_photons: 20_000,
        ..scene.settings.clone()
    }
}

/// Photons of `plan`'s maps, traced with `s`, that their map keeps.
fn kept(scene: &Scene, plan: &MapPlan, s: &RenderSettings) -> Vec<(MapKind, usize)> {
    let (bvh, lights) = (CpuBvh::build(scene), LightTable::new(scene));
    let ctx = TraceContext {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings: s,
        pass: 0,
    };
    plan.maps
        .iter()
        .map(|m| {
            let traced = trace_map(&ctx, m, plan.volume);
            let n = traced.surface.iter().filter(|p| m.filter.keeps(p)).count();
            (m.kind, n + traced.volume.len())
        })
        .collect()
}

#[test]
fn one_bounce_direct_renders_trace_no_map_that_would_stay_empty() {
    let scene = load(Path::new("scenes/cornell-caustics.toml")).expect("scene loads");
    let lights = LightTable::new(&scene);
    let two = settings(&scene, Mode::Direct, 2);
    let plan = MapPlan::new(&scene, &lights, &two);
    let kinds: Vec<MapKind> = plan.maps.iter().map(|m| m.kind).collect();
    assert_eq!(kinds, [MapKind::Global, MapKind::Caustic]);
    // Two bounces: both maps keep photons, so the count below can fail.
    for (kind, n) in kept(&scene, &plan, &two) {
        assert!(n > 0, "{kind:?}: no photon kept at two bounces");
    }
    // One bounce: the same maps would keep nothing, and the plan builds neither.
    let one = settings(&scene, Mode::Direct, 1);
    assert_eq!(
        kept(&scene, &plan, &one),
        [(MapKind::Global, 0), (MapKind::Caustic, 0)]
    );
    assert!(MapPlan::new(&scene, &lights, &one).maps.is_empty());
    // The photon mode keeps direct photons: its global map stays; no caustic at one bounce.
    let photon = MapPlan::new(&scene, &lights, &settings(&scene, Mode::Photon, 1));
    let kinds: Vec<MapKind> = photon.maps.iter().map(|m| m.kind).collect();
    assert_eq!(kinds, [MapKind::Global]);
}
