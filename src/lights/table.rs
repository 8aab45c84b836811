//! Sampling tables for every light of a scene ([`LightTable`]) and the scene-level queries of
//! the photon tracers: a light's context, emission and shadow-ray samples by index, and the
//! bounds caustic photons aim at. Twin: `src/lights/light.wgsl` (with each kind's file).

use crate::lights::area;
use crate::lights::emission;
use crate::lights::environment::sampling::{self as env, EnvDistribution};
use crate::lights::interface::{Emission, LightContext, LightKind, LightSample};
use crate::lights::triangles::Triangles;
use crate::lights::LightShape;
use crate::math::geometry::Aabb;
use crate::scene::Scene;
use glam::Vec3;

/// Sampling tables for every light of a scene.
#[derive(Clone, Debug)]
pub struct LightTable {
    /// Per light: where its triangle CDF starts in `tri_cdf` (its end for the other kinds).
    pub cdf_start: Vec<u32>,
    /// Concatenated per-light triangle CDFs (normalised to end at 1) and projectors' image
    /// distributions (`LightKind::distribution`).
    pub tri_cdf: Vec<f32>,
    /// Per light: total emitting area (0 for lights without a surface).
    pub area: Vec<f32>,
    /// The scene's bounding sphere (centre, radius): where directional lights' photons
    /// start ([`Scene::bounding_sphere`]).
    pub bounds: (Vec3, f32),
    /// Per light: its emission texture (`NO_TEXTURE` without one; `emission::texture_of`).
    pub emission_texture: Vec<u32>,
    /// Per light: its emission texture's mean over its surface (one without one), which its
    /// power includes (`crate::lights::emission`).
    pub texture_mean: Vec<Vec3>,
    /// An image environment's sampling distribution (`None` without one).
    pub env: Option<EnvDistribution>,
}

impl LightTable {
    /// The sampling tables of every light of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let mut t = LightTable {
            cdf_start: vec![],
            tri_cdf: vec![],
            area: vec![],
            bounds: scene.bounding_sphere(),
            emission_texture: (0..scene.lights.len())
                .map(|l| emission::texture_of(scene, l))
                .collect(),
            texture_mean: (0..scene.lights.len())
                .map(|l| emission::texture_mean(scene, l))
                .collect(),
            env: scene
                .environment()
                .and_then(|e| env::distribution(e, &scene.textures)),
        };
        for l in &scene.lights {
            t.cdf_start.push(t.tri_cdf.len() as u32);
            let (area, cdf) = l.shape.surface(&scene.triangles, &scene.spheres);
            t.area.push(area);
            t.tri_cdf.extend(cdf);
            t.tri_cdf.extend(l.shape.distribution(&scene.textures));
        }
        t
    }

    /// What light `l` of `scene` sees of it and of this table.
    pub fn context<'a>(&'a self, scene: &'a Scene, l: usize) -> LightContext<'a> {
        let start = self.cdf_start[l] as usize;
        let end = self
            .cdf_start
            .get(l + 1)
            .map_or(self.tri_cdf.len(), |&e| e as usize);
        let cdf_start = match scene.lights[l].shape {
            // The environment's distribution follows every triangle CDF on the GPU.
            LightShape::Environment(_) => self.tri_cdf.len() as u32,
            _ => self.cdf_start[l],
        };
        LightContext {
            triangles: &scene.triangles,
            spheres: &scene.spheres,
            materials: &scene.materials,
            textures: &scene.textures,
            uvs: &scene.uvs,
            power: scene.lights[l].power,
            area: self.area[l],
            cdf: &self.tri_cdf[start..end],
            cdf_start,
            emission_texture: self.emission_texture[l],
            texture_mean: self.texture_mean[l],
            bounds: self.bounds,
            env: self.env.as_ref(),
        }
    }

    /// The solid-angle density with which [`sample`](Self::sample) picks `point` (normal
    /// `normal`) on area light `l` as seen from `x` ([`area::solid_angle_pdf`]).
    pub fn solid_angle_pdf(&self, l: usize, x: Vec3, point: Vec3, normal: Vec3) -> f32 {
        area::solid_angle_pdf(self.area[l], x, point, normal)
    }

    /// Picks a triangle of light `l` (a triangle light) with probability proportional to
    /// area ([`Triangles::pick`]).
    pub fn pick_triangle(&self, scene: &Scene, l: usize, u: f32) -> usize {
        let LightShape::Triangles(t) = scene.lights[l].shape else {
            unreachable!("not a triangle light")
        };
        Triangles::pick(&t, &self.context(scene, l), u)
    }

    /// Emits a photon from light `l` using five uniform numbers ([`LightKind::emit`]).
    pub fn emit(&self, scene: &Scene, l: usize, u: [f32; 5]) -> Emission {
        scene.lights[l].shape.emit(&self.context(scene, l), u)
    }

    /// The solid-angle density with which [`sample`](Self::sample) picks direction `dir`
    /// towards light `l` (one sampled by direction) from a point of shading normal `ns`.
    pub fn direction_pdf(&self, scene: &Scene, l: usize, ns: Vec3, dir: Vec3) -> f32 {
        scene.lights[l]
            .shape
            .direction_pdf(&self.context(scene, l), ns, dir)
    }

    /// The point [`sample`](Self::sample) picks on light `l` for `u` whatever the shading
    /// point, where there is one ([`LightKind::anchor`]).
    pub fn anchor(&self, scene: &Scene, l: usize, u: [f32; 3]) -> Option<Vec3> {
        scene.lights[l].shape.anchor(&self.context(scene, l), u)
    }

    /// A shadow-ray target on light `l` for shading point `x` (shading normal `ns`), from
    /// three uniform numbers ([`LightKind::sample`]).
    pub fn sample(&self, scene: &Scene, l: usize, x: Vec3, ns: Vec3, u: [f32; 3]) -> LightSample {
        scene.lights[l]
            .shape
            .sample(&self.context(scene, l), x, ns, u)
    }
}

/// Bounds of the surfaces that caustic photons are aimed at, those with a delta or glossy
/// lobe (`Material::casts_caustics`): one box per such material over its triangles, and
/// each such sphere's box.
pub fn specular_bounds(scene: &Scene) -> Vec<Aabb> {
    let mut per_material: Vec<Aabb> = vec![Aabb::EMPTY; scene.materials.len()];
    for t in &scene.triangles {
        if scene.materials[t.material as usize].casts_caustics() {
            per_material[t.material as usize] =
                per_material[t.material as usize].union(Aabb::of_triangle(t));
        }
    }
    let mut out: Vec<Aabb> = per_material.into_iter().filter(|b| !b.is_empty()).collect();
    for s in &scene.spheres {
        if scene.materials[s.material as usize].casts_caustics() {
            out.push(Aabb::of_sphere(s));
        }
    }
    out
}

/// Whether a ray from `origin` along `dir` enters any of `bounds`.
pub fn aims_at(bounds: &[Aabb], origin: Vec3, dir: Vec3) -> bool {
    let inv = dir.recip();
    bounds.iter().any(|b| b.hit(origin, inv, f32::INFINITY))
}
