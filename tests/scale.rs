//! Scale: `scenes/cornell-caustics.toml` with its glass sphere replaced by a generated
//! 500,000-triangle sphere mesh (written as binary PLY into a temporary directory, never
//! committed), rendered small on both backends. The GPU image must agree with the CPU's as
//! every example scene does (tests/gpu_images.rs statistic), and no GPU bound may be hit: the
//! BVH traversal's loop budget, the photon buffers and the searches all suffice.

mod common;

use common::{gpu, within_seed_noise};
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::settings::RenderSettings;
use std::f32::consts::PI;
use std::io::Write;

/// Slices around the axis; the stacks are one more, so the sphere has 2 SLICES (STACKS - 1)
/// = 500,000 triangles.
const SLICES: u32 = 500;
const STACKS: u32 = 501;

/// A UV sphere (centre `c`, radius `r`) as binary little-endian PLY, faces wound outwards.
fn sphere_ply(c: [f32; 3], r: f32) -> Vec<u8> {
    let mut verts = vec![[c[0], c[1] + r, c[2]]];
    for i in 1..STACKS {
        let theta = PI * i as f32 / STACKS as f32;
        for j in 0..SLICES {
            let phi = 2.0 * PI * j as f32 / SLICES as f32;
            verts.push([
                c[0] + r * theta.sin() * phi.cos(),
                c[1] + r * theta.cos(),
                c[2] + r * theta.sin() * phi.sin(),
            ]);
        }
    }
    verts.push([c[0], c[1] - r, c[2]]);
    let bottom = verts.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * SLICES + j % SLICES;
    let mut faces = Vec::new();
    for j in 0..SLICES {
        faces.push([0, ring(1, j + 1), ring(1, j)]);
        faces.push([bottom, ring(STACKS - 1, j), ring(STACKS - 1, j + 1)]);
    }
    for i in 1..STACKS - 1 {
        for j in 0..SLICES {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c2, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            faces.push([a, b, d]);
            faces.push([a, d, c2]);
        }
    }
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        verts.len(),
        faces.len()
    )
    .into_bytes();
    for v in &verts {
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    for f in &faces {
        out.push(3);
        for i in f {
            out.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    out
}

fn settings(scene: &gpu_photon::scene::Scene, seed: u32) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 24,
        spp: 2,
        photons: 10_000,
        caustic_photons: 5_000,
        seed,
        ..scene.settings.clone()
    }
}

#[test]
fn half_a_million_triangle_glass_sphere_renders_alike_on_both_backends() {
    let Some(_ctx) = gpu() else { return };
    let dir = std::env::temp_dir().join(format!("gpu-photon-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("scenes/cornell-caustics.toml").unwrap();
    let sphere = "[[shapes]]\ntype = \"sphere\"\ncenter = [0.45, -0.6, 0.3]\nradius = 0.4\n\
                  material = \"crown\"\n";
    assert!(text.contains(sphere), "the glass sphere moved in the scene");
    let mesh = "[[shapes]]\ntype = \"mesh\"\nfile = \"sphere.ply\"\nmaterial = \"crown\"\n";
    std::fs::File::create(dir.join("sphere.ply"))
        .unwrap()
        .write_all(&sphere_ply([0.45, -0.6, 0.3], 0.4))
        .unwrap();
    let scene_path = dir.join("scale.toml");
    std::fs::write(&scene_path, text.replace(sphere, mesh)).unwrap();
    let scene = gpu_photon::importers::load(&scene_path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        scene.triangles.len(),
        2 * SLICES as usize * (STACKS as usize - 1) + 12,
        "the sphere's triangles and the box's walls and light"
    );

    let run = |backend, seed| {
        let t = std::time::Instant::now();
        let out = render(
            &scene,
            &settings(&scene, seed),
            backend,
            Progress::default(),
        )
        .unwrap();
        eprintln!(
            "{backend:?} seed {seed}: {:.2?} {:?}",
            t.elapsed(),
            out.1.phases
        );
        out
    };
    let (cpu1, _) = run(Backend::Cpu, 1);
    let (cpu2, _) = run(Backend::Cpu, 2);
    let (gpu1, report) = run(Backend::Gpu, 1);
    assert_eq!(
        report.gpu_stats[..3],
        [0, 0, 0],
        "GPU bounds hit (photons dropped, loop budget, truncated searches)"
    );
    assert_eq!(gpu1.non_finite(), 0, "NaN or infinity in the GPU image");
    let noise = diff(&cpu1, &cpu2, 8).unwrap();
    let cross = diff(&gpu1, &cpu2, 8).unwrap();
    let (pixels, blocks) = within_seed_noise(&cross, &noise, 1e-6);
    assert!(
        pixels && blocks,
        "rmse gpu1-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}",
        cross.rmse,
        noise.rmse,
        cross.block_rmse,
        noise.block_rmse
    );
}
