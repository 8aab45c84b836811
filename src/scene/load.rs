//! Scene files: a TOML description (format in `scenes/README.md`) turned into a [`Scene`].
//!
//! Every table is read as a map from key to [`Spanned`] value, so that each error names the
//! line and the field path (`shapes[3].radius`, `materials.white.albedo`, ...) it is about.
//! Unknown keys, and keys that do not apply to a table's `type`, are errors.

use super::{obj, Light, LightShape, Material, Scene, Sphere, Triangle, NO_LIGHT};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::settings::{Filter, FresnelMode, Mode, RenderSettings, MAX_K, MAX_RESOLUTION};
use glam::Vec3;
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::f32::consts::PI;
use std::ops::Range;
use std::path::Path;
use toml::{Spanned, Value};

/// One TOML table: key -> value with its byte span.
type RawTable = BTreeMap<String, Spanned<Value>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: Option<Spanned<RawTable>>,
    render: Option<Spanned<RawTable>>,
    #[serde(default)]
    materials: BTreeMap<String, Spanned<RawTable>>,
    #[serde(default)]
    shapes: Vec<Spanned<RawTable>>,
    #[serde(default)]
    lights: Vec<Spanned<RawTable>>,
}

/// A table kind's types, each with the keys (besides `type`) it accepts.
type Types = [(&'static str, &'static [&'static str])];

const CAMERA_KEYS: &[&str] = &["eye", "target", "up", "fov", "width", "height"];
const MATERIAL_TYPES: &Types = &[
    ("diffuse", &["albedo"]),
    ("glossy", &["kd", "ks", "exponent"]),
    ("mirror", &["reflectance"]),
    ("glass", &["ior"]),
    ("emissive", &["radiance", "two_sided"]),
];
const SHAPE_TYPES: &Types = &[
    ("quad", &["corners"]),
    ("triangle", &["vertices"]),
    ("sphere", &["center", "radius"]),
    ("box", &["min", "max", "rotate_y"]),
    ("mesh", &["file", "scale", "translate"]),
];
const SHAPE_KEYS: &[&str] = &["material", "emission", "two_sided"];
const LIGHT_TYPES: &Types = &[("point", &["position", "intensity"])];
const BIG: i64 = u32::MAX as i64;

/// Reads and loads the scene file at `path`; meshes are resolved relative to its directory.
///
/// An unreadable file is [`Error::Io`]; everything wrong inside it is [`Error::Scene`].
pub fn load(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path);
    let text = text.map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let base_dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    load_str(&text, &path.display().to_string(), base_dir)
}

/// Loads a scene from TOML `text`. `file` names it in errors; mesh paths are relative to
/// `base_dir`. Every problem is an [`Error::Scene`] naming the line and field it is about.
pub fn load_str(text: &str, file: &str, base_dir: &Path) -> Result<Scene> {
    let cx = Ctx { text, file };
    let raw: RawScene = toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        // A syntax error is about the file; a wrong top-level key is about that key.
        let field = match toml::from_str::<toml::Table>(text) {
            Err(e) if !e.message().contains("duplicate") => "toml".into(),
            _ => path_at(text, span.start),
        };
        cx.err(span, field, e.message().trim())
    })?;

    let mut settings = RenderSettings::default();
    let Some(camera_table) = &raw.camera else {
        return Err(cx.err(0..0, "camera", "missing table [camera]"));
    };
    let camera = camera(&Tab::new(&cx, "camera".into(), camera_table), &mut settings)?;
    if let Some(r) = &raw.render {
        render(&Tab::new(&cx, "render".into(), r), &mut settings)?;
    }
    let (materials, triangles, spheres, lights) = (vec![], vec![], vec![], vec![]);
    let mut scene = Scene {
        camera,
        materials,
        triangles,
        spheres,
        lights,
        settings,
    };

    // Materials, in file order.
    let mut named: Vec<_> = raw.materials.iter().collect();
    named.sort_by_key(|(_, m)| m.span().start);
    let mut by_name = HashMap::new();
    for (name, m) in named {
        let material = material(&Tab::new(&cx, format!("materials.{name}"), m))?;
        by_name.insert(name.as_str(), scene.materials.len() as u32);
        scene.materials.push(material);
    }
    for (i, s) in raw.shapes.iter().enumerate() {
        let t = Tab::new(&cx, format!("shapes[{i}]"), s);
        shape(&t, &by_name, base_dir, &mut scene)?;
    }
    for (i, l) in raw.lights.iter().enumerate() {
        let t = Tab::new(&cx, format!("lights[{i}]"), l);
        t.typed(LIGHT_TYPES, &[])?;
        let position = t.need("position", t.vec3("position")?)?;
        let intensity = t.need("intensity", t.color("intensity", None)?)?;
        let power = 4.0 * PI * intensity;
        let shape = LightShape::Point {
            position,
            intensity,
        };
        scene.lights.push(Light { shape, power });
    }
    Ok(scene)
}

fn camera(t: &Tab, settings: &mut RenderSettings) -> Result<Camera> {
    t.only(CAMERA_KEYS, |_| false, "")?;
    let eye = t.need("eye", t.vec3("eye")?)?;
    let target = t.need("target", t.vec3("target")?)?;
    let up = t.vec3("up")?.unwrap_or(Vec3::Y);
    let fov = t.need("fov", t.num("fov")?)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(t.fail("fov", "must be in (0, 180) degrees"));
    }
    let max = MAX_RESOLUTION as i64;
    set(&mut settings.width, t.int("width", 1, max)?);
    set(&mut settings.height, t.int("height", 1, max)?);
    Camera::look_at(eye, target, up, fov).ok_or_else(|| {
        if target == eye {
            t.fail("eye", "degenerate camera frame (eye equals target)")
        } else {
            t.fail("up", "degenerate camera frame (up is parallel to the view)")
        }
    })
}

/// Reads `[render]` keys into `RenderSettings` fields of the same names, through `Tab` methods.
macro_rules! settings {
    ($t:ident, $s:ident, $($key:ident: $read:ident($($arg:expr),*)),* $(,)?) => {
        $t.only(&[$(stringify!($key)),*], |_| false, "")?;
        $(if let Some(v) = $t.$read(stringify!($key) $(, $arg)*)? { $s.$key = v; })*
    };
}

fn render(t: &Tab, s: &mut RenderSettings) -> Result<()> {
    let fresnel = |f: &str| match f {
        "exact" => Some(FresnelMode::Exact),
        "schlick" => Some(FresnelMode::Schlick),
        _ => None,
    };
    settings!(t, s,
        photons: int(1, BIG), caustic_photons: int(0, BIG), k: int(1, MAX_K as i64),
        radius: positive(), caustic_radius: positive(), spp: int(1, BIG),
        shadow_samples: int(1, BIG), mode: parse(&Mode::NAMES, Mode::parse),
        filter: parse(&Filter::NAMES, Filter::parse), fresnel: parse(&["exact", "schlick"], fresnel),
        max_photon_bounces: int(1, 64), max_depth: int(1, 64), seed: int(0, BIG), exposure: num(),
    );
    Ok(())
}

fn material(t: &Tab) -> Result<Material> {
    let unit = Some(1.0);
    Ok(match t.typed(MATERIAL_TYPES, &[])? {
        "diffuse" => Material::diffuse(t.need("albedo", t.color("albedo", unit)?)?),
        "glossy" => {
            let kd = t.need("kd", t.color("kd", unit)?)?;
            let ks = t.need("ks", t.color("ks", unit)?)?;
            if (kd + ks).max_element() > 1.0 {
                let message = "kd + ks must be at most 1 in every channel (energy conservation)";
                return Err(t.fail("ks", message));
            }
            let exponent = t.need("exponent", t.num("exponent")?)?;
            if exponent < 0.0 {
                return Err(t.fail("exponent", "must be >= 0"));
            }
            Material::glossy(kd, ks, exponent)
        }
        "mirror" => Material::mirror(t.need("reflectance", t.color("reflectance", unit)?)?),
        "glass" => Material::glass(t.need("ior", t.positive("ior")?)?),
        _ => Material {
            two_sided_emission: t.boolean("two_sided")?.unwrap_or(false),
            ..Material::emitter(t.need("radiance", t.color("radiance", None)?)?)
        },
    })
}

fn shape(t: &Tab, names: &HashMap<&str, u32>, base_dir: &Path, scene: &mut Scene) -> Result<()> {
    let kind = t.typed(SHAPE_TYPES, SHAPE_KEYS)?;

    // The material, with the shape's own emission if it has one.
    let emission = t.color("emission", None)?;
    let mut index = match t.string("material")? {
        Some(name) => material_index(t, name, names)?,
        None if emission.is_some() => u32::MAX,
        None => return Err(t.missing("material")),
    };
    let black = Material::black();
    let base = *scene.materials.get(index as usize).unwrap_or(&black);
    let mut material = base;
    material.emission = emission.unwrap_or(base.emission);
    if let Some(two_sided) = t.boolean("two_sided")? {
        if !material.is_emissive() {
            return Err(t.fail("two_sided", "only applies to emissive shapes"));
        }
        material.two_sided_emission = two_sided;
    }
    if index == u32::MAX || material != base {
        index = scene.materials.len() as u32;
        scene.materials.push(material);
    }
    let emissive = material.is_emissive();
    let next_light = scene.lights.len() as u32;
    let light = if emissive { next_light } else { NO_LIGHT };
    let two = material.two_sided_emission;
    let radiance = material.emission * if two { 2.0 } else { 1.0 };

    let (tris, key) = match kind {
        "sphere" => {
            let center = t.need("center", t.vec3("center")?)?;
            let radius = t.need("radius", t.positive("radius")?)?;
            if emissive {
                let area = 4.0 * PI * radius * radius;
                let power = PI * area * radiance;
                t.check_light(area, power, "radius")?;
                let index = scene.spheres.len() as u32;
                scene.lights.push(Light {
                    shape: LightShape::Sphere { index },
                    power,
                });
            }
            let material = index;
            scene.spheres.push(Sphere {
                center,
                radius,
                material,
                light,
            });
            return Ok(());
        }
        "quad" => {
            let c = t.points("corners", 4)?;
            (vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]], "corners")
        }
        "triangle" => {
            let v = t.points("vertices", 3)?;
            (vec![[v[0], v[1], v[2]]], "vertices")
        }
        "box" => {
            let min = t.need("min", t.vec3("min")?)?;
            let max = t.need("max", t.vec3("max")?)?;
            if !min.cmplt(max).all() {
                return Err(t.fail("max", "must be greater than `min` on every axis"));
            }
            let angle = t.num("rotate_y")?.unwrap_or(0.0);
            (obj::box_triangles(min, max, angle), "max")
        }
        _ => (mesh(t, base_dir)?, "file"),
    };
    if tris.iter().flatten().any(|p| !p.is_finite()) {
        return Err(t.fail(key, "vertices must be finite"));
    }
    let first = scene.triangles.len() as u32;
    let mut area = 0.0;
    for [a, b, c] in tris.iter().copied() {
        let mut triangle = Triangle::new(a, b, c, index);
        triangle.light = light;
        area += triangle.area();
        scene.triangles.push(triangle);
    }
    if emissive {
        let power = PI * area * radiance;
        t.check_light(area, power, key)?;
        let count = tris.len() as u32;
        scene.lights.push(Light {
            shape: LightShape::Triangles { first, count },
            power,
        });
    }
    Ok(())
}

/// The index of material `name`, which must be defined.
fn material_index(t: &Tab, name: &str, names: &HashMap<&str, u32>) -> Result<u32> {
    if let Some(&index) = names.get(name) {
        return Ok(index);
    }
    let mut known: Vec<String> = names.keys().map(|k| format!("`{k}`")).collect();
    known.sort();
    let known = Some(known.join(", ")).filter(|k| !k.is_empty());
    let known = known.unwrap_or_else(|| "none".into());
    Err(t.fail(
        "material",
        format!("unknown material `{name}` (defined: {known})"),
    ))
}

/// A `mesh` shape's triangles: the OBJ file, scaled, then translated.
fn mesh(t: &Tab, base_dir: &Path) -> Result<Vec<[Vec3; 3]>> {
    let file = t.need("file", t.string("file")?)?;
    let scale = match t.get("scale").map(|v| v.get_ref()) {
        None => Ok(Vec3::ONE),
        Some(v) => match number(v) {
            Some(s) if (s as f32).is_finite() => Ok(Vec3::splat(s as f32)),
            Some(_) => Err("must be finite"),
            None if v.is_array() => vec3_of(v),
            None => Err("must be a number or [x, y, z]"),
        },
    };
    let scale = scale.map_err(|m| t.fail("scale", m))?;
    let translate = t.vec3("translate")?.unwrap_or(Vec3::ZERO);
    let path = base_dir.join(file);
    let tris = obj::load_triangles(&path).map_err(|m| t.fail("file", m))?;
    Ok(obj::transform(tris, scale, translate))
}

fn set<T>(slot: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *slot = v;
    }
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

fn vec3_of(v: &Value) -> std::result::Result<Vec3, &'static str> {
    let xs: Option<Vec<f64>> = v.as_array().and_then(|a| a.iter().map(number).collect());
    match xs.as_deref() {
        Some(&[x, y, z]) => Some(Vec3::new(x as f32, y as f32, z as f32)),
        _ => None,
    }
    .ok_or("must be three numbers [x, y, z]")
    .and_then(|p| p.is_finite().then_some(p).ok_or("must be finite"))
}

/// The text being loaded, for turning byte spans into `file:line` errors.
struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, span: Range<usize>, field: impl Into<String>, msg: impl Into<String>) -> Error {
        let (file, line) = (self.file.to_string(), line_of(self.text, span.start));
        let (field, message) = (field.into(), msg.into());
        Error::Scene {
            file,
            line,
            field,
            message,
        }
    }
}

/// One table of the file (`camera`, `materials.white`, `shapes[2]`, ...) being validated.
struct Tab<'a> {
    cx: &'a Ctx<'a>,
    path: String,
    span: Range<usize>,
    map: &'a RawTable,
}

impl<'a> Tab<'a> {
    fn new(cx: &'a Ctx<'a>, path: String, table: &'a Spanned<RawTable>) -> Self {
        let (span, map) = (table.span(), table.get_ref());
        Tab {
            cx,
            path,
            span,
            map,
        }
    }
    fn get(&self, key: &str) -> Option<&'a Spanned<Value>> {
        self.map.get(key)
    }
    /// An error about `key`, on its line when present, else on the table's.
    fn fail(&self, key: &str, message: impl Into<String>) -> Error {
        let span = self.get(key).map_or(self.span.clone(), |v| v.span());
        self.cx.err(span, format!("{}.{key}", self.path), message)
    }
    fn missing(&self, key: &str) -> Error {
        self.fail(key, format!("missing field `{key}`"))
    }
    fn need<T>(&self, key: &str, value: Option<T>) -> Result<T> {
        value.ok_or_else(|| self.missing(key))
    }
    /// Checks every key is in `allowed`; `elsewhere(key)` says whether a key belongs to
    /// another `type` of this table ("does not apply to type `kind`" instead of "unknown").
    fn only(&self, allowed: &[&str], elsewhere: impl Fn(&str) -> bool, kind: &str) -> Result<()> {
        let bad = self
            .map
            .iter()
            .filter(|(k, _)| !allowed.contains(&k.as_str()));
        let Some((key, _)) = bad.min_by_key(|(_, v)| v.span().start) else {
            return Ok(());
        };
        let keys = allowed.join("`, `");
        Err(self.fail(
            key,
            if elsewhere(key) {
                format!("`{key}` does not apply to type \"{kind}\" (its keys: `{keys}`)")
            } else {
                format!("unknown field `{key}`, expected one of `{keys}`")
            },
        ))
    }
    /// The table's required `type` (one of `types`); checks the keys against it and `common`.
    fn typed(&self, types: &Types, common: &[&str]) -> Result<&'a str> {
        let kind = self.need("type", self.string("type")?)?;
        let Some((_, own)) = types.iter().find(|(name, _)| *name == kind) else {
            let names: Vec<&str> = types.iter().map(|(name, _)| *name).collect();
            let names = names.join("\", \"");
            return Err(self.fail(
                "type",
                format!("unknown type \"{kind}\" (valid: \"{names}\")"),
            ));
        };
        let allowed: Vec<&str> = ["type"].iter().chain(*own).chain(common).copied().collect();
        let elsewhere = |k: &str| types.iter().any(|(_, keys)| keys.contains(&k));
        self.only(&allowed, elsewhere, kind)?;
        Ok(kind)
    }
    /// The value of `key` converted by `read`, or the error `what` when it does not fit.
    fn read<T>(
        &self,
        key: &str,
        read: impl Fn(&'a Value) -> Option<T>,
        what: &str,
    ) -> Result<Option<T>> {
        let read = |v: &'a Spanned<Value>| read(v.get_ref()).ok_or_else(|| self.fail(key, what));
        self.get(key).map(read).transpose()
    }
    fn string(&self, key: &str) -> Result<Option<&'a str>> {
        self.read(key, Value::as_str, "must be a string")
    }
    /// A string that must be one of `names`, turned into a `T` by `parse`.
    fn parse<T>(
        &self,
        key: &str,
        names: &[&str],
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Option<T>> {
        let names = names.join("\", \"");
        let what = format!("must be one of \"{names}\"");
        self.read(key, |v| v.as_str().and_then(&parse), &what)
    }
    fn boolean(&self, key: &str) -> Result<Option<bool>> {
        self.read(key, Value::as_bool, "must be true or false")
    }
    fn num(&self, key: &str) -> Result<Option<f32>> {
        let x = self.read(key, |v| number(v).map(|x| x as f32), "must be a number")?;
        match x {
            Some(x) if !x.is_finite() => Err(self.fail(key, "must be finite")),
            x => Ok(x),
        }
    }
    fn positive(&self, key: &str) -> Result<Option<f32>> {
        match self.num(key)? {
            Some(x) if x <= 0.0 => Err(self.fail(key, "must be positive")),
            x => Ok(x),
        }
    }
    fn int(&self, key: &str, lo: i64, hi: i64) -> Result<Option<u32>> {
        let int = |v: &Value| v.as_integer().filter(|i| (lo..=hi).contains(i));
        let int = |v: &Value| int(v).and_then(|i| u32::try_from(i).ok());
        self.read(key, int, &format!("must be an integer in {lo}..={hi}"))
    }
    fn vec3(&self, key: &str) -> Result<Option<Vec3>> {
        let vec3 = |v: &'a Spanned<Value>| vec3_of(v.get_ref()).map_err(|m| self.fail(key, m));
        self.get(key).map(vec3).transpose()
    }
    /// An RGB triple `>= 0`, and `<= max` when given.
    fn color(&self, key: &str, max: Option<f32>) -> Result<Option<Vec3>> {
        match (self.vec3(key)?, max) {
            (Some(c), _) if c.min_element() < 0.0 => Err(self.fail(key, "components must be >= 0")),
            (Some(c), Some(m)) if c.max_element() > m => {
                Err(self.fail(key, format!("components must be in [0, {m}]")))
            }
            (c, _) => Ok(c),
        }
    }
    /// Exactly `n` points (required).
    fn points(&self, key: &str, n: usize) -> Result<Vec<Vec3>> {
        let v = self.get(key).ok_or_else(|| self.missing(key))?;
        let points = v.get_ref().as_array().filter(|a| a.len() == n);
        let points =
            points.ok_or_else(|| self.fail(key, format!("must be an array of {n} points")))?;
        let point = |p| vec3_of(p).map_err(|m| self.fail(key, format!("every point {m}")));
        points.iter().map(point).collect()
    }
    fn check_light(&self, area: f32, power: Vec3, key: &str) -> Result<()> {
        if area.is_nan() || area <= 0.0 {
            return Err(self.fail(key, "zero-area light"));
        }
        if !power.is_finite() {
            return Err(self.fail(key, "light power is not finite"));
        }
        Ok(())
    }
}

/// 1-based line of byte `offset`.
fn line_of(text: &str, offset: usize) -> usize {
    let before = &text.as_bytes()[..offset.min(text.len())];
    before.iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort field path (`shapes[2].radius`) of the key whose value covers byte `offset`,
/// from the table headers and `key =` lines before it (for the toml crate's own errors).
fn path_at(text: &str, offset: usize) -> String {
    let mut table = String::new();
    let mut key: Option<&str> = None;
    let mut counts: HashMap<String, usize> = HashMap::new();
    for line in text.lines().take(line_of(text, offset)) {
        let line = line.split('#').next().unwrap_or("").trim();
        let header = |open: &str, close: &str| {
            let name = line.strip_prefix(open)?.strip_suffix(close)?;
            is_key(name).then(|| name.trim().to_string())
        };
        if let Some(name) = header("[[", "]]") {
            let n = counts.entry(name.clone()).or_insert(0);
            (table, key) = (format!("{name}[{n}]"), None);
            *n += 1;
        } else if let Some(name) = header("[", "]") {
            (table, key) = (name, None);
        } else if let Some((k, _)) = line.split_once('=').filter(|(k, _)| is_key(k)) {
            key = Some(k.trim());
        }
    }
    match (table.is_empty(), key) {
        (true, None) => "toml".into(),
        (true, Some(k)) => k.into(),
        (false, None) => table,
        (false, Some(k)) => format!("{table}.{k}"),
    }
}

/// Whether `s` looks like a (dotted) bare key rather than a value.
fn is_key(s: &str) -> bool {
    let s = s.trim();
    let valid = |c: char| c.is_ascii_alphanumeric() || "_-.\" ".contains(c);
    s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_' || c == '"')
        && !matches!(s, "true" | "false" | "inf" | "nan")
        && s.chars().all(valid)
}
