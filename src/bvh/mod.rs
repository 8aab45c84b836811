//! A binned-SAH bounding volume hierarchy over the scene's triangles and spheres, built once
//! on the CPU and flattened depth-first so both backends traverse the same nodes.
//!
//! Layout: the left child of interior node `i` is `i + 1`, the right child is `left_first`;
//! a leaf (`count > 0`) holds `prim_ids[left_first .. left_first + count]`. A primitive id
//! below [`SPHERE_BIT`] is a triangle index; with the bit set, the rest is a sphere index.
//! The GPU walks a copy laid out for its traversal (src/bvh/gpu_layout.rs,
//! `src/bvh/intersect.wgsl`).

pub mod gpu_instances;
pub mod gpu_layout;
pub mod gpu_sdf;
pub mod gpu_wide;

use crate::math::geometry::{intersect_sphere, intersect_triangle, Aabb, Ray, Shear};
use crate::scene::Scene;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

mod build_binned;
mod build_wide;
pub mod hit;
pub mod instances;
mod isa;
pub mod sdf;
// std::arch intrinsics and the run-time choice between them.
#[allow(unsafe_code)]
mod simd;
mod surface;
pub mod wide;
mod wide_layout;
pub use hit::Hit;
pub use isa::Isa;
pub use surface::{alpha_passes, alpha_test, uv_tangent};
pub use wide::WideBvh;

/// The hierarchy the CPU backend traces: the 8-wide one.
pub type CpuBvh = WideBvh;

/// Marks a sphere in a leaf's primitive list.
pub const SPHERE_BIT: u32 = 0x8000_0000;
/// With [`SPHERE_BIT`], marks an SDF grid's occupied cell in the GPU's hierarchy
/// ([`gpu_sdf`]); the CPU walks the cells in a tree of their own ([`sdf`]).
pub const SDF_BIT: u32 = 0x4000_0000;
/// Maximum primitives in a leaf of the CPU's hierarchy.
pub const MAX_LEAF: usize = 2;
/// Depth bound of the tree, and so the traversal stack size on both backends.
pub const MAX_DEPTH: usize = 64;
/// Depth up to which splits follow the SAH.
const SAH_DEPTH: usize = 24;
const BINS: usize = 12;

/// One flattened node (32 bytes); the GPU reads it in src/bvh/gpu_layout.rs's layout.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Lower corner of the node's bounds.
    pub bmin: [f32; 3],
    /// Right child (interior) or first entry of `prim_ids` (leaf).
    pub left_first: u32,
    /// Upper corner of the node's bounds.
    pub bmax: [f32; 3],
    /// Number of primitives; 0 for an interior node.
    pub count: u32,
}

/// What a hierarchy's SAH weighs: the cost of one node step relative to one primitive test,
/// and the largest leaf (twice that where no split is cheaper).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildCosts {
    /// Cost of a node step, in primitive tests.
    pub node_step: f32,
    /// Leaves hold at most this many primitives unless no split is cheaper.
    pub max_leaf: usize,
}

impl BuildCosts {
    /// The CPU's walk: a node step costs about what a primitive test does.
    pub const CPU: BuildCosts = BuildCosts {
        node_step: 1.0,
        max_leaf: MAX_LEAF,
    };
}

/// The flattened hierarchy.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Nodes in depth-first order; node 0 is the root.
    pub nodes: Vec<BvhNode>,
    /// Primitive indices referenced by the leaves (triangles first, then spheres).
    pub prim_ids: Vec<u32>,
    /// Whether some material is alpha-tested ([`crate::scene::Alpha`]): hits are then
    /// checked against its opacity.
    pub alpha: bool,
}

struct Item {
    bounds: Aabb,
    centroid: Vec3,
    id: u32,
}

impl Bvh {
    /// Builds the hierarchy over every triangle and sphere of `scene` (the CPU's costs).
    pub fn build(scene: &Scene) -> Self {
        Self::build_with(scene, BuildCosts::CPU)
    }

    /// Builds the hierarchy over every triangle and sphere of `scene` for a walk of `costs`.
    pub fn build_with(scene: &Scene, costs: BuildCosts) -> Self {
        Self::build_over(scene, std::iter::empty(), 0, costs)
    }

    /// Builds the hierarchy over every triangle and sphere of `scene` and the `n` `more`
    /// boxes (with their ids) for a walk of `costs`.
    pub fn build_over(
        scene: &Scene,
        more: impl Iterator<Item = (Aabb, u32)>,
        n: usize,
        costs: BuildCosts,
    ) -> Self {
        let tris = (scene.triangles.iter().map(Aabb::of_triangle)).zip(0u32..);
        let balls =
            (scene.spheres.iter().map(Aabb::of_sphere)).zip((0u32..).map(|i| i | SPHERE_BIT));
        let n = scene.triangles.len() + scene.spheres.len() + n;
        let mut bvh = Self::over_boxes(tris.chain(balls).chain(more), n, costs);
        bvh.alpha = scene.materials.iter().any(|m| m.alpha.is_some());
        bvh
    }

    /// Builds the hierarchy over `boxes` (each with the id its leaves list; `n` of them)
    /// for a walk of `costs`: the instances' top level uses it with instance indices.
    pub fn over_boxes(
        boxes: impl Iterator<Item = (Aabb, u32)>,
        n: usize,
        costs: BuildCosts,
    ) -> Self {
        let mut items: Vec<Item> = Vec::with_capacity(n);
        for (b, id) in boxes {
            items.push(Item {
                bounds: b,
                centroid: b.centroid(),
                id,
            });
        }
        let mut bvh = Bvh::default();
        if items.is_empty() {
            // One empty leaf whose box no ray enters.
            bvh.nodes.push(BvhNode {
                bmin: [1.0; 3],
                bmax: [-1.0; 3],
                left_first: 0,
                count: 0,
            });
            return bvh;
        }
        bvh.nodes.reserve(2 * items.len());
        bvh.build_node(&mut items, 0, 1, costs);
        bvh.prim_ids = items.iter().map(|it| it.id).collect();
        bvh
    }

    /// Builds the subtree over `items` (which start at `offset` in the final order) and
    /// returns its node index.
    fn build_node(
        &mut self,
        items: &mut [Item],
        offset: usize,
        depth: usize,
        costs: BuildCosts,
    ) -> usize {
        let idx = self.nodes.len();
        let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
        self.nodes.push(BvhNode {
            bmin: bounds.min.to_array(),
            bmax: bounds.max.to_array(),
            left_first: offset as u32,
            count: items.len() as u32,
        });
        if items.len() <= costs.max_leaf {
            return idx;
        }
        // Past SAH_DEPTH only balanced median splits: the depth stays below
        // SAH_DEPTH + log2(N), within MAX_DEPTH for any N < 2^38.
        let sah = if depth < SAH_DEPTH {
            sah_split(items, bounds.half_area(), costs)
        } else {
            None
        };
        let mid = match sah {
            Some(m) => m,
            // No split beats a leaf; split at the median anyway when the leaf would be large.
            None if items.len() <= 2 * costs.max_leaf && depth < SAH_DEPTH => return idx,
            None => median_split(items),
        };
        let (left, right) = items.split_at_mut(mid);
        self.build_node(left, offset, depth + 1, costs);
        let r = self.build_node(right, offset + mid, depth + 1, costs);
        self.nodes[idx].left_first = r as u32;
        self.nodes[idx].count = 0;
        idx
    }

    /// Nearest hit along `ray` before `t_max`.
    pub fn intersect(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (id, t, u, v) = self.closest(scene, ray, t_max)?;
        Some(surface::hit_at(scene, ray, id, t, u, v))
    }

    /// The nearest hit along `ray` before `t_max` as (primitive id, `t`, barycentric `u`,
    /// `v`), without assembling the surface.
    pub fn closest(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<wide::Closest> {
        let mut best_t = t_max;
        let mut best: Option<(u32, f32, f32)> = None; // (prim id, u, v)
        let shear = Shear::new(ray.dir);
        self.walk(
            ray,
            |id, t_limit| {
                if id & SPHERE_BIT == 0 {
                    if let Some((t, u, v)) =
                        intersect_triangle(&scene.triangles[id as usize], ray, &shear, t_limit)
                    {
                        if self.alpha && alpha_passes(scene, id, ray, t, u, v) {
                            return None;
                        }
                        best_t = t;
                        best = Some((id, u, v));
                        return Some(t);
                    }
                } else if let Some(t) =
                    intersect_sphere(&scene.spheres[(id & !SPHERE_BIT) as usize], ray, t_limit)
                {
                    if self.alpha && alpha_passes(scene, id, ray, t, 0.0, 0.0) {
                        return None;
                    }
                    best_t = t;
                    best = Some((id, 0.0, 0.0));
                    return Some(t);
                }
                None
            },
            t_max,
        );
        let (id, u, v) = best?;
        Some((id, best_t, u, v))
    }

    /// Whether anything blocks `ray` before `t_max`.
    pub fn occluded(&self, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        let shear = Shear::new(ray.dir);
        self.walk(
            ray,
            |id, t_limit| {
                let h = if id & SPHERE_BIT == 0 {
                    intersect_triangle(&scene.triangles[id as usize], ray, &shear, t_limit)
                        .is_some_and(|(t, u, v)| {
                            !(self.alpha && alpha_passes(scene, id, ray, t, u, v))
                        })
                } else {
                    intersect_sphere(&scene.spheres[(id & !SPHERE_BIT) as usize], ray, t_limit)
                        .is_some_and(|t| !(self.alpha && alpha_passes(scene, id, ray, t, 0.0, 0.0)))
                };
                if h {
                    hit = true;
                    return Some(-1.0); // negative: stop the walk
                }
                None
            },
            t_max,
        );
        hit
    }

    /// Visits the primitives in leaves the ray enters, front to back. `visit(id, t_max)`
    /// returns a new `t_max` on a hit (negative stops the walk).
    #[inline]
    fn walk(&self, ray: &Ray, mut visit: impl FnMut(u32, f32) -> Option<f32>, t_max: f32) {
        // A scene without primitives has one placeholder node and nothing to hit (an inverted
        // box still passes the slab test, so it must not be walked).
        if self.prim_ids.is_empty() {
            return;
        }
        let inv = ray.dir.recip();
        let mut t_max = t_max;
        let mut stack = [0u32; MAX_DEPTH + 2];
        let mut sp = 1usize;
        stack[0] = 0;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            let b = Aabb {
                min: Vec3::from(node.bmin),
                max: Vec3::from(node.bmax),
            };
            if !b.hit(ray.origin, inv, t_max) {
                continue;
            }
            if node.count > 0 {
                let first = node.left_first as usize;
                for &id in &self.prim_ids[first..first + node.count as usize] {
                    if let Some(t) = visit(id, t_max) {
                        if t < 0.0 {
                            return;
                        }
                        t_max = t;
                    }
                }
            } else {
                // Visit the nearer child first: push the farther one.
                let left = stack[sp] + 1;
                let right = node.left_first;
                let axis = if ray.dir.x.abs() > ray.dir.y.abs() && ray.dir.x.abs() > ray.dir.z.abs()
                {
                    0
                } else if ray.dir.y.abs() > ray.dir.z.abs() {
                    1
                } else {
                    2
                };
                let (near, far) = if ray.dir[axis] >= 0.0 {
                    (left, right)
                } else {
                    (right, left)
                };
                if sp + 2 <= stack.len() {
                    stack[sp] = far;
                    stack[sp + 1] = near;
                    sp += 2;
                }
            }
        }
    }

    /// Depth of the tree (the root alone is 1).
    pub fn depth(&self) -> usize {
        fn go(nodes: &[BvhNode], i: usize) -> usize {
            let n = &nodes[i];
            if n.count > 0 || nodes.len() == 1 {
                1
            } else {
                1 + go(nodes, i + 1).max(go(nodes, n.left_first as usize))
            }
        }
        go(&self.nodes, 0)
    }
}

/// Binned SAH: the split position in `items` (reordered) or `None` when a leaf is cheaper.
fn sah_split(items: &mut [Item], parent_half_area: f32, costs: BuildCosts) -> Option<usize> {
    let cb = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let extent = cb.max - cb.min;
    let mut best: Option<(f32, usize, f32)> = None; // (cost, axis, split value)
    for axis in 0..3 {
        if extent[axis] <= 0.0 || !extent[axis].is_finite() {
            continue;
        }
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - cb.min[axis]) * scale) as usize).min(BINS - 1);
        for it in items.iter() {
            let b = &mut bins[bin_of(it.centroid)];
            b.0 = b.0.union(it.bounds);
            b.1 += 1;
        }
        // Sweep from the right to get suffix areas and counts.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for i in (1..BINS).rev() {
            acc = acc.union(bins[i].0);
            cnt += bins[i].1;
            right_area[i] = acc.half_area();
            right_count[i] = cnt;
        }
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for i in 0..BINS - 1 {
            acc = acc.union(bins[i].0);
            cnt += bins[i].1;
            if cnt == 0 || right_count[i + 1] == 0 {
                continue;
            }
            let cost = cnt as f32 * acc.half_area() + right_count[i + 1] as f32 * right_area[i + 1];
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, cb.min[axis] + (i + 1) as f32 / scale));
            }
        }
    }
    let (cost, axis, split) = best?;
    // Leaf cost = N intersections; interior = a node step + weighted children.
    let leaf_cost = items.len() as f32;
    if parent_half_area > 0.0
        && costs.node_step + cost / parent_half_area >= leaf_cost
        && items.len() <= costs.max_leaf * 2
    {
        return None;
    }
    let mut mid = partition(items, |it| it.centroid[axis] < split);
    if mid == 0 || mid == items.len() {
        mid = median_split(items);
    }
    Some(mid)
}

fn median_split(items: &mut [Item]) -> usize {
    let cb = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let axis = (cb.max - cb.min).max_position();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    mid
}

fn partition(items: &mut [Item], pred: impl Fn(&Item) -> bool) -> usize {
    let mut i = 0;
    for j in 0..items.len() {
        if pred(&items[j]) {
            items.swap(i, j);
            i += 1;
        }
    }
    i
}
