//! `--backend auto` by measurement (`gpu_photon::render::calibration`): the first auto render on an
//! adapter times the calibration scene on both backends and keeps the times in the cache file;
//! later renders follow the stored times, whichever backend they favour. Run as processes
//! with their own `XDG_CACHE_HOME`. Needs an adapter (lavapipe in CI; elsewhere it skips).

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

fn render(cache: &Path, out: &Path) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
        .args([
            "render",
            "scenes/cornell-box.toml",
            "--backend",
            "auto",
            "--passes",
            "0",
        ])
        .args([
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "1",
            "--photons",
            "2000",
        ])
        .arg("-o")
        .arg(out)
        .env("XDG_CACHE_HOME", cache)
        .output()
        .unwrap()
}

/// The summary's backend: `cpu` or `gpu`.
fn backend_of(out: &Output) -> &'static str {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err
        .lines()
        .find(|l| l.contains(", backend "))
        .expect("summary line");
    if line.contains("backend gpu") {
        "gpu"
    } else {
        assert!(line.contains("backend cpu"), "{line}");
        "cpu"
    }
}

#[test]
fn auto_measures_once_then_follows_the_stored_times() {
    if common::gpu().is_none() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("gpu-photon-auto-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file: PathBuf = dir.join("gpu-photon").join("backend-calibration.tsv");
    let out = dir.join("o.exr");

    // First run: the calibration is measured and stored, and the choice follows it.
    let first = render(&dir, &out);
    let text = std::fs::read_to_string(&file).expect("the calibration is stored");
    let fields: Vec<&str> = text.lines().next().unwrap().split('\t').collect();
    let (key, cpu, gpu): (&str, f64, f64) = (
        fields[0],
        fields[1].parse().unwrap(),
        fields[2].parse().unwrap(),
    );
    assert!(cpu > 0.0 && cpu.is_finite() && gpu > 0.0, "{text}");
    assert!(key.contains(" threads"), "{key}");
    let faster = if gpu < cpu { "gpu" } else { "cpu" };
    assert_eq!(
        backend_of(&first),
        faster,
        "measured cpu {cpu} s, gpu {gpu} s"
    );
    eprintln!("calibration on this machine: cpu {cpu} s, gpu {gpu} s");

    // Stored times decide, without measuring again (the file keeps one line per decision).
    for (cpu, gpu, want) in [(1.0, 0.5, "gpu"), (0.5, 1.0, "cpu")] {
        std::fs::write(&file, format!("{key}\t{cpu}\t{gpu}\n")).unwrap();
        let run = render(&dir, &out);
        assert_eq!(backend_of(&run), want, "stored cpu {cpu} s, gpu {gpu} s");
        if want == "cpu" {
            let err = String::from_utf8_lossy(&run.stderr);
            assert!(err.contains("the CPU backend is faster"), "{err}");
            assert!(err.contains(&file.display().to_string()), "{err}");
        }
        let lines = std::fs::read_to_string(&file).unwrap().lines().count();
        assert_eq!(lines, 1, "measured again although a calibration was stored");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
