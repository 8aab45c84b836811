//! Smooth shading (vertex normals) on both backends, against analytic spheres.
//!
//! 1. A tessellated diffuse sphere (written here as OBJ with `vn`) lit by a point light, mode
//!    `direct-only`: smooth-shaded pixels follow the analytic sphere's cosine law within a
//!    tight bound; the same mesh flat-shaded (`smooth = false`) does not.
//! 2. No light leaks at the terminator: where the geometric surface faces away from the light
//!    a pixel is exactly black, even where the shading normal faces the light (an open mesh,
//!    so no other surface shadows it), on both backends.
//! 3. A tessellated glass sphere in the caustics scene renders within noise of the analytic
//!    sphere, on both backends; flat-shaded, it does not.
//! 4. CPU and GPU agree on a smooth-shaded mesh scene without glass, seed for seed.

mod common;

use common::gpu;
use glam::{DVec3, Vec3};
use gpu_photon::bsdfs::Bsdf;
use gpu_photon::bvh::Bvh;
use gpu_photon::importers::load_str;
use gpu_photon::math::geometry::Ray;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::{diff, DiffStats};
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::settings::{Mode, RenderSettings};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;

/// A fresh directory for this test's mesh files.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gpu-photon-smooth-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A UV sphere of `stacks` x `slices` (vertices on the sphere), as OBJ text with a `vn` per
/// vertex (the exact sphere normal); faces wound outwards. Only the faces whose three
/// corners' unit normals pass `keep` are written (all of them: a closed sphere). Returns the
/// text and the number of triangles.
fn uv_sphere_obj(
    center: Vec3,
    radius: f32,
    stacks: u32,
    slices: u32,
    keep: impl Fn(DVec3) -> bool,
) -> (String, usize) {
    let mut text = String::new();
    let mut normals = Vec::new();
    for i in 0..=stacks {
        let theta = PI * i as f64 / stacks as f64;
        for j in 0..slices {
            let phi = 2.0 * PI * j as f64 / slices as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let p = center.as_dvec3() + radius as f64 * n;
            writeln!(text, "v {} {} {}", p.x, p.y, p.z).unwrap();
            writeln!(text, "vn {} {} {}", n.x, n.y, n.z).unwrap();
            normals.push(n);
        }
    }
    let id = |i: u32, j: u32| i * slices + (j % slices) + 1;
    let mut count = 0;
    let mut face = |a: u32, b: u32, c: u32| {
        let n = |k: u32| normals[k as usize - 1];
        if ![a, b, c].iter().all(|&k| keep(n(k))) {
            return;
        }
        // Outward: the winding's normal along the corners' mean normal.
        let p = |k: u32| n(k);
        let outward = (p(b) - p(a)).cross(p(c) - p(a)).dot(p(a) + p(b) + p(c)) > 0.0;
        let (b, c) = if outward { (b, c) } else { (c, b) };
        writeln!(text, "f {a}//{a} {b}//{b} {c}//{c}").unwrap();
        count += 1;
    };
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if i != 0 {
                face(a, b, d);
            }
            if i + 1 != stacks {
                face(b, c, d);
            }
        }
    }
    (text, count)
}

fn run(scene: &Scene, settings: &RenderSettings, backend: Backend) -> Image {
    let (image, _) = render(scene, settings, backend, Progress::default()).unwrap();
    assert_eq!(image.non_finite(), 0, "NaN or infinity in the image");
    image
}

// ---------------------------------------------------------------------------------------------
// 1. The cosine law on a tessellated diffuse sphere
// ---------------------------------------------------------------------------------------------

const LIGHT: [f32; 3] = [4.0, 1.5, 2.5];
const INTENSITY: f32 = 12.0;
const ALBEDO: f32 = 0.8;
const SIZE: u32 = 40;

/// The diffuse sphere scene: `shape` is the TOML of the sphere's shape table.
fn diffuse_scene(shape: &str, dir: &std::path::Path) -> Scene {
    let [lx, ly, lz] = LIGHT;
    let text = format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\n\
         fov = 36.0\nwidth = {SIZE}\nheight = {SIZE}\n\
         [render]\nmode = \"direct-only\"\n\
         [materials.white]\ntype = \"diffuse\"\nalbedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]\n\
         [[shapes]]\nmaterial = \"white\"\n{shape}\n\
         [[lights]]\ntype = \"point\"\nposition = [{lx}, {ly}, {lz}]\n\
         intensity = [{INTENSITY}, {INTENSITY}, {INTENSITY}]\n"
    );
    load_str(&text, "smooth-sphere.toml", dir).unwrap()
}

/// Per pixel, the exact mean radiance over the pixel of the unit sphere at the origin lit as
/// in [`diffuse_scene`] (an 8 x 8 grid of rays, f64), and whether the pixel is well inside
/// the lit part (every ray hits with cos(view) > 0.5 and cos(light) > 0.2), where the
/// tessellation's silhouette and terminator do not reach.
fn analytic_sphere(scene: &Scene) -> Vec<(f64, bool)> {
    let cam = &scene.camera;
    let light = Vec3::from(LIGHT).as_dvec3();
    let eye = cam.eye.as_dvec3();
    let n = 8;
    let mut out = Vec::new();
    for py in 0..SIZE {
        for px in 0..SIZE {
            let (mut sum, mut inside) = (0.0, true);
            for k in 0..n * n {
                let (fx, fy) = ((k % n) as f32 + 0.5, (k / n) as f32 + 0.5);
                let d = cam
                    .direction(
                        px as f32 + fx / n as f32,
                        py as f32 + fy / n as f32,
                        SIZE,
                        SIZE,
                    )
                    .as_dvec3()
                    .normalize();
                let b = eye.dot(d);
                let disc = b * b - (eye.dot(eye) - 1.0);
                if disc <= 0.0 {
                    inside = false;
                    continue;
                }
                let p = eye + d * (-b - disc.sqrt());
                let to = light - p;
                let cos = p.dot(to) / to.length();
                inside &= -d.dot(p) > 0.5 && cos > 0.2;
                sum += ALBEDO as f64 / PI * INTENSITY as f64 * cos.max(0.0) / to.length_squared();
            }
            out.push((sum / (n * n) as f64, inside));
        }
    }
    out
}

/// Relative RMS and largest relative error of `image` (red) against the analytic means,
/// over the pixels well inside the lit part.
fn relative_error(image: &Image, analytic: &[(f64, bool)]) -> (f64, f64, usize) {
    let (mut sum2, mut max, mut count) = (0.0, 0.0f64, 0);
    for (px, &(want, inside)) in image.pixels.iter().zip(analytic) {
        if inside {
            let e = (px[0] as f64 - want) / want;
            sum2 += e * e;
            max = max.max(e.abs());
            count += 1;
        }
    }
    ((sum2 / count as f64).sqrt(), max, count)
}

#[test]
fn smooth_shading_follows_the_analytic_cosine_law_and_flat_does_not() {
    let dir = temp_dir("cosine");
    let (obj, tris) = uv_sphere_obj(Vec3::ZERO, 1.0, 24, 48, |_| true);
    std::fs::write(dir.join("sphere.obj"), obj).unwrap();
    let mesh = |smooth: bool| format!("type = \"mesh\"\nfile = \"sphere.obj\"\nsmooth = {smooth}");
    let smooth = diffuse_scene(&mesh(true), &dir);
    let flat = diffuse_scene(&mesh(false), &dir);
    let exact = diffuse_scene(
        "type = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0",
        &dir,
    );
    assert_eq!(
        smooth.shading_normals.len(),
        tris,
        "one normal set per triangle"
    );
    assert!(
        flat.shading_normals.is_empty(),
        "smooth = false drops the normals"
    );
    let analytic = analytic_sphere(&exact);
    let s = RenderSettings {
        spp: 16,
        ..smooth.settings.clone()
    };
    let mut backends = vec![Backend::Cpu];
    if gpu().is_some() {
        backends.push(Backend::Gpu);
    }
    for backend in backends {
        let (e_exact, _, count) = relative_error(&run(&exact, &s, backend), &analytic);
        let (e_smooth, max_smooth, _) = relative_error(&run(&smooth, &s, backend), &analytic);
        let (e_flat, max_flat, _) = relative_error(&run(&flat, &s, backend), &analytic);
        eprintln!(
            "{backend:?}, {tris} triangles, {count} pixels: relative rms (max) analytic sphere \
             {e_exact:.5}, smooth {e_smooth:.5} ({max_smooth:.4}), flat {e_flat:.5} ({max_flat:.4})"
        );
        assert!(count >= 250, "{count} pixels compared");
        // The analytic sphere's own error is the pixel jitter's (spp 16).
        assert!(e_exact < 0.002, "{backend:?}: analytic sphere {e_exact}");
        assert!(
            e_smooth < 0.004 && max_smooth < 0.01,
            "{backend:?}: smooth {e_smooth}"
        );
        assert!(
            e_flat > 0.02 && e_flat > 5.0 * e_smooth,
            "{backend:?}: flat {e_flat}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. No light leaks at the terminator
// ---------------------------------------------------------------------------------------------

#[test]
fn no_light_leaks_where_the_geometric_surface_faces_away() {
    // Part of an open cap of a coarse sphere (the upper half, without the side nearest the
    // light), seen from above, lit by a light low on its side: past the terminator the facets
    // face away from the light while their interpolated normals still face it, and nothing
    // is there to cast a shadow (the near side that would is cut away).
    let dir = temp_dir("terminator");
    let (obj, _) = uv_sphere_obj(Vec3::ZERO, 1.0, 8, 16, |n| n.y >= 0.0 && n.x <= 0.3);
    std::fs::write(dir.join("cap.obj"), obj).unwrap();
    let text = "[camera]\neye = [0.0, 4.0, 0.5]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
                fov = 40.0\nwidth = 64\nheight = 64\n[render]\nmode = \"direct-only\"\n\
                [materials.white]\ntype = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]\n\
                [[shapes]]\ntype = \"mesh\"\nfile = \"cap.obj\"\nmaterial = \"white\"\n\
                [[lights]]\ntype = \"point\"\nposition = [6.0, 0.2, 0.0]\nintensity = [30.0, 30.0, 30.0]\n";
    let scene = load_str(text, "cap.toml", &dir).unwrap();
    let light = Vec3::new(6.0, 0.2, 0.0);
    // Pixels whose every point (a 5 x 5 grid over the pixel, its edges included) hits a
    // triangle facing away from the light; of those, the ones where some shading normal
    // faces the light (where a leak would show).
    let bvh = Bvh::build(&scene);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let (mut away, mut tempting) = (Vec::new(), 0);
    for py in 0..h {
        for px in 0..w {
            let (mut all_away, mut any_tempting) = (true, false);
            for k in 0..25 {
                let (fx, fy) = ((k % 5) as f32 / 4.0, (k / 5) as f32 / 4.0);
                let d = scene.camera.direction(px as f32 + fx, py as f32 + fy, w, h);
                let ray = Ray {
                    origin: scene.camera.eye,
                    dir: d,
                };
                match bvh.intersect(&scene, &ray, f32::INFINITY) {
                    Some(hit) => {
                        let wi = light - hit.position;
                        let side = if d.dot(hit.normal) < 0.0 { 1.0 } else { -1.0 };
                        all_away &= wi.dot(side * hit.normal) < 0.0;
                        any_tempting |= wi.dot(side * hit.shading) > 0.0;
                    }
                    None => all_away = false,
                }
            }
            if all_away {
                away.push((py * w + px) as usize);
                tempting += any_tempting as usize;
            }
        }
    }
    eprintln!("{} pixels face away from the light, {tempting} of them with a shading normal that faces it", away.len());
    assert!(
        tempting >= 30,
        "the scene must tempt a leak ({tempting} pixels)"
    );
    let mut backends = vec![Backend::Cpu];
    if gpu().is_some() {
        backends.push(Backend::Gpu);
    }
    for backend in backends {
        let image = run(&scene, &scene.settings, backend);
        let lit = image.pixels.iter().filter(|p| p[0] > 0.0).count();
        eprintln!("{backend:?}: {lit} pixels lit");
        assert!(lit > 20, "{backend:?}: the lit side is lit ({lit} pixels)");
        let leaks: Vec<_> = away
            .iter()
            .filter(|&&i| image.pixels[i] != [0.0; 3])
            .map(|&i| (i % w as usize, i / w as usize, image.pixels[i]))
            .collect();
        assert!(leaks.is_empty(), "{backend:?}: light leaks at {leaks:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 3. The tessellated glass sphere in the caustics scene
// ---------------------------------------------------------------------------------------------

/// scenes/cornell-caustics.toml with its glass sphere replaced by `shape` (TOML lines).
fn caustics_with(shape: Option<&str>, dir: &std::path::Path) -> Scene {
    let text = std::fs::read_to_string("scenes/cornell-caustics.toml").unwrap();
    let glass = "type = \"sphere\"\ncenter = [0.45, -0.6, 0.3]\nradius = 0.4\nmaterial = \"crown\"";
    assert!(
        text.contains(glass),
        "the caustics scene's glass sphere moved"
    );
    let text = match shape {
        Some(s) => text.replace(glass, &format!("{s}\nmaterial = \"crown\"")),
        None => text,
    };
    load_str(&text, "caustics-mesh.toml", dir).unwrap()
}

fn caustics_settings(scene: &Scene, seed: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 48,
        spp: 4,
        photons: 40_000,
        caustic_photons: 20_000,
        seed,
        ..scene.settings.clone()
    }
}

/// The glass test's settings: enough caustic photons and samples that the sphere's own
/// pixels and its caustic are not lost in the noise.
fn glass_settings(scene: &Scene, seed: u32) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 64,
        spp: 32,
        photons: 60_000,
        caustic_photons: 100_000,
        seed,
        ..scene.settings.clone()
    }
}

/// The pixels (by the analytic scene's camera ray through the pixel centre) that see the
/// glass sphere, and those that see the floor where its caustic lies (within 0.3 of the
/// point below the sphere away from the light).
fn glass_regions(scene: &Scene, s: &RenderSettings) -> [Vec<usize>; 2] {
    let bvh = Bvh::build(scene);
    let caustic = Vec3::new(0.55, -1.0, 0.4);
    let mut regions = [Vec::new(), Vec::new()];
    for py in 0..s.height {
        for px in 0..s.width {
            let dir = scene
                .camera
                .direction(px as f32 + 0.5, py as f32 + 0.5, s.width, s.height);
            let ray = Ray {
                origin: scene.camera.eye,
                dir,
            };
            let Some(hit) = bvh.intersect(scene, &ray, f32::INFINITY) else {
                continue;
            };
            let i = (py * s.width + px) as usize;
            if matches!(scene.materials[hit.material as usize].bsdf, Bsdf::Glass(_)) {
                regions[0].push(i);
            } else if hit.position.y < -0.999 && hit.position.distance(caustic) < 0.3 {
                regions[1].push(i);
            }
        }
    }
    regions
}

/// RMSE of `a` against `b` over the pixels `region`.
fn region_rmse(a: &Image, b: &Image, region: &[usize]) -> f64 {
    let sum: f64 = region
        .iter()
        .map(|&i| {
            (0..3)
                .map(|c| (a.pixels[i][c] as f64 - b.pixels[i][c] as f64).powi(2))
                .sum::<f64>()
                / 3.0
        })
        .sum();
    (sum / region.len() as f64).sqrt()
}

#[test]
fn tessellated_glass_sphere_renders_within_noise_of_the_analytic_one() {
    let dir = temp_dir("glass");
    let (obj, tris) = uv_sphere_obj(Vec3::new(0.45, -0.6, 0.3), 0.4, 32, 64, |_| true);
    std::fs::write(dir.join("glass.obj"), obj).unwrap();
    let exact = caustics_with(None, &dir);
    let smooth = caustics_with(Some("type = \"mesh\"\nfile = \"glass.obj\""), &dir);
    let flat = caustics_with(
        Some("type = \"mesh\"\nfile = \"glass.obj\"\nsmooth = false"),
        &dir,
    );
    assert!(smooth.has_smooth() && !flat.has_smooth());
    let regions = glass_regions(&exact, &glass_settings(&exact, 1));
    let mut backends = vec![Backend::Cpu];
    if gpu().is_some() {
        backends.push(Backend::Gpu);
    }
    let mut failures = Vec::new();
    for backend in backends {
        let r = |scene: &Scene, seed| run(scene, &glass_settings(scene, seed), backend);
        // The noise: two seeds of the analytic sphere on this backend (the GPU chooses one
        // glass branch where the CPU splits the first ones: more noise inside the sphere).
        let exact2 = r(&exact, 2);
        let exact1 = r(&exact, 1);
        let noise = regions.each_ref().map(|g| region_rmse(&exact1, &exact2, g));
        let mut same_seed = [[0.0; 2]; 2];
        for (k, (what, scene)) in [("smooth", &smooth), ("flat", &flat)]
            .into_iter()
            .enumerate()
        {
            let image = r(scene, 1);
            let e = regions.each_ref().map(|g| region_rmse(&image, &exact2, g));
            same_seed[k] = regions.each_ref().map(|g| region_rmse(&image, &exact1, g));
            let l = format!(
                "{backend:?} {what} ({tris} triangles): rmse against analytic seed 2 on the \
                 sphere {:.5}, on its caustic {:.5} (noise: analytic seed 1 {:.5}, {:.5}); \
                 against analytic seed 1 (same seed) {:.5}, {:.5}",
                e[0], e[1], noise[0], noise[1], same_seed[k][0], same_seed[k][1]
            );
            eprintln!("{l}");
            // The smooth sphere: within the noise, like another seed of the analytic one.
            if k == 0 && !(0..2).all(|g| e[g] <= common::SEED_NOISE_RMSE_SLACK * noise[g]) {
                failures.push(l);
            }
        }
        // Same seed, same random numbers: the smooth sphere's paths follow the analytic
        // one's, the flat facets scatter them (on the sphere and in its caustic).
        let [smooth_same, flat_same] = same_seed;
        for g in 0..2 {
            if !(smooth_same[g] <= 0.5 * noise[g] && flat_same[g] >= 2.0 * smooth_same[g]) {
                failures.push(format!(
                    "{backend:?} region {g}: same-seed rmse smooth {:.5}, flat {:.5}, noise {:.5}",
                    smooth_same[g], flat_same[g], noise[g]
                ));
            }
        }
        if flat_same[0] < 0.5 * noise[0] {
            failures.push(format!(
                "{backend:?}: flat facets lost in the noise on the sphere"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn line(what: &str, d: &DiffStats, noise: &DiffStats) -> String {
    format!(
        "{what}: rmse {:.5} (noise {:.5}), block rmse {:.5} (noise {:.5})",
        d.rmse, noise.rmse, d.block_rmse, noise.block_rmse
    )
}

// ---------------------------------------------------------------------------------------------
// 4. CPU and GPU on a smooth-shaded mesh scene
// ---------------------------------------------------------------------------------------------

#[test]
fn gpu_matches_cpu_on_a_smooth_mesh_scene() {
    let Some(_ctx) = gpu() else { return };
    // The Cornell box of the caustics scene with a smooth diffuse sphere (coarse, so that
    // shading normals and geometric normals differ a lot) where the glass one was, and the
    // mirror sphere; mode gather (shadow rays, caustics, gather rays into the cache).
    let dir = temp_dir("backends");
    let (obj, _) = uv_sphere_obj(Vec3::new(0.45, -0.6, 0.3), 0.4, 10, 20, |_| true);
    std::fs::write(dir.join("ball.obj"), obj).unwrap();
    let scene = caustics_with(
        Some("type = \"mesh\"\nfile = \"ball.obj\"\nsmooth = true"),
        &dir,
    );
    let scene = Scene {
        materials: scene
            .materials
            .iter()
            .map(|m| match m.bsdf {
                Bsdf::Glass(_) => gpu_photon::scene::Material::diffuse(Vec3::splat(0.7)),
                _ => *m,
            })
            .collect(),
        ..scene
    };
    let mut failures = Vec::new();
    for mode in [Mode::Gather, Mode::Direct] {
        let s = |seed| RenderSettings {
            mode,
            ..caustics_settings(&scene, seed)
        };
        let cpu1 = run(&scene, &s(1), Backend::Cpu);
        let cpu2 = run(&scene, &s(2), Backend::Cpu);
        let gpu1 = run(&scene, &s(1), Backend::Gpu);
        let noise = diff(&cpu1, &cpu2, 8).unwrap();
        let cross = diff(&gpu1, &cpu2, 8).unwrap();
        let same = diff(&gpu1, &cpu1, 8).unwrap();
        let l = line(&format!("{mode:?}: gpu1 vs cpu2"), &cross, &noise);
        eprintln!("{l}; same seed rmse {:.6}", same.rmse);
        let (pixels, blocks) = common::within_seed_noise(&cross, &noise, 1e-6);
        if !(pixels && blocks) {
            failures.push(l);
        }
        // No glass: both backends draw the same numbers for the same paths.
        if same.rmse > 0.01 * noise.rmse {
            failures.push(format!(
                "{mode:?}: same seed rmse {:.6} vs noise {:.6}",
                same.rmse, noise.rmse
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// 5. Vertex normals from each format
// ---------------------------------------------------------------------------------------------

const CAMERA: &str = "[camera]\neye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\nfov = 40.0\n\
                      [materials.white]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n";

/// The scene of one TOML mesh shape (`keys` added to its table) over `file`, or its error.
fn toml_mesh(dir: &std::path::Path, file: &str, keys: &str) -> Result<Scene, String> {
    let text = format!(
        "{CAMERA}[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"white\"\n{keys}\n"
    );
    load_str(&text, "mesh.toml", dir).map_err(|e| e.to_string())
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn obj_and_ply_normals_are_read_transformed_and_checked() {
    let dir = temp_dir("formats");
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 1 0 1\nvn 0 1 1\n";
    std::fs::write(dir.join("tri.obj"), format!("{tri}f 1//1 2//2 3//3\n")).unwrap();
    // A mirroring scale: positions scaled, normals divided by the scale and renormalised,
    // corners 1 and 2 swapped with their normals (fronts stay outside).
    let s = toml_mesh(&dir, "tri.obj", "scale = [-1.0, 2.0, 1.0]").unwrap();
    assert_eq!(s.triangles[0].shading, 0);
    let want = [
        Vec3::Z,
        Vec3::new(0.0, 0.5, 1.0).normalize(),
        Vec3::new(-1.0, 0.0, 1.0).normalize(),
    ];
    for (got, want) in s.shading_normals[0].iter().zip(want) {
        assert!(close(*got, want), "{:?}", s.shading_normals[0]);
    }
    assert_eq!(s.triangles[0].v1, Vec3::new(0.0, 2.0, 0.0));
    // smooth = false: flat, no normals kept.
    let s = toml_mesh(&dir, "tri.obj", "smooth = false").unwrap();
    assert!(s.shading_normals.is_empty() && s.triangles[0].shading == gpu_photon::scene::FLAT);
    // A corner without a normal: the whole mesh is flat; smooth = true then is an error.
    std::fs::write(dir.join("part.obj"), format!("{tri}f 1//1 2 3//3\n")).unwrap();
    assert!(toml_mesh(&dir, "part.obj", "")
        .unwrap()
        .shading_normals
        .is_empty());
    let e = toml_mesh(&dir, "part.obj", "smooth = true").unwrap_err();
    assert!(
        e.contains("part.obj") && e.contains("no vertex normals"),
        "{e}"
    );
    // Zero, NaN and missing normals: errors naming the file and the field.
    let bad = [
        (
            "zero.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n",
            "vn",
        ),
        (
            "nan.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan 0 1\nf 1//1 2//1 3//1\n",
            "vn",
        ),
        (
            "range.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//7\n",
            "3//7",
        ),
        (
            "ahead.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//2\nvn 0 0 1\nvn 0 0 1\n",
            "1//1",
        ),
    ];
    for (file, text, field) in bad {
        std::fs::write(dir.join(file), text).unwrap();
        let e = toml_mesh(&dir, file, "").unwrap_err();
        assert!(e.contains(file) && e.contains(field), "{file}: {e}");
    }
    let ply = |n: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
             property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n\
             0 0 0 0 0 1\n1 0 0 {n}\n0 1 0 0 0 1\n3 0 1 2\n"
        )
    };
    std::fs::write(dir.join("ok.ply"), ply("0 2 2")).unwrap();
    let s = toml_mesh(&dir, "ok.ply", "").unwrap();
    let n = Vec3::new(0.0, 1.0, 1.0).normalize();
    let got = s.shading_normals[0];
    assert!(
        close(got[0], Vec3::Z) && close(got[1], n) && close(got[2], Vec3::Z),
        "{got:?}"
    );
    // Normals along the face normal (a planar mesh): flat, nothing kept.
    std::fs::write(dir.join("planar.ply"), ply("0 0 2")).unwrap();
    let s = toml_mesh(&dir, "planar.ply", "").unwrap();
    assert!(s.shading_normals.is_empty() && s.triangles[0].shading == gpu_photon::scene::FLAT);
    std::fs::write(dir.join("zero.ply"), ply("0 0 0")).unwrap();
    let e = toml_mesh(&dir, "zero.ply", "").unwrap_err();
    assert!(
        e.contains("zero.ply") && e.contains("vertex 1") && e.contains("nx, ny, nz"),
        "{e}"
    );
}

#[test]
fn mitsuba_face_normals_forces_flat_shading() {
    let dir = temp_dir("mitsuba");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 1 0 1\nvn 0 1 1\nf 1//1 2//2 3//3\n";
    std::fs::write(dir.join("tri.obj"), obj).unwrap();
    let xml = |extra: &str| {
        format!(
            "<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\
             <transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform></sensor>\
             <shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/>{extra}\
             <transform name=\"to_world\"><scale x=\"2\" y=\"1\" z=\"1\"/></transform></shape></scene>"
        )
    };
    let import = |text: &str| {
        gpu_photon::importers::mitsuba::import(text, "t.xml", &dir)
            .unwrap()
            .scene
    };
    let smooth = import(&xml(""));
    // The inverse transpose of scale(2, 1, 1) halves the normal's x.
    assert!(close(
        smooth.shading_normals[0][1],
        Vec3::new(0.5, 0.0, 1.0).normalize()
    ));
    let flat = import(&xml("<boolean name=\"face_normals\" value=\"true\"/>"));
    assert!(flat.shading_normals.is_empty());
}

#[test]
fn gltf_normals_go_through_the_inverse_transpose_and_zero_ones_are_refused() {
    let dir = temp_dir("gltf");
    let gltf = |normals: [Vec3; 3]| {
        let points = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let mut bytes = Vec::new();
        for v in points.iter().chain(&normals) {
            for x in v.to_array() {
                bytes.extend(x.to_le_bytes());
            }
        }
        format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
"nodes": [{{"mesh": 0, "scale": [2, 1, 1]}}, {{"camera": 0, "translation": [0, 0, 5]}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "znear": 0.1}}}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}}}]}}],
"buffers": [{{"byteLength": 72, "uri": "data:application/octet-stream;base64,{}"}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 36}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
{{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#,
            common::b64(&bytes)
        )
    };
    let path = dir.join("tri.gltf");
    let n = Vec3::new(1.0, 0.0, 1.0).normalize();
    std::fs::write(&path, gltf([Vec3::Z, n, Vec3::Z])).unwrap();
    let s = gpu_photon::importers::load(&path).unwrap();
    assert!(
        close(
            s.shading_normals[0][1],
            Vec3::new(0.5, 0.0, 1.0).normalize()
        ),
        "{:?}",
        s.shading_normals
    );
    assert!(close(s.shading_normals[0][0], Vec3::Z));
    std::fs::write(&path, gltf([Vec3::Z, Vec3::ZERO, Vec3::Z])).unwrap();
    let e = gpu_photon::importers::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("tri.gltf") && e.contains("NORMAL 1 is zero"),
        "{e}"
    );
}
