//! Renders a scene with gpu-photon's library API and writes it as EXR and PNG.
//!
//!     cargo run --release --example render -- [SCENE] [OUT_STEM]

use gpu_photon::{Backend, Flow, Renderer, Scene, Stop};

fn main() -> gpu_photon::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or("scenes/cornell-box.toml".into());
    let stem = args.next().unwrap_or("render".into());
    let scene = Scene::load(&path)?;
    let mut settings = scene.settings();
    settings.set("passes", 8u32)?; // any setting by its command-line name, checked
    settings.set("spp", 8u32)?;
    let mut renderer = Renderer::new(&scene, &settings, Backend::Auto)?;
    renderer.run(&Stop::default(), |info, _| {
        eprintln!("pass {} done, noise {:?}", info.pass, info.noise);
        Flow::Continue
    })?;
    let later = renderer.take_warnings();
    for w in scene.warnings().iter().chain(&later) {
        eprintln!("warning: {w}");
    }
    let image = renderer.image();
    image.write_exr(format!("{stem}.exr"))?;
    image.write_png(format!("{stem}.png"), settings.exposure)
}
