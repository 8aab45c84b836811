//! glTF metallic-roughness materials mapped to ours (the table is in `scenes/README.md`):
//! - metallic 0, `KHR_materials_specular` 0, no transmission: Lambertian of the base colour
//!   (exactly the specification's BRDF then; a black base reflects nothing: our `black`);
//! - `KHR_materials_transmission` with a `KHR_materials_volume` of non-zero thickness,
//!   transmission 1 and metallic 0: a dielectric boundary of `KHR_materials_ior` (smooth
//!   glass at roughness 0 and a white base, else a rough dielectric whose transmission is
//!   tinted by the base colour);
//! - anything else: [`crate::bsdfs::MetallicRoughness`], the specification's Appendix B with
//!   `KHR_materials_specular` (`specularFactor`, `specularColorFactor`) and `_ior`, and a
//!   thin-walled `_transmission` (a volume with transmission below 1 or some metal is
//!   rendered thin-walled, and a note says so).
//!
//! Emission is `emissiveFactor x KHR_materials_emissive_strength`, one-sided. The base colour,
//! metallic-roughness and normal textures are read (`texture.rs`); the occlusion texture is
//! baked ambient occlusion, which global illumination computes itself, so it is not used.
//! The metallic-roughness BSDF also reads the transmission, specular and specular colour
//! textures, and an emissive material its emissive texture (`crate::lights::emission`).

use crate::bsdfs::rough_dielectric::RoughDielectric;
use crate::bsdfs::{Bsdf, Distribution, MetallicRoughness, Microfacet};
use crate::scene::Material;
use glam::Vec3;

/// Our material for glTF material `m`, and a note when it is only an approximation.
pub(crate) fn map(m: &gltf::Material) -> (Material, Option<String>) {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = Vec3::new(r, g, b).clamp(Vec3::ZERO, Vec3::ONE);
    let metallic = pbr.metallic_factor().clamp(0.0, 1.0);
    let roughness = pbr.roughness_factor().clamp(0.0, 1.0);
    let transmission = m
        .transmission()
        .map_or(0.0, |t| t.transmission_factor())
        .clamp(0.0, 1.0);
    let emission = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    // glTF's ior is 1 or more, or 0 (F0 = 1, for specular-glossiness conversions).
    let ior = m
        .ior()
        .filter(|i| *i == 0.0 || (*i >= 1.0 && i.is_finite()))
        .unwrap_or(1.5);
    let volume = m.volume().is_some_and(|v| v.thickness_factor() > 0.0);
    let mut note = None;
    let material = if transmission > 0.0 && volume && transmission == 1.0 && metallic == 0.0 {
        dielectric(ior, base, roughness)
    } else if is_lambertian(m) {
        match base == Vec3::ZERO {
            true => Material::black(),
            false => Material::diffuse(base),
        }
    } else {
        if transmission > 0.0 && volume {
            note = Some(format!(
                "KHR_materials_volume rendered thin-walled (transmission {transmission}, \
                 metallic {metallic}: a volume is rendered for transmission 1, metallic 0)"
            ));
        }
        let (specular, colour) = m.specular().map_or((1.0, Vec3::ONE), |s| {
            let c = Vec3::from(s.specular_color_factor());
            (s.specular_factor().clamp(0.0, 1.0), c.max(Vec3::ZERO))
        });
        let f0_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = (f0_ior * colour).min(Vec3::ONE) * specular;
        Material::of(MetallicRoughness::new(
            base,
            metallic,
            roughness,
            f0,
            specular,
            transmission,
        ))
    };
    (
        Material {
            emission,
            ..material
        },
        note,
    )
}

/// The absorbing medium inside a volume dielectric (`KHR_materials_volume` on a material
/// [`map`] made a dielectric boundary), as the extension defines it: light travelling a
/// distance `d` inside keeps `attenuationColor ^ (d / attenuationDistance)`, so
/// `sigma_t = -ln(attenuationColor) / attenuationDistance` per channel, albedo 0 (it absorbs,
/// it does not scatter). `None` without attenuation (the default distance is infinite) or for
/// a material rendered thin-walled. A colour channel of 0 absorbs as 1e-6 does.
pub(crate) fn absorption(
    m: &gltf::Material,
    material: &Material,
) -> Option<crate::media::builder::MediumParams> {
    let v = m.volume().filter(|v| v.thickness_factor() > 0.0)?;
    if !matches!(material.bsdf, Bsdf::Glass(_) | Bsdf::RoughDielectric(_)) {
        return None;
    }
    let d = v.attenuation_distance();
    let colour = Vec3::from(v.attenuation_color()).clamp(Vec3::splat(1e-6), Vec3::ONE);
    if !(d > 0.0 && d.is_finite()) || colour == Vec3::ONE {
        return None;
    }
    Some(crate::media::builder::MediumParams {
        sigma_t: Vec3::new(-colour.x.ln(), -colour.y.ln(), -colour.z.ln()) / d,
        albedo: Vec3::ZERO,
        scale: 1.0,
        g: 0.0,
    })
}

/// A dielectric boundary of index `ior`: glass when smooth and untinted, else a GGX rough
/// dielectric (alpha = roughness^2) whose transmission the base colour tints.
fn dielectric(ior: f32, base: Vec3, roughness: f32) -> Material {
    if roughness == 0.0 && base == Vec3::ONE {
        return Material::glass(ior);
    }
    let alpha = roughness * roughness;
    let mf = Microfacet::isotropic(Distribution::Ggx, alpha);
    Material::of(RoughDielectric::new(ior, Vec3::ONE, base, mf))
}

/// Whether `m` is exactly Lambertian: metallic 0, `KHR_materials_specular` 0 (no dielectric
/// reflection at all), no transmission.
fn is_lambertian(m: &gltf::Material) -> bool {
    let pbr = m.pbr_metallic_roughness();
    let specular = m.specular().map_or(1.0, |s| s.specular_factor());
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    transmission <= 0.0 && pbr.metallic_factor() <= 0.0 && specular <= 0.0
}

/// Whether `material`'s kind reads a base colour texture (diffuse, metallic-roughness).
pub(crate) fn reads_base_colour(material: &Material) -> bool {
    matches!(material.bsdf, Bsdf::Diffuse(_) | Bsdf::MetallicRoughness(_))
}

/// The texture whose uv set a primitive of `m` reads: the base colour's, else the
/// metallic-roughness', else the normal map's, else the emissive one's (one set per
/// primitive).
pub(crate) fn uv_texture<'a>(m: &gltf::Material<'a>) -> Option<(u32, &'static str)> {
    let pbr = m.pbr_metallic_roughness();
    let (material, _) = map(m);
    let base = pbr
        .base_color_texture()
        .filter(|_| reads_base_colour(&material))
        .map(|i| {
            (
                crate::importers::gltf::texture::uv_set(&i),
                "baseColorTexture",
            )
        });
    let mr = pbr
        .metallic_roughness_texture()
        .filter(|_| matches!(material.bsdf, Bsdf::MetallicRoughness(_)))
        .map(|i| {
            (
                crate::importers::gltf::texture::uv_set(&i),
                "metallicRoughnessTexture",
            )
        });
    let normal = m.normal_texture().map(|n| (n.tex_coord(), "normalTexture"));
    let emissive = m
        .emissive_texture()
        .filter(|_| material.is_emissive())
        .map(|i| {
            (
                crate::importers::gltf::texture::uv_set(&i),
                "emissiveTexture",
            )
        });
    base.or(mr).or(normal).or(emissive)
}

/// The textures `m` uses that are not read, by name (or `textures[i]`), with the slot they
/// fill: a base colour texture of a kind that has none (a dielectric), the emissive texture,
/// and the transmission and specular textures of a material that is not rendered as the
/// metallic-roughness BSDF.
pub(crate) fn textures(m: &gltf::Material) -> Vec<(String, &'static str)> {
    let pbr = m.pbr_metallic_roughness();
    let (material, _) = map(m);
    let mut out = Vec::new();
    let mut add = |t: Option<gltf::texture::Texture>, slot| {
        if let Some(t) = t {
            let name = t
                .name()
                .map_or(format!("textures[{}]", t.index()), str::to_string);
            out.push((name, slot));
        }
    };
    if !reads_base_colour(&material) {
        add(pbr.base_color_texture().map(|i| i.texture()), "base colour");
    }
    if !material.is_emissive() {
        // An emissive texture under a black emissiveFactor changes nothing: say so.
        add(
            m.emissive_texture().map(|i| i.texture()),
            "emissive (emissiveFactor is black)",
        );
    }
    if matches!(material.bsdf, Bsdf::MetallicRoughness(_)) {
        return out;
    }
    if let Some(t) = m.transmission() {
        add(
            t.transmission_texture().map(|i| i.texture()),
            "transmission",
        );
    }
    if let Some(s) = m.specular() {
        add(s.specular_texture().map(|i| i.texture()), "specular");
        add(
            s.specular_color_texture().map(|i| i.texture()),
            "specular colour",
        );
    }
    out
}
