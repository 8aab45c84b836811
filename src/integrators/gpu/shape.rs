//! The kernel shape: the workgroup widths, the radiance cache build's cooperative width and
//! the loop guard, chosen per adapter (its subgroup size, limits and type) and passed to every
//! kernel as WGSL override constants (`WG_SIZE`, `GATHER_TILE`, `CACHE_LANES`, `LOOP_GUARD`,
//! declared with the default shape's values by `codes::wgsl_prelude`).
//!
//! `GPU_PHOTON_KERNEL_SHAPE` forces a shape ([`KernelShape::parse`]): `nvidia`, `lavapipe`,
//! or `subgroup:N` with optional `guard:on|off`, `wg:N`, `tile:N`, `lanes:N`, comma-separated.

use crate::integrators::gpu::codes::{
    CACHE_BINS, CACHE_CANDIDATES, CACHE_LANES, CACHE_NEAR, CACHE_SELECT_LOW, GATHER_TILE, WG_SIZE,
};

/// The environment variable that forces a kernel shape.
pub const SHAPE_ENV: &str = "GPU_PHOTON_KERNEL_SHAPE";

/// Widest workgroup the device is asked for (`GpuContext::new` requests 256 invocations).
pub const MAX_WG: u32 = 256;

/// How the kernels are shaped for one adapter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct KernelShape {
    /// The subgroup (SIMD group, warp) width the shape was derived from.
    pub subgroup: u32,
    /// Workgroup width of the one-dimensional kernels (override `WG_SIZE`).
    pub wg_size: u32,
    /// The gather's workgroups are `gather_tile` x `gather_tile` pixels (`GATHER_TILE`).
    pub gather_tile: u32,
    /// Invocations that share one cache point's search in `build_cache` (`CACHE_LANES`).
    pub cache_lanes: u32,
    /// Every loop pays `spend()`'s budget (`LOOP_GUARD`): lavapipe ends loops silently after
    /// 65,535 iterations, so CPU adapters keep it; hardware GPUs compile it out.
    pub loop_guard: bool,
}

/// The adapter facts a shape is derived from.
#[derive(Clone, Copy, Debug)]
pub struct AdapterFacts {
    /// Largest subgroup the adapter reports (0: unknown).
    pub subgroup_max: u32,
    /// `DeviceType::Cpu` (lavapipe, llvmpipe, any software adapter).
    pub cpu: bool,
    /// `max_compute_workgroup_storage_size`, bytes.
    pub workgroup_storage: u32,
    /// `max_compute_invocations_per_workgroup`.
    pub invocations: u32,
}

impl AdapterFacts {
    /// The facts of a wgpu adapter.
    pub fn of(adapter: &wgpu::Adapter) -> Self {
        Self::from_parts(&adapter.get_info(), &adapter.limits())
    }

    /// The facts of an adapter's info and limits.
    pub fn from_parts(info: &wgpu::AdapterInfo, limits: &wgpu::Limits) -> Self {
        AdapterFacts {
            subgroup_max: info.subgroup_max_size,
            cpu: info.device_type == wgpu::DeviceType::Cpu,
            workgroup_storage: limits.max_compute_workgroup_storage_size,
            invocations: limits.max_compute_invocations_per_workgroup,
        }
    }
}

/// Bytes of `build_cache`'s workgroup memory with `lanes` cooperating invocations: each
/// variable of src/integrators/gpu/cache_build.wgsl, rounded up to 16 bytes (tests/kernel_shape.rs checks
/// the list against the module).
pub fn cache_build_bytes(lanes: u32) -> u32 {
    let pad = |b: u32| b.div_ceil(16) * 16;
    let fixed = [
        CACHE_BINS * 4,                            // hist
        (CACHE_SELECT_LOW + CACHE_CANDIDATES) * 8, // sel
        4,                                         // n_low
        4,                                         // n_cand
        CACHE_NEAR * 8,                            // near
        4,                                         // n_near
        4,                                         // m_bits
        8,                                         // wg_u
        16,                                        // wg_pick
        8,                                         // wg_kth
        4,                                         // wg_point
        4,                                         // wg_scalar
        8,                                         // wg_counts
    ];
    // lane_sum (vec2), lane_hi and lane_lo (vec3, a 16-byte stride).
    let per_lane = [8, 16, 16];
    fixed.iter().map(|&b| pad(b)).sum::<u32>()
        + per_lane.iter().map(|&b| pad(b * lanes)).sum::<u32>()
}

impl KernelShape {
    /// Today's lavapipe shape, also the WGSL defaults (the probes run with it).
    pub const DEFAULT: KernelShape = KernelShape {
        subgroup: CACHE_LANES,
        wg_size: WG_SIZE,
        gather_tile: GATHER_TILE,
        cache_lanes: CACHE_LANES,
        loop_guard: true,
    };

    /// The shape for `facts`: workgroups of 4 subgroups (64 to 256 invocations), the cache
    /// build one subgroup wide (a power of two dividing `CACHE_BINS`, within the adapter's
    /// workgroup memory), the loop guard on CPU adapters only. An adapter that reports no
    /// subgroup size gets the default shape's widths.
    pub fn for_adapter(facts: &AdapterFacts) -> Self {
        let subgroup = match facts.subgroup_max {
            0 => Self::DEFAULT.subgroup,
            s => s,
        };
        Self::with_subgroup(subgroup, facts.cpu, facts)
    }

    /// The shape of a `subgroup`-wide adapter, with or without the loop guard, clamped to
    /// `facts`' limits.
    pub fn with_subgroup(subgroup: u32, loop_guard: bool, facts: &AdapterFacts) -> Self {
        let invocations = facts.invocations.clamp(1, MAX_WG);
        let wg_size = floor_pow2(
            subgroup
                .saturating_mul(4)
                .clamp(64, MAX_WG)
                .min(invocations),
        );
        KernelShape {
            subgroup,
            wg_size,
            gather_tile: GATHER_TILE,
            cache_lanes: Self::clamp_lanes(subgroup, facts),
            loop_guard,
        }
    }

    /// The widest power of two up to `lanes` that divides `CACHE_BINS` and whose cache build
    /// fits the adapter's workgroup memory and invocations (at least 1).
    fn clamp_lanes(lanes: u32, facts: &AdapterFacts) -> u32 {
        let mut l = floor_pow2(lanes.clamp(1, CACHE_BINS.min(facts.invocations.max(1))));
        while l > 1 && cache_build_bytes(l) > facts.workgroup_storage {
            l /= 2;
        }
        l
    }

    /// The shape `spec` (the value of [`SHAPE_ENV`]) forces on an adapter with `facts`:
    /// `nvidia` (a 32-wide warp, no loop guard), `lavapipe` (the default shape), or
    /// `subgroup:N` with optional `guard:on|off` (default: what the adapter needs),
    /// `wg:N`, `tile:N` and `lanes:N`; widths stay within the adapter's limits.
    pub fn parse(spec: &str, facts: &AdapterFacts) -> Result<Self, String> {
        let bad = |why: String| format!("{SHAPE_ENV}={spec:?}: {why}");
        match spec.trim() {
            "nvidia" => return Ok(Self::with_subgroup(32, false, facts)),
            "lavapipe" => return Ok(Self::DEFAULT),
            _ => {}
        }
        let mut subgroup = None;
        let (mut guard, mut wg, mut tile, mut lanes) = (None, None, None, None);
        for part in spec.split(',').map(str::trim) {
            let (key, value) = part
                .split_once(':')
                .ok_or_else(|| bad(format!("`{part}` is not key:value (or nvidia, lavapipe)")))?;
            let num = || -> Result<u32, String> {
                match value.trim().parse::<u32>() {
                    Ok(n) if n.is_power_of_two() && n <= MAX_WG => Ok(n),
                    _ => Err(bad(format!(
                        "{key} must be a power of two from 1 to {MAX_WG}, not `{value}`"
                    ))),
                }
            };
            match key.trim() {
                "subgroup" => subgroup = Some(num()?),
                "wg" => wg = Some(num()?),
                "tile" => tile = Some(num()?),
                "lanes" => lanes = Some(num()?),
                "guard" => {
                    guard = Some(match value.trim() {
                        "on" => true,
                        "off" => false,
                        v => return Err(bad(format!("guard must be on or off, not `{v}`"))),
                    })
                }
                k => {
                    return Err(bad(format!(
                        "unknown key `{k}` (subgroup, guard, wg, tile, lanes)"
                    )))
                }
            }
        }
        let subgroup = subgroup.ok_or_else(|| bad("subgroup:N is required".into()))?;
        let mut shape = Self::with_subgroup(subgroup, guard.unwrap_or(facts.cpu), facts);
        let invocations = facts.invocations.clamp(1, MAX_WG);
        if let Some(w) = wg {
            shape.wg_size = w.min(invocations).max(1);
        }
        if let Some(t) = tile {
            if t * t > invocations {
                return Err(bad(format!("tile:{t} needs {} invocations", t * t)));
            }
            shape.gather_tile = t;
        }
        if let Some(l) = lanes {
            shape.cache_lanes = Self::clamp_lanes(l, facts);
        }
        Ok(shape)
    }

    /// The adapter's shape, or the one [`SHAPE_ENV`] forces (an error names the variable).
    pub fn from_env(facts: &AdapterFacts) -> Result<Self, String> {
        match std::env::var(SHAPE_ENV) {
            Ok(spec) if !spec.trim().is_empty() => Self::parse(&spec, facts),
            _ => Ok(Self::for_adapter(facts)),
        }
    }

    /// The override constants of the shape (pipeline creation).
    pub fn overrides(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("WG_SIZE", self.wg_size as f64),
            ("GATHER_TILE", self.gather_tile as f64),
            ("CACHE_LANES", self.cache_lanes as f64),
            ("LOOP_GUARD", self.loop_guard as u32 as f64),
        ]
    }

    /// "subgroup 32, workgroups 128, gather tile 8x8, cache lanes 32, loop guard off".
    pub fn describe(&self) -> String {
        format!(
            "subgroup {}, workgroups {}, gather tile {t}x{t}, cache lanes {}, loop guard {}",
            self.subgroup,
            self.wg_size,
            self.cache_lanes,
            if self.loop_guard { "on" } else { "off" },
            t = self.gather_tile
        )
    }
}

/// The largest power of two at most `n` (1 for 0).
fn floor_pow2(n: u32) -> u32 {
    if n <= 1 {
        1
    } else {
        1 << (31 - n.leading_zeros())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lavapipe() -> AdapterFacts {
        AdapterFacts {
            subgroup_max: 8,
            cpu: true,
            workgroup_storage: 32 << 10,
            invocations: 1024,
        }
    }

    #[test]
    fn floor_pow2_rounds_down() {
        assert_eq!(
            [0, 1, 2, 3, 8, 9, 255, 256].map(floor_pow2),
            [1, 1, 2, 2, 8, 8, 128, 256]
        );
    }

    #[test]
    fn lanes_shrink_to_fit_workgroup_memory() {
        let mut f = lavapipe();
        f.workgroup_storage = 16 << 10;
        // 32 lanes need 16,800 bytes: above 16 KiB, so 16.
        assert_eq!(KernelShape::with_subgroup(32, false, &f).cache_lanes, 16);
        f.workgroup_storage = 48 << 10;
        assert_eq!(KernelShape::with_subgroup(32, false, &f).cache_lanes, 32);
    }

    #[test]
    fn bad_specs_name_the_variable_and_the_part() {
        let f = lavapipe();
        for (spec, want) in [
            (
                "subgroup:24",
                "subgroup must be a power of two from 1 to 256, not `24`",
            ),
            ("guard:off", "subgroup:N is required"),
            (
                "subgroup:32,guard:maybe",
                "guard must be on or off, not `maybe`",
            ),
            ("subgroup:32,warp:4", "unknown key `warp`"),
            ("amd", "`amd` is not key:value"),
        ] {
            let e = KernelShape::parse(spec, &f).unwrap_err();
            assert!(e.starts_with("GPU_PHOTON_KERNEL_SHAPE=\""), "{e}");
            assert!(e.contains(want), "{spec}: {e}");
        }
    }
}
