//! Instancing (`shapegroup` + `instance`, `src/scene/instances.rs`, `src/bvh/instances.rs`):
//! the two-level walk finds the hits the same scene flattened into world triangles finds,
//! normals of a non-uniformly scaled instance follow the inverse transpose, memory grows
//! with mesh + instances (not their product) and the budgets count it so, the Mitsuba
//! importer reads groups and refuses what Mitsuba refuses, and an instanced render equals
//! the flattened one within noise, and the device walks the two levels as the host does.

mod common;
mod probes;

use glam::{Mat3, Mat4, Quat, Vec3};
use gpu_photon::bvh::CpuBvh;
use gpu_photon::math::geometry::Ray;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{Material, Origin, Scene, SceneBudgets, SceneBuilder, Surface};
use gpu_photon::settings::{Mode, RenderSettings};

fn at(field: &str) -> Origin {
    Origin {
        file: "test".into(),
        line: 1,
        field: field.into(),
    }
}

/// A builder with a camera at `eye` looking at the origin and one grey diffuse material.
fn grey_builder(eye: Vec3, budgets: SceneBudgets) -> (SceneBuilder, gpu_photon::scene::MaterialId) {
    let mut b = SceneBuilder::new();
    b.set_budgets(budgets);
    b.camera(eye, Vec3::ZERO, Vec3::Z, 50.0, &at("camera"))
        .unwrap();
    let m = b
        .add_material(None, Material::diffuse(Vec3::splat(0.5)), &at("m"))
        .unwrap();
    (b, m)
}

/// A deterministic generator of uniforms in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn dir(&mut self) -> Vec3 {
        let z = 2.0 * self.next() - 1.0;
        let phi = 2.0 * std::f32::consts::PI * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// A smooth-shaded uv sphere of `rings` x `segments` quads (two triangles each) around the
/// origin, radius 1, with its vertex normals.
fn uv_sphere(rings: usize, segments: usize) -> (Vec<[Vec3; 3]>, Vec<[Vec3; 3]>) {
    let p = |i: usize, j: usize| {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        let ph = 2.0 * std::f32::consts::PI * j as f32 / segments as f32;
        Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos())
    };
    let mut tris = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            if i + 1 < rings {
                tris.push([a, b, c]);
            }
            if i > 0 {
                tris.push([a, c, d]);
            }
        }
    }
    let normals = tris.clone();
    (tris, normals)
}

/// The transforms the instances use: rotations, uniform and non-uniform scales,
/// translations (all with a positive determinant).
fn placements() -> Vec<Mat4> {
    vec![
        Mat4::IDENTITY,
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1.5),
            Quat::from_rotation_y(0.7),
            Vec3::new(0.0, 0.0, 3.0),
        ),
        Mat4::from_translation(Vec3::new(3.0, 0.5, -1.0))
            * Mat4::from_rotation_x(-0.4)
            * Mat4::from_scale(Vec3::new(0.5, 2.0, 1.0)),
        Mat4::from_translation(Vec3::new(-3.0, 0.0, 0.0))
            * Mat4::from_scale(Vec3::new(0.3, 1.0, 3.0)),
    ]
}

/// The scene of a group (a smooth uv sphere of material 0 and an analytic sphere of
/// material 1) placed by [`placements`], either instanced or flattened into world
/// primitives (normals by the inverse transpose), lit by a point light.
fn scene(instanced: bool) -> Scene {
    let mut b = SceneBuilder::new();
    b.camera(
        Vec3::new(0.0, -9.0, 1.0),
        Vec3::ZERO,
        Vec3::Z,
        50.0,
        &at("camera"),
    )
    .unwrap();
    let m0 = b
        .add_material(None, Material::diffuse(Vec3::new(0.8, 0.4, 0.2)), &at("m0"))
        .unwrap();
    let m1 = b
        .add_material(None, Material::diffuse(Vec3::new(0.2, 0.6, 0.8)), &at("m1"))
        .unwrap();
    let floor = b
        .add_material(None, Material::diffuse(Vec3::splat(0.5)), &at("m2"))
        .unwrap();
    b.add_quad(
        [
            Vec3::new(-20.0, -20.0, -3.0),
            Vec3::new(20.0, -20.0, -3.0),
            Vec3::new(20.0, 20.0, -3.0),
            Vec3::new(-20.0, 20.0, -3.0),
        ],
        Surface::of(floor),
        &at("floor"),
    )
    .unwrap();
    b.add_point_light(Vec3::new(2.0, -6.0, 6.0), Vec3::splat(60.0), &at("light"))
        .unwrap();
    let (tris, normals) = uv_sphere(8, 12);
    let ball = (Vec3::new(0.0, 0.0, 1.6), 0.4);
    if instanced {
        b.begin_shape_group(&at("group")).unwrap();
        b.add_smooth_mesh(tris, Some(normals), Surface::of(m0), &at("mesh"))
            .unwrap();
        b.add_sphere(ball.0, ball.1, Surface::of(m1), &at("ball"))
            .unwrap();
        let mesh = b.end_shape_group();
        for m in placements() {
            b.add_instance(mesh, m, &at("instance")).unwrap();
        }
    } else {
        for m in placements() {
            let nm = Mat3::from_mat4(m).inverse().transpose();
            let t: Vec<[Vec3; 3]> = tris
                .iter()
                .map(|t| t.map(|p| m.transform_point3(p)))
                .collect();
            let n: Vec<[Vec3; 3]> = normals.iter().map(|n| n.map(|v| nm * v)).collect();
            b.add_smooth_mesh(t, Some(n), Surface::of(m0), &at("mesh"))
                .unwrap();
            // Only the similarity placements keep the ball a sphere; the test rays skip
            // the others' balls (see `agrees`).
            let s = Mat3::from_mat4(m).x_axis.length();
            b.add_sphere(
                m.transform_point3(ball.0),
                ball.1 * s,
                Surface::of(m1),
                &at("ball"),
            )
            .unwrap();
        }
    }
    b.finish(&at("scene")).unwrap()
}

/// Rays from around the scene towards its instances.
fn rays(n: usize) -> Vec<Ray> {
    let mut g = Lcg(7);
    (0..n)
        .map(|_| {
            let origin = 8.0 * g.dir();
            let target = Vec3::new(
                6.0 * g.next() - 3.0,
                2.0 * g.next() - 1.0,
                6.0 * g.next() - 3.0,
            );
            Ray {
                origin,
                dir: (target - origin).normalize(),
            }
        })
        .collect()
}

#[test]
fn instanced_hits_match_the_flattened_scene() {
    let (inst, flat) = (scene(true), scene(false));
    assert_eq!(inst.instancing.instances.len(), 4);
    assert_eq!(
        inst.instancing.meshes[0].triangles.len(),
        (flat.triangles.len() - 2) / 4
    );
    let (bi, bf) = (CpuBvh::build(&inst), CpuBvh::build(&flat));
    // The balls of the non-uniform placements are ellipsoids in the instanced scene and
    // spheres in the flattened one: rays that reach a ball (material 1) there are skipped.
    let skip = |h: &gpu_photon::bvh::Hit| h.material == 1;
    let (mut compared, mut differ, mut hits) = (0, 0, 0);
    // Failures by kind: t, point, normal, shading normal, material, tangent, hit or miss,
    // shadow.
    let mut why = [0usize; 8];
    // The least cosine between the shading normals: similarity placements, the others.
    let mut worst = [1.0f32; 2];
    for ray in rays(20_000) {
        let (a, b) = (
            bi.intersect(&inst, &ray, f32::INFINITY),
            bf.intersect(&flat, &ray, f32::INFINITY),
        );
        if a.as_ref().is_some_and(skip) || b.as_ref().is_some_and(skip) {
            continue;
        }
        compared += 1;
        match (a, b) {
            (Some(a), Some(b)) => {
                hits += 1;
                let checks = [
                    (a.t - b.t).abs() <= 1e-4 * b.t,
                    (a.position - b.position).length() <= 1e-4 * (1.0 + b.position.length()),
                    a.normal.dot(b.normal) > 1.0 - 1e-5,
                    // The similarity placements (|x| < 2.2) interpolate the same normals;
                    // a non-uniform scale's instance interpolates its object-space normals
                    // before the transform, as Mitsuba's instances do, its flattened copy
                    // the transformed ones, as Mitsuba's meshes do: close, not equal (26
                    // degrees apart at most on this coarse sphere scaled 10:1, measured).
                    a.shading.dot(b.shading)
                        > if b.position.x.abs() < 2.2 {
                            1.0 - 1e-4
                        } else {
                            0.85
                        },
                    a.material == b.material,
                    // The shading frame's tangent is a direction: the similarity placements
                    // carry the object's dp/du (or first edge) to the flattened copy's.
                    b.position.x.abs() >= 2.2 || a.tangent.dot(b.tangent) > 1.0 - 1e-4,
                ];
                let region = usize::from(b.position.x.abs() >= 2.2);
                worst[region] = worst[region].min(a.shading.dot(b.shading));
                for (k, ok) in checks.iter().enumerate() {
                    why[k] += usize::from(!ok);
                }
                if checks.contains(&false) {
                    differ += 1;
                }
            }
            (None, None) => {}
            _ => {
                differ += 1;
                why[6] += 1;
            }
        }
        // Shadow rays to half the distance of the first hit and past it.
        let t = bf
            .intersect(&flat, &ray, f32::INFINITY)
            .map_or(50.0, |h| h.t);
        for limit in [0.5 * t, 1.01 * t] {
            let (oi, of) = (
                bi.occluded(&inst, &ray, limit),
                bf.occluded(&flat, &ray, limit),
            );
            if oi != of {
                differ += 1;
                why[7] += 1;
            }
        }
    }
    assert!(
        hits > 5_000,
        "{hits} hits of {compared} rays: the test misses the instances"
    );
    // Rays grazing an edge may round to either side: one in a thousand.
    assert!(
        differ * 1000 <= compared,
        "{differ} of {compared} rays differ (t, point, normal, shading, material, tangent, \
         hit, shadow: {why:?}; least shading cosines {worst:?})"
    );
    eprintln!("least shading cosines {worst:?}");
}

#[test]
fn normals_of_a_non_uniformly_scaled_instance_follow_the_inverse_transpose() {
    // A unit sphere scaled by (1, 1, 4) and turned: the ellipsoid x^2 + y^2 + (z/4)^2 = 1
    // before the turn, whose normal at p is (x, y, z / 16) (the linear map's would be
    // (x, y, 4 z)).
    let (mut b, m) = grey_builder(Vec3::new(0.0, -9.0, 0.0), SceneBudgets::default());
    b.begin_shape_group(&at("group")).unwrap();
    b.add_sphere(Vec3::ZERO, 1.0, Surface::of(m), &at("ball"))
        .unwrap();
    let mesh = b.end_shape_group();
    let turn = Quat::from_rotation_x(0.3);
    let to_world = Mat4::from_quat(turn) * Mat4::from_scale(Vec3::new(1.0, 1.0, 4.0));
    b.add_instance(mesh, to_world, &at("instance")).unwrap();
    let scene = b.finish(&at("scene")).unwrap();
    let bvh = CpuBvh::build(&scene);
    let mut g = Lcg(3);
    let mut n = 0;
    for _ in 0..2000 {
        let origin = 10.0 * g.dir();
        let target = Vec3::new(g.next() - 0.5, g.next() - 0.5, 4.0 * g.next() - 2.0);
        let ray = Ray {
            origin,
            dir: (target - origin).normalize(),
        };
        let Some(hit) = bvh.intersect(&scene, &ray, f32::INFINITY) else {
            continue;
        };
        n += 1;
        let p = turn.inverse() * hit.position;
        let on = p.x * p.x + p.y * p.y + p.z * p.z / 16.0;
        assert!(
            (on - 1.0).abs() < 1e-4,
            "{p} is not on the ellipsoid ({on})"
        );
        let want = turn * Vec3::new(p.x, p.y, p.z / 16.0).normalize();
        assert!(
            hit.normal.dot(want) > 1.0 - 1e-5,
            "normal {} at {p}, want {want}",
            hit.normal
        );
        assert!(hit.shading.dot(want) > 1.0 - 1e-5);
        assert!((hit.t - (hit.position - origin).length()).abs() < 1e-4 * hit.t);
    }
    assert!(n > 500, "{n} hits");
}

/// A flat mesh of `n` triangles (a strip) in its group.
fn strip(n: usize) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|i| {
            let x = i as f32 * 0.01;
            [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 0.01, 0.0, 0.0),
                Vec3::new(x, 0.01, 0.01),
            ]
        })
        .collect()
}

#[test]
fn many_instances_cost_mesh_plus_instances() {
    // 10,000 instances of a 10,000-triangle mesh: 10^8 triangles flattened (4.8 GB of
    // triangles alone), a few MB instanced. A budget of 64 MB takes it.
    let budgets = SceneBudgets {
        max_bytes: 64 << 20,
        ..SceneBudgets::default()
    };
    let (mut b, m) = grey_builder(Vec3::new(0.0, -9.0, 0.0), budgets);
    b.begin_shape_group(&at("group")).unwrap();
    b.add_mesh(strip(10_000), Surface::of(m), &at("mesh"))
        .unwrap();
    let mesh = b.end_shape_group();
    for i in 0..10_000 {
        let t = Vec3::new((i % 100) as f32 * 2.0, (i / 100) as f32 * 2.0, 0.0);
        b.add_instance(mesh, Mat4::from_translation(t), &at("instance"))
            .unwrap();
    }
    let scene = b.finish(&at("scene")).unwrap();
    assert_eq!(scene.triangles.len(), 0);
    assert_eq!(scene.instancing.meshes[0].triangles.len(), 10_000);
    let started = std::time::Instant::now();
    let bvh = CpuBvh::build(&scene);
    let built = started.elapsed().as_secs_f64();
    let one = CpuBvh::build(&scene.instancing.meshes[0]).memory_bytes();
    let bytes = bvh.memory_bytes();
    // For docs/bvh.md (not asserted: timings are for benchmarks).
    eprintln!(
        "10,000 instances of 10,000 triangles: built in {built:.3} s, {bytes} bytes ({one} for \
         the mesh, {:.1} per instance)",
        (bytes - one) as f64 / 10_000.0
    );
    // The mesh's hierarchy once, plus at most 128 bytes of top level per instance.
    assert!(
        bytes <= one + 128 * 10_000,
        "{bytes} bytes (one mesh: {one})"
    );
    // Every instance is there: a ray down onto each row of instances hits.
    for i in (0..10_000).step_by(97) {
        let c = Vec3::new(
            (i % 100) as f32 * 2.0 + 0.005,
            (i / 100) as f32 * 2.0 + 0.001,
            5.0,
        );
        let ray = Ray {
            origin: c,
            dir: -Vec3::Z,
        };
        assert!(bvh.occluded(&scene, &ray, 10.0), "instance {i}");
    }
    // The budget counts instances, not their triangles: a budget too small for one more
    // instance refuses it, naming it.
    let tiny = SceneBudgets {
        max_bytes: scene.instancing.meshes[0].triangles.len() as u64 * 48 + 10 * 144,
        ..SceneBudgets::default()
    };
    let mut b = SceneBuilder::new();
    b.set_budgets(tiny);
    b.begin_shape_group(&at("group")).unwrap();
    b.add_mesh(strip(10_000), Surface::default(), &at("mesh"))
        .unwrap();
    let mesh = b.end_shape_group();
    let placed = (0..100)
        .take_while(|&i| {
            b.add_instance(
                mesh,
                Mat4::from_translation(Vec3::X * i as f32),
                &at("instance"),
            )
            .is_ok()
        })
        .count();
    assert!((5..=10).contains(&placed), "{placed} instances placed");
    let e = b
        .add_instance(mesh, Mat4::IDENTITY, &at("instance"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("this instance"), "{e}");
}

#[test]
fn groups_refuse_emitters_nesting_and_singular_transforms() {
    let mut b = SceneBuilder::new();
    b.begin_shape_group(&at("group")).unwrap();
    let e = b.begin_shape_group(&at("inner")).unwrap_err().to_string();
    assert!(e.contains("shape group inside a shape group"), "{e}");
    let e = b
        .add_mesh(strip(2), Surface::emitting(Vec3::ONE), &at("lamp"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("lamp") && e.contains("emitter in a shape group"),
        "{e}"
    );
    let mesh = b.end_shape_group();
    let flat = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
    let e = b
        .add_instance(mesh, flat, &at("instance"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("invertible"), "{e}");
    let e = b
        .add_instance(mesh, Mat4::from_translation(Vec3::NAN), &at("instance"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("finite"), "{e}");
}

/// A Mitsuba scene around `body`, written to a temporary file and loaded.
fn mitsuba(name: &str, body: &str) -> gpu_photon::Result<Scene> {
    let dir = std::env::temp_dir().join(format!("gpu-photon-instancing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.xml"));
    let xml = format!(
        "<scene version='3.0.0'>\n<sensor type='perspective'><transform name='to_world'>\
         <lookat origin='0,-9,0' target='0,0,0' up='0,0,1'/></transform></sensor>\n{body}\n</scene>\n"
    );
    std::fs::write(&path, xml).unwrap();
    gpu_photon::importers::load(&path)
}

#[test]
fn mitsuba_groups_and_instances() {
    let group = "<shape type='shapegroup' id='g'>\n<shape type='sphere'/>\n\
                 <shape type='rectangle'/>\n</shape>";
    let s = mitsuba(
        "ok",
        &format!(
            "{group}\n<shape type='instance'><ref id='g'/></shape>\n\
             <shape type='instance'><ref id='g'/><transform name='to_world'>\
             <scale x='1' y='2' z='3'/><translate z='4'/></transform></shape>"
        ),
    )
    .unwrap();
    assert_eq!(s.instancing.instances.len(), 2);
    assert_eq!(s.instancing.meshes.len(), 1);
    assert_eq!((s.triangles.len(), s.spheres.len()), (0, 0));
    let m = &s.instancing.meshes[0];
    assert_eq!((m.triangles.len(), m.spheres.len()), (2, 1));
    let i = &s.instancing.instances[1];
    assert!((i.to_world.transform_point3(Vec3::ONE) - Vec3::new(1.0, 2.0, 7.0)).length() < 1e-5);

    let cases = [
        (
            "<shape type='shapegroup' id='g'><shape type='sphere'><emitter type='area'>\
             <rgb name='radiance' value='1'/></emitter></shape></shape>",
            "emitter in a shape group",
        ),
        (
            "<shape type='shapegroup' id='g'><shape type='shapegroup' id='h'/></shape>",
            "shapegroup inside a shapegroup",
        ),
        (
            "<shape type='shapegroup' id='g'><emitter type='point'/></shape>",
            "emitter in a shapegroup",
        ),
        (
            "<bsdf type='diffuse' id='b'/><shape type='instance'><ref id='b'/></shape>",
            "only a shapegroup",
        ),
        (
            "<shape type='instance'/>",
            "needs a reference to a shapegroup",
        ),
        (
            "<shape type='shapegroup' id='g'><shape type='sdfgrid'/></shape>",
            "shape[g].shape[0].filename: missing",
        ),
    ];
    for (i, (body, want)) in cases.iter().enumerate() {
        let e = mitsuba(&format!("bad{i}"), body).unwrap_err().to_string();
        assert!(e.contains(want), "case {i}: {e}");
    }
}

fn mean(img: &Image) -> Vec3 {
    let sum: Vec3 = img.pixels.iter().map(|p| Vec3::from(*p)).sum();
    sum / img.pixels.len() as f32
}

#[test]
fn instanced_render_equals_the_flattened_one_within_noise() {
    // Only the similarity placements: the flattened scene cannot make an ellipsoid.
    let s = RenderSettings {
        width: 48,
        height: 48,
        spp: 8,
        photons: 40_000,
        mode: Mode::Gather,
        ..RenderSettings::default()
    };
    let render_of = |instanced: bool, seed: u32| {
        let mut scene = scene(instanced);
        if instanced {
            scene.instancing.instances.truncate(2);
        } else {
            // The first two placements' primitives: their spheres and mesh triangles.
            let floor = 2;
            let per = (scene.triangles.len() - floor) / 4;
            scene.triangles.truncate(floor + 2 * per);
            scene.spheres.truncate(2);
        }
        let settings = RenderSettings { seed, ..s.clone() };
        render(&scene, &settings, Backend::Cpu, Progress::default())
            .unwrap()
            .0
    };
    let (a, b, c) = (render_of(true, 1), render_of(false, 1), render_of(false, 2));
    let same_seed = diff(&a, &b, 4).unwrap();
    let other_seed = diff(&b, &c, 4).unwrap();
    // The same seed traces (almost) the same paths: no farther than another seed is.
    assert!(
        same_seed.rmse <= other_seed.rmse + 1e-6,
        "instanced vs flattened {same_seed:?}, flattened seed 1 vs 2 {other_seed:?}"
    );
    let (ma, mb) = (mean(&a), mean(&b));
    assert!(ma.max_element() > 0.01, "black image {ma}");
    assert!(
        (ma - mb).abs().max_element() <= 0.02 * mb.max_element(),
        "{ma} vs {mb}"
    );
}

#[test]
fn device_walks_instances_as_the_host() {
    use probes::light::{RayCase, SceneProbes};
    let Some(ctx) = common::gpu() else { return };
    for scene in [scene(true), nested_normals_scene()] {
        let bvh = CpuBvh::build(&scene);
        let cases: Vec<RayCase> = rays(3000)
            .iter()
            .map(|r| RayCase {
                origin: r.origin.to_array(),
                dir: r.dir.to_array(),
                t_max: 1e30,
                primitive: u32::MAX,
            })
            .collect();
        let mut probes = SceneProbes::new(&ctx, &scene, &RenderSettings::default()).unwrap();
        let got = probes.intersect(&cases).unwrap();
        let (mut hits, mut differ) = (0, 0);
        for (i, (c, g)) in cases.iter().zip(&got).enumerate() {
            let ray = c.ray();
            let want = bvh.intersect(&scene, &ray, c.t_max);
            let same = match (g.nearest, want) {
                (None, None) => true,
                (Some((t, material, _)), Some(h)) => {
                    hits += 1;
                    let p = Vec3::from_array(g.position);
                    let n = Vec3::from_array(g.normal);
                    (t - h.t).abs() <= 1e-4 * h.t
                        && material == h.material
                        && (p - h.position).length() <= 1e-4 * (1.0 + h.position.length())
                        && n.dot(h.normal) > 1.0 - 1e-5
                }
                _ => false,
            };
            let occluded = g.occluded == bvh.occluded(&scene, &ray, c.t_max);
            if !(same && occluded) {
                differ += 1;
                eprintln!(
                    "ray {i}: device {g:?}, host {:?}",
                    want.map(|h| (h.t, h.material, h.position, h.normal))
                );
            }
        }
        assert!(hits > 500, "{hits} hits");
        eprintln!("{hits} hits, {differ} rays differ");
        // Rays grazing an edge may round to either side on the two backends.
        assert!(
            differ * 500 <= cases.len(),
            "{differ} of {} rays differ",
            cases.len()
        );
    }
}

/// A scene of instances only (no world primitive), one mirrored and non-uniformly scaled,
/// with the meshes' spheres and smooth triangles.
fn nested_normals_scene() -> Scene {
    let (mut b, m) = grey_builder(Vec3::new(0.0, -9.0, 1.0), SceneBudgets::default());
    let (tris, normals) = uv_sphere(6, 10);
    b.begin_shape_group(&at("group")).unwrap();
    b.add_smooth_mesh(tris, Some(normals), Surface::of(m), &at("mesh"))
        .unwrap();
    let a = b.end_shape_group();
    b.begin_shape_group(&at("group")).unwrap();
    b.add_sphere(Vec3::new(0.5, 0.0, 0.0), 0.7, Surface::of(m), &at("ball"))
        .unwrap();
    let c = b.end_shape_group();
    for (mesh, m) in [
        (a, Mat4::from_scale(Vec3::new(-1.0, 2.0, 0.5))),
        (
            c,
            Mat4::from_translation(Vec3::new(2.5, 0.0, 0.0))
                * Mat4::from_scale(Vec3::new(1.0, 0.5, 2.0)),
        ),
        (
            c,
            Mat4::from_translation(Vec3::new(-2.5, 1.0, -1.0)) * Mat4::from_rotation_z(0.8),
        ),
    ] {
        b.add_instance(mesh, m, &at("instance")).unwrap();
    }
    b.finish(&at("scene")).unwrap()
}

#[test]
fn instanced_gpu_render_is_within_seed_noise_of_the_cpus() {
    if common::gpu().is_none() {
        return;
    }
    let s = RenderSettings {
        width: 32,
        height: 32,
        spp: 4,
        passes: 1,
        photons: 20_000,
        mode: Mode::Gather,
        ..RenderSettings::default()
    };
    let (d, noise) = common::gpu_and_seed_diffs(&scene(true), &s);
    let (pixels, blocks) = common::within_seed_noise(&d, &noise, 1e-4);
    assert!(pixels && blocks, "gpu vs cpu {d:?}; cpu seeds {noise:?}");
}

/// The fuzzer's glTF sphere seed (4,096 smooth triangles) with its mesh placed by three
/// nodes (one twice at one place), as one mesh named three times (`shared`) or as three
/// meshes over the same accessors; the scene file's path.
fn gltf_spheres(shared: bool) -> std::path::PathBuf {
    let seed = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz/gltf/sphere");
    let d = std::env::temp_dir().join(format!(
        "gpu-photon-instancing-gltf-{}-{shared}",
        std::process::id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(seed.join("scene.bin"), d.join("scene.bin")).unwrap();
    let text = std::fs::read_to_string(seed.join("scene.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mesh = json["meshes"][0].clone();
    json["meshes"] = serde_json::json!([mesh.clone(), mesh.clone(), mesh]);
    let m = |i: usize| if shared { 0 } else { i };
    json["nodes"][0]["scale"] = serde_json::json!([0.5, 1.0, 0.8]);
    let extra = [
        serde_json::json!({"mesh": m(1), "translation": [1.5, 0.0, -1.0], "rotation": [0.0, 0.38268343, 0.0, 0.92387953]}),
        serde_json::json!({"mesh": m(2), "translation": [-1.5, 0.5, -2.0], "scale": [1.0, -1.0, 1.0]}),
    ];
    json["nodes"].as_array_mut().unwrap().extend(extra);
    // Node 0 twice at one place: one placement.
    json["scenes"][0]["nodes"] = serde_json::json!([0, 0, 1, 2, 3, 4]);
    let path = d.join("scene.gltf");
    std::fs::write(&path, serde_json::to_string(&json).unwrap()).unwrap();
    path
}

#[test]
fn gltf_meshes_named_at_several_places_are_instanced() {
    let shared = gpu_photon::importers::load(&gltf_spheres(true)).unwrap();
    let copies = gpu_photon::importers::load(&gltf_spheres(false)).unwrap();
    // One mesh stored once for three placements; the three single meshes are copies.
    assert_eq!(shared.triangles.len(), 0);
    assert_eq!(shared.instancing.meshes.len(), 1);
    assert_eq!(shared.instancing.meshes[0].triangles.len(), 4096);
    assert_eq!(shared.instancing.instances.len(), 3);
    assert_eq!(
        (copies.triangles.len(), copies.instancing.instances.len()),
        (3 * 4096, 0)
    );
    // The same surfaces: every ray hits alike (the mirrored node's normals included).
    let (bs, bc) = (CpuBvh::build(&shared), CpuBvh::build(&copies));
    let (mut hits, mut differ) = (0, 0);
    for ray in rays(5000) {
        let (a, b) = (
            bs.intersect(&shared, &ray, f32::INFINITY),
            bc.intersect(&copies, &ray, f32::INFINITY),
        );
        match (a, b) {
            (Some(a), Some(b)) => {
                hits += 1;
                let same = (a.t - b.t).abs() <= 1e-4 * b.t
                    && a.normal.dot(b.normal) > 1.0 - 1e-5
                    && a.material == b.material;
                differ += usize::from(!same);
            }
            (None, None) => {}
            _ => differ += 1,
        }
    }
    assert!(hits > 1000, "{hits} hits");
    assert!(differ * 1000 <= 5000, "{differ} rays differ");
}
