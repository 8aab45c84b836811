//! One Mitsuba plugin element (`<shape type="...">`, `<bsdf ...>`, ...): its typed parameters
//! by name, and its nested objects. Every parameter must be read by the importer (or listed
//! as ignored): [`Plugin::done`] reports the first one nobody read as unsupported, so that
//! nothing in a file is skipped silently.

use crate::error::Result;
use crate::importers::file;
use crate::importers::mitsuba::spectrum::{self, Use, UNBOUNDED};
use crate::importers::mitsuba::values::{Cx, IOR_NAMES};
use crate::settings::{setting, RenderSettings, Slot};
use glam::{Mat4, Vec3};
use roxmltree::Node;
use std::cell::Cell;

/// Elements that are parameters (they carry a `name`); every other child is an object.
const PARAM_TAGS: &[&str] = &[
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "texture",
    "blackbody",
];

/// The elements a colour may be given as.
const COLOR_TAGS: &[&str] = &["rgb", "spectrum", "float", "blackbody"];

/// A plugin element, read.
pub(crate) struct Plugin<'a> {
    /// The element.
    pub node: Node<'a, 'a>,
    /// Its `type` attribute.
    pub kind: String,
    /// Its field path, for errors.
    pub field: String,
    /// Parameters: name, element, whether read.
    params: Vec<(String, Node<'a, 'a>, Cell<bool>)>,
    /// Nested objects (`bsdf`, `emitter`, `film`, `ref`, ...), in order.
    pub objects: Vec<Node<'a, 'a>>,
}

impl<'a> Plugin<'a> {
    /// Reads `node` (which must have a `type`) as the plugin at `field`.
    pub fn new(cx: &Cx<'a>, node: Node<'a, 'a>, field: String) -> Result<Self> {
        let kind = cx.need_attr(node, &field, "type")?;
        let mut params: Vec<(String, Node, Cell<bool>)> = Vec::new();
        let mut objects = Vec::new();
        for child in node.children().filter(Node::is_element) {
            let tag = child.tag_name().name();
            // A named `<ref>` to a top-level texture is that texture as a parameter.
            if let (true, Some(name)) = (tag == "ref", child.attribute("name")) {
                let target = cx.deref(child, &format!("{field}.{name}"))?;
                if target.tag_name().name() == "texture" {
                    params.push((name.to_string(), target, Cell::new(false)));
                    continue;
                }
            }
            if !PARAM_TAGS.contains(&tag) {
                objects.push(child);
                continue;
            }
            let name = cx.need_attr(child, &field, "name")?;
            if params.iter().any(|(n, _, _)| *n == name) {
                let message = format!("parameter `{name}` given twice");
                return Err(cx.err(child, &format!("{field}.{name}"), message));
            }
            params.push((name, child, Cell::new(false)));
        }
        Ok(Plugin {
            node,
            kind,
            field,
            params,
            objects,
        })
    }

    /// The field path of parameter `name`.
    pub fn at(&self, name: &str) -> String {
        format!("{}.{name}", self.field)
    }

    /// The element of parameter `name` when present (else the plugin's own), for pointing
    /// an error at its line; does not mark it read.
    pub fn node_of(&self, name: &str) -> Node<'a, 'a> {
        let found = self.params.iter().find(|(n, _, _)| n == name);
        found.map_or(self.node, |(_, node, _)| *node)
    }

    /// The element of parameter `name`, marked read; its tag must be one of `tags`.
    fn param(&self, cx: &Cx, name: &str, tags: &[&str]) -> Result<Option<Node<'a, 'a>>> {
        let Some((_, node, read)) = self.params.iter().find(|(n, _, _)| n == name) else {
            return Ok(None);
        };
        read.set(true);
        let tag = node.tag_name().name();
        if tag == "texture" && tags.contains(&"rgb") {
            let kind = cx.attr(*node, &self.at(name), "type")?.unwrap_or_default();
            let message = format!("unsupported texture `{kind}` (only constant colours)");
            return Err(cx.err(*node, &self.at(name), message));
        }
        if !tags.contains(&tag) {
            let want: Vec<String> = tags.iter().map(|t| format!("<{t}>")).collect();
            let message = format!("expected {}, found <{tag}>", want.join(" or "));
            return Err(cx.err(*node, &self.at(name), message));
        }
        Ok(Some(*node))
    }

    /// The `<texture>` element given for parameter `name`, marked read; `None` when the
    /// parameter is absent or not a texture.
    pub fn texture_param(&self, name: &str) -> Option<Node<'a, 'a>> {
        let (_, node, read) = self.params.iter().find(|(n, _, _)| n == name)?;
        if node.tag_name().name() != "texture" {
            return None;
        }
        read.set(true);
        Some(*node)
    }

    /// The names of every `<texture>` parameter (whatever its name: Mitsuba's `bumpmap` takes
    /// its one texture by type), not marked read.
    pub fn texture_names(&self) -> Vec<String> {
        (self.params.iter())
            .filter(|(_, node, _)| node.tag_name().name() == "texture")
            .map(|(name, _, _)| name.clone())
            .collect()
    }

    /// Marks parameters the importer accepts but does not use.
    pub fn ignore(&self, names: &[&str]) {
        for (name, _, read) in &self.params {
            if names.contains(&name.as_str()) {
                read.set(true);
            }
        }
    }

    /// A `float` (or `integer`) parameter.
    pub fn float(&self, cx: &Cx, name: &str) -> Result<Option<f32>> {
        let Some(node) = self.param(cx, name, &["float", "integer"])? else {
            return Ok(None);
        };
        cx.number(node, &self.at(name), "value").map(Some)
    }

    /// A positive `float` parameter, `default` when absent.
    pub fn positive(&self, cx: &Cx, name: &str, default: f32) -> Result<f32> {
        let v = self.float(cx, name)?.unwrap_or(default);
        if v > 0.0 {
            return Ok(v);
        }
        let node = self
            .param(cx, name, &["float", "integer"])?
            .unwrap_or(self.node);
        Err(cx.err(node, &self.at(name), "must be positive"))
    }

    /// A `string` parameter.
    pub fn string(&self, cx: &Cx, name: &str) -> Result<Option<String>> {
        let Some(node) = self.param(cx, name, &["string"])? else {
            return Ok(None);
        };
        cx.need_attr(node, &self.at(name), "value").map(Some)
    }

    /// A `boolean` parameter, `false` when absent.
    pub fn boolean(&self, cx: &Cx, name: &str) -> Result<bool> {
        self.boolean_or(cx, name, false)
    }

    /// A `boolean` parameter, `default` when absent.
    pub fn boolean_or(&self, cx: &Cx, name: &str, default: bool) -> Result<bool> {
        let Some(node) = self.param(cx, name, &["boolean"])? else {
            return Ok(default);
        };
        match cx.need_attr(node, &self.at(name), "value")?.as_str() {
            "true" => Ok(true),
            "false" => Ok(false),
            other => {
                let message = format!("`{other}` is not `true` or `false`");
                Err(cx.err(node, &self.at(name), message))
            }
        }
    }

    /// A colour: `rgb` (1 or 3 numbers), `float`, or a spectrum converted as Mitsuba's RGB
    /// variants convert a bsdf's parameter `name` (see `spectrum.rs`).
    pub fn color(&self, cx: &Cx, name: &str) -> Result<Option<Vec3>> {
        let usage = match UNBOUNDED.contains(&name) {
            true => Use::Unbounded,
            false => Use::Bounded,
        };
        self.color_as(cx, name, usage)
    }

    /// An emitter's colour (`radiance`, `intensity`, `irradiance`), as [`Plugin::color`].
    pub fn emission(&self, cx: &Cx, name: &str) -> Result<Option<Vec3>> {
        self.color_as(cx, name, Use::Emission)
    }

    fn color_as(&self, cx: &Cx, name: &str, usage: Use) -> Result<Option<Vec3>> {
        let Some(node) = self.param(cx, name, COLOR_TAGS)? else {
            return Ok(None);
        };
        let field = self.at(name);
        let c = match node.tag_name().name() {
            "rgb" => cx.triple(node, &field, 0.0)?,
            "float" => Vec3::splat(cx.number(node, &field, "value")?),
            _ => spectrum_element(cx, node, &field, usage)?,
        };
        if c.min_element() < 0.0 {
            return Err(cx.err(node, &field, "components must be >= 0"));
        }
        Ok(Some(c))
    }

    /// A reflectance: a colour with every component in [0, 1], `default` when absent.
    pub fn albedo(&self, cx: &Cx, name: &str, default: f32) -> Result<Vec3> {
        let c = self.color(cx, name)?.unwrap_or(Vec3::splat(default));
        if c.max_element() > 1.0 {
            let node = self.param(cx, name, COLOR_TAGS)?;
            let message = "components must be in [0, 1]";
            return Err(cx.err(node.unwrap_or(self.node), &self.at(name), message));
        }
        Ok(c)
    }

    /// A `point` or `vector` parameter.
    pub fn point(&self, cx: &Cx, name: &str) -> Result<Option<Vec3>> {
        let Some(node) = self.param(cx, name, &["point", "vector"])? else {
            return Ok(None);
        };
        cx.triple(node, &self.at(name), 0.0).map(Some)
    }

    /// A `transform` parameter.
    pub fn transform(&self, cx: &Cx, name: &str) -> Result<Option<Mat4>> {
        let Some(node) = self.param(cx, name, &["transform"])? else {
            return Ok(None);
        };
        cx.transform(node, &self.at(name)).map(Some)
    }

    /// An index of refraction: a positive `float` or a name from Mitsuba's table.
    pub fn ior(&self, cx: &Cx, name: &str, default: f32) -> Result<f32> {
        let Some(node) = self.param(cx, name, &["float", "string", "integer"])? else {
            return Ok(default);
        };
        let field = self.at(name);
        if node.tag_name().name() == "string" {
            let text = cx.need_attr(node, &field, "value")?;
            let found = IOR_NAMES.iter().find(|(n, _)| *n == text);
            let message = format!("unknown index of refraction `{text}`");
            return found
                .map(|(_, v)| *v)
                .ok_or_else(|| cx.err(node, &field, message));
        }
        match cx.number(node, &field, "value")? {
            v if v > 0.0 => Ok(v),
            _ => Err(cx.err(node, &field, "must be positive")),
        }
    }

    /// Sets the integer setting `key` from parameter `name`, within the setting's range.
    pub fn setting(&self, cx: &Cx, name: &str, key: &str, s: &mut RenderSettings) -> Result<()> {
        let Some(node) = self.param(cx, name, &["integer"])? else {
            return Ok(());
        };
        let field = self.at(name);
        let text = cx.need_attr(node, &field, "value")?;
        let Ok(v) = text.trim().parse::<i64>() else {
            return Err(cx.err(node, &field, format!("`{text}` is not an integer")));
        };
        let row = setting(key).expect("a setting of the table");
        if let (true, Slot::U32 { set, .. }) = (row.range.admits_int(v), row.slot) {
            set(s, v as u32);
            return Ok(());
        }
        let message = format!("must be {}", row.range.requirement());
        Err(cx.err(node, &field, message))
    }

    /// Fails on the first parameter nobody read: it is not supported.
    pub fn done(&self, cx: &Cx) -> Result<()> {
        match self.params.iter().find(|(_, _, read)| !read.get()) {
            None => Ok(()),
            Some((name, node, _)) => {
                let message = format!("unsupported parameter of `{}`", self.kind);
                Err(cx.err(*node, &self.at(name), message))
            }
        }
    }
}

/// A `<spectrum>`: a constant `value`, `wavelength:value` pairs in `value` or in a file
/// (`filename`: a pair per line, `#` comments), or `type="blackbody"` with a `temperature`
/// (also Mitsuba 0.6's `<blackbody temperature>`), as sRGB for `usage`.
fn spectrum_element(cx: &Cx, node: Node, field: &str, usage: Use) -> Result<Vec3> {
    if node.tag_name().name() == "blackbody" || node.attribute("type").is_some() {
        let kelvin = match node.tag_name().name() {
            "blackbody" => cx.number(node, field, "temperature")?,
            _ => {
                let p = Plugin::new(cx, node, field.to_string())?;
                if p.kind != "blackbody" {
                    let message = format!("unsupported spectrum `{}` (only blackbody)", p.kind);
                    return Err(cx.err(node, field, message));
                }
                let t = p.float(cx, "temperature")?;
                p.done(cx)?;
                t.ok_or_else(|| cx.err(node, &p.at("temperature"), "missing"))?
            }
        };
        if usage != Use::Emission {
            let message = "a blackbody is an emission spectrum (only in an <emitter>)";
            return Err(cx.err(node, field, message));
        }
        if kelvin <= 0.0 {
            return Err(cx.err(node, field, "the temperature must be positive"));
        }
        return Ok(spectrum::blackbody(kelvin as f64));
    }
    let text = match (
        cx.attr(node, field, "value")?,
        cx.attr(node, field, "filename")?,
    ) {
        (Some(text), None) => text,
        (None, Some(name)) => file::read_text(&cx.resolve(&name))
            .map_err(|e| cx.err(node, field, e.to_string()))?
            .lines()
            .filter(|l| !l.trim_start().starts_with('#'))
            .flat_map(|l| {
                let mut words = l.split_whitespace();
                words
                    .next()
                    .zip(words.next())
                    .map(|(w, v)| format!("{w}:{v} "))
            })
            .collect(),
        _ => {
            let message = "a spectrum needs one of `value` or `filename`";
            return Err(cx.err(node, field, message));
        }
    };
    let words: Vec<&str> = text
        .split([',', ' ', '\t', '\n', '\r'])
        .filter(|w| !w.is_empty())
        .collect();
    if let [word] = words[..] {
        if !word.contains(':') {
            return Ok(spectrum::constant(cx.number(node, field, "value")?, usage));
        }
    }
    let mut pairs: Vec<(f64, f64)> = Vec::with_capacity(words.len());
    for word in words {
        let pair = word
            .split_once(':')
            .and_then(|(w, v)| Some((w.parse().ok()?, v.parse().ok()?)));
        let Some((w, v)) = pair.filter(|&(w, v): &(f64, f64)| w.is_finite() && v.is_finite())
        else {
            let message = format!("`{word}` is not a finite wavelength:value pair");
            return Err(cx.err(node, field, message));
        };
        if pairs.last().is_some_and(|&(last, _)| w <= last) {
            return Err(cx.err(node, field, "the wavelengths must increase"));
        }
        pairs.push((w, v));
    }
    if pairs.len() < 2 {
        let message = "a spectrum needs one value or at least two wavelength:value pairs";
        return Err(cx.err(node, field, message));
    }
    Ok(spectrum::list_to_srgb(&pairs, usage))
}
