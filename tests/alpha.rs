//! Alpha-tested surfaces (Mitsuba's `mask`, glTF's `alphaMode`): a masked plane between a
//! directional light and a floor passes the light in proportion to its transparency, a
//! textured opacity follows its texture, the importer's errors are exact, and the GPU
//! renders masks as the CPU does.

use gpu_photon::importers::mitsuba::import;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{AlphaMode, Scene};
use gpu_photon::settings::{Mode, RenderSettings};
use std::f32::consts::PI;
use std::path::Path;

mod common;

/// A white (0.5) floor in z = 0 seen from z = 1.5 below a 20 x 20 occluder at z = 2 whose
/// bsdf is `occluder`, under a directional light of irradiance 1 straight down.
fn scene(occluder: &str) -> Result<Scene, gpu_photon::Error> {
    let text = format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 1.5" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film></sensor>
<shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
<shape type="rectangle"><transform name="to_world"><scale value="10"/><translate z="2"/></transform>
{occluder}</shape>
<emitter type="directional"><vector name="direction" value="0, 0, -1"/><rgb name="irradiance" value="1"/></emitter>
</scene>
"#
    );
    import(&text, "t.xml", Path::new(env!("CARGO_MANIFEST_DIR"))).map(|i| i.scene)
}

/// The mean radiance (per channel, averaged) of a direct-light CPU render of `s`.
fn mean(s: &Scene, spp: u32) -> f32 {
    let settings = RenderSettings {
        spp,
        mode: Mode::DirectOnly,
        ..s.settings.clone()
    };
    let (img, _) = render(s, &settings, Backend::Cpu, Progress::default()).unwrap();
    let sum: f64 = img.pixels.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum();
    (sum / (3 * img.pixels.len()) as f64) as f32
}

#[test]
fn a_mask_passes_light_in_proportion_to_its_transparency() {
    let full = 0.5 / PI; // rho / pi E
    let opaque = scene(r#"<bsdf type="diffuse"/>"#).unwrap();
    assert!(
        mean(&opaque, 4) < 1e-6,
        "an opaque occluder casts a full shadow"
    );
    for opacity in [0.0f32, 0.25, 0.8] {
        let s = scene(&format!(
            r#"<bsdf type="mask"><float name="opacity" value="{opacity}"/><bsdf type="diffuse"/></bsdf>"#
        ))
        .unwrap();
        let alpha = s.materials.iter().find_map(|m| m.alpha).expect("the mask");
        assert_eq!((alpha.mode, alpha.factor), (AlphaMode::Blend, opacity));
        // 32 x 32 pixels x 16 spp shadow rays, each passing with 1 - opacity: the mean's
        // relative standard error is below 0.5%; 3% is a wide margin.
        let m = mean(&s, 16);
        let want = full * (1.0 - opacity);
        assert!(
            (m - want).abs() <= 0.03 * full,
            "opacity {opacity}: mean {m}, want {want}"
        );
    }
}

#[test]
fn a_textured_opacity_follows_its_luminance() {
    // A checkerboard of black and white squares: half the shadow rays pass.
    let s = scene(
        r#"<bsdf type="mask"><texture name="opacity" type="checkerboard">
<rgb name="color0" value="0"/><rgb name="color1" value="1"/>
<transform name="to_uv"><scale x="40" y="40"/></transform></texture><bsdf type="diffuse"/></bsdf>"#,
    )
    .unwrap();
    let m = mean(&s, 8);
    let want = 0.5 * 0.5 / PI;
    assert!((m - want).abs() < 0.05 * want, "mean {m}, want {want}");
}

#[test]
fn mask_errors_are_exact() {
    let err = |body: &str| scene(body).expect_err("an error").to_string();
    assert_eq!(
        err(
            r#"<bsdf type="mask"><float name="opacity" value="1.5"/><bsdf type="diffuse"/></bsdf>"#
        ),
        "t.xml:8: shape[1].bsdf.opacity: must be in [0, 1] (got 1.5)"
    );
    assert_eq!(
        err(r#"<bsdf type="mask"><float name="opacity" value="0.5"/></bsdf>"#),
        "t.xml:8: shape[1].bsdf: `mask` needs a nested <bsdf>"
    );
}

/// The GPU tests the same opacities at the same hits: a textured stochastic mask renders
/// within seed noise of the CPU (the blend's choices hash the same primitive, distance and
/// direction, so most agree exactly).
#[test]
fn the_gpu_renders_masks_as_the_cpu_does() {
    if common::gpu().is_none() {
        return;
    }
    // A textured opacity of 0.2 and 0.9: both the texture lookup and the stochastic choice.
    let occluder = r#"<bsdf type="mask"><texture name="opacity" type="checkerboard">
<rgb name="color0" value="0.2"/><rgb name="color1" value="0.9"/>
<transform name="to_uv"><scale x="40" y="40"/></transform></texture><bsdf type="diffuse"/></bsdf>"#;
    let s = scene(occluder).unwrap();
    let settings = RenderSettings {
        spp: 16,
        mode: Mode::DirectOnly,
        ..s.settings.clone()
    };
    let (cpu, _) = render(&s, &settings, Backend::Cpu, Progress::default()).unwrap();
    let (gpu, _) = render(&s, &settings, Backend::Gpu, Progress::default()).unwrap();
    let mean = |img: &gpu_photon::render::film::Image| {
        img.pixels.iter().map(|p| p[0] as f64).sum::<f64>() / img.pixels.len() as f64
    };
    let (c, g) = (mean(&cpu), mean(&gpu));
    assert!((c - g).abs() < 0.03 * c, "cpu {c} vs gpu {g}");
}
