//! Mitsuba 3's `normalmap` bsdf: a flat Mitsuba `rectangle` (uv tangent +x, bitangent +y,
//! normal +z) under a directional light, direct light only. A constant normal map whose texel
//! decodes (raw 8-bit: k / 255) to `c` gives the normal `normalize(2 c - 1)` in that frame, and
//! the diffuse radiance `albedo / pi * E * cos` of the angle between the light and that normal,
//! to 1e-4 at every pixel whose footprint lies inside the square; a flat map (0.5, 0.5, 1) gives
//! the image without a normal map bit for bit. An OBJ quad with a mirrored uv mapping
//! (Mitsuba 3.9.1 keeps its bitangent n x s) and a sphere with a varying map. The GPU
//! renders all of them as the CPU does (within 1e-4; skipped without a Vulkan adapter).
//! Malformed `normalmap`s are `FILE:LINE: field:` errors; without `raw` the map is sRGB-decoded.

mod common;

use glam::{DVec3, Vec3};
use gpu_photon::error::Error;
use gpu_photon::importers::mitsuba::import;
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{Scene, NO_TEXTURE};
use gpu_photon::settings::{Mode, RenderSettings};
use std::path::{Path, PathBuf};

const SIDE: u32 = 32;
const ALBEDO: f64 = 0.6;
const E: f64 = 3.0;
/// Where the light comes from (the emitter's `direction` is its negation).
const TO_LIGHT: [f64; 3] = [0.5, 0.3, 0.8];
/// The normal map's texel (raw 8-bit): tilted towards +x (u) and +y (v).
const TEXEL: [u8; 3] = [181, 150, 243];

fn header() -> String {
    let d = DVec3::from(TO_LIGHT).normalize();
    format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 3.5" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="{SIDE}"/><integer name="height" value="{SIDE}"/><rfilter type="box"/></film></sensor>
<emitter type="directional"><vector name="direction" value="{}, {}, {}"/><rgb name="irradiance" value="{E}"/></emitter>
"#,
        -d.x, -d.y, -d.z
    )
}

const DIFFUSE: &str = r#"<bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>"#;

/// The scene: the rectangle with `bsdf`; files relative to `dir`.
fn scene(bsdf: &str, dir: &Path) -> Scene {
    let text = format!(
        "{}<shape type=\"rectangle\">{bsdf}</shape>\n</scene>\n",
        header()
    );
    import(&text, "t.xml", dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .scene
}

/// A directory holding a 2x2 PNG of `TEXEL`.
fn texel_dir(test: &str) -> PathBuf {
    let name = format!("gpu-photon-normal-map-{}-{test}", std::process::id());
    let dir = std::env::temp_dir().join(name);
    std::fs::create_dir_all(&dir).unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb(TEXEL))
        .save(dir.join("n.png"))
        .unwrap();
    dir
}

/// Mitsuba's shadowing of a normal map (`use_shadowing_function`, on by default): Estevez et
/// al.'s G1 of roughness min(tan^2(tilt) / 8, 1) for light at `cos_l` to the unperturbed normal,
/// the normal tilted to `cos_p`; written out here in f64.
fn shadowing(cos_p: f64, cos_l: f64) -> f64 {
    let tan2 = |c: f64| (1.0 - c * c) / (c * c);
    let alpha2 = (0.125 * tan2(cos_p)).min(1.0);
    2.0 / (1.0 + (1.0 + alpha2 * tan2(cos_l)).sqrt())
}

fn normal_map(texture: &str) -> String {
    format!(r#"<bsdf type="normalmap">{texture}{DIFFUSE}</bsdf>"#)
}

const PNG: &str = r#"<texture type="bitmap" name="normalmap"><string name="filename" value="n.png"/><boolean name="raw" value="true"/></texture>"#;
/// A constant texture of exactly (0.5, 0.5, 1): the unperturbed normal.
const FLAT: &str = r#"<texture type="checkerboard" name="normalmap"><rgb name="color0" value="0.5, 0.5, 1"/><rgb name="color1" value="0.5, 0.5, 1"/></texture>"#;

fn settings(s: &Scene) -> RenderSettings {
    RenderSettings {
        mode: Mode::DirectOnly,
        spp: 4,
        ..s.settings.clone()
    }
}

fn render_on(s: &Scene, backend: Backend) -> Image {
    render(s, &settings(s), backend, Progress::default())
        .unwrap_or_else(|e| panic!("{backend:?}: {e}"))
        .0
}

/// The pixels whose four corners see the square within 0.95 of its centre.
fn interior(s: &Scene) -> Vec<usize> {
    within(s, [-0.95, -0.95], [0.95, 0.95])
}

/// The pixels whose four corners see the plane z = 0 inside the box `lo`..`hi`.
fn within(s: &Scene, lo: [f64; 2], hi: [f64; 2]) -> Vec<usize> {
    let eye = s.camera.eye.as_dvec3();
    let inside = |x: f32, y: f32| {
        let d = s.camera.direction(x, y, SIDE, SIDE).as_dvec3();
        let p = eye + d * (-eye.z / d.z);
        p.x > lo[0] && p.x < hi[0] && p.y > lo[1] && p.y < hi[1]
    };
    let mut out = Vec::new();
    for y in 0..SIDE {
        for x in 0..SIDE {
            let (fx, fy) = (x as f32, y as f32);
            if [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .iter()
                .all(|&(a, b)| inside(fx + a, fy + b))
            {
                out.push((y * SIDE + x) as usize);
            }
        }
    }
    assert!(out.len() > 10, "{} interior pixels", out.len());
    out
}

/// Every interior pixel is `want` (each channel) to 1e-4.
fn assert_uniform(img: &Image, s: &Scene, want: f64, what: &str) {
    assert_pixels(img, &interior(s), want, what)
}

/// Each of `pixels` is `want` (each channel) to 1e-4.
fn assert_pixels(img: &Image, pixels: &[usize], want: f64, what: &str) {
    let mut worst = 0.0f64;
    for &i in pixels {
        for c in &img.pixels[i][..3] {
            worst = worst.max((*c as f64 - want).abs());
        }
    }
    eprintln!("{what}: want {want:.6}, worst difference {worst:.2e}");
    assert!(worst < 1e-4, "{what}: worst difference {worst} from {want}");
}

/// The perturbed normal the texel gives in the rectangle's frame (s = +x, t = +y, n = +z).
fn perturbed() -> DVec3 {
    DVec3::from(TEXEL.map(|k| 2.0 * (k as f32 / 255.0) as f64 - 1.0)).normalize()
}

#[test]
fn a_constant_normal_map_tilts_the_diffuse_cosine() {
    let dir = texel_dir("tilt");
    let plain = scene(DIFFUSE, &dir);
    let mapped = scene(&normal_map(PNG), &dir);
    let flat = scene(&normal_map(FLAT), &dir);
    let m = &mapped.materials[mapped.triangles[0].material as usize];
    assert_ne!(m.normal_texture, NO_TEXTURE);
    assert_eq!(plain.materials[0].normal_texture, NO_TEXTURE);

    let l = DVec3::from(TO_LIGHT).normalize();
    let n = perturbed();
    let tilt = n.z.acos().to_degrees();
    let angle = n.dot(l).acos().to_degrees();
    eprintln!(
        "normal {n:?}: tilted {tilt:.3} deg; light at {angle:.3} deg (unperturbed {:.3})",
        l.z.acos().to_degrees()
    );
    assert!(
        tilt > 10.0 && angle < 15.0,
        "a test that can tell the frames apart"
    );

    let k = ALBEDO / std::f64::consts::PI * E;
    let img_plain = render_on(&plain, Backend::Cpu);
    let img_mapped = render_on(&mapped, Backend::Cpu);
    let img_flat = render_on(&flat, Backend::Cpu);
    assert_uniform(&img_plain, &plain, k * l.z, "cpu, no normal map");
    let g = shadowing(n.z, l.z);
    assert!(g < 0.999, "{g}: a test that sees the shadowing");
    assert_uniform(&img_mapped, &mapped, k * n.dot(l) * g, "cpu, normal map");
    assert!(
        img_flat.pixels == img_plain.pixels,
        "a flat normal map changes the image"
    );

    // The GPU: the same estimates, only f32 rounding apart.
    if common::gpu().is_none() {
        return;
    }
    for (s, cpu, what) in [
        (&plain, &img_plain, "no normal map"),
        (&mapped, &img_mapped, "normal map"),
        (&flat, &img_flat, "flat normal map"),
    ] {
        let gpu = render_on(s, Backend::Gpu);
        let d = diff(&gpu, cpu, 8).unwrap();
        eprintln!("gpu vs cpu, {what}: {d:?}");
        assert!(d.max_error < 1e-4, "gpu vs cpu, {what}: {d:?}");
    }
    let gpu = render_on(&mapped, Backend::Gpu);
    assert_uniform(&gpu, &mapped, k * n.dot(l) * g, "gpu, normal map");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A quad in z = 0 over [-0.9, -0.3]^2, facing +z, whose uv mapping is mirrored (u runs
/// along -x, v along +y; Mitsuba 3.9.1 does not flip its frame).
const MIRRORED_QUAD: &str = "v -0.9 -0.9 0\nv -0.3 -0.9 0\nv -0.3 -0.3 0\nv -0.9 -0.3 0\n\
vt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

#[test]
fn spheres_and_mirrored_uv_meshes_on_both_backends() {
    let dir = texel_dir("shapes");
    std::fs::write(dir.join("q.obj"), MIRRORED_QUAD).unwrap();
    // A varying map (bilinear over 4 x 3 texels, all tilted less than 60 degrees).
    let mut rng = common::TestRng(5);
    let varying = image::RgbImage::from_fn(4, 3, |_, _| {
        image::Rgb([
            (rng.range(0.25, 0.75) * 255.0) as u8,
            (rng.range(0.25, 0.75) * 255.0) as u8,
            (rng.range(0.8, 1.0) * 255.0) as u8,
        ])
    });
    varying.save(dir.join("v.png")).unwrap();
    let bitmap = |file: &str| {
        format!(
            r#"<texture type="bitmap" name="normalmap"><string name="filename" value="{file}"/><boolean name="raw" value="true"/></texture>"#
        )
    };
    let text = format!(
        r#"{}<shape type="obj"><string name="filename" value="q.obj"/><boolean name="flip_tex_coords" value="false"/>{}</shape>
<shape type="sphere"><point name="center" value="0.5, 0.3, 0.3"/><float name="radius" value="0.35"/>{}</shape>
</scene>
"#,
        header(),
        normal_map(&bitmap("n.png")),
        normal_map(&bitmap("v.png")),
    );
    let s = import(&text, "t.xml", &dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .scene;
    let cpu = render_on(&s, Backend::Cpu);
    // The mirrored quad: frame s = -x (dp/du), t = n x s = -y, n = +z: Mitsuba 3.9.1 does not
    // flip a mirrored mapping's frame (`initialize_sh_frame`), and the suite's normal-mapped
    // references follow it (test_normalmap_roughconductor 1.3% off with the flip, 0.3% without).
    let m = perturbed();
    let n = DVec3::new(-m.x, -m.y, m.z);
    let l = DVec3::from(TO_LIGHT).normalize();
    let k = ALBEDO / std::f64::consts::PI * E;
    let quad = within(&s, [-0.85, -0.85], [-0.35, -0.35]);
    let g = shadowing(n.z, l.z);
    assert_pixels(&cpu, &quad, k * n.dot(l) * g, "cpu, mirrored quad");
    if common::gpu().is_none() {
        return;
    }
    let gpu = render_on(&s, Backend::Gpu);
    let d = diff(&gpu, &cpu, 8).unwrap();
    eprintln!("gpu vs cpu, sphere and mirrored quad: {d:?}");
    assert!(d.max_error < 1e-4, "gpu vs cpu: {d:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The error of importing the rectangle with `bsdf`.
fn error(bsdf: &str) -> String {
    let text = format!(
        "{}<shape type=\"rectangle\">\n{bsdf}</shape>\n</scene>\n",
        header()
    );
    match import(&text, "t.xml", Path::new(".")) {
        Ok(_) => panic!("accepted: {bsdf}"),
        Err(e @ Error::Scene { .. }) => e.to_string(),
        Err(e) => panic!("not a scene error: {e}"),
    }
}

#[test]
fn malformed_normal_maps_name_file_line_and_field() {
    // The header is lines 1-5; the rectangle line 6, its bsdf line 7.
    let cases = [
        (
            format!(r#"<bsdf type="normalmap">{FLAT}</bsdf>"#),
            "t.xml:7: shape[0].bsdf: `normalmap` needs a nested <bsdf>",
        ),
        (
            format!(r#"<bsdf type="normalmap">{DIFFUSE}</bsdf>"#),
            "t.xml:7: shape[0].bsdf: `normalmap` needs a <texture name=\"normalmap\">",
        ),
        (
            format!(r#"<bsdf type="normalmap">{FLAT}{DIFFUSE}{DIFFUSE}</bsdf>"#),
            "t.xml:7: shape[0].bsdf: unsupported <bsdf> inside a `normalmap` bsdf",
        ),
        (
            format!(
                r#"<bsdf type="normalmap"><boolean name="flip_invalid_normals" value="false"/>{FLAT}{DIFFUSE}</bsdf>"#
            ),
            "t.xml:7: shape[0].bsdf.flip_invalid_normals: only Mitsuba's default `true` is supported",
        ),
        (
            format!(r#"<bsdf type="normalmap">{FLAT}{}</bsdf>"#, normal_map(FLAT)),
            "t.xml:7: shape[0].bsdf: a `normalmap` inside a `normalmap` is not supported",
        ),
        (
            normal_map(r#"<texture type="bitmap" name="normalmap"><boolean name="raw" value="true"/></texture>"#),
            "t.xml:7: shape[0].bsdf.normalmap.filename: missing",
        ),
    ];
    for (bsdf, want) in cases {
        assert_eq!(error(&bsdf), want, "{bsdf}");
    }
}

#[test]
fn a_normal_map_without_raw_is_srgb_decoded_as_mitsuba_does() {
    let dir = texel_dir("srgb");
    let srgb = r#"<texture type="bitmap" name="normalmap"><string name="filename" value="n.png"/></texture>"#;
    let s = scene(&normal_map(srgb), &dir);
    let t = &s.textures[s.materials[s.triangles[0].material as usize].normal_texture as usize];
    let got = t.eval(glam::Vec2::new(0.3, 0.6));
    let want = Vec3::from_array(TEXEL.map(|k| {
        let c = k as f64 / 255.0;
        (if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }) as f32
    }));
    assert!((got - want).abs().max_element() < 1e-6, "{got} vs {want}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_normal_maps_shadowing_is_estevez_g1() {
    use gpu_photon::bsdfs::material::terminator;
    // An unperturbed normal shadows nothing, at any angle.
    for c in [1.0, 0.5, 0.1] {
        assert_eq!(terminator(1.0, c), 1.0);
    }
    // Perturbed by 45 degrees: alpha^2 = tan^2(45) / 8 = 0.125; light at 60 degrees
    // (tan^2 = 3): G1 = 2 / (1 + sqrt(1 + 0.375)), as Mitsuba's eval_shadow_terminator.
    let c45 = std::f32::consts::FRAC_1_SQRT_2;
    let want = 2.0 / (1.0 + 1.375f32.sqrt());
    assert!(
        (terminator(c45, 0.5) - want).abs() < 1e-6,
        "{}",
        terminator(c45, 0.5)
    );
    // alpha^2 is capped at 1 (a normal 80 degrees off), and G1 falls towards grazing light.
    let c80 = 80f32.to_radians().cos();
    let tan2 = |c: f32| (1.0 - c * c) / (c * c);
    assert!((terminator(c80, 0.5) - 2.0 / (1.0 + (1.0 + tan2(0.5)).sqrt())).abs() < 1e-6);
    assert!(terminator(c45, 0.2) < terminator(c45, 0.5));
    assert!(terminator(c45, 0.0) < 1e-3);
}
