//! Mitsuba's `principled` as the importer reads it: defaults, `specular` to `eta`, the
//! transmission adjustments, textured parameters (a float parameter reads a checkerboard as
//! Mitsuba's `eval_1` does, colours swapped: scripts/mitsuba_checkerboard_eval1.py) and
//! located errors.

use glam::{Vec2, Vec3};
use gpu_photon::bsdfs::{Bsdf, BsdfKind, Principled};
use gpu_photon::importers::mitsuba::import;
use gpu_photon::scene::Scene;
use std::path::Path;

/// A scene with one rectangle whose bsdf is `bsdf`, on line 3.
fn scene_with(bsdf: &str) -> String {
    format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film></sensor>\n<shape type=\"rectangle\">{bsdf}</shape>\n</scene>\n"
    )
}

fn load_bsdf(bsdf: &str) -> Result<Scene, String> {
    import(&scene_with(bsdf), "p.xml", Path::new("."))
        .map(|im| im.scene)
        .map_err(|e| e.to_string())
}

/// The scene of a `principled` bsdf with `params`.
fn load(params: &str) -> Result<Scene, String> {
    load_bsdf(&format!(r#"<bsdf type="principled">{params}</bsdf>"#))
}

/// The principled kind of the scene's one material, resolved at `uv`.
fn principled_at(s: &Scene, uv: Vec2) -> Principled {
    match s.materials[s.triangles[0].material as usize]
        .bsdf
        .resolve(&s.textures, uv)
    {
        Bsdf::Principled(p) => p,
        other => panic!("not principled: {other:?}"),
    }
}

#[test]
fn defaults_and_the_index() {
    let p = principled_at(&load("").unwrap(), Vec2::ZERO);
    assert_eq!(p.base_color.get(), Vec3::splat(0.5));
    assert_eq!(p.roughness.float(), 0.5);
    assert_eq!(p.metallic.float(), 0.0);
    // specular 0.5: 2 / (1 - sqrt(0.04)) - 1.
    assert!((p.eta - 1.5).abs() < 1e-6, "{}", p.eta);
    let p = principled_at(
        &load(r#"<float name="specular" value="0.7"/>"#).unwrap(),
        Vec2::ZERO,
    );
    assert!((p.eta - (2.0 / (1.0 - 0.056f32.sqrt()) - 1.0)).abs() < 1e-6);
    // Transmission: eta 1 becomes 1.001, specular 0 becomes 0.001 (Mitsuba's adjustments).
    let t = r#"<float name="spec_trans" value="0.5"/>"#;
    let p = principled_at(
        &load(&format!(r#"{t}<float name="eta" value="1"/>"#)).unwrap(),
        Vec2::ZERO,
    );
    assert_eq!(p.eta, 1.001);
    let p = principled_at(
        &load(&format!(r#"{t}<float name="specular" value="0"/>"#)).unwrap(),
        Vec2::ZERO,
    );
    assert_eq!(p.eta, Principled::eta_of_specular(1e-3));
    // Without transmission eta 1 stays.
    let p = principled_at(
        &load(r#"<float name="eta" value="1"/>"#).unwrap(),
        Vec2::ZERO,
    );
    assert_eq!(p.eta, 1.0);
}

#[test]
fn float_parameters_read_checkerboards_as_mitsubas_eval_1() {
    let checker = |name: &str| {
        format!(
            r#"<texture name="{name}" type="checkerboard"><float name="color0" value="0.7"/><float name="color1" value="0.1"/></texture>"#
        )
    };
    let s = load(&format!(
        "{}{}{}",
        checker("metallic"),
        checker("sheen"),
        r#"<texture name="base_color" type="checkerboard"><rgb name="color0" value="0.9, 0.5, 0.1"/><rgb name="color1" value="0.2, 0.3, 0.4"/></texture>"#
    ))
    .unwrap();
    // uv (0.1, 0.1): both cell masks false, RGB eval color0, eval_1 color1.
    let p = principled_at(&s, Vec2::new(0.1, 0.1));
    assert!((p.metallic.float() - 0.1).abs() < 1e-6, "{:?}", p.metallic);
    assert!((p.sheen.float() - 0.1).abs() < 1e-6, "{:?}", p.sheen);
    assert!(
        (p.base_color.get() - Vec3::new(0.9, 0.5, 0.1))
            .abs()
            .max_element()
            < 1e-6
    );
    let p = principled_at(&s, Vec2::new(0.6, 0.1));
    assert!((p.metallic.float() - 0.7).abs() < 1e-6, "{:?}", p.metallic);
    assert!(
        (p.base_color.get() - Vec3::new(0.2, 0.3, 0.4))
            .abs()
            .max_element()
            < 1e-6
    );
}

#[test]
fn bad_parameters_are_located_errors() {
    let both = load(r#"<float name="eta" value="1.5"/><float name="specular" value="0.5"/>"#);
    let e = both.unwrap_err();
    assert!(
        e.contains("p.xml:3") && e.contains("give `eta` or `specular`, not both"),
        "{e}"
    );
    let e = load(r#"<float name="metallic" value="1.5"/>"#).unwrap_err();
    assert!(
        e.contains("p.xml:3") && e.contains("metallic") && e.contains("must be in [0, 1]"),
        "{e}"
    );
    let e = load(r#"<float name="eta" value="-2"/>"#).unwrap_err();
    assert!(e.contains("eta") && e.contains("must be positive"), "{e}");
    let e = load(r#"<float name="specular" value="13"/>"#).unwrap_err();
    assert!(e.contains("specular") && e.contains("12.5"), "{e}");
    let e = load(r#"<float name="sheen" value="-1"/>"#).unwrap_err();
    assert!(e.contains("sheen") && e.contains("must be >= 0"), "{e}");
    let e = load(r#"<float name="glitter" value="1"/>"#).unwrap_err();
    assert!(e.contains("glitter"), "{e}");
    let e = load(r#"<float name="roughness" value="nan"/>"#).unwrap_err();
    assert!(e.contains("roughness"), "{e}");
}

#[test]
fn twosided_makes_it_two_sided() {
    let p = principled_at(&load("").unwrap(), Vec2::ZERO);
    assert!(!p.two_sided);
    let wrapped = r#"<bsdf type="twosided"><bsdf type="principled"><float name="roughness" value="0.3"/></bsdf></bsdf>"#;
    let p = principled_at(&load_bsdf(wrapped).unwrap(), Vec2::ZERO);
    assert!(p.two_sided && p.roughness.float() == 0.3, "{p:?}");
    // Seen from behind it reflects as from the front; alone it is black there.
    let b = Bsdf::Principled(p);
    let (wi, wo) = (
        Vec3::new(0.3, 0.1, 0.95).normalize(),
        Vec3::new(-0.2, 0.4, 0.9).normalize(),
    );
    let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    let t = gpu_photon::bsdfs::Transport::Radiance;
    assert!(b.eval(wi, wo, t).max_element() > 0.0);
    assert_eq!(b.eval(flip(wi), flip(wo), t), b.eval(wi, wo, t));
    let one_sided = Bsdf::Principled(Principled {
        two_sided: false,
        ..p
    });
    assert_eq!(one_sided.eval(flip(wi), flip(wo), t), Vec3::ZERO);
}

/// The thin kind of the scene's one material (a `principledthin` with `params`), resolved at
/// `uv`, and whether the material is one-sided.
fn thin_at(params: &str, uv: Vec2) -> Result<(gpu_photon::bsdfs::PrincipledThin, bool), String> {
    let s = load_bsdf(&format!(r#"<bsdf type="principledthin">{params}</bsdf>"#))?;
    let m = &s.materials[s.triangles[0].material as usize];
    match m.bsdf.resolve(&s.textures, uv) {
        Bsdf::PrincipledThin(p) => Ok((p, m.one_sided)),
        other => panic!("not principledthin: {other:?}"),
    }
}

/// `principledthin`: Mitsuba's defaults, two-sided by nature, textured parameters read as
/// Mitsuba's `eval_1` (a checkerboard's colours swapped), `eta` a number or a texture, and
/// located errors for values out of range (`diff_trans` up to 2).
#[test]
fn principled_thin_reads_as_mitsuba() {
    let (p, one_sided) = thin_at("", Vec2::ZERO).unwrap();
    assert!(!one_sided);
    assert_eq!(p.base_color.get(), Vec3::splat(0.5));
    assert_eq!((p.roughness.float(), p.eta.float()), (0.5, 1.5));
    assert_eq!((p.spec_trans.float(), p.diff_trans.float()), (0.0, 0.0));
    let checker = |name: &str, c0: f32, c1: f32| {
        format!(
            r#"<texture name="{name}" type="checkerboard"><float name="color0" value="{c0}"/><float name="color1" value="{c1}"/></texture>"#
        )
    };
    let params = format!(
        r#"{}{}<float name="diff_trans" value="1.4"/><float name="sheen" value="0.3"/>"#,
        checker("spec_trans", 0.2, 0.8),
        checker("eta", 1.3, 1.6)
    );
    // uv (0.1, 0.1): eval_1 reads color1.
    let (p, _) = thin_at(&params, Vec2::new(0.1, 0.1)).unwrap();
    assert!(
        (p.spec_trans.float() - 0.8).abs() < 1e-6,
        "{:?}",
        p.spec_trans
    );
    assert!((p.eta.float() - 1.6).abs() < 1e-6, "{:?}", p.eta);
    assert_eq!((p.diff_trans.float(), p.sheen.float()), (1.4, 0.3));
    let (p, _) = thin_at(&params, Vec2::new(0.6, 0.1)).unwrap();
    assert!(
        (p.spec_trans.float() - 0.2).abs() < 1e-6,
        "{:?}",
        p.spec_trans
    );
    let e = thin_at(r#"<float name="diff_trans" value="2.5"/>"#, Vec2::ZERO).unwrap_err();
    assert!(
        e.contains("p.xml:3") && e.contains("diff_trans") && e.contains("must be in [0, 2]"),
        "{e}"
    );
    let e = thin_at(r#"<float name="eta" value="0"/>"#, Vec2::ZERO).unwrap_err();
    assert!(e.contains("eta") && e.contains("must be positive"), "{e}");
    let e = thin_at(r#"<float name="metallic" value="0.5"/>"#, Vec2::ZERO).unwrap_err();
    assert!(e.contains("metallic"), "{e}");
}
