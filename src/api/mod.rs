//! The facade: the few types a program needs to load a scene, set render settings, render
//! and save images. `lib.rs` re-exports all of it at the crate root.

mod build;
mod build_material;
mod files;
mod image;
mod renderer;
mod scene;
mod settings;

pub use crate::textures::Wrap as TextureWrap;
pub use build::{
    AlphaSpec, CameraSpec, MaterialSpec, MeshSpec, Scattering, SceneBuild, TextureSpec,
};
pub use files::{
    adapters, check_output_path, merge, parse_pass_range, parse_slice, progressive_summary,
    quiet_headless_vulkan, slice_pass_range, Adapter, MergeSummary, SliceFile, SliceSpec,
    MAX_PASSES,
};
pub use renderer::{PassInfo, Renderer, Stop};
pub use scene::{LoadOptions, Scene};
pub use settings::SettingValue;

/// Which backend renders: `Auto` takes the GPU when this machine's measured rule says it is
/// faster (else the CPU, with a [`crate::Warning`]); `Cpu` the rayon reference; `Gpu` the
/// wgpu compute kernels (its failures are errors).
pub use crate::render::session::BackendChoice as Backend;
