//! Oracle tests: each GPU kernel against the Rust function it mirrors, on the same input.
//! They run on lavapipe in CI (a missing adapter fails there; elsewhere it skips).

mod common;
mod probes;

use common::{gpu, TestRng};
use glam::Vec3;
use gpu_photon::integrators::cpu::photon_map::PhotonMap;
use gpu_photon::integrators::estimate;
use gpu_photon::integrators::gpu::grid::{cell_hash, cell_of, counting_sort};

use gpu_photon::integrators::photon::Photon;
use gpu_photon::math::rng::{draw_u32, path_key, pcg_hash, to_unit, Stream};
use gpu_photon::settings::Filter;

#[test]
fn wgsl_rng_equals_rust_rng_bit_for_bit() {
    let Some(ctx) = gpu() else { return };
    let n = 4096;
    let (seed, pass) = (0xdead_beef, 7);
    let got = probes::rng_values(&ctx, seed, pass, n).unwrap();
    let streams = [
        Stream::Photon,
        Stream::Caustic,
        Stream::Camera,
        Stream::Pilot,
    ];
    for (i, g) in got.iter().enumerate() {
        let i = i as u32;
        let key = path_key(seed, streams[(i % 4) as usize], pass, i);
        let bits = draw_u32(key, i % 9);
        let want = [key, bits, to_unit(bits).to_bits(), pcg_hash(i)];
        assert_eq!(*g, want, "value {i}");
    }
}

/// Photons on two planes and in a denser cluster (`cluster` wide), with distinct powers (so
/// a mix-up shows).
fn test_photons(n: usize, seed: u64, cluster: f32) -> Vec<Photon> {
    let mut r = TestRng(seed);
    (0..n)
        .map(|i| {
            let (p, n) = match i % 3 {
                0 => (
                    Vec3::new(r.f32() * 2.0 - 1.0, 0.0, r.f32() * 2.0 - 1.0),
                    Vec3::Y,
                ),
                1 => (
                    Vec3::new(r.f32() * 2.0 - 1.0, r.f32() * 2.0 - 1.0, -1.0),
                    Vec3::Z,
                ),
                _ => (
                    Vec3::new(0.3 + cluster * r.f32(), 0.0, -0.2 + cluster * r.f32()),
                    Vec3::Y,
                ),
            };
            let dir = Vec3::new(r.f32() - 0.5, -1.0, r.f32() - 0.5).normalize();
            let power = Vec3::new(1.0 + i as f32 * 1e-3, 2.0 + r.f32(), 0.5 + r.f32());
            Photon::new(p, power * 1e-3, dir, n, i as u32, (i % 4) as u32, false)
        })
        .collect()
}

#[test]
fn device_grid_equals_cpu_counting_sort() {
    let Some(ctx) = gpu() else { return };
    let photons = test_photons(50_000, 1, 0.05);
    let (cell_size, table) = (0.05, 1 << 14);
    let (starts, sorted) = probes::build_grid(&ctx, &photons, cell_size, table).unwrap();
    let keys: Vec<u32> = photons
        .iter()
        .map(|p| cell_hash(cell_of(p.position, cell_size), table))
        .collect();
    let (want_starts, want_order) = counting_sort(&keys, table);
    assert_eq!(starts, want_starts, "cell starts differ");
    // Within a cell the device order is unspecified: compare each cell's photons as a set.
    for c in 0..table as usize {
        let (a, b) = (want_starts[c] as usize, want_starts[c + 1] as usize);
        let mut got: Vec<(u32, u32)> = sorted[a..b].iter().map(|p| (p.id, p.flags)).collect();
        let mut want: Vec<(u32, u32)> = want_order[a..b]
            .iter()
            .map(|&i| (photons[i as usize].id, photons[i as usize].flags))
            .collect();
        got.sort_unstable();
        want.sort_unstable();
        assert_eq!(got, want, "cell {c}");
    }
    // Payloads travel with their keys.
    for p in &sorted {
        assert_eq!(*p, photons[p.id as usize]);
    }
}

#[test]
fn device_knn_estimate_equals_kd_tree() {
    let Some(ctx) = gpu() else { return };
    // The cluster holds 10x the planes' density: dense, but within the visit bound.
    let photons = test_photons(30_000, 2, 0.4);
    let map = PhotonMap::build(photons.clone());
    let mut r = TestRng(3);
    let mut queries = Vec::new();
    for i in 0..512 {
        let p = match i % 3 {
            0 => [r.f32() * 2.0 - 1.0, 0.0, r.f32() * 2.0 - 1.0],
            1 => [r.f32() * 2.0 - 1.0, r.f32() * 2.0 - 1.0, -1.0],
            _ => [0.32, 0.0, -0.18],
        };
        let n = if i % 3 == 1 {
            [0.0, 0.0, 1.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        queries.push((p, n));
    }
    for (k, radius, cell) in [
        (50u32, 0.2f32, 0.06f32),
        (100, 0.1, 0.1),
        (8, 0.5, 0.1),
        (200, 0.05, 0.02),
    ] {
        let (got, stats) = probes::estimate(&ctx, &photons, &queries, k, radius, cell).unwrap();
        assert_eq!(
            stats[..3],
            [0, 0, 0],
            "k={k} r={radius}: a bound was hit (photon overflow, loop budget, truncated search)"
        );
        let mut found = Vec::new();
        for (qi, ((p, n), (l, count))) in queries.iter().zip(&got).enumerate() {
            map.nearest(*p, k as usize, radius * radius, &mut found);
            assert_eq!(
                *count as usize,
                found.len(),
                "k={k} r={radius} query {qi}: neighbour count"
            );
            let what = format!("k={k} r={radius} query {qi}");
            assert_estimate_equals_cpu(*l, &found, k as usize, radius, *p, *n, &what);
        }
    }
}

/// The device's estimate `got` (f = 1, disc filter) equals the library's estimate from the
/// kd-tree's neighbours `found` of query `(p, n)`, within 1e-4 relative per channel.
fn assert_estimate_equals_cpu(
    got: [f32; 3],
    found: &[(f32, &Photon)],
    k: usize,
    radius: f32,
    p: [f32; 3],
    n: [f32; 3],
    what: &str,
) {
    let want = estimate::radiance(
        found,
        k,
        radius * radius,
        Filter::Disc,
        Vec3::from(p),
        Vec3::from(n),
        |_| Vec3::ONE,
    );
    for c in 0..3 {
        let tol = 1e-4 * want[c].abs().max(1e-6);
        assert!(
            (got[c] - want[c]).abs() <= tol,
            "{what} channel {c}: gpu {} cpu {}",
            got[c],
            want[c]
        );
    }
}

/// A search that would exceed the visit bound is cut and counted, never silently wrong.
#[test]
fn truncated_searches_are_counted() {
    let Some(ctx) = gpu() else { return };
    // 10,000 photons in one 0.05-wide cluster, searched with 0.2-wide cells: one cell holds
    // more photons than an estimate may visit.
    let photons = test_photons(30_000, 2, 0.05);
    let queries = vec![([0.32, 0.0, -0.18], [0.0, 1.0, 0.0]); 8];
    let (_, stats) = probes::estimate(&ctx, &photons, &queries, 50, 0.2, 0.2).unwrap();
    assert!(
        stats[2] > 0,
        "expected truncated searches to be counted: {stats:?}"
    );
}

/// The device's fixed-radius estimate (K = 0, the progressive passes' estimate, summed in
/// fixed point) equals the kd-tree's sum over every photon within the radius: the same count
/// and radiance within 1e-4 relative (the fixed point rounds each term to 2^-25 of the
/// largest, far below that).
#[test]
fn device_fixed_radius_estimate_equals_kd_tree() {
    let Some(ctx) = gpu() else { return };
    let photons = test_photons(30_000, 4, 0.8);
    let map = PhotonMap::build(photons.clone());
    let mut r = TestRng(5);
    let queries: Vec<([f32; 3], [f32; 3])> = (0..384)
        .map(|i| match i % 3 {
            0 => (
                [r.f32() * 2.0 - 1.0, 0.0, r.f32() * 2.0 - 1.0],
                [0.0, 1.0, 0.0],
            ),
            1 => (
                [r.f32() * 2.0 - 1.0, r.f32() * 2.0 - 1.0, -1.0],
                [0.0, 0.0, 1.0],
            ),
            _ => (
                [0.3 + 0.8 * r.f32(), 0.0, -0.2 + 0.8 * r.f32()],
                [0.0, 1.0, 0.0],
            ),
        })
        .collect();
    let mut found = Vec::new();
    let mut dense = 0;
    for (radius, cell) in [(0.05f32, 0.05f32), (0.1, 0.1), (0.15, 0.05)] {
        let (got, stats) = probes::estimate(&ctx, &photons, &queries, 0, radius, cell).unwrap();
        assert_eq!(stats[..3], [0, 0, 0], "r={radius}: a bound was hit");
        for (qi, ((p, n), (l, count))) in queries.iter().zip(&got).enumerate() {
            map.within(*p, radius * radius, &mut found);
            assert_eq!(*count as usize, found.len(), "r={radius} query {qi}: count");
            dense += usize::from(found.len() > 256);
            let what = format!("r={radius} query {qi}");
            assert_estimate_equals_cpu(*l, &found, usize::MAX, radius, *p, *n, &what);
        }
    }
    // Some queries must hold more photons than the K-nearest heap (256), the case the fixed
    // point was written for.
    assert!(dense > 0, "no query held more than 256 photons");
}

/// The device sizes a traced map's grid cells (`size_grid`, no read-back inside a pass) as
/// the host's `grid::cell_size_for` would from the photons actually stored.
#[test]
fn device_sizes_grid_cells_as_the_host_rule() {
    use gpu_photon::integrators::gpu::buffers::read_back;
    use gpu_photon::integrators::gpu::grid::cell_size_for;
    use gpu_photon::integrators::gpu::types::GpuMapParams;
    use gpu_photon::settings::RenderSettings;
    let Some(ctx) = gpu() else { return };
    let s = RenderSettings {
        width: 16,
        height: 16,
        spp: 1,
        photons: 20_000,
        ..Default::default()
    };
    let (run, _, report, _) = common::cornell_gpu_pass(ctx, &s);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = gpu_photon::importers::load(&root.join("scenes/cornell-box.toml")).unwrap();
    let global = run
        .map_cache
        .iter()
        .find(|m| m.params.is_caustic == 0 && m.params.paths > 0)
        .expect("the pass's global map");
    let bytes = std::mem::size_of::<GpuMapParams>() as u64;
    let device: Vec<GpuMapParams> = read_back(&run.ctx, &global.params_buf, bytes).unwrap();
    let stored = (report.stored[0] as u32).min(global.params.capacity);
    let want = cell_size_for(s.radius, s.k, stored, scene.storing_area(), 1.0);
    let got = device[0].cell_size;
    eprintln!(
        "stored {stored}, host's first guess {}, device {got}, host rule {want}",
        global.params.cell_size
    );
    assert!(
        (got / want - 1.0).abs() < 1e-5,
        "device {got} vs host {want}"
    );
    // The first guess (3 photons a path) was not what the trace stored: the device resized.
    assert!((global.params.cell_size / want - 1.0).abs() > 1e-3);
}
