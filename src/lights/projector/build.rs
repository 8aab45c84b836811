//! The projector's call of the scene builder: its checks, frame and power (`pi E A`; the
//! image's mean is multiplied in when the scene is finished, `crate::lights::emission`).

use crate::error::Result;
use crate::lights::projector::Projector;
use crate::lights::{Light, LightShape};
use crate::scene::builder::SceneBuilder;
use crate::scene::checks::check_emission;
use crate::scene::locate::{Locate, Part};
use glam::{Mat4, Vec3};

/// A projector as [`SceneBuilder::add_projector_light`] takes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectorLight {
    /// Its frame: local +z is the axis it shines along, local x and y the image's axes (u
    /// grows against x, v against y); rotation and translation only.
    pub to_world: Mat4,
    /// Its horizontal field of view, degrees in (0, 180).
    pub fov_x: f32,
    /// The image's width over its height (one without an image).
    pub aspect: f32,
    /// Irradiance on the image plane at unit distance, W/m^2 per channel (times the
    /// image's texel).
    pub irradiance: Vec3,
    /// The image it projects, from [`SceneBuilder::add_texture`].
    pub texture: Option<u32>,
}

impl SceneBuilder {
    /// Adds a projector (`crate::lights::projector`). Errors: `Part::Geometry` (a frame
    /// that is not a finite rotation and translation), `Parameter("fov")`,
    /// `Parameter("aspect")`, `Part::Emission` (the irradiance or the texture).
    pub fn add_projector_light(&mut self, p: ProjectorLight, at: &dyn Locate) -> Result<()> {
        let m = p.to_world;
        let (x, y, z) = (
            m.transform_vector3(Vec3::X),
            m.transform_vector3(Vec3::Y),
            m.transform_vector3(Vec3::Z),
        );
        let orthonormal = [x, y, z].iter().all(|v| (v.length() - 1.0).abs() < 1e-4)
            && x.dot(y).abs() < 1e-4
            && x.dot(z).abs() < 1e-4
            && y.dot(z).abs() < 1e-4;
        let position = m.transform_point3(Vec3::ZERO);
        if !(orthonormal && position.is_finite()) {
            let message = "must be a rotation and translation (no scale or shear)";
            return Err(at.error(Part::Geometry, message.into()));
        }
        if !(p.fov_x > 0.0 && p.fov_x < 180.0) {
            let message = format!("must be in (0, 180) degrees (got {})", p.fov_x);
            return Err(at.error(Part::Parameter("fov"), message));
        }
        if !(p.aspect > 0.0 && p.aspect.is_finite()) {
            let message = format!("must be positive (got {})", p.aspect);
            return Err(at.error(Part::Parameter("aspect"), message));
        }
        check_emission(p.irradiance, at)?;
        if p.texture.is_some_and(|t| t as usize >= self.textures.len()) {
            return Err(at.error(Part::Emission, "no such texture".into()));
        }
        let tan_x = (p.fov_x.to_radians() * 0.5).tan();
        let projector = Projector {
            position,
            x_half: x.normalize() * tan_x,
            y_half: y.normalize() * (tan_x / p.aspect),
            axis: z.normalize(),
            irradiance: p.irradiance,
            texture: p.texture,
        };
        let power = p.irradiance * (std::f32::consts::PI * projector.plane_area());
        if !power.is_finite() {
            return Err(at.error(Part::Emission, "light power is not finite".into()));
        }
        let shape = LightShape::Projector(projector);
        self.lights.push(Light { shape, power });
        Ok(())
    }
}
