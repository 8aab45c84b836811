//! Mitsuba 3's `bumpmap` bsdf (src/bsdfs/bumpmap.cpp): its height texture and `scale`. The
//! texture is its one `<texture>` of any name, a `bitmap` (the one texture with a gradient,
//! `eval_1_grad`, in Mitsuba 3.9.1), read as Mitsuba reads any bitmap: sRGB-decoded unless
//! `raw`. The caller (`bsdf.rs`) makes it the material's `normal_texture` with `bump` set to
//! the scale; the intersection tilts the normal (`crate::math::geometry::bump_mapped`), and
//! the normal map's shadowing applies as Mitsuba's `use_shadowing_function` (default on) says.

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::texture::texture;
use crate::importers::mitsuba::values::Cx;
use crate::textures::SceneTexture;

/// The height texture and `scale` (default 1) of the `bumpmap` plugin `p` at `field`.
pub(super) fn height(cx: &Cx, p: &Plugin, field: &str) -> Result<(SceneTexture, f32)> {
    let names = p.texture_names();
    if let Some(extra) = names.get(1) {
        let message = "`bumpmap` takes one <texture>";
        return Err(cx.err(p.node_of(extra), &p.at(extra), message));
    }
    let (Some(name), Some(t)) = (
        names.first(),
        names.first().and_then(|n| p.texture_param(n)),
    ) else {
        return Err(cx.err(p.node, field, "`bumpmap` needs a <texture>"));
    };
    if t.attribute("type") != Some("bitmap") {
        let message = "a `bumpmap` needs a `bitmap` (Mitsuba's other textures have no gradient)";
        return Err(cx.err(t, &p.at(name), message));
    }
    let tex = texture(cx, t, &p.at(name))?;
    let scale = p.float(cx, "scale")?.unwrap_or(1.0);
    if !scale.is_finite() {
        return Err(cx.err(p.node_of("scale"), &p.at("scale"), "must be finite"));
    }
    Ok((tex, scale))
}
