//! The point light's call of the scene builder: its checks and power (`4 pi I`).

use crate::error::Result;
use crate::lights::point::Point;
use crate::lights::{Light, LightShape};
use crate::scene::builder::SceneBuilder;
use crate::scene::checks::check_emission;
use crate::scene::locate::{Locate, Part};
use glam::Vec3;
use std::f32::consts::PI;

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
        let shape = LightShape::Point(Point {
            position,
            intensity,
        });
        self.lights.push(Light { shape, power });
        Ok(())
    }
}
