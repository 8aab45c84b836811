// The stored photon's packed normal, the side test of the radiance estimate and the end of a
// path whose power is spent; twin of src/integrators/photon.rs (pack_normal, unpack_normal, power_ends)
// and src/integrators/estimate.rs (FACING_COS, photon_faces).
// Library, no entry point; writes nothing.

// A Photon as PHOTON_WORDS 16-byte words: (position, flags), (power, id), (dir, normal).
// The map buffers hold these words: lavapipe turns each member of a struct load or store
// into its own per-lane loop of bounds-checked accesses, a vec4 into one.

// The Photon of its three words (a caller that has read some words already passes them).
fn photon_of_words(a: vec4<u32>, b: vec4<u32>, c: vec4<u32>) -> Photon {
    return Photon(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w, bitcast<vec3<f32>>(c.xyz), c.w);
}

// FACING_COS (prelude): normals within 60 degrees are the same surface; beyond 120 its
// other side.

fn sign_not_zero(v: vec2<f32>) -> vec2<f32> {
    return select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

// Octahedral encoding into two 16-bit snorms.
fn pack_normal(n: vec3<f32>) -> u32 {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if l1 == 0.0 {
        return 0u;
    }
    var p = n.xy / l1;
    if n.z < 0.0 {
        p = (vec2<f32>(1.0) - abs(p.yx)) * sign_not_zero(p);
    }
    return pack2x16snorm(p);
}

fn unpack_normal(bits: u32) -> vec3<f32> {
    var p = unpack2x16snorm(bits);
    let z = 1.0 - abs(p.x) - abs(p.y);
    if z < 0.0 {
        p = (vec2<f32>(1.0) - abs(p.yx)) * sign_not_zero(p);
    }
    // Never zero: |x| + |y| + |z| = 1 before the fold and after it.
    return normalize(vec3<f32>(p, z));
}

// Whether photon p lends light to an estimate at x on a surface with normal ns facing the
// viewer: from the front; the same surface yes, its other side no, and a surface meeting it
// at an edge only where each lies in front of the other (concave corner) or each behind the
// other (convex edge), never across the solid (see src/integrators/estimate.rs).
fn photon_faces(p: Photon, x: vec3<f32>, ns: vec3<f32>) -> bool {
    if dot(p.dir, ns) >= 0.0 {
        return false;
    }
    let np = unpack_normal(p.normal);
    let c = dot(np, ns);
    if c > FACING_COS {
        return true;
    }
    if c < -FACING_COS {
        return false;
    }
    return (dot(p.position - x, ns) > 0.0) == (dot(x - p.position, np) > 0.0);
}

// Whether a photon's power is no longer positive and finite (the abs test is false for NaN
// as for infinity): its path ends (twin of photon::power_ends).
fn power_ends(power: vec3<f32>) -> bool {
    return !(max3(power) > 0.0) || any(!(abs(power) <= vec3<f32>(3.4028235e38)));
}
