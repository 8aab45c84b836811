//! gpu-photon: a photon-mapping renderer (Jensen) with a WGSL/wgpu GPU backend and a
//! rayon CPU backend that is its reference.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod camera;
pub mod choices;
pub mod error;
pub mod scene;
pub mod settings;

pub use error::{Error, Result};
pub use scene::Scene;
pub use settings::RenderSettings;
pub mod bench;
pub mod bsdf;
pub mod bvh;
pub mod calibration;
pub mod cpu;
pub mod environment;
pub mod estimate;
pub mod film;
pub mod geometry;
pub mod light;
pub mod material;
pub mod medium;
pub mod merge;
pub mod phase;
pub mod photon;
pub mod pixel_filter;
pub mod plan;
pub mod progressive;
pub mod read;
pub mod report;
pub mod rng;
pub mod sampling;
pub mod session;
pub mod shading;
pub mod slice;
pub mod sobol;
pub mod texture;

pub use film::Image;
pub use report::{Progress, RenderReport};
pub use session::{render, Backend, BackendChoice};
pub mod gpu;
