//! The checks the scene builder applies to colours, materials and lights.

use crate::scene::locate::{Locate, Part};
use crate::bsdfs::BsdfKind;
use crate::scene::Material;
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

pub(crate) use crate::scene::locate::check_color;

/// The rules of [`SceneBuilder::add_material`]: its emission, then its kind's own checks.
pub(crate) fn check_material(m: &Material, at: &dyn Locate) -> Result<()> {
    check_color(m.emission, None, Part::Parameter("radiance"), at)?;
    m.bsdf.check(at)
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
