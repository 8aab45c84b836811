//! Where a projector's photons pass its image plane: in proportion to its image, as
//! Mitsuba's projector samples its pixels ("efficient even if only a single pixel is turned
//! on"). The image's uv square is cut into a grid of cells (the image's resolution, at most
//! [`MAX_CELLS`] a side); a cell's weight is the image's largest channel integrated over it
//! by Simpson's rule on the 3 x 3 points of its corners, edge midpoints and centre (with
//! cells of one texel, every point a bilinear lookup lights has a lit point among those),
//! mixed with [`UNIFORM`] of a uniform density so that no lit point has density 0 whatever
//! the lookup (a lit texel between the points of a larger cell). A photon picks a cell by
//! the CDF, a uniform point in it, and carries `texel / (mean pdf)`: unbiased for any
//! weights.
//!
//! As the GPU reads it from the light's `cdf_start` in `light_cdf`: the grid's width and
//! height, the cells' CDF (row by row, ending at 1), then each cell's density over the uv
//! square. Twin: `projector_cell` in `projector.wgsl`.

use crate::textures::SceneTexture;

/// Most cells along a side of the grid.
pub const MAX_CELLS: u32 = 128;
/// The share of the photons spread uniformly over the image.
pub const UNIFORM: f64 = 0.1;
/// Words before the CDF: the grid's width and height.
pub const HEADER_WORDS: usize = 2;

/// The grid of `texture`: its size (cells across, down) and its words (module docs).
pub fn image_distribution(texture: &SceneTexture) -> Vec<f32> {
    let (gw, gh) = match texture {
        SceneTexture::Bitmap(b) => (b.width.min(MAX_CELLS), b.height.min(MAX_CELLS)),
        SceneTexture::Checkerboard(_) => (32, 32),
    };
    // The image at the (2 gw + 1) x (2 gh + 1) lattice of cell corners, edge midpoints and
    // centres.
    let (lw, lh) = (2 * gw + 1, 2 * gh + 1);
    let lattice: Vec<f32> = (0..lh * lw)
        .map(|k| {
            let uv = glam::Vec2::new(
                (k % lw) as f32 / (2 * gw) as f32,
                (k / lw) as f32 / (2 * gh) as f32,
            );
            texture.eval(uv).max_element().max(0.0)
        })
        .collect();
    let mut weights = Vec::with_capacity((gw * gh) as usize);
    for j in 0..gh {
        for i in 0..gw {
            // Simpson's rule over the cell: corners 1, edge midpoints 4, the centre 16.
            let mut w = 0.0f64;
            for dy in 0..3 {
                for dx in 0..3 {
                    let k = [1.0, 4.0, 1.0][dy as usize] * [1.0, 4.0, 1.0][dx as usize];
                    w += k * lattice[((2 * j + dy) * lw + 2 * i + dx) as usize] as f64;
                }
            }
            weights.push(w / 36.0);
        }
    }
    let n = weights.len() as f64;
    let sum: f64 = weights.iter().sum();
    let p: Vec<f64> = weights
        .iter()
        .map(|w| match sum > 0.0 {
            true => (1.0 - UNIFORM) * w / sum + UNIFORM / n,
            false => 1.0 / n,
        })
        .collect();
    let mut cdf = Vec::with_capacity(p.len());
    let mut acc = 0.0f64;
    for q in &p {
        acc += q;
        cdf.push(acc as f32);
    }
    *cdf.last_mut().expect("at least one cell") = 1.0;
    // Each cell's density is its probability as the f32 CDF draws it, times the cells.
    let density = (0..cdf.len()).map(|k| {
        let below = if k == 0 { 0.0 } else { cdf[k - 1] as f64 };
        ((cdf[k] as f64 - below) * n) as f32
    });
    let mut out = vec![gw as f32, gh as f32];
    out.extend_from_slice(&cdf);
    out.extend(density);
    out
}

/// The cell `u` picks in `words` (a distribution as [`image_distribution`] writes it), by
/// bisecting its CDF: the uv of its corner, its size and its density over the uv square.
pub fn pick(words: &[f32], u: f32) -> ([f32; 2], [f32; 2], f32) {
    let (gw, gh) = (words[0] as usize, words[1] as usize);
    let n = gw * gh;
    let cdf = &words[HEADER_WORDS..HEADER_WORDS + n];
    let k = cdf.partition_point(|&c| c <= u).min(n - 1);
    let size = [1.0 / gw as f32, 1.0 / gh as f32];
    let corner = [(k % gw) as f32 * size[0], (k / gw) as f32 * size[1]];
    (corner, size, words[HEADER_WORDS + n + k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::{Encoding, Texture};

    /// A `w x h` 8-bit image, black but for the texels `lit`.
    fn image(w: u32, h: u32, lit: &[(u32, u32)]) -> SceneTexture {
        let texels = (0..w * h)
            .map(|k| match lit.contains(&(k % w, k / w)) {
                true => u32::from_le_bytes([255, 128, 0, 255]),
                false => u32::from_le_bytes([0, 0, 0, 255]),
            })
            .collect();
        SceneTexture::Bitmap(Texture::from_rgba8("t", w, h, texels, Encoding::Raw).unwrap())
    }

    /// The cells' probabilities as `pick` draws them: by a fine sweep of `u`.
    fn picked(words: &[f32]) -> Vec<f64> {
        let (gw, gh) = (words[0] as usize, words[1] as usize);
        let mut p = vec![0.0; gw * gh];
        let m = 1 << 20;
        for i in 0..m {
            let (corner, size, _) = pick(words, (i as f32 + 0.5) / m as f32);
            let k = (corner[1] / size[1]).round() as usize * gw
                + (corner[0] / size[0]).round() as usize;
            p[k] += 1.0 / m as f64;
        }
        p
    }

    #[test]
    fn densities_are_what_the_cdf_draws_and_average_one() {
        let t = image(40, 30, &[(3, 4), (20, 20), (39, 29)]);
        let w = image_distribution(&t);
        assert_eq!((w[0], w[1]), (40.0, 30.0));
        let n = 40 * 30;
        assert_eq!(w.len(), HEADER_WORDS + 2 * n);
        let density = &w[HEADER_WORDS + n..];
        let mean: f64 = density.iter().map(|&d| d as f64).sum::<f64>() / n as f64;
        assert!((mean - 1.0).abs() < 1e-5, "{mean}");
        for (k, p) in picked(&w).iter().enumerate() {
            let want = density[k] as f64 / n as f64;
            assert!(
                (p - want).abs() < 2e-5,
                "cell {k}: drawn {p}, density / n {want}"
            );
        }
    }

    #[test]
    fn a_lit_texel_and_its_bilinear_neighbours_get_all_but_the_uniform_share() {
        // One lit texel of a 16 x 16 image: its bilinear footprint reaches the 3 x 3 cells
        // around it, which take 90% of the photons, most of them the lit one (Simpson's rule
        // of the bilinear tent: 25/36 of its mass there, 2.5/36 each side, 0.25/36 each
        // corner); every other cell keeps its share of the uniform tenth.
        let t = image(16, 16, &[(5, 7)]);
        let w = image_distribution(&t);
        let n = 256;
        let p = picked(&w);
        let near: f64 = (4..=6)
            .flat_map(|x| (6..=8).map(move |y| y * 16 + x))
            .map(|k| p[k])
            .sum();
        let want = 1.0 - UNIFORM + UNIFORM * 9.0 / n as f64;
        assert!((near - want).abs() < 1e-4, "{near} vs {want}");
        // The lit cell: its centre, its edge midpoints at half, its corners at a quarter.
        let lit =
            (1.0 - UNIFORM) * (16.0 + 4.0 * 4.0 * 0.5 + 4.0 * 0.25) / 36.0 + UNIFORM / n as f64;
        assert!(
            (p[7 * 16 + 5] - lit).abs() < 1e-4,
            "{} vs {lit}",
            p[7 * 16 + 5]
        );
        assert!(p.iter().all(|&q| q >= 0.99 * UNIFORM / n as f64));
    }

    #[test]
    fn a_black_image_is_uniform_and_a_large_one_is_capped() {
        let w = image_distribution(&image(8, 4, &[]));
        assert!(w[HEADER_WORDS + 32..]
            .iter()
            .all(|&d| (d - 1.0).abs() < 1e-5));
        let big = image_distribution(&image(300, 2, &[(0, 0)]));
        assert_eq!((big[0], big[1]), (MAX_CELLS as f32, 2.0));
    }
}
