//! The directional light's call of the scene builder: its checks; its power needs the
//! finished scene's extent, so `SceneBuilder::finish` sets it.

use crate::error::Result;
use crate::lights::directional::Directional;
use crate::lights::{Light, LightShape};
use crate::scene::builder::SceneBuilder;
use crate::scene::checks::{check_direction, check_emission};
use crate::scene::locate::Locate;
use glam::Vec3;

impl SceneBuilder {
    /// Adds a directional light travelling along `direction` (any length but zero) with
    /// `irradiance` in W/m^2 per channel (>= 0) on a surface facing it; its power is set by
    /// [`Self::finish`], when the scene's extent is known. Errors:
    /// `Parameter("direction")`, `Part::Emission`.
    pub fn add_directional_light(
        &mut self,
        direction: Vec3,
        irradiance: Vec3,
        at: &dyn Locate,
    ) -> Result<()> {
        let direction = check_direction(direction, at)?;
        check_emission(irradiance, at)?;
        let shape = LightShape::Directional(Directional {
            direction,
            irradiance,
        });
        let power = Vec3::ZERO;
        self.lights.push(Light { shape, power });
        Ok(())
    }
}
