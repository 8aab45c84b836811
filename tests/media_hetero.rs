//! Heterogeneous media (issue 41): Mitsuba's `heterogeneous` with `gridvolume` (binary
//! `.vol` files) and `constvolume` volumes, their errors (a bad grid file named with its
//! byte offset), and renders that hold the tracking estimators to the homogeneous medium's
//! exact ones: a fog box whose extinction and albedo come from a constant volume or from a
//! uniform grid renders as the homogeneous fog box does, within the seed-to-seed noise. The
//! estimators themselves (ratio tracking against a density ramp's optical depth, delta
//! tracking's free-flight distribution by chi-square) are tested in `media::heterogeneous`.

mod common;

use gpu_photon::importers::mitsuba::import;
use gpu_photon::media::MediumKind;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;
use std::path::Path;

/// A `.vol` file: `res` voxels of `channels` values each, all `values` repeated.
fn vol(res: [i32; 3], channels: i32, voxel: &[f32]) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for v in [1, res[0], res[1], res[2], channels] {
        b.extend(v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        b.extend(v.to_le_bytes());
    }
    for _ in 0..res[0] * res[1] * res[2] {
        for v in voxel {
            b.extend(v.to_le_bytes());
        }
    }
    b
}

/// A fog box (`medium`, the interior of a null cube [-1, 1]^3) around a diffuse ball, lit by
/// a point light, the camera outside.
fn fog_box(medium: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="50"/>
<transform name="to_world"><lookat origin="0.3, 0.4, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
{medium}
<shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
<shape type="sphere"><float name="radius" value="0.4"/><bsdf type="diffuse"/></shape>
<emitter type="point"><point name="position" x="0.5" y="2" z="1"/><rgb name="intensity" value="20"/></emitter>
</scene>
"#
    )
}

const SIGMA_T: [f32; 3] = [1.2, 0.7, 0.3];
const ALBEDO: [f32; 3] = [0.9, 0.6, 0.8];
/// The cube's box as a volume's `to_world`: the unit cube scaled by 2, then moved by -1.
const CUBE: &str =
    r#"<transform name="to_world"><scale value="2"/><translate value="-1"/></transform>"#;

fn load(xml: &str, dir: &Path) -> Result<Scene, String> {
    import(xml, "t.xml", dir)
        .map(|im| im.scene)
        .map_err(|e| e.to_string())
}

fn rgb(v: [f32; 3]) -> String {
    format!("{}, {}, {}", v[0], v[1], v[2])
}

/// The fog box in its three forms: homogeneous, constant volumes, uniform grids.
fn scenes(dir: &Path) -> [Scene; 3] {
    // The grid's values are twice the extinction, halved by `scale`.
    let doubled = SIGMA_T.map(|x| 2.0 * x);
    std::fs::write(dir.join("sigma.vol"), vol([3, 2, 2], 3, &doubled)).unwrap();
    std::fs::write(dir.join("albedo.vol"), vol([2, 2, 1], 3, &ALBEDO)).unwrap();
    let (s, a) = (rgb(SIGMA_T), rgb(ALBEDO));
    let homogeneous = format!(
        r#"<medium type="homogeneous" id="fog"><rgb name="sigma_t" value="{s}"/><rgb name="albedo" value="{a}"/></medium>"#
    );
    let constant = format!(
        r#"<medium type="heterogeneous" id="fog"><volume name="sigma_t" type="constvolume"><rgb name="value" value="{s}"/>{CUBE}</volume><rgb name="albedo" value="{a}"/></medium>"#
    );
    let grid = format!(
        r#"<medium type="heterogeneous" id="fog"><float name="scale" value="0.5"/>
<volume name="sigma_t" type="gridvolume"><string name="filename" value="sigma.vol"/><boolean name="use_grid_bbox" value="false"/>{CUBE}</volume>
<volume name="albedo" type="gridvolume"><string name="filename" value="albedo.vol"/><string name="filter_type" value="nearest"/>{CUBE}</volume></medium>"#
    );
    [homogeneous, constant, grid].map(|m| load(&fog_box(&m), dir).unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn mitsuba_heterogeneous_media_load() {
    let dir = common::scratch("hetero-load");
    let [homogeneous, constant, grid] = scenes(&dir);
    assert_eq!(homogeneous.media[0].kind, MediumKind::Homogeneous);
    for s in [&constant, &grid] {
        let MediumKind::Heterogeneous(h) = &s.media[0].kind else {
            panic!("not heterogeneous: {:?}", s.media[0]);
        };
        // The majorant is the largest channel; the box is the cube's.
        assert!((h.majorant - 1.2).abs() < 1e-6, "{}", h.majorant);
        assert!((h.sigma_t.lo + 1.0).abs().max_element() < 1e-6);
        assert!((h.sigma_t.hi - 1.0).abs().max_element() < 1e-6);
        let x = glam::Vec3::new(0.3, -0.2, 0.7);
        let want = glam::Vec3::from(SIGMA_T);
        assert!((h.sigma_t_at(x) - want).abs().max_element() < 1e-6);
        assert!(
            (h.sigma_s_at(x) - want * glam::Vec3::from(ALBEDO))
                .abs()
                .max_element()
                < 1e-6
        );
        // Outside the box: nothing.
        assert_eq!(
            h.sigma_t_at(glam::Vec3::new(0.0, 1.5, 0.0)),
            glam::Vec3::ZERO
        );
    }
}

#[test]
fn bad_grids_and_volumes_are_located_errors() {
    let dir = common::scratch("hetero-errors");
    let good = vol([2, 2, 2], 1, &[1.0]);
    std::fs::write(dir.join("short.vol"), &good[..70]).unwrap();
    let mut nan = good.clone();
    nan[52..56].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(dir.join("nan.vol"), nan).unwrap();
    std::fs::write(dir.join("huge.vol"), vol([65536, 65536, 65536], 3, &[])).unwrap();
    std::fs::write(dir.join("negative.vol"), vol([1, 1, 2], 1, &[-2.0])).unwrap();
    let d = dir.display();
    let grid = |file: &str, extra: &str| {
        format!(
            r#"<medium type="heterogeneous" id="fog"><volume name="sigma_t" type="gridvolume"><string name="filename" value="{file}"/>{extra}</volume></medium>"#
        )
    };
    let cases = [
        (grid("short.vol", ""), format!("t.xml:5: medium[fog].sigma_t.filename: {d}/short.vol: byte 70: truncated data (2x2x2 voxels of 1 channel(s) need 80 bytes)")),
        (grid("nan.vol", ""), format!("t.xml:5: medium[fog].sigma_t.filename: {d}/nan.vol: byte 52: value NaN is not finite")),
        (grid("huge.vol", ""), format!("t.xml:5: medium[fog].sigma_t.filename: {d}/huge.vol: byte 8: 65536x65536x65536 voxels of 3 channel(s) would take 3377699720527872 bytes, more than the")),
        (grid("missing.vol", ""), format!("t.xml:5: medium[fog].sigma_t.filename: {d}/missing.vol: No such file or directory")),
        (grid("negative.vol", ""), "t.xml:5: medium[fog].sigma_t: must be >= 0: the grid's value -2 at byte 48".to_string()),
        (grid("short.vol", r#"<string name="filter_type" value="cubic"/>"#), "t.xml:5: medium[fog].sigma_t.filter_type: `cubic` is not `trilinear` or `nearest`".to_string()),
        (grid("short.vol", r#"<string name="wrap_mode" value="repeat"/>"#), "t.xml:5: medium[fog].sigma_t.wrap_mode: unsupported wrap_mode `repeat` (only `clamp`)".to_string()),
        (r#"<medium type="heterogeneous" id="fog"><volume name="density" type="constvolume"/></medium>"#.to_string(), "t.xml:5: medium[fog].volume: unsupported volume `density` (`sigma_t`, `albedo`)".to_string()),
        (r#"<medium type="heterogeneous" id="fog"><volume name="albedo" type="constvolume"><float name="value" value="1.5"/></volume></medium>"#.to_string(), "t.xml:5: medium[fog].albedo: must be in [0, 1]: [1.5, 1.5, 1.5]".to_string()),
        (r#"<medium type="heterogeneous" id="fog"><volume name="albedo" type="perlin"/></medium>"#.to_string(), "t.xml:5: medium[fog].albedo: unsupported volume `perlin` (`gridvolume`, `constvolume`)".to_string()),
    ];
    for (medium, want) in cases {
        let e = load(&fog_box(&medium), &dir).map(|_| ()).unwrap_err();
        assert!(e.starts_with(&want), "{e}\nwanted {want}");
    }
}

/// The fog box rendered with a heterogeneous medium that is uniform (a constant volume, and
/// grids with `scale`) equals the homogeneous medium's render within the noise: the image
/// means over eight seeds differ per channel by at most four standard errors (each measured
/// from its seeds), plus 0.1%.
#[test]
fn uniform_heterogeneous_media_render_as_homogeneous_ones() {
    let dir = common::scratch("hetero-render");
    let [homogeneous, constant, grid] = scenes(&dir);
    let settings = RenderSettings {
        photons: 20_000,
        caustic_photons: 0,
        spp: 16,
        pass_range: None,
        ..homogeneous.settings.clone()
    };
    let mean = |s: &Scene, seed: u32| -> [f64; 3] {
        let settings = RenderSettings {
            seed,
            ..settings.clone()
        };
        let (img, _) = render(s, &settings, Backend::Cpu, Progress::default()).unwrap();
        let mut m = [0.0; 3];
        for p in &img.pixels {
            for c in 0..3 {
                assert!(p[c].is_finite() && p[c] >= 0.0, "pixel {p:?}");
                m[c] += p[c] as f64 / img.pixels.len() as f64;
            }
        }
        m
    };
    // Mean and standard error of the image mean per channel over `N` seeds.
    const N: u32 = 8;
    let stats = |s: &Scene, first: u32| -> [(f64, f64); 3] {
        let ms: Vec<[f64; 3]> = (first..first + N).map(|seed| mean(s, seed)).collect();
        [0, 1, 2].map(|c| {
            let mu = ms.iter().map(|m| m[c]).sum::<f64>() / N as f64;
            let var = ms.iter().map(|m| (m[c] - mu).powi(2)).sum::<f64>() / (N - 1) as f64;
            (mu, (var / N as f64).sqrt())
        })
    };
    let reference = stats(&homogeneous, 1);
    for (name, s) in [("constant", &constant), ("grid", &grid)] {
        let got = stats(s, 101);
        for c in 0..3 {
            let ((a, sa), (b, sb)) = (reference[c], got[c]);
            let se = (sa * sa + sb * sb).sqrt();
            eprintln!("{name} channel {c}: {b} +- {sb} vs {a} +- {sa}");
            assert!(a > 0.0);
            assert!(
                (b - a).abs() <= 4.0 * se + 1e-3 * a,
                "{name} channel {c}: {b} +- {sb} vs the homogeneous {a} +- {sa}"
            );
        }
    }
}

/// TOML's `[media.NAME]` with `type = "heterogeneous"`: grid files placed in `bounds` (or the
/// file's own box), constants over `bounds`, and their errors at the key.
#[test]
fn toml_heterogeneous_media_load_grids_and_constants() {
    let dir = common::scratch("hetero-toml");
    // A 2 x 1 x 1 grid of 1 and 3 whose file box is [0, 2] x [0, 1] x [0, 1].
    let mut ramp = vol([2, 1, 1], 1, &[0.0]);
    ramp.truncate(48);
    ramp[36..40].copy_from_slice(&2.0f32.to_le_bytes());
    for v in [1.0f32, 3.0] {
        ramp.extend(v.to_le_bytes());
    }
    std::fs::write(dir.join("ramp.vol"), &ramp).unwrap();
    std::fs::write(dir.join("short.vol"), &ramp[..50]).unwrap();
    // An OpenVDB file's first bytes: its magic number 0x56444220 as a little-endian i64.
    let mut vdb = vec![0x20u8, 0x42, 0x44, 0x56, 0, 0, 0, 0];
    vdb.resize(256, 0);
    std::fs::write(dir.join("smoke.vdb"), &vdb).unwrap();
    let scene = |media: &str| {
        let text = format!(
            "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n{media}\n\
             [materials.clear]\ntype = \"null\"\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.5\nmaterial = \"clear\"\ninterior = \"smoke\"\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = [1, 1, 1]\n"
        );
        gpu_photon::importers::load_str(&text, "s.toml", &dir).map_err(|e| e.to_string())
    };
    let hetero = |s: &Scene| match &s.media[0].kind {
        MediumKind::Heterogeneous(h) => h.clone(),
        k => panic!("{k:?}"),
    };
    let v = |x: f32| glam::Vec3::new(x, 0.5, 0.5);
    // The file's box: voxel centres at x = 0.5 and 1.5.
    let s = scene("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"ramp.vol\"\nscale = 2\nalbedo = [0.5, 0.6, 0.7]").unwrap();
    let h = hetero(&s);
    assert_eq!(h.majorant, 6.0);
    // What `gpu-photon bench` reports of it: two f32 voxels (the albedo is a constant), and
    // one majorant cell (a grid of at most VOXELS_PER_CELL voxels a side).
    assert_eq!(
        gpu_photon::bench::media_memory(&s),
        ["medium 0 (heterogeneous): grids 8 bytes, majorant grid 1x1x1 cells 4 bytes"]
    );
    assert!((h.sigma_t_at(v(1.0)).x - 4.0).abs() < 1e-6);
    assert!((h.sigma_t_at(v(1.5)).x - 6.0).abs() < 1e-6);
    assert_eq!(h.sigma_t_at(v(2.5)).x, 0.0);
    assert!(
        (h.sigma_s_at(v(0.5)) - glam::Vec3::new(1.0, 1.2, 1.4))
            .abs()
            .max_element()
            < 1e-6
    );
    // Placed in bounds, nearest filter.
    let s = scene("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"ramp.vol\"\nbounds = [[-1, -1, -1], [1, 1, 1]]\nfilter = \"nearest\"").unwrap();
    let h = hetero(&s);
    assert_eq!(h.sigma_t_at(glam::Vec3::new(0.1, 0.0, 0.0)).x, 3.0);
    assert_eq!(h.sigma_t_at(glam::Vec3::new(-0.1, 0.0, 0.0)).x, 1.0);
    // Constants over bounds.
    let s = scene("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = [1, 2, 3]\nbounds = [[0, 0, 0], [1, 1, 1]]").unwrap();
    let h = hetero(&s);
    assert_eq!(
        h.sigma_t_at(glam::Vec3::splat(0.5)),
        glam::Vec3::new(1.0, 2.0, 3.0)
    );
    assert_eq!(h.sigma_t_at(glam::Vec3::splat(-0.5)), glam::Vec3::ZERO);
    let d = dir.display();
    let cases = [
        ("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = 2", "s.toml:9: media.smoke.sigma_t: a heterogeneous medium without a grid file for sigma_t needs `bounds`".to_string()),
        ("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"short.vol\"", format!("s.toml:9: media.smoke.sigma_t: {d}/short.vol: byte 50: truncated data (2x1x1 voxels of 1 channel(s) need 56 bytes)")),
        ("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"smoke.vdb\"", format!("s.toml:9: media.smoke.sigma_t: {d}/smoke.vdb: byte 0: an OpenVDB file; grids are read from Mitsuba's .vol files only (write the grid out densely in that format: docs/media.md, \"Grid files\")")),
        ("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"ramp.vol\"\nbounds = [[0, 0, 0], [0, 1, 1]]", "s.toml:10: media.smoke.bounds: needs min < max on every axis".to_string()),
        ("[media.smoke]\ntype = \"heterogeneous\"\nsigma_t = \"ramp.vol\"\nfilter = \"cubic\"", "s.toml:10: media.smoke.filter: must be one of \"trilinear\", \"nearest\"".to_string()),
        ("[media.smoke]\nsigma_t = 1\nbounds = [[0, 0, 0], [1, 1, 1]]", "s.toml:9: media.smoke.bounds: `bounds` does not apply to type \"homogeneous\"".to_string()),
        ("[media.smoke]\ntype = \"cloudy\"", "s.toml:8: media.smoke.type: unsupported medium type `cloudy` (\"homogeneous\", \"heterogeneous\")".to_string()),
    ];
    for (media, want) in cases {
        let e = scene(media).map(|_| ()).unwrap_err();
        assert!(e.starts_with(&want), "{e}\nwanted {want}");
    }
}

/// A grid value so large that the majorant's optical depth across the box passes
/// `MAX_OPTICAL_DEPTH` (a corrupt file: every walk near it would take the most steps) is an
/// error, as the fuzzer's xml case 362 (a value of 2.8e29) showed it should be.
#[test]
fn absurd_densities_are_refused() {
    let dir = common::scratch("hetero-absurd");
    std::fs::write(dir.join("spike.vol"), vol([1, 1, 1], 1, &[2.8e29])).unwrap();
    let medium = r#"<medium type="heterogeneous" id="fog"><volume name="sigma_t" type="gridvolume"><string name="filename" value="spike.vol"/></volume></medium>"#;
    let e = load(&fog_box(medium), &dir).map(|_| ()).unwrap_err();
    let want = "t.xml:5: medium[fog].sigma_t: sigma_t x scale reaches 2.8e29 per unit, an optical depth of 4.8497423e29 across the volume's box, more than 1e6 (nothing would pass it)";
    assert_eq!(e, want);
}
