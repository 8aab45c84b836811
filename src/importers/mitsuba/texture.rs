//! Mitsuba textures as our [`SceneTexture`]s: `bitmap` (`filename`, `filter_type`,
//! `wrap_mode`, `raw`, `to_uv`), `checkerboard` (`color0`, `color1`, `to_uv`), with
//! Mitsuba's defaults (bilinear, repeat, sRGB unless `raw`), and `rawconstant` (`value`, a
//! float or a vector, taken as it is: a 1 x 1 float image).

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::values::Cx;
use crate::textures::{
    Checkerboard, Encoding, Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap,
};
use glam::{Mat4, Vec3};
use roxmltree::Node;

/// The 2D affine part of a `to_uv` transform (Mitsuba's `extract()` of the 4x4 matrix).
fn uv_transform(m: Mat4) -> UvTransform {
    let c = m.to_cols_array_2d();
    UvTransform::from_mitsuba([
        [c[0][0], c[1][0], c[3][0]],
        [c[0][1], c[1][1], c[3][1]],
        [0.0, 0.0, 1.0],
    ])
}

/// Reads the `<texture>` element `node` at `field`; image files are looked up as Mitsuba's
/// file resolver does ([`Cx::resolve`]).
pub(crate) fn texture(cx: &Cx, node: Node, field: &str) -> Result<SceneTexture> {
    let p = Plugin::new(cx, node, field.to_string())?;
    if let Some(&extra) = p.objects.first() {
        let message = format!("unsupported <{}> inside a texture", extra.tag_name().name());
        return Err(cx.err(extra, field, message));
    }
    let to_uv = p
        .transform(cx, "to_uv")?
        .map_or(UvTransform::IDENTITY, uv_transform);
    let texture = match p.kind.as_str() {
        "bitmap" => {
            let Some(file) = p.string(cx, "filename")? else {
                return Err(cx.err(node, &p.at("filename"), "missing"));
            };
            let filter = match p.string(cx, "filter_type")? {
                Some(name) => Filter::from_mitsuba(&name).map_err(|e| {
                    cx.err(
                        p.node_of("filter_type"),
                        &p.at("filter_type"),
                        e.to_string(),
                    )
                })?,
                None => Filter::Bilinear,
            };
            let wrap = match p.string(cx, "wrap_mode")? {
                Some(name) => Wrap::from_mitsuba(&name).map_err(|e| {
                    cx.err(p.node_of("wrap_mode"), &p.at("wrap_mode"), e.to_string())
                })?,
                None => Wrap::Repeat,
            };
            let encoding = if p.boolean(cx, "raw")? {
                Encoding::Raw
            } else {
                Encoding::Srgb
            };
            p.ignore(&["format"]);
            let image = Texture::load(&cx.resolve(&file), encoding)
                .map_err(|e| cx.err(p.node_of("filename"), &p.at("filename"), e.to_string()))?;
            SceneTexture::Bitmap(image.with_sampler(Sampler::mitsuba(filter, wrap, to_uv)))
        }
        "checkerboard" => SceneTexture::Checkerboard(Checkerboard {
            color0: p.color(cx, "color0")?.unwrap_or(Vec3::splat(0.4)),
            color1: p.color(cx, "color1")?.unwrap_or(Vec3::splat(0.2)),
            to_uv,
        }),
        "rawconstant" => {
            // Mitsuba's `rawconstant`: a float (broadcast) or a vector, with no colour
            // conversion or range check: a 1 x 1 float image.
            let at = p.node_of("value");
            let value = match at.tag_name().name() {
                "vector" | "point" => p.point(cx, "value")?,
                _ if at == node => None,
                _ => p.float(cx, "value")?.map(Vec3::splat),
            };
            let Some(value) = value else {
                let message = "missing (a `float` or a `vector`)";
                return Err(cx.err(node, &p.at("value"), message));
            };
            let image = Texture::from_float("rawconstant", 1, 1, value.to_array().to_vec(), 3)?;
            SceneTexture::Bitmap(image.with_sampler(Sampler::mitsuba(
                Filter::Nearest,
                Wrap::Clamp,
                to_uv,
            )))
        }
        other => {
            let message = format!("unsupported texture `{other}`");
            return Err(cx.err(node, field, message));
        }
    };
    p.done(cx)?;
    Ok(texture)
}
