//! Mitsuba's volumes (issue 41), the parameters of a `heterogeneous` medium:
//! `<volume name="sigma_t|albedo" type="gridvolume|constvolume">`. A `gridvolume` reads a
//! binary `.vol` file (`filename`, resolved as Mitsuba's file resolver does) with
//! `filter_type` (`trilinear` or `nearest`), `wrap_mode` `clamp` (the default; `repeat` and
//! `mirror` are refused), `use_grid_bbox` and `to_world`; `raw` and `accel` change nothing in
//! RGB. A `constvolume` is its `value` (default 1) within the box of its `to_world`.

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::Importer;
use crate::media::grid::{Filter, Volume, VolumeGrid, VolumeKind};
use glam::{Affine3A, Vec3};
use roxmltree::Node;
use std::sync::Arc;

impl Importer<'_> {
    /// The volume of `<volume>` `node` at `field`.
    pub(crate) fn volume(&mut self, node: Node, field: &str) -> Result<Volume> {
        let cx = &self.cx;
        let p = Plugin::new(cx, node, field.to_string())?;
        if let Some(child) = p.objects.first() {
            let tag = child.tag_name().name();
            let message = format!("unsupported <{tag}> in a volume");
            return Err(cx.err(*child, field, message));
        }
        let to_world = p.transform(cx, "to_world")?.unwrap_or_default();
        let to_world = Affine3A::from_mat4(to_world);
        let det = to_world.matrix3.determinant();
        let invertible = det.is_finite() && det.abs() > 1e-20;
        if !invertible || !to_world.translation.is_finite() {
            let message = "the transform cannot be inverted";
            return Err(cx.err(p.node_of("to_world"), &p.at("to_world"), message));
        }
        let mut to_local = to_world.inverse();
        let kind = match p.kind.as_str() {
            "constvolume" => VolumeKind::Constant(p.color(cx, "value")?.unwrap_or(Vec3::ONE)),
            "gridvolume" => {
                let Some(file) = p.string(cx, "filename")? else {
                    return Err(cx.err(node, &p.at("filename"), "missing"));
                };
                let filter = match p.string(cx, "filter_type")?.as_deref() {
                    None | Some("trilinear") => Filter::Trilinear,
                    Some("nearest") => Filter::Nearest,
                    Some(other) => {
                        let message = format!("`{other}` is not `trilinear` or `nearest`");
                        let at = p.node_of("filter_type");
                        return Err(cx.err(at, &p.at("filter_type"), message));
                    }
                };
                if let Some(wrap) = p.string(cx, "wrap_mode")? {
                    if wrap != "clamp" {
                        let message = format!("unsupported wrap_mode `{wrap}` (only `clamp`)");
                        let at = p.node_of("wrap_mode");
                        return Err(cx.err(at, &p.at("wrap_mode"), message));
                    }
                }
                let grid = VolumeGrid::open(&cx.resolve(&file), self.b.grid_room())
                    .map_err(|e| cx.err(p.node_of("filename"), &p.at("filename"), e))?;
                if p.boolean(cx, "use_grid_bbox")? {
                    let [lo, hi] = grid.bbox;
                    let to_unit =
                        Affine3A::from_scale((hi - lo).recip()) * Affine3A::from_translation(-lo);
                    to_local = to_unit * to_local;
                }
                VolumeKind::Grid {
                    grid: Arc::new(grid),
                    to_local,
                    filter,
                }
            }
            other => {
                let message = format!("unsupported volume `{other}` (`gridvolume`, `constvolume`)");
                return Err(cx.err(node, field, message));
            }
        };
        p.ignore(&["raw", "accel"]);
        p.done(cx)?;
        Ok(Volume::new(kind, to_local))
    }
}
