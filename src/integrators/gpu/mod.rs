//! The GPU backend: WGSL compute kernels through wgpu (Vulkan), from an H100 down to Mesa
//! lavapipe. Photon tracing, the hash-grid build and the gather all run on the device; the
//! image is read back once per pass. `GpuRenderer` is the backend's `report::PassRenderer`.
//!
//! Layers, each module importing only those above it in this list:
//! `bvh_layout` (the BVH as the traversal reads it), `codes` (shared constants, the WGSL
//! prelude),
//! `textures` (the scene's textures packed into words, the texture library's constants),
//! `types` (Gpu* twins of WGSL structs, the materials with their BSDFs),
//! `shaders` (composition), `bindings` (named binding tables, layouts), `faults` (the device's
//! failures described, their injection for tests, the watchdog), `shape` (the kernel shape
//! chosen per adapter: widths and the loop guard as override constants), `context`,
//! `buffers`, `branches` (the camera paths' deferred glass branches), `texture_buffers` (the packed textures on the device), `grid`, `host` (plan and settings to kernel parameters), `pipelines`,
//! `scene_buffers`, `maps`, `volume` (the volume photon map's buffers and grid), `run` (what a render sets up once), `photon_maps`,
//! `radiance_cache` (final gathering's cache), `pass`,
//! then `renderer`. The oracle probes that compare kernels with their Rust twins are test
//! code (`tests/probes/`), composed over the same libraries (`shaders::probe_source`).

pub mod bindings;
pub mod branches;
pub mod buffers;
pub mod codes;
pub mod context;
pub mod faults;
pub mod grid;
pub mod host;
pub mod maps;
pub mod pass;
pub mod photon_maps;
pub mod pipeline_cache;
pub mod pipelines;
pub mod radiance_cache;
pub mod recorder;
pub mod renderer;
pub mod run;
pub mod scene_buffers;
pub mod shaders;
pub mod shape;
pub mod specialise;
pub mod texture_buffers;
pub mod textures;
pub mod types;
pub mod volume;

pub use context::{list_adapters, preferred_adapter, quiet_headless_vulkan, GpuContext};
pub use renderer::GpuRenderer;
