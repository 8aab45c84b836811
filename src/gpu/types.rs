//! Rust twins of the WGSL structs in `shaders/common/types.wgsl`: `GpuX` mirrors WGSL `X`
//! field for field (`BvhNode` and `Photon` live in src/bvh.rs and src/photon.rs).
//! tests/gpu_layout.rs checks every size and offset against naga's reflection.

use super::codes::{material_code, LIGHT_POINT, LIGHT_SPHERE, LIGHT_TRIANGLES};
use crate::scene::{LightShape, Material, Scene, Sphere, Triangle};
use bytemuck::{Pod, Zeroable};

/// Twin of WGSL `Triangle`: a triangle's vertices, material and light (NO_LIGHT if none).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    pub v0: [f32; 3],
    pub material: u32,
    pub v1: [f32; 3],
    pub light: u32,
    pub v2: [f32; 3],
    pub _pad: u32,
}

/// Twin of WGSL `Sphere`: an analytic sphere with its material and light.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuSphere {
    pub center: [f32; 3],
    pub radius: f32,
    pub material: u32,
    pub light: u32,
    pub _pad0: u32,
    pub _pad1: u32,
}

/// Twin of WGSL `Material`: the BSDF parameters; `kind` is a MAT_* code.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub kd: [f32; 3],
    pub kind: u32,
    pub ks: [f32; 3],
    pub exponent: f32,
    pub emission: [f32; 3],
    pub ior: f32,
    pub two_sided: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}

/// Twin of WGSL `Light`: a light's sampling data (`kind` a LIGHT_* code) and its photon budgets.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 3],
    pub kind: u32,
    pub intensity: [f32; 3],
    pub first: u32,
    pub global_power: [f32; 3],
    pub count: u32,
    pub caustic_power: [f32; 3],
    pub cdf_start: u32,
    pub area: f32,
    pub global_offset: u32,
    pub global_count: u32,
    pub caustic_offset: u32,
    pub caustic_count: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}

/// Twin of WGSL `Aabb`: a specular surface's bounds that caustic photons aim at.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuAabb {
    pub bmin: [f32; 3],
    pub _pad0: u32,
    pub bmax: [f32; 3],
    pub _pad1: u32,
}

/// Twin of WGSL `Params`: the per-sample parameters of a pass (read-only storage, one slot per sample).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuParams {
    pub eye: [f32; 3],
    pub width: u32,
    pub forward: [f32; 3],
    pub height: u32,
    pub right: [f32; 3],
    pub spp: u32,
    pub up: [f32; 3],
    pub sample: u32,
    pub seed: u32,
    pub pass_index: u32,
    pub k: u32,
    pub filter_kind: u32,
    pub mode: u32,
    pub max_depth: u32,
    pub max_photon_bounces: u32,
    pub shadow_samples: u32,
    pub fresnel: u32,
    pub n_lights: u32,
    pub n_bounds: u32,
    pub n_triangles: u32,
    pub terms: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}

/// Twin of WGSL `MapParams`: what one photon map traces and how its hash grid is laid out.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMapParams {
    pub stream: u32,
    pub paths: u32,
    pub capacity: u32,
    pub table_size: u32,
    pub cell_size: f32,
    pub is_caustic: u32,
    pub drop_flags: u32,
    pub radius2: f32,
}

impl From<&Triangle> for GpuTriangle {
    fn from(t: &Triangle) -> Self {
        GpuTriangle {
            v0: t.v0.to_array(),
            material: t.material,
            v1: t.v1.to_array(),
            light: t.light,
            v2: t.v2.to_array(),
            _pad: 0,
        }
    }
}

impl From<&Sphere> for GpuSphere {
    fn from(s: &Sphere) -> Self {
        GpuSphere {
            center: s.center.to_array(),
            radius: s.radius,
            material: s.material,
            light: s.light,
            _pad0: 0,
            _pad1: 0,
        }
    }
}

impl From<&Material> for GpuMaterial {
    fn from(m: &Material) -> Self {
        GpuMaterial {
            kd: m.kd.to_array(),
            kind: material_code(m.kind),
            ks: m.ks.to_array(),
            exponent: m.exponent,
            emission: m.emission.to_array(),
            ior: m.ior,
            two_sided: m.two_sided_emission as u32,
            ..Default::default()
        }
    }
}

/// The lights with their sampling data; budgets are filled in by the renderer.
pub fn lights(scene: &Scene, table: &crate::light::LightTable) -> Vec<GpuLight> {
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let mut g = GpuLight {
                cdf_start: table.cdf_start[i],
                area: table.area[i],
                ..Default::default()
            };
            match l.shape {
                LightShape::Point {
                    position,
                    intensity,
                } => {
                    g.kind = LIGHT_POINT;
                    g.position = position.to_array();
                    g.intensity = intensity.to_array();
                }
                LightShape::Triangles { first, count } => {
                    g.kind = LIGHT_TRIANGLES;
                    g.first = first;
                    g.count = count;
                }
                LightShape::Sphere { index } => {
                    g.kind = LIGHT_SPHERE;
                    g.first = index;
                }
            }
            g
        })
        .collect()
}
