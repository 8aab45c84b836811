//! The CPU's 8-wide hierarchy (`bvh::WideBvh`) finds what the binary one (`bvh::Bvh`) and a
//! test of every primitive find: the same closest `t` bit for bit and the same primitive (or
//! one hit at exactly that `t`), the same barycentrics, and the same answer to `occluded`,
//! with every instruction set this CPU has; on the example scenes and on a random soup of
//! triangles (degenerate ones included), spheres and alpha-tested surfaces, for rays from
//! inside boxes and along the axes.

use glam::Vec3;
use gpu_photon::bvh::wide::{leaf_blocks, EMPTY, WIDTH};
use gpu_photon::bvh::{alpha_passes, Bvh, Isa, WideBvh, SPHERE_BIT};
use gpu_photon::math::geometry::{intersect_sphere, intersect_triangle, Ray, Shear};
use gpu_photon::math::rng::{pcg_hash, to_unit};
use gpu_photon::scene::{
    Alpha, AlphaMode, Material, Scene, Sphere, Triangle, NO_LIGHT, NO_TEXTURE,
};
use std::path::Path;

struct Rand(u32);
impl Rand {
    fn f(&mut self) -> f32 {
        self.0 = pcg_hash(self.0);
        to_unit(self.0)
    }
    fn v(&mut self) -> Vec3 {
        Vec3::new(self.f(), self.f(), self.f())
    }
}

/// Every primitive's hit (`t`, accepted by the alpha test), nearest first.
fn brute(scene: &Scene, alpha: bool, ray: &Ray, t_max: f32) -> Vec<(f32, u32)> {
    let shear = Shear::new(ray.dir);
    let mut hits = Vec::new();
    for (i, t) in scene.triangles.iter().enumerate() {
        if let Some((t, u, v)) = intersect_triangle(t, ray, &shear, t_max) {
            if !(alpha && alpha_passes(scene, i as u32, ray, t, u, v)) {
                hits.push((t, i as u32));
            }
        }
    }
    for (i, s) in scene.spheres.iter().enumerate() {
        let id = i as u32 | SPHERE_BIT;
        if let Some(t) = intersect_sphere(s, ray, t_max) {
            if !(alpha && alpha_passes(scene, id, ray, t, 0.0, 0.0)) {
                hits.push((t, id));
            }
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    hits
}

/// Rays from inside and around the scene's bounds: random directions, the six axis
/// directions, and directions in the axis planes.
fn rays(scene: &Scene, n: usize, seed: u32) -> Vec<Ray> {
    let bvh = Bvh::build(scene);
    let root = &bvh.nodes[0];
    let (lo, hi) = (Vec3::from(root.bmin), Vec3::from(root.bmax));
    let size = (hi - lo).max(Vec3::splat(1e-3));
    let mut r = Rand(seed);
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    (0..n)
        .map(|i| {
            let origin = lo - 0.1 * size + 1.2 * size * r.v();
            let dir = match i % 4 {
                0 => axes[i / 4 % 6],
                1 => {
                    let mut d = r.v() * 2.0 - Vec3::ONE;
                    d[i / 4 % 3] = 0.0;
                    d.normalize_or(Vec3::X)
                }
                _ => (r.v() * 2.0 - Vec3::ONE).normalize_or(Vec3::Y),
            };
            Ray { origin, dir }
        })
        .collect()
}

/// Checks every ray; returns how many hit something.
fn check(name: &str, scene: &Scene, rays: &[Ray]) -> usize {
    let bin = Bvh::build(scene);
    let wide = WideBvh::build(scene);
    let mut hits = 0;
    for isa in Isa::ALL.into_iter().filter(|i| i.available()) {
        let w = wide.clone().with_isa(isa);
        hits = 0;
        for (i, ray) in rays.iter().enumerate() {
            let all = brute(scene, bin.alpha, ray, f32::INFINITY);
            let expected = all.first().map(|h| h.0);
            let b = bin.closest(scene, ray, f32::INFINITY);
            let got = w.closest(scene, ray, f32::INFINITY);
            let what = format!(
                "{name} {} ray {i} {ray:?}: wide {got:?}, binary {b:?}",
                isa.name()
            );
            assert_eq!(
                got.map(|h| h.1.to_bits()),
                expected.map(f32::to_bits),
                "{what}"
            );
            assert_eq!(
                b.map(|h| h.1),
                expected,
                "{what}: binary against all primitives"
            );
            if let (Some(g), Some(b)) = (got, b) {
                // The same primitive, or another hit at exactly the same t.
                assert!(
                    all.iter().any(|h| h.0 == g.1 && h.1 == g.0),
                    "{what}: not a hit of its primitive"
                );
                if g.0 == b.0 {
                    assert_eq!(
                        (g.2.to_bits(), g.3.to_bits()),
                        (b.2.to_bits(), b.3.to_bits())
                    );
                }
                hits += 1;
            }
            // Occlusion before, at and past the hit, and unbounded.
            let t = expected.unwrap_or(1.0);
            for t_max in [0.5 * t, t, t * 1.0001 + 1e-6, f32::INFINITY] {
                let any = all.iter().any(|h| h.0 < t_max);
                assert_eq!(
                    w.occluded(scene, ray, t_max),
                    any,
                    "{what} occluded {t_max}"
                );
                assert_eq!(bin.occluded(scene, ray, t_max), any, "{what} binary occl.");
            }
        }
    }
    hits
}

fn soup(seed: u32, n: usize) -> Scene {
    let mut scene = Scene::empty();
    scene.materials.push(Material::diffuse(Vec3::splat(0.5)));
    let mut masked = Material::diffuse(Vec3::splat(0.5));
    masked.alpha = Some(Alpha {
        mode: AlphaMode::Blend,
        factor: 0.5,
        texture: NO_TEXTURE,
        luminance: false,
    });
    scene.materials.push(masked);
    let mut r = Rand(seed);
    for i in 0..n {
        let a = r.v() * 10.0;
        let (b, c) = match i % 10 {
            // Degenerate: a repeated corner, and three corners on a line.
            0 => (a, a + r.v()),
            1 => {
                let d = r.v();
                (a + d, a + 2.0 * d)
            }
            // Axis-aligned, as boxes' faces are.
            2 => (
                a + Vec3::new(r.f(), 0.0, 0.0),
                a + Vec3::new(0.0, r.f(), 0.0),
            ),
            _ => (a + r.v() - Vec3::splat(0.5), a + r.v() - Vec3::splat(0.5)),
        };
        scene
            .triangles
            .push(Triangle::new(a, b, c, (i % 3 == 0) as u32));
    }
    for i in 0..n / 20 {
        scene.spheres.push(Sphere {
            center: r.v() * 10.0,
            radius: 0.05 + r.f(),
            material: (i % 2) as u32,
            light: NO_LIGHT,
            frame: glam::Quat::IDENTITY,
        });
    }
    scene
}

#[test]
fn wide_hits_what_the_binary_hierarchy_and_every_primitive_hit_on_a_random_soup() {
    for (seed, n) in [(1, 1), (2, 7), (3, 300), (4, 3000)] {
        let scene = soup(seed, n);
        let hits = check(&format!("soup {n}"), &scene, &rays(&scene, 3000, seed));
        assert!(hits > 0 || n < 10, "soup {n}: some rays hit ({hits})");
    }
}

#[test]
fn wide_hits_what_the_binary_hierarchy_hits_on_the_example_scenes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in [
        "scenes/cornell-box.toml",
        "scenes/cornell-caustics.toml",
        "scenes/glossy-sphere.toml",
        "scenes/mesh-light.toml",
        "scenes/mitsuba/materials.xml",
    ] {
        let scene = gpu_photon::importers::load(&root.join(name)).expect(name);
        let hits = check(name, &scene, &rays(&scene, 4000, 9));
        assert!(hits > 1000, "{name}: {hits} hits");
    }
}

#[test]
fn an_empty_scene_has_nothing_to_hit() {
    let scene = Scene::empty();
    let wide = WideBvh::build(&scene);
    let ray = Ray {
        origin: Vec3::ZERO,
        dir: Vec3::Z,
    };
    assert!(wide.closest(&scene, &ray, f32::INFINITY).is_none());
    assert!(!wide.occluded(&scene, &ray, f32::INFINITY));
}

#[test]
fn the_cornell_boxs_walls_do_not_share_leaves() {
    // Its binary build keeps leaves of 8-12 triangles (the walls with the boxes' faces:
    // every split's boxes span the room) and its wide root had three children, one a
    // leaf of the floor, ceiling, back and right walls that every ray entered.
    let scene = gpu_photon::importers::load(Path::new("scenes/cornell-box.toml")).unwrap();
    let walls = 0..10u32; // Floor, ceiling, back, left, right: two triangles each.
    for t in walls.clone().map(|t| &scene.triangles[t as usize]) {
        assert!(
            t.e1().cross(t.e2()).length() > 3.99,
            "a wall's triangle: half a 2 x 2 square"
        );
    }
    let w = WideBvh::build(&scene);
    assert_eq!(w.nodes.len(), 1);
    let root = &w.nodes[0];
    for slot in (0..WIDTH).filter(|&s| root.child[s] != EMPTY) {
        let (first, count) = leaf_blocks(root.child[slot]);
        let mut faces: Vec<u32> = (w.blocks[first..first + count].iter())
            .flat_map(|b| b.id)
            .filter(|id| walls.contains(id))
            .map(|id| id / 2)
            .collect();
        faces.dedup();
        assert!(faces.len() <= 1, "slot {slot}: walls {faces:?} in one leaf");
    }
}
