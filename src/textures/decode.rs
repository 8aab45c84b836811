//! Image files to [`Texture`]s: PNG, JPEG, BMP and Radiance HDR through the `image` crate,
//! OpenEXR through `exr`. The size is read from the header and checked against
//! [`MAX_SIDE`] and [`MAX_TEXELS`] before any texel is decoded; every failure is an
//! [`Error::Image`] or [`Error::Io`] naming the file.

use crate::error::{Error, Result};
use crate::textures::{
    check_size, image_error, pack_rgba8, srgb_to_linear, Encoding, Texture, MAX_SIDE, MAX_TEXELS,
};
use std::io::Cursor;
use std::path::Path;

/// Largest image file read (4 GiB: an uncompressed float RGBA image of 2^28 texels).
pub const MAX_FILE_BYTES: u64 = 1 << 32;

/// Loads the image at `path` (its format from its first bytes, not its name). 8-bit images
/// become packed RGBA8 texels decoded with `encoding`; 16-bit ones float texels (their
/// colour sRGB-decoded at load when `encoding` is sRGB); EXR and HDR images float texels,
/// linear whatever `encoding` says. Grey images expand to RGB; alpha is kept.
pub fn load(path: &Path, encoding: Encoding) -> Result<Texture> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let len = std::fs::metadata(path).map_err(io)?.len();
    if len > MAX_FILE_BYTES {
        return Err(image_error(
            &path.display().to_string(),
            format!("{len} bytes is too large for a texture file"),
        ));
    }
    let bytes = crate::importers::read::regular_file(path).map_err(io)?;
    decode(&path.display().to_string(), &bytes, encoding)
}

/// Decodes an image file's bytes (as [`load`] does); `name` names it in errors (a file, or
/// a glTF image).
pub fn decode(name: &str, bytes: &[u8], encoding: Encoding) -> Result<Texture> {
    if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        return decode_exr(name, bytes);
    }
    // Radiance files may sign themselves `#?RGBE` (Mitsuba does), which `image` refuses.
    let patched;
    let bytes = match bytes.strip_prefix(b"#?RGBE\n") {
        Some(rest) => {
            patched = [b"#?RADIANCE\n".as_slice(), rest].concat();
            patched.as_slice()
        }
        None => bytes,
    };
    let err = |e: image::ImageError| image_error(name, e.to_string());
    let reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| image_error(name, e.to_string()))?;
    let Some(format) = reader.format() else {
        return Err(image_error(
            name,
            "unknown image format (expected PNG, JPEG, BMP, OpenEXR or Radiance HDR)".into(),
        ));
    };
    let (w, h) = image::ImageReader::with_format(Cursor::new(bytes), format)
        .into_dimensions()
        .map_err(err)?;
    check_size(name, w, h)?;
    let mut reader = reader;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    // Within a quarter of the memory left (the decoded image is converted, a copy or two),
    // so that a large image fails here rather than aborting on a failed allocation.
    let room = crate::render::memory::available().map_or(u64::MAX, |(bytes, _)| bytes / 4);
    limits.max_alloc = Some((MAX_TEXELS * 16 + (1 << 20)).min(room));
    reader.limits(limits);
    let img = reader.decode().map_err(err)?;
    let (w, h) = (img.width(), img.height());
    use image::DynamicImage as D;
    match &img {
        D::ImageLuma8(_) | D::ImageLumaA8(_) | D::ImageRgb8(_) | D::ImageRgba8(_) => {
            let texels = img.to_rgba8().pixels().map(|p| pack_rgba8(p.0)).collect();
            Texture::from_rgba8(name, w, h, texels, encoding)
        }
        D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => {
            let channels = if img.color().has_alpha() { 4 } else { 3 };
            let rgba = img.to_rgba32f();
            let mut data = Vec::with_capacity(w as usize * h as usize * channels);
            for p in rgba.pixels() {
                let mut c = p.0;
                if encoding == Encoding::Srgb {
                    for v in &mut c[..3] {
                        *v = srgb_to_linear(*v as f64) as f32;
                    }
                }
                data.extend_from_slice(&c[..channels]);
            }
            Texture::from_float(name, w, h, data, channels as u32)
        }
        _ => {
            // Float images (Radiance HDR): linear.
            if img.color().has_alpha() {
                Texture::from_float(name, w, h, img.to_rgba32f().into_raw(), 4)
            } else {
                Texture::from_float(name, w, h, img.to_rgb32f().into_raw(), 3)
            }
        }
    }
}

/// The texels of an EXR decode, and whether the layer has alpha.
struct ExrPixels {
    width: usize,
    data: Vec<f32>,
    alpha: bool,
}

fn decode_exr(name: &str, bytes: &[u8]) -> Result<Texture> {
    let err = |e: exr::error::Error| image_error(name, e.to_string());
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(err)?;
    for header in &meta.headers {
        let size = header.layer_size;
        let (w, h) = (size.width(), size.height());
        if w > MAX_SIDE as usize || h > MAX_SIDE as usize {
            return Err(image_error(
                name,
                format!("{w} x {h} is too large for a texture"),
            ));
        }
    }
    use exr::prelude::*;
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |res, channels: &RgbaChannels| {
                let ok = res.width() as u64 * res.height() as u64 <= MAX_TEXELS;
                let n = if ok {
                    res.width() * res.height() * 4
                } else {
                    0
                };
                ExrPixels {
                    width: res.width(),
                    data: vec![0.0; n],
                    alpha: channels.3.is_some(),
                }
            },
            |px: &mut ExrPixels, pos, (r, g, b, a): (f32, f32, f32, f32)| {
                let i = (pos.y() * px.width + pos.x()) * 4;
                if let Some(t) = px.data.get_mut(i..i + 4) {
                    t.copy_from_slice(&[r, g, b, a]);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(err)?;
    let size = img.layer_data.size;
    let (w, h) = (size.width() as u32, size.height() as u32);
    check_size(name, w, h)?;
    let px = img.layer_data.channel_data.pixels;
    if px.alpha {
        Texture::from_float(name, w, h, px.data, 4)
    } else {
        let data = px
            .data
            .chunks_exact(4)
            .flat_map(|t| [t[0], t[1], t[2]])
            .collect();
        Texture::from_float(name, w, h, data, 3)
    }
}
