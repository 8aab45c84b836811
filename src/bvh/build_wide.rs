//! Collapsing a binary hierarchy into the 8-wide one: each wide node takes a binary node's
//! two children and keeps opening the largest (by surface area) until it has eight; a
//! subtree of at most [`LEAF_PRIMS`] primitives becomes one leaf (its triangles one block).

use super::wide::{Leaf, Node8, TriBlock, WideBvh, BLOCK, LEAF_BIT, WIDTH};
use super::{BuildCosts, Bvh, BvhNode, SPHERE_BIT};
use crate::math::geometry::Aabb;
use crate::scene::Scene;
use glam::Vec3;

/// The binary tree's costs for the wide walk (leaves as the CPU's; small subtrees are merged
/// into leaf blocks here).
pub const WIDE_COSTS: BuildCosts = BuildCosts::CPU;
/// A subtree of at most this many primitives becomes one leaf.
pub const LEAF_PRIMS: u32 = BLOCK as u32;

struct Collapse<'a> {
    bin: &'a Bvh,
    scene: &'a Scene,
    /// Primitives under each binary node.
    count: Vec<u32>,
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
        out: WideBvh {
            nodes: Vec::with_capacity(n / 4 + 1),
            leaves: Vec::with_capacity(n / 2 + 1),
            blocks: Vec::with_capacity(n / 2 + 1),
            spheres: Vec::new(),
            alpha: bin.alpha,
            isa: super::simd::Isa::detect(),
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
    c.out
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
        let leaf = Leaf {
            first_block: self.out.blocks.len() as u32,
            blocks: 0,
            first_sphere: self.out.spheres.len() as u32,
            spheres: 0,
        };
        let mut block = empty_block();
        let mut lane = 0;
        for &id in ids {
            if id & SPHERE_BIT != 0 {
                self.out.spheres.push(id & !SPHERE_BIT);
                continue;
            }
            let t = &self.scene.triangles[id as usize];
            let n = t.e1().cross(t.e2());
            for axis in 0..3 {
                block.v0[axis][lane] = t.v0[axis];
                block.v1[axis][lane] = t.v1[axis];
                block.v2[axis][lane] = t.v2[axis];
                block.n[axis][lane] = n[axis];
            }
            block.id[lane] = id;
            lane += 1;
            if lane == BLOCK {
                self.out.blocks.push(block);
                block = empty_block();
                lane = 0;
            }
        }
        if lane > 0 {
            self.out.blocks.push(block);
        }
        let leaf = Leaf {
            blocks: self.out.blocks.len() as u32 - leaf.first_block,
            spheres: self.out.spheres.len() as u32 - leaf.first_sphere,
            ..leaf
        };
        self.out.leaves.push(leaf);
        LEAF_BIT | (self.out.leaves.len() - 1) as u32
    }
}

fn empty_block() -> TriBlock {
    TriBlock {
        id: [u32::MAX; BLOCK],
        ..TriBlock::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::wide::EMPTY;
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
        let w = WideBvh::build(&scene);
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
                    let leaf = w.leaves[(c & !LEAF_BIT) as usize];
                    for blk in &w.blocks[leaf.first_block as usize..][..leaf.blocks as usize] {
                        for &id in blk.id.iter().filter(|&&id| id != u32::MAX) {
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
