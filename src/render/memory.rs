//! The memory this process may still use, and byte counts as messages show them. Read by the
//! render's estimate (`crate::render::budget`) and by the scene's budget (`crate::scene::SceneBudgets`),
//! which both refuse what would not fit before allocating it.

/// Memory available to this process and where the figure comes from: `GPU_PHOTON_MEMORY`
/// (bytes, or with a K, M or G suffix) when set, else the least of `MemAvailable` in
/// /proc/meminfo, the room left under the cgroup's limit and the address space left under
/// the process's limit (`ulimit -v`); `None` where none is known.
pub fn available() -> Option<(u64, &'static str)> {
    if let Ok(v) = std::env::var("GPU_PHOTON_MEMORY") {
        return parse_bytes(&v).map(|b| (b, "GPU_PHOTON_MEMORY"));
    }
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        let line = t.lines().find(|l| l.starts_with("MemAvailable:"))?;
        let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some((kib * 1024, "MemAvailable in /proc/meminfo"))
    });
    let cgroup = cgroup_room().map(|b| (b, "the cgroup's memory limit"));
    let address = address_space_room().map(|b| (b, "the address-space limit (ulimit -v)"));
    [meminfo, cgroup, address]
        .into_iter()
        .flatten()
        .min_by_key(|&(bytes, _)| bytes)
}

/// Bytes left under this process's cgroup memory limit (v2 `memory.max`, else v1
/// `memory.limit_in_bytes`), when it has one.
fn cgroup_room() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok()?.trim().parse::<u64>().ok();
    let (limit, used) = match read("/sys/fs/cgroup/memory.max") {
        Some(l) => (l, read("/sys/fs/cgroup/memory.current")?),
        None => (
            read("/sys/fs/cgroup/memory/memory.limit_in_bytes")?,
            read("/sys/fs/cgroup/memory/memory.usage_in_bytes")?,
        ),
    };
    // v1 writes "no limit" as a number near 2^63.
    (limit < 1 << 60).then(|| limit.saturating_sub(used))
}

/// Address space left under this process's `RLIMIT_AS` (its soft limit, from
/// /proc/self/limits, less the `VmSize` of /proc/self/status), when it has one: past it every
/// allocation fails, and Rust aborts.
fn address_space_room() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    // "Max address space  SOFT  HARD  bytes": "unlimited" does not parse.
    let soft: u64 = line.split_whitespace().nth(3)?.parse().ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmSize:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(soft.saturating_sub(kib * 1024))
}

/// `123`, `64K`, `512M`, `8G` (binary units) as bytes.
pub fn parse_bytes(s: &str) -> Option<u64> {
    let s = s.trim();
    let (digits, unit) = match s.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => (&s[..i], c.to_ascii_uppercase()),
        _ => (s, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        'T' => 40,
        _ => return None,
    };
    digits.trim().parse::<u64>().ok()?.checked_mul(1 << shift)
}

/// Bytes in the largest binary unit that keeps the number at least 1 (`1.5 GiB`, `12 KiB`).
pub fn size(bytes: u64) -> String {
    let units = [(40, "TiB"), (30, "GiB"), (20, "MiB"), (10, "KiB")];
    match units.iter().find(|&&(shift, _)| bytes >= 1 << shift) {
        Some(&(shift, unit)) => format!("{:.1} {unit}", bytes as f64 / (1u64 << shift) as f64),
        None => format!("{bytes} bytes"),
    }
}
