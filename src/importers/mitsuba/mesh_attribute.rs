//! Mitsuba's `mesh_attribute` texture (`name`: a `vertex_...` or `face_...` attribute of the
//! shape's mesh, `scale`), as a diffuse reflectance or a `blendbsdf`'s weight: its value at a hit is the face's row, or
//! the corners' rows interpolated barycentrically, times `scale`, as Mitsuba 3.9's
//! `Mesh::eval_attribute` gives it.
//!
//! The values reach both backends as an ordinary float texture with its own uvs, exactly:
//! each triangle gets a 2 x 2 block of texels holding its corner values `a`, `b`, `c` and
//! `b + c - a`, and its corners the uvs of the first three texels' centres. Bilinear
//! interpolation over such a block is `a + s (b - a) + t (c - a)`, the barycentric
//! interpolation itself (a face attribute's block is constant). The mesh's own uvs are
//! replaced, so its material may have no other texture.

use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::values::Cx;
use crate::scene::builder::MaterialId;
use crate::scene::Material;
use crate::textures::{Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap};
use glam::{Vec2, Vec3};
use roxmltree::Node;

/// A material whose diffuse reflectance is a mesh attribute: what each shape using it
/// needs to make its own copy.
#[derive(Clone, Debug)]
pub(crate) struct AttributeUse {
    /// The material, its base colour to be textured per shape.
    pub material: Material,
    /// The attribute's name (`vertex_color`).
    pub name: String,
    /// Mitsuba's `scale`.
    pub scale: f32,
    /// For a `blendbsdf`'s weight: its two components (`material` is then unused).
    pub blend: Option<[MaterialId; 2]>,
}

/// `node`, a `<texture>` at `field`: its attribute name and scale when it is a
/// `mesh_attribute`, else `None`.
pub(crate) fn read(cx: &Cx, node: Node, field: &str) -> Result<Option<(String, f32)>> {
    if node.attribute("type") != Some("mesh_attribute") {
        return Ok(None);
    }
    let p = Plugin::new(cx, node, field.to_string())?;
    let Some(name) = p.string(cx, "name")? else {
        return Err(cx.err(node, &p.at("name"), "missing"));
    };
    if !(name.starts_with("vertex_") || name.starts_with("face_")) {
        let message = format!("`{name}` must start with `vertex_` or `face_`");
        return Err(cx.err(p.node_of("name"), &p.at("name"), message));
    }
    let scale = p.float(cx, "scale")?.unwrap_or(1.0);
    if !scale.is_finite() {
        return Err(cx.err(p.node_of("scale"), &p.at("scale"), "must be finite"));
    }
    p.done(cx)?;
    Ok(Some((name, scale)))
}

/// The texture and the triangles' uvs that give `values` (per triangle, per corner) at
/// every hit (see the module's header). An error message when the texture would be too
/// large.
pub(crate) fn texture(
    values: &[[Vec3; 3]],
) -> std::result::Result<(SceneTexture, Vec<[Vec2; 3]>), String> {
    let bad = |t: &[Vec3; 3]| !t.iter().all(|v| v.is_finite());
    if let Some(i) = values.iter().position(bad) {
        return Err(format!(
            "triangle {i}: its values {:?} are not all finite",
            values[i]
        ));
    }
    let n = values.len().max(1);
    let per_row = (n as f64).sqrt().ceil() as usize;
    let rows = n.div_ceil(per_row);
    let (w, h) = (2 * per_row, 2 * rows);
    let mut data = vec![0.0f32; w * h * 3];
    let mut uvs = Vec::with_capacity(values.len());
    let (wf, hf) = (w as f32, h as f32);
    for (i, [a, b, c]) in values.iter().enumerate() {
        let (x, y) = (2 * (i % per_row), 2 * (i / per_row));
        for (dx, dy, v) in [(0, 0, *a), (1, 0, *b), (0, 1, *c), (1, 1, *b + *c - *a)] {
            let at = ((y + dy) * w + x + dx) * 3;
            data[at..at + 3].copy_from_slice(&v.to_array());
        }
        let centre = |dx: usize, dy: usize| {
            Vec2::new((x + dx) as f32 + 0.5, (y + dy) as f32 + 0.5) / Vec2::new(wf, hf)
        };
        uvs.push([centre(0, 0), centre(1, 0), centre(0, 1)]);
    }
    let image = Texture::from_float("mesh_attribute", w as u32, h as u32, data, 3)
        .map_err(|e| e.to_string())?;
    let sampler = Sampler::mitsuba(Filter::Bilinear, Wrap::Clamp, UvTransform::IDENTITY);
    Ok((SceneTexture::Bitmap(image.with_sampler(sampler)), uvs))
}
