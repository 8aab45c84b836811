//! The backend-neutral scene: camera, materials, world-space primitives and lights.
//!
//! A [`Scene`] is what both backends render. It is built from a TOML description by
//! [`load()`] (see `scenes/README.md` for the format) or directly in code by tests. All
//! geometry is flattened into world-space triangles and analytic spheres; emission lives on
//! the primitive's material, and every emissive primitive belongs to exactly one area
//! [`Light`].

mod builder;
mod obj;
mod toml;
mod toml_table;

pub use builder::{Locate, MaterialId, Origin, Part, SceneBuilder, Surface};
pub use toml::{load, load_str};

use crate::camera::Camera;
use crate::settings::RenderSettings;
use glam::Vec3;

/// The kind of surface scattering a material performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialKind {
    /// Lambertian: BRDF = albedo / pi, two-sided.
    Diffuse,
    /// Lambertian `kd` plus a normalised Phong lobe `ks (n+2)/(2 pi) cos^n` around the mirror direction.
    Glossy,
    /// Perfect mirror: reflected radiance = reflectance x incident radiance.
    Mirror,
    /// Smooth dielectric with index of refraction `ior` inside, 1.0 outside.
    Glass,
    /// Reflects nothing (the surface of an area light, or a black absorber).
    Black,
}

/// A material. Unused coefficients are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub kind: MaterialKind,
    /// Diffuse albedo (`diffuse`) or `kd` (`glossy`).
    pub kd: Vec3,
    /// Specular coefficient (`glossy`) or reflectance (`mirror`).
    pub ks: Vec3,
    /// Phong exponent of the glossy lobe.
    pub exponent: f32,
    /// Index of refraction of a glass interior.
    pub ior: f32,
    /// Radiance emitted from the front face (zero for non-emitters).
    pub emission: Vec3,
    /// Whether emission leaves both faces.
    pub two_sided_emission: bool,
}

impl Material {
    pub fn diffuse(albedo: Vec3) -> Self {
        Self {
            kind: MaterialKind::Diffuse,
            kd: albedo,
            ..Self::black()
        }
    }
    pub fn glossy(kd: Vec3, ks: Vec3, exponent: f32) -> Self {
        Self {
            kind: MaterialKind::Glossy,
            kd,
            ks,
            exponent,
            ..Self::black()
        }
    }
    pub fn mirror(reflectance: Vec3) -> Self {
        Self {
            kind: MaterialKind::Mirror,
            ks: reflectance,
            ..Self::black()
        }
    }
    pub fn glass(ior: f32) -> Self {
        Self {
            kind: MaterialKind::Glass,
            ior,
            ..Self::black()
        }
    }
    pub fn black() -> Self {
        Self {
            kind: MaterialKind::Black,
            kd: Vec3::ZERO,
            ks: Vec3::ZERO,
            exponent: 0.0,
            ior: 1.0,
            emission: Vec3::ZERO,
            two_sided_emission: false,
        }
    }
    /// An area-light surface: emits `radiance` from its front face, reflects nothing.
    pub fn emitter(radiance: Vec3) -> Self {
        Self {
            emission: radiance,
            ..Self::black()
        }
    }
    /// Mirror and glass: delta BSDFs, the `S` of Heckbert's path notation.
    pub fn is_specular(&self) -> bool {
        matches!(self.kind, MaterialKind::Mirror | MaterialKind::Glass)
    }
    /// Surfaces where photons are stored and radiance is estimated (diffuse and glossy).
    pub fn stores_photons(&self) -> bool {
        matches!(self.kind, MaterialKind::Diffuse | MaterialKind::Glossy)
    }
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}

/// A world-space triangle `v0, v1, v2`; front normal = normalize(cross(e1, e2)) with
/// `e1 = v1 - v0`, `e2 = v2 - v0`. The vertices are kept as given (not as edges) so that two
/// triangles sharing an edge share its end points bit for bit: the watertight intersection
/// test (src/geometry.rs) relies on that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub v0: Vec3,
    pub v1: Vec3,
    pub v2: Vec3,
    pub material: u32,
    /// Index into [`Scene::lights`] when the triangle is emissive, else [`NO_LIGHT`].
    pub light: u32,
}

impl Triangle {
    pub fn new(a: Vec3, b: Vec3, c: Vec3, material: u32) -> Self {
        Self {
            v0: a,
            v1: b,
            v2: c,
            material,
            light: NO_LIGHT,
        }
    }
    pub fn e1(&self) -> Vec3 {
        self.v1 - self.v0
    }
    pub fn e2(&self) -> Vec3 {
        self.v2 - self.v0
    }
    pub fn area(&self) -> f32 {
        0.5 * self.e1().cross(self.e2()).length()
    }
    /// Unit front normal (zero for a degenerate triangle).
    pub fn normal(&self) -> Vec3 {
        self.e1().cross(self.e2()).normalize_or_zero()
    }
    /// The point with barycentric coordinates `(1 - u - v, u, v)`.
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        self.v0 + u * self.e1() + v * self.e2()
    }
}

/// An analytic sphere with outward normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    pub material: u32,
    /// Index into [`Scene::lights`] when the sphere is emissive, else [`NO_LIGHT`].
    pub light: u32,
}

/// Marks a primitive that is not a light.
pub const NO_LIGHT: u32 = u32::MAX;

/// What a light is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum LightShape {
    /// Isotropic point source, `intensity` in W/sr per channel; invisible to the camera.
    Point { position: Vec3, intensity: Vec3 },
    /// Emissive triangles `first..first + count` of [`Scene::triangles`] (one emissive shape),
    /// with the radiance of their material.
    Triangles { first: u32, count: u32 },
    /// Emissive sphere `index` of [`Scene::spheres`].
    Sphere { index: u32 },
}

/// A light source: a point light or an emissive shape.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub shape: LightShape,
    /// Emitted power per channel (W): 4 pi I for a point light, pi A L for a one-sided emitter.
    pub power: Vec3,
}

/// A loaded scene, ready for either backend.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub materials: Vec<Material>,
    pub triangles: Vec<Triangle>,
    pub spheres: Vec<Sphere>,
    pub lights: Vec<Light>,
    /// Render settings from the file's `[render]` table (defaults where absent).
    pub settings: RenderSettings,
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
            },
            materials: vec![],
            triangles: vec![],
            spheres: vec![],
            lights: vec![],
            settings: RenderSettings::default(),
        }
    }

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
        tris + spheres
    }

    pub fn has_glass(&self) -> bool {
        self.materials.iter().any(|m| m.kind == MaterialKind::Glass)
    }
    pub fn has_point_lights(&self) -> bool {
        self.lights
            .iter()
            .any(|l| matches!(l.shape, LightShape::Point { .. }))
    }
    /// Total emitted power per channel.
    pub fn total_power(&self) -> Vec3 {
        self.lights.iter().map(|l| l.power).sum()
    }
}
