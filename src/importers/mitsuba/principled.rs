//! Mitsuba 3.9's `principled` as our [`Principled`]: every parameter a float (or `rgb` for
//! `base_color`) or a `<texture>` (a float parameter reads a texture's luminance, as
//! Mitsuba's `eval_1` does), `eta` or `specular` (not both), Mitsuba's defaults and its
//! adjustments for transmission (`eta` 1 becomes 1.001, `specular` 0 becomes 0.001 when
//! `spec_trans` is given). The sampling rates change only Mitsuba's noise: accepted, unused.
//! `principledthin` likewise as our [`PrincipledThin`] (its `eta` a positive float or a
//! texture, `diff_trans` in [0, 2]).

use crate::bsdfs::{Bsdf, Channel, Param, Principled, PrincipledThin};
use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::texture::texture;
use crate::importers::mitsuba::values::Cx;
use crate::textures::{Checkerboard, SceneTexture};
use glam::Vec3;

/// Where the caller puts a parameter's texture once it has added it to the scene.
pub(crate) type ParamSlot = fn(&mut Bsdf) -> Option<&mut Param>;

/// A principled parameter of the kind (`None` for another kind).
macro_rules! slot {
    ($field:ident) => {
        slot!(Principled, $field)
    };
    ($variant:ident, $field:ident) => {
        |b: &mut Bsdf| match b {
            Bsdf::$variant(p) => Some(&mut p.$field),
            _ => None,
        }
    };
}

/// The float parameters.
const FLOATS: &[FloatParam] = &[
    ("roughness", 0.5, 1.0, slot!(roughness)),
    ("anisotropic", 0.0, 1.0, slot!(anisotropic)),
    ("metallic", 0.0, 1.0, slot!(metallic)),
    ("spec_trans", 0.0, 1.0, slot!(spec_trans)),
    ("spec_tint", 0.0, 1.0, slot!(spec_tint)),
    ("sheen", 0.0, f32::MAX, slot!(sheen)),
    ("sheen_tint", 0.0, 1.0, slot!(sheen_tint)),
    ("clearcoat", 0.0, f32::MAX, slot!(clearcoat)),
    ("clearcoat_gloss", 0.0, 1.0, slot!(clearcoat_gloss)),
    ("flatness", 0.0, 1.0, slot!(flatness)),
];

/// A texture as Mitsuba's `eval_1` reads it (a float parameter): a `checkerboard`'s
/// `eval_1` gives `color0` where its RGB `eval` gives `color1` and the other way round
/// (Mitsuba 3.9.1; scripts/mitsuba_checkerboard_eval1.py pins it), so its colours swap.
pub(crate) fn float_texture(t: SceneTexture) -> SceneTexture {
    match t {
        SceneTexture::Checkerboard(c) => SceneTexture::Checkerboard(Checkerboard {
            color0: c.color1,
            color1: c.color0,
            ..c
        }),
        other => other,
    }
}

/// A texture read for a parameter: the texture, the channel the parameter reads, its slot.
pub(crate) type ParamTexture = (SceneTexture, Channel, ParamSlot);

/// A float parameter: name, Mitsuba's default, the largest value accepted, the slot.
pub(crate) type FloatParam = (&'static str, f32, f32, ParamSlot);

/// Reads `base_color` and the float parameters `floats` of plugin `p` into `b` (a textured
/// parameter has factor one) and returns their textures, for the caller to add and point the
/// slots at.
pub(crate) fn read_params(
    cx: &Cx,
    p: &Plugin,
    b: &mut Bsdf,
    base: ParamSlot,
    floats: &[FloatParam],
) -> Result<Vec<ParamTexture>> {
    let mut textures: Vec<ParamTexture> = Vec::new();
    let colour = match p.texture_param("base_color") {
        Some(t) => {
            textures.push((texture(cx, t, &p.at("base_color"))?, Channel::Rgb, base));
            Vec3::ONE
        }
        None => p.albedo(cx, "base_color", 0.5)?,
    };
    if let Some(v) = base(b) {
        *v = Param::rgb(colour);
    }
    for &(name, default, max, slot) in floats {
        let value = match p.texture_param(name) {
            Some(t) => {
                let t = float_texture(texture(cx, t, &p.at(name))?);
                textures.push((t, Channel::Luminance, slot));
                Param::constant(1.0)
            }
            None => {
                let v = p.float(cx, name)?.unwrap_or(default);
                if !(0.0..=max).contains(&v) {
                    let range = match max {
                        f32::MAX => "must be >= 0".to_string(),
                        _ => format!("must be in [0, {max}]"),
                    };
                    return Err(cx.err(p.node_of(name), &p.at(name), range));
                }
                Param::constant(v)
            }
        };
        if let Some(v) = slot(b) {
            *v = value;
        }
    }
    Ok(textures)
}

/// Reads a `principled` plugin: the kind (a textured parameter has factor one) and the
/// textures of its parameters, for the caller to add and point the slots at.
pub(crate) fn principled(cx: &Cx, p: &Plugin) -> Result<(Bsdf, Vec<ParamTexture>)> {
    let mut b = Bsdf::Principled(Principled::new());
    let textures = read_params(cx, p, &mut b, slot!(base_color), FLOATS)?;
    // Mitsuba's `get_flag`: given, and not the float 0.
    let has_spec_trans = p.texture_param("spec_trans").is_some()
        || p.float(cx, "spec_trans")?.is_some_and(|v| v != 0.0);
    let eta = match (p.float(cx, "eta")?, p.float(cx, "specular")?) {
        (Some(_), Some(_)) => {
            let message = "give `eta` or `specular`, not both";
            return Err(cx.err(p.node_of("specular"), &p.at("specular"), message));
        }
        (Some(eta), None) => {
            if !(eta > 0.0 && eta.is_finite()) {
                return Err(cx.err(p.node_of("eta"), &p.at("eta"), "must be positive"));
            }
            if has_spec_trans && eta == 1.0 {
                1.001
            } else {
                eta
            }
        }
        (None, specular) => {
            let mut s = specular.unwrap_or(0.5);
            if !(0.0..12.5).contains(&s) {
                let message = "must be in [0, 12.5) (an index of refraction from 1 up)";
                return Err(cx.err(p.node_of("specular"), &p.at("specular"), message));
            }
            if has_spec_trans && s == 0.0 {
                s = 1e-3;
            }
            Principled::eta_of_specular(s)
        }
    };
    p.ignore(&[
        "main_specular_sampling_rate",
        "clearcoat_sampling_rate",
        "diffuse_reflectance_sampling_rate",
    ]);
    if let Bsdf::Principled(kind) = &mut b {
        kind.eta = eta;
    }
    Ok((b, textures))
}

/// `principledthin`'s float parameters (`eta` apart).
const THIN_FLOATS: &[FloatParam] = &[
    ("roughness", 0.5, 1.0, slot!(PrincipledThin, roughness)),
    ("anisotropic", 0.0, 1.0, slot!(PrincipledThin, anisotropic)),
    ("spec_trans", 0.0, 1.0, slot!(PrincipledThin, spec_trans)),
    ("diff_trans", 0.0, 2.0, slot!(PrincipledThin, diff_trans)),
    ("sheen", 0.0, f32::MAX, slot!(PrincipledThin, sheen)),
    ("sheen_tint", 0.0, 1.0, slot!(PrincipledThin, sheen_tint)),
    ("flatness", 0.0, 1.0, slot!(PrincipledThin, flatness)),
    ("spec_tint", 0.0, 1.0, slot!(PrincipledThin, spec_tint)),
];

/// Reads a `principledthin` plugin as [`principled`] reads a `principled` one.
pub(crate) fn principled_thin(cx: &Cx, p: &Plugin) -> Result<(Bsdf, Vec<ParamTexture>)> {
    let mut b = Bsdf::PrincipledThin(PrincipledThin::new());
    let base: ParamSlot = slot!(PrincipledThin, base_color);
    let mut textures = read_params(cx, p, &mut b, base, THIN_FLOATS)?;
    let eta: ParamSlot = slot!(PrincipledThin, eta);
    let value = match p.texture_param("eta") {
        Some(t) => {
            let t = float_texture(texture(cx, t, &p.at("eta"))?);
            textures.push((t, Channel::Luminance, eta));
            Param::constant(1.0)
        }
        None => {
            let v = p.float(cx, "eta")?.unwrap_or(1.5);
            if !(v > 0.0 && v.is_finite()) {
                return Err(cx.err(p.node_of("eta"), &p.at("eta"), "must be positive"));
            }
            Param::constant(v)
        }
    };
    if let Some(v) = eta(&mut b) {
        *v = value;
    }
    p.ignore(&[
        "specular_reflectance_sampling_rate",
        "specular_transmittance_sampling_rate",
        "diffuse_transmittance_sampling_rate",
        "diffuse_reflectance_sampling_rate",
    ]);
    Ok((b, textures))
}
