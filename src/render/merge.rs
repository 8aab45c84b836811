//! Slices of a progressive render and their merge: the header tags a slice carries (its pass
//! range, the pass count of the whole render it belongs to, a fingerprint of the scene and
//! settings), and the pass-weighted mean of slices rendered anywhere, which equals the image
//! of a single run over the same passes (bit for bit when every slice holds one pass: the
//! sums are the same, in the same order; else to within the f32 rounding of each slice's
//! mean). The merge reads every header first and refuses what does not fit, then adds one
//! slice's pixels at a time into one f64 accumulator: its memory is that of one image,
//! whatever the number of slices.

use crate::error::{Error, Result};
use crate::render::film::{read_header, Image};
use crate::render::progressive::Accumulator;
use crate::settings::RenderSettings;
use std::fmt;
use std::path::{Path, PathBuf};

/// Header tag holding a slice's pass range `A..B` (or `A..B,C..D` after a merge of gaps).
pub const TAG_PASS_RANGE: &str = "gpu_photon.pass_range";
/// Header tag holding the number of passes in a slice.
pub const TAG_PASSES: &str = "gpu_photon.passes";
/// Header tag holding the fingerprint of the scene file and settings.
pub const TAG_SIGNATURE: &str = "gpu_photon.signature";
/// Header tag holding the pass count `P` of the render `0..P` a file holds a part of
/// (`render --passes P --slice I/N`, an interrupted `--passes P`, a partial merge). Absent
/// from a file that holds all its render's passes `0..P`, and from `--pass-range` slices.
pub const TAG_TOTAL: &str = "gpu_photon.total_passes";

/// A fingerprint of the scene file and every setting but the pass range and count (the
/// render's pass count is a tag of its own, [`TAG_TOTAL`]): slices to merge must share it.
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
        passes: 0,
        timed_phases: false,
        ..s.clone()
    };
    Ok(format!("scene-fnv1a {h:016x}; {s:?}"))
}

/// The header tags of a slice holding the passes in `acc`, of a render of `total` passes
/// `0..total` when known (`--passes`). [`TAG_TOTAL`] is written only when the slice holds
/// less than `0..total`, so a whole render's file stays the same bytes.
pub fn slice_tags(
    acc: &Accumulator,
    signature: &str,
    total: Option<u32>,
) -> Vec<(&'static str, String)> {
    let mut tags = vec![
        (
            TAG_PASS_RANGE,
            format!("{}..{}", acc.first, acc.first + acc.count),
        ),
        (TAG_PASSES, acc.count.to_string()),
        (TAG_SIGNATURE, signature.to_string()),
    ];
    if let Some(t) = total.filter(|&t| (acc.first, acc.count) != (0, t)) {
        tags.push((TAG_TOTAL, t.to_string()));
    }
    tags
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

/// Parses the pass ranges of a header tag: `A..B` or, after a partial merge, `A..B,C..D`.
pub fn parse_ranges(s: &str) -> std::result::Result<Vec<(u32, u32)>, String> {
    s.split(',').map(parse_range).collect()
}

/// Writes ranges as `A..B,C..D`, joining touching ones (`0..2,2..5` is `0..5`).
pub fn format_ranges(ranges: &[(u32, u32)]) -> String {
    let mut sorted = ranges.to_vec();
    sorted.sort();
    let mut joined: Vec<(u32, u32)> = Vec::new();
    for (a, b) in sorted {
        match joined.last_mut() {
            Some(last) if last.1 == a => last.1 = b,
            _ => joined.push((a, b)),
        }
    }
    let parts: Vec<String> = joined.iter().map(|(a, b)| format!("{a}..{b}")).collect();
    parts.join(",")
}

/// The passes of `0..total` (or, without a total, between the first and the last range)
/// that no range holds, in order. `ranges` must not overlap.
pub fn missing_ranges(ranges: &[(u32, u32)], total: Option<u32>) -> Vec<(u32, u32)> {
    let mut sorted = ranges.to_vec();
    sorted.sort();
    let mut missing = Vec::new();
    let mut next = match total {
        Some(_) => 0,
        None => sorted.first().map_or(0, |r| r.0),
    };
    for &(a, b) in &sorted {
        if a > next {
            missing.push((next, a));
        }
        next = next.max(b);
    }
    if let Some(t) = total.filter(|&t| t > next) {
        missing.push((next, t));
    }
    missing
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
    /// The pass count of the whole render, when the slices record it.
    pub total: Option<u32>,
    /// Pass ranges no slice held (empty unless `partial`).
    pub missing: Vec<(u32, u32)>,
}

impl fmt::Display for MergeSummary {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "{} slices, passes {} ({} passes)",
            self.slices, self.range, self.passes
        )?;
        if !self.missing.is_empty() {
            write!(
                f,
                "; partial: passes {} missing",
                format_ranges(&self.missing)
            )?;
            if let Some(t) = self.total {
                write!(f, " of 0..{t}")?;
            }
        }
        Ok(())
    }
}

/// A slice's header, read and checked before any pixel is.
struct Slice {
    path: PathBuf,
    ranges: Vec<(u32, u32)>,
    passes: u32,
    total: Option<u32>,
    signature: String,
    size: (u32, u32),
}

fn slice_error(path: &Path, message: String) -> Error {
    Error::Image {
        path: path.to_path_buf(),
        message,
    }
}

fn read_slice(path: &Path) -> Result<Slice> {
    let header = read_header(path)?;
    let get = |k: &str| header.tags.iter().find(|t| t.0 == k).map(|t| t.1.clone());
    let range = get(TAG_PASS_RANGE).ok_or_else(|| {
        slice_error(
            path,
            format!("no {TAG_PASS_RANGE} in its header (not a progressive slice)"),
        )
    })?;
    let ranges =
        parse_ranges(&range).map_err(|e| slice_error(path, format!("{TAG_PASS_RANGE} {e}")))?;
    let passes: u32 = ranges.iter().map(|r| r.1 - r.0).sum();
    if let Some(p) = get(TAG_PASSES) {
        if p.trim().parse() != Ok(passes) {
            return Err(slice_error(
                path,
                format!("{TAG_PASSES} is '{p}', but {TAG_PASS_RANGE} {range} holds {passes}"),
            ));
        }
    }
    let total = match get(TAG_TOTAL) {
        None => None,
        Some(t) => Some(
            t.trim()
                .parse::<u32>()
                .map_err(|e| slice_error(path, format!("{TAG_TOTAL} '{t}': {e}")))?,
        ),
    };
    Ok(Slice {
        path: path.to_path_buf(),
        ranges,
        passes,
        total,
        signature: get(TAG_SIGNATURE).unwrap_or_default(),
        size: (header.width, header.height),
    })
}

/// Merges slices written by `render --passes P --slice I/N` or `--pass-range` into `output`:
/// their mean weighted by pass counts. Reads every header first and refuses overlapping
/// ranges, slices of another scene, settings, size or pass count, and (unless `partial`)
/// missing passes: those of `0..P` no slice holds, or, for slices that do not record `P`,
/// gaps between their ranges. Then adds the slices' pixels one slice at a time, in pass
/// order.
pub fn merge(inputs: &[PathBuf], output: &Path, partial: bool) -> Result<MergeSummary> {
    crate::render::film::check_output_path(output)?;
    if inputs.is_empty() {
        return Err(Error::Setting {
            field: "merge",
            message: "merge needs at least one slice".into(),
        });
    }
    let mut slices = inputs
        .iter()
        .map(|p| read_slice(p))
        .collect::<Result<Vec<_>>>()?;
    slices.sort_by_key(|s| s.ranges.iter().min().copied());
    let mut all: Vec<((u32, u32), usize)> = slices
        .iter()
        .enumerate()
        .flat_map(|(i, s)| s.ranges.iter().map(move |&r| (r, i)))
        .collect();
    all.sort();
    for w in all.windows(2) {
        let (((a0, b0), i0), ((a1, b1), i1)) = (w[0], w[1]);
        if a1 < b0 {
            return Err(slice_error(
                &slices[i1].path,
                format!(
                    "(passes {a1}..{b1}) overlaps {} (passes {a0}..{b0})",
                    slices[i0].path.display()
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
        if s.size != first.size {
            return Err(slice_error(
                &s.path,
                format!(
                    "is {}x{}, {} is {}x{}",
                    s.size.0,
                    s.size.1,
                    first.path.display(),
                    first.size.0,
                    first.size.1
                ),
            ));
        }
    }
    let total = check_totals(&slices)?;
    let ranges: Vec<(u32, u32)> = all.iter().map(|r| r.0).collect();
    let missing = missing_ranges(&ranges, total);
    if !missing.is_empty() && !partial {
        let of = total.map_or_else(
            || "between the slices' ranges".to_string(),
            |t| format!("of the render's 0..{t}"),
        );
        return Err(slice_error(
            output,
            format!(
                "not written: passes {} {of} are missing (no slice holds them); merge their slices too, or pass --partial for the mean of the {} passes there",
                format_ranges(&missing),
                slices.iter().map(|s| s.passes).sum::<u32>()
            ),
        ));
    }
    let image = accumulate(&slices)?;
    let range = format_ranges(&ranges);
    let passes: u32 = slices.iter().map(|s| s.passes).sum();
    let mut tags = vec![
        (TAG_PASS_RANGE, range.clone()),
        (TAG_PASSES, passes.to_string()),
        (TAG_SIGNATURE, first.signature.clone()),
    ];
    if let Some(t) = total.filter(|&t| range != format!("0..{t}")) {
        tags.push((TAG_TOTAL, t.to_string()));
    }
    image.write_tagged(output, 0.0, &tags)?;
    Ok(MergeSummary {
        slices: slices.len(),
        range,
        passes,
        total,
        missing,
    })
}

/// The render's pass count the slices record (all that record one must agree), checking
/// that every range lies within it.
fn check_totals(slices: &[Slice]) -> Result<Option<u32>> {
    let Some(with) = slices.iter().find(|s| s.total.is_some()) else {
        return Ok(None);
    };
    let total = with.total;
    for s in slices {
        if s.total.is_some() && s.total != total {
            return Err(slice_error(
                &s.path,
                format!(
                    "is a slice of a render of {} passes, {} of one of {} ({TAG_TOTAL})",
                    s.total.unwrap_or(0),
                    with.path.display(),
                    total.unwrap_or(0)
                ),
            ));
        }
        if let Some(&(a, b)) = s.ranges.iter().find(|r| Some(r.1) > total) {
            return Err(slice_error(
                &s.path,
                format!(
                    "(passes {a}..{b}) lies beyond the {} passes of the render {} belongs to",
                    total.unwrap_or(0),
                    with.path.display()
                ),
            ));
        }
    }
    Ok(total)
}

/// The pass-weighted mean of the slices (sorted by pass), reading one slice's pixels at a
/// time.
fn accumulate(slices: &[Slice]) -> Result<Image> {
    let (width, height) = slices[0].size;
    let mut sum = vec![[0.0f64; 3]; width as usize * height as usize];
    for s in slices {
        let image = Image::read(&s.path)?;
        if (image.width, image.height) != s.size {
            return Err(slice_error(
                &s.path,
                format!(
                    "its pixels are {}x{}, its header says {}x{}",
                    image.width, image.height, s.size.0, s.size.1
                ),
            ));
        }
        let w = s.passes as f64;
        for (acc, p) in sum.iter_mut().zip(&image.pixels) {
            for c in 0..3 {
                acc[c] += w * p[c] as f64;
            }
        }
    }
    let total: u32 = slices.iter().map(|s| s.passes).sum();
    Ok(Image {
        width,
        height,
        pixels: sum
            .iter()
            .map(|v| v.map(|x| (x / total as f64) as f32))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_join_and_show_their_gaps() {
        assert_eq!(parse_ranges("0..2,5..6").unwrap(), vec![(0, 2), (5, 6)]);
        assert!(parse_ranges("0..2,").is_err());
        assert_eq!(format_ranges(&[(2, 5), (0, 2), (7, 8)]), "0..5,7..8");
        assert_eq!(
            missing_ranges(&[(2, 3), (5, 6)], Some(8)),
            [(0, 2), (3, 5), (6, 8)]
        );
        assert_eq!(missing_ranges(&[(0, 4), (4, 8)], Some(8)), []);
        // Without a total only the gaps between ranges are known to be missing.
        assert_eq!(missing_ranges(&[(5, 6), (2, 3)], None), [(3, 5)]);
        assert_eq!(missing_ranges(&[(2, 3)], None), []);
    }

    #[test]
    fn the_total_is_tagged_only_on_part_of_a_render() {
        let mut acc = Accumulator::new(1, 1, 2);
        acc.count = 2;
        let tags = slice_tags(&acc, "sig", Some(8));
        assert_eq!(tags.last().unwrap(), &(TAG_TOTAL, "8".to_string()));
        assert_eq!(slice_tags(&acc, "sig", None).len(), 3);
        let mut whole = Accumulator::new(1, 1, 0);
        whole.count = 8;
        assert_eq!(slice_tags(&whole, "sig", Some(8)).len(), 3);
    }
}
