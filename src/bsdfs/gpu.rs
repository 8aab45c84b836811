//! The BSDFs on the GPU, generated from the list of kinds ([`KINDS`]): each material's BSDF
//! packed as words ([`pack`]) and the WGSL library the kernels compose ([`wgsl_library`]):
//! the kinds' codes and feature flags, the `Bsdf` record, its loading and texture lookup, and
//! one dispatch function per method of the interface, which calls `<kind>_<method>` where a
//! kind's WGSL file defines it and `default_<method>` otherwise. A new kind needs nothing here.

use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::microfacet::{MF_BECKMANN, MF_GGX};
use crate::bsdfs::param::{Channel, GpuWords, BSDF_WORDS, PARAM_TEXTURE_BITS};
use crate::bsdfs::{Bsdf, KINDS};

/// Every material's BSDF as the device reads it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedBsdfs {
    /// [`BSDF_WORDS`] words per material (`bsdfs` in WGSL).
    pub words: Vec<[u32; 4]>,
    /// Per material: its kind's code and the mask of its textured words.
    pub headers: Vec<(u32, u32)>,
    /// The kinds' extra tables (`bsdf_tables`; one zero when none, as a binding is never empty).
    pub tables: Vec<f32>,
}

/// Packs `bsdfs` (one per material, in order).
pub fn pack<'a>(bsdfs: impl IntoIterator<Item = &'a Bsdf>) -> PackedBsdfs {
    let mut out = PackedBsdfs::default();
    for b in bsdfs {
        let mut w = GpuWords::default();
        b.gpu_words(&mut w);
        assert!(
            w.words.len() <= BSDF_WORDS,
            "a kind takes at most BSDF_WORDS words"
        );
        if let Some((word, component)) = w.table_at {
            w.words[word][component] = out.tables.len() as u32;
            out.tables.extend(&w.table);
        }
        w.words.resize(BSDF_WORDS, [0; 4]);
        out.words.extend(&w.words);
        out.headers.push((b.code(), w.textured));
    }
    if out.words.is_empty() {
        out.words.resize(BSDF_WORDS, [0; 4]);
    }
    if out.tables.is_empty() {
        out.tables.push(0.0);
    }
    out
}

/// The WGSL name of a kind's code and flag: `MetallicRoughness` -> `METALLIC_ROUGHNESS`.
pub fn upper(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
    }
    out
}

/// The pipeline-overridable flag of each kind, in the order of their codes (`HAS_DIFFUSE`,
/// ...): a render sets the flags of the kinds its scene has.
pub fn kind_flags() -> &'static [String] {
    static FLAGS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    FLAGS.get_or_init(|| {
        KINDS
            .iter()
            .map(|k| format!("HAS_{}", upper(k.name)))
            .collect()
    })
}

/// The code of a surface class in WGSL (`CLASS_*`, the generated prelude's).
fn class_const(c: SurfaceClass) -> &'static str {
    match c {
        SurfaceClass::Black => "CLASS_BLACK",
        SurfaceClass::Delta => "CLASS_DELTA",
        SurfaceClass::Shaded => "CLASS_SHADED",
        SurfaceClass::Null => "CLASS_NULL",
    }
}

/// One method of the interface as the kernels call it: the dispatcher's name, the kinds'
/// suffix (`<kind>_<suffix>`, `default_<suffix>`), its parameters, the call's arguments, the
/// return type and the expression of the kind it dispatches on.
struct Method {
    name: &'static str,
    suffix: &'static str,
    params: &'static str,
    args: &'static str,
    ret: &'static str,
    kind: &'static str,
}

/// A method of the BSDF in the local frame: `bsdf_<suffix>(b: Bsdf, ...)`.
const fn local(
    suffix: &'static str,
    name: &'static str,
    params: &'static str,
    args: &'static str,
    ret: &'static str,
) -> Method {
    Method {
        name,
        suffix,
        params,
        args,
        ret,
        kind: "b.kind",
    }
}

/// A method of the surface: `surface_<suffix>(s: Surface, ...)`, dispatched on its BSDF's kind.
const fn surface(
    suffix: &'static str,
    name: &'static str,
    params: &'static str,
    args: &'static str,
    ret: &'static str,
) -> Method {
    Method {
        kind: "s.b.kind",
        ..local(suffix, name, params, args, ret)
    }
}

/// The methods: the BSDF's in the local frame (`bsdf_*`) and the surface's (`surface_*`).
#[rustfmt::skip]
const METHODS: &[Method] = &[
    local("diffuse_out", "bsdf_diffuse_out", "b: Bsdf, wo: vec3<f32>", "b, wo", "vec3<f32>"),
    local("store_weight", "bsdf_store_weight", "b: Bsdf, wi: vec3<f32>", "b, wi", "f32"),
    local("eval_lobe", "bsdf_eval_lobe", "b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool", "b, wi, wo, radiance", "vec3<f32>"),
    local("pdf_lobe", "bsdf_pdf_lobe", "b: Bsdf, wi: vec3<f32>, wo: vec3<f32>", "b, wi, wo", "f32"),
    local("sample_lobe", "bsdf_sample_lobe", "b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool", "b, wo, u, radiance", "LobeSampleW"),
    local("has_diffuse", "bsdf_has_diffuse", "b: Bsdf", "b", "bool"),
    local("has_lobe", "bsdf_has_lobe", "b: Bsdf", "b", "bool"),
    local("lobe_is_delta", "bsdf_lobe_is_delta", "b: Bsdf", "b", "bool"),
    local("lobe_probability", "bsdf_lobe_probability", "b: Bsdf, wo: vec3<f32>", "b, wo", "f32"),
    local("diffuse_value", "bsdf_diffuse_value", "b: Bsdf, wi: vec3<f32>, wo: vec3<f32>", "b, wi, wo", "vec3<f32>"),
    local("eval", "bsdf_eval", "b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool", "b, wi, wo, radiance", "vec3<f32>"),
    local("pdf", "bsdf_pdf", "b: Bsdf, wi: vec3<f32>, wo: vec3<f32>", "b, wi, wo", "f32"),
    local("sample", "bsdf_sample", "b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool", "b, wo, u, radiance", "LobeSampleW"),
    local("finish", "bsdf_finish", "b: Bsdf", "b", "Bsdf"),
    local("lobe_transmits", "bsdf_lobe_transmits", "b: Bsdf", "b", "bool"),
    local("passes_null", "bsdf_passes_null", "b: Bsdf", "b", "bool"),
    local("null_transmission", "bsdf_null_transmission", "b: Bsdf, wo: vec3<f32>", "b, wo", "vec3<f32>"),
    surface("surface_diffuse_albedo", "surface_diffuse_albedo", "s: Surface, wo: vec3<f32>", "s, wo", "vec3<f32>"),
    surface("surface_store_weight", "surface_store_weight_unshadowed", "s: Surface, wi: vec3<f32>", "s, wi", "f32"),
    surface("surface_eval_diffuse", "surface_eval_diffuse_unshadowed", "s: Surface, wi: vec3<f32>, wo: vec3<f32>", "s, wi, wo", "vec3<f32>"),
    surface("surface_eval_lobe", "surface_eval_lobe_unshadowed", "s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>", "s, wi, wo, ns", "vec3<f32>"),
    surface("surface_pdf_lobe", "surface_pdf_lobe", "s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>", "s, wi, wo, ns", "f32"),
    surface("surface_has_lobe", "surface_has_lobe", "s: Surface", "s", "bool"),
    surface("surface_lobe_is_glossy", "surface_lobe_is_glossy", "s: Surface", "s", "bool"),
    surface("surface_lobe_takes_point_lights", "surface_lobe_takes_point_lights", "s: Surface", "s", "bool"),
    surface("surface_stores_photons", "surface_stores_photons", "s: Surface", "s", "bool"),
    surface("surface_sample_lobe", "surface_sample_lobe_unshadowed", "s: Surface, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>", "s, d, f, rng", "LobeRay"),
    surface("surface_photon_bounce", "surface_photon_bounce", "s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>", "s, d, hit, u", "Bounce"),
    surface("surface_delta", "surface_delta_event", "hit: Hit, s: Surface, f: Facing, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>", "hit, s, f, d, t, rng", "bool"),
    surface("surface_split", "surface_split", "hit: Hit, s: Surface, f: Facing, d: vec3<f32>", "hit, s, f, d", "Dielectric"),
];

/// Whether `wgsl` declares `fn name(`.
fn declares(wgsl: &str, name: &str) -> bool {
    wgsl.contains(&format!("fn {name}("))
}

fn dispatcher(out: &mut String, method: &Method) {
    out.push_str(&format!(
        "fn {}({}) -> {} {{\n",
        method.name, method.params, method.ret
    ));
    let cases: Vec<String> = KINDS
        .iter()
        .filter(|k| declares(k.wgsl, &format!("{}_{}", k.prefix, method.suffix)))
        .map(|k| {
            let up = upper(k.name);
            format!(
                "        case BSDF_{up}: {{ if HAS_{up} {{ return {}_{}({}); }} }}\n",
                k.prefix, method.suffix, method.args
            )
        })
        .collect();
    if !cases.is_empty() {
        out.push_str(&format!("    switch {} {{\n", method.kind));
        cases.iter().for_each(|c| out.push_str(c));
        out.push_str("        default: {}\n    }\n");
    }
    out.push_str(&format!(
        "    return default_{}({});\n}}\n",
        method.suffix, method.args
    ));
}

/// The generated part: codes, flags, the `Bsdf` record, its loading and lookup, and the
/// dispatch of every method.
pub fn generated() -> String {
    let mut out = String::from(
        "// Generated from the list of kinds (src/bsdfs/mod.rs) by src/bsdfs/gpu.rs.\n",
    );
    for (i, k) in KINDS.iter().enumerate() {
        out.push_str(&format!("const BSDF_{}: u32 = {i}u;\n", upper(k.name)));
    }
    // A kind no material of the scene has folds away where a pipeline is compiled.
    for k in KINDS {
        out.push_str(&format!("override HAS_{}: bool = true;\n", upper(k.name)));
    }
    out.push_str(&format!(
        "const BSDF_WORDS: u32 = {BSDF_WORDS}u;\nconst PARAM_TEXTURE_BITS: u32 = {PARAM_TEXTURE_BITS}u;\n\
         const MF_GGX: u32 = {MF_GGX}u;\nconst MF_BECKMANN: u32 = {MF_BECKMANN}u;\n"
    ));
    for (name, c) in [
        ("R", Channel::R),
        ("G", Channel::G),
        ("B", Channel::B),
        ("A", Channel::A),
        ("LUMINANCE", Channel::Luminance),
    ] {
        out.push_str(&format!(
            "const PARAM_CHANNEL_{name}: u32 = {}u;\n",
            c.code()
        ));
    }
    for k in KINDS {
        out.push_str(&(k.consts)());
    }
    // The record: the kind, its textured words, the words.
    let fields: String = (0..BSDF_WORDS)
        .map(|i| format!("    w{i}: vec4<u32>,\n"))
        .collect();
    out.push_str(&format!(
        "// A material's BSDF: its kind (BSDF_*), the mask of its textured slot words, its words.\n\
         struct Bsdf {{\n    kind: u32,\n    textured: u32,\n{fields}}}\n"
    ));
    // Each kind's class.
    out.push_str("// The class of a material's kind (shading::SurfaceClass).\nfn material_class(kind: u32) -> u32 {\n    switch kind {\n");
    for k in KINDS {
        out.push_str(&format!(
            "        case BSDF_{}: {{ return {}; }}\n",
            upper(k.name),
            class_const(k.class)
        ));
    }
    out.push_str("        default: { return CLASS_BLACK; }\n    }\n}\n");
    // Whether a camera path splits at the kind (it defines a split).
    let splits: Vec<String> = KINDS
        .iter()
        .filter(|k| declares(k.wgsl, &format!("{}_surface_split", k.prefix)))
        .map(|k| format!("(HAS_{0} && s.b.kind == BSDF_{0})", upper(k.name)))
        .collect();
    out.push_str(&format!(
        "// Whether a camera path splits at the surface (glass_branches.wgsl).\nfn surface_splits(s: Surface) -> bool {{\n    return {};\n}}\n",
        if splits.is_empty() { "false".to_string() } else { splits.join(" || ") }
    ));
    // Loading: only the kind's own words.
    out.push_str("// Material i's BSDF words: as many as its kind has (the rest zero).\nfn load_bsdf(i: u32, kind: u32, textured: u32) -> Bsdf {\n    var b: Bsdf;\n    b.kind = kind;\n    b.textured = textured;\n    var n = 0u;\n    switch kind {\n");
    for k in KINDS {
        out.push_str(&format!(
            "        case BSDF_{}: {{ n = {}u; }}\n",
            upper(k.name),
            k.words
        ));
    }
    out.push_str("        default: {}\n    }\n    let o = BSDF_WORDS * i;\n");
    for i in 0..BSDF_WORDS {
        out.push_str(&format!(
            "    if n > {i}u {{ b.w{i} = bsdfs[o + {i}u]; }}\n"
        ));
    }
    out.push_str("    return b;\n}\n");
    // Word k of a record, and the record with word k replaced (one switch each, so that
    // the lookup below is one call site in one loop, however many words a kind textures).
    out.push_str("fn bsdf_word(b: Bsdf, k: u32) -> vec4<u32> {\n    switch k {\n");
    for i in 0..BSDF_WORDS {
        out.push_str(&format!("        case {i}u: {{ return b.w{i}; }}\n"));
    }
    out.push_str("        default: { return vec4<u32>(0u); }\n    }\n}\n");
    out.push_str("fn bsdf_with_word(b_in: Bsdf, k: u32, w: vec4<u32>) -> Bsdf {\n    var b = b_in;\n    switch k {\n");
    for i in 0..BSDF_WORDS {
        out.push_str(&format!("        case {i}u: {{ b.w{i} = w; }}\n"));
    }
    out.push_str("        default: {}\n    }\n    return b;\n}\n");
    // The texture lookup: each textured word (a loop of at most BSDF_WORDS steps), then what
    // the kind recomputes.
    out.push_str(
        "// The BSDF with its textured slot words looked up at uv.\n\
         fn bsdf_resolve(b_in: Bsdf, uv: vec2<f32>) -> Bsdf {\n\
         \x20   var b = b_in;\n\
         \x20   if HAS_TEXTURES && b.textured != 0u {\n\
         \x20       for (var k = 0u; k < BSDF_WORDS; k += 1u) {\n\
         \x20           if (b.textured & (1u << k)) != 0u {\n\
         \x20               b = bsdf_with_word(b, k, param_eval(bsdf_word(b, k), uv));\n\
         \x20           }\n\
         \x20       }\n\
         \x20       b = bsdf_finish(b);\n\
         \x20   }\n\
         \x20   return b;\n}\n",
    );
    for method in METHODS {
        dispatcher(&mut out, method);
    }
    out
}

/// The WGSL files of the BSDFs the kernels compose, in order: the shared libraries, every
/// kind's file, the interface's defaults and the shading interface, then the generated part.
pub fn wgsl_library() -> String {
    let mut parts: Vec<&str> = vec![
        include_str!("math.wgsl"),
        include_str!("microfacet.wgsl"),
        include_str!("fresnel.wgsl"),
        include_str!("param.wgsl"),
        include_str!("interface.wgsl"),
        include_str!("blend.wgsl"),
    ];
    parts.extend(KINDS.iter().map(|k| k.wgsl).filter(|w| !w.is_empty()));
    parts.push(include_str!("shading.wgsl"));
    let generated = generated();
    parts.push(&generated);
    parts.join("\n")
}

/// Every WGSL file of this folder, by its path under `src/` (for the tests that read them).
pub fn wgsl_files() -> Vec<(String, &'static str)> {
    let mut out = vec![
        ("bsdfs/math.wgsl".to_string(), include_str!("math.wgsl")),
        (
            "bsdfs/microfacet.wgsl".to_string(),
            include_str!("microfacet.wgsl"),
        ),
        (
            "bsdfs/fresnel.wgsl".to_string(),
            include_str!("fresnel.wgsl"),
        ),
        ("bsdfs/param.wgsl".to_string(), include_str!("param.wgsl")),
        ("bsdfs/blend.wgsl".to_string(), include_str!("blend.wgsl")),
        (
            "bsdfs/interface.wgsl".to_string(),
            include_str!("interface.wgsl"),
        ),
        (
            "bsdfs/shading.wgsl".to_string(),
            include_str!("shading.wgsl"),
        ),
    ];
    out.extend(
        KINDS
            .iter()
            .filter(|k| !k.wgsl.is_empty())
            .map(|k| (format!("bsdfs/{}.wgsl", k.prefix), k.wgsl)),
    );
    out
}

/// The suffixes of the interface's methods: a kind implements `bsdf_eval_lobe` by declaring
/// `<prefix>_eval_lobe` in its WGSL file, and `interface.wgsl` / `shading.wgsl` declare the
/// defaults `default_eval_lobe`.
pub fn method_suffixes() -> Vec<&'static str> {
    METHODS.iter().map(|m| m.suffix).collect()
}
