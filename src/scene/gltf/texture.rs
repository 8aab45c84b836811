//! glTF textures read for a material: the base colour texture of a material mapped to a
//! Lambertian albedo ([`super::material::diffuse_texture`]). The image (a file relative to
//! the glTF file, a `data:` URI or a bufferView, PNG or JPEG) is decoded as sRGB and looked up
//! with its sampler (`magFilter`, `wrapS`, `wrapT`) after `KHR_texture_transform`.
//!
//! glTF multiplies the texel by `baseColorFactor`. The factor is baked into the texels: a
//! factor of 1 keeps the 8-bit texels as they are; any other makes float texels, each the
//! decoded texel times the factor (alpha kept). Filtering is linear in the texels, so the
//! lookup equals the factor times the unscaled lookup up to f32 rounding.

use super::data;
use crate::error::Error;
use crate::texture::{decode, Encoding, Sampler, SceneTexture, Texture, UvTransform};
use glam::Vec3;
use std::path::Path;

/// The texture coordinate set `info` reads: its `texCoord`, or the `KHR_texture_transform`
/// override.
pub(super) fn uv_set(info: &gltf::texture::Info) -> u32 {
    info.texture_transform()
        .and_then(|t| t.tex_coord())
        .unwrap_or(info.tex_coord())
}

/// The texture `info` names, its texels times `factor`. Errors are `(field, message)`: the
/// image that cannot be read or decoded (`images[i]`), the sampler whose codes are not
/// glTF's (`samplers[i]`).
pub(super) fn base_colour(
    info: &gltf::texture::Info,
    factor: Vec3,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<SceneTexture, (String, String)> {
    let texture = info.texture();
    let image = texture.source();
    let image_field = format!("images[{}]", image.index());
    let (bytes, path) =
        data::image_bytes(&image, buffers, base_dir).map_err(|m| (image_field.clone(), m))?;
    let name = match (&path, image.name()) {
        (Some(p), _) => p.display().to_string(),
        (None, Some(n)) => n.to_string(),
        (None, None) => image_field.clone(),
    };
    let decoded = decode::decode(&name, &bytes, Encoding::Srgb).map_err(|e| {
        let message = match e {
            Error::Image { message, .. } => format!("image {name}: {message}"),
            e => e.to_string(),
        };
        (image_field.clone(), message)
    })?;
    let to_uv = info.texture_transform().map_or(UvTransform::IDENTITY, |t| {
        UvTransform::from_gltf(t.offset(), t.rotation(), t.scale())
    });
    let s = texture.sampler();
    let sampler = Sampler::gltf(
        s.mag_filter().map(|f| f.as_gl_enum()),
        Some(s.wrap_s().as_gl_enum()),
        Some(s.wrap_t().as_gl_enum()),
        to_uv,
    )
    .map_err(|e| {
        let field = s
            .index()
            .map_or(format!("textures[{}]", texture.index()), |i| {
                format!("samplers[{i}]")
            });
        (field, e.to_string())
    })?;
    let scaled = scale(decoded, factor).map_err(|e| (image_field, e.to_string()))?;
    Ok(SceneTexture::Bitmap(scaled.with_sampler(sampler)))
}

/// `t` with its colour times `factor` (see the module documentation).
fn scale(t: Texture, factor: Vec3) -> crate::error::Result<Texture> {
    if factor == Vec3::ONE {
        return Ok(t);
    }
    let mut data = Vec::with_capacity(4 * t.width as usize * t.height as usize);
    for y in 0..t.height {
        for x in 0..t.width {
            let c = t.texel(x, y);
            data.extend((c.truncate() * factor).to_array());
            data.push(c.w);
        }
    }
    Texture::from_float(&t.name, t.width, t.height, data, 4)
}
