//! The render's memory, estimated from the scene and settings before anything of the render
//! is allocated, against what this machine has available: an impossible render fails at once,
//! naming what is too big and by how much, instead of being killed by the kernel later.
//!
//! The estimate counts what grows with the settings and the scene: the photon maps of one
//! pass (CPU backend; the GPU's are device memory, batched to one binding), the volume photons
//! where the scene has media, the image and its
//! running mean, the BVH. Its rates were measured on the CPU backend (peak resident memory of
//! `render scenes/cornell-box.toml` at two photon counts and two sizes, docs/guide.md).

use crate::error::{Error, Result};
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// Bytes per stored photon on the CPU backend (the record, its kd-tree and the tracers'
/// buffers): measured 189 bytes per global path, about 3 stored photons each.
pub const BYTES_PER_PHOTON: u64 = 64;
/// Photons a global path stores on average (one per diffuse bounce).
pub const STORES_PER_PATH: u64 = 3;
/// Bytes per pixel: the pass image, the running sums and the image written (measured 48).
pub const BYTES_PER_PIXEL: u64 = 48;
/// Bytes per triangle of the BVH built for the render (nodes, references, the GPU's copy).
pub const BYTES_PER_TRIANGLE: u64 = 128;

/// One part of the estimate: what it is, its size in bytes, and the setting that sizes it.
#[derive(Clone, Debug)]
pub struct Part {
    /// What it is, with its count (`photon maps for 1000000 global paths`).
    pub what: String,
    /// Bytes.
    pub bytes: u64,
    /// How to make it smaller.
    pub remedy: &'static str,
}

/// The parts of the render's memory that grow with the scene and settings; `host_maps`:
/// the photon maps are in this process's memory (the CPU backend).
pub fn estimate(scene: &Scene, s: &RenderSettings, host_maps: bool) -> Vec<Part> {
    let mut parts = Vec::new();
    if host_maps {
        let global = s.photons as u64 * STORES_PER_PATH;
        parts.push(Part {
            what: format!("photon maps for {} global paths", s.photons),
            bytes: global * BYTES_PER_PHOTON,
            remedy: "lower --photons (more passes of fewer photons converge alike)",
        });
        parts.push(Part {
            what: format!("{} caustic photons", s.caustic_photons),
            bytes: s.caustic_photons as u64 * BYTES_PER_PHOTON,
            remedy: "lower --caustic-photons",
        });
        if !scene.media.is_empty() {
            // A path scatters in a medium about as often as it bounces off surfaces (both
            // end by the same Russian roulette), and a caustic path stores at most one.
            let volume = global + s.caustic_photons as u64;
            parts.push(Part {
                what: format!("{volume} volume photons"),
                bytes: volume * BYTES_PER_PHOTON,
                remedy: "lower --photons and --caustic-photons",
            });
        }
    }
    parts.push(Part {
        what: format!("a {}x{} image", s.width, s.height),
        bytes: s.width as u64 * s.height as u64 * BYTES_PER_PIXEL,
        remedy: "lower --width and --height",
    });
    parts.push(Part {
        what: format!("a BVH of {} triangles", scene.triangles.len()),
        bytes: scene.triangles.len() as u64 * BYTES_PER_TRIANGLE,
        remedy: "simplify the scene",
    });
    if !scene.instancing.is_empty() {
        // Each mesh's hierarchy once, and the top level's node and id per instance.
        let inst = &scene.instancing;
        let tris: u64 = inst.meshes.iter().map(|m| m.triangles.len() as u64).sum();
        let n = inst.instances.len() as u64;
        parts.push(Part {
            what: format!(
                "{n} instances of {} meshes of {tris} triangles",
                inst.meshes.len()
            ),
            bytes: tris * BYTES_PER_TRIANGLE + n * (2 * 32 + 4),
            remedy: "simplify the scene",
        });
    }
    parts
}

pub use crate::render::memory::{available, parse_bytes, size};

/// Fails when the render of `scene` with `s` (`host_maps`: see [`estimate`]) would need more
/// memory than is available, naming the parts, the shortfall and how to shrink the largest.
pub fn check(scene: &Scene, s: &RenderSettings, host_maps: bool) -> Result<()> {
    let Some((room, source)) = available() else {
        return Ok(());
    };
    let parts = estimate(scene, s, host_maps);
    let need: u64 = parts.iter().map(|p| p.bytes).sum();
    if need <= room {
        return Ok(());
    }
    let largest = parts.iter().max_by_key(|p| p.bytes).expect("parts");
    let listed: Vec<String> = parts
        .iter()
        .filter(|p| p.bytes > 0)
        .map(|p| format!("{} for {}", size(p.bytes), p.what))
        .collect();
    Err(Error::Memory(format!(
        "the render needs about {} of memory ({}), {} more than the {} available ({source}); {}",
        size(need),
        listed.join(", "),
        size(need - room),
        size(room),
        largest.remedy
    )))
}
