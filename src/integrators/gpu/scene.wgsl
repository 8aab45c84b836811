// Group 0: the scene, bound read-only by every kernel (table: SCENE_GROUP in
// src/integrators/gpu/bindings.rs), the scene features as override constants, and the loop budget that
// keeps every invocation well below lavapipe's 65,535 loop iterations (see LOOP_BUDGET).
// Library, no entry point; writes stats[STAT_LOOP_BUDGET] when a budget runs out.

// Structs are read as 16-byte words through load_triangle, load_sphere, load_material and
// load_light below: lavapipe turns each member of a struct load into its own per-lane loop
// of bounds-checked loads, a vec4 into one.
@group(0) @binding(0) var<storage, read> triangles: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read> spheres: array<vec4<u32>>;
// The BVH in the traversal's layout (src/bvh/gpu_layout.rs): the BvhFrame, then every
// TraversalNode in left-first preorder, then every one in right-first preorder; each leaf
// entry's LeafPrim in leaf order, then the SDF grids' words (src/bvh/gpu_sdf.rs). Read as
// words too (trace_ray, intersect.wgsl).
@group(0) @binding(2) var<storage, read> nodes: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read> leaf_prims: array<vec4<u32>>;
@group(0) @binding(4) var<storage, read> materials: array<vec4<u32>>;
@group(0) @binding(5) var<storage, read> lights: array<vec4<u32>>;
@group(0) @binding(6) var<storage, read> light_cdf: array<f32>;
@group(0) @binding(7) var<storage, read> spec_bounds: array<Aabb>;
@group(0) @binding(8) var<storage, read> params: Params;
@group(0) @binding(9) var<storage, read_write> stats: array<atomic<u32>>;
// Vertex normals of the smooth-shaded triangles (one placeholder when the scene has none).
@group(0) @binding(10) var<storage, read> shading_normals: array<ShadingNormals>;
// Each material's BSDF words (BSDF_WORDS per material, src/bsdfs/gpu.rs) and the kinds'
// tables (a rough plastic's), each triangle's corner uvs as two words, and the textures
// (src/textures/texture.wgsl); one placeholder each when the scene has none.
@group(0) @binding(11) var<storage, read> bsdfs: array<vec4<u32>>;
@group(0) @binding(12) var<storage, read> bsdf_tables: array<f32>;
@group(0) @binding(13) var<storage, read> uvs: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read> tex_table: array<TextureRecord>;
@group(0) @binding(15) var<storage, read> tex_words: array<u32>;
// Participating media (src/media/medium.wgsl): the media as two words each (Medium), and
// each material's (interior, exterior) media; one placeholder each when the scene has none.
@group(0) @binding(16) var<storage, read> media: array<vec4<f32>>;
@group(0) @binding(17) var<storage, read> material_media: array<vec2<u32>>;

// Scene features, set per render as pipeline-overridable constants: code for what a scene
// lacks folds away when the pipeline is compiled.
override HAS_SPHERES: bool = true;
// The scene has SDF grids (Mitsuba's sdfgrid, src/bvh/gpu_sdf.rs): the world hierarchy holds
// their cells, which walk_bvh tests and trace_ray shades (src/scene/sdf_grid.wgsl).
override HAS_SDF_GRIDS: bool = true;
// The scene has instances (src/bvh/gpu_instances.rs): trace_ray walks their top level.
override HAS_INSTANCES: bool = true;
override HAS_POINT_LIGHTS: bool = true;
// The scene has an environment light (its last light).
override HAS_ENVIRONMENT: bool = true;
// Some triangle is smooth-shaded: without, the shading normal is the geometric one.
override HAS_SMOOTH: bool = true;
// Some material has a texture: hits carry uvs.
override HAS_TEXTURES: bool = true;
// Some material has a normal map (Mitsuba's normalmap): the nearest hit perturbs its shading
// normal (shading_frame.wgsl's normal_mapped). Implies HAS_TEXTURES.
override HAS_NORMAL_MAPS: bool = true;
// Some material's normal texture is a bump map (Mitsuba's bumpmap): the nearest hit carries
// its uv partials and tilts its shading normal by the texture's gradient (shading_frame.wgsl's
// bump_mapped). Implies HAS_NORMAL_MAPS.
override HAS_BUMP_MAPS: bool = true;
// Some triangle has uvs: the uv record of every triangle is bound and gives the shading frame's
// tangent (without textures too: an anisotropic BSDF's frame follows dp/du).
override HAS_UVS: bool = true;
// Some triangle has vertex tangents (glTF's TANGENT or MikkTSpace's): its uv record carries
// them after its uvs (UV_TANGENT_WORDS words a triangle instead of UV_WORDS).
override HAS_TANGENTS: bool = true;
// Some material is alpha-tested (glTF alphaMode, Mitsuba's mask): every candidate hit in
// trace_ray checks its opacity (intersect.wgsl's alpha_passes).
override HAS_ALPHA: bool = true;
// The render's passes may run K-nearest estimates (classic passes, params.k > 0); false for a
// progressive render, whose passes all use fixed radii: the heap search and the cache build's
// K-th selection then fold away (on lavapipe the gather kernel compiles 6x faster, and runs
// about 10% faster).
override KNN: bool = true;
// The scene needs media transport (Scene::has_media_transport: a medium, or a `null`
// boundary): free flights, volume photons, transmittance and in-scattering
// (src/media/medium.wgsl); without, none of it is compiled.
override HAS_MEDIA: bool = true;
// Some medium is heterogeneous (a grid or volume, src/media/heterogeneous.wgsl): the media
// functions dispatch on a medium's kind; without, only the homogeneous code is compiled.
override HAS_HETERO_MEDIA: bool = true;
// A camera path may meet glass or a thin dielectric (crate::gpu::pipelines::glass_split):
// the gather splits such hits below GLASS_SPLIT_DEPTH and defers a branch to a later round
// (src/integrators/gpu/glass_branches.wgsl); without, the branch stack and its rounds fold away.
override GLASS_SPLIT: bool = true;

// Loop iterations one invocation may spend in total, across all its loops. Lavapipe cuts
// loops silently after 65,535 iterations counted per SIMD group (8 lanes), across all loops,
// and a group iterates while any lane does: so each lane gets 65,535 / 8 (rounded down to
// 8,000) there, and every loop in every kernel calls spend() once per iteration, which bounds
// the group's total by 8 x 8,000 = 64,000. The host raises it on other devices. Exhausting
// it ends the invocation's work and is counted in stats[STAT_LOOP_BUDGET]. Adapters without
// the cut compile the guard out (LOOP_GUARD false, src/integrators/gpu/shape.rs): spend() is then true
// and the counter is dropped.
override LOOP_BUDGET: u32 = 8000u;
var<private> loop_iters: u32 = 0u;

// Spends one loop iteration; false once the budget is gone (counted once).
fn spend() -> bool {
    if !LOOP_GUARD {
        return true;
    }
    loop_iters += 1u;
    if loop_iters == LOOP_BUDGET {
        atomicAdd(&stats[STAT_LOOP_BUDGET], 1u);
    }
    return loop_iters < LOOP_BUDGET;
}

// Triangle i from its three words.
fn load_triangle(i: u32) -> Triangle {
    let a = triangles[TRIANGLE_WORDS * i];
    let b = triangles[TRIANGLE_WORDS * i + 1u];
    let c = triangles[TRIANGLE_WORDS * i + 2u];
    return Triangle(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w, bitcast<vec3<f32>>(c.xyz), c.w);
}

// Sphere i from its two words.
fn load_sphere(i: u32) -> Sphere {
    let a = spheres[SPHERE_WORDS * i];
    let b = spheres[SPHERE_WORDS * i + 1u];
    return Sphere(bitcast<vec3<f32>>(a.xyz), bitcast<f32>(a.w), b.x, b.y, b.zw);
}

// Material i's header from its six words (its BSDF: load_bsdf, generated by src/bsdfs/gpu.rs).
fn load_material(i: u32) -> Material {
    let a = materials[MATERIAL_WORDS * i];
    let b = materials[MATERIAL_WORDS * i + 1u];
    let c = materials[MATERIAL_WORDS * i + 2u];
    let e = materials[MATERIAL_WORDS * i + 3u];
    let f = materials[MATERIAL_WORDS * i + 5u];
    return Material(bitcast<vec3<f32>>(a.xyz), a.w, b.x, b.y, b.z, b.w, c.x, c.y, bitcast<f32>(c.z), bitcast<f32>(c.w),
        e.x, e.y, e.z, e.w, materials[MATERIAL_WORDS * i + 4u], bitcast<f32>(f.x), f.y, f.z, f.w);
}

// Light i from its eight words.
fn load_light(i: u32) -> Light {
    let a = lights[LIGHT_WORDS * i];
    let b = lights[LIGHT_WORDS * i + 1u];
    let c = lights[LIGHT_WORDS * i + 2u];
    let d = lights[LIGHT_WORDS * i + 3u];
    return Light(a.x, a.y, a.z, a.w, bitcast<vec3<f32>>(b.xyz), b.w,
        bitcast<vec3<f32>>(c.xyz), bitcast<f32>(c.w), bitcast<vec3<f32>>(d.xyz), d.w,
        lights[LIGHT_WORDS * i + 4u], lights[LIGHT_WORDS * i + 5u],
        lights[LIGHT_WORDS * i + 6u], lights[LIGHT_WORDS * i + 7u]);
}

// The first word of triangle id's uv record (gpu::types::triangle_uvs).
fn uv_record(id: u32) -> u32 {
    return select(UV_WORDS, UV_TANGENT_WORDS, HAS_TANGENTS) * id;
}

// The uv at barycentrics bc of triangle id.
fn triangle_uv(id: u32, bc: vec2<f32>) -> vec2<f32> {
    let r = uv_record(id);
    let a = uvs[r];
    let c = uvs[r + 1u].xy;
    return (1.0 - bc.x - bc.y) * a.xy + bc.x * a.zw + bc.y * c;
}
