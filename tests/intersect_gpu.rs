//! Oracle test of ray intersection on the device (src/bvh/intersect.wgsl; the surface
//! helpers' test, src/bvh/shading_frame.wgsl's too) against src/math/geometry.rs and
//! src/bvh/, through the probe `tests/probes/probe_geometry.wgsl`
//! (`gpu::probe_light::intersect`): each primitive's own test (the watertight
//! ray-triangle test, the sphere's) and the BVH walk (nearest and any hit) over a small scene
//! of quads, a box, spheres and a degenerate triangle, on random rays and on the edge cases
//! of a watertight test: rays aimed exactly at shared edges and vertices (the device hits the
//! same triangles as the host, and at least one of the two sharing an edge), rays in a
//! triangle's plane, a degenerate triangle (never hit), hits with t_max at and just past the
//! hit, rays tangent to a sphere and from inside it.
//! Hit or miss must be identical; t within 4 ulp (`T_ULPS`), barycentrics within 1e-6.
//! Without a Vulkan adapter the test is skipped (CI fails instead, see common::gpu).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::{Vec2, Vec3};
use gpu_photon::bvh::{Bvh, SPHERE_BIT};
use gpu_photon::importers::load_str;
use gpu_photon::math::geometry::{intersect_sphere, intersect_triangle, Ray, Shear};
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;
use probes::light::{IntersectProbe, RayCase, SceneProbes};
use std::path::Path;

/// Two quads meeting at an edge (each two triangles sharing a diagonal), a closed box and
/// spheres, one large enough to hold ray origins.
const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 8.0]
target = [0.0, 0.0, 0.0]
fov = 40.0

[materials.a]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]

[materials.b]
type = "diffuse"
albedo = [0.2, 0.6, 0.2]

[[shapes]]
type = "quad"
corners = [[-2.0, -1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [-2.0, 1.0, 0.0]]
material = "a"

[[shapes]]
type = "quad"
corners = [[0.0, -1.0, 0.0], [1.7, -1.3, 0.9], [1.9, 1.1, 1.0], [0.0, 1.0, 0.0]]
material = "b"

[[shapes]]
type = "box"
min = [-1.0, -3.0, -2.0]
max = [0.7, -2.2, -0.5]
rotate_y = 30.0
material = "b"

[[shapes]]
type = "triangle"
vertices = [[2.0, 2.0, -1.0], [3.0, 2.0, -1.0], [2.0, 3.0, -1.2]]
material = "a"

[[shapes]]
type = "sphere"
center = [2.5, -2.0, -1.0]
radius = 0.6
material = "a"

[[shapes]]
type = "sphere"
center = [-2.5, 2.0, 1.5]
radius = 0.3
material = "b"
"#;

/// Largest difference in t, in ulp of the host's t: the device evaluates the same
/// expressions, but may contract a multiply and an add (WGSL allows it), a rounding each.
/// Measured on lavapipe: each primitive's test bit for bit (t and barycentrics), the walk's
/// nearest t within 1 ulp (the same test inlined in the walk, compiled differently).
const T_ULPS: u32 = 4;
/// Barycentrics: differences of edge functions over their sum, each a few roundings.
const UV_ABS: f32 = 1e-6;

/// The scene, with its last triangle made degenerate (its three vertices on a line).
fn scene() -> Scene {
    let mut s = load_str(SCENE, "rays.toml", Path::new(".")).expect("the ray scene loads");
    let t = s.triangles.last_mut().unwrap();
    t.v2 = t.v0 + 0.5 * (t.v1 - t.v0);
    s
}

fn ulps(a: f32, b: f32) -> u32 {
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs() as u32
}

/// The host's test of `c.primitive` alone.
fn host_primitive(scene: &Scene, c: &RayCase) -> Option<[f32; 3]> {
    let ray = Ray {
        origin: Vec3::from_array(c.origin),
        dir: Vec3::from_array(c.dir),
    };
    if c.primitive == u32::MAX {
        None
    } else if c.primitive & SPHERE_BIT == 0 {
        let tri = &scene.triangles[c.primitive as usize];
        intersect_triangle(tri, &ray, &Shear::new(ray.dir), c.t_max).map(|(t, u, v)| [t, u, v])
    } else {
        let s = &scene.spheres[(c.primitive & !SPHERE_BIT) as usize];
        intersect_sphere(s, &ray, c.t_max).map(|t| [t, 0.0, 0.0])
    }
}

fn case(o: Vec3, d: Vec3, t_max: f32, primitive: u32) -> RayCase {
    RayCase {
        origin: o.to_array(),
        dir: d.normalize().to_array(),
        t_max,
        primitive,
    }
}

/// Random rays at random primitives (and at none), from anywhere around the scene.
fn random_rays(scene: &Scene, r: &mut TestRng, n: usize) -> Vec<RayCase> {
    let nt = scene.triangles.len() as u32;
    let ns = scene.spheres.len() as u32;
    (0..n)
        .map(|i| {
            let o = Vec3::new(r.range(-4.0, 4.0), r.range(-4.0, 4.0), r.range(-4.0, 4.0));
            // Half the rays aimed near a primitive, so that they hit it often.
            let k = (r.f32() * (nt + ns) as f32) as u32 % (nt + ns);
            let (target, prim) = if k < nt {
                let t = &scene.triangles[k as usize];
                (t.point(r.f32() * 0.6, r.f32() * 0.6), k)
            } else {
                let s = &scene.spheres[(k - nt) as usize];
                (s.center + r.dir() * s.radius * 1.1, SPHERE_BIT | (k - nt))
            };
            let d = if i % 2 == 0 { target - o } else { r.dir() };
            let t_max = [3.0e38, r.range(0.5, 8.0)][i % 3 / 2];
            case(o, d, t_max, if i % 17 == 0 { u32::MAX } else { prim })
        })
        .collect()
}

/// Rays from random origins aimed exactly at points of every triangle's edges (their ends,
/// midpoints and random points), each tested against every triangle that has that edge or
/// vertex; rays in each triangle's plane.
fn edge_rays(scene: &Scene, r: &mut TestRng) -> (Vec<RayCase>, Vec<(usize, usize)>) {
    let mut rays = Vec::new();
    let mut shared = Vec::new();
    let tris = &scene.triangles;
    let on_edge = |p: Vec3, j: usize| {
        let t = &tris[j];
        let vs = [t.v0, t.v1, t.v2];
        (0..3).any(|e| {
            let (a, b) = (vs[e], vs[(e + 1) % 3]);
            let ab = b - a;
            let s = (p - a).dot(ab) / ab.length_squared();
            (0.0..=1.0).contains(&s) && (a + s * ab - p).length() < 1e-6
        })
    };
    for (k, t) in tris.iter().enumerate() {
        let vs = [t.v0, t.v1, t.v2];
        for e in 0..3 {
            let (a, b) = (vs[e], vs[(e + 1) % 3]);
            for s in [0.0, 0.5, r.f32(), r.f32()] {
                let p = a + s * (b - a);
                let o = p + r.dir() * r.range(0.5, 4.0);
                let owners: Vec<usize> = (0..tris.len()).filter(|&j| on_edge(p, j)).collect();
                for &j in &owners {
                    rays.push(case(o, p - o, 3.0e38, j as u32));
                }
                // A shared edge the ray crosses (the two triangles on either side of the
                // plane through the edge and the ray; not a silhouette, which a ray may pass).
                if owners.len() == 2 && s > 0.0 && s < 1.0 {
                    let plane = (b - a).cross(p - o);
                    let side = |j: usize| {
                        let t = &tris[j];
                        let c = (t.v0 + t.v1 + t.v2) / 3.0;
                        plane.dot(c - a).signum()
                    };
                    if side(owners[0]) != side(owners[1]) {
                        shared.push((rays.len() - 2, rays.len() - 1));
                    }
                }
            }
        }
        // In the plane: through the centroid, from outside the triangle.
        let c = (t.v0 + t.v1 + t.v2) / 3.0;
        let along = (t.v1 - t.v0).normalize();
        rays.push(case(c - 3.0 * along, along, 3.0e38, k as u32));
    }
    (rays, shared)
}

/// Sphere edge cases: tangent rays, rays from the centre and from the surface outwards.
fn sphere_rays(scene: &Scene, r: &mut TestRng) -> Vec<RayCase> {
    let mut rays = Vec::new();
    for (k, s) in scene.spheres.iter().enumerate() {
        let id = SPHERE_BIT | k as u32;
        for _ in 0..20 {
            let n = r.dir();
            let t = n.any_orthonormal_vector();
            // Tangent at c + r n, from 2 units back.
            let p = s.center + s.radius * n;
            rays.push(case(p - 2.0 * t, t, 3.0e38, id));
            rays.push(case(s.center, r.dir(), 3.0e38, id));
            rays.push(case(p, n, 3.0e38, id));
            rays.push(case(p, -n, 3.0e38, id));
        }
    }
    rays
}

/// Compares one primitive's test; returns its (t ulps, barycentric error) for the report.
fn check_primitive(scene: &Scene, i: usize, c: &RayCase, g: &IntersectProbe) -> (u32, f32) {
    let want = host_primitive(scene, c);
    match (g.primitive, want) {
        (None, None) => (0, 0.0),
        (Some(g), Some(w)) => {
            assert!(
                ulps(g[0], w[0]) <= T_ULPS,
                "ray {i} {c:?}: t {} vs {}",
                g[0],
                w[0]
            );
            for k in 1..3 {
                assert!(
                    (g[k] - w[k]).abs() <= UV_ABS,
                    "ray {i} {c:?}: uv {g:?} vs {w:?}"
                );
            }
            let uv = (g[1] - w[1]).abs().max((g[2] - w[2]).abs());
            (ulps(g[0], w[0]), uv)
        }
        _ => panic!("ray {i} {c:?}: device {:?}, host {want:?}", g.primitive),
    }
}

#[test]
fn device_intersection_equals_the_hosts() {
    let Some(ctx) = gpu() else { return };
    let scene = scene();
    let bvh = Bvh::build(&scene);
    let mut r = TestRng(0x7a7);
    let mut rays = random_rays(&scene, &mut r, 3000);
    let n_random = rays.len();
    let (edges, shared) = edge_rays(&scene, &mut r);
    let first_edge = rays.len();
    rays.extend(edges);
    rays.extend(sphere_rays(&scene, &mut r));
    // t_max at the host's hit (a miss: hits count below t_max) and just past it.
    let at_hits: Vec<RayCase> = rays[..200]
        .iter()
        .filter_map(|c| host_primitive(&scene, c).map(|h| (c, h[0])))
        .flat_map(|(c, t)| [t, t.next_up()].map(|t_max| RayCase { t_max, ..*c }))
        .collect();
    rays.extend(at_hits);
    let mut probes = SceneProbes::new(&ctx, &scene, &RenderSettings::default()).unwrap();
    let got = probes.intersect(&rays).unwrap();
    let (mut hits, mut nearest) = (0, 0);
    let mut worst = (0u32, 0f32, 0u32);
    for (i, (c, g)) in rays.iter().zip(&got).enumerate() {
        let (t_ulps, uv) = check_primitive(&scene, i, c, g);
        worst = (worst.0.max(t_ulps), worst.1.max(uv), worst.2);
        hits += g.primitive.is_some() as usize;
        // The walk: the same nearest hit (a tie between primitives at one t, as on a shared
        // edge, may pick either: compared by t only there).
        let ray = Ray {
            origin: Vec3::from_array(c.origin),
            dir: Vec3::from_array(c.dir),
        };
        let want = bvh.intersect(&scene, &ray, c.t_max);
        assert_eq!(
            g.occluded,
            bvh.occluded(&scene, &ray, c.t_max),
            "ray {i} {c:?}: any hit"
        );
        match (g.nearest, want) {
            (None, None) => {}
            (Some((t, material, light)), Some(h)) => {
                assert!(
                    ulps(t, h.t) <= T_ULPS,
                    "ray {i} {c:?}: nearest t {t} vs {}",
                    h.t
                );
                nearest += 1;
                worst.2 = worst.2.max(ulps(t, h.t));
                if i < n_random {
                    assert_eq!(
                        (material, light),
                        (h.material, (h.light != u32::MAX).then_some(h.light))
                    );
                    let e = (Vec3::from_array(g.position) - h.position)
                        .abs()
                        .max_element();
                    assert!(
                        e <= 1e-5,
                        "ray {i}: position {:?} vs {}",
                        g.position,
                        h.position
                    );
                    let e = (Vec3::from_array(g.normal) - h.normal).abs().max_element();
                    assert!(e <= 1e-6, "ray {i}: normal {:?} vs {}", g.normal, h.normal);
                }
            }
            (g, w) => panic!(
                "ray {i} {c:?}: nearest device {g:?}, host {:?}",
                w.map(|h| h.t)
            ),
        }
    }
    // Watertight: of two triangles sharing an edge, a ray through the edge hits at least one.
    for &(a, b) in &shared {
        let (a, b) = (first_edge + a, first_edge + b);
        assert!(
            got[a].primitive.is_some() || got[b].primitive.is_some(),
            "rays {a}, {b}: through a shared edge, neither triangle hit"
        );
    }
    let degenerate = scene.triangles.len() as u32 - 1;
    assert!(rays[first_edge..]
        .iter()
        .zip(&got[first_edge..])
        .filter(|(c, _)| c.primitive == degenerate)
        .all(|(_, g)| g.primitive.is_none()));
    eprintln!(
        "{} rays: {hits} primitive hits, {nearest} nearest hits, {} shared-edge pairs; \
         worst t {} ulp, barycentrics {:e}, nearest t {} ulp",
        rays.len(),
        shared.len(),
        worst.0,
        worst.1,
        worst.2
    );
    assert!(hits > rays.len() / 3 && shared.len() >= 10);
}

/// The surface frame's helpers on the device equal their Rust twins: `phong_lobe`
/// (`sampling::phong_lobe`), `sphere_uv` (`texture::uv::sphere`), `reflection_leaks` and
/// `refraction_leaks` (`geometry::Facing`), `normal_mapped` (`geometry::normal_mapped`),
/// `bump_mapped` (`geometry::bump_mapped`; zero partials give `ns`), on
/// random cases plus the edges: exponents 0 and 10^4, u at 0 and 1, the poles, a degenerate
/// dp/du, mirrored frames, a flat frame (never leaks), directions in the geometric plane.
#[test]
fn surface_helpers_equal_the_hosts() {
    use gpu_photon::math::geometry::{bump_mapped, normal_mapped, Facing};
    use probes::{surface, SurfaceCase};
    let Some(ctx) = gpu() else {
        eprintln!("no GPU adapter: skipped");
        return;
    };
    let mut r = TestRng(0x5eed_5afe);
    let mut cases = Vec::new();
    for i in 0..2000 {
        let ng = r.dir();
        // Shading normals near the geometric one (a flat frame every 8th case).
        let ns = if i % 8 == 0 {
            ng
        } else {
            (ng + 0.4 * r.dir()).normalize()
        };
        let exponent = [0.0, 1.0, 20.0, 1e4][i % 4] * if i % 5 == 0 { 1.0 } else { r.f32() };
        let u = match i % 7 {
            0 => [0.0, 0.0],
            1 => [1.0, 1.0],
            _ => [r.f32(), r.f32()],
        };
        let axis = match i % 11 {
            0 => Vec3::Z,
            1 => -Vec3::Z,
            _ => r.dir(),
        };
        // A direction in the geometric plane every 9th case.
        let d = if i % 9 == 0 {
            let t = ng.cross(r.dir()).normalize();
            if t.is_finite() {
                t
            } else {
                r.dir()
            }
        } else {
            r.dir()
        };
        // A degenerate mapping (zero partials: no bump normal) every 17th case.
        let dp_du = match i {
            _ if i % 17 == 0 => Vec3::ZERO,
            _ if i % 13 == 0 => ns * 2.0,
            _ => r.dir() * 3.0,
        };
        let dp_dv = if i % 17 == 0 {
            Vec3::ZERO
        } else {
            r.dir() * 2.0
        };
        let grad = [r.range(-3.0, 3.0), r.range(-3.0, 3.0)];
        cases.push(SurfaceCase {
            axis: axis.to_array(),
            exponent,
            u,
            ng: ng.to_array(),
            ns: ns.to_array(),
            dp_du: dp_du.to_array(),
            flipped: i % 3 == 0,
            c: [r.f32(), r.f32(), r.f32()],
            d: d.to_array(),
            dp_dv: dp_dv.to_array(),
            grad,
            ..Default::default()
        });
    }
    let got = surface(&ctx, &cases).unwrap();
    let close = |a: Vec3, b: [f32; 3], tol: f32| (a - Vec3::from(b)).abs().max_element() <= tol;
    let (mut mapped_checked, mut bumped_checked) = (0, 0);
    for (i, (c, g)) in cases.iter().zip(&got).enumerate() {
        let (axis, ng, ns, d) = (
            Vec3::from(c.axis),
            Vec3::from(c.ng),
            Vec3::from(c.ns),
            Vec3::from(c.d),
        );
        let lobe = gpu_photon::math::sampling::phong_lobe(axis, c.exponent, c.u[0], c.u[1]);
        // sin = sqrt(1 - cos^2) magnifies pow's last-bit differences in cos by cos / sin
        // near the axis (large exponents).
        let sin = lobe.cross(axis).length().max(1e-6);
        let tol = 2e-5 + 4e-7 / sin;
        assert!(
            close(lobe, g.lobe, tol),
            "case {i}: lobe {lobe} vs {:?}",
            g.lobe
        );
        let uv = gpu_photon::textures::uv::sphere(axis);
        // u wraps at phi = 0: 1 - 1e-7 and 0 name the same point; at a pole every u does
        // (WGSL leaves atan2(0, 0) to the device: lavapipe's gives u = 0.375).
        let du = (uv.x - g.uv[0]).abs();
        let pole = axis.x == 0.0 && axis.y == 0.0;
        assert!(
            (pole || du.min(1.0 - du) <= 2e-6) && (uv.y - g.uv[1]).abs() <= 2e-6,
            "case {i}: uv {uv} vs {:?}",
            g.uv
        );
        let f = Facing::new(ng, ns, true);
        assert_eq!(
            g.leaks,
            [f.reflection_leaks(d), f.refraction_leaks(d)],
            "case {i}"
        );
        // The map's flip decision is a sign test: skip the cases within rounding of it.
        let m = normal_mapped(ng, ns, Vec3::from(c.dp_du), c.flipped, Vec3::from(c.c), d);
        let w = 2.0 * Vec3::from(c.c) - Vec3::ONE;
        if (d.dot(ns)).abs() > 1e-3 && w.length() > 1e-2 && m.dot(ng).abs() > 1e-3 {
            mapped_checked += 1;
            assert!(
                close(m, g.mapped, 1e-4),
                "case {i}: mapped {m} vs {:?}",
                g.mapped
            );
        }
        // The bump's flip is a sign test too: skip the cases within rounding of it (and of
        // the turn to ng's side).
        let (du, dv, grad) = (Vec3::from(c.dp_du), Vec3::from(c.dp_dv), Vec2::from(c.grad));
        let b = bump_mapped(ng, ns, du, dv, grad, d);
        let lift = |p: Vec3, g: f32| p + ns * (g - ns.dot(p));
        let raw = lift(du, grad.x).cross(lift(dv, grad.y)).normalize_or_zero();
        if du == Vec3::ZERO {
            assert_eq!(
                (b, Vec3::from(g.bumped)),
                (ns, ns),
                "case {i}: no bump normal"
            );
        } else if d.dot(ns).abs() > 1e-3 && d.dot(raw).abs() > 1e-3 && raw.dot(ng).abs() > 1e-3 {
            bumped_checked += 1;
            assert!(
                close(b, g.bumped, 1e-4),
                "case {i}: bumped {b} vs {:?}",
                g.bumped
            );
        }
    }
    assert!(mapped_checked > 1500, "{mapped_checked}");
    assert!(bumped_checked > 1500, "{bumped_checked}");
}

/// The four-wide walk (`walk_wide`, src/bvh/gpu_wide.wgsl) finds what the host's hierarchy
/// finds, and so does the binary walk, both run by the ray benchmark's kernel
/// (src/bench/gpu_rays.rs): on this file's scene
/// (random, edge and sphere rays, nearest and any hit) and on the Cornell box with a
/// displaced sphere of 20,000 triangles (a deeper tree; the benchmark's camera, shadow,
/// gather and photon rays), the same hit or miss, the nearest t within `T_ULPS`, the same
/// occlusion.
#[test]
fn the_wide_walk_finds_the_hosts_hits() {
    use gpu_photon::bench::gpu_rays::{GpuRays, Walk};
    use gpu_photon::bench::rays::{ray_sets, RayKind, RaySet};
    let Some(ctx) = gpu() else { return };
    let small = scene();
    let mut r = TestRng(0x51de);
    let mut cases = random_rays(&small, &mut r, 2000);
    cases.extend(edge_rays(&small, &mut r).0);
    cases.extend(sphere_rays(&small, &mut r));
    let set = |kind| RaySet {
        kind,
        rays: cases.iter().map(RayCase::ray).collect(),
        t_max: cases.iter().map(|c| c.t_max).collect(),
    };
    let cornell = gpu_photon::importers::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml"),
    )
    .expect("the Cornell box loads");
    let big = gpu_photon::bench::mesh::with_mesh(&cornell, 20_000);
    let big_sets = ray_sets(&big, 40, 40, 3);
    for (name, scene, sets) in [
        (
            "rays.toml",
            &small,
            vec![set(RayKind::Camera), set(RayKind::Shadow)],
        ),
        ("cornell-box + mesh", &big, big_sets),
    ] {
        let bvh = Bvh::build(scene);
        let mut device = GpuRays::new(&ctx, scene).expect("the benchmark's set-up");
        for set in &sets {
            for walk in Walk::ALL {
                let (got, _) = device.trace(walk, set).expect("traced");
                let mut hits = 0;
                for (i, ((ray, &t_max), g)) in set.rays.iter().zip(&set.t_max).zip(&got).enumerate()
                {
                    let at = format!("{name}, {} ray {i}, {}", set.kind.name(), walk.name());
                    if set.kind == RayKind::Shadow {
                        assert_eq!(
                            g.is_some(),
                            bvh.occluded(scene, ray, t_max),
                            "{at}: any hit"
                        );
                        continue;
                    }
                    match (g, bvh.closest(scene, ray, t_max)) {
                        (None, None) => {}
                        (Some((_, t)), Some(h)) => {
                            assert!(ulps(*t, h.1) <= T_ULPS, "{at}: nearest t {t} vs {}", h.1);
                            hits += 1;
                        }
                        (g, w) => panic!("{at}: device {g:?}, host {:?}", w.map(|h| h.1)),
                    }
                }
                assert!(
                    set.kind == RayKind::Shadow || hits > set.rays.len() / 4,
                    "{name}: {hits} hits"
                );
            }
        }
    }
}
