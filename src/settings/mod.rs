//! Render settings: defaults, the scene file's `[camera]` and `[render]` tables and the
//! command line all produce one [`RenderSettings`]. [`SETTINGS`] is the one table of valid
//! ranges that the scene reader and [`validate`] (command line, library API) both follow.

pub mod choices;

use crate::error::{Error, Result};
use std::fmt;

pub use crate::settings::choices::{Filter, FresnelMode, Mode, Sampler};

/// Everything that controls a render besides the scene. The ranges of its numeric fields are
/// in [`SETTINGS`].
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
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
    /// Largest radius of the volume photons in the beam radiance estimate (scene units):
    /// the radius of a classic pass, the cap of the first progressive pass's.
    pub volume_radius: f32,
    /// Camera samples per pixel (n x n jittered when a perfect square).
    pub spp: u32,
    /// Shadow rays per area light sample where direct light is estimated, and next-event
    /// estimates of single scattering per light along a camera segment in a medium.
    pub shadow_samples: u32,
    /// Adaptive sampling: a pixel may take up to this many times `spp` camera samples in each
    /// pass (rounded down to a power of two), by the noise of two pilot images
    /// (`crate::render::adaptive`); 1: every pixel takes `spp`; 0 (the default): 16 where a
    /// pass has at least 16 samples per pixel and the image at least 64 x 64 pixels, else 1
    /// (`adaptive::resolve`). CPU backend only (the GPU takes `spp` everywhere).
    pub adaptive: u32,
    /// The caustic-map estimate runs on one camera sample in this many (see
    /// [`crate::integrators::plan::caustic_weight`]); 1: on every sample.
    pub caustic_every: u32,
    /// How radiance is computed at the first diffuse or glossy hit.
    pub mode: Mode,
    /// The density-estimation kernel.
    pub filter: Filter,
    /// Which Fresnel reflectance dielectrics use.
    pub fresnel: FresnelMode,
    /// Where camera samples' first numbers come from.
    pub sampler: Sampler,
    /// Maximum photon bounces (stored photons per path are at most this many).
    pub max_photon_bounces: u32,
    /// Bounces a camera path may make (mirror, glass, glossy lobes): a hit after this many
    /// only emits; one before takes direct light and photon estimates too.
    pub max_depth: u32,
    /// Random seed.
    pub seed: u32,
    /// PNG exposure in stops (EXR is always linear and unscaled).
    pub exposure: f32,
    /// Progressive passes `gpu-photon render` runs when its command line names no pass
    /// count, range or time (`--passes` sets it too); 0: one classic pass with K-nearest
    /// estimates. The library's `render` ignores it (it follows `pass_range`).
    pub passes: u32,
    /// Progressive photon mapping over passes `start..end` (None: one classic pass with the
    /// K-nearest estimate). See `crate::render::progressive`.
    pub pass_range: Option<(u32, u32)>,
    /// Radius reduction of progressive passes (Knaus and Zwicker's alpha, in (0, 1)).
    pub alpha: f32,
    /// Global-map radius of the first progressive pass (None: chosen from the scene).
    pub initial_radius: Option<f32>,
    /// GPU only (`bench`): time a pass's phases apart. On a device with timestamp queries
    /// they are device times, and each kernel is timed too; without, each phase is submitted
    /// and waited for on its own and its wall time reported, instead of one submission per
    /// pass. Changes no pixel.
    pub timed_phases: bool,
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
            volume_radius: 0.25,
            spp: 64,
            shadow_samples: 1,
            adaptive: 0,
            caustic_every: 4,
            mode: Mode::Gather,
            filter: Filter::Disc,
            fresnel: FresnelMode::Exact,
            sampler: Sampler::Sobol,
            max_photon_bounces: 16,
            max_depth: 12,
            seed: 1,
            exposure: 0.0,
            passes: 4,
            pass_range: None,
            alpha: 0.7,
            initial_radius: None,
            timed_phases: false,
        }
    }
}

impl RenderSettings {
    /// What `gpu-photon render` renders when its command line names no pass count, range or
    /// time: these settings with `pass_range` `0..passes` (progressive), or unchanged (one
    /// classic pass) when `passes` is 0.
    pub fn as_default_render(&self) -> RenderSettings {
        RenderSettings {
            pass_range: (self.passes > 0).then_some((0, self.passes)),
            ..self.clone()
        }
    }
}

/// Fewest samples per pixel a pass gets when a total sample count is split over passes
/// ([`split_samples`]).
pub const MIN_PASS_SPP: u32 = 16;

/// A total of `total` samples per pixel (Mitsuba's `sample_count`) as `(passes, spp)` with
/// `passes * spp == total` exactly: the most passes `p <= max_passes` that divide `total`
/// with `total / p >= MIN_PASS_SPP`, else one pass of `total` (so 256 -> 4 x 64, 100 -> 4 x
/// 25, 48 -> 3 x 16, 40 -> 2 x 20, 8 -> 1 x 8, 257 -> 1 x 257). `max_passes` 0 (one classic
/// pass) gives `(0, total)`.
pub fn split_samples(total: u32, max_passes: u32) -> (u32, u32) {
    if max_passes == 0 {
        return (0, total);
    }
    let p = (2..=max_passes.min(total / MIN_PASS_SPP))
        .rev()
        .find(|&p| total.is_multiple_of(p))
        .unwrap_or(1);
    (p, total / p)
}

/// Largest accepted `adaptive` multiple of `spp`.
pub const MAX_ADAPTIVE: u32 = 64;

/// Largest accepted progressive pass count (pass indices leave the RNG's top 8 bits free).
pub const MAX_PASSES: u32 = u32::MAX >> 8;
/// Largest accepted photon count, global or caustic (2^28): a photon path may store up to
/// `max_photon_bounces` photons, so the maps' memory is bounded before they are allocated.
pub const MAX_PHOTONS: u32 = 1 << 28;
/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 16384;
/// Largest accepted K.
pub const MAX_K: u32 = 1024;
/// Largest accepted number of camera samples per pixel.
pub const MAX_SPP: u32 = 65_536;
/// Largest accepted number of shadow rays per area-light sample.
pub const MAX_SHADOW_SAMPLES: u32 = 1024;
/// Largest accepted photon bounce count and camera-ray specular depth.
pub const MAX_BOUNCES: u32 = 64;

/// The values a setting accepts. Its [`Display`](fmt::Display) form is the range text that
/// every message about the setting shows (scene file, command line and library API alike).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// An integer in `lo..=hi`.
    Int {
        /// Smallest accepted value.
        lo: u32,
        /// Largest accepted value.
        hi: u32,
    },
    /// A finite number greater than zero.
    Positive,
    /// Any finite number.
    Finite,
    /// A number strictly between `lo` and `hi`.
    Open {
        /// Lower bound (excluded).
        lo: f32,
        /// Upper bound (excluded).
        hi: f32,
    },
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Range::Int { lo, hi } => write!(f, "{lo}..={hi}"),
            Range::Positive => f.write_str("positive and finite"),
            Range::Finite => f.write_str("finite"),
            Range::Open { lo, hi } => write!(f, "({lo}, {hi})"),
        }
    }
}

impl Range {
    /// Whether the integer `v` is in the range (never for a non-integer range).
    pub fn admits_int(&self, v: i64) -> bool {
        match *self {
            Range::Int { lo, hi } => (lo as i64..=hi as i64).contains(&v),
            _ => false,
        }
    }
    /// Whether the number `v` is in the range.
    pub fn admits(&self, v: f32) -> bool {
        match *self {
            Range::Int { lo, hi } => v.fract() == 0.0 && v >= lo as f32 && v <= hi as f32,
            Range::Positive => v.is_finite() && v > 0.0,
            Range::Finite => v.is_finite(),
            Range::Open { lo, hi } => v > lo && v < hi,
        }
    }
    /// What a value must be, as a scene-file error says it after "must be ":
    /// `an integer in 1..=65536`, `positive and finite`, `finite`, `in (0, 1)`.
    pub fn requirement(&self) -> String {
        match self {
            Range::Int { .. } => format!("an integer in {self}"),
            Range::Open { .. } => format!("in {self}"),
            _ => self.to_string(),
        }
    }
    /// Why `value` is refused, as [`validate`] says it: `70000 is outside 1..=65536`,
    /// `-1 must be positive and finite`.
    pub fn refusal(&self, value: impl fmt::Display) -> String {
        match self {
            Range::Int { .. } | Range::Open { .. } => format!("{value} is outside {self}"),
            _ => format!("{value} must be {self}"),
        }
    }
}

/// Where a setting lives in [`RenderSettings`].
#[derive(Clone, Copy, Debug)]
pub enum Slot {
    /// A `u32` field.
    U32 {
        /// Reads the field.
        get: fn(&RenderSettings) -> u32,
        /// Writes the field.
        set: fn(&mut RenderSettings, u32),
    },
    /// An `f32` field, or an `Option<f32>` one (unset: `get` gives `None`, nothing to check).
    F32 {
        /// Reads the field.
        get: fn(&RenderSettings) -> Option<f32>,
        /// Writes the field.
        set: fn(&mut RenderSettings, f32),
    },
}

/// One numeric setting: its names, its range and what it means.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    /// The [`RenderSettings`] field, and the key in the scene file.
    pub name: &'static str,
    /// The command-line flag (without `--`); [`Error::Setting`] names the setting by it.
    pub flag: &'static str,
    /// The scene-file table that may set it (`camera` or `render`); `None`: command line and
    /// library API only.
    pub table: Option<&'static str>,
    /// The values it accepts.
    pub range: Range,
    /// Unit and meaning, for documentation.
    pub meaning: &'static str,
    /// Where it lives in [`RenderSettings`].
    pub slot: Slot,
}

impl Setting {
    /// Checks this setting's value in `s` against its range.
    pub fn check(&self, s: &RenderSettings) -> Result<()> {
        let refusal = match self.slot {
            Slot::U32 { get, .. } => {
                let v = get(s);
                (!self.range.admits_int(v as i64)).then(|| self.range.refusal(v))
            }
            Slot::F32 { get, .. } => match get(s) {
                Some(v) if !self.range.admits(v) => Some(self.range.refusal(v)),
                _ => None,
            },
        };
        match refusal {
            Some(message) => Err(Error::Setting {
                field: self.flag,
                message,
            }),
            None => Ok(()),
        }
    }
}

/// One row of [`SETTINGS`]: `row!(field, "flag", table, range, u32 | f32 | opt_f32, "meaning")`.
macro_rules! row {
    ($name:ident, $flag:literal, $table:expr, $range:expr, u32, $meaning:literal) => {
        row!(@ $name, $flag, $table, $range, $meaning, Slot::U32 {
            get: |s: &RenderSettings| s.$name,
            set: |s: &mut RenderSettings, v: u32| s.$name = v,
        })
    };
    ($name:ident, $flag:literal, $table:expr, $range:expr, f32, $meaning:literal) => {
        row!(@ $name, $flag, $table, $range, $meaning, Slot::F32 {
            get: |s: &RenderSettings| Some(s.$name),
            set: |s: &mut RenderSettings, v: f32| s.$name = v,
        })
    };
    ($name:ident, $flag:literal, $table:expr, $range:expr, opt_f32, $meaning:literal) => {
        row!(@ $name, $flag, $table, $range, $meaning, Slot::F32 {
            get: |s: &RenderSettings| s.$name,
            set: |s: &mut RenderSettings, v: f32| s.$name = Some(v),
        })
    };
    (@ $name:ident, $flag:literal, $table:expr, $range:expr, $meaning:literal, $slot:expr) => {
        Setting {
            name: stringify!($name),
            flag: $flag,
            table: $table,
            range: $range,
            meaning: $meaning,
            slot: $slot,
        }
    };
}

const fn int(lo: u32, hi: u32) -> Range {
    Range::Int { lo, hi }
}
const CAMERA: Option<&str> = Some("camera");
const RENDER: Option<&str> = Some("render");

/// The one table of numeric settings and their ranges. The scene file's `[camera]` and
/// `[render]` tables, [`validate`] (which the command line and the library API go through)
/// and `scenes/README.md` all follow it.
#[rustfmt::skip]
pub static SETTINGS: &[Setting] = &[
    row!(width, "width", CAMERA, int(1, MAX_RESOLUTION), u32, "image width, pixels"),
    row!(height, "height", CAMERA, int(1, MAX_RESOLUTION), u32, "image height, pixels"),
    row!(photons, "photons", RENDER, int(1, MAX_PHOTONS), u32, "photon paths for the global map"),
    row!(caustic_photons, "caustic-photons", RENDER, int(0, MAX_PHOTONS), u32,
        "photons stored in the caustic map (0: none)"),
    row!(k, "k", RENDER, int(1, MAX_K), u32, "photons per K-nearest radiance estimate"),
    row!(radius, "radius", RENDER, Range::Positive, f32,
        "largest search radius of the global map, scene units"),
    row!(caustic_radius, "caustic-radius", RENDER, Range::Positive, f32,
        "largest search radius of the caustic map, scene units"),
    row!(volume_radius, "volume-radius", RENDER, Range::Positive, f32,
        "radius of the volume photons' beam estimate (largest when progressive), scene units"),
    row!(spp, "spp", RENDER, int(1, MAX_SPP), u32, "camera samples per pixel"),
    row!(shadow_samples, "shadow-samples", RENDER, int(1, MAX_SHADOW_SAMPLES), u32,
        "shadow rays per area light and camera sample; single-scattering estimates per light in media"),
    row!(adaptive, "adaptive", RENDER, int(0, MAX_ADAPTIVE), u32,
        "most camera samples of a pixel, as a multiple of spp, by the pilots' noise (1: spp everywhere; 0: automatic)"),
    row!(caustic_every, "caustic-every", RENDER, int(1, MAX_SPP), u32,
        "camera samples per caustic-map estimate (1: every sample)"),
    row!(max_photon_bounces, "max-photon-bounces", RENDER, int(1, MAX_BOUNCES), u32,
        "bounces a photon path may make"),
    row!(max_depth, "max-depth", RENDER, int(1, MAX_BOUNCES), u32,
        "bounces of a camera path (mirror, glass, glossy); a hit past them only emits"),
    row!(seed, "seed", RENDER, int(0, u32::MAX), u32, "random seed"),
    row!(exposure, "exposure", RENDER, Range::Finite, f32, "PNG exposure, stops"),
    row!(passes, "passes", RENDER, int(0, MAX_PASSES), u32,
        "progressive passes of a render (0: one classic K-nearest pass)"),
    row!(alpha, "alpha", None, Range::Open { lo: 0.0, hi: 1.0 }, f32,
        "radius reduction of progressive passes"),
    row!(initial_radius, "initial-radius", None, Range::Positive, opt_f32,
        "global-map radius of the first progressive pass, scene units"),
];

/// The row of [`SETTINGS`] for the field `name`.
pub fn setting(name: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.name == name)
}

/// Checks every setting of [`SETTINGS`] against its range (the command line and the library
/// API go through this; a scene file's values are checked as it is read, with the same table).
pub fn validate(s: &RenderSettings) -> Result<()> {
    SETTINGS.iter().try_for_each(|row| row.check(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_row_is_consistent() {
        let d = RenderSettings::default();
        for row in SETTINGS {
            let int = matches!(row.range, Range::Int { .. });
            assert_eq!(int, matches!(row.slot, Slot::U32 { .. }), "{}", row.name);
            assert_eq!(row.flag, row.name.replace('_', "-"), "{}", row.name);
            assert!(
                row.check(&d).is_ok(),
                "{}: the default is refused",
                row.name
            );
            assert_eq!(setting(row.name).map(|r| r.flag), Some(row.flag));
        }
    }

    #[test]
    fn validate_refuses_each_bound_and_names_the_flag() {
        for row in SETTINGS {
            let mut s = RenderSettings::default();
            let bad = match (row.range, row.slot) {
                (Range::Int { lo, hi }, Slot::U32 { set, .. }) => {
                    let Some(v) = hi.checked_add(1).or(lo.checked_sub(1)) else {
                        continue;
                    };
                    set(&mut s, v);
                    v.to_string()
                }
                (_, Slot::F32 { set, .. }) => {
                    let v = if row.range == Range::Finite {
                        f32::NAN
                    } else {
                        -1.0
                    };
                    set(&mut s, v);
                    v.to_string()
                }
                _ => unreachable!("{}", row.name),
            };
            match validate(&s) {
                Err(Error::Setting { field, message }) => {
                    assert_eq!(field, row.flag);
                    assert!(message.contains(&bad), "{message}");
                    assert!(message.contains(&row.range.to_string()), "{message}");
                }
                other => panic!("{}: {bad} gave {other:?}", row.name),
            }
        }
    }

    #[test]
    fn range_texts() {
        assert_eq!(int(1, 65536).requirement(), "an integer in 1..=65536");
        assert_eq!(int(1, 65536).refusal(70000), "70000 is outside 1..=65536");
        assert_eq!(
            Range::Positive.refusal(-1.0),
            "-1 must be positive and finite"
        );
        let open = Range::Open { lo: 0.0, hi: 1.0 };
        assert_eq!(
            (open.refusal(1.5), open.requirement()),
            ("1.5 is outside (0, 1)".into(), "in (0, 1)".into())
        );
        assert!(!open.admits(1.0) && !open.admits(f32::NAN) && open.admits(0.5));
        assert!(!Range::Positive.admits(f32::INFINITY) && !Range::Positive.admits(0.0));
        assert!(int(0, u32::MAX).admits_int(u32::MAX as i64) && !int(1, 4).admits_int(0));
    }
}
