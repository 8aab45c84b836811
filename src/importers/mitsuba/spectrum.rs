//! Spectra to linear sRGB as Mitsuba 3's RGB variants convert them when they load a scene
//! (`Properties::get_texture_impl` in `src/core/properties.cpp`, `spectrum_list_to_srgb` in
//! `src/core/spectrum.cpp`):
//! - a constant `<spectrum value="v"/>` is `v` grey, except in an emitter, where it is the
//!   equal-energy spectrum's colour `v * xyz_to_srgb(1, 1, 1)` (sRGB's white is D65);
//! - `wavelength:value` pairs are integrated against the CIE 1931 curves at 1000 points of
//!   [360, 830] nm (linear between the pairs, zero outside them), a reflectance weighted by
//!   the D65 illuminant, an emission not; reflectances are clamped to [0, 1], emissions and
//!   the unbounded `eta`, `k`, `int_ior`, `ext_ior` to >= 0;
//! - a blackbody, which the RGB variants refuse, is what the spectral variants record: Planck's
//!   law in W m^-2 sr^-1 nm^-1 integrated the same way, unweighted.

use crate::importers::mitsuba::cie::{CIE_1931_D65, CIE_MAX, CIE_MIN};
use glam::Vec3;

/// Mitsuba's `MI_CIE_Y_NORMALIZATION`: a unit spectrum integrates to luminance 1.
const Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;
/// Mitsuba's `MI_CIE_D65_NORMALIZATION`: D65 integrates to luminance 1.
const D65_NORMALIZATION: f64 = 1.0 / 98.997_417_518_762_55;
/// Integration points of `spectrum_list_to_srgb`.
const STEPS: usize = 1000;

/// Parameters Mitsuba reads as unbounded spectra (clamped to >= 0 only).
pub const UNBOUNDED: &[&str] = &["eta", "k", "int_ior", "ext_ior", "sigma_t"];

/// CIE XYZ to linear sRGB (Mitsuba's `xyz_to_srgb`).
pub fn xyz_to_srgb(xyz: [f64; 3]) -> Vec3 {
    let [x, y, z] = xyz;
    Vec3::new(
        (3.240479 * x - 1.537150 * y - 0.498535 * z) as f32,
        (-0.969256 * x + 1.875991 * y + 0.041556 * z) as f32,
        (0.055648 * x - 0.204043 * y + 1.057311 * z) as f32,
    )
}

/// The CIE curves and the normalised D65 at `w` nm, linear between the table's samples.
fn cie_at(w: f64) -> [f64; 4] {
    let t = (w - CIE_MIN) * ((CIE_1931_D65.len() - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i = (t.max(0.0) as usize).min(CIE_1931_D65.len() - 2);
    let f = t - i as f64;
    let (a, b) = (CIE_1931_D65[i], CIE_1931_D65[i + 1]);
    let mut out: [f64; 4] = std::array::from_fn(|k| a[k] * (1.0 - f) + b[k] * f);
    out[3] *= D65_NORMALIZATION;
    out
}

/// The integration wavelengths of `spectrum_list_to_srgb`.
fn steps() -> impl Iterator<Item = f64> {
    (0..STEPS).map(|i| CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN))
}

/// sum over the steps of `f(w) * cie(w)` (times D65 when `d65`), normalised, as sRGB.
fn integrate(f: impl Fn(f64) -> Option<f64>, d65: bool) -> Vec3 {
    let mut xyz = [0.0; 3];
    for w in steps() {
        let Some(v) = f(w) else { continue };
        let c = cie_at(w);
        let v = if d65 { v * c[3] } else { v };
        for k in 0..3 {
            xyz[k] += c[k] * v;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) * Y_NORMALIZATION / STEPS as f64;
    xyz_to_srgb(xyz.map(|v| v * scale))
}

/// How a spectrum is used: Mitsuba converts each differently.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Use {
    /// A reflectance (or another bounded parameter): D65-weighted, clamped to [0, 1].
    Bounded,
    /// `eta`, `k`, `int_ior`, `ext_ior`: D65-weighted, clamped to >= 0.
    Unbounded,
    /// A parameter of an emitter: unweighted, clamped to >= 0.
    Emission,
}

/// The sRGB colour of the constant spectrum `v`.
pub fn constant(v: f32, usage: Use) -> Vec3 {
    match usage {
        Use::Emission => v * xyz_to_srgb([1.0; 3]),
        _ => Vec3::splat(v),
    }
}

/// The sRGB colour of the piecewise-linear spectrum through `(wavelength nm, value)` pairs
/// (at least two, wavelengths increasing), clamped as Mitsuba clamps it.
pub fn list_to_srgb(pairs: &[(f64, f64)], usage: Use) -> Vec3 {
    let (first, last) = (pairs[0].0, pairs[pairs.len() - 1].0);
    let value = |w: f64| {
        if w < first || w > last {
            return None;
        }
        // The last pair whose wavelength is <= w, at most the one before the last.
        let i = pairs
            .partition_point(|p| p.0 <= w)
            .clamp(1, pairs.len() - 1)
            - 1;
        let ((w0, v0), (w1, v1)) = (pairs[i], pairs[i + 1]);
        Some(((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1))
    };
    let rgb = integrate(value, usage != Use::Emission);
    match usage {
        Use::Bounded => rgb.clamp(Vec3::ZERO, Vec3::ONE),
        _ => rgb.max(Vec3::ZERO),
    }
}

/// The sRGB colour of a blackbody at `kelvin`, in W m^-2 sr^-1 (Mitsuba's `blackbody`
/// spectrum over [360, 830] nm, as its spectral variants would record it).
pub fn blackbody(kelvin: f64) -> Vec3 {
    // Mitsuba's constants (speed of light, Planck, Boltzmann).
    let (c, h, k) = (2.99792458e8, 6.62607004e-34, 1.38064852e-23);
    let (c0, c1) = (2.0 * h * c * c, h * c / k);
    let planck = |w: f64| {
        let l = w * 1e-9;
        Some(1e-9 * c0 / (l.powi(5) * ((c1 / (l * kelvin)).exp() - 1.0)))
    };
    integrate(planck, false).max(Vec3::ZERO)
}
