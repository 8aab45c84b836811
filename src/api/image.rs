//! [`Image`] as the facade shows it: contiguous f32 RGB, EXR and PNG writers, and the
//! comparison `gpu-photon diff` prints.

use crate::error::{Error, Result};
use crate::render::film::Image;
use crate::render::image_diff::DiffStats;
use std::path::Path;

impl Image {
    /// An image from `width * height * 3` linear RGB values, row by row from the top.
    pub fn from_rgb(width: u32, height: u32, rgb: Vec<f32>) -> Result<Image> {
        let n = width as usize * height as usize * 3;
        if rgb.len() != n || width == 0 || height == 0 {
            return Err(Error::Setting {
                field: "image",
                message: format!(
                    "{} values for a {width}x{height} RGB image (expected {n}, and a size of at least 1x1)",
                    rgb.len()
                ),
            });
        }
        let pixels = rgb.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Ok(Image {
            width,
            height,
            pixels,
        })
    }

    /// The pixels as contiguous linear RGB values (`height` rows of `width * 3`), no copy.
    pub fn rgb(&self) -> &[f32] {
        self.pixels.as_flattened()
    }

    /// The pixels as contiguous linear RGB values, taken without a copy.
    pub fn into_rgb(self) -> Vec<f32> {
        self.pixels.into_flattened()
    }

    /// Writes a linear float EXR (atomically: a temporary file renamed over `path`).
    pub fn write_exr(&self, path: impl AsRef<Path>) -> Result<()> {
        self.write_as(path.as_ref(), "exr", 0.0)
    }

    /// Writes an 8-bit sRGB PNG, scaled by 2^`exposure` (atomically).
    pub fn write_png(&self, path: impl AsRef<Path>, exposure: f32) -> Result<()> {
        self.write_as(path.as_ref(), "png", exposure)
    }

    fn write_as(&self, path: &Path, ext: &str, exposure: f32) -> Result<()> {
        let actual = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !actual.eq_ignore_ascii_case(ext) {
            return Err(Error::Image {
                path: path.to_path_buf(),
                message: format!("expected a .{ext} file name"),
            });
        }
        self.write(path, exposure)
    }

    /// How this image differs from the reference `b` (same size): RMSE, block RMSE over
    /// `block` x `block` means (0 counts as 1), relative MSE, per-channel mean ratio, largest error.
    pub fn diff(&self, b: &Image, block: u32) -> Result<DiffStats> {
        crate::render::image_diff::diff(self, b, block).map_err(Error::Sizes)
    }
}
