//! The media scenes (`scenes/fog-cornell.toml`, `scenes/volume-caustic.toml`,
//! `scenes/mitsuba/fog-box-null.xml`: fog inside a `null` cube, camera and light outside it,
//! and `scenes/mitsuba/smoke-caustic.xml`: a volume caustic in a smoke grid; issue 41) rendered by the CPU backend at their default settings against their Mitsuba 3 `volpath`
//! references (`scripts/media_references.py`, 128 x 128). To keep CI short the render is
//! 32 x 32 and the reference is averaged over 4 x 4 pixels: with the box pixel filter both
//! scenes use, a 32 x 32 pixel is exactly the mean of the 16 reference pixels it covers.
//!
//! Each scene renders twice (seeds 1 and 2). The means of the two must be within 1% of the
//! reference's per channel, and the RMSE of 4 x 4-block means of their mean against the
//! reference at most 2.5x what the noise alone explains: our own (half the two renders'
//! block difference) and the reference's, in quadrature. A bias shows as more.

use gpu_photon::importers::load;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::settings::RenderSettings;
use std::path::Path;

const SIDE: u32 = 32;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `img` averaged over `f` x `f` pixel blocks.
fn shrink(img: &Image, f: u32) -> Image {
    let (w, h) = (img.width / f, img.height / f);
    let mut out = Image::new(w, h);
    for y in 0..img.height / f * f {
        for x in 0..img.width / f * f {
            let p = img.pixels[(y * img.width + x) as usize];
            let q = &mut out.pixels[((y / f) * w + x / f) as usize];
            for c in 0..3 {
                q[c] += p[c] / (f * f) as f32;
            }
        }
    }
    out
}

/// `name`'s scene file below `scenes/` against `tests/data/NAME.exr`.
fn check(name: &str, file: &str) {
    let scene = load(&root().join("scenes").join(file)).unwrap();
    let reference = Image::read(&root().join("tests/data").join(format!("{name}.exr"))).unwrap();
    let reference = shrink(&reference, reference.width / SIDE);
    let json =
        std::fs::read_to_string(root().join("tests/data").join(format!("{name}.json"))).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    // The reference's own 16 x 16-block noise at 128 x 128 is its 4 x 4-block noise here.
    let ref_block = v["estimated_block16_rmse_of_reference"].as_f64().unwrap();
    let renders: Vec<Image> = [1, 2]
        .map(|seed| {
            let s = RenderSettings {
                width: SIDE,
                height: SIDE,
                seed,
                ..scene.settings.as_default_render()
            };
            render(&scene, &s, Backend::Cpu, Progress::default())
                .unwrap()
                .0
        })
        .into();
    let mut mean = Image::new(SIDE, SIDE);
    for (m, (a, b)) in mean
        .pixels
        .iter_mut()
        .zip(renders[0].pixels.iter().zip(&renders[1].pixels))
    {
        for c in 0..3 {
            m[c] = 0.5 * (a[c] + b[c]);
        }
    }
    let own = 0.5 * diff(&renders[0], &renders[1], 4).unwrap().block_rmse;
    let d = diff(&mean, &reference, 4).unwrap();
    let bound = 2.5 * (own * own + ref_block * ref_block).sqrt();
    println!(
        "{name}: mean ratios {:?}, block RMSE {:.5} (own noise {own:.5}, reference's \
         {ref_block:.5}, bound {bound:.5})",
        d.mean_ratio, d.block_rmse
    );
    for c in 0..3 {
        assert!(
            (d.mean_ratio[c] - 1.0).abs() < 0.01,
            "{name}: mean ratio {:?}",
            d.mean_ratio
        );
    }
    assert!(
        d.block_rmse <= bound,
        "{name}: block RMSE {} over {bound}",
        d.block_rmse
    );
}

#[test]
fn fog_cornell_matches_its_volpath_reference() {
    check("fog-cornell", "fog-cornell.toml");
}

#[test]
fn volume_caustic_matches_its_volpath_reference() {
    check("volume-caustic", "volume-caustic.toml");
}

/// The light's surface is `null` since Mitsuba's volpath lost single scattering below an opaque
/// one (docs/media.md, "Mitsuba's media tests"): measured means 1.0012, 4 x 4-block RMSE
/// 0.00306 against the bound 0.00626 (before, with the opaque light: 1.0003, 0.00326 against
/// 0.00321).
#[test]
fn null_bounded_fog_box_matches_its_volpath_reference() {
    check("fog-box-null", "mitsuba/fog-box-null.xml");
}

/// Issue 41's heterogeneous volume caustic (`scenes/mitsuba/smoke-caustic.xml`: glass focusing
/// a small light into a smoke grid bounded by a null cube, camera and light outside).
/// Measured at 128 x 128 (`scripts/media_race.py`, seeds 1 and 2): mean ratios 1.0002-1.0008.
#[test]
fn smoke_caustic_matches_its_volpath_reference() {
    check("smoke-caustic", "mitsuba/smoke-caustic.xml");
}
