//! Scene files: a TOML description (format in `scenes/README.md`) read into a
//! [`SceneBuilder`], which applies the rules of building a [`Scene`].
//!
//! Every table is read as a map from key to spanned value (`toml_table.rs`), so that each
//! error names the line and the field path (`shapes[3].radius`, `materials.white.albedo`, ...)
//! it is about. Unknown keys, and keys that do not apply to a table's `type`, are errors. The
//! numeric settings of `[camera]` and `[render]` and their ranges come from
//! [`crate::settings::SETTINGS`].

pub mod media;
mod projection;
pub mod table;

use crate::camera::pixel_filter::{PixelFilter, FILTER_NAMES};
use crate::error::Result;
use crate::importers::file;
use crate::importers::mesh_file;
use crate::importers::toml::media as toml_media;
use crate::importers::toml::table::{number, vec3_of, At, Ctx, RawTable, Tab, Types};
use crate::lights::spot::SpotFalloff;
use crate::lights::spot::SpotLight;
use crate::scene::builder::{SceneBuilder, Surface};
use crate::scene::locate::Locate;
use crate::scene::locate::Part;
use crate::scene::{Material, Scene};
use crate::settings::{Filter, FresnelMode, Mode, RenderSettings, Sampler, SETTINGS};
use glam::Vec3;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;

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
    environment: Option<Spanned<RawTable>>,
    #[serde(default)]
    media: BTreeMap<String, Spanned<RawTable>>,
}

/// `[camera]` keys besides the settings whose table is `camera` (width, height).
const CAMERA_KEYS: &[&str] = &[
    "eye",
    "target",
    "up",
    "fov",
    "filter",
    "filter_radius",
    "filter_stddev",
    "aperture_radius",
    "focus_distance",
    "medium",
];
/// `[render]` keys besides the settings whose table is `render`.
const RENDER_NAMES: &[&str] = &["mode", "filter", "fresnel", "sampler"];
const MATERIAL_TYPES: &Types = &[
    ("diffuse", &["albedo"]),
    ("glossy", &["kd", "ks", "exponent"]),
    ("mirror", &["reflectance"]),
    ("glass", &["ior"]),
    ("null", &[]),
    ("emissive", &["radiance", "two_sided"]),
];
const SHAPE_TYPES: &Types = &[
    ("quad", &["corners"]),
    ("triangle", &["vertices"]),
    ("sphere", &["center", "radius"]),
    ("box", &["min", "max", "rotate_y"]),
    ("mesh", &["file", "scale", "translate", "smooth"]),
];
const SHAPE_KEYS: &[&str] = &["material", "emission", "two_sided", "interior", "exterior"];
const LIGHT_TYPES: &Types = &[
    ("point", &["position", "intensity"]),
    (
        "spot",
        &[
            "position",
            "direction",
            "target",
            "intensity",
            "inner_angle",
            "outer_angle",
            "falloff",
            "filename",
            "up",
        ],
    ),
    ("directional", &["direction", "irradiance"]),
    (
        "projector",
        &[
            "position",
            "direction",
            "target",
            "up",
            "fov",
            "irradiance",
            "scale",
            "filename",
        ],
    ),
];

/// Reads and loads the scene file at `path`; meshes are resolved relative to its directory.
///
/// An unreadable file is [`Error::Io`]; everything wrong inside it is [`Error::Scene`].
pub fn load(path: &Path) -> Result<Scene> {
    let text = file::read_text(path)?;
    load_str(&text, &path.display().to_string(), file::base_dir(path))
}

/// Loads a scene from TOML `text`. `file` names it in errors; mesh paths are relative to
/// `base_dir`. Every problem is an [`Error::Scene`](crate::error::Error::Scene) naming the line and field it is about.
pub fn load_str(text: &str, file: &str, base_dir: &Path) -> Result<Scene> {
    let cx = Ctx { text, file };
    let raw: RawScene = toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        // A syntax error is about the file; a wrong top-level key is about that key.
        let field = match toml::from_str::<toml::Table>(text) {
            Err(e) if !e.message().contains("duplicate") => "toml".into(),
            _ => crate::importers::toml::table::path_at(text, span.start),
        };
        cx.err(span, field, e.message().trim())
    })?;

    let mut b = SceneBuilder::new();
    // Media first: the camera and shapes name them.
    let mut media: Vec<_> = raw.media.iter().collect();
    media.sort_by_key(|(_, m)| m.span().start);
    for (name, m) in media {
        let t = Tab::new(&cx, format!("media.{name}"), m);
        toml_media::medium(&t, name, base_dir, &mut b)?;
    }
    let no_camera = |_: Part, _: String| cx.err(0..0, "camera", "missing table [camera]");
    let Some(camera_table) = &raw.camera else {
        return Err(no_camera(Part::Camera, String::new()));
    };
    camera(&Tab::new(&cx, "camera".into(), camera_table), &mut b)?;
    if let Some(r) = &raw.render {
        render(&Tab::new(&cx, "render".into(), r), b.settings())?;
    }
    // Materials, in file order.
    let mut named: Vec<_> = raw.materials.iter().collect();
    named.sort_by_key(|(_, m)| m.span().start);
    for (name, m) in named {
        let t = Tab::new(&cx, format!("materials.{name}"), m);
        let at = At {
            tab: &t,
            geometry: "type",
            emission: "radiance",
        };
        b.add_material(Some(name), material(&t)?, &at)?;
    }
    for (i, s) in raw.shapes.iter().enumerate() {
        shape(&Tab::new(&cx, format!("shapes[{i}]"), s), base_dir, &mut b)?;
    }
    for (i, l) in raw.lights.iter().enumerate() {
        light(&Tab::new(&cx, format!("lights[{i}]"), l), base_dir, &mut b)?;
    }
    if let Some(e) = &raw.environment {
        environment(&Tab::new(&cx, "environment".into(), e), base_dir, &mut b)?;
    }
    let mut scene = b.finish(&no_camera)?;
    let given = |key| {
        raw.render
            .as_ref()
            .is_some_and(|r| r.get_ref().contains_key(key))
    };
    scene.scale_default_radii([
        given("radius"),
        given("caustic_radius"),
        given("volume_radius"),
    ]);
    Ok(scene)
}

/// `[environment]`: `radiance = [r, g, b]` (constant), or `filename` (a lat-long image,
/// relative to the scene's directory) with an optional `scale` and `rotate_y` (degrees).
fn environment(t: &Tab, base_dir: &Path, b: &mut SceneBuilder) -> Result<()> {
    t.only(
        &["radiance", "filename", "scale", "rotate_y"],
        |_| false,
        "",
    )?;
    let radiance = t.color("radiance", None)?;
    let file = t.string("filename")?;
    let (radiance, image, name) = match (radiance, file) {
        (Some(_), Some(_)) => {
            return Err(t.fail("filename", "give `radiance` or `filename`, not both"))
        }
        (None, None) => return Err(t.fail("radiance", "missing field `radiance` (or `filename`)")),
        (Some(r), None) => {
            if t.get("scale").is_some() {
                return Err(t.fail("scale", "only with `filename`"));
            }
            (r, None, "radiance")
        }
        (None, Some(file)) => {
            let image = crate::textures::Texture::load(
                &base_dir.join(file),
                crate::textures::Encoding::Srgb,
            )
            .map_err(|e| t.fail("filename", e.to_string()))?;
            let scale = t.num("scale")?.unwrap_or(1.0);
            (Vec3::splat(scale), Some(image), "scale")
        }
    };
    let angle = t.num("rotate_y")?.unwrap_or(0.0);
    let at = |part: Part, message: String| match part {
        Part::Geometry => t.fail("rotate_y", message),
        _ => t.fail(name, message),
    };
    let to_world = glam::Mat3::from_rotation_y(angle.to_radians());
    b.set_environment(radiance, image, to_world, &at)
}

/// A `[[lights]]` table: a point, spot, directional light or projector.
fn light(t: &Tab, base_dir: &Path, b: &mut SceneBuilder) -> Result<()> {
    let kind = t.typed(LIGHT_TYPES, &[])?;
    if kind == "projector" {
        return projection::projector(t, base_dir, b);
    }
    let emission = if kind == "directional" {
        "irradiance"
    } else {
        "intensity"
    };
    let at = At {
        tab: t,
        geometry: "position",
        emission,
    };
    let color = t.need(emission, t.color(emission, None)?)?;
    if kind == "directional" {
        let direction = t.need("direction", t.vec3("direction")?)?;
        return b.add_directional_light(direction, color, &at);
    }
    let position = t.need("position", t.vec3("position")?)?;
    if kind == "point" {
        return b.add_point_light(position, color, &at);
    }
    // A spot aims along `direction`, or at `target` (exactly one of them).
    let (direction, target) = projection::aim(t, position)?;
    let spot = SpotLight {
        position,
        direction,
        intensity: color,
        inner: t.num("inner_angle")?.unwrap_or(0.0),
        outer: t.need("outer_angle", t.num("outer_angle")?)?,
        falloff: t
            .parse("falloff", &SpotFalloff::NAMES, SpotFalloff::from_name)?
            .unwrap_or_default(),
    };
    // With `target`, a zero direction is the target's fault.
    let aimed = |part: Part, message: String| match part {
        Part::Parameter("direction") if target.is_some() => {
            t.fail("target", format!("{message} (`target` equals `position`)"))
        }
        part => at.error(part, message),
    };
    if t.get("filename").is_some() {
        return projection::textured_spot(t, base_dir, spot, b, &aimed);
    }
    if t.get("up").is_some() {
        return Err(t.fail("up", "only with `filename` (the projected image's frame)"));
    }
    b.add_spot_light(spot, &aimed)
}

/// The settings of [`SETTINGS`] that table `table` may set.
fn settings_of(table: &'static str) -> impl Iterator<Item = &'static crate::settings::Setting> {
    SETTINGS.iter().filter(move |row| row.table == Some(table))
}

fn camera(t: &Tab, b: &mut SceneBuilder) -> Result<()> {
    let keys = CAMERA_KEYS.iter().copied();
    let keys: Vec<&str> = keys.chain(settings_of("camera").map(|r| r.name)).collect();
    t.only(&keys, |_| false, "")?;
    let eye = t.need("eye", t.vec3("eye")?)?;
    let target = t.need("target", t.vec3("target")?)?;
    let up = t.vec3("up")?.unwrap_or(Vec3::Y);
    let fov = t.need("fov", t.num("fov")?)?;
    for row in settings_of("camera") {
        t.setting(row, b.settings())?;
    }
    let at = At {
        tab: t,
        geometry: "eye",
        emission: "eye",
    };
    b.camera(eye, target, up, fov, &at)?;
    let filter = pixel_filter(t)?;
    let aperture = t.num("aperture_radius")?.unwrap_or(0.0);
    if aperture < 0.0 {
        return Err(t.fail("aperture_radius", "must be 0 (a pinhole) or positive"));
    }
    let focus = t
        .positive("focus_distance")?
        .unwrap_or((target - eye).length());
    b.optics(filter, aperture, focus);
    toml_media::camera_medium(t, b)
}

/// `filter` (`"box"`, `"tent"` with `filter_radius`, `"gaussian"` with `filter_stddev`;
/// Mitsuba's defaults 1 and 0.5).
fn pixel_filter(t: &Tab) -> Result<PixelFilter> {
    let known = |f: &str| FILTER_NAMES.iter().copied().find(|n| *n == f);
    let kind = t.parse("filter", &FILTER_NAMES, known)?;
    for (key, owner) in [("filter_radius", "tent"), ("filter_stddev", "gaussian")] {
        if t.get(key).is_some() && kind != Some(owner) {
            return Err(t.fail(key, format!("only with filter = \"{owner}\"")));
        }
    }
    Ok(match kind.unwrap_or("box") {
        "tent" => PixelFilter::Tent {
            radius: t.positive("filter_radius")?.unwrap_or(1.0),
        },
        "gaussian" => PixelFilter::Gaussian {
            stddev: t.positive("filter_stddev")?.unwrap_or(0.5),
        },
        _ => PixelFilter::Box,
    })
}

fn render(t: &Tab, s: &mut RenderSettings) -> Result<()> {
    let keys = settings_of("render").map(|r| r.name);
    let keys: Vec<&str> = keys.chain(RENDER_NAMES.iter().copied()).collect();
    t.only(&keys, |_| false, "")?;
    for row in settings_of("render") {
        t.setting(row, s)?;
    }
    let fresnel = |f: &str| match f {
        "exact" => Some(FresnelMode::Exact),
        "schlick" => Some(FresnelMode::Schlick),
        _ => None,
    };
    if let Some(mode) = t.parse("mode", &Mode::NAMES, Mode::parse)? {
        s.mode = mode;
    }
    if let Some(filter) = t.parse("filter", &Filter::NAMES, Filter::parse)? {
        s.filter = filter;
    }
    if let Some(f) = t.parse("fresnel", &["exact", "schlick"], fresnel)? {
        s.fresnel = f;
    }
    if let Some(f) = t.parse("sampler", &Sampler::NAMES, Sampler::parse)? {
        s.sampler = f;
    }
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
        "null" => Material::null(),
        _ => Material {
            two_sided_emission: t.boolean("two_sided")?.unwrap_or(false),
            ..Material::emitter(t.need("radiance", t.color("radiance", None)?)?)
        },
    })
}

fn shape(t: &Tab, base_dir: &Path, b: &mut SceneBuilder) -> Result<()> {
    let kind = t.typed(SHAPE_TYPES, SHAPE_KEYS)?;
    let at = |geometry| At {
        tab: t,
        geometry,
        emission: "emission",
    };
    // The material, with the shape's own emission if it has one.
    let emission = t.color("emission", None)?;
    let material = match t.string("material")? {
        Some(name) => Some(b.material_named(name, &at("material"))?),
        None if emission.is_some() => None,
        None => return Err(t.missing("material")),
    };
    let two_sided = t.boolean("two_sided")?;
    let surface = Surface {
        material,
        emission,
        two_sided,
        emission_texture: None,
        media: toml_media::shape_media(t, b)?,
    };
    match kind {
        "sphere" => {
            let center = t.need("center", t.vec3("center")?)?;
            let radius = t.need("radius", t.positive("radius")?)?;
            b.add_sphere(center, radius, surface, &at("radius"))
        }
        "quad" => {
            let c = t.points("corners", 4)?;
            b.add_quad([c[0], c[1], c[2], c[3]], surface, &at("corners"))
        }
        "triangle" => {
            let v = t.points("vertices", 3)?;
            b.add_triangle([v[0], v[1], v[2]], surface, &at("vertices"))
        }
        "box" => {
            let min = t.need("min", t.vec3("min")?)?;
            let max = t.need("max", t.vec3("max")?)?;
            let angle = t.num("rotate_y")?.unwrap_or(0.0);
            b.add_box(min, max, angle, surface, &at("max"))
        }
        _ => {
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
            let smooth = t.boolean("smooth")?;
            let path = base_dir.join(file);
            let at = at(if smooth == Some(true) {
                "smooth"
            } else {
                "file"
            });
            mesh_file::add_mesh_file(b, &path, scale, translate, smooth, surface, &at)
        }
    }
}
