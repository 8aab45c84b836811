//! Mitsuba BSDFs as our materials (the mapping is documented in `scenes/README.md`), each as
//! Mitsuba 3 defines it (`crate::bsdfs`): `diffuse` (constant or textured reflectance),
//! `twosided` (the reflective kinds are one-sided without it), `conductor`, `roughconductor`
//! (named materials, eta/k), `dielectric`, `roughdielectric`, `thindielectric`, `plastic`,
//! `roughplastic`, `principled`, `principledthin`, and `normalmap` or `bumpmap` (`bumpmap.rs`)
//! around any of them.

use crate::bsdfs::conductor::Conductor;
use crate::bsdfs::rough_conductor::RoughConductor;
use crate::bsdfs::rough_dielectric::RoughDielectric;
use crate::bsdfs::thin_dielectric::ThinDielectric;
use crate::bsdfs::{
    named_conductor, Bsdf, Channel, Distribution, Microfacet, Param, Plastic, METAL_NAMES,
};
use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::principled::{ParamSlot, ParamTexture};
use crate::importers::mitsuba::texture::texture;
use crate::importers::mitsuba::values::Cx;
use crate::scene::{Alpha, AlphaMode, Material, NO_TEXTURE};
use crate::textures::{Checkerboard, SceneTexture};
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
    /// A diffuse reflectance that is a `mesh_attribute`: its name and scale (each shape
    /// gets its own texture of it, `mesh_attribute.rs`).
    pub mesh_attribute: Option<(String, f32)>,
    /// The textures of other parameters (a rough conductor's or dielectric's `alpha_u` and
    /// `alpha_v`, `principled`'s), each with the channel it reads and where it goes.
    pub param_textures: Vec<ParamTexture>,
}

/// The one `<bsdf>` (or `<ref>` to one) nested in the wrapper bsdf `p` (`twosided`,
/// `normalmap`, `bumpmap`, `mask`) at `node`.
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

/// The rest of a `normalmap` or `bumpmap` `p` (nested bsdf `inner`, at `field`) once its
/// texture `tex` is read: Mitsuba's `flip_invalid_normals` (only its default) and
/// `use_shadowing_function` (the perturbed normal's shadowing of grazing light, default on),
/// then the nested bsdf with `tex` as its `normal_texture` (one a material).
fn perturbed(
    cx: &Cx,
    p: &Plugin,
    inner: Node,
    field: &str,
    warnings: &mut Vec<String>,
    tex: SceneTexture,
) -> Result<Read> {
    if !p.boolean_or(cx, "flip_invalid_normals", true)? {
        let message = "only Mitsuba's default `true` is supported";
        let name = "flip_invalid_normals";
        return Err(cx.err(p.node_of(name), &p.at(name), message));
    }
    let shadowing = p.boolean_or(cx, "use_shadowing_function", true)?;
    p.done(cx)?;
    let mut read = bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?;
    if read.normal_texture.is_some() {
        let nested = if read.material.bump.is_some() {
            "bumpmap"
        } else {
            "normalmap"
        };
        let message = format!("a `{nested}` inside a `{}` is not supported", p.kind);
        return Err(cx.err(inner, field, message));
    }
    read.normal_texture = Some(tex);
    read.material.normal_shadowing = shadowing;
    Ok(read)
}

/// The microfacet roughness of a rough plugin, as Mitsuba's microfacet plugins read it:
/// `distribution` (`beckmann` default, `ggx`), and `alpha` (default 0.1) or both `alpha_u` and
/// `alpha_v` (not one alone, nor with `alpha`). Where `textured` (`roughconductor`,
/// `roughdielectric`), each may be a `<texture>`, read as its luminance (Mitsuba's `eval_1`):
/// its slot is returned (u, v) and the constant is then 1.
/// A rough conductor's or dielectric's textured `alpha_u` and `alpha_v` as parameter
/// textures: Mitsuba evaluates them as floats, their luminance.
fn roughness_textures(textures: [Option<SceneTexture>; 2]) -> Vec<ParamTexture> {
    fn roughness(b: &mut Bsdf) -> Option<&mut crate::bsdfs::microfacet::Roughness> {
        match b {
            Bsdf::RoughConductor(k) => Some(&mut k.roughness),
            Bsdf::RoughDielectric(k) => Some(&mut k.roughness),
            _ => None,
        }
    }
    let slots: [ParamSlot; 2] = [
        |b| roughness(b).map(|r| &mut r.alpha_u),
        |b| roughness(b).map(|r| &mut r.alpha_v),
    ];
    (textures.into_iter().zip(slots))
        .filter_map(|(t, slot)| Some((t?, Channel::Luminance, slot)))
        .collect()
}

fn microfacet(
    cx: &Cx,
    p: &Plugin,
    textured: bool,
) -> Result<(Microfacet, [Option<SceneTexture>; 2])> {
    let distribution = match p.string(cx, "distribution")?.as_deref() {
        None | Some("beckmann") => Distribution::Beckmann,
        Some("ggx") => Distribution::Ggx,
        Some(other) => {
            let message = format!("unknown distribution `{other}` (expected beckmann or ggx)");
            return Err(cx.err(p.node_of("distribution"), &p.at("distribution"), message));
        }
    };
    p.ignore(&["sample_visible"]);
    let given = |name: &str| p.node_of(name) != p.node;
    let names = match (given("alpha_u"), given("alpha_v")) {
        (false, false) => ["alpha", "alpha"],
        (true, true) if given("alpha") => {
            let message = "give either `alpha` or `alpha_u` and `alpha_v`";
            return Err(cx.err(p.node_of("alpha"), &p.at("alpha"), message));
        }
        (true, true) => ["alpha_u", "alpha_v"],
        (u, _) => {
            let (name, other) = if u {
                ("alpha_u", "alpha_v")
            } else {
                ("alpha_v", "alpha_u")
            };
            let message = format!("needs `{other}` too (Mitsuba takes both or neither)");
            return Err(cx.err(p.node_of(name), &p.at(name), message));
        }
    };
    let mut alphas = [0.1; 2];
    let mut textures = [None, None];
    for (i, name) in names.into_iter().enumerate() {
        if let Some(t) = p.texture_param(name) {
            if !textured {
                let message = format!("a textured roughness is not supported by `{}`", p.kind);
                return Err(cx.err(t, &p.at(name), message));
            }
            let tex = texture(cx, t, &p.at(name))?;
            textures[i] = Some(float_texture(cx, t, &p.at(name), tex)?);
            alphas[i] = 1.0;
        } else if let Some(a) = p.float(cx, name)? {
            if !(a > 0.0 && a.is_finite()) {
                return Err(cx.err(p.node_of(name), &p.at(name), "must be positive"));
            }
            alphas[i] = a;
        }
    }
    Ok((
        Microfacet::new(distribution, alphas[0], alphas[1]),
        textures,
    ))
}

/// The texture `tex` (read from `node`, at `field`) as Mitsuba evaluates it as a float (`eval_1`), for
/// a [`Channel::Luminance`](crate::bsdfs::Channel) slot: a bitmap's luminance (as is); a
/// checkerboard's colours each their mean (Mitsuba's `srgb` colour gives its mean), made
/// grey, and swapped (Mitsuba's checkerboard `eval_1` inverts its `eval`'s parity;
/// `scripts/mitsuba_roughness_texture_probe.py`); a 3D `rawconstant` has none (Mitsuba
/// throws), an error.
fn float_texture(cx: &Cx, node: Node, field: &str, tex: SceneTexture) -> Result<SceneTexture> {
    let vector = node.children().any(|c| {
        c.attribute("name") == Some("value") && matches!(c.tag_name().name(), "vector" | "point")
    });
    if node.attribute("type") == Some("rawconstant") && vector {
        let message = "a 3D `rawconstant` has no float value (Mitsuba's eval_1 refuses it)";
        return Err(cx.err(node, field, message));
    }
    Ok(match tex {
        SceneTexture::Checkerboard(c) => {
            let grey = |v: Vec3| Vec3::splat(v.element_sum() / 3.0);
            // Mitsuba's checkerboard `eval_1` takes color0 where its `eval` takes color1 (and
            // the other way round): swapped, as there.
            SceneTexture::Checkerboard(Checkerboard {
                color0: grey(c.color1),
                color1: grey(c.color0),
                ..c
            })
        }
        other => other,
    })
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
    let wrapper = matches!(kind, "twosided" | "normalmap" | "bumpmap" | "mask");
    if let Some(&extra) = p.objects.get(usize::from(wrapper)) {
        let tag = extra.tag_name().name();
        let message = format!("unsupported <{tag}> inside a `{kind}` bsdf");
        return Err(cx.err(extra, field, message));
    }
    let mut kd_texture = None;
    let mut mesh_attribute = None;
    let mut param_textures = Vec::new();
    let mut material = match kind {
        "twosided" => {
            // The nested bsdf, seen from both sides alike; a principled one (one interface,
            // as in Mitsuba) is told it is two-sided.
            let inner = nested_bsdf(cx, &p, node, field)?;
            p.done(cx)?;
            let mut read = bsdf(cx, inner, &format!("{field}.bsdf"), warnings)?;
            read.material.one_sided = false;
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
            return perturbed(cx, &p, inner, field, warnings, tex);
        }
        "bumpmap" => {
            // Mitsuba 3's `bumpmap`: the nested bsdf with the normal that the gradient of a
            // height texture tilts (bumpmap.rs).
            let inner = nested_bsdf(cx, &p, node, field)?;
            let (tex, scale) = crate::importers::mitsuba::bumpmap::height(cx, &p, field)?;
            let mut read = perturbed(cx, &p, inner, field, warnings, tex)?;
            read.material.bump = Some(scale);
            return Ok(read);
        }
        "mask" => {
            // Mitsuba 3's `mask`: the nested bsdf where a stochastic choice of probability
            // `opacity` (float or texture, default 0.5) stops the ray, else the ray passes on
            // unchanged (crate::scene::AlphaMode::Blend). A textured opacity is read as
            // Mitsuba's `eval_1` reads it (`float_texture`: a bitmap's luminance).
            let inner = nested_bsdf(cx, &p, node, field)?;
            let (factor, tex) = match p.texture_param("opacity") {
                Some(t) => {
                    let tex = texture(cx, t, &p.at("opacity"))?;
                    (1.0, Some(float_texture(cx, t, &p.at("opacity"), tex)?))
                }
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
                let field = p.at("reflectance");
                match crate::importers::mitsuba::mesh_attribute::read(cx, t, &field)? {
                    Some(attribute) => mesh_attribute = Some(attribute),
                    None => kd_texture = Some(texture(cx, t, &field)?),
                }
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
                _ => {
                    let (mf, textures) = microfacet(cx, &p, true)?;
                    param_textures = roughness_textures(textures);
                    Some(mf)
                }
            };
            // A smooth conductor of material `none` (eta 0, k 1) reflects everything.
            if microfacet.is_none() && eta == Vec3::ZERO && k == Vec3::ONE {
                p.done(cx)?;
                return Ok(Read {
                    material: Material {
                        one_sided: true,
                        ..Material::mirror(specular)
                    },
                    kd_texture,
                    normal_texture: None,
                    alpha_texture: None,
                    mesh_attribute,
                    param_textures,
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
                _ => {
                    let (mf, textures) = microfacet(cx, &p, true)?;
                    param_textures = roughness_textures(textures);
                    Material::of(RoughDielectric::new(
                        eta,
                        specular_reflectance,
                        specular_transmittance,
                        mf,
                    ))
                }
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
                _ => Some(microfacet(cx, &p, false)?.0),
            };
            Material::of(Plastic::new(kd, specular, eta, nonlinear, microfacet))
        }
        "principled" => {
            let (kind, textures) = crate::importers::mitsuba::principled::principled(cx, &p)?;
            param_textures = textures;
            Material::of(kind)
        }
        "principledthin" => {
            let read = crate::importers::mitsuba::principled::principled_thin;
            let (kind, textures) = read(cx, &p)?;
            param_textures = textures;
            Material::of(kind)
        }
        // Mitsuba 3's `null`: an index-matched boundary that only bounds media.
        "null" => Material::null(),
        "blendbsdf" => {
            let message = "a `blendbsdf` inside a `normalmap` or `mask` is not supported \
                           (only at the top or inside `twosided`)";
            return Err(cx.err(node, field, message));
        }
        other => {
            let message = format!("unsupported bsdf `{other}`");
            return Err(cx.err(node, field, message));
        }
    };
    p.done(cx)?;
    let _ = warnings;
    // Mitsuba's reflective bsdfs reflect nothing from the back unless wrapped in `twosided`
    // (the dielectrics and `null` are two-sided by nature).
    // (A black one reflects nothing from either side: left two-sided, as our own scenes'.)
    material.one_sided = matches!(
        kind,
        "diffuse" | "conductor" | "roughconductor" | "plastic" | "roughplastic"
    ) && !matches!(material.bsdf, crate::bsdfs::Bsdf::Black(_));
    Ok(Read {
        material,
        kd_texture,
        normal_texture: None,
        alpha_texture: None,
        mesh_attribute,
        param_textures,
    })
}
