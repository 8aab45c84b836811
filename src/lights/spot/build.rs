//! The spot light's call of the scene builder: its checks and power (its on-axis intensity
//! times [`SpotCone::solid_angle`]).

use crate::error::Result;
use crate::lights::spot::{Spot, SpotCone, SpotFalloff};
use crate::lights::{Light, LightShape};
use crate::scene::builder::SceneBuilder;
use crate::scene::checks::{check_direction, check_emission};
use crate::scene::locate::{Locate, Part};
use glam::Vec3;

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
    /// Adds a spot light at `position` shining along `direction` (any length but zero),
    /// `intensity` in W/sr per channel on its axis (>= 0), full inside the half-angle `inner`
    /// and dark outside `outer` (degrees, `0 <= inner <= outer`, `0 < outer <= 90`), with the
    /// falloff of [`SpotCone`] between. Errors: `Part::Geometry` (position),
    /// `Parameter("direction")`, `Part::Emission`, `Parameter("inner_angle")`,
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
        let shape = LightShape::Spot(Spot {
            position: spot.position,
            direction,
            intensity: spot.intensity,
            cone,
        });
        self.lights.push(Light { shape, power });
        Ok(())
    }
}
