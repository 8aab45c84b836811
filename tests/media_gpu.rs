//! Participating media on the GPU backend (issue 24) against the CPU's twins: the free-flight
//! and Henyey-Greenstein samplers on the same random numbers, and photon tracing through fog
//! (the same paths, by the shared random-number streams, so the same volume photons and the
//! same power where they go). Tests that need a device skip without one (CI has lavapipe).

mod common;

use common::gpu;
use glam::Vec3;
use gpu_photon::bvh::Bvh;
use gpu_photon::cpu::photons::{trace_map, TraceContext, Traced};
use gpu_photon::gpu::probe_media::{medium_samplers, trace_photons, MediumCase, TracedPhotons};
use gpu_photon::light::LightTable;
use gpu_photon::photon::Photon;
use gpu_photon::plan::MapPlan;
use gpu_photon::scene::{load_str, Scene};
use gpu_photon::settings::RenderSettings;
use std::collections::HashMap;
use std::path::Path;

#[test]
fn the_boundary_crossing_bound_is_the_cpus() {
    assert_eq!(
        gpu_photon::gpu::codes::MAX_CROSSINGS,
        gpu_photon::cpu::media::MAX_CROSSINGS
    );
}

/// A closed box of grey walls with a light under its ceiling, filled with fog of `albedo`
/// and `sigma_t` (coloured: each channel's flights differ) and phase `g`.
fn fog_box(sigma_t: [f32; 3], albedo: f32, g: f32) -> Scene {
    let text = format!(
        r#"
[camera]
eye = [0, 0, 0.5]
target = [0, 0, 0]
up = [0, 1, 0]
fov = 60.0
width = 4
height = 4
medium = "fog"

[render]
max_photon_bounces = 16

[media.fog]
sigma_t = [{}, {}, {}]
albedo = {albedo}
g = {g}

[materials.wall]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]

[[shapes]]
type = "box"
min = [-1, -1, -1]
max = [1, 1, 1]
material = "wall"

[[shapes]]
type = "quad"
corners = [[-0.2, 0.95, -0.2], [0.2, 0.95, -0.2], [0.2, 0.95, 0.2], [-0.2, 0.95, 0.2]]
emission = [5, 5, 5]
"#,
        sigma_t[0], sigma_t[1], sigma_t[2]
    );
    load_str(&text, "box.toml", Path::new(".")).expect("the fog box loads")
}

#[test]
fn device_samplers_equal_the_rust_ones_on_the_same_numbers() {
    let Some(ctx) = gpu() else { return };
    let scene = fog_box([0.3, 1.0, 0.0], 0.8, 0.6);
    let m = scene.media[0];
    let mut r = common::TestRng(11);
    let cases: Vec<MediumCase> = (0..2000)
        .map(|i| MediumCase {
            u_channel: r.f32(),
            u: r.f32(),
            // Some surfaces near, some far, some misses.
            t_max: match i % 3 {
                0 => 0.3 + r.f32(),
                1 => 5.0 * r.f32(),
                _ => 3.0e38,
            },
            dir: r.dir().to_array(),
            u_phase: [r.f32(), r.f32()],
        })
        .collect();
    let got = medium_samplers(&ctx, &scene, &cases).unwrap();
    for (c, g) in cases.iter().zip(&got) {
        let t_max = if c.t_max > 1e30 {
            f32::INFINITY
        } else {
            c.t_max
        };
        let want = m.sample_flight(c.u_channel, c.u, t_max);
        assert_eq!(g.in_medium, want.in_medium, "{c:?}: {g:?} vs {want:?}");
        if want.in_medium {
            assert!(
                (g.t - want.t).abs() <= 1e-5 * want.t.max(1.0),
                "{c:?}: {g:?}"
            );
        }
        let w = Vec3::from(g.weight);
        let rel = (w - want.weight).abs().max_element() / want.weight.max_element().max(1e-6);
        assert!(rel < 1e-4, "{c:?}: weight {w} vs {}", want.weight);
        let d = Vec3::from(c.dir);
        let s = m.phase.sample(d, c.u_phase[0], c.u_phase[1]);
        let gs = Vec3::from(g.scattered);
        assert!((gs - s).abs().max_element() < 1e-4, "{c:?}: {gs} vs {s}");
    }
    // Both kinds of flight ends occurred.
    assert!(got.iter().any(|g| g.in_medium) && got.iter().any(|g| !g.in_medium));
}

/// The CPU's traced photons of the plan's global map (and its volume photons).
fn cpu_trace(scene: &Scene, s: &RenderSettings) -> Traced {
    let (bvh, lights) = (Bvh::build(scene), LightTable::new(scene));
    let plan = MapPlan::new(scene, &lights, s);
    let ctx = TraceContext {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings: s,
        pass: 0,
    };
    let mut all = Traced::default();
    for spec in &plan.maps {
        let t = trace_map(&ctx, spec, plan.volume);
        all.surface.extend(t.surface);
        all.volume.extend(t.volume);
    }
    all
}

fn power_sum(photons: &[Photon]) -> [f64; 3] {
    let mut s = [0.0f64; 3];
    for p in photons {
        for c in 0..3 {
            s[c] += p.power[c] as f64;
        }
    }
    s
}

/// The device's photons against the CPU's of the same paths: by (path, depth, caustic flag)
/// nearly all the same, at the same places with the same power, and the power sums within
/// `tol` relative (the few paths whose float rounding sent them another way).
fn assert_same_photons(cpu: &[Photon], gpu: &[Photon], what: &str, tol: f64) {
    assert!(!cpu.is_empty(), "{what}: the CPU stored none");
    let key = |p: &Photon| (p.id, p.flags);
    let by_key: HashMap<(u32, u32), &Photon> = cpu.iter().map(|p| (key(p), p)).collect();
    let mut same = 0usize;
    for g in gpu {
        if let Some(c) = by_key.get(&key(g)) {
            let dp = (Vec3::from(g.position) - Vec3::from(c.position)).length();
            let pw = (Vec3::from(g.power) - Vec3::from(c.power))
                .abs()
                .max_element();
            if dp < 1e-3 && pw <= 1e-3 * Vec3::from(c.power).max_element() && g.normal == c.normal {
                same += 1;
            }
        }
    }
    let frac = same as f64 / cpu.len() as f64;
    assert!(
        frac > 0.98 && gpu.len().abs_diff(cpu.len()) * 50 < cpu.len(),
        "{what}: {same} of the CPU's {} photons the same on the device ({} stored there)",
        cpu.len(),
        gpu.len()
    );
    let (a, b) = (power_sum(cpu), power_sum(gpu));
    for c in 0..3 {
        assert!(
            (a[c] - b[c]).abs() <= tol * a[c].abs().max(1e-12),
            "{what}: power sums {a:?} (CPU) vs {b:?} (GPU)"
        );
    }
}

fn gpu_trace(
    ctx: &gpu_photon::gpu::GpuContext,
    scene: &Scene,
    s: &RenderSettings,
) -> TracedPhotons {
    trace_photons(ctx, scene, s, 0).expect("the device traces")
}

/// Coloured fog, forward scattering: the device's photon paths are the CPU's (the same
/// random-number streams: emission, free flights, roulette, phase and surface bounces).
#[test]
fn device_photon_paths_through_fog_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let scene = fog_box([0.6, 1.0, 1.5], 0.8, 0.4);
    let s = RenderSettings {
        photons: 20_000,
        ..scene.settings.clone()
    };
    let cpu = cpu_trace(&scene, &s);
    let g = gpu_trace(&ctx, &scene, &s);
    assert_same_photons(&cpu.volume, &g.volume, "volume photons", 0.02);
    assert_same_photons(&cpu.surface, &g.surface[0], "surface photons", 0.02);
    // Every volume photon carries its medium's index where a surface photon's normal is.
    assert!(g.volume.iter().all(|p| p.normal == 0));
}

/// The volume caustic scene: the caustic map's paths store L S+ V photons (and end there),
/// the global paths leave those to them.
#[test]
fn device_volume_caustic_photons_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let scene = gpu_photon::scene::load(Path::new("scenes/volume-caustic.toml")).unwrap();
    let s = RenderSettings {
        photons: 20_000,
        caustic_photons: 20_000,
        pass_range: None,
        ..scene.settings.clone()
    };
    let cpu = cpu_trace(&scene, &s);
    let g = gpu_trace(&ctx, &scene, &s);
    let caustic =
        |v: &[Photon]| -> Vec<Photon> { v.iter().filter(|p| p.is_caustic()).copied().collect() };
    let diffuse =
        |v: &[Photon]| -> Vec<Photon> { v.iter().filter(|p| !p.is_caustic()).copied().collect() };
    assert!(
        !caustic(&cpu.volume).is_empty(),
        "no volume caustic photon on the CPU"
    );
    assert_same_photons(
        &caustic(&cpu.volume),
        &caustic(&g.volume),
        "L S+ V photons",
        0.03,
    );
    assert_same_photons(
        &diffuse(&cpu.volume),
        &diffuse(&g.volume),
        "other volume photons",
        0.03,
    );
}
