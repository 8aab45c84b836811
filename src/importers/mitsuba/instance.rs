//! Mitsuba's instancing: a `shapegroup` (shapes stored once, as one mesh in their own
//! object space, invisible by themselves) and `instance`s that place it by their `to_world`
//! (`crate::scene::instances`). As in Mitsuba (`src/render/shapegroup.cpp`,
//! `src/shapes/instance.cpp`): a group holds shapes only, no emitter, no other group or
//! instance; an instance names exactly one group (`<ref>` or nested).

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::{elements, Importer};
use crate::scene::MeshId;
use glam::Mat4;
use roxmltree::Node;

impl<'f> Importer<'f> {
    /// The mesh of the `<shape type="shapegroup" id>` `node` at `field`, read the first time
    /// it is asked for (where it stands, or where an instance first names it).
    pub(crate) fn shape_group(&mut self, node: Node, field: &str) -> Result<MeshId> {
        let id = self.cx.need_attr(node, field, "id")?;
        if let Some(&mesh) = self.groups.get(&id) {
            return Ok(mesh);
        }
        let at = self.origin(node, field);
        self.b.begin_shape_group(&at)?;
        let mut read = Ok(());
        for (i, child) in elements(node).enumerate() {
            let tag = child.tag_name().name();
            let sub = format!("{field}.shape[{i}]");
            read = match (tag, child.attribute("type")) {
                ("shape", Some("shapegroup")) => {
                    let message = "a shapegroup inside a shapegroup (Mitsuba: nested ShapeGroup \
                                   is not permitted)";
                    Err(self.cx.err(child, &sub, message))
                }
                ("shape", Some("instance")) => {
                    let message = "an instance inside a shapegroup (Mitsuba: nested instancing \
                                   is not permitted)";
                    Err(self.cx.err(child, &sub, message))
                }
                ("shape", _) => self.shape(child, &sub),
                ("emitter", _) => {
                    let message = "an emitter in a shapegroup (Mitsuba: instancing of emitters \
                                   is not supported)";
                    Err(self.cx.err(child, &sub, message))
                }
                (other, _) => {
                    let message = format!("unsupported <{other}> in a shapegroup");
                    Err(self.cx.err(child, field, message))
                }
            };
            if read.is_err() {
                break;
            }
        }
        let mesh = self.b.end_shape_group();
        read?;
        self.groups.insert(id, mesh);
        Ok(mesh)
    }

    /// A `<shape type="instance">`: the group it names, placed by its `to_world`.
    pub(crate) fn instance(&mut self, node: Node, field: &str) -> Result<()> {
        let p = Plugin::new(&self.cx, node, field.to_string())?;
        let mut mesh = None;
        for child in &p.objects {
            let tag = child.tag_name().name();
            let sub = format!("{field}.{tag}");
            let target = match tag {
                "ref" => self.referenced(*child, &sub)?.1,
                "shape" => *child,
                other => {
                    let message = format!("unsupported <{other}> in an instance");
                    return Err(self.cx.err(*child, &sub, message));
                }
            };
            if target.attribute("type") != Some("shapegroup") {
                let message = "only a shapegroup can be specified in an instance";
                return Err(self.cx.err(*child, &sub, message));
            }
            let group = format!("shape[{}]", target.attribute("id").unwrap_or("?"));
            let m = self.shape_group(target, &group)?;
            if mesh.replace(m).is_some() {
                let message = "only a single shapegroup can be specified per instance";
                return Err(self.cx.err(*child, &sub, message));
            }
        }
        let Some(mesh) = mesh else {
            let message = "an instance needs a reference to a shapegroup";
            return Err(self.cx.err(node, field, message));
        };
        let to_world = p.transform(&self.cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        p.done(&self.cx)?;
        let at = self.origin(node, &p.at("to_world"));
        self.b.add_instance(mesh, to_world, &at)
    }
}
