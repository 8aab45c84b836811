//! The GPU backend: WGSL compute kernels through wgpu (Vulkan), from an H100 down to Mesa
//! lavapipe. Photon tracing, the hash-grid build and the gather all run on the device; the
//! image is read back once at the end.

pub mod context;
pub mod grid;
pub mod probe;
pub mod render;
pub mod shaders;
pub mod types;

pub use context::{hardware_adapter, list_adapters, GpuContext};
pub use render::render;
