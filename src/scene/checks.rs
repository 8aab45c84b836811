//! The checks the scene builder applies to colours, materials and lights.

use crate::scene::locate::{Locate, Part};
use crate::scene::{Material, MaterialKind};
use crate::error::Result;
use glam::Vec3;

/// Most triangles a scene may have (after instancing): 64 Mi, about 3 GiB of triangles alone
/// on each backend. Checked before a shape's triangles are added, so that a scene graph
/// that instances a mesh many times fails with the shape that crossed it.
pub const MAX_TRIANGLES: usize = 1 << 26;

/// Most bytes of decoded texels a scene may hold, all textures together: 4 GiB. (One texture
/// is bounded on its own by `texture::MAX_TEXELS`; a scene that names many is bounded here.)
pub const MAX_TEXTURE_BYTES: u64 = 1 << 32;

/// What a scene may hold, checked as it is built (see [`SceneBuilder::set_budgets`]).
///
/// [`SceneBuilder::set_budgets`]: crate::scene::SceneBuilder::set_budgets
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBudgets {
    /// Most triangles, after instancing ([`MAX_TRIANGLES`] by default).
    pub max_triangles: usize,
    /// Most bytes of decoded texels, all textures together ([`MAX_TEXTURE_BYTES`] by default).
    pub max_texture_bytes: u64,
}

impl Default for SceneBudgets {
    fn default() -> Self {
        Self {
            max_triangles: MAX_TRIANGLES,
            max_texture_bytes: MAX_TEXTURE_BYTES,
        }
    }
}

impl SceneBudgets {
    /// `have` triangles so far plus `adding` must stay within the budget.
    pub(crate) fn check_triangles(
        &self,
        have: usize,
        adding: usize,
        at: &dyn Locate,
    ) -> Result<()> {
        let (total, max) = (have.saturating_add(adding), self.max_triangles);
        if total > max {
            let message = format!(
                "the scene would have {total} triangles ({adding} from this shape), more than \
                 the {max} a scene may have"
            );
            return Err(at.error(Part::Geometry, message));
        }
        Ok(())
    }

    /// `have` bytes of texels so far plus `adding` must stay within the budget.
    pub(crate) fn check_texels(&self, have: u64, adding: u64, at: &dyn Locate) -> Result<()> {
        let (total, max) = (have.saturating_add(adding), self.max_texture_bytes);
        if total > max {
            let message = format!(
                "the scene's textures would take {total} bytes ({adding} for this one), more \
                 than the {max} a scene may have"
            );
            return Err(at.error(Part::Material, message));
        }
        Ok(())
    }
}

/// Emitted radiance or intensity: finite and >= 0 in every channel.
pub(crate) fn check_emission(c: Vec3, at: &dyn Locate) -> Result<()> {
    check_color(c, None, Part::Emission, at)
}

/// A colour: finite, >= 0 and, when given, <= `max` in every channel.
pub(crate) fn check_color(c: Vec3, max: Option<f32>, part: Part, at: &dyn Locate) -> Result<()> {
    if !c.is_finite() {
        return Err(at.error(part, "must be finite".into()));
    }
    if c.min_element() < 0.0 {
        return Err(at.error(part, "components must be >= 0".into()));
    }
    match max {
        Some(m) if c.max_element() > m => {
            Err(at.error(part, format!("components must be in [0, {m}]")))
        }
        _ => Ok(()),
    }
}

/// The rules of [`SceneBuilder::add_material`].
pub(crate) fn check_material(m: &Material, at: &dyn Locate) -> Result<()> {
    let param = Part::Parameter;
    check_color(m.emission, None, param("radiance"), at)?;
    let unit = Some(1.0);
    match m.kind {
        MaterialKind::Diffuse => check_color(m.kd, unit, param("albedo"), at),
        MaterialKind::Mirror => check_color(m.ks, unit, param("reflectance"), at),
        MaterialKind::Glossy => {
            check_color(m.kd, unit, param("kd"), at)?;
            check_color(m.ks, unit, param("ks"), at)?;
            if (m.kd + m.ks).max_element() > 1.0 {
                let message = "kd + ks must be at most 1 in every channel (energy conservation)";
                return Err(at.error(param("ks"), message.into()));
            }
            match m.exponent {
                e if e.is_finite() && e >= 0.0 => Ok(()),
                _ => Err(at.error(param("exponent"), "must be >= 0 and finite".into())),
            }
        }
        MaterialKind::Glass => match m.ior {
            ior if ior.is_finite() && ior > 0.0 => Ok(()),
            _ => Err(at.error(param("ior"), "must be positive and finite".into())),
        },
        MaterialKind::Black | MaterialKind::Null => Ok(()),
        // Built by crate::bsdfs from checked parameters (importers check their ranges).
        _ => match m.bsdf {
            Some(_) => Ok(()),
            None => Err(at.error(param("bsdf"), "missing BSDF parameters".into())),
        },
    }
}

/// An area light must have a positive area and finite power.
pub(crate) fn check_light(area: f32, power: Vec3, at: &dyn Locate) -> Result<()> {
    if area.is_nan() || area <= 0.0 {
        return Err(at.error(Part::Geometry, "zero-area light".into()));
    }
    if !power.is_finite() {
        return Err(at.error(Part::Geometry, "light power is not finite".into()));
    }
    Ok(())
}
