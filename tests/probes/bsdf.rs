//! The BSDF library's oracle probe (`probe_bsdf.wgsl` beside this file): composed after the
//! prelude and the BSDF library alone, for tests/bsdf_gpu.rs.

use gpu_photon::integrators::gpu::bsdf_params::bsdf_library;
use gpu_photon::integrators::gpu::codes::wgsl_prelude;

/// The probe's module: the prelude, the BSDF library, `probe_bsdf.wgsl`.
pub fn source() -> String {
    [
        wgsl_prelude(),
        bsdf_library(),
        include_str!("probe_bsdf.wgsl").to_string(),
    ]
    .join("\n")
}
