//! The backend-neutral scene: camera, materials, world-space primitives and lights.
//!
//! A [`Scene`] is what both backends render. Every importer builds one through a
//! [`SceneBuilder`], which holds the rules (emission copies, lights and their power, the
//! checks): `crate::importers::load` reads a scene file of any format into one; tests may
//! also fill a `Scene` directly. All geometry is flattened into
//! world-space triangles and analytic spheres; emission lives on the primitive's material,
//! and every emissive primitive belongs to exactly one area [`Light`].

pub mod builder;
pub mod checks;
pub mod cost;
pub mod geometry_budget;
mod group_build;
pub mod instances;
pub mod locate;
pub mod normals;
mod outer_medium;
pub mod sdf_build;
pub mod sdf_grid;
mod shape_build;
pub mod shapes;
pub mod tangents;

pub use crate::bsdfs::material::{Alpha, AlphaMode, Material, NO_TEXTURE};
pub use crate::lights::environment::Environment;
pub use crate::lights::{Light, LightShape};
pub use builder::{MaterialId, SceneBuilder, Surface};
pub use checks::{SceneBudgets, MAX_SCENE_BYTES, MAX_TEXTURE_BYTES, MAX_TRIANGLES};
pub use cost::MeshCost;
pub use instances::{Instance, Instancing, MeshId};
pub use locate::{Locate, Origin, Part};
pub use shapes::{Sphere, Triangle, VertexNormals, VertexTangents, FLAT, NO_LIGHT};

use crate::camera::Camera;
use crate::settings::RenderSettings;
use crate::textures::SceneTexture;
use glam::Vec2;
use glam::Vec3;

/// A loaded scene, ready for either backend.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// Materials, indexed by the primitives' `material`.
    pub materials: Vec<Material>,
    /// World-space triangles; an emissive shape's triangles are contiguous.
    pub triangles: Vec<Triangle>,
    /// Vertex normals of the smooth-shaded triangles, indexed by [`Triangle::shading`];
    /// empty when every triangle is flat.
    pub shading_normals: Vec<VertexNormals>,
    /// Texture coordinates of each triangle's corners, parallel to `triangles`; empty when
    /// no triangle has any (then every uv is zero).
    pub uvs: Vec<[Vec2; 3]>,
    /// Vertex tangents of each triangle, parallel to `triangles`; empty when no triangle has
    /// any (normal maps then use each triangle's uv tangent).
    pub tangents: Vec<VertexTangents>,
    /// The textures materials refer to ([`Material::kd_texture`]).
    pub textures: Vec<SceneTexture>,
    /// Analytic spheres.
    pub spheres: Vec<Sphere>,
    /// Signed distance fields on grids (Mitsuba's `sdfgrid`), placed in the world.
    pub sdf_grids: Vec<sdf_grid::SdfGrid>,
    /// Lights, in the order their shapes (then point lights) were added.
    pub lights: Vec<Light>,
    /// Participating media, indexed by `Material::media` and [`Self::camera_medium`].
    pub media: Vec<crate::media::Medium>,
    /// The medium the camera sits in, or `crate::media::NO_MEDIUM` (vacuum).
    pub camera_medium: u32,
    /// The medium outside every shape ([`Scene::medium_outside`]), where photons that start
    /// outside the scene or meet no boundary of a medium travel.
    pub outer_medium: u32,
    /// Render settings from the file's `[camera]` and `[render]` tables (defaults where
    /// absent).
    pub settings: RenderSettings,
    /// Meshes stored once and their instances (`instances.rs`); empty in most scenes.
    pub instancing: Instancing,
}

impl Scene {
    /// A scene with nothing in it (renders black), looking down -z from the origin.
    pub fn empty() -> Self {
        Scene {
            camera: Camera {
                eye: Vec3::ZERO,
                forward: -Vec3::Z,
                right: Vec3::X,
                up: Vec3::Y,
                aperture_radius: 0.0,
                focus_distance: 1.0,
                filter: crate::camera::pixel_filter::PixelFilter::Box,
                orthographic: false,
            },
            materials: vec![],
            triangles: vec![],
            shading_normals: vec![],
            uvs: vec![],
            tangents: vec![],
            textures: vec![],
            spheres: vec![],
            sdf_grids: vec![],
            lights: vec![],
            media: vec![],
            camera_medium: crate::media::NO_MEDIUM,
            outer_medium: crate::media::NO_MEDIUM,
            settings: RenderSettings::default(),
            instancing: Instancing::default(),
        }
    }

    /// The material of triangle `i`.
    pub fn material_of_triangle(&self, i: usize) -> &Material {
        &self.materials[self.triangles[i].material as usize]
    }
    /// Total area of the surfaces that store photons (diffuse and glossy).
    pub fn storing_area(&self) -> f32 {
        let stores = |m: u32| self.materials[m as usize].stores_photons();
        let tris: f32 = self
            .triangles
            .iter()
            .filter(|t| stores(t.material))
            .map(|t| t.area())
            .sum();
        let spheres: f32 = self
            .spheres
            .iter()
            .filter(|s| stores(s.material))
            .map(|s| 4.0 * std::f32::consts::PI * s.radius * s.radius)
            .sum();
        let sdf: f32 = (self.sdf_grids.iter())
            .filter(|g| stores(g.material))
            .map(sdf_grid::SdfGrid::area_estimate)
            .sum();
        tris + spheres + sdf + self.instancing.storing_area(stores)
    }

    /// Whether some triangle is smooth-shaded.
    pub fn has_smooth(&self) -> bool {
        !self.shading_normals.is_empty()
    }
    /// Whether some light is a delta light ([`LightShape::is_delta`]).
    pub fn has_delta_lights(&self) -> bool {
        self.lights.iter().any(|l| l.shape.is_delta())
    }
    /// A sphere around every triangle and sphere (centre and radius): the centre and half
    /// the diagonal of their bounding box, the radius grown by 0.1% (and 1e-4) so that a
    /// directional light's photons start clear of the scene. `(0, 0)` for an empty scene.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let Some((lo, hi)) = self.bounds() else {
            return (Vec3::ZERO, 0.0);
        };
        let centre = 0.5 * (lo + hi);
        (centre, 0.5 * (hi - lo).length() * 1.001 + 1e-4)
    }
    /// The scene's size class: the power of two at or below the half-diagonal of its bounding
    /// box (1 when it is empty or a point). Scenes of half-diagonal 1 to 2, such as the Cornell
    /// box's [-1, 1]^3, have 1; the same scene in millimetres has 1024.
    pub fn size_unit(&self) -> f32 {
        let half = (self.bounds()).map_or(0.0, |(lo, hi)| 0.5 * (hi - lo).length());
        if !(half > 0.0 && half.is_finite()) {
            return 1.0;
        }
        2f32.powi(half.log2().floor() as i32)
    }
    /// Multiplies the search radii the scene file left at their defaults (`radius`,
    /// `caustic_radius`, `volume_radius`; `given`: which the file set) by [`Scene::size_unit`] when it is above
    /// 1, so that a larger scene renders as it would in smaller units. Never down: the radii
    /// are caps on searches the photon density sizes, harmless when large. A power of two, so
    /// scenes of size class 1 or below keep them exactly.
    pub fn scale_default_radii(&mut self, given: [bool; 3]) {
        let unit = self.size_unit().max(1.0);
        if !given[0] {
            self.settings.radius *= unit;
        }
        if !given[1] {
            self.settings.caustic_radius *= unit;
        }
        if !given[2] {
            self.settings.volume_radius *= unit;
        }
    }
    /// The bounding box `(min, max)` of every primitive and instance; `None` when empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let sdf = (self.sdf_grids.iter()).fold(crate::math::geometry::Aabb::EMPTY, |b, g| {
            b.union(g.world_box())
        });
        let sdf = (!sdf.is_empty()).then_some((sdf.min, sdf.max));
        join_bounds(
            join_bounds(bounds_of(&self.triangles, &self.spheres), sdf),
            self.instancing.bounds(),
        )
    }
    /// Total emitted power per channel.
    pub fn total_power(&self) -> Vec3 {
        self.lights.iter().map(|l| l.power).sum()
    }
}

/// The box around two boxes, either of which may be absent.
pub(crate) fn join_bounds(
    a: Option<(Vec3, Vec3)>,
    b: Option<(Vec3, Vec3)>,
) -> Option<(Vec3, Vec3)> {
    match (a, b) {
        (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
        (a, b) => a.or(b),
    }
}

/// The bounding box `(min, max)` of `triangles` and `spheres`; `None` when both are empty.
pub(crate) fn bounds_of(triangles: &[Triangle], spheres: &[Sphere]) -> Option<(Vec3, Vec3)> {
    let corners = triangles.iter().flat_map(|t| [t.v0, t.v1, t.v2]);
    let balls = spheres
        .iter()
        .flat_map(|s| [s.center - s.radius, s.center + s.radius]);
    corners.chain(balls).fold(None, |b, p| {
        Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))))
    })
}
