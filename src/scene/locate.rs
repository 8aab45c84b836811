//! Where a scene error points: an importer passes a [`Locate`] with everything it adds to the
//! [`crate::scene::SceneBuilder`], which reports a problem about one [`Part`] of it; the locator
//! turns that into an [`Error::Scene`] naming the file, line and field in the importer's own
//! terms. [`Origin`] is the simplest locator, one fixed place.

use crate::error::{Error, Result};
use glam::Vec3;

/// Which part of an added item an error is about; the importer's [`Locate`] maps it to the
/// line and field of its own format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The shape's material (a reference by name, or a missing one).
    Material,
    /// The shape's own emission, or a point light's intensity.
    Emission,
    /// The shape's two-sided emission flag.
    TwoSided,
    /// The shape's geometry (radius, corners, vertices, box bounds, mesh file), or a point
    /// light's position.
    Geometry,
    /// The camera's position.
    Eye,
    /// The camera's up direction.
    Up,
    /// The camera's field of view.
    Fov,
    /// The camera as a whole (a scene without one).
    Camera,
    /// A material parameter, by its name in the TOML scene format: `albedo` (a diffuse
    /// material's kd), `kd`, `ks`, `exponent`, `reflectance` (a mirror's ks), `ior`,
    /// `radiance` (an emitter's emission).
    Parameter(&'static str),
}

/// Turns a message about a [`Part`] of an added item into an [`Error::Scene`] naming the
/// file, line and field it is about. Closures `Fn(Part, String) -> Error` are locators.
pub trait Locate {
    /// The error `message` about `part`.
    fn error(&self, part: Part, message: String) -> Error;
}

impl<F: Fn(Part, String) -> Error> Locate for F {
    fn error(&self, part: Part, message: String) -> Error {
        self(part, message)
    }
}

/// A fixed place in a file: every part of the item is reported there (for formats whose
/// items have one line, or none: `line` 0 then).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Origin {
    /// The file, as errors show it.
    pub file: String,
    /// 1-based line of the item.
    pub line: usize,
    /// The item's field path in the format's own terms (`shapes[3]`, `meshes[0].primitives[1]`).
    pub field: String,
}

impl Locate for Origin {
    fn error(&self, _part: Part, message: String) -> Error {
        Error::Scene {
            file: self.file.clone(),
            line: self.line,
            field: self.field.clone(),
            message,
        }
    }
}

/// The message for a reference to `name` that no `kind` of the scene has:
/// `` unknown KIND `NAME` (defined: `a`, `b`) ``, the names sorted, or `none`.
pub(crate) fn unknown_name<'a>(
    kind: &str,
    name: &str,
    defined: impl Iterator<Item = &'a String>,
) -> String {
    let mut known: Vec<String> = defined.map(|k| format!("`{k}`")).collect();
    known.sort();
    let known = match known.is_empty() {
        true => "none".to_string(),
        false => known.join(", "),
    };
    format!("unknown {kind} `{name}` (defined: {known})")
}

/// A colour: finite, >= 0 and, when given, <= `max` in every channel.
pub fn check_color(c: Vec3, max: Option<f32>, part: Part, at: &dyn Locate) -> Result<()> {
    if !c.is_finite() {
        return Err(at.error(part, "must be finite".into()));
    }
    if c.min_element() < 0.0 {
        return Err(at.error(part, "components must be >= 0".into()));
    }
    match max {
        Some(m) if c.max_element() > m => {
            Err(at.error(part, format!("components must be in [0, {m}]")))
        }
        _ => Ok(()),
    }
}
