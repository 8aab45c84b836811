//! The materials scene (`scenes/mitsuba/materials.xml`: the Cornell box with a rough gold
//! sphere, a rough blue plastic sphere, a rough glass sphere and a bitmap-textured floor)
//! against its Mitsuba 3.9.1 reference (`tests/data/materials.exr`, 4,096 spp; its own noise
//! is 0.0032 per pixel and 0.00019 on 16x16 block means, `tests/data/materials.json`), and
//! the two backends against each other on it.

mod common;

use gpu_photon::bsdfs::Bsdf;
use gpu_photon::importers::mitsuba::import;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::settings::RenderSettings;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scene() -> gpu_photon::importers::mitsuba::Imported {
    let path = root().join("scenes/mitsuba/materials.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    import(&text, "materials.xml", path.parent().unwrap()).unwrap()
}

#[test]
fn the_materials_file_imports_exactly() {
    let im = scene();
    // No "approximated" or "ignored" warning: every bsdf is what Mitsuba defines (the one
    // warning says that the file's integrator is a hint).
    let hint = ": integrator[0]: integrator `path` rendered with our photon mapping";
    let only_hint = im.warnings.len() == 1 && im.warnings[0].contains(hint);
    assert!(only_hint, "{:?}", im.warnings);
    let has = |f: fn(&Bsdf) -> bool| im.scene.materials.iter().any(|m| f(&m.bsdf));
    assert!(
        has(|b| matches!(b, Bsdf::RoughConductor(_))),
        "no rough conductor"
    );
    assert!(
        has(|b| matches!(b, Bsdf::Plastic(p) if p.microfacet.is_some())),
        "no rough plastic"
    );
    assert!(
        has(|b| matches!(b, Bsdf::RoughDielectric(_))),
        "no rough dielectric"
    );
    // The floor's reflectance is the bitmap, looked up through the rectangle's uvs.
    assert_eq!(im.scene.textures.len(), 1);
    assert_eq!(im.scene.uvs.len(), im.scene.triangles.len());
    // The file's 256 samples per pixel are the total, spread over the 4 default passes.
    assert_eq!(im.scene.settings.spp * im.scene.settings.passes, 256);
    // 64 samples per pass share each pass's caustic map: four times the default photons.
    let default = gpu_photon::settings::RenderSettings::default();
    assert_eq!(im.scene.settings.spp, 64);
    assert_eq!(
        im.scene.settings.caustic_photons,
        4 * default.caustic_photons
    );
}

#[test]
fn default_render_matches_the_mitsuba_reference() {
    let im = scene();
    let s = im.scene.settings.as_default_render();
    let (img, _) = render(&im.scene, &s, Backend::Cpu, Progress::default()).unwrap();
    let reference = Image::read(&root().join("tests/data/materials.exr")).unwrap();
    let d = diff(&img, &reference, 16).unwrap();
    eprintln!("materials, default render vs Mitsuba: {d:?}");
    // The issue's bounds: every channel's mean within 1%, 16x16 block RMSE at most 0.003
    // (the reference's own block noise is 0.00019; the default render measures ~0.0007).
    for (c, r) in d.mean_ratio.iter().enumerate() {
        assert!((r - 1.0).abs() < 0.01, "channel {c}: mean ratio {r}");
    }
    assert!(d.block_rmse <= 0.003, "block RMSE {}", d.block_rmse);
    // Per pixel: the reference's own 0.0032 and our passes' noise (~0.005 measured).
    assert!(d.rmse <= 0.009, "RMSE {}", d.rmse);
}

#[test]
fn gpu_renders_the_materials_scene_as_the_cpu_does() {
    let Some(_ctx) = common::gpu() else {
        return;
    };
    let im = scene();
    let s = RenderSettings {
        width: 64,
        height: 64,
        spp: 4,
        photons: 50_000,
        caustic_photons: 20_000,
        ..im.scene.settings.clone()
    }
    .as_default_render();
    let cpu = render(&im.scene, &s, Backend::Cpu, Progress::default())
        .unwrap()
        .0;
    let gpu = render(&im.scene, &s, Backend::Gpu, Progress::default())
        .unwrap()
        .0;
    let other_seed = RenderSettings {
        seed: s.seed + 1,
        ..s.clone()
    };
    let cpu2 = render(&im.scene, &other_seed, Backend::Cpu, Progress::default())
        .unwrap()
        .0;
    let d = diff(&gpu, &cpu, 8).unwrap();
    let noise = diff(&cpu2, &cpu, 8).unwrap();
    eprintln!("gpu vs cpu: {d:?}\ncpu seed noise: {noise:?}");
    // Same random numbers, same BSDFs: far closer than another seed (measured RMSE ~1e-5
    // against a seed-to-seed 0.05); a BSDF twin that drifts lands at the seed noise.
    assert!(d.rmse < 0.05 * noise.rmse, "{d:?} vs {noise:?}");
    assert!(
        d.block_rmse < 0.05 * noise.block_rmse + 1e-6,
        "{d:?} vs {noise:?}"
    );
}

/// The materials scene with its floor a rough plastic whose `diffuse_reflectance` is the
/// bitmap (`textured`) or the bitmap's mean colour.
fn plastic_floor(textured: bool) -> gpu_photon::scene::Scene {
    let path = root().join("scenes/mitsuba/materials.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    let old = r#"<bsdf type="twosided" id="floor"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="checker.png"/><string name="filter_type" value="bilinear"/></texture></bsdf></bsdf>"#;
    assert!(text.contains(old), "the floor's bsdf moved");
    let mean = scene().scene.textures[0].mean();
    let base = if textured {
        r#"<texture type="bitmap" name="diffuse_reflectance"><string name="filename" value="checker.png"/></texture>"#.to_string()
    } else {
        format!(
            r#"<rgb name="diffuse_reflectance" value="{}, {}, {}"/>"#,
            mean.x, mean.y, mean.z
        )
    };
    let new = format!(
        r#"<bsdf type="roughplastic" id="floor"><float name="alpha" value="0.2"/>{base}</bsdf>"#
    );
    import(
        &text.replace(old, &new),
        "materials.xml",
        path.parent().unwrap(),
    )
    .unwrap()
    .scene
}

#[test]
fn a_textured_plastic_renders_its_texture_on_both_backends() {
    let textured = plastic_floor(true);
    let floor = textured.materials.iter().find(|m| {
        matches!(&m.bsdf, Bsdf::Plastic(p)
            if p.microfacet.is_some() && p.diffuse_reflectance.texture != gpu_photon::textures::NO_TEXTURE)
    });
    assert!(floor.is_some(), "the floor is a textured rough plastic");
    let s = RenderSettings {
        width: 48,
        height: 48,
        spp: 4,
        photons: 40_000,
        caustic_photons: 10_000,
        ..textured.settings.clone()
    }
    .as_default_render();
    let render_cpu = |sc: &gpu_photon::scene::Scene, seed: u32| {
        let s = RenderSettings { seed, ..s.clone() };
        render(sc, &s, Backend::Cpu, Progress::default()).unwrap().0
    };
    let (a, b) = (render_cpu(&textured, 1), render_cpu(&textured, 2));
    let flat = render_cpu(&plastic_floor(false), 1);
    let noise = diff(&a, &b, 8).unwrap();
    let d = diff(&flat, &a, 8).unwrap();
    // The checker shows: with the same random numbers, a floor of the texture's mean colour
    // would give the same image bit for bit if the texture were ignored (measured: RMSE
    // 0.017, the largest pixel 0.5 apart).
    assert!(d.rmse > 0.005 && d.max_error > 0.1, "{d:?}");
    if common::gpu().is_none() {
        return;
    }
    let s1 = RenderSettings {
        seed: 1,
        ..s.clone()
    };
    let gpu = render(&textured, &s1, Backend::Gpu, Progress::default())
        .unwrap()
        .0;
    let g = diff(&gpu, &a, 8).unwrap();
    assert!(
        g.rmse < 0.05 * noise.rmse,
        "gpu vs cpu {g:?}, seed noise {noise:?}"
    );
}

/// The materials scene with the spheres' bsdfs replaced by `gold`, `plastic` and `glass`.
fn with_spheres(gold: &str, plastic: &str, glass: &str) -> gpu_photon::scene::Scene {
    let path = root().join("scenes/mitsuba/materials.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        // Only the definitions: the spheres' `<ref id="gold"/>` lines stay.
        let def = |id: &str| line.trim_start().starts_with("<bsdf") && line.contains(id);
        let replaced = if def(r#"id="gold""#) {
            gold
        } else if def(r#"id="bluep""#) {
            plastic
        } else if def(r#"id="rglass""#) {
            glass
        } else {
            line
        };
        out.push_str(replaced);
        out.push('\n');
    }
    import(&out, "materials.xml", path.parent().unwrap())
        .unwrap()
        .scene
}

#[test]
fn smooth_and_anisotropic_kinds_agree_across_backends() {
    // A smooth copper conductor, a smooth nonlinear plastic and a thin dielectric (delta
    // lobes: the specular chain), then an anisotropic Beckmann conductor, a GGX plastic and
    // a Beckmann rough glass.
    let sets = [
        (
            r#"<bsdf type="conductor" id="gold"><string name="material" value="Cu"/></bsdf>"#,
            r#"<bsdf type="plastic" id="bluep"><rgb name="diffuse_reflectance" value="0.1, 0.2, 0.6"/><boolean name="nonlinear" value="true"/></bsdf>"#,
            r#"<bsdf type="thindielectric" id="rglass"><float name="int_ior" value="1.5"/></bsdf>"#,
        ),
        (
            r#"<bsdf type="roughconductor" id="gold"><string name="material" value="Al"/><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/></bsdf>"#,
            r#"<bsdf type="roughplastic" id="bluep"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>"#,
            r#"<bsdf type="roughdielectric" id="rglass"><string name="distribution" value="beckmann"/><float name="alpha" value="0.2"/></bsdf>"#,
        ),
    ];
    let Some(_ctx) = common::gpu() else {
        return;
    };
    for (gold, plastic, glass) in sets {
        let scene = with_spheres(gold, plastic, glass);
        let s = RenderSettings {
            width: 48,
            height: 48,
            spp: 4,
            photons: 40_000,
            caustic_photons: 10_000,
            ..scene.settings.clone()
        }
        .as_default_render();
        let (d, noise) = common::gpu_and_seed_diffs(&scene, &s);
        // The CPU splits delta branches near the camera where the GPU picks one, so the two
        // are independent estimates of the same image: no farther apart than two seeds.
        let (pixels, blocks) = common::within_seed_noise(&d, &noise, 1e-4);
        assert!(
            pixels && blocks,
            "{gold}\ngpu vs cpu {d:?}\nseed noise {noise:?}"
        );
    }
}
