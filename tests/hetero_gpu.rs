//! Heterogeneous media on the GPU backend (issue 41) against their CPU twins, on the same
//! inputs and the same random-number streams: the extinction and scattering lookups
//! (a rotated, scaled three-channel grid filtered trilinearly, a one-channel albedo grid
//! filtered by nearest voxel) at points in and around the box, the majorant grid's DDA walk
//! (the cells a ray crosses and the majorant's optical depth over them), ratio tracking's
//! transmittance and delta tracking's free flights. The streams are the CPU's, so the
//! estimates are the CPU's case by case; a logarithm or lookup a few ulps apart may flip a
//! rare decision, so at most 1% of cases may differ, and the means over every case must
//! agree within four standard errors. The camera side (stage 3) likewise: single
//! scattering (equiangular points towards the point light, free-flight points for the
//! directional light and the environment), the final-gather rays' four point estimates and
//! the beam estimate over one replayed ratio-tracking walk. Skips
//! without a device (CI has lavapipe).

mod common;
mod probes;

use common::{gpu, vol_file as vol};
use glam::Vec3;
use gpu_photon::bvh::CpuBvh;
use gpu_photon::importers::mitsuba::import;
use gpu_photon::integrators::cpu::media::transmittance;
use gpu_photon::integrators::cpu::volume_map::VolumeMap;
use gpu_photon::integrators::photon::{BeamPhotons, Photon};
use gpu_photon::math::rng::{Rng, Stream};
use gpu_photon::media::heterogeneous::Heterogeneous;
use gpu_photon::media::MediumKind;
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;
use probes::media::{hetero, HeteroCase, HeteroSample};
use std::path::Path;

/// A sparse, lumpy grid in a rotated and scaled box, with a coarser albedo grid.
fn scene(dir: &Path) -> Scene {
    let mut rng = Rng::new(11, Stream::Photon, 0, 0);
    let values: Vec<f32> = (0..12 * 10 * 8 * 3)
        .map(|_| match rng.next() < 0.3 {
            true => rng.next() * 6.0,
            false => 0.0,
        })
        .collect();
    std::fs::write(dir.join("sigma.vol"), vol([12, 10, 8], 3, |i| values[i])).unwrap();
    std::fs::write(
        dir.join("albedo.vol"),
        vol([3, 4, 2], 1, |i| 0.3 + 0.025 * i as f32),
    )
    .unwrap();
    let to_world = r#"<transform name="to_world"><scale x="2" y="1.5" z="1"/><rotate x="1" y="2" z="0.5" angle="35"/><translate x="-1" y="-0.5" z="-0.4"/></transform>"#;
    let xml = format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film>
<transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
<medium type="heterogeneous" id="smoke">
<volume name="sigma_t" type="gridvolume"><string name="filename" value="sigma.vol"/>{to_world}</volume>
<volume name="albedo" type="gridvolume"><string name="filename" value="albedo.vol"/><string name="filter_type" value="nearest"/>{to_world}</volume>
<float name="scale" value="1.5"/>
</medium>
<shape type="cube"><bsdf type="null"/><ref name="interior" id="smoke"/><transform name="to_world"><scale value="3"/></transform></shape>
<emitter type="point"><point name="position" x="0" y="4" z="0"/><rgb name="intensity" value="1"/></emitter>
<emitter type="directional"><vector name="direction" x="0.3" y="-1" z="0.2"/><rgb name="irradiance" value="2"/></emitter>
<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
</scene>
"#
    );
    import(&xml, "hetero.xml", dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .scene
}

fn medium(scene: &Scene) -> &Heterogeneous {
    match &scene.media[0].kind {
        MediumKind::Heterogeneous(h) => h,
        MediumKind::Homogeneous => panic!("the scene's medium is homogeneous"),
    }
}

/// Random rays from around the box through it, with random lengths (some ending inside).
fn cases(h: &Heterogeneous, n: u32) -> Vec<HeteroCase> {
    let (lo, hi) = (h.sigma_t.lo, h.sigma_t.hi);
    let mut rng = Rng::new(3, Stream::Camera, 0, 0);
    let mut point = |pad: f32| {
        let u = Vec3::new(rng.next(), rng.next(), rng.next());
        lo - Vec3::splat(pad) + (hi - lo + Vec3::splat(2.0 * pad)) * u
    };
    (0..n)
        .map(|i| {
            let o = point(0.3);
            let d = (point(0.0) - o).normalize();
            let t = match i % 3 {
                0 => 3.0e38,
                _ => 0.5 + 2.0 * (i % 7) as f32 / 7.0,
            };
            HeteroCase {
                o: o.to_array(),
                d: d.to_array(),
                t,
                seed: 5 + i % 4,
            }
        })
        .collect()
}

/// The CPU's answers for one case, as the probe gives them.
fn cpu(h: &Heterogeneous, c: &HeteroCase, i: u32) -> HeteroSample {
    let (o, d) = (Vec3::from(c.o), Vec3::from(c.d));
    let tr = h.transmittance(o, d, c.t, &mut Rng::new(c.seed, Stream::Photon, 0, i));
    let f = h.sample_flight(o, d, c.t, &mut Rng::new(c.seed, Stream::Caustic, 0, i));
    let inv = d.recip();
    let (a, b) = ((h.sigma_t.lo - o) * inv, (h.sigma_t.hi - o) * inv);
    let (t0, t1) = (
        a.min(b).max_element().max(0.0),
        a.max(b).min_element().min(c.t),
    );
    let (mut cells, mut depth) = (0, 0.0);
    if t0 < t1 {
        h.majorants.walk(o, d, t0, t1, |ta, tb, mu| {
            cells += 1;
            depth += (tb - ta) * mu;
            true
        });
    }
    HeteroSample {
        sigma_t: h.sigma_t_at(o).to_array(),
        sigma_s: h.sigma_s_at(o).to_array(),
        transmittance: tr.to_array(),
        flight: (f.weight.to_array(), f.t, f.in_medium),
        walk: (cells, depth, false),
    }
}

fn close(a: [f32; 3], b: [f32; 3], rel: f32) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= rel * a[k].abs().max(b[k].abs()) + 1e-6)
}

#[test]
fn lookup_walk_and_tracking_are_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let dir = common::scratch("hetero-gpu");
    let scene = scene(&dir);
    let h = medium(&scene);
    assert!(h.majorants.cell_count() > 1, "the walk must cross cells");
    let n = 4000;
    let cases = cases(h, n);
    let device = hetero(&ctx, &scene, &cases).expect("the probe runs");
    let (mut tr_off, mut flight_off) = (0, 0);
    let (mut sum_gpu, mut sum_cpu, mut sum2) = ([0f64; 3], [0f64; 3], [0f64; 3]);
    let (mut events, mut inside) = (0, 0);
    for (i, (c, g)) in cases.iter().zip(&device).enumerate() {
        let want = cpu(h, c, i as u32);
        // Deterministic: the lookups and the walk, case by case.
        assert!(
            close(g.sigma_t, want.sigma_t, 1e-5) && close(g.sigma_s, want.sigma_s, 1e-5),
            "case {i} {c:?}: lookups {g:?} vs {want:?}"
        );
        assert_eq!(g.walk.0, want.walk.0, "case {i} {c:?}: cells walked");
        assert!(!g.walk.2, "case {i}: the walk ran out");
        assert!(
            (g.walk.1 - want.walk.1).abs() <= 1e-4 * want.walk.1.max(1.0),
            "case {i} {c:?}: majorant depth {} vs {}",
            g.walk.1,
            want.walk.1
        );
        inside += (want.sigma_t.iter().sum::<f32>() > 0.0) as u32;
        // The same streams: the same estimates, but for rare flipped decisions.
        tr_off += !close(g.transmittance, want.transmittance, 1e-4) as u32;
        let (fg, fc) = (g.flight, want.flight);
        let same_flight = fg.2 == fc.2
            && (fg.1 - fc.1).abs() <= 1e-4 * fc.1.abs().max(1.0)
            && close(fg.0, fc.0, 1e-4);
        flight_off += !same_flight as u32;
        events += fc.2 as u32;
        for k in 0..3 {
            let (a, b) = (g.transmittance[k] as f64, want.transmittance[k] as f64);
            sum_gpu[k] += a;
            sum_cpu[k] += b;
            sum2[k] += b * b;
        }
    }
    assert!(inside > n / 10, "only {inside} points inside the medium");
    assert!(
        events > n / 10 && events < 9 * n / 10,
        "{events} events of {n}"
    );
    assert!(tr_off <= n / 100, "{tr_off} of {n} transmittances differ");
    assert!(flight_off <= n / 100, "{flight_off} of {n} flights differ");
    for k in 0..3 {
        let nf = n as f64;
        let sd = ((sum2[k] / nf - (sum_cpu[k] / nf).powi(2)).max(0.0) / nf).sqrt();
        let (a, b) = (sum_gpu[k] / nf, sum_cpu[k] / nf);
        assert!(
            (a - b).abs() <= 4.0 * sd + 1e-6,
            "channel {k}: {a} vs {b} (sd {sd})"
        );
    }
    eprintln!(
        "{n} cases: {inside} inside, {events} events; {tr_off} transmittances and \
         {flight_off} flights differ"
    );
}

/// The shadow walk (`shadow_transmittance`, through `medium_transmittance_along`) from points
/// in the smoke's null cube, crossing its boundary or ending inside: the CPU's
/// `cpu::media::transmittance` on the same stream, case by case but for rare flipped
/// decisions.
#[test]
fn shadow_walk_through_the_grid_is_the_cpus() {
    let Some(ctx) = gpu() else { return };
    let dir = common::scratch("hetero-gpu-shadow");
    let scene = scene(&dir);
    let h = medium(&scene);
    let bvh = CpuBvh::build(&scene);
    let seed = RenderSettings::default().seed;
    let cases: Vec<([f32; 3], [f32; 3], f32, u32)> =
        cases(h, 2000).iter().map(|c| (c.o, c.d, c.t, 0)).collect();
    let device = probes::media::transmittance(&ctx, &scene, &cases).expect("the probe runs");
    let (mut off, mut dark) = (0, 0);
    for (i, ((o, d, t, m), g)) in cases.iter().zip(&device).enumerate() {
        let t_max = if *t > 1e30 { f32::INFINITY } else { *t };
        let mut rng = Rng::new(seed, Stream::Photon, 0, i as u32);
        let want = transmittance(
            &scene,
            &bvh,
            Vec3::from(*o),
            Vec3::from(*d),
            t_max,
            *m,
            &mut rng,
        );
        off += !close(*g, want.to_array(), 1e-4) as u32;
        dark += (want.max_element() < 0.5) as u32;
    }
    assert!(off <= 20, "{off} of 2000 shadow walks differ");
    assert!(dark > 100 && dark < 1900, "{dark} of 2000 dark");
    eprintln!("2000 shadow walks: {dark} dark, {off} differ");
}

/// Volume photons of medium 0 spread through the grid's box (its corners `lo`, `hi`), depths
/// 0 to 3, some of them caustic, distinct powers and directions.
fn volume_photons(lo: Vec3, hi: Vec3, n: usize) -> Vec<Photon> {
    let mut rng = Rng::new(17, Stream::Photon, 0, 0);
    (0..n)
        .map(|i| {
            let u = Vec3::new(rng.next(), rng.next(), rng.next());
            let power = Vec3::new(1.0 + rng.next(), 0.5 + rng.next(), 0.2 + rng.next()) * 1e-3;
            let dir = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5 + 1e-3);
            let (depth, caustic) = ((i % 4) as u32, i % 7 == 0);
            Photon::in_medium(
                lo + (hi - lo) * u,
                power,
                dir.normalize(),
                0,
                i as u32,
                depth,
                caustic,
            )
        })
        .collect()
}

/// Whether `a` and `b` agree to `rel` of the larger's largest channel.
fn near(a: [f32; 3], b: [f32; 3], rel: f32) -> bool {
    let scale = a.iter().chain(&b).fold(0f32, |m, v| m.max(v.abs()));
    (0..3).all(|k| (a[k] - b[k]).abs() <= rel * scale + 1e-9)
}

/// The beam estimate through the grid (`beam` with a replayed walk, `probe_beam`): the
/// CPU's `VolumeMap::beam_through` over `Medium::transmittances` on the same stream, whole
/// segments and their parts beyond a split (`Transmittances::split`), case by case but for
/// rare flipped decisions.
#[test]
fn beam_through_the_grid_is_the_cpus() {
    use probes::media::{beam, BeamQuery};
    let Some(ctx) = gpu() else { return };
    let dir = common::scratch("hetero-gpu-beam");
    let scene = scene(&dir);
    let h = medium(&scene);
    let m = &scene.media[0];
    let (photons, r) = (volume_photons(h.sigma_t.lo, h.sigma_t.hi, 20_000), 0.12f32);
    let map = VolumeMap::build(photons.clone(), r);
    let n = 600;
    let queries: Vec<BeamQuery> = cases(h, n)
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let exit = map.exit(Vec3::from(c.o), Vec3::from(c.d));
            BeamQuery {
                o: c.o,
                d: c.d,
                t_max: c.t,
                medium: 0,
                photons: match i % 3 {
                    0 => BeamPhotons::All,
                    1 => BeamPhotons::SkipDirect,
                    _ => BeamPhotons::Caustic,
                },
                z: match i % 2 {
                    0 => 0.0,
                    _ => 0.5 * c.t.min(exit),
                },
            }
        })
        .collect();
    let got = beam(&ctx, &scene, &photons, r, &queries).expect("the probe runs");
    let seed = RenderSettings::default().seed;
    let (mut off, mut lit) = (0, 0);
    for (i, (q, g)) in queries.iter().zip(&got).enumerate() {
        let t = if q.t_max >= 3.0e38 {
            f32::INFINITY
        } else {
            q.t_max
        };
        let (o, d) = (Vec3::from(q.o), Vec3::from(q.d));
        let tr = m.transmittances(o, d, t, &mut Rng::new(seed, Stream::Photon, 0, i as u32));
        let (w, far) = tr.split(q.z);
        let want = w * map.beam_through((o + d * q.z, d, t - q.z), (m, 0), q.photons, &far);
        off += !near(*g, want.to_array(), 1e-4) as u32;
        lit += (want.max_element() > 0.0) as u32;
    }
    assert!(lit > n / 3, "only {lit} of {n} beams met photons");
    assert!(off <= n / 100, "{off} of {n} beams differ");
    eprintln!("{n} beams: {lit} lit, {off} differ");
}

/// A camera segment's estimates through the grid (`probe_segment`): single scattering
/// (`cpu::media::single_scattering`: equiangular points towards the point light, free
/// flights for the directional light and the environment) and a gather ray's four point
/// estimates (`Gatherer::gathered_in_medium`'s steps), on the CPU's streams, case by case but
/// for rare flipped decisions.
#[test]
fn camera_segments_through_the_grid_are_the_cpus() {
    use gpu_photon::integrators::cpu::media::single_scattering;
    use gpu_photon::lights::table::LightTable;
    let Some(ctx) = gpu() else { return };
    let dir = common::scratch("hetero-gpu-segment");
    let scene = scene(&dir);
    let h = medium(&scene);
    let m = &scene.media[0];
    let bvh = CpuBvh::build(&scene);
    let lights = LightTable::new(&scene);
    let settings = RenderSettings::default();
    let (photons, r) = (volume_photons(h.sigma_t.lo, h.sigma_t.hi, 20_000), 0.12f32);
    let map = VolumeMap::build(photons.clone(), r);
    let n = 800;
    let cases: Vec<([f32; 3], [f32; 3], f32)> =
        cases(h, n).iter().map(|c| (c.o, c.d, c.t)).collect();
    let device = probes::media::segments(&ctx, &scene, &settings, &photons, r, &cases)
        .expect("the probe runs");
    let seed = settings.seed;
    let (mut single_off, mut gathered_off, mut single_lit, mut gathered_lit) = (0, 0, 0, 0);
    for (i, ((o, d, t), g)) in cases.iter().zip(&device).enumerate() {
        let (o, d, i) = (Vec3::from(*o), Vec3::from(*d), i as u32);
        let t = if *t >= 3.0e38 { f32::INFINITY } else { *t };
        let mut rng = Rng::new(seed, Stream::Photon, 0, i);
        let samples = settings.shadow_samples;
        let single = single_scattering(&scene, &bvh, &lights, o, d, t, 0, samples, &mut rng);
        single_off += !near(g.single, single.to_array(), 1e-4) as u32;
        single_lit += (single.max_element() > 0.0) as u32;
        // Gatherer::gathered_in_medium.
        let mut rng = Rng::new(seed, Stream::Caustic, 0, i);
        let (uc, u) = (rng.next(), rng.next());
        let mut gathered = Vec3::ZERO;
        for k in 0..4 {
            let uk = (k as f32 + u) / 4.0;
            if let Some(p) = m.scatter_in_segment(o, d, (uc, uk), t, &mut rng) {
                gathered += p.tr_over_pdf * map.point(o + d * p.t, -d, m, 0);
            }
        }
        gathered /= 4.0;
        gathered_off += !near(g.gathered, gathered.to_array(), 1e-4) as u32;
        gathered_lit += (gathered.max_element() > 0.0) as u32;
    }
    eprintln!(
        "{n} segments: single scattering {single_lit} lit, {single_off} differ; gathered \
         {gathered_lit} lit, {gathered_off} differ"
    );
    assert!(single_lit > n / 3 && gathered_lit > n / 10);
    assert!(
        single_off <= n / 100,
        "{single_off} of {n} single scatterings differ"
    );
    assert!(
        gathered_off <= n / 100,
        "{gathered_off} of {n} gathered estimates differ"
    );
}
