//! Low-discrepancy samples: Owen-scrambled Sobol points (Burley, "Practical Hash-based Owen
//! Scrambling", JCGT 2020) from the `sobol_burley` crate, keyed by
//! (seed, pass, pixel, sample, dimension) so images stay deterministic and progressive passes
//! rendered on different machines merge.
//!
//! Twin: `src/math/sobol.wgsl` (`tests/sobol.rs` checks they agree bit for bit).
//!
//! # The mapping
//! - The pixel's key is `pcg_hash(pcg_hash(seed) ^ pixel)` ([`pixel_key`]); the pass is *not*
//!   part of it.
//! - Sample `s` of pass `p` at `spp` samples per pass is index `p * spp + s` of the pixel's
//!   sequence ([`SobolSampler::index`], wrapping at 2^32), so pass `p`'s points continue the
//!   sequence of passes `0..p`: passes 0 and 1 at `spp` together are pass 0 at `2 * spp`.
//! - Dimensions come in pairs ("padding", Burley section 4; pbrt-v4's samplers do the same):
//!   dimension `d` is the crate's dimension `d % 2` of pair `d / 2`, and each pair is its own
//!   independently scrambled and shuffled sequence. So every pair `(2j, 2j + 1)` is an
//!   Owen-scrambled (0, 2)-sequence (with `spp` a power of two, each pass's points form a
//!   (0, m, 2)-net), whatever `j`; pairs are only randomly associated with each other. Draw
//!   2-D decisions (camera jitter, a light sample, a gather direction) from one pair.
//!   Measured (docs/sobol.md): the crate's own dimensions past 1 have poorer 2-D
//!   projections (dimensions 20 and 21 at 256 samples: 10x the RMSE of a pair on a smooth
//!   integrand), which is why pairs are used.
//! - The crate covers indices below 2^[`INDEX_BITS`]: index `i` uses block
//!   `b = i >> INDEX_BITS`, at index `i & (2^INDEX_BITS - 1)` in it, so past 2^16 samples the
//!   points are freshly scrambled ones (the error keeps falling at the Monte Carlo rate between
//!   blocks) instead of the same 2^16 points again.
//! - The crate's seed for pair `j` and block `b` is `pcg_hash(pcg_hash(key ^ b) ^ j)`
//!   ([`crate_seed`]). There is no dimension limit: any u32 index and dimension is valid.

use crate::math::rng::pcg_hash;

/// Dimensions per independently scrambled set: the crate's dimensions 0 and 1 (a pair;
/// [`sample_pair`] relies on it).
pub const SET_DIMENSIONS: u32 = 2;

/// Index bits the crate's direction numbers cover: one block holds 2^16 samples.
pub const INDEX_BITS: u32 = 16;

const _: () = assert!(SET_DIMENSIONS == 2 && SET_DIMENSIONS <= sobol_burley::NUM_DIMENSIONS);

/// Camera pass (both backends): the pair of the pixel jitter `(fx, fy)` of every sample.
pub const PAIR_JITTER: u32 = 0;
/// Camera pass: the pair of the first area-light shadow sample's `u[0], u[1]` at the first
/// diffuse or glossy hit the sample shades.
pub const PAIR_LIGHT: u32 = 1;
/// Camera pass: the dimension of that shadow sample's `u[2]` (pair 2's first component).
pub const DIM_LIGHT_THIRD: u32 = 4;
/// Camera pass: the pair of the gather ray's direction `(u1, u2)` at that first hit.
pub const PAIR_GATHER: u32 = 3;

/// Camera pass: the pair of a thin lens's aperture sample (pinhole cameras draw none).
pub const PAIR_LENS: u32 = 4;

/// The key of one pixel's sequence: a hash of (seed, pixel).
#[inline]
pub fn pixel_key(seed: u32, pixel: u32) -> u32 {
    pcg_hash(pcg_hash(seed) ^ pixel)
}

/// The seed handed to the crate for sample block `block` and dimension set `set` of the
/// sequence keyed `key` (see the module's mapping).
#[inline]
pub fn crate_seed(key: u32, block: u32, set: u32) -> u32 {
    pcg_hash(pcg_hash(key ^ block) ^ set)
}

/// Dimension `dim` of point `index` of the sequence keyed `key`, in [0, 1) (23 bits of
/// precision, exact in f32). Any `index` and `dim` are allowed.
#[inline]
pub fn sample(key: u32, index: u32, dim: u32) -> f32 {
    let seed = crate_seed(key, index >> INDEX_BITS, dim / SET_DIMENSIONS);
    sobol_burley::sample(index & ((1 << INDEX_BITS) - 1), dim % SET_DIMENSIONS, seed)
}

/// Dimensions `2 * pair` and `2 * pair + 1` of point `index` of the sequence keyed `key`:
/// `(sample(key, index, 2 * pair), sample(key, index, 2 * pair + 1))` at the cost of about one
/// (the crate's `sample_4d` shuffles the index once).
#[inline]
pub fn sample_pair(key: u32, index: u32, pair: u32) -> (f32, f32) {
    let seed = crate_seed(key, index >> INDEX_BITS, pair);
    let [x, y, _, _] = sobol_burley::sample_4d(index & ((1 << INDEX_BITS) - 1), 0, seed);
    (x, y)
}

/// One pixel's samples in one pass: sample `s` is point `pass * spp + s` of the pixel's
/// sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SobolSampler {
    key: u32,
    first: u32,
}

impl SobolSampler {
    /// The sampler of `pixel` in pass `pass` of a render seeded `seed` at `spp` samples per
    /// pixel and pass.
    pub fn new(seed: u32, pass: u32, pixel: u32, spp: u32) -> Self {
        Self {
            key: pixel_key(seed, pixel),
            first: pass.wrapping_mul(spp),
        }
    }
    /// The pixel's key ([`pixel_key`]).
    pub fn key(&self) -> u32 {
        self.key
    }
    /// The sequence index of sample `sample` of this pass.
    #[inline]
    pub fn index(&self, sample: u32) -> u32 {
        self.first.wrapping_add(sample)
    }
    /// Dimension `dim` of sample `sample`, in [0, 1).
    #[inline]
    pub fn get(&self, sample: u32, dim: u32) -> f32 {
        self::sample(self.key, self.index(sample), dim)
    }
    /// A sequential view of sample `sample`: the n-th call to `next` returns dimension n.
    pub fn stream(&self, sample: u32) -> SobolStream {
        SobolStream {
            key: self.key,
            index: self.index(sample),
            dim: 0,
        }
    }
}

/// The dimensions of one sample in order, like [`crate::math::rng::Rng`] does for hashed numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SobolStream {
    /// The pixel's key.
    pub key: u32,
    /// The sample's sequence index.
    pub index: u32,
    /// The next dimension to return.
    pub dim: u32,
}

impl SobolStream {
    /// The next dimension, in [0, 1).
    #[inline]
    #[allow(clippy::should_implement_trait)] // named like `Rng::next`; never ends, so no Iterator
    pub fn next(&mut self) -> f32 {
        let v = sample(self.key, self.index, self.dim);
        self.dim = self.dim.wrapping_add(1);
        v
    }
    /// The next pair: skips a dimension first if the stream is mid-pair, so the two values
    /// are always one stratified pair `(2j, 2j + 1)`.
    #[inline]
    pub fn next2(&mut self) -> (f32, f32) {
        self.dim = self.dim.wrapping_add(self.dim & 1);
        let v = sample_pair(self.key, self.index, self.dim / SET_DIMENSIONS);
        self.dim = self.dim.wrapping_add(2);
        v
    }
}

/// The crate's direction numbers, bit-reversed as the crate keeps them: entry
/// `d * INDEX_BITS + k` is the vector XORed in when bit `k` of the (shuffled) index is set,
/// for the crate's dimension `d < SET_DIMENSIONS`. Read from the crate's public `sobol_rev`,
/// so they are never typed by hand; [`rev_pair`], which the WGSL twin computes, is tested
/// against them.
pub fn direction_table() -> Vec<u32> {
    (0..SET_DIMENSIONS)
        .flat_map(|d| {
            (0..INDEX_BITS)
                .map(move |k| sobol_burley::parts::sobol_rev((1u32 << k).reverse_bits(), d))
        })
        .collect()
}

/// The crate's unscrambled Sobol integers of dimensions 0 and 1 (bit-reversed, as the crate
/// keeps them) for the index bits `bits < 2^INDEX_BITS`, without the [`direction_table`]:
/// dimension 0's direction `k` is `1 << k`, so its integer is `bits` itself; dimension 1's is
/// row `k` of Pascal's triangle mod 2 (bit `j` set iff `j & k == j`), so bit `j` of its
/// integer is the XOR of the bits `k` with `k & j == j`: four butterfly steps over the 4-bit
/// `k`. Twin of `sobol_rev_pair` in src/math/sobol.wgsl, which computes it this way
/// because lavapipe keeps a table in per-lane scratch memory.
pub fn rev_pair(bits: u32) -> [u32; 2] {
    let mut y = bits;
    y ^= (y >> 1) & 0x5555;
    y ^= (y >> 2) & 0x3333;
    y ^= (y >> 4) & 0x0f0f;
    y ^= (y >> 8) & 0x00ff;
    [bits, y]
}

// rev_pair's four steps cover 16 index bits.
const _: () = assert!(INDEX_BITS == 16);

/// The WGSL library: constants generated here (`SOBOL_SET_DIMENSIONS`, `SOBOL_INDEX_BITS`)
/// followed by `src/math/sobol.wgsl`. Needs `pcg_hash` (`src/math/rng.wgsl`)
/// before it.
pub fn wgsl_library() -> String {
    format!(
        "// Generated by src/math/sobol.rs wgsl_library().\n\
         const SOBOL_SET_DIMENSIONS: u32 = {SET_DIMENSIONS}u;\n\
         const SOBOL_INDEX_BITS: u32 = {INDEX_BITS}u;\n{}",
        include_str!("sobol.wgsl")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table rebuilds the crate's unscrambled Sobol integers for any index.
    #[test]
    fn direction_table_rebuilds_the_crates_sobol_integers() {
        let table = direction_table();
        assert_eq!(table.len(), (SET_DIMENSIONS * INDEX_BITS) as usize);
        for d in 0..SET_DIMENSIONS {
            for i in [0u32, 1, 2, 3, 5, 255, 1000, 0x8001, 0xffff] {
                let mut want = 0;
                for k in 0..INDEX_BITS {
                    if i >> k & 1 == 1 {
                        want ^= table[(d * INDEX_BITS + k) as usize];
                    }
                }
                assert_eq!(
                    sobol_burley::parts::sobol_rev(i.reverse_bits(), d),
                    want,
                    "dim {d} index {i}"
                );
            }
        }
    }

    /// The closed form the WGSL uses equals the crate's direction numbers for every index.
    #[test]
    fn rev_pair_equals_the_direction_table_for_every_index() {
        let table = direction_table();
        for bits in 0..1u32 << INDEX_BITS {
            let mut want = [0u32; 2];
            for k in 0..INDEX_BITS {
                if bits >> k & 1 == 1 {
                    want[0] ^= table[k as usize];
                    want[1] ^= table[(INDEX_BITS + k) as usize];
                }
            }
            assert_eq!(rev_pair(bits), want, "index bits {bits:#x}");
        }
    }

    /// True when the points fall one in each cell of every 2^a x 2^(k-a) grid (n = 2^k):
    /// the elementary intervals of a (0, k, 2)-net in base 2.
    fn is_0_k_2_net(points: &[(f32, f32)]) -> bool {
        let n = points.len();
        assert!(n.is_power_of_two());
        let k = n.trailing_zeros();
        (0..=k).all(|a| {
            let (nx, ny) = (1usize << a, 1usize << (k - a));
            let mut seen = vec![false; n];
            points.iter().all(|&(x, y)| {
                let cell = (x * nx as f32) as usize * ny + (y * ny as f32) as usize;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    }

    #[test]
    fn each_pass_of_a_power_of_two_spp_is_a_net_in_every_dimension_pair() {
        for (seed, pixel) in [(0, 0), (7, 12345), (0xdead_beef, 1 << 20)] {
            for k in 0..=10 {
                let spp = 1 << k;
                // Pass 1100 at 64 spp starts past 2^16: the second block.
                for pass in [0, 1, 5, 63, (1100 * 64) >> k] {
                    let s = SobolSampler::new(seed, pass, pixel, spp);
                    // Every pair is a net, however far out.
                    for d in [0, 2, 10, 510, 1 << 31, u32::MAX - 1] {
                        let pts: Vec<_> =
                            (0..spp).map(|i| (s.get(i, d), s.get(i, d + 1))).collect();
                        assert!(
                            is_0_k_2_net(&pts),
                            "seed {seed} pixel {pixel} spp {spp} pass {pass} dims {d},{}",
                            d + 1
                        );
                    }
                }
            }
        }
        // The check can fail: independent uniform points are not a net.
        let mut r = crate::math::rng::Rng::new(1, crate::math::rng::Stream::Camera, 0, 0);
        let pts: Vec<_> = (0..64).map(|_| r.next2()).collect();
        assert!(!is_0_k_2_net(&pts));
    }

    #[test]
    fn every_dimension_is_stratified_in_one_dimension() {
        let s = SobolSampler::new(3, 2, 99, 256);
        for d in (0..300).chain([1000, u32::MAX]) {
            let mut seen = [false; 256];
            for i in 0..256 {
                let cell = (s.get(i, d) * 256.0) as usize;
                assert!(!seen[cell], "dimension {d}: two points in interval {cell}");
                seen[cell] = true;
            }
        }
    }

    #[test]
    fn values_are_in_the_unit_interval() {
        let mut r = crate::math::rng::Rng::new(5, crate::math::rng::Stream::Photon, 0, 0);
        let edges = [0, 1, 255, 256, 65535, 65536, u32::MAX];
        for _ in 0..20_000 {
            let mut u = || (r.next() * 4_294_967_296.0) as u32;
            let (key, index, dim) = (u(), u(), u() % 2048);
            let v = sample(key, index, dim);
            assert!((0.0..1.0).contains(&v), "{key} {index} {dim}: {v}");
        }
        for key in edges {
            for index in edges {
                for dim in edges {
                    assert!((0.0..1.0).contains(&sample(key, index, dim)));
                }
            }
        }
    }

    #[test]
    fn passes_continue_one_sequence_and_streams_match_get() {
        let (seed, pixel, spp) = (42, 777, 16);
        let whole = SobolSampler::new(seed, 0, pixel, 4 * spp);
        for pass in 0..4 {
            let part = SobolSampler::new(seed, pass, pixel, spp);
            for i in 0..spp {
                let mut st = part.stream(i);
                for d in 0..300 {
                    let v = part.get(i, d);
                    assert_eq!(v.to_bits(), whole.get(pass * spp + i, d).to_bits());
                    assert_eq!(v.to_bits(), st.next().to_bits(), "stream dim {d}");
                }
            }
        }
        // next2 starts on a pair: from dimension 3 it returns dimensions 4 and 5.
        let mut st = whole.stream(5);
        st.dim = 3;
        let pair = st.next2();
        assert_eq!(pair, (whole.get(5, 4), whole.get(5, 5)));
        assert_eq!(
            (st.dim, st.next2()),
            (6, (whole.get(5, 6), whole.get(5, 7)))
        );
        // A pair costs one shuffle and equals its two dimensions.
        for (i, d) in [
            (0, 0),
            (70_000, 2),
            (u32::MAX, u32::MAX - 1),
            (12_345, 1 << 30),
        ] {
            let key = whole.key();
            let (x, y) = sample_pair(key, i, d / 2);
            assert_eq!(
                (x, y),
                (sample(key, i, d), sample(key, i, d + 1)),
                "{i} {d}"
            );
        }
        // Deterministic: built twice, same values.
        assert_eq!(SobolSampler::new(1, 2, 3, 4), SobolSampler::new(1, 2, 3, 4));
        assert_eq!(sample(9, 70_000, 300), sample(9, 70_000, 300));
    }

    /// Count of equal values between two samplers over 64 samples x 8 dimensions.
    fn shared_values(a: SobolSampler, b: SobolSampler) -> usize {
        (0..64)
            .flat_map(|i| (0..8).map(move |d| (i, d)))
            .filter(|&(i, d)| a.get(i, d) == b.get(i, d))
            .count()
    }

    #[test]
    fn pixels_and_seeds_get_different_scrambles() {
        let base = SobolSampler::new(1, 0, 500, 64);
        for other in [
            SobolSampler::new(1, 0, 501, 64),
            SobolSampler::new(1, 0, 500 + 1024, 64),
            SobolSampler::new(2, 0, 500, 64),
        ] {
            // Independent 23-bit values coincide with probability 2^-23 each.
            assert!(shared_values(base, other) <= 1, "{other:?}");
        }
        assert_eq!(shared_values(base, base), 64 * 8);
    }

    #[test]
    fn blocks_and_dimension_pairs_are_new_points_not_repeats() {
        let key = pixel_key(11, 4);
        let block = |b: u32, d: u32| {
            let mut v: Vec<u32> = (0..1 << INDEX_BITS)
                .map(|i| sample(key, (b << INDEX_BITS) + i, d).to_bits())
                .collect();
            v.sort_unstable();
            v
        };
        // Fed raw to the crate, block 1 would be block 0's point set reshuffled.
        assert_ne!(block(0, 0), block(1, 0));
        assert_ne!(block(0, 0), block(0, SET_DIMENSIONS));
    }

    #[test]
    fn the_library_parses_and_validates() {
        let src = format!(
            "{}\n@group(0) @binding(0) var<storage, read_write> out: array<f32>;\n{}\n\
             @compute @workgroup_size(1) fn main() {{ out[0] = sobol_sample(1u, 2u, 300u); }}",
            include_str!("rng.wgsl"),
            wgsl_library()
        );
        let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| {
            panic!("{}", e.emit_to_string(&src));
        });
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    }
}
