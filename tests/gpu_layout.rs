//! Host/shader agreement checked on naga's reflection of the composed kernels (no GPU):
//!
//! 1. every WGSL struct of `src/integrators/gpu/types.wgsl` has the size, alignment-compatible size,
//!    member names, member offsets and member sizes of its Rust twin;
//! 2. every WGSL global bound by a kernel is the entry of the same name in the host's binding
//!    tables (src/integrators/gpu/bindings.rs, which build the layouts and fill the bind groups), at the
//!    same (group, binding) with the same access, and every entry is declared (a swap of two
//!    buffers, in the table or in WGSL, is caught);
//! 3. every kernel parses and validates and has the entry points the host creates pipelines for;
//! 4. every constant of the generated prelude (src/integrators/gpu/codes.rs) has its Rust value in every
//!    composed module, no WGSL file declares one by hand, and every WGSL file is short with a
//!    header.
//!
//! Each test gathers every mismatch it finds and fails once with the whole list.

use gpu_photon::bvh;
use gpu_photon::bvh::gpu_instances::GpuInstance;
use gpu_photon::bvh::gpu_layout::{GpuBvhFrame, GpuLeafPrim, GpuTraversalNode, LEAF_COUNT_SHIFT};
use gpu_photon::bvh::gpu_sdf::GpuSdfGrid;
use gpu_photon::integrators::gpu::bindings::{
    groups_of, Access, Binding, GroupTable, GATHER_GROUP, MAP_GROUP, PARAMS, SCENE_GROUP,
};
use gpu_photon::integrators::gpu::branches::{GpuBranch, GpuBranchStack};
use gpu_photon::integrators::gpu::codes::{self, shared_constants, WgslValue};
use gpu_photon::integrators::gpu::pipelines::CPU_DEVICE_LOOP_BUDGET;
use gpu_photon::integrators::gpu::shaders::{self, validate, Kernel};
use gpu_photon::integrators::gpu::shape::KernelShape;
use gpu_photon::integrators::gpu::types::{
    GpuAabb, GpuLight, GpuMapParams, GpuMaterial, GpuMedium, GpuParams, GpuShadingNormals,
    GpuSphere, GpuTriangle,
};
use gpu_photon::integrators::photon::{self, Photon};
use gpu_photon::math::geometry;
use gpu_photon::math::rng::Stream;
use gpu_photon::scene::{FLAT, NO_LIGHT};
use naga::proc::Layouter;
use naga::{AddressSpace, Expression, Literal, Module, StorageAccess, TypeInner};
use std::collections::BTreeMap;
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// The validated module of every kernel, built once for all tests.
fn modules() -> &'static [(Kernel, Module)] {
    static MODULES: OnceLock<Vec<(Kernel, Module)>> = OnceLock::new();
    MODULES.get_or_init(|| {
        Kernel::ALL
            .iter()
            .map(|&k| match validate(&k.source()) {
                Ok(m) => (k, m),
                Err(e) => panic!("kernel {} does not validate:\n{e}", k.name()),
            })
            .collect()
    })
}

fn module(kernel: Kernel) -> &'static Module {
    &modules()
        .iter()
        .find(|(k, _)| *k == kernel)
        .expect("kernel in Kernel::ALL")
        .1
}

fn fail_if_any(what: &str, errors: &[String]) {
    if !errors.is_empty() {
        panic!(
            "{what}: {} mismatch(es):\n  {}",
            errors.len(),
            errors.join("\n  ")
        );
    }
}

/// One field of a Rust twin: name, `offset_of!`, size.
struct RustField {
    name: &'static str,
    offset: usize,
    size: usize,
}

/// One Rust twin: its name, size, alignment and fields in declaration order.
struct RustStruct {
    name: &'static str,
    size: usize,
    align: usize,
    fields: Vec<RustField>,
}

/// `fields!(Type: a, b, c)` lists the fields of `Type` in order. The destructuring `let`
/// makes the list exhaustive at compile time: a field added to the Rust struct and not
/// listed here is a compile error, so the list cannot silently drift from the struct.
macro_rules! fields {
    ($ty:ident : $($f:ident),+ $(,)?) => {{
        #[allow(unused_variables)]
        let $ty { $($f),+ } = $ty::default();
        let value = $ty::default();
        RustStruct {
            name: stringify!($ty),
            size: std::mem::size_of::<$ty>(),
            align: std::mem::align_of::<$ty>(),
            fields: vec![$(RustField {
                name: stringify!($f),
                offset: std::mem::offset_of!($ty, $f),
                size: std::mem::size_of_val(&value.$f),
            }),+],
        }
    }};
}

/// The WGSL struct of name `name` in `module`, with its layout.
struct WgslStruct {
    size: u32,
    alignment: u32,
    /// (name, offset, size)
    members: Vec<(String, u32, u32)>,
}

fn wgsl_struct(module: &Module, layouter: &Layouter, name: &str) -> Option<WgslStruct> {
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))?;
    let TypeInner::Struct { members, span } = &ty.inner else {
        panic!("WGSL type {name} is not a struct: {:?}", ty.inner);
    };
    let layout = &layouter[handle];
    assert_eq!(
        layout.size, *span,
        "layouter and struct span disagree for WGSL {name}"
    );
    Some(WgslStruct {
        size: *span,
        // `round_up(1)` of an alignment is the alignment itself.
        alignment: layout.alignment.round_up(1),
        members: members
            .iter()
            .map(|m| {
                (
                    m.name.clone().unwrap_or_default(),
                    m.offset,
                    layouter[m.ty].size,
                )
            })
            .collect(),
    })
}

// ---------------------------------------------------------------------------------------------
// 1. Struct layouts
// ---------------------------------------------------------------------------------------------

/// (WGSL name, Rust twin with its fields in order).
fn twins() -> Vec<(&'static str, RustStruct)> {
    vec![
        (
            "Triangle",
            fields!(GpuTriangle: v0, material, v1, light, v2, shading),
        ),
        (
            "ShadingNormals",
            fields!(GpuShadingNormals: n0, _pad0, n1, _pad1, n2, _pad2),
        ),
        (
            "Sphere",
            fields!(GpuSphere: center, radius, material, light, frame),
        ),
        ("BvhFrame", fields!(GpuBvhFrame: base, nodes, step, next)),
        (
            "InstanceRecord",
            fields!(GpuInstance: to_object, to_world, frame, _pad0, _pad1, _pad2),
        ),
        ("TraversalNode", fields!(GpuTraversalNode: qx, qy, qz, link)),
        (
            "SdfGridRecord",
            fields!(GpuSdfGrid: to_object, to_world, res, material, values, smooth_normals, _pad0, _pad1),
        ),
        (
            "LeafPrim",
            fields!(GpuLeafPrim: v0, id, v1, _pad0, v2, _pad1),
        ),
        (
            "Material",
            fields!(GpuMaterial: emission, two_sided, kind, textured, one_sided, normal_texture,
                alpha_mode, alpha_texture, alpha_factor, alpha_cutoff, blend_first, blend_second,
                blend_stores, normal_shadowing, blend_weight, bump_scale, bump, _pad0, _pad1),
        ),
        (
            "Light",
            fields!(GpuLight: kind, global_offset, global_count, caustic_offset, global_power, caustic_count,
                caustic_power, area, texture_mean, emission_texture, p0, p1, p2, p3),
        ),
        ("Aabb", fields!(GpuAabb: bmin, _pad0, bmax, _pad1)),
        (
            "Photon",
            fields!(Photon: position, flags, power, id, dir, normal),
        ),
        (
            "Params",
            fields!(GpuParams: eye, width, forward, height, right, spp, up, sample, seed, pass_index, k,
                filter_kind, mode, max_depth, max_photon_bounces, shadow_samples, fresnel, n_lights, n_bounds,
                n_triangles, terms, caustic_weight, sampler, pixel_filter, filter_param,
                aperture_radius, focus_distance, camera_medium, first_row, branch_round, orthographic,
                outer_medium),
        ),
        ("Medium", fields!(GpuMedium: sigma_t, g, sigma_s, grid)),
        ("Branch", fields!(GpuBranch: o, depth, d, medium, t, _pad)),
        ("BranchStack", fields!(GpuBranchStack: n, resume, queue, b)),
        (
            "MapParams",
            fields!(GpuMapParams: stream, paths, capacity, table_size, cell_size, is_caustic, drop_flags, radius2, k, storing_area, max_power, volume_flags),
        ),
    ]
}

fn compare_struct(
    kernel: Kernel,
    wgsl_name: &str,
    w: &WgslStruct,
    r: &RustStruct,
    errors: &mut Vec<String>,
) {
    let at = format!("[{}] WGSL {wgsl_name} vs Rust {}", kernel.name(), r.name);
    if w.size as usize != r.size {
        errors.push(format!("{at}: size {} (WGSL) != {} (Rust)", w.size, r.size));
    }
    if r.size % w.alignment as usize != 0 {
        errors.push(format!(
            "{at}: Rust size {} is not a multiple of the WGSL alignment {} (array strides would differ)",
            r.size, w.alignment
        ));
    }
    if w.alignment as usize % r.align != 0 {
        errors.push(format!(
            "{at}: Rust alignment {} does not divide the WGSL alignment {}",
            r.align, w.alignment
        ));
    }
    // The Rust fields must tile the struct (bytemuck's Pod already forbids padding; this keeps
    // the list honest about order, too).
    let mut end = 0;
    for f in &r.fields {
        if f.offset != end {
            errors.push(format!("{at}: Rust field {} at offset {} does not follow the previous field (ends at {end})", f.name, f.offset));
        }
        end = f.offset + f.size;
    }
    if end != r.size {
        errors.push(format!(
            "{at}: Rust fields end at {end}, struct size is {}",
            r.size
        ));
    }
    if w.members.len() != r.fields.len() {
        errors.push(format!(
            "{at}: {} WGSL members {:?} vs {} Rust fields {:?}",
            w.members.len(),
            w.members.iter().map(|m| m.0.as_str()).collect::<Vec<_>>(),
            r.fields.len(),
            r.fields.iter().map(|f| f.name).collect::<Vec<_>>()
        ));
    }
    for (i, ((name, offset, size), f)) in w.members.iter().zip(&r.fields).enumerate() {
        if name != f.name {
            errors.push(format!(
                "{at}: member {i} is `{name}` in WGSL, `{}` in Rust",
                f.name
            ));
        }
        if *offset as usize != f.offset {
            errors.push(format!(
                "{at}: member {i} `{name}` at offset {offset} (WGSL) != {} (Rust `{}`)",
                f.offset, f.name
            ));
        }
        if *size as usize != f.size {
            errors.push(format!(
                "{at}: member {i} `{name}` of size {size} (WGSL) != {} (Rust `{}`)",
                f.size, f.name
            ));
        }
    }
}

#[test]
fn struct_layouts_match_rust_twins() {
    let twins = twins();
    let mut errors = Vec::new();
    for (kernel, module) in modules() {
        let mut layouter = Layouter::default();
        layouter
            .update(module.to_ctx())
            .unwrap_or_else(|e| panic!("[{}] layouter: {e:?}", kernel.name()));
        for (wgsl_name, rust) in &twins {
            // types.wgsl is the first library of every kernel, so every struct is in every module.
            match wgsl_struct(module, &layouter, wgsl_name) {
                Some(w) => compare_struct(*kernel, wgsl_name, &w, rust, &mut errors),
                None => errors.push(format!(
                    "[{}] WGSL struct {wgsl_name} not found",
                    kernel.name()
                )),
            }
        }
    }
    // Every struct of the shared types file has a twin here (a new WGSL struct needs one).
    let shared: Vec<&str> = include_str!("../src/integrators/gpu/types.wgsl")
        .lines()
        .filter_map(|l| l.trim().strip_prefix("struct "))
        .filter_map(|l| l.split(|c: char| !(c.is_alphanumeric() || c == '_')).next())
        .collect();
    assert!(
        !shared.is_empty(),
        "no `struct` found in src/integrators/gpu/types.wgsl"
    );
    for name in shared {
        if !twins.iter().any(|(w, _)| *w == name) {
            errors.push(format!(
                "WGSL struct {name} in types.wgsl has no Rust twin listed in tests/gpu_layout.rs"
            ));
        }
    }
    fail_if_any("struct layouts", &errors);
}

// ---------------------------------------------------------------------------------------------
// 2. Bindings
// ---------------------------------------------------------------------------------------------

/// Every mismatch between the bindings `module` declares and the host's tables `tables` (one
/// per bind group the kernel's pipelines use): each WGSL global with a binding must be the
/// table entry of the same name, at the same (group, binding), with the same access; every
/// table entry must be declared; no two entries of a table share a binding number.
fn check_bindings(kernel: &str, module: &Module, tables: &[&GroupTable]) -> Vec<String> {
    let mut errors = Vec::new();
    for t in tables {
        let mut seen = BTreeMap::new();
        for b in t.entries {
            if let Some(prev) = seen.insert(b.binding, b.name) {
                errors.push(format!(
                    "table {} (group {}): binding {} given to both `{prev}` and `{}`",
                    t.label, t.group, b.binding, b.name
                ));
            }
        }
    }
    let mut declared = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else {
            continue;
        };
        let name = var.name.as_deref().unwrap_or("?");
        let at = format!(
            "[{kernel}] @group({}) @binding({}) `{name}`",
            rb.group, rb.binding
        );
        let access = match var.space {
            AddressSpace::Storage { access } if access == StorageAccess::LOAD => Access::Read,
            AddressSpace::Storage { access }
                if access.contains(StorageAccess::LOAD | StorageAccess::STORE) =>
            {
                Access::ReadWrite
            }
            other => {
                errors.push(format!(
                    "{at}: address space {other:?} is neither read nor read_write storage"
                ));
                continue;
            }
        };
        let Some(table) = tables.iter().find(|t| t.group == rb.group) else {
            errors.push(format!("{at}: no host table for group {}", rb.group));
            continue;
        };
        declared.push((rb.group, name.to_string()));
        match table.entry(name) {
            None => errors.push(format!(
                "{at}: no entry `{name}` in the host table {}",
                table.label
            )),
            Some(e) => {
                if e.binding != rb.binding {
                    errors.push(format!(
                        "{at}: the host table {} binds `{name}` at binding {}",
                        table.label, e.binding
                    ));
                }
                if e.access != access {
                    errors.push(format!(
                        "{at}: declared {access:?}, the host table {} has {:?}",
                        table.label, e.access
                    ));
                }
            }
        }
    }
    for t in tables {
        for b in t.entries {
            if !declared.iter().any(|(g, n)| *g == t.group && n == b.name) {
                errors.push(format!(
                    "[{kernel}] host table {} entry `{}` (binding {}) is not declared by the kernel",
                    t.label, b.name, b.binding
                ));
            }
        }
    }
    errors
}

#[test]
fn kernel_bindings_match_host_tables() {
    let mut errors = Vec::new();
    for (kernel, module) in modules() {
        errors.extend(check_bindings(kernel.name(), module, &groups_of(*kernel)));
    }
    fail_if_any("kernel bindings", &errors);
}

#[test]
fn tables_use_no_uniform_buffers_and_one_dynamic_offset() {
    // Every binding is storage by construction (`bindings::layout`); the one dynamic offset
    // is the per-sample parameters, the binding the gather steps through.
    let dynamic: Vec<(u32, &str)> = [&SCENE_GROUP, &MAP_GROUP, &GATHER_GROUP]
        .iter()
        .flat_map(|t| {
            t.entries
                .iter()
                .filter(|b| b.dynamic)
                .map(|b| (t.group, b.name))
        })
        .collect();
    assert_eq!(dynamic, vec![(0, PARAMS)]);
}

#[test]
fn host_tables_are_the_expected_layouts() {
    // (table, its bindings 0.. in order with their access): the scene (with its BSDF
    // parameters, uvs, textures and media) is read-only but for the stats counters, a map's
    // buffers (and the volume photons its paths add to) are all written by its kernels (its parameters'
    // cell size by size_grid, max_power by scan_sums), and the gather group reads both maps
    // and writes only the accumulator and the radiance cache with its point list (built by
    // `list_cache_points` and `build_cache` or `build_cache_fixed`, read by the gather), and
    // the camera paths' glass branch stacks.
    use Access::{Read as R, ReadWrite as W};
    let expected: [(&GroupTable, &[Access]); 3] = [
        (
            &SCENE_GROUP,
            &[R, R, R, R, R, R, R, R, R, W, R, R, R, R, R, R, R, R],
        ),
        (&MAP_GROUP, &[W, W, W, W, W, W, W, W, W, W]),
        (&GATHER_GROUP, &[R, R, R, R, R, R, W, W, W, R, R, R, R, W]),
    ];
    let mut errors = Vec::new();
    for (table, kinds) in expected {
        let mut host: Vec<&Binding> = table.entries.iter().collect();
        host.sort_by_key(|b| b.binding);
        let numbers: Vec<u32> = host.iter().map(|b| b.binding).collect();
        let access: Vec<Access> = host.iter().map(|b| b.access).collect();
        if numbers != (0..kinds.len() as u32).collect::<Vec<_>>() || access != kinds {
            errors.push(format!(
                "table {}: bindings {numbers:?} with {access:?}, expected 0.. with {kinds:?}",
                table.label
            ));
        }
    }
    fail_if_any("host binding tables", &errors);
}

/// `table` with the binding numbers of entries `a` and `b` exchanged.
fn swapped(table: &GroupTable, a: &str, b: &str) -> GroupTable {
    let entries: Vec<Binding> = table
        .entries
        .iter()
        .map(|e| {
            let mut e = *e;
            let other = if e.name == a {
                b
            } else if e.name == b {
                a
            } else {
                return e;
            };
            e.binding = table.entry(other).expect("entry in table").binding;
            e
        })
        .collect();
    GroupTable {
        entries: Box::leak(entries.into_boxed_slice()),
        ..*table
    }
}

#[test]
fn a_swap_of_two_read_only_buffers_is_caught() {
    // In the host table: two read-only scene buffers exchanged.
    let scene = swapped(&SCENE_GROUP, "triangles", "spheres");
    for (kernel, module) in modules() {
        let [_, group1] = groups_of(*kernel);
        let errors = check_bindings(kernel.name(), module, &[&scene, group1]);
        assert!(
            errors.iter().any(|e| e.contains("`triangles`"))
                && errors.iter().any(|e| e.contains("`spheres`")),
            "[{}] swapped scene table not rejected: {errors:?}",
            kernel.name()
        );
    }
    // The two read-only maps of the gather group.
    let gather = swapped(&GATHER_GROUP, "g_cells", "c_cells");
    let errors = check_bindings("gather", module(Kernel::Gather), &[&SCENE_GROUP, &gather]);
    assert_eq!(errors.len(), 2, "swapped gather table: {errors:?}");

    // In the WGSL: the same two declarations exchanged in the composed source.
    let src = Kernel::Gather.source();
    let (t, s) = (
        "@group(0) @binding(0) var<storage, read> triangles",
        "@group(0) @binding(1) var<storage, read> spheres",
    );
    assert!(
        src.contains(t) && src.contains(s),
        "scene declarations moved"
    );
    let src = src
        .replace(t, "TRIANGLES_DECL")
        .replace(s, "@group(0) @binding(0) var<storage, read> spheres")
        .replace(
            "TRIANGLES_DECL",
            "@group(0) @binding(1) var<storage, read> triangles",
        );
    let m = validate(&src).expect("the swapped module still validates");
    let errors = check_bindings("gather (swapped WGSL)", &m, &groups_of(Kernel::Gather));
    assert_eq!(errors.len(), 2, "swapped WGSL: {errors:?}");
}

// ---------------------------------------------------------------------------------------------
// 3. Validation and entry points
// ---------------------------------------------------------------------------------------------

#[test]
fn every_kernel_validates_with_its_entry_points() {
    let mut errors = Vec::new();
    for &kernel in &Kernel::ALL {
        // Validate here too (not only through `modules()`), so this test names the failure.
        let module = match validate(&kernel.source()) {
            Ok(m) => m,
            Err(e) => {
                errors.push(format!("[{}] does not validate:\n{e}", kernel.name()));
                continue;
            }
        };
        let expected = kernel.entry_points();
        let names: Vec<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        for want in expected {
            match module.entry_points.iter().find(|e| e.name == *want) {
                None => errors.push(format!(
                    "[{}] entry point `{want}` missing (has {names:?})",
                    kernel.name()
                )),
                Some(e) if e.stage != naga::ShaderStage::Compute => errors.push(format!(
                    "[{}] entry point `{want}` is {:?}, not compute",
                    kernel.name(),
                    e.stage
                )),
                Some(_) => {}
            }
        }
    }
    fail_if_any("kernel validation", &errors);
}

// ---------------------------------------------------------------------------------------------
// 4. Shared constants
// ---------------------------------------------------------------------------------------------

/// A module-scope `const` of the module, evaluated to its literal.
fn constant(module: &Module, name: &str) -> Option<Literal> {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))?;
    match module.global_expressions[c.init] {
        Expression::Literal(l) => Some(l),
        ref other => panic!("WGSL const {name} did not evaluate to a literal: {other:?}"),
    }
}

#[test]
fn shared_constants_agree() {
    let shared = shared_constants();
    let mut errors = Vec::new();
    // The constants the kernels used to repeat from Rust are all in the generated prelude.
    for name in [
        "SPHERE_BIT",
        "FLAG_CAUSTIC",
        "DEPTH_MASK",
        "NO_LIGHT",
        "FLAT",
        "OFFSET_SCALE",
        "BOX_SLACK",
        "FACING_COS",
        "OFFSET_FLOOR",
        "STAT_PHOTON_OVERFLOW",
        "STAT_LOOP_BUDGET",
        "STAT_GATHER_TRUNCATED",
        "STREAM_PHOTON",
        "STREAM_CAUSTIC",
        "STREAM_CAMERA",
        "MAX_HEAP",
        "FRAME_WORDS",
        "DROP_DIRECT",
        "DROP_CAUSTIC",
        "TERM_DIRECT",
        "TERM_POINT_LOBE",
        "TERM_LOBE_RAY",
        "TERM_FINAL_GATHER",
        "CACHE_STRIDE",
        "CACHE_NORMAL_COS",
        "BOUNCE_ABSORB",
        "BOUNCE_DELTA",
        "FILTER_CONE",
        "FRESNEL_SCHLICK",
        "SCAN_BLOCK",
        "SCAN_ITEMS",
        "SOBOL_PAIR_JITTER",
        "SOBOL_PAIR_LIGHT",
        "SOBOL_DIM_LIGHT_THIRD",
        "SOBOL_PAIR_GATHER",
        "SOBOL_PAIR_LENS",
        "PIXEL_FILTER_BOX",
        "PIXEL_FILTER_TENT",
        "PIXEL_FILTER_GAUSSIAN",
        "ERF_2_SQRT_2",
        "LEAF_COUNT_SHIFT",
    ] {
        if !shared.iter().any(|(n, _)| *n == name) {
            errors.push(format!("{name} is not in codes::shared_constants()"));
        }
    }
    // Every shared constant, in every composed module, has the Rust value (bit for bit).
    let expected = [
        ("SPHERE_BIT", Literal::U32(bvh::SPHERE_BIT)),
        ("LEAF_COUNT_SHIFT", Literal::U32(LEAF_COUNT_SHIFT)),
        ("FLAG_CAUSTIC", Literal::U32(photon::FLAG_CAUSTIC)),
        ("DEPTH_MASK", Literal::U32(photon::DEPTH_MASK)),
        ("NO_LIGHT", Literal::U32(NO_LIGHT)),
        ("FLAT", Literal::U32(FLAT)),
        ("OFFSET_SCALE", Literal::F32(geometry::OFFSET_SCALE)),
        ("BOX_SLACK", Literal::F32(geometry::BOX_SLACK)),
        (
            "FACING_COS",
            Literal::F32(gpu_photon::integrators::estimate::FACING_COS),
        ),
        ("OFFSET_FLOOR", Literal::F32(geometry::OFFSET_FLOOR)),
        ("STREAM_PHOTON", Literal::U32(Stream::Photon as u32)),
        ("STREAM_CAUSTIC", Literal::U32(Stream::Caustic as u32)),
        ("STREAM_CAMERA", Literal::U32(Stream::Camera as u32)),
        ("MAX_HEAP", Literal::U32(codes::MAX_HEAP)),
        ("TERM_FINAL_GATHER", Literal::U32(codes::TERM_FINAL_GATHER)),
        (
            "CACHE_STRIDE",
            Literal::U32(gpu_photon::integrators::plan::CACHE_STRIDE),
        ),
        (
            "CACHE_NORMAL_COS",
            Literal::F32(gpu_photon::integrators::plan::CACHE_NORMAL_COS),
        ),
        (
            "SOBOL_PAIR_JITTER",
            Literal::U32(gpu_photon::math::sobol::PAIR_JITTER),
        ),
        (
            "SOBOL_PAIR_LIGHT",
            Literal::U32(gpu_photon::math::sobol::PAIR_LIGHT),
        ),
        (
            "SOBOL_DIM_LIGHT_THIRD",
            Literal::U32(gpu_photon::math::sobol::DIM_LIGHT_THIRD),
        ),
        (
            "SOBOL_PAIR_GATHER",
            Literal::U32(gpu_photon::math::sobol::PAIR_GATHER),
        ),
        (
            "SOBOL_PAIR_LENS",
            Literal::U32(gpu_photon::math::sobol::PAIR_LENS),
        ),
        (
            "ERF_2_SQRT_2",
            Literal::F32(gpu_photon::camera::pixel_filter::ERF_2_SQRT_2),
        ),
    ];
    let mut check = |kernel: Kernel, name: &str, rust: Literal| match constant(module(kernel), name)
    {
        None => errors.push(format!("[{}] WGSL const {name} not found", kernel.name())),
        Some(w) if w != rust => errors.push(format!(
            "[{}] WGSL const {name} = {w:?}, Rust has {rust:?}",
            kernel.name()
        )),
        Some(_) => {}
    };
    for &kernel in &Kernel::ALL {
        for &(name, value) in &shared {
            let rust = match value {
                WgslValue::U32(v) => Literal::U32(v),
                WgslValue::F32(v) => Literal::F32(v),
            };
            check(kernel, name, rust);
        }
        for &(name, rust) in &expected {
            check(kernel, name, rust);
        }
        // Every BSDF and light kind's code is its place in the Rust list of kinds.
        for (i, kind) in gpu_photon::bsdfs::KINDS.iter().enumerate() {
            let name = format!("BSDF_{}", gpu_photon::bsdfs::gpu::upper(kind.name));
            check(kernel, &name, Literal::U32(i as u32));
        }
        for (i, flag) in gpu_photon::lights::gpu::kind_flags().iter().enumerate() {
            let name = flag.replace("HAS_LIGHT_", "LIGHT_");
            check(kernel, &name, Literal::U32(i as u32));
        }
    }

    // The WGSL defaults of the loop budget and of the kernel shape's overrides (which the
    // probes run with) are lavapipe's: the default shape, `KernelShape::DEFAULT`.
    let shape = KernelShape::DEFAULT;
    let defaults = [
        ("LOOP_BUDGET", Literal::U32(CPU_DEVICE_LOOP_BUDGET)),
        ("WG_SIZE", Literal::U32(shape.wg_size)),
        ("GATHER_TILE", Literal::U32(shape.gather_tile)),
        ("CACHE_LANES", Literal::U32(shape.cache_lanes)),
        ("LOOP_GUARD", Literal::Bool(shape.loop_guard)),
    ];
    for &kernel in &Kernel::ALL {
        for (name, want) in defaults {
            let init = module(kernel)
                .overrides
                .iter()
                .find(|(_, o)| o.name.as_deref() == Some(name))
                .and_then(|(_, o)| o.init)
                .map(|e| &module(kernel).global_expressions[e]);
            match init {
                Some(Expression::Literal(l)) if *l == want => {}
                other => errors.push(format!(
                    "[{}] override {name} defaults to {other:?}, not {want:?}",
                    kernel.name()
                )),
            }
        }
        // The shape's names are overrides only, never module constants.
        for (name, _) in shape.overrides() {
            if constant(module(kernel), name).is_some() {
                errors.push(format!(
                    "[{}] {name} is a const, not an override",
                    kernel.name()
                ));
            }
        }
    }
    fail_if_any("shared constants", &errors);
}

/// Every WGSL file under src/ (they live beside their Rust twins), read from disk (so a new
/// file is checked too), by its path under src/.
fn wgsl_files() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    let mut dirs = vec![root.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).expect("src/ is readable") {
            let p = e.expect("directory entry").path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "wgsl") {
                let text = std::fs::read_to_string(&p).expect("WGSL file is readable");
                let rel = p.strip_prefix(&root).unwrap_or(&p).display().to_string();
                out.push((rel, text));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn no_wgsl_file_declares_a_prelude_constant() {
    let shared = shared_constants();
    let files = wgsl_files();
    let composed = shaders::wgsl_files();
    assert!(
        files.len() >= composed.len(),
        "WGSL files not found: {files:?}"
    );
    let mut errors = Vec::new();
    for (path, text) in &files {
        if !composed.iter().any(|(p, _)| p == path) {
            errors.push(format!(
                "src/{path} is not composed (shaders::wgsl_files())"
            ));
        }
        for (n, line) in text.lines().enumerate() {
            let decl = line.trim_start();
            let Some(rest) = decl
                .strip_prefix("const ")
                .or_else(|| decl.strip_prefix("override "))
            else {
                continue;
            };
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if shared.iter().any(|(s, _)| *s == name) {
                errors.push(format!(
                    "src/{path}:{}: declares {name}, which the generated prelude holds",
                    n + 1
                ));
            }
        }
    }
    fail_if_any("prelude constants declared by hand", &errors);
}

#[test]
fn wgsl_files_have_a_header() {
    let mut errors = Vec::new();
    for (path, text) in wgsl_files() {
        let header = text.lines().take_while(|l| l.starts_with("//")).count();
        if !(3..=5).contains(&header) {
            errors.push(format!(
                "src/{path}: a header of {header} comment line(s), 3 to 5 wanted"
            ));
        }
    }
    fail_if_any("WGSL files", &errors);
}

#[test]
fn radiance_cache_entries_fit_where_the_global_maps_photons_do() {
    // The cache holds one entry per slot of the global map; its binding stays within the
    // device limit because an entry is no larger than the photon whose slot it shares.
    use gpu_photon::integrators::gpu::buffers::CACHE_ENTRY_BYTES;
    assert!(CACHE_ENTRY_BYTES <= std::mem::size_of::<Photon>() as u64);
    let mut errors = Vec::new();
    for kernel in [Kernel::Gather] {
        let m = module(kernel);
        let Some((_, var)) = m
            .global_variables
            .iter()
            .find(|(_, v)| v.name.as_deref() == Some("cache"))
        else {
            errors.push(format!("[{}] no `cache` global", kernel.name()));
            continue;
        };
        match m.types[var.ty].inner {
            TypeInner::Array { stride, .. } if stride as u64 == CACHE_ENTRY_BYTES => {}
            ref other => errors.push(format!(
                "[{}] `cache` is {other:?}, want an array of {CACHE_ENTRY_BYTES}-byte entries",
                kernel.name()
            )),
        }
    }
    fail_if_any("radiance cache", &errors);
}
