//! SDF grids on the GPU (Mitsuba's `sdfgrid`, `crate::scene::sdf_grid`): every grid's occupied
//! cells are primitives of the world hierarchy beside its triangles and spheres, id
//! `SPHERE_BIT | SDF_BIT | k` with `k` the cell's index over the scene's grids in order
//! ([`world_bvh`]); `walk_bvh` (src/bvh/intersect.wgsl) tests them with `sdf_intersect_cell`
//! and `trace_ray` shades their hits with `sdf_surface` (src/scene/sdf_grid.wgsl).
//!
//! Their data follows the leaf entries in the `leaf_prims` binding ([`SdfWords`]): one
//! [`GpuSdfGrid`] record per placed grid, then per grid's values (once for the placements
//! that share them) the vertex values (f32, x fastest) and each occupied cell's eight corner
//! values (two words, corner `i` at `c + (i & 1, i >> 1 & 1, i >> 2 & 1)`). A cell's leaf
//! entry holds what its test reads: its tight box in object space (`v0`, `v1`), its corner
//! (`v2`, as floats), the word of its corner values (`_pad0`) and its grid's record
//! (`_pad1`); words are vec4 indices into the binding. A scene without SDF grids builds
//! exactly `Bvh::build_with(scene, GPU_COSTS)` and no words.

use super::gpu_layout::{GpuLeafPrim, GPU_COSTS, LEAF_PRIM_WORDS};
use super::{Bvh, SDF_BIT, SPHERE_BIT};
use crate::scene::sdf_grid::SdfData;
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Affine3A;
use std::collections::HashMap;

/// Twin of WGSL `SdfGridRecord`: a placed grid. Maps as rows (`xyz` the linear part's row,
/// `w` the translation's), as `InstanceRecord`'s.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuSdfGrid {
    /// World to object (the grid's unit cube).
    pub to_object: [[f32; 4]; 3],
    /// Object to world.
    pub to_world: [[f32; 4]; 3],
    /// Vertices per axis.
    pub res: [u32; 3],
    /// Its material (`Scene::materials`).
    pub material: u32,
    /// The flat word (f32 index into the binding) of its first vertex value.
    pub values: u32,
    /// 1: smooth shading normals (Mitsuba's `normals` `smooth`); 0: analytic.
    pub smooth_normals: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// 16-byte words per [`GpuSdfGrid`].
pub const SDF_GRID_WORDS: u32 = (std::mem::size_of::<GpuSdfGrid>() / 16) as u32;
const _: () = assert!(std::mem::size_of::<GpuSdfGrid>().is_multiple_of(16));

/// The rows of `a` (`xyz` the linear part's row, `w` the translation's), as the GPU's records
/// hold maps (also `super::gpu_instances`').
pub fn rows(a: &Affine3A) -> [[f32; 4]; 3] {
    let m = a.matrix3;
    std::array::from_fn(|r| [m.x_axis[r], m.y_axis[r], m.z_axis[r], a.translation[r]])
}

/// The world boxes of every grid's occupied cells with their ids (`SPHERE_BIT | SDF_BIT | k`).
fn cell_boxes(scene: &Scene) -> Vec<(crate::math::geometry::Aabb, u32)> {
    let cells = scene
        .sdf_grids
        .iter()
        .flat_map(|g| (0..g.data.cells.len()).map(move |c| (g, c)));
    (cells.zip(0u32..))
        .map(|((g, c), k)| (g.cell_world_box(c), SPHERE_BIT | SDF_BIT | k))
        .collect()
}

/// The hierarchy the GPU walks over `scene`'s own primitives: its triangles, spheres and SDF
/// grid cells (the GPU's costs).
pub fn world_bvh(scene: &Scene) -> Bvh {
    let cells = cell_boxes(scene);
    Bvh::build_over(scene, cells.iter().copied(), cells.len(), GPU_COSTS)
}

/// The SDF grids' words and their cells' leaf entries.
#[derive(Clone, Debug, Default)]
pub struct SdfWords {
    /// The words that follow the leaf entries.
    pub words: Vec<[u32; 4]>,
    /// Each cell's leaf entry, by `k` (its id left 0).
    pub cells: Vec<GpuLeafPrim>,
}

impl SdfWords {
    /// The words of `scene`'s grids to start at vec4 word `first` of the binding; `None` when
    /// a word index would not fit 30 bits (a binding that large cannot exist).
    pub fn pack(scene: &Scene, first: u64) -> Option<Self> {
        let grids = &scene.sdf_grids;
        let mut out = SdfWords::default();
        // Per distinct grid data: the flat word of its values and the vec4 word of its cells'.
        let mut placed: HashMap<*const SdfData, (u64, u64)> = HashMap::new();
        let mut flat: Vec<f32> = Vec::new();
        let data_at = first + grids.len() as u64 * SDF_GRID_WORDS as u64;
        let mut records = Vec::with_capacity(grids.len());
        for (g, gi) in grids.iter().zip(0u64..) {
            let key = std::sync::Arc::as_ptr(&g.data);
            let (values, corners) = *placed.entry(key).or_insert_with(|| {
                let values = 4 * data_at + flat.len() as u64;
                flat.extend_from_slice(&g.data.grid.data);
                flat.resize(flat.len().div_ceil(4) * 4, 0.0);
                let corners = data_at + flat.len() as u64 / 4;
                for c in &g.data.cells {
                    flat.extend_from_slice(&g.data.corners(c.corner));
                }
                (values, corners)
            });
            let record = first + gi * SDF_GRID_WORDS as u64;
            records.push(GpuSdfGrid {
                to_object: rows(&g.to_object),
                to_world: rows(&g.to_world),
                res: g.data.grid.res,
                material: g.material,
                values: u32::try_from(values).ok()?,
                smooth_normals: g.smooth as u32,
                ..GpuSdfGrid::default()
            });
            for (c, ci) in g.data.cells.iter().zip(0u64..) {
                out.cells.push(GpuLeafPrim {
                    v0: c.bounds.min.to_array(),
                    id: 0,
                    v1: c.bounds.max.to_array(),
                    _pad0: u32::try_from(corners + 2 * ci).ok()?,
                    v2: c.corner.as_vec3().to_array(),
                    _pad1: u32::try_from(record).ok()?,
                });
            }
        }
        if 4 * data_at + flat.len() as u64 >= 1 << 32 || data_at >= 1 << 30 {
            return None;
        }
        out.words = bytemuck::cast_slice(&records).to_vec();
        out.words.extend(
            flat.chunks_exact(4)
                .map(|c| [0, 1, 2, 3].map(|i| c[i].to_bits())),
        );
        Some(out)
    }

    /// Fills in the entry of each SDF cell of `prims` (every level's leaf entries, whose
    /// cells are `scene`'s) and returns the words to follow them; `None` as [`Self::pack`].
    pub fn fill(scene: &Scene, prims: &mut [GpuLeafPrim]) -> Option<Vec<[u32; 4]>> {
        if scene.sdf_grids.is_empty() {
            return Some(Vec::new());
        }
        let sdf = Self::pack(scene, prims.len() as u64 * LEAF_PRIM_WORDS as u64)?;
        let both = SPHERE_BIT | SDF_BIT;
        for p in prims.iter_mut().filter(|p| p.id & both == both) {
            *p = GpuLeafPrim {
                id: p.id,
                ..sdf.cells[(p.id & !both) as usize]
            };
        }
        Some(sdf.words)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::grid::VolumeGrid;
    use crate::scene::sdf_grid::SdfGrid;
    use glam::{Affine3A, Vec3};
    use std::sync::Arc;

    /// Two placements of one 3 x 3 x 3 plane field and one of a 2 x 2 x 2 one: the values are
    /// stored once per field, each cell's entry names its grid's record and its corner values
    /// (`SdfData::corners`, read back from the words), and the world hierarchy lists every
    /// cell once beside the scene's triangles.
    #[test]
    fn cells_name_their_records_and_values() {
        let field = |res: u32, z0: f32| {
            let n = (res * res * res) as usize;
            let data = (0..n)
                .map(|i| (i / (res * res) as usize) as f32 / (res - 1) as f32 - z0)
                .collect();
            let grid = VolumeGrid {
                res: [res; 3],
                channels: 1,
                bbox: [Vec3::ZERO, Vec3::ONE],
                data,
            };
            Arc::new(SdfData::new(grid).unwrap())
        };
        let (a, b) = (field(3, 0.3), field(2, 0.6));
        let mut scene = Scene::empty();
        let shift = Affine3A::from_translation(Vec3::X * 2.0);
        scene.sdf_grids = vec![
            SdfGrid::new(a.clone(), Affine3A::IDENTITY, 0, true),
            SdfGrid::new(b.clone(), Affine3A::IDENTITY, 1, false),
            SdfGrid::new(a.clone(), shift, 2, true),
        ];
        let first = 5u64;
        let sdf = SdfWords::pack(&scene, first).unwrap();
        let flat: Vec<u32> = sdf.words.iter().flatten().copied().collect();
        let word = |i: u64| f32::from_bits(flat[(i - 4 * first) as usize]);
        let records: &[GpuSdfGrid] =
            bytemuck::cast_slice(&sdf.words[..3 * SDF_GRID_WORDS as usize]);
        assert_eq!(
            records[0].values, records[2].values,
            "shared values stored once"
        );
        assert_ne!(records[0].values, records[1].values);
        assert_eq!((records[1].material, records[1].smooth_normals), (1, 0));
        assert_eq!(records[2].to_world[0][3], 2.0);
        let n_cells = 2 * a.cells.len() + b.cells.len();
        assert_eq!(sdf.cells.len(), n_cells);
        let mut k = 0;
        for (g, grid) in scene.sdf_grids.iter().enumerate() {
            let record = first + g as u64 * SDF_GRID_WORDS as u64;
            for cell in &grid.data.cells {
                let e = sdf.cells[k];
                assert_eq!(e._pad1 as u64, record, "cell {k}");
                assert_eq!(e.v2, cell.corner.as_vec3().to_array());
                assert_eq!(
                    [e.v0, e.v1],
                    [cell.bounds.min, cell.bounds.max].map(|v| v.to_array())
                );
                let corners: [f32; 8] =
                    std::array::from_fn(|i| word(4 * e._pad0 as u64 + i as u64));
                assert_eq!(corners, grid.data.corners(cell.corner), "cell {k}");
                let v = records[g].values as u64;
                assert_eq!(word(v + 5), grid.data.grid.data[5]);
                k += 1;
            }
        }
        let bvh = world_bvh(&scene);
        let mut ids = bvh.prim_ids.clone();
        ids.sort_unstable();
        let want: Vec<u32> = (0..n_cells as u32)
            .map(|k| SPHERE_BIT | SDF_BIT | k)
            .collect();
        assert_eq!(ids, want);
    }
}
