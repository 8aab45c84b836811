//! The checks the scene builder applies to colours, materials and lights.

use crate::bsdfs::BsdfKind;
use crate::error::Result;
use crate::render::memory::size;
use crate::scene::cost::MeshCost;
use crate::scene::locate::{Locate, Part};
use crate::scene::Material;
use glam::Vec3;

/// Most triangles a scene may have (after instancing): 64 Mi, about 3 GiB of triangles alone
/// on each backend. Checked before a shape's triangles are added, so that a scene graph
/// that instances a mesh many times fails with the shape that crossed it.
pub const MAX_TRIANGLES: usize = 1 << 26;

/// Most bytes of decoded texels a scene may hold, all textures together: 4 GiB. (One texture
/// is bounded on its own by `texture::MAX_TEXELS`; a scene that names many is bounded here.)
pub const MAX_TEXTURE_BYTES: u64 = 1 << 32;

/// Most bytes a scene's geometry and textures may take together where the memory available
/// is not known: 32 GiB.
pub const MAX_SCENE_BYTES: u64 = 1 << 35;

/// What a scene may hold, checked as it is built, before what is added is allocated (see
/// [`SceneBuilder::set_budgets`]).
///
/// [`SceneBuilder::set_budgets`]: crate::scene::SceneBuilder::set_budgets
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBudgets {
    /// Most triangles, after instancing ([`MAX_TRIANGLES`] by default).
    pub max_triangles: usize,
    /// Most bytes of decoded texels, all textures together ([`MAX_TEXTURE_BYTES`] by default).
    pub max_texture_bytes: u64,
    /// Most bytes the scene may hold, geometry ([`MeshCost::bytes`]) and texels together: by
    /// default half the memory available to the process (`crate::render::memory::available`; the other
    /// half for the importers' working copies and the render), at most [`MAX_SCENE_BYTES`].
    pub max_bytes: u64,
    /// The memory available that `max_bytes` is half of, and where that figure comes from;
    /// `None` when it was not known or the caller set `max_bytes`.
    pub memory: Option<(u64, &'static str)>,
}

impl Default for SceneBudgets {
    fn default() -> Self {
        let memory = crate::render::memory::available().filter(|&(b, _)| b / 2 < MAX_SCENE_BYTES);
        Self {
            max_triangles: MAX_TRIANGLES,
            max_texture_bytes: MAX_TEXTURE_BYTES,
            max_bytes: memory.map_or(MAX_SCENE_BYTES, |(b, _)| b / 2),
            memory,
        }
    }
}

impl SceneBudgets {
    /// A scene holding `have` (geometry, and `texels` bytes of textures) may take `adding`,
    /// `what` (`this shape`, `the 1000 instances of meshes[0]`): within [`Self::max_triangles`]
    /// and, with the texels, [`Self::max_bytes`]. The one check of geometry, for shapes as
    /// for instance lists.
    pub fn check_geometry(
        &self,
        have: MeshCost,
        texels: u64,
        adding: MeshCost,
        what: &str,
        at: &dyn Locate,
    ) -> Result<()> {
        let total = have.and(adding);
        let max = self.max_triangles;
        if total.triangles > max as u64 {
            let message = format!(
                "the scene would have {} triangles ({} from {what}), more than the {max} a \
                 scene may have",
                total.triangles, adding.triangles
            );
            return Err(at.error(Part::Geometry, message));
        }
        let (before, after) = (have.bytes().saturating_add(texels), total.bytes());
        if after.saturating_add(texels) > self.max_bytes {
            let why = match self.memory {
                Some((room, source)) => format!(" (half the {} available: {source})", size(room)),
                None => String::new(),
            };
            let held = match before {
                0 => String::new(),
                b => format!("; the scene holds {} already", size(b)),
            };
            let message = format!(
                "{what} would need {} triangles / {}, over the scene's budget of {}{why}{held}",
                adding.triangles,
                size(after - have.bytes()),
                size(self.max_bytes)
            );
            return Err(at.error(Part::Geometry, message));
        }
        Ok(())
    }

    /// `have` bytes of texels so far plus `adding` must stay within the texture budget, and
    /// with the scene's `geometry` within [`Self::max_bytes`].
    pub(crate) fn check_texels(
        &self,
        have: u64,
        adding: u64,
        geometry: MeshCost,
        at: &dyn Locate,
    ) -> Result<()> {
        let (total, max) = (have.saturating_add(adding), self.max_texture_bytes);
        if total.saturating_add(geometry.bytes()) > self.max_bytes {
            let message = format!(
                "the scene would take {} with this texture's {}, more than its budget of {}",
                size(total.saturating_add(geometry.bytes())),
                size(adding),
                size(self.max_bytes)
            );
            return Err(at.error(Part::Material, message));
        }
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

/// A light's direction: finite and not zero; returned normalised.
pub(crate) fn check_direction(d: Vec3, at: &dyn Locate) -> Result<Vec3> {
    let part = Part::Parameter("direction");
    if !d.is_finite() {
        return Err(at.error(part, "must be finite".into()));
    }
    let n = d.normalize_or_zero();
    if n == Vec3::ZERO || !n.is_finite() {
        return Err(at.error(part, "must not be zero".into()));
    }
    Ok(n)
}

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
