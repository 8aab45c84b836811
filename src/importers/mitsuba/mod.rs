//! Mitsuba 3 XML scenes (a subset; the mapping is documented in `scenes/README.md`), parsed
//! with roxmltree and fed to the [`SceneBuilder`].
//!
//! Read: `<include>`, `<path>`, `<default>` and `$name` (see `include.rs`); one `perspective`
//! sensor (with its `hdrfilm` size and `sampler` count as spp) and any `integrator` as a hint
//! (see `integrator.rs`); `bsdf`s (see `bsdf.rs`), shapes `rectangle`, `cube`, `sphere`, `disk`,
//! `cylinder` (see `round.rs`), `obj`, `ply`, `area` emitters on shapes, `point`, `spot` and
//! `directional` emitters (see `emitter.rs`); `ref` to any top-level object with an `id`,
//! before or after it; spectra as Mitsuba's RGB variants convert them (see `spectrum.rs`).
//! Anything else (other plugins, environment maps, parameters we do not read) is an
//! `unsupported` error: nothing is skipped silently. Files written for Mitsuba 0.x
//! (`version` below 2.0.0) are upgraded first, as Mitsuba 3 does (see `upgrade.rs`). Every
//! error is `FILE:LINE: field: message` (the file an element is in, included or not);
//! approximations are warnings.

mod blend;
mod bsdf;
mod bumpmap;
mod cie;
mod emitter;
mod include;
mod instance;
mod integrator;
mod medium;
mod mesh_attribute;
mod plugin;
mod principled;
mod round;
mod sensor;
mod serialized;
mod shape;
mod spectrum;
mod texture;
mod upgrade;
mod values;
mod volume;

pub use include::{MAX_INCLUDED_BYTES, MAX_INCLUDED_FILES, MAX_INCLUDE_DEPTH};

use crate::bsdfs::BsdfKind;
use crate::error::{Error, Result};
use crate::importers::file;
use crate::scene::builder::{MaterialId, SceneBuilder};
use crate::scene::locate::Origin;
use crate::scene::{Material, Scene};
use glam::Vec3;
use roxmltree::{Document, Node};
use std::collections::HashMap;
use std::path::Path;
use values::Cx;

/// Deepest element nesting accepted below `<scene>` (real scenes nest a few levels; the
/// readers recurse through nested elements such as `twosided` bsdfs).
pub const MAX_NESTING: usize = 64;

/// Most bytes all `<default>` values may expand to together (each is also bounded by
/// `values::MAX_VALUE_BYTES`).
pub const MAX_DEFAULTS_BYTES: usize = 16 << 20;

/// A scene read from Mitsuba XML, with the warnings about what was approximated.
#[derive(Debug)]
pub struct Imported {
    /// The scene.
    pub scene: Scene,
    /// One `FILE:LINE: field: what` line per approximated item, in file order.
    pub warnings: Vec<String>,
}

/// Reads and loads the Mitsuba XML file at `path` (meshes relative to its directory),
/// printing its warnings to stderr. An unreadable file is [`Error::Io`]; everything wrong
/// inside it is [`Error::Scene`].
pub fn load(path: &Path) -> Result<Scene> {
    load_with_defines(path, &[])
}

/// [`load()`] with parameters `(NAME, VALUE)` for `$NAME`, which override the file's
/// `<default>`s (Mitsuba's `-D NAME=VALUE`, our `--define`).
pub fn load_with_defines(path: &Path, defines: &[(String, String)]) -> Result<Scene> {
    let text = file::read_text(path)?;
    let file = path.display().to_string();
    let imported = import_with(text, &file, file::base_dir(path), defines)?;
    for warning in &imported.warnings {
        crate::warning::warn(warning.to_string());
    }
    Ok(imported.scene)
}

/// Loads Mitsuba XML `text` (`file` names it in errors, meshes are relative to `base_dir`),
/// printing its warnings to stderr.
pub fn load_str(text: &str, file: &str, base_dir: &Path) -> Result<Scene> {
    let imported = import(text, file, base_dir)?;
    for warning in &imported.warnings {
        crate::warning::warn(warning.to_string());
    }
    Ok(imported.scene)
}

/// Loads Mitsuba XML `text` like [`load_str`], returning the warnings instead of printing them.
pub fn import(text: &str, file: &str, base_dir: &Path) -> Result<Imported> {
    import_with(text.to_string(), file, base_dir, &[])
}

/// Parses a command-line `NAME=VALUE` parameter (`--define`): NAME is 1 to 256 letters,
/// digits or `_`.
pub fn parse_define(arg: &str) -> std::result::Result<(String, String), String> {
    let Some((name, value)) = arg.split_once('=') else {
        return Err(format!("`{arg}` is not NAME=VALUE"));
    };
    values::check_name(name)?;
    Ok((name.to_string(), value.to_string()))
}

/// [`import`] with parameters `(NAME, VALUE)` that override the file's `<default>`s.
pub fn import_with(
    text: String,
    file: &str,
    base_dir: &Path,
    defines: &[(String, String)],
) -> Result<Imported> {
    let g = include::gather(text, file, base_dir, defines)?;
    let docs = g
        .sources
        .iter()
        .map(|s| include::parse(&s.text, &s.name))
        .collect::<Result<Vec<Document>>>()?;
    let mut cx = Cx {
        file,
        docs: docs
            .iter()
            .zip(&g.sources)
            .map(|(d, s)| (d, s.name.as_str()))
            .collect(),
        defaults: g.defaults,
        search: g.search,
        ids: HashMap::new(),
    };
    let root = docs[0].root_element();
    if root.tag_name().name() != "scene" {
        let message = format!(
            "the root element must be <scene>, found <{}>",
            root.tag_name().name()
        );
        return Err(cx.err(root, "scene", message));
    }
    let top = include::flatten(&docs, &g.includes);
    // Every top-level object with an id, for references before or after it.
    for &node in &top {
        let tag = node.tag_name().name();
        if let Some(id) = cx.attr(node, tag, "id")? {
            if let Some(first) = cx.ids.insert(id.clone(), node) {
                let message = format!("duplicate id `{id}` (first at {})", cx.loc(first));
                return Err(cx.err(node, &format!("{tag}[{id}]"), message));
            }
        }
    }
    let mut im = Importer {
        cx,
        b: SceneBuilder::new(),
        bsdfs: HashMap::new(),
        default_material: None,
        media: HashMap::new(),
        attribute_materials: Vec::new(),
        groups: HashMap::new(),
        warnings: Vec::new(),
    };
    let mut counts: HashMap<&str, usize> = HashMap::new();
    let mut sensor = None;
    for node in top {
        let tag = node.tag_name().name();
        let count = counts.entry(tag).or_default();
        let id = im.cx.attr(node, tag, "id")?;
        let field = match &id {
            Some(id) => format!("{tag}[{id}]"),
            None => format!("{tag}[{count}]"),
        };
        *count += 1;
        let kind = node.attribute("type");
        match (tag, id) {
            ("default" | "path", _) => {}
            ("integrator", _) => im.integrator(node, &field)?,
            ("sensor", _) if sensor.is_some() => {
                return Err(im.cx.err(node, &field, "only one <sensor> is supported"));
            }
            ("sensor", _) => sensor = Some(im.sensor(node, &field)?),
            ("bsdf", Some(id)) => {
                im.bsdf_by_id(&id, node)?;
            }
            ("bsdf", None) => {
                im.add_bsdf(node, &field)?;
            }
            // Read where a <ref> names them.
            ("texture" | "medium", Some(_)) => {}
            ("emitter", Some(_)) if kind == Some("area") => {}
            ("shape", _) => im.shape(node, &field)?,
            ("emitter", _) => im.emitter(node, &field)?,
            (other, _) => {
                let message = match other {
                    "texture" | "medium" => {
                        format!("a top-level <{other}> needs an `id` (for <ref>)")
                    }
                    _ => format!("unsupported element <{other}>"),
                };
                return Err(im.cx.err(node, &field, message));
            }
        }
    }
    let at = Origin {
        file: file.to_string(),
        line: docs[0].text_pos_at(root.range().start).row as usize,
        field: "scene".into(),
    };
    if sensor.is_none() {
        return Err(im.cx.err(root, "scene", "the scene has no <sensor>"));
    }
    let mut scene = im.b.finish(&at)?;
    scene.scale_default_radii([false; 3]);
    Ok(Imported {
        scene,
        warnings: im.warnings,
    })
}

/// Refuses elements nested deeper than [`MAX_NESTING`] below the root, at the first such
/// element, before any reader recurses into them.
pub(crate) fn check_nesting(file: &str, doc: &Document) -> Result<()> {
    // Ancestors are counted only up to the limit, so the check is linear in the elements.
    let too_deep = doc.descendants().filter(Node::is_element).find(|n| {
        // The root element and the document node above it are not nesting.
        n.ancestors().take(MAX_NESTING + 3).count() > MAX_NESTING + 2
    });
    match too_deep {
        None => Ok(()),
        Some(node) => Err(Error::Scene {
            file: file.to_string(),
            line: doc.text_pos_at(node.range().start).row as usize,
            field: node.tag_name().name().to_string(),
            message: format!("elements nested deeper than {MAX_NESTING} are not supported"),
        }),
    }
}

/// The element children of `node`.
pub(crate) fn elements<'a, 'i>(node: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(Node::is_element)
}

/// The state of one import.
struct Importer<'f> {
    cx: Cx<'f>,
    b: SceneBuilder,
    /// Materials of the `bsdf`s with an `id`, for `ref`.
    bsdfs: HashMap<String, MaterialId>,
    /// Mitsuba's material for shapes without a bsdf (diffuse 0.5), added when first needed.
    default_material: Option<MaterialId>,
    /// Media of the top-level `medium`s with an `id`, for `ref`.
    media: HashMap<String, crate::media::builder::MediumId>,
    /// The materials whose diffuse reflectance is a `mesh_attribute`, which each shape
    /// makes its own copy of.
    attribute_materials: Vec<(MaterialId, mesh_attribute::AttributeUse)>,
    /// Meshes of the `shapegroup`s read so far, by id (`instance.rs`).
    groups: HashMap<String, crate::scene::MeshId>,
    warnings: Vec<String>,
}

impl<'f> Importer<'f> {
    /// Reads the `<bsdf>` `node` at `field` and adds its material (and texture).
    fn add_bsdf(&mut self, node: Node, field: &str) -> Result<MaterialId> {
        self.add_bsdf_sided(node, field, false)
    }

    /// [`add_bsdf`](Self::add_bsdf), made two-sided when `two_sided` (a `twosided` around
    /// it); a `blendbsdf` (also inside a `twosided`) adds its components first.
    fn add_bsdf_sided(&mut self, node: Node, field: &str, two_sided: bool) -> Result<MaterialId> {
        match node.attribute("type") {
            Some("blendbsdf") => return self.add_blend(node, field, two_sided),
            Some("twosided") => {
                let p = plugin::Plugin::new(&self.cx, node, field.to_string())?;
                if let [inner] = p.objects[..] {
                    let inner = self.cx.deref(inner, field)?;
                    if inner.attribute("type") == Some("blendbsdf") {
                        p.done(&self.cx)?;
                        return self.add_blend(inner, &format!("{field}.bsdf"), true);
                    }
                }
            }
            _ => {}
        }
        let read = bsdf::bsdf(&self.cx, node, field, &mut self.warnings)?;
        let mut material = read.material;
        if two_sided {
            material.one_sided = false;
        }
        let at = self.origin(node, field);
        if let Some(t) = read.kd_texture {
            let id = self.b.add_texture(t, &at)?;
            if let Some(p) = material.bsdf.base_colour_mut() {
                *p = crate::bsdfs::Param::texture(id);
            }
        }
        for (t, channel, slot) in read.param_textures {
            let id = self.b.add_texture(t, &at)?;
            if let Some(p) = slot(&mut material.bsdf) {
                *p = p.times(id, channel);
            }
        }
        if let Some(t) = read.normal_texture {
            material.normal_texture = self.b.add_texture(t, &at)?;
        }
        if let (Some(t), Some(alpha)) = (read.alpha_texture, material.alpha.as_mut()) {
            alpha.texture = self.b.add_texture(t, &at)?;
        }
        let Some((name, scale)) = read.mesh_attribute else {
            return self.b.add_material(None, material, &at);
        };
        // The mesh's uvs will be the attribute's: no other texture may read them.
        let no = crate::textures::NO_TEXTURE;
        if material.normal_texture != no || material.alpha.is_some_and(|a| a.texture != no) {
            let message = "a `mesh_attribute` with another texture in one bsdf is not supported";
            return Err(self.cx.err(node, field, message));
        }
        let id = self.b.add_material(None, material, &at)?;
        let attribute = mesh_attribute::AttributeUse {
            material,
            name,
            scale,
            blend: None,
        };
        self.attribute_materials.push((id, attribute));
        Ok(id)
    }

    /// A fixed place for the builder's errors: the element's line and field.
    fn origin(&self, node: Node, field: &str) -> Origin {
        Origin {
            file: self.cx.file_of(node).to_string(),
            line: node.document().text_pos_at(node.range().start).row as usize,
            field: field.to_string(),
        }
    }

    /// The top-level object a `<ref id>` names, with its id (before or after the ref).
    fn referenced(&self, node: Node, field: &str) -> Result<(String, Node<'f, 'f>)> {
        let id = self.cx.need_attr(node, field, "id")?;
        if let Some(&target) = self.cx.ids.get(&id) {
            return Ok((id, target));
        }
        let mut known: Vec<String> = self.cx.ids.keys().map(|k| format!("`{k}`")).collect();
        known.sort();
        let known = match known.is_empty() {
            true => "none".to_string(),
            false => known.join(", "),
        };
        let message = format!("unknown id `{id}` (the scene's ids: {known})");
        Err(self.cx.err(node, field, message))
    }

    /// The material of the top-level `<bsdf id>` `node`, added the first time it is asked for.
    fn bsdf_by_id(&mut self, id: &str, node: Node) -> Result<MaterialId> {
        if let Some(&mid) = self.bsdfs.get(id) {
            return Ok(mid);
        }
        let mid = self.add_bsdf(node, &format!("bsdf[{id}]"))?;
        self.bsdfs.insert(id.to_string(), mid);
        Ok(mid)
    }

    /// Mitsuba's bsdf for shapes without one: diffuse, reflectance 0.5.
    fn default_material(&mut self, at: &Origin) -> Result<MaterialId> {
        if let Some(id) = self.default_material {
            return Ok(id);
        }
        let id = self
            .b
            .add_material(None, Material::diffuse(Vec3::splat(0.5)), at)?;
        self.default_material = Some(id);
        Ok(id)
    }
}
