//! An analytic texture test on both backends: a textured square under a directional light
//! renders `albedo(u, v) / pi * E cos(theta)` at every pixel whose footprint lies inside one
//! texel (nearest filtering, so the footprint average is that texel's value), and the image
//! mean is the texels' mean over the visible area.

mod common;

use glam::{Vec2, Vec3};
use gpu_photon::bsdfs::BsdfKind;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{Material, Origin, Scene, SceneBuilder, Surface};
use gpu_photon::settings::{Mode, RenderSettings};
use gpu_photon::textures::{Encoding, Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap};

/// Texels of the 4 x 4 test texture (raw 8-bit, so a channel reads exactly byte / 255).
fn texel_bytes(x: u32, y: u32) -> [u8; 4] {
    [
        (40 + 50 * x) as u8,
        (30 + 60 * y) as u8,
        (200 - 30 * (x + y)) as u8,
        255,
    ]
}

const EYE_Z: f32 = 3.0;
const FOV: f32 = 30.0;
const SIDE: u32 = 64;

/// The unit square [-1, 1]^2 in z = 0 (uv as Mitsuba's rectangle: (x + 1) / 2, (y + 1) / 2),
/// textured, under a directional light along `dir` of irradiance `e`.
fn scene(dir: Vec3, e: f32) -> Scene {
    let at = Origin {
        file: "test".into(),
        line: 1,
        field: "scene".into(),
    };
    let mut b = SceneBuilder::new();
    b.camera(Vec3::new(0.0, 0.0, EYE_Z), Vec3::ZERO, Vec3::Y, FOV, &at)
        .unwrap();
    let texels = (0..16)
        .map(|i| gpu_photon::textures::pack_rgba8(texel_bytes(i % 4, i / 4)))
        .collect();
    let tex = Texture::from_rgba8("test", 4, 4, texels, Encoding::Raw)
        .unwrap()
        .with_sampler(Sampler::mitsuba(
            Filter::Nearest,
            Wrap::Clamp,
            UvTransform::IDENTITY,
        ));
    let id = b.add_texture(SceneTexture::Bitmap(tex), &at).unwrap();
    let mut m = Material::diffuse(Vec3::splat(0.5));
    *m.bsdf.base_colour_mut().expect("a diffuse reflectance") =
        gpu_photon::bsdfs::Param::texture(id);
    let mat = b.add_material(None, m, &at).unwrap();
    let c = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let uv = |p: Vec3| Vec2::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5);
    let tris = vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]];
    let uvs = tris.iter().map(|t| t.map(uv)).collect();
    b.add_uv_mesh(tris, None, uvs, Surface::of(mat), &at)
        .unwrap();
    b.add_directional_light(dir, Vec3::splat(e), &at).unwrap();
    b.finish(&at).unwrap()
}

/// The texel (column, row) the camera ray through raster point (px, py) lands on.
fn texel_at(px: f32, py: f32) -> (u32, u32) {
    let t = (FOV.to_radians() * 0.5).tan();
    let sx = (2.0 * px / SIDE as f32 - 1.0) * t;
    let sy = (1.0 - 2.0 * py / SIDE as f32) * t;
    // The ray (sx, sy, -1) from z = EYE_Z meets z = 0 at EYE_Z (sx, sy).
    let (u, v) = ((EYE_Z * sx + 1.0) * 0.5, (EYE_Z * sy + 1.0) * 0.5);
    let q = |w: f32| ((w * 4.0).floor() as i32).clamp(0, 3) as u32;
    (q(u), q(v))
}

fn check(backend: Backend) {
    let theta = 35f32.to_radians();
    let e = 2.0;
    let dir = Vec3::new(theta.sin(), 0.0, -theta.cos());
    let s = RenderSettings {
        width: SIDE,
        height: SIDE,
        spp: 4,
        mode: Mode::DirectOnly,
        ..Default::default()
    };
    let (img, _) = render(&scene(dir, e), &s, backend, Progress::default()).unwrap();
    let scale = e * theta.cos() / std::f32::consts::PI;
    let (mut checked, mut worst) = (0, 0.0f32);
    for py in 0..SIDE {
        for px in 0..SIDE {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(dx, dy)| texel_at(px as f32 + dx, py as f32 + dy));
            if corners.iter().any(|c| *c != corners[0]) {
                continue;
            }
            let (x, y) = corners[0];
            let b = texel_bytes(x, y);
            let got = img.pixels[(py * SIDE + px) as usize];
            for c in 0..3 {
                let want = b[c] as f32 / 255.0 * scale;
                worst = worst.max((got[c] - want).abs() / want);
            }
            checked += 1;
        }
    }
    // Most pixels lie inside one texel (16 texels over a 64 x 64 image, the square filling
    // ~79% of it), and each reads the analytic value up to f32 rounding.
    assert!(checked > 2000, "{checked} pixels checked");
    assert!(worst < 1e-4, "{backend:?}: worst relative error {worst}");
}

#[test]
fn textured_square_under_a_sun_is_albedo_over_pi_times_e_cos_cpu() {
    check(Backend::Cpu);
}

#[test]
fn textured_square_under_a_sun_is_albedo_over_pi_times_e_cos_gpu() {
    if common::gpu().is_none() {
        return;
    }
    check(Backend::Gpu);
}
