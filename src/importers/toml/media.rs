//! Participating media in the TOML scene format (issue 24): `[media.NAME]` tables,
//! `interior` / `exterior` on a shape and `medium` in `[camera]`, each naming a medium.
//! A medium's keys are Mitsuba's `homogeneous` parameters with its defaults: `sigma_t`
//! (a number or `[r, g, b]`, per scene unit, default 1), `albedo` (default 0.75), `scale`
//! (default 1) and `g` (Henyey-Greenstein asymmetry, default 0: isotropic).

use crate::error::Result;
use crate::importers::toml::table::{number, Tab};
use crate::media::builder::{interface, MediumId, MediumParams};
use crate::media::MediumInterface;
use crate::scene::builder::SceneBuilder;
use crate::scene::locate::Part;
use glam::Vec3;

/// The keys of a `[media.NAME]` table.
const MEDIUM_KEYS: &[&str] = &["type", "sigma_t", "albedo", "scale", "g"];

/// Adds the medium of table `t` as `name`.
pub(crate) fn medium(t: &Tab, name: &str, b: &mut SceneBuilder) -> Result<()> {
    t.only(MEDIUM_KEYS, |_| false, "")?;
    if let Some(kind) = t.string("type")? {
        if kind != "homogeneous" {
            let message = format!("unsupported medium type `{kind}` (only \"homogeneous\")");
            return Err(t.fail("type", message));
        }
    }
    let p = MediumParams {
        sigma_t: grey_or_colour(t, "sigma_t")?.unwrap_or(Vec3::ONE),
        albedo: grey_or_colour(t, "albedo")?.unwrap_or(Vec3::splat(0.75)),
        scale: t.num("scale")?.unwrap_or(1.0),
        g: t.num("g")?.unwrap_or(0.0),
    };
    let at = |part: Part, message: String| match part {
        Part::Parameter(key) => t.fail(key, message),
        _ => t.fail("type", message),
    };
    b.add_medium(Some(name), p, &at)?;
    Ok(())
}

/// A number (grey) or `[r, g, b]` at `key`.
fn grey_or_colour(t: &Tab, key: &str) -> Result<Option<Vec3>> {
    match t.get(key).map(|v| number(v.get_ref())) {
        Some(Some(x)) => Ok(Some(Vec3::splat(x as f32))),
        _ => t.vec3(key),
    }
}

/// The medium named by `key` of `t`, if given.
fn named(t: &Tab, key: &'static str, b: &SceneBuilder) -> Result<Option<MediumId>> {
    let Some(name) = t.string(key)? else {
        return Ok(None);
    };
    let at = |_: Part, message: String| t.fail(key, message);
    b.medium_named(name, Part::Parameter(key), &at).map(Some)
}

/// A shape's `interior` and `exterior`, when it gives either.
pub(crate) fn shape_media(t: &Tab, b: &SceneBuilder) -> Result<Option<MediumInterface>> {
    Ok(interface(
        named(t, "interior", b)?,
        named(t, "exterior", b)?,
    ))
}

/// `[camera] medium`: the medium the camera sits in.
pub(crate) fn camera_medium(t: &Tab, b: &mut SceneBuilder) -> Result<()> {
    if let Some(m) = named(t, "medium", b)? {
        b.set_camera_medium(m);
    }
    Ok(())
}
