//! The CPU's hierarchy over a scene's SDF grids (`crate::scene::sdf_grid`): one binary SAH
//! tree ([`Bvh::over_boxes`]) over the world boxes of every grid's occupied cells, each
//! leaf entry a (grid, cell) pair, walked after the triangles and spheres with what is left
//! of the ray. Scenes without SDF grids build none of it (`WideBvh::sdf` is `None`).

use super::{BuildCosts, Bvh, Hit};
use crate::math::geometry::Ray;
use crate::scene::{Scene, NO_LIGHT};
use glam::{Vec2, Vec3};

/// The cells of every SDF grid of a scene under one hierarchy.
#[derive(Clone, Debug)]
pub struct SdfBvh {
    /// Over the cells' world boxes; leaves list indices into `cells`.
    tree: Bvh,
    /// (grid, cell) of each entry.
    cells: Vec<(u32, u32)>,
}

impl SdfBvh {
    /// The hierarchy of `scene`'s SDF grids; `None` when it has none.
    pub fn build(scene: &Scene) -> Option<Self> {
        if scene.sdf_grids.is_empty() {
            return None;
        }
        let cells: Vec<(u32, u32)> = (scene.sdf_grids.iter().zip(0u32..))
            .flat_map(|(g, gi)| (0..g.data.cells.len() as u32).map(move |c| (gi, c)))
            .collect();
        let boxes = cells
            .iter()
            .zip(0u32..)
            .map(|(&(g, c), i)| (scene.sdf_grids[g as usize].cell_world_box(c as usize), i));
        let tree = Bvh::over_boxes(boxes, cells.len(), BuildCosts::CPU);
        Some(SdfBvh { tree, cells })
    }

    /// Bytes the hierarchy takes.
    pub fn memory_bytes(&self) -> usize {
        self.tree.nodes.len() * std::mem::size_of::<super::BvhNode>()
            + self.tree.prim_ids.len() * 4
            + self.cells.len() * 8
    }

    /// The hit of `ray` on entry `i`'s cell before `t_lim` (the walk takes a hit at its
    /// limit as a new, equal limit): (grid, distance).
    fn hit_cell(&self, scene: &Scene, i: u32, ray: &Ray, t_lim: f32) -> Option<(u32, f32)> {
        let (g, c) = self.cells[i as usize];
        let grid = &scene.sdf_grids[g as usize];
        let t = grid.intersect_cell(c as usize, ray.origin, ray.dir, t_lim)?;
        (t < t_lim).then_some((g, t))
    }

    /// The nearest hit along `ray` before `t_max`: (grid, distance).
    fn closest(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
        let mut best = None;
        self.tree.walk(
            ray,
            |i, t_lim| {
                let (g, t) = self.hit_cell(scene, i, ray, t_lim)?;
                best = Some((g, t));
                Some(t)
            },
            t_max,
        );
        best
    }

    /// Nearest hit along `ray` before `t_max`.
    pub fn intersect(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (g, t) = self.closest(scene, ray, t_max)?;
        let grid = &scene.sdf_grids[g as usize];
        let (position, normal, shading) = grid.surface_at(ray.origin + t * ray.dir);
        Some(Hit {
            t,
            position,
            normal,
            shading,
            material: grid.material,
            light: NO_LIGHT,
            uv: Vec2::ZERO,
            // No dp/du (Mitsuba's sdfgrid has no parameterisation): the BSDF frame takes
            // the shading normal's basis.
            tangent: Vec3::ZERO,
        })
    }

    /// Whether some grid blocks `ray` before `t_max`.
    pub fn occluded(&self, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        self.tree.walk(
            ray,
            |i, t_lim| {
                self.hit_cell(scene, i, ray, t_lim)?;
                hit = true;
                Some(-1.0)
            },
            t_max,
        );
        hit
    }
}
