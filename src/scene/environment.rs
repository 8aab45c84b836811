//! Environment lights: radiance arriving from infinitely far away along every ray that
//! leaves the scene. A constant one (Mitsuba's `constant`, TOML `radiance`) or a lat-long
//! image (Mitsuba's `envmap`), looked up as Mitsuba 3 looks it up: `u = atan2(x, -z) / 2 pi`,
//! `v = acos(y) / pi` in the map's frame, texel column `i` centred at `u = (i + 0.5) / W`
//! (periodic), row `j` at `v = j / (H - 1)`, bilinear. A scene has at most one; the builder
//! makes it the last light ([`Scene::environment`]). Its power is the flux through a disc of
//! the bounding sphere's radius R facing each direction: `pi R^2` times the integral of the
//! radiance over the sphere of directions (`4 pi^2 R^2 L` for a constant L).

use super::locate::{Locate, Part};
use super::{Light, LightShape, Scene, SceneBuilder, NO_TEXTURE};
use crate::error::Result;
use crate::texture::{SceneTexture, Texture};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

/// Luminance of linear RGB (Rec. 709 weights, Mitsuba's `luminance`).
pub fn luminance(c: Vec3) -> f32 {
    0.212_671 * c.x + 0.715_160 * c.y + 0.072_169 * c.z
}

/// An environment light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    /// A constant environment's radiance; an image's scale on its texels.
    pub radiance: Vec3,
    /// Index into [`Scene::textures`] of the lat-long image, or [`NO_TEXTURE`] (constant).
    pub texture: u32,
    /// The map's frame to world (the rotation of Mitsuba's `to_world`).
    pub to_world: Mat3,
}

impl Environment {
    /// A constant environment of radiance `radiance`.
    pub fn constant(radiance: Vec3) -> Self {
        Environment {
            radiance,
            texture: NO_TEXTURE,
            to_world: Mat3::IDENTITY,
        }
    }

    /// Radiance arriving from unit direction `dir` (the direction of a ray leaving the scene).
    pub fn eval(&self, textures: &[SceneTexture], dir: Vec3) -> Vec3 {
        match self.texture {
            NO_TEXTURE => self.radiance,
            t => {
                let SceneTexture::Bitmap(image) = &textures[t as usize] else {
                    return Vec3::ZERO;
                };
                self.radiance * latlong_lookup(image, latlong_uv(self.to_world.transpose() * dir))
            }
        }
    }
}

/// Mitsuba's `direction_to_uv` of a unit direction in the map's frame.
pub fn latlong_uv(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) * (0.5 / PI);
    let v = d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI);
    Vec2::new(u, v)
}

/// Mitsuba's `uv_to_direction`: the unit direction in the map's frame at `uv`.
pub fn latlong_dir(uv: Vec2) -> Vec3 {
    let (sin_t, cos_t) = (uv.y * PI).sin_cos();
    let (sin_p, cos_p) = (uv.x * 2.0 * PI).sin_cos();
    Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t)
}

/// The image at `uv` as Mitsuba's `envmap` filters it: `u` wraps with column `i` centred at
/// `(i + 0.5) / W`, `v` clamps with row `j` at `j / (H - 1)`, bilinear.
pub fn latlong_lookup(t: &Texture, uv: Vec2) -> Vec3 {
    let (w, h) = (t.width as i64, t.height as i64);
    let x = (uv.x - uv.x.floor()) * w as f32 - 0.5;
    let y = uv.y.clamp(0.0, 1.0) * (h - 1).max(0) as f32;
    let (fx, fy) = (x.floor(), y.floor());
    let (tx, ty) = (x - fx, y - fy);
    let (x0, y0) = (fx as i64, fy as i64);
    let fetch = |i: i64, j: i64| {
        let i = i.rem_euclid(w) as u32;
        let j = j.clamp(0, h - 1) as u32;
        t.texel(i, j).truncate()
    };
    let row0 = fetch(x0, y0) * (1.0 - tx) + fetch(x0 + 1, y0) * tx;
    let row1 = fetch(x0, y0 + 1) * (1.0 - tx) + fetch(x0 + 1, y0 + 1) * tx;
    row0 * (1.0 - ty) + row1 * ty
}

/// The integral of an image environment's texels over the sphere of directions (before its
/// scale): the midpoint rule on a grid twice the image's resolution.
pub fn image_integral(t: &Texture) -> Vec3 {
    let (nu, nv) = (2 * t.width.max(1), 2 * t.height.max(1));
    let mut sum = glam::DVec3::ZERO;
    for j in 0..nv {
        let v = (j as f32 + 0.5) / nv as f32;
        let sin_t = (v * PI).sin() as f64;
        for i in 0..nu {
            let u = (i as f32 + 0.5) / nu as f32;
            sum += latlong_lookup(t, Vec2::new(u, v)).as_dvec3() * sin_t;
        }
    }
    // dw = 2 pi^2 sin(theta) du dv.
    (sum * (2.0 * std::f64::consts::PI.powi(2) / (nu as f64 * nv as f64))).as_vec3()
}

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
            let image = Texture::load(std::path::Path::new(spec), crate::texture::Encoding::Srgb)?;
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
