//! The environment light in a scene: the scene's accessor and setter (it is always the last
//! light, with its power), the scene builder's entry, and the command line's `--env`.

use crate::error::Result;
use crate::lights::environment::{image_integral, Environment};
use crate::scene::locate::{Locate, Part};
use crate::scene::{Light, LightShape, Scene, SceneBuilder, NO_TEXTURE};
use crate::textures::{SceneTexture, Texture};
use glam::{Mat3, Vec3};
use std::f32::consts::PI;

impl Scene {
    /// The environment light, if any: the last light.
    #[inline]
    pub fn environment(&self) -> Option<&Environment> {
        match self.lights.last().map(|l| &l.shape) {
            Some(LightShape::Environment(e)) => Some(e),
            _ => None,
        }
    }

    /// Sets (or replaces) the environment light, keeping it the last light and giving it its
    /// power (the scene's textures must hold its image).
    pub fn set_environment(&mut self, env: Environment) {
        if self.environment().is_some() {
            self.lights.pop();
        }
        let (_, r) = self.bounding_sphere();
        let integral = match env.texture {
            NO_TEXTURE => Vec3::splat(4.0 * PI),
            t => match &self.textures[t as usize] {
                SceneTexture::Bitmap(image) => image_integral(image),
                SceneTexture::Checkerboard(_) => Vec3::ZERO,
            },
        };
        let power = env.radiance * integral * (PI * r * r);
        self.lights.push(Light {
            shape: LightShape::Environment(env),
            power,
        });
    }
}

impl SceneBuilder {
    /// Adds the environment light: radiance `radiance` (a constant one) or `radiance` times
    /// the lat-long `image` (rotated by `to_world`). A scene has at most one.
    pub fn set_environment(
        &mut self,
        radiance: Vec3,
        image: Option<Texture>,
        to_world: Mat3,
        at: &dyn Locate,
    ) -> Result<()> {
        if !radiance.is_finite() || radiance.min_element() < 0.0 {
            return Err(at.error(Part::Emission, "must be finite and >= 0".into()));
        }
        if !to_world.is_finite() || to_world.determinant().abs() < 1e-12 {
            return Err(at.error(Part::Geometry, "must be an invertible rotation".into()));
        }
        if image.as_ref().is_some_and(|t| t.height < 2 || t.width == 0) {
            return Err(at.error(
                Part::Emission,
                "an environment image needs at least 2 rows".into(),
            ));
        }
        if self.environment.is_some() {
            return Err(at.error(Part::Emission, "the scene has one environment".into()));
        }
        // Only the rotation: a scale or shear of the frame would not change directions.
        let to_world = Mat3::from_cols(
            to_world.x_axis.normalize(),
            to_world.y_axis.normalize(),
            to_world.z_axis.normalize(),
        );
        let texture = match image {
            Some(t) => self.add_texture(SceneTexture::Bitmap(t), at)?,
            None => NO_TEXTURE,
        };
        self.environment = Some(Environment {
            radiance,
            texture,
            to_world,
        });
        Ok(())
    }
}

/// The command line's `--env SPEC [--env-scale S]` on `scene` (read from `file`): `SPEC` is
/// `R,G,B` (a constant radiance) or a lat-long image file, `scale` multiplies either; it
/// supplies or replaces the environment. A malformed value is an
/// [`crate::error::Error::Setting`] on `env`. Then, with or without `SPEC`, a scene with no
/// light at all is [`crate::error::Error::NoLight`] ([`require_light`]).
pub fn apply_env_arg(
    scene: &mut Scene,
    spec: Option<&str>,
    scale: Option<f32>,
    file: &std::path::Path,
) -> Result<()> {
    if let Some(spec) = spec {
        set_env_arg(scene, spec, scale)?;
    }
    require_light(scene, file)
}

fn set_env_arg(scene: &mut Scene, spec: &str, scale: Option<f32>) -> Result<()> {
    use crate::error::Error;
    let bad = |message: String| Error::Setting {
        field: "env",
        message,
    };
    let scale = scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(Error::Setting {
            field: "env-scale",
            message: format!("{scale} must be finite and >= 0"),
        });
    }
    let parts: Vec<&str> = spec.split(',').map(str::trim).collect();
    let numbers: Option<Vec<f32>> = parts.iter().map(|p| p.parse::<f32>().ok()).collect();
    let env = match numbers {
        Some(c) if c.len() == 3 => {
            let radiance = Vec3::new(c[0], c[1], c[2]) * scale;
            if !radiance.is_finite() || radiance.min_element() < 0.0 {
                return Err(bad(format!("{spec}: a radiance must be finite and >= 0")));
            }
            Environment::constant(radiance)
        }
        Some(_) if parts.len() > 1 => {
            return Err(bad(format!(
                "{spec}: expected R,G,B (three numbers) or an image file"
            )))
        }
        _ => {
            let image = Texture::load(std::path::Path::new(spec), crate::textures::Encoding::Srgb)?;
            if image.height < 2 || image.width == 0 {
                return Err(bad(format!(
                    "{spec}: an environment image needs at least 2 rows"
                )));
            }
            scene.textures.push(SceneTexture::Bitmap(image));
            Environment {
                radiance: Vec3::splat(scale),
                texture: scene.textures.len() as u32 - 1,
                to_world: Mat3::IDENTITY,
            }
        }
    };
    scene.set_environment(env);
    Ok(())
}

/// Fails with [`crate::error::Error::NoLight`] when `scene` (read from `file`) has no light
/// and no environment: it would render black.
pub fn require_light(scene: &Scene, file: &std::path::Path) -> Result<()> {
    if scene.lights.is_empty() {
        return Err(crate::error::Error::NoLight {
            file: file.to_path_buf(),
        });
    }
    Ok(())
}
