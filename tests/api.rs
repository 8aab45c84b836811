//! The facade at the crate root: the same images as the inner session, a renderer that owns
//! its scene, the cancellation flag, warnings as values, settings by name, `Image` as f32 RGB.

use gpu_photon::{Backend, Flow, Image, Renderer, Scene, Stop};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn small(scene: &Scene, passes: u32) -> gpu_photon::RenderSettings {
    let mut s = scene.settings();
    for (name, v) in [("width", 16), ("height", 12), ("spp", 1), ("photons", 2000)] {
        s.set(name, v as u32).unwrap();
    }
    s.set("passes", passes).unwrap();
    s
}

#[test]
fn the_facade_renders_what_the_session_renders() {
    let scene = Scene::load(scenes().join("cornell-box.toml")).unwrap();
    for passes in [0, 3] {
        let s = small(&scene, passes);
        let (ours, warnings) = scene.render(&s, Backend::Cpu).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let quiet = gpu_photon::render::report::Progress::default();
        let inner = gpu_photon::render::session::render(
            &scene,
            &s.as_default_render(),
            Backend::Cpu,
            quiet,
        );
        let (theirs, _) = inner.unwrap();
        assert_eq!((ours.width, ours.height), (16, 12));
        let bits = |i: &Image| i.rgb().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&ours), bits(&theirs), "passes {passes}");
    }
}

#[test]
fn a_renderer_outlives_the_scene_value_and_stops_when_cancelled() {
    let mut r = {
        let scene = Scene::load(scenes().join("cornell-box.toml")).unwrap();
        Renderer::new(&scene, &small(&scene, 5), Backend::Cpu).unwrap()
    };
    assert_eq!(r.passes(), 0..5);
    assert!(r.render_pass().unwrap());
    r.cancel_flag().store(true, Ordering::SeqCst);
    let mut seen = Vec::new();
    r.run(&Stop::default(), |info, _| {
        seen.push((info.pass, info.done, info.planned));
        Flow::Continue
    })
    .unwrap();
    assert_eq!(
        seen,
        [(1, 2, Some(5))],
        "one more pass, then the flag stops it"
    );
    assert_eq!(r.done(), 0..2);
    r.cancel_flag().store(false, Ordering::SeqCst);
    r.run(&Stop::default(), |info, _| {
        if info.done == 4 {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })
    .unwrap();
    assert_eq!(r.done(), 0..4);
    assert!(r.noise().is_some() && r.report().unwrap().backend.starts_with("cpu"));
}

#[test]
fn warnings_are_values() {
    let scene = Scene::load(scenes().join("mitsuba/materials.xml")).unwrap();
    let texts: Vec<String> = scene.warnings().iter().map(|w| w.to_string()).collect();
    assert_eq!(texts.len(), 1, "{texts:?}");
    assert!(
        texts[0].contains("integrator `path` rendered with our photon mapping"),
        "{texts:?}"
    );
}

#[test]
fn settings_by_name_refuse_what_the_cli_refuses() {
    let scene = Scene::load(scenes().join("cornell-box.toml")).unwrap();
    let mut s = scene.settings();
    let e = s.set("shadow_samples", 0u32).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid setting shadow-samples: 0 is outside 1..=1024"
    );
    let mut bad = scene.settings();
    bad.spp = 0;
    let e = Renderer::new(&scene, &bad, Backend::Cpu).err().unwrap();
    assert_eq!(e.to_string(), "invalid setting spp: 0 is outside 1..=65536");
}

#[test]
fn images_are_contiguous_rgb() {
    let rgb: Vec<f32> = (0..2 * 3 * 3).map(|v| v as f32).collect();
    let image = Image::from_rgb(3, 2, rgb.clone()).unwrap();
    assert_eq!(image.pixels[4], [12.0, 13.0, 14.0]);
    assert_eq!(image.rgb(), &rgb[..]);
    assert_eq!(image.clone().into_rgb(), rgb);
    let e = Image::from_rgb(3, 3, rgb).unwrap_err().to_string();
    assert_eq!(e, "invalid setting image: 18 values for a 3x3 RGB image (expected 27, and a size of at least 1x1)");
    let d = image.diff(&Image::new(2, 2), 16).unwrap_err().to_string();
    assert_eq!(d, "sizes differ: 3x2 vs 2x2");
}
