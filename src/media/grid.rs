//! Voxel grids of heterogeneous media (issue 41): Mitsuba's binary `.vol` format and its
//! `gridvolume` lookup. The file is little-endian: `VOL`, version byte 3, encoding 1
//! (float32), the resolution x, y, z and the channel count (1 or 3) as 32-bit integers, the
//! grid's bounding box (min xyz, max xyz, float32), then the values with x fastest and the
//! channels innermost (`data[((z * yres + y) * xres + x) * channels + c]`), 48 bytes in.
//!
//! A lookup maps a world point into the grid's unit cube (`to_world`'s inverse, and the
//! file's box with `use_grid_bbox`) and filters as drjit's textures do for Mitsuba: voxel
//! centres at `(i + 0.5) / res`, `trilinear` between the eight nearest, `nearest` the one
//! that holds the point, indices clamped to the grid (`wrap_mode` `clamp`).

use glam::{Affine3A, Vec3};
use std::io::Read;
use std::path::Path;

/// Bytes before the values.
pub const HEADER_BYTES: u64 = 48;

/// Values a grid may hold per axis (Mitsuba stores them as signed 32-bit integers).
pub const MAX_RES: u32 = 1 << 16;

/// A grid's values as read from a `.vol` file.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeGrid {
    /// Voxels along x, y and z (each >= 1).
    pub res: [u32; 3],
    /// Values per voxel: 1 or 3.
    pub channels: u32,
    /// The box the file gives its data (used with `use_grid_bbox`).
    pub bbox: [Vec3; 2],
    /// The values, x fastest, channels innermost.
    pub data: Vec<f32>,
}

/// How a lookup between voxel centres is filtered (Mitsuba's `filter_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Trilinear interpolation of the eight nearest voxel centres (Mitsuba's default).
    Trilinear,
    /// The voxel that holds the point.
    Nearest,
}

/// Little-endian reads of the header, each naming its field and byte offset on failure.
struct Header<'a> {
    bytes: &'a [u8; HEADER_BYTES as usize],
}

impl Header<'_> {
    fn u32(&self, at: usize) -> u32 {
        u32::from_le_bytes(self.bytes[at..at + 4].try_into().expect("4 bytes"))
    }
    fn f32(&self, at: usize) -> f32 {
        f32::from_bits(self.u32(at))
    }
}

impl VolumeGrid {
    /// Reads the `.vol` file at `path`, refusing one whose values would take more than
    /// `room` bytes (what the scene's budget has room for) before they are allocated. The
    /// error (a message for the caller to place) names the file and the byte offset or field.
    pub fn open(path: &Path, room: u64) -> Result<VolumeGrid, String> {
        let name = crate::escape::escape(&path.display().to_string()).into_owned();
        let fail = |m: String| format!("{name}: {m}");
        let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
        let len = file.metadata().map_err(|e| fail(e.to_string()))?.len();
        Self::read(std::io::BufReader::new(file), len, room).map_err(fail)
    }

    /// Reads a `.vol` grid of `len` bytes from `r` (see [`Self::open`]; the message names
    /// the byte offset or field but not the file).
    pub fn read(mut r: impl Read, len: u64, room: u64) -> Result<VolumeGrid, String> {
        let mut head = [0u8; HEADER_BYTES as usize];
        if len < HEADER_BYTES {
            return Err(format!(
                "byte {len}: truncated header (a .vol file's header takes {HEADER_BYTES} bytes)"
            ));
        }
        r.read_exact(&mut head)
            .map_err(|e| format!("byte 0: reading the header: {e}"))?;
        let h = Header { bytes: &head };
        // OpenVDB's magic number, 0x56444220, as its files begin (little-endian).
        if head[0..4] == [0x20, 0x42, 0x44, 0x56] {
            return Err(
                "byte 0: an OpenVDB file; grids are read from Mitsuba's .vol files \
                        only (write the grid out densely in that format: docs/media.md, \
                        \"Grid files\")"
                    .into(),
            );
        }
        if &head[0..3] != b"VOL" {
            return Err("byte 0: not a .vol file (it does not start with `VOL`)".into());
        }
        if head[3] != 3 {
            return Err(format!(
                "byte 3: version {}, only version 3 is supported",
                head[3]
            ));
        }
        let encoding = h.u32(4);
        if encoding != 1 {
            return Err(format!(
                "byte 4 (encoding): {}, only 1 (float32) is supported",
                encoding as i32
            ));
        }
        let mut res = [0u32; 3];
        for (axis, r) in res.iter_mut().enumerate() {
            let v = h.u32(8 + 4 * axis) as i32;
            if !(1..=MAX_RES as i32).contains(&v) {
                return Err(format!(
                    "byte {} ({}res): {v}, must be in 1..={MAX_RES}",
                    8 + 4 * axis,
                    ["x", "y", "z"][axis]
                ));
            }
            *r = v as u32;
        }
        let channels = h.u32(20) as i32;
        if channels != 1 && channels != 3 {
            return Err(format!(
                "byte 20 (channels): {channels}, only 1 or 3 are supported"
            ));
        }
        let channels = channels as u32;
        let lo = Vec3::new(h.f32(24), h.f32(28), h.f32(32));
        let hi = Vec3::new(h.f32(36), h.f32(40), h.f32(44));
        if !(lo.is_finite() && hi.is_finite() && lo.cmplt(hi).all()) {
            return Err(format!(
                "byte 24 (bbox): {lo} to {hi}, must be finite with min < max on every axis"
            ));
        }
        let values = res.iter().map(|&r| r as u64).product::<u64>() * channels as u64;
        let bytes = values * 4;
        if bytes > room {
            return Err(format!(
                "byte 8: {}x{}x{} voxels of {channels} channel(s) would take {bytes} bytes, \
                 more than the {room} the scene's budget has room for",
                res[0], res[1], res[2]
            ));
        }
        if len < HEADER_BYTES + bytes {
            return Err(format!(
                "byte {len}: truncated data ({}x{}x{} voxels of {channels} channel(s) need {} \
                 bytes)",
                res[0],
                res[1],
                res[2],
                HEADER_BYTES + bytes
            ));
        }
        let mut raw = vec![0u8; bytes as usize];
        r.read_exact(&mut raw)
            .map_err(|e| format!("byte {HEADER_BYTES}: reading the data: {e}"))?;
        let mut data = Vec::with_capacity(values as usize);
        for (i, b) in raw.chunks_exact(4).enumerate() {
            let v = f32::from_le_bytes(b.try_into().expect("4 bytes"));
            if !v.is_finite() {
                return Err(format!(
                    "byte {}: value {v} is not finite",
                    HEADER_BYTES + 4 * i as u64
                ));
            }
            data.push(v);
        }
        Ok(VolumeGrid {
            res,
            channels,
            bbox: [lo, hi],
            data,
        })
    }

    /// The byte offset of value `i` in the file (for messages about a value).
    pub fn offset_of(i: usize) -> u64 {
        HEADER_BYTES + 4 * i as u64
    }

    /// The largest value over every voxel and channel (0 for an empty grid).
    pub fn max(&self) -> f32 {
        self.data.iter().copied().fold(0.0, f32::max)
    }

    /// The voxel `(x, y, z)` (in range), as RGB: a one-channel grid's value in all three.
    fn voxel(&self, x: u32, y: u32, z: u32) -> Vec3 {
        let [rx, ry, _] = self.res;
        let i = (((z * ry + y) * rx + x) * self.channels) as usize;
        match self.channels {
            1 => Vec3::splat(self.data[i]),
            _ => Vec3::new(self.data[i], self.data[i + 1], self.data[i + 2]),
        }
    }

    /// The filtered value at `p` in the grid's unit cube (outside it, the nearest edge's).
    pub fn lookup(&self, p: Vec3, filter: Filter) -> Vec3 {
        let res = Vec3::new(self.res[0] as f32, self.res[1] as f32, self.res[2] as f32);
        let last = |axis: usize| self.res[axis] as i64 - 1;
        let clamp = |i: f32, axis: usize| (i as i64).clamp(0, last(axis)) as u32;
        match filter {
            Filter::Nearest => {
                let i = (p * res).floor();
                self.voxel(clamp(i.x, 0), clamp(i.y, 1), clamp(i.z, 2))
            }
            Filter::Trilinear => {
                let pos = p * res - 0.5;
                let i0 = pos.floor();
                let f = pos - i0;
                let (x, y, z) = (
                    [clamp(i0.x, 0), clamp(i0.x + 1.0, 0)],
                    [clamp(i0.y, 1), clamp(i0.y + 1.0, 1)],
                    [clamp(i0.z, 2), clamp(i0.z + 1.0, 2)],
                );
                let mut v = Vec3::ZERO;
                for (k, &zk) in z.iter().enumerate() {
                    let wz = if k == 0 { 1.0 - f.z } else { f.z };
                    for (j, &yj) in y.iter().enumerate() {
                        let wy = if j == 0 { 1.0 - f.y } else { f.y };
                        for (i, &xi) in x.iter().enumerate() {
                            let wx = if i == 0 { 1.0 - f.x } else { f.x };
                            v += self.voxel(xi, yj, zk) * (wx * wy * wz);
                        }
                    }
                }
                v
            }
        }
    }
}

/// A volume of RGB values over space: Mitsuba's `constvolume` or `gridvolume`, with its box
/// in world space (the image of the unit cube under `to_world`).
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// What it holds.
    pub kind: VolumeKind,
    /// The world box of its unit cube: its lower corner.
    pub lo: Vec3,
    /// Its upper corner.
    pub hi: Vec3,
}

/// The kinds of [`Volume`].
#[derive(Clone, Debug, PartialEq)]
pub enum VolumeKind {
    /// One value everywhere.
    Constant(Vec3),
    /// A voxel grid looked up through `to_local` (world to the grid's unit cube).
    Grid {
        /// The values.
        grid: std::sync::Arc<VolumeGrid>,
        /// World space to the grid's unit cube.
        to_local: Affine3A,
        /// Its filter.
        filter: Filter,
    },
}

impl Volume {
    /// A volume of `kind` whose unit cube `to_local` maps world points into.
    pub fn new(kind: VolumeKind, to_local: Affine3A) -> Volume {
        let to_world = to_local.inverse();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for i in 0..8 {
            let c = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32);
            let w = to_world.transform_point3(c);
            (lo, hi) = (lo.min(w), hi.max(w));
        }
        Volume { kind, lo, hi }
    }

    /// The value at world point `x`.
    pub fn eval(&self, x: Vec3) -> Vec3 {
        match &self.kind {
            VolumeKind::Constant(v) => *v,
            VolumeKind::Grid {
                grid,
                to_local,
                filter,
            } => grid.lookup(to_local.transform_point3(x), *filter),
        }
    }

    /// The largest value in any channel anywhere (a majorant).
    pub fn max(&self) -> f32 {
        match &self.kind {
            VolumeKind::Constant(v) => v.max_element(),
            VolumeKind::Grid { grid, .. } => grid.max(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `.vol` file's bytes: header fields as given, then `values`.
    pub(crate) fn vol(res: [i32; 3], channels: i32, values: &[f32]) -> Vec<u8> {
        let mut b = b"VOL\x03".to_vec();
        for v in [1, res[0], res[1], res[2], channels] {
            b.extend(v.to_le_bytes());
        }
        for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0].iter().chain(values) {
            b.extend(v.to_le_bytes());
        }
        b
    }

    fn read(b: &[u8]) -> Result<VolumeGrid, String> {
        VolumeGrid::read(b, b.len() as u64, 1 << 20)
    }

    #[test]
    fn reads_and_filters_like_mitsuba() {
        // 2 x 1 x 1, one channel: values 1 and 3 at x centres 0.25 and 0.75.
        let g = read(&vol([2, 1, 1], 1, &[1.0, 3.0])).unwrap();
        assert_eq!((g.res, g.channels), ([2, 1, 1], 1));
        let at = |x: f32, f| g.lookup(Vec3::new(x, 0.5, 0.5), f).x;
        assert_eq!(at(0.25, Filter::Trilinear), 1.0);
        assert_eq!(at(0.5, Filter::Trilinear), 2.0);
        assert_eq!(at(0.625, Filter::Trilinear), 2.5);
        // Clamped beyond the outer centres and outside the cube.
        assert_eq!(at(0.1, Filter::Trilinear), 1.0);
        assert_eq!(at(1.7, Filter::Trilinear), 3.0);
        assert_eq!(at(0.49, Filter::Nearest), 1.0);
        assert_eq!(at(0.51, Filter::Nearest), 3.0);
        // Three channels, x fastest: voxel (1, 0, 0) is the second triple.
        let g = read(&vol([2, 1, 1], 3, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0])).unwrap();
        let v = g.lookup(Vec3::new(0.9, 0.5, 0.5), Filter::Nearest);
        assert_eq!(v, Vec3::new(4.0, 5.0, 6.0));
        assert_eq!(g.max(), 6.0);
        // z slowest: a 1 x 1 x 2 grid's second value is at z = 0.75.
        let g = read(&vol([1, 1, 2], 1, &[0.0, 8.0])).unwrap();
        assert_eq!(
            g.lookup(Vec3::new(0.5, 0.5, 0.75), Filter::Trilinear).x,
            8.0
        );
    }

    #[test]
    fn bad_files_are_located_errors() {
        let good = vol([2, 2, 2], 1, &[1.0; 8]);
        let mut nan = good.clone();
        nan[48 + 4 * 5..48 + 4 * 6].copy_from_slice(&f32::NAN.to_le_bytes());
        let mut version = good.clone();
        version[3] = 2;
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (good[..20].to_vec(), "byte 20: truncated header"),
            (
                b"VOX".iter().chain(&good[3..]).copied().collect(),
                "byte 0: not a .vol",
            ),
            (version, "byte 3: version 2"),
            (vol([0, 2, 2], 1, &[]), "byte 8 (xres): 0"),
            (vol([2, -5, 2], 1, &[]), "byte 12 (yres): -5"),
            (vol([2, 2, 2], 2, &[]), "byte 20 (channels): 2"),
            (
                good[..60].to_vec(),
                "byte 60: truncated data (2x2x2 voxels of 1 channel(s) need 80 bytes)",
            ),
            (nan, "byte 68: value NaN is not finite"),
            (
                vol([65536, 65536, 65536], 3, &[]),
                "byte 8: 65536x65536x65536 voxels",
            ),
        ];
        for (bytes, want) in cases {
            let e = read(&bytes).expect_err(want);
            assert!(e.contains(want), "{e:?} lacks {want:?}");
        }
        let e = VolumeGrid::open(Path::new("/nonexistent/x.vol"), 1 << 20).unwrap_err();
        assert!(e.starts_with("/nonexistent/x.vol: "), "{e}");
    }

    #[test]
    fn a_volume_box_is_its_unit_cube_in_world_space() {
        let to_world =
            Affine3A::from_translation(Vec3::splat(-0.5)) * Affine3A::from_scale(Vec3::splat(1.5));
        let v = Volume::new(VolumeKind::Constant(Vec3::ONE), to_world.inverse());
        assert!((v.lo - Vec3::splat(-0.5)).abs().max_element() < 1e-6);
        assert!((v.hi - Vec3::splat(1.0)).abs().max_element() < 1e-6);
    }
}
