//! Mitsuba shapes: `rectangle` ([-1,1]^2 in z = 0, front +z), `cube` ([-1,1]^3, outward,
//! each face's uvs as Mitsuba's cube mesh has them: `uv::cube`),
//! `sphere` (analytic; `center`, `radius`, and a `to_world` that scales uniformly), `disk`
//! and `cylinder` (`p0`, `p1`, `radius`; both as meshes of `round::SEGMENTS` facets around,
//! with a warning), `obj` and `ply` meshes (smooth-shaded with the file's vertex normals, or,
//! in a file without them, normals computed from the faces as Mitsuba computes them; flat when
//! `face_normals` is true; the file's texture coordinates with v flipped when
//! `flip_tex_coords`, Mitsuba's default true for `obj` and false for `ply`), `serialized`
//! meshes (`shape_index`, `face_normals`; [`serialized`]), `sdfgrid` (a signed distance field
//! on a grid, `crate::scene::sdf_grid`), each with its
//! bsdf (nested or `ref`) and optionally an `area` emitter.

use crate::bsdfs::{BsdfKind, Param};
use crate::error::Result;
use crate::importers::mesh_file::{self, MeshData, MeshFormat};
use crate::importers::mitsuba::medium::side;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::{mesh_attribute, round, serialized, Importer};
use crate::media::builder::{interface, MediumId};
use crate::media::grid::VolumeGrid;
use crate::scene::builder::Surface;
use crate::scene::sdf_grid::SdfData;
use crate::textures::uv;
use crate::textures::SceneTexture;
use glam::{Mat4, Vec3};
use roxmltree::Node;
use std::sync::Arc;

/// The outward faces of the cube [-1,1]^3: the normal and two edges `u`, `v` with
/// `cross(u, v)` = normal.
const CUBE_FACES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::Y, Vec3::Z],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::Z, Vec3::X],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::Y, Vec3::X],
];

/// The two triangles of the quad with `normal`, edges `u`, `v` (corners `n -/+ u -/+ v` in
/// order around the edge), front face along `normal`.
fn quad(normal: Vec3, u: Vec3, v: Vec3) -> [[Vec3; 3]; 2] {
    let c = [
        normal - u - v,
        normal + u - v,
        normal + u + v,
        normal - u + v,
    ];
    [[c[0], c[1], c[2]], [c[0], c[2], c[3]]]
}

impl<'f> Importer<'f> {
    /// A `<shape>` element: its surface, then its geometry.
    pub(crate) fn shape(&mut self, node: Node, field: &str) -> Result<()> {
        match node.attribute("type") {
            Some("shapegroup") => return self.shape_group(node, field).map(|_| ()),
            Some("instance") => return self.instance(node, field),
            _ => {}
        }
        let p = Plugin::new(&self.cx, node, field.to_string())?;
        let mut material = None;
        let mut emission = None;
        let mut emission_texture = None;
        let mut media: [Option<MediumId>; 2] = [None, None];
        for child in &p.objects {
            let tag = child.tag_name().name();
            let sub = format!("{field}.{tag}");
            let found = match tag {
                "bsdf" => Some(self.add_bsdf(*child, &sub)?),
                "medium" => {
                    self.shape_medium(*child, &sub, &mut media)?;
                    None
                }
                "ref" => {
                    let (id, target) = self.referenced(*child, &sub)?;
                    match target.tag_name().name() {
                        "medium" => {
                            self.shape_medium(*child, &sub, &mut media)?;
                            None
                        }
                        "bsdf" => Some(self.bsdf_by_id(&id, target)?),
                        "emitter" => {
                            let (radiance, t) = self.area(target, &format!("emitter[{id}]"))?;
                            emission_texture = t;
                            if emission.replace(radiance).is_some() {
                                return Err(self.cx.err(*child, &sub, "a shape has one emitter"));
                            }
                            None
                        }
                        other => {
                            let message =
                                format!("`{id}` is a <{other}>, not a bsdf, emitter or medium");
                            return Err(self.cx.err(*child, &sub, message));
                        }
                    }
                }
                "emitter" => {
                    let (radiance, t) = self.area(*child, &sub)?;
                    emission_texture = t;
                    if emission.replace(radiance).is_some() {
                        return Err(self.cx.err(*child, &sub, "a shape has one emitter"));
                    }
                    None
                }
                other => {
                    let message = format!("unsupported <{other}> in a shape");
                    return Err(self.cx.err(*child, field, message));
                }
            };
            if let Some(id) = found {
                if material.replace(id).is_some() {
                    return Err(self.cx.err(*child, &sub, "a shape has one bsdf"));
                }
            }
        }
        let material = match material {
            Some(m) => m,
            None => {
                let at = self.origin(node, field);
                self.default_material(&at)?
            }
        };
        let emission_texture = match emission_texture {
            Some(t) => Some(self.b.add_texture(t, &self.origin(node, field))?),
            None => None,
        };
        let surface = Surface {
            media: interface(media[0], media[1]),
            material: Some(material),
            emission,
            two_sided: None,
            emission_texture,
        };
        self.geometry(&p, surface)
    }

    /// The `<medium>` or `<ref>` `child` of a shape, into `media` (interior, exterior) by
    /// its `name`; each side once.
    fn shape_medium(
        &mut self,
        child: Node,
        field: &str,
        media: &mut [Option<MediumId>; 2],
    ) -> Result<()> {
        let interior = side(&self.cx, child, field)?;
        let m = self.medium_child(child, field)?;
        let slot = &mut media[usize::from(!interior)];
        if slot.replace(m).is_some() {
            return Err(self
                .cx
                .err(child, field, "a shape has one medium on each side"));
        }
        Ok(())
    }

    /// An `area` emitter's radiance, and its texture when `radiance` is a `<texture>` (the
    /// radiance is then one and the texture's colour gives it, as Mitsuba evaluates it).
    fn area(&self, node: Node, field: &str) -> Result<(Vec3, Option<SceneTexture>)> {
        let e = Plugin::new(&self.cx, node, field.to_string())?;
        if e.kind != "area" {
            let message = format!("unsupported emitter `{}` on a shape", e.kind);
            return Err(self.cx.err(node, field, message));
        }
        if let Some(extra) = e.objects.first() {
            let message = format!("unsupported <{}> in an emitter", extra.tag_name().name());
            return Err(self.cx.err(*extra, field, message));
        }
        if let Some(t) = e.texture_param("radiance") {
            let texture =
                crate::importers::mitsuba::texture::texture(&self.cx, t, &e.at("radiance"))?;
            e.done(&self.cx)?;
            return Ok((Vec3::ONE, Some(texture)));
        }
        let Some(radiance) = e.emission(&self.cx, "radiance")? else {
            return Err(self.cx.err(node, &e.at("radiance"), "missing"));
        };
        e.done(&self.cx)?;
        Ok((radiance, None))
    }

    /// Adds the shape `p` is, of `surface`.
    fn geometry(&mut self, p: &Plugin, surface: Surface) -> Result<()> {
        let cx = &self.cx;
        let at = self.origin(p.node, &p.field);
        let m = p.transform(cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        let mesh = match p.kind.as_str() {
            "sphere" => {
                let center = p.point(cx, "center")?.unwrap_or(Vec3::ZERO);
                let radius = p.positive(cx, "radius", 1.0)?;
                if p.boolean(cx, "flip_normals")? {
                    let message = "unsupported: an inward-facing sphere";
                    return Err(cx.err(p.node, &p.at("flip_normals"), message));
                }
                p.done(cx)?;
                // A uniform scale keeps the sphere a sphere.
                let cols = [m.x_axis, m.y_axis, m.z_axis].map(|c| c.truncate());
                let s = cols[0].length();
                let uniform = cols.iter().all(|c| (c.length() - s).abs() <= 1e-4 * s)
                    && cols[0].dot(cols[1]).abs() <= 1e-4 * s * s
                    && cols[1].dot(cols[2]).abs() <= 1e-4 * s * s
                    && cols[0].dot(cols[2]).abs() <= 1e-4 * s * s;
                if !uniform {
                    let message = "unsupported: a sphere's to_world must scale uniformly";
                    return Err(cx.err(p.node, &p.at("to_world"), message));
                }
                let center = m.transform_point3(center);
                // Mitsuba's uv and dp/du are its object space's: keep the rotation (a
                // mirroring to_world keeps the world frame, as before).
                let rotation = glam::Mat3::from_cols(cols[0] / s, cols[1] / s, cols[2] / s);
                let frame = if rotation.determinant() > 0.0 {
                    glam::Quat::from_mat3(&rotation).normalize()
                } else {
                    glam::Quat::IDENTITY
                };
                return self
                    .b
                    .add_oriented_sphere(center, radius * s, frame, surface, &at);
            }
            "rectangle" => {
                let tris = quad(Vec3::ZERO, Vec3::X, Vec3::Y).to_vec();
                let uvs = tris.iter().map(|t| t.map(uv::rectangle)).collect();
                round::uv_mesh(tris, uvs)
            }
            "cube" => {
                let tris: Vec<[Vec3; 3]> = CUBE_FACES
                    .iter()
                    .flat_map(|&[n, u, v]| quad(n, u, v))
                    .collect();
                // Mitsuba's cube has uvs per face (`uv::cube`, affine on a face): read at a
                // point half way to the face's centre, where the face is not ambiguous.
                let corner_uv = |n: Vec3, c: Vec3| {
                    let centre = uv::cube(n);
                    centre + 2.0 * (uv::cube(n + 0.5 * (c - n)) - centre)
                };
                let normals = CUBE_FACES.iter().flat_map(|&[n, _, _]| [n, n]);
                let uvs = (tris.iter().zip(normals))
                    .map(|(t, n)| t.map(|c| corner_uv(n, c)))
                    .collect();
                round::uv_mesh(tris, uvs)
            }
            "disk" | "cylinder" => {
                let what = format!(
                    "{}: {}: a `{}` is rendered as {} facets around (its area kept)",
                    cx.loc(p.node),
                    p.field,
                    p.kind,
                    round::SEGMENTS
                );
                self.warnings.push(what);
                if p.kind == "disk" {
                    round::disk()
                } else {
                    let p0 = p.point(cx, "p0")?.unwrap_or(Vec3::ZERO);
                    let p1 = p.point(cx, "p1")?.unwrap_or(Vec3::Z);
                    let radius = p.positive(cx, "radius", 1.0)?;
                    let Some(frame) = round::cylinder_frame(p0, p1, radius) else {
                        return Err(cx.err(p.node, &p.at("p1"), "p1 must differ from p0"));
                    };
                    // Placed on its axis here; to_world and flip_normals below, as for all.
                    round::cylinder().transform(frame, false)
                }
            }
            "obj" | "ply" => {
                let Some(file) = p.string(cx, "filename")? else {
                    return Err(cx.err(p.node, &p.at("filename"), "missing"));
                };
                let path = self.cx.resolve(&file);
                let node = p
                    .node
                    .children()
                    .find(|c| c.attribute("name") == Some("filename"));
                let node = node.unwrap_or(p.node);
                let format = if p.kind == "obj" {
                    MeshFormat::Obj
                } else {
                    MeshFormat::Ply
                };
                // Mitsuba's `flip_tex_coords`: v to 1 - v, by default for OBJ only.
                let flip_v = p.boolean_or(cx, "flip_tex_coords", format.flips_tex_coords())?;
                let room = self.b.triangle_room();
                let mesh = mesh_file::load_mesh(&path, format, flip_v, room)
                    .map_err(|m| cx.err(node, &p.at("filename"), m))?;
                // Mitsuba's `face_normals`: flat shading even where the file has normals.
                mesh.flat_if(p.boolean(cx, "face_normals")?)
            }
            "serialized" => {
                let Some(file) = p.string(cx, "filename")? else {
                    return Err(cx.err(p.node, &p.at("filename"), "missing"));
                };
                let index = p.float(cx, "shape_index")?.unwrap_or(0.0);
                if !(index >= 0.0 && index <= u32::MAX as f32 && index.fract() == 0.0) {
                    let message = format!("{index} is not a mesh index (an integer >= 0)");
                    return Err(cx.err(p.node_of("shape_index"), &p.at("shape_index"), message));
                }
                let path = self.cx.resolve(&file);
                let room = self.b.triangle_room();
                let mesh = serialized::read_serialized(&path, index as u32, room)
                    .map_err(|m| cx.err(p.node_of("filename"), &p.at("filename"), m))?;
                mesh.flat_if(p.boolean(cx, "face_normals")?)
            }
            "sdfgrid" => return self.sdf_grid(p, m, surface),
            other => {
                let message = format!("unsupported shape `{other}`");
                return Err(cx.err(p.node, &p.field, message));
            }
        };
        let flip = p.boolean(cx, "flip_normals")?;
        p.done(cx)?;
        // A mesh file without normals is smooth in Mitsuba (unless `face_normals`): normals
        // from its faces, after to_world.
        let mesh = mesh.transform(m, flip).smooth_from_faces();
        let (mesh, surface) = self.attribute_surface(p, mesh, surface)?;
        match mesh.uvs {
            Some(uvs) => self
                .b
                .add_uv_mesh(mesh.tris, mesh.normals, uvs, surface, &at),
            None => self
                .b
                .add_smooth_mesh(mesh.tris, mesh.normals, surface, &at),
        }
    }

    /// An `sdfgrid` (`crate::scene::sdf_grid`): its `filename` (a one-channel `.vol`;
    /// Mitsuba's `grid` tensor cannot be given in XML) and `normals` (`smooth` or
    /// `analytic`), placed by `to_world` `m`.
    fn sdf_grid(&mut self, p: &Plugin, m: Mat4, surface: Surface) -> Result<()> {
        let cx = &self.cx;
        let Some(file) = p.string(cx, "filename")? else {
            return Err(cx.err(p.node, &p.at("filename"), "missing"));
        };
        let smooth = match p.string(cx, "normals")?.as_deref() {
            None | Some("smooth") => true,
            Some("analytic") => false,
            Some(other) => {
                let message = format!("`{other}` is not `analytic` or `smooth`");
                return Err(cx.err(p.node_of("normals"), &p.at("normals"), message));
            }
        };
        let held: u64 = (self.b.sdf_grids.iter())
            .map(|g| 4 * g.data.grid.data.len() as u64)
            .sum();
        let room = self.b.grid_room().saturating_sub(held);
        let path = cx.resolve(&file);
        let at_file = |m: String| cx.err(p.node_of("filename"), &p.at("filename"), m);
        let grid = VolumeGrid::open(&path, room).map_err(at_file)?;
        let name = crate::escape::escape(&path.display().to_string()).into_owned();
        let data = SdfData::new(grid).map_err(|m| at_file(format!("{name}: {m}")))?;
        p.done(cx)?;
        let at = self.origin(p.node, &p.field);
        self.b.add_sdf_grid(Arc::new(data), m, smooth, surface, &at)
    }

    /// `mesh` and `surface`, or, when the surface's material reads a `mesh_attribute`, the
    /// mesh with the attribute's uvs and a copy of the material whose diffuse reflectance is
    /// its texture (`mesh_attribute.rs`). A shape without the attribute is an error.
    fn attribute_surface(
        &mut self,
        p: &Plugin,
        mut mesh: MeshData,
        mut surface: Surface,
    ) -> Result<(MeshData, Surface)> {
        let used = (self.attribute_materials.iter())
            .find(|(id, _)| Some(*id) == surface.material)
            .map(|(_, a)| a.clone());
        let Some(used) = used else {
            return Ok((mesh, surface));
        };
        let Some((_, values)) = mesh.attributes.iter().find(|(n, _)| *n == used.name) else {
            let mut names: Vec<String> = mesh
                .attributes
                .iter()
                .map(|(n, _)| format!("`{n}`"))
                .collect();
            if names.is_empty() {
                names.push("none".into());
            }
            let message = format!(
                "its bsdf reads the mesh attribute `{}`, which this shape does not have (its \
                 attributes: {})",
                used.name,
                names.join(", ")
            );
            return Err(self.cx.err(p.node, &p.field, message));
        };
        let at = self.origin(p.node, &p.field);
        let (texture, uvs) = mesh_attribute::texture(values).map_err(|m| {
            self.cx
                .err(p.node, &p.field, format!("mesh attribute: {m}"))
        })?;
        let texture = self.b.add_texture(texture, &at)?;
        surface.material = Some(match used.blend {
            // A blend's weight: a float texture, read as Mitsuba's eval_1 (one channel
            // repeated, so its luminance).
            Some([first, second]) => {
                let weight = Param {
                    value: Vec3::splat(used.scale),
                    texture,
                    channel: crate::bsdfs::Channel::Luminance,
                };
                self.b.add_blend(first, second, weight, &at)?
            }
            None => {
                let mut material = used.material;
                if let Some(base) = material.bsdf.base_colour_mut() {
                    *base = Param::texture(texture);
                    base.value = Vec3::splat(used.scale);
                }
                self.b.add_material(None, material, &at)?
            }
        });
        mesh.uvs = Some(uvs);
        Ok((mesh, surface))
    }
}
