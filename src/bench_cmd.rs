//! `gpu-photon bench`: throughput of each backend, the speed-against-error ladder and the
//! progressive curve, printed and written as CSV and plots.

use crate::{print_warnings, BackendArg, BenchArgs};
use anyhow::{Context, Result};
use gpu_photon::{Image, Mode, RenderSettings, Scene};

pub(crate) fn run_bench(args: &BenchArgs) -> Result<()> {
    use gpu_photon::bench::{self, BenchBackends};
    if args.rays {
        return crate::bench_rays_cmd::run(args);
    }
    let scene = Scene::load(&args.scene)?;
    print_warnings(scene.warnings());
    let sizes = (args.photons, args.spp, args.width, args.height);
    let s = bench::bench_settings(&scene, (!args.default_render).then_some(sizes));
    let which = BenchBackends::of(args.backend.map(BackendArg::choice));
    let modes = match &args.modes {
        Some(list) => Mode::parse_list(list)?,
        None => vec![s.mode],
    };
    println!("{}", bench::heading(&args.scene, &s, args.runs));
    bench::media_memory(&scene)
        .iter()
        .for_each(|l| println!("{l}"));
    println!("{}", bench::Throughput::header());
    let results = bench::throughputs(&scene, &s, &which, args.runs, |r| match r {
        Ok(t) => println!("{t}"),
        Err(why) => eprintln!("gpu: skipped ({why})"),
    })?;
    let ran = which.only(results.iter().map(|t| t.kind).collect());
    if let Some(dir) = &args.out {
        let reference = match &args.reference {
            Some(r) => r.clone(),
            None => {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("creating {}", dir.display()))?;
                let path = dir.join("reference.exr");
                println!(
                    "no --reference: rendering one first with the CPU backend ({}) to {}",
                    bench::ladder::describe_reference(&bench::reference_settings(&scene)),
                    path.display()
                );
                bench::ladder::render_reference(&scene, &path)?;
                path
            }
        };
        ladder_bench(&scene, &args.scene, &s, &ran, &modes, &reference, dir)?;
    }
    if let (Some(reference), Some(passes)) = (&args.reference, args.passes) {
        curve_bench(&scene, &s, &ran, reference, passes, args.out.as_deref())?;
    }
    bench::phase_table(&results)
        .iter()
        .for_each(|l| println!("{l}"));
    if let [cpu, gpu] = &results[..] {
        println!("{}", bench::ratios(cpu, gpu));
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&json(args, &s, &results))?;
        std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// What `bench --json` writes: the scene and sizes, each adapter wgpu finds, and each
/// backend's medians (`bench::Throughput`, phases and kernels in seconds).
fn json(
    args: &BenchArgs,
    s: &RenderSettings,
    results: &[gpu_photon::bench::Throughput],
) -> serde_json::Value {
    use gpu_photon::bench::backend_name;
    let seconds = |v: &[(&str, f64)]| -> serde_json::Map<String, serde_json::Value> {
        v.iter()
            .map(|(k, t)| (k.to_string(), (*t).into()))
            .collect()
    };
    let results: Vec<_> = results
        .iter()
        .map(|t| {
            serde_json::json!({
                "backend": backend_name(t.kind),
                "device": t.backend,
                "photon_paths_per_s": t.paths_per_s,
                "map_build_s": t.build_s,
                "gather_s_per_mpix_sample": t.gather_s_per_mpix_sample,
                "camera_samples_per_s": 1e6 / t.gather_s_per_mpix_sample,
                "total_s": t.total_s,
                "phases_s": seconds(&t.phases),
                "kernels_s": seconds(&t.kernels),
            })
        })
        .collect();
    serde_json::json!({
        "scene": args.scene.display().to_string(),
        "runs": args.runs,
        "settings": {
            "photons": s.photons,
            "caustic_photons": s.caustic_photons,
            "spp": s.spp,
            "width": s.width,
            "height": s.height,
            "mode": format!("{:?}", s.mode),
        },
        "adapters": gpu_photon::adapters(),
        "results": results,
    })
}

/// The speed-against-error ladder: every rung on every backend, as DIR/bench.csv and a
/// log-log plot DIR/bench.png.
fn ladder_bench(
    scene: &Scene,
    scene_path: &std::path::Path,
    s: &RenderSettings,
    which: &gpu_photon::bench::BenchBackends,
    modes: &[Mode],
    reference: &std::path::Path,
    dir: &std::path::Path,
) -> Result<()> {
    use gpu_photon::bench::{ladder, ladder_csv, plot, plot_title, LadderRow, LADDER};
    let reference = Image::read(reference)?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    println!(
        "speed against error ({}x{}, the reference's size):",
        reference.width, reference.height
    );
    println!("{}", LadderRow::header());
    let rows = ladder(scene, s, &which.backends, modes, &reference, &LADDER, |r| {
        println!("{r}")
    })?;
    let csv = dir.join("bench.csv");
    std::fs::write(&csv, ladder_csv(&rows))
        .with_context(|| format!("writing {}", csv.display()))?;
    println!("wrote {}", csv.display());
    let png = dir.join("bench.png");
    let title = plot_title(scene_path, reference.width, reference.height, modes);
    match plot(&rows, &png, &title) {
        Ok(()) => println!("wrote {}", png.display()),
        Err(e) => eprintln!("warning: no plot: {e}"),
    }
    Ok(())
}

/// Error against the reference after 1, 2, 4, ... passes, with the wall time, per backend.
fn curve_bench(
    scene: &Scene,
    s: &RenderSettings,
    which: &gpu_photon::bench::BenchBackends,
    reference: &std::path::Path,
    passes: u32,
    out: Option<&std::path::Path>,
) -> Result<()> {
    let peer = gpu_photon::bench::PeerCurve::beside(reference)?;
    let reference = Image::read(reference)?;
    println!("progressive curve against the reference ({passes} passes):");
    println!("{}", gpu_photon::bench::CurvePoint::header());
    let points = gpu_photon::bench::progressive_curve(
        scene,
        s,
        which,
        &reference,
        passes,
        |p| println!("{p}"),
        |why| eprintln!("gpu: skipped ({why})"),
    )?;
    if let Some(peer) = peer {
        print_peer(&peer, &points);
    }
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join("progressive.csv");
        std::fs::write(&path, gpu_photon::bench::curve_csv(&points))
            .with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The peer's recorded curve, and each backend's last point against it at equal RMSE.
fn print_peer(peer: &gpu_photon::bench::PeerCurve, points: &[gpu_photon::bench::CurvePoint]) {
    println!(
        "peer: {} as recorded in {} (its own run, not this one):",
        peer.renderer,
        peer.path.display()
    );
    for p in &peer.points {
        println!(
            "  {:>6} spp {:>9.2} s  rmse {:.5}",
            p.spp, p.seconds, p.rmse
        );
    }
    println!(
        "at equal RMSE (the reference's own noise, {:.5}, taken out of both):",
        peer.reference_noise
    );
    let mut last: Vec<&gpu_photon::bench::CurvePoint> = Vec::new();
    for p in points {
        match last.iter_mut().find(|q| q.backend == p.backend) {
            Some(q) => *q = p,
            None => last.push(p),
        }
    }
    for p in last {
        match peer.seconds_at(p.rmse) {
            Some(t) => println!(
                "  {} after {} passes: {:.2} s, rmse {:.5}; the peer needs {:.2} s: {:.2}x",
                p.backend,
                p.passes,
                p.seconds,
                p.rmse,
                t,
                t / p.seconds
            ),
            None => println!(
                "  {} after {} passes: rmse {:.5} is within the reference's noise",
                p.backend, p.passes, p.rmse
            ),
        }
    }
}
