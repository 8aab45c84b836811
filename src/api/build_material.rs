//! The materials of a scene built in memory ([`super::SceneBuild`]): a [`MaterialSpec`] names
//! one of the renderer's own kinds ([`Scattering`]) with its parameters and textures, checked
//! here (the scene builder checks the classic kinds; the kinds of `crate::bsdfs` are checked
//! by whoever builds them) and turned into a `crate::scene::Material` by the constructors the
//! importers use.

use crate::bsdfs::{Bsdf, BsdfKind, Channel, Distribution, MetallicRoughness, Microfacet, Param};
use crate::scene::{Alpha, AlphaMode, Material, NO_TEXTURE};
use glam::Vec3;

/// How a built material scatters light: one of the renderer's material kinds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scattering {
    /// Reflects nothing (an emitter's surface, a black absorber).
    Black,
    /// Lambertian reflection of `colour` (each channel in [0, 1]).
    Diffuse {
        /// Albedo.
        colour: [f32; 3],
    },
    /// A perfect mirror of reflectance `colour` (no Fresnel).
    Mirror {
        /// Reflectance.
        colour: [f32; 3],
    },
    /// A dielectric boundary of index `ior` (inside over outside): smooth, untinted glass when
    /// `roughness` is 0 and `tint` white; else a GGX rough dielectric (alpha = roughness^2)
    /// whose transmission `tint` colours.
    Dielectric {
        /// Index of refraction, > 0.
        ior: f32,
        /// Perceptual roughness in [0, 1].
        roughness: f32,
        /// Tint of the transmitted light, each channel in [0, 1].
        tint: [f32; 3],
    },
    /// A conductor whose Fresnel reflectance is 1, tinted by `colour`: a mirror at roughness 0,
    /// else GGX with alpha = roughness^2.
    Conductor {
        /// Reflectance.
        colour: [f32; 3],
        /// Perceptual roughness in [0, 1].
        roughness: f32,
    },
    /// Lambertian `kd` plus a normalised Phong lobe `ks` (kd + ks <= 1 per channel).
    Phong {
        /// Diffuse albedo.
        kd: [f32; 3],
        /// Specular reflectance.
        ks: [f32; 3],
        /// Phong exponent, >= 0.
        exponent: f32,
    },
    /// glTF 2.0's metallic-roughness BSDF (`crate::bsdfs::MetallicRoughness`).
    MetallicRoughness {
        /// Base colour: diffuse albedo, metal F0, transmission tint (each in [0, 1]).
        base: [f32; 3],
        /// Metalness in [0, 1].
        metallic: f32,
        /// Perceptual roughness in [0, 1].
        roughness: f32,
        /// The dielectric's F0 colour (each in [0, 1]), e.g. `((ior - 1) / (ior + 1))^2`.
        f0: [f32; 3],
        /// The dielectric's F90, in [0, 1] (1 for a plain dielectric).
        f90: f32,
        /// Thin-walled transmission in [0, 1].
        transmission: f32,
    },
    /// An index-matched boundary: everything passes straight through.
    Transparent,
}

/// The opacity of a built material: `factor` times its texture's alpha (or luminance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaSpec {
    /// `Some(cutoff)`: opaque where the opacity reaches it, else transparent; `None`: opaque
    /// with probability equal to the opacity (stochastic blend).
    pub cutoff: Option<f32>,
    /// Constant opacity in [0, 1].
    pub factor: f32,
    /// A texture of the build that varies it.
    pub texture: Option<u32>,
    /// Read the texture's luminance rather than its alpha.
    pub luminance: bool,
}

/// A material of a [`super::SceneBuild`]: its kind and the textures that vary it (indices
/// returned by [`super::SceneBuild::add_texture`], linear RGBA).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialSpec {
    /// How it scatters.
    pub scattering: Scattering,
    /// Radiance it emits (W m^-2 sr^-1 per channel, >= 0).
    pub emission: [f32; 3],
    /// Emission from both faces (else from the front face only).
    pub two_sided_emission: bool,
    /// Base colour (diffuse albedo, metallic-roughness base colour), replacing the constant.
    pub colour_texture: Option<u32>,
    /// Metallic-roughness kind: blue multiplies the metalness, green the roughness.
    pub metallic_roughness_texture: Option<u32>,
    /// Metallic-roughness kind: red multiplies the transmission.
    pub transmission_texture: Option<u32>,
    /// Tangent-space normal map: rgb `c` is the normal `2 c - 1` in the frame (tangent along
    /// +u, bitangent along +v, normal).
    pub normal_texture: Option<u32>,
    /// Multiplies the emission.
    pub emission_texture: Option<u32>,
    /// Cut-outs and partial coverage; `None`: opaque.
    pub alpha: Option<AlphaSpec>,
}

impl MaterialSpec {
    /// A material of `scattering` with no emission, textures or alpha.
    pub fn new(scattering: Scattering) -> Self {
        MaterialSpec {
            scattering,
            emission: [0.0; 3],
            two_sided_emission: false,
            colour_texture: None,
            metallic_roughness_texture: None,
            transmission_texture: None,
            normal_texture: None,
            emission_texture: None,
            alpha: None,
        }
    }
}

/// `c` with every channel in [0, 1], else the message naming `field`.
fn unit_colour(c: [f32; 3], field: &str) -> Result<Vec3, String> {
    let v = Vec3::from(c);
    match v.is_finite() && v.min_element() >= 0.0 && v.max_element() <= 1.0 {
        true => Ok(v),
        false => Err(format!("{field}: components must be in [0, 1] (got {c:?})")),
    }
}

/// `x` in [0, 1], else the message naming `field`.
fn unit(x: f32, field: &str) -> Result<f32, String> {
    match (0.0..=1.0).contains(&x) {
        true => Ok(x),
        false => Err(format!("{field}: must be in [0, 1] (got {x})")),
    }
}

/// GGX of perceptual `roughness` (alpha = roughness^2, at least 1e-4).
fn ggx(roughness: f32) -> Microfacet {
    Microfacet::isotropic(Distribution::Ggx, (roughness * roughness).max(1e-4))
}

/// The material `spec` describes (its texture indices already checked against the build's
/// textures), or a message naming the field that is out of range.
pub(super) fn material(spec: &MaterialSpec) -> Result<Material, String> {
    let mut m = match spec.scattering {
        Scattering::Black => Material::black(),
        Scattering::Diffuse { colour } => Material::diffuse(unit_colour(colour, "colour")?),
        Scattering::Mirror { colour } => Material::mirror(unit_colour(colour, "colour")?),
        Scattering::Dielectric {
            ior,
            roughness,
            tint,
        } => {
            if !(ior.is_finite() && ior > 0.0) {
                return Err(format!("ior: must be positive and finite (got {ior})"));
            }
            let (roughness, tint) = (unit(roughness, "roughness")?, unit_colour(tint, "tint")?);
            if roughness == 0.0 && tint == Vec3::ONE {
                Material::glass(ior)
            } else {
                Material::from_bsdf(Bsdf::dielectric(ior, Vec3::ONE, tint, Some(ggx(roughness))))
            }
        }
        Scattering::Conductor { colour, roughness } => {
            let (colour, roughness) = (
                unit_colour(colour, "colour")?,
                unit(roughness, "roughness")?,
            );
            match roughness {
                0.0 => Material::mirror(colour),
                // Mitsuba's `none`: eta 0, k 1 reflects everything at every angle.
                r => Material::from_bsdf(Bsdf::conductor(
                    Vec3::ZERO,
                    Vec3::ONE,
                    colour,
                    Some(ggx(r)),
                )),
            }
        }
        Scattering::Phong { kd, ks, exponent } => {
            let (kd, ks) = (unit_colour(kd, "kd")?, unit_colour(ks, "ks")?);
            Material::glossy(kd, ks, exponent)
        }
        Scattering::MetallicRoughness {
            base,
            metallic,
            roughness,
            f0,
            f90,
            transmission,
        } => {
            let g = MetallicRoughness::new(
                unit_colour(base, "base")?,
                unit(metallic, "metallic")?,
                unit(roughness, "roughness")?,
                unit_colour(f0, "f0")?,
                unit(f90, "f90")?,
                unit(transmission, "transmission")?,
            );
            Material::from_bsdf(Bsdf::MetallicRoughness(g))
        }
        Scattering::Transparent => Material::null(),
    };
    m.emission = Vec3::from(spec.emission);
    m.two_sided_emission = spec.two_sided_emission;
    let texture = |t: Option<u32>| t.unwrap_or(NO_TEXTURE);
    let base_kinds = matches!(
        spec.scattering,
        Scattering::Diffuse { .. } | Scattering::MetallicRoughness { .. }
    );
    let mr = matches!(spec.scattering, Scattering::MetallicRoughness { .. });
    for (t, field, ok) in [
        (spec.colour_texture, "colour_texture", base_kinds),
        (
            spec.metallic_roughness_texture,
            "metallic_roughness_texture",
            mr,
        ),
        (spec.transmission_texture, "transmission_texture", mr),
    ] {
        if t.is_some() && !ok {
            let kind = format!("{:?}", spec.scattering);
            let kind = kind.split([' ', '{']).next().unwrap_or("");
            return Err(format!("{field}: a {kind} material has no such texture"));
        }
    }
    // As glTF's importer: the colour texture replaces the colour, metalness is the blue and
    // roughness the green channel of theirs, transmission the red.
    if let (Some(id), Some(p)) = (spec.colour_texture, m.bsdf.base_colour_mut()) {
        *p = Param::texture(id);
    }
    if let Bsdf::MetallicRoughness(g) = &mut m.bsdf {
        if let Some(id) = spec.metallic_roughness_texture {
            g.metallic = g.metallic.times(id, Channel::B);
            g.roughness = g.roughness.times(id, Channel::G);
        }
        if let Some(id) = spec.transmission_texture {
            g.transmission = g.transmission.times(id, Channel::R);
        }
    }
    m.normal_texture = texture(spec.normal_texture);
    if spec.emission_texture.is_some() && !m.is_emissive() {
        return Err("emission_texture: the material emits nothing".into());
    }
    m.emission_texture = texture(spec.emission_texture);
    if let Some(a) = spec.alpha {
        let factor = unit(a.factor, "alpha")?;
        let mode = match a.cutoff {
            Some(c) => AlphaMode::Mask(unit(c, "alpha_cutoff")?),
            None => AlphaMode::Blend,
        };
        m.alpha = Some(Alpha {
            mode,
            factor,
            texture: texture(a.texture),
            luminance: a.luminance,
        });
    }
    Ok(m)
}

/// The texture indices `spec` refers to, with their fields.
pub(super) fn textures(spec: &MaterialSpec) -> [(Option<u32>, &'static str); 6] {
    [
        (spec.colour_texture, "colour_texture"),
        (
            spec.metallic_roughness_texture,
            "metallic_roughness_texture",
        ),
        (spec.transmission_texture, "transmission_texture"),
        (spec.normal_texture, "normal_texture"),
        (spec.emission_texture, "emission_texture"),
        (spec.alpha.and_then(|a| a.texture), "alpha_texture"),
    ]
}
