//! Collapsing a binary hierarchy into the 8-wide one: each wide node takes a binary node's
//! two children and keeps opening the largest (by surface area) until it has eight; a
//! subtree of at most [`LEAF_PRIMS`] primitives becomes one leaf (its triangles one block).

use super::wide_layout::{leaf_blocks, Node8, TriBlock, WideBvh};
use super::wide_layout::{BLOCK, LEAF_BIT, LEAF_COUNT_SHIFT, MAX_LEAF_BLOCKS, NO_PRIM, WIDTH};
use super::{Bvh, BvhNode, SPHERE_BIT};
use crate::math::geometry::Aabb;
use crate::scene::Scene;
use glam::Vec3;

/// A subtree of at most this many primitives becomes one leaf.
pub const LEAF_PRIMS: u32 = BLOCK as u32;

struct Collapse<'a> {
    bin: &'a Bvh,
    scene: &'a Scene,
    /// Primitives under each binary node.
    count: Vec<u32>,
    /// Each block's primitives: (first index into `bin.prim_ids`, how many).
    sources: Vec<(u32, u32)>,
    out: WideBvh,
}

/// The wide hierarchy of binary hierarchy `bin` over `scene`.
pub fn collapse(bin: &Bvh, scene: &Scene) -> WideBvh {
    let n = bin.nodes.len();
    let mut count = vec![0u32; n];
    // Children follow their parent in depth-first order: fill counts from the back.
    for i in (0..n).rev() {
        let node = &bin.nodes[i];
        count[i] = if node.count > 0 || n == 1 {
            node.count
        } else {
            count[i + 1] + count[node.left_first as usize]
        };
    }
    let mut c = Collapse {
        bin,
        scene,
        count,
        sources: Vec::with_capacity(n / 2 + 1),
        out: WideBvh {
            nodes: Vec::with_capacity(n / 4 + 1),
            blocks: Vec::new(),
            alpha: bin.alpha,
            isa: super::isa::Isa::detect(),
            instances: None,
            sdf: None,
        },
    };
    c.out.nodes.push(Node8::EMPTY);
    if !bin.prim_ids.is_empty() {
        if c.becomes_leaf(0) {
            let leaf = c.leaf(0);
            set_child(&mut c.out.nodes[0], 0, node_box(&bin.nodes[0]), leaf);
        } else {
            c.interior(0, 0);
        }
    }
    // The blocks' contents, in parallel (their triangles are read in tree order, not
    // the scene's: mostly cache misses).
    use rayon::prelude::*;
    let (ids, scene) = (&bin.prim_ids, scene);
    c.out.blocks = (c.sources.par_iter())
        .map(|&(first, n)| block(scene, &ids[first as usize..(first + n) as usize]))
        .collect();
    c.out
}

/// The block of primitives `ids` of `scene`.
fn block(scene: &Scene, ids: &[u32]) -> TriBlock {
    let mut block = TriBlock {
        id: [NO_PRIM; BLOCK],
        ..TriBlock::default()
    };
    for (lane, &id) in ids.iter().enumerate() {
        block.id[lane] = id;
        if id & SPHERE_BIT != 0 {
            continue;
        }
        let t = &scene.triangles[id as usize];
        let n = t.e1().cross(t.e2());
        for axis in 0..3 {
            block.v0[axis][lane] = t.v0[axis];
            block.v1[axis][lane] = t.v1[axis];
            block.v2[axis][lane] = t.v2[axis];
            block.n[axis][lane] = n[axis];
        }
    }
    block
}

fn node_box(n: &BvhNode) -> Aabb {
    Aabb {
        min: Vec3::from(n.bmin),
        max: Vec3::from(n.bmax),
    }
}

fn set_child(node: &mut Node8, slot: usize, b: Aabb, child: u32) {
    for axis in 0..3 {
        node.bounds[axis][slot] = b.min[axis];
        node.bounds[3 + axis][slot] = b.max[axis];
    }
    node.child[slot] = child;
}

impl Collapse<'_> {
    fn is_binary_leaf(&self, i: usize) -> bool {
        self.bin.nodes[i].count > 0 || self.bin.nodes.len() == 1
    }

    fn becomes_leaf(&self, i: usize) -> bool {
        self.is_binary_leaf(i) || self.count[i] <= LEAF_PRIMS
    }

    /// Fills wide node `at` with the children of binary interior node `i`.
    fn interior(&mut self, i: usize, at: usize) {
        let kids = |j: usize| [j + 1, self.bin.nodes[j].left_first as usize];
        let mut open: Vec<usize> = kids(i).to_vec();
        while open.len() < WIDTH {
            // Open the largest child that is not to become a leaf.
            let best = (open.iter().enumerate())
                .filter(|(_, &j)| !self.becomes_leaf(j))
                .max_by(|a, b| {
                    let area = |j: usize| node_box(&self.bin.nodes[j]).half_area();
                    area(*a.1).total_cmp(&area(*b.1))
                })
                .map(|(k, _)| k);
            let Some(k) = best else { break };
            let j = open.swap_remove(k);
            open.extend(kids(j));
        }
        for (slot, &j) in open.iter().enumerate() {
            let b = node_box(&self.bin.nodes[j]);
            let child = if self.becomes_leaf(j) {
                self.leaf(j)
            } else {
                let idx = self.out.nodes.len();
                self.out.nodes.push(Node8::EMPTY);
                self.interior(j, idx);
                idx as u32
            };
            set_child(&mut self.out.nodes[at], slot, b, child);
        }
    }

    /// A leaf holding every primitive under binary node `i`; returns its child reference.
    fn leaf(&mut self, i: usize) -> u32 {
        // A subtree's primitives are contiguous in `prim_ids`, starting at its leftmost leaf.
        let mut first = i;
        while !self.is_binary_leaf(first) {
            first += 1;
        }
        let start = self.bin.nodes[first].left_first as usize;
        let ids = &self.bin.prim_ids[start..start + self.count[i] as usize];
        let max = MAX_LEAF_BLOCKS * BLOCK;
        if ids.len() <= max {
            return self.blocks(start, ids.len());
        }
        // Larger than a leaf can be: a node of leaves (by index) instead.
        assert!(
            ids.len() <= WIDTH * max,
            "a leaf of {} primitives",
            ids.len()
        );
        let at = self.out.nodes.len();
        self.out.nodes.push(Node8::EMPTY);
        for (slot, chunk) in ids.chunks(max).enumerate() {
            let b = (chunk.iter())
                .map(|&id| prim_box(self.scene, id))
                .fold(Aabb::EMPTY, Aabb::union);
            let child = self.blocks(start + slot * max, chunk.len());
            set_child(&mut self.out.nodes[at], slot, b, child);
        }
        at as u32
    }

    /// Blocks for the `n` primitives at `start` in `prim_ids` (at most `MAX_LEAF_BLOCKS`
    /// blocks' worth; filled at the end); returns the leaf reference.
    fn blocks(&mut self, start: usize, n: usize) -> u32 {
        let first = self.sources.len();
        for s in (start..start + n).step_by(BLOCK) {
            self.sources
                .push((s as u32, (start + n - s).min(BLOCK) as u32));
        }
        let count = (self.sources.len() - first) as u32;
        let r = LEAF_BIT | ((count - 1) << LEAF_COUNT_SHIFT) | first as u32;
        debug_assert_eq!(leaf_blocks(r), (first, count as usize));
        r
    }
}

/// The bounds of primitive `id` of `scene`.
fn prim_box(scene: &Scene, id: u32) -> Aabb {
    match id & SPHERE_BIT {
        0 => Aabb::of_triangle(&scene.triangles[id as usize]),
        _ => Aabb::of_sphere(&scene.spheres[(id & !SPHERE_BIT) as usize]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::wide_layout::EMPTY;
    use crate::scene::Triangle;

    #[test]
    fn every_primitive_lands_in_exactly_one_leaf_and_every_child_box_holds_its_subtree() {
        let mut scene = Scene::empty();
        let mut s = 1u32;
        let mut r = || {
            s = crate::math::rng::pcg_hash(s);
            crate::math::rng::to_unit(s) * 10.0
        };
        for _ in 0..1000 {
            let a = Vec3::new(r(), r(), r());
            let b = a + Vec3::new(r(), r(), r()) * 0.1;
            let c = a + Vec3::new(r(), r(), r()) * 0.1;
            scene.triangles.push(Triangle::new(a, b, c, 0));
        }
        let w = crate::bvh::WideBvh::build(&scene);
        let mut seen = vec![0; 1000];
        fn walk(w: &WideBvh, scene: &Scene, node: usize, b: Option<Aabb>, seen: &mut [u32]) {
            let n = &w.nodes[node];
            for slot in 0..WIDTH {
                let c = n.child[slot];
                if c == EMPTY {
                    continue;
                }
                let cb = Aabb {
                    min: Vec3::new(n.bounds[0][slot], n.bounds[1][slot], n.bounds[2][slot]),
                    max: Vec3::new(n.bounds[3][slot], n.bounds[4][slot], n.bounds[5][slot]),
                };
                if let Some(b) = b {
                    assert_eq!(b.union(cb), b, "a child's box inside its parent's");
                }
                if c & LEAF_BIT != 0 {
                    let (first, count) = leaf_blocks(c);
                    for blk in &w.blocks[first..first + count] {
                        for &id in blk.id.iter().filter(|&&id| id != NO_PRIM) {
                            seen[id as usize] += 1;
                            let tb = Aabb::of_triangle(&scene.triangles[id as usize]);
                            assert_eq!(cb.union(tb), cb, "a triangle inside its leaf's box");
                        }
                    }
                } else {
                    walk(w, scene, c as usize, Some(cb), seen);
                }
            }
        }
        walk(&w, &scene, 0, None, &mut seen);
        assert!(seen.iter().all(|&k| k == 1), "each triangle once");
        assert!(w.nodes.len() < 1000 / 8, "wide nodes: {}", w.nodes.len());
    }
}
