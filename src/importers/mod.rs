//! The scene importers, one folder (or file) per format: TOML, Mitsuba 3 XML, glTF 2.0, PLY
//! and OBJ meshes. Each reads its files (bounded reads: `read`, `file`) and feeds the one
//! scene builder (`crate::scene::SceneBuilder`).

pub mod file;
pub mod gltf;
pub mod mesh_file;
pub mod mitsuba;
pub mod obj;
pub mod ply;
pub mod read;
pub mod toml;
pub mod vertex_normals;

pub use gltf::load_gltf;
pub use toml::load_str;

use crate::error::{Error, Result};
use crate::scene::Scene;
use std::path::Path;

/// Reads and loads the scene file at `path`, by its extension: `.toml` (our format, see
/// `scenes/README.md`), `.xml` (Mitsuba 3, see [`mitsuba`]) or `.gltf`/`.glb` (glTF 2.0, see
/// [`gltf::load_gltf`]). An unreadable file, or one of another extension, is [`Error::Io`];
/// everything wrong inside it is [`Error::Scene`].
pub fn load(path: &Path) -> Result<Scene> {
    load_with_camera(path, None)
}

/// [`load()`], with `camera` naming the glTF camera to render from (the command line's
/// `--camera`); a name for a scene of another format, which has one camera, is an
/// [`Error::Setting`].
pub fn load_with_camera(path: &Path, camera: Option<&str>) -> Result<Scene> {
    load_with_options(path, camera, &[])
}

/// [`load_with_camera`], with Mitsuba parameters `(NAME, VALUE)` for `$NAME` that override
/// the file's `<default>`s (the command line's `--define`); defines for a scene of another
/// format, which has no parameters, are an [`Error::Setting`].
pub fn load_with_options(
    path: &Path,
    camera: Option<&str>,
    defines: &[(String, String)],
) -> Result<Scene> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let gltf = matches!(ext.as_deref(), Some("gltf" | "glb"));
    if let (Some(_), false) = (camera, gltf) {
        return Err(Error::Setting {
            field: "camera",
            message: format!(
                "{} has one camera; --camera picks among a glTF scene's cameras",
                path.display()
            ),
        });
    }
    if let (Some((name, _)), false) = (defines.first(), ext.as_deref() == Some("xml")) {
        return Err(Error::Setting {
            field: "define",
            message: format!(
                "{} has no parameters: --define {name}=... sets a Mitsuba .xml scene's $name",
                path.display()
            ),
        });
    }
    match ext.as_deref() {
        Some("toml") => toml::load(path),
        Some("xml") => mitsuba::load_with_defines(path, defines),
        Some("gltf" | "glb") => gltf::load_gltf(path, camera),
        _ => Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "unknown scene format (expected .toml, Mitsuba .xml, or glTF .gltf/.glb)",
            ),
        }),
    }
}
