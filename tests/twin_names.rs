//! Twins share names (issue 25): every function of the device's shared libraries
//! (the WGSL libraries beside their Rust twins under src/) is listed in `TWINS` with the Rust function it mirrors (same
//! name, or the pair where a method's name reads differently on its type) and the oracle
//! test that compares them value by value, or that compares the callers it is a piece of,
//! or as a device-only helper: none is left to photon paths or whole images alone. The
//! libraries in `NOT_YET_LISTED` (their oracle tests named there) and the functions in
//! `UNCHECKED` (no oracle compares them or a caller yet) are the known exceptions. The test
//! checks that every listed name exists in its source, that no function of those libraries
//! is missing from the lists, and that docs/architecture.md's oracle table has each one's
//! row as listed here (the twin and the check included).

use gpu_photon::bsdfs::{gpu::method_suffixes, KINDS};
use gpu_photon::integrators::gpu::shaders::wgsl_files;
use gpu_photon::lights::gpu::method_suffixes as light_method_suffixes;
use gpu_photon::lights::KINDS as LIGHT_KINDS;
use std::path::Path;

/// How a device function is checked against its twin.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Check {
    /// A probe compares it value by value with the Rust twin (the named test).
    Oracle(&'static str),
    /// It has a Rust twin but is compared only inside its callers, value by value with
    /// theirs by the named test (a piece of a twin, or a step a probe does not expose).
    Caller(&'static str),
    /// A device-only helper without a Rust twin (buffer layout, or a piece of a twin).
    Helper,
}

use Check::{Caller, Helper, Oracle};

/// Libraries whose functions are not yet listed one by one, with the tests whose oracles
/// check them (per those tests' documentation). None today; a new library may wait here.
const NOT_YET_LISTED: &[(&str, &str)] = &[];

/// Functions of the listed libraries that no oracle compares yet, themselves or through a
/// caller (only photon paths or images exercise them, or nothing calls them): (WGSL file,
/// function). A function added without an oracle goes here until it has one.
const UNCHECKED: &[(&str, &str)] = &[];

/// (WGSL file under src/, WGSL function, Rust file under src/, Rust function, check).
#[rustfmt::skip]
const TWINS: &[(&str, &str, &str, &str, Check)] = &[
    ("lights/light.wgsl", "light_vec", "", "", Helper),
    ("lights/light.wgsl", "light_of", "integrators/photon.rs", "light_of", Oracle("light_gpu.rs")),
    ("lights/light.wgsl", "light_disc", "lights/interface.rs", "disc", Caller("light_gpu.rs")),
    ("lights/light.wgsl", "light_solid_angle_pdf", "lights/area.rs", "solid_angle_pdf", Oracle("light_gpu.rs")),
    ("lights/light.wgsl", "aims_at", "lights/table.rs", "aims_at", Oracle("light_gpu.rs")),
    ("lights/area.wgsl", "area_texel", "lights/area.rs", "texel", Caller("light_gpu.rs")),
    ("lights/area.wgsl", "area_emit", "lights/area.rs", "emit", Caller("light_gpu.rs")),
    ("lights/area.wgsl", "area_sample", "lights/area.rs", "sample", Caller("light_gpu.rs")),
    ("lights/triangles.wgsl", "triangles_pick", "lights/triangles.rs", "pick", Oracle("light_gpu.rs")),
    ("lights/triangles.wgsl", "triangles_point", "lights/triangles.rs", "point", Caller("light_gpu.rs")),
    ("lights/sphere.wgsl", "sphere_point", "lights/sphere.rs", "point", Caller("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_cone", "", "", Helper),
    ("lights/spot/spot.wgsl", "spot_falloff", "lights/spot/mod.rs", "falloff", Oracle("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_linear_mass", "lights/spot/mod.rs", "linear_ramp_mass", Oracle("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_cos", "lights/spot/mod.rs", "sample_cos", Oracle("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_cos_linear", "lights/spot/mod.rs", "sample_cos", Oracle("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_uv", "lights/spot/mod.rs", "spot_uv", Caller("light_gpu.rs")),
    ("lights/spot/spot.wgsl", "spot_texel", "lights/spot/mod.rs", "texel", Caller("light_gpu.rs")),
    ("lights/projector/projector.wgsl", "projector_uv", "lights/projector/mod.rs", "uv", Caller("light_gpu.rs")),
    ("lights/projector/projector.wgsl", "projector_cell", "lights/projector/distribution.rs", "pick", Caller("light_gpu.rs")),
    ("bvh/intersect.wgsl", "max_abs", "", "", Helper),
    ("bvh/intersect.wgsl", "offset_origin", "math/geometry.rs", "offset_origin", Oracle("hit_gpu.rs")),
    ("bvh/intersect.wgsl", "inset", "math/geometry.rs", "inset", Oracle("intersect_gpu.rs")),
    ("bvh/shading_frame.wgsl", "shading_normal", "math/geometry.rs", "shading_normal", Oracle("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "triangle_tangent", "math/geometry.rs", "triangle_tangent", Oracle("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "vertex_tangent", "math/geometry.rs", "vertex_tangent", Oracle("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "uv_tangent", "bvh/surface.rs", "uv_tangent", Oracle("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "orthogonal_tangent", "math/geometry.rs", "orthogonal_tangent", Caller("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "shading_tangent", "math/geometry.rs", "shading_tangent", Caller("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "normal_mapped", "math/geometry.rs", "normal_mapped", Oracle("intersect_gpu.rs")),
    ("bvh/shading_frame.wgsl", "uv_jacobian", "math/geometry.rs", "uv_jacobian", Caller("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "sphere_partials", "math/geometry.rs", "sphere_partials", Caller("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "bump_mapped", "math/geometry.rs", "bump_mapped", Oracle("intersect_gpu.rs")),
    ("bvh/shading_frame.wgsl", "bump_tangent", "math/geometry.rs", "bump_tangent", Caller("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "facing", "bvh/hit.rs", "facing", Oracle("hit_gpu.rs")),
    ("bvh/shading_frame.wgsl", "reflection_leaks", "math/geometry.rs", "reflection_leaks", Oracle("intersect_gpu.rs")),
    ("bvh/shading_frame.wgsl", "refraction_leaks", "math/geometry.rs", "refraction_leaks", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "make_shear", "math/geometry.rs", "new", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "shear_project", "math/geometry.rs", "project", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "edge_function", "math/geometry.rs", "edge_function", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "intersect_triangle", "math/geometry.rs", "intersect_triangle", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "intersect_sphere", "math/geometry.rs", "intersect_sphere", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "hit_box", "math/geometry.rs", "hit", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "sphere_rotate", "scene/shapes.rs", "rotate", Caller("hit_gpu.rs")),
    ("bvh/intersect.wgsl", "sphere_frame", "", "", Helper),
    ("bvh/intersect.wgsl", "sphere_uv", "textures/uv.rs", "sphere", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "alpha_passes", "bvh/surface.rs", "alpha_passes", Oracle("hit_gpu.rs")),
    ("bvh/intersect.wgsl", "trace_ray", "bvh/mod.rs", "intersect", Oracle("intersect_gpu.rs")),
    ("bvh/intersect.wgsl", "dominant_axis", "", "", Helper),
    ("bvh/intersect.wgsl", "next_leaf", "", "", Helper),
    ("bvh/intersect.wgsl", "leaf_hits", "", "", Helper),
    ("bvh/intersect.wgsl", "walk_bvh", "bvh/mod.rs", "closest", Caller("intersect_gpu.rs")),
    ("bvh/gpu_wide.wgsl", "slabs4", "", "", Helper),
    ("bvh/gpu_wide.wgsl", "walk_wide", "bvh/mod.rs", "closest", Oracle("intersect_gpu.rs")),
    ("bvh/instances.wgsl", "affine_row", "", "", Helper),
    ("bvh/instances.wgsl", "affine_point", "", "", Helper),
    ("bvh/instances.wgsl", "affine_vector", "", "", Helper),
    ("bvh/instances.wgsl", "affine_normal", "", "", Helper),
    ("bvh/instances.wgsl", "walk_instances", "bvh/instances.rs", "closest", Caller("instancing.rs")),
    ("scene/sdf_grid.wgsl", "sdf_word", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_point", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_vector", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_cells", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_slab", "scene/sdf_grid.rs", "slab", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_solve_quadratic", "scene/sdf_grid.rs", "solve_quadratic", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_cubic", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_solve_cubic", "scene/sdf_grid.rs", "solve_cubic", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_intersect_cell", "scene/sdf_grid.rs", "intersect_cell", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_voxel", "scene/sdf_grid.rs", "value", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_value_at", "scene/sdf_grid.rs", "value_at", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_cell_gradient", "scene/sdf_grid.rs", "cell_gradient", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_round", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_smooth_normal", "scene/sdf_grid.rs", "smooth_normal", Caller("sdf_grid.rs")),
    ("scene/sdf_grid.wgsl", "sdf_normalize", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_normal", "", "", Helper),
    ("scene/sdf_grid.wgsl", "sdf_surface", "scene/sdf_grid.rs", "surface_at", Caller("sdf_grid.rs")),
    ("integrators/gpu/photon.wgsl", "photon_of_words", "", "", Helper),
    ("integrators/gpu/photon.wgsl", "sign_not_zero", "", "", Helper),
    ("integrators/gpu/photon.wgsl", "pack_normal", "integrators/photon.rs", "pack_normal", Oracle("hit_gpu.rs")),
    ("integrators/gpu/photon.wgsl", "unpack_normal", "integrators/photon.rs", "unpack_normal", Oracle("gpu_oracle.rs")),
    ("integrators/gpu/photon.wgsl", "photon_faces", "integrators/estimate.rs", "photon_faces", Oracle("gpu_oracle.rs")),
    ("integrators/gpu/photon.wgsl", "power_ends", "integrators/photon.rs", "power_ends", Oracle("light_gpu.rs")),
    ("math/sampling.wgsl", "basis_sign", "", "", Helper),
    ("math/sampling.wgsl", "basis_t", "math/sampling.rs", "basis", Oracle("light_gpu.rs")),
    ("math/sampling.wgsl", "basis_b", "math/sampling.rs", "basis", Oracle("light_gpu.rs")),
    ("math/sampling.wgsl", "to_world", "math/sampling.rs", "to_world", Oracle("light_gpu.rs")),
    ("math/sampling.wgsl", "cosine_hemisphere", "math/sampling.rs", "cosine_hemisphere", Oracle("gpu_oracle.rs")),
    ("math/sampling.wgsl", "uniform_sphere", "math/sampling.rs", "uniform_sphere", Oracle("light_gpu.rs")),
    ("math/sampling.wgsl", "phong_lobe", "math/sampling.rs", "phong_lobe", Oracle("intersect_gpu.rs")),
    ("camera/camera.wgsl", "erf_inv", "camera/pixel_filter.rs", "erf_inv", Oracle("camera.rs")),
    ("camera/camera.wgsl", "filter_offset", "camera/pixel_filter.rs", "offset", Oracle("camera.rs")),
    ("camera/camera.wgsl", "filter_jitter", "camera/pixel_filter.rs", "jitter", Oracle("camera.rs")),
    ("camera/camera.wgsl", "concentric_disc", "camera/pixel_filter.rs", "concentric_disc", Oracle("camera.rs")),
    ("camera/camera.wgsl", "camera_ray", "camera/mod.rs", "ray", Oracle("camera.rs")),
    ("bsdfs/shading.wgsl", "bsdf_at", "bsdfs/shading.rs", "bsdf_at", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_stores", "bsdfs/shading.rs", "stores_photons", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "terminator", "bsdfs/material.rs", "terminator", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_shadowing", "bsdfs/shading.rs", "shadowing", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_store_weight", "bsdfs/shading.rs", "store_weight", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_eval_diffuse", "bsdfs/shading.rs", "eval_diffuse", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_eval_lobe", "bsdfs/shading.rs", "eval_lobe", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_sample_lobe", "bsdfs/shading.rs", "sample_lobe", Oracle("shading_gpu.rs")),
    ("bsdfs/blend.wgsl", "blend_u", "bsdfs/blend.rs", "blend_u", Caller("shading_gpu.rs")),
    ("bsdfs/blend.wgsl", "blend_choose", "bsdfs/blend.rs", "choose", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "frame_tangent", "bsdfs/interface.rs", "new", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_local", "bsdfs/interface.rs", "local", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_world", "bsdfs/interface.rs", "world", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_class", "bsdfs/shading.rs", "class", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_emitted", "bsdfs/shading.rs", "emitted", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_estimate_brdf", "bsdfs/shading.rs", "estimate_brdf", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "power_heuristic", "bsdfs/shading.rs", "power_heuristic", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_world_ray", "bsdfs/interface.rs", "world_direction", Caller("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "surface_delta", "bsdfs/shading.rs", "delta", Oracle("shading_gpu.rs")),
    ("bsdfs/shading.wgsl", "escape", "bsdfs/shading.rs", "escape", Oracle("shading_gpu.rs")),
    ("bsdfs/math.wgsl", "bsdf_dot", "", "", Helper),
    ("bsdfs/math.wgsl", "bsdf_normalize", "", "", Helper),
    ("bsdfs/math.wgsl", "safe_sqrt", "bsdfs/math.rs", "safe_sqrt", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "erf", "bsdfs/math.rs", "erf", Oracle("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "erfinv", "bsdfs/math.rs", "erfinv", Oracle("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "square_to_disk_concentric", "bsdfs/math.rs", "square_to_disk_concentric", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "square_to_cosine_hemisphere", "bsdfs/math.rs", "square_to_cosine_hemisphere", Oracle("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "cosine_hemisphere_pdf", "bsdfs/math.rs", "cosine_hemisphere_pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "reflect_z", "bsdfs/math.rs", "reflect_z", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "bsdf_reflect", "bsdfs/math.rs", "reflect", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "bsdf_refract", "bsdfs/math.rs", "refract", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "mulsign", "bsdfs/math.rs", "mulsign", Caller("bsdf_gpu.rs")),
    ("bsdfs/math.wgsl", "flip_z", "bsdfs/interface.rs", "flip_z", Caller("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_d", "bsdfs/microfacet.rs", "d", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_smith_g1", "bsdfs/microfacet.rs", "smith_g1", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_g", "bsdfs/microfacet.rs", "g", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_sample_visible_11", "bsdfs/microfacet.rs", "sample_visible_11", Caller("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_pdf_visible", "bsdfs/microfacet.rs", "pdf_visible", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "mf_sample_visible", "bsdfs/microfacet.rs", "sample_visible", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "fresnel_dielectric_mi", "bsdfs/microfacet.rs", "fresnel_dielectric", Oracle("bsdf_gpu.rs")),
    ("bsdfs/microfacet.wgsl", "fresnel_conductor_1", "", "", Helper),
    ("bsdfs/microfacet.wgsl", "fresnel_conductor", "bsdfs/microfacet.rs", "fresnel_conductor", Oracle("bsdf_gpu.rs")),
    ("bsdfs/fresnel.wgsl", "reflect_dir", "bsdfs/fresnel.rs", "reflect", Oracle("material_gpu.rs")),
    ("bsdfs/fresnel.wgsl", "fresnel_exact", "bsdfs/fresnel.rs", "fresnel_exact", Oracle("material_gpu.rs")),
    ("bsdfs/fresnel.wgsl", "fresnel_schlick", "bsdfs/fresnel.rs", "fresnel_schlick", Oracle("material_gpu.rs")),
    ("bsdfs/fresnel.wgsl", "dielectric", "bsdfs/fresnel.rs", "dielectric_shading", Oracle("material_gpu.rs")),
    ("bsdfs/fresnel.wgsl", "max3", "", "", Helper),
    ("bsdfs/fresnel.wgsl", "sum3", "", "", Helper),
    ("bsdfs/param.wgsl", "param_eval", "bsdfs/param.rs", "eval", Caller("bsdf_gpu.rs")),
    ("bsdfs/param.wgsl", "w_rgb", "", "", Helper),
    ("bsdfs/param.wgsl", "w_f", "", "", Helper),
    ("bsdfs/interface.wgsl", "lobe_none", "", "", Helper),
    ("bsdfs/interface.wgsl", "to_front", "bsdfs/interface.rs", "to_front", Caller("bsdf_gpu.rs")),
    ("bsdfs/interface.wgsl", "back_to_side", "bsdfs/interface.rs", "back_to_side", Caller("bsdf_gpu.rs")),
    ("bsdfs/conductor.wgsl", "conductor_smooth_sample", "bsdfs/conductor.rs", "sample_smooth", Caller("bsdf_gpu.rs")),
    ("bsdfs/diffuse.wgsl", "diffuse_front_pdf", "bsdfs/diffuse.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/glass.wgsl", "glass_smooth_sample", "bsdfs/glass.rs", "sample_smooth", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "mr_params", "", "", Helper),
    ("bsdfs/metallic_roughness.wgsl", "gltf_schlick_weight", "bsdfs/metallic_roughness.rs", "schlick_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_mean", "bsdfs/metallic_roughness.rs", "mean", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_max3", "", "", Helper),
    ("bsdfs/metallic_roughness.wgsl", "gltf_schlick_mean", "bsdfs/metallic_roughness.rs", "schlick_mean", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_microfacet", "bsdfs/metallic_roughness.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_diffuse_weight", "bsdfs/metallic_roughness.rs", "diffuse_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_dielectric_max", "bsdfs/metallic_roughness.rs", "dielectric_max", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_reflect_tint", "bsdfs/metallic_roughness.rs", "reflect_tint", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_transmit_tint", "bsdfs/metallic_roughness.rs", "transmit_tint", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_reflect_probability", "bsdfs/metallic_roughness.rs", "reflect_probability", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_diffuse_out", "bsdfs/metallic_roughness.rs", "diffuse_out", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_has_diffuse", "bsdfs/metallic_roughness.rs", "has_diffuse", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_half", "bsdfs/metallic_roughness.rs", "half", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_eval_lobe", "bsdfs/metallic_roughness.rs", "eval_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_pdf_lobe", "bsdfs/metallic_roughness.rs", "pdf_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_sample_lobe", "bsdfs/metallic_roughness.rs", "sample_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_lobe_probability", "bsdfs/metallic_roughness.rs", "lobe_probability", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_diffuse_value", "bsdfs/metallic_roughness.rs", "front_diffuse_value", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_pdf", "bsdfs/metallic_roughness.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/metallic_roughness.wgsl", "gltf_sample", "bsdfs/metallic_roughness.rs", "sample", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "principled_params", "", "", Helper),
    ("bsdfs/principled.wgsl", "pr_luminance", "bsdfs/principled_terms.rs", "luminance", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_calc_schlick", "bsdfs/principled_terms.rs", "calc_schlick", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_disney_diffuse", "bsdfs/principled_terms.rs", "disney_diffuse", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_gtr1_d", "bsdfs/principled_terms.rs", "gtr1_d", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_gtr1_sample", "bsdfs/principled_terms.rs", "gtr1_sample", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_smith_ggx1", "bsdfs/principled_terms.rs", "smith_ggx1", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_compatible", "bsdfs/principled_terms.rs", "compatible", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_weights", "bsdfs/principled.rs", "weights", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_microfacet", "bsdfs/principled.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_brdf", "bsdfs/principled.rs", "brdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_bsdf", "bsdfs/principled.rs", "bsdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_tint", "bsdfs/principled.rs", "tint", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_fresnel", "bsdfs/principled.rs", "fresnel_p", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_clearcoat_alpha", "bsdfs/principled.rs", "clearcoat_alpha", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_half_schlick", "bsdfs/principled.rs", "half_schlick", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_diffuse_weight", "bsdfs/principled.rs", "diffuse_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_parts", "bsdfs/principled.rs", "parts", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_pdf_with", "bsdfs/principled.rs", "pdf_with", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_choice", "bsdfs/principled.rs", "choice", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_sample_with", "bsdfs/principled.rs", "sample_with", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_remainder_weight", "bsdfs/principled.rs", "remainder_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_full_weight", "bsdfs/principled.rs", "full_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled.wgsl", "pr_oriented", "bsdfs/principled.rs", "oriented", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "principled_thin_params", "", "", Helper),
    ("bsdfs/principled_thin.wgsl", "pt_distribution", "bsdfs/principled_thin.rs", "distribution", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_microfacet", "bsdfs/principled_thin.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_transmission_microfacet", "bsdfs/principled_thin.rs", "transmission_microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_dt", "bsdfs/principled_thin.rs", "dt", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_brdf", "bsdfs/principled_thin.rs", "brdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_diffuse_weight", "bsdfs/principled_thin.rs", "diffuse_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_tint", "bsdfs/principled_thin.rs", "tint", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_half", "bsdfs/principled_thin.rs", "half", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_parts", "bsdfs/principled_thin.rs", "parts", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_probabilities", "bsdfs/principled_thin.rs", "probabilities", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_pdf_with", "bsdfs/principled_thin.rs", "pdf_with", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_sample_with", "bsdfs/principled_thin.rs", "sample_with", Caller("bsdf_gpu.rs")),
    ("bsdfs/principled_thin.wgsl", "pt_cos_weight", "bsdfs/principled_thin.rs", "cos_weight", Caller("bsdf_gpu.rs")),
    ("bsdfs/phong.wgsl", "phong_lobe_value", "bsdfs/phong.rs", "phong_lobe_value", Oracle("material_gpu.rs")),
    ("bsdfs/phong.wgsl", "phong_pdf_value", "bsdfs/phong.rs", "phong_pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/phong.wgsl", "classic_bounce", "bsdfs/phong.rs", "classic_bounce", Oracle("material_gpu.rs")),
    ("bsdfs/phong.wgsl", "phong_lobe_choice", "bsdfs/phong.rs", "lobe_choice", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_params", "", "", Helper),
    ("bsdfs/plastic.wgsl", "plastic_transmittance", "bsdfs/plastic.rs", "transmittance", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_diffuse_out", "bsdfs/plastic.rs", "front_diffuse_out", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_prob_specular", "bsdfs/plastic.rs", "prob_specular", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_eval_lobe", "bsdfs/plastic.rs", "front_eval_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_pdf_lobe", "bsdfs/plastic.rs", "front_pdf_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_sample_lobe", "bsdfs/plastic.rs", "front_sample_lobe", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_pdf", "bsdfs/plastic.rs", "front_pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/plastic.wgsl", "plastic_front_sample", "bsdfs/plastic.rs", "front_sample", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_conductor.wgsl", "rough_conductor_microfacet", "bsdfs/rough_conductor.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_conductor.wgsl", "rough_conductor_front_eval", "bsdfs/rough_conductor.rs", "eval", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_conductor.wgsl", "rough_conductor_front_pdf", "bsdfs/rough_conductor.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_conductor.wgsl", "rough_conductor_front_sample", "bsdfs/rough_conductor.rs", "sample", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_dielectric.wgsl", "rough_dielectric_microfacet", "bsdfs/rough_dielectric.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_dielectric.wgsl", "rough_dielectric_half_vector", "bsdfs/rough_dielectric.rs", "half_vector", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_dielectric.wgsl", "rough_dielectric_front_eval", "bsdfs/rough_dielectric.rs", "eval", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_dielectric.wgsl", "rough_dielectric_front_pdf", "bsdfs/rough_dielectric.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("bsdfs/rough_dielectric.wgsl", "rough_dielectric_front_sample", "bsdfs/rough_dielectric.rs", "sample", Caller("bsdf_gpu.rs")),
    ("bsdfs/thin_dielectric.wgsl", "thin_dielectric_front_sample", "bsdfs/thin_dielectric.rs", "sample_thin", Caller("bsdf_gpu.rs")),
    ("math/rng.wgsl", "pcg_hash", "math/rng.rs", "pcg_hash", Oracle("gpu_oracle.rs")),
    ("math/rng.wgsl", "path_key", "math/rng.rs", "path_key", Oracle("gpu_oracle.rs")),
    ("math/rng.wgsl", "draw_u32", "math/rng.rs", "draw_u32", Oracle("gpu_oracle.rs")),
    ("math/rng.wgsl", "to_unit", "math/rng.rs", "to_unit", Oracle("gpu_oracle.rs")),
    ("math/rng.wgsl", "rng_next", "math/rng.rs", "next", Caller("shading_gpu.rs")),
    ("integrators/gpu/grid.wgsl", "cell_of", "integrators/estimate.rs", "cell_of", Caller("gpu_oracle.rs")),
    ("integrators/gpu/grid.wgsl", "cell_gap2", "", "", Helper),
    ("integrators/gpu/grid.wgsl", "cell_hash", "integrators/estimate.rs", "cell_hash", Caller("gpu_oracle.rs")),
    ("integrators/gpu/grid.wgsl", "keep_photon", "integrators/plan.rs", "keeps", Oracle("media_gpu.rs")),
    ("integrators/gpu/grid.wgsl", "is_cache_point", "integrators/cpu/cache.rs", "is_cache_point", Oracle("media_gpu.rs")),
    ("integrators/gpu/grid.wgsl", "volume_cell", "integrators/cpu/volume_map.rs", "volume_cell", Oracle("media_gpu.rs")),
    ("integrators/gpu/map.wgsl", "flat_index", "", "", Helper),
    ("integrators/gpu/map.wgsl", "photon_word", "", "", Helper),
    ("integrators/gpu/map.wgsl", "copy_to_sorted", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "spend", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "load_triangle", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "load_sphere", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "load_material", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "load_light", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "uv_record", "", "", Helper),
    ("integrators/gpu/scene.wgsl", "triangle_uv", "", "", Helper),
    ("lights/environment/environment.wgsl", "env_is_map", "", "", Helper),
    ("lights/environment/environment.wgsl", "env_word", "", "", Helper),
    ("lights/environment/environment.wgsl", "env_mat", "", "", Helper),
    ("lights/environment/environment.wgsl", "latlong_uv", "lights/environment/mod.rs", "latlong_uv", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "latlong_dir", "lights/environment/mod.rs", "latlong_dir", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_lookup", "lights/environment/mod.rs", "latlong_lookup", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_radiance", "lights/environment/mod.rs", "eval", Oracle("environment.rs")),
    ("lights/environment/environment.wgsl", "env_grid", "", "", Helper),
    ("lights/environment/environment.wgsl", "env_pdf_uv", "lights/environment/sampling.rs", "pdf_uv", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_sample_linear", "lights/environment/sampling.rs", "sample_linear", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_sample_map", "lights/environment/sampling.rs", "image_sample", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_pdf_map", "lights/environment/sampling.rs", "image_pdf", Caller("environment.rs")),
    ("lights/environment/environment.wgsl", "env_sample", "lights/environment/sampling.rs", "sample_direction", Oracle("environment.rs")),
    ("lights/environment/environment.wgsl", "env_pdf", "lights/environment/sampling.rs", "direction_pdf", Oracle("environment.rs")),
    ("lights/environment/environment.wgsl", "env_emit_dir", "lights/environment/sampling.rs", "emit_direction", Caller("light_gpu.rs")),
    ("media/medium.wgsl", "load_medium", "", "", Helper),
    ("media/medium.wgsl", "medium_after", "integrators/cpu/media.rs", "medium_after", Oracle("media_gpu.rs")),
    ("media/medium.wgsl", "light_medium", "integrators/cpu/media.rs", "light_medium", Oracle("media_gpu.rs")),
    ("media/medium.wgsl", "photon_medium", "integrators/cpu/media.rs", "photon_medium", Caller("media_gpu.rs")),
    ("media/medium.wgsl", "enclosing_medium", "integrators/cpu/media.rs", "enclosing_medium", Caller("media_gpu.rs")),
    ("media/medium.wgsl", "medium_interface_after", "media/mod.rs", "after", Oracle("media_gpu.rs")),
    ("media/medium.wgsl", "medium_transmittance", "media/mod.rs", "transmittance", Caller("media_gpu.rs")),
    ("media/medium.wgsl", "sample_flight", "media/mod.rs", "sample_flight", Oracle("media_gpu.rs")),
    ("media/medium.wgsl", "medium_transmittance_along", "media/mod.rs", "transmittance_along", Caller("hetero_gpu.rs")),
    ("media/medium.wgsl", "medium_flight", "media/mod.rs", "flight", Caller("media_gpu.rs")),
    ("media/medium.wgsl", "hg_eval", "media/phase.rs", "eval", Oracle("media_gpu.rs")),
    ("media/medium.wgsl", "hg_sample_cos", "media/phase.rs", "sample_cos", Caller("media_gpu.rs")),
    ("media/medium.wgsl", "hg_sample", "media/phase.rs", "sample", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "media_f32", "", "", Helper),
    ("media/heterogeneous.wgsl", "media_u32", "", "", Helper),
    ("media/heterogeneous.wgsl", "media_vec3", "", "", Helper),
    ("media/heterogeneous.wgsl", "hetero_record", "", "", Helper),
    ("media/heterogeneous.wgsl", "volume_voxel", "media/grid.rs", "voxel", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "volume_index", "", "", Helper),
    ("media/heterogeneous.wgsl", "grid_lookup", "media/grid.rs", "lookup", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "volume_eval", "media/grid.rs", "eval", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_sigma_t_at", "media/heterogeneous.rs", "sigma_t_at", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_sigma_s_at", "media/heterogeneous.rs", "sigma_s_at", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_span", "media/heterogeneous.rs", "span", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "majorant_walk_start", "media/majorant.rs", "walk", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "majorant_walk_next", "media/majorant.rs", "walk", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "tracking_next", "media/heterogeneous.rs", "collisions", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_transmittance", "media/heterogeneous.rs", "transmittance", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_track", "media/heterogeneous.rs", "track", Caller("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "hetero_sample_flight", "media/heterogeneous.rs", "sample_flight", Oracle("media_gpu.rs")),
    ("media/heterogeneous.wgsl", "replay_draw", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_start", "media/heterogeneous.rs", "steps", Caller("hetero_gpu.rs")),
    ("media/heterogeneous.wgsl", "replay_apply", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_next", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_skip", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_fill", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_set", "", "", Helper),
    ("media/heterogeneous.wgsl", "replay_at", "media/mod.rs", "at", Caller("hetero_gpu.rs")),
    ("textures/texture.wgsl", "tex_rem", "", "", Helper),
    ("textures/texture.wgsl", "tex_wrap", "textures/sampler.rs", "index", Caller("texture_gpu.rs")),
    ("textures/texture.wgsl", "tex_coord", "", "", Helper),
    ("textures/texture.wgsl", "tex_lut", "", "", Helper),
    ("textures/texture.wgsl", "tex_texel", "textures/mod.rs", "texel", Caller("texture_gpu.rs")),
    ("textures/texture.wgsl", "tex_quad", "textures/mod.rs", "quad", Caller("texture_gpu.rs")),
    ("textures/texture.wgsl", "tex_uv", "textures/sampler.rs", "apply", Caller("texture_gpu.rs")),
    ("textures/texture.wgsl", "texture_eval_rgba", "", "", Helper),
    ("textures/texture.wgsl", "texture_eval", "textures/mod.rs", "eval", Oracle("texture_gpu.rs")),
    ("textures/texture.wgsl", "texture_alpha", "textures/mod.rs", "eval_alpha", Oracle("texture_gpu.rs")),
    ("textures/texture.wgsl", "texture_grad", "textures/mod.rs", "eval_grad", Oracle("texture_gpu.rs")),
    ("integrators/estimate.wgsl", "map_word", "", "", Helper),
    ("integrators/estimate.wgsl", "map_photon", "", "", Helper),
    ("integrators/estimate.wgsl", "map_position", "", "", Helper),
    ("integrators/estimate.wgsl", "map_cell", "", "", Helper),
    ("integrators/estimate.wgsl", "heap_less", "", "", Helper),
    ("integrators/estimate.wgsl", "heap_d2", "", "", Helper),
    ("integrators/estimate.wgsl", "heap_swap", "", "", Helper),
    ("integrators/estimate.wgsl", "entry_less", "", "", Helper),
    ("integrators/estimate.wgsl", "sift_down", "", "", Helper),
    ("integrators/estimate.wgsl", "sift_up", "", "", Helper),
    ("integrators/estimate.wgsl", "kernel_weight", "integrators/estimate.rs", "kernel_weight", Caller("gpu_final_gather.rs")),
    ("integrators/estimate.wgsl", "kernel_norm", "integrators/estimate.rs", "kernel_norm", Caller("gpu_final_gather.rs")),
    ("integrators/estimate.wgsl", "heap_k", "", "", Helper),
    ("integrators/estimate.wgsl", "fixed_add", "", "", Helper),
    ("integrators/estimate.wgsl", "fixed_value", "", "", Helper),
    ("integrators/estimate.wgsl", "radius_scan", "", "", Helper),
    ("integrators/estimate.wgsl", "fixed_radius_estimate", "integrators/estimate.rs", "radiance", Caller("gpu_oracle.rs")),
    ("integrators/estimate.wgsl", "ring_step", "", "", Helper),
    ("integrators/estimate.wgsl", "knn", "integrators/cpu/photon_map.rs", "nearest", Caller("gpu_oracle.rs")),
    ("integrators/estimate.wgsl", "estimate", "integrators/estimate.rs", "radiance", Oracle("gpu_oracle.rs")),
    ("math/sobol.wgsl", "sobol_hash", "", "", Helper),
    ("math/sobol.wgsl", "sobol_owen_rev", "", "", Helper),
    ("math/sobol.wgsl", "sobol_shuffle", "", "", Helper),
    ("math/sobol.wgsl", "sobol_finish", "", "", Helper),
    ("math/sobol.wgsl", "sobol_rev_pair", "math/sobol.rs", "rev_pair", Caller("sobol.rs")),
    ("math/sobol.wgsl", "sobol_burley_sample", "", "", Helper),
    ("math/sobol.wgsl", "sobol_burley_pair", "", "", Helper),
    ("math/sobol.wgsl", "sobol_pixel_key", "math/sobol.rs", "pixel_key", Caller("sobol.rs")),
    ("math/sobol.wgsl", "sobol_crate_seed", "math/sobol.rs", "crate_seed", Caller("sobol.rs")),
    ("math/sobol.wgsl", "sobol_sample", "math/sobol.rs", "sample", Caller("sobol.rs")),
    ("math/sobol.wgsl", "sobol_sample_pair", "math/sobol.rs", "sample_pair", Caller("sobol.rs")),
    ("math/sobol.wgsl", "sobol_stream", "math/sobol.rs", "stream", Oracle("sobol.rs")),
    ("math/sobol.wgsl", "sobol_next", "math/sobol.rs", "next", Oracle("sobol.rs")),
    ("math/sobol.wgsl", "sobol_next2", "math/sobol.rs", "next2", Oracle("sobol.rs")),
];

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Whether `src` declares a function `name` (`fn name(` or `fn name<`).
fn declares(src: &str, name: &str) -> bool {
    [format!("fn {name}("), format!("fn {name}<")]
        .iter()
        .any(|d| src.contains(d.as_str()))
}

fn wgsl(path: &str) -> &'static str {
    wgsl_files()
        .into_iter()
        .find(|(p, _)| p == path)
        .unwrap_or_else(|| panic!("{path} is not composed (shaders::wgsl_files)"))
        .1
}

/// Whether `name` in the BSDF or light file `path` implements a method of its interface: a
/// light kind's (`spot_emit` in `lights/spot/spot.wgsl`, checked for every kind of
/// `lights::KINDS` by `tests/light_gpu.rs`) or its default (`light_default_emit`), or for the
/// BSDFs
/// default (`default_eval_lobe` in `bsdfs/interface.wgsl`, `default_surface_delta` in
/// `bsdfs/shading.wgsl`) or a kind's own (`plastic_eval_lobe` in `bsdfs/plastic.wgsl`). The
/// generated dispatch calls them, and `tests/bsdf_gpu.rs` (the BSDF's methods) and
/// `tests/shading_gpu.rs` (the surface's) compare them with the Rust union's for every kind
/// of `bsdfs::KINDS`: they need no row of their own.
fn implements_interface(path: &str, name: &str) -> bool {
    let light_method = |suffix: &str| light_method_suffixes().contains(&suffix);
    if let Some(suffix) = name.strip_prefix("light_default_") {
        return path == "lights/light.wgsl" && light_method(suffix);
    }
    let light_kind = LIGHT_KINDS.iter().any(|k| {
        path == k.path
            && name
                .strip_prefix(k.prefix)
                .and_then(|rest| rest.strip_prefix('_'))
                .is_some_and(light_method)
    });
    if light_kind {
        return true;
    }
    let method = |suffix: &str| method_suffixes().contains(&suffix);
    if let Some(suffix) = name.strip_prefix("default_") {
        return path.starts_with("bsdfs/") && method(suffix);
    }
    KINDS.iter().any(|k| {
        path == format!("bsdfs/{}.wgsl", k.prefix)
            && name
                .strip_prefix(k.prefix)
                .and_then(|rest| rest.strip_prefix('_'))
                .is_some_and(method)
    })
}

#[test]
fn every_twin_named_exists_and_has_its_check() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for &(wf, wname, rf, rname, check) in TWINS {
        assert!(declares(wgsl(wf), wname), "{wf} declares no fn {wname}");
        if check == Helper {
            assert!(rf.is_empty() && rname.is_empty());
            continue;
        }
        let src = read(&root.join("src").join(rf));
        assert!(
            declares(&src, rname),
            "src/{rf} declares no fn {rname} (twin of {wname})"
        );
        let (Oracle(t) | Caller(t)) = check else {
            unreachable!()
        };
        assert!(
            root.join("tests").join(t).is_file(),
            "tests/{t} (for {wname})"
        );
    }
}

/// The functions `src` declares at the start of a line.
fn functions(src: &str) -> impl Iterator<Item = &str> {
    src.lines()
        .filter_map(|l| l.strip_prefix("fn "))
        .map(|rest| rest.split(['(', '<']).next().unwrap())
}

/// Whether the WGSL file at `path` (under src/) is a shared library: one beside its Rust twin,
/// or the GPU backend's own libraries (its structs, bindings, photon and grid helpers), not a
/// part of a kernel family.
fn is_library(path: &str) -> bool {
    // The benchmarks' kernels are entry points, as the integrators' are.
    if path.starts_with("bench/") {
        return false;
    }
    match path.strip_prefix("integrators/gpu/") {
        Some(f) => [
            "types.wgsl",
            "scene.wgsl",
            "photon.wgsl",
            "grid.wgsl",
            "map.wgsl",
        ]
        .contains(&f),
        None => true,
    }
}

#[test]
fn every_function_of_the_shared_libraries_is_listed() {
    let files = wgsl_files();
    for (f, src) in files.iter().filter(|(p, _)| is_library(p)) {
        let f = f.as_str();
        if let Some((_, t)) = NOT_YET_LISTED.iter().find(|(p, _)| *p == f) {
            let root = Path::new(env!("CARGO_MANIFEST_DIR"));
            assert!(root.join("tests").join(t).is_file(), "tests/{t} (for {f})");
            assert!(!TWINS.iter().any(|r| r.0 == f), "{f} is listed after all");
            continue;
        }
        for name in functions(src) {
            if implements_interface(f, name) {
                continue;
            }
            let listed = TWINS.iter().any(|t| t.0 == f && t.1 == name);
            let unchecked = UNCHECKED.contains(&(f, name));
            assert!(
                listed != unchecked,
                "{f}: fn {name} must be in exactly one of TWINS (its Rust twin and oracle) and \
                 UNCHECKED"
            );
        }
    }
    for &(f, name) in UNCHECKED {
        assert!(declares(wgsl(f), name), "{f} declares no fn {name}");
    }
}

#[test]
fn the_architecture_doc_names_every_twin() {
    let doc = read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/architecture.md"));
    for &(wf, wname, rf, rname, check) in TWINS {
        let twin = match check {
            Helper => "device-only helper".to_string(),
            _ => format!("`{rf}`: `{rname}`"),
        };
        let how = match check {
            Oracle(t) => format!("oracle, `tests/{t}`"),
            Caller(t) => format!("through its callers, `tests/{t}`"),
            Helper => "through its callers".to_string(),
        };
        let row = format!("| `{wf}` | `{wname}` | {twin} | {how} |");
        assert!(
            doc.lines().any(|l| l == row),
            "docs/architecture.md's oracle table lacks the row {row}"
        );
    }
}
