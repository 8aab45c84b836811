//! Heterogeneous media on the device (issue 41): the words the GPU backend appends to its
//! `media` buffer after the media table, read by `media/heterogeneous.wgsl`. Each
//! heterogeneous medium has one record of [`HETERO_WORDS`] f32 words (integers as their bits):
//! its extinction and albedo volumes ([`VOLUME_WORDS`] each: kind, filter, channels,
//! resolution, where the voxels start, a constant's value, `to_local` as its three columns
//! and translation, the world box), `scale`, the global majorant and the majorant grid
//! (corner, cell size, cells per axis, where the cells start); voxels and cells follow as
//! plain f32 words. Offsets are flat word indices into the buffer (word `i` is component
//! `i % 4` of its vec4 `i / 4`), so one storage binding holds every medium's grids.

use crate::media::grid::{Filter, Volume, VolumeKind};
use crate::media::heterogeneous::{Heterogeneous, MAX_TRACKING_STEPS};
use crate::media::{Medium, MediumKind, NO_MEDIUM};

/// A volume's record: its kind ([`VOLUME_CONSTANT`] or [`VOLUME_GRID`]).
pub const VOLUME_KIND: u32 = 0;
/// Its filter ([`FILTER_TRILINEAR`] or [`FILTER_NEAREST`]).
pub const VOLUME_FILTER: u32 = 1;
/// Its channels (1 or 3).
pub const VOLUME_CHANNELS: u32 = 2;
/// Its voxels per axis (three words).
pub const VOLUME_RES: u32 = 3;
/// The flat word index of its first voxel value.
pub const VOLUME_DATA: u32 = 6;
/// A constant volume's value (three words).
pub const VOLUME_VALUE: u32 = 7;
/// `to_local`: x, y and z columns, then the translation (twelve words).
pub const VOLUME_TO_LOCAL: u32 = 10;
/// The world box's lower corner (three words).
pub const VOLUME_LO: u32 = 22;
/// Its upper corner (three words).
pub const VOLUME_HI: u32 = 25;
/// Words of a volume's record.
pub const VOLUME_WORDS: u32 = 28;
/// [`VOLUME_KIND`] of a constant volume.
pub const VOLUME_CONSTANT: u32 = 0;
/// [`VOLUME_KIND`] of a grid.
pub const VOLUME_GRID: u32 = 1;
/// [`VOLUME_FILTER`] of trilinear filtering.
pub const FILTER_TRILINEAR: u32 = 0;
/// [`VOLUME_FILTER`] of nearest filtering.
pub const FILTER_NEAREST: u32 = 1;

/// A heterogeneous medium's record: the extinction volume.
pub const HETERO_SIGMA_T: u32 = 0;
/// The albedo volume.
pub const HETERO_ALBEDO: u32 = VOLUME_WORDS;
/// `scale`.
pub const HETERO_SCALE: u32 = 2 * VOLUME_WORDS;
/// The global majorant.
pub const HETERO_MAJORANT: u32 = HETERO_SCALE + 1;
/// The majorant grid's lower corner (three words).
pub const HETERO_CELLS_LO: u32 = HETERO_SCALE + 2;
/// Its cell size (three words).
pub const HETERO_CELL_SIZE: u32 = HETERO_SCALE + 5;
/// Its cells per axis (three words).
pub const HETERO_CELLS_RES: u32 = HETERO_SCALE + 8;
/// The flat word index of its first cell.
pub const HETERO_CELLS: u32 = HETERO_SCALE + 11;
/// Words of a heterogeneous medium's record (a multiple of four).
pub const HETERO_WORDS: u32 = HETERO_SCALE + 12;

/// The constants `heterogeneous.wgsl` reads from the generated prelude.
pub const WGSL_U32: [(&str, u32); 24] = [
    ("VOLUME_KIND", VOLUME_KIND),
    ("VOLUME_FILTER", VOLUME_FILTER),
    ("VOLUME_CHANNELS", VOLUME_CHANNELS),
    ("VOLUME_RES", VOLUME_RES),
    ("VOLUME_DATA", VOLUME_DATA),
    ("VOLUME_VALUE", VOLUME_VALUE),
    ("VOLUME_TO_LOCAL", VOLUME_TO_LOCAL),
    ("VOLUME_LO", VOLUME_LO),
    ("VOLUME_HI", VOLUME_HI),
    ("VOLUME_WORDS", VOLUME_WORDS),
    ("VOLUME_CONSTANT", VOLUME_CONSTANT),
    ("VOLUME_GRID", VOLUME_GRID),
    ("FILTER_TRILINEAR", FILTER_TRILINEAR),
    ("FILTER_NEAREST", FILTER_NEAREST),
    ("HETERO_SIGMA_T", HETERO_SIGMA_T),
    ("HETERO_ALBEDO", HETERO_ALBEDO),
    ("HETERO_SCALE", HETERO_SCALE),
    ("HETERO_MAJORANT", HETERO_MAJORANT),
    ("HETERO_CELLS_LO", HETERO_CELLS_LO),
    ("HETERO_CELL_SIZE", HETERO_CELL_SIZE),
    ("HETERO_CELLS_RES", HETERO_CELLS_RES),
    ("HETERO_CELLS", HETERO_CELLS),
    ("HETERO_WORDS", HETERO_WORDS),
    ("MAX_TRACKING_STEPS", MAX_TRACKING_STEPS),
];

/// The grids of `media` as words to follow a table of `table_words` vec4 words: the words,
/// and per medium the vec4 index of its record ([`NO_MEDIUM`] for a homogeneous one). `Err`
/// with the bytes they would take when over `max_bytes` (the device's storage binding, which
/// the whole buffer must fit), before anything is allocated.
pub fn pack(
    media: &[Medium],
    table_words: u64,
    max_bytes: u64,
) -> Result<(Vec<[f32; 4]>, Vec<u32>), u64> {
    let volume_words = |v: &Volume| match &v.kind {
        VolumeKind::Grid { grid, .. } => grid.data.len() as u64,
        VolumeKind::Constant(_) => 0,
    };
    let words: u64 = media
        .iter()
        .map(|m| match &m.kind {
            MediumKind::Heterogeneous(h) => {
                let cells = h.majorants.cell_count() as u64;
                let data = HETERO_WORDS as u64 + volume_words(&h.sigma_t) + volume_words(&h.albedo);
                (data + cells).div_ceil(4) * 4
            }
            MediumKind::Homogeneous => 0,
        })
        .sum();
    let bytes = 16 * table_words + 4 * words;
    if bytes > max_bytes || (table_words * 4 + words) > u32::MAX as u64 {
        return Err(bytes);
    }
    let mut flat: Vec<f32> = Vec::with_capacity(words as usize);
    let start = 4 * table_words as u32;
    let mut records = Vec::with_capacity(media.len());
    for m in media {
        let MediumKind::Heterogeneous(h) = &m.kind else {
            records.push(NO_MEDIUM);
            continue;
        };
        records.push((start + flat.len() as u32) / 4);
        push_record(h, start, &mut flat);
        flat.resize(flat.len().div_ceil(4) * 4, 0.0);
    }
    let out = flat
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    Ok((out, records))
}

/// Appends `h`'s record, then its voxels and cells, to `flat`, whose word 0 is the buffer's
/// word `start`.
fn push_record(h: &Heterogeneous, start: u32, flat: &mut Vec<f32>) {
    let at = flat.len();
    flat.resize(at + HETERO_WORDS as usize, 0.0);
    let mut tail = Vec::new();
    let base = start + (at + HETERO_WORDS as usize) as u32;
    for (v, slot) in [(&h.sigma_t, HETERO_SIGMA_T), (&h.albedo, HETERO_ALBEDO)] {
        let data = base + tail.len() as u32;
        let rec = volume_record(v, data, &mut tail);
        flat[at + slot as usize..at + (slot + VOLUME_WORDS) as usize].copy_from_slice(&rec);
    }
    let (lo, size, res, cells) = h.majorants.parts();
    let r = &mut flat[at + HETERO_SCALE as usize..at + HETERO_WORDS as usize];
    r[0] = h.scale;
    r[1] = h.majorant;
    r[2..5].copy_from_slice(&lo.to_array());
    r[5..8].copy_from_slice(&size.to_array());
    for (k, n) in res.to_array().into_iter().enumerate() {
        r[8 + k] = f32::from_bits(n);
    }
    r[11] = f32::from_bits(base + tail.len() as u32);
    tail.extend_from_slice(cells);
    flat.extend(tail);
}

/// A volume's record; a grid's values go to `tail`, at flat word `data`.
fn volume_record(v: &Volume, data: u32, tail: &mut Vec<f32>) -> [f32; VOLUME_WORDS as usize] {
    let mut r = [0.0f32; VOLUME_WORDS as usize];
    let bits = f32::from_bits;
    match &v.kind {
        VolumeKind::Constant(c) => {
            r[VOLUME_KIND as usize] = bits(VOLUME_CONSTANT);
            r[VOLUME_VALUE as usize..][..3].copy_from_slice(&c.to_array());
        }
        VolumeKind::Grid {
            grid,
            to_local,
            filter,
        } => {
            r[VOLUME_KIND as usize] = bits(VOLUME_GRID);
            r[VOLUME_FILTER as usize] = bits(match filter {
                Filter::Trilinear => FILTER_TRILINEAR,
                Filter::Nearest => FILTER_NEAREST,
            });
            r[VOLUME_CHANNELS as usize] = bits(grid.channels);
            for k in 0..3 {
                r[(VOLUME_RES + k) as usize] = bits(grid.res[k as usize]);
            }
            r[VOLUME_DATA as usize] = bits(data);
            let m = to_local.matrix3;
            let columns = [m.x_axis, m.y_axis, m.z_axis, to_local.translation];
            for (k, c) in columns.iter().enumerate() {
                r[VOLUME_TO_LOCAL as usize + 3 * k..][..3].copy_from_slice(&c.to_array());
            }
            tail.extend_from_slice(&grid.data);
        }
    }
    r[VOLUME_LO as usize..][..3].copy_from_slice(&v.lo.to_array());
    r[VOLUME_HI as usize..][..3].copy_from_slice(&v.hi.to_array());
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::phase::HenyeyGreenstein;
    use glam::{Affine3A, Vec3};

    fn constant_medium() -> Medium {
        let unit = Affine3A::IDENTITY;
        let h = Heterogeneous::new(
            Volume::new(VolumeKind::Constant(Vec3::splat(2.0)), unit),
            Volume::new(VolumeKind::Constant(Vec3::splat(0.5)), unit),
            1.5,
        );
        Medium {
            sigma_t: Vec3::splat(3.0),
            albedo: Vec3::splat(0.5),
            phase: HenyeyGreenstein { g: 0.0 },
            kind: MediumKind::Heterogeneous(std::sync::Arc::new(h)),
        }
    }

    /// Records start where the table ends, homogeneous media have none, the majorant's cell
    /// follows the record, and a buffer over the binding limit is refused with its size.
    #[test]
    fn records_follow_the_table_and_oversize_is_refused() {
        let mut homogeneous = constant_medium();
        homogeneous.kind = MediumKind::Homogeneous;
        let media = [homogeneous, constant_medium()];
        let (words, records) = pack(&media, 4, 1 << 20).unwrap();
        assert_eq!(records, vec![NO_MEDIUM, 4]);
        let flat: Vec<f32> = words.iter().flatten().copied().collect();
        assert_eq!(flat.len() % 4, 0);
        assert_eq!(flat[HETERO_SCALE as usize], 1.5);
        assert_eq!(flat[HETERO_MAJORANT as usize], 3.0);
        let cells = flat[HETERO_CELLS as usize].to_bits();
        assert_eq!(cells, 16 + HETERO_WORDS);
        assert_eq!(flat[(cells - 16) as usize], 3.0);
        assert_eq!(pack(&media, 4, 100), Err(64 + 4 * flat.len() as u64));
    }
}
