//! Twins share names (issue 25): every function of the device's shared libraries for the
//! lights, intersection, the classic materials, photons, sampling and the camera
//! (shaders/common/light.wgsl, intersect.wgsl, material.wgsl, photon.wgsl, sampling.wgsl,
//! camera.wgsl) is listed in `TWINS` with the
//! Rust function it mirrors (same name, or the pair where a method's name reads differently
//! on its type) and the oracle test that compares them value by value, or as a device-only
//! helper: none is left to photon paths or whole images alone. The test checks
//! that every listed name exists in its source, that no function of those libraries is
//! missing from the list, and that docs/architecture.md's oracle table has each one's row
//! as listed here (the twin and the check included).

use gpu_photon::gpu::shaders::WGSL_FILES;
use std::path::Path;

/// How a device function is checked against its twin.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Check {
    /// A probe compares it value by value with the Rust twin (the named test).
    Oracle(&'static str),
    /// A device-only helper without a Rust twin (buffer layout, or a piece of a twin).
    Helper,
}

use Check::{Helper, Oracle};

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
        let Oracle(t) = check else { unreachable!() };
        assert!(
            root.join("tests").join(t).is_file(),
            "tests/{t} (for {wname})"
        );
    }
}

#[test]
fn every_function_of_the_shared_libraries_is_listed() {
    let files: Vec<&str> = TWINS.iter().map(|t| t.0).collect();
    for f in files {
        for line in wgsl(f).lines() {
            let Some(rest) = line.strip_prefix("fn ") else {
                continue;
            };
            let name = rest.split('(').next().unwrap();
            assert!(
                TWINS.iter().any(|t| t.0 == f && t.1 == name),
                "{f}: fn {name} has no entry in TWINS (its Rust twin and oracle)"
            );
        }
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
            Helper => "through its callers".to_string(),
        };
        let row = format!("| `{wf}` | `{wname}` | {twin} | {how} |");
        assert!(
            doc.lines().any(|l| l == row),
            "docs/architecture.md's oracle table lacks the row {row}"
        );
    }
}
