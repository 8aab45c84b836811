//! Mitsuba's top-level emitters: `point`, `spot`, `projector` and `directional` (an `area`
//! emitter lives inside its shape, `shape.rs`). Intensity is W/sr and irradiance W/m^2 per
//! linear RGB channel, as in Mitsuba. A `spot` (cone along its `to_world`'s +Z) keeps its
//! angles and Mitsuba's falloff: `beam_width` is the inner and `cutoff_angle` the outer
//! half-angle of a ramp linear in the angle (`SpotFalloff::LinearAngle`); its `texture` is
//! projected over the cone (`crate::lights::spot`). A `projector` (`crate::lights::projector`)
//! takes `irradiance` (a colour or a texture), `scale`, and the perspective sensor's `fov`,
//! `fov_axis` or `focal_length` over its image's aspect (one for a colour). `constant`
//! (`radiance`, default 1) and `envmap` (`filename` of a lat-long image, `scale`, `to_world`'s
//! rotation) are the environment (`crate::scene::Environment`).

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::sensor::{fov_and_axis, tan_half_y};
use crate::importers::mitsuba::texture;
use crate::importers::mitsuba::Importer;
use crate::lights::projector::ProjectorLight;
use crate::lights::spot::SpotFalloff;
use crate::lights::spot::SpotLight;
use crate::scene::locate::{Locate, Part};
use crate::textures::{Encoding, SceneTexture, Texture};
use glam::{Mat3, Mat4, Vec3};
use roxmltree::Node;

/// Mitsuba's default `cutoff_angle` of a spot, degrees.
const DEFAULT_CUTOFF: f32 = 20.0;

impl Importer<'_> {
    /// `<emitter type="point|spot|directional">` at the top level.
    pub(crate) fn emitter(&mut self, node: Node, field: &str) -> Result<()> {
        let cx = &self.cx;
        let p = Plugin::new(cx, node, field.to_string())?;
        let kind = p.kind.as_str();
        if matches!(kind, "constant" | "envmap") {
            return self.environment(node, field, p);
        }
        if kind == "projector" {
            return self.projector(node, field, p);
        }
        if !matches!(kind, "point" | "spot" | "directional") {
            let message = match kind {
                "area" => "an `area` emitter must be inside a <shape>".to_string(),
                other => format!("unsupported emitter `{other}`"),
            };
            return Err(cx.err(node, field, message));
        }
        if let Some(extra) = p.objects.first() {
            let tag = extra.tag_name().name();
            let message = format!("unsupported <{tag}> in a {kind} emitter");
            return Err(cx.err(*extra, field, message));
        }
        let emission = if kind == "directional" {
            "irradiance"
        } else {
            "intensity"
        };
        let Some(color) = p.emission(cx, emission)? else {
            return Err(cx.err(node, &p.at(emission), "missing"));
        };
        // Builder errors point at the parameter they are about.
        let origin = self.origin(node, field);
        let given = |name: &str| p.node_of(name) != node;
        let at = |part: Part, message: String| {
            let name = match part {
                Part::Emission => emission,
                Part::Parameter("outer_angle") => "cutoff_angle",
                Part::Parameter("inner_angle") => "beam_width",
                Part::Parameter("direction") if given("direction") => "direction",
                Part::Parameter("direction") | Part::Geometry => "to_world",
                _ => return origin.error(part, message),
            };
            cx.err(p.node_of(name), &p.at(name), message)
        };
        let to_world = p.transform(cx, "to_world")?;
        match kind {
            "point" => {
                let position = match (p.point(cx, "position")?, to_world) {
                    (Some(_), Some(_)) => {
                        let message = "give `position` or `to_world`, not both";
                        return Err(cx.err(node, field, message));
                    }
                    (Some(position), None) => position,
                    (None, m) => m.unwrap_or(Mat4::IDENTITY).transform_point3(Vec3::ZERO),
                };
                p.done(cx)?;
                self.b.add_point_light(position, color, &at)
            }
            "spot" => {
                let m = to_world.unwrap_or(Mat4::IDENTITY);
                let outer = p.float(cx, "cutoff_angle")?.unwrap_or(DEFAULT_CUTOFF);
                let beam = p.float(cx, "beam_width")?.unwrap_or(outer * 0.75);
                let texture = match p.texture_param("texture") {
                    Some(t) => Some(texture::texture(cx, t, &p.at("texture"))?),
                    None => None,
                };
                p.done(cx)?;
                let spot = SpotLight {
                    position: m.transform_point3(Vec3::ZERO),
                    direction: m.transform_vector3(Vec3::Z),
                    intensity: color,
                    inner: beam,
                    outer,
                    falloff: SpotFalloff::LinearAngle,
                };
                let Some(texture) = texture else {
                    return self.b.add_spot_light(spot, &at);
                };
                let t = self.b.add_texture(texture, &at)?;
                let axes = (m.transform_vector3(Vec3::X), m.transform_vector3(Vec3::Y));
                self.b.add_projecting_spot_light(spot, t, axes, &at)
            }
            _ => {
                let direction = match (p.point(cx, "direction")?, to_world) {
                    (Some(_), Some(_)) => {
                        let message = "give `direction` or `to_world`, not both";
                        return Err(cx.err(node, field, message));
                    }
                    (Some(d), None) => d,
                    (None, m) => m.unwrap_or(Mat4::IDENTITY).transform_vector3(Vec3::Z),
                };
                p.done(cx)?;
                self.b.add_directional_light(direction, color, &at)
            }
        }
    }
}

impl Importer<'_> {
    /// `<emitter type="projector">`.
    fn projector(&mut self, node: Node, field: &str, p: Plugin) -> Result<()> {
        let cx = &self.cx;
        if let Some(extra) = p.objects.first() {
            let tag = extra.tag_name().name();
            let message = format!("unsupported <{tag}> in a projector emitter");
            return Err(cx.err(*extra, field, message));
        }
        let scale = p.float(cx, "scale")?.unwrap_or(1.0);
        let (irradiance, image) = match p.texture_param("irradiance") {
            Some(t) => (
                Vec3::ONE,
                Some(texture::texture(cx, t, &p.at("irradiance"))?),
            ),
            None => (p.emission(cx, "irradiance")?.unwrap_or(Vec3::ONE), None),
        };
        // Mitsuba's constant textures have a resolution of 1 x 1.
        let (w, h) = match &image {
            Some(SceneTexture::Bitmap(b)) => (b.width as f32, b.height as f32),
            _ => (1.0, 1.0),
        };
        let (fov, axis) = fov_and_axis(cx, &p, node)?;
        let tan_x = tan_half_y(cx, &p, node, (fov, &axis), (w, h))? * w / h;
        let to_world = p.transform(cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        p.done(cx)?;
        let at = |part: Part, message: String| {
            let name = match part {
                Part::Geometry => "to_world",
                Part::Parameter("fov") => "fov",
                Part::Emission if !(scale >= 0.0 && scale.is_finite()) => "scale",
                _ => "irradiance",
            };
            cx.err(p.node_of(name), &p.at(name), message)
        };
        let texture = match image {
            Some(t) => Some(self.b.add_texture(t, &at)?),
            None => None,
        };
        let light = ProjectorLight {
            to_world,
            fov_x: 2.0 * tan_x.atan().to_degrees(),
            aspect: w / h,
            irradiance: irradiance * scale,
            texture,
        };
        self.b.add_projector_light(light, &at)
    }

    /// `<emitter type="constant|envmap">`: the environment.
    fn environment(&mut self, node: Node, field: &str, p: Plugin) -> Result<()> {
        let cx = &self.cx;
        if let Some(extra) = p.objects.first() {
            let tag = extra.tag_name().name();
            let message = format!("unsupported <{tag}> in a {} emitter", p.kind);
            return Err(cx.err(*extra, field, message));
        }
        let (radiance, image, name) = if p.kind == "constant" {
            let radiance = p.emission(cx, "radiance")?.unwrap_or(Vec3::ONE);
            (radiance, None, "radiance")
        } else {
            let Some(file) = p.string(cx, "filename")? else {
                return Err(cx.err(node, &p.at("filename"), "missing"));
            };
            let image = Texture::load(&cx.resolve(&file), Encoding::Srgb)
                .map_err(|e| cx.err(p.node_of("filename"), &p.at("filename"), e.to_string()))?;
            let scale = p.float(cx, "scale")?.unwrap_or(1.0);
            (Vec3::splat(scale), Some(image), "scale")
        };
        let to_world = p.transform(cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        p.done(cx)?;
        let at = |part: Part, message: String| {
            let name = if part == Part::Geometry {
                "to_world"
            } else {
                name
            };
            cx.err(p.node_of(name), &p.at(name), message)
        };
        let to_world = Mat3::from_mat4(to_world);
        self.b.set_environment(radiance, image, to_world, &at)
    }
}
