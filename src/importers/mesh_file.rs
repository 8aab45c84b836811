//! Mesh files named by a scene: OBJ ([`crate::importers::obj`]) or PLY ([`crate::importers::ply`]), read to
//! world-space triangles and, when the file has them, vertex normals (OBJ `vn`, PLY `nx`,
//! `ny`, `nz`) for smooth shading and texture coordinates (OBJ `vt`, PLY `u v` and its
//! synonyms). Every importer that refers to a mesh file (the TOML `type = "mesh"` shape,
//! Mitsuba's `obj` and `ply` shapes) reads it here.
//!
//! Texture coordinates follow Mitsuba 3's `flip_tex_coords` (its `obj.cpp` and `ply.cpp`):
//! uv (0, 0) is the image's top-left corner, so an OBJ file's v (0 at the bottom, by the
//! format's convention) is flipped to `1 - v` by default, and a PLY file's is kept. The TOML
//! `mesh` shape always uses these defaults; Mitsuba's shapes take `flip_tex_coords`.

use crate::error::Result;
use crate::importers::{obj, ply};
use crate::scene::builder::{SceneBuilder, Surface};
use crate::scene::locate::{Locate, Part};
use crate::scene::VertexNormals;
use glam::{Mat3, Mat4, Vec2, Vec3};
use std::path::Path;

/// The format of a mesh file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MeshFormat {
    /// Wavefront OBJ.
    Obj,
    /// PLY, ASCII or binary.
    Ply,
}

impl MeshFormat {
    /// The format `path` names by its extension: `.ply` (any case) is PLY, anything else OBJ.
    pub(crate) fn of_path(path: &Path) -> Self {
        let is_ply = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
        if is_ply {
            MeshFormat::Ply
        } else {
            MeshFormat::Obj
        }
    }

    /// Mitsuba 3's default `flip_tex_coords` for the format: true for OBJ (`obj.cpp`),
    /// false for PLY (`ply.cpp`).
    pub(crate) fn flips_tex_coords(self) -> bool {
        self == MeshFormat::Obj
    }
}

/// A mesh file's triangles and, when it has them, one set of vertex normals per triangle
/// (zero and non-finite normals already refused; not normalised).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MeshData {
    /// The triangles, corners in the file's winding.
    pub tris: Vec<[Vec3; 3]>,
    /// The corners' normals, parallel to `tris`; `None` for a flat mesh.
    pub normals: Option<Vec<VertexNormals>>,
    /// The corners' texture coordinates, parallel to `tris`; `None` without.
    pub uvs: Option<Vec<[Vec2; 3]>>,
    /// The corners' vertices in the file (a PLY vertex; an OBJ `v` with its `vt`), parallel
    /// to `tris`, for normals computed from the faces ([`MeshData::smooth_from_faces`]);
    /// `None` for a shape that is not a mesh file.
    pub vertices: Option<Vec<[u32; 3]>>,
    /// A PLY file's custom attributes by Mitsuba's name (`vertex_color`, `face_color`; see
    /// [`ply::attributes`]): each corner's value as a colour (one field broadcast, a fourth
    /// dropped; a face attribute's three corners equal), parallel to `tris`.
    pub attributes: Vec<(String, Vec<[Vec3; 3]>)>,
}

impl MeshData {
    /// The mesh through the affine map `m` (normals through its inverse transpose), front
    /// faces kept on the side they were: a mirroring `m` reverses the winding (corners 1 and
    /// 2 swap, with their normals), as does `flip`.
    pub(crate) fn transform(self, m: Mat4, flip: bool) -> Self {
        let swap = (m.determinant() < 0.0) != flip;
        let tris = self.tris.into_iter().map(|t| {
            let mut t = t.map(|p| m.transform_point3(p));
            if swap {
                t.swap(1, 2);
            }
            t
        });
        let normal_map = Mat3::from_mat4(m).inverse().transpose();
        MeshData {
            vertices: self.vertices.map(|mut vs| {
                if swap {
                    vs.iter_mut().for_each(|t| t.swap(1, 2));
                }
                vs
            }),
            tris: tris.collect(),
            normals: self
                .normals
                .map(|ns| transform_normals(ns, normal_map, swap)),
            uvs: self.uvs.map(|mut uvs| {
                if swap {
                    uvs.iter_mut().for_each(|t| t.swap(1, 2));
                }
                uvs
            }),
            attributes: (self.attributes.into_iter())
                .map(|(name, mut values)| {
                    if swap {
                        values.iter_mut().for_each(|t| t.swap(1, 2));
                    }
                    (name, values)
                })
                .collect(),
        }
    }

    /// Drops the normals when `flat` (forced flat shading), and the vertices, so that none
    /// are computed either.
    pub(crate) fn flat_if(self, flat: bool) -> Self {
        MeshData {
            normals: self.normals.filter(|_| !flat),
            vertices: self.vertices.filter(|_| !flat),
            ..self
        }
    }

    /// A mesh file without normals made smooth as Mitsuba 3 makes it: vertex normals from
    /// its (transformed) faces, angle-weighted (`vertex_normals::from_faces`). Unchanged when
    /// it has normals or is not a mesh file.
    pub(crate) fn smooth_from_faces(self) -> Self {
        match (&self.normals, &self.vertices) {
            (None, Some(ids)) => MeshData {
                normals: Some(crate::importers::vertex_normals::from_faces(
                    &self.tris, ids,
                )),
                ..self
            },
            _ => self,
        }
    }
}

/// Each normal through `map` (an inverse transpose), corners 1 and 2 swapped when `swap`.
fn transform_normals(mut ns: Vec<VertexNormals>, map: Mat3, swap: bool) -> Vec<VertexNormals> {
    for set in &mut ns {
        *set = set.map(|n| map * n);
        if swap {
            set.swap(1, 2);
        }
    }
    ns
}

/// The mesh file at `path`, in the file's coordinates, its texture coordinates' v flipped
/// to `1 - v` when `flip_v` (Mitsuba's `flip_tex_coords`; an OBJ corner without `vt` keeps
/// (0, 0) either way). Errors are messages naming the resolved path (for PLY, the
/// [`ply::PlyError`]); a vertex normal that is zero or not finite is one, naming its field
/// (`vn`, or `nx, ny, nz` and the vertex). A file with more than `room` triangles (what the
/// scene's budget has room for, `SceneBuilder::triangle_room`) is refused as it is read,
/// before they are built.
pub(crate) fn load_mesh(
    path: &Path,
    format: MeshFormat,
    flip_v: bool,
    room: u64,
) -> Result<MeshData, String> {
    match format {
        MeshFormat::Obj => {
            let obj = obj::load_triangles(path, flip_v, room)?;
            // Mitsuba keys an OBJ vertex by its `v` and `vt`: corners with other uvs are
            // other vertices.
            let vertices = match &obj.uvs {
                None => obj.vertices,
                Some(uvs) => split_by_uv(&obj.vertices, uvs),
            };
            Ok(MeshData {
                tris: obj.tris,
                normals: obj.normals,
                uvs: obj.uvs,
                vertices: Some(vertices),
                attributes: Vec::new(),
            })
        }
        MeshFormat::Ply => {
            let mesh = ply::read_ply_within(path, room).map_err(|e| e.to_string())?;
            let normals = match &mesh.normals {
                None => None,
                Some(ns) => {
                    if let Some(i) = ns.iter().position(|n| !n.is_finite() || *n == Vec3::ZERO) {
                        return Err(format!(
                            "{}: vertex {i}: the normal (nx, ny, nz) {} is zero or not finite",
                            path.display(),
                            ns[i]
                        ));
                    }
                    let at = |i: u32| ns[i as usize];
                    Some(mesh.triangles.iter().map(|t| t.map(at)).collect())
                }
            };
            let uvs = mesh.uvs.as_ref().map(|uvs| {
                let at = |i: u32| {
                    let uv = uvs[i as usize];
                    if flip_v {
                        Vec2::new(uv.x, 1.0 - uv.y)
                    } else {
                        uv
                    }
                };
                mesh.triangles.iter().map(|t| t.map(at)).collect()
            });
            let attributes = (mesh.attributes.iter())
                .map(|a| (a.name.clone(), corner_values(a, &mesh.triangles)))
                .collect();
            Ok(MeshData {
                tris: mesh.triangle_positions(),
                normals,
                uvs,
                vertices: Some(mesh.triangles.clone()),
                attributes,
            })
        }
    }
}

/// The corners' values of PLY attribute `a` as colours: a `vertex_` one's rows by the
/// corners' vertices, a `face_` one's row (one per triangle) at all three corners.
fn corner_values(a: &ply::attributes::PlyAttribute, triangles: &[[u32; 3]]) -> Vec<[Vec3; 3]> {
    let colour = |row: usize| {
        let v = &a.values[row * a.dim..][..a.dim];
        match a.dim {
            1 => Vec3::splat(v[0]),
            _ => Vec3::new(v[0], v[1], v[2]),
        }
    };
    let per_face = a.name.starts_with("face_");
    (triangles.iter().enumerate())
        .map(|(i, t)| match per_face {
            true => [colour(i); 3],
            false => t.map(|v| colour(v as usize)),
        })
        .collect()
}

/// Vertex ids that also tell corners with other texture coordinates apart: one per distinct
/// (vertex, uv) pair.
fn split_by_uv(vertices: &[[u32; 3]], uvs: &[[Vec2; 3]]) -> Vec<[u32; 3]> {
    let mut ids = std::collections::HashMap::new();
    let mut id = |v: u32, uv: Vec2| {
        let next = ids.len() as u32;
        *ids.entry((v, uv.x.to_bits(), uv.y.to_bits()))
            .or_insert(next)
    };
    vertices
        .iter()
        .zip(uvs)
        .map(|(t, uv)| [0, 1, 2].map(|k| id(t[k], uv[k])))
        .collect()
}

/// Scales, then translates, `tris`. A scale that mirrors (negative product) also reverses
/// the winding, so that front faces stay on the same side of the surface.
pub(crate) fn transform(mut tris: Vec<[Vec3; 3]>, scale: Vec3, translate: Vec3) -> Vec<[Vec3; 3]> {
    for tri in &mut tris {
        *tri = tri.map(|p| p * scale + translate);
        if scale.x * scale.y * scale.z < 0.0 {
            tri.swap(1, 2);
        }
    }
    tris
}

/// Adds the mesh file at `path`, scaled then translated, to `builder` as one shape of
/// `surface`: smooth-shaded with the file's vertex normals unless `smooth` is `Some(false)`;
/// `Some(true)` requires the file to have them. Its texture coordinates, if any, are kept
/// with Mitsuba's default `flip_tex_coords` (v flipped for OBJ, not for PLY). A file that
/// cannot be read or used is an error on [`Part::Geometry`].
pub(crate) fn add_mesh_file(
    builder: &mut SceneBuilder,
    path: &Path,
    scale: Vec3,
    translate: Vec3,
    smooth: Option<bool>,
    surface: Surface,
    at: &dyn Locate,
) -> Result<()> {
    let format = MeshFormat::of_path(path);
    let room = builder.triangle_room();
    let mesh = load_mesh(path, format, format.flips_tex_coords(), room)
        .map_err(|m| at.error(Part::Geometry, m))?
        .flat_if(smooth == Some(false));
    if smooth == Some(true) && mesh.normals.is_none() {
        let message = format!(
            "{}: `smooth = true`, but the mesh has no vertex normals",
            path.display()
        );
        return Err(at.error(Part::Geometry, message));
    }
    // Normals through the inverse of the (diagonal) scale; the winding swap as `transform`.
    let mirrored = scale.x * scale.y * scale.z < 0.0;
    let normals = mesh
        .normals
        .map(|ns| transform_normals(ns, Mat3::from_diagonal(scale.recip()), mirrored));
    let uvs = mesh.uvs.map(|mut uvs| {
        if mirrored {
            uvs.iter_mut().for_each(|t| t.swap(1, 2));
        }
        uvs
    });
    let tris = transform(mesh.tris, scale, translate);
    match uvs {
        Some(uvs) => builder.add_uv_mesh(tris, normals, uvs, surface, at),
        None => builder.add_smooth_mesh(tris, normals, surface, at),
    }
}
