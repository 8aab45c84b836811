//! Counter-based random numbers: every value is a pure function of
//! (seed, stream, pass, index, dimension), so results never depend on thread scheduling and
//! the two backends draw the same numbers.
//!
//! Twin: `src/math/rng.wgsl` (a test checks they agree bit for bit). Only 32-bit integer
//! operations with wrapping arithmetic are used, so WGSL reproduces them exactly.

/// Which kind of path a stream of numbers belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Stream {
    /// Photon paths for the global map.
    Photon = 1,
    /// Photon paths for the caustic map.
    Caustic = 2,
    /// Camera samples (index = pixel * spp + sample).
    Camera = 3,
    /// Pilot photons that estimate how often caustic emission hits the specular bounds.
    Pilot = 4,
}

/// The PCG-RXS-M-XS 32-bit hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020).
#[inline]
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The key of one path's stream: a hash of (seed, stream, pass, index).
#[inline]
pub fn path_key(seed: u32, stream: Stream, pass: u32, index: u32) -> u32 {
    let a = pcg_hash(seed ^ pcg_hash(stream as u32));
    let b = pcg_hash(a ^ pass);
    pcg_hash(b ^ index)
}

/// Dimension `dim` of the stream with key `key`, as 32 random bits.
#[inline]
pub fn draw_u32(key: u32, dim: u32) -> u32 {
    pcg_hash(key ^ pcg_hash(dim))
}

/// Maps 32 random bits to a float in [0, 1) with 24 bits of precision (exact in f32).
#[inline]
pub fn to_unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A sequential view of one path's stream: the n-th call returns dimension n.
#[derive(Clone, Copy, Debug)]
pub struct Rng {
    key: u32,
    dim: u32,
}

impl Rng {
    /// The stream of path `index` of `stream` in pass `pass` of a render with `seed`.
    pub fn new(seed: u32, stream: Stream, pass: u32, index: u32) -> Self {
        Self {
            key: path_key(seed, stream, pass, index),
            dim: 0,
        }
    }
    /// The next uniform float in [0, 1).
    #[inline]
    pub fn next(&mut self) -> f32 {
        let v = to_unit(draw_u32(self.key, self.dim));
        self.dim += 1;
        v
    }
    /// Two uniform floats.
    #[inline]
    pub fn next2(&mut self) -> (f32, f32) {
        (self.next(), self.next())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_floats_are_in_range_and_roughly_uniform() {
        let mut r = Rng::new(7, Stream::Photon, 0, 3);
        let n = 100_000;
        let mut sum = 0.0f64;
        let mut buckets = [0u32; 10];
        for _ in 0..n {
            let v = r.next();
            assert!((0.0..1.0).contains(&v));
            sum += v as f64;
            buckets[(v * 10.0) as usize] += 1;
        }
        // Mean of U(0,1) has standard deviation 1/sqrt(12 n) ~ 0.0009: allow 5 sigma.
        assert!((sum / n as f64 - 0.5).abs() < 0.0046);
        // Each bucket expects 10,000 with sd ~95: allow 5 sigma.
        for b in buckets {
            assert!((b as i32 - 10_000).abs() < 475, "{buckets:?}");
        }
    }

    #[test]
    fn streams_differ_by_every_key_part() {
        let base = path_key(1, Stream::Photon, 0, 0);
        assert_ne!(base, path_key(2, Stream::Photon, 0, 0));
        assert_ne!(base, path_key(1, Stream::Caustic, 0, 0));
        assert_ne!(base, path_key(1, Stream::Photon, 1, 0));
        assert_ne!(base, path_key(1, Stream::Photon, 0, 1));
    }
}
