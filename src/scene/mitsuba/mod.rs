//! Mitsuba 3 XML scenes (a subset; the mapping is documented in `scenes/README.md`), parsed
//! with roxmltree and fed to the [`SceneBuilder`].
//!
//! Read: one `perspective` sensor (with its `hdrfilm` size and `sampler` count as spp),
//! `bsdf`s (see `bsdf.rs`), shapes `rectangle`, `cube`, `sphere`, `obj`, `area` emitters on
//! shapes, `point`, `spot` and `directional` emitters (see `emitter.rs`), `ref` ids, `default` parameters and `$name` substitution. The
//! `integrator` is ignored (the render mode is ours). Anything else (other plugins, textures,
//! environment maps, parameters we do not read) is an `unsupported` error: nothing is skipped
//! silently. Every error is `FILE:LINE: field: message`; approximations are warnings.

mod bsdf;
mod emitter;
mod plugin;
mod shape;
mod texture;
mod values;

use super::builder::{MaterialId, SceneBuilder};
use super::locate::Origin;
use super::{Material, Scene};
use crate::error::{Error, Result};
use crate::scene::file;
use glam::{Mat4, Vec3};
use plugin::Plugin;
use roxmltree::{Document, Node};
use std::collections::HashMap;
use std::path::Path;
use values::Cx;

/// Deepest element nesting accepted below `<scene>` (real scenes nest a few levels; the
/// readers recurse through nested elements such as `twosided` bsdfs).
pub const MAX_NESTING: usize = 64;

/// Most bytes all `<default>` values may expand to together (each is also bounded by
/// [`values::MAX_VALUE_BYTES`]).
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
    let text = file::read_text(path)?;
    load_str(&text, &path.display().to_string(), file::base_dir(path))
}

/// Loads Mitsuba XML `text` (`file` names it in errors, meshes are relative to `base_dir`),
/// printing its warnings to stderr.
pub fn load_str(text: &str, file: &str, base_dir: &Path) -> Result<Scene> {
    let imported = import(text, file, base_dir)?;
    for warning in &imported.warnings {
        eprintln!("warning: {warning}");
    }
    Ok(imported.scene)
}

/// Loads Mitsuba XML `text` like [`load_str`], returning the warnings instead of printing them.
pub fn import(text: &str, file: &str, base_dir: &Path) -> Result<Imported> {
    let doc = Document::parse(text).map_err(|e| {
        // A truncated file is reported where it ends (roxmltree says line 1).
        let truncated = matches!(
            e,
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode
        );
        let end = text.trim_end().lines().count().max(1);
        Error::Scene {
            file: file.to_string(),
            line: if truncated { end } else { e.pos().row as usize },
            field: "xml".into(),
            message: e.to_string(),
        }
    })?;
    let root = doc.root_element();
    check_nesting(file, &doc)?;
    let mut cx = Cx {
        file,
        defaults: HashMap::new(),
    };
    if root.tag_name().name() != "scene" {
        let message = format!(
            "the root element must be <scene>, found <{}>",
            root.tag_name().name()
        );
        return Err(cx.err(root, "scene", message));
    }
    let mut kept = 0;
    for node in elements(root).filter(|n| n.tag_name().name() == "default") {
        let name = cx.need_attr(node, "default", "name")?;
        let field = format!("default.{name}");
        let value = cx.need_attr(node, &field, "value")?;
        // Each value is bounded, but many of them (each `$big`) would not be.
        kept += value.len();
        if kept > MAX_DEFAULTS_BYTES {
            let message = format!("the defaults expand to more than {MAX_DEFAULTS_BYTES} bytes");
            return Err(cx.err(node, &field, message));
        }
        cx.defaults.insert(name, value);
    }
    let mut im = Importer {
        cx,
        base_dir,
        b: SceneBuilder::new(),
        bsdfs: HashMap::new(),
        default_material: None,
        warnings: Vec::new(),
    };
    let mut counts: HashMap<&str, usize> = HashMap::new();
    let mut sensor = None;
    for node in elements(root) {
        let tag = node.tag_name().name();
        let count = counts.entry(tag).or_default();
        let field = match node.attribute("id") {
            Some(id) => format!("{tag}[{id}]"),
            None => format!("{tag}[{count}]"),
        };
        *count += 1;
        match tag {
            "default" | "integrator" => {}
            "sensor" if sensor.is_some() => {
                return Err(im.cx.err(node, &field, "only one <sensor> is supported"));
            }
            "sensor" => sensor = Some(im.sensor(node, &field)?),
            "bsdf" => {
                let id = im.cx.attr(node, &field, "id")?;
                let mid = im.add_bsdf(node, &field)?;
                if let Some(id) = id {
                    im.bsdfs.insert(id, mid);
                }
            }
            "shape" => im.shape(node, &field)?,
            "emitter" => im.emitter(node, &field)?,
            other => {
                let message = format!("unsupported element <{other}>");
                return Err(im.cx.err(node, &field, message));
            }
        }
    }
    let at = Origin {
        file: file.to_string(),
        line: doc.text_pos_at(root.range().start).row as usize,
        field: "scene".into(),
    };
    if sensor.is_none() {
        return Err(im.cx.err(root, "scene", "the scene has no <sensor>"));
    }
    Ok(Imported {
        scene: im.b.finish(&at)?,
        warnings: im.warnings,
    })
}

/// Refuses elements nested deeper than [`MAX_NESTING`] below the root, at the first such
/// element, before any reader recurses into them.
fn check_nesting(file: &str, doc: &Document) -> Result<()> {
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
fn elements<'a, 'i>(node: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(Node::is_element)
}

/// The state of one import.
struct Importer<'f> {
    cx: Cx<'f>,
    base_dir: &'f Path,
    b: SceneBuilder,
    /// Materials of the `bsdf`s with an `id`, for `ref`.
    bsdfs: HashMap<String, MaterialId>,
    /// Mitsuba's material for shapes without a bsdf (diffuse 0.5), added when first needed.
    default_material: Option<MaterialId>,
    warnings: Vec<String>,
}

impl Importer<'_> {
    /// Reads the `<bsdf>` `node` at `field` and adds its material (and texture).
    fn add_bsdf(&mut self, node: Node, field: &str) -> Result<MaterialId> {
        let read = bsdf::bsdf(&self.cx, node, field, self.base_dir, &mut self.warnings)?;
        let mut material = read.material;
        if let Some(t) = read.kd_texture {
            material.kd_texture = self.b.add_texture(t);
        }
        if let Some(t) = read.normal_texture {
            material.normal_texture = self.b.add_texture(t);
        }
        if let (Some(t), Some(alpha)) = (read.alpha_texture, material.alpha.as_mut()) {
            alpha.texture = self.b.add_texture(t);
        }
        let at = self.origin(node, field);
        self.b.add_material(None, material, &at)
    }

    /// A fixed place for the builder's errors: the element's line and field.
    fn origin(&self, node: Node, field: &str) -> Origin {
        Origin {
            file: self.cx.file.to_string(),
            line: node.document().text_pos_at(node.range().start).row as usize,
            field: field.to_string(),
        }
    }

    /// `<sensor type="perspective">` with its film and sampler: the camera, image size, spp.
    fn sensor(&mut self, node: Node, field: &str) -> Result<()> {
        let cx = &self.cx;
        let p = Plugin::new(cx, node, field.to_string())?;
        if p.kind != "perspective" {
            let message = format!("unsupported sensor `{}` (only `perspective`)", p.kind);
            return Err(cx.err(node, field, message));
        }
        // Mitsuba's film size when the file gives none.
        self.b.settings().width = 768;
        self.b.settings().height = 576;
        for child in &p.objects {
            let sub = format!("{field}.{}", child.tag_name().name());
            match child.tag_name().name() {
                "film" => film(cx, *child, sub, &mut self.warnings, &mut self.b)?,
                "sampler" => {
                    let s = Plugin::new(cx, *child, sub)?;
                    s.setting(cx, "sample_count", "spp", self.b.settings())?;
                    // `sample_count` is the author's total per pixel: our default render
                    // spreads it over its progressive passes.
                    let settings = self.b.settings();
                    settings.spp = settings.spp.div_ceil(settings.passes.max(1));
                    s.ignore(&["seed"]);
                    s.done(cx)?;
                }
                other => {
                    let message = format!("unsupported <{other}> in a sensor");
                    return Err(cx.err(*child, field, message));
                }
            }
        }
        let fov_node = p.float(cx, "fov")?;
        let Some(fov) = fov_node else {
            return Err(cx.err(node, &p.at("fov"), "missing (focal_length is unsupported)"));
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(cx.err(node, &p.at("fov"), "must be in (0, 180) degrees"));
        }
        let axis = p.string(cx, "fov_axis")?.unwrap_or_else(|| "x".into());
        let (w, h) = (
            self.b.settings().width as f32,
            self.b.settings().height as f32,
        );
        let t = (fov.to_radians() / 2.0).tan();
        let ty = match axis.as_str() {
            "x" => t * h / w,
            "y" => t,
            "diagonal" => t * h / (w * w + h * h).sqrt(),
            "smaller" if w < h => t * h / w,
            "larger" if w > h => t * h / w,
            "smaller" | "larger" => t,
            other => {
                let message =
                    format!("unknown fov_axis `{other}` (x, y, diagonal, smaller, larger)");
                return Err(cx.err(node, &p.at("fov_axis"), message));
            }
        };
        let fov_y = 2.0 * ty.atan().to_degrees();
        let m = p.transform(cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        p.ignore(&["near_clip", "far_clip"]);
        p.done(cx)?;
        let eye = m.transform_point3(Vec3::ZERO);
        let forward = m.transform_vector3(Vec3::Z);
        let up = m.transform_vector3(Vec3::Y);
        let left = m.transform_vector3(Vec3::X).normalize_or_zero();
        if left.dot(up.cross(forward).normalize_or_zero()) < 0.999 {
            let message = "unsupported camera to_world (only rotation, translation, uniform scale)";
            return Err(cx.err(node, &p.at("to_world"), message));
        }
        let at = self.origin(node, field);
        self.b.camera(eye, eye + forward, up, fov_y, &at)
    }

    /// The material of a `<ref id>` to a bsdf defined earlier.
    fn reference(&self, node: Node, field: &str) -> Result<MaterialId> {
        let id = self.cx.need_attr(node, field, "id")?;
        if let Some(&mid) = self.bsdfs.get(&id) {
            return Ok(mid);
        }
        let mut known: Vec<String> = self.bsdfs.keys().map(|k| format!("`{k}`")).collect();
        known.sort();
        let known = if known.is_empty() {
            "none".to_string()
        } else {
            known.join(", ")
        };
        let message = format!("unknown bsdf id `{id}` (defined before this line: {known})");
        Err(self.cx.err(node, field, message))
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

/// `<film type="hdrfilm">`: the image size; a non-box `rfilter` is approximated by our box.
fn film(
    cx: &Cx,
    node: Node,
    field: String,
    warnings: &mut Vec<String>,
    b: &mut SceneBuilder,
) -> Result<()> {
    let f = Plugin::new(cx, node, field)?;
    if f.kind != "hdrfilm" {
        let message = format!("unsupported film `{}` (only `hdrfilm`)", f.kind);
        return Err(cx.err(node, &f.field, message));
    }
    f.setting(cx, "width", "width", b.settings())?;
    f.setting(cx, "height", "height", b.settings())?;
    f.ignore(&["pixel_format", "file_format", "component_format"]);
    f.done(cx)?;
    if f.objects.is_empty() {
        let line = node.document().text_pos_at(node.range().start).row;
        let what = "no rfilter: Mitsuba's default `gaussian` approximated by a one-pixel box";
        warnings.push(format!("{}:{line}: {}: {what}", cx.file, f.field));
    }
    for child in &f.objects {
        let sub = format!("{}.{}", f.field, child.tag_name().name());
        if child.tag_name().name() != "rfilter" {
            let message = format!("unsupported <{}> in a film", child.tag_name().name());
            return Err(cx.err(*child, &f.field, message));
        }
        let r = Plugin::new(cx, *child, sub.clone())?;
        r.ignore(&["radius", "stddev", "B", "C", "lobes"]);
        r.done(cx)?;
        if r.kind != "box" {
            let line = child.document().text_pos_at(child.range().start).row;
            let what = format!("pixel filter `{}` approximated by a one-pixel box", r.kind);
            warnings.push(format!("{}:{line}: {sub}: {what}", cx.file));
        }
    }
    Ok(())
}
