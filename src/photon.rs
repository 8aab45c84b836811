//! The stored photon, shared by both backends (twin: `Photon` in `shaders/common/types.wgsl`),
//! and the photon budget of a render.

use crate::light::{scalar_power, split_budget};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Flag: the photon's path is L S+ D (first hit specular, stored at the first diffuse hit).
pub const FLAG_CAUSTIC: u32 = 1 << 8;
/// Mask of the number of surface interactions before this hit (0: direct light).
pub const DEPTH_MASK: u32 = 0xff;

/// A photon stored at a diffuse or glossy surface (48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Photon {
    pub position: [f32; 3],
    /// Path depth (bits 0-7) and [`FLAG_CAUSTIC`].
    pub flags: u32,
    /// Power per channel (W).
    pub power: [f32; 3],
    /// Index of the path that stored it (with `flags`, a stable identity for tie-breaks).
    pub id: u32,
    /// Unit direction of travel when it arrived.
    pub dir: [f32; 3],
    pub _pad1: u32,
}

impl Photon {
    pub fn new(position: Vec3, power: Vec3, dir: Vec3, id: u32, depth: u32, caustic: bool) -> Self {
        Photon {
            position: position.to_array(),
            flags: depth.min(DEPTH_MASK) | if caustic { FLAG_CAUSTIC } else { 0 },
            power: power.to_array(),
            id,
            dir: dir.to_array(),
            _pad1: 0,
        }
    }
    pub fn depth(&self) -> u32 {
        self.flags & DEPTH_MASK
    }
    pub fn is_caustic(&self) -> bool {
        self.flags & FLAG_CAUSTIC != 0
    }
    pub fn pos(&self) -> Vec3 {
        Vec3::from(self.position)
    }
}

/// How many paths each light emits in one pass, and the power each path starts with.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Paths per light; light `l` owns path indices `offsets[l] .. offsets[l] + counts[l]`.
    pub counts: Vec<u32>,
    pub offsets: Vec<u32>,
    /// Starting power per path of each light: `power / count` (or `/ attempts`).
    pub path_power: Vec<Vec3>,
}

impl Budget {
    /// Splits `total` paths between the scene's lights in proportion to their power.
    pub fn split(scene: &Scene, total: u32) -> Self {
        let powers: Vec<f64> = scene.lights.iter().map(|l| scalar_power(l.power)).collect();
        Self::from_counts(scene, split_budget(&powers, total))
    }

    /// A budget with the given per-light path counts.
    pub fn from_counts(scene: &Scene, counts: Vec<u32>) -> Self {
        let mut offsets = Vec::with_capacity(counts.len());
        let mut acc = 0u32;
        for &c in &counts {
            offsets.push(acc);
            acc += c;
        }
        let path_power = scene
            .lights
            .iter()
            .zip(&counts)
            .map(|(l, &c)| {
                if c > 0 {
                    l.power / c as f32
                } else {
                    Vec3::ZERO
                }
            })
            .collect();
        Budget {
            counts,
            offsets,
            path_power,
        }
    }

    pub fn total(&self) -> u32 {
        self.counts.iter().sum()
    }

    /// The light that owns path `index`.
    pub fn light_of(&self, index: u32) -> usize {
        self.offsets
            .partition_point(|&o| o <= index)
            .saturating_sub(1)
            .min(self.counts.len().saturating_sub(1))
    }
}
