//! Twins share names (issue 25): every function of the device's shared libraries
//! (shaders/common/*.wgsl) is listed in `TWINS` with the Rust function it mirrors (same
//! name, or the pair where a method's name reads differently on its type) and the oracle
//! test that compares them value by value, or that compares the callers it is a piece of,
//! or as a device-only helper: none is left to photon paths or whole images alone. The
//! libraries in `NOT_YET_LISTED` (their oracle tests named there) and the functions in
//! `UNCHECKED` (no oracle compares them or a caller yet) are the known exceptions. The test
//! checks that every listed name exists in its source, that no function of those libraries
//! is missing from the lists, and that docs/architecture.md's oracle table has each one's
//! row as listed here (the twin and the check included).

use gpu_photon::gpu::shaders::WGSL_FILES;
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

/// (WGSL file under shaders/, WGSL function, Rust file under src/, Rust function, check).
#[rustfmt::skip]
const TWINS: &[(&str, &str, &str, &str, Check)] = &[
    ("common/light.wgsl", "is_delta_light", "scene/mod.rs", "is_delta", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "spot_falloff", "scene/spot.rs", "falloff", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "spot_linear_mass", "scene/spot.rs", "linear_ramp_mass", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "spot_cos", "scene/spot.rs", "sample_cos", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "spot_cos_linear", "scene/spot.rs", "sample_cos", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "light_of", "photon.rs", "light_of", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "pick_triangle", "light.rs", "pick_triangle", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "light_point", "light.rs", "surface_point", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "light_disc", "light.rs", "disc", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "emit", "light.rs", "emit", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "light_solid_angle_pdf", "light.rs", "solid_angle_pdf", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "sample_light", "light.rs", "sample", Oracle("light_gpu.rs")),
    ("common/light.wgsl", "aims_at", "light.rs", "aims_at", Oracle("light_gpu.rs")),
    ("common/intersect.wgsl", "max_abs", "", "", Helper),
    ("common/intersect.wgsl", "offset_origin", "geometry.rs", "offset_origin", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "inset", "geometry.rs", "inset", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "shading_normal", "geometry.rs", "shading_normal", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "triangle_tangent", "geometry.rs", "triangle_tangent", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "vertex_tangent", "geometry.rs", "vertex_tangent", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "uv_tangent", "bvh/surface.rs", "uv_tangent", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "normal_mapped", "geometry.rs", "normal_mapped", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "facing", "bvh/surface.rs", "facing", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "reflection_leaks", "geometry.rs", "reflection_leaks", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "refraction_leaks", "geometry.rs", "refraction_leaks", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "make_shear", "geometry.rs", "new", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "shear_project", "geometry.rs", "project", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "edge_function", "geometry.rs", "edge_function", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "intersect_triangle", "geometry.rs", "intersect_triangle", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "intersect_sphere", "geometry.rs", "intersect_sphere", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "hit_box", "geometry.rs", "hit", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "sphere_uv", "texture/uv.rs", "sphere", Oracle("intersect_gpu.rs")),
    ("common/intersect.wgsl", "alpha_passes", "bvh/surface.rs", "alpha_passes", Oracle("hit_gpu.rs")),
    ("common/intersect.wgsl", "trace_ray", "bvh/mod.rs", "intersect", Oracle("intersect_gpu.rs")),
    ("common/material.wgsl", "reflect_dir", "material.rs", "reflect", Oracle("material_gpu.rs")),
    ("common/material.wgsl", "fresnel_exact", "material.rs", "fresnel_exact", Oracle("material_gpu.rs")),
    ("common/material.wgsl", "fresnel_schlick", "material.rs", "fresnel_schlick", Oracle("material_gpu.rs")),
    ("common/material.wgsl", "dielectric", "material.rs", "dielectric_shading", Oracle("material_gpu.rs")),
    ("common/material.wgsl", "max3", "", "", Helper),
    ("common/material.wgsl", "sum3", "", "", Helper),
    ("common/material.wgsl", "phong_lobe_value", "material.rs", "phong_lobe_value", Oracle("material_gpu.rs")),
    ("common/material.wgsl", "photon_bounce", "material.rs", "photon_bounce_shading", Oracle("material_gpu.rs")),
    ("common/photon.wgsl", "photon_of_words", "", "", Helper),
    ("common/photon.wgsl", "sign_not_zero", "", "", Helper),
    ("common/photon.wgsl", "pack_normal", "photon.rs", "pack_normal", Oracle("hit_gpu.rs")),
    ("common/photon.wgsl", "unpack_normal", "photon.rs", "unpack_normal", Oracle("gpu_oracle.rs")),
    ("common/photon.wgsl", "photon_faces", "estimate.rs", "photon_faces", Oracle("gpu_oracle.rs")),
    ("common/photon.wgsl", "power_ends", "photon.rs", "power_ends", Oracle("light_gpu.rs")),
    ("common/sampling.wgsl", "basis_sign", "", "", Helper),
    ("common/sampling.wgsl", "basis_t", "sampling.rs", "basis", Oracle("light_gpu.rs")),
    ("common/sampling.wgsl", "basis_b", "sampling.rs", "basis", Oracle("light_gpu.rs")),
    ("common/sampling.wgsl", "to_world", "sampling.rs", "to_world", Oracle("light_gpu.rs")),
    ("common/sampling.wgsl", "cosine_hemisphere", "sampling.rs", "cosine_hemisphere", Oracle("gpu_oracle.rs")),
    ("common/sampling.wgsl", "uniform_sphere", "sampling.rs", "uniform_sphere", Oracle("light_gpu.rs")),
    ("common/sampling.wgsl", "phong_lobe", "sampling.rs", "phong_lobe", Oracle("intersect_gpu.rs")),
    ("common/camera.wgsl", "erf_inv", "pixel_filter.rs", "erf_inv", Oracle("camera.rs")),
    ("common/camera.wgsl", "filter_offset", "pixel_filter.rs", "offset", Oracle("camera.rs")),
    ("common/camera.wgsl", "filter_jitter", "pixel_filter.rs", "jitter", Oracle("camera.rs")),
    ("common/camera.wgsl", "concentric_disc", "pixel_filter.rs", "concentric_disc", Oracle("camera.rs")),
    ("common/camera.wgsl", "camera_ray", "camera.rs", "ray", Oracle("camera.rs")),
    ("common/shading.wgsl", "bsdf_at", "shading.rs", "bsdf_at", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "gltf_textures", "shading.rs", "gltf_textures", Caller("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_is_bsdf", "", "", Helper),
    ("common/shading.wgsl", "surface_local", "shading.rs", "local", Caller("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_class", "shading.rs", "class", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_emitted", "shading.rs", "emitted", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_diffuse_albedo", "shading.rs", "diffuse_albedo", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_store_weight", "shading.rs", "store_weight", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_eval_diffuse", "shading.rs", "eval_diffuse", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_estimate_brdf", "shading.rs", "estimate_brdf", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_has_lobe", "shading.rs", "has_lobe", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_lobe_takes_point_lights", "shading.rs", "lobe_takes_point_lights", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_eval_lobe", "shading.rs", "eval_lobe", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_pdf_lobe", "shading.rs", "pdf_lobe", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_lobe_is_glossy", "shading.rs", "lobe_is_glossy", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "power_heuristic", "shading.rs", "power_heuristic", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_world_ray", "shading.rs", "world_direction", Caller("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_sample_lobe", "shading.rs", "sample_lobe", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_stores_photons", "shading.rs", "stores_photons", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_delta", "shading.rs", "delta", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "surface_photon_bounce", "shading.rs", "photon_bounce", Oracle("shading_gpu.rs")),
    ("common/shading.wgsl", "escape", "shading.rs", "escape", Oracle("shading_gpu.rs")),
    ("common/rng.wgsl", "pcg_hash", "rng.rs", "pcg_hash", Oracle("gpu_oracle.rs")),
    ("common/rng.wgsl", "path_key", "rng.rs", "path_key", Oracle("gpu_oracle.rs")),
    ("common/rng.wgsl", "draw_u32", "rng.rs", "draw_u32", Oracle("gpu_oracle.rs")),
    ("common/rng.wgsl", "to_unit", "rng.rs", "to_unit", Oracle("gpu_oracle.rs")),
    ("common/rng.wgsl", "rng_next", "rng.rs", "next", Caller("shading_gpu.rs")),
    ("common/grid.wgsl", "cell_of", "estimate.rs", "cell_of", Caller("gpu_oracle.rs")),
    ("common/grid.wgsl", "cell_gap2", "", "", Helper),
    ("common/grid.wgsl", "cell_hash", "estimate.rs", "cell_hash", Caller("gpu_oracle.rs")),
    ("common/grid.wgsl", "keep_photon", "plan.rs", "keeps", Oracle("media_gpu.rs")),
    ("common/grid.wgsl", "is_cache_point", "cpu/cache.rs", "is_cache_point", Oracle("media_gpu.rs")),
    ("common/grid.wgsl", "volume_cell", "cpu/volume_map.rs", "volume_cell", Oracle("media_gpu.rs")),
    ("common/map.wgsl", "flat_index", "", "", Helper),
    ("common/map.wgsl", "photon_word", "", "", Helper),
    ("common/map.wgsl", "copy_to_sorted", "", "", Helper),
    ("common/scene.wgsl", "spend", "", "", Helper),
    ("common/scene.wgsl", "load_triangle", "", "", Helper),
    ("common/scene.wgsl", "load_sphere", "", "", Helper),
    ("common/scene.wgsl", "load_material", "", "", Helper),
    ("common/scene.wgsl", "load_light", "", "", Helper),
    ("common/scene.wgsl", "uv_record", "", "", Helper),
    ("common/scene.wgsl", "triangle_uv", "", "", Helper),
    ("common/environment.wgsl", "env_is_map", "", "", Helper),
    ("common/environment.wgsl", "env_word", "", "", Helper),
    ("common/environment.wgsl", "env_mat", "", "", Helper),
    ("common/environment.wgsl", "latlong_uv", "scene/environment.rs", "latlong_uv", Caller("environment.rs")),
    ("common/environment.wgsl", "latlong_dir", "scene/environment.rs", "latlong_dir", Caller("environment.rs")),
    ("common/environment.wgsl", "env_lookup", "scene/environment.rs", "latlong_lookup", Caller("environment.rs")),
    ("common/environment.wgsl", "env_radiance", "scene/environment.rs", "eval", Oracle("environment.rs")),
    ("common/environment.wgsl", "env_grid", "", "", Helper),
    ("common/environment.wgsl", "env_pdf_uv", "environment.rs", "pdf_uv", Caller("environment.rs")),
    ("common/environment.wgsl", "env_sample_linear", "environment.rs", "sample_linear", Caller("environment.rs")),
    ("common/environment.wgsl", "env_sample_map", "environment.rs", "image_sample", Caller("environment.rs")),
    ("common/environment.wgsl", "env_pdf_map", "environment.rs", "image_pdf", Caller("environment.rs")),
    ("common/environment.wgsl", "env_sample", "environment.rs", "sample_direction", Oracle("environment.rs")),
    ("common/environment.wgsl", "env_pdf", "environment.rs", "direction_pdf", Oracle("environment.rs")),
    ("common/environment.wgsl", "env_emit_dir", "environment.rs", "emit_direction", Caller("light_gpu.rs")),
    ("common/medium.wgsl", "load_medium", "", "", Helper),
    ("common/medium.wgsl", "medium_after", "cpu/media.rs", "medium_after", Oracle("media_gpu.rs")),
    ("common/medium.wgsl", "light_medium", "cpu/media.rs", "light_medium", Oracle("media_gpu.rs")),
    ("common/medium.wgsl", "medium_interface_after", "medium.rs", "after", Oracle("media_gpu.rs")),
    ("common/medium.wgsl", "medium_transmittance", "medium.rs", "transmittance", Caller("media_gpu.rs")),
    ("common/medium.wgsl", "sample_flight", "medium.rs", "sample_flight", Oracle("media_gpu.rs")),
    ("common/medium.wgsl", "hg_eval", "phase.rs", "eval", Oracle("media_gpu.rs")),
    ("common/medium.wgsl", "hg_sample_cos", "phase.rs", "sample_cos", Caller("media_gpu.rs")),
    ("common/medium.wgsl", "hg_sample", "phase.rs", "sample", Oracle("media_gpu.rs")),
    ("common/texture.wgsl", "tex_rem", "", "", Helper),
    ("common/texture.wgsl", "tex_wrap", "texture/sampler.rs", "index", Caller("texture_gpu.rs")),
    ("common/texture.wgsl", "tex_coord", "", "", Helper),
    ("common/texture.wgsl", "tex_lut", "", "", Helper),
    ("common/texture.wgsl", "tex_texel", "texture/mod.rs", "texel", Caller("texture_gpu.rs")),
    ("common/texture.wgsl", "texture_eval_rgba", "", "", Helper),
    ("common/texture.wgsl", "texture_eval", "texture/mod.rs", "eval", Oracle("texture_gpu.rs")),
    ("common/texture.wgsl", "texture_alpha", "texture/mod.rs", "eval_alpha", Oracle("texture_gpu.rs")),
    ("common/estimate.wgsl", "map_word", "", "", Helper),
    ("common/estimate.wgsl", "map_photon", "", "", Helper),
    ("common/estimate.wgsl", "map_position", "", "", Helper),
    ("common/estimate.wgsl", "map_cell", "", "", Helper),
    ("common/estimate.wgsl", "heap_less", "", "", Helper),
    ("common/estimate.wgsl", "heap_d2", "", "", Helper),
    ("common/estimate.wgsl", "heap_swap", "", "", Helper),
    ("common/estimate.wgsl", "entry_less", "", "", Helper),
    ("common/estimate.wgsl", "sift_down", "", "", Helper),
    ("common/estimate.wgsl", "sift_up", "", "", Helper),
    ("common/estimate.wgsl", "kernel_weight", "estimate.rs", "kernel_weight", Caller("gpu_final_gather.rs")),
    ("common/estimate.wgsl", "kernel_norm", "estimate.rs", "kernel_norm", Caller("gpu_final_gather.rs")),
    ("common/estimate.wgsl", "heap_k", "", "", Helper),
    ("common/estimate.wgsl", "fixed_add", "", "", Helper),
    ("common/estimate.wgsl", "fixed_value", "", "", Helper),
    ("common/estimate.wgsl", "radius_scan", "", "", Helper),
    ("common/estimate.wgsl", "fixed_radius_estimate", "estimate.rs", "radiance", Caller("gpu_oracle.rs")),
    ("common/estimate.wgsl", "ring_step", "", "", Helper),
    ("common/estimate.wgsl", "knn", "cpu/photon_map.rs", "nearest", Caller("gpu_oracle.rs")),
    ("common/estimate.wgsl", "estimate", "estimate.rs", "radiance", Oracle("gpu_oracle.rs")),
    ("common/sobol.wgsl", "sobol_hash", "", "", Helper),
    ("common/sobol.wgsl", "sobol_owen_rev", "", "", Helper),
    ("common/sobol.wgsl", "sobol_shuffle", "", "", Helper),
    ("common/sobol.wgsl", "sobol_finish", "", "", Helper),
    ("common/sobol.wgsl", "sobol_rev_pair", "sobol.rs", "rev_pair", Caller("sobol.rs")),
    ("common/sobol.wgsl", "sobol_burley_sample", "", "", Helper),
    ("common/sobol.wgsl", "sobol_burley_pair", "", "", Helper),
    ("common/sobol.wgsl", "sobol_pixel_key", "sobol.rs", "pixel_key", Caller("sobol.rs")),
    ("common/sobol.wgsl", "sobol_crate_seed", "sobol.rs", "crate_seed", Caller("sobol.rs")),
    ("common/sobol.wgsl", "sobol_sample", "sobol.rs", "sample", Caller("sobol.rs")),
    ("common/sobol.wgsl", "sobol_sample_pair", "sobol.rs", "sample_pair", Caller("sobol.rs")),
    ("common/sobol.wgsl", "sobol_stream", "sobol.rs", "stream", Oracle("sobol.rs")),
    ("common/sobol.wgsl", "sobol_next", "sobol.rs", "next", Oracle("sobol.rs")),
    ("common/sobol.wgsl", "sobol_next2", "sobol.rs", "next2", Oracle("sobol.rs")),
    ("common/bsdf.wgsl", "lobe_none", "", "", Helper),
    ("common/bsdf.wgsl", "bsdf_dot", "", "", Helper),
    ("common/bsdf.wgsl", "bsdf_normalize", "", "", Helper),
    ("common/bsdf.wgsl", "safe_sqrt", "bsdf/math.rs", "safe_sqrt", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "erf", "bsdf/math.rs", "erf", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "erfinv", "bsdf/math.rs", "erfinv", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "square_to_disk_concentric", "bsdf/math.rs", "square_to_disk_concentric", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "square_to_cosine_hemisphere", "bsdf/math.rs", "square_to_cosine_hemisphere", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "cosine_hemisphere_pdf", "bsdf/math.rs", "cosine_hemisphere_pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "reflect_z", "bsdf/math.rs", "reflect_z", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "bsdf_reflect", "bsdf/math.rs", "reflect", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "bsdf_refract", "bsdf/math.rs", "refract", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mulsign", "bsdf/math.rs", "mulsign", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "flip_z", "bsdf/mod.rs", "flip_z", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "bsdf_microfacet", "", "", Helper),
    ("common/bsdf.wgsl", "mf_d", "bsdf/microfacet.rs", "d", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mf_smith_g1", "bsdf/microfacet.rs", "smith_g1", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mf_g", "bsdf/microfacet.rs", "g", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mf_sample_visible_11", "bsdf/microfacet.rs", "sample_visible_11", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mf_pdf_visible", "bsdf/microfacet.rs", "pdf_visible", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "mf_sample_visible", "bsdf/microfacet.rs", "sample_visible", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "fresnel_dielectric_mi", "bsdf/microfacet.rs", "fresnel_dielectric", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "fresnel_conductor_1", "", "", Helper),
    ("common/bsdf.wgsl", "fresnel_conductor", "bsdf/microfacet.rs", "fresnel_conductor", Oracle("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "diffuse_pdf", "bsdf/diffuse.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "diffuse_sample", "bsdf/diffuse.rs", "sample", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "conductor_eval", "bsdf/conductor.rs", "eval", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "conductor_pdf", "bsdf/conductor.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "conductor_sample", "bsdf/conductor.rs", "sample", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "conductor_sample_smooth", "bsdf/conductor.rs", "sample_smooth", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_half_vector", "bsdf/dielectric.rs", "half_vector", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_eval", "bsdf/dielectric.rs", "eval", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_pdf", "bsdf/dielectric.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_sample", "bsdf/dielectric.rs", "sample", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_sample_smooth", "bsdf/dielectric.rs", "sample_smooth", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "dielectric_sample_thin", "bsdf/dielectric.rs", "sample_thin", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_transmittance", "bsdf/plastic.rs", "transmittance", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_diffuse_out", "bsdf/plastic.rs", "diffuse_out", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_prob_specular", "bsdf/plastic.rs", "prob_specular", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_eval_lobe", "bsdf/plastic.rs", "eval_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_pdf_lobe", "bsdf/plastic.rs", "pdf_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_sample_lobe", "bsdf/plastic.rs", "sample_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_pdf", "bsdf/plastic.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf.wgsl", "plastic_sample", "bsdf/plastic.rs", "sample", Caller("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "to_front", "bsdf/mod.rs", "to_front", Caller("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "back_to_side", "bsdf/mod.rs", "back_to_side", Caller("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_is_plastic", "", "", Helper),
    ("common/bsdf_dispatch.wgsl", "bsdf_has_diffuse", "bsdf/mod.rs", "has_diffuse", Caller("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_has_lobe", "bsdf/mod.rs", "has_lobe", Caller("shading_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_lobe_is_delta", "bsdf/mod.rs", "lobe_is_delta", Caller("shading_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_eval", "bsdf/mod.rs", "eval", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_pdf", "bsdf/mod.rs", "pdf", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_sample", "bsdf/mod.rs", "sample", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_diffuse_out", "bsdf/mod.rs", "diffuse_out", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_store_weight", "bsdf/mod.rs", "store_weight", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_diffuse_value", "bsdf/mod.rs", "diffuse_value", Caller("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_eval_lobe", "bsdf/mod.rs", "eval_lobe", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_pdf_lobe", "bsdf/mod.rs", "pdf_lobe", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_sample_lobe", "bsdf/mod.rs", "sample_lobe", Oracle("bsdf_gpu.rs")),
    ("common/bsdf_dispatch.wgsl", "bsdf_lobe_probability", "bsdf/mod.rs", "lobe_probability", Caller("shading_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_schlick_weight", "bsdf/gltf.rs", "schlick_weight", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_mean", "bsdf/gltf.rs", "mean", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_max3", "", "", Helper),
    ("common/bsdf_gltf.wgsl", "gltf_schlick_mean", "bsdf/gltf.rs", "schlick_mean", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_microfacet", "bsdf/gltf.rs", "microfacet", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_diffuse_weight", "bsdf/gltf.rs", "diffuse_weight", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_dielectric_max", "bsdf/gltf.rs", "dielectric_max", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_reflect_tint", "bsdf/gltf.rs", "reflect_tint", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_transmit_tint", "bsdf/gltf.rs", "transmit_tint", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_reflect_probability", "bsdf/gltf.rs", "reflect_probability", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_diffuse_out", "bsdf/gltf.rs", "diffuse_out", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_has_diffuse", "bsdf/gltf.rs", "has_diffuse", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_half", "bsdf/gltf.rs", "half", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_eval_lobe", "bsdf/gltf.rs", "eval_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_pdf_lobe", "bsdf/gltf.rs", "pdf_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_sample_lobe", "bsdf/gltf.rs", "sample_lobe", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_lobe_probability", "bsdf/gltf.rs", "lobe_probability", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_diffuse_value", "bsdf/gltf.rs", "diffuse_value", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_pdf", "bsdf/gltf.rs", "pdf", Caller("bsdf_gpu.rs")),
    ("common/bsdf_gltf.wgsl", "gltf_sample", "bsdf/gltf.rs", "sample", Caller("bsdf_gpu.rs")),
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
    WGSL_FILES
        .iter()
        .find(|(p, _)| *p == path)
        .unwrap_or_else(|| panic!("{path} is not in WGSL_FILES"))
        .1
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

#[test]
fn every_function_of_the_shared_libraries_is_listed() {
    for &(f, src) in WGSL_FILES.iter().filter(|(p, _)| p.starts_with("common/")) {
        if let Some((_, t)) = NOT_YET_LISTED.iter().find(|(p, _)| *p == f) {
            let root = Path::new(env!("CARGO_MANIFEST_DIR"));
            assert!(root.join("tests").join(t).is_file(), "tests/{t} (for {f})");
            assert!(!TWINS.iter().any(|r| r.0 == f), "{f} is listed after all");
            continue;
        }
        for name in functions(src) {
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
