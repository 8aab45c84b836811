//! Render settings: defaults, the scene file's `[render]` table and the command line all
//! produce one [`RenderSettings`].

use crate::error::{Error, Result};

/// How radiance is computed at the first diffuse or glossy hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Everything from the photon maps (global + caustic).
    Photon,
    /// Direct light by shadow rays + the global map for indirect light + the caustic map.
    Direct,
    /// Debug view: direct light by shadow rays only.
    DirectOnly,
    /// Debug view: the global map's estimate only (all global photons).
    GlobalOnly,
    /// Debug view: the caustic map's estimate only.
    CausticOnly,
}

impl Mode {
    pub const NAMES: [&'static str; 5] = [
        "photon",
        "direct",
        "direct-only",
        "global-only",
        "caustic-only",
    ];
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "photon" => Mode::Photon,
            "direct" => Mode::Direct,
            "direct-only" => Mode::DirectOnly,
            "global-only" => Mode::GlobalOnly,
            "caustic-only" => Mode::CausticOnly,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        match self {
            Mode::Photon => "photon",
            Mode::Direct => "direct",
            Mode::DirectOnly => "direct-only",
            Mode::GlobalOnly => "global-only",
            Mode::CausticOnly => "caustic-only",
        }
    }
}

/// The density-estimation kernel of the radiance estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Constant kernel: sum of photon flux / (pi r^2), r = distance to the K-th photon.
    Disc,
    /// Jensen's cone filter, w = 1 - d / (k r) with k = 1, normalised by (1 - 2/(3k)).
    Cone,
    /// Epanechnikov kernel, w = 1 - d^2 / r^2 (each photon weighted down with its squared
    /// distance), normalised by 2 / (pi r^2).
    Epanechnikov,
}

impl Filter {
    pub const NAMES: [&'static str; 3] = ["disc", "cone", "epanechnikov"];
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "disc" => Filter::Disc,
            "cone" => Filter::Cone,
            "epanechnikov" => Filter::Epanechnikov,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        match self {
            Filter::Disc => "disc",
            Filter::Cone => "cone",
            Filter::Epanechnikov => "epanechnikov",
        }
    }
}

/// Which Fresnel reflectance dielectrics use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FresnelMode {
    /// Exact unpolarised Fresnel equations.
    Exact,
    /// Schlick's approximation.
    Schlick,
}

/// Everything that controls a render besides the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Photon paths emitted for the global map.
    pub photons: u32,
    /// Photons to store in the caustic map (0 disables it; ignored without specular surfaces).
    pub caustic_photons: u32,
    /// K of the K-nearest-neighbour estimate.
    pub k: u32,
    /// Maximum search radius of the global map (scene units).
    pub radius: f32,
    /// Maximum search radius of the caustic map (scene units).
    pub caustic_radius: f32,
    /// Camera samples per pixel (n x n jittered when a perfect square).
    pub spp: u32,
    /// Shadow rays per area light sample in `direct` mode.
    pub shadow_samples: u32,
    pub mode: Mode,
    pub filter: Filter,
    pub fresnel: FresnelMode,
    /// Maximum photon bounces (stored photons per path are at most this many).
    pub max_photon_bounces: u32,
    /// Maximum depth of the camera ray's mirror/glass chain.
    pub max_depth: u32,
    pub seed: u32,
    /// PNG exposure in stops (EXR is always linear and unscaled).
    pub exposure: f32,
    /// Progressive photon mapping over passes `start..end` (None: one classic pass with the
    /// K-nearest estimate). See `crate::progressive`.
    pub pass_range: Option<(u32, u32)>,
    /// Radius reduction of progressive passes (Knaus and Zwicker's alpha, in (0, 1)).
    pub alpha: f32,
    /// Global-map radius of the first progressive pass (None: chosen from the scene).
    pub initial_radius: Option<f32>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 256,
            height: 256,
            photons: 200_000,
            caustic_photons: 100_000,
            k: 100,
            radius: 0.25,
            caustic_radius: 0.1,
            spp: 64,
            shadow_samples: 1,
            mode: Mode::Direct,
            filter: Filter::Disc,
            fresnel: FresnelMode::Exact,
            max_photon_bounces: 16,
            max_depth: 12,
            seed: 1,
            exposure: 0.0,
            pass_range: None,
            alpha: 0.7,
            initial_radius: None,
        }
    }
}

/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 16384;
/// Largest accepted K.
pub const MAX_K: u32 = 1024;

/// Checks settings that the command line or API may have set out of range.
pub fn validate(s: &RenderSettings) -> Result<()> {
    let bad = |field: &'static str, message: String| Err(Error::Setting { field, message });
    if s.width == 0 || s.height == 0 || s.width > MAX_RESOLUTION || s.height > MAX_RESOLUTION {
        return bad(
            "width/height",
            format!("{}x{} is outside 1..={MAX_RESOLUTION}", s.width, s.height),
        );
    }
    if s.k == 0 || s.k > MAX_K {
        return bad("k", format!("{} is outside 1..={MAX_K}", s.k));
    }
    if !(s.radius.is_finite() && s.radius > 0.0) {
        return bad(
            "radius",
            format!("{} must be positive and finite", s.radius),
        );
    }
    if !(s.caustic_radius.is_finite() && s.caustic_radius > 0.0) {
        return bad(
            "caustic-radius",
            format!("{} must be positive and finite", s.caustic_radius),
        );
    }
    if s.spp == 0 || s.spp > 65_536 {
        return bad("spp", format!("{} is outside 1..=65536", s.spp));
    }
    if s.shadow_samples == 0 || s.shadow_samples > 1024 {
        return bad(
            "shadow-samples",
            format!("{} is outside 1..=1024", s.shadow_samples),
        );
    }
    if s.photons == 0 {
        return bad("photons", "must be at least 1".into());
    }
    if !s.exposure.is_finite() {
        return bad("exposure", "must be finite".into());
    }
    Ok(())
}
