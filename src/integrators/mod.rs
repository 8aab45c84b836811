//! The integrators: the backend-neutral plan of a render (which photon maps, which terms),
//! the photon record and the radiance estimate, the first-hit feature images (AOVs) for
//! denoisers, and the two backends that trace photons, build their maps and run the camera
//! pass (`cpu/`, `gpu/` with its kernels beside it).

pub mod aov;
pub mod cpu;
pub mod estimate;
pub mod gpu;
pub mod photon;
pub mod plan;
