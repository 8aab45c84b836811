//! `--backend auto`'s rule, by measurement (issue 11): the GPU renders when, on that adapter,
//! it rendered the calibration scene faster than the CPU backend did. The calibration is the
//! Cornell box made small, in the default technique ([`CALIBRATION_SCENE`] with
//! [`calibration_settings`]: 64x64, 8 spp, 50,000 photon paths, mode `gather`, progressive);
//! each backend's renderer is opened (device, pipelines), renders progressive pass 0 to warm
//! up, then pass 1 is timed. The two times are stored per adapter,
//! driver, crate version and CPU thread count in [`cache_file`], so the measurement (a few
//! seconds on a software device) runs once per machine; deleting the file measures again.
//! Software adapters (lavapipe) are measured like any other: nothing is assumed from the
//! device type.

use crate::settings::{Mode, RenderSettings};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The calibration scene: `scenes/cornell-box.toml` (its geometry, materials and light), which
/// [`calibration_settings`] makes small.
pub const CALIBRATION_SCENE: &str = include_str!("../../scenes/cornell-box.toml");

/// Bumped whenever the calibration render changes, so times measured for another one are not
/// reused (2: progressive passes instead of one classic pass; 3: the fixed-radius cache
/// kernel, which made the GPU's pass faster; 4: the while-while traversal and the shading
/// after the specular chain, likewise).
pub const CALIBRATION_VERSION: u32 = 4;

/// The calibration render's settings: the scene's own, in mode `gather`, at 64x64, 8 spp and
/// 50,000 photon paths, progressive passes 0..2 (the default render's technique: each pass
/// from `progressive::pass_settings`).
pub fn calibration_settings(scene: &RenderSettings) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 64,
        spp: 8,
        photons: 50_000,
        mode: Mode::Gather,
        pass_range: Some((0, 2)),
        ..scene.clone()
    }
}

/// One adapter's calibration: the timed pass's wall time on each backend.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// What the times were measured for ([`key`]).
    pub key: String,
    /// Seconds of the CPU backend's timed pass.
    pub cpu_seconds: f64,
    /// Seconds of the GPU backend's timed pass (infinite when it failed).
    pub gpu_seconds: f64,
}

impl Calibration {
    /// The rule: the GPU when its pass was the faster one.
    pub fn gpu_is_faster(&self) -> bool {
        self.gpu_seconds < self.cpu_seconds
    }
}

/// What a calibration holds for: the adapter's name and driver, this crate's version (the
/// kernels change with it) and [`CALIBRATION_VERSION`], and the CPU backend's thread count.
pub fn key(adapter_name: &str, driver: &str) -> String {
    format!(
        "{adapter_name} | {driver} | gpu-photon {} calibration {CALIBRATION_VERSION} | {} threads",
        env!("CARGO_PKG_VERSION"),
        rayon::current_num_threads()
    )
    .replace(['\t', '\n'], " ")
}

/// Where calibrations are kept: `$XDG_CACHE_HOME/gpu-photon/backend-calibration.tsv`, else
/// `$HOME/.cache/...`; `None` when neither is set.
pub fn cache_file() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("gpu-photon").join("backend-calibration.tsv"))
}

/// The calibration stored for `key` in `file` (lines `key<TAB>cpu<TAB>gpu`), if any.
pub fn read(file: &Path, key: &str) -> Option<Calibration> {
    let text = std::fs::read_to_string(file).ok()?;
    text.lines().rev().find_map(|line| {
        let mut f = line.split('\t');
        let (k, cpu, gpu) = (f.next()?, f.next()?, f.next()?);
        (k == key).then_some(())?;
        Some(Calibration {
            key: k.to_string(),
            cpu_seconds: cpu.trim().parse().ok()?,
            gpu_seconds: gpu.trim().parse().ok()?,
        })
    })
}

/// Appends `c` to `file` (creating its directory); best effort: a cache that cannot be
/// written only means measuring again next time.
pub fn write(file: &Path, c: &Calibration) -> std::io::Result<()> {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(file)?;
    writeln!(f, "{}\t{}\t{}", c.key, c.cpu_seconds, c.gpu_seconds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calibrations_round_trip_and_the_last_one_counts() {
        let dir = std::env::temp_dir().join(format!("gp-calibration-{}", std::process::id()));
        let file = dir.join("sub").join("c.tsv");
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(read(&file, "a"), None);
        let a = Calibration {
            key: key("llvmpipe (LLVM 15)", "Mesa\t22.3"),
            cpu_seconds: 0.25,
            gpu_seconds: 0.75,
        };
        write(&file, &a).unwrap();
        assert_eq!(read(&file, &a.key), Some(a.clone()));
        assert!(!a.gpu_is_faster());
        let b = Calibration {
            gpu_seconds: 0.125,
            ..a.clone()
        };
        write(&file, &b).unwrap();
        assert_eq!(read(&file, &a.key), Some(b.clone()));
        assert!(b.gpu_is_faster());
        assert_eq!(read(&file, "another adapter"), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
