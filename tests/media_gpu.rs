//! Participating media on the GPU backend (issue 24) against the CPU's twins: the free-flight
//! and Henyey-Greenstein samplers on the same random numbers, the phase density (`hg_eval`,
//! 1e-5 relative) and the interface rule (`medium_interface_after`, exactly), the media of
//! a path after a surface and at its light (`medium_after`, `light_medium`) and the grid's
//! rules (`keep_photon`, `is_cache_point`, `volume_cell`) exactly, and photon tracing
//! through fog
//! (the same paths, by the shared random-number streams, so the same volume photons and the
//! same power where they go). Tests that need a device skip without one (CI has lavapipe).

mod common;
mod probes;

use common::gpu;
use glam::{Vec2, Vec3};
use gpu_photon::bvh::{CpuBvh, Hit};
use gpu_photon::importers::load_str;
use gpu_photon::integrators::cpu::cache::is_cache_point;
use gpu_photon::integrators::cpu::media::{light_medium, medium_after};
use gpu_photon::integrators::cpu::photons::{trace_map, TraceContext, Traced};
use gpu_photon::integrators::cpu::volume_map::volume_cell;
use gpu_photon::integrators::gpu::codes::{DROP_CAUSTIC, DROP_DIRECT};
use gpu_photon::integrators::gpu::host::drop_flags;
use gpu_photon::integrators::photon::{Photon, DEPTH_MASK, FLAG_CAUSTIC};
use gpu_photon::integrators::plan::{MapPlan, StoreFilter};
use gpu_photon::lights::interface::Emission;
use gpu_photon::lights::table::LightTable;
use gpu_photon::media::{MediumInterface, NO_MEDIUM};
use gpu_photon::scene::{Scene, NO_LIGHT};
use gpu_photon::settings::RenderSettings;
use probes::media::{medium_samplers, trace_photons, MediumCase, MediumSample, TracedPhotons};
use std::collections::HashMap;
use std::path::Path;

#[test]
fn the_boundary_crossing_bound_is_the_cpus() {
    assert_eq!(
        gpu_photon::integrators::gpu::codes::MAX_CROSSINGS,
        gpu_photon::integrators::cpu::media::MAX_CROSSINGS
    );
}

/// A closed box of grey walls with a light under its ceiling, filled with fog of `albedo`
/// and `sigma_t` (coloured: each channel's flights differ) and phase `g`.
fn fog_box(sigma_t: [f32; 3], albedo: f32, g: f32) -> Scene {
    load_str(
        &fog_box_text(sigma_t, albedo, g),
        "box.toml",
        Path::new("."),
    )
    .expect("the fog box loads")
}

/// Media bounded by surfaces and lights, for the fog box: a second medium inside a glass
/// sphere (fog outside), a sphere light and a quad light holding it, a point light in the
/// fog (the camera's medium).
const BOUNDED_MEDIA: &str = r#"
[media.juice]
sigma_t = [1, 2, 4]
albedo = 0.5

[materials.glass]
type = "glass"
ior = 1.5

[[shapes]]
type = "sphere"
center = [0.5, -0.5, 0]
radius = 0.2
material = "glass"
interior = "juice"
exterior = "fog"

[[shapes]]
type = "sphere"
center = [-0.5, -0.5, 0]
radius = 0.1
emission = [1, 1, 1]
interior = "juice"

[[shapes]]
type = "quad"
corners = [[-0.2, -0.9, -0.2], [0.2, -0.9, -0.2], [0.2, -0.9, 0.2], [-0.2, -0.9, 0.2]]
emission = [1, 1, 1]
interior = "juice"

[[lights]]
type = "point"
position = [0, 0.5, 0]
intensity = [1, 1, 1]
"#;

/// The fog box's scene text.
fn fog_box_text(sigma_t: [f32; 3], albedo: f32, g: f32) -> String {
    format!(
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
    )
}

#[test]
fn device_samplers_equal_the_rust_ones_on_the_same_numbers() {
    let Some(ctx) = gpu() else { return };
    let text = fog_box_text([0.3, 1.0, 0.0], 0.8, 0.6) + BOUNDED_MEDIA;
    let scene = load_str(&text, "media.toml", Path::new(".")).unwrap();
    let m = scene.media[0].clone();
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
            // The forward peak too (g = 0.6: the density's steep side).
            cos: if i % 4 == 0 {
                1.0 - 1e-3 * r.f32()
            } else {
                r.range(-1.0, 1.0)
            },
            interface: (
                [0, 1].map(|_| [NO_MEDIUM, 0, 1][(r.f32() * 3.0) as usize]),
                [NO_MEDIUM, 0][i % 2],
                r.dir().to_array(),
            ),
            photon: photon_case(&mut r, i),
            cell: cell_case(&mut r, i),
            material_light: (
                r.next_u64() as u32 % scene.materials.len() as u32,
                (i % scene.lights.len()) as u32,
            ),
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
        // The density: the same rational expression and one sqrt, a few roundings.
        let p = m.phase.eval(c.cos);
        assert!(
            (g.density - p).abs() <= 1e-5 * p,
            "{c:?}: hg_eval {} vs {p}",
            g.density
        );
        let ([interior, exterior], current, n) = c.interface;
        let iface = MediumInterface { interior, exterior };
        let want = iface.after(current, Vec3::from(n), d);
        assert_eq!(g.after, want, "{c:?}: medium_interface_after");
        // The grid's rules, exactly (integers and bools).
        let (flags, id, drop) = c.photon;
        let p = Photon {
            flags,
            id,
            ..Default::default()
        };
        let filter = StoreFilter {
            drop_direct: drop & DROP_DIRECT != 0,
            drop_caustic: drop & DROP_CAUSTIC != 0,
        };
        assert_eq!(drop_flags(filter), drop);
        assert_eq!(g.keep, filter.keeps(&p), "{c:?}: keep_photon");
        assert_eq!(g.cache_point, is_cache_point(&p), "{c:?}: is_cache_point");
        let (x, lo, cell) = c.cell;
        let want = volume_cell(Vec3::from(x), Vec3::from(lo), cell).to_array();
        assert_eq!(g.cell, want, "{c:?}: volume_cell");
        // Which medium a path is in after a surface and when it leaves a light, exactly.
        let (material, light) = c.material_light;
        let hit = Hit {
            t: 1.0,
            position: Vec3::ZERO,
            normal: Vec3::from(n),
            shading: Vec3::from(n),
            material,
            light: NO_LIGHT,
            uv: Vec2::ZERO,
            tangent: Vec3::ZERO,
        };
        let want = medium_after(&scene, &hit, current, d);
        assert_eq!(g.medium_after, want, "{c:?}: medium_after");
        let e = Emission {
            origin: Vec3::ZERO,
            dir: d,
            normal: Vec3::from(n),
            scale: Vec3::ONE,
        };
        let want = light_medium(&scene, light as usize, &e);
        assert_eq!(g.light_medium, want, "{c:?}: light_medium");
    }
    // Both kinds of flight ends occurred.
    assert!(got.iter().any(|g| g.in_medium) && got.iter().any(|g| !g.in_medium));
    // Each rule took each of its answers: kept and dropped, cache points and others, every
    // medium after a surface and at a light (none, the fog, the juice).
    let all = |f: &dyn Fn(&MediumSample) -> u32| -> Vec<u32> {
        let mut v: Vec<u32> = got.iter().map(f).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    assert_eq!(all(&|g| g.keep as u32), [0, 1]);
    assert_eq!(all(&|g| g.cache_point as u32), [0, 1]);
    assert_eq!(all(&|g| g.medium_after), [0, 1, NO_MEDIUM]);
    assert_eq!(all(&|g| g.light_medium), [0, 1, NO_MEDIUM]);
}

/// A photon's (flags, id) and a map's drop flags: depths 0 to 3 and the deepest, caustic or
/// not, every filter.
fn photon_case(r: &mut common::TestRng, i: usize) -> (u32, u32, u32) {
    let depth = [0, 1, 2, 3, DEPTH_MASK][r.next_u64() as usize % 5];
    let caustic = if r.f32() < 0.5 { FLAG_CAUSTIC } else { 0 };
    let drop = [0, DROP_DIRECT, DROP_CAUSTIC, DROP_DIRECT | DROP_CAUSTIC][i % 4];
    (depth | caustic, r.next_u64() as u32, drop)
}

/// A point, a grid corner and a cell edge: random, or a cell corner exactly (edges of a
/// power of two, corners on multiples of 1/8: every step exact, so both sides' floors must
/// agree on the boundary) and the float just below it (the cell before).
fn cell_case(r: &mut common::TestRng, i: usize) -> ([f32; 3], [f32; 3], f32) {
    if !i.is_multiple_of(4) {
        let x = [0; 3].map(|_| r.range(-3.0, 3.0));
        let lo = [0; 3].map(|_| r.range(-2.0, 0.0));
        return (x, lo, r.range(0.05, 1.0));
    }
    let cell = [0.25, 0.5, 1.0][r.next_u64() as usize % 3];
    let lo = [0; 3].map(|_| (r.next_u64() % 17) as f32 / 8.0 - 1.0);
    let x = [0, 1, 2].map(|k| {
        let on = lo[k] + cell * ((r.next_u64() % 13) as f32 - 6.0);
        if i.is_multiple_of(8) {
            on
        } else {
            on.next_down()
        }
    });
    (x, lo, cell)
}

/// The CPU's traced photons of the plan's global map (and its volume photons).
fn cpu_trace(scene: &Scene, s: &RenderSettings) -> Traced {
    let (bvh, lights) = (CpuBvh::build(scene), LightTable::new(scene));
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
        for (s, v) in s.iter_mut().zip(p.power) {
            *s += v as f64;
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
    ctx: &gpu_photon::integrators::gpu::GpuContext,
    scene: &Scene,
    s: &RenderSettings,
) -> TracedPhotons {
    trace_photons(ctx, scene, s, 0).expect("the device traces")
}

/// 20,000 photon paths of `scene` on both backends: the same volume and surface photons
/// ([`assert_same_photons`], 2%); the device's.
fn assert_same_paths(
    ctx: &gpu_photon::integrators::gpu::GpuContext,
    scene: &Scene,
) -> TracedPhotons {
    let s = RenderSettings {
        photons: 20_000,
        ..scene.settings.clone()
    };
    let cpu = cpu_trace(scene, &s);
    let g = gpu_trace(ctx, scene, &s);
    assert_same_photons(&cpu.volume, &g.volume, "volume photons", 0.02);
    assert_same_photons(&cpu.surface, &g.surface[0], "surface photons", 0.02);
    g
}

/// Coloured fog, forward scattering: the device's photon paths are the CPU's (the same
/// random-number streams: emission, free flights, roulette, phase and surface bounces).
#[test]
fn device_photon_paths_through_fog_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let g = assert_same_paths(&ctx, &fog_box([0.6, 1.0, 1.5], 0.8, 0.4));
    // Every volume photon carries its medium's index where a surface photon's normal is.
    assert!(g.volume.iter().all(|p| p.normal == 0));
}

/// Lights inside a bounded medium (issue 41): fog inside a `null` sphere, the camera in it,
/// a point and a spot light in it and a sun outside over a floor. Their photons start in the
/// medium `enclosing_medium` finds (the sun's outside the sphere, in `Scene::outer_medium`,
/// not the camera's); the device's photon paths are the CPU's.
#[test]
fn device_photons_of_lights_in_a_bounded_medium_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let text = r#"
[camera]
eye = [0, 0, 0.5]
target = [0, 0, 0]
up = [0, 1, 0]
fov = 60.0
width = 4
height = 4
medium = "fog"

[media.fog]
sigma_t = [0.6, 1.0, 1.5]
albedo = 0.8

[materials.boundary]
type = "null"

[materials.floor]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "boundary"
interior = "fog"

[[shapes]]
type = "quad"
corners = [[-3, -1.5, 3], [3, -1.5, 3], [3, -1.5, -3], [-3, -1.5, -3]]
material = "floor"

[[lights]]
type = "point"
position = [0.2, 0.3, 0]
intensity = [1, 1, 1]

[[lights]]
type = "spot"
position = [-0.3, 0, 0.2]
direction = [0, -1, 0.3]
intensity = [2, 2, 2]
outer_angle = 40.0

[[lights]]
type = "directional"
direction = [0.3, -1, 0.2]
irradiance = [1, 1, 1]
"#;
    let scene = load_str(text, "sphere.toml", Path::new(".")).expect("the fog sphere loads");
    assert_eq!((scene.camera_medium, scene.outer_medium), (0, NO_MEDIUM));
    assert_same_paths(&ctx, &scene);
}

/// Heterogeneous fog (issue 41): a coloured 8 x 6 x 4 grid of lumpy density over the box, so
/// the majorant walk crosses cells; the device's delta-tracked photon paths are the CPU's
/// (`medium_flight`, on the same streams).
#[test]
fn device_photon_paths_through_grid_fog_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    assert_same_paths(&ctx, &grid_fog_box("media-gpu-grid-fog"));
}

/// The fog box filled by a coloured, lumpy 8 x 6 x 4 grid (its file in scratch folder `name`).
fn grid_fog_box(name: &str) -> Scene {
    let dir = common::scratch(name);
    let vol = common::vol_file([8, 6, 4], 3, |i| ((i * 7919) % 23) as f32 * 0.1);
    std::fs::write(dir.join("fog.vol"), vol).unwrap();
    let homogeneous = "[media.fog]\nsigma_t = [0.6, 1, 1.5]\nalbedo = 0.8\ng = 0.4\n";
    let text = fog_box_text([0.6, 1.0, 1.5], 0.8, 0.4);
    assert!(text.contains(homogeneous), "the fog box's medium moved");
    let grid =
        "[media.fog]\ntype = \"heterogeneous\"\nsigma_t = \"fog.vol\"\nalbedo = 0.8\ng = 0.4\n\
        bounds = [[-1, -1, -1], [1, 1, 1]]\n";
    let scene = load_str(&text.replace(homogeneous, grid), "box.toml", &dir).unwrap();
    assert!(!scene.media[0].is_homogeneous());
    scene
}

/// The volume caustic scene: the caustic map's paths store L S+ V photons (and end there),
/// the global paths leave those to them.
#[test]
fn device_volume_caustic_photons_equal_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let scene = gpu_photon::importers::load(Path::new("scenes/volume-caustic.toml")).unwrap();
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

#[test]
fn the_volume_grids_cell_sizing_is_the_cpus() {
    assert_eq!(
        gpu_photon::integrators::gpu::codes::VOLUME_PHOTONS_PER_CELL,
        gpu_photon::integrators::cpu::volume_map::PHOTONS_PER_CELL
    );
}

/// Volume photons in fog: spread through a box, a dense cluster, two media (the index in the
/// normal's word), depths 0 to 3, distinct powers and directions.
fn volume_photons(n: usize, seed: u64) -> Vec<Photon> {
    let mut r = common::TestRng(seed);
    (0..n)
        .map(|i| {
            let p = match i % 4 {
                3 => Vec3::new(0.2 + 0.05 * r.f32(), -0.1 + 0.05 * r.f32(), 0.3 * r.f32()),
                _ => Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)),
            };
            let power = Vec3::new(1.0 + r.f32(), 0.5 + r.f32(), 0.2 + r.f32()) * 1e-3;
            Photon::in_medium(
                p,
                power,
                r.dir(),
                (i % 5 == 0) as u32,
                i as u32,
                (i % 4) as u32,
                i % 7 == 0,
            )
        })
        .collect()
}

/// The device's grid lists each photon in exactly the cells its sphere's box overlaps (the
/// CPU map's rule), each entry in its cell's hash slot; its bounds are the photons' less and
/// plus r, its cell the CPU's sizing rule.
#[test]
fn device_volume_grid_lists_each_photon_in_the_cpus_cells() {
    use gpu_photon::integrators::gpu::grid::cell_hash;
    use std::collections::BTreeMap;
    let Some(ctx) = gpu() else { return };
    let (photons, r) = (volume_photons(20_000, 3), 0.04f32);
    let g = probes::media::volume_grid(&ctx, &photons, r).unwrap();
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in &photons {
        lo = lo.min(p.pos());
        hi = hi.max(p.pos());
    }
    let (lo, hi) = (lo - Vec3::splat(r), hi + Vec3::splat(r));
    assert_eq!((Vec3::from(g.lo), Vec3::from(g.hi)), (lo, hi));
    let density = photons.len() as f32 / (hi - lo).element_product();
    let want_cell = (2.0 * r).max((16.0 / density).cbrt().min(8.0 * r));
    assert!(
        (g.cell / want_cell - 1.0).abs() < 1e-5,
        "cell {} vs {want_cell}",
        g.cell
    );
    // The CPU's lists for the device's grid (its corner and cell).
    let cell_of = |x: Vec3| ((x - lo) / g.cell).floor().as_ivec3().to_array();
    let mut want: BTreeMap<[i32; 3], Vec<u32>> = BTreeMap::new();
    for (i, p) in photons.iter().enumerate() {
        let (a, b) = (
            cell_of(p.pos() - Vec3::splat(r)),
            cell_of(p.pos() + Vec3::splat(r)),
        );
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    want.entry([x, y, z]).or_default().push(i as u32);
                }
            }
        }
    }
    let mut got: BTreeMap<[i32; 3], Vec<u32>> = BTreeMap::new();
    for h in 0..g.table_size as usize {
        for k in g.cell_start[h]..g.cell_start[h + 1] {
            let (i, c) = g.entries[k as usize];
            assert_eq!(
                cell_hash(c, g.table_size) as usize,
                h,
                "entry {k} in the wrong slot"
            );
            got.entry(c).or_default().push(i);
        }
    }
    for v in got.values_mut() {
        v.sort_unstable();
    }
    assert!(want.len() > 100, "only {} cells", want.len());
    assert_eq!(got, want, "the cell lists differ");
}

/// The device's beam estimate over its grid equals the CPU's VolumeMap::beam for the same
/// photons and segments (short, long, endless, through the cluster, in either medium, with
/// and without the single-scattering photons) to 1e-4 relative.
#[test]
fn device_beam_estimate_equals_the_cpu_volume_map() {
    use gpu_photon::integrators::cpu::volume_map::VolumeMap;
    use gpu_photon::integrators::photon::BeamPhotons;
    use probes::media::{beam, BeamQuery};
    let Some(ctx) = gpu() else { return };
    let mut scene = fog_box([0.6, 1.0, 1.5], 0.8, 0.4);
    let mut other = scene.media[0].clone();
    other.phase.g = -0.3;
    other.sigma_t = Vec3::new(0.2, 0.1, 0.05);
    scene.media.push(other);
    let (photons, r) = (volume_photons(30_000, 5), 0.06f32);
    let map = VolumeMap::build(photons.clone(), r);
    let mut rng = common::TestRng(9);
    let queries: Vec<BeamQuery> = (0..512)
        .map(|i| {
            let o = Vec3::new(
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
            );
            // Every other ray aimed through the cluster.
            let d = match i % 2 {
                0 => (Vec3::new(0.22, -0.08, 0.15) - o).normalize(),
                _ => rng.dir(),
            };
            BeamQuery {
                o: o.to_array(),
                d: d.to_array(),
                t_max: match i % 3 {
                    0 => 3.0e38,
                    1 => rng.range(0.1, 1.0),
                    _ => rng.range(1.0, 4.0),
                },
                medium: (i % 5 == 1) as u32,
                photons: match i % 4 {
                    1 => BeamPhotons::SkipDirect,
                    2 => BeamPhotons::Caustic,
                    _ => BeamPhotons::All,
                },
                z: 0.0,
            }
        })
        .collect();
    let got = beam(&ctx, &scene, &photons, r, &queries).unwrap();
    let mut lit = 0;
    for (q, g) in queries.iter().zip(&got) {
        let t_max = if q.t_max >= 3.0e38 {
            f32::INFINITY
        } else {
            q.t_max
        };
        let m = &scene.media[q.medium as usize];
        let want = map.beam(
            Vec3::from(q.o),
            Vec3::from(q.d),
            t_max,
            m,
            q.medium,
            q.photons,
        );
        let g = Vec3::from(*g);
        let scale = want.max_element().max(1e-9);
        assert!(
            (g - want).abs().max_element() <= 1e-4 * scale,
            "{q:?}: {g} vs {want}"
        );
        lit += (want.max_element() > 0.0) as usize;
    }
    assert!(lit > 200, "only {lit} of the segments met photons");
}

/// The example media scenes at 32 x 32 (two progressive passes of 8 samples):
/// the GPU's image is no farther from the CPU's second seed than the CPU's first seed is
/// (common::within_seed_noise).
#[test]
fn gpu_renders_the_media_scenes_as_the_cpu_does() {
    let Some(_ctx) = gpu() else { return };
    let mut failures = Vec::new();
    for name in ["fog-cornell", "volume-caustic"] {
        let path = format!("scenes/{name}.toml");
        let scene = gpu_photon::importers::load(Path::new(&path)).unwrap();
        let s = RenderSettings {
            width: 32,
            height: 32,
            spp: 8,
            pass_range: Some((0, 2)),
            ..scene.settings.clone()
        };
        let (d, noise) = common::gpu_and_seed_diffs(&scene, &s);
        let line = format!(
            "{name}: rmse gpu-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}; mean ratio {:?}",
            d.rmse, noise.rmse, d.block_rmse, noise.block_rmse, d.mean_ratio
        );
        eprintln!("{line}");
        let (pixels, blocks) = common::within_seed_noise(&d, &noise, 1e-6);
        if !(pixels && blocks) {
            failures.push(line);
        }
    }
    assert!(
        failures.is_empty(),
        "backends disagree:\n{}",
        failures.join("\n")
    );
}

/// Heterogeneous fog (issue 41): the fog box filled by a coloured, lumpy 8 x 6 x 4 grid at
/// 16 x 16 (two passes of 4 samples, gather mode: single scattering of the area light by
/// equiangular points, the beams over replayed walks, the near gather and the gather rays'
/// free-flight points, all through ratio and delta tracking). The GPU's image is no farther
/// from the CPU's second seed than the CPU's first seed is (common::within_seed_noise).
#[test]
fn gpu_renders_grid_fog_as_the_cpu_does() {
    let Some(_ctx) = gpu() else { return };
    let scene = grid_fog_box("media-gpu-grid-render");
    let s = RenderSettings {
        width: 16,
        height: 16,
        spp: 4,
        photons: 20_000,
        pass_range: Some((0, 2)),
        ..scene.settings.clone()
    };
    let (d, noise) = common::gpu_and_seed_diffs(&scene, &s);
    eprintln!(
        "grid fog: rmse gpu-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}; mean ratio {:?}",
        d.rmse, noise.rmse, d.block_rmse, noise.block_rmse, d.mean_ratio
    );
    let (pixels, blocks) = common::within_seed_noise(&d, &noise, 1e-6);
    assert!(pixels && blocks, "the backends disagree on the grid fog");
    for c in 0..3 {
        assert!(
            (d.mean_ratio[c] - 1.0).abs() < 0.1,
            "mean ratio {:?}",
            d.mean_ratio
        );
    }
}

/// Same seed, same backend, the same image: two GPU renders of each media scene are the same
/// bits. The volume grid lists photons through atomics, in an order that varies from run to
/// run; the beam and point estimates sum in fixed point so that it does not show.
#[test]
fn gpu_media_renders_repeat_bit_for_bit() {
    use gpu_photon::render::report::Progress;
    use gpu_photon::render::session::{render, Backend};
    let Some(_ctx) = gpu() else { return };
    for name in ["fog-cornell", "volume-caustic"] {
        let scene = gpu_photon::importers::load(Path::new(&format!("scenes/{name}.toml"))).unwrap();
        let s = RenderSettings {
            width: 24,
            height: 24,
            spp: 2,
            pass_range: Some((0, 1)),
            seed: 3,
            ..scene.settings.clone()
        };
        let once = || {
            render(&scene, &s, Backend::Gpu, Progress::default())
                .unwrap()
                .0
        };
        let (a, b) = (once(), once());
        let differ = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| p.map(f32::to_bits) != q.map(f32::to_bits))
            .count();
        assert_eq!(
            differ, 0,
            "{name}: {differ} pixels differ between two renders"
        );
    }
}
