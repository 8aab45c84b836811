//! Images: accumulation, EXR (linear float) and PNG (sRGB with exposure) input and output,
//! written atomically, and their tags (how two differ: `image_diff`).

use crate::error::{Error, Result};
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// A linear RGB image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB, row by row from the top.
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Image {
            width,
            height,
            pixels: vec![[0.0; 3]; (width * height) as usize],
        }
    }

    /// Per-channel mean.
    pub fn mean(&self) -> [f64; 3] {
        let mut m = [0.0f64; 3];
        for p in &self.pixels {
            for c in 0..3 {
                m[c] += p[c] as f64;
            }
        }
        m.map(|v| v / self.pixels.len().max(1) as f64)
    }

    /// Number of pixels with a NaN or infinite channel.
    pub fn non_finite(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|c| !c.is_finite()))
            .count()
    }

    /// `|self - other|` per pixel and channel, at `self`'s size (pixels past the shorter
    /// image stay as in `self`).
    pub fn abs_diff(&self, other: &Image) -> Image {
        let mut err = self.clone();
        for (p, q) in err.pixels.iter_mut().zip(&other.pixels) {
            *p = [0, 1, 2].map(|c| (p[c] - q[c]).abs());
        }
        err
    }

    /// Reads an EXR (linear) or PNG (sRGB, decoded to linear) image.
    pub fn read(path: &Path) -> Result<Image> {
        let err = |message: String| Error::Image {
            path: path.to_path_buf(),
            message,
        };
        if !path.exists() {
            return Err(err("no such file".into()));
        }
        let kind = image_kind(path)?;
        match kind {
            Kind::Exr => {
                let img = exr::prelude::read_first_rgba_layer_from_file(
                    path,
                    |res, _| Self::new(res.width() as u32, res.height() as u32),
                    |img: &mut Self, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                        let i = pos.y() * img.width as usize + pos.x();
                        img.pixels[i] = [r, g, b];
                    },
                )
                .map_err(|e| err(e.to_string()))?;
                Ok(img.layer_data.channel_data.pixels)
            }
            Kind::Png => {
                let img = image::open(path).map_err(|e| err(e.to_string()))?.to_rgb8();
                let (w, h) = img.dimensions();
                let pixels = img
                    .pixels()
                    .map(|p| p.0.map(|v| srgb_to_linear(v as f32 / 255.0)))
                    .collect();
                Ok(Image {
                    width: w,
                    height: h,
                    pixels,
                })
            }
        }
    }

    /// Writes `.exr` (linear float) or `.png` (sRGB, scaled by 2^exposure) atomically: to a
    /// temporary file beside `path`, then renamed over it.
    pub fn write(&self, path: &Path, exposure: f32) -> Result<()> {
        self.write_tagged(path, exposure, &[])
    }

    /// [`Image::write`] with text attributes in the EXR header (ignored for PNG).
    pub fn write_tagged(&self, path: &Path, exposure: f32, tags: &[(&str, String)]) -> Result<()> {
        let kind = image_kind(path)?;
        write_atomically(path, |out| match kind {
            Kind::Exr => {
                use exr::prelude::*;
                let (w, h) = (self.width as usize, self.height as usize);
                let pixels: &[[f32; 3]] = &self.pixels;
                let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                    let p: [f32; 3] = pixels[y * w + x];
                    (p[0], p[1], p[2])
                });
                let mut image = exr::image::Image::from_channels((w, h), channels);
                if !tags.is_empty() {
                    // One attribute holding every tag as `key=value` lines: the exr crate
                    // keeps attributes in a HashMap, whose order (and so the file's bytes)
                    // would differ from run to run with several.
                    let text: Vec<String> = tags.iter().map(|(k, v)| format!("{k}={v}")).collect();
                    image.layer_data.attributes.other.insert(
                        Text::from(TAGS_ATTRIBUTE),
                        AttributeValue::Text(Text::from(text.join("\n").as_str())),
                    );
                }
                // Sequential compression: the tiles are written in order (in parallel they
                // are written as threads finish them, so an image larger than one 64x64
                // tile would be other bytes from run to run).
                image
                    .write()
                    .non_parallel()
                    .to_buffered(out)
                    .map_err(|e| e.to_string())
            }
            Kind::Png => {
                let scale = 2f32.powf(exposure);
                let bytes: Vec<u8> = self
                    .pixels
                    .iter()
                    .flat_map(|p| {
                        p.map(|c| (linear_to_srgb(c * scale) * 255.0 + 0.5).clamp(0.0, 255.0) as u8)
                    })
                    .collect();
                image::write_buffer_with_format(
                    out,
                    &bytes,
                    self.width,
                    self.height,
                    image::ColorType::Rgb8,
                    image::ImageFormat::Png,
                )
                .map_err(|e| e.to_string())
            }
        })
    }
}

/// Checks, before time is spent on a render, that `path` names an image type this writes
/// and a place it can be written: not an existing directory or device, in a directory where
/// a file can be created (a temporary one is, then removed).
pub fn check_output_path(path: &Path) -> Result<()> {
    let ext = extension(path);
    image_kind(path)?;
    let err = |message: String| Error::Image {
        path: path.to_path_buf(),
        message,
    };
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() {
            let what = if meta.is_dir() {
                "a directory"
            } else {
                "not a regular file"
            };
            return Err(err(format!("cannot be written: it is {what}")));
        }
    }
    let (tmp, _) = create_temp(path, &ext).map_err(|e| err(format!("cannot be written: {e}")))?;
    let _ = std::fs::remove_file(tmp);
    Ok(())
}

/// A temporary file beside `path` (same directory, so the rename is atomic), created new:
/// `dir/.NAME.PID.N.tmp.EXT`, N counting this process's files.
fn create_temp(path: &Path, ext: &str) -> std::io::Result<(PathBuf, File)> {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("image");
    loop {
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let tmp = path.with_file_name(format!(".{name}.{}.{n}.tmp.{ext}", std::process::id()));
        match File::options().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// A writer that keeps the first error of the file under it, so a failed write is
/// reported as the operating system said it (`No space left on device`), not as the
/// encoder wrapped it.
struct Tracked<W> {
    inner: W,
    error: Option<std::io::Error>,
}

impl<W> Tracked<W> {
    fn keep<T>(&mut self, r: std::io::Result<T>) -> std::io::Result<T> {
        r.map_err(|e| {
            let copy = std::io::Error::new(e.kind(), e.to_string());
            self.error.get_or_insert(e);
            copy
        })
    }
}

impl<W: Write> Write for Tracked<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.inner.write(buf);
        self.keep(r)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.inner.flush();
        self.keep(r)
    }
}

impl<W: Seek> Seek for Tracked<W> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let r = self.inner.seek(pos);
        self.keep(r)
    }
}

/// Writes what `encode` writes to `path` atomically: into a new temporary file beside it,
/// flushed to the disk, then renamed over `path`. On any failure (no permission, disk full,
/// a file size limit) the temporary file is removed and an earlier file at `path` stays as
/// it was; the error names `path` and says so.
fn write_atomically(
    path: &Path,
    encode: impl FnOnce(&mut Tracked<BufWriter<File>>) -> std::result::Result<(), String>,
) -> Result<()> {
    let ext = extension(path);
    let failed = |why: String| {
        let kept = if std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
            "; the earlier file there is unchanged"
        } else {
            ""
        };
        Error::Image {
            path: path.to_path_buf(),
            message: format!("not written: {why}{kept}"),
        }
    };
    let (tmp, file) = create_temp(path, &ext).map_err(|e| failed(e.to_string()))?;
    let mut out = Tracked {
        inner: BufWriter::new(file),
        error: None,
    };
    let encoded = encode(&mut out);
    let written = encoded.and_then(|()| {
        let file = out
            .inner
            .into_inner()
            .map_err(|e| e.into_error().to_string())?;
        // On the disk before the rename: a late error (a full disk, a quota) is seen here,
        // and a crash after the rename never leaves an empty file.
        file.sync_all().map_err(|e| e.to_string())?;
        std::fs::rename(&tmp, path).map_err(|e| e.to_string())
    });
    written.map_err(|why| {
        let _ = std::fs::remove_file(&tmp);
        failed(out.error.map_or(why, |e| e.to_string()))
    })
}

/// The EXR header attribute that holds [`Image::write_tagged`]'s tags.
pub const TAGS_ATTRIBUTE: &str = "gpu_photon";

/// The text attributes of an EXR file's header, with the tags of [`Image::write_tagged`]
/// unpacked, sorted by key.
pub fn read_tags(path: &Path) -> Result<Vec<(String, String)>> {
    Ok(read_header(path)?.tags)
}

/// What an EXR file's header says about its image, read without its pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrHeader {
    /// Width of the first layer, in pixels.
    pub width: u32,
    /// Height of the first layer, in pixels.
    pub height: u32,
    /// The text attributes, as [`read_tags`] returns them.
    pub tags: Vec<(String, String)>,
}

/// Reads the header of an EXR file (its first layer's size and text attributes), not its
/// pixels: cheap enough to validate many files before reading any image.
pub fn read_header(path: &Path) -> Result<ExrHeader> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| Error::Image {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut tags = Vec::new();
    let (mut width, mut height) = (0, 0);
    if let Some(h) = meta.headers.first() {
        (width, height) = (h.layer_size.width() as u32, h.layer_size.height() as u32);
        for (k, v) in h
            .own_attributes
            .other
            .iter()
            .chain(&h.shared_attributes.other)
        {
            if let exr::meta::attribute::AttributeValue::Text(t) = v {
                if k.to_string() == TAGS_ATTRIBUTE {
                    for line in t.to_string().lines() {
                        if let Some((key, value)) = line.split_once('=') {
                            tags.push((key.to_string(), value.to_string()));
                        }
                    }
                } else {
                    tags.push((k.to_string(), t.to_string()));
                }
            }
        }
    }
    tags.sort();
    Ok(ExrHeader {
        width,
        height,
        tags,
    })
}

/// The image types read and written.
#[derive(Clone, Copy)]
enum Kind {
    Exr,
    Png,
}

/// The image type `path`'s extension names, or the error that names the types there are.
fn image_kind(path: &Path) -> Result<Kind> {
    match extension(path).as_str() {
        "exr" => Ok(Kind::Exr),
        "png" => Ok(Kind::Png),
        ext => Err(Error::Image {
            path: path.to_path_buf(),
            message: format!("unknown image type '.{ext}' (expected .exr or .png)"),
        }),
    }
}

fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

pub fn linear_to_srgb(c: f32) -> f32 {
    let c = if c.is_finite() {
        c.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse sRGB transfer function.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Rewrites the EXR file at `path` (an image `gpu-photon render` wrote, its header's tags
/// kept) with `layers` after its RGB layer: each a layer of that name with channels R, G, B
/// (`albedo.R`, ...). Atomic, as every image write.
pub fn add_exr_layers(path: &Path, layers: &[(&str, &Image)]) -> Result<()> {
    let main = Image::read(path)?;
    let tags = read_tags(path)?;
    for (name, image) in layers {
        if (image.width, image.height) != (main.width, main.height) {
            return Err(Error::Image {
                path: path.to_path_buf(),
                message: format!(
                    "layer {name} is {}x{}, the image {}x{}",
                    image.width, image.height, main.width, main.height
                ),
            });
        }
    }
    let mut all = vec![("", &main)];
    all.extend(layers.iter().copied());
    let tags: Vec<(&str, String)> = tags.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
    write_exr_layers(path, &all, &tags)
}

/// Writes the images of `layers` (same size) as one EXR image, atomically, in OpenEXR's
/// layer convention: each `(name, image)` the channels `name.R`, `name.G`, `name.B` (an
/// empty name: plain R, G, B, what readers take for the image), `tags` in the header as
/// `Image::write_tagged` puts them.
fn write_exr_layers(path: &Path, layers: &[(&str, &Image)], tags: &[(&str, String)]) -> Result<()> {
    write_atomically(path, |out| {
        use exr::prelude::*;
        let Some((_, first)) = layers.first() else {
            return Err("no layer to write".to_string());
        };
        let size = (first.width as usize, first.height as usize);
        let mut channels = SmallVec::new();
        for (name, image) in layers {
            for (c, n) in ["R", "G", "B"].into_iter().enumerate() {
                let samples = FlatSamples::F32(image.pixels.iter().map(|p| p[c]).collect());
                let full = match name.is_empty() {
                    true => n.to_string(),
                    false => format!("{name}.{n}"),
                };
                channels.push(AnyChannel::new(full.as_str(), samples));
            }
        }
        let mut attributes = LayerAttributes::default();
        if !tags.is_empty() {
            let text: Vec<String> = tags.iter().map(|(k, v)| format!("{k}={v}")).collect();
            attributes.other.insert(
                Text::from(TAGS_ATTRIBUTE),
                AttributeValue::Text(Text::from(text.join("\n").as_str())),
            );
        }
        let layer = Layer::new(
            size,
            attributes,
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(channels),
        );
        exr::image::Image::from_layer(layer)
            .write()
            .non_parallel()
            .to_buffered(out)
            .map_err(|e| e.to_string())
    })
}
