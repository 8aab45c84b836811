//! The GPU twin of a resolved BSDF ([`crate::bsdfs::Bsdf`]): [`GpuBsdf`] is WGSL's
//! `BsdfParams` of `src/bsdfs/bsdf.wgsl` (the WGSL twin of `src/bsdf/`), with the kind
//! and distribution codes both sides use and the rough plastics' transmittance tables, which
//! the kernels read from a read-only storage array `bsdf_tables: array<f32>` at
//! `BsdfParams.table`.
//!
//! The codes are Rust consts here and reach WGSL through [`wgsl_codes`]; they will move into
//! `codes.rs`'s generated prelude (`shared_constants`) when a kernel composes `bsdf.wgsl`.
//! Until then only the oracle probe (`tests/probes/probe_bsdf.wgsl`, composed by
//! [`probe_source`]) uses the library.

use crate::bsdfs::{
    schlick_mean_table, Bsdf, Distribution, Microfacet, SCHLICK_MEAN_RES, TRANSMITTANCE_RES,
};
use bytemuck::{Pod, Zeroable};

/// `src/bsdfs/bsdf.wgsl`: the BSDF library's kinds (no entry point).
pub const BSDF_WGSL: &str = include_str!("../../bsdfs/bsdf.wgsl");
/// `src/bsdfs/bsdf_gltf.wgsl`: glTF's metallic-roughness kind.
pub const BSDF_GLTF_WGSL: &str = include_str!("../../bsdfs/bsdf_gltf.wgsl");
/// `src/bsdfs/bsdf_dispatch.wgsl`: the Bsdf methods, dispatching to the kinds.
pub const BSDF_DISPATCH_WGSL: &str = include_str!("../../bsdfs/bsdf_dispatch.wgsl");

/// `Bsdf::Diffuse`.
pub const BSDF_DIFFUSE: u32 = 0;
/// `Bsdf::Conductor` without a microfacet (Mitsuba's `conductor`).
pub const BSDF_CONDUCTOR: u32 = 1;
/// `Bsdf::Conductor` with a microfacet (`roughconductor`).
pub const BSDF_ROUGH_CONDUCTOR: u32 = 2;
/// `Bsdf::Dielectric` without a microfacet (`dielectric`).
pub const BSDF_DIELECTRIC: u32 = 3;
/// `Bsdf::Dielectric` with a microfacet (`roughdielectric`).
pub const BSDF_ROUGH_DIELECTRIC: u32 = 4;
/// `Bsdf::ThinDielectric` (`thindielectric`).
pub const BSDF_THIN_DIELECTRIC: u32 = 5;
/// `Bsdf::Plastic` with a smooth coating (`plastic`).
pub const BSDF_PLASTIC: u32 = 6;
/// `Bsdf::Plastic` with a rough coating (`roughplastic`): reads its table.
pub const BSDF_ROUGH_PLASTIC: u32 = 7;
/// `Bsdf::MetallicRoughness` (glTF): `albedo` the base colour, `eta_c` (metallic,
/// roughness, transmission), `specular` the dielectric's f0, `eta` its f90, `textures` the
/// material's parameter textures.
pub const BSDF_GLTF: u32 = 8;
/// `Distribution::Ggx`.
pub const MF_GGX: u32 = 0;
/// `Distribution::Beckmann`.
pub const MF_BECKMANN: u32 = 1;
/// Words of one rough plastic's transmittance table in `bsdf_tables`.
pub const BSDF_TABLE_RES: u32 = TRANSMITTANCE_RES as u32;

/// Every code `bsdf.wgsl` reads: (WGSL name, value).
pub fn codes() -> [(&'static str, u32); 13] {
    [
        ("BSDF_DIFFUSE", BSDF_DIFFUSE),
        ("BSDF_CONDUCTOR", BSDF_CONDUCTOR),
        ("BSDF_ROUGH_CONDUCTOR", BSDF_ROUGH_CONDUCTOR),
        ("BSDF_DIELECTRIC", BSDF_DIELECTRIC),
        ("BSDF_ROUGH_DIELECTRIC", BSDF_ROUGH_DIELECTRIC),
        ("BSDF_THIN_DIELECTRIC", BSDF_THIN_DIELECTRIC),
        ("BSDF_PLASTIC", BSDF_PLASTIC),
        ("BSDF_ROUGH_PLASTIC", BSDF_ROUGH_PLASTIC),
        ("BSDF_GLTF", BSDF_GLTF),
        ("MF_GGX", MF_GGX),
        ("MF_BECKMANN", MF_BECKMANN),
        ("BSDF_TABLE_RES", BSDF_TABLE_RES),
        ("GLTF_MEAN_RES", SCHLICK_MEAN_RES as u32),
    ]
}

/// The codes as WGSL `const` declarations (to join the prelude later, see the module docs).
pub fn wgsl_codes() -> String {
    let mut out = String::from(
        "// BSDF codes, generated from src/integrators/gpu/bsdf_params.rs (to move into the prelude).\n",
    );
    for (name, v) in codes() {
        out.push_str(&format!("const {name}: u32 = {v}u;\n"));
    }
    // S(mu) of the glTF material's diffuse part, as Rust computed it (Debug prints the
    // shortest decimal that reads back to the same f32).
    let table: Vec<String> = schlick_mean_table()
        .iter()
        .map(|v| format!("{v:?}f"))
        .collect();
    out.push_str(&format!(
        "const BSDF_GLTF_MEAN = array<f32, {}>({});\n",
        SCHLICK_MEAN_RES + 1,
        table.join(", ")
    ));
    out
}

/// The BSDF library as the kernels compose it: its codes, the kinds and the dispatch.
pub fn bsdf_library() -> String {
    [
        wgsl_codes().as_str(),
        BSDF_WGSL,
        BSDF_GLTF_WGSL,
        BSDF_DISPATCH_WGSL,
    ]
    .join("\n")
}

/// WGSL `BsdfParams` (112 bytes, 16-aligned): each kind fills the fields its variant has and
/// leaves the others zero.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBsdf {
    /// Conductor: real part of the complex index.
    pub eta_c: [f32; 3],
    /// `BSDF_*` code.
    pub kind: u32,
    /// Conductor: imaginary part of the complex index.
    pub k_c: [f32; 3],
    /// `MF_GGX` or `MF_BECKMANN` (rough kinds).
    pub distribution: u32,
    /// Conductor tint; dielectric, thin dielectric and plastic `specular_reflectance`.
    pub specular: [f32; 3],
    /// Roughness along x (rough kinds).
    pub alpha_u: f32,
    /// Dielectric and thin dielectric `specular_transmittance`.
    pub transmittance: [f32; 3],
    /// Roughness along y (rough kinds; the plastic's equals `alpha_u`).
    pub alpha_v: f32,
    /// Diffuse albedo; plastic `diffuse_reflectance`.
    pub albedo: [f32; 3],
    /// Dielectric, thin dielectric and plastic relative index (interior / exterior).
    pub eta: f32,
    /// Plastic: 1 when nonlinear.
    pub nonlinear: u32,
    /// Rough plastic: offset of its [`BSDF_TABLE_RES`] words in `bsdf_tables`.
    pub table: u32,
    /// Plastic: the coating's sampling weight.
    pub specular_sampling_weight: f32,
    /// Plastic: Fdr, the coating's internal reflectance.
    pub internal_reflectance: f32,
    /// Metallic-roughness: its textures in `tex_table` (metallic-roughness, transmission,
    /// specular, specular colour; `NO_TEXTURE` when absent), set by `types::materials`.
    pub textures: [u32; 4],
}

fn microfacet(g: &mut GpuBsdf, mf: &Microfacet) {
    g.distribution = match mf.distribution {
        Distribution::Ggx => MF_GGX,
        Distribution::Beckmann => MF_BECKMANN,
    };
    g.alpha_u = mf.alpha_u;
    g.alpha_v = mf.alpha_v;
}

/// The GPU form of `b`; a rough plastic's table is expected at word `table_offset` of
/// `bsdf_tables` (see [`table_words`]); `textures` are `NO_TEXTURE` here (a
/// metallic-roughness material's are set by `types::materials`).
pub fn gpu_bsdf(b: &Bsdf, table_offset: u32) -> GpuBsdf {
    let mut g = GpuBsdf {
        table: table_offset,
        textures: [crate::scene::NO_TEXTURE; 4],
        ..GpuBsdf::default()
    };
    match b {
        Bsdf::Diffuse { albedo } => {
            g.kind = BSDF_DIFFUSE;
            g.albedo = albedo.to_array();
        }
        Bsdf::Conductor {
            eta,
            k,
            specular,
            microfacet: mf,
        } => {
            g.kind = if mf.is_some() {
                BSDF_ROUGH_CONDUCTOR
            } else {
                BSDF_CONDUCTOR
            };
            g.eta_c = eta.to_array();
            g.k_c = k.to_array();
            g.specular = specular.to_array();
            if let Some(mf) = mf {
                microfacet(&mut g, mf);
            }
        }
        Bsdf::Dielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
            microfacet: mf,
        } => {
            g.kind = if mf.is_some() {
                BSDF_ROUGH_DIELECTRIC
            } else {
                BSDF_DIELECTRIC
            };
            g.eta = *eta;
            g.specular = specular_reflectance.to_array();
            g.transmittance = specular_transmittance.to_array();
            if let Some(mf) = mf {
                microfacet(&mut g, mf);
            }
        }
        Bsdf::ThinDielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
        } => {
            g.kind = BSDF_THIN_DIELECTRIC;
            g.eta = *eta;
            g.specular = specular_reflectance.to_array();
            g.transmittance = specular_transmittance.to_array();
        }
        Bsdf::Plastic(p) => {
            g.kind = if p.microfacet.is_some() {
                BSDF_ROUGH_PLASTIC
            } else {
                BSDF_PLASTIC
            };
            g.albedo = p.diffuse_reflectance.to_array();
            g.specular = p.specular_reflectance.to_array();
            g.eta = p.eta;
            g.nonlinear = p.nonlinear as u32;
            g.specular_sampling_weight = p.specular_sampling_weight;
            g.internal_reflectance = p.internal_reflectance;
            if let Some(mf) = &p.microfacet {
                microfacet(&mut g, mf);
            }
        }
        Bsdf::MetallicRoughness(m) => {
            g.kind = BSDF_GLTF;
            g.albedo = m.base.to_array();
            g.eta_c = [m.metallic, m.roughness, m.transmission];
            g.specular = m.f0.to_array();
            g.eta = m.f90;
            microfacet(&mut g, &m.microfacet());
        }
    }
    g
}

/// The words `b` needs in `bsdf_tables`: a rough plastic's transmittance table
/// ([`BSDF_TABLE_RES`] words), nothing for the other kinds.
pub fn table_words(b: &Bsdf) -> Vec<f32> {
    match b {
        Bsdf::Plastic(p) if p.microfacet.is_some() => p.external_transmittance.to_vec(),
        _ => Vec::new(),
    }
}

/// Packs `bsdfs` for the device: their `GpuBsdf`s and `bsdf_tables` (each rough plastic's
/// table appended in order; one zero word when there is none, as a binding is never empty).
pub fn pack(bsdfs: &[Bsdf]) -> (Vec<GpuBsdf>, Vec<f32>) {
    let mut tables = Vec::new();
    let params = bsdfs
        .iter()
        .map(|b| {
            let g = gpu_bsdf(b, tables.len() as u32);
            tables.extend(table_words(b));
            g
        })
        .collect();
    if tables.is_empty() {
        tables.push(0.0);
    }
    (params, tables)
}
