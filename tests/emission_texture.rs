//! Textured emission (`Material::emission_texture`, glTF's `emissiveTexture`): the camera
//! sees the emitter's radiance times the texel, the light's power includes the texture's
//! mean, and a floor lit by it receives the same light from shadow rays (which weigh each
//! sampled point by its texel) as from photons (which carry texel / mean): two estimators
//! of one integral; the GPU renders it as the CPU does.

use glam::{Vec2, Vec3};
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{Material, Origin, Scene, SceneBuilder, Surface};
use gpu_photon::settings::{Mode, RenderSettings};
use gpu_photon::textures::{Encoding, Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap};
use std::f32::consts::PI;

mod common;

/// Texels of the 2 x 2 emission texture (raw 8-bit: a channel reads byte / 255).
const TEXELS: [[u8; 4]; 4] = [
    [255, 51, 0, 255],
    [0, 255, 102, 255],
    [51, 0, 255, 255],
    [255, 255, 255, 255],
];

fn at() -> Origin {
    Origin {
        file: "test".into(),
        line: 1,
        field: "scene".into(),
    }
}

/// A 0.5 x 0.5 emitter of radiance `L x texel` facing down at height 1 over a 6 x 6 grey floor
/// (albedo 0.5); the camera at height 0.5 looks down at the floor (`up`: false) or up at the
/// emitter's centre.
fn scene(l: f32, up: bool) -> Scene {
    let mut b = SceneBuilder::new();
    let (eye, target) = match up {
        true => (Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 1.0, 0.0)),
        // Off centre, nearer one quadrant: the floor there is not lit in the mean colour.
        false => (Vec3::new(0.4, 0.5, 0.4), Vec3::new(0.4, 0.0, 0.4)),
    };
    b.camera(eye, target, Vec3::Z, 20.0, &at()).unwrap();
    let texels = TEXELS
        .iter()
        .map(|t| gpu_photon::textures::pack_rgba8(*t))
        .collect();
    let tex = Texture::from_rgba8("emission", 2, 2, texels, Encoding::Raw)
        .unwrap()
        .with_sampler(Sampler::mitsuba(
            Filter::Nearest,
            Wrap::Clamp,
            UvTransform::IDENTITY,
        ));
    let tex = b.add_texture(SceneTexture::Bitmap(tex), &at()).unwrap();
    let mut m = Material::emitter(Vec3::splat(l));
    m.emission_texture = tex;
    let light = b.add_material(None, m, &at()).unwrap();
    let h = 0.25;
    // Facing down (-y): the winding below gives cross(v1 - v0, v2 - v0) along -y. uv (x, z)
    // over [-h, h]^2.
    let c = square(h, 1.0);
    let uv = |p: Vec3| Vec2::new((p.x + h) / (2.0 * h), (p.z + h) / (2.0 * h));
    let tris = vec![[c[0], c[2], c[1]], [c[0], c[3], c[2]]];
    let uvs = tris.iter().map(|t| t.map(uv)).collect();
    b.add_uv_mesh(tris, None, uvs, Surface::of(light), &at())
        .unwrap();
    let grey = b
        .add_material(None, Material::diffuse(Vec3::splat(0.5)), &at())
        .unwrap();
    let f = 3.0;
    let floor = square(f, 0.0);
    // Facing up (+y), as cross(v1 - v0, v2 - v0) says.
    b.add_mesh(
        vec![
            [floor[0], floor[1], floor[2]],
            [floor[0], floor[2], floor[3]],
        ],
        Surface::of(grey),
        &at(),
    )
    .unwrap();
    b.finish(&at()).unwrap()
}

/// The corners of the square `[-h, h]^2` in the plane at height `y`, in order around it.
fn square(h: f32, y: f32) -> [Vec3; 4] {
    [
        Vec3::new(-h, y, -h),
        Vec3::new(-h, y, h),
        Vec3::new(h, y, h),
        Vec3::new(h, y, -h),
    ]
}

/// The first light's power is `want` (to 0.1%).
fn assert_power(s: &Scene, want: Vec3) {
    let got = s.lights[0].power;
    let close = (got - want).abs().max_element() < 1e-3 * want.max_element();
    assert!(close, "power {got} vs {want}");
}

/// Photon-mode settings of a 24 x 24 render of `s` (400,000 photons, 4 spp).
fn photon_settings(s: &Scene) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 24,
        spp: 4,
        mode: Mode::Photon,
        photons: 400_000,
        ..s.settings.clone()
    }
}

/// Direct-light settings of a 16 x 16 render of `s` at `spp`.
fn direct(s: &Scene, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 16,
        height: 16,
        spp,
        mode: Mode::DirectOnly,
        ..s.settings.clone()
    }
}

fn mean_texel() -> Vec3 {
    TEXELS
        .iter()
        .map(|t| Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32) / 255.0)
        .sum::<Vec3>()
        / 4.0
}

/// The mean radiance of a render of `s` on `backend`.
fn image_mean(s: &Scene, settings: &RenderSettings, backend: Backend) -> Vec3 {
    let (img, _) = render(s, settings, backend, Progress::default()).unwrap();
    let sum: Vec3 = img.pixels.iter().map(|p| Vec3::new(p[0], p[1], p[2])).sum();
    sum / img.pixels.len() as f32
}

#[test]
fn the_camera_sees_radiance_times_texel_and_the_power_includes_the_mean() {
    let s = scene(2.0, true);
    // Power: pi A L x the texture's mean (one-sided).
    assert_power(&s, PI * 0.25 * 2.0 * mean_texel());
    // Looking straight up from below the emitter's centre, each image quadrant is a texel.
    let settings = direct(&s, 4);
    let (img, _) = render(&s, &settings, Backend::Cpu, Progress::default()).unwrap();
    let mut seen: Vec<Vec3> = Vec::new();
    for (px, py) in [(3, 3), (12, 3), (3, 12), (12, 12)] {
        let p = img.pixels[py * 16 + px];
        seen.push(Vec3::new(p[0], p[1], p[2]));
    }
    for t in TEXELS {
        let want = 2.0 * Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32) / 255.0;
        assert!(
            seen.iter().any(|v| (*v - want).abs().max_element() < 1e-4),
            "texel {t:?}: radiance {want} not among the quadrants {seen:?}"
        );
    }
}

#[test]
fn shadow_rays_and_photons_agree_on_a_textured_light() {
    let s = scene(4.0, false);
    let direct = image_mean(
        &s,
        &RenderSettings {
            width: 24,
            height: 24,
            spp: 16,
            mode: Mode::DirectOnly,
            ..s.settings.clone()
        },
        Backend::Cpu,
    );
    let photons = image_mean(&s, &photon_settings(&s), Backend::Cpu);
    // The floor only: no other surface reflects back to it (photon mode adds nothing else).
    let err = ((photons - direct) / direct).abs().max_element();
    assert!(err < 0.03, "direct {direct} vs photons {photons}");
    // The view is lit off the mean colour, so photons carrying the mean would not match.
    let tint = direct / direct.element_sum() - mean_texel() / mean_texel().element_sum();
    assert!(
        tint.abs().max_element() > 0.01,
        "{direct} is lit in the mean colour"
    );
    assert!(direct.min_element() > 0.0);
}

/// The GPU looks up the same texels: the emitter seen directly (same random numbers, the
/// same texels) to f32 rounding, and the floor's photon estimate within seed noise.
#[test]
fn the_gpu_renders_textured_emission_as_the_cpu_does() {
    if common::gpu().is_none() {
        return;
    }
    let s = scene(2.0, true);
    let settings = direct(&s, 4);
    let (cpu, _) = render(&s, &settings, Backend::Cpu, Progress::default()).unwrap();
    let (gpu, _) = render(&s, &settings, Backend::Gpu, Progress::default()).unwrap();
    let d = gpu_photon::render::image_diff::diff(&gpu, &cpu, 8).unwrap();
    assert!(
        d.max_error < 1e-4,
        "emitter seen directly, gpu vs cpu: {d:?}"
    );
    let s = scene(4.0, false);
    let settings = photon_settings(&s);
    let (c, g) = (
        image_mean(&s, &settings, Backend::Cpu),
        image_mean(&s, &settings, Backend::Gpu),
    );
    assert!(
        ((g - c) / c).abs().max_element() < 0.03,
        "photons: cpu {c} vs gpu {g}"
    );
}

/// Mitsuba's area emitter with a textured `radiance`: the texture gives the radiance, and
/// the light's power is pi A x the texture's mean.
#[test]
fn mitsuba_area_emitters_take_a_textured_radiance() {
    let text = r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
<shape type="rectangle"><emitter type="area"><texture name="radiance" type="checkerboard">
<rgb name="color0" value="1, 0, 0"/><rgb name="color1" value="0, 0, 1"/></texture></emitter></shape>
</scene>
"#;
    let s = gpu_photon::importers::mitsuba::import(text, "t.xml", std::path::Path::new("."))
        .unwrap()
        .scene;
    let m = s.materials[s.triangles[0].material as usize];
    assert!(m.emission_texture != gpu_photon::scene::NO_TEXTURE);
    assert_eq!(m.emission, Vec3::ONE);
    // The checkerboard's mean is (color0 + color1) / 2; the rectangle's area 4.
    assert_power(&s, PI * 4.0 * Vec3::new(0.5, 0.0, 0.5));
    let settings = direct(&s, 1);
    let (img, _) = render(&s, &settings, Backend::Cpu, Progress::default()).unwrap();
    // Every pixel sees one cell or an edge between two: red and blue only, never green.
    assert!(img.pixels.iter().all(|p| p[1] == 0.0 && p[0] + p[2] > 0.0));
    assert!(img.pixels.iter().any(|p| p[0] == 1.0) && img.pixels.iter().any(|p| p[2] == 1.0));
}
