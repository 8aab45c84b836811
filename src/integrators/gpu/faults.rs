//! The device's failures as the backend meets them, and their injection for tests.
//!
//! `GPU_PHOTON_FAULT=device-lost|oom|timeout|shader` (read here, once) makes a render meet
//! one fault through wgpu's real paths: `device-lost` destroys the device once the first
//! submission is made (the `GPU_PHOTON_FAULT_AFTER`-th with that variable: a later batch or
//! pass); `oom` asks for the image accumulator one byte over the device's largest
//! buffer; `timeout` gives the watchdog no time at all; `shader` compiles the gather kernel
//! from a malformed source. `GPU_PHOTON_WATCHDOG=SECONDS` sets how long one wait for the
//! device may take before the render ends with an error ([`DEFAULT_WATCHDOG`]).

use std::sync::OnceLock;
use std::time::Duration;

/// A fault to inject.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// The device is destroyed after the first pass's submission.
    DeviceLost,
    /// The image accumulator is asked for one byte over the largest buffer.
    OutOfMemory,
    /// The watchdog allows no time.
    Timeout,
    /// The gather kernel's source does not parse.
    Shader,
}

impl Fault {
    /// The names `GPU_PHOTON_FAULT` takes, in the order of [`Fault::ALL`].
    pub const NAMES: [&'static str; 4] = ["device-lost", "oom", "timeout", "shader"];
    /// Every fault.
    pub const ALL: [Fault; 4] = [
        Fault::DeviceLost,
        Fault::OutOfMemory,
        Fault::Timeout,
        Fault::Shader,
    ];

    /// The fault named `name` (one of [`Fault::NAMES`]).
    pub fn parse(name: &str) -> Option<Fault> {
        let i = Self::NAMES.iter().position(|&n| n == name)?;
        Some(Self::ALL[i])
    }
}

/// How long one wait for the device may take by default: far beyond any pass this backend
/// renders (minutes on lavapipe), so only a hung device meets it.
pub const DEFAULT_WATCHDOG: Duration = Duration::from_secs(1800);

/// The fault `GPU_PHOTON_FAULT` asks for (an unknown name is ignored with a warning).
pub fn injected() -> Option<Fault> {
    static FAULT: OnceLock<Option<Fault>> = OnceLock::new();
    *FAULT.get_or_init(|| {
        let name = std::env::var("GPU_PHOTON_FAULT").ok()?;
        let fault = Fault::parse(&name);
        if fault.is_none() {
            crate::warning::warn(format!(
                "GPU_PHOTON_FAULT={name} ignored: expected one of {}",
                Fault::NAMES.join(", ")
            ));
        }
        fault
    })
}

/// After how many submissions an injected `device-lost` destroys the device:
/// `GPU_PHOTON_FAULT_AFTER` (at least 1), else 1.
pub fn lose_after() -> u32 {
    static AFTER: OnceLock<u32> = OnceLock::new();
    *AFTER.get_or_init(|| {
        std::env::var("GPU_PHOTON_FAULT_AFTER")
            .ok()
            .and_then(|s| s.trim().parse::<u32>().ok())
            .map_or(1, |n| n.max(1))
    })
}

/// How long one wait for the device may take: `GPU_PHOTON_WATCHDOG` seconds, else
/// [`DEFAULT_WATCHDOG`]; nothing under an injected timeout.
pub fn watchdog() -> Duration {
    static WATCHDOG: OnceLock<Duration> = OnceLock::new();
    if injected() == Some(Fault::Timeout) {
        return Duration::ZERO;
    }
    *WATCHDOG.get_or_init(|| {
        std::env::var("GPU_PHOTON_WATCHDOG")
            .ok()
            .and_then(|s| s.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s > 0.0)
            .map_or(DEFAULT_WATCHDOG, Duration::from_secs_f64)
    })
}

/// One line for a wgpu error: its kind, the innermost cause wgpu gives (its text is a chain
/// of "Caused by:" blocks) and, for a shader, where in the source (`wgsl:LINE:COLUMN`).
pub fn describe(e: &wgpu::Error) -> String {
    let (kind, text) = match e {
        wgpu::Error::OutOfMemory { .. } => ("out of device memory", e.to_string()),
        wgpu::Error::Validation { description, .. } => ("validation error", description.clone()),
        wgpu::Error::Internal { description, .. } => ("internal error", description.clone()),
    };
    let (mut cause, mut at) = (None, None);
    for line in text.lines().map(str::trim) {
        if let Some(place) = line.strip_prefix("┌─") {
            at = Some(place.trim());
            break;
        }
        let context = line.is_empty()
            || line == "Caused by:"
            || line.starts_with("Validation Error")
            || line.starts_with("Out of Memory")
            || line.starts_with("In ");
        if !context {
            cause = Some(line.trim_end_matches('.'));
        }
    }
    match (cause, at) {
        (None, _) => kind.to_string(),
        (Some(c), None) => format!("{kind}: {c}"),
        (Some(c), Some(at)) => format!("{kind}: {c} ({at})"),
    }
}
