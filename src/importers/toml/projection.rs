//! The TOML lights that project an image: a spot's `filename` (projected over its cone,
//! `crate::lights::spot`) and the `projector` (`crate::lights::projector`). Both are framed
//! as Mitsuba's `lookat`: local z along the direction, local x `up × direction`, local y
//! the rest of `up`.

use crate::error::Result;
use crate::importers::toml::table::{At, Tab};
use crate::lights::projector::ProjectorLight;
use crate::lights::spot::SpotLight;
use crate::scene::builder::SceneBuilder;
use crate::scene::locate::{Locate, Part};
use crate::textures::{Encoding, SceneTexture, Texture};
use glam::{Mat4, Vec3};
use std::path::Path;

/// A light's aim: along `direction`, or at `target` (exactly one of them), from `position`;
/// `None` for the target when it is given by `direction`.
pub(crate) fn aim(t: &Tab, position: Vec3) -> Result<(Vec3, Option<Vec3>)> {
    match (t.vec3("direction")?, t.vec3("target")?) {
        (Some(d), None) => Ok((d, None)),
        (None, Some(target)) => Ok((target - position, Some(target))),
        (Some(_), Some(_)) => Err(t.fail("target", "give `direction` or `target`, not both")),
        (None, None) => Err(t.fail("direction", "missing field `direction` (or `target`)")),
    }
}

/// The frame of a light at `position` aiming along `direction` with `up` (default +y):
/// Mitsuba's `lookat` (module docs).
fn frame(t: &Tab, position: Vec3, direction: Vec3) -> Result<Mat4> {
    let given = t.vec3("up")?;
    let Some(dir) = direction.try_normalize() else {
        let message = "must not be zero (or `target` equals `position`)";
        return Err(t.fail("direction", message));
    };
    let Some(left) = given.unwrap_or(Vec3::Y).cross(dir).try_normalize() else {
        let message = match given {
            Some(_) => "must not be zero or parallel to the direction",
            None => "the default up (+y) is parallel to the direction: give `up`",
        };
        return Err(t.fail("up", message));
    };
    Ok(Mat4::from_cols(
        left.extend(0.0),
        dir.cross(left).extend(0.0),
        dir.extend(0.0),
        position.extend(1.0),
    ))
}

/// The image of `filename` (relative to the scene's directory), as a colour texture.
fn image(t: &Tab, base_dir: &Path) -> Result<Option<Texture>> {
    let Some(file) = t.string("filename")? else {
        return Ok(None);
    };
    Texture::load(&base_dir.join(file), Encoding::Srgb)
        .map(Some)
        .map_err(|e| t.fail("filename", e.to_string()))
}

/// A spot with `filename`: its image projected over the cone, framed by `up`.
pub(crate) fn textured_spot(
    t: &Tab,
    base_dir: &Path,
    spot: SpotLight,
    b: &mut SceneBuilder,
    at: &dyn Locate,
) -> Result<()> {
    let m = frame(t, spot.position, spot.direction)?;
    let Some(image) = image(t, base_dir)? else {
        unreachable!("called with a filename")
    };
    let id = b.add_texture(SceneTexture::Bitmap(image), &|_: Part, m: String| {
        t.fail("filename", m)
    })?;
    let axes = (m.transform_vector3(Vec3::X), m.transform_vector3(Vec3::Y));
    b.add_projecting_spot_light(spot, id, axes, at)
}

/// `type = "projector"`: `position`, `direction` or `target`, `up`, `fov` (horizontal,
/// degrees), `irradiance` (default 1) and `scale` (default 1), and an image `filename`.
pub(crate) fn projector(t: &Tab, base_dir: &Path, b: &mut SceneBuilder) -> Result<()> {
    let position = t.need("position", t.vec3("position")?)?;
    let (direction, _) = aim(t, position)?;
    let to_world = frame(t, position, direction)?;
    let fov_x = t.need("fov", t.num("fov")?)?;
    let irradiance = t.color("irradiance", None)?.unwrap_or(Vec3::ONE);
    let scale = t.num("scale")?.unwrap_or(1.0);
    let image = image(t, base_dir)?;
    let aspect = image
        .as_ref()
        .map_or(1.0, |i| i.width as f32 / i.height as f32);
    let texture = match image {
        Some(i) => Some(
            b.add_texture(SceneTexture::Bitmap(i), &|_: Part, m: String| {
                t.fail("filename", m)
            })?,
        ),
        None => None,
    };
    let at = At {
        tab: t,
        geometry: "position",
        emission: if scale < 0.0 { "scale" } else { "irradiance" },
    };
    let light = ProjectorLight {
        to_world,
        fov_x,
        aspect,
        irradiance: irradiance * scale,
        texture,
    };
    b.add_projector_light(light, &at)
}
