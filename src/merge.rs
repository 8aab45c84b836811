//! Slices of a progressive render and their merge: the header tags a slice carries (its pass
//! range and a fingerprint of the scene and settings), and the pass-weighted mean of slices
//! rendered anywhere, which equals the image of a single run over the same passes.

use crate::error::{Error, Result};
use crate::film::{read_tags, Image};
use crate::progressive::Accumulator;
use crate::settings::RenderSettings;
use std::path::{Path, PathBuf};

/// Header tag holding a slice's pass range `A..B` (or `A..B,C..D` after a merge of gaps).
pub const TAG_PASS_RANGE: &str = "gpu_photon.pass_range";
/// Header tag holding the number of passes in a slice.
pub const TAG_PASSES: &str = "gpu_photon.passes";
/// Header tag holding the fingerprint of the scene file and settings.
pub const TAG_SIGNATURE: &str = "gpu_photon.signature";

/// A fingerprint of the scene file and every setting but the pass range: slices to merge
/// must share it.
pub fn signature(scene_path: &Path, s: &RenderSettings) -> Result<String> {
    let text = std::fs::read(scene_path).map_err(|source| Error::Io {
        path: scene_path.to_path_buf(),
        source,
    })?;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325; // FNV-1a
    for b in text {
        h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
    }
    let s = RenderSettings {
        pass_range: None,
        ..s.clone()
    };
    Ok(format!("scene-fnv1a {h:016x}; {s:?}"))
}

/// The header tags of a slice holding the passes in `acc`.
pub fn slice_tags(acc: &Accumulator, signature: &str) -> Vec<(&'static str, String)> {
    vec![
        (
            TAG_PASS_RANGE,
            format!("{}..{}", acc.first, acc.first + acc.count),
        ),
        (TAG_PASSES, acc.count.to_string()),
        (TAG_SIGNATURE, signature.to_string()),
    ]
}

/// Parses a pass range `A..B` (B > A).
pub fn parse_range(s: &str) -> std::result::Result<(u32, u32), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("'{s}' is not a range A..B"))?;
    let a: u32 = a.trim().parse().map_err(|e| format!("'{a}': {e}"))?;
    let b: u32 = b.trim().parse().map_err(|e| format!("'{b}': {e}"))?;
    if b <= a {
        return Err(format!("{a}..{b} holds no pass"));
    }
    Ok((a, b))
}

/// What a merge wrote.
#[derive(Clone, Debug)]
pub struct MergeSummary {
    /// Slices merged.
    pub slices: usize,
    /// The merged pass range(s), as written in the header.
    pub range: String,
    /// Passes in the merged image.
    pub passes: u32,
}

struct Slice {
    path: PathBuf,
    first: u32,
    end: u32,
    signature: String,
    image: Image,
}

fn slice_error(path: &Path, message: String) -> Error {
    Error::Image {
        path: path.to_path_buf(),
        message,
    }
}

/// Merges slices written by `render --pass-range` into `output`: their mean weighted by pass
/// counts. Refuses overlapping ranges, slices of another scene or settings, other sizes.
pub fn merge(inputs: &[PathBuf], output: &Path) -> Result<MergeSummary> {
    crate::film::check_output_path(output)?;
    if inputs.is_empty() {
        return Err(Error::Setting {
            field: "merge",
            message: "merge needs at least one slice".into(),
        });
    }
    let mut slices = Vec::new();
    for path in inputs {
        let tags = read_tags(path)?;
        let get = |k: &str| tags.iter().find(|t| t.0 == k).map(|t| t.1.clone());
        let range = get(TAG_PASS_RANGE).ok_or_else(|| {
            slice_error(
                path,
                format!("no {TAG_PASS_RANGE} in its header (not a progressive slice)"),
            )
        })?;
        let (first, end) =
            parse_range(&range).map_err(|e| slice_error(path, format!("pass range {e}")))?;
        slices.push(Slice {
            path: path.clone(),
            first,
            end,
            signature: get(TAG_SIGNATURE).unwrap_or_default(),
            image: Image::read(path)?,
        });
    }
    slices.sort_by_key(|s| s.first);
    for w in slices.windows(2) {
        if w[1].first < w[0].end {
            return Err(slice_error(
                &w[1].path,
                format!(
                    "(passes {}..{}) overlaps {} (passes {}..{})",
                    w[1].first,
                    w[1].end,
                    w[0].path.display(),
                    w[0].first,
                    w[0].end
                ),
            ));
        }
    }
    let first = &slices[0];
    for s in &slices[1..] {
        if s.signature != first.signature {
            return Err(slice_error(
                &s.path,
                format!(
                    "was rendered with another scene or other settings than {}",
                    first.path.display()
                ),
            ));
        }
        if (s.image.width, s.image.height) != (first.image.width, first.image.height) {
            return Err(slice_error(
                &s.path,
                format!(
                    "is {}x{}, {} is {}x{}",
                    s.image.width,
                    s.image.height,
                    first.path.display(),
                    first.image.width,
                    first.image.height
                ),
            ));
        }
    }
    let total: u32 = slices.iter().map(|s| s.end - s.first).sum();
    let mut sum = vec![[0.0f64; 3]; first.image.pixels.len()];
    for s in &slices {
        let w = (s.end - s.first) as f64;
        for (acc, p) in sum.iter_mut().zip(&s.image.pixels) {
            for c in 0..3 {
                acc[c] += w * p[c] as f64;
            }
        }
    }
    let image = Image {
        width: first.image.width,
        height: first.image.height,
        pixels: sum
            .iter()
            .map(|v| v.map(|x| (x / total as f64) as f32))
            .collect(),
    };
    let contiguous = slices.windows(2).all(|w| w[1].first == w[0].end);
    let range = if contiguous {
        format!(
            "{}..{}",
            first.first,
            slices.last().map_or(first.end, |s| s.end)
        )
    } else {
        slices
            .iter()
            .map(|s| format!("{}..{}", s.first, s.end))
            .collect::<Vec<_>>()
            .join(",")
    };
    let tags = [
        (TAG_PASS_RANGE, range.clone()),
        (TAG_PASSES, total.to_string()),
        (TAG_SIGNATURE, first.signature.clone()),
    ];
    image.write_tagged(output, 0.0, &tags)?;
    Ok(MergeSummary {
        slices: slices.len(),
        range,
        passes: total,
    })
}
