//! Mitsuba BSDFs as our materials (the mapping is documented in `scenes/README.md`):
//! `diffuse`, `twosided`, `conductor`, `dielectric` exactly; `plastic`, `roughplastic`,
//! `roughconductor` (and named conductors) approximately, with one warning each.

use super::plugin::Plugin;
use super::values::Cx;
use crate::error::Result;
use crate::scene::Material;
use glam::Vec3;
use roxmltree::Node;

/// The Phong exponent of a smooth coating (`plastic`): a sharp but finite lobe.
pub(super) const SMOOTH_EXPONENT: f32 = 1000.0;
/// Mitsuba's default `ext_ior` (air).
const AIR: f32 = 1.000277;

/// The Phong exponent that matches a microfacet roughness `alpha`: `2 / alpha^2 - 2`
/// (Walter et al. 2007, the Beckmann-Phong correspondence), at least 0.
pub(super) fn phong_exponent(alpha: f32) -> f32 {
    (2.0 / (alpha * alpha) - 2.0).max(0.0)
}

/// Reads the `<bsdf>` element `node` at `field` as a material; approximations push a
/// warning naming the bsdf.
pub(super) fn bsdf(
    cx: &Cx,
    node: Node,
    field: &str,
    warnings: &mut Vec<String>,
) -> Result<Material> {
    let p = Plugin::new(cx, node, field.to_string())?;
    let mut notes: Vec<String> = Vec::new();
    let kind = p.kind.as_str();
    if let Some(&extra) = p.objects.get(usize::from(kind == "twosided")) {
        let tag = extra.tag_name().name();
        let message = format!("unsupported <{tag}> inside a `{kind}` bsdf");
        return Err(cx.err(extra, field, message));
    }
    let material = match kind {
        "twosided" => {
            // Our materials reflect on both sides already: the nested bsdf is the material.
            let Some(&inner) = p.objects.first() else {
                return Err(cx.err(node, field, "`twosided` needs a nested <bsdf>"));
            };
            if inner.tag_name().name() != "bsdf" {
                let message = "`twosided` needs a nested <bsdf>";
                return Err(cx.err(inner, field, message));
            }
            bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?
        }
        "diffuse" => {
            let albedo = p.albedo(cx, "reflectance", 0.5)?;
            if albedo == Vec3::ZERO {
                Material::black()
            } else {
                Material::diffuse(albedo)
            }
        }
        "conductor" | "roughconductor" => {
            let reflectance = conductor_reflectance(cx, &p, &mut notes)?;
            if kind == "conductor" {
                Material::mirror(reflectance)
            } else {
                p.ignore(&["distribution", "sample_visible"]);
                let exponent = phong_exponent(roughness(cx, &p)?);
                notes.push(format!(
                    "`roughconductor` approximated as glossy (ks {reflectance}, Phong exponent {exponent})"
                ));
                Material::glossy(Vec3::ZERO, reflectance, exponent)
            }
        }
        "dielectric" => {
            let int_ior = p.ior(cx, "int_ior", 1.5046)?;
            let ext_ior = p.ior(cx, "ext_ior", AIR)?;
            // Refraction and Fresnel depend only on the ratio; our outside is exactly 1.
            Material::glass(int_ior / ext_ior)
        }
        "plastic" | "roughplastic" => {
            let kd = p.albedo(cx, "diffuse_reflectance", 0.5)?;
            let specular = p.albedo(cx, "specular_reflectance", 1.0)?;
            let eta = p.ior(cx, "int_ior", 1.49)? / p.ior(cx, "ext_ior", AIR)?;
            let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            p.ignore(&["nonlinear", "distribution", "sample_visible"]);
            let exponent = match kind {
                "plastic" => SMOOTH_EXPONENT,
                _ => phong_exponent(roughness(cx, &p)?),
            };
            let (kd, ks) = (kd * (1.0 - f0), specular * f0);
            notes.push(format!(
                "`{kind}` approximated as glossy (kd {kd}, ks {ks}, Phong exponent {exponent})"
            ));
            Material::glossy(kd, ks, exponent)
        }
        other => {
            let message = format!("unsupported bsdf `{other}`");
            return Err(cx.err(node, field, message));
        }
    };
    p.done(cx)?;
    let line = node.document().text_pos_at(node.range().start).row;
    for note in notes {
        warnings.push(format!("{}:{line}: {field}: {note}", cx.file));
    }
    Ok(material)
}

/// The roughness `alpha` (default 0.1; anisotropic `alpha_u`, `alpha_v`: their geometric mean).
fn roughness(cx: &Cx, p: &Plugin) -> Result<f32> {
    let alpha = p.positive(cx, "alpha", 0.1)?;
    match (p.float(cx, "alpha_u")?, p.float(cx, "alpha_v")?) {
        (None, None) => Ok(alpha),
        (u, v) => {
            let u = u.unwrap_or(alpha);
            let v = v.unwrap_or(alpha);
            if u > 0.0 && v > 0.0 {
                return Ok((u * v).sqrt());
            }
            Err(cx.err(p.node, &p.at("alpha_u"), "must be positive"))
        }
    }
}

/// A conductor's reflectance: `specular_reflectance` for `material` `none` (the default);
/// with `eta` and `k` given, times their normal-incidence Fresnel reflectance, with a warning;
/// a named material is a mirror of `specular_reflectance`, with a warning.
fn conductor_reflectance(cx: &Cx, p: &Plugin, notes: &mut Vec<String>) -> Result<Vec3> {
    let specular = p.albedo(cx, "specular_reflectance", 1.0)?;
    let material = p.string(cx, "material")?;
    let eta = p.color(cx, "eta")?;
    let k = p.color(cx, "k")?;
    match (material.as_deref(), eta, k) {
        (None | Some("none"), None, None) => Ok(specular),
        (_, Some(eta), k) => {
            let k = k.unwrap_or(Vec3::ZERO);
            let num = (eta - 1.0) * (eta - 1.0) + k * k;
            let r0 = num / ((eta + 1.0) * (eta + 1.0) + k * k);
            notes.push(format!(
                "conductor with eta/k approximated by its normal-incidence reflectance {r0}"
            ));
            Ok(specular * r0)
        }
        (None, None, Some(_)) => Err(cx.err(p.node, &p.at("k"), "`k` needs `eta`")),
        (Some(name), None, _) => {
            notes.push(format!(
                "conductor material `{name}` approximated by specular_reflectance {specular}"
            ));
            Ok(specular)
        }
    }
}
