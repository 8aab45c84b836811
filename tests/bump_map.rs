//! Mitsuba 3's `bumpmap` bsdf (src/bsdfs/bumpmap.cpp): at the hits
//! `scripts/mitsuba_bumpmap.py` measured with Mitsuba 3.9.1, the height texture's gradient
//! (`SceneTexture::eval_grad`, Mitsuba's bitmap `eval_1_grad`), the bumped shading normal
//! (`Hit::shading`, through `bump_mapped`) and the bumped frame's tangent (`Hit::tangent`,
//! `bump_tangent`: 3.9.1's Gram-Schmidt of the world dp/du against the local normal) equal
//! the frame Mitsuba hands its nested bsdf: on the suite's uv sphere mesh
//! rotated (its `floor_tiles_bumpmap.png`, raw, scale 0.02 as `test_bumpmap_path.xml`), an OBJ
//! quad with mirrored uvs (sRGB-decoded) and an analytic sphere with a sheared `to_uv`.
//! Malformed `bumpmap`s are `FILE:LINE: field:` errors.

mod common;

use glam::{Vec2, Vec3};
use gpu_photon::error::Error;
use gpu_photon::importers::mitsuba::import;
use std::path::Path;

/// The gradient, relative to the texture's side (2048; the luminance's spread is 1): the same
/// texels and weights, each rounded in its own order (fused or not); measured 3.8e-6.
const GRAD_REL: f32 = 2e-5;
/// The bumped frame's normal and tangent: ours from the same partials and gradient as
/// Mitsuba's, each rounded in its own order.
const NORMAL_ABS: f32 = 5e-5;

const MIRROR_OBJ: &str = "v -1 -1 0\nv 1 -1 0.2\nv 1 1 0\nv -1 1 -0.3\n\
    vt 0.7 0.1\nvt 0.1 0.2\nvt 0.2 0.9\nvt 0.8 0.7\n\
    vn 0.1 0 1\nvn 0 0.2 1\nvn -0.1 0.1 1\nvn 0.2 -0.1 1\n\
    f 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\n";

fn suite() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba-suite/common")
}

fn bumpmap(texture: &str, scale: f32) -> String {
    format!(
        r#"<bsdf type="bumpmap"><float name="scale" value="{scale}"/>{texture}<bsdf type="diffuse"/></bsdf>"#
    )
}

#[test]
fn gradients_and_bumped_normals_are_mitsubas() {
    let dir = common::scratch("bump-map");
    std::fs::write(dir.join("mirror.obj"), MIRROR_OBJ).unwrap();
    let png = suite().join("textures/floor_tiles_bumpmap.png");
    let png = png.display();
    let raw = format!(
        r#"<texture type="bitmap" name="height"><string name="filename" value="{png}"/><boolean name="raw" value="true"/></texture>"#
    );
    let srgb = format!(
        r#"<texture type="bitmap" name="height"><string name="filename" value="{png}"/></texture>"#
    );
    let sheared = format!(
        r#"<texture type="bitmap" name="height"><string name="filename" value="{png}"/><boolean name="raw" value="true"/>
        <transform name="to_uv"><matrix value="2 0.5 0 0.1  -0.25 1.5 0 0.3  0 0 1 0  0 0 0 1"/></transform></texture>"#
    );
    let sphere = suite().join("meshes/sphere.obj");
    let rotate = r#"<transform name="to_world"><rotate z="1" angle="30"/><rotate y="1" angle="30"/>
        <rotate x="1" angle="30"/></transform>"#;
    let shapes = [
        (
            "uv",
            format!(
                r#"<shape type="obj"><string name="filename" value="{}"/>{rotate}{}</shape>"#,
                sphere.display(),
                bumpmap(&raw, 0.02)
            ),
        ),
        (
            "mirror",
            format!(
                r#"<shape type="obj"><string name="filename" value="mirror.obj"/>{}</shape>"#,
                bumpmap(&srgb, 0.001)
            ),
        ),
        (
            "sphere",
            format!(
                r#"<shape type="sphere"><point name="center" value="0.3, -0.2, 0.1"/><float name="radius" value="0.8"/>{}</shape>"#,
                bumpmap(&sheared, 0.002)
            ),
        ),
    ];
    let (mut worst_grad, mut worst_normal, mut worst_tangent) = (0f32, 0f32, 0f32);
    let mut tilted = 0;
    common::mitsuba_hits(
        &dir,
        "mitsuba_bumpmap.csv",
        &shapes,
        |name, scene, hit, r| {
            let at = format!("{name} at {}", hit.position);
            let uv = Vec2::new(r[9], r[10]);
            assert!(
                (hit.uv - uv).abs().max_element() < 1e-5,
                "{at}: uv {} vs {uv}",
                hit.uv
            );
            let m = &scene.materials[hit.material as usize];
            let grad = scene.textures[m.normal_texture as usize].eval_grad(hit.uv);
            let want = Vec2::new(r[11], r[12]);
            let e = (grad - want).abs().max_element() / 2048.0;
            assert!(e < GRAD_REL, "{at}: gradient {grad} vs Mitsuba's {want}");
            worst_grad = worst_grad.max(e);
            // The frame's normal (columns 13-15) and tangent (16-18).
            for (k, got, worst) in [
                (13, hit.shading, &mut worst_normal),
                (16, hit.tangent, &mut worst_tangent),
            ] {
                let want = Vec3::new(r[k], r[k + 1], r[k + 2]);
                let e = (got - want).abs().max_element();
                assert!(
                    e < NORMAL_ABS,
                    "{at}: column {k}: {got} vs Mitsuba's {want}"
                );
                *worst = worst.max(e);
            }
            tilted += (hit.shading.dot(hit.normal) < 0.999) as usize;
        },
    );
    // Most hits are tilted: the test compares bumps, not unperturbed normals.
    assert!(tilted > 18, "{tilted} tilted");
    eprintln!(
        "worst gradient difference from Mitsuba 3.9.1: {worst_grad:e} of 2048; worst normal \
         {worst_normal:e}, tangent {worst_tangent:e}; {tilted} of 36 tilted"
    );
}

fn error(bsdf: &str) -> String {
    let text = format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n<shape type=\"rectangle\">\n{bsdf}\n</shape>\n</scene>\n"
    );
    match import(&text, "t.xml", &suite()) {
        Ok(_) => panic!("accepted: {bsdf}"),
        Err(e @ Error::Scene { .. }) => e.to_string(),
        Err(e) => panic!("not a scene error: {e}"),
    }
}

#[test]
fn malformed_bump_maps_name_file_line_and_field() {
    const DIFFUSE: &str = r#"<bsdf type="diffuse"/>"#;
    let tex = r#"<texture type="bitmap" name="h"><string name="filename" value="textures/floor_tiles_bumpmap.png"/></texture>"#;
    let checker = r#"<texture type="checkerboard" name="h"/>"#;
    // The bsdf is line 4.
    let cases = [
        (
            format!(r#"<bsdf type="bumpmap">{tex}</bsdf>"#),
            "t.xml:4: shape[0].bsdf: `bumpmap` needs a nested <bsdf>".to_string(),
        ),
        (
            format!(r#"<bsdf type="bumpmap">{DIFFUSE}</bsdf>"#),
            "t.xml:4: shape[0].bsdf: `bumpmap` needs a <texture>".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap">{tex}{}{DIFFUSE}</bsdf>"#, tex.replace("\"h\"", "\"g\"")),
            "t.xml:4: shape[0].bsdf.g: `bumpmap` takes one <texture>".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap">{checker}{DIFFUSE}</bsdf>"#),
            "t.xml:4: shape[0].bsdf.h: a `bumpmap` needs a `bitmap` (Mitsuba's other textures have no gradient)".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap">{tex}{DIFFUSE}{DIFFUSE}</bsdf>"#),
            "t.xml:4: shape[0].bsdf: unsupported <bsdf> inside a `bumpmap` bsdf".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap"><boolean name="flip_invalid_normals" value="false"/>{tex}{DIFFUSE}</bsdf>"#),
            "t.xml:4: shape[0].bsdf.flip_invalid_normals: only Mitsuba's default `true` is supported".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap">{tex}{}</bsdf>"#, bumpmap(tex, 1.0)),
            "t.xml:4: shape[0].bsdf: a `bumpmap` inside a `bumpmap` is not supported".into(),
        ),
        (
            format!(r#"<bsdf type="bumpmap"><float name="sigma" value="1"/>{tex}{DIFFUSE}</bsdf>"#),
            "t.xml:4: shape[0].bsdf.sigma: unsupported parameter of `bumpmap`".into(),
        ),
    ];
    for (bsdf, want) in cases {
        assert_eq!(error(&bsdf), want, "{bsdf}");
    }
}
