//! The render's memory against the machine's (`gpu_photon::render::budget`): a render whose estimate
//! exceeds the memory available fails before anything of it is allocated, with exit status
//! 1 and one error naming the parts, the shortfall and how to shrink the largest; one that
//! fits renders. `GPU_PHOTON_MEMORY` stands in for the machine's figure so the cases do not
//! depend on this machine.

use gpu_photon::render::budget::{available, parse_bytes, size, BYTES_PER_PHOTON, STORES_PER_PATH};
use std::process::{Command, Output};

/// A classic render on `backend` with `GPU_PHOTON_MEMORY=memory`.
fn render(backend: &str, memory: &str, extra: &[&str]) -> Output {
    render_scene("scenes/cornell-box.toml", backend, memory, extra)
}

/// [`render`] of `scene`.
fn render_scene(scene: &str, backend: &str, memory: &str, extra: &[&str]) -> Output {
    let out = std::env::temp_dir().join(format!("gpu-photon-budget-{}.exr", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
        .args(["render", scene, "--backend", backend, "-q", "-o"])
        .arg(&out)
        .args(["--spp", "1", "--passes", "0"])
        .args(extra)
        .env("GPU_PHOTON_MEMORY", memory)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&out);
    o
}

#[track_caller]
fn assert_refused(o: &Output, message: &str) {
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!("error: {message}\n")
    );
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn too_many_photons_for_the_memory_is_refused_naming_them() {
    // 4,000,000 paths: 4e6 x 3 x 64 bytes = 732.4 MiB of maps, against 256 MiB.
    let o = render(
        "cpu",
        "256M",
        &[
            "--photons",
            "4000000",
            "--caustic-photons",
            "0",
            "--width",
            "64",
            "--height",
            "64",
        ],
    );
    assert_eq!(4_000_000 * STORES_PER_PATH * BYTES_PER_PHOTON, 768_000_000);
    assert_refused(
        &o,
        "the render needs about 732.6 MiB of memory (732.4 MiB for photon maps for 4000000 \
         global paths, 192.0 KiB for a 64x64 image, 4.0 KiB for a BVH of 32 triangles), \
         476.6 MiB more than the 256.0 MiB available (GPU_PHOTON_MEMORY); lower --photons \
         (more passes of fewer photons converge alike)",
    );
}

#[test]
fn volume_photons_count_where_the_scene_has_media() {
    // 1,000,000 paths in fog: 3e6 surface and 3e6 volume photons, 183.1 MiB each.
    let args = [
        "--photons",
        "1000000",
        "--caustic-photons",
        "0",
        "--width",
        "64",
        "--height",
        "64",
    ];
    let o = render_scene("scenes/fog-cornell.toml", "cpu", "256M", &args);
    assert_refused(
        &o,
        "the render needs about 366.4 MiB of memory (183.1 MiB for photon maps for 1000000 \
         global paths, 183.1 MiB for 3000000 volume photons, 192.0 KiB for a 64x64 image, \
         4.0 KiB for a BVH of 32 triangles), 110.4 MiB more than the 256.0 MiB available \
         (GPU_PHOTON_MEMORY); lower --photons and --caustic-photons",
    );
    // The same without fog fits.
    let o = render("cpu", "256M", &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn too_large_an_image_for_the_memory_is_refused_on_either_backend() {
    // 16384 x 8192 pixels x 48 bytes = 6 GiB, against 1 GiB; the GPU backend's maps are
    // device memory, so its estimate is the image and the BVH alone.
    let o = render(
        "gpu",
        "1G",
        &["--width", "16384", "--height", "8192", "--photons", "1000"],
    );
    assert_refused(
        &o,
        "the render needs about 6.0 GiB of memory (6.0 GiB for a 16384x8192 image, 4.0 KiB \
         for a BVH of 32 triangles), 5.0 GiB more than the 1.0 GiB available \
         (GPU_PHOTON_MEMORY); lower --width and --height",
    );
}

#[test]
fn a_render_that_fits_renders() {
    let o = render(
        "cpu",
        "64M",
        &["--photons", "20000", "--width", "32", "--height", "32"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn sizes_and_the_machine_figure() {
    assert_eq!(parse_bytes("512"), Some(512));
    assert_eq!(parse_bytes("64k"), Some(64 << 10));
    assert_eq!(parse_bytes("3G"), Some(3 << 30));
    assert_eq!(parse_bytes("2X"), None);
    assert_eq!(parse_bytes("G"), None);
    assert_eq!(size(1023), "1023 bytes");
    assert_eq!(size(1536 << 20), "1.5 GiB");
    // On Linux the machine's figure comes from /proc/meminfo (or the cgroup) and is positive.
    if std::env::var_os("GPU_PHOTON_MEMORY").is_none() && cfg!(target_os = "linux") {
        let (bytes, source) = available().expect("MemAvailable");
        assert!(bytes > 0, "{source}");
    }
}
