//! The stored photon, shared by both backends (twin: `Photon` in `src/integrators/gpu/types.wgsl`),
//! and the photon budget of a render.

use crate::lights::{scalar_power, split_budget};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Flag: the photon's path is L S+ D (first hit specular, stored at the first diffuse hit).
pub const FLAG_CAUSTIC: u32 = 1 << 8;
/// Mask of the number of surface interactions before this hit (0: direct light).
pub const DEPTH_MASK: u32 = 0xff;

/// Which volume photons a beam estimate takes (twin: the `BEAM_*` codes of the WGSL
/// prelude, `beam_entry` in `src/integrators/gpu/volume_estimate.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeamPhotons {
    /// Every photon (a mode without next-event estimation).
    All = 0,
    /// All but single scattering (depth 0): next-event estimation does it.
    SkipDirect = 1,
    /// Only L S+ V photons (volume caustics): the near part of a camera segment whose other
    /// light a gather ray brings (`medium::NEAR_GATHER_FRACTION`).
    Caustic = 2,
}

impl BeamPhotons {
    /// Whether photon `p` counts.
    pub fn keeps(self, p: &Photon) -> bool {
        match self {
            BeamPhotons::All => true,
            BeamPhotons::SkipDirect => p.depth() != 0,
            BeamPhotons::Caustic => p.is_caustic(),
        }
    }
}

/// A photon stored at a diffuse or glossy surface (48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Photon {
    /// Where it was stored.
    pub position: [f32; 3],
    /// Path depth (bits 0-7) and [`FLAG_CAUSTIC`].
    pub flags: u32,
    /// Power per channel (W).
    pub power: [f32; 3],
    /// Index of the path that stored it (with `flags`, a stable identity for tie-breaks).
    pub id: u32,
    /// Unit direction of travel when it arrived.
    pub dir: [f32; 3],
    /// The surface's geometric normal on the side the photon arrived from ([`pack_normal`]):
    /// an estimate takes only photons of a surface facing the same way as its own, so the
    /// other side of a wall, or a face meeting it at an edge, lends it no light. A volume
    /// photon ([`Photon::in_medium`]) has no surface: this is its medium's index.
    pub normal: u32,
}

/// Octahedral encoding of a unit vector into two 16-bit snorm values, x in the low half
/// (WGSL `pack2x16snorm`'s layout and rounding); about 1e-4 rad of error.
pub fn pack_normal(n: Vec3) -> u32 {
    let sign = |v: f32| if v >= 0.0 { 1.0 } else { -1.0 };
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if l1 == 0.0 {
        return 0;
    }
    let (mut x, mut y) = (n.x / l1, n.y / l1);
    if n.z < 0.0 {
        (x, y) = ((1.0 - y.abs()) * sign(x), (1.0 - x.abs()) * sign(y));
    }
    let snorm = |v: f32| ((0.5 + 32767.0 * v.clamp(-1.0, 1.0)).floor() as i16 as u16) as u32;
    snorm(x) | snorm(y) << 16
}

/// Inverse of [`pack_normal`] (WGSL `unpack2x16snorm`, then the octahedral unfolding).
pub fn unpack_normal(bits: u32) -> Vec3 {
    let sign = |v: f32| if v >= 0.0 { 1.0 } else { -1.0 };
    let snorm = |h: u32| (h as u16 as i16 as f32 / 32767.0).max(-1.0);
    let (x, y) = (snorm(bits & 0xffff), snorm(bits >> 16));
    let z = 1.0 - x.abs() - y.abs();
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * sign(x), (1.0 - x.abs()) * sign(y))
    } else {
        (x, y)
    };
    // Never zero: |x| + |y| + |z| = 1 before the fold and after it.
    Vec3::new(x, y, z).normalize()
}

/// Whether a photon path's `power` is spent: no longer positive in any channel, or not
/// finite (NaN or infinite in any channel). The path ends there on both backends (twin:
/// `power_ends` in src/integrators/gpu/photon.wgsl).
pub fn power_ends(power: Vec3) -> bool {
    // A finite power has no NaN, so its largest channel then compares.
    !power.is_finite() || power.max_element() <= 0.0
}

impl Photon {
    /// A photon travelling along `dir` that hit a surface with geometric normal `n` (either
    /// orientation: the stored normal faces where the photon came from).
    pub fn new(
        position: Vec3,
        power: Vec3,
        dir: Vec3,
        n: Vec3,
        id: u32,
        depth: u32,
        caustic: bool,
    ) -> Self {
        let normal = pack_normal(if dir.dot(n) < 0.0 { n } else { -n });
        Photon {
            normal,
            ..Self::in_medium(position, power, dir, 0, id, depth, caustic)
        }
    }
    /// A photon that scattered in medium `medium` at `position` while travelling along `dir`
    /// (a volume photon: `power` is what it scatters, `sigma_s` already in it).
    pub fn in_medium(
        position: Vec3,
        power: Vec3,
        dir: Vec3,
        medium: u32,
        id: u32,
        depth: u32,
        caustic: bool,
    ) -> Self {
        Photon {
            position: position.to_array(),
            flags: depth.min(DEPTH_MASK) | if caustic { FLAG_CAUSTIC } else { 0 },
            power: power.to_array(),
            id,
            dir: dir.to_array(),
            normal: medium,
        }
    }
    /// Scattering events (at surfaces or in media) before this one (0: direct light).
    pub fn depth(&self) -> u32 {
        self.flags & DEPTH_MASK
    }
    /// Whether its path was L S+ D (stored after specular bounces only).
    pub fn is_caustic(&self) -> bool {
        self.flags & FLAG_CAUSTIC != 0
    }
    /// [`Photon::position`] as a vector.
    pub fn pos(&self) -> Vec3 {
        Vec3::from(self.position)
    }
    /// The unit normal of the side of the surface the photon arrived on.
    pub fn normal(&self) -> Vec3 {
        unpack_normal(self.normal)
    }
}

/// How many paths each light emits in one pass, and the power each path starts with.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Paths per light; light `l` owns path indices `offsets[l] .. offsets[l] + counts[l]`.
    pub counts: Vec<u32>,
    /// The first path index of each light (the running sum of `counts`).
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

    /// Paths of all lights together.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed normal comes back within 1e-4 rad (as the sine of the angle), over the whole sphere (both halves of
    /// the octahedron, the axes and the fold at z = 0).
    #[test]
    fn packed_normals_round_trip() {
        let mut worst = 0.0f32;
        let mut dirs: Vec<Vec3> = vec![
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::new(1.0, 1.0, 0.0).normalize(),
            Vec3::new(-1.0, 1.0, -1e-7).normalize(),
        ];
        for i in 0..2000 {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            dirs.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        for n in dirs {
            let back = unpack_normal(pack_normal(n));
            worst = worst.max(back.cross(n).length()); // sin of the angle
        }
        assert!(worst < 1e-4, "worst angle {worst}");
    }

    /// The stored normal faces the side the photon came from, whichever way the surface's
    /// normal points.
    #[test]
    fn stored_normal_faces_the_incoming_photon() {
        for n in [Vec3::Y, Vec3::NEG_Y] {
            let p = Photon::new(Vec3::ZERO, Vec3::ONE, Vec3::NEG_Y, n, 0, 0, false);
            assert!(p.normal().dot(Vec3::Y) > 0.9999, "{n}: {}", p.normal());
        }
    }
}
