//! `gpu-photon bench SCENE --rays`: ray throughput per kind and tracer, one thread, as a
//! table (and JSON with --json).

use crate::{print_warnings, BenchArgs};
use anyhow::{Context, Result};
use gpu_photon::bench::rays::{self, RayRate, Tracer};
use gpu_photon::Scene;
use std::time::Instant;

pub(crate) fn run(args: &BenchArgs) -> Result<()> {
    let loaded = Scene::load(&args.scene)?;
    print_warnings(loaded.warnings());
    let scene = match args.mesh {
        Some(n) => gpu_photon::bench::mesh::with_mesh(&loaded, n),
        None => (*loaded).clone(),
    };
    let (w, h) = (args.width, args.height);
    let t = Instant::now();
    let sets = rays::ray_sets(&scene, w, h, 1);
    println!(
        "{}{}: {} triangles, {} spheres; rays at {w}x{h} made in {:.2} s; one thread, \
         medians of {} rounds, Mrays/s",
        args.scene.display(),
        args.mesh
            .map_or(String::new(), |n| format!(" + a {n}-triangle mesh")),
        scene.triangles.len(),
        scene.spheres.len(),
        t.elapsed().as_secs_f64(),
        args.runs,
    );
    if matches!(args.backend, Some(crate::BackendArg::Gpu)) {
        return run_gpu(args, &scene, &sets);
    }
    let ours = rays::our_tracers(&scene, 3);
    let prims = (scene.triangles.len() + scene.spheres.len()).max(1) as f64;
    let mut builds: Vec<String> = Vec::new();
    let mut json_builds = serde_json::Map::new();
    let mut report = |name: &str, c: &rays::BuildCost| {
        // Embree's size is not asked for (0).
        let size = match c.bytes {
            0 => String::new(),
            b => format!(", {:.0} B/prim", b as f64 / prims),
        };
        builds.push(format!(
            "{name} {:.3} s ({:.3} s CPU){size}",
            c.wall_s, c.cpu_s
        ));
        let v = serde_json::json!({"wall_s": c.wall_s, "cpu_s": c.cpu_s, "bytes": c.bytes});
        json_builds.insert(name.to_string(), v);
    };
    report("binary", &ours[0].1);
    if let Some((_, c)) = ours.get(1) {
        report("wide", c);
    }
    #[allow(unused_mut)] // extended only with the embree feature
    let mut tracers: Vec<&dyn Tracer> = ours.iter().map(|(t, _)| t.as_ref()).collect();
    #[cfg(feature = "embree")]
    let embree = embree_tracers(&scene, &mut report);
    #[cfg(feature = "embree")]
    tracers.extend(embree.iter().map(|t| t as &dyn Tracer));
    println!("build: {}", builds.join("; "));
    let rates = rays::measure(&sets, &tracers, args.runs);
    print_table(&rates, &tracers);
    let extra = serde_json::json!({ "build": json_builds });
    write_json(args, &scene, &rates, extra)?;
    Ok(())
}

/// The GPU's walks: one row per ray kind (Mrays/s of the whole device), and JSON with
/// --json.
fn run_gpu(
    args: &BenchArgs,
    scene: &gpu_photon::scene::Scene,
    sets: &[rays::RaySet],
) -> Result<()> {
    use gpu_photon::bench::gpu_rays::{measure, GpuRays};
    use gpu_photon::integrators::gpu::context::GpuContext;
    let ctx = GpuContext::new()?;
    let t = Instant::now();
    let mut gpu = GpuRays::new(&ctx, scene)?;
    let device = ctx.describe();
    println!(
        "device: {device}; set-up {:.2} s; nodes: binary {:.1} MB, wide {:.1} MB; Mrays/s of the device, medians of {} dispatches",
        t.elapsed().as_secs_f64(),
        gpu.node_bytes[0] as f64 / 1e6,
        gpu.node_bytes[1] as f64 / 1e6,
        args.runs
    );
    let rates = measure(&mut gpu, sets, args.runs)?;
    println!(
        "{:<8} {:>8} {:>12} {:>12} {:>12} {:>10}",
        "kind", "rays", "gpu binary", "gpu wide", "wide/binary", "agree"
    );
    for pair in rates.chunks(2) {
        let (b, w) = (&pair[0], &pair[1]);
        println!(
            "{:<8} {:>8} {:>12.2} {:>12.2} {:>12.2} {:>9.2}%",
            b.kind.name(),
            b.rays,
            b.rays_per_s / 1e6,
            w.rays_per_s / 1e6,
            w.rays_per_s / b.rays_per_s,
            100.0 * w.agree as f64 / w.rays.max(1) as f64
        );
    }
    let extra = serde_json::json!({
        "device": device,
        "node_bytes": {"binary": gpu.node_bytes[0], "wide": gpu.node_bytes[1]},
    });
    write_json(args, scene, &rates, extra)?;
    Ok(())
}

/// With --json: the scene, the sizes and `rates` with the fields of `extra`, to the file.
fn write_json(
    args: &BenchArgs,
    scene: &gpu_photon::scene::Scene,
    rates: &[RayRate],
    extra: serde_json::Value,
) -> Result<()> {
    let Some(path) = &args.json else {
        return Ok(());
    };
    let rows: Vec<_> = rates
        .iter()
        .map(|r| {
            serde_json::json!({
                "tracer": r.tracer, "kind": r.kind.name(), "rays": r.rays,
                "rays_per_s": r.rays_per_s, "hits": r.hits, "agree": r.agree,
            })
        })
        .collect();
    let mut v = serde_json::json!({
        "scene": args.scene.display().to_string(),
        "mesh": args.mesh,
        "triangles": scene.triangles.len(),
        "spheres": scene.spheres.len(),
        "width": args.width, "height": args.height, "rounds": args.runs,
        "rates": rows,
    });
    if let (Some(v), serde_json::Value::Object(extra)) = (v.as_object_mut(), extra) {
        v.extend(extra);
    }
    let text = serde_json::to_string_pretty(&v)?;
    std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

#[cfg(feature = "embree")]
fn embree_tracers(
    scene: &gpu_photon::scene::Scene,
    report: &mut impl FnMut(&str, &rays::BuildCost),
) -> Vec<gpu_photon::bench::embree::EmbreeTracer> {
    use gpu_photon::bench::embree::{EmbreeTracer, Quality};
    let mut out = Vec::new();
    for q in [Quality::Medium, Quality::High] {
        let (e, cost) = rays::timed(3, || EmbreeTracer::new(scene, q), |_| 0);
        match e {
            Some(e) => {
                report(&e.name(), &cost);
                out.push(e);
            }
            None => eprintln!("warning: Embree failed to build the scene ({q:?})"),
        }
    }
    out
}

/// Rows per ray kind, a column per tracer (Mrays/s), then the best wide tracer over the
/// first Embree one.
fn print_table(rates: &[RayRate], tracers: &[&dyn Tracer]) {
    let names: Vec<String> = tracers.iter().map(|t| t.name()).collect();
    let mut head = format!("{:<8} {:>8}", "kind", "rays");
    for n in &names {
        head += &format!(" {n:>14}");
    }
    let embree = names.iter().position(|n| n.starts_with("embree"));
    if embree.is_some() {
        head += &format!(" {:>12} {:>10}", "wide/embree", "agree");
    }
    println!("{head}");
    for chunk in rates.chunks(names.len()) {
        let mut line = format!("{:<8} {:>8}", chunk[0].kind.name(), chunk[0].rays);
        for r in chunk {
            line += &format!(" {:>14.2}", r.rays_per_s / 1e6);
        }
        if let Some(e) = embree {
            let wide = (chunk.iter().filter(|r| r.tracer.starts_with("wide")))
                .map(|r| r.rays_per_s)
                .fold(0.0, f64::max);
            let agree = chunk[e].agree as f64 / chunk[e].rays.max(1) as f64;
            line += &format!(
                " {:>12.2} {:>9.2}%",
                wide / chunk[e].rays_per_s,
                100.0 * agree
            );
        }
        println!("{line}");
    }
}
