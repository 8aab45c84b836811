//! The GPU's stackless traversal layout (`gpu::bvh_layout::traversal_nodes`): for every
//! example scene and a generated 20,000-triangle mesh, built with the CPU's SAH costs and the
//! GPU's (`GPU_COSTS`: smaller leaves), in both child orders, entering every
//! box must walk the depth-first preorder of the stack traversal, missing a node must jump to
//! the first node after its whole subtree in that order, leaves must keep their primitives,
//! and every quantised box must contain the node's exact box.

use glam::Vec3;
use gpu_photon::bvh::gpu_layout::{traversal_nodes, GPU_COSTS, LEAF_COUNT_SHIFT};
use gpu_photon::bvh::Bvh;
use gpu_photon::scene::{Scene, Triangle};
use std::path::Path;

/// The depth-first preorder entering the left child first (`right_first` false) or the
/// right child first, and each node's subtree size.
fn preorder(bvh: &Bvh, right_first: bool) -> (Vec<u32>, Vec<usize>) {
    fn go(bvh: &Bvh, i: usize, rf: bool, order: &mut Vec<u32>, size: &mut [usize]) -> usize {
        order.push(i as u32);
        let n = &bvh.nodes[i];
        let mut s = 1;
        if n.count == 0 {
            let (l, r) = (i + 1, n.left_first as usize);
            let (a, b) = if rf { (r, l) } else { (l, r) };
            s += go(bvh, a, rf, order, size);
            s += go(bvh, b, rf, order, size);
        }
        size[i] = s;
        s
    }
    let mut order = Vec::new();
    let mut size = vec![0; bvh.nodes.len()];
    go(bvh, 0, right_first, &mut order, &mut size);
    (order, size)
}

fn check(name: &str, bvh: &Bvh) {
    let layout = traversal_nodes(bvh).expect("fits");
    let n = bvh.nodes.len();
    assert_eq!(layout.frame.nodes as usize, n, "{name}");
    assert_eq!(layout.nodes.len(), 2 * n, "{name}");
    let mask = (1u32 << LEAF_COUNT_SHIFT) - 1;
    for (c, right_first) in [(0usize, false), (1, true)] {
        let copy = &layout.nodes[c * n..(c + 1) * n];
        let (order, size) = preorder(bvh, right_first);
        // Copy position p holds the preorder's p-th node.
        for (p, &i) in order.iter().enumerate() {
            assert_eq!(
                layout.position[c][i as usize] as usize, p,
                "{name}: node {i}"
            );
            let (b, t) = (&bvh.nodes[i as usize], &copy[p]);
            if b.count > 0 {
                assert_eq!(t.link, b.left_first | b.count << LEAF_COUNT_SHIFT, "{name}");
            } else {
                // Missing an interior node skips exactly its subtree.
                assert_eq!(t.link >> LEAF_COUNT_SHIFT, 0, "{name}");
                assert_eq!(
                    (t.link & mask) as usize,
                    p + size[i as usize],
                    "{name}: node {i}"
                );
            }
            let (lo, hi) = layout.bounds(t);
            for a in 0..3 {
                assert!(
                    lo[a] <= b.bmin[a] && hi[a] >= b.bmax[a],
                    "{name}: node {i} axis {a}"
                );
            }
        }
    }
}

#[test]
fn layout_gives_the_stack_traversal_order_on_every_example_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = gpu_photon::importers::load(&path).unwrap();
            let name = path.display().to_string();
            check(&name, &Bvh::build(&scene));
            check(&name, &Bvh::build_with(&scene, GPU_COSTS));
            n += 1;
        }
    }
    assert!(n >= 8, "found {n} scenes");
}

#[test]
fn layout_gives_the_stack_traversal_order_on_a_deep_mesh() {
    let mut scene: Scene = gpu_photon::importers::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml"),
    )
    .unwrap();
    // A strip of 20,000 thin triangles along a spiral: a deep, unbalanced tree.
    let mut rng = 1u32;
    let mut next = || {
        rng = rng.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        (rng >> 8) as f32 / (1u32 << 24) as f32
    };
    for i in 0..20_000 {
        let t = i as f32 * 0.01;
        let p = Vec3::new(t.cos() * 0.5, (i as f32 / 20_000.0) - 0.5, t.sin() * 0.5);
        let q = p + Vec3::new(next(), next(), next()) * 0.01;
        scene
            .triangles
            .push(Triangle::new(p, q, p + Vec3::Y * 0.001, 0));
    }
    let bvh = Bvh::build(&scene);
    assert!(bvh.depth() > 12, "depth {}", bvh.depth());
    check("spiral", &bvh);
    check("spiral (GPU costs)", &Bvh::build_with(&scene, GPU_COSTS));
    // The placeholder tree of an empty scene ends at once.
    scene.triangles.clear();
    scene.spheres.clear();
    let layout = traversal_nodes(&Bvh::build(&scene)).expect("fits");
    assert!(layout.nodes.iter().all(|t| t.link == 1));
}
