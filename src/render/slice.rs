//! Slices of a progressive render for array jobs: `--slice I/N` names slice I (0-based) of N
//! of the passes `0..P`, and `--slice /N` takes I from the scheduler's environment
//! (`SLURM_ARRAY_TASK_ID` of a Slurm array task, else `JOB_COMPLETION_INDEX` of a Kubernetes
//! Indexed Job pod), so a task script needs no arithmetic. The split is balanced: every
//! slice holds `P / N` passes and the first `P mod N` slices one more, in order, so slices
//! `0..N` tile `0..P` without gaps or overlaps.

use crate::error::{Error, Result};

/// Environment variables read, in this order, when `--slice /N` omits the index.
pub const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// A parsed `--slice` argument: slice `index` (None: from the environment) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SliceSpec {
    /// The 0-based slice index, when given on the command line.
    pub index: Option<u32>,
    /// How many slices the render is split into.
    pub count: u32,
}

fn setting(message: String) -> Error {
    Error::Setting {
        field: "slice",
        message,
    }
}

/// Parses `I/N` or `/N` (N >= 1; I < N is checked once I is known).
pub fn parse_spec(s: &str) -> std::result::Result<SliceSpec, String> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| format!("'{s}' is not I/N (slice I of N, 0-based) or /N"))?;
    let count: u32 = n
        .trim()
        .parse()
        .map_err(|e| format!("'{s}': slice count '{n}': {e}"))?;
    if count == 0 {
        return Err(format!("'{s}': the slice count must be at least 1"));
    }
    let index = match i.trim() {
        "" => None,
        i => Some(
            i.parse()
                .map_err(|e| format!("'{s}': slice index '{i}': {e}"))?,
        ),
    };
    Ok(SliceSpec { index, count })
}

/// The pass range `first..end` of slice `index` of `count` of the passes `0..passes`.
pub fn slice_range(passes: u32, index: u32, count: u32) -> Result<(u32, u32)> {
    if count == 0 {
        return Err(setting("the slice count must be at least 1".into()));
    }
    if index >= count {
        return Err(setting(format!(
            "slice {index}/{count}: the index must be below the count (slices are numbered 0..{count}; a Slurm array is --array=0-{})",
            count - 1
        )));
    }
    if count > passes {
        return Err(setting(format!(
            "{count} slices of {passes} passes: every slice needs a pass (use at most {passes} slices)"
        )));
    }
    let (q, r) = (passes / count, passes % count);
    let first = index * q + index.min(r);
    let len = q + u32::from(index < r);
    Ok((first, first + len))
}

/// The pass range of `--passes passes` with an optional `--slice`, reading a missing index
/// from the environment through `env` (see [`INDEX_VARIABLES`]).
pub fn pass_range_with_env(
    passes: u32,
    spec: Option<SliceSpec>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<(u32, u32)> {
    let Some(spec) = spec else {
        return Ok((0, passes));
    };
    let index = match spec.index {
        Some(i) => i,
        None => {
            let (name, value) = INDEX_VARIABLES
                .iter()
                .find_map(|&k| env(k).map(|v| (k, v)))
                .ok_or_else(|| {
                    setting(format!(
                        "--slice /{n} without an index, and neither {} nor {} is set: give it (--slice I/{n}) or run as a Slurm array task or an Indexed Job pod",
                        INDEX_VARIABLES[0],
                        INDEX_VARIABLES[1],
                        n = spec.count
                    ))
                })?;
            value
                .trim()
                .parse()
                .map_err(|e| setting(format!("{name}='{value}' is not a slice index: {e}")))?
        }
    };
    slice_range(passes, index, spec.count)
}

/// [`pass_range_with_env`] with the process environment.
pub fn pass_range(passes: u32, spec: Option<SliceSpec>) -> Result<(u32, u32)> {
    pass_range_with_env(passes, spec, |k| std::env::var(k).ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_tile_the_passes_in_order_and_differ_by_at_most_one() {
        for passes in 1..40 {
            for count in 1..=passes {
                let mut next = 0;
                let mut lens = Vec::new();
                for i in 0..count {
                    let (a, b) = slice_range(passes, i, count).unwrap();
                    assert_eq!(a, next, "{i}/{count} of {passes}");
                    assert!(b > a);
                    lens.push(b - a);
                    next = b;
                }
                assert_eq!(next, passes);
                let (lo, hi) = (lens.iter().min().unwrap(), lens.iter().max().unwrap());
                assert!(hi - lo <= 1, "{lens:?}");
                // The longer slices come first.
                assert!(lens.windows(2).all(|w| w[0] >= w[1]), "{lens:?}");
            }
        }
        assert_eq!(slice_range(10, 0, 4).unwrap(), (0, 3));
        assert_eq!(slice_range(10, 3, 4).unwrap(), (8, 10));
    }

    #[test]
    fn bad_slices_are_refused() {
        assert!(slice_range(8, 4, 4).is_err());
        assert!(slice_range(3, 0, 4)
            .unwrap_err()
            .to_string()
            .contains("at most 3"));
        assert!(parse_spec("4").is_err());
        assert!(parse_spec("1/0").is_err());
        assert!(parse_spec("x/4").is_err());
        assert_eq!(
            parse_spec("/4").unwrap(),
            SliceSpec {
                index: None,
                count: 4
            }
        );
        assert_eq!(parse_spec("2/4").unwrap().index, Some(2));
    }

    #[test]
    fn a_missing_index_comes_from_the_scheduler() {
        let spec = parse_spec("/4").ok();
        let none = |_: &str| None;
        let err = pass_range_with_env(8, spec, none).unwrap_err().to_string();
        assert!(err.contains("SLURM_ARRAY_TASK_ID"), "{err}");
        let slurm = |k: &str| (k == "SLURM_ARRAY_TASK_ID").then(|| "3".to_string());
        assert_eq!(pass_range_with_env(8, spec, slurm).unwrap(), (6, 8));
        let k8s = |k: &str| (k == "JOB_COMPLETION_INDEX").then(|| "1".to_string());
        assert_eq!(pass_range_with_env(8, spec, k8s).unwrap(), (2, 4));
        let both = |k: &str| Some(if k == "SLURM_ARRAY_TASK_ID" { "0" } else { "1" }.into());
        assert_eq!(pass_range_with_env(8, spec, both).unwrap(), (0, 2));
        let bad = |_: &str| Some("two".to_string());
        assert!(pass_range_with_env(8, spec, bad).is_err());
        let high = |_: &str| Some("4".to_string());
        assert!(pass_range_with_env(8, spec, high).is_err());
        // An explicit index wins over the environment.
        assert_eq!(
            pass_range_with_env(8, parse_spec("1/4").ok(), high).unwrap(),
            (2, 4)
        );
        assert_eq!(pass_range_with_env(8, None, high).unwrap(), (0, 8));
    }
}
