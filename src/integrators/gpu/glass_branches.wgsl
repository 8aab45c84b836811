// glass_branches: a camera path's glass hits, twin of cpu::gather's DeltaEvent::Split: below
// GLASS_SPLIT_DEPTH the heavier branch goes on and the other waits on its pixel's stack in
// `branch_stacks`, for a later round of gather (gather.wgsl) to trace in an
// invocation, and so a loop budget, of its own; a queue there lists the pixels that have one.
// Library of gather.wgsl; writes branch_stacks.

// Branch and BranchStack: src/integrators/gpu/types.wgsl.

// The band's pixels with branches pending after each dispatch of a sample, so that a round
// runs only those (full SIMD groups and warps rather than an image of mostly idle lanes):
// counts[d] pixels were listed by the sample's dispatch d (0: gather; r + 1: round r), in list
// d % 2, whose entry i is stacks[i].queue[d % 2]. Each count is zeroed by a later dispatch
// (queue_reset). A pixel is listed at most once a dispatch and its accumulator, stack and RNG
// are its own, so the order in which the atomics list pixels changes no image. Then one stack
// per pixel of the band of rows being gathered (from params.first_row); a one-stack stand-in
// where GLASS_SPLIT is false.
struct BranchStacks {
    counts: array<atomic<u32>, BRANCH_LISTS>,
    stacks: array<BranchStack>,
}

@group(1) @binding(13) var<storage, read_write> branch_stacks: BranchStacks;

// This invocation's stack (set by the entry point) and how many branches it holds.
var<private> stack_at: u32;
var<private> n_branches: u32 = 0u;

// Writes the stack's depth and what the sample's next path resumes with.
fn save_branches(rng: Rng, first_shade: bool) {
    branch_stacks.stacks[stack_at].n = n_branches;
    branch_stacks.stacks[stack_at].resume = rng.dim | select(0u, BRANCH_SOBOL_UNUSED, first_shade);
}

// Lists this invocation's pixel after the sample's dispatch `dispatch` (0: gather; r + 1:
// round r) when a branch is pending, for the next round to pop.
fn queue_pixel(dispatch: u32) {
    if n_branches == 0u {
        return;
    }
    let k = atomicAdd(&branch_stacks.counts[dispatch], 1u);
    if k < arrayLength(&branch_stacks.stacks) {
        branch_stacks.stacks[k].queue[dispatch % 2u] = stack_at;
    }
}

// Sets stack_at to the pixel invocation k of the dispatch after `listed_by` serves; false
// past the pixels `listed_by` listed.
fn queued_pixel(listed_by: u32, k: u32) -> bool {
    if k >= min(atomicLoad(&branch_stacks.counts[listed_by]), arrayLength(&branch_stacks.stacks)) {
        return false;
    }
    stack_at = branch_stacks.stacks[k].queue[listed_by % 2u];
    return true;
}

// Zeroes, from one invocation of the sample's dispatch `dispatch`, counts that neither it nor
// any dispatch before their next write reads: dispatch d >= 2 zeroes counts[d - 2] (written
// by d - 2, read by d - 1, both finished); the gather zeroes the last two, which the previous
// sample's last rounds used.
fn queue_reset(dispatch: u32) {
    if dispatch == 0u {
        atomicStore(&branch_stacks.counts[BRANCH_LISTS - 2u], 0u);
        atomicStore(&branch_stacks.counts[BRANCH_LISTS - 1u], 0u);
    } else if dispatch >= 2u {
        atomicStore(&branch_stacks.counts[dispatch - 2u], 0u);
    }
}

// A camera path's delta bounce (surface_delta's contract). Glass and the thin dielectric as
// cpu::gather does: on total internal reflection (glass) the reflection, no rng draw; below
// GLASS_SPLIT_DEPTH the heavier branch (the reflection when reflectance >= 0.5) times its
// weight, the other pushed on the pixel's stack; deeper, one draw u < reflectance reflects.
// A branch on the other side of the geometric surface than its shading normal meant goes on
// there (Mitsuba's). Final-gather rays always choose one branch (surface_delta).
fn camera_delta(hit: Hit, s: Surface, d: ptr<function, vec3<f32>>, o: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, depth: u32, medium: u32, rng: ptr<function, Rng>) -> bool {
    if !GLASS_SPLIT || !surface_splits(s) {
        return surface_delta(hit, s, d, o, t, rng);
    }
    let f = facing(hit, dot(*d, hit.normal) < 0.0);
    let g = surface_split(hit, s, f, *d);
    let refracts = any(g.refracted != vec3<f32>(0.0));
    var reflects = true;
    if refracts && depth < GLASS_SPLIT_DEPTH {
        reflects = g.reflectance >= 0.5;
        let later = select(g.reflected, g.refracted, reflects);
        if n_branches < GLASS_SPLIT_DEPTH {
            var bm = medium;
            if HAS_MEDIA {
                bm = medium_after(hit, medium, later);
            }
            let bo = offset_origin(hit.position, hit.normal, later);
            let w = select(g.reflectance, (1.0 - g.reflectance) * g.eta * g.eta, reflects);
            branch_stacks.stacks[stack_at].b[n_branches] = Branch(bo, depth + 1u, later, bm, *t * w, 0u);
            n_branches += 1u;
        }
        *t *= select((1.0 - g.reflectance) * g.eta * g.eta, g.reflectance, reflects);
    } else if refracts {
        reflects = rng_next(rng) < g.reflectance;
        *t *= select(g.eta * g.eta, 1.0, reflects);
    }
    *d = select(g.refracted, g.reflected, reflects);
    *o = offset_origin(hit.position, hit.normal, *d);
    return true;
}
