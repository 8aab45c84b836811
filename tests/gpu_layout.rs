//! Host/shader agreement checked on naga's reflection of the composed kernels (no GPU):
//!
//! 1. every WGSL struct of `shaders/common/types.wgsl` has the size, alignment-compatible size,
//!    member names, member offsets and member sizes of its Rust twin;
//! 2. every `(group, binding)` the kernels declare has the buffer kind the host's bind-group
//!    layouts (`Layouts::new` in src/gpu/render.rs) give it, and every layout entry is declared;
//! 3. every kernel parses and validates and has the entry points the host creates pipelines for;
//! 4. the constants WGSL repeats from Rust have the same values.
//!
//! Each test gathers every mismatch it finds and fails once with the whole list.

use gpu_photon::bvh::{self, BvhNode};
use gpu_photon::geometry;
use gpu_photon::gpu::render as host;
use gpu_photon::gpu::shaders::{validate, Kernel};
use gpu_photon::gpu::types::{
    material_code, GpuAabb, GpuLight, GpuMapParams, GpuMaterial, GpuParams, GpuSphere, GpuTriangle,
};
use gpu_photon::photon::{self, Photon};
use gpu_photon::rng::Stream;
use gpu_photon::scene::{MaterialKind, NO_LIGHT};
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
            fields!(GpuTriangle: v0, material, v1, light, v2, _pad),
        ),
        (
            "Sphere",
            fields!(GpuSphere: center, radius, material, light, _pad0, _pad1),
        ),
        ("BvhNode", fields!(BvhNode: bmin, left_first, bmax, count)),
        (
            "Material",
            fields!(GpuMaterial: kd, kind, ks, exponent, emission, ior, two_sided, _pad0, _pad1, _pad2),
        ),
        (
            "Light",
            fields!(GpuLight: position, kind, intensity, first, global_power, count, caustic_power, cdf_start,
                area, global_offset, global_count, caustic_offset, caustic_count, _pad0, _pad1, _pad2),
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
                n_triangles, terms, _pad0, _pad1, _pad2),
        ),
        (
            "MapParams",
            fields!(GpuMapParams: stream, paths, capacity, table_size, cell_size, is_caustic, drop_flags, radius2),
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
    let shared: Vec<&str> = include_str!("../shaders/common/types.wgsl")
        .lines()
        .filter_map(|l| l.trim().strip_prefix("struct "))
        .filter_map(|l| l.split(|c: char| !(c.is_alphanumeric() || c == '_')).next())
        .collect();
    assert!(
        !shared.is_empty(),
        "no `struct` found in shaders/common/types.wgsl"
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

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Read-only storage (`wgpu::BufferBindingType::Storage { read_only: true }`, WGSL `read`).
    Ro,
    /// Read-write storage (`read_only: false`, WGSL `read_write`).
    Rw,
    Uniform,
}

/// The host's bind-group layouts, as this test expects them.
const SCENE: [Kind; 10] = [
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Rw,
];
const MAP: [Kind; 7] = [
    Kind::Rw,
    Kind::Rw,
    Kind::Rw,
    Kind::Rw,
    Kind::Rw,
    Kind::Rw,
    Kind::Ro,
];
const GATHER: [Kind; 7] = [
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Ro,
    Kind::Rw,
];

/// (group, binding) -> kind for the pipelines built from `kernel` (render.rs `Pipelines::new`:
/// trace and grid kernels use [scene, map], the gather uses [scene, gather]).
fn expected_bindings(kernel: Kernel) -> BTreeMap<(u32, u32), Kind> {
    let group1: &[Kind] = match kernel {
        Kernel::TracePhotons | Kernel::BuildGrid => &MAP,
        Kernel::Gather => &GATHER,
    };
    let mut table = BTreeMap::new();
    for (g, kinds) in [(0u32, &SCENE[..]), (1, group1)] {
        for (b, &k) in kinds.iter().enumerate() {
            table.insert((g, b as u32), k);
        }
    }
    table
}

/// The kinds listed in `Layouts::new` of src/gpu/render.rs for `field` (`scene`, `map`,
/// `gather`), read from the source text: the layouts need a device to build, so this is how a
/// test without one sees the host's table.
fn host_layout(field: &str) -> Vec<Kind> {
    let src = include_str!("../src/gpu/render.rs");
    let body = src
        .split("impl Layouts")
        .nth(1)
        .expect("`impl Layouts` in src/gpu/render.rs");
    let key = format!("{field}: mk(");
    let rest = &body[body
        .find(&key)
        .unwrap_or_else(|| panic!("`{key}` in Layouts::new"))..];
    let list = &rest[rest.find("&[").expect("`&[` after the layout label") + 2..];
    let list = &list[..list.find(']').expect("closing `]`")];
    list.split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| match s {
            "RO" => Kind::Ro,
            "RW" => Kind::Rw,
            "UNIFORM" => Kind::Uniform,
            other => panic!("unknown binding type `{other}` in Layouts::new `{field}`"),
        })
        .collect()
}

#[test]
fn host_layouts_are_the_expected_table() {
    let mut errors = Vec::new();
    for (field, expected) in [
        ("scene", &SCENE[..]),
        ("map", &MAP[..]),
        ("gather", &GATHER[..]),
    ] {
        let host = host_layout(field);
        if host != expected {
            errors.push(format!(
                "Layouts::new `{field}`: host {host:?} != expected {expected:?}"
            ));
        }
    }
    fail_if_any("host bind-group layouts (src/gpu/render.rs)", &errors);
}

#[test]
fn kernel_bindings_match_host_layouts() {
    let mut errors = Vec::new();
    for (kernel, module) in modules() {
        let expected = expected_bindings(*kernel);
        let mut declared = BTreeMap::new();
        for (_, var) in module.global_variables.iter() {
            let name = var.name.as_deref().unwrap_or("?");
            let Some(rb) = &var.binding else {
                continue;
            };
            let kind = match var.space {
                AddressSpace::Uniform => Some(Kind::Uniform),
                AddressSpace::Storage { access } if access == StorageAccess::LOAD => Some(Kind::Ro),
                AddressSpace::Storage { access }
                    if access.contains(StorageAccess::LOAD | StorageAccess::STORE) =>
                {
                    Some(Kind::Rw)
                }
                _ => None,
            };
            let at = format!(
                "[{}] @group({}) @binding({}) `{name}`",
                kernel.name(),
                rb.group,
                rb.binding
            );
            let Some(kind) = kind else {
                errors.push(format!(
                    "{at}: address space {:?} is none of read / read_write storage / uniform",
                    var.space
                ));
                continue;
            };
            if let Some(prev) = declared.insert((rb.group, rb.binding), (kind, name)) {
                errors.push(format!("{at}: binding also declared by `{}`", prev.1));
            }
            match expected.get(&(rb.group, rb.binding)) {
                None => errors.push(format!(
                    "{at}: not in the host's layouts (pipeline creation would fail)"
                )),
                Some(&e) if e != kind => {
                    errors.push(format!("{at}: declared {kind:?}, host layout has {e:?}"))
                }
                Some(_) => {}
            }
        }
        for (&(g, b), &kind) in &expected {
            if !declared.contains_key(&(g, b)) {
                errors.push(format!("[{}] host layout entry @group({g}) @binding({b}) {kind:?} is not declared by the kernel", kernel.name()));
            }
        }
    }
    fail_if_any("kernel bindings", &errors);
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
        let expected: &[&str] = match kernel {
            Kernel::TracePhotons => &["trace_photons"],
            Kernel::BuildGrid => &[
                "count_cells",
                "scan_blocks",
                "scan_sums",
                "add_offsets",
                "scatter",
            ],
            Kernel::Gather => &["gather"],
        };
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
    let common = [
        ("SPHERE_BIT", Literal::U32(bvh::SPHERE_BIT)),
        ("FLAG_CAUSTIC", Literal::U32(photon::FLAG_CAUSTIC)),
        ("DEPTH_MASK", Literal::U32(photon::DEPTH_MASK)),
        ("NO_LIGHT", Literal::U32(NO_LIGHT)),
        ("OFFSET_SCALE", Literal::F32(geometry::OFFSET_SCALE)),
        ("BOX_SLACK", Literal::F32(geometry::BOX_SLACK)),
        ("FACING_COS", Literal::F32(gpu_photon::estimate::FACING_COS)),
        ("OFFSET_FLOOR", Literal::F32(geometry::OFFSET_FLOOR)),
        (
            "STAT_PHOTON_OVERFLOW",
            Literal::U32(host::STAT_PHOTON_OVERFLOW as u32),
        ),
        (
            "STAT_LOOP_BUDGET",
            Literal::U32(host::STAT_LOOP_BUDGET as u32),
        ),
        (
            "STAT_GATHER_TRUNCATED",
            Literal::U32(host::STAT_GATHER_TRUNCATED as u32),
        ),
        (
            "MAT_DIFFUSE",
            Literal::U32(material_code(MaterialKind::Diffuse)),
        ),
        (
            "MAT_GLOSSY",
            Literal::U32(material_code(MaterialKind::Glossy)),
        ),
        (
            "MAT_MIRROR",
            Literal::U32(material_code(MaterialKind::Mirror)),
        ),
        (
            "MAT_GLASS",
            Literal::U32(material_code(MaterialKind::Glass)),
        ),
        (
            "MAT_BLACK",
            Literal::U32(material_code(MaterialKind::Black)),
        ),
        ("STREAM_PHOTON", Literal::U32(Stream::Photon as u32)),
        ("STREAM_CAUSTIC", Literal::U32(Stream::Caustic as u32)),
        ("STREAM_CAMERA", Literal::U32(Stream::Camera as u32)),
    ];
    let mut errors = Vec::new();
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
        for &(name, rust) in &common {
            check(kernel, name, rust);
        }
    }
    check(Kernel::Gather, "MAX_HEAP", Literal::U32(host::MAX_HEAP));

    // The CPU traversal (Bvh::intersect) uses a stack of MAX_DEPTH + 2 entries; the WGSL one
    // (intersect.wgsl) must hold at least as many, or deep trees traverse differently.
    for &kernel in &Kernel::ALL {
        match constant(module(kernel), "BVH_STACK") {
            Some(Literal::U32(s)) if s as usize >= bvh::MAX_DEPTH + 2 => {}
            other => errors.push(format!(
                "[{}] WGSL BVH_STACK = {other:?}, must be a u32 >= bvh::MAX_DEPTH + 2 = {}",
                kernel.name(),
                bvh::MAX_DEPTH + 2
            )),
        }
    }
    fail_if_any("shared constants", &errors);
}
