//! Rust twins of the WGSL structs in `src/integrators/gpu/types.wgsl`: `GpuX` mirrors WGSL `X`
//! field for field (`Photon` lives in src/integrators/photon.rs, the BVH's in src/bvh/gpu_layout.rs).
//! tests/gpu_layout.rs checks every size and offset against naga's reflection.

use crate::scene::{Material, Scene, Sphere, Triangle, VertexNormals};
use bytemuck::{Pod, Zeroable};

/// Twin of WGSL `Triangle`: a triangle's vertices, material, light (NO_LIGHT if none) and
/// vertex normals (FLAT if none).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    /// First vertex.
    pub v0: [f32; 3],
    /// Index into the materials.
    pub material: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// Index of its light, or NO_LIGHT.
    pub light: u32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// Index into the shading normals, or FLAT.
    pub shading: u32,
}

/// Twin of WGSL `ShadingNormals`: the unit vertex normals of one smooth-shaded triangle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuShadingNormals {
    /// Normal at `v0`.
    pub n0: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Normal at `v1`.
    pub n1: [f32; 3],
    /// Padding.
    pub _pad1: u32,
    /// Normal at `v2`.
    pub n2: [f32; 3],
    /// Padding.
    pub _pad2: u32,
}

impl From<&VertexNormals> for GpuShadingNormals {
    fn from(n: &VertexNormals) -> Self {
        GpuShadingNormals {
            n0: n[0].to_array(),
            n1: n[1].to_array(),
            n2: n[2].to_array(),
            ..Self::default()
        }
    }
}

/// Twin of WGSL `Sphere`: an analytic sphere with its material and light.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuSphere {
    /// Centre.
    pub center: [f32; 3],
    /// Radius.
    pub radius: f32,
    /// Index into the materials.
    pub material: u32,
    /// Index of its light, or NO_LIGHT.
    pub light: u32,
    /// Its frame (`Sphere::frame_words`: the quaternion as four snorm16).
    pub frame: [u32; 2],
}

/// Twin of WGSL `Material`: what wraps a material's BSDF (its emission, normal map and mask)
/// and the BSDF's kind (a `BSDF_*` code) with the mask of its textured words; the BSDF's own
/// words are the `bsdfs` buffer's (`crate::bsdfs::gpu::pack`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Emitted radiance.
    pub emission: [f32; 3],
    /// 1 when both sides emit.
    pub two_sided: u32,
    /// The BSDF's kind: its code in the list of kinds (`BSDF_*`).
    pub kind: u32,
    /// Bit i: the BSDF's word i is a slot with a texture.
    pub textured: u32,
    /// 1: black seen from the back of the geometric normal (`Material::one_sided`).
    pub one_sided: u32,
    /// Index into `tex_table` of the tangent-space normal map, or `NO_TEXTURE` (the last of
    /// word `MATERIAL_NORMAL_WORD`, which the intersection reads alone).
    pub normal_texture: u32,
    /// `ALPHA_NONE`, `ALPHA_MASK` or `ALPHA_BLEND`, plus `ALPHA_LUMINANCE` when the
    /// texture's luminance (not its alpha) is the opacity (`crate::scene::Alpha`); the
    /// alpha test's word `MATERIAL_ALPHA_WORD` starts here.
    pub alpha_mode: u32,
    /// Index into `tex_table` of the opacity's texture, or `NO_TEXTURE`.
    pub alpha_texture: u32,
    /// The opacity's constant factor.
    pub alpha_factor: f32,
    /// A mask's cutoff.
    pub alpha_cutoff: f32,
    /// A blend's first component (`crate::bsdfs::blend::Blend`), or `NO_BLEND`.
    pub blend_first: u32,
    /// A blend's second component.
    pub blend_second: u32,
    /// 1 when the blend stores photons (either component does).
    pub blend_stores: u32,
    /// 1 when the normal map shadows grazing light (`Material::normal_shadowing`).
    pub normal_shadowing: u32,
    /// The blend's weight: the probability of `blend_second`, a slot word (`Param::word`).
    pub blend_weight: [u32; 4],
    /// A bump map's scale (`Material::bump`; word `MATERIAL_BUMP_WORD`, which the
    /// intersection reads alone).
    pub bump_scale: f32,
    /// 1 when `normal_texture` is a bump map's height texture.
    pub bump: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
}

/// Twin of WGSL `Light`: a light's kind (its code in `lights::KINDS`) and photon budgets,
/// the emission texture of an area light, and the kind's own parameter words
/// (`LightKind::gpu_words`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// The kind's code (`LIGHT_*` in WGSL).
    pub kind: u32,
    /// First global path index of this light (word 0 `.y`: `light_of` bisects it).
    pub global_offset: u32,
    /// Global paths of this light.
    pub global_count: u32,
    /// First caustic path index of this light (word 0 `.w`).
    pub caustic_offset: u32,
    /// Power each global path carries.
    pub global_power: [f32; 3],
    /// Caustic paths (attempts) of this light.
    pub caustic_count: u32,
    /// Power each caustic path carries.
    pub caustic_power: [f32; 3],
    /// Emitting area.
    pub area: f32,
    /// Area light: the emission texture's mean over its surface (`LightTable::texture_mean`).
    pub texture_mean: [f32; 3],
    /// Area light: index into `tex_table` of its emission texture, or `NO_TEXTURE`.
    pub emission_texture: u32,
    /// The kind's parameters, word 4.
    pub p0: [u32; 4],
    /// Word 5.
    pub p1: [u32; 4],
    /// Word 6.
    pub p2: [u32; 4],
    /// Word 7.
    pub p3: [u32; 4],
}

/// Twin of WGSL `Aabb`: a specular surface's bounds that caustic photons aim at.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuAabb {
    /// Lower corner.
    pub bmin: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Upper corner.
    pub bmax: [f32; 3],
    /// Padding.
    pub _pad1: u32,
}

/// Twin of WGSL `Params`: a pass's parameters, one read-only storage slot per dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuParams {
    /// Camera position.
    pub eye: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Camera forward axis.
    pub forward: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Camera right axis (scaled by the field of view).
    pub right: [f32; 3],
    /// Camera samples per pixel.
    pub spp: u32,
    /// Camera up axis (scaled by the field of view).
    pub up: [f32; 3],
    /// The camera sample this slot's dispatch gathers.
    pub sample: u32,
    /// RNG seed.
    pub seed: u32,
    /// RNG pass index (with the batch in its high bits).
    pub pass_index: u32,
    /// Photons per K-nearest estimate (0: fixed radius).
    pub k: u32,
    /// A FILTER_* code.
    pub filter_kind: u32,
    /// The render mode (`settings::Mode as u32`).
    pub mode: u32,
    /// Camera path depth.
    pub max_depth: u32,
    /// Photon path bounces.
    pub max_photon_bounces: u32,
    /// Shadow rays per area light.
    pub shadow_samples: u32,
    /// A FRESNEL_* code.
    pub fresnel: u32,
    /// Number of lights.
    pub n_lights: u32,
    /// Number of specular bounds caustic photons aim at.
    pub n_bounds: u32,
    /// Number of triangles.
    pub n_triangles: u32,
    /// TERM_* bits of the mode.
    pub terms: u32,
    /// This sample's weight of the caustic-map estimate (`plan::caustic_weight`; 0: skip).
    pub caustic_weight: f32,
    /// A SAMPLER_* code.
    pub sampler: u32,
    /// The camera's pixel filter (`PixelFilter::code`).
    pub pixel_filter: u32,
    /// Its parameter (`PixelFilter::param`).
    pub filter_param: f32,
    /// The camera's aperture radius (0: a pinhole).
    pub aperture_radius: f32,
    /// The camera's focus distance.
    pub focus_distance: f32,
    /// The medium the camera sits in (`Scene::camera_medium`; `NO_MEDIUM` for vacuum).
    pub camera_medium: u32,
    /// The first image row of a gather dispatch's band of rows (`gpu::branches`).
    pub first_row: u32,
    /// 0: a sample's gather dispatch; `r + 1`: its round `r` of glass branches.
    pub branch_round: u32,
    /// 1: an orthographic camera (`Camera::orthographic`), else 0.
    pub orthographic: u32,
    /// The medium outside every shape (`Scene::outer_medium`).
    pub outer_medium: u32,
}

/// Twin of WGSL `Medium`: a homogeneous medium (`crate::media::Medium`) as the kernels use
/// it, `sigma_s = albedo sigma_t` precomputed.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMedium {
    /// Extinction per channel per scene unit.
    pub sigma_t: [f32; 3],
    /// The Henyey-Greenstein asymmetry.
    pub g: f32,
    /// Scattering per channel per scene unit.
    pub sigma_s: [f32; 3],
    /// A heterogeneous medium's record in the media buffer (its vec4 index, `media/gpu.rs`);
    /// `NO_MEDIUM` for a homogeneous one.
    pub grid: u32,
}

/// Twin of WGSL `MapParams`: what one photon map traces and how its hash grid is laid out.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMapParams {
    /// RNG stream of the map's paths (`rng::Stream`).
    pub stream: u32,
    /// Photon paths to trace (0: absent map).
    pub paths: u32,
    /// Photons the map's buffer holds.
    pub capacity: u32,
    /// Hash-table slots (a power of two).
    pub table_size: u32,
    /// Grid cell edge.
    pub cell_size: f32,
    /// 1 for the caustic map.
    pub is_caustic: u32,
    /// DROP_* bits: photons the grid leaves out.
    pub drop_flags: u32,
    /// Squared search radius.
    pub radius2: f32,
    /// K of the map's K-nearest estimates (0: fixed radius), for sizing the cells.
    pub k: u32,
    /// The area the map's photons are expected on (the scene's storing area times the map's
    /// concentration), for sizing the cells on the device; 0 keeps `cell_size` (an uploaded
    /// map's cells are the host's).
    pub storing_area: f32,
    /// The largest power channel of the photons in the grid, written on the device by the
    /// grid build (`scan_sums`; the host writes 0): the fixed-radius estimates' scale.
    pub max_power: f32,
    /// VOLUME_* bits: whether the map's paths store volume photons (participating media)
    /// and whether they leave the L S+ V ones to the caustic map's paths.
    pub volume_flags: u32,
}

// The word counts the WGSL accessors use (codes::*_WORDS) are the twins' sizes.
const _: () = {
    use crate::integrators::gpu::codes::{
        LIGHT_EMISSION_WORD, LIGHT_WORDS, MATERIAL_ALPHA_WORD, MATERIAL_BUMP_WORD,
        MATERIAL_NORMAL_WORD, MATERIAL_WORDS, MEDIUM_WORDS, PHOTON_WORDS, SPHERE_WORDS,
        TRIANGLE_WORDS,
    };
    use std::mem::size_of;
    assert!(size_of::<GpuTriangle>() == 16 * TRIANGLE_WORDS as usize);
    assert!(size_of::<GpuSphere>() == 16 * SPHERE_WORDS as usize);
    assert!(size_of::<GpuMaterial>() == 16 * MATERIAL_WORDS as usize);
    // The intersection reads the normal map as the last member of one word, and the alpha
    // test as one whole word (intersect.wgsl).
    assert!(std::mem::offset_of!(GpuMaterial, normal_texture) % 16 == 12);
    assert!(
        std::mem::offset_of!(GpuMaterial, normal_texture) / 16 == MATERIAL_NORMAL_WORD as usize
    );
    assert!(std::mem::offset_of!(GpuMaterial, bump_scale) == 16 * MATERIAL_BUMP_WORD as usize);
    assert!(std::mem::offset_of!(GpuMaterial, alpha_mode) % 16 == 0);
    assert!(std::mem::offset_of!(GpuMaterial, alpha_mode) / 16 == MATERIAL_ALPHA_WORD as usize);
    assert!(size_of::<GpuMedium>() == 16 * MEDIUM_WORDS as usize);
    assert!(size_of::<GpuLight>() == 16 * LIGHT_WORDS as usize);
    // bsdf_at reads an emitter's texture as the last member of one word.
    assert!(
        std::mem::offset_of!(GpuLight, emission_texture) == 16 * LIGHT_EMISSION_WORD as usize + 12
    );
    assert!(size_of::<crate::integrators::photon::Photon>() == 16 * PHOTON_WORDS as usize);
};

impl From<&Triangle> for GpuTriangle {
    fn from(t: &Triangle) -> Self {
        GpuTriangle {
            v0: t.v0.to_array(),
            material: t.material,
            v1: t.v1.to_array(),
            light: t.light,
            v2: t.v2.to_array(),
            shading: t.shading,
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
            frame: s.frame_words(),
        }
    }
}

impl GpuMaterial {
    /// `m`'s header, its BSDF of kind `kind` with textured words `textured`.
    pub fn new(m: &Material, kind: u32, textured: u32) -> Self {
        GpuMaterial {
            emission: m.emission.to_array(),
            two_sided: m.two_sided_emission as u32,
            kind,
            textured,
            normal_texture: m.normal_texture,
            alpha_mode: alpha_code(m),
            alpha_texture: m.alpha.map_or(crate::scene::NO_TEXTURE, |a| a.texture),
            alpha_factor: m.alpha.map_or(1.0, |a| a.factor),
            alpha_cutoff: match m.alpha.map(|a| a.mode) {
                Some(crate::scene::AlphaMode::Mask(c)) => c,
                _ => 0.0,
            },
            one_sided: m.one_sided as u32,
            blend_first: m
                .blend
                .map_or(crate::integrators::gpu::codes::NO_BLEND, |b| b.first),
            blend_second: m
                .blend
                .map_or(crate::integrators::gpu::codes::NO_BLEND, |b| b.second),
            blend_stores: m.blend.is_some_and(|b| b.stores_photons) as u32,
            normal_shadowing: m.normal_shadowing as u32,
            blend_weight: m.blend.map_or([0; 4], |b| b.weight.word()),
            bump_scale: m.bump.unwrap_or(0.0),
            bump: m.bump.is_some() as u32,
            _pad0: 0,
            _pad1: 0,
        }
    }
}

/// The `ALPHA_*` code of `m`'s alpha test; emitters are opaque (as on the CPU).
fn alpha_code(m: &Material) -> u32 {
    use crate::integrators::gpu::codes::{ALPHA_BLEND, ALPHA_LUMINANCE, ALPHA_MASK, ALPHA_NONE};
    match m.alpha.filter(|_| !m.is_emissive()) {
        None => ALPHA_NONE,
        Some(a) => {
            let mode = match a.mode {
                crate::scene::AlphaMode::Mask(_) => ALPHA_MASK,
                crate::scene::AlphaMode::Blend => ALPHA_BLEND,
            };
            mode | if a.luminance { ALPHA_LUMINANCE } else { 0 }
        }
    }
}

/// The materials' headers and their BSDFs' words and tables (`crate::bsdfs::gpu::pack`).
pub fn materials(scene: &Scene) -> (Vec<GpuMaterial>, crate::bsdfs::gpu::PackedBsdfs) {
    let packed = crate::bsdfs::gpu::pack(scene.materials.iter().map(|m| &m.bsdf));
    let mats = scene
        .materials
        .iter()
        .zip(&packed.headers)
        .map(|(m, &(kind, textured))| GpuMaterial::new(m, kind, textured))
        .collect();
    (mats, packed)
}

/// Each triangle's uv record: corner uvs as vec4 words `(u0, v0, u1, v1), (u2, v2, 0, 0)`
/// (`UV_WORDS`), then with vertex tangents its corners' `(x, y, z, w)` (`UV_TANGENT_WORDS` in
/// all); one zeroed record when the scene has none.
pub fn triangle_uvs(scene: &Scene) -> Vec<[f32; 4]> {
    let words = if scene.tangents.is_empty() {
        crate::integrators::gpu::codes::UV_WORDS
    } else {
        crate::integrators::gpu::codes::UV_TANGENT_WORDS
    } as usize;
    // Without uvs no kernel reads them (HAS_UVS is false).
    if scene.uvs.is_empty() {
        return vec![[0.0; 4]; words];
    }
    let mut out = Vec::with_capacity(words * scene.uvs.len());
    for (i, c) in scene.uvs.iter().enumerate() {
        out.push([c[0].x, c[0].y, c[1].x, c[1].y]);
        out.push([c[2].x, c[2].y, 0.0, 0.0]);
        if let Some(t) = scene.tangents.get(i) {
            out.extend(t.map(|t| t.to_array()));
        }
    }
    out
}

/// The lights with their sampling data; budgets are filled in by the renderer.
pub fn lights(scene: &Scene, table: &crate::lights::table::LightTable) -> Vec<GpuLight> {
    use crate::lights::interface::LightKind;
    scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let c = table.context(scene, i);
            let [p0, p1, p2, p3] = l.shape.gpu_words(&c);
            GpuLight {
                kind: l.shape.code(),
                area: c.area,
                emission_texture: c.emission_texture,
                texture_mean: c.texture_mean.to_array(),
                p0,
                p1,
                p2,
                p3,
                ..Default::default()
            }
        })
        .collect()
}
