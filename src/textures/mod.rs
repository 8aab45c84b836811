//! Textures: images (PNG, JPEG, BMP through `image`; OpenEXR through `exr`; Radiance HDR)
//! and Mitsuba's procedural checkerboard, looked up at a uv the way Mitsuba 3's `bitmap`
//! plugin and glTF 2.0 do. `src/textures/texture.wgsl` is the GPU twin of [`SceneTexture::eval`];
//! `crate::integrators::gpu::textures` packs textures for it.
//!
//! Conventions (checked against Mitsuba 3.9.1 by `tests/texture_mitsuba.rs`):
//! - uv (0, 0) is the top-left corner of the image (the first row of the file) and v grows
//!   downwards, as in glTF: no flip. Texel (i, j) covers `[i, i+1] / width` by
//!   `[j, j+1] / height`; its centre is at `((i + 0.5) / width, (j + 0.5) / height)`.
//! - Nearest reads texel `floor(u * width)`; bilinear interpolates between the texel centres
//!   around `u * width - 0.5`, each of the four texels wrapped on its own (so a repeated
//!   image blends its last and first texels across the border, a clamped one holds its edge).
//! - 8-bit colour channels are decoded per texel, before interpolation, through a 256-entry
//!   table: sRGB to linear for colour textures, x / 255 for raw (data) textures. Alpha is
//!   always x / 255. 16-bit images are converted to float at load (sRGB decoded there).
//! - Float images (EXR, HDR) are linear and never decoded.
//!
//! Unlike Mitsuba, an image narrower or shorter than 2 texels is not padded to 2x2.

pub mod checker;
pub mod decode;
pub mod sampler;
pub mod uv;

pub use checker::Checkerboard;
pub use sampler::{Filter, Sampler, UvTransform, Wrap};

use crate::error::{Error, Result};
use glam::{Vec2, Vec3, Vec4};
use std::sync::OnceLock;

/// Largest width or height of an image texture.
pub const MAX_SIDE: u32 = 16384;
/// Marks a parameter (or light) that no texture varies: the index of no texture.
pub const NO_TEXTURE: u32 = u32::MAX;
/// Most texels of one image texture (2^28).
pub const MAX_TEXELS: u64 = 1 << 28;
/// Pixel coordinates are clamped to +-2^24 before they are rounded to integers (beyond, f32
/// has no fraction left): uv far outside the image stays defined.
pub const COORD_LIMIT: f32 = 16_777_216.0;

/// How the colour channels of an 8-bit image are decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// sRGB-encoded colour (base colour, emission): decoded to linear.
    Srgb,
    /// Linear data (Mitsuba `raw`; roughness, normal and opacity maps): x / 255.
    Raw,
}

/// sRGB's decoding curve (IEC 61966-2-1), in f64.
pub fn srgb_to_linear(x: f64) -> f64 {
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

impl Encoding {
    /// The table that decodes an 8-bit channel (entry x: sRGB-decoded x / 255, or x / 255),
    /// each entry the f32 nearest to the exact value.
    pub fn lut(self) -> &'static [f32; 256] {
        static SRGB: OnceLock<[f32; 256]> = OnceLock::new();
        static RAW: OnceLock<[f32; 256]> = OnceLock::new();
        match self {
            Encoding::Srgb => SRGB
                .get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f64 / 255.0) as f32)),
            Encoding::Raw => RAW.get_or_init(|| std::array::from_fn(|i| (i as f64 / 255.0) as f32)),
        }
    }
}

/// A texture's texels, row after row from the top of the image.
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// 8 bits per channel packed into one word: red in the low byte, alpha in the high one.
    Rgba8 {
        /// One word per texel.
        texels: Vec<u32>,
        /// How the colour channels decode.
        encoding: Encoding,
    },
    /// Linear f32 channels.
    Float {
        /// `channels` values per texel.
        data: Vec<f32>,
        /// 3 (RGB, alpha 1) or 4 (RGBA).
        channels: u32,
    },
}

/// An image texture with its sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Where it came from (its file), for messages.
    pub name: String,
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// The texels.
    pub texels: Texels,
    /// How it is looked up.
    pub sampler: Sampler,
}

/// Packs four 8-bit channels into a texel word (red in the low byte).
pub fn pack_rgba8(c: [u8; 4]) -> u32 {
    u32::from_le_bytes(c)
}

/// Fails unless a `width` x `height` image is within [`MAX_SIDE`] and [`MAX_TEXELS`].
pub fn check_size(name: &str, width: u32, height: u32) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(image_error(
            name,
            format!("empty image ({width} x {height})"),
        ));
    }
    if width > MAX_SIDE || height > MAX_SIDE || width as u64 * height as u64 > MAX_TEXELS {
        return Err(image_error(
            name,
            format!("{width} x {height} is too large for a texture (at most {MAX_SIDE} per side and 2^28 texels)"),
        ));
    }
    Ok(())
}

/// An [`Error::Image`] about the texture `name`.
pub fn image_error(name: &str, message: String) -> Error {
    Error::Image {
        path: name.into(),
        message,
    }
}

impl Texture {
    /// An 8-bit texture from packed texels (see [`pack_rgba8`]), with the default sampler.
    pub fn from_rgba8(
        name: &str,
        width: u32,
        height: u32,
        texels: Vec<u32>,
        encoding: Encoding,
    ) -> Result<Self> {
        check_size(name, width, height)?;
        if texels.len() as u64 != width as u64 * height as u64 {
            return Err(image_error(
                name,
                format!("{} texels for {width} x {height}", texels.len()),
            ));
        }
        Ok(Texture {
            name: name.into(),
            width,
            height,
            texels: Texels::Rgba8 { texels, encoding },
            sampler: Sampler::default(),
        })
    }

    /// A float texture with `channels` (3 or 4) values per texel, with the default sampler.
    pub fn from_float(
        name: &str,
        width: u32,
        height: u32,
        data: Vec<f32>,
        channels: u32,
    ) -> Result<Self> {
        check_size(name, width, height)?;
        if !(channels == 3 || channels == 4)
            || data.len() as u64 != width as u64 * height as u64 * channels as u64
        {
            return Err(image_error(
                name,
                format!(
                    "{} values for {width} x {height} x {channels} channels",
                    data.len()
                ),
            ));
        }
        Ok(Texture {
            name: name.into(),
            width,
            height,
            texels: Texels::Float { data, channels },
            sampler: Sampler::default(),
        })
    }

    /// Loads an image file (see [`decode::load`]).
    pub fn load(path: &std::path::Path, encoding: Encoding) -> Result<Self> {
        decode::load(path, encoding)
    }

    /// The same texture looked up with `sampler`.
    pub fn with_sampler(mut self, sampler: Sampler) -> Self {
        self.sampler = sampler;
        self
    }

    /// Texel `(x, y)` (in range), decoded: linear RGB and alpha.
    pub fn texel(&self, x: u32, y: u32) -> Vec4 {
        let i = y as usize * self.width as usize + x as usize;
        match &self.texels {
            Texels::Rgba8 { texels, encoding } => {
                let (w, lut) = (texels[i], encoding.lut());
                let raw = Encoding::Raw.lut();
                Vec4::new(
                    lut[(w & 255) as usize],
                    lut[(w >> 8 & 255) as usize],
                    lut[(w >> 16 & 255) as usize],
                    raw[(w >> 24) as usize],
                )
            }
            Texels::Float { data, channels } => {
                let k = i * *channels as usize;
                let a = if *channels == 4 { data[k + 3] } else { 1.0 };
                Vec4::new(data[k], data[k + 1], data[k + 2], a)
            }
        }
    }

    /// Linear RGB and alpha at `uv` (before the sampler's uv transform).
    pub fn eval_rgba(&self, uv: Vec2) -> Vec4 {
        let uv = self.sampler.to_uv.apply(uv);
        let s = &self.sampler;
        match s.filter {
            Filter::Nearest => {
                let (w, h) = (self.width as i32, self.height as i32);
                let px = pixel_coord(uv.x * self.width as f32).floor() as i32;
                let py = pixel_coord(uv.y * self.height as f32).floor() as i32;
                self.texel(s.wrap_u.index(px, w) as u32, s.wrap_v.index(py, h) as u32)
            }
            Filter::Bilinear => {
                let ([c00, c10, c01, c11], Vec2 { x: tx, y: ty }) = self.quad(uv);
                let row0 = c00 * (1.0 - tx) + c10 * tx;
                let row1 = c01 * (1.0 - tx) + c11 * tx;
                row0 * (1.0 - ty) + row1 * ty
            }
        }
    }

    /// The four texels a bilinear lookup at transformed `uv` blends (`(x0, y0)`, `(x0 + 1,
    /// y0)`, `(x0, y0 + 1)`, `(x0 + 1, y0 + 1)`, each wrapped) and the weights of the second
    /// column and row.
    fn quad(&self, uv: Vec2) -> ([Vec4; 4], Vec2) {
        let (w, h) = (self.width as i32, self.height as i32);
        let s = &self.sampler;
        let fetch =
            |x: i32, y: i32| self.texel(s.wrap_u.index(x, w) as u32, s.wrap_v.index(y, h) as u32);
        let px = pixel_coord(uv.x * self.width as f32 - 0.5);
        let py = pixel_coord(uv.y * self.height as f32 - 0.5);
        let (fx, fy) = (px.floor(), py.floor());
        let (x0, y0) = (fx as i32, fy as i32);
        let c = [
            fetch(x0, y0),
            fetch(x0 + 1, y0),
            fetch(x0, y0 + 1),
            fetch(x0 + 1, y0 + 1),
        ];
        (c, Vec2::new(px - fx, py - fy))
    }

    /// The gradient of the luminance at `uv` with respect to u and v: Mitsuba 3.9.1's
    /// `bitmap` `eval_1_grad`, which its `bumpmap` reads. The bilinear interpolant's partials
    /// in texels, carried through the transpose of the uv transform's linear part, then
    /// multiplied by the resolution per axis (Mitsuba's order); zero for a nearest lookup.
    /// Twin: `texture_grad` in `src/textures/texture.wgsl`.
    pub fn eval_grad(&self, uv: Vec2) -> Vec2 {
        if self.sampler.filter == Filter::Nearest {
            return Vec2::ZERO;
        }
        let ([c00, c10, c01, c11], t) = self.quad(self.sampler.to_uv.apply(uv));
        let [f00, f10, f01, f11] = [c00, c10, c01, c11].map(|c| luminance(c.truncate()));
        let dx = (1.0 - t.y) * (f10 - f00) + t.y * (f11 - f01);
        let dy = (1.0 - t.x) * (f01 - f00) + t.x * (f11 - f10);
        let [r0, r1] = self.sampler.to_uv.rows;
        let du = r0[0] * dx + r1[0] * dy;
        let dv = r0[1] * dx + r1[1] * dy;
        Vec2::new(self.width as f32 * du, self.height as f32 * dv)
    }

    /// Linear RGB at `uv`.
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        self.eval_rgba(uv).truncate()
    }

    /// Alpha at `uv` (1 for images without alpha), filtered like the colour.
    pub fn eval_alpha(&self, uv: Vec2) -> f32 {
        self.eval_rgba(uv).w
    }

    /// The average linear RGB of the texels (for power and albedo estimates).
    pub fn mean(&self) -> Vec3 {
        let mut sum = [0.0f64; 3];
        for y in 0..self.height {
            for x in 0..self.width {
                let t = self.texel(x, y);
                for (c, s) in sum.iter_mut().enumerate() {
                    *s += t[c] as f64;
                }
            }
        }
        let n = self.width as f64 * self.height as f64;
        Vec3::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        )
    }

    /// Whether any texel has alpha below 1.
    pub fn has_alpha(&self) -> bool {
        match &self.texels {
            Texels::Rgba8 { texels, .. } => texels.iter().any(|t| t >> 24 != 255),
            Texels::Float { data, channels } => {
                *channels == 4 && data.chunks_exact(4).any(|t| t[3] < 1.0)
            }
        }
    }
}

/// Rec. 709 luminance of linear RGB, as Mitsuba's `luminance()`.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.212_671, 0.715_160, 0.072_169))
}

/// A pixel coordinate within [`COORD_LIMIT`] (NaN becomes 0).
fn pixel_coord(p: f32) -> f32 {
    if p.is_nan() {
        0.0
    } else {
        p.clamp(-COORD_LIMIT, COORD_LIMIT)
    }
}

/// Any texture a material may reference: what `texture_eval(id, uv)` in WGSL evaluates.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneTexture {
    /// An image.
    Bitmap(Texture),
    /// Mitsuba's checkerboard.
    Checkerboard(Checkerboard),
}

impl SceneTexture {
    /// The bytes its texels take (none for a procedural texture).
    pub fn bytes(&self) -> u64 {
        match self {
            SceneTexture::Bitmap(t) => match &t.texels {
                Texels::Rgba8 { texels, .. } => 4 * texels.len() as u64,
                Texels::Float { data, .. } => 4 * data.len() as u64,
            },
            SceneTexture::Checkerboard(_) => 0,
        }
    }
    /// Linear RGB at `uv`.
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        match self {
            SceneTexture::Bitmap(t) => t.eval(uv),
            SceneTexture::Checkerboard(c) => c.eval(uv),
        }
    }

    /// The gradient of the luminance at `uv` ([`Texture::eval_grad`]); zero for a
    /// checkerboard (Mitsuba's has none: importers refuse it where a gradient is read).
    pub fn eval_grad(&self, uv: Vec2) -> Vec2 {
        match self {
            SceneTexture::Bitmap(t) => t.eval_grad(uv),
            SceneTexture::Checkerboard(_) => Vec2::ZERO,
        }
    }

    /// Alpha at `uv` (1 for a checkerboard).
    pub fn eval_alpha(&self, uv: Vec2) -> f32 {
        match self {
            SceneTexture::Bitmap(t) => t.eval_alpha(uv),
            SceneTexture::Checkerboard(_) => 1.0,
        }
    }

    /// Whether some texel has alpha below 1 (never for a checkerboard).
    pub fn has_alpha(&self) -> bool {
        match self {
            SceneTexture::Bitmap(t) => t.has_alpha(),
            SceneTexture::Checkerboard(_) => false,
        }
    }

    /// The average linear RGB.
    pub fn mean(&self) -> Vec3 {
        match self {
            SceneTexture::Bitmap(t) => t.mean(),
            SceneTexture::Checkerboard(c) => c.mean(),
        }
    }
}

#[cfg(test)]
mod tests;
