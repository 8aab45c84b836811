//! The BVH's escape links (`Bvh::links`), which the GPU's stackless traversal follows: for
//! every example scene and a generated 20,000-triangle mesh, in both child orders, the links
//! must give the depth-first preorder of the stack traversal, and a missed node must jump to
//! the first node after its whole subtree in that order.

use glam::Vec3;
use gpu_photon::bvh::{Bvh, NO_NODE};
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
    let links = bvh.links();
    assert_eq!(links.len(), bvh.nodes.len(), "{name}");
    for (o, right_first) in [(0usize, false), (1, true)] {
        let (order, size) = preorder(bvh, right_first);
        assert_eq!(order.len(), bvh.nodes.len(), "{name}: every node once");
        // Entering every box: interior nodes go to their first child, leaves to their link.
        let mut walked = Vec::new();
        let mut ni = 0u32;
        while ni != NO_NODE {
            assert!(walked.len() < bvh.nodes.len(), "{name}: the walk must end");
            walked.push(ni);
            let n = &bvh.nodes[ni as usize];
            ni = match (n.count, right_first) {
                (0, false) => ni + 1,
                (0, true) => n.left_first,
                _ => links[ni as usize][o],
            };
        }
        assert_eq!(walked, order, "{name}: order {o} is the preorder");
        // Missing a node skips exactly its subtree.
        for (pos, &n) in order.iter().enumerate() {
            let after = order
                .get(pos + size[n as usize])
                .copied()
                .unwrap_or(NO_NODE);
            assert_eq!(links[n as usize][o], after, "{name}: node {n}, order {o}");
        }
    }
}

#[test]
fn links_give_the_stack_traversal_order_on_every_example_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = gpu_photon::scene::load(&path).unwrap();
            check(&path.display().to_string(), &Bvh::build(&scene));
            n += 1;
        }
    }
    assert!(n >= 8, "found {n} scenes");
}

#[test]
fn links_give_the_stack_traversal_order_on_a_deep_mesh() {
    let mut scene: Scene = gpu_photon::scene::load(
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
    // The placeholder tree of an empty scene is never entered.
    scene.triangles.clear();
    scene.spheres.clear();
    assert!(Bvh::build(&scene)
        .links()
        .iter()
        .all(|l| *l == [NO_NODE; 2]));
}
