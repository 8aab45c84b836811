//! Collapsing a binary hierarchy into the 8-wide one: each wide node takes a binary node's
//! two children and keeps opening the largest (by surface area) until it has eight; a
//! subtree of at most [`LEAF_PRIMS`] primitives becomes one leaf (its triangles one block).
//! Slots still free then take halves of the node's leaves, split by the surface-area
//! heuristic: the binary build keeps leaves of up to 16 primitives where a binary node step
//! does not pay, but a wide node's test costs the same with eight boxes as with three, and a
//! smaller leaf is entered by fewer rays.

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
    /// `bin.prim_ids`, each binary subtree's contiguous; a split leaf's reordered.
    ids: Vec<u32>,
    /// Each block's primitives: (first index into `ids`, how many).
    sources: Vec<(u32, u32)>,
    out: WideBvh,
}

/// A child of the wide node being filled: a binary node, or a run of `Collapse::ids` (part
/// of a split leaf) with its box.
#[derive(Clone, Copy)]
enum Slot {
    Node(usize),
    Run { start: usize, n: usize, b: Aabb },
}

/// Blocks for `n` primitives.
fn blocks_of(n: usize) -> usize {
    n.div_ceil(BLOCK)
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
        ids: bin.prim_ids.clone(),
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
        c.fill(vec![Slot::Node(0)], 0);
    }
    // The blocks' contents, in parallel (their triangles are read in tree order, not
    // the scene's: mostly cache misses).
    use rayon::prelude::*;
    let (ids, scene) = (&c.ids, scene);
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

    /// The run of `ids` under binary node `i`: (first, count).
    fn range(&self, i: usize) -> (usize, usize) {
        // A subtree's primitives are contiguous, starting at its leftmost leaf's.
        let mut first = i;
        while !self.is_binary_leaf(first) {
            first += 1;
        }
        (
            self.bin.nodes[first].left_first as usize,
            self.count[i] as usize,
        )
    }

    /// The two children of binary interior node `j`.
    fn kids(&self, j: usize) -> [Slot; 2] {
        [j + 1, self.bin.nodes[j].left_first as usize].map(Slot::Node)
    }

    /// The box of `slot`.
    fn slot_box(&self, slot: Slot) -> Aabb {
        match slot {
            Slot::Node(j) => node_box(&self.bin.nodes[j]),
            Slot::Run { b, .. } => b,
        }
    }

    /// The run of primitives `slot` would be a leaf of, if it is to be one.
    fn leaf_range(&self, slot: Slot) -> Option<(usize, usize)> {
        match slot {
            Slot::Node(j) => self.becomes_leaf(j).then(|| self.range(j)),
            Slot::Run { start, n, .. } => Some((start, n)),
        }
    }

    /// Fills wide node `at` with the slots `open`, opening binary nodes and then splitting
    /// leaves while it has room.
    fn fill(&mut self, mut open: Vec<Slot>, at: usize) {
        while open.len() < WIDTH {
            // Open the largest child that is not to become a leaf.
            let best = (open.iter().enumerate())
                .filter_map(|(k, &s)| match s {
                    Slot::Node(j) if !self.becomes_leaf(j) => Some((k, j)),
                    _ => None,
                })
                .max_by(|a, b| {
                    let area = |j: usize| node_box(&self.bin.nodes[j]).half_area();
                    area(a.1).total_cmp(&area(b.1))
                });
            let Some((k, j)) = best else { break };
            open.swap_remove(k);
            open.extend(self.kids(j));
        }
        let mut whole = vec![false; WIDTH];
        while open.len() < WIDTH {
            // Split the leaf of the largest expected cost (area times blocks) among those a
            // split makes cheaper.
            let best = (open.iter().enumerate())
                .filter(|&(k, _)| !whole[k])
                .filter_map(|(k, &s)| {
                    let (start, n) = self.leaf_range(s)?;
                    let fits = n > 1 && n <= MAX_LEAF_BLOCKS * BLOCK;
                    let cost = self.slot_box(s).half_area() * blocks_of(n) as f32;
                    fits.then_some((k, start, n, cost))
                })
                .max_by(|a, b| a.3.total_cmp(&b.3));
            let Some((k, start, n, cost)) = best else {
                break;
            };
            match self.split_run(start, n, cost) {
                Some([l, r]) => {
                    open.swap_remove(k);
                    whole.swap_remove(k);
                    open.extend([l, r]);
                    whole.extend([false, false]);
                }
                None => whole[k] = true,
            }
        }
        for (slot, &s) in open.iter().enumerate() {
            let b = self.slot_box(s);
            let child = match (s, self.leaf_range(s)) {
                (_, Some((start, n))) => self.leaf(start, n),
                (Slot::Node(j), None) => {
                    let idx = self.out.nodes.len();
                    self.out.nodes.push(Node8::EMPTY);
                    self.fill(self.kids(j).to_vec(), idx);
                    idx as u32
                }
                (Slot::Run { .. }, None) => unreachable!("a run is always a leaf"),
            };
            set_child(&mut self.out.nodes[at], slot, b, child);
        }
    }

    /// Splits the run of `n` primitives at `start` in two by the surface-area heuristic
    /// (a leaf's cost its box's area times its blocks, a part-filled block counted whole),
    /// ordered by centroid along the axis where the centroids spread most (one sort, not
    /// three: the build's time, see docs/bvh.md); reorders that run of `ids`. `None` where
    /// no split costs less than `cost`, the run as one leaf.
    fn split_run(&mut self, start: usize, n: usize, cost: f32) -> Option<[Slot; 2]> {
        let mut order: Vec<(f32, u32, Aabb)> = (self.ids[start..start + n].iter())
            .map(|&id| (0.0, id, prim_box(self.scene, id)))
            .collect();
        let spread = (order.iter()).fold(Aabb::EMPTY, |b, o| b.grow(o.2.centroid()));
        let axis = (spread.max - spread.min).max_position();
        for o in &mut order {
            o.0 = o.2.centroid()[axis];
        }
        // Ties by id: the same build on every run.
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut right = vec![Aabb::EMPTY; n + 1];
        for i in (0..n).rev() {
            right[i] = right[i + 1].union(order[i].2);
        }
        let mut best: Option<(f32, usize)> = None; // (cost, primitives left)
        let mut left = Aabb::EMPTY;
        for (i, o) in order.iter().enumerate().take(n - 1) {
            left = left.union(o.2);
            let k = i + 1;
            let c = left.half_area() * blocks_of(k) as f32
                + right[k].half_area() * blocks_of(n - k) as f32;
            if c < cost && best.is_none_or(|b| c < b.0) {
                best = Some((c, k));
            }
        }
        let (_, k) = best?;
        for (slot, o) in self.ids[start..start + n].iter_mut().zip(&order) {
            *slot = o.1;
        }
        let left = (order[..k].iter()).fold(Aabb::EMPTY, |b, o| b.union(o.2));
        Some([
            Slot::Run {
                start,
                n: k,
                b: left,
            },
            Slot::Run {
                start: start + k,
                n: n - k,
                b: right[k],
            },
        ])
    }

    /// A leaf holding the `n` primitives at `start` in `ids`; returns its child reference.
    fn leaf(&mut self, start: usize, n: usize) -> u32 {
        let max = MAX_LEAF_BLOCKS * BLOCK;
        if n <= max {
            return self.blocks(start, n);
        }
        // Larger than a leaf can be: a node of leaves (by index) instead.
        assert!(n <= WIDTH * max, "a leaf of {n} primitives");
        let at = self.out.nodes.len();
        self.out.nodes.push(Node8::EMPTY);
        for (slot, s) in (start..start + n).step_by(max).enumerate() {
            let m = max.min(start + n - s);
            let b = (self.ids[s..s + m].iter())
                .map(|&id| prim_box(self.scene, id))
                .fold(Aabb::EMPTY, Aabb::union);
            let child = self.blocks(s, m);
            set_child(&mut self.out.nodes[at], slot, b, child);
        }
        at as u32
    }

    /// Blocks for the `n` primitives at `start` in `ids` (at most `MAX_LEAF_BLOCKS`
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
