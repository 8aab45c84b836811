// Types shared by every kernel. Each struct has a Rust twin with the same name prefixed by
// `Gpu` (or the same name: Photon) in src/integrators/gpu/types.rs, src/bvh/gpu_layout.rs, src/integrators/photon.rs;
// tests/gpu_layout.rs checks sizes and offsets against naga's reflection of this file.
// Library of types only; no entry point.

struct Triangle {
    v0: vec3<f32>,
    material: u32,
    v1: vec3<f32>,
    light: u32,
    v2: vec3<f32>,
    shading: u32,
}

// The vertex normals of one smooth-shaded triangle (Triangle.shading indexes them).
struct ShadingNormals {
    n0: vec3<f32>,
    _pad0: u32,
    n1: vec3<f32>,
    _pad1: u32,
    n2: vec3<f32>,
    _pad2: u32,
}

struct Sphere {
    center: vec3<f32>,
    radius: f32,
    material: u32,
    light: u32,
    frame: vec2<u32>,
}

// The grid of the quantised node boxes (src/bvh/gpu_layout.rs): grid coordinate q on axis
// a is the point f32(base[a] + q) * step[a], exactly; `nodes` nodes per copy.
// `next`: the word of the next level (src/bvh/gpu_instances.rs): the world's frame names the
// instances' top level (0: none), the top level's the instance records.
struct BvhFrame {
    base: vec3<i32>,
    nodes: u32,
    step: vec3<f32>,
    next: u32,
}

// One instance (src/bvh/gpu_instances.rs): the rows of its world-to-object and
// object-to-world affine maps (xyz the linear part's row, w the translation's), and the word
// of its mesh's BvhFrame.
struct InstanceRecord {
    to_object: array<vec4<f32>, 3>,
    to_world: array<vec4<f32>, 3>,
    frame: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// One BVH node in one copy's preorder: qx, qy, qz = lower | upper << 16 grid coordinates of
// its box; link = (interior) the node after its subtree, (leaf) first | count <<
// LEAF_COUNT_SHIFT.
struct TraversalNode {
    qx: u32,
    qy: u32,
    qz: u32,
    link: u32,
}

// One leaf entry: the primitive id (SPHERE_BIT: a sphere) and a triangle's vertices.
struct LeafPrim {
    v0: vec3<f32>,
    id: u32,
    v1: vec3<f32>,
    _pad0: u32,
    v2: vec3<f32>,
    _pad1: u32,
}

// A placed SDF grid (twin of GpuSdfGrid in src/bvh/gpu_sdf.rs): maps as rows, its vertices per
// axis, material, the flat word of its values, 1 for smooth normals.
struct SdfGridRecord {
    to_object: array<vec4<f32>, 3>,
    to_world: array<vec4<f32>, 3>,
    res: vec3<u32>,
    material: u32,
    values: u32,
    smooth_normals: u32,
    _pad0: u32,
    _pad1: u32,
}

struct Material {
    emission: vec3<f32>,
    two_sided: u32,
    // The BSDF's kind (BSDF_*, generated from the list of kinds) and its textured words.
    kind: u32,
    textured: u32,
    // 1: black seen from the back (Material::one_sided).
    one_sided: u32,
    // Index into tex_table of the tangent-space normal map, or NO_TEXTURE.
    normal_texture: u32,
    // ALPHA_NONE, ALPHA_MASK or ALPHA_BLEND, plus ALPHA_LUMINANCE (crate::scene::Alpha).
    alpha_mode: u32,
    // Index into tex_table of the opacity's texture, or NO_TEXTURE.
    alpha_texture: u32,
    alpha_factor: f32,
    alpha_cutoff: f32,
    // A blend's components (NO_BLEND when it is none), whether it stores photons, its weight's
    // slot word (crate::bsdfs::blend::Blend).
    blend_first: u32,
    blend_second: u32,
    blend_stores: u32,
    // 1: the normal map shadows grazing light (Material::normal_shadowing).
    normal_shadowing: u32,
    blend_weight: vec4<u32>,
    // A bump map's scale and 1 when normal_texture is its height texture (Material::bump).
    bump_scale: f32,
    bump: u32,
    _pad0: u32,
    _pad1: u32,
}

struct Light {
    // Its kind (LIGHT_*, generated from lights::KINDS) and photon budgets.
    kind: u32,
    global_offset: u32,
    global_count: u32,
    caustic_offset: u32,
    global_power: vec3<f32>,
    caustic_count: u32,
    caustic_power: vec3<f32>,
    area: f32,
    // Area light: its emission texture's mean and the texture (NO_TEXTURE: none).
    texture_mean: vec3<f32>,
    emission_texture: u32,
    // The kind's own parameters (each kind's WGSL file reads them).
    p0: vec4<u32>,
    p1: vec4<u32>,
    p2: vec4<u32>,
    p3: vec4<u32>,
}

struct Aabb {
    bmin: vec3<f32>,
    _pad0: u32,
    bmax: vec3<f32>,
    _pad1: u32,
}

struct Photon {
    position: vec3<f32>,
    flags: u32,
    power: vec3<f32>,
    id: u32,
    dir: vec3<f32>,
    normal: u32,
}

// Per-render parameters (a read-only storage buffer, one slot per gather sample).
struct Params {
    eye: vec3<f32>,
    width: u32,
    forward: vec3<f32>,
    height: u32,
    right: vec3<f32>,
    spp: u32,
    up: vec3<f32>,
    sample: u32,
    seed: u32,
    pass_index: u32,
    k: u32,
    filter_kind: u32,
    mode: u32,
    max_depth: u32,
    max_photon_bounces: u32,
    shadow_samples: u32,
    fresnel: u32,
    n_lights: u32,
    n_bounds: u32,
    n_triangles: u32,
    terms: u32,
    caustic_weight: f32,
    sampler: u32,
    pixel_filter: u32,
    filter_param: f32,
    aperture_radius: f32,
    focus_distance: f32,
    // The medium the camera sits in (NO_MEDIUM: vacuum).
    camera_medium: u32,
    // The first image row of the band this dispatch gathers (rows of the glass branch stacks).
    first_row: u32,
    // Which of a sample's gather dispatches this is: 0 the gather, r + 1 its round r of glass
    // branches (glass_branches.wgsl's queue).
    branch_round: u32,
    // 1: an orthographic camera.
    orthographic: u32,
    // The medium outside every shape (Scene::outer_medium).
    outer_medium: u32,
}

// A homogeneous medium (twin of crate::medium::Medium; sigma_s = albedo sigma_t).
struct Medium {
    sigma_t: vec3<f32>,
    g: f32,
    sigma_s: vec3<f32>,
    // A heterogeneous medium's record in `media` (src/media/gpu.rs), NO_MEDIUM for none.
    grid: u32,
}

// Per photon map: what to trace and how its hash grid is laid out.
struct MapParams {
    stream: u32,
    paths: u32,
    capacity: u32,
    table_size: u32,
    cell_size: f32,
    is_caustic: u32,
    drop_flags: u32,
    radius2: f32,
    k: u32,
    storing_area: f32,
    max_power: f32,
    // VOLUME_STORE: the paths store volume photons; VOLUME_DROP_CAUSTIC: not the L S+ V ones.
    volume_flags: u32,
}

// The codes these structs carry (BSDF_*, LIGHT_*, TERM_*, FILTER_*, FRESNEL_*, STAT_*, flags)
// are generated from src/integrators/gpu/codes.rs into the prelude every kernel starts with.

// A camera path's glass branch waiting on its pixel's stack (glass_branches.wgsl; twin of
// crate::gpu::branches::GpuBranch): where it starts, its direction, throughput, depth and
// medium (a delta bounce leaves no MIS weighing to carry).
struct Branch {
    o: vec3<f32>,
    depth: u32,
    d: vec3<f32>,
    medium: u32,
    t: vec3<f32>,
    _pad: u32,
}

// One pixel's pending branches, last in first out, and what its sample's next path resumes
// with (twin of GpuBranchStack): `resume` is the RNG's next dimension, with BRANCH_SOBOL_UNUSED
// set while the Sobol point is (the first shaded hit takes it). Those pending at once come from
// splits on one path's way back to the camera, each at its own depth < GLASS_SPLIT_DEPTH, so
// GLASS_SPLIT_DEPTH slots suffice. `queue[l]`: entry i of the branch queue's list l (the i-th
// pixel listed, not this one: glass_branches.wgsl).
struct BranchStack {
    n: u32,
    resume: u32,
    queue: array<u32, 2>,
    b: array<Branch, GLASS_SPLIT_DEPTH>,
}
