//! Reading Mitsuba 3 XML values: `$name` substitution in attributes, the typed parameter
//! elements (`float`, `integer`, `boolean`, `string`, `rgb`, `spectrum`, `point`, `vector`)
//! and `transform` elements (`lookat`, `matrix`, `translate`, `rotate`, `scale`, applied in
//! the order they appear, each one after the previous).
//!
//! Every error is an [`Error::Scene`] naming the file, the line of the element and its field.

use crate::error::{Error, Result};
use glam::{Mat3, Mat4, Vec3, Vec4};
use roxmltree::{Document, Node};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Longest attribute value accepted after `$name` substitution: defaults may refer to earlier
/// defaults, so each level can double the text (`$d0$d0`).
pub const MAX_VALUE_BYTES: usize = 1 << 20;

/// What every reader needs: the files (for errors), the `default` parameters, where file
/// names are looked up and the top-level objects with an `id`.
pub(crate) struct Cx<'f> {
    /// The scene file, as errors show it.
    pub file: &'f str,
    /// Every parsed file (the scene and the files it includes) with its name, for errors.
    pub docs: Vec<(&'f Document<'f>, &'f str)>,
    /// The defines and `<default name="..." value="..."/>`s, for `$name` substitution.
    pub defaults: Params,
    /// Mitsuba's file resolver: the `<path>` directories, the latest first, then the scene
    /// file's directory.
    pub search: Vec<PathBuf>,
    /// The top-level objects with an `id`, for `<ref>`.
    pub ids: HashMap<String, Node<'f, 'f>>,
}

/// The parameters for `$name`: the command line's defines and the `<default>`s.
#[derive(Default)]
pub(crate) struct Params {
    values: HashMap<String, String>,
    /// The lengths of the names, longest first (to match the longest name first).
    lengths: Vec<usize>,
}

impl Params {
    /// Parameters `(NAME, VALUE)`.
    pub fn new(defines: &[(String, String)]) -> Self {
        let mut p = Params::default();
        for (name, value) in defines {
            p.add(name.clone(), value.clone());
        }
        p
    }

    /// Adds `name` unless it exists (Mitsuba keeps the first).
    pub fn add(&mut self, name: String, value: String) {
        if let Err(i) = self.lengths.binary_search_by(|l| name.len().cmp(l)) {
            self.lengths.insert(i, name.len());
        }
        self.values.entry(name).or_insert(value);
    }

    /// The longest parameter whose name starts `text`: its name's length and its value.
    /// Names are words (checked by [`check_name`]), so only the word `text` starts with is
    /// tried, at the lengths names have: at most [`MAX_NAME_BYTES`] lookups of as many bytes.
    fn longest_at(&self, text: &str) -> Option<(usize, &str)> {
        let word = text.find(|c| !is_name_char(c)).unwrap_or(text.len());
        let mut lengths = self.lengths.iter().filter(|&&n| n <= word);
        lengths.find_map(|&n| Some((n, self.values.get(&text[..n])?.as_str())))
    }
}

/// Longest parameter name accepted (real names are a few words).
pub const MAX_NAME_BYTES: usize = 256;

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Refuses a parameter name that is not 1 to [`MAX_NAME_BYTES`] letters, digits or `_`
/// (Mitsuba takes any text, but matches it textually).
pub fn check_name(name: &str) -> std::result::Result<(), String> {
    match !name.is_empty() && name.len() <= MAX_NAME_BYTES && name.chars().all(is_name_char) {
        true => Ok(()),
        false => Err(format!(
            "`{name}` is not a parameter name (1 to {MAX_NAME_BYTES} letters, digits, _)"
        )),
    }
}

/// `raw` with every `$name` replaced by its value, as Mitsuba substitutes: the longest name
/// that follows the `$` (so `$spp_x` is `$spp` then `_x` when only `spp` is defined), `\$` a
/// literal `$`; values are not substituted again. The error names the first unknown
/// `$name` or says the value grew over [`MAX_VALUE_BYTES`].
pub(crate) fn substitute(raw: &str, params: &Params) -> std::result::Result<String, String> {
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(i) = rest.find('$') {
        let tail = &rest[i + 1..];
        if rest[..i].ends_with('\\') {
            out.push_str(&rest[..i - 1]);
            out.push('$');
            rest = tail;
            continue;
        }
        out.push_str(&rest[..i]);
        let Some((len, value)) = params.longest_at(tail) else {
            let len = tail.find(|c| !is_name_char(c)).unwrap_or(tail.len());
            let key = &tail[..len];
            return Err(format!("`${key}` has no <default name=\"{key}\" .../>"));
        };
        if out.len() + value.len() > MAX_VALUE_BYTES {
            let key = &tail[..len];
            return Err(format!(
                "the value expands to more than {MAX_VALUE_BYTES} bytes (through `${key}`)"
            ));
        }
        out.push_str(value);
        rest = &tail[len..];
    }
    out.push_str(rest);
    Ok(out)
}

impl<'f> Cx<'f> {
    /// The top-level object `<ref id>` `node` names (`node` itself when it is no `ref`).
    pub fn deref(&self, node: Node<'f, 'f>, field: &str) -> Result<Node<'f, 'f>> {
        if node.tag_name().name() != "ref" {
            return Ok(node);
        }
        let id = self.need_attr(node, field, "id")?;
        let message = || format!("unknown id `{id}`");
        self.ids
            .get(&id)
            .copied()
            .ok_or_else(|| self.err(node, field, message()))
    }

    /// The name of the file `node` is in.
    pub fn file_of(&self, node: Node) -> &str {
        let doc = node.document();
        let found = self.docs.iter().find(|(d, _)| std::ptr::eq(*d, doc));
        found.map_or(self.file, |(_, name)| name)
    }

    /// `FILE:LINE` of `node`, for warnings.
    pub fn loc(&self, node: Node) -> String {
        let line = node.document().text_pos_at(node.range().start).row;
        format!("{}:{line}", self.file_of(node))
    }

    /// An error about `node` (its file and line) and `field`.
    pub fn err(&self, node: Node, field: &str, message: impl Into<String>) -> Error {
        let line = node.document().text_pos_at(node.range().start).row as usize;
        Error::Scene {
            file: self.file_of(node).to_string(),
            line,
            field: field.to_string(),
            message: message.into(),
        }
    }

    /// The file a scene names: absolute as given, else the first `search` directory that
    /// has it (Mitsuba's `FileResolver::resolve`), else in the scene's directory.
    pub fn resolve(&self, name: &str) -> PathBuf {
        resolve(&self.search, name)
    }

    /// The attribute `name` of `node` after `$name` substitution, if present.
    pub fn attr(&self, node: Node, field: &str, name: &str) -> Result<Option<String>> {
        let Some(raw) = node.attribute(name) else {
            return Ok(None);
        };
        substitute(raw, &self.defaults)
            .map(Some)
            .map_err(|m| self.err(node, field, m))
    }

    /// The attribute `name` of `node`, which must be present.
    pub fn need_attr(&self, node: Node, field: &str, name: &str) -> Result<String> {
        let message = || format!("<{}> needs a `{name}` attribute", node.tag_name().name());
        self.attr(node, field, name)?
            .ok_or_else(|| self.err(node, field, message()))
    }

    /// The finite numbers of attribute `name` (separated by commas and/or spaces).
    pub fn numbers(&self, node: Node, field: &str, name: &str) -> Result<Vec<f32>> {
        let text = self.need_attr(node, field, name)?;
        let words = text.split(|c: char| c == ',' || c.is_whitespace());
        let mut out = Vec::new();
        for word in words.filter(|w| !w.is_empty()) {
            let Ok(v) = word.parse::<f32>() else {
                let message = format!("`{word}` is not a number");
                return Err(self.err(node, field, message));
            };
            if !v.is_finite() {
                return Err(self.err(node, field, format!("`{word}` must be finite")));
            }
            out.push(v);
        }
        Ok(out)
    }

    /// One finite number in attribute `name`.
    pub fn number(&self, node: Node, field: &str, name: &str) -> Result<f32> {
        match self.numbers(node, field, name)?[..] {
            [v] => Ok(v),
            ref v => Err(self.err(node, field, format!("expected 1 number, found {}", v.len()))),
        }
    }

    /// Three numbers: attribute `value` (one number is repeated) or `x`, `y`, `z` (each
    /// `missing` when absent).
    pub fn triple(&self, node: Node, field: &str, missing: f32) -> Result<Vec3> {
        if node.attribute("value").is_some() {
            return match self.numbers(node, field, "value")?[..] {
                [v] => Ok(Vec3::splat(v)),
                [x, y, z] => Ok(Vec3::new(x, y, z)),
                ref v => {
                    let message = format!("expected 1 or 3 numbers, found {}", v.len());
                    Err(self.err(node, field, message))
                }
            };
        }
        let mut v = [missing; 3];
        for (axis, slot) in ["x", "y", "z"].into_iter().zip(&mut v) {
            if node.attribute(axis).is_some() {
                *slot = self.number(node, field, axis)?;
            }
        }
        Ok(Vec3::from(v))
    }

    /// A 3-vector attribute (`lookat`'s `origin`, `target`, `up`).
    fn vec3_attr(&self, node: Node, field: &str, name: &str) -> Result<Vec3> {
        match self.numbers(node, field, name)?[..] {
            [x, y, z] => Ok(Vec3::new(x, y, z)),
            ref v => {
                let message = format!("`{name}` needs 3 numbers, found {}", v.len());
                Err(self.err(node, field, message))
            }
        }
    }

    /// The matrix of a `<transform>` element.
    pub fn transform(&self, node: Node, field: &str) -> Result<Mat4> {
        let mut m = Mat4::IDENTITY;
        for op in node.children().filter(Node::is_element) {
            let step = match op.tag_name().name() {
                "translate" => Mat4::from_translation(self.triple(op, field, 0.0)?),
                "scale" => {
                    let s = self.triple(op, field, 1.0)?;
                    if s.x * s.y * s.z == 0.0 {
                        return Err(self.err(op, field, "a zero scale"));
                    }
                    Mat4::from_scale(s)
                }
                "rotate" => {
                    let axis = self.triple(op, field, 0.0)?;
                    let angle = self.number(op, field, "angle")?;
                    let m = mitsuba_rotate(axis, angle.to_radians());
                    if !m.is_finite() || m.determinant() == 0.0 {
                        return Err(self.err(op, field, "the rotation is singular"));
                    }
                    m
                }
                "matrix" => self.matrix(op, field)?,
                "lookat" => self.look_at(op, field)?,
                other => {
                    let message = format!("unsupported transform <{other}>");
                    return Err(self.err(op, field, message));
                }
            };
            m = step * m;
        }
        Ok(m)
    }

    /// `<matrix value="..."/>`: 16 (or 9) numbers, row by row; the last row must be 0 0 0 1.
    fn matrix(&self, op: Node, field: &str) -> Result<Mat4> {
        let v = self.numbers(op, field, "value")?;
        let rows: [Vec4; 4] = match v.len() {
            16 => std::array::from_fn(|r| Vec4::from_slice(&v[4 * r..4 * r + 4])),
            9 => std::array::from_fn(|r| match r {
                3 => Vec4::W,
                r => Vec4::new(v[3 * r], v[3 * r + 1], v[3 * r + 2], 0.0),
            }),
            n => {
                let message = format!("a matrix needs 16 or 9 numbers, found {n}");
                return Err(self.err(op, field, message));
            }
        };
        if rows[3] != Vec4::W {
            let message = "projective matrices are unsupported (last row must be 0 0 0 1)";
            return Err(self.err(op, field, message));
        }
        let m = Mat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
        if m.determinant() == 0.0 {
            return Err(self.err(op, field, "the matrix is singular"));
        }
        Ok(m)
    }

    /// `<lookat origin target up/>`: camera space +z towards the target, +y up, +x left.
    fn look_at(&self, op: Node, field: &str) -> Result<Mat4> {
        let origin = self.vec3_attr(op, field, "origin")?;
        let target = self.vec3_attr(op, field, "target")?;
        let up = self.vec3_attr(op, field, "up")?;
        let Some(dir) = (target - origin).try_normalize() else {
            return Err(self.err(op, field, "lookat origin equals target"));
        };
        let Some(left) = up.cross(dir).try_normalize() else {
            return Err(self.err(op, field, "lookat up is parallel to the view"));
        };
        let new_up = dir.cross(left);
        Ok(Mat4::from_cols(
            left.extend(0.0),
            new_up.extend(0.0),
            dir.extend(0.0),
            origin.extend(1.0),
        ))
    }
}

/// `name` looked up in the `search` directories (the last is the scene's directory).
pub(crate) fn resolve(search: &[PathBuf], name: &str) -> PathBuf {
    let path = Path::new(name);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    let found = search.iter().map(|d| d.join(path)).find(|p| p.exists());
    found.unwrap_or_else(|| search.last().map_or(path.to_path_buf(), |d| d.join(path)))
}

/// Refractive indices Mitsuba 3 accepts by name (its `ior` table).
pub(crate) const IOR_NAMES: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.333),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.47),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.575),
    ("diamond", 2.419),
];

/// Mitsuba's `rotate` about `axis` by `angle` radians: Rodrigues' formula
/// `cos I + sin [axis]x + (1 - cos) axis axis^T` with the axis as written, **not normalised**
/// (Mitsuba 3.9.1's `Transform4f::rotate`; `scripts/mitsuba_conformance_probe.py`): an axis
/// that is not a unit vector also scales and shears, as it does in Mitsuba.
pub fn mitsuba_rotate(axis: Vec3, angle: f32) -> Mat4 {
    let (sin, cos) = angle.sin_cos();
    let a = axis;
    let skew = Mat3::from_cols(
        Vec3::new(0.0, a.z, -a.y),
        Vec3::new(-a.z, 0.0, a.x),
        Vec3::new(a.y, -a.x, 0.0),
    );
    let outer = Mat3::from_cols(a * a.x, a * a.y, a * a.z);
    Mat4::from_mat3(Mat3::IDENTITY * cos + skew * sin + outer * (1.0 - cos))
}
