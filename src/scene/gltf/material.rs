//! glTF metallic-roughness materials mapped to ours (the table is in `scenes/README.md`):
//! - `KHR_materials_transmission` > 0: glass of `KHR_materials_ior` (default 1.5); exact
//!   for transmission 1, roughness 0 and a white base colour, else approximated;
//! - metallic 1, roughness 0: a mirror of reflectance = base colour;
//! - metallic 0, roughness 1, `KHR_materials_specular` 0: Lambertian of the base colour (a
//!   black base colour reflects nothing: our `black`, as the TOML `emissive` type);
//! - anything else: glossy (approximated), with alpha = roughness^2 and the Phong exponent
//!   `n = 2 / alpha^2 - 2` (the Blinn-Phong/Beckmann equivalence, capped at [`MAX_EXPONENT`]),
//!   `ks = (1 - metallic) 0.04 specular + metallic base` and
//!   `kd = (1 - metallic) (1 - 0.04 specular) base`, so kd + ks <= 1.
//!
//! Emission is `emissiveFactor x KHR_materials_emissive_strength`, one-sided. The base colour
//! texture of a Lambertian material is read ([`diffuse_texture`], `texture.rs`); other
//! textures are not: the factors are used and a warning names each texture.

use super::super::Material;
use glam::Vec3;

/// The largest Phong exponent a glossy approximation gets (roughness near 0).
pub const MAX_EXPONENT: f32 = 10_000.0;

/// F0 of a dielectric at `KHR_materials_specular` 1 (glTF's default, ior 1.5).
const DIELECTRIC_F0: f32 = 0.04;

/// Our material for glTF material `m`, and a note when it is only an approximation.
pub(super) fn map(m: &gltf::Material) -> (Material, Option<String>) {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = Vec3::new(r, g, b);
    let metallic = pbr.metallic_factor();
    let roughness = pbr.roughness_factor();
    let specular = m.specular().map_or(1.0, |s| s.specular_factor());
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    let emission = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    let (material, note) = if transmission > 0.0 {
        let ior = m.ior().unwrap_or(1.5);
        let exact = transmission == 1.0 && roughness == 0.0 && base == Vec3::ONE;
        let note = format!(
            "approximated as clear smooth glass of ior {ior} (transmission {transmission}, \
             roughness {roughness}, base colour {base})"
        );
        (Material::glass(ior), (!exact).then_some(note))
    } else if metallic == 1.0 && roughness == 0.0 {
        (Material::mirror(base), None)
    } else if is_lambertian(m) {
        match base == Vec3::ZERO {
            true => (Material::black(), None),
            false => (Material::diffuse(base), None),
        }
    } else {
        let f0 = DIELECTRIC_F0 * specular.clamp(0.0, 1.0);
        let ks = Vec3::splat((1.0 - metallic) * f0) + metallic * base;
        let kd = (1.0 - metallic) * (1.0 - f0) * base;
        let n = exponent(roughness);
        let note = format!(
            "approximated as glossy kd {kd}, ks {ks}, exponent {n} \
             (metallic {metallic}, roughness {roughness}, specular {specular})"
        );
        (Material::glossy(kd, ks, n), Some(note))
    };
    (
        Material {
            emission,
            ..material
        },
        note,
    )
}

/// Whether `m` maps to a Lambertian surface: metallic 0, roughness 1,
/// `KHR_materials_specular` 0, no transmission.
fn is_lambertian(m: &gltf::Material) -> bool {
    let pbr = m.pbr_metallic_roughness();
    let specular = m.specular().map_or(1.0, |s| s.specular_factor());
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    transmission <= 0.0
        && pbr.metallic_factor() == 0.0
        && pbr.roughness_factor() == 1.0
        && specular == 0.0
}

/// The base colour texture of `m` when it gives a diffuse albedo: `m` is Lambertian and its
/// `baseColorFactor` is not black (a black factor makes every texel black: our `black`).
pub(super) fn diffuse_texture<'a>(m: &gltf::Material<'a>) -> Option<gltf::texture::Info<'a>> {
    let [r, g, b, _] = m.pbr_metallic_roughness().base_color_factor();
    let black = Vec3::new(r, g, b) == Vec3::ZERO;
    (is_lambertian(m) && !black)
        .then(|| m.pbr_metallic_roughness().base_color_texture())
        .flatten()
}

/// The Phong exponent of roughness `r`: `2 / alpha^2 - 2` with `alpha = r^2`, in
/// [0, [`MAX_EXPONENT`]].
pub fn exponent(r: f32) -> f32 {
    let alpha = r * r;
    if alpha <= 0.0 {
        return MAX_EXPONENT;
    }
    (2.0 / (alpha * alpha) - 2.0).clamp(0.0, MAX_EXPONENT)
}

/// The textures `m` uses that are not read, by name (or `textures[i]`), with the slot they
/// fill (all but a [`diffuse_texture`]).
pub(super) fn textures(m: &gltf::Material) -> Vec<(String, &'static str)> {
    let pbr = m.pbr_metallic_roughness();
    let mut out = Vec::new();
    let mut add = |t: Option<gltf::texture::Texture>, slot| {
        if let Some(t) = t {
            let name = t
                .name()
                .map_or(format!("textures[{}]", t.index()), str::to_string);
            out.push((name, slot));
        }
    };
    if diffuse_texture(m).is_none() {
        add(pbr.base_color_texture().map(|i| i.texture()), "base colour");
    }
    add(
        pbr.metallic_roughness_texture().map(|i| i.texture()),
        "metallic-roughness",
    );
    add(m.normal_texture().map(|i| i.texture()), "normal");
    add(m.occlusion_texture().map(|i| i.texture()), "occlusion");
    add(m.emissive_texture().map(|i| i.texture()), "emissive");
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

#[cfg(test)]
mod tests {
    use super::exponent;

    #[test]
    fn exponent_follows_the_documented_rule() {
        assert_eq!(exponent(1.0), 0.0);
        assert!((exponent(0.5) - 30.0).abs() < 1e-4);
        assert_eq!(exponent(0.0), super::MAX_EXPONENT);
    }
}
