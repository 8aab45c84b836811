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
// Unsafe code only where a module allows it: the BVH's SIMD kernels (`bvh::simd`).
#![deny(unsafe_code)]
#![warn(missing_docs)]

mod api;

pub use api::*;
pub use error::{Error, Result};
pub use integrators::aov::Aov;
pub use render::film::{add_exr_layers, Image};
pub use render::image_diff::DiffStats;
pub use render::progressive::Flow;
pub use render::report::RenderReport as Report;
pub use settings::{Filter, FresnelMode, Mode, RenderSettings, Sampler};
pub use warning::Warning;

// The layout is by concept (docs/architecture.md): the kinds of a closed set (BSDFs, lights,
// media, textures) each in their folder with their WGSL beside them, every importer feeding
// the one scene builder, the integrators of both backends, then the render around them.

/// Throughput and speed-against-error measurements (what `gpu-photon bench` runs).
pub mod bench;
/// The BSDFs: one union of every scattering model, the shading interface the integrators use.
#[doc(hidden)]
pub mod bsdfs;
/// The bounding volume hierarchy, its walk on both backends.
#[doc(hidden)]
pub mod bvh;
/// The pinhole and thin-lens camera and the pixel filters.
#[doc(hidden)]
pub mod camera;
/// The library's error type.
#[doc(hidden)]
pub mod error;
/// Control characters of echoed input, escaped so every message is one line of plain text.
#[doc(hidden)]
pub mod escape;
/// Scene files of every format, read into the one scene builder.
#[doc(hidden)]
pub mod importers;
/// Photon tracing, photon maps, estimates and the camera pass on the CPU and the GPU.
#[doc(hidden)]
pub mod integrators;
/// The lights: sampling, emission, the photon budget.
#[doc(hidden)]
pub mod lights;
/// Rays, intersections, random numbers and sample warps.
#[doc(hidden)]
pub mod math;
/// Participating media and their phase functions.
#[doc(hidden)]
pub mod media;
/// A render around the backends: the session, passes, budgets, images and their slices.
#[doc(hidden)]
pub mod render;
/// The backend-neutral scene and its builder.
#[doc(hidden)]
pub mod scene;
/// Render settings and their ranges.
#[doc(hidden)]
pub mod settings;
/// Textures: images, checkerboards, their lookups.
#[doc(hidden)]
pub mod textures;
/// Warnings as values.
#[doc(hidden)]
pub mod warning;
