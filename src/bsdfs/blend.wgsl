// A blend of two materials (Mitsuba's blendbsdf), twin of src/bsdfs/blend.rs: blend_u hashes a
// hit and a ray direction into the uniform of the choice, blend_choose follows a material's
// blends to the component chosen there. Library, no entry point; writes nothing.

// The uniform in [0, 1) of a blend's choice at hit p for a ray along d.
fn blend_u(p: vec3<f32>, d: vec3<f32>) -> f32 {
    var h = 0x9e3779b9u;
    h = pcg_hash(h ^ bitcast<u32>(p.x));
    h = pcg_hash(h ^ bitcast<u32>(p.y));
    h = pcg_hash(h ^ bitcast<u32>(p.z));
    h = pcg_hash(h ^ bitcast<u32>(d.x));
    h = pcg_hash(h ^ bitcast<u32>(d.y));
    h = pcg_hash(h ^ bitcast<u32>(d.z));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// The index of the material that a hit at p (uv) on material i (header m), seen along d, is:
// i itself unless it is a blend, else the component chosen, nested blends followed.
fn blend_choose(i: u32, m: Material, p: vec3<f32>, d: vec3<f32>, uv: vec2<f32>) -> u32 {
    var index = i;
    var c = m;
    var u = blend_u(p, d);
    for (var k = 0u; k < MAX_BLEND_DEPTH; k++) {
        if c.blend_first == NO_BLEND {
            break;
        }
        let w = clamp(w_f(param_eval(c.blend_weight, uv)), 0.0, 1.0);
        if u < w {
            index = c.blend_second;
            u = u / w;
        } else {
            index = c.blend_first;
            u = (u - w) / (1.0 - w);
        }
        u = min(u, ONE_BELOW);
        c = load_material(index);
    }
    return index;
}
