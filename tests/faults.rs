//! GPU faults, injected through wgpu's real paths (`GPU_PHOTON_FAULT`, `gpu::faults`): a lost
//! device, an allocation the device refuses, a submission the watchdog gives up on and a
//! shader that does not compile. Under `--backend gpu` each ends the render with exit status
//! 1 and one `error: GPU backend: ...` line; under `--backend auto` (with a calibration that
//! prefers the GPU) each gives one warning naming the same reason and the render finishes
//! on the CPU with the CPU's pixels. Never a panic, never a hang (each run has a deadline).
//! Needs an adapter (lavapipe in CI; elsewhere it skips).

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A two-pass 16x16 render of the Cornell box on `backend` into `out`, with `fault`
/// injected; its own calibration cache `cache`. Fails (killing it) after 120 s.
fn render(backend: &str, fault: Option<&str>, cache: &Path, out: &Path) -> Output {
    render_with(backend, fault, &[], cache, out)
}

/// [`render`] with more environment variables `env`.
fn render_with(
    backend: &str,
    fault: Option<&str>,
    env: &[(&str, &str)],
    cache: &Path,
    out: &Path,
) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_gpu-photon"));
    c.args(["render", "scenes/cornell-box.toml", "--backend", backend])
        .args(["--width", "16", "--height", "16", "--spp", "1"])
        .args(["--photons", "2000", "--passes", "2", "-o"])
        .arg(out)
        .env("XDG_CACHE_HOME", cache)
        .env_remove("GPU_PHOTON_FAULT")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if let Some(f) = fault {
        c.env("GPU_PHOTON_FAULT", f);
    }
    c.envs(env.iter().copied());
    let mut child = c.spawn().unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("{backend} render with fault {fault:?} still running after 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The reason each fault gives (the whole reason, or its start where it quotes wgpu).
const FAULTS: [(&str, &str, bool); 4] = [
    ("device-lost", "the device was lost (destroyed)", true),
    (
        "oom",
        "could not allocate the image accumulator (134217729 bytes): validation error: Buffer size 134217729 is greater than the maximum buffer size (134217728)",
        false,
    ),
    (
        "timeout",
        "the device did not finish its work within 0 s (the watchdog; GPU_PHOTON_WATCHDOG sets it): hung, or a pass far too large for it",
        true,
    ),
    (
        "shader",
        "pipeline creation failed: validation error: Shader 'gather (malformed)' parsing error: ",
        false,
    ),
];

/// Whether `reason` is what fault `(name, expected, exact)` should say. The accumulator's
/// size is lavapipe's largest buffer; another adapter names its own.
fn matches(reason: &str, expected: &str, exact: bool, max_buffer: u64) -> bool {
    let expected = expected
        .replace("134217729", &(max_buffer + 1).to_string())
        .replace("134217728", &max_buffer.to_string());
    if exact {
        reason == expected
    } else {
        reason.starts_with(&expected)
    }
}

#[test]
fn each_fault_ends_a_gpu_render_with_one_error() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let max_buffer = ctx.device.limits().max_buffer_size;
    let d = common::scratch("gpu");
    for (name, expected, exact) in FAULTS {
        let out = d.join(format!("{name}.exr"));
        let o = render("gpu", Some(name), &d, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{name}: {err}");
        let reason = lines[0]
            .strip_prefix("error: GPU backend: ")
            .unwrap_or_else(|| panic!("{name}: {err}"));
        assert!(
            matches(reason, expected, exact, max_buffer),
            "{name}: {err}"
        );
        assert!(!out.exists(), "{name} wrote an image");
    }
    // The shader's error says where in the source it is.
    let o = render("gpu", Some("shader"), &d, &d.join("s.exr"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.trim_end().ends_with(')') && err.contains("(wgsl:"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// A device lost in the second pass (after the first pass's submission, whose image was
/// read back), not the first: the same one error, no image (the passes done are not
/// written as if the render had finished).
#[test]
fn a_device_lost_in_a_later_pass_ends_the_render_with_one_error() {
    if common::gpu().is_none() {
        return;
    }
    let d = common::scratch("later");
    let out = d.join("later.exr");
    let env = [("GPU_PHOTON_FAULT_AFTER", "2")];
    let o = render_with("gpu", Some("device-lost"), &env, &d, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(
        err.trim_end(),
        "error: GPU backend: the device was lost (destroyed)"
    );
    assert!(!out.exists(), "wrote an image");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn each_fault_under_auto_falls_back_to_the_cpu_saying_so() {
    let Some(ctx) = common::gpu() else {
        return;
    };
    let max_buffer = ctx.device.limits().max_buffer_size;
    let d = common::scratch("auto");
    // A stored calibration in which the GPU is faster: auto picks it without measuring.
    let adapter = gpu_photon::integrators::gpu::preferred_adapter().unwrap();
    let file = d.join("gpu-photon").join("backend-calibration.tsv");
    let calibration = gpu_photon::render::calibration::Calibration {
        key: gpu_photon::render::calibration::key(&adapter.name, &adapter.driver),
        cpu_seconds: 1.0,
        gpu_seconds: 0.5,
    };
    gpu_photon::render::calibration::write(&file, &calibration).unwrap();
    let cpu_out = d.join("cpu.exr");
    let o = render("cpu", None, &d, &cpu_out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cpu = gpu_photon::Image::read(&cpu_out).unwrap();
    for (name, expected, exact) in FAULTS {
        let out = d.join(format!("{name}.exr"));
        let o = render("auto", Some(name), &d, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{name}: {}: {err}", o.status);
        let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
        assert_eq!(warnings.len(), 1, "{name}: {err}");
        let reason = warnings[0]
            .strip_prefix("warning: GPU backend failed (")
            .and_then(|r| r.strip_suffix("); rendering on the CPU"))
            .unwrap_or_else(|| panic!("{name}: {err}"));
        assert!(
            matches(reason, expected, exact, max_buffer),
            "{name}: {err}"
        );
        assert!(err.contains(", backend cpu"), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        let image = gpu_photon::Image::read(&out).unwrap();
        assert_eq!(image.rgb(), cpu.rgb(), "{name}: not the CPU's pixels");
    }
    let _ = std::fs::remove_dir_all(&d);
}
