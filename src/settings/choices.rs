//! The named choices of a render (`mode`, `filter`, `sampler`, `fresnel`): what the scene
//! file and the command line accept by name, and what each means. [`crate::settings`]
//! re-exports them.

use crate::error::{Error, Result};

/// How radiance is computed at the first diffuse or glossy hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Everything from the photon maps (global + caustic).
    Photon,
    /// Direct light by shadow rays + the global map for indirect light + the caustic map.
    Direct,
    /// Final gathering (Jensen; Christensen's radiance cache): direct light by shadow rays,
    /// caustics from the caustic map, indirect light from gather rays that read a radiance
    /// cache built from the global map (see `crate::integrators::plan::CACHE_STRIDE`).
    Gather,
    /// Debug view: direct light by shadow rays only.
    DirectOnly,
    /// Debug view: the global map's estimate only (all global photons).
    GlobalOnly,
    /// Debug view: the caustic map's estimate only.
    CausticOnly,
}

impl Mode {
    /// The names [`Mode::parse`] accepts, as the scene file and the command line write them.
    pub const NAMES: [&'static str; 6] = [
        "photon",
        "direct",
        "gather",
        "direct-only",
        "global-only",
        "caustic-only",
    ];
    /// The mode named `s` (one of [`Mode::NAMES`]).
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "photon" => Mode::Photon,
            "direct" => Mode::Direct,
            "gather" => Mode::Gather,
            "direct-only" => Mode::DirectOnly,
            "global-only" => Mode::GlobalOnly,
            "caustic-only" => Mode::CausticOnly,
            _ => return None,
        })
    }
    /// The modes of a comma-separated `list` (`direct,gather`); an unknown name is an
    /// [`Error::Setting`] on `modes` naming it and the modes there are.
    pub fn parse_list(list: &str) -> Result<Vec<Self>> {
        list.split(',')
            .map(|m| {
                Mode::parse(m.trim()).ok_or_else(|| Error::Setting {
                    field: "modes",
                    message: format!(
                        "`{}` in `{list}` is not one of {}",
                        m.trim(),
                        Mode::NAMES.join(", ")
                    ),
                })
            })
            .collect()
    }
    /// The mode's name, as [`Mode::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Photon => "photon",
            Mode::Direct => "direct",
            Mode::Gather => "gather",
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
    /// The names [`Filter::parse`] accepts.
    pub const NAMES: [&'static str; 3] = ["disc", "cone", "epanechnikov"];
    /// The filter named `s` (one of [`Filter::NAMES`]).
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "disc" => Filter::Disc,
            "cone" => Filter::Cone,
            "epanechnikov" => Filter::Epanechnikov,
            _ => return None,
        })
    }
    /// The filter's name, as [`Filter::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Disc => "disc",
            Filter::Cone => "cone",
            Filter::Epanechnikov => "epanechnikov",
        }
    }
}

/// Where a camera sample's first numbers come from (issue 10: a technique that can be
/// switched off, so `bench` can show what it buys).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampler {
    /// Owen-scrambled Sobol points (`crate::math::sobol`) for the pixel jitter, the first shaded
    /// hit's first area-light sample and its gather direction.
    Sobol,
    /// Every number from the hash RNG (independent uniform samples).
    Independent,
}

impl Sampler {
    /// The names [`Sampler::parse`] accepts.
    pub const NAMES: [&'static str; 2] = ["sobol", "independent"];
    /// The sampler named `s` (one of [`Sampler::NAMES`]).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "sobol" => Some(Sampler::Sobol),
            "independent" => Some(Sampler::Independent),
            _ => None,
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
