//! The spot light's calls of the scene builder: their checks and power (its on-axis intensity
//! times [`SpotCone::solid_angle`]; a projected texture's mean under the falloff is
//! multiplied in when the scene is finished, `crate::lights::emission`).

use crate::error::Result;
use crate::lights::spot::{Spot, SpotCone, SpotFalloff, SpotTexture};
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
        let light = self.spot(spot, at)?;
        self.lights.push(light);
        Ok(())
    }

    /// Adds a spot light as [`add_spot_light`](Self::add_spot_light) that projects texture
    /// `texture` (from [`add_texture`](Self::add_texture)) over its cone: `x_axis` and
    /// `y_axis` are its frame's local x and y (where u and v grow), orthonormalised about
    /// the direction (`crate::lights::spot` has the mapping). The outer angle must be under
    /// 90 degrees. Errors: those of `add_spot_light`, `Part::Emission` (the texture), and
    /// `Parameter("direction")` (axes parallel to the direction).
    pub fn add_projecting_spot_light(
        &mut self,
        spot: SpotLight,
        texture: u32,
        (x_axis, y_axis): (Vec3, Vec3),
        at: &dyn Locate,
    ) -> Result<()> {
        let mut light = self.spot(spot, at)?;
        if texture as usize >= self.textures.len() {
            return Err(at.error(Part::Emission, format!("no texture {texture}")));
        }
        if spot.outer >= 90.0 {
            let message = format!(
                "must be under 90 degrees with a texture (got {})",
                spot.outer
            );
            return Err(at.error(Part::Parameter("outer_angle"), message));
        }
        let LightShape::Spot(s) = &mut light.shape else {
            unreachable!("Self::spot makes a spot")
        };
        let x = x_axis - s.direction * s.direction.dot(x_axis);
        let y = y_axis - s.direction * s.direction.dot(y_axis);
        let Some(x) = x
            .try_normalize()
            .filter(|_| y.length() > 1e-6 * y_axis.length())
        else {
            let message = "the frame's x and y axes must not be parallel to the direction";
            return Err(at.error(Part::Parameter("direction"), message.into()));
        };
        s.projection = Some(SpotTexture {
            texture,
            x_axis: x,
            mirrored: s.direction.cross(x).dot(y) < 0.0,
        });
        self.lights.push(light);
        Ok(())
    }

    /// The spot light of `spot`, checked (`add_spot_light`'s errors).
    fn spot(&self, spot: SpotLight, at: &dyn Locate) -> Result<Light> {
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
            projection: None,
        });
        Ok(Light { shape, power })
    }
}
