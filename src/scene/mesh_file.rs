//! Mesh files named by a scene: OBJ ([`super::obj`]) or PLY ([`super::ply`]), read to
//! world-space triangles. Every importer that refers to a mesh file (the TOML `type = "mesh"`
//! shape, Mitsuba's `obj` and `ply` shapes) reads it here.

use super::builder::{SceneBuilder, Surface};
use super::locate::{Locate, Part};
use super::{obj, ply};
use crate::error::Result;
use glam::Vec3;
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
}

/// The triangles of the mesh file at `path`, in the file's coordinates. Errors are messages
/// naming the resolved path (for PLY, the [`ply::PlyError`]).
pub(crate) fn load_triangles(path: &Path, format: MeshFormat) -> Result<Vec<[Vec3; 3]>, String> {
    match format {
        MeshFormat::Obj => obj::load_triangles(path),
        MeshFormat::Ply => ply::read_ply(path)
            .map(|mesh| mesh.triangle_positions())
            .map_err(|e| e.to_string()),
    }
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
/// `surface`. A file that cannot be read or used is an error on [`Part::Geometry`].
pub(crate) fn add_mesh_file(
    builder: &mut SceneBuilder,
    path: &Path,
    scale: Vec3,
    translate: Vec3,
    surface: Surface,
    at: &dyn Locate,
) -> Result<()> {
    let tris =
        load_triangles(path, MeshFormat::of_path(path)).map_err(|m| at.error(Part::Geometry, m))?;
    builder.add_mesh(transform(tris, scale, translate), surface, at)
}
