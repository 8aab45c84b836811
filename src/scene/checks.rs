//! The checks the scene builder applies to colours, materials and lights.

use super::locate::{Locate, Part};
use super::{Material, MaterialKind};
use crate::error::Result;
use glam::Vec3;

/// Emitted radiance or intensity: finite and >= 0 in every channel.
pub(super) fn check_emission(c: Vec3, at: &dyn Locate) -> Result<()> {
    check_color(c, None, Part::Emission, at)
}

/// A colour: finite, >= 0 and, when given, <= `max` in every channel.
pub(super) fn check_color(c: Vec3, max: Option<f32>, part: Part, at: &dyn Locate) -> Result<()> {
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
pub(super) fn check_material(m: &Material, at: &dyn Locate) -> Result<()> {
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
        MaterialKind::Black => Ok(()),
        // Built by crate::bsdf from checked parameters (importers check their ranges).
        _ => match m.bsdf {
            Some(_) => Ok(()),
            None => Err(at.error(param("bsdf"), "missing BSDF parameters".into())),
        },
    }
}

/// An area light must have a positive area and finite power.
pub(super) fn check_light(area: f32, power: Vec3, at: &dyn Locate) -> Result<()> {
    if area.is_nan() || area <= 0.0 {
        return Err(at.error(Part::Geometry, "zero-area light".into()));
    }
    if !power.is_finite() {
        return Err(at.error(Part::Geometry, "light power is not finite".into()));
    }
    Ok(())
}
