//! `render --passes P --slice I/N` (index from the command line or from a scheduler's
//! environment) and `merge`'s coverage check: missing passes are named and refused unless
//! `--partial`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_gpu-photon"));
    // The index must come from where each test says, not from the environment of a CI job
    // that happens to run as an array task.
    c.env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    c
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gpu-photon-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn render(out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    render_sized(out, (20, 16), extra, env)
}

fn render_sized(out: &Path, size: (u32, u32), extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = bin();
    c.args(["render", "scenes/cornell-box.toml", "-o"]).arg(out);
    c.args([
        "--width",
        &size.0.to_string(),
        "--height",
        &size.1.to_string(),
    ]);
    c.args(["--backend", "cpu", "--spp", "1", "--photons", "3000", "-q"]);
    c.envs(env.iter().copied());
    c.args(extra).output().unwrap()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Exit status 1 with `needle` in the message.
fn refused(out: &Output, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains(needle), "'{needle}' not in: {err}");
}

fn merge(inputs: &[&Path], out: &Path, extra: &[&str]) -> Output {
    bin()
        .arg("merge")
        .args(inputs)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn tag(path: &Path, key: &str) -> Option<String> {
    gpu_photon::render::film::read_tags(path)
        .unwrap()
        .into_iter()
        .find(|t| t.0 == key)
        .map(|t| t.1)
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

#[test]
fn slices_from_the_command_line_or_the_scheduler_merge_to_the_single_run() {
    let d = tmp("slice");
    // Several 64x64 tiles in the EXR, so their order in the file counts too.
    let big = (200, 150);
    let whole = d.join("whole.exr");
    ok(&render_sized(&whole, big, &["--passes", "3"], &[]));
    assert_eq!(tag(&whole, "gpu_photon.total_passes"), None);
    // One pass per slice: the merge adds the same numbers in the same order as the single
    // run, so the files are the same bytes. Each slice's index comes another way.
    let s: Vec<PathBuf> = (0..3).map(|i| d.join(format!("s{i}.exr"))).collect();
    ok(&render_sized(
        &s[0],
        big,
        &["--passes", "3", "--slice", "0/3"],
        &[],
    ));
    ok(&render_sized(
        &s[1],
        big,
        &["--passes", "3", "--slice", "/3"],
        &[("SLURM_ARRAY_TASK_ID", "1")],
    ));
    ok(&render_sized(
        &s[2],
        big,
        &["--passes", "3", "--slice", "/3"],
        &[("JOB_COMPLETION_INDEX", "2")],
    ));
    for (i, p) in s.iter().enumerate() {
        assert_eq!(
            tag(p, "gpu_photon.pass_range"),
            Some(format!("{i}..{}", i + 1))
        );
        assert_eq!(tag(p, "gpu_photon.total_passes").as_deref(), Some("3"));
    }
    let m = d.join("m.exr");
    ok(&merge(&[&s[2], &s[0], &s[1]], &m, &[]));
    assert!(
        bytes(&m) == bytes(&whole),
        "merged slices differ from the single run"
    );
    // A slice of all the passes is the whole render, the same bytes.
    let all = d.join("all.exr");
    ok(&render_sized(
        &all,
        big,
        &["--passes", "3", "--slice", "0/1"],
        &[],
    ));
    assert!(bytes(&all) == bytes(&whole));
    // Uneven slices: 5 passes in 2 slices are 0..3 and 3..5, and merge to the single run
    // up to the f32 rounding of each slice's mean.
    let (a, b, w5) = (d.join("a.exr"), d.join("b.exr"), d.join("w5.exr"));
    ok(&render(&a, &["--passes", "5", "--slice", "0/2"], &[]));
    ok(&render(&b, &["--passes", "5", "--slice", "1/2"], &[]));
    ok(&render(&w5, &["--passes", "5"], &[]));
    assert_eq!(tag(&a, "gpu_photon.pass_range").as_deref(), Some("0..3"));
    assert_eq!(tag(&b, "gpu_photon.pass_range").as_deref(), Some("3..5"));
    let m5 = d.join("m5.exr");
    ok(&merge(&[&a, &b], &m5, &[]));
    assert_eq!(tag(&m5, "gpu_photon.pass_range").as_deref(), Some("0..5"));
    assert_eq!(tag(&m5, "gpu_photon.total_passes"), None);
    let (mi, wi) = (
        gpu_photon::Image::read(&m5).unwrap(),
        gpu_photon::Image::read(&w5).unwrap(),
    );
    for (p, q) in mi.pixels.iter().zip(&wi.pixels) {
        for c in 0..3 {
            assert!(
                (p[c] - q[c]).abs() <= 1e-6 * q[c].abs().max(1e-3),
                "{p:?} {q:?}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_slices_are_refused_with_their_reason() {
    let d = tmp("badslice");
    let x = d.join("x.exr");
    refused(
        &render(&x, &["--passes", "4", "--slice", "/4"], &[]),
        "SLURM_ARRAY_TASK_ID",
    );
    refused(
        &render(&x, &["--passes", "4", "--slice", "4/4"], &[]),
        "--array=0-3",
    );
    refused(
        &render(
            &x,
            &["--passes", "4", "--slice", "/4"],
            &[("SLURM_ARRAY_TASK_ID", "7")],
        ),
        "must be below",
    );
    refused(
        &render(
            &x,
            &["--passes", "4", "--slice", "/4"],
            &[("JOB_COMPLETION_INDEX", "one")],
        ),
        "JOB_COMPLETION_INDEX='one'",
    );
    refused(
        &render(&x, &["--passes", "2", "--slice", "0/3"], &[]),
        "at most 2",
    );
    refused(
        &render(&x, &["--slice", "0/3"], &[]),
        "--slice needs --passes",
    );
    let parse = render(&x, &["--passes", "4", "--slice", "2"], &[]);
    assert_eq!(parse.status.code(), Some(2), "clap's usage error");
    assert!(!x.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn merge_names_missing_passes_and_partial_writes_a_preview() {
    let d = tmp("coverage");
    let s: Vec<PathBuf> = (0..4).map(|i| d.join(format!("s{i}.exr"))).collect();
    for (i, p) in s.iter().enumerate() {
        ok(&render(
            p,
            &["--passes", "8", "--slice", &format!("{i}/4")],
            &[],
        ));
    }
    let out = d.join("m.exr");
    // Slices 1 and 3 are missing: passes 2..4 and 6..8.
    refused(&merge(&[&s[0], &s[2]], &out, &[]), "passes 2..4,6..8");
    assert!(!out.exists(), "a refused merge writes nothing");
    // The first slice is missing.
    refused(&merge(&[&s[1], &s[2], &s[3]], &out, &[]), "passes 0..2 of");
    let partial = d.join("partial.exr");
    let o = merge(&[&s[0], &s[2]], &partial, &["--partial"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("2..4,6..8 missing"));
    assert_eq!(
        tag(&partial, "gpu_photon.pass_range").as_deref(),
        Some("0..2,4..6")
    );
    assert_eq!(tag(&partial, "gpu_photon.passes").as_deref(), Some("4"));
    assert_eq!(
        tag(&partial, "gpu_photon.total_passes").as_deref(),
        Some("8")
    );
    // The preview is the pass-weighted mean of what is there.
    let img = |p: &Path| gpu_photon::Image::read(p).unwrap();
    let (p0, p2, pm) = (img(&s[0]), img(&s[2]), img(&partial));
    for i in 0..pm.pixels.len() {
        for c in 0..3 {
            let want = (p0.pixels[i][c] as f64 + p2.pixels[i][c] as f64) / 2.0;
            assert!((pm.pixels[i][c] as f64 - want).abs() <= 1e-6 * want.abs().max(1e-3));
        }
    }
    // The preview merges with the slices it lacked into the whole render.
    ok(&merge(&[&partial, &s[1], &s[3]], &out, &[]));
    assert_eq!(tag(&out, "gpu_photon.pass_range").as_deref(), Some("0..8"));
    assert_eq!(tag(&out, "gpu_photon.total_passes"), None);
    // A slice of a render of another pass count is refused.
    let other = d.join("other.exr");
    ok(&render(&other, &["--passes", "9", "--slice", "1/4"], &[]));
    refused(
        &merge(&[&s[0], &other], &d.join("o.exr"), &["--partial"]),
        "render of 9 passes",
    );
    // Old-style --pass-range slices record no total: only the gaps between them are missing.
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    ok(&render(&a, &["--pass-range", "0..2"], &[]));
    ok(&render(&b, &["--pass-range", "3..5"], &[]));
    assert_eq!(tag(&a, "gpu_photon.total_passes"), None);
    refused(
        &merge(&[&a, &b], &d.join("ab.exr"), &[]),
        "passes 2..3 between",
    );
    ok(&merge(&[&a, &b], &d.join("ab.exr"), &["--partial"]));
    let _ = std::fs::remove_dir_all(&d);
}
