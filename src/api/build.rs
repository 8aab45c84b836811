//! [`SceneBuild`]: a [`Scene`] built in memory, without a file, through the scene builder
//! every importer feeds (`crate::scene::SceneBuilder`, which owns the rules: emission copies,
//! light power, zero-area and NaN checks, the triangle and texture budgets). For programs that
//! hold a scene themselves: the Blender add-on builds one through Python's
//! `gpu_photon.SceneBuilder`, which binds this.
//!
//! Everything is in world space and the renderer's units: metres (any unit, consistently),
//! radiance in W m^-2 sr^-1, point and spot intensity in W/sr, a directional light's
//! irradiance in W/m^2. Meshes come as vertex positions, triangles of vertex indices and
//! optional per-corner attributes (normals, uvs, tangents, as a DCC tool keeps them), with a
//! transform applied here (so that one mesh placed many times is handed over once).
//! Materials are the renderer's own kinds ([`MaterialSpec`]). Errors are
//! [`Error::Scene`](crate::Error::Scene) naming the build and the item (`NAME:0: ITEM: what`).

pub use super::build_material::{AlphaSpec, MaterialSpec, Scattering};
use super::Scene;
use crate::camera::pixel_filter::PixelFilter;
use crate::error::{Error, Result};
use crate::lights::spot::SpotFalloff;
use crate::lights::spot::SpotLight;
use crate::scene::{Locate, MaterialId, MeshId, Origin, Part, SceneBuilder, Surface};
use crate::textures::{Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap};
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// A mesh as [`SceneBuild::add_mesh`] takes it. Corner attributes hold 3 entries per
/// triangle, in the triangle's corner order.
#[derive(Clone, Copy, Debug)]
pub struct MeshSpec<'a> {
    /// Vertex positions (in the space `transform` maps to the world's).
    pub positions: &'a [[f32; 3]],
    /// Triangles: three indices into `positions` each, counter-clockwise seen from the front.
    pub triangles: &'a [[u32; 3]],
    /// The material of each triangle (indices from [`SceneBuild::add_material`]); one entry
    /// for all of them.
    pub materials: &'a [u32],
    /// Per-corner normals (smooth shading), any length but zero.
    pub normals: Option<&'a [[f32; 3]]>,
    /// Per-corner texture coordinates.
    pub uvs: Option<&'a [[f32; 2]]>,
    /// Per-corner tangents (xyz along +u; w = -1 where the bitangent `n x t` must be negated to
    /// point along +v), for normal maps; needs `uvs` and `normals`.
    pub tangents: Option<&'a [[f32; 4]]>,
    /// Object to world, a column-major 4x4 matrix (`None`: the identity). A mirroring
    /// transform keeps the front faces on their side.
    pub transform: Option<[[f32; 4]; 4]>,
}

/// The camera of a [`SceneBuild`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    /// Where the lens centre is.
    pub eye: [f32; 3],
    /// The view direction (any length but zero).
    pub forward: [f32; 3],
    /// The image's up direction (not along `forward`).
    pub up: [f32; 3],
    /// Full vertical field of view, degrees, in (0, 180).
    pub fov_y: f32,
    /// Thin-lens aperture radius (0: a pinhole), scene units.
    pub aperture_radius: f32,
    /// Distance to the plane in focus along `forward`, > 0.
    pub focus_distance: f32,
    /// `Some(h)`: an orthographic camera whose view is `h` scene units high (`fov_y`,
    /// `aperture_radius` and `focus_distance` then unused).
    pub orthographic_height: Option<f32>,
}

/// A texture of a [`SceneBuild`].
#[derive(Clone, Debug, PartialEq)]
pub struct TextureSpec {
    /// Its name, for messages.
    pub name: String,
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
    /// `width * height * 4` linear RGBA values, row by row: row 0 at v = 0, column 0 at u = 0.
    pub rgba: Vec<f32>,
    /// Bilinear (else nearest).
    pub bilinear: bool,
    /// How uv outside [0, 1] reads the image.
    pub wrap: Wrap,
}

/// A scene being built in memory; [`SceneBuild::finish`] returns it as a [`Scene`].
#[derive(Debug)]
pub struct SceneBuild {
    b: SceneBuilder,
    name: String,
    materials: Vec<MaterialId>,
    textures: u32,
    /// The meshes of [`SceneBuild::add_mesh_group`], by group index.
    groups: Vec<MeshId>,
}

impl SceneBuild {
    /// An empty scene; `name` names it in errors (and as its [`Scene::path`]).
    pub fn new(name: &str) -> Self {
        SceneBuild {
            b: SceneBuilder::new(),
            name: name.to_string(),
            materials: Vec::new(),
            textures: 0,
            groups: Vec::new(),
        }
    }

    /// The error `message` about `item`.
    fn err(&self, item: &str, message: String) -> Error {
        Error::Scene {
            file: self.name.clone(),
            line: 0,
            field: item.to_string(),
            message,
        }
    }

    /// A locator naming `item`.
    fn at(&self, item: &str) -> Origin {
        Origin {
            file: self.name.clone(),
            line: 0,
            field: item.to_string(),
        }
    }

    /// Adds a texture; returns its index for [`MaterialSpec`]s.
    pub fn add_texture(&mut self, t: TextureSpec) -> Result<u32> {
        let item = format!("textures[{}]", t.name);
        let bad = |e: Error| self.err(&item, e.to_string());
        if t.rgba.iter().any(|c| !c.is_finite()) {
            return Err(self.err(&item, "texels must be finite".into()));
        }
        let texture = Texture::from_float(&t.name, t.width, t.height, t.rgba, 4).map_err(bad)?;
        let filter = match t.bilinear {
            true => Filter::Bilinear,
            false => Filter::Nearest,
        };
        let sampler = Sampler::mitsuba(filter, t.wrap, UvTransform::IDENTITY);
        let texture = SceneTexture::Bitmap(texture.with_sampler(sampler));
        let id = self.b.add_texture(texture, &self.at(&item))?;
        self.textures = self.textures.max(id + 1);
        Ok(id)
    }

    /// Adds a material named `name` (for messages); returns its index for meshes.
    pub fn add_material(&mut self, name: &str, spec: &MaterialSpec) -> Result<u32> {
        let item = format!("materials[{name}]");
        for (t, field) in super::build_material::textures(spec) {
            if let Some(t) = t.filter(|&t| t >= self.textures) {
                let message = format!("{field}: no texture {t} (the build has {})", self.textures);
                return Err(self.err(&item, message));
            }
        }
        let material = super::build_material::material(spec).map_err(|m| self.err(&item, m))?;
        let id = self.b.add_material(None, material, &self.at(&item))?;
        self.materials.push(id);
        Ok(self.materials.len() as u32 - 1)
    }

    /// Adds a mesh named `name`: one shape per material its triangles use (an emissive one
    /// is one area light). Degenerate triangles are dropped.
    pub fn add_mesh(&mut self, name: &str, mesh: &MeshSpec) -> Result<()> {
        let item = format!("meshes[{name}]");
        let at = self.at(&item);
        let fail = |m: String| at.error(Part::Geometry, m);
        let n = mesh.triangles.len();
        let corners = 3 * n;
        let count = |len: Option<usize>, what: &str| match len {
            Some(l) if l != corners => Err(fail(format!(
                "{l} {what} for {n} triangles (one per corner: {corners})"
            ))),
            _ => Ok(()),
        };
        count(mesh.normals.map(<[_]>::len), "normals")?;
        count(mesh.uvs.map(<[_]>::len), "uvs")?;
        count(mesh.tangents.map(<[_]>::len), "tangents")?;
        if mesh.tangents.is_some() && (mesh.uvs.is_none() || mesh.normals.is_none()) {
            return Err(fail("tangents need uvs and normals".into()));
        }
        if mesh.materials.len() != n && mesh.materials.len() != 1 {
            let m = format!(
                "{} materials for {n} triangles (one, or one each)",
                mesh.materials.len()
            );
            return Err(fail(m));
        }
        if let Some(&m) = mesh
            .materials
            .iter()
            .find(|&&m| m as usize >= self.materials.len())
        {
            return Err(fail(format!(
                "no material {m} (the build has {})",
                self.materials.len()
            )));
        }
        let world = match mesh.transform {
            Some(t) => Mat4::from_cols_array_2d(&t),
            None => Mat4::IDENTITY,
        };
        if !world.is_finite() {
            return Err(fail("the transform is not finite".into()));
        }
        let linear = Mat3::from_mat4(world);
        let normal_map = linear.inverse().transpose();
        let mirrored = world.determinant() < 0.0;
        let order = |c: [usize; 3]| if mirrored { [c[0], c[2], c[1]] } else { c };
        let points: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|&p| world.transform_point3(Vec3::from(p)))
            .collect();
        // Triangles grouped by material, in the order of their first use.
        let mut groups: Vec<(u32, Vec<usize>)> = Vec::new();
        for t in 0..n {
            let m = mesh.materials[if mesh.materials.len() == 1 { 0 } else { t }];
            match groups.iter_mut().find(|(g, _)| *g == m) {
                Some((_, list)) => list.push(t),
                None => groups.push((m, vec![t])),
            }
        }
        for (m, list) in groups {
            let mut tris = Vec::with_capacity(list.len());
            let (mut normals, mut uvs, mut tangents) = (Vec::new(), Vec::new(), Vec::new());
            for t in list {
                let [a, b, c] = mesh.triangles[t];
                let p = |i: u32| {
                    points.get(i as usize).copied().ok_or_else(|| {
                        fail(format!(
                            "triangle {t}: vertex {i} is out of range ({} vertices)",
                            points.len()
                        ))
                    })
                };
                let tri = [p(a)?, p(b)?, p(c)?];
                if (tri[1] - tri[0]).cross(tri[2] - tri[0]).length_squared() == 0.0 {
                    continue;
                }
                let k = order([3 * t, 3 * t + 1, 3 * t + 2]);
                tris.push(order([0, 1, 2]).map(|i| tri[i]));
                if let Some(ns) = mesh.normals {
                    normals.push(k.map(|i| normal_map * Vec3::from(ns[i])));
                }
                if let Some(us) = mesh.uvs {
                    uvs.push(k.map(|i| Vec2::from(us[i])));
                }
                if let Some(ts) = mesh.tangents {
                    tangents.push(k.map(|i| {
                        let t = Vec4::from(ts[i]);
                        let w = if mirrored { -t.w } else { t.w };
                        (linear * t.truncate()).extend(w)
                    }));
                }
            }
            if tris.is_empty() {
                continue;
            }
            let surface = Surface {
                material: Some(self.materials[m as usize]),
                // Emission, from one side or both, is the material's own.
                ..Surface::default()
            };
            let normals = mesh.normals.map(|_| normals);
            match (mesh.uvs.is_some(), mesh.tangents.is_some()) {
                (true, true) => self
                    .b
                    .add_tangent_mesh(tris, normals, uvs, tangents, surface, &at)?,
                (true, false) => self.b.add_uv_mesh(tris, normals, uvs, surface, &at)?,
                _ => self.b.add_smooth_mesh(tris, normals, surface, &at)?,
            }
        }
        Ok(())
    }

    /// Whether material `m` (an index of [`Self::add_material`]) may be in a mesh group:
    /// neither emissive nor alpha-tested. A mesh with another material is added as copies.
    pub fn material_instanceable(&self, m: u32) -> bool {
        self.materials
            .get(m as usize)
            .is_some_and(|&id| self.b.instanceable(id))
    }

    /// Adds `mesh` (in its object space: its transform, if any, places it there) as a mesh
    /// group stored once, which [`Self::add_instance`] places; returns the group's index.
    /// Its materials must be instanceable ([`Self::material_instanceable`]).
    pub fn add_mesh_group(&mut self, name: &str, mesh: &MeshSpec) -> Result<u32> {
        let item = format!("meshes[{name}]");
        if let Some(&m) = mesh
            .materials
            .iter()
            .find(|&&m| !self.material_instanceable(m))
        {
            let message = format!(
                "material {m} emits or is alpha-tested: a mesh group cannot use it (add the \
                 mesh's copies with add_mesh)"
            );
            return Err(self.at(&item).error(Part::Geometry, message));
        }
        self.b.begin_shape_group(&self.at(&item))?;
        let added = self.add_mesh(name, mesh);
        let id = self.b.end_shape_group();
        added?;
        self.groups.push(id);
        Ok(self.groups.len() as u32 - 1)
    }

    /// Places mesh group `group` by the object-to-world `transform` (glam's column-major
    /// `[[f32; 4]; 4]`: finite, invertible, affine); `name` names it in errors. The scene
    /// stores the group's triangles once, whatever the number of its instances.
    pub fn add_instance(&mut self, name: &str, group: u32, transform: [[f32; 4]; 4]) -> Result<()> {
        let at = self.at(&format!("instances[{name}]"));
        let Some(&mesh) = self.groups.get(group as usize) else {
            let message = format!(
                "no mesh group {group} (the build has {})",
                self.groups.len()
            );
            return Err(at.error(Part::Geometry, message));
        };
        self.b
            .add_instance(mesh, Mat4::from_cols_array_2d(&transform), &at)
    }

    /// Adds an analytic sphere of `material` (an emissive one is one area light).
    pub fn add_sphere(
        &mut self,
        name: &str,
        centre: [f32; 3],
        radius: f32,
        material: u32,
    ) -> Result<()> {
        let item = format!("spheres[{name}]");
        let Some(&id) = self.materials.get(material as usize) else {
            return Err(self.err(&item, format!("no material {material}")));
        };
        let at = self.at(&item);
        self.b
            .add_sphere(Vec3::from(centre), radius, Surface::of(id), &at)
    }

    /// Adds an isotropic point light, `intensity` in W/sr per channel.
    pub fn add_point_light(
        &mut self,
        name: &str,
        position: [f32; 3],
        intensity: [f32; 3],
    ) -> Result<()> {
        let at = self.at(&format!("lights[{name}]"));
        self.b
            .add_point_light(Vec3::from(position), Vec3::from(intensity), &at)
    }

    /// Adds a spot light: `intensity` W/sr on its axis, full inside the half-angle `inner`
    /// and none outside `outer` (degrees), glTF's ramp (quadratic in the cosine) between.
    pub fn add_spot_light(
        &mut self,
        name: &str,
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        inner: f32,
        outer: f32,
    ) -> Result<()> {
        let spot = SpotLight {
            position: Vec3::from(position),
            direction: Vec3::from(direction),
            intensity: Vec3::from(intensity),
            inner,
            outer,
            falloff: SpotFalloff::Gltf,
        };
        let at = self.at(&format!("lights[{name}]"));
        self.b.add_spot_light(spot, &at)
    }

    /// Adds a directional light travelling along `direction`, `irradiance` in W/m^2 on a
    /// surface facing it.
    pub fn add_directional_light(
        &mut self,
        name: &str,
        direction: [f32; 3],
        irradiance: [f32; 3],
    ) -> Result<()> {
        let at = self.at(&format!("lights[{name}]"));
        let (d, e) = (Vec3::from(direction), Vec3::from(irradiance));
        self.b.add_directional_light(d, e, &at)
    }

    /// Sets the environment: `radiance` from every direction, or `radiance` times a lat-long
    /// image (`width * height * 3` linear RGB values, row 0 at the zenith, `u = atan2(x, -z) /
    /// 2 pi` in the map's frame, Mitsuba's `envmap`), the map's frame turned into the world by
    /// `to_world` (a rotation, column-major).
    pub fn set_environment(
        &mut self,
        radiance: [f32; 3],
        image: Option<(u32, u32, Vec<f32>)>,
        to_world: [[f32; 3]; 3],
    ) -> Result<()> {
        let item = "environment";
        let image = match image {
            Some((w, h, rgb)) => {
                if rgb.iter().any(|c| !c.is_finite()) {
                    return Err(self.err(item, "texels must be finite".into()));
                }
                let t = Texture::from_float(item, w, h, rgb, 3)
                    .map_err(|e| self.err(item, e.to_string()))?;
                Some(t)
            }
            None => None,
        };
        let to_world = Mat3::from_cols_array_2d(&to_world);
        let at = self.at(item);
        self.b
            .set_environment(Vec3::from(radiance), image, to_world, &at)
    }

    /// Sets the camera and the image size in pixels.
    pub fn set_camera(&mut self, c: &CameraSpec, width: u32, height: u32) -> Result<()> {
        let at = self.at("camera");
        let eye = Vec3::from(c.eye);
        let (target, up) = (eye + Vec3::from(c.forward), Vec3::from(c.up));
        if let Some(h) = c.orthographic_height {
            self.b.orthographic_camera(eye, target, up, 0.5 * h, &at)?;
            let s = self.b.settings();
            (s.width, s.height) = (width, height);
            return Ok(());
        }
        self.b.camera(eye, target, up, c.fov_y, &at)?;
        if !(c.aperture_radius.is_finite() && c.aperture_radius >= 0.0) {
            return Err(self.err("camera", "aperture_radius: must be >= 0 and finite".into()));
        }
        if !(c.focus_distance.is_finite() && c.focus_distance > 0.0) {
            return Err(self.err(
                "camera",
                "focus_distance: must be positive and finite".into(),
            ));
        }
        self.b
            .optics(PixelFilter::Box, c.aperture_radius, c.focus_distance);
        let s = self.b.settings();
        (s.width, s.height) = (width, height);
        Ok(())
    }

    /// The scene. Without a camera, an error on `camera`; without any light (no emitter,
    /// light or environment), [`Error::NoLight`].
    pub fn finish(self) -> Result<Scene> {
        let at = self.at("camera");
        let mut scene = self.b.finish(&at)?;
        scene.scale_default_radii([false; 3]);
        let path = std::path::PathBuf::from(&self.name);
        crate::lights::environment::setup::require_light(&scene, &path)?;
        Ok(Scene::built(scene, path))
    }
}
