//! A progressive render stopped by SIGTERM (what Slurm, Kubernetes and systemd send before
//! they kill): it finishes the pass in flight, writes a valid slice of the passes done (the
//! same pixels as a render of just those passes, tagged so that `merge` names what is
//! missing), says so on stderr even with `-q`, and exits with 143 when planned passes are
//! left undone (0 when the file holds them all). Ctrl-C is in `tests/cli_progressive.rs`.

mod common;

use std::path::Path;
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

/// A small CPU render of the Cornell box into `out`, with `extra` flags.
fn render_command(out: &Path, extra: &[&str]) -> Command {
    let mut c = common::bin();
    c.args(["render", "scenes/cornell-box.toml", "-o"]).arg(out);
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
        "-q",
    ]);
    c.args(extra);
    c
}

fn tag(path: &Path, key: &str) -> Option<String> {
    gpu_photon::render::film::read_tags(path)
        .unwrap()
        .into_iter()
        .find(|t| t.0 == key)
        .map(|t| t.1)
}

/// Spawns `c` (which writes `out` after every pass), waits for the first pass's file, sends
/// SIGTERM and returns what the render did. Fails (killing it) rather than hang.
fn terminate_after_first_pass(mut c: Command, out: &Path) -> Output {
    let mut child: Child = c.stderr(std::process::Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    while !out.exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the render ended ({status:?}) before it wrote its first pass");
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("no pass written after 120 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("the render went on for 120 s after SIGTERM");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn sigterm_writes_the_passes_done_as_a_valid_slice() {
    let d = common::scratch("sigterm");
    let out = d.join("t.exr");
    let c = render_command(&out, &["--passes", "100000", "--write-every", "1"]);
    let result = terminate_after_first_pass(c, &out);
    let stderr = String::from_utf8_lossy(&result.stderr);
    let passes: u32 = tag(&out, "gpu_photon.passes").unwrap().parse().unwrap();
    assert!((1..100_000).contains(&passes), "{passes}");
    assert_eq!(result.status.code(), Some(143), "{stderr}");
    assert_eq!(
        stderr.trim_end(),
        format!(
            "{}: stopped by SIGTERM after passes 0..{passes} of 0..100000; wrote them",
            out.display()
        )
    );
    assert_eq!(
        tag(&out, "gpu_photon.pass_range"),
        Some(format!("0..{passes}"))
    );
    assert_eq!(
        tag(&out, "gpu_photon.total_passes").as_deref(),
        Some("100000")
    );
    // The same pixels as a render of just those passes.
    let same = d.join("same.exr");
    let range = format!("0..{passes}");
    let o = render_command(&same, &["--pass-range", &range])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (
        gpu_photon::Image::read(&out).unwrap(),
        gpu_photon::Image::read(&same).unwrap(),
    );
    assert_eq!(a.rgb(), b.rgb());
    assert_eq!(a.non_finite(), 0);
    // A slice to merge: alone, the merge names the passes the signal cut off.
    let merged = d.join("m.exr");
    let o = common::bin()
        .arg("merge")
        .arg(&out)
        .arg("-o")
        .arg(&merged)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!(
            "passes {passes}..100000 of the render's 0..100000 are missing"
        )),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// A signal during the last planned pass still lets it finish: the file then holds every
/// planned pass and the render succeeded. Which pass the signal lands in is up to the
/// scheduler, so the test checks the rule both ways: status 0 exactly when the file holds
/// all the slice's passes, else 143.
#[test]
fn sigterm_in_the_last_pass_of_a_slice_exits_by_what_was_written() {
    let d = common::scratch("sigterm-slice");
    let out = d.join("s.exr");
    let c = render_command(
        &out,
        &["--passes", "4", "--slice", "1/2", "--write-every", "1"],
    );
    let result = terminate_after_first_pass(c, &out);
    let range = tag(&out, "gpu_photon.pass_range").unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains(&format!("stopped by SIGTERM after passes {range} of 2..4")),
        "{stderr}"
    );
    match range.as_str() {
        "2..4" => assert_eq!(result.status.code(), Some(0), "{stderr}"),
        "2..3" => assert_eq!(result.status.code(), Some(143), "{stderr}"),
        r => panic!("slice 1/2 of 4 passes holds {r}"),
    }
    let _ = std::fs::remove_dir_all(&d);
}
