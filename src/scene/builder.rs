//! The rules of building a [`Scene`], shared by every importer: the TOML scene files
//! (`importers/toml/`), Mitsuba 3 XML, glTF 2.0, PLY and OBJ meshes.
//!
//! An importer reads its format and calls a [`SceneBuilder`]: materials (named or not),
//! shapes with a [`Surface`] (a material and optionally the shape's own emission), point
//! lights, the camera and the settings; [`SceneBuilder::finish`] returns the scene. The
//! builder owns the rules:
//! - a shape whose emission (or two-sidedness) differs from its material's gets its own copy
//!   of the material, appended to the materials;
//! - every emissive shape becomes **one** area light, in the order shapes are added: a
//!   sphere's light is the sphere, any other shape's is its triangles, stored contiguously;
//!   the light's power is `pi * area * radiance` (doubled when two-sided); the lights without
//!   a surface are added by their kinds' calls (`src/lights/*/build.rs`), which set their
//!   power, a directional light's here once the scene's extent is known (`irradiance * pi R^2`
//!   with R the radius of the finished scene's [`Scene::bounding_sphere`]);
//! - a mesh may come with vertex normals (smooth shading): each set is normalised and stored
//!   in [`Scene::shading_normals`], unless it lies along the face normal (then flat);
//! - an emissive shape must have a positive area and finite power; vertices must be finite;
//!   `two_sided` only applies to emissive surfaces. A call that fails changes nothing, so an
//!   importer may skip what it cannot use and go on.
//!
//! The calls for shapes are in `shape_build.rs`, for SDF grids in `sdf_build.rs` and for
//! shape groups in `group_build.rs`. The builder never knows the file format. Every call that can fail takes a [`Locate`],
//! which turns a message about one [`Part`] of what is added into an [`Error::Scene`](crate::Error::Scene) naming
//! the file, line and field (a TOML table maps each part to its key; [`Origin`](crate::scene::Origin) names one
//! fixed place).

use crate::bsdfs::blend::{Blend, MAX_BLEND_DEPTH};
use crate::camera::pixel_filter::PixelFilter;
use crate::camera::Camera;
use crate::error::Result;
use crate::scene::checks::{check_emission, check_material, SceneBudgets};
use crate::scene::locate::{unknown_name, Locate, Part};
use crate::scene::{
    Light, LightShape, Material, Scene, Sphere, Triangle, VertexNormals, NO_TEXTURE,
};
use crate::settings::RenderSettings;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::f32::consts::PI;

/// A material of the scene being built, as [`SceneBuilder::add_material`] returns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialId(u32);

impl MaterialId {
    /// Index into [`Scene::materials`].
    pub fn index(self) -> u32 {
        self.0
    }
}

/// What a shape is made of: a material and, optionally, its own emission.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Surface {
    /// The material; `None` is a black surface that reflects nothing.
    pub material: Option<MaterialId>,
    /// Radiance emitted from the front face, replacing the material's (components >= 0).
    pub emission: Option<Vec3>,
    /// Emission from both faces, replacing the material's setting; only for emissive surfaces.
    pub two_sided: Option<bool>,
    /// A texture (from [`SceneBuilder::add_texture`]) multiplying the emission at each point
    /// (`Material::emission_texture`); only for emissive surfaces.
    pub emission_texture: Option<u32>,
    /// The media the shape bounds ([`SceneBuilder::add_medium`]), replacing the material's.
    pub media: Option<crate::media::MediumInterface>,
}

impl Surface {
    /// A surface of `material`, emitting what the material emits.
    pub fn of(material: MaterialId) -> Self {
        Surface {
            material: Some(material),
            ..Self::default()
        }
    }
    /// A black surface emitting `radiance` from its front face.
    pub fn emitting(radiance: Vec3) -> Self {
        Surface {
            emission: Some(radiance),
            ..Self::default()
        }
    }
}

/// Builds a [`Scene`] by the rules in the module documentation.
#[derive(Debug, Default)]
pub struct SceneBuilder {
    camera: Option<Camera>,
    pub(super) materials: Vec<Material>,
    names: HashMap<String, MaterialId>,
    pub(crate) triangles: Vec<Triangle>,
    pub(super) shading_normals: Vec<VertexNormals>,
    pub(super) uvs: Vec<[Vec2; 3]>,
    pub(crate) tangents: Vec<crate::scene::VertexTangents>,
    pub(crate) textures: Vec<SceneTexture>,
    pub(crate) spheres: Vec<Sphere>,
    pub(crate) sdf_grids: Vec<super::sdf_grid::SdfGrid>,
    pub(crate) lights: Vec<Light>,
    pub(crate) environment: Option<crate::scene::Environment>,
    pub(crate) media: crate::media::builder::Media,
    settings: RenderSettings,
    optics: Option<(PixelFilter, f32, f32)>,
    pub(super) budgets: SceneBudgets,
    /// The world geometry set aside while a shape group is recorded (`instances.rs`).
    pub(super) group: Option<super::instances::GroupStash>,
    /// The meshes of shape groups and their instances.
    pub(super) instancing: super::instances::Instancing,
}

impl SceneBuilder {
    /// An empty scene: no camera yet, default settings.
    pub fn new() -> Self {
        Self::default()
    }

    /// Replaces the scene's budgets (what it may hold; [`SceneBudgets::default`] until set).
    pub fn set_budgets(&mut self, budgets: SceneBudgets) {
        self.budgets = budgets;
    }

    /// The render settings the scene will carry (defaults until changed).
    pub fn settings(&mut self) -> &mut RenderSettings {
        &mut self.settings
    }

    /// Sets the camera: at `eye`, looking at `target`, `fov` degrees of vertical field of view
    /// in (0, 180). A degenerate frame (eye at the target, up along the view) is an error.
    pub fn camera(
        &mut self,
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov: f32,
        at: &dyn Locate,
    ) -> Result<()> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            let message = "the camera's eye, target and up must be finite";
            return Err(at.error(Part::Eye, message.into()));
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(at.error(Part::Fov, "must be in (0, 180) degrees".into()));
        }
        let camera = Camera::look_at(eye, target, up, fov).ok_or_else(|| {
            if target == eye {
                let message = "degenerate camera frame (eye equals target)";
                at.error(Part::Eye, message.into())
            } else {
                let message = "degenerate camera frame (up is parallel to the view)";
                at.error(Part::Up, message.into())
            }
        })?;
        self.camera = Some(camera);
        Ok(())
    }

    /// Sets an orthographic camera (`Camera::orthographic`: parallel rays along the view) at
    /// `eye` looking at `target`, its view `half_height` scene units from the centre to the top
    /// edge (> 0; the width follows the image's aspect). Errors as [`SceneBuilder::camera`]'s,
    /// the half-height's on [`Part::Fov`].
    pub fn orthographic_camera(
        &mut self,
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        half_height: f32,
        at: &dyn Locate,
    ) -> Result<()> {
        if !(half_height.is_finite() && half_height > 0.0) {
            let message = format!("the view's half-height must be positive (got {half_height})");
            return Err(at.error(Part::Fov, message));
        }
        // The frame's checks and messages are the perspective camera's.
        self.camera(eye, target, up, 90.0, at)?;
        self.camera = Camera::orthographic(eye, target, up, half_height);
        Ok(())
    }

    /// The camera's pixel filter, aperture radius (0: a pinhole) and focus distance, which
    /// `finish` gives the camera (checked by the importer that read them).
    pub fn optics(&mut self, filter: PixelFilter, aperture_radius: f32, focus_distance: f32) {
        self.optics = Some((filter, aperture_radius, focus_distance));
    }

    /// Adds `material` (materials get indices in the order they are added); with a `name`,
    /// shapes may find it by [`SceneBuilder::material_named`] (a later one of the same name
    /// replaces it there). Reflectances must be in [0, 1] with kd + ks <= 1 (energy
    /// conservation), the Phong exponent >= 0, the index of refraction positive, emission
    /// >= 0; all finite. Errors are on [`Part::Parameter`].
    pub fn add_material(
        &mut self,
        name: Option<&str>,
        material: Material,
        at: &dyn Locate,
    ) -> Result<MaterialId> {
        check_material(&material, at)?;
        if let Some(b) = material.blend {
            self.check_blend(&b, at)?;
        }
        let id = self.push_material(material);
        if let Some(name) = name {
            self.names.insert(name.to_string(), id);
        }
        Ok(id)
    }

    /// Adds the blend of `first` and `second` (Mitsuba's `blendbsdf`,
    /// `crate::bsdfs::blend`): `second` with probability `weight` (its first number, a
    /// constant or a texture channel, clamped to [0, 1]), else `first`. Both must have been
    /// added; blends nest up to `MAX_BLEND_DEPTH` deep.
    pub fn add_blend(
        &mut self,
        first: MaterialId,
        second: MaterialId,
        weight: crate::bsdfs::Param,
        at: &dyn Locate,
    ) -> Result<MaterialId> {
        let Some(blend) = Blend::new(first.0, second.0, weight, &self.materials) else {
            return Err(at.error(Part::Material, "a blend of unknown materials".into()));
        };
        let material = Material {
            bsdf: self.materials[first.0 as usize].bsdf,
            blend: Some(blend),
            ..Material::black()
        };
        self.add_material(None, material, at)
    }

    /// A blend is [`Blend::new`]'s of its components (which exist; its derived fields are
    /// theirs), its weight is finite (its texture too) and the nest is at most
    /// `MAX_BLEND_DEPTH` deep.
    fn check_blend(&self, b: &Blend, at: &dyn Locate) -> Result<()> {
        // Components are added before their blends, so a nest has no cycle.
        let Some(made) = Blend::new(b.first, b.second, b.weight, &self.materials) else {
            return Err(at.error(Part::Material, "a blend of unknown materials".into()));
        };
        if made != *b {
            let message = "a blend's derived fields must be its components' (Blend::new)";
            return Err(at.error(Part::Material, message.into()));
        }
        let w = b.weight;
        let texture_ok = w.texture == NO_TEXTURE || (w.texture as usize) < self.textures.len();
        if !w.value.is_finite() || !texture_ok {
            let message = "a blend's weight must be finite (its texture one of the scene's)";
            return Err(at.error(Part::Parameter("weight"), message.into()));
        }
        if b.depth > MAX_BLEND_DEPTH {
            let message = format!("blends nested deeper than {MAX_BLEND_DEPTH}");
            return Err(at.error(Part::Material, message));
        }
        Ok(())
    }

    fn push_material(&mut self, material: Material) -> MaterialId {
        self.materials.push(material);
        MaterialId(self.materials.len() as u32 - 1)
    }

    /// The material called `name`; an unknown name is an error on [`Part::Material`] that
    /// lists the names defined.
    pub fn material_named(&self, name: &str, at: &dyn Locate) -> Result<MaterialId> {
        if let Some(&id) = self.names.get(name) {
            return Ok(id);
        }
        let message = unknown_name("material", name, self.names.keys());
        Err(at.error(Part::Material, message))
    }

    /// Adds a texture that materials can refer to by the index returned; past the scene's
    /// texture budget ([`SceneBudgets::max_texture_bytes`]) it is an error at `at`.
    pub fn add_texture(&mut self, texture: SceneTexture, at: &dyn Locate) -> Result<u32> {
        let have = self.textures.iter().map(SceneTexture::bytes).sum();
        (self.budgets).check_texels(have, texture.bytes(), self.geometry(), at)?;
        self.textures.push(texture);
        Ok(self.textures.len() as u32 - 1)
    }

    /// The texture added as `id` by [`add_texture`](Self::add_texture).
    pub fn texture(&self, id: u32) -> &SceneTexture {
        &self.textures[id as usize]
    }

    /// The scene; without a camera, an error on [`Part::Camera`]. Directional lights get
    /// their power here: `irradiance * pi R^2`, R the radius of [`Scene::bounding_sphere`].
    pub fn finish(mut self, at: &dyn Locate) -> Result<Scene> {
        let Some(mut camera) = self.camera else {
            return Err(at.error(Part::Camera, "the scene has no camera".into()));
        };
        if self.group.is_some() {
            self.end_shape_group();
        }
        if let Some((filter, aperture, focus)) = self.optics {
            (camera.filter, camera.aperture_radius, camera.focus_distance) =
                (filter, aperture, focus);
        }
        if !self.uvs.is_empty() {
            self.uvs.resize(self.triangles.len(), [Vec2::ZERO; 3]);
        }
        if !self.tangents.is_empty() {
            self.tangents
                .resize(self.triangles.len(), Default::default());
        }
        let mut scene = Scene {
            camera,
            materials: self.materials,
            triangles: self.triangles,
            shading_normals: self.shading_normals,
            uvs: self.uvs,
            tangents: self.tangents,
            textures: self.textures,
            spheres: self.spheres,
            sdf_grids: self.sdf_grids,
            lights: self.lights,
            media: self.media.media,
            camera_medium: self.media.camera,
            outer_medium: self.media.camera,
            settings: self.settings,
            instancing: self.instancing,
        };
        scene.outer_medium = scene.medium_outside();
        // A textured emitter's power includes its texture's mean (crate::lights::emission).
        for l in 0..scene.lights.len() {
            let mean = crate::lights::emission::texture_mean(&scene, l);
            scene.lights[l].power *= mean;
        }
        let (_, radius) = scene.bounding_sphere();
        for l in &mut scene.lights {
            if let LightShape::Directional(d) = l.shape {
                let irradiance = d.irradiance;
                l.power = irradiance * (PI * radius * radius);
            }
        }
        if let Some(env) = self.environment {
            scene.set_environment(env);
        }
        Ok(scene)
    }

    /// The material a shape of `surface` gets, and its radiance; changes nothing yet (a
    /// shape that fails its checks leaves no trace).
    pub(super) fn resolve(&self, surface: Surface, at: &dyn Locate) -> Result<Resolved> {
        if let Some(emission) = surface.emission {
            check_emission(emission, at)?;
        }
        let black = Material::black();
        let index = surface.material.map(MaterialId::index);
        let base = match index {
            Some(i) => *self.materials.get(i as usize).unwrap_or(&black),
            None => black,
        };
        let mut material = base;
        material.emission = surface.emission.unwrap_or(base.emission);
        if self.group.is_some() && material.is_emissive() {
            let message = "an emitter in a shape group (instancing of emitters is not \
                           supported, as in Mitsuba)";
            return Err(at.error(Part::Emission, message.into()));
        }
        if let Some(t) = surface.emission_texture {
            if !material.is_emissive() || t as usize >= self.textures.len() {
                let message = "an emission texture needs an emissive shape and a texture";
                return Err(at.error(Part::Emission, message.into()));
            }
            material.emission_texture = t;
        }
        material.media = surface.media.unwrap_or(material.media);
        if let Some(two_sided) = surface.two_sided {
            if !material.is_emissive() {
                let message = "only applies to emissive shapes";
                return Err(at.error(Part::TwoSided, message.into()));
            }
            material.two_sided_emission = two_sided;
        }
        let valid = |i: u32| (i as usize) < self.materials.len();
        let two = if material.two_sided_emission {
            2.0
        } else {
            1.0
        };
        Ok(Resolved {
            existing: index.filter(|&i| material == base && valid(i)),
            material,
            radiance: material.is_emissive().then(|| material.emission * two),
        })
    }

    /// The index of `surface`'s material, adding its copy when it has one.
    pub(super) fn commit(&mut self, surface: &Resolved) -> u32 {
        match surface.existing {
            Some(index) => index,
            None => self.push_material(surface.material).index(),
        }
    }

    pub(super) fn add_light(&mut self, light: Light) -> u32 {
        self.lights.push(light);
        self.lights.len() as u32 - 1
    }
}

/// A shape's surface, resolved: its material (an existing one, or a copy still to add) and,
/// when it emits, its radiance (doubled when two-sided).
pub(super) struct Resolved {
    existing: Option<u32>,
    material: Material,
    pub(super) radiance: Option<Vec3>,
}
