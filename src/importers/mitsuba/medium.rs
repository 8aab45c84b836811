//! Mitsuba's participating media (issue 24): `homogeneous` (`sigma_t`, `albedo`, `scale`,
//! a nested `<phase>` of type `isotropic` or `hg` with `g`), nested in a shape as its
//! `interior` / `exterior` or in the sensor, or declared at the top level with an `id` and
//! referenced (`<ref name="interior" id="..."/>`). Mitsuba's defaults: `sigma_t` 1,
//! `albedo` 0.75, `scale` 1, isotropic. `sample_emitters` and `has_spectral_extinction`
//! change how Mitsuba samples, not what it renders: ignored. `heterogeneous` (issue 41) takes
//! `sigma_t` and `albedo` as colours or nested `<volume>`s (`volume.rs`); a colour is a
//! constant volume over the unit cube, as in Mitsuba, where the medium's extinction ends.

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::Importer;
use crate::media::builder::{MediumId, MediumParams};
use crate::media::grid::{Volume, VolumeKind};
use crate::scene::locate::Part;
use glam::Affine3A;
use glam::Vec3;
use roxmltree::Node;

impl Importer<'_> {
    /// The medium of `<medium>` `node` (nested, or the target of a `<ref>` with `id`),
    /// added the first time a top-level one is asked for.
    pub(crate) fn medium(&mut self, node: Node, field: &str, id: Option<&str>) -> Result<MediumId> {
        if let Some(&m) = id.and_then(|id| self.media.get(id)) {
            return Ok(m);
        }
        let cx = &self.cx;
        let p = Plugin::new(cx, node, field.to_string())?;
        let heterogeneous = match p.kind.as_str() {
            "homogeneous" => false,
            "heterogeneous" => true,
            other => {
                let message =
                    format!("unsupported medium `{other}` (`homogeneous`, `heterogeneous`)");
                return Err(cx.err(node, field, message));
            }
        };
        let mut g = 0.0;
        let mut volumes = Vec::new();
        for child in &p.objects {
            let tag = child.tag_name().name();
            let sub = format!("{field}.{tag}");
            if tag == "volume" && heterogeneous {
                let name = cx.need_attr(*child, &sub, "name")?;
                if name != "sigma_t" && name != "albedo" {
                    let message = format!("unsupported volume `{name}` (`sigma_t`, `albedo`)");
                    return Err(cx.err(*child, &sub, message));
                }
                if volumes.iter().any(|(n, _)| *n == name) || p.node_of(&name) != node {
                    let message = format!("parameter `{name}` given twice");
                    return Err(cx.err(*child, &format!("{field}.{name}"), message));
                }
                volumes.push((name, *child));
                continue;
            }
            if tag != "phase" {
                let message = format!("unsupported <{tag}> in a medium");
                return Err(cx.err(*child, field, message));
            }
            let phase = Plugin::new(cx, *child, sub.clone())?;
            g = match phase.kind.as_str() {
                "isotropic" => 0.0,
                "hg" => phase.float(cx, "g")?.unwrap_or(0.8),
                other => {
                    let message = format!("unsupported phase `{other}` (`isotropic`, `hg`)");
                    return Err(cx.err(*child, &sub, message));
                }
            };
            phase.done(cx)?;
        }
        let scale = p.float(cx, "scale")?.unwrap_or(1.0);
        let hetero = match heterogeneous {
            true => {
                let mut volume = |name: &str, default: Vec3| -> Result<Volume> {
                    match volumes.iter().find(|(n, _)| n == name) {
                        Some(&(_, child)) => self.volume(child, &format!("{field}.{name}")),
                        None => {
                            let c = p.color(&self.cx, name)?.unwrap_or(default);
                            Ok(Volume::new(VolumeKind::Constant(c), Affine3A::IDENTITY))
                        }
                    }
                };
                Some((
                    volume("sigma_t", Vec3::ONE)?,
                    volume("albedo", Vec3::splat(0.75))?,
                ))
            }
            false => None,
        };
        let cx = &self.cx;
        let kind = match hetero {
            Some((sigma_t, albedo)) => Err((sigma_t, albedo)),
            None => Ok(MediumParams {
                sigma_t: p.color(cx, "sigma_t")?.unwrap_or(Vec3::ONE),
                albedo: p.albedo(cx, "albedo", 0.75)?,
                scale,
                g,
            }),
        };
        p.ignore(&["sample_emitters", "has_spectral_extinction"]);
        p.done(cx)?;
        let at = |part: Part, message: String| match part {
            Part::Parameter("g") => {
                let phase = p.objects.first().copied().unwrap_or(node);
                cx.err(phase, &format!("{field}.phase.g"), message)
            }
            // The parameter's element, or the medium's where the file leaves it out.
            Part::Parameter(name) => cx.err(p.node_of(name), &p.at(name), message),
            _ => cx.err(node, field, message),
        };
        // Ok: homogeneous parameters; Err: a heterogeneous medium's volumes.
        let m = match kind {
            Ok(params) => self.b.add_medium(id, params, &at)?,
            Err((sigma_t, albedo)) => {
                (self.b).add_heterogeneous_medium(id, sigma_t, albedo, scale, g, &at)?
            }
        };
        if let Some(id) = id {
            self.media.insert(id.to_string(), m);
        }
        Ok(m)
    }

    /// A `<medium>` child of a shape or sensor, or a `<ref>` to a top-level one: the medium.
    pub(crate) fn medium_child(&mut self, child: Node, field: &str) -> Result<MediumId> {
        match child.tag_name().name() {
            "medium" => self.medium(child, field, None),
            _ => {
                let (id, target) = self.referenced(child, field)?;
                let tag = target.tag_name().name();
                if tag != "medium" {
                    let message = format!("`{id}` is a <{tag}>, not a medium");
                    return Err(self.cx.err(child, field, message));
                }
                self.medium(target, &format!("medium[{id}]"), Some(&id))
            }
        }
    }
}

/// Which side of a shape a `<medium>` or `<ref>` child bounds: its `name`, `interior` or
/// `exterior`.
pub(crate) fn side(
    cx: &crate::importers::mitsuba::values::Cx,
    child: Node,
    field: &str,
) -> Result<bool> {
    match child.attribute("name") {
        Some("interior") => Ok(true),
        Some("exterior") => Ok(false),
        _ => Err(cx.err(
            child,
            field,
            "a shape's medium needs name=\"interior\" or name=\"exterior\"",
        )),
    }
}
