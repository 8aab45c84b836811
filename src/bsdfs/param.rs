//! A BSDF parameter that a texture may vary ([`Param`], a "texture slot"): a constant, or a
//! constant times one of the scene's textures (a bitmap, a checkerboard; later mesh
//! attributes) looked up at the hit's uv, read as a colour or one channel. Every parameter of
//! every kind that a scene format lets vary is one, evaluated by [`Param::eval`] on the CPU
//! and by `param_eval` (`param.wgsl`) on the GPU: one evaluation path each.
//!
//! On the GPU a kind's parameters are 16-byte words ([`GpuWords`]): a slot word holds the
//! value (xyz) and the texture with its channel (w), a plain word four numbers. The words of
//! textured slots are flagged in a mask, so the GPU looks up only those.

use crate::textures::{SceneTexture, NO_TEXTURE};
use glam::{Vec2, Vec3};

/// What a textured parameter reads of its texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Channel {
    /// The colour (rgb).
    #[default]
    Rgb,
    /// The red channel (all three components).
    R,
    /// The green channel.
    G,
    /// The blue channel.
    B,
    /// The alpha channel.
    A,
    /// The Rec. 709 luminance of the colour.
    Luminance,
}

impl Channel {
    /// The code the GPU's slot word carries (bits 28..31 of its texture word).
    pub const fn code(self) -> u32 {
        match self {
            Channel::Rgb => 0,
            Channel::R => 1,
            Channel::G => 2,
            Channel::B => 3,
            Channel::A => 4,
            Channel::Luminance => 5,
        }
    }
}

/// Bits of a slot word's texture field that hold the texture's index (the rest: the channel).
pub const PARAM_TEXTURE_BITS: u32 = 28;

/// A parameter: `value`, or `value` times `texture`'s [`Channel`] at the hit's uv. A float
/// parameter keeps its value in `value.x` (read with [`Param::float`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// The constant, or the factor on the texture.
    pub value: Vec3,
    /// Index into the scene's textures, or [`NO_TEXTURE`].
    pub texture: u32,
    /// What is read of the texture.
    pub channel: Channel,
}

impl Param {
    /// A constant colour.
    pub const fn rgb(value: Vec3) -> Self {
        Self {
            value,
            texture: NO_TEXTURE,
            channel: Channel::Rgb,
        }
    }

    /// A constant number.
    pub const fn constant(value: f32) -> Self {
        Self::rgb(Vec3::new(value, 0.0, 0.0))
    }

    /// A colour read from `texture` (factor one).
    pub const fn texture(texture: u32) -> Self {
        Self {
            value: Vec3::ONE,
            texture,
            channel: Channel::Rgb,
        }
    }

    /// This parameter times `channel` of `texture`.
    pub const fn times(self, texture: u32, channel: Channel) -> Self {
        Self {
            texture,
            channel,
            ..self
        }
    }

    /// The constant colour (a resolved parameter's value).
    #[inline]
    pub fn get(&self) -> Vec3 {
        self.value
    }

    /// The constant number (a resolved float parameter's value).
    #[inline]
    pub fn float(&self) -> f32 {
        self.value.x
    }

    /// Whether a texture varies it.
    #[inline]
    pub fn is_textured(&self) -> bool {
        self.texture != NO_TEXTURE
    }

    /// Its value at `uv`.
    #[inline]
    pub fn eval(&self, textures: &[SceneTexture], uv: Vec2) -> Vec3 {
        if self.texture == NO_TEXTURE {
            return self.value;
        }
        let t = &textures[self.texture as usize];
        match self.channel {
            Channel::Rgb => self.value * t.eval(uv),
            Channel::R => self.value * t.eval(uv).x,
            Channel::G => self.value * t.eval(uv).y,
            Channel::B => self.value * t.eval(uv).z,
            Channel::A => self.value * t.eval_alpha(uv),
            Channel::Luminance => self.value * crate::lights::environment::luminance(t.eval(uv)),
        }
    }

    /// The constant this parameter takes at `uv` (textures looked up).
    #[inline]
    pub fn resolved(&self, textures: &[SceneTexture], uv: Vec2) -> Self {
        Self::rgb(self.eval(textures, uv))
    }

    /// The slot word: `(value, texture | channel << 28)`, or `NO_TEXTURE` untextured.
    pub fn word(&self) -> [u32; 4] {
        let t = if self.texture == NO_TEXTURE {
            NO_TEXTURE
        } else {
            self.texture | self.channel.code() << PARAM_TEXTURE_BITS
        };
        [
            self.value.x.to_bits(),
            self.value.y.to_bits(),
            self.value.z.to_bits(),
            t,
        ]
    }
}

/// The most words a kind's parameters take on the GPU (`BSDF_WORDS` in WGSL).
pub const BSDF_WORDS: usize = 12;

/// A kind's parameters as the GPU reads them: up to [`BSDF_WORDS`] words, with the mask of
/// those that are textured slots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuWords {
    /// The words, in the kind's order.
    pub words: Vec<[u32; 4]>,
    /// Bit i: word i is a slot with a texture, to be looked up at each hit.
    pub textured: u32,
    /// Extra `f32`s the kind reads from `bsdf_tables` (a rough plastic's transmittance table),
    /// placed by the packer.
    pub table: Vec<f32>,
    /// Where the packer writes the table's offset in `bsdf_tables`: (word, component).
    pub table_at: Option<(usize, usize)>,
}

impl GpuWords {
    /// Appends a slot word.
    pub fn slot(&mut self, p: &Param) {
        if p.is_textured() {
            self.textured |= 1 << self.words.len();
        }
        self.words.push(p.word());
    }

    /// Appends a colour and a number as one plain word.
    pub fn rgb_u(&mut self, v: Vec3, w: u32) {
        self.words
            .push([v.x.to_bits(), v.y.to_bits(), v.z.to_bits(), w]);
    }

    /// Appends four raw 32-bit values as one plain word.
    pub fn raw(&mut self, w: [u32; 4]) {
        self.words.push(w);
    }

    /// Appends four numbers as one plain word.
    pub fn floats(&mut self, v: [f32; 4]) {
        self.words.push(v.map(f32::to_bits));
    }
}
