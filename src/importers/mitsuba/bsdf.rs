//! Mitsuba BSDFs as our materials (the mapping is documented in `scenes/README.md`), each as
//! Mitsuba 3 defines it (`crate::bsdfs`): `diffuse` (constant or textured reflectance),
//! `twosided`, `conductor`, `roughconductor` (named materials, eta/k), `dielectric`,
//! `roughdielectric`, `thindielectric`, `plastic`, `roughplastic`, `principled`, and
//! `normalmap` around any of them.

use crate::bsdfs::conductor::Conductor;
use crate::bsdfs::rough_conductor::RoughConductor;
use crate::bsdfs::rough_dielectric::RoughDielectric;
use crate::bsdfs::thin_dielectric::ThinDielectric;
use crate::bsdfs::{named_conductor, Distribution, Microfacet, Param, Plastic, METAL_NAMES};
use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::texture::texture;
use crate::importers::mitsuba::values::Cx;
use crate::scene::{Alpha, AlphaMode, Material, NO_TEXTURE};
use crate::textures::SceneTexture;
use glam::Vec3;
use roxmltree::Node;

/// Mitsuba's default `ext_ior` (air).
const AIR: f32 = 1.000277;

/// A material read from a `<bsdf>`, with the textures its base colour and its normal take (the
/// caller adds them to the scene and sets the base colour's texture and `normal_texture`).
pub(crate) struct Read {
    /// The material.
    pub material: Material,
    /// A textured diffuse reflectance (the kind's base colour).
    pub kd_texture: Option<SceneTexture>,
    /// The tangent-space normal map of a `normalmap` bsdf.
    pub normal_texture: Option<SceneTexture>,
    /// The textured opacity of a `mask` bsdf (its luminance; `material.alpha` set).
    pub alpha_texture: Option<SceneTexture>,
    /// The textures of other parameters (`principled`), each with the channel it reads and
    /// where it goes.
    pub param_textures: Vec<crate::importers::mitsuba::principled::ParamTexture>,
}

/// The one `<bsdf>` (or `<ref>` to one) nested in the wrapper bsdf `p` (`twosided`,
/// `normalmap`, `mask`) at `node`.
fn nested_bsdf<'f>(
    cx: &Cx<'f>,
    p: &Plugin<'f>,
    node: Node<'f, 'f>,
    field: &str,
) -> Result<Node<'f, 'f>> {
    let message = format!("`{}` needs a nested <bsdf>", p.kind);
    let Some(&inner) = p.objects.first() else {
        return Err(cx.err(node, field, message));
    };
    let inner = cx.deref(inner, field)?;
    if inner.tag_name().name() != "bsdf" {
        return Err(cx.err(inner, field, message));
    }
    Ok(inner)
}

/// The microfacet roughness of a rough plugin: `distribution` (`beckmann` default, `ggx`),
/// `alpha` (default 0.1) or `alpha_u` and `alpha_v`.
fn microfacet(cx: &Cx, p: &Plugin) -> Result<Microfacet> {
    let distribution = match p.string(cx, "distribution")?.as_deref() {
        None | Some("beckmann") => Distribution::Beckmann,
        Some("ggx") => Distribution::Ggx,
        Some(other) => {
            let message = format!("unknown distribution `{other}` (expected beckmann or ggx)");
            return Err(cx.err(p.node_of("distribution"), &p.at("distribution"), message));
        }
    };
    p.ignore(&["sample_visible"]);
    let alpha = p.positive(cx, "alpha", 0.1)?;
    let u = p.float(cx, "alpha_u")?.unwrap_or(alpha);
    let v = p.float(cx, "alpha_v")?.unwrap_or(alpha);
    for (name, a) in [("alpha_u", u), ("alpha_v", v)] {
        if !(a > 0.0 && a.is_finite()) {
            return Err(cx.err(p.node_of(name), &p.at(name), "must be positive"));
        }
    }
    Ok(Microfacet::new(distribution, u, v))
}

/// A conductor's complex index: `material` (a name from Mitsuba's table; default `none`,
/// a perfect reflector) or `eta` and `k`.
fn conductor_ior(cx: &Cx, p: &Plugin) -> Result<(Vec3, Vec3)> {
    let eta = p.color(cx, "eta")?;
    let k = p.color(cx, "k")?;
    let material = p.string(cx, "material")?;
    match (eta, k, material.as_deref()) {
        (Some(eta), k, None) => Ok((eta, k.unwrap_or(Vec3::ZERO))),
        (None, Some(_), _) => Err(cx.err(p.node_of("k"), &p.at("k"), "`k` needs `eta`")),
        (Some(_), _, Some(_)) => {
            let message = "give either `material` or `eta` and `k`";
            Err(cx.err(p.node_of("material"), &p.at("material"), message))
        }
        // A perfect mirror: Mitsuba's `none` is eta 0, k 1 (reflectance 1).
        (None, None, None | Some("none")) => Ok((Vec3::ZERO, Vec3::ONE)),
        (None, None, Some(name)) => named_conductor(name).ok_or_else(|| {
            let message = format!(
                "unknown conductor material `{name}` (Mitsuba's names: {})",
                METAL_NAMES.join(", ")
            );
            cx.err(p.node_of("material"), &p.at("material"), message)
        }),
    }
}

/// Reads the `<bsdf>` element `node` at `field` as a material; approximations push a warning
/// naming the bsdf.
pub(crate) fn bsdf(cx: &Cx, node: Node, field: &str, warnings: &mut Vec<String>) -> Result<Read> {
    let p = Plugin::new(cx, node, field.to_string())?;
    let kind = p.kind.as_str();
    let wrapper = kind == "twosided" || kind == "normalmap" || kind == "mask";
    if let Some(&extra) = p.objects.get(usize::from(wrapper)) {
        let tag = extra.tag_name().name();
        let message = format!("unsupported <{tag}> inside a `{kind}` bsdf");
        return Err(cx.err(extra, field, message));
    }
    let mut kd_texture = None;
    let mut param_textures = Vec::new();
    let material = match kind {
        "twosided" => {
            // Our materials reflect on both sides already: the nested bsdf is the material;
            // a principled one (one interface, as in Mitsuba) is told it is two-sided.
            let inner = nested_bsdf(cx, &p, node, field)?;
            p.done(cx)?;
            let mut read = bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?;
            if let crate::bsdfs::Bsdf::Principled(k) = &mut read.material.bsdf {
                k.two_sided = true;
            }
            return Ok(read);
        }
        "normalmap" => {
            // Mitsuba 3's `normalmap`: the nested bsdf in the shading frame that the texture's
            // rgb `c` gives as the normal `2 c - 1` relative to the hit's frame. The texture
            // is read as Mitsuba reads any bitmap: sRGB-decoded unless `raw` (Mitsuba's
            // documentation sets `raw`, normal maps being linear data).
            let inner = nested_bsdf(cx, &p, node, field)?;
            let Some(t) = p.texture_param("normalmap") else {
                let message = "`normalmap` needs a <texture name=\"normalmap\">";
                return Err(cx.err(p.node_of("normalmap"), field, message));
            };
            let tex = texture(cx, t, &p.at("normalmap"))?;
            if !p.boolean_or(cx, "flip_invalid_normals", true)? {
                let message = "only Mitsuba's default `true` is supported";
                let name = "flip_invalid_normals";
                return Err(cx.err(p.node_of(name), &p.at(name), message));
            }
            if p.boolean_or(cx, "use_shadowing_function", true)? {
                warnings.push(format!(
                    "{field}: `normalmap` without Mitsuba's shadowing function \
                     (use_shadowing_function: the shadow-terminator factor is not applied)"
                ));
            }
            p.done(cx)?;
            let mut read = bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?;
            if read.normal_texture.is_some() {
                let message = "a `normalmap` inside a `normalmap` is not supported";
                return Err(cx.err(inner, field, message));
            }
            read.normal_texture = Some(tex);
            return Ok(read);
        }
        "mask" => {
            // Mitsuba 3's `mask`: the nested bsdf where a stochastic choice of probability
            // `opacity` (float or texture, default 0.5) stops the ray, else the ray passes on
            // unchanged (crate::scene::AlphaMode::Blend). A textured opacity is the texture's
            // luminance, as Mitsuba evaluates a colour texture as a float.
            let inner = nested_bsdf(cx, &p, node, field)?;
            let (factor, tex) = match p.texture_param("opacity") {
                Some(t) => (1.0, Some(texture(cx, t, &p.at("opacity"))?)),
                None => {
                    let v = p.float(cx, "opacity")?.unwrap_or(0.5);
                    if !(0.0..=1.0).contains(&v) {
                        let message = format!("must be in [0, 1] (got {v})");
                        return Err(cx.err(p.node_of("opacity"), &p.at("opacity"), message));
                    }
                    (v, None)
                }
            };
            p.done(cx)?;
            let mut read = bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?;
            if read.material.alpha.is_some() {
                let message = "a `mask` inside a `mask` is not supported";
                return Err(cx.err(inner, field, message));
            }
            read.material.alpha = Some(Alpha {
                mode: AlphaMode::Blend,
                factor,
                texture: NO_TEXTURE,
                luminance: true,
            });
            read.alpha_texture = tex;
            return Ok(read);
        }
        "diffuse" => match p.texture_param("reflectance") {
            Some(t) => {
                let tex = texture(cx, t, &p.at("reflectance"))?;
                kd_texture = Some(tex);
                // The texture's index is set when the caller adds it.
                Material::diffuse(Vec3::ONE)
            }
            None => {
                let albedo = p.albedo(cx, "reflectance", 0.5)?;
                if albedo == Vec3::ZERO {
                    Material::black()
                } else {
                    Material::diffuse(albedo)
                }
            }
        },
        "conductor" | "roughconductor" => {
            let (eta, k) = conductor_ior(cx, &p)?;
            let specular = p.albedo(cx, "specular_reflectance", 1.0)?;
            let microfacet = match kind {
                "conductor" => None,
                _ => Some(microfacet(cx, &p)?),
            };
            // A smooth conductor of material `none` (eta 0, k 1) reflects everything.
            if microfacet.is_none() && eta == Vec3::ZERO && k == Vec3::ONE {
                p.done(cx)?;
                return Ok(Read {
                    material: Material::mirror(specular),
                    kd_texture,
                    normal_texture: None,
                    alpha_texture: None,
                    param_textures: Vec::new(),
                });
            }
            match microfacet {
                None => Material::of(Conductor {
                    eta,
                    k,
                    specular: Param::rgb(specular),
                }),
                Some(mf) => Material::of(RoughConductor::new(eta, k, specular, mf)),
            }
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let int_ior = p.ior(cx, "int_ior", 1.5046)?;
            let ext_ior = p.ior(cx, "ext_ior", AIR)?;
            let specular_reflectance = p.albedo(cx, "specular_reflectance", 1.0)?;
            let specular_transmittance = p.albedo(cx, "specular_transmittance", 1.0)?;
            // Refraction and Fresnel depend only on the ratio; our outside is exactly 1.
            let eta = int_ior / ext_ior;
            // The smooth kinds' delta events carry no tint (yet).
            let untinted = specular_reflectance == Vec3::ONE && specular_transmittance == Vec3::ONE;
            match kind {
                "dielectric" | "thindielectric" if !untinted => {
                    let message = format!("a tinted `{kind}` is not supported yet");
                    return Err(cx.err(node, field, message));
                }
                "dielectric" => Material::glass(eta),
                "thindielectric" => Material::of(ThinDielectric::new(
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                )),
                _ => Material::of(RoughDielectric::new(
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                    microfacet(cx, &p)?,
                )),
            }
        }
        "plastic" | "roughplastic" => {
            let kd = match p.texture_param("diffuse_reflectance") {
                Some(t) => {
                    let tex = texture(cx, t, &p.at("diffuse_reflectance"))?;
                    let mean = tex.mean();
                    kd_texture = Some(tex);
                    mean
                }
                None => p.albedo(cx, "diffuse_reflectance", 0.5)?,
            };
            let specular = p.albedo(cx, "specular_reflectance", 1.0)?;
            let eta = p.ior(cx, "int_ior", 1.49)? / p.ior(cx, "ext_ior", AIR)?;
            let nonlinear = p.boolean(cx, "nonlinear")?;
            let microfacet = match kind {
                "plastic" => None,
                _ => Some(microfacet(cx, &p)?),
            };
            Material::of(Plastic::new(kd, specular, eta, nonlinear, microfacet))
        }
        "principled" => {
            let (kind, textures) = crate::importers::mitsuba::principled::principled(cx, &p)?;
            param_textures = textures;
            Material::of(kind)
        }
        // Mitsuba 3's `null`: an index-matched boundary that only bounds media.
        "null" => Material::null(),
        other => {
            let message = format!("unsupported bsdf `{other}`");
            return Err(cx.err(node, field, message));
        }
    };
    p.done(cx)?;
    let _ = warnings;
    Ok(Read {
        material,
        kd_texture,
        normal_texture: None,
        alpha_texture: None,
        param_textures,
    })
}
