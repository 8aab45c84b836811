//! How two images differ: the statistics `gpu-photon diff`, the benches and the tests read
//! (RMSE, block RMSE that keeps bias and suppresses noise, relative MSE, mean ratios).

use super::film::Image;

/// How two images differ.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffStats {
    /// Root mean square error over all pixels and channels.
    pub rmse: f64,
    /// RMSE of the means of `block` x `block` pixel blocks (noise suppressed, bias kept).
    pub block_rmse: f64,
    /// Relative MSE: mean of (a - b)^2 / (b^2 + 0.01).
    pub rel_mse: f64,
    /// Per-channel mean of `a` over mean of `b`.
    pub mean_ratio: [f64; 3],
    /// Largest absolute difference of any channel.
    pub max_error: f64,
}

impl DiffStats {
    /// What `gpu-photon diff` prints, one statistic per line; `block` is the block side
    /// the block RMSE was measured with.
    pub fn lines(&self, block: u32) -> Vec<String> {
        let r = self.mean_ratio;
        vec![
            format!("rmse        {:.6}", self.rmse),
            format!(
                "block_rmse  {:.6} ({block}x{block} blocks)",
                self.block_rmse
            ),
            format!("rel_mse     {:.6}", self.rel_mse),
            format!("mean_ratio  {:.4} {:.4} {:.4}", r[0], r[1], r[2]),
            format!("max_error   {:.6}", self.max_error),
        ]
    }
}

/// Compares `a` with reference `b` (same size required).
pub fn diff(a: &Image, b: &Image, block: u32) -> std::result::Result<DiffStats, String> {
    if a.width != b.width || a.height != b.height {
        return Err(format!(
            "sizes differ: {}x{} vs {}x{}",
            a.width, a.height, b.width, b.height
        ));
    }
    let (mut se, mut rel, mut max) = (0.0f64, 0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let d = p[c] as f64 - q[c] as f64;
            se += d * d;
            rel += d * d / (q[c] as f64 * q[c] as f64 + 0.01);
            max = max.max(d.abs());
        }
    }
    let n = (a.pixels.len() * 3).max(1) as f64;
    let (ma, mb) = (a.mean(), b.mean());
    let mean_ratio = [0, 1, 2].map(|c| {
        if mb[c] != 0.0 {
            ma[c] / mb[c]
        } else if ma[c] == 0.0 {
            1.0
        } else {
            f64::INFINITY
        }
    });
    let block = block.max(1);
    let (bw, bh) = (a.width / block, a.height / block);
    let mut bse = 0.0f64;
    for by in 0..bh {
        for bx in 0..bw {
            let mut sa = [0.0f64; 3];
            let mut sb = [0.0f64; 3];
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let i = (y * a.width + x) as usize;
                    for c in 0..3 {
                        sa[c] += a.pixels[i][c] as f64;
                        sb[c] += b.pixels[i][c] as f64;
                    }
                }
            }
            let k = (block * block) as f64;
            for c in 0..3 {
                bse += ((sa[c] - sb[c]) / k).powi(2);
            }
        }
    }
    let block_rmse = if bw * bh > 0 {
        (bse / (bw * bh * 3) as f64).sqrt()
    } else {
        0.0
    };
    Ok(DiffStats {
        rmse: (se / n).sqrt(),
        block_rmse,
        rel_mse: rel / n,
        mean_ratio,
        max_error: max,
    })
}
