//! A four-wide layout of the GPU's hierarchy: the binary tree of src/bvh/gpu_layout.rs (the
//! same build, the same leaves and `leaf_prims`) collapsed into nodes of four children,
//! walked with a stack by `walk_wide` in src/bvh/gpu_wide.wgsl. The ray benchmark
//! (`gpu-photon bench --rays --backend gpu`, src/bench/gpu_rays.rs; `scripts/gpu-figures.sh`
//! on a real GPU) measures it against the binary walk. Renders keep the binary walk: on
//! lavapipe the wide one traces the rays of large scenes faster (1.1-1.5x at a million
//! triangles) but made their renders no faster (docs/bvh.md has the measurements).
//!
//! The `nodes` binding holds a [`GpuBvhFrame`] (the binary layout's grid; `nodes` the wide
//! node count), then the [`GpuWideNode`]s, the root first. A node is four 16-byte words:
//! per axis the four children's boxes on the grid (16 bits per bound, as the binary
//! layout's), then the four children's links.

use super::gpu_layout::{BoxGrid, GpuBvhFrame, FRAME_WORDS, LEAF_COUNT_SHIFT};
use super::{Bvh, BvhNode};
use bytemuck::{Pod, Zeroable};

/// Children per node.
pub const WIDE_ARITY: usize = 4;

/// Entries of the walk's stack (`WIDE_STACK` in WGSL): a node pushes at most three of its
/// children and visits the fourth, so a hierarchy `WIDE_STACK / 3` nodes deep is walked
/// without overflow; a deeper one is refused ([`WideTraversal::of`]). WGSL zeroes a
/// function's array at every call: on lavapipe a stack of 192 entries made the Cornell box's
/// wide walk 0.58-0.77 of the binary one, 48 0.86-1.02 (docs/bvh.md).
pub const WIDE_STACK: u32 = 48;

/// Twin of the words `walk_wide` reads for one node.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuWideNode {
    /// Per axis (x, y, z), per child: the box's lower grid coordinate in the low 16 bits,
    /// the upper in the high 16 (as `GpuTraversalNode`'s).
    pub q: [[u32; WIDE_ARITY]; 3],
    /// Per child: an interior child's node index (never 0, the root's), a leaf's
    /// `first | count << LEAF_COUNT_SHIFT`, 0 for an empty slot.
    pub link: [u32; WIDE_ARITY],
}

/// 16-byte words per [`GpuWideNode`].
pub const WIDE_NODE_WORDS: u32 = (std::mem::size_of::<GpuWideNode>() / 16) as u32;
const _: () = assert!(std::mem::size_of::<GpuWideNode>() == 64);

/// The wide layout of one hierarchy: what the `nodes` binding gets.
#[derive(Clone, Debug)]
pub struct WideTraversal {
    /// The grid, with the node count.
    pub frame: GpuBvhFrame,
    /// The nodes, the root first.
    pub nodes: Vec<GpuWideNode>,
}

impl WideTraversal {
    /// `bvh` collapsed into four-wide nodes: each binary interior node's children, the
    /// interior child of the largest surface opened until there are four (or only leaves).
    /// None for a hierarchy without primitives, one the binary layout refuses (the same
    /// limits), or one whose walk could overflow its stack of [`WIDE_STACK`] entries.
    pub fn of(bvh: &Bvh) -> Option<Self> {
        if bvh.prim_ids.is_empty() || bvh.nodes.len() >= 1 << LEAF_COUNT_SHIFT {
            return None;
        }
        let grid = BoxGrid::of(&bvh.nodes[0])?;
        let link_of = |i: usize| -> Option<u32> {
            let b = &bvh.nodes[i];
            (b.count > 0).then_some(b.left_first | b.count << LEAF_COUNT_SHIFT)
        };
        let mut nodes = vec![GpuWideNode::default()];
        // (binary node, wide node, depth in wide nodes)
        let mut todo = vec![(0usize, 0usize, 1u32)];
        let mut deepest = 0;
        while let Some((i, w, depth)) = todo.pop() {
            deepest = deepest.max(depth);
            let children = if bvh.nodes[i].count > 0 {
                // A leaf root: one child, itself.
                vec![i]
            } else {
                open(bvh, i)
            };
            let mut node = GpuWideNode::default();
            for (slot, &c) in children.iter().enumerate() {
                let q = grid.quantise(&bvh.nodes[c]);
                for (axis, &bounds) in node.q.iter_mut().zip(&q) {
                    axis[slot] = bounds;
                }
                node.link[slot] = match link_of(c) {
                    Some(leaf) => {
                        if bvh.nodes[c].count >= 1 << (32 - LEAF_COUNT_SHIFT) {
                            return None;
                        }
                        leaf
                    }
                    None => {
                        nodes.push(GpuWideNode::default());
                        todo.push((c, nodes.len() - 1, depth + 1));
                        (nodes.len() - 1) as u32
                    }
                };
            }
            nodes[w] = node;
        }
        // A node pushes at most three children and visits the fourth: the stack holds at
        // most three per level above the deepest.
        if 3 * deepest > WIDE_STACK {
            return None;
        }
        Some(WideTraversal {
            frame: grid.frame(nodes.len() as u32),
            nodes,
        })
    }

    /// The bytes of the `nodes` binding: the frame, then the nodes.
    pub fn bytes(&self) -> Vec<u8> {
        let mut out = bytemuck::bytes_of(&self.frame).to_vec();
        out.extend_from_slice(bytemuck::cast_slice(&self.nodes));
        out
    }

    /// 16-byte words of [`WideTraversal::bytes`].
    pub fn words(&self) -> u32 {
        FRAME_WORDS + WIDE_NODE_WORDS * self.nodes.len() as u32
    }
}

fn area(b: &BvhNode) -> f32 {
    let e = [0, 1, 2].map(|a| (b.bmax[a] - b.bmin[a]).max(0.0));
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
}

/// Up to [`WIDE_ARITY`] descendants of interior node `i` covering its subtree: its two
/// children, the interior one of the largest surface replaced by its own two while there is
/// room.
fn open(bvh: &Bvh, i: usize) -> Vec<usize> {
    let kids = |n: usize| [n + 1, bvh.nodes[n].left_first as usize];
    let mut out = kids(i).to_vec();
    while out.len() < WIDE_ARITY {
        let widest = (0..out.len())
            .filter(|&k| bvh.nodes[out[k]].count == 0)
            .max_by(|&a, &b| area(&bvh.nodes[out[a]]).total_cmp(&area(&bvh.nodes[out[b]])));
        let Some(k) = widest else { break };
        let n = out.remove(k);
        out.splice(k..k, kids(n));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::gpu_layout::GPU_COSTS;

    /// A hierarchy `depth` interior nodes deep: each holds a leaf of one primitive and the
    /// next interior node, all over the unit box.
    fn chain(depth: usize) -> Bvh {
        let node = |left_first: usize, count: u32| BvhNode {
            bmin: [0.0; 3],
            left_first: left_first as u32,
            bmax: [1.0; 3],
            count,
        };
        let mut nodes = Vec::new();
        for k in 0..depth {
            nodes.push(node(2 * k + 2, 0));
            nodes.push(node(k, 1));
        }
        nodes.push(node(depth, 1));
        Bvh {
            nodes,
            prim_ids: (0..=depth as u32).collect(),
            alpha: false,
        }
    }

    #[test]
    fn a_hierarchy_too_deep_for_the_stack_is_refused() {
        // A chain collapses three interior nodes into each wide one.
        let fits = (WIDE_STACK as usize / 3 - 1) * 3;
        let wide = WideTraversal::of(&chain(fits)).expect("a chain the stack holds");
        assert_eq!(wide.nodes.len(), fits / 3);
        assert!(WideTraversal::of(&chain(fits + 6)).is_none());
    }

    /// Every node is reached once from the root and every leaf of the binary tree exactly
    /// once.
    #[test]
    fn wide_nodes_cover_every_leaf_once() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-box.toml");
        let cornell = crate::importers::load(std::path::Path::new(path)).expect("scene");
        let scene = crate::bench::mesh::with_mesh(&cornell, 5000);
        let bvh = Bvh::build_with(&scene, GPU_COSTS);
        let wide = WideTraversal::of(&bvh).expect("a wide layout");
        let leaves: Vec<u32> = (bvh.nodes.iter())
            .filter(|n| n.count > 0)
            .map(|n| n.left_first | n.count << LEAF_COUNT_SHIFT)
            .collect();
        let mut seen = Vec::new();
        let mut todo = vec![0usize];
        let mut interior = 0;
        while let Some(w) = todo.pop() {
            interior += 1;
            for &l in wide.nodes[w].link.iter().filter(|&&l| l != 0) {
                if l >> LEAF_COUNT_SHIFT == 0 {
                    todo.push(l as usize);
                } else {
                    seen.push(l);
                }
            }
        }
        assert_eq!(interior, wide.nodes.len(), "every node is reached once");
        seen.sort_unstable();
        let mut want = leaves.clone();
        want.sort_unstable();
        assert_eq!(seen, want);
    }
}
