//! The CPU backend: rayon over photon paths and image rows, kiddo kd-trees for the K nearest
//! photons, hashed grids (`point_grid`) for fixed-radius estimates and the radiance cache.
//! It is the fallback and the reference the GPU backend is tested against.

pub mod cache;
pub mod density;
mod direct_light;
pub mod final_gather;
pub mod gather;
mod gather_media;
pub mod media;
pub mod photon_map;
pub mod photons;
pub mod point_grid;
pub mod renderer;
pub mod volume_map;

pub use renderer::CpuRenderer;
