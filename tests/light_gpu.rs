//! Oracle test of the lights' device functions (src/lights/light.wgsl, photon.wgsl)
//! against src/lights/mod.rs and src/integrators/photon.rs, through the probe `tests/probes/probe_light.wgsl`
//! (`gpu::probe_light`): for every light kind (point, glTF and linear-angle spots, a spot
//! projecting an image, projectors with an image and without, directional, a one-sided box of 12 triangles of three sizes, a two-sided quad, a sphere,
//! an image environment) the photon emission (origin, direction, normal, power scale) and the
//! shadow-ray sample (point, weight, distant, pdf) and whether it is a delta light
//! (`is_delta_light`, exactly) on the same random numbers, with the
//! triangle picked exactly at, just below and just above every CDF value, and whether the
//! emission aims at the caustic map's bounds; the light that owns each photon path of both
//! maps (the device scans the lights, the host bisects their offsets: identical for every
//! path, so at every boundary); and the end of a path whose power is spent (zero, negative,
//! NaN, infinite).
//! Tolerances: `ABS`, `REL`, the linear-angle spot's `LINEAR_ABS`, `LINEAR_REL` and the image
//! environment's `ENV_REL` (each with its measured worst case on lavapipe).
//! Without a Vulkan adapter the test is skipped (CI fails instead, see common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::Vec3;
use gpu_photon::importers::load_str;
use gpu_photon::integrators::photon::power_ends;
use gpu_photon::integrators::plan::{MapKind, MapPlan};
use gpu_photon::lights::interface::LightSample;
use gpu_photon::lights::spot::SpotFalloff;
use gpu_photon::lights::table::{aims_at, LightTable};
use gpu_photon::scene::{LightShape, Scene};
use gpu_photon::settings::RenderSettings;
use probes::light::{LightCase, SceneProbes};
use std::path::Path;

/// Every light kind the scene format has, over a floor, with a glass sphere (so that a
/// caustic map is planned) and a black light (no photon paths: a light of zero power).
const SCENE: &str = r#"
[camera]
eye = [0.0, 1.0, 6.0]
target = [0.0, 0.5, 0.0]
fov = 40.0

[materials.white]
type = "diffuse"
albedo = [0.7, 0.7, 0.7]

[materials.glass]
type = "glass"
ior = 1.5

[[shapes]]
type = "quad"
corners = [[-3.0, 0.0, 3.0], [3.0, 0.0, 3.0], [3.0, 0.0, -3.0], [-3.0, 0.0, -3.0]]
material = "white"

[[shapes]]
type = "sphere"
center = [0.0, 0.5, 0.0]
radius = 0.5
material = "glass"

[[lights]]
type = "point"
position = [1.0, 2.0, 0.5]
intensity = [3.0, 2.0, 1.0]

[[lights]]
type = "point"
position = [-1.0, 2.0, 0.5]
intensity = [0.0, 0.0, 0.0]

[[lights]]
type = "spot"
position = [0.0, 2.5, 1.0]
target = [0.0, 0.0, 0.0]
intensity = [5.0, 5.0, 5.0]
inner_angle = 15.0
outer_angle = 30.0

[[lights]]
type = "spot"
position = [0.5, 2.5, -1.0]
target = [0.0, 0.0, 0.0]
intensity = [4.0, 5.0, 6.0]
inner_angle = 10.0
outer_angle = 40.0
falloff = "linear-angle"

[[lights]]
type = "spot"
position = [-0.5, 2.5, 0.5]
target = [0.0, 0.0, 0.0]
intensity = [6.0, 5.0, 4.0]
inner_angle = 10.0
outer_angle = 35.0
filename = "mitsuba-suite/common/textures/flower.bmp"
up = [0.0, 0.0, 1.0]

[[lights]]
type = "projector"
position = [0.3, 3.0, 0.2]
target = [0.0, 0.0, 0.0]
fov = 60.0
scale = 2.0
filename = "mitsuba-suite/common/textures/carrot.png"

[[lights]]
type = "projector"
position = [-0.2, 3.5, 0.5]
direction = [0.1, -1.0, -0.2]
up = [1.0, 0.0, 0.0]
fov = 110.0
irradiance = [1.0, 2.0, 3.0]

[[lights]]
type = "directional"
direction = [-1.0, -0.6, -0.8]
irradiance = [0.6, 0.65, 0.8]

[[shapes]]
type = "box"
min = [-2.0, 2.0, -2.0]
max = [-1.9, 2.3, -1.0]
material = "white"
emission = [4.0, 3.0, 2.0]

[[shapes]]
type = "quad"
corners = [[1.0, 2.5, -1.0], [1.5, 2.5, -1.0], [1.5, 2.6, -0.5], [1.0, 2.6, -0.5]]
material = "white"
emission = [2.0, 2.0, 3.0]
two_sided = true

[[shapes]]
type = "sphere"
center = [2.0, 1.5, 1.0]
radius = 0.2
material = "white"
emission = [5.0, 4.0, 4.0]

[environment]
filename = "envlight.exr"
scale = 0.5
"#;

fn scene() -> Scene {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    load_str(SCENE, "lights.toml", &data).expect("the light scene loads")
}

/// Worst errors seen, per light kind and quantity, in units of their bounds (for the report).
#[derive(Default, Debug)]
struct Worst(Vec<(String, f32)>);

/// One comparison's context: the case, its light kind's name and tolerances.
struct At<'a> {
    case: usize,
    kind: &'a str,
    abs: f32,
    rel: f32,
}

impl Worst {
    /// `got` equals `want` within `at.abs` (positions, directions) or `at.rel |want|` (weights,
    /// scales, pdfs) per component; records the error in units of that bound.
    fn check(&mut self, what: &str, at: &At, got: Vec3, want: Vec3, relative: bool) {
        let bound = if relative {
            1e-30 + at.rel * want.abs()
        } else {
            Vec3::splat(at.abs)
        };
        let e = ((got - want).abs() / bound).max_element();
        assert!(
            e <= 1.0,
            "case {} ({}): {what}: device {got} host {want} (error {e} x the bound)",
            at.case,
            at.kind
        );
        let key = format!("{} {what}", at.kind);
        match self.0.iter_mut().find(|(w, _)| *w == key) {
            Some((_, m)) => *m = m.max(e),
            None => self.0.push((key, e)),
        }
    }
}

/// Absolute tolerance on unit vectors and on positions in this scene (|p| < 7): the device's
/// sin, cos and sqrt are within a few ulp (a few 1e-7), and a direction from `to_world` or
/// the disc's basis adds a few more roundings; a glTF spot's cosine inverted from its
/// falloff (a cube root) amplifies that near the cone's edge. Measured worst on lavapipe:
/// 1.2e-7 (a sphere light's point) and 9.5e-7 (a directional photon's origin).
const ABS: f32 = 1e-5;
/// Relative tolerance on weights, pdfs and scales: the same functions, divided by d^2 and
/// cosines (relative errors add: a few 1e-7 each). Measured worst: 4.2e-6 (a glTF spot's
/// weight, its falloff squared near the edge).
const REL: f32 = 1e-5;
/// Mitsuba's linear-angle spot goes through acos (its falloff, and the bisection of its
/// ramp's mass back to a cosine): lavapipe's acos is good to ~3e-5 rad only (Vulkan bounds
/// it by its atan2 formula's error, not in ulp), which the ramp's slope 1 / (outer - inner)
/// turns into up to 1.3e-4 relative in the weight and 6.4e-5 in an emitted direction
/// (measured). Its bounds: 2e-4 absolute, 5e-4 relative.
const LINEAR_ABS: f32 = 2e-4;
const LINEAR_REL: f32 = 5e-4;
/// The image environment's radiance and density are looked up at a direction's latitude and
/// longitude, through atan2 and acos: lavapipe's differ from Rust's by up to ~1e-4 rad
/// (Vulkan allows 4096 ulp), and this image's sharp edges (a rendered room with its light)
/// turn that into up to 6.2e-3 relative in a photon's power scale and a shadow sample's
/// weight (measured; the same at the device's own directions, so not the sampled direction's
/// error). Its directions and points keep `ABS`; what comes from the lookup is held to 2e-2
/// relative (tests/environment.rs bounds the lookup itself by its range over nearby
/// directions).
const ENV_REL: f32 = 2e-2;
/// A projecting spot's and a projector's image: looked up (bilinearly) at a uv from the
/// direction, whose few-ulp difference between the device and the host moves the lookup by
/// ~1e-6 of the image: on an 8-bit image's sharp edges that is up to ~1e-4 of a texel's
/// value relative to a dark neighbour's. Measured worst on lavapipe: 6.7e-5 (a projecting
/// spot's photon scale); bound 1e-3.
const IMAGE_REL: f32 = 1e-3;

/// The photon budgets of the paths' test (both maps planned).
fn settings() -> RenderSettings {
    RenderSettings {
        photons: 20_000,
        caustic_photons: 5_000,
        ..Default::default()
    }
}

/// The probed scene has a light of every kind of the list (`lights::KINDS`), so a new kind
/// is compared with its Rust twin once it is in the scene format.
#[test]
fn every_light_kind_is_probed() {
    let scene = scene();
    for (code, kind) in gpu_photon::lights::KINDS.iter().enumerate() {
        assert!(
            scene.lights.iter().any(|l| l.shape.code() as usize == code),
            "no {} light in the probed scene",
            kind.name
        );
    }
}

/// Both checks on one upload of the scene (its pipelines compile once: most of the time).
#[test]
fn device_lights_equal_the_hosts() {
    let Some(ctx) = gpu() else { return };
    let scene = scene();
    let mut probes = SceneProbes::new(&ctx, &scene, &settings()).unwrap();
    emission_and_shadow_samples_equal_the_hosts(&scene, &mut probes);
    every_path_has_the_hosts_light_and_spent_powers_end(&scene, &mut probes);
}

fn emission_and_shadow_samples_equal_the_hosts(scene: &Scene, probes: &mut SceneProbes) {
    let table = LightTable::new(scene);
    let plan = MapPlan::new(scene, &table, &settings());
    let aim = &plan.map(MapKind::Caustic).expect("a caustic map").aim;
    let mut n_aimed = 0;
    let mut r = TestRng(0x1167);
    let mut cases = Vec::new();
    for (l, light) in scene.lights.iter().enumerate() {
        let mut us: Vec<f32> = (0..200).map(|_| r.f32()).collect();
        us.extend([0.0, 0.5, 1.0 - f32::EPSILON / 2.0]);
        // A triangle light: u0 at, below and above every value of its CDF.
        if let LightShape::Triangles(gpu_photon::lights::triangles::Triangles { count, .. }) =
            light.shape
        {
            let start = table.cdf_start[l] as usize;
            for &c in &table.tri_cdf[start..start + count as usize] {
                us.extend(
                    [c, c.next_down(), c.next_up()]
                        .into_iter()
                        .filter(|u| *u < 1.0),
                );
            }
        }
        for u0 in us {
            let x = Vec3::new(r.range(-2.5, 2.5), r.range(0.0, 3.0), r.range(-2.5, 2.5));
            cases.push(LightCase {
                light: l as u32,
                u: [u0, r.f32(), r.f32(), r.f32(), r.f32()],
                x: x.to_array(),
                ns: r.dir().to_array(),
            });
        }
    }
    let got = probes.lights(&cases).unwrap();
    let mut worst = Worst::default();
    let mut kinds = std::collections::BTreeMap::new();
    let mut lit = std::collections::BTreeMap::new();
    for (i, (c, g)) in cases.iter().zip(&got).enumerate() {
        let l = c.light as usize;
        let v = Vec3::from_array;
        let kind = kind_of(&scene.lights[l].shape);
        assert_eq!(
            g.delta,
            scene.lights[l].shape.is_delta(),
            "case {i} ({kind}): is_delta_light"
        );
        let linear = kind == "spot linear-angle";
        let at = At {
            case: i,
            kind,
            abs: if linear { LINEAR_ABS } else { ABS },
            rel: match kind {
                "spot linear-angle" => LINEAR_REL,
                "spot projecting" | "projector image" => IMAGE_REL,
                "environment" => ENV_REL,
                _ => REL,
            },
        };
        *kinds.entry(kind).or_insert(0) += 1;
        let e = table.emit(scene, l, c.u);
        worst.check("emit origin", &at, v(g.origin), e.origin, false);
        worst.check("emit dir", &at, v(g.dir), e.dir, false);
        worst.check("emit normal", &at, v(g.normal), e.normal, false);
        worst.check("emit scale", &at, v(g.scale), e.scale, true);
        // The caustic map's aim, for the device's own emission.
        let aims = aims_at(aim, v(g.origin), v(g.dir));
        assert_eq!(
            g.aims, aims,
            "case {i}: aims_at({:?}, {:?})",
            g.origin, g.dir
        );
        n_aimed += aims as usize;
        let (x, ns) = (v(c.x), v(c.ns));
        let s = table.sample(scene, l, x, ns, [c.u[0], c.u[3], c.u[4]]);
        if let LightShape::Triangles(_) = scene.lights[l].shape {
            let want = table.pick_triangle(scene, l, c.u[0]) as u32;
            assert_eq!(
                g.triangle,
                Some(want),
                "case {i}: the triangle for u0 = {}",
                c.u[0]
            );
        } else {
            assert_eq!(g.triangle, None);
        }
        assert_eq!(g.distant, s.distant, "case {i}: distant");
        // A distant sample's point is x plus a unit direction: compared as a direction.
        worst.check("sample point", &at, v(g.point), s.point, false);
        worst.check("sample weight", &at, v(g.weight), s.weight, true);
        *lit.entry(kind).or_insert(0) += (s.weight != Vec3::ZERO) as usize;
        let pdf = host_pdf(scene, &table, l, x, ns, &s);
        worst.check(
            "sample pdf",
            &at,
            Vec3::splat(g.pdf),
            Vec3::splat(pdf),
            true,
        );
    }
    // The lights with an edge (the cones, the projectors' images) light some of the random
    // points and leave others dark: both sides of the edge are compared.
    let edged = lit
        .iter()
        .filter(|(k, _)| k.starts_with("spot") || k.starts_with("projector"));
    for (kind, n) in edged {
        let all = kinds[kind];
        assert!(
            *n > all / 20 && *n < all,
            "{kind}: {n} of {all} shadow samples lit"
        );
    }
    // Some emissions towards the glass sphere, most elsewhere: both answers occur.
    assert!(
        n_aimed > 20 && n_aimed < cases.len() / 2,
        "{n_aimed} emissions aimed"
    );
    eprintln!(
        "{n_aimed} emissions aimed; cases per kind {kinds:?}, lit {lit:?}; worst errors / bound: {:?}",
        worst.0
    );
}

fn kind_of(s: &LightShape) -> &'static str {
    match s {
        LightShape::Point(_) => "point",
        LightShape::Spot(gpu_photon::lights::spot::Spot {
            projection: Some(_),
            ..
        }) => "spot projecting",
        LightShape::Spot(gpu_photon::lights::spot::Spot { cone, .. }) => match cone.profile {
            SpotFalloff::Gltf => "spot gltf",
            SpotFalloff::LinearAngle => "spot linear-angle",
        },
        LightShape::Projector(p) if p.texture.is_some() => "projector image",
        LightShape::Projector(_) => "projector",
        LightShape::Directional(_) => "directional",
        LightShape::Triangles(_) => "triangles",
        LightShape::Sphere(_) => "sphere",
        LightShape::Environment(_) => "environment",
    }
}

/// The sample's solid-angle pdf on the host: an area light's (`solid_angle_pdf`, 0 where the
/// sample is black), the environment's (`direction_pdf` of its direction), 0 for the delta
/// lights.
fn host_pdf(
    scene: &Scene,
    table: &LightTable,
    l: usize,
    x: Vec3,
    ns: Vec3,
    s: &LightSample,
) -> f32 {
    match scene.lights[l].shape {
        LightShape::Triangles(_) | LightShape::Sphere(_) => {
            if s.weight == Vec3::ZERO {
                0.0
            } else {
                table.solid_angle_pdf(l, x, s.point, s.normal)
            }
        }
        LightShape::Environment(_) => table.direction_pdf(scene, l, ns, s.point - x),
        _ => 0.0,
    }
}

fn every_path_has_the_hosts_light_and_spent_powers_end(scene: &Scene, probes: &mut SceneProbes) {
    let s = settings();
    let inf = f32::INFINITY;
    let nan = f32::NAN;
    let powers: Vec<[f32; 3]> = vec![
        [1.0, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [-1.0, -2.0, -0.5],
        [0.0, 1e-3, 0.0],
        [-1.0, 0.0, 2.0],
        [f32::MAX, 1.0, 1.0],
        [f32::MIN_POSITIVE, 0.0, 0.0],
        [nan, 1.0, 1.0],
        [1.0, nan, 1.0],
        [1.0, 1.0, nan],
        [inf, 1.0, 1.0],
        [1.0, -inf, 1.0],
        [1.0, 1.0, inf],
        [nan, nan, nan],
        [-inf, -inf, -inf],
    ];
    let got = probes.paths(&powers).unwrap();
    for (p, &g) in powers.iter().zip(&got.ends) {
        assert_eq!(g, power_ends(Vec3::from_array(*p)), "power_ends({p:?})");
    }
    // The run's budgets are the host's plan, and each path's light is the host's.
    let plan = MapPlan::new(scene, &LightTable::new(scene), &s);
    let mut seen = 0;
    for (k, kind) in [MapKind::Global, MapKind::Caustic].into_iter().enumerate() {
        let b = got.budgets[k].as_ref().expect("both maps are planned");
        assert_eq!(
            Some(b),
            plan.map(kind).map(|m| &m.budget),
            "{kind:?} budget"
        );
        assert!(b.counts.contains(&0), "{kind:?}: a light without paths");
        for i in 0..b.total() {
            assert_eq!(
                got.owners[i as usize][k] as usize,
                b.light_of(i),
                "{kind:?} path {i} (offsets {:?})",
                b.offsets
            );
            seen += 1;
        }
    }
    assert!(seen > 20_000);
}
