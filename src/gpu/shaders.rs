//! Shader composition: each kernel is its own file in `shaders/`, prefixed by the shared
//! libraries of `shaders/common/` in a fixed order (no text substitution inside a kernel;
//! scene features reach WGSL as pipeline-overridable constants).

/// The compute kernels of the GPU backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    TracePhotons,
    BuildGrid,
    Gather,
}

const TYPES: &str = include_str!("../../shaders/common/types.wgsl");
const PHOTON: &str = include_str!("../../shaders/common/photon.wgsl");
const RNG: &str = include_str!("../../shaders/common/rng.wgsl");
const SAMPLING: &str = include_str!("../../shaders/common/sampling.wgsl");
const SCENE: &str = include_str!("../../shaders/common/scene.wgsl");
const INTERSECT: &str = include_str!("../../shaders/common/intersect.wgsl");
const MATERIAL: &str = include_str!("../../shaders/common/material.wgsl");
const LIGHT: &str = include_str!("../../shaders/common/light.wgsl");
const GRID: &str = include_str!("../../shaders/common/grid.wgsl");
const MAP: &str = include_str!("../../shaders/common/map.wgsl");
const TRACE_PHOTONS: &str = include_str!("../../shaders/trace_photons.wgsl");
const BUILD_GRID: &str = include_str!("../../shaders/build_grid.wgsl");
const GATHER: &str = include_str!("../../shaders/gather.wgsl");

impl Kernel {
    pub const ALL: [Kernel; 3] = [Kernel::TracePhotons, Kernel::BuildGrid, Kernel::Gather];

    pub fn name(self) -> &'static str {
        match self {
            Kernel::TracePhotons => "trace_photons",
            Kernel::BuildGrid => "build_grid",
            Kernel::Gather => "gather",
        }
    }

    /// The composed WGSL source of this kernel's module.
    pub fn source(self) -> String {
        let libs: &[&str] = &[
            TYPES, PHOTON, RNG, SAMPLING, SCENE, INTERSECT, MATERIAL, LIGHT, GRID,
        ];
        let own: &[&str] = match self {
            Kernel::TracePhotons => &[MAP, TRACE_PHOTONS],
            Kernel::BuildGrid => &[MAP, BUILD_GRID],
            Kernel::Gather => &[GATHER],
        };
        libs.iter()
            .chain(own)
            .copied()
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// Parses and validates a composed module with naga (no GPU needed).
pub fn validate(source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok(module)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kernel_parses_and_validates() {
        for k in Kernel::ALL {
            if let Err(e) = validate(&k.source()) {
                panic!("{}: {e}", k.name());
            }
        }
    }
}
