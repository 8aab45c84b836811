//! Reading one TOML table of a scene file with the line and field path of every value:
//! [`Tab`] turns each key into a typed value or an [`Error::Scene`] naming `file:line` and
//! the field (`shapes[3].radius`); [`At`] is a table as the builder's [`Locate`].

use crate::error::{Error, Result};
use crate::scene::locate::{Locate, Part};
use crate::settings::{RenderSettings, Setting, Slot};
use glam::Vec3;
use std::collections::{BTreeMap, HashMap};
use std::ops::Range;
use toml::{Spanned, Value};

/// One TOML table: key -> value with its byte span.
pub(crate) type RawTable = BTreeMap<String, Spanned<Value>>;

/// A table kind's types, each with the keys (besides `type`) it accepts.
pub(crate) type Types = [(&'static str, &'static [&'static str])];

pub(crate) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

pub(crate) fn vec3_of(v: &Value) -> std::result::Result<Vec3, &'static str> {
    let xs: Option<Vec<f64>> = v.as_array().and_then(|a| a.iter().map(number).collect());
    match xs.as_deref() {
        Some(&[x, y, z]) => Some(Vec3::new(x as f32, y as f32, z as f32)),
        _ => None,
    }
    .ok_or("must be three numbers [x, y, z]")
    .and_then(|p| p.is_finite().then_some(p).ok_or("must be finite"))
}

/// The text being loaded, for turning byte spans into `file:line` errors.
pub(crate) struct Ctx<'a> {
    pub(crate) text: &'a str,
    pub(crate) file: &'a str,
}

impl Ctx<'_> {
    pub(crate) fn err(
        &self,
        span: Range<usize>,
        field: impl Into<String>,
        msg: impl Into<String>,
    ) -> Error {
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
pub(crate) struct Tab<'a> {
    cx: &'a Ctx<'a>,
    path: String,
    span: Range<usize>,
    map: &'a RawTable,
}

impl<'a> Tab<'a> {
    pub(crate) fn new(cx: &'a Ctx<'a>, path: String, table: &'a Spanned<RawTable>) -> Self {
        let (span, map) = (table.span(), table.get_ref());
        Tab {
            cx,
            path,
            span,
            map,
        }
    }
    pub(crate) fn get(&self, key: &str) -> Option<&'a Spanned<Value>> {
        self.map.get(key)
    }
    /// An error about `key`, on its line when present, else on the table's.
    pub(crate) fn fail(&self, key: &str, message: impl Into<String>) -> Error {
        let span = self.get(key).map_or(self.span.clone(), |v| v.span());
        self.cx.err(span, format!("{}.{key}", self.path), message)
    }
    pub(crate) fn missing(&self, key: &str) -> Error {
        self.fail(key, format!("missing field `{key}`"))
    }
    pub(crate) fn need<T>(&self, key: &str, value: Option<T>) -> Result<T> {
        value.ok_or_else(|| self.missing(key))
    }
    /// Checks every key is in `allowed`; `elsewhere(key)` says whether a key belongs to
    /// another `type` of this table ("does not apply to type `kind`" instead of "unknown").
    pub(crate) fn only(
        &self,
        allowed: &[&str],
        elsewhere: impl Fn(&str) -> bool,
        kind: &str,
    ) -> Result<()> {
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
    pub(crate) fn typed(&self, types: &Types, common: &[&str]) -> Result<&'a str> {
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
    pub(crate) fn string(&self, key: &str) -> Result<Option<&'a str>> {
        self.read(key, Value::as_str, "must be a string")
    }
    /// A string that must be one of `names`, turned into a `T` by `parse`.
    pub(crate) fn parse<T>(
        &self,
        key: &str,
        names: &[&str],
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Option<T>> {
        let names = names.join("\", \"");
        let what = format!("must be one of \"{names}\"");
        self.read(key, |v| v.as_str().and_then(&parse), &what)
    }
    pub(crate) fn boolean(&self, key: &str) -> Result<Option<bool>> {
        self.read(key, Value::as_bool, "must be true or false")
    }
    pub(crate) fn num(&self, key: &str) -> Result<Option<f32>> {
        let x = self.read(key, |v| number(v).map(|x| x as f32), "must be a number")?;
        match x {
            Some(x) if !x.is_finite() => Err(self.fail(key, "must be finite")),
            x => Ok(x),
        }
    }
    pub(crate) fn positive(&self, key: &str) -> Result<Option<f32>> {
        match self.num(key)? {
            Some(x) if x <= 0.0 => Err(self.fail(key, "must be positive")),
            x => Ok(x),
        }
    }
    /// Reads `row`'s key, when present, into `settings`: a value outside the row's range is
    /// an error with the range text that [`crate::settings::validate`] shows.
    pub(crate) fn setting(&self, row: &Setting, settings: &mut RenderSettings) -> Result<()> {
        let (key, range) = (row.name, row.range);
        let what = format!("must be {}", range.requirement());
        match row.slot {
            Slot::U32 { set, .. } => {
                let int = |v: &Value| v.as_integer().filter(|&i| range.admits_int(i));
                let int = |v: &Value| int(v).and_then(|i| u32::try_from(i).ok());
                if let Some(v) = self.read(key, int, &what)? {
                    set(settings, v);
                }
            }
            Slot::F32 { set, .. } => match self.num(key)? {
                Some(v) if !range.admits(v) => return Err(self.fail(key, what)),
                Some(v) => set(settings, v),
                None => {}
            },
        }
        Ok(())
    }
    pub(crate) fn vec3(&self, key: &str) -> Result<Option<Vec3>> {
        let vec3 = |v: &'a Spanned<Value>| vec3_of(v.get_ref()).map_err(|m| self.fail(key, m));
        self.get(key).map(vec3).transpose()
    }
    /// An RGB triple `>= 0`, and `<= max` when given.
    pub(crate) fn color(&self, key: &str, max: Option<f32>) -> Result<Option<Vec3>> {
        match (self.vec3(key)?, max) {
            (Some(c), _) if c.min_element() < 0.0 => Err(self.fail(key, "components must be >= 0")),
            (Some(c), Some(m)) if c.max_element() > m => {
                Err(self.fail(key, format!("components must be in [0, {m}]")))
            }
            (c, _) => Ok(c),
        }
    }
    /// Exactly `n` points (required).
    pub(crate) fn points(&self, key: &str, n: usize) -> Result<Vec<Vec3>> {
        let v = self.get(key).ok_or_else(|| self.missing(key))?;
        let points = v.get_ref().as_array().filter(|a| a.len() == n);
        let points =
            points.ok_or_else(|| self.fail(key, format!("must be an array of {n} points")))?;
        let point = |p| vec3_of(p).map_err(|m| self.fail(key, format!("every point {m}")));
        points.iter().map(point).collect()
    }
}

/// A table as the builder's [`Locate`]: each [`Part`] is reported at its key; `geometry` and
/// `emission` name the keys of those parts for the table's type.
pub(crate) struct At<'t, 'a> {
    pub(crate) tab: &'t Tab<'a>,
    pub(crate) geometry: &'static str,
    pub(crate) emission: &'static str,
}

impl Locate for At<'_, '_> {
    fn error(&self, part: Part, message: String) -> Error {
        let key = match part {
            Part::Material => "material",
            Part::Emission => self.emission,
            Part::TwoSided => "two_sided",
            Part::Geometry => self.geometry,
            Part::Eye => "eye",
            Part::Up => "up",
            Part::Fov => "fov",
            Part::Parameter(name) => name,
            Part::Camera => {
                let (span, path) = (self.tab.span.clone(), self.tab.path.clone());
                return self.tab.cx.err(span, path, message);
            }
        };
        self.tab.fail(key, message)
    }
}

/// 1-based line of byte `offset`.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    let before = &text.as_bytes()[..offset.min(text.len())];
    before.iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort field path (`shapes[2].radius`) of the key whose value covers byte `offset`,
/// from the table headers and `key =` lines before it (for the toml crate's own errors).
pub(crate) fn path_at(text: &str, offset: usize) -> String {
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
