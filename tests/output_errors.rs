//! Output failures: a full disk, a file size limit, a read-only output directory, a path
//! through a file and a device target each end `render` with exit status 1 and one error
//! naming the output, leave an earlier image there byte for byte, and leave no temporary
//! file. The real full disk and, as root (where permissions do not stop writes), the
//! read-only directory use a small tmpfs; where it cannot be mounted those two cases skip
//! with a message, except with `CI=true`, where they fail.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A scratch directory unique to one test, removed when dropped (after its mount, if any).
struct Scratch {
    dir: PathBuf,
    mounted: bool,
}

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("gpu-photon-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch {
            dir,
            mounted: false,
        }
    }

    /// Mounts a tmpfs of `kib` KiB on the directory; false (with the reason on stderr) where
    /// that is not allowed. Fails under CI=true, where the cases that need it must run.
    fn mount_tmpfs(&mut self, kib: u32) -> bool {
        let o = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={kib}k"), "tmpfs"])
            .arg(&self.dir)
            .output();
        match o {
            Ok(o) if o.status.success() => {
                self.mounted = true;
                true
            }
            other => {
                let why = match other {
                    Ok(o) => String::from_utf8_lossy(&o.stderr).trim().to_string(),
                    Err(e) => e.to_string(),
                };
                assert!(
                    std::env::var("CI").as_deref() != Ok("true"),
                    "cannot mount a tmpfs in CI: {why}"
                );
                eprintln!("skipping: cannot mount a tmpfs ({why})");
                false
            }
        }
    }

    fn remount_read_only(&self) {
        let o = Command::new("mount")
            .args(["-o", "remount,ro"])
            .arg(&self.dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Asserts that the directory holds exactly `names` (no temporary file).
    #[track_caller]
    fn assert_holds(&self, names: &[&str]) {
        let mut found: Vec<String> = std::fs::read_dir(&self.dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        found.sort();
        assert_eq!(found, names, "in {}", self.dir.display());
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if self.mounted {
            let _ = Command::new("umount").arg(&self.dir).status();
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn is_root() -> bool {
    let o = Command::new("id").arg("-u").output().unwrap();
    String::from_utf8_lossy(&o.stdout).trim() == "0"
}

/// A quick CPU render of the Cornell box, `size` pixels square, to `out`; `shell` (e.g.
/// `ulimit -f 8`) runs first in the same shell.
fn render(out: &Path, size: u32, shell: &str) -> Output {
    let size = size.to_string();
    Command::new("sh")
        .arg("-c")
        .arg(format!(r#"{shell}; exec "$0" "$@""#))
        .arg(env!("CARGO_BIN_EXE_gpu-photon"))
        .args(["render", "scenes/cornell-box.toml", "-o"])
        .arg(out)
        .args(["--backend", "cpu", "--width", &size, "--height", &size])
        .args(["--spp", "1", "--photons", "2000", "--passes", "0", "-q"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

/// Asserts `o` failed with exit status 1 and exactly `error: OUT: MESSAGE` on stderr.
#[track_caller]
fn assert_error(o: &Output, out: &Path, message: &str) {
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!("error: {}: {message}\n", out.display())
    );
    assert_eq!(o.status.code(), Some(1));
}

/// An earlier image at `out` (a small render), returned as bytes.
fn earlier_image(out: &Path) -> Vec<u8> {
    let o = render(out, 8, "true");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(out).unwrap()
}

#[test]
fn a_full_disk_keeps_the_earlier_image() {
    let mut s = Scratch::new("full");
    // 128 KiB: the earlier 8x8 EXR fits, a 128x128 one (about 200 KB) does not.
    if !s.mount_tmpfs(128) {
        return;
    }
    let out = s.path("a.exr");
    let before = earlier_image(&out);
    let o = render(&out, 128, "true");
    assert_error(
        &o,
        &out,
        "not written: No space left on device (os error 28); the earlier file there is unchanged",
    );
    assert_eq!(std::fs::read(&out).unwrap(), before);
    s.assert_holds(&["a.exr"]);
}

/// A file size limit (`ulimit -f`) fails the write like a full disk, on any machine.
#[test]
fn a_file_size_limit_keeps_the_earlier_image() {
    let s = Scratch::new("fsize");
    let out = s.path("a.png");
    let before = earlier_image(&out);
    // 8 blocks (4 or 8 KiB by the shell): less than a 128x128 PNG of this render.
    let o = render(&out, 128, "ulimit -f 8");
    assert_error(
        &o,
        &out,
        "not written: File too large (os error 27); the earlier file there is unchanged",
    );
    assert_eq!(std::fs::read(&out).unwrap(), before);
    s.assert_holds(&["a.png"]);
}

/// A read-only output directory is found before the render starts.
#[test]
fn a_read_only_directory_keeps_the_earlier_image() {
    let mut s = Scratch::new("ro");
    let message = if is_root() {
        // Permissions do not stop root: a read-only file system does.
        if !s.mount_tmpfs(256) {
            return;
        }
        "cannot be written: Read-only file system (os error 30)"
    } else {
        "cannot be written: Permission denied (os error 13)"
    };
    let out = s.path("a.exr");
    let before = earlier_image(&out);
    if s.mounted {
        s.remount_read_only();
    } else {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&s.dir, std::fs::Permissions::from_mode(0o555)).unwrap();
    }
    let o = render(&out, 8, "true");
    assert_error(&o, &out, message);
    assert_eq!(std::fs::read(&out).unwrap(), before);
    s.assert_holds(&["a.exr"]);
    if !s.mounted {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&s.dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
}

/// Paths that cannot hold an image file, on any machine and as any user.
#[test]
fn impossible_output_paths_are_refused_before_the_render() {
    let s = Scratch::new("paths");
    let file = s.path("a.exr");
    let before = earlier_image(&file);
    // Through a regular file.
    let through = s.path("a.exr/b.exr");
    assert_error(
        &render(&through, 8, "true"),
        &through,
        "cannot be written: Not a directory (os error 20)",
    );
    // A directory, and a link to a device (written atomically, the image would replace
    // the link rather than go to the device).
    std::fs::create_dir(s.path("d.exr")).unwrap();
    assert_error(
        &render(&s.path("d.exr"), 8, "true"),
        &s.path("d.exr"),
        "cannot be written: it is a directory",
    );
    std::os::unix::fs::symlink("/dev/full", s.path("full.exr")).unwrap();
    assert_error(
        &render(&s.path("full.exr"), 8, "true"),
        &s.path("full.exr"),
        "cannot be written: it is not a regular file",
    );
    assert_eq!(std::fs::read(&file).unwrap(), before);
    s.assert_holds(&["a.exr", "d.exr", "full.exr"]);
}
