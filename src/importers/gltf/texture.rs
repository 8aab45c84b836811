//! glTF textures read for a material: the base colour (sRGB, times `baseColorFactor`), the
//! data textures (linear: metallic-roughness, transmission, specular; their factors multiply
//! them at each hit), the specular colour (sRGB) and the normal texture (linear, with its
//! `scale`). The image (a file
//! relative to the glTF file, a `data:` URI or a bufferView, PNG or JPEG) is looked up with
//! its sampler (`magFilter`, `wrapS`, `wrapT`) after `KHR_texture_transform`.
//!
//! Factors are baked into the texels where a texel's use is affine in it, so that filtering
//! (linear in the texels) commutes with it: the base colour times its factor (alpha kept);
//! the normal map's `2c - 1` scaled by `(scale, scale, 1)` and its green negated (glTF's
//! bitangent points to the image's top, `-dp/dv`; the shading frame of
//! `crate::math::geometry::normal_mapped` takes `+dp/dv`). A texel map of the identity keeps the
//! 8-bit texels; any other makes float texels.

use crate::error::Error;
use crate::importers::gltf::data;
use crate::textures::{decode, Encoding, Sampler, SceneTexture, Texture, UvTransform};
use glam::{Vec3, Vec4};
use std::path::Path;

/// A texture reference of a material: the texture, its uv set and uv transform.
pub(crate) struct TexRef<'a> {
    texture: gltf::Texture<'a>,
    set: u32,
    to_uv: UvTransform,
}

impl<'a> TexRef<'a> {
    /// A `textureInfo` (base colour, metallic-roughness, ...).
    pub(crate) fn info(info: &gltf::texture::Info<'a>) -> Self {
        let t = info.texture_transform();
        Self {
            texture: info.texture(),
            set: uv_set(info),
            to_uv: t.map_or(UvTransform::IDENTITY, |t| {
                UvTransform::from_gltf(t.offset(), t.rotation(), t.scale())
            }),
        }
    }

    /// A `normalTextureInfo`: its `KHR_texture_transform` is read from the extension's JSON.
    pub(crate) fn normal(n: &gltf::material::NormalTexture<'a>) -> Self {
        let ext = n.extension_value("KHR_texture_transform");
        let pair = |key: &str, default: [f32; 2]| {
            ext.and_then(|e| e.get(key))
                .and_then(|v| v.as_array())
                .filter(|a| a.len() == 2)
                .and_then(|a| Some([a[0].as_f64()? as f32, a[1].as_f64()? as f32]))
                .unwrap_or(default)
        };
        let rotation = ext
            .and_then(|e| e.get("rotation"))
            .and_then(|v| v.as_f64())
            .unwrap_or(0.0) as f32;
        let set = ext
            .and_then(|e| e.get("texCoord"))
            .and_then(|v| v.as_u64())
            .map_or(n.tex_coord(), |s| s.min(u32::MAX as u64) as u32);
        Self {
            texture: n.texture(),
            set,
            to_uv: UvTransform::from_gltf(
                pair("offset", [0.0; 2]),
                rotation,
                pair("scale", [1.0; 2]),
            ),
        }
    }

    /// The texture coordinate set it reads.
    pub(crate) fn set(&self) -> u32 {
        self.set
    }

    /// The texture's name (or `textures[i]`), for messages.
    pub(crate) fn name(&self) -> String {
        self.texture.name().map_or(
            format!("textures[{}]", self.texture.index()),
            str::to_string,
        )
    }
}

/// The texture coordinate set `info` reads: its `texCoord`, or the `KHR_texture_transform`
/// override.
pub(crate) fn uv_set(info: &gltf::texture::Info) -> u32 {
    info.texture_transform()
        .and_then(|t| t.tex_coord())
        .unwrap_or(info.tex_coord())
}

/// The base colour texture, its texels times `factor`.
pub(crate) fn base_colour(
    r: &TexRef,
    factor: Vec3,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<SceneTexture, (String, String)> {
    let map = (factor != Vec3::ONE).then_some(move |c: Vec4| (c.truncate() * factor).extend(c.w));
    load(r, Encoding::Srgb, map, buffers, base_dir)
}

/// A data texture, linear (metallic-roughness, transmission, specular: their factors
/// multiply it at each hit).
pub(crate) fn linear(
    r: &TexRef,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<SceneTexture, (String, String)> {
    load(
        r,
        Encoding::Raw,
        None::<fn(Vec4) -> Vec4>,
        buffers,
        base_dir,
    )
}

/// The normal texture with its `scale`, as texels of `crate::math::geometry::normal_mapped` (see
/// the module documentation).
pub(crate) fn normal(
    r: &TexRef,
    scale: f32,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<SceneTexture, (String, String)> {
    let map = move |c: Vec4| {
        Vec4::new(
            0.5 + (c.x - 0.5) * scale,
            0.5 - (c.y - 0.5) * scale,
            c.z,
            c.w,
        )
    };
    load(r, Encoding::Raw, Some(map), buffers, base_dir)
}

/// The texture `r` names, decoded with `encoding`, each texel through `map` (if any). Errors
/// are `(field, message)`: the image that cannot be read or decoded (`images[i]`), the
/// sampler whose codes are not glTF's (`samplers[i]`).
fn load(
    r: &TexRef,
    encoding: Encoding,
    map: Option<impl Fn(Vec4) -> Vec4>,
    buffers: &[Vec<u8>],
    base_dir: &Path,
) -> Result<SceneTexture, (String, String)> {
    let texture = &r.texture;
    let image = texture.source();
    let image_field = format!("images[{}]", image.index());
    let (bytes, path) =
        data::image_bytes(&image, buffers, base_dir).map_err(|m| (image_field.clone(), m))?;
    let name = match (&path, image.name()) {
        (Some(p), _) => p.display().to_string(),
        (None, Some(n)) => n.to_string(),
        (None, None) => image_field.clone(),
    };
    let decoded = decode::decode(&name, &bytes, encoding).map_err(|e| {
        let message = match e {
            Error::Image { message, .. } => format!("image {name}: {message}"),
            e => e.to_string(),
        };
        (image_field.clone(), message)
    })?;
    let s = texture.sampler();
    let sampler = Sampler::gltf(
        s.mag_filter().map(|f| f.as_gl_enum()),
        Some(s.wrap_s().as_gl_enum()),
        Some(s.wrap_t().as_gl_enum()),
        r.to_uv,
    )
    .map_err(|e| {
        let field = s
            .index()
            .map_or(format!("textures[{}]", texture.index()), |i| {
                format!("samplers[{i}]")
            });
        (field, e.to_string())
    })?;
    let mapped = match map {
        Some(f) => map_texels(decoded, f).map_err(|e| (image_field, e.to_string()))?,
        None => decoded,
    };
    Ok(SceneTexture::Bitmap(mapped.with_sampler(sampler)))
}

/// `t` with every texel through `f`, as float texels.
fn map_texels(t: Texture, f: impl Fn(Vec4) -> Vec4) -> crate::error::Result<Texture> {
    let mut data = Vec::with_capacity(4 * t.width as usize * t.height as usize);
    for y in 0..t.height {
        for x in 0..t.width {
            data.extend(f(t.texel(x, y)).to_array());
        }
    }
    Texture::from_float(&t.name, t.width, t.height, data, 4)
}
