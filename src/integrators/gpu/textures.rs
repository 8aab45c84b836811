//! A scene's textures for the device: every texture packed into ONE read-only storage
//! buffer of `u32` words (`tex_words`) and a table of [`GpuTexture`] records (`tex_table`),
//! read by `src/textures/texture.wgsl` (the twin of `texture::SceneTexture::eval`).
//!
//! `tex_words` layout: words `0..256` the sRGB-to-linear table and `256..512` the x / 255
//! table (f32 bits, `texture::Encoding::lut`), then each image's texels at its record's
//! `offset`, row after row from the top: one packed RGBA8 word per 8-bit texel, 3 or 4 f32
//! bit patterns per float texel. No uniforms, no sampled textures, no optional features.

use crate::error::{Error, Result};
use crate::textures::{Checkerboard, Encoding, SceneTexture, Texels, Texture, COORD_LIMIT};

/// The name the WGSL library expects for the record table binding:
/// `var<storage, read> tex_table: array<TextureRecord>`.
pub const TABLE_BINDING_NAME: &str = "tex_table";
/// The name the WGSL library expects for the word binding:
/// `var<storage, read> tex_words: array<u32>`.
pub const WORDS_BINDING_NAME: &str = "tex_words";

/// Record format: 8-bit RGBA, colour decoded through the sRGB table.
pub const FORMAT_RGBA8_SRGB: u32 = 0;
/// Record format: 8-bit RGBA, colour decoded as x / 255.
pub const FORMAT_RGBA8_RAW: u32 = 1;
/// Record format: float RGB (3 words per texel).
pub const FORMAT_RGB32F: u32 = 2;
/// Record format: float RGBA (4 words per texel).
pub const FORMAT_RGBA32F: u32 = 3;
/// Record format: Mitsuba's checkerboard (no texels; `color0`, `color1`).
pub const FORMAT_CHECKERBOARD: u32 = 4;
/// First word of the sRGB-to-linear table in `tex_words`.
pub const LUT_SRGB: u32 = 0;
/// First word of the x / 255 table in `tex_words`.
pub const LUT_RAW: u32 = 256;
/// Words before the first texel.
pub const LUT_WORDS: u32 = 512;

/// One texture as the WGSL `TextureRecord` reads it (96 bytes, 16-byte aligned).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuTexture {
    /// First word of the texels in `tex_words` (0 for a checkerboard).
    pub offset: u32,
    /// Texels per row (0 for a checkerboard).
    pub width: u32,
    /// Rows (0 for a checkerboard).
    pub height: u32,
    /// One of the `FORMAT_*` codes.
    pub format: u32,
    /// `texture::Filter::code`.
    pub filter_mode: u32,
    /// `texture::Wrap::code` of u.
    pub wrap_u: u32,
    /// `texture::Wrap::code` of v.
    pub wrap_v: u32,
    /// Padding (0).
    pub pad: u32,
    /// The uv transform's first row `[a, b, c]` and a 0: `u' = (a u + c) + b v`.
    pub uv_u: [f32; 4],
    /// Its second row `[d, e, f]` and a 0.
    pub uv_v: [f32; 4],
    /// A checkerboard's `color0` (RGB, 1); zero for images.
    pub color0: [f32; 4],
    /// A checkerboard's `color1`.
    pub color1: [f32; 4],
}

/// The packed textures of a scene, on the host.
#[derive(Clone, Debug, PartialEq)]
pub struct PackedTextures {
    /// One record per texture, in the order given (a texture's index is its WGSL `id`).
    pub table: Vec<GpuTexture>,
    /// The tables and the texels.
    pub words: Vec<u32>,
}

fn record(t: &Texture, offset: u32) -> GpuTexture {
    let format = match &t.texels {
        Texels::Rgba8 {
            encoding: Encoding::Srgb,
            ..
        } => FORMAT_RGBA8_SRGB,
        Texels::Rgba8 {
            encoding: Encoding::Raw,
            ..
        } => FORMAT_RGBA8_RAW,
        Texels::Float { channels: 3, .. } => FORMAT_RGB32F,
        Texels::Float { .. } => FORMAT_RGBA32F,
    };
    let s = &t.sampler;
    let [r0, r1] = s.to_uv.rows;
    GpuTexture {
        offset,
        width: t.width,
        height: t.height,
        format,
        filter_mode: s.filter.code(),
        wrap_u: s.wrap_u.code(),
        wrap_v: s.wrap_v.code(),
        pad: 0,
        uv_u: [r0[0], r0[1], r0[2], 0.0],
        uv_v: [r1[0], r1[1], r1[2], 0.0],
        color0: [0.0; 4],
        color1: [0.0; 4],
    }
}

fn checker_record(c: &Checkerboard) -> GpuTexture {
    let [r0, r1] = c.to_uv.rows;
    GpuTexture {
        offset: 0,
        width: 0,
        height: 0,
        format: FORMAT_CHECKERBOARD,
        filter_mode: 0,
        wrap_u: 0,
        wrap_v: 0,
        pad: 0,
        uv_u: [r0[0], r0[1], r0[2], 0.0],
        uv_v: [r1[0], r1[1], r1[2], 0.0],
        color0: c.color0.extend(1.0).to_array(),
        color1: c.color1.extend(1.0).to_array(),
    }
}

impl PackedTextures {
    /// Packs `textures` (record `i` is `textures[i]`). Fails when the words would pass
    /// `max_binding` bytes (the device's largest storage binding, `GpuContext::max_binding`).
    pub fn pack(textures: &[SceneTexture], max_binding: u64) -> Result<Self> {
        let mut bytes = 4 * LUT_WORDS as u64;
        for t in textures {
            if let SceneTexture::Bitmap(t) = t {
                bytes += 4 * texel_words(t) as u64;
            }
        }
        let table_bytes = (textures.len() * std::mem::size_of::<GpuTexture>()) as u64;
        if bytes > max_binding.min(1 << 34) || table_bytes > max_binding {
            return Err(Error::Gpu(format!(
                "the scene's textures need {} MiB in one storage buffer; this device binds at most {} MiB",
                bytes.max(table_bytes).div_ceil(1 << 20),
                max_binding >> 20
            )));
        }
        let mut words = Vec::with_capacity((bytes / 4) as usize);
        words.extend(Encoding::Srgb.lut().iter().map(|v| v.to_bits()));
        words.extend(Encoding::Raw.lut().iter().map(|v| v.to_bits()));
        let mut table = Vec::with_capacity(textures.len());
        for t in textures {
            match t {
                SceneTexture::Bitmap(t) => {
                    table.push(record(t, words.len() as u32));
                    match &t.texels {
                        Texels::Rgba8 { texels, .. } => words.extend_from_slice(texels),
                        Texels::Float { data, .. } => {
                            words.extend(data.iter().map(|v| v.to_bits()))
                        }
                    }
                }
                SceneTexture::Checkerboard(c) => table.push(checker_record(c)),
            }
        }
        Ok(PackedTextures { table, words })
    }
}

/// Words a texture's texels take.
fn texel_words(t: &Texture) -> usize {
    match &t.texels {
        Texels::Rgba8 { texels, .. } => texels.len(),
        Texels::Float { data, .. } => data.len(),
    }
}

/// The WGSL library: the constants above, generated, then `src/textures/texture.wgsl`
/// (`struct TextureRecord`, `texture_eval`, `texture_alpha`, `texture_eval_rgba`). The
/// module composing it declares the `tex_table` and `tex_words` bindings.
pub fn wgsl_library() -> String {
    let consts = [
        ("TEX_FORMAT_RGBA8_SRGB", FORMAT_RGBA8_SRGB),
        ("TEX_FORMAT_RGBA8_RAW", FORMAT_RGBA8_RAW),
        ("TEX_FORMAT_RGB32F", FORMAT_RGB32F),
        ("TEX_FORMAT_RGBA32F", FORMAT_RGBA32F),
        ("TEX_FORMAT_CHECKERBOARD", FORMAT_CHECKERBOARD),
        ("TEX_LUT_SRGB", LUT_SRGB),
        ("TEX_LUT_RAW", LUT_RAW),
        (
            "TEX_FILTER_NEAREST",
            crate::textures::Filter::Nearest.code(),
        ),
        ("TEX_WRAP_MIRROR", crate::textures::Wrap::Mirror.code()),
        ("TEX_WRAP_CLAMP", crate::textures::Wrap::Clamp.code()),
    ];
    let mut out = String::from("// Generated by src/integrators/gpu/textures.rs wgsl_library().\n");
    for (name, v) in consts {
        out.push_str(&format!("const {name}: u32 = {v}u;\n"));
    }
    out.push_str(&format!("const TEX_COORD_LIMIT: f32 = {COORD_LIMIT:.1};\n"));
    out.push_str(include_str!("../../textures/texture.wgsl"));
    out
}
