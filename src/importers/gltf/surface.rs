//! A glTF material as the importer adds it: its mapping (`material.rs`), the textures it
//! reads (`texture.rs`) and its alpha test, warned about once per material.

use crate::bsdfs::{Bsdf, BsdfKind, Channel, Param};
use crate::error::Result;
use crate::importers::gltf::{material, texture, Importer};
use crate::scene::builder::MaterialId;
use crate::scene::locate::Part;
use crate::scene::{Alpha, AlphaMode, Material, NO_TEXTURE};
use glam::Vec3;

/// Which field of a material a texture read for it fills.
enum Slot {
    BaseColour,
    Emission,
    MetallicRoughness,
    Normal,
    /// `Material::gltf_textures[i]`.
    Param(usize),
}

impl Importer<'_> {
    /// Reads the textures of `m` that `material` uses (base colour, metallic-roughness,
    /// emissive, normal; a metallic-roughness material's transmission, specular and specular
    /// colour)
    /// into the scene and points `material` at them. A texture on another uv set than the
    /// primitive's (`material::uv_texture`) is read on that one, with a warning.
    fn textures(&mut self, m: &gltf::Material, name: &str, material: &mut Material) -> Result<()> {
        let pbr = m.pbr_metallic_roughness();
        let set = material::uv_texture(m).map_or(0, |(set, _)| set);
        let err = |(f, msg): (String, String)| self.cx.err(&f, format!("material {name}: {msg}"));
        let warn_set = |r: &texture::TexRef| {
            if r.set() != set {
                crate::warning::warn(format!(
                    "{}: material {name}: texture {} reads TEXCOORD_{}, rendered with \
                     TEXCOORD_{set} (one uv set per primitive)",
                    self.cx.file,
                    r.name(),
                    r.set()
                ));
            }
        };
        let (buffers, dir) = (&self.buffers, self.base_dir);
        let gltf_kind = matches!(material.bsdf, Bsdf::MetallicRoughness(_));
        let mut read = Vec::new();
        if let Some(info) = pbr.base_color_texture() {
            if material::reads_base_colour(material) {
                let [r, g, b, _] = pbr.base_color_factor();
                let t = texture::TexRef::info(&info);
                warn_set(&t);
                let t = texture::base_colour(&t, Vec3::new(r, g, b), buffers, dir).map_err(err)?;
                read.push((Slot::BaseColour, t));
            }
        }
        // The metallic-roughness kind's parameter textures, linear but the specular colour.
        let transmission = m.transmission().and_then(|t| t.transmission_texture());
        let specular = m.specular().and_then(|s| s.specular_texture());
        let colour = m.specular().and_then(|s| s.specular_color_texture());
        let params = [
            (
                Slot::MetallicRoughness,
                pbr.metallic_roughness_texture(),
                false,
            ),
            (Slot::Param(0), transmission, false),
            (Slot::Param(1), specular, false),
            (Slot::Param(2), colour, true),
        ];
        for (slot, info, srgb) in params {
            let Some(info) = info.filter(|_| gltf_kind) else {
                continue;
            };
            let r = texture::TexRef::info(&info);
            warn_set(&r);
            let t = match srgb {
                true => texture::base_colour(&r, Vec3::ONE, buffers, dir),
                false => texture::linear(&r, buffers, dir),
            };
            read.push((slot, t.map_err(err)?));
        }
        if let Some(info) = m.emissive_texture().filter(|_| material.is_emissive()) {
            let t = texture::TexRef::info(&info);
            warn_set(&t);
            let t = texture::base_colour(&t, Vec3::ONE, buffers, dir).map_err(err)?;
            read.push((Slot::Emission, t));
        }
        if let Some(n) = m.normal_texture() {
            let r = texture::TexRef::normal(&n);
            warn_set(&r);
            let t = texture::normal(&r, n.scale(), buffers, dir).map_err(err)?;
            read.push((Slot::Normal, t));
        }
        let budget = |_: Part, m: String| err(("texture".into(), m));
        for (slot, t) in read {
            let id = self.b.add_texture(t, &budget)?;
            match (slot, &mut material.bsdf) {
                (Slot::BaseColour, b) => {
                    if let Some(p) = b.base_colour_mut() {
                        *p = Param::texture(id);
                    }
                }
                (Slot::Emission, _) => material.emission_texture = id,
                (Slot::Normal, _) => material.normal_texture = id,
                // The metallic-roughness texture: metalness in blue, roughness in green.
                (Slot::MetallicRoughness, Bsdf::MetallicRoughness(g)) => {
                    g.metallic = g.metallic.times(id, Channel::B);
                    g.roughness = g.roughness.times(id, Channel::G);
                }
                (Slot::Param(0), Bsdf::MetallicRoughness(g)) => {
                    g.transmission = g.transmission.times(id, Channel::R);
                }
                (Slot::Param(1), Bsdf::MetallicRoughness(g)) => {
                    g.specular = g.specular.times(id, Channel::A);
                }
                (Slot::Param(_), Bsdf::MetallicRoughness(g)) => g.f0 = g.f0.times(id, Channel::Rgb),
                _ => {}
            }
        }
        Ok(())
    }

    /// The alpha test of `m` (`alphaMode` MASK with its `alphaCutoff`, BLEND as a stochastic
    /// coverage): the opacity is `baseColorFactor`'s alpha times the base colour texture's
    /// (when `material` reads it); `None` when opaque or when nothing can be transparent.
    fn alpha(&self, m: &gltf::Material, material: &Material) -> Option<Alpha> {
        let mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => return None,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let factor = m.pbr_metallic_roughness().base_color_factor()[3].clamp(0.0, 1.0);
        let base = material.bsdf.clone().base_colour_mut().map(|p| p.texture);
        let texture = match base.unwrap_or(NO_TEXTURE) {
            NO_TEXTURE => NO_TEXTURE,
            t if self.b.texture(t).has_alpha() => t,
            _ => NO_TEXTURE,
        };
        let alpha = Alpha {
            mode,
            factor,
            texture,
            luminance: false,
        };
        let opaque = texture == NO_TEXTURE && alpha.stops(factor, 1.0 - f32::EPSILON / 2.0);
        (!opaque).then_some(alpha)
    }

    /// Our material for `m`, added (and warned about) the first time it is used.
    pub(crate) fn material(&mut self, m: &gltf::Material) -> Result<MaterialId> {
        if let Some(&id) = self.materials.get(&m.index()) {
            return Ok(id);
        }
        let (field, name) = match m.index() {
            Some(i) => {
                let field = format!("materials[{i}]");
                (field.clone(), m.name().map_or(field, str::to_string))
            }
            None => ("materials".to_string(), "(default material)".to_string()),
        };
        let file = self.cx.file;
        let (mut material, note) = material::map(m);
        self.textures(m, &name, &mut material)?;
        material.alpha = self.alpha(m, &material);
        if let Some(note) = note {
            crate::warning::warn(format!("{file}: material {name}: {note}"));
        }
        for (texture, slot) in material::textures(m) {
            if !self.warned.contains(&texture) {
                crate::warning::warn(format!(
                    "{file}: material {name}: {slot} texture {texture} ignored \
                     (its factor is used)"
                ));
                self.warned.push(texture);
            }
        }
        let at = |_: Part, msg: String| self.cx.err(&field, format!("material {name}: {msg}"));
        if let Some(p) = material::absorption(m, &material) {
            let medium = self.b.add_medium(None, p, &at)?;
            material.media = crate::media::MediumInterface {
                interior: medium.index(),
                exterior: crate::media::NO_MEDIUM,
            };
        }
        let id = self.b.add_material(None, material, &at)?;
        self.materials.insert(m.index(), id);
        Ok(id)
    }
}
