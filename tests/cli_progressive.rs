//! The progressive command line: slices and `merge`, Ctrl-C.

mod common;

use std::path::Path;
use std::process::Command;

/// The small caustics render every test here runs, with `extra` flags, writing `out`.
fn render_command(out: &Path, extra: &[&str]) -> Command {
    let mut c = common::bin();
    c.args(["render", "scenes/cornell-caustics.toml", "-o"])
        .arg(out);
    c.args([
        "--backend",
        "cpu",
        "--width",
        "24",
        "--height",
        "24",
        "--spp",
        "1",
        "--photons",
        "5000",
        "--caustic-photons",
        "2000",
        "-q",
    ]);
    c.args(extra);
    c
}

fn render(out: &Path, extra: &[&str]) -> std::process::Output {
    render_command(out, extra).output().unwrap()
}

fn tag(path: &Path, key: &str) -> Option<String> {
    gpu_photon::render::film::read_tags(path)
        .unwrap()
        .into_iter()
        .find(|t| t.0 == key)
        .map(|t| t.1)
}

#[test]
fn slices_merge_to_the_single_run_and_bad_merges_are_refused() {
    let d = common::scratch("merge");
    let (a, b, c, whole, merged) = (
        d.join("a.exr"),
        d.join("b.exr"),
        d.join("c.exr"),
        d.join("whole.exr"),
        d.join("m.exr"),
    );
    assert!(render(&a, &["--pass-range", "0..2"]).status.success());
    assert!(render(&b, &["--pass-range", "2..5"]).status.success());
    assert!(render(&whole, &["--passes", "5"]).status.success());
    assert_eq!(tag(&a, "gpu_photon.pass_range").as_deref(), Some("0..2"));
    assert_eq!(tag(&whole, "gpu_photon.passes").as_deref(), Some("5"));
    let out = common::bin()
        .args(["merge"])
        .arg(&b)
        .arg(&a)
        .arg("-o")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        tag(&merged, "gpu_photon.pass_range").as_deref(),
        Some("0..5")
    );
    let (m, w) = (
        gpu_photon::Image::read(&merged).unwrap(),
        gpu_photon::Image::read(&whole).unwrap(),
    );
    for (p, q) in m.pixels.iter().zip(&w.pixels) {
        for ch in 0..3 {
            // Same passes, other float summation order.
            assert!(
                (p[ch] - q[ch]).abs() <= 1e-5 * q[ch].abs().max(1e-3),
                "{p:?} vs {q:?}"
            );
        }
    }
    // Overlapping slices are refused.
    let out = common::bin()
        .args(["merge"])
        .arg(&a)
        .arg(&whole)
        .arg("-o")
        .arg(d.join("x.exr"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("overlaps"));
    // Another seed is another render.
    assert!(render(&c, &["--pass-range", "5..6", "--seed", "9"])
        .status
        .success());
    let out = common::bin()
        .args(["merge"])
        .arg(&a)
        .arg(&c)
        .arg("-o")
        .arg(d.join("y.exr"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("other settings"));
    // A plain render is no slice.
    let plain = d.join("plain.exr");
    assert!(render(&plain, &[]).status.success());
    let out = common::bin()
        .args(["merge"])
        .arg(&a)
        .arg(&plain)
        .arg("-o")
        .arg(d.join("z.exr"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let _ = std::fs::remove_dir_all(&d);
}

/// Ctrl-C finishes the pass in flight and writes the mean of the passes done.
#[test]
fn interrupt_writes_the_passes_done() {
    let d = common::scratch("sigint");
    let out = d.join("i.exr");
    let mut c = common::bin();
    c.args(["render", "scenes/cornell-box.toml", "-o"])
        .arg(&out);
    c.args([
        "--backend",
        "cpu",
        "--width",
        "24",
        "--height",
        "24",
        "--spp",
        "1",
        "--photons",
        "5000",
        "--passes",
        "1000000",
        "-q",
    ]);
    let child = c.spawn().unwrap();
    // Let some passes finish, then interrupt.
    let start = std::time::Instant::now();
    while start.elapsed().as_secs_f64() < 2.0 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let result = child.wait_with_output().unwrap();
    assert!(result.status.success(), "exit {:?}", result.status);
    let passes: u32 = tag(&out, "gpu_photon.passes").unwrap().parse().unwrap();
    assert!(passes >= 1 && passes < 1_000_000, "{passes}");
    assert_eq!(gpu_photon::Image::read(&out).unwrap().non_finite(), 0);
    let _ = std::fs::remove_dir_all(&d);
}

/// `--time 1` without `--passes` renders passes until a second has gone, then stops: were
/// the budget ignored it would pass forever, so the test waits at most 120 s and then fails
/// (killing the render) instead of hanging.
#[test]
fn time_budget_stops_passes() {
    let d = common::scratch("time");
    let out = d.join("t.exr");
    let mut child = render_command(&out, &["--time", "1"]).spawn().unwrap();
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > std::time::Duration::from_secs(120) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("`render --time 1` was still rendering after 120 s: the time budget did not stop it");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    assert!(status.success(), "exit {status:?}");
    let passes: u32 = tag(&out, "gpu_photon.passes").unwrap().parse().unwrap();
    assert!(passes >= 1);
    let _ = std::fs::remove_dir_all(&d);
}

/// The default is progressive (the scene's `passes`, 4 when unset); `--passes 0` is one
/// classic pass; `--noise T` stops at the first even pass count whose estimated noise is at
/// most T, at most `--passes` of them; the estimate is printed.
#[test]
fn default_passes_classic_pass_and_noise_target() {
    let d = common::scratch("noise");
    let out = d.join("o.exr");
    let ok = |extra: &[&str]| {
        let o = render(&out, extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    // No flag: passes 0..4, recorded like any progressive render.
    ok(&[]);
    assert_eq!(tag(&out, "gpu_photon.pass_range").as_deref(), Some("0..4"));
    // One classic pass writes no pass range.
    ok(&["--passes", "0"]);
    assert_eq!(tag(&out, "gpu_photon.pass_range"), None);
    // A loose target: met at the first estimate (2 passes); an unreachable one runs
    // every pass allowed.
    ok(&["--noise", "10"]);
    assert_eq!(tag(&out, "gpu_photon.pass_range").as_deref(), Some("0..2"));
    ok(&["--noise", "1e-9", "--passes", "6"]);
    assert_eq!(tag(&out, "gpu_photon.pass_range").as_deref(), Some("0..6"));
    // The summary names the estimate.
    let o = common::bin()
        .args(["render", "scenes/cornell-box.toml", "-o"])
        .arg(&out)
        .args([
            "--backend",
            "cpu",
            "--width",
            "16",
            "--height",
            "16",
            "--spp",
            "1",
        ])
        .args(["--photons", "2000", "--passes", "2"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("estimated noise "), "{err}");
    let refused = render(&out, &["--passes", "0", "--noise", "0.1"]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&refused.stderr).contains("excludes --slice, --time and --noise")
    );
    std::fs::remove_dir_all(&d).unwrap();
}
