//! The GPU side of the list of light kinds: the generated WGSL (each kind's code `LIGHT_*`,
//! its override `HAS_LIGHT_*`, the dispatch of every method to `<prefix>_<method>` or the
//! default (`light_default_*` in `light.wgsl`)), the library the kernels compose, and the pipeline constants a
//! scene's lights set.

use crate::lights::{Light, KINDS};

/// `Point` as `POINT`, `Triangles` as `TRIANGLES` (the WGSL names' upper case).
fn upper(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
    }
    out
}

/// A method of the interface as the generated dispatch calls it.
struct Method {
    /// The dispatcher's name.
    name: &'static str,
    /// The suffix of a kind's implementation (`<prefix>_<suffix>`) and its default's
    /// (`default_<suffix>`).
    suffix: &'static str,
    params: &'static str,
    args: &'static str,
    ret: &'static str,
}

/// The methods the generated code dispatches.
#[rustfmt::skip]
const METHODS: &[Method] = &[
    Method { name: "emit", suffix: "emit", params: "l: Light, u0: vec3<f32>, u3: f32, u4: f32", args: "l, u0, u3, u4", ret: "Emission" },
    Method { name: "sample_light", suffix: "sample", params: "l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>", args: "l, x, ns, u", ret: "LightSample" },
    Method { name: "light_anchor", suffix: "anchor", params: "l: Light, u: vec3<f32>", args: "l, u", ret: "Anchor" },
    Method { name: "light_material", suffix: "material", params: "l: Light", args: "l", ret: "LightSurface" },
];

/// The suffixes of the interface's methods (a kind's `<prefix>_<suffix>`, `default_<suffix>`).
pub fn method_suffixes() -> Vec<&'static str> {
    METHODS.iter().map(|m| m.suffix).collect()
}

/// The pipeline-overridable flag of each kind (`HAS_LIGHT_POINT`), in the order of their codes.
pub fn kind_flags() -> &'static [String] {
    static FLAGS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    FLAGS.get_or_init(|| {
        KINDS
            .iter()
            .map(|k| format!("HAS_LIGHT_{}", upper(k.name)))
            .collect()
    })
}

/// The override constants a scene's lights set: each kind's flag (whether some light is of
/// it) and each kind's own.
pub fn overrides(lights: &[Light]) -> Vec<(&'static str, f64)> {
    let mut out: Vec<(&'static str, f64)> = kind_flags()
        .iter()
        .enumerate()
        .map(|(i, flag)| {
            let used = lights.iter().any(|l| l.shape.code() as usize == i);
            (flag.as_str(), used as u32 as f64)
        })
        .collect();
    for k in KINDS {
        out.extend((k.overrides)(lights));
    }
    out
}

/// Whether `wgsl` declares `fn name(`.
fn declares(wgsl: &str, name: &str) -> bool {
    wgsl.contains(&format!("fn {name}("))
}

/// The generated part: codes, flags, and the dispatch of every method.
fn generated() -> String {
    let mut out = String::from("// Generated from the list of light kinds (src/lights/mod.rs).\n");
    for (i, k) in KINDS.iter().enumerate() {
        out.push_str(&format!("const LIGHT_{}: u32 = {i}u;\n", upper(k.name)));
        out.push_str(&format!("override {}: bool = true;\n", kind_flags()[i]));
    }
    // Delta lights: no surface, one shadow ray each, every BRDF lobe.
    let delta: Vec<String> = (0..KINDS.len())
        .filter(|&i| KINDS[i].delta)
        .map(|i| {
            format!(
                "({} && l.kind == LIGHT_{})",
                kind_flags()[i],
                upper(KINDS[i].name)
            )
        })
        .collect();
    let delta = if delta.is_empty() {
        "false".to_string()
    } else {
        delta.join(" || ")
    };
    out.push_str(&format!(
        "fn is_delta_light(l: Light) -> bool {{\n    return {delta};\n}}\n"
    ));
    for m in METHODS {
        out.push_str(&format!(
            "fn {}({}) -> {} {{\n    switch l.kind {{\n",
            m.name, m.params, m.ret
        ));
        for (i, k) in KINDS.iter().enumerate() {
            if declares(k.wgsl, &format!("{}_{}", k.prefix, m.suffix)) {
                out.push_str(&format!(
                    "        case LIGHT_{}: {{ if {} {{ return {}_{}({}); }} }}\n",
                    upper(k.name),
                    kind_flags()[i],
                    k.prefix,
                    m.suffix,
                    m.args
                ));
            }
        }
        out.push_str(&format!(
            "        default: {{}}\n    }}\n    return light_default_{}({});\n}}\n",
            m.suffix, m.args
        ));
    }
    out
}

/// The WGSL of the lights the kernels compose, in order: the shared part, the area lights'
/// helpers, every kind's file with its constants, then the generated part.
pub fn wgsl_library() -> String {
    let mut parts: Vec<String> = vec![
        include_str!("light.wgsl").to_string(),
        include_str!("area.wgsl").to_string(),
    ];
    for k in KINDS {
        parts.push((k.consts)());
        parts.push(k.wgsl.to_string());
    }
    parts.push(generated());
    parts.join("\n")
}

/// Every WGSL file of this folder, by its path under `src/` (for the tests that read them).
pub fn wgsl_files() -> Vec<(String, &'static str)> {
    let mut out = vec![
        ("lights/light.wgsl".to_string(), include_str!("light.wgsl")),
        ("lights/area.wgsl".to_string(), include_str!("area.wgsl")),
    ];
    out.extend(KINDS.iter().map(|k| (k.path.to_string(), k.wgsl)));
    out
}
