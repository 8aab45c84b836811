//! glTF 2.0 scenes (`.gltf` with embedded or external buffers, `.glb`), read with the `gltf`
//! crate and fed to the [`SceneBuilder`]. The mapping (units, materials, what is unsupported)
//! is documented in `scenes/README.md`.
//!
//! The default scene (else the first) is walked from its root nodes; every node's world
//! transform is its parents' times its own (matrix or TRS), so instanced meshes appear once
//! per node (a mesh named at several places is stored once and instanced, `mesh_groups.rs`).
//! Each primitive (triangles, strips, fans; indexed or not) becomes one shape, and
//! a transform that mirrors reverses the winding so front faces stay on the same side. Vertex
//! normals (`NORMAL`, through the inverse transpose of the world matrix) make a primitive
//! smooth-shaded; without them it is flat. Texture coordinates (`TEXCOORD_n`, n the set the
//! material's textures read, `material::uv_texture`, else 0) are kept as glTF gives them
//! (uv (0, 0) at the image's top-left, as ours). Materials and their textures are added by
//! `surface.rs`. The camera is the first met in the traversal, or the one named; without
//! one, the Khronos glTF-Sample-Viewer's default view of the scene's bounds
//! ([`crate::camera::fit_view`]); `KHR_lights_punctual` lights are converted from photometric units at
//! 683 lm/W (point and spot from candela to W/sr, directional from lux to W/m^2), spot and
//! directional lights shining along their node's -Z axis. Errors are [`Error::Scene`]
//! naming the file, the JSON line of the item (0 where
//! unknown) and its field path; warnings (a volume rendered thin-walled, textures not read,
//! uv sets) go to stderr.

mod data;
mod instances;
mod json_line;
mod material;
mod mesh_groups;
mod refs;
mod surface;
mod tangents;
mod texture;

use crate::camera::{fit_view, DEFAULT_FOV_Y};
use crate::error::{Error, Result};
use crate::importers::file;
use crate::lights::spot::SpotFalloff;
use crate::lights::spot::SpotLight;
use crate::scene::builder::{MaterialId, SceneBuilder, Surface};
use crate::scene::locate::Part;
use crate::scene::Scene;
use glam::{Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;
use gltf::mesh::Mode;
use std::collections::HashMap;
use std::path::Path;

/// Luminous efficacy used to convert photometric light units: `I [W/sr] = I [cd] / 683`.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// The image height when the camera gives only an aspect ratio.
pub const DEFAULT_HEIGHT: u32 = 256;

/// Deepest node nesting accepted (deeper is taken for a cycle).
const MAX_DEPTH: usize = 256;

/// Most node instances unfolded from the scene's roots: nodes shared by several parents
/// (a DAG) are visited once per path, which doubles with every level of `[n, n]` children.
pub const MAX_NODE_INSTANCES: usize = 1_000_000;

/// Loads the glTF or GLB file at `path`; `camera` picks a camera by name (else the first in
/// the scene's node traversal). External buffers are relative to the file's directory.
///
/// An unreadable file is [`Error::Io`]; anything wrong inside is [`Error::Scene`].
pub fn load_gltf(path: &Path, camera: Option<&str>) -> Result<Scene> {
    let bytes = file::read_bytes(path)?;
    load_slice(
        &bytes,
        &path.display().to_string(),
        file::base_dir(path),
        camera,
    )
}

/// Loads a glTF (JSON) or GLB file from `bytes`; `file` names it in errors, external buffers
/// are relative to `base_dir`. See [`load_gltf`].
pub fn load_slice(
    bytes: &[u8],
    file: &str,
    base_dir: &Path,
    camera: Option<&str>,
) -> Result<Scene> {
    let cx = Ctx {
        file,
        json: json_text(bytes),
    };
    // Indices and camera types are checked on the raw JSON first: the crate panics on some
    // and wraps others. JSON that does not parse is refused here, with its line, as the
    // crate would: it reads some such text (a number past f64 in a member it skips, as a
    // misspelt `accessors`), unchecked, and then panicked in its validation. A GLB whose
    // container hides its JSON is left to the crate to report.
    match serde_json::from_str(&cx.json) {
        Ok(json) => refs::check(&json).map_err(|(field, m)| cx.err(&field, m))?,
        Err(e) if !cx.json.is_empty() => return Err(cx.parse_error(gltf::Error::Deserialize(e))),
        Err(_) => {}
    }
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| cx.parse_error(e))?;
    let budget = crate::scene::SceneBudgets::default().max_bytes;
    let buffers = data::load_buffers(&gltf.document, gltf.blob.as_deref(), base_dir, budget)
        .map_err(|(field, m)| cx.err(&field, m))?;
    let doc = &gltf.document;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| cx.err("scenes", "the file has no scene".into()))?;
    let mut im = Importer {
        cx: &cx,
        buffers,
        base_dir,
        b: SceneBuilder::new(),
        materials: HashMap::new(),
        camera,
        has_camera: false,
        warned: Vec::new(),
        instances: 0,
        placed: Default::default(),
        mesh_groups: Default::default(),
    };
    // Which meshes are instanced, then what every node instance will cost, checked before
    // the first is built.
    im.count_mesh_uses(&scene);
    im.check_instances(&scene)?;
    for node in scene.nodes() {
        im.node(&node, Mat4::IDENTITY, 0)?;
    }
    if let (Some(name), false) = (camera, im.has_camera) {
        return Err(cx.err("cameras", format!("no camera named `{name}` in the scene")));
    }
    let at = |_: Part, m: String| cx.err("cameras", m);
    // No camera: the glTF-Sample-Viewer's default view of the scene's bounds.
    if let (false, Some((min, max))) = (im.has_camera, im.b.bounds()) {
        let s = im.b.settings();
        let (eye, target) = fit_view(min, max, s.width as f32 / s.height as f32);
        im.b.camera(eye, target, Vec3::Y, DEFAULT_FOV_Y, &at)?;
    }
    let mut scene = im.b.finish(&at)?;
    scene.scale_default_radii([false; 3]);
    if scene.lights.is_empty() {
        // Most models carry no light: viewers (the Khronos Sample Viewer, Blender) light them
        // with an environment. Ours is uniform white, so a surface shows its albedo.
        scene.set_environment(crate::lights::environment::Environment::constant(
            DEFAULT_ENVIRONMENT,
        ));
        crate::warning::warn(format!(
            "{file}: no light in the scene: lit by a uniform white environment of radiance {} \
             (as model viewers light a model; --env replaces it)",
            DEFAULT_ENVIRONMENT.x
        ));
    }
    Ok(scene)
}

/// The radiance of the environment that lights a glTF scene without lights.
pub const DEFAULT_ENVIRONMENT: Vec3 = Vec3::ONE;

/// The file's name and JSON text (for the line of an item).
struct Ctx<'a> {
    file: &'a str,
    json: String,
}

impl Ctx<'_> {
    /// The error `message` about the item at `field`.
    fn err(&self, field: &str, message: String) -> Error {
        Error::Scene {
            file: self.file.to_string(),
            line: json_line::line_of(&self.json, field),
            field: field.to_string(),
            message,
        }
    }

    fn parse_error(&self, e: gltf::Error) -> Error {
        match e {
            gltf::Error::Deserialize(e) => Error::Scene {
                file: self.file.to_string(),
                line: e.line(),
                field: "json".into(),
                message: e.to_string(),
            },
            gltf::Error::Validation(errors) => {
                let (path, e) = &errors[0];
                let more = match errors.len() {
                    1 => String::new(),
                    n => format!(" (and {} more problems)", n - 1),
                };
                self.err(&path.to_string(), format!("{e}{more}"))
            }
            gltf::Error::Binary(e) => self.err("glb", format!("malformed GLB: {e}")),
            e => self.err("gltf", e.to_string()),
        }
    }
}

/// The JSON text of a glTF file or of a GLB's JSON chunk (empty when there is none).
fn json_text(bytes: &[u8]) -> String {
    let json = match bytes.get(..4) {
        Some(b"glTF") => bytes
            .get(12..16)
            .map(|n| u32::from_le_bytes([n[0], n[1], n[2], n[3]]) as usize)
            .and_then(|n| bytes.get(20..20 + n))
            .unwrap_or(&[]),
        _ => bytes,
    };
    String::from_utf8_lossy(json).into_owned()
}

struct Importer<'a> {
    cx: &'a Ctx<'a>,
    buffers: Vec<Vec<u8>>,
    /// Where external images are.
    base_dir: &'a Path,
    b: SceneBuilder,
    /// glTF material index (None: the default material) to ours.
    materials: HashMap<Option<usize>, MaterialId>,
    camera: Option<&'a str>,
    has_camera: bool,
    /// Textures already warned about.
    warned: Vec<String>,
    /// Node instances visited so far (bounded by [`MAX_NODE_INSTANCES`]).
    instances: usize,
    /// The places of the instances built so far, and the nodes warned about a copy
    /// (`instances.rs`).
    placed: instances::Placed,
    /// The meshes stored once and instanced (`mesh_groups.rs`).
    mesh_groups: mesh_groups::MeshGroups,
}

impl Importer<'_> {
    fn node(&mut self, node: &gltf::Node, parent: Mat4, depth: usize) -> Result<()> {
        let field = format!("nodes[{}]", node.index());
        if depth > MAX_DEPTH {
            let message = format!("nodes nested deeper than {MAX_DEPTH} (a cycle?)");
            return Err(self.cx.err(&field, message));
        }
        self.instances += 1;
        if self.instances > MAX_NODE_INSTANCES {
            let message = format!(
                "the scene unfolds to more than {MAX_NODE_INSTANCES} node instances \
                 (nodes shared by several parents are instanced once per path)"
            );
            return Err(self.cx.err(&field, message));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(self.cx.err(&field, "the transform is not finite".into()));
        }
        // A copy of an earlier instance, at its very place, adds nothing but work.
        if self.first_at(node, world) {
            if let Some(camera) = node.camera() {
                self.camera(&camera, world)?;
            }
            if let Some(light) = node.light() {
                self.light(&light, world)?;
            }
            if let Some(mesh) = node.mesh() {
                if !self.place_instance(&mesh, world)? {
                    for primitive in mesh.primitives() {
                        self.primitive(&mesh, &primitive, world)?;
                    }
                }
            }
        }
        for child in node.children() {
            self.node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn camera(&mut self, camera: &gltf::Camera, world: Mat4) -> Result<()> {
        let wanted = match self.camera {
            Some(name) => camera.name() == Some(name),
            None => !self.has_camera,
        };
        if !wanted || self.has_camera {
            return Ok(());
        }
        let field = format!("cameras[{}]", camera.index());
        let gltf::camera::Projection::Perspective(p) = camera.projection() else {
            let message = "unsupported orthographic camera".into();
            return Err(self.cx.err(&field, message));
        };
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(-Vec3::Z);
        let up = world.transform_vector3(Vec3::Y);
        let at = |_: Part, m: String| self.cx.err(&field, m);
        self.b
            .camera(eye, eye + forward, up, p.yfov().to_degrees(), &at)?;
        if let Some(aspect) = p.aspect_ratio() {
            if !(aspect.is_finite() && aspect > 0.0) {
                return Err(self.cx.err(&field, "aspectRatio must be positive".into()));
            }
            let width = (DEFAULT_HEIGHT as f32 * aspect).round().max(1.0) as u32;
            let s = self.b.settings();
            (s.width, s.height) = (width, DEFAULT_HEIGHT);
        }
        self.has_camera = true;
        Ok(())
    }

    fn light(&mut self, light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Result<()> {
        let field = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
        let name = light
            .name()
            .map_or(format!("lights[{}]", light.index()), str::to_string);
        // Point and spot in candela, directional in lux: both / 683 to W/sr and W/m^2.
        let position = world.transform_point3(Vec3::ZERO);
        let intensity = Vec3::from(light.color()) * light.intensity() / LUMENS_PER_WATT;
        // Spot and directional lights point along the node's -Z axis.
        let direction = world.transform_vector3(-Vec3::Z);
        let at = |part: Part, m: String| {
            let what = match part {
                Part::Parameter("inner_angle") => "spot.innerConeAngle (in degrees): ",
                Part::Parameter("outer_angle") => "spot.outerConeAngle (in degrees): ",
                Part::Parameter("direction") => "direction (the node's -Z axis): ",
                _ => "",
            };
            self.cx.err(&field, format!("light {name}: {what}{m}"))
        };
        match light.kind() {
            Kind::Point => self.b.add_point_light(position, intensity, &at),
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let spot = SpotLight {
                    position,
                    direction,
                    intensity,
                    inner: inner_cone_angle.to_degrees(),
                    outer: outer_cone_angle.to_degrees(),
                    falloff: SpotFalloff::Gltf,
                };
                self.b.add_spot_light(spot, &at)
            }
            Kind::Directional => self.b.add_directional_light(direction, intensity, &at),
        }
    }

    fn primitive(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        world: Mat4,
    ) -> Result<()> {
        let field = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
        let fail = |m: String| self.cx.err(&field, m);
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            return Err(fail("has no POSITION attribute".into()));
        };
        let points = data::read_positions(&positions, &self.buffers).map_err(&fail)?;
        let normals = match primitive.get(&gltf::Semantic::Normals) {
            Some(a) => Some(data::read_normals(&a, &self.buffers).map_err(&fail)?),
            None => None,
        };
        if let Some(n) = normals.as_ref().filter(|n| n.len() != points.len()) {
            let message = format!("{} NORMALs for {} POSITIONs", n.len(), points.len());
            return Err(fail(message));
        }
        // The uv set the material's textures read (TEXCOORD_0 without one).
        let texture = material::uv_texture(&primitive.material());
        let set = texture.map_or(0, |(set, _)| set);
        let uvs = match primitive.get(&gltf::Semantic::TexCoords(set)) {
            Some(a) => {
                let name = format!("TEXCOORD_{set}");
                Some(data::read_uvs(&a, &self.buffers, &name).map_err(&fail)?)
            }
            None if texture.is_some() => {
                let slot = texture.map_or("", |(_, slot)| slot);
                let message =
                    format!("has no TEXCOORD_{set} attribute, which its material's {slot} reads");
                return Err(fail(message));
            }
            None => None,
        };
        if let Some(uv) = uvs.as_ref().filter(|uv| uv.len() != points.len()) {
            let message = format!(
                "{} TEXCOORD_{set}s for {} POSITIONs",
                uv.len(),
                points.len()
            );
            return Err(fail(message));
        }
        // Normals go through the inverse transpose of the node's matrix.
        let normal_map = glam::Mat3::from_mat4(world).inverse().transpose();
        let indices = match primitive.indices() {
            Some(a) => data::read_indices(&a, &self.buffers).map_err(&fail)?,
            None => (0..points.len() as u32).collect(),
        };
        let corners: Vec<[u32; 3]> = match primitive.mode() {
            Mode::Triangles => indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect(),
            Mode::TriangleStrip => (2..indices.len())
                .map(|i| {
                    let (a, b, c) = (indices[i - 2], indices[i - 1], indices[i]);
                    if i % 2 == 0 {
                        [a, b, c]
                    } else {
                        [b, a, c]
                    }
                })
                .collect(),
            Mode::TriangleFan => (2..indices.len())
                .map(|i| [indices[0], indices[i - 1], indices[i]])
                .collect(),
            other => {
                let m = format!("{other:?} primitives are skipped (only triangles are rendered)");
                crate::warning::warn(format!("{}: {field}: {m}", self.cx.file));
                return Ok(());
            }
        };
        let mirrored = world.determinant() < 0.0;
        let mut tris = Vec::with_capacity(corners.len());
        let mut shading = Vec::with_capacity(normals.as_ref().map_or(0, |_| corners.len()));
        let mut corner_uvs = Vec::with_capacity(uvs.as_ref().map_or(0, |_| corners.len()));
        for (t, c) in corners.iter().enumerate() {
            let p = |i: u32| {
                let p = points.get(i as usize).ok_or_else(|| {
                    fail(format!(
                        "triangle {t}: index {i} is out of range ({} vertices)",
                        points.len()
                    ))
                })?;
                Ok::<_, Error>(world.transform_point3(*p))
            };
            let (a, b, c) = (p(c[0])?, p(c[1])?, p(c[2])?);
            tris.push(if mirrored { [a, c, b] } else { [a, b, c] });
            if let Some(normals) = &normals {
                // In range: the indices were checked against the positions, as many.
                let n = corners[t].map(|i| normal_map * normals[i as usize]);
                shading.push(if mirrored { [n[0], n[2], n[1]] } else { n });
            }
            if let Some(uvs) = &uvs {
                // In range: as many as the positions.
                let uv = corners[t].map(|i| uvs[i as usize]);
                corner_uvs.push(if mirrored { [uv[0], uv[2], uv[1]] } else { uv });
            }
        }
        if tris.is_empty() {
            return Ok(());
        }
        // Vertex tangents where a normal texture needs them (uvs and normals present).
        let tangents = match (&normals, &uvs) {
            (Some(normals), Some(uvs)) if primitive.material().normal_texture().is_some() => {
                let v = tangents::Vertices {
                    points: &points,
                    normals,
                    uvs,
                    corners: &corners,
                };
                tangents::primitive_tangents(primitive, &self.buffers, &v, world).map_err(&fail)?
            }
            (None, Some(_)) if primitive.material().normal_texture().is_some() => {
                tangents::face_tangents(&tris, &corner_uvs)
            }
            _ => vec![],
        };
        let material = self.material(&primitive.material())?;
        let at = |_: Part, m: String| self.cx.err(&field, m);
        let shading = normals.map(|_| shading);
        let surface = Surface::of(material);
        match uvs {
            Some(_) if !tangents.is_empty() => {
                (self.b).add_tangent_mesh(tris, shading, corner_uvs, tangents, surface, &at)
            }
            Some(_) => self.b.add_uv_mesh(tris, shading, corner_uvs, surface, &at),
            None => self.b.add_smooth_mesh(tris, shading, surface, &at),
        }
    }
}
