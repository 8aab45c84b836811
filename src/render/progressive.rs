//! Progressive photon mapping after Knaus and Zwicker (2011), "Progressive photon mapping: a
//! probabilistic approach": independent passes, each with fresh photons (the RNG's pass
//! index), its own photon maps and a fixed-radius estimate whose radius shrinks as
//! `r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1)` (i counted from 1). Pass i's image depends on
//! nothing but i, the scene and the settings, so ranges of passes rendered anywhere can be
//! merged into the image the whole range gives (`gpu-photon merge`).

use crate::render::film::Image;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// `r_i^2 / r_0^2` for 0-based pass `pass`: the product of `(j + alpha) / (j + 1)` for
/// j = 1..=pass (in f64, so every machine computes the same value).
pub fn radius2_factor(pass: u32, alpha: f32) -> f64 {
    let a = alpha as f64;
    (1..=pass as u64).fold(1.0f64, |f, j| f * (j as f64 + a) / (j as f64 + 1.0))
}

/// Expected number of photons within `radius`... inverted: the radius holding `k` photons
/// when `photons` are spread over `area`.
pub fn radius_for(k: u32, photons: f64, area: f64) -> f64 {
    (k as f64 * area / (std::f64::consts::PI * photons.max(1.0))).sqrt()
}

/// The first pass's radii (global, caustic): `initial_radius` when given, else the radius
/// that would hold K photons if a pass's photons covered the storing surfaces uniformly
/// (global) or 5% of them (caustic), capped by the configured maximum radii.
pub fn initial_radii(scene: &Scene, s: &RenderSettings) -> (f32, f32) {
    let area = scene.storing_area().max(1e-12) as f64;
    // A global path stores about 1.8 photons in closed scenes of albedo ~0.5.
    let global = s.initial_radius.unwrap_or_else(|| {
        radius_for(s.k, s.photons as f64 * 1.8, area).min(s.radius as f64) as f32
    });
    let caustic = radius_for(
        s.k,
        s.caustic_photons as f64,
        area * crate::integrators::plan::MapKind::Caustic.area_fraction(),
    )
    .min(s.caustic_radius as f64) as f32;
    let caustic = if s.initial_radius.is_some() {
        caustic.min(global)
    } else {
        caustic
    };
    (global, caustic)
}

/// Volume photons a beam query of the first pass is sized to read, per K of a surface
/// estimate: a camera sample's beam runs once per sample, so the pixel's samples average
/// its noise, and its cost grows with the photons it reads.
pub const BEAM_PHOTONS_PER_K: f64 = 0.25;
/// Volume photons a global path is assumed to store, for the first volume radius.
pub const VOLUME_PHOTONS_PER_PATH: f64 = 2.0;

/// The first pass's volume radius: the radius of a beam that would hold
/// `BEAM_PHOTONS_PER_K * K` volume photons along a segment as long as the media's box
/// ([`media_box`]) is wide (the cube root of its volume V), were a pass's
/// `VOLUME_PHOTONS_PER_PATH * N` volume photons (N global paths) spread evenly through the
/// box: `pi r^2 V^(1/3) (2 N / V) = K / 4`. At most `volume_radius`.
pub fn initial_volume_radius(scene: &Scene, s: &RenderSettings) -> f32 {
    let volume = media_box(scene)
        .map_or(0.0, |(lo, hi)| (hi - lo).as_dvec3().element_product())
        .max(1e-12);
    let photons = VOLUME_PHOTONS_PER_PATH * s.photons.max(1) as f64;
    let per_length = photons / volume.powf(2.0 / 3.0);
    let r = (BEAM_PHOTONS_PER_K * s.k as f64 / (std::f64::consts::PI * per_length)).sqrt();
    (r as f32).min(s.volume_radius)
}

/// The box volume photons can fill: the scene's when the camera sits in a medium (fog
/// everywhere), else that of the shapes bounding a medium (a medium-filled sphere on a large
/// backdrop: the scene's box would give a kernel wider than the medium's mean free path,
/// whose bias near the medium's boundary made the suite's dense media 3-12% dark in the
/// second bounce).
fn media_box(scene: &Scene) -> Option<(glam::Vec3, glam::Vec3)> {
    if scene.camera_medium != crate::media::NO_MEDIUM {
        return scene.bounds();
    }
    let bounding = |m: u32| !scene.materials[m as usize].media.is_vacuum();
    let triangles: Vec<_> = scene
        .triangles
        .iter()
        .filter(|t| bounding(t.material))
        .copied()
        .collect();
    let spheres: Vec<_> = scene
        .spheres
        .iter()
        .filter(|s| bounding(s.material))
        .copied()
        .collect();
    crate::scene::bounds_of(&triangles, &spheres).or_else(|| scene.bounds())
}

/// The volume radius of pass `pass` ([`pass_settings`]): in three dimensions the kernel's
/// volume, r^3, takes the place of the area, so `r_{i+1}^3 = r_i^3 (i + alpha) / (i + 1)`.
/// Knaus and Zwicker's argument carries over unchanged: a pass's estimate is unbiased up to
/// the kernel's width, its variance grows as the inverse of the kernel's volume, and
/// shrinking that volume by `(i + alpha) / (i + 1)` per pass makes the variance of the mean
/// over passes vanish while the bias does too (docs/media.md).
pub fn volume_radius(scene: &Scene, s: &RenderSettings, pass: u32) -> f32 {
    initial_volume_radius(scene, s) * radius2_factor(pass, s.alpha).cbrt() as f32
}

/// Settings of progressive pass `pass`: a fixed-radius estimate (`k = 0`) with the pass's
/// shrunken radii.
pub fn pass_settings(scene: &Scene, s: &RenderSettings, pass: u32) -> RenderSettings {
    let (g, c) = initial_radii(scene, s);
    let f = radius2_factor(pass, s.alpha).sqrt() as f32;
    RenderSettings {
        k: 0,
        radius: g * f,
        caustic_radius: c * f,
        volume_radius: volume_radius(scene, s, pass),
        pass_range: None,
        ..s.clone()
    }
}

/// What the caller says after each pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Render the next pass.
    Continue,
    /// Stop after this pass (its image is in the mean).
    Stop,
}

/// A running mean of pass images.
#[derive(Clone, Debug)]
pub struct Accumulator {
    /// Per-pixel sum of the pass images (f64, so the order of adding barely matters).
    pub sum: Vec<[f64; 3]>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Passes `first..first + count` are in the sum.
    pub first: u32,
    /// Passes in the sum.
    pub count: u32,
    /// Per-pixel alternating sum `img_0 - img_1 + img_2 - ...` of the passes added, for
    /// [`Accumulator::noise`] (f32: it only measures noise).
    alternating: Vec<[f32; 3]>,
}

impl Accumulator {
    /// An empty sum of `width` x `height` images whose first pass will be `first`.
    pub fn new(width: u32, height: u32, first: u32) -> Self {
        Accumulator {
            sum: vec![[0.0; 3]; (width * height) as usize],
            width,
            height,
            first,
            count: 0,
            alternating: vec![[0.0; 3]; (width * height) as usize],
        }
    }
    /// Adds the next pass's image.
    pub fn add(&mut self, img: &Image) {
        let sign = if self.count.is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        for ((s, a), p) in self
            .sum
            .iter_mut()
            .zip(&mut self.alternating)
            .zip(&img.pixels)
        {
            for c in 0..3 {
                s[c] += p[c] as f64;
                a[c] += sign * p[c];
            }
        }
        self.count += 1;
    }

    /// Estimated relative noise of [`Accumulator::mean`]: the RMS over pixels and channels
    /// of its standard error, over the mean pixel value. The passes are independent with
    /// the same expectation, so after an even number n of them the alternating sum D has
    /// mean 0 and variance n sigma^2 per pixel, and the mean's standard error sigma/sqrt(n)
    /// is estimated by |D| / n. Bias (the photon maps' blur) is not noise and is not
    /// counted. `None` before two passes, after an odd number, or on a black image.
    pub fn noise(&self) -> Option<f64> {
        if self.count < 2 || !self.count.is_multiple_of(2) {
            return None;
        }
        let n = self.count as f64;
        let (mut d2, mut total) = (0.0f64, 0.0f64);
        for (a, s) in self.alternating.iter().zip(&self.sum) {
            for c in 0..3 {
                d2 += (a[c] as f64).powi(2);
                total += s[c];
            }
        }
        let values = 3.0 * self.sum.len() as f64;
        let mean = total / n / values;
        (mean > 0.0).then(|| (d2 / values).sqrt() / n / mean)
    }
    /// The mean of the passes so far.
    pub fn mean(&self) -> Image {
        let n = self.count.max(1) as f64;
        Image {
            width: self.width,
            height: self.height,
            pixels: self.sum.iter().map(|s| s.map(|v| (v / n) as f32)).collect(),
        }
    }
}
