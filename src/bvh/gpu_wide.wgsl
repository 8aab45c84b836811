// The four-wide walk of the GPU's hierarchy (src/bvh/gpu_wide.rs lays its nodes out): a
// stack of links, the children a node admits visited nearest first. Only the ray benchmark
// composes it (src/bench/gpu_rays.wgsl), against walk_bvh, which renders keep (docs/bvh.md).
// WIDE_NODE_WORDS and WIDE_STACK come from the generated prelude.
// Library, no entry point; writes nothing but the loop budget it spends.

// Slab distances of four boxes on one axis: grid coordinates q (low 16 bits lower, high
// upper), the axis' grid base and step, the ray's origin and inverse direction on it. The
// boxes decode as hit_box's do, exactly.
struct Slabs4 {
    near: vec4<f32>,
    far: vec4<f32>,
}

fn slabs4(q: vec4<u32>, base: i32, step: f32, o: f32, inv: f32) -> Slabs4 {
    let lo = (vec4<f32>(vec4<i32>(base) + vec4<i32>(q & vec4<u32>(0xffffu))) * step - o) * inv;
    let hi = (vec4<f32>(vec4<i32>(base) + vec4<i32>(q >> vec4<u32>(16u))) * step - o) * inv;
    return Slabs4(min(lo, hi), max(lo, hi));
}

// The walk's place: the link to visit next (a node, or a leaf to test), the stack of links
// still to visit and its height; done once nothing is left.
struct WideCursor {
    link: u32,
    sp: u32,
    done: bool,
}

// As walk_bvh, over the wide layout whose frame starts at word `frame` of `nodes`.
fn walk_wide(frame: u32, o: vec3<f32>, d: vec3<f32>, best_in: PrimHit, any_hit: bool) -> PrimHit {
    var best = best_in;
    let inv = 1.0 / d;
    let sh = make_shear(d);
    let grid_base = bitcast<vec3<i32>>(nodes[frame].xyz);
    let step = bitcast<vec3<f32>>(nodes[frame + 1u].xyz);
    let first_word = frame + FRAME_WORDS;
    var stack: array<u32, WIDE_STACK>;
    // The root is node 0: a link with count bits 0.
    var at = WideCursor(0u, 0u, false);
    // While-while, as walk_bvh: the inner loop visits nodes only, up to the next leaf to
    // test, so that a SIMD group's lanes test their leaves together. The outer loop ends
    // when the inner one finds no leaf, which it does once spend() refuses.
    loop {
        var leaf = 0u;
        while !at.done && spend() {
            let count = at.link >> LEAF_COUNT_SHIFT;
            if count != 0u {
                leaf = at.link;
                at.done = at.sp == 0u;
                if !at.done {
                    at.sp -= 1u;
                    at.link = stack[at.sp];
                }
                break;
            }
            let w = first_word + WIDE_NODE_WORDS * at.link;
            let links = nodes[w + 3u];
            let x = slabs4(nodes[w], grid_base.x, step.x, o.x, inv.x);
            let y = slabs4(nodes[w + 1u], grid_base.y, step.y, o.y, inv.y);
            let z = slabs4(nodes[w + 2u], grid_base.z, step.z, o.z, inv.z);
            let near = max(max(x.near, y.near), max(z.near, vec4<f32>(0.0)));
            let far = min(min(x.far, min(y.far, z.far)) * BOX_SLACK, vec4<f32>(best.t));
            let enter = (near <= far) & (links != vec4<u32>(0u));
            let n = u32(enter.x) + u32(enter.y) + u32(enter.z) + u32(enter.w);
            if n == 0u {
                at.done = at.sp == 0u;
                if !at.done {
                    at.sp -= 1u;
                    at.link = stack[at.sp];
                }
                continue;
            }
            // The entered children sorted by entry distance (a sorting network on (key,
            // link)); a child not entered sorts last (the largest key).
            var k = select(vec4<f32>(3.4028235e38), near, enter);
            var l = links;
            // (0,1) (2,3) (0,2) (1,3) (1,2)
            var s = k.y < k.x;
            k = select(k, k.yxzw, vec4<bool>(s, s, false, false));
            l = select(l, l.yxzw, vec4<bool>(s, s, false, false));
            s = k.w < k.z;
            k = select(k, k.xywz, vec4<bool>(false, false, s, s));
            l = select(l, l.xywz, vec4<bool>(false, false, s, s));
            s = k.z < k.x;
            k = select(k, k.zyxw, vec4<bool>(s, false, s, false));
            l = select(l, l.zyxw, vec4<bool>(s, false, s, false));
            s = k.w < k.y;
            k = select(k, k.xwzy, vec4<bool>(false, s, false, s));
            l = select(l, l.xwzy, vec4<bool>(false, s, false, s));
            s = k.z < k.y;
            k = select(k, k.xzyw, vec4<bool>(false, s, s, false));
            l = select(l, l.xzyw, vec4<bool>(false, s, s, false));
            // The farther ones on the stack, the farthest deepest; the nearest next.
            for (var j = n - 1u; j > 0u; j -= 1u) {
                stack[at.sp] = l[j];
                at.sp += 1u;
            }
            at.link = l.x;
        }
        if leaf == 0u {
            break;
        }
        best = leaf_hits(leaf & ((1u << LEAF_COUNT_SHIFT) - 1u), leaf >> LEAF_COUNT_SHIFT, o, d, sh, best);
        if any_hit && best.found {
            break;
        }
    }
    return best;
}
