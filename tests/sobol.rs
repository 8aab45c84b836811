//! Oracle test of the low-discrepancy sampler: `src/math/sobol.wgsl` on the device against
//! `gpu_photon::math::sobol` (the `sobol_burley` crate) on the CPU, bit for bit, over many
//! (seed, pass, pixel, spp, sample, dimension) tuples. Runs on lavapipe in CI (a missing
//! adapter fails there; elsewhere it skips).

mod common;

use bytemuck::{Pod, Zeroable};
use common::{gpu, TestRng};
use gpu_photon::integrators::gpu::GpuContext;
use gpu_photon::math::sobol::{wgsl_library, SobolSampler, INDEX_BITS};

/// One probe input; the twin of `Query` in [`PROBE`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Query {
    seed: u32,
    pass_index: u32,
    pixel: u32,
    spp: u32,
    sample: u32,
    dim: u32,
}

/// The probe kernel: per query, the stream's key and index, the bits of dimensions `dim` and
/// `dim + 1` (drawn in order through `sobol_next`), then of one `sobol_next2` pair and the
/// dimension it leaves the stream at.
const PROBE: &str = r#"
struct Query {
    seed: u32,
    pass_index: u32,
    pixel: u32,
    spp: u32,
    sample: u32,
    dim: u32,
}

@group(0) @binding(0) var<storage, read> queries: array<Query>;
@group(0) @binding(1) var<storage, read_write> results: array<array<u32, 7>>;

@compute @workgroup_size(64)
fn probe_sobol(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&queries) {
        return;
    }
    let q = queries[i];
    var s = sobol_stream(q.seed, q.pass_index, q.pixel, q.spp, q.sample);
    s.dim = q.dim;
    let a = sobol_next(&s);
    let b = sobol_next(&s);
    let p = bitcast<vec2<u32>>(sobol_next2(&s));
    results[i] = array<u32, 7>(s.key, s.index, bitcast<u32>(a), bitcast<u32>(b), p.x, p.y, s.dim);
}
"#;

/// What the probe computes, on the CPU.
fn cpu(q: &Query) -> [u32; 7] {
    let s = SobolSampler::new(q.seed, q.pass_index, q.pixel, q.spp);
    let mut st = s.stream(q.sample);
    st.dim = q.dim;
    let a = st.next();
    let b = st.next();
    let (x, y) = st.next2();
    let (key, index) = (s.key(), s.index(q.sample));
    [
        key,
        index,
        a.to_bits(),
        b.to_bits(),
        x.to_bits(),
        y.to_bits(),
        st.dim,
    ]
}

/// Runs the probe kernel over `queries` on the device.
fn gpu_values(ctx: &GpuContext, queries: &[Query]) -> Vec<[u32; 7]> {
    let source = [include_str!("../src/math/rng.wgsl"), &wgsl_library(), PROBE].join("\n");
    let bytes = common::run_probe(
        ctx,
        &source,
        "probe_sobol",
        bytemuck::cast_slice(queries),
        queries.len() as u32,
        (queries.len() * 28) as u64,
    );
    bytemuck::pod_collect_to_vec(&bytes)
}

/// Edge tuples (block and dimension-copy boundaries, wrapping passes, extreme keys) and random
/// ones (mostly within the crate's dimensions, some far past them).
fn queries() -> Vec<Query> {
    let mut qs = Vec::new();
    for seed in [0, u32::MAX] {
        for pixel in [0, 1, u32::MAX] {
            for pass_index in [0, 1, 1023, 1024, 65535, u32::MAX] {
                for spp in [1, 64, 1 << INDEX_BITS] {
                    for sample in [0, spp - 1] {
                        for dim in [0, 1, 2, 3, 255, 256, 1 << 31, u32::MAX - 1, u32::MAX] {
                            qs.push(Query {
                                seed,
                                pass_index,
                                pixel,
                                spp,
                                sample,
                                dim,
                            });
                        }
                    }
                }
            }
        }
    }
    let mut r = TestRng(0x50b0);
    let mut u = |n: u64| (r.next_u64() % n) as u32;
    for _ in 0..60_000 {
        let spp = [1, 4, 16, 64, 256, 1 + u(1000)][u(6) as usize];
        let pass_index = [u(16), u(5000), u(1 << 32)][u(3) as usize];
        let pixel = [u(1 << 22), u(1 << 32)][u(2) as usize];
        let dim = [u(16), u(1024), u(1 << 32), u32::MAX][u(4) as usize];
        qs.push(Query {
            seed: u(1 << 32),
            pass_index,
            pixel,
            spp,
            sample: u(spp as u64),
            dim,
        });
    }
    qs
}

#[test]
fn wgsl_sobol_equals_rust_sobol_bit_for_bit() {
    let Some(ctx) = gpu() else { return };
    let qs = queries();
    let got = gpu_values(&ctx, &qs);
    assert_eq!(got.len(), qs.len());
    let mut blocks = std::collections::BTreeSet::new();
    for (q, g) in qs.iter().zip(&got) {
        let want = cpu(q);
        assert_eq!(*g, want, "{q:?}: device {g:08x?}, CPU {want:08x?}");
        blocks.insert(want[1] >> INDEX_BITS);
    }
    // The inputs reach far past the first index block, and up to the last dimension (whose
    // stream wraps to dimension 0).
    assert!(blocks.len() > 100, "only {} index blocks", blocks.len());
    assert!(qs.iter().filter(|q| q.dim == u32::MAX).count() > 1000);
}

/// A 2-D test integrand and its exact integral over the unit square.
struct Integrand {
    name: &'static str,
    f: fn(f32, f32) -> f64,
    exact: f64,
}

const INTEGRANDS: [Integrand; 3] = [
    Integrand {
        name: "disc (r = 0.45)",
        f: |x, y| ((x - 0.5).powi(2) + (y - 0.5).powi(2) < 0.2025) as u8 as f64,
        exact: std::f64::consts::PI * 0.2025,
    },
    Integrand {
        name: "slanted edge",
        f: |x, y| (y > 0.3 + 0.4 * x) as u8 as f64,
        exact: 0.5,
    },
    Integrand {
        name: "smooth x y e^(x+y)",
        f: |x, y| (x as f64 * y as f64) * (x as f64 + y as f64).exp(),
        exact: 1.0,
    },
];

/// Where a sample's two dimensions come from.
#[derive(Clone, Copy, PartialEq)]
enum Source {
    /// The project's hash RNG, camera stream, index `pixel * n + sample` (today's camera pass).
    Hash,
    /// `gpu_photon::math::sobol` (independently scrambled dimension pairs).
    Pairs,
    /// The crate's own dimensions `d`, `d + 1` under one seed per pixel (the alternative the
    /// pairs replaced).
    CrateDims,
}

/// RMSE over `pixels` independent estimates of `g` at `n` samples each, with dimensions
/// `dims` from `src`.
fn rmse(g: &Integrand, n: u32, pixels: u32, src: Source, dims: (u32, u32)) -> f64 {
    use gpu_photon::math::rng::{draw_u32, path_key, to_unit, Stream};
    let seed = 2026;
    let mut sq = 0.0;
    for p in 0..pixels {
        let s = SobolSampler::new(seed, 0, p, n);
        let mut sum = 0.0;
        for i in 0..n {
            let (x, y) = match src {
                Source::Hash => {
                    let key = path_key(seed, Stream::Camera, 0, p * n + i);
                    (
                        to_unit(draw_u32(key, dims.0)),
                        to_unit(draw_u32(key, dims.1)),
                    )
                }
                Source::Pairs => (s.get(i, dims.0), s.get(i, dims.1)),
                Source::CrateDims => (
                    sobol_burley::sample(i, dims.0, s.key()),
                    sobol_burley::sample(i, dims.1, s.key()),
                ),
            };
            sum += (g.f)(x, y);
        }
        sq += (sum / n as f64 - g.exact).powi(2);
    }
    (sq / pixels as f64).sqrt()
}

/// The convergence gain the camera pass can expect (docs/sobol.md quotes this table; run with
/// `--nocapture` to see it). Asserts that the sampler never loses to the hash RNG and gains
/// at least 2.5x at 256 samples on every pair, which independent samples (ratio ~1) cannot.
#[test]
fn sobol_beats_the_hash_rng_on_2d_integrands() {
    let pixels = 4096;
    println!("| integrand | dims | spp | hash RMSE | Sobol pairs RMSE | gain | crate dims RMSE |");
    println!("|---|---|---|---|---|---|---|");
    for g in &INTEGRANDS {
        for dims in [(0, 1), (4, 5), (20, 21)] {
            for n in [16, 64, 256] {
                let h = rmse(g, n, pixels, Source::Hash, dims);
                let s = rmse(g, n, pixels, Source::Pairs, dims);
                let c = rmse(g, n, pixels, Source::CrateDims, dims);
                println!(
                    "| {} | {},{} | {n} | {h:.5} | {s:.5} | {:.1}x | {c:.5} |",
                    g.name,
                    dims.0,
                    dims.1,
                    h / s
                );
                assert!(
                    s < h,
                    "{}, dims {dims:?}, {n} spp: hash {h}, Sobol {s}",
                    g.name
                );
                if n == 256 {
                    assert!(
                        h > 2.5 * s,
                        "{}, dims {dims:?}: hash {h}, Sobol {s}",
                        g.name
                    );
                }
            }
        }
    }
}
