//! Mitsuba 3's `checkerboard` texture: two colours alternating over the unit squares of
//! uv, a 2x2 pattern per unit square.

use crate::textures::sampler::UvTransform;
use glam::{Vec2, Vec3};

/// The checkerboard: at the transformed uv `p`, with `fx = p.x - floor(p.x) > 0.5` and
/// `fy` likewise, `color0` where `fx == fy` and `color1` elsewhere (Mitsuba's RGB `eval`;
/// the quarter squares holding uv's integer corners are `color0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checkerboard {
    /// The colour of the squares at uv's integer corners (Mitsuba's default 0.4).
    pub color0: Vec3,
    /// The other squares' colour (default 0.2).
    pub color1: Vec3,
    /// Applied to uv first (Mitsuba `to_uv`).
    pub to_uv: UvTransform,
}

impl Default for Checkerboard {
    fn default() -> Self {
        Checkerboard {
            color0: Vec3::splat(0.4),
            color1: Vec3::splat(0.2),
            to_uv: UvTransform::IDENTITY,
        }
    }
}

impl Checkerboard {
    /// The colour at `uv`.
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let p = self.to_uv.apply(uv);
        let fx = p.x - p.x.floor() > 0.5;
        let fy = p.y - p.y.floor() > 0.5;
        if fx == fy {
            self.color0
        } else {
            self.color1
        }
    }

    /// The average colour (each covers half of every unit square).
    pub fn mean(&self) -> Vec3 {
        (self.color0 + self.color1) * 0.5
    }
}
