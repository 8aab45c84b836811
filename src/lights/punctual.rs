//! The point, spot and directional lights of a [`SceneBuilder`] (the rules of the
//! builder's module documentation): their checks and power. A spot's falloff is
//! [`SpotCone`]'s; a directional light's power needs the finished scene's extent, so
//! [`SceneBuilder::finish`] sets it.

use crate::scene::builder::SceneBuilder;
use crate::scene::checks::check_emission;
use crate::scene::locate::{Locate, Part};
use crate::scene::{Light, LightShape, SpotCone, SpotFalloff};
use crate::error::Result;
use glam::Vec3;
use std::f32::consts::PI;

/// A spot light as [`SceneBuilder::add_spot_light`] takes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    /// Where it is.
    pub position: Vec3,
    /// The direction it shines in (any length but zero).
    pub direction: Vec3,
    /// Radiant intensity on the axis, W/sr per channel.
    pub intensity: Vec3,
    /// Inner half-angle in degrees: full intensity inside.
    pub inner: f32,
    /// Outer half-angle in degrees: no light outside.
    pub outer: f32,
    /// The ramp between the two (glTF's form by default).
    pub falloff: SpotFalloff,
}

impl SceneBuilder {
    /// Adds an isotropic point light at `position`, `intensity` in W/sr per channel (>= 0).
    pub fn add_point_light(
        &mut self,
        position: Vec3,
        intensity: Vec3,
        at: &dyn Locate,
    ) -> Result<()> {
        if !position.is_finite() {
            return Err(at.error(Part::Geometry, "must be finite".into()));
        }
        check_emission(intensity, at)?;
        let power = 4.0 * PI * intensity;
        if !power.is_finite() {
            return Err(at.error(Part::Emission, "light power is not finite".into()));
        }
        let shape = LightShape::Point {
            position,
            intensity,
        };
        self.lights.push(Light { shape, power });
        Ok(())
    }

    /// Adds a spot light at `position` shining along `direction` (any length but zero),
    /// `intensity` in W/sr per channel on its axis (>= 0), full inside the half-angle `inner`
    /// and dark outside `outer` (degrees, `0 <= inner <= outer`, `0 < outer <= 90`), with the
    /// falloff of [`SpotCone`] between. Errors: [`Part::Geometry`] (position),
    /// `Parameter("direction")`, [`Part::Emission`], `Parameter("inner_angle")`,
    /// `Parameter("outer_angle")`.
    pub fn add_spot_light(&mut self, spot: SpotLight, at: &dyn Locate) -> Result<()> {
        if !spot.position.is_finite() {
            return Err(at.error(Part::Geometry, "must be finite".into()));
        }
        let direction = check_direction(spot.direction, at)?;
        check_emission(spot.intensity, at)?;
        if !(spot.outer > 0.0 && spot.outer <= 90.0) {
            let message = format!("must be in (0, 90] degrees (got {})", spot.outer);
            return Err(at.error(Part::Parameter("outer_angle"), message));
        }
        if !(spot.inner >= 0.0 && spot.inner <= spot.outer) {
            let message = format!(
                "must be in [0, outer angle {}] degrees (got {})",
                spot.outer, spot.inner
            );
            return Err(at.error(Part::Parameter("inner_angle"), message));
        }
        let cone = SpotCone::with_profile(spot.inner, spot.outer, spot.falloff);
        let power = spot.intensity * cone.solid_angle() as f32;
        if !power.is_finite() {
            return Err(at.error(Part::Emission, "light power is not finite".into()));
        }
        let shape = LightShape::Spot {
            position: spot.position,
            direction,
            intensity: spot.intensity,
            cone,
        };
        self.lights.push(Light { shape, power });
        Ok(())
    }

    /// Adds a directional light travelling along `direction` (any length but zero) with
    /// `irradiance` in W/m^2 per channel (>= 0) on a surface facing it; its power is set by
    /// [`Self::finish`], when the scene's extent is known. Errors:
    /// `Parameter("direction")`, [`Part::Emission`].
    pub fn add_directional_light(
        &mut self,
        direction: Vec3,
        irradiance: Vec3,
        at: &dyn Locate,
    ) -> Result<()> {
        let direction = check_direction(direction, at)?;
        check_emission(irradiance, at)?;
        let shape = LightShape::Directional {
            direction,
            irradiance,
        };
        let power = Vec3::ZERO;
        self.lights.push(Light { shape, power });
        Ok(())
    }
}

/// A light's direction: finite and not zero; returned normalised.
fn check_direction(d: Vec3, at: &dyn Locate) -> Result<Vec3> {
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
