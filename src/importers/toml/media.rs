//! Participating media in the TOML scene format (issue 24): `[media.NAME]` tables,
//! `interior` / `exterior` on a shape and `medium` in `[camera]`, each naming a medium.
//! A medium's keys are Mitsuba's `homogeneous` parameters with its defaults: `sigma_t`
//! (a number or `[r, g, b]`, per scene unit, default 1), `albedo` (default 0.75), `scale`
//! (default 1) and `g` (Henyey-Greenstein asymmetry, default 0: isotropic).
//!
//! `type = "heterogeneous"` (issue 41) lets `sigma_t` and `albedo` also be the name of a
//! Mitsuba `.vol` grid file (relative to the scene file), placed in the box `bounds = [[x0,
//! y0, z0], [x1, y1, z1]]` (default: the box the grid file gives) and filtered by `filter`
//! (`"trilinear"`, the default, or `"nearest"`). The medium's extinction is zero outside the
//! extinction's box; a constant `sigma_t` fills `bounds` (which it then needs).
use crate::error::Result;
use crate::importers::toml::table::{number, Tab};
use crate::media::builder::{interface, MediumId, MediumParams};
use crate::media::grid::{Filter, Volume, VolumeGrid, VolumeKind};
use crate::media::MediumInterface;
use crate::scene::builder::SceneBuilder;
use crate::scene::locate::Part;
use glam::{Affine3A, Vec3};
use std::path::Path;
use std::sync::Arc;

/// The keys of a `[media.NAME]` table.
const MEDIUM_KEYS: &[&str] = &["type", "sigma_t", "albedo", "scale", "g"];

/// The further keys of a heterogeneous medium.
const HETEROGENEOUS_KEYS: &[&str] = &["bounds", "filter"];

/// Adds the medium of table `t` as `name` (grid files relative to `base_dir`).
pub(crate) fn medium(t: &Tab, name: &str, base_dir: &Path, b: &mut SceneBuilder) -> Result<()> {
    let heterogeneous = match t.string("type")? {
        None | Some("homogeneous") => false,
        Some("heterogeneous") => true,
        Some(kind) => {
            let message =
                format!("unsupported medium type `{kind}` (\"homogeneous\", \"heterogeneous\")");
            return Err(t.fail("type", message));
        }
    };
    match heterogeneous {
        true => t.only(&[MEDIUM_KEYS, HETEROGENEOUS_KEYS].concat(), |_| false, "")?,
        false => t.only(
            MEDIUM_KEYS,
            |k| HETEROGENEOUS_KEYS.contains(&k),
            "homogeneous",
        )?,
    }
    let at = |part: Part, message: String| match part {
        Part::Parameter(key) => t.fail(key, message),
        _ => t.fail("type", message),
    };
    if heterogeneous {
        let bounds = match t.get("bounds") {
            Some(_) => {
                let [lo, hi]: [Vec3; 2] = (t.points("bounds", 2)?.try_into())
                    .map_err(|_| t.fail("bounds", "must be an array of 2 points"))?;
                if !(lo.cmplt(hi).all()) {
                    return Err(t.fail("bounds", "needs min < max on every axis"));
                }
                Some([lo, hi])
            }
            None => None,
        };
        let filter = t.parse("filter", &["trilinear", "nearest"], |s| match s {
            "trilinear" => Some(Filter::Trilinear),
            "nearest" => Some(Filter::Nearest),
            _ => None,
        })?;
        let filter = filter.unwrap_or(Filter::Trilinear);
        let sigma_t = volume(t, "sigma_t", Vec3::ONE, bounds, filter, base_dir, b)?;
        let albedo_bounds = bounds.or(Some([sigma_t.lo, sigma_t.hi]));
        let albedo = volume(
            t,
            "albedo",
            Vec3::splat(0.75),
            albedo_bounds,
            filter,
            base_dir,
            b,
        )?;
        let (scale, g) = (t.num("scale")?.unwrap_or(1.0), t.num("g")?.unwrap_or(0.0));
        b.add_heterogeneous_medium(Some(name), sigma_t, albedo, scale, g, &at)?;
        return Ok(());
    }
    let p = MediumParams {
        sigma_t: grey_or_colour(t, "sigma_t")?.unwrap_or(Vec3::ONE),
        albedo: grey_or_colour(t, "albedo")?.unwrap_or(Vec3::splat(0.75)),
        scale: t.num("scale")?.unwrap_or(1.0),
        g: t.num("g")?.unwrap_or(0.0),
    };
    b.add_medium(Some(name), p, &at)?;
    Ok(())
}

/// A heterogeneous medium's `key`: a grid file's name, a number or `[r, g, b]` (`default`
/// when absent), over `bounds` (a grid's own box when `None`; a constant needs one).
fn volume(
    t: &Tab,
    key: &str,
    default: Vec3,
    bounds: Option<[Vec3; 2]>,
    filter: Filter,
    base_dir: &Path,
    b: &SceneBuilder,
) -> Result<Volume> {
    let to_local = |[lo, hi]: [Vec3; 2]| {
        Affine3A::from_scale((hi - lo).recip()) * Affine3A::from_translation(-lo)
    };
    let Some(file) = t.get(key).and_then(|v| v.get_ref().as_str()) else {
        let c = grey_or_colour(t, key)?.unwrap_or(default);
        let Some(bounds) = bounds else {
            let message = "a heterogeneous medium without a grid file for sigma_t needs `bounds`";
            return Err(t.fail(key, message));
        };
        return Ok(Volume::new(VolumeKind::Constant(c), to_local(bounds)));
    };
    let grid = VolumeGrid::open(&base_dir.join(file), b.grid_room()).map_err(|e| t.fail(key, e))?;
    let to_local = to_local(bounds.unwrap_or(grid.bbox));
    let kind = VolumeKind::Grid {
        grid: Arc::new(grid),
        to_local,
        filter,
    };
    Ok(Volume::new(kind, to_local))
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
