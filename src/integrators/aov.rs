//! First-hit feature images (AOVs) for denoisers: albedo and normal, defined as Cycles
//! defines its Denoising Albedo and Denoising Normal passes (Cycles 3.4,
//! `kernel/film/denoising_passes.h`), so that Blender's Denoise node (OpenImageDenoise) reads
//! ours as it reads Cycles':
//! - camera rays go on through delta surfaces (mirrors, smooth glass and conductors, null
//!   boundaries), their throughput multiplied by the delta weight (glass picks reflection or
//!   refraction with the Fresnel probability, weight 1), up to 16 bounces;
//! - at the first shaded surface the albedo is the throughput times the diffuse part's albedo
//!   plus the non-delta lobe's (its directional albedo, one lobe sample per camera sample);
//!   the normal is the shading normal turned towards the ray, in camera space: x right, y up,
//!   z along the view direction (Cycles' `worldtocamera`), so a surface facing the camera
//!   has z < 0;
//! - emission met on the way (an emitter's, or the environment's when the ray leaves the
//!   scene) adds the throughput times its radiance to the albedo, as Cycles' emission and
//!   background passes do; such a pixel's normal is 0.
//!
//! Backend-neutral (the CPU walks the scene's BVH), independent of the render's passes:
//! `samples` stratified camera samples per pixel, each a deterministic function of the seed
//! and the pixel. Both the Blender add-on and `gpu-photon render --aov` use it.

use crate::bsdfs::shading::{bsdf_at, escape, DeltaEvent, SurfaceClass};
use crate::bvh::CpuBvh;
use crate::error::{Error, Result};
use crate::math::geometry::{offset_origin, Facing, Ray};
use crate::math::rng::{Rng, Stream};
use crate::render::film::Image;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::Vec3;
use rayon::prelude::*;

/// The feature images there are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// The first shaded surface's albedo (see the module documentation).
    Albedo,
    /// Its shading normal in camera space.
    Normal,
}

/// The most delta bounces a feature ray follows.
pub const MAX_DELTA_BOUNCES: u32 = 16;

/// The RNG pass index of the feature rays: past every render pass, so their numbers are
/// their own.
const AOV_PASS: u32 = u32::MAX;

impl Aov {
    /// Every feature, in the order of [`Aov::NAMES`].
    pub const ALL: [Aov; 2] = [Aov::Albedo, Aov::Normal];
    /// Their names (the command line's `--aov albedo,normal`, the EXR layers').
    pub const NAMES: [&'static str; 2] = ["albedo", "normal"];

    /// Its name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// A comma-separated list of names (`albedo,normal`), each once; an unknown or
    /// repeated name is an [`Error::Setting`] on `aov`.
    pub fn parse_list(text: &str) -> Result<Vec<Aov>> {
        let mut out = Vec::new();
        for name in text.split(',').map(str::trim) {
            let bad = |m: String| Error::Setting {
                field: "aov",
                message: m,
            };
            let Some(i) = Self::NAMES.iter().position(|n| *n == name) else {
                let names = Self::NAMES.join(", ");
                return Err(bad(format!("unknown AOV `{name}` (expected {names})")));
            };
            if out.contains(&Self::ALL[i]) {
                return Err(bad(format!("`{name}` is listed twice")));
            }
            out.push(Self::ALL[i]);
        }
        Ok(out)
    }
}

/// What one feature ray found.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Features {
    albedo: Vec3,
    normal: Vec3,
}

/// The features seen along the camera ray `ray` (module documentation).
fn trace(scene: &Scene, bvh: &CpuBvh, mut ray: Ray, rng: &mut Rng, s: &RenderSettings) -> Features {
    let mut throughput = Vec3::ONE;
    let mut albedo = Vec3::ZERO;
    for _ in 0..=MAX_DELTA_BOUNCES {
        let Some(hit) = bvh.intersect(scene, &ray, f32::INFINITY) else {
            albedo += throughput * escape(scene, ray.dir);
            return Features {
                albedo,
                normal: Vec3::ZERO,
            };
        };
        let bsdf = bsdf_at(scene, &hit, ray.dir);
        let front = ray.dir.dot(hit.normal) < 0.0;
        albedo += throughput * bsdf.emitted(front);
        let f = Facing::new(hit.normal, hit.shading, front);
        let next = |dir: Vec3| Ray {
            origin: offset_origin(hit.position, hit.normal, dir),
            dir,
        };
        match bsdf.class() {
            SurfaceClass::Black => {
                return Features {
                    albedo,
                    normal: Vec3::ZERO,
                }
            }
            SurfaceClass::Null => ray = next(ray.dir),
            SurfaceClass::Delta => match bsdf.delta(ray.dir, &hit, &f, s.fresnel) {
                DeltaEvent::Reflect { dir, weight } => {
                    throughput *= weight;
                    ray = next(dir);
                }
                DeltaEvent::Split(g) => {
                    let dir = match g.refracted {
                        Some(t) if rng.next() >= g.reflectance => t,
                        _ => g.reflected,
                    };
                    ray = next(dir);
                }
            },
            SurfaceClass::Shaded => {
                let wo = -ray.dir;
                let mut a = bsdf.diffuse_albedo(wo);
                if bsdf.has_lobe() {
                    if let Some(l) = bsdf.sample_lobe(ray.dir, &f, rng) {
                        a += l.weight;
                    }
                }
                return Features {
                    albedo: albedo + throughput * a,
                    normal: f.ns,
                };
            }
        }
        if throughput == Vec3::ZERO {
            break;
        }
    }
    Features {
        albedo,
        normal: Vec3::ZERO,
    }
}

/// The feature images `which` of `scene` at `settings`' size and seed, `samples` (at least 1)
/// stratified camera samples per pixel, in the order asked.
pub fn render(scene: &Scene, settings: &RenderSettings, which: &[Aov], samples: u32) -> Vec<Image> {
    let (w, h) = (settings.width, settings.height);
    let bvh = CpuBvh::build(scene);
    let n = (samples.max(1) as f32).sqrt().ceil() as u32;
    let cam = &scene.camera;
    let (right, up, forward) = (cam.right.normalize(), cam.up.normalize(), cam.forward);
    let rows: Vec<Vec<Features>> = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .map(|x| {
                    let pixel = y * w + x;
                    let mut rng = Rng::new(settings.seed, Stream::Camera, AOV_PASS, pixel);
                    let mut sum = Features::default();
                    for i in 0..n * n {
                        let (u1, u2) = rng.next2();
                        let fx = ((i % n) as f32 + u1) / n as f32;
                        let fy = ((i / n) as f32 + u2) / n as f32;
                        let lens = rng.next2();
                        let (origin, dir) = cam.ray(x as f32 + fx, y as f32 + fy, w, h, lens);
                        let f = trace(scene, &bvh, Ray { origin, dir }, &mut rng, settings);
                        sum.albedo += f.albedo;
                        sum.normal +=
                            Vec3::new(f.normal.dot(right), f.normal.dot(up), f.normal.dot(forward));
                    }
                    let k = 1.0 / (n * n) as f32;
                    Features {
                        albedo: sum.albedo * k,
                        normal: sum.normal * k,
                    }
                })
                .collect()
        })
        .collect();
    which
        .iter()
        .map(|aov| {
            let pixels = rows
                .iter()
                .flatten()
                .map(|f| {
                    let v = match aov {
                        Aov::Albedo => f.albedo,
                        Aov::Normal => f.normal,
                    };
                    v.to_array()
                })
                .collect();
            Image {
                width: w,
                height: h,
                pixels,
            }
        })
        .collect()
}
