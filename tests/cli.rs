//! The `gpu-photon` command line, run as a process: outputs, exit codes, error messages,
//! atomic writes, `diff`, and seed determinism.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A scratch directory unique to one test (name + process id), removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(test: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("gpu-photon-cli-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    /// Names of the entries in the directory, sorted.
    fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&self.0)
            .expect("read temp dir")
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
    /// Asserts no temporary file of the atomic writer (`.NAME.PID.N.tmp.EXT`) is left.
    #[track_caller]
    fn assert_no_temp_files(&self) {
        let left: Vec<String> = self
            .entries()
            .into_iter()
            .filter(|n| n.starts_with('.') || n.contains(".tmp"))
            .collect();
        assert!(
            left.is_empty(),
            "temporary files left in {}: {left:?}",
            self.0.display()
        );
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary in the crate root (so `scenes/...` resolves).
fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run gpu-photon")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts the process failed with exit code 1 and a message, without a panic.
#[track_caller]
fn assert_fails_cleanly(o: &Output, what: &str) -> String {
    let err = stderr(o);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{what}: exit status {:?}, stderr:\n{err}",
        o.status
    );
    assert!(!err.contains("panicked"), "{what}: panicked:\n{err}");
    assert!(
        err.starts_with("error: "),
        "{what}: stderr should be one error message:\n{err}"
    );
    err
}

#[track_caller]
fn assert_ok(o: &Output, what: &str) {
    assert!(
        o.status.success(),
        "{what}: {:?}\nstderr:\n{}",
        o.status,
        stderr(o)
    );
}

/// A tiny CPU render of the Cornell box to `out` with `extra` arguments.
fn tiny_render(out: &Path, extra: &[&str]) -> Output {
    tiny_render_sized(out, "32", extra)
}

/// The same, `width` x 32 pixels.
fn tiny_render_sized(out: &Path, width: &str, extra: &[&str]) -> Output {
    let out = out.to_str().unwrap();
    let mut args = vec![
        "render",
        "scenes/cornell-box.toml",
        "-o",
        out,
        "--width",
        width,
        "--height",
        "32",
        "--spp",
        "1",
        "--photons",
        "20000",
        "--backend",
        "cpu",
    ];
    args.extend_from_slice(extra);
    run(&args)
}

// ---------------------------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------------------------

#[test]
fn renders_a_png_of_the_requested_size() {
    let dir = TempDir::new("png");
    let out = dir.path("tmp.png");
    let o = tiny_render(&out, &[]);
    assert_ok(&o, "png render");
    let img = image::open(&out).expect("a readable PNG").to_rgb8();
    assert_eq!(img.dimensions(), (32, 32));
    // The lit box is not black.
    assert!(img.pixels().any(|p| p.0.iter().any(|&c| c > 0)));
    // Not quiet: the summary names the output and the size.
    assert!(stderr(&o).contains("32x32"), "{}", stderr(&o));
    assert_eq!(dir.entries(), vec!["tmp.png".to_string()]);
    dir.assert_no_temp_files();
}

#[test]
fn renders_an_exr_of_the_requested_size() {
    let dir = TempDir::new("exr");
    let out = dir.path("tmp.exr");
    let o = tiny_render(&out, &["-q"]);
    assert_ok(&o, "exr render");
    // -q: nothing on stderr.
    assert_eq!(stderr(&o), "");
    let img = gpu_photon::Image::read(&out).expect("a readable EXR");
    assert_eq!((img.width, img.height), (32, 32));
    assert_eq!(img.non_finite(), 0);
    assert!(img.mean().iter().all(|&m| m > 0.0), "{:?}", img.mean());
    assert_eq!(dir.entries(), vec!["tmp.exr".to_string()]);
    dir.assert_no_temp_files();
}

#[test]
fn unknown_output_extension_fails_naming_it() {
    let dir = TempDir::new("jpg");
    let o = tiny_render(&dir.path("tmp.jpg"), &["-q"]);
    let err = assert_fails_cleanly(&o, ".jpg output");
    assert!(
        err.contains("jpg"),
        "message does not name the extension:\n{err}"
    );
    assert!(dir.entries().is_empty(), "{:?}", dir.entries());
}

#[test]
fn failed_write_leaves_no_temporary_file() {
    // The output path is an existing directory: the image is encoded to the temporary file
    // beside it, and the final rename fails. The temporary file must be removed.
    let dir = TempDir::new("rename");
    std::fs::create_dir(dir.path("out.png")).unwrap();
    let o = tiny_render(&dir.path("out.png"), &["-q"]);
    let err = assert_fails_cleanly(&o, "output is a directory");
    assert!(err.contains("out.png"), "{err}");
    assert_eq!(dir.entries(), vec!["out.png".to_string()]);
    dir.assert_no_temp_files();
    // An output directory that does not exist: a clean error too.
    let o = tiny_render(&dir.path("missing/out.exr"), &["-q"]);
    assert_fails_cleanly(&o, "missing output directory");
    // A successful write over an existing file replaces it and leaves nothing else.
    std::fs::write(dir.path("old.exr"), b"not an image").unwrap();
    assert_ok(&tiny_render(&dir.path("old.exr"), &["-q"]), "overwrite");
    assert!(gpu_photon::Image::read(&dir.path("old.exr")).is_ok());
    dir.assert_no_temp_files();
}

// ---------------------------------------------------------------------------------------------
// Bad scenes and settings
// ---------------------------------------------------------------------------------------------

/// A valid scene up to (and without) its shapes: 14 lines.
const HEAD: &str = "[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40

[materials.white]
type = \"diffuse\"
albedo = [0.5, 0.5, 0.5]

[[lights]]
type = \"point\"
position = [0, 1, 0]
intensity = [1, 1, 1]

";

/// 1-based number of the first line of `text` at or after line `from` (1-based) that starts
/// with `prefix`.
fn line_of(text: &str, prefix: &str, from: usize) -> usize {
    let skip = from.saturating_sub(1);
    skip + text
        .lines()
        .skip(skip)
        .position(|l| l.starts_with(prefix))
        .expect("prefix in scene")
        + 1
}

#[test]
fn bad_scenes_fail_with_file_line_and_field() {
    let dir = TempDir::new("scenes");
    let sphere =
        |body: &str| format!("{HEAD}[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\n{body}");
    // (file, text, field, prefix of the line the error must point at (the first such line
    // in the field's table), words of the message)
    let cases: Vec<(&str, String, &str, &str, &[&str])> = vec![
        ("missing.toml", sphere("material = \"white\"\n"), "shapes[0].radius", "[[shapes]]", &["missing"]),
        ("nan.toml", sphere("radius = nan\nmaterial = \"white\"\n"), "shapes[0].radius", "radius", &["finite"]),
        ("negative.toml", sphere("radius = -1.0\nmaterial = \"white\"\n"), "shapes[0].radius", "radius", &["positive"]),
        (
            "obj.toml",
            format!("{HEAD}[[shapes]]\ntype = \"mesh\"\nfile = \"no-such-mesh.obj\"\nmaterial = \"white\"\n"),
            "shapes[0].file",
            "file",
            &["no-such-mesh.obj"],
        ),
        ("material.toml", sphere("radius = 1.0\nmaterial = \"chrome\"\n"), "shapes[0].material", "material", &["chrome"]),
        (
            "albedo.toml",
            HEAD.replace("albedo = [0.5, 0.5, 0.5]", "albedo = [0.5, 1.5, 0.5]") + "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\nmaterial = \"white\"\n",
            "materials.white.albedo",
            "albedo",
            &[],
        ),
    ];
    for (file, text, field, prefix, words) in cases {
        let path = dir.path(file);
        std::fs::write(&path, &text).unwrap();
        let o = run(&[
            "render",
            path.to_str().unwrap(),
            "-o",
            dir.path("out.png").to_str().unwrap(),
            "--backend",
            "cpu",
            "-q",
        ]);
        let err = assert_fails_cleanly(&o, file);
        let section = if field.starts_with("shapes") {
            line_of(&text, "[[shapes]]", 0)
        } else {
            1
        };
        // FILE:LINE: with the line of the offending key (of the table, for a missing key).
        let line = line_of(&text, prefix, section);
        let want = format!("{}:{line}:", path.display());
        assert!(err.contains(&want), "{file}: expected {want:?} in:\n{err}");
        assert!(
            err.contains(field),
            "{file}: expected field {field:?} in:\n{err}"
        );
        for w in words {
            assert!(err.contains(w), "{file}: expected {w:?} in:\n{err}");
        }
        assert!(!dir.path("out.png").exists());
    }
    // A scene file that does not exist.
    let o = run(&[
        "render",
        dir.path("absent.toml").to_str().unwrap(),
        "-o",
        dir.path("out.png").to_str().unwrap(),
        "-q",
    ]);
    let err = assert_fails_cleanly(&o, "absent scene");
    assert!(err.contains("absent.toml"), "{err}");
    dir.assert_no_temp_files();
}

#[test]
fn absurd_settings_fail_with_a_clear_message() {
    let dir = TempDir::new("settings");
    let out = dir.path("out.exr");
    let o = tiny_render_sized(&out, "100000", &["-q"]);
    let err = assert_fails_cleanly(&o, "--width 100000");
    assert!(
        err.contains("width") && err.contains("100000") && err.contains("16384"),
        "{err}"
    );
    let o = tiny_render(&out, &["--k", "0", "-q"]);
    let err = assert_fails_cleanly(&o, "--k 0");
    assert!(err.contains('k') && err.contains('0'), "{err}");
    let o = tiny_render(&out, &["--radius=-1", "-q"]);
    let err = assert_fails_cleanly(&o, "--radius=-1");
    assert!(err.contains("radius"), "{err}");
    let o = tiny_render(&out, &["--mode", "bogus", "-q"]);
    let err = assert_fails_cleanly(&o, "--mode bogus");
    assert!(
        err.contains("bogus") && err.contains("direct-only"),
        "{err}"
    );
    assert!(dir.entries().is_empty(), "{:?}", dir.entries());
}

// ---------------------------------------------------------------------------------------------
// diff
// ---------------------------------------------------------------------------------------------

/// The numbers after `key` on its line of `diff`'s output.
fn field(out: &str, key: &str) -> Vec<f64> {
    let line = out
        .lines()
        .find(|l| l.split_whitespace().next() == Some(key))
        .unwrap_or_else(|| panic!("no {key} in:\n{out}"));
    line.split_whitespace()
        .skip(1)
        .map_while(|w| w.parse().ok())
        .collect()
}

#[test]
fn diff_of_an_image_with_itself_is_zero_and_sizes_must_match() {
    let dir = TempDir::new("diff");
    let a = dir.path("a.exr");
    assert_ok(&tiny_render(&a, &["-q"]), "render a");
    let a = a.to_str().unwrap();
    let o = run(&["diff", a, a]);
    assert_ok(&o, "diff a a");
    let out = stdout(&o);
    assert_eq!(field(&out, "rmse"), vec![0.0], "{out}");
    assert_eq!(field(&out, "max_error"), vec![0.0], "{out}");
    assert_eq!(field(&out, "mean_ratio"), vec![1.0, 1.0, 1.0], "{out}");
    // Against a different image the statistics are not trivial.
    let b = dir.path("b.exr");
    assert_ok(&tiny_render(&b, &["-q", "--seed", "2"]), "render b");
    let o = run(&["diff", a, b.to_str().unwrap()]);
    assert_ok(&o, "diff a b");
    assert!(field(&stdout(&o), "rmse")[0] > 0.0);
    // Different sizes: exit 1.
    let c = dir.path("c.exr");
    assert_ok(&tiny_render_sized(&c, "16", &["-q"]), "render c");
    let o = run(&["diff", a, c.to_str().unwrap()]);
    let err = assert_fails_cleanly(&o, "diff of two sizes");
    assert!(err.contains("32x32") && err.contains("16x32"), "{err}");
    // A missing file: exit 1.
    let o = run(&["diff", a, dir.path("none.exr").to_str().unwrap()]);
    assert_fails_cleanly(&o, "diff with a missing file");
}

// ---------------------------------------------------------------------------------------------
// Determinism
// ---------------------------------------------------------------------------------------------

#[test]
fn same_seed_gives_byte_identical_exr_and_another_seed_does_not() {
    let dir = TempDir::new("seed");
    let paths = ["a.exr", "b.exr", "c.exr"].map(|n| dir.path(n));
    assert_ok(&tiny_render(&paths[0], &["-q", "--seed", "5"]), "seed 5");
    assert_ok(
        &tiny_render(&paths[1], &["-q", "--seed", "5"]),
        "seed 5 again",
    );
    assert_ok(&tiny_render(&paths[2], &["-q", "--seed", "6"]), "seed 6");
    let bytes = paths.map(|p| std::fs::read(p).unwrap());
    assert!(bytes[0] == bytes[1], "same seed, different EXR bytes");
    assert!(bytes[0] != bytes[2], "different seeds, same EXR bytes");
    // A progressive slice's header carries tags (pass range, passes, signature): they too
    // must come out in the same order every run (they once followed a HashMap's order).
    let slices: Vec<Vec<u8>> = (0..4)
        .map(|i| {
            let p = dir.path(&format!("slice{i}.exr"));
            assert_ok(
                &tiny_render(&p, &["-q", "--seed", "5", "--pass-range", "0..2"]),
                "slice",
            );
            std::fs::read(p).unwrap()
        })
        .collect();
    assert!(
        slices.iter().all(|b| *b == slices[0]),
        "same seed and pass range, different EXR bytes"
    );
    dir.assert_no_temp_files();
}

// ---------------------------------------------------------------------------------------------
// --backend auto
// ---------------------------------------------------------------------------------------------

/// `--backend auto` is one rule for classic and progressive renders alike: the GPU where it
/// measured faster than the CPU on the calibration scene (`tests/auto_backend.rs`); else the
/// CPU, with exactly one warning line saying so. (Progressive
/// renders once fell back silently, and only classic renders fell back on a GPU failure.)
#[test]
fn auto_backend_decides_alike_for_classic_and_progressive_renders() {
    let dir = TempDir::new("auto");
    let out = dir.path("auto.exr");
    let mut on_cpu = Vec::new();
    for extra in [&[][..], &["--passes", "2"][..]] {
        let mut args = vec![
            "render",
            "scenes/cornell-box.toml",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "16",
            "--spp",
            "1",
            "--photons",
            "2000",
            "--backend",
            "auto",
        ];
        args.extend_from_slice(extra);
        let o = run(&args);
        assert_ok(&o, "auto render");
        let err = stderr(&o);
        let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
        let cpu = err.contains(", backend cpu (");
        assert!(
            cpu || err.contains(", backend "),
            "{extra:?}: no summary line:\n{err}"
        );
        if cpu {
            assert_eq!(warnings.len(), 1, "{extra:?}: one warning:\n{err}");
            assert!(
                warnings[0].ends_with("rendering on the CPU"),
                "{extra:?}:\n{err}"
            );
        } else {
            assert!(
                warnings.is_empty(),
                "{extra:?}: a GPU render warned:\n{err}"
            );
        }
        on_cpu.push(cpu);
    }
    assert_eq!(
        on_cpu[0], on_cpu[1],
        "classic and progressive renders chose different backends"
    );
    dir.assert_no_temp_files();
}

/// `bench --modes` names the ladder's techniques; a wrong name fails before any rendering,
/// naming the name and the modes there are.
#[test]
fn bench_modes_are_checked_before_rendering() {
    let o = run(&[
        "bench",
        "scenes/cornell-box.toml",
        "--modes",
        "direct,fast",
        "--out",
        "target/test-output/never-bench",
    ]);
    let err = assert_fails_cleanly(&o, "bench --modes direct,fast");
    assert!(
        err.contains("invalid setting modes: `fast` in `direct,fast` is not one of photon, direct, gather, direct-only, global-only, caustic-only"),
        "{err}"
    );
    assert!(
        stdout(&o).is_empty(),
        "it measured before checking: {}",
        stdout(&o)
    );
}

/// `bench --json FILE` writes the sizes, the adapters wgpu finds (name, driver, limits,
/// subgroup size and kernel shape, for the real-GPU figures) and each backend's medians, as
/// JSON.
#[test]
fn bench_writes_its_figures_as_json() {
    let dir = TempDir::new("bench-json");
    let out = dir.path("bench.json");
    let o = run(&[
        "bench",
        "scenes/cornell-box.toml",
        "--backend",
        "cpu",
        "--runs",
        "1",
        "--photons",
        "4000",
        "--width",
        "16",
        "--height",
        "12",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(v["scene"], "scenes/cornell-box.toml");
    assert_eq!(
        (
            v["settings"]["width"].as_u64(),
            v["settings"]["height"].as_u64()
        ),
        (Some(16), Some(12))
    );
    assert_eq!(v["settings"]["photons"].as_u64(), Some(4000));
    let results = v["results"].as_array().unwrap();
    assert_eq!(results.len(), 1);
    assert_eq!(results[0]["backend"], "cpu");
    for key in ["photon_paths_per_s", "camera_samples_per_s", "total_s"] {
        assert!(
            results[0][key].as_f64().unwrap() > 0.0,
            "{key}: {}",
            results[0][key]
        );
    }
    assert!(results[0]["phases_s"]["gather"].as_f64().unwrap() > 0.0);
    for a in v["adapters"].as_array().unwrap() {
        let (lo, hi) = (
            a["subgroup_size"][0].as_u64().unwrap(),
            a["subgroup_size"][1].as_u64().unwrap(),
        );
        assert!(lo >= 1 && lo <= hi, "{a}");
        assert!(
            a["max_storage_buffer_binding_size"].as_u64().unwrap() > 0,
            "{a}"
        );
        let shape = &a["kernel_shape"];
        let lanes = shape["cache_lanes"].as_u64().unwrap();
        assert!(
            lanes.is_power_of_two() && shape["loop_guard"].is_boolean(),
            "{a}"
        );
    }
}

/// Output into a pipe that closes early (`gpu-photon diff A B | head -1`) ends the process
/// quietly, as other command-line tools do, never with a panic in `println!`.
#[test]
fn a_closed_output_pipe_is_no_panic() {
    use std::process::Stdio;
    let reference = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/cornell-diffuse.exr"
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
        .args(["diff", reference, reference])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run gpu-photon");
    // Close the reading end before the two images are read and the first line is printed.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{err}");
    assert_ne!(out.status.code(), Some(101), "{err}");
}

/// `bench --reference R --passes N` reads the peer's curve recorded beside the reference
/// (`R.json`'s `peer_curve`) and puts each backend's last point against it at equal RMSE.
#[test]
fn bench_curve_stands_against_the_peer_recorded_beside_the_reference() {
    let dir = TempDir::new("bench-peer");
    let reference = dir.path("ref.exr");
    let size = ["--width", "16", "--height", "12"];
    let o = run(&[
        &[
            "render",
            "scenes/cornell-box.toml",
            "-o",
            reference.to_str().unwrap(),
        ],
        &size[..],
        &["--backend", "cpu", "--spp", "64", "--quiet"],
    ]
    .concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let peer = r#"{"renderer": "Peer 1.0", "estimated_rmse_of_reference": 0.0,
        "peer_curve": [{"spp": 16, "seconds": 1.0, "rmse": 0.2},
                       {"spp": 64, "seconds": 4.0, "rmse": 0.1}]}"#;
    std::fs::write(dir.path("ref.json"), peer).unwrap();
    let bench = |passes: &str| {
        let against = [
            "--reference",
            reference.to_str().unwrap(),
            "--passes",
            passes,
        ];
        run(&[
            &[
                "bench",
                "scenes/cornell-box.toml",
                "--backend",
                "cpu",
                "--runs",
                "1",
            ][..],
            &["--photons", "4000"][..],
            &against[..],
            &size[..],
        ]
        .concat())
    };
    let o = bench("2");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("peer: Peer 1.0 as recorded in"), "{out}");
    assert!(
        out.contains("      64 spp      4.00 s  rmse 0.10000"),
        "{out}"
    );
    // RMSE^2 x seconds is 0.04 for both peer points: the peer needs 0.04 / rmse^2 seconds.
    let line = out
        .lines()
        .find(|l| l.contains("cpu after 2 passes"))
        .unwrap_or_else(|| panic!("{out}"));
    let num = |key: &str| -> f64 {
        let at = line.find(key).unwrap() + key.len();
        line[at..]
            .split(|c: char| c == ';' || c == ' ' || c == ':')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (rmse, needs) = (num("rmse "), num("the peer needs "));
    assert!(
        (needs - 0.04 / (rmse * rmse)).abs() < 0.01 * needs + 0.01,
        "{line}"
    );
    // A malformed sidecar is an error naming it.
    std::fs::write(dir.path("ref.json"), "{\"peer_curve\": [1,").unwrap();
    let o = bench("1");
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("ref.json:1: peer_curve:"),
        "{}",
        stderr(&o)
    );
}
