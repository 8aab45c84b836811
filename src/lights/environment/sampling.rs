//! Sampling the environment light (`crate::lights::environment::Environment`). Twin:
//! `src/lights/environment.wgsl`.
//!
//! A constant environment is sampled by a cosine-weighted direction about the shading normal
//! (shadow rays; exact for a Lambertian surface) and a uniform direction (photons). An image
//! is sampled as Mitsuba 3's `envmap` is: a density over the map's uv square that is the
//! bilinear interpolation of the luminance times `sin(theta)` on a grid of `(W + 1) x H`
//! vertices (vertex `(x, y)` is texel `(x mod W, y)`, at `u = x / W` before the half-texel
//! shift, `v = y / (H - 1)`), so the solid-angle density is `pdf_uv / (2 pi^2 sin(theta))`.
//! It is drawn exactly: a cell by its integral, then `v` and `u` within the cell by
//! inverting their linear densities.

use crate::lights::environment::Environment;
use crate::lights::environment::{latlong_dir, latlong_uv, luminance};
use crate::math::sampling::{cosine_hemisphere, uniform_sphere};
use crate::textures::NO_TEXTURE;
use crate::textures::{SceneTexture, Texture};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Words before the CDF in [`EnvDistribution::gpu_words`]: width, height, integral, a pad,
/// then the map's frame to world and back (column-major, 9 each), then two pads.
pub const ENV_HEADER_WORDS: u32 = 24;

/// The 2D sampling distribution of an image environment.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvDistribution {
    /// The image's width W (the grid has W + 1 columns).
    pub width: u32,
    /// The image's height H (rows of the grid; at least 2).
    pub height: u32,
    /// Cumulative cell weights, `W x (H - 1)` cells row by row, ending at 1.
    pub cdf: Vec<f32>,
    /// Luminance times `sin(theta)` at the `(W + 1) x H` vertices, row by row.
    pub grid: Vec<f32>,
    /// The integral of the bilinear interpolant of `grid` over the unit square (0: black).
    pub integral: f32,
}

/// A `t` in [0, 1) with density proportional to `(1 - t) a + t b` (a, b >= 0).
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if a + b <= 0.0 {
        return u;
    }
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    let x = u * (a + b) / (a + (a * a + u * (b * b - a * a)).max(0.0).sqrt());
    x.min(1.0 - f32::EPSILON)
}

impl EnvDistribution {
    /// The distribution of `image` (at least 2 rows).
    pub fn new(image: &Texture) -> Self {
        let (w, h) = (image.width, image.height.max(2));
        let gw = w as usize + 1;
        let mut grid = vec![0.0f32; gw * h as usize];
        for y in 0..h as usize {
            let sin_t = (y as f32 * PI / (h - 1) as f32).sin().max(0.0);
            for x in 0..gw {
                let c = image.texel(x as u32 % w, (y as u32).min(image.height - 1));
                grid[y * gw + x] = luminance(c.truncate()).max(0.0) * sin_t;
            }
        }
        let mut cdf = Vec::with_capacity(w as usize * (h as usize - 1));
        let mut acc = 0.0f64;
        for y in 0..h as usize - 1 {
            for x in 0..w as usize {
                let k = y * gw + x;
                acc += (grid[k] + grid[k + 1] + grid[k + gw] + grid[k + gw + 1]) as f64 * 0.25;
                cdf.push(acc as f32);
            }
        }
        for c in &mut cdf {
            *c = if acc > 0.0 {
                (*c as f64 / acc) as f32
            } else {
                1.0
            };
        }
        let integral = (acc / (w as f64 * (h - 1) as f64)) as f32;
        EnvDistribution {
            width: w,
            height: h,
            cdf,
            grid,
            integral,
        }
    }

    fn corners(&self, cx: usize, cy: usize) -> [f32; 4] {
        let gw = self.width as usize + 1;
        let k = cy * gw + cx;
        [
            self.grid[k],
            self.grid[k + 1],
            self.grid[k + gw],
            self.grid[k + gw + 1],
        ]
    }

    /// A map uv (with Mitsuba's half-texel shift in u) and its density over the uv square,
    /// from three uniforms; `None` for a black map.
    pub fn sample(&self, u: [f32; 3]) -> Option<(Vec2, f32)> {
        if self.integral <= 0.0 {
            return None;
        }
        let w = self.width as usize;
        let i = self
            .cdf
            .partition_point(|&c| c <= u[0])
            .min(self.cdf.len() - 1);
        let (cx, cy) = (i % w, i / w);
        let [a, b, c, d] = self.corners(cx, cy);
        let ty = sample_linear(u[1], a + b, c + d);
        let (p0, p1) = (a + (c - a) * ty, b + (d - b) * ty);
        let tx = sample_linear(u[2], p0, p1);
        let pdf = (p0 + (p1 - p0) * tx) / self.integral;
        let uv = Vec2::new(
            (cx as f32 + tx + 0.5) / w as f32,
            (cy as f32 + ty) / (self.height - 1) as f32,
        );
        Some((uv, pdf))
    }

    /// The density over the uv square of map uv `uv` (as [`sample`](Self::sample) returns).
    pub fn pdf_uv(&self, uv: Vec2) -> f32 {
        if self.integral <= 0.0 {
            return 0.0;
        }
        let w = self.width as f32;
        let g = uv.x - 0.5 / w;
        let gx = (g - g.floor()) * w;
        let gy = uv.y.clamp(0.0, 1.0) * (self.height - 1) as f32;
        let cx = (gx.floor() as usize).min(self.width as usize - 1);
        let cy = (gy.floor() as usize).min(self.height as usize - 2);
        let (tx, ty) = (gx - cx as f32, gy - cy as f32);
        let [a, b, c, d] = self.corners(cx, cy);
        let top = a + (b - a) * tx;
        let bottom = c + (d - c) * tx;
        (top + (bottom - top) * ty) / self.integral
    }

    /// The distribution as the GPU reads it: [`ENV_HEADER_WORDS`] of header (with `env`'s
    /// frame), the CDF, then the grid.
    pub fn gpu_words(&self, env: &Environment) -> Vec<f32> {
        let mut out = vec![self.width as f32, self.height as f32, self.integral, 0.0];
        out.extend_from_slice(&env.to_world.to_cols_array());
        out.extend_from_slice(&env.to_world.transpose().to_cols_array());
        out.resize(ENV_HEADER_WORDS as usize, 0.0);
        out.extend_from_slice(&self.cdf);
        out.extend_from_slice(&self.grid);
        out
    }
}

/// The distribution of `env`'s image, if it has one.
pub fn distribution(env: &Environment, textures: &[SceneTexture]) -> Option<EnvDistribution> {
    match (env.texture, env.texture != NO_TEXTURE) {
        (t, true) => match &textures[t as usize] {
            SceneTexture::Bitmap(image) => Some(EnvDistribution::new(image)),
            SceneTexture::Checkerboard(_) => None,
        },
        _ => None,
    }
}

/// The solid-angle density of world direction `dir` under an image distribution.
fn image_pdf(env: &Environment, dist: &EnvDistribution, dir: Vec3) -> f32 {
    let d = env.to_world.transpose() * dir;
    let sin_t = (d.x * d.x + d.z * d.z)
        .max(f32::EPSILON * f32::EPSILON)
        .sqrt();
    dist.pdf_uv(latlong_uv(d)) / (2.0 * PI * PI * sin_t)
}

/// A world direction from an image distribution and its solid-angle density (0: none).
fn image_sample(env: &Environment, dist: &EnvDistribution, u: [f32; 3]) -> (Vec3, f32) {
    let Some((uv, pdf_uv)) = dist.sample(u) else {
        return (Vec3::Z, 0.0);
    };
    let d = latlong_dir(uv);
    let sin_t = (uv.y * PI).sin().max(f32::EPSILON);
    let dir = (env.to_world * d).normalize();
    (dir, pdf_uv / (2.0 * PI * PI * sin_t))
}

/// A shadow-ray direction towards the environment from a point of shading normal `ns`, and
/// its solid-angle density: cosine-weighted about `ns` for a constant one, else the map's
/// distribution.
pub fn sample_direction(
    env: &Environment,
    dist: Option<&EnvDistribution>,
    ns: Vec3,
    u: [f32; 3],
) -> (Vec3, f32) {
    match dist {
        Some(dist) => image_sample(env, dist, u),
        None => {
            let dir = cosine_hemisphere(ns, u[1], u[2]);
            (dir, dir.dot(ns).max(0.0) / PI)
        }
    }
}

/// The density with which [`sample_direction`] picks `dir` at a point of normal `ns`.
pub fn direction_pdf(
    env: &Environment,
    dist: Option<&EnvDistribution>,
    ns: Vec3,
    dir: Vec3,
) -> f32 {
    match dist {
        Some(dist) => image_pdf(env, dist, dir),
        None => dir.dot(ns).max(0.0) / PI,
    }
}

/// The direction a photon's light comes from (the photon travels along its negative) and
/// its density: uniform for a constant environment (`u[1], u[2]`), else the map's.
pub fn emit_direction(
    env: &Environment,
    dist: Option<&EnvDistribution>,
    u: [f32; 3],
) -> (Vec3, f32) {
    match dist {
        Some(dist) => image_sample(env, dist, u),
        None => (uniform_sphere(u[1], u[2]), 0.25 / PI),
    }
}
