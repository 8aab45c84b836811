// glass_branches: a camera path's glass hits, twin of cpu::gather's DeltaEvent::Split: below
// GLASS_SPLIT_DEPTH the heavier branch goes on and the other waits on its pixel's stack in
// `branch_stacks`, for a later dispatch of gather_branches (gather.wgsl) to trace in an
// invocation, and so a loop budget, of its own. Library of gather.wgsl; writes branch_stacks.

// Branch and BranchStack: shaders/common/types.wgsl.

// One stack per pixel of the band of rows being gathered (from params.first_row); a
// one-stack stand-in where GLASS_SPLIT is false.
@group(1) @binding(13) var<storage, read_write> branch_stacks: array<BranchStack>;

// This invocation's stack (set by the entry point) and how many branches it holds.
var<private> stack_at: u32;
var<private> n_branches: u32 = 0u;

// Writes the stack's depth and what the sample's next path resumes with.
fn save_branches(rng: Rng, first_shade: bool) {
    branch_stacks[stack_at].n = n_branches;
    branch_stacks[stack_at].rng_dim = rng.dim;
    branch_stacks[stack_at].first_shade = u32(first_shade);
}

// A camera path's delta bounce (surface_delta's contract). Glass and the thin dielectric as
// cpu::gather does: on total internal reflection (glass) the reflection, no rng draw; below
// GLASS_SPLIT_DEPTH the heavier branch (the reflection when reflectance >= 0.5) times its
// weight, the other pushed on the pixel's stack (unless it leaks); deeper, one draw u <
// reflectance reflects. Final-gather rays always choose one branch (surface_delta).
fn camera_delta(hit: Hit, s: Surface, d: ptr<function, vec3<f32>>, o: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, depth: u32, medium: u32, rng: ptr<function, Rng>) -> bool {
    let m = s.m;
    let thin = HAS_BSDFS && m.kind == MAT_THIN_DIELECTRIC;
    if !GLASS_SPLIT || (!thin && !(HAS_GLASS && m.kind == MAT_GLASS)) {
        return surface_delta(hit, s, d, o, t, rng);
    }
    let f = facing(hit, dot(*d, hit.normal) < 0.0);
    var g: Dielectric;
    if thin {
        let r = fresnel_dielectric_mi(abs(dot(*d, f.ns)), s.b.eta).f;
        g = Dielectric(reflect_dir(*d, f.ns), *d, select(1.0, 2.0 * r / (1.0 + r), r < 1.0));
    } else {
        g = dielectric(*d, hit.normal, hit.shading, m.ior);
    }
    let refracts = thin || any(g.refracted != vec3<f32>(0.0));
    var reflects = true;
    if refracts && depth < GLASS_SPLIT_DEPTH {
        reflects = g.reflectance >= 0.5;
        let later = select(g.reflected, g.refracted, reflects);
        let leaks = select(reflection_leaks(f, later), refraction_leaks(f, later), reflects);
        if !leaks && n_branches < GLASS_SPLIT_DEPTH {
            var bm = medium;
            if HAS_MEDIA {
                bm = medium_after(hit, medium, later);
            }
            let bo = offset_origin(hit.position, hit.normal, later);
            let w = select(g.reflectance, 1.0 - g.reflectance, reflects);
            branch_stacks[stack_at].b[n_branches] = Branch(bo, depth + 1u, later, bm, *t * w, 0u);
            n_branches += 1u;
        }
        *t *= select(1.0 - g.reflectance, g.reflectance, reflects);
    } else if refracts {
        reflects = rng_next(rng) < g.reflectance;
    }
    *d = select(g.refracted, g.reflected, reflects);
    *o = offset_origin(hit.position, hit.normal, *d);
    return !select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
}
