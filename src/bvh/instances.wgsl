// The two-level walk of a scene with instances: an InstanceRecord's affine maps (their rows
// in `nodes`) and walk_instances, the top level with each instance's mesh walked in its object
// space; twin of src/bvh/instances.rs (the records' layout: src/bvh/gpu_instances.rs).
// trace_ray (intersect.wgsl) calls the walk and maps the hit back to world space.
// Library, no entry point; writes nothing but the loop budget it spends.

// Row r of the affine map whose rows start at word w of `nodes` (an InstanceRecord's).
fn affine_row(w: u32, r: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(nodes[w + r]);
}

fn affine_point(w: u32, p: vec3<f32>) -> vec3<f32> {
    let q = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(affine_row(w, 0u), q), dot(affine_row(w, 1u), q), dot(affine_row(w, 2u), q));
}

fn affine_vector(w: u32, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(affine_row(w, 0u).xyz, v), dot(affine_row(w, 1u).xyz, v), dot(affine_row(w, 2u).xyz, v));
}

// The transpose of the linear part at word w times n: with w an instance's world-to-object
// map, a normal to world space (the inverse transpose of object-to-world).
fn affine_normal(w: u32, n: vec3<f32>) -> vec3<f32> {
    return affine_row(w, 0u).xyz * n.x + affine_row(w, 1u).xyz * n.y + affine_row(w, 2u).xyz * n.z;
}

// Walks the instances' top level (its frame at word `top`) for the nearest hit before
// best.t (world distances), each instance's mesh in its object space (unit direction,
// distances scaled by k = |to_object d|). Returns the instance hit (NO_LIGHT: none) and
// updates best (t in world units).
fn walk_instances(top: u32, o: vec3<f32>, d: vec3<f32>, best: ptr<function, PrimHit>, any_hit: bool) -> u32 {
    var found = NO_LIGHT;
    let inv = 1.0 / d;
    let f0 = nodes[top];
    let f1 = nodes[top + 1u];
    let grid_base = bitcast<vec3<i32>>(f0.xyz);
    let n_nodes = f0.w;
    let step = bitcast<vec3<f32>>(f1.xyz);
    let records = f1.w;
    let left_first = d[dominant_axis(d)] >= 0.0;
    let first_word = top + FRAME_WORDS + select(n_nodes, 0u, left_first) * NODE_WORDS;
    var ni = 0u;
    // As walk_bvh's, with instances in the leaves.
    loop {
        let leaf = next_leaf(first_word, n_nodes, &ni, grid_base, step, o, inv, (*best).t);
        let first = leaf.x;
        let count = leaf.y;
        if count == 0u {
            break;
        }
        for (var i = 0u; i < count && spend(); i += 1u) {
            let inst = leaf_prims[LEAF_PRIM_WORDS * (first + i)].w;
            let r = records + INSTANCE_WORDS * inst;
            let od = affine_vector(r, d);
            let k = length(od);
            let oo = affine_point(r, o);
            let t_world = (*best).t;
            let h = walk_bvh(nodes[r + 6u].x, oo, od / k, PrimHit(t_world * k, 0u, vec2<f32>(0.0), false), any_hit);
            if h.found {
                *best = PrimHit(min(h.t / k, t_world), h.id, h.bc, true);
                found = inst;
                if any_hit {
                    return found;
                }
            }
        }
    }
    return found;
}
