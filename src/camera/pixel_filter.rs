//! Reconstruction (pixel) filters, Mitsuba 3's `box`, `tent` and `gaussian`, by filter
//! importance sampling: each camera sample's offset from the pixel centre is drawn from the
//! filter's density (separable, one inverse CDF per axis) and weighs 1, so a pixel is still the
//! plain mean of its samples and passes stay independent and merge exactly.
//!
//! - `box` (radius 0.5): the jitter is the sample `(u1, u2)` itself, bit for bit as before.
//! - `tent` (`radius` r, default 1): density `1 - |x| / r` on `[-r, r]`.
//! - `gaussian` (`stddev` s, default 0.5; radius 4 s): the normal density truncated at 4 s,
//!   sampled as `s sqrt(2) erfinv((2u - 1) erf(2 sqrt(2)))`. Mitsuba's filter also subtracts
//!   `exp(-8)` (3.4e-4 of the peak) so it reaches 0 at the radius; the densities differ by at
//!   most 3e-4 in their CDFs.
//!
//! Twin: `src/camera/camera.wgsl` (`tests/camera_gpu.rs` checks them against each other).

/// `erf(2 sqrt(2))`: the mass of the normal density within 4 standard deviations.
pub const ERF_2_SQRT_2: f32 = 0.999_936_66;

/// The pixel filter of a camera.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum PixelFilter {
    /// A one-pixel box (radius 0.5).
    #[default]
    Box,
    /// A tent of half-width `radius` pixels.
    Tent {
        /// Half-width, pixels (Mitsuba's default 1).
        radius: f32,
    },
    /// A normal density of standard deviation `stddev` pixels, truncated at 4 `stddev`.
    Gaussian {
        /// Standard deviation, pixels (Mitsuba's default 0.5).
        stddev: f32,
    },
}

/// The names a scene file uses, as Mitsuba's `rfilter` types.
pub const FILTER_NAMES: [&str; 3] = ["box", "tent", "gaussian"];

impl PixelFilter {
    /// The code the WGSL twin switches on (0 box, 1 tent, 2 gaussian).
    pub fn code(self) -> u32 {
        match self {
            PixelFilter::Box => 0,
            PixelFilter::Tent { .. } => 1,
            PixelFilter::Gaussian { .. } => 2,
        }
    }

    /// The filter's parameter: the tent's radius, the gaussian's standard deviation, 0 for
    /// the box.
    pub fn param(self) -> f32 {
        match self {
            PixelFilter::Box => 0.0,
            PixelFilter::Tent { radius } => radius,
            PixelFilter::Gaussian { stddev } => stddev,
        }
    }

    /// Half-width of the filter's support, pixels.
    pub fn radius(self) -> f32 {
        match self {
            PixelFilter::Box => 0.5,
            PixelFilter::Tent { radius } => radius,
            PixelFilter::Gaussian { stddev } => 4.0 * stddev,
        }
    }

    /// The density samples' offsets follow along one axis (integrates to 1).
    pub fn density(self, x: f32) -> f32 {
        if x.abs() > self.radius() {
            return 0.0;
        }
        match self {
            PixelFilter::Box => 1.0,
            PixelFilter::Tent { radius } => (1.0 - x.abs() / radius) / radius,
            PixelFilter::Gaussian { stddev } => {
                let t = x / stddev;
                (-0.5 * t * t).exp() / (stddev * (2.0 * std::f32::consts::PI).sqrt() * ERF_2_SQRT_2)
            }
        }
    }

    /// The offset from the pixel centre of a sample `u` in [0, 1), one axis.
    pub fn offset(self, u: f32) -> f32 {
        match self {
            PixelFilter::Box => u - 0.5,
            PixelFilter::Tent { radius } => {
                if u < 0.5 {
                    radius * ((2.0 * u).sqrt() - 1.0)
                } else {
                    radius * (1.0 - (2.0 - 2.0 * u).sqrt())
                }
            }
            PixelFilter::Gaussian { stddev } => {
                stddev * std::f32::consts::SQRT_2 * erf_inv((2.0 * u - 1.0) * ERF_2_SQRT_2)
            }
        }
    }

    /// The sample's position in its pixel's raster square (added to the pixel's corner): the
    /// box returns `(u1, u2)` unchanged; the others `0.5 + offset`.
    pub fn jitter(self, u1: f32, u2: f32) -> (f32, f32) {
        match self {
            PixelFilter::Box => (u1, u2),
            _ => (0.5 + self.offset(u1), 0.5 + self.offset(u2)),
        }
    }
}

/// Giles' polynomial in `w - 2.5` for `w = -ln(1 - x^2) < 5` ("Approximating the erfinv
/// function", GPU Computing Gems, 2011), highest power first.
pub const ERF_INV_CENTRAL: [f64; 9] = [
    2.81022636e-08,
    3.43273939e-07,
    -3.5233877e-06,
    -4.39150654e-06,
    0.00021858087,
    -0.00125372503,
    -0.00417768164,
    0.246640727,
    1.50140941,
];
/// Giles' polynomial in `sqrt(w) - 3` for `w >= 5`, highest power first.
pub const ERF_INV_TAIL: [f64; 9] = [
    -0.000200214257,
    0.000100950558,
    0.00134934322,
    -0.00367342844,
    0.00573950773,
    -0.0076224613,
    0.00943887047,
    1.00167406,
    2.83297682,
];

fn horner(c: &[f64; 9], w: f32) -> f32 {
    c[1..].iter().fold(c[0] as f32, |p, &c| c as f32 + p * w)
}

/// The inverse error function on (-1, 1), single precision (Giles' polynomials above):
/// `erf(erf_inv(x))` within 5e-8 of `x`.
pub fn erf_inv(x: f32) -> f32 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        horner(&ERF_INV_CENTRAL, w - 2.5)
    } else {
        horner(&ERF_INV_TAIL, w.sqrt() - 3.0)
    };
    p * x
}

/// The WGSL library: `erf_inv`'s polynomials generated from [`ERF_INV_CENTRAL`] and
/// [`ERF_INV_TAIL`] (Horner steps, no array), then `src/camera/camera.wgsl`. Needs the
/// prelude's `PIXEL_FILTER_*` and `ERF_2_SQRT_2`.
pub fn wgsl_library() -> String {
    let poly = |name: &str, c: &[f64; 9]| {
        let mut f = format!(
            "fn {name}(w: f32) -> f32 {{\n    var p = {:?}f;\n",
            c[0] as f32
        );
        for c in &c[1..] {
            f.push_str(&format!("    p = {:?}f + p * w;\n", *c as f32));
        }
        f + "    return p;\n}\n"
    };
    format!(
        "// Generated by src/camera/pixel_filter.rs wgsl_library().\n{}{}{}",
        poly("erf_inv_central", &ERF_INV_CENTRAL),
        poly("erf_inv_tail", &ERF_INV_TAIL),
        include_str!("camera.wgsl")
    )
}

/// A uniform point on the unit disc from `(u1, u2)` in [0, 1)^2 (Shirley and Chiu's concentric
/// map): the thin lens's aperture sample.
pub fn concentric_disc(u1: f32, u2: f32) -> (f32, f32) {
    let (a, b) = (2.0 * u1 - 1.0, 2.0 * u2 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_constant_is_erf_of_2_sqrt_2() {
        // erf by the trapezoid rule on 2/sqrt(pi) exp(-t^2), t in [0, 2 sqrt(2)].
        let (n, b) = (200_000, 2.0 * 2f64.sqrt());
        let h = b / n as f64;
        let f = |t: f64| (-t * t).exp();
        let sum: f64 = (1..n).map(|i| f(i as f64 * h)).sum::<f64>() + 0.5 * (f(0.0) + f(b));
        let erf = 2.0 / std::f64::consts::PI.sqrt() * h * sum;
        assert!((erf - ERF_2_SQRT_2 as f64).abs() < 1e-7, "{erf}");
    }

    #[test]
    fn box_jitter_is_the_sample_and_offsets_stay_in_the_support() {
        for u in [0.0, 0.25, 0.5, 0.999_999_9] {
            assert_eq!(PixelFilter::Box.jitter(u, 1.0 - u), (u, 1.0 - u));
            for f in [
                PixelFilter::Tent { radius: 1.5 },
                PixelFilter::Gaussian { stddev: 0.5 },
            ] {
                let o = f.offset(u);
                assert!(o.abs() <= f.radius() * 1.0001, "{f:?} {u}: {o}");
            }
        }
        assert_eq!(PixelFilter::Gaussian { stddev: 2.0 }.offset(0.5), 0.0);
        assert_eq!(PixelFilter::Tent { radius: 2.0 }.offset(0.5), 0.0);
    }

    #[test]
    fn concentric_disc_stays_in_the_disc() {
        for i in 0..64 {
            for j in 0..64 {
                let (x, y) = concentric_disc(i as f32 / 64.0, j as f32 / 64.0);
                assert!(x * x + y * y <= 1.0 + 1e-6);
            }
        }
    }
}
