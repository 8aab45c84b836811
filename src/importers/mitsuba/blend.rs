//! Mitsuba's `blendbsdf`: two nested bsdfs (or refs to them) and their `weight`, a float in
//! [0, 1] or a texture (read as a float: a colour texture's luminance, as Mitsuba's `eval_1`),
//! the second's share: `(1 - weight) bsdf_0 + weight bsdf_1`. Each component becomes a material
//! of its own and the blend a material of both (`SceneBuilder::add_blend`,
//! `crate::bsdfs::blend`). A `twosided` around a blend makes both components two-sided. A
//! `mesh_attribute` weight makes a blend per shape that uses it (`mesh_attribute.rs`).

use crate::bsdfs::{Channel, Param};
use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::texture::texture;
use crate::importers::mitsuba::{mesh_attribute, Importer};
use crate::scene::builder::MaterialId;
use glam::Vec3;
use roxmltree::Node;

impl Importer<'_> {
    /// The `<bsdf type="blendbsdf">` `node` at `field` as a material; `two_sided` when a
    /// `twosided` wraps it.
    pub(crate) fn add_blend(
        &mut self,
        node: Node,
        field: &str,
        two_sided: bool,
    ) -> Result<MaterialId> {
        let p = Plugin::new(&self.cx, node, field.to_string())?;
        let at = self.origin(node, field);
        let mut components = Vec::new();
        for (k, &child) in p.objects.iter().enumerate() {
            let sub = format!("{field}.bsdf[{k}]");
            let target = self.cx.deref(child, &sub)?;
            if target.tag_name().name() != "bsdf" || k >= 2 {
                let tag = child.tag_name().name();
                let message = format!("unsupported <{tag}> in a `blendbsdf` (two nested bsdfs)");
                return Err(self.cx.err(child, field, message));
            }
            components.push(self.add_bsdf_sided(target, &sub, two_sided)?);
        }
        let [first, second] = components[..] else {
            let message = "a `blendbsdf` needs two nested bsdfs";
            return Err(self.cx.err(node, field, message));
        };
        let weight = match p.texture_param("weight") {
            Some(t) if node_is_attribute(t) => {
                // A mesh attribute: each shape makes its own blend, its weight the
                // attribute's texture on the shape's uvs, which nothing else may read.
                let field = p.at("weight");
                let Some((name, scale)) = mesh_attribute::read(&self.cx, t, &field)? else {
                    unreachable!("a mesh_attribute node")
                };
                if let Some(textured) = (p.objects.iter()).find(|&&c| self.reads_a_texture(c)) {
                    let message = "a `blendbsdf` weighted by a `mesh_attribute` takes untextured \
                                   bsdfs (the mesh's uvs become the attribute's)";
                    return Err(self.cx.err(*textured, field.as_str(), message));
                }
                p.done(&self.cx)?;
                let id = self.b.add_blend(first, second, Param::constant(0.0), &at)?;
                let attribute = mesh_attribute::AttributeUse {
                    material: crate::scene::Material::black(),
                    name,
                    scale,
                    blend: Some([first, second]),
                };
                self.attribute_materials.push((id, attribute));
                return Ok(id);
            }
            Some(t) => {
                let tex = texture(&self.cx, t, &p.at("weight"))?;
                Param {
                    value: Vec3::ONE,
                    texture: self.b.add_texture(tex, &at)?,
                    channel: Channel::Luminance,
                }
            }
            None => {
                let Some(w) = p.float(&self.cx, "weight")? else {
                    let message = "a `blendbsdf` needs a `weight` (float or texture)";
                    return Err(self.cx.err(node, &p.at("weight"), message));
                };
                if !(0.0..=1.0).contains(&w) {
                    let message = format!("must be in [0, 1] (got {w})");
                    return Err(self.cx.err(p.node_of("weight"), &p.at("weight"), message));
                }
                Param::constant(w)
            }
        };
        p.done(&self.cx)?;
        self.b.add_blend(first, second, weight, &at)
    }

    /// Whether the bsdf `node` (or what a `ref` names) has a texture inside it.
    fn reads_a_texture(&self, node: Node) -> bool {
        node.descendants().any(|n| match n.tag_name().name() {
            "texture" => true,
            "ref" => (n.attribute("id").and_then(|id| self.cx.ids.get(id)))
                .is_some_and(|&t| t != n && self.reads_a_texture(t)),
            _ => false,
        })
    }
}

/// Whether `node` is a `mesh_attribute` texture.
fn node_is_attribute(node: Node) -> bool {
    node.attribute("type") == Some("mesh_attribute")
}
