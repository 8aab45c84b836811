//! gpu-photon: a photon-mapping renderer (Jensen; progressive after Knaus and Zwicker) with
//! a WGSL/wgpu GPU backend and a rayon CPU backend that is its reference.
//!
//! The whole interface is at the crate root: load a [`Scene`] (TOML, Mitsuba 3 XML, glTF),
//! adjust its [`RenderSettings`] by name ([`RenderSettings::set`], the command line's names
//! and ranges), render it ([`Scene::render`], or pass by pass with a [`Renderer`]), and save
//! the [`Image`] ([`Image::write_exr`], [`Image::write_png`]).
//!
//! ```no_run
//! # fn main() -> gpu_photon::Result<()> {
//! let scene = gpu_photon::Scene::load("scenes/cornell-box.toml")?;
//! let mut settings = scene.settings();
//! settings.set("spp", 16u32)?;
//! let (image, warnings) = scene.render(&settings, gpu_photon::Backend::Auto)?;
//! warnings.iter().for_each(|w| eprintln!("warning: {w}"));
//! image.write_exr("cornell.exr")?;
//! # Ok(())
//! # }
//! ```
//!
//! The modules below the facade are public for the tests and tools of this repository only;
//! they are hidden from the documentation and may change at any time.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod api;

pub use api::*;
pub use error::{Error, Result};
pub use film::{DiffStats, Image};
pub use progressive::Flow;
pub use report::RenderReport as Report;
pub use settings::{Filter, FresnelMode, Mode, RenderSettings, Sampler};
pub use warning::Warning;

/// Throughput and speed-against-error measurements (what `gpu-photon bench` runs).
pub mod bench;
#[doc(hidden)]
pub mod bsdf;
#[doc(hidden)]
pub mod budget;
#[doc(hidden)]
pub mod bvh;
#[doc(hidden)]
pub mod calibration;
#[doc(hidden)]
pub mod camera;
#[doc(hidden)]
pub mod choices;
#[doc(hidden)]
pub mod cpu;
#[doc(hidden)]
pub mod environment;
#[doc(hidden)]
pub mod error;
#[doc(hidden)]
pub mod estimate;
#[doc(hidden)]
pub mod film;
#[doc(hidden)]
pub mod geometry;
#[doc(hidden)]
pub mod gpu;
#[doc(hidden)]
pub mod light;
#[doc(hidden)]
pub mod material;
#[doc(hidden)]
pub mod medium;
#[doc(hidden)]
pub mod merge;
#[doc(hidden)]
pub mod phase;
#[doc(hidden)]
pub mod photon;
#[doc(hidden)]
pub mod pixel_filter;
#[doc(hidden)]
pub mod plan;
#[doc(hidden)]
pub mod progressive;
#[doc(hidden)]
pub mod read;
#[doc(hidden)]
pub mod report;
#[doc(hidden)]
pub mod rng;
#[doc(hidden)]
pub mod sampling;
#[doc(hidden)]
pub mod scene;
#[doc(hidden)]
pub mod session;
#[doc(hidden)]
pub mod settings;
#[doc(hidden)]
pub mod shading;
#[doc(hidden)]
pub mod slice;
#[doc(hidden)]
pub mod sobol;
#[doc(hidden)]
pub mod texture;
#[doc(hidden)]
pub mod warning;
