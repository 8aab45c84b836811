//! Adaptive sampling: how many camera samples each pixel takes.
//!
//! Once per render, two pilot images of [`PILOT_SPP`] samples per pixel each, with seeds of
//! their own ([`pilot_seed`]), are rendered over pass 0's photon maps. Half their squared
//! difference is an estimate of a sample's variance at the pixel; averaged over the pixel's
//! 3 x 3 neighbourhood, its square root `sigma` sets the pixel's share. For a sum of pixel
//! variances `sigma^2 / n` at a fixed total of samples, the best counts are `n ~ sigma`
//! (Lagrange), so pixel i takes `spp * m_i` samples in every pass, `m_i` the power of two
//! nearest `sigma_i / mean(sigma)`, at least 1 and at most the setting `adaptive` (rounded
//! down to a power of two; 0, the default, is [`resolve`]'s choice). Pixels of less than
//! average noise keep `spp`; the edges of lights, caustics and glossy highlights take more.
//!
//! A pixel's count is the same in every pass, so its samples over the passes continue one
//! Sobol sequence (`pass * count + i`): a pixel on a light's edge converges at the
//! low-discrepancy rate, which extra samples from another sequence would lose. The pilots
//! are not part of the image and their camera samples are independent of the passes': each
//! pixel's estimate is the plain mean of its own samples, whatever their number, so it is
//! unbiased exactly as a uniform pass is. The counts depend on nothing but the scene and the
//! settings (a range of passes rendered elsewhere traces pass 0's photons for them), so
//! passes rendered anywhere still merge. The error measure is absolute (RMSE), as the
//! references judge renders.

use crate::math::rng::pcg_hash;
use crate::render::film::Image;

/// What the setting `adaptive` 0 (automatic, the default) gives on the CPU backend where
/// [`resolve`] turns it on.
pub const AUTO: u32 = 16;
/// Fewest camera samples per pixel and pass for which `adaptive` 0 turns adaptive sampling
/// on: as many as the pilots' 2 x [`PILOT_SPP`], taken once per render.
pub const AUTO_MIN_SPP: u32 = 16;
/// Fewest pixels for which `adaptive` 0 turns it on (64 x 64): the pilots' noise is judged
/// over 3 x 3 neighbourhoods, and a smaller image is a preview or a test.
pub const AUTO_MIN_PIXELS: u32 = 64 * 64;

/// The multiple of `spp` a render's pixels may take: the setting `adaptive`, or for 0
/// (automatic) [`AUTO`] when a pass has at least [`AUTO_MIN_SPP`] samples per pixel and the
/// image at least [`AUTO_MIN_PIXELS`], else 1 (uniform).
pub fn resolve(s: &crate::settings::RenderSettings) -> u32 {
    match s.adaptive {
        0 if s.spp >= AUTO_MIN_SPP && s.width.saturating_mul(s.height) >= AUTO_MIN_PIXELS => AUTO,
        0 => 1,
        n => n,
    }
}

/// Camera samples per pixel of each of a pass's two pilot images.
pub const PILOT_SPP: u32 = 8;

/// The seed of pilot image `half` (0 or 1) of a render seeded `seed`: hashed apart from the
/// render's own seed and from each other.
pub fn pilot_seed(seed: u32, half: u32) -> u32 {
    pcg_hash(pcg_hash(seed ^ 0x5eed_ad47) ^ half)
}

/// The largest per-pixel multiple of `spp` a pass may give: `adaptive` (resolved, see
/// [`resolve`]) rounded down to a power of two (1: no adaptive sampling).
pub fn most(adaptive: u32) -> u32 {
    1 << adaptive.max(1).ilog2()
}

/// The stride of a pixel's RNG indices: `spp` times [`most`], so that the samples of
/// different pixels never share an RNG stream whatever their counts. `spp` itself without
/// adaptive sampling.
pub fn stride(spp: u32, adaptive: u32) -> u32 {
    spp.saturating_mul(most(adaptive))
}

/// Each pixel's camera samples for a pass of `spp` samples per pixel, from the pass's pilot
/// images `a` and `b` (see the module): `spp` times a power of two in `1..=most(adaptive)`.
pub fn sample_counts(a: &Image, b: &Image, spp: u32, adaptive: u32) -> Vec<u32> {
    let (w, h) = (a.width as usize, a.height as usize);
    let top = most(adaptive);
    if top == 1 || w == 0 || h == 0 {
        return vec![spp; w * h];
    }
    // Half the squared difference of the pilots, per pixel (channels averaged); NaN or
    // infinite pilots count as no information.
    let d: Vec<f64> = (a.pixels.iter().zip(&b.pixels))
        .map(|(p, q)| {
            let v = (0..3)
                .map(|c| (p[c] as f64 - q[c] as f64).powi(2))
                .sum::<f64>()
                / 6.0;
            if v.is_finite() {
                v
            } else {
                0.0
            }
        })
        .collect();
    let mut sigma = vec![0.0f64; w * h];
    for y in 0..h {
        for x in 0..w {
            let (mut sum, mut n) = (0.0, 0.0);
            for yy in y.saturating_sub(1)..(y + 2).min(h) {
                for xx in x.saturating_sub(1)..(x + 2).min(w) {
                    sum += d[yy * w + xx];
                    n += 1.0;
                }
            }
            sigma[y * w + x] = (sum / n).sqrt();
        }
    }
    let mean = sigma.iter().sum::<f64>() / sigma.len() as f64;
    if mean <= 0.0 || !mean.is_finite() {
        return vec![spp; w * h];
    }
    sigma
        .iter()
        .map(|s| {
            let r = s / mean;
            // The power of two nearest r in the log (r >= sqrt 2 -> 2, >= 2 sqrt 2 -> 4, ...).
            let m = if r < std::f64::consts::SQRT_2 {
                1
            } else {
                1u32 << ((r * std::f64::consts::SQRT_2).log2().floor() as u32).min(31)
            };
            spp.saturating_mul(m.min(top))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Image {
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                img.pixels[(y * w + x) as usize] = [f(x, y); 3];
            }
        }
        img
    }

    #[test]
    fn strides_and_most_are_powers_of_two() {
        assert_eq!(
            (most(0), most(1), most(2), most(7), most(8)),
            (1, 1, 2, 4, 8)
        );
        assert_eq!(
            (stride(32, 1), stride(32, 8), stride(16, 12)),
            (32, 256, 128)
        );
    }

    #[test]
    fn automatic_is_on_for_passes_of_16_spp_on_64_by_64_or_more() {
        use crate::settings::RenderSettings;
        let s = |adaptive, spp, width| RenderSettings {
            adaptive,
            spp,
            width,
            height: 64,
            ..RenderSettings::default()
        };
        assert_eq!(resolve(&s(0, 16, 64)), AUTO);
        assert_eq!(resolve(&s(0, 15, 64)), 1);
        assert_eq!(resolve(&s(0, 64, 63)), 1);
        assert_eq!((resolve(&s(1, 64, 64)), resolve(&s(8, 1, 1))), (1, 8));
    }

    #[test]
    fn equal_pilots_or_no_adaptive_keep_spp() {
        let a = image(5, 4, |x, y| (x * y) as f32);
        assert_eq!(sample_counts(&a, &a, 16, 8), vec![16; 20]);
        let b = image(5, 4, |x, _| x as f32);
        assert_eq!(sample_counts(&a, &b, 16, 1), vec![16; 20]);
    }

    /// One noisy pixel in a quiet 12 x 12 image: its 3 x 3 neighbourhood has a sigma of
    /// sqrt(D / 9) where D is its squared difference, the other 135 pixels 0, so the mean
    /// sigma is 9 sqrt(D / 9) / 144 and the neighbourhood's ratio 144 / 9 = 16: capped at
    /// `most`; the rest keep spp.
    #[test]
    fn a_noisy_pixel_and_its_neighbours_take_the_most() {
        let a = image(12, 12, |_, _| 1.0);
        let b = image(12, 12, |x, y| if (x, y) == (5, 6) { 3.0 } else { 1.0 });
        let n = sample_counts(&a, &b, 4, 8);
        for y in 0..12u32 {
            for x in 0..12u32 {
                let near = x.abs_diff(5) <= 1 && y.abs_diff(6) <= 1;
                assert_eq!(
                    n[(y * 12 + x) as usize],
                    if near { 32 } else { 4 },
                    "{x},{y}"
                );
            }
        }
        // With room for more, the ratio itself: 16 x spp.
        let n = sample_counts(&a, &b, 4, 64);
        assert_eq!((n[6 * 12 + 5], n[0]), (64, 4));
    }
}
