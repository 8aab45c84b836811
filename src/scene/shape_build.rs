//! The scene builder's calls for shapes made of triangles or analytic spheres (the rules
//! in `builder.rs`): spheres, triangles, quads, boxes and meshes, flat, smooth or with
//! texture coordinates; an emissive shape becomes one area light.

use super::builder::{SceneBuilder, Surface};
use crate::error::Result;
use crate::scene::checks::check_light;
use crate::scene::cost::MeshCost;
use crate::scene::locate::{Locate, Part};
use crate::scene::normals::{is_flat, unit_normals};
use crate::scene::{Light, LightShape, Sphere, Triangle, VertexNormals, FLAT, NO_LIGHT};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

impl SceneBuilder {
    /// Adds an analytic sphere (outward normal); an emissive one is one light.
    pub fn add_sphere(
        &mut self,
        center: Vec3,
        radius: f32,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        self.add_oriented_sphere(center, radius, glam::Quat::IDENTITY, surface, at)
    }

    /// Adds a sphere as [`Self::add_sphere`] whose parameterisation (uv, dp/du) is turned by
    /// the unit quaternion `frame` (object to world: Mitsuba's rotating `to_world`).
    pub fn add_oriented_sphere(
        &mut self,
        center: Vec3,
        radius: f32,
        frame: glam::Quat,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        let surface = self.resolve(surface, at)?;
        if !center.is_finite() {
            return Err(at.error(Part::Geometry, "the centre must be finite".into()));
        }
        if !(radius.is_finite() && radius > 0.0) {
            let message = "the radius must be positive and finite";
            return Err(at.error(Part::Geometry, message.into()));
        }
        let mut light = None;
        if let Some(radiance) = surface.radiance {
            let area = 4.0 * PI * radius * radius;
            let power = PI * area * radiance;
            check_light(area, power, at)?;
            let index = self.spheres.len() as u32;
            let shape = LightShape::Sphere(crate::lights::sphere::SphereLight { index });
            light = Some(Light { shape, power });
        }
        let material = self.commit(&surface);
        let light = light.map_or(NO_LIGHT, |l| self.add_light(l));
        self.spheres.push(Sphere {
            center,
            radius,
            material,
            light,
            frame: Sphere::quantized_frame(frame),
        });
        Ok(())
    }

    /// Adds the triangle `v` (front normal `cross(v1 - v0, v2 - v0)`).
    pub fn add_triangle(&mut self, v: [Vec3; 3], surface: Surface, at: &dyn Locate) -> Result<()> {
        self.add_mesh(vec![v], surface, at)
    }

    /// Adds the quad `c` (corners in order around the edge) as triangles `(c0, c1, c2)`,
    /// `(c0, c2, c3)`.
    pub fn add_quad(&mut self, c: [Vec3; 4], surface: Surface, at: &dyn Locate) -> Result<()> {
        self.add_mesh(vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]], surface, at)
    }

    /// Adds the box `min..max` (min < max on every axis), turned `rotate_y` degrees about the
    /// vertical axis through its centre: 6 outward-facing quads, 12 triangles.
    pub fn add_box(
        &mut self,
        min: Vec3,
        max: Vec3,
        rotate_y: f32,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        if !min.cmplt(max).all() {
            let message = "must be greater than `min` on every axis";
            return Err(at.error(Part::Geometry, message.into()));
        }
        self.add_mesh(box_triangles(min, max, rotate_y), surface, at)
    }

    /// Adds one shape made of world-space triangles (a mesh, already transformed); an
    /// emissive one is one light. Every vertex must be finite.
    pub fn add_mesh(
        &mut self,
        tris: Vec<[Vec3; 3]>,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        self.add_smooth_mesh(tris, None, surface, at)
    }

    /// [`SceneBuilder::add_mesh`] with, when `normals` is given, smooth shading: one
    /// [`VertexNormals`] per triangle (the corners' normals in world space, any length; each
    /// is normalised). A triangle whose three normals are all its face normal (or all its
    /// opposite, within 0.1 degrees) stays flat, and keeps no normals: a planar mesh costs
    /// nothing. A normal that is zero or not finite, or a count that differs from the
    /// triangles', is an error on [`Part::Geometry`] (importers check first, naming their
    /// file and field).
    pub fn add_smooth_mesh(
        &mut self,
        tris: Vec<[Vec3; 3]>,
        normals: Option<Vec<VertexNormals>>,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        let cost = MeshCost::mesh(tris.len() as u64, normals.is_some(), false, false);
        self.check_geometry(cost, "this shape", at)?;
        let surface = self.resolve(surface, at)?;
        if tris.iter().flatten().any(|p| !p.is_finite()) {
            return Err(at.error(Part::Geometry, "vertices must be finite".into()));
        }
        let normals = match normals {
            Some(n) => Some(unit_normals(n, tris.len()).map_err(|m| at.error(Part::Geometry, m))?),
            None => None,
        };
        let triangles = tris.iter().map(|&[a, b, c]| Triangle::new(a, b, c, 0));
        let mut light = None;
        if let Some(radiance) = surface.radiance {
            let mut area = 0.0;
            for triangle in triangles.clone() {
                area += triangle.area();
            }
            let power = PI * area * radiance;
            check_light(area, power, at)?;
            let first = self.triangles.len() as u32;
            let count = tris.len() as u32;
            let shape = LightShape::Triangles(crate::lights::triangles::Triangles { first, count });
            light = Some(Light { shape, power });
        }
        let material = self.commit(&surface);
        let light = light.map_or(NO_LIGHT, |l| self.add_light(l));
        for (i, triangle) in triangles.enumerate() {
            let shading = match &normals {
                Some(n) if !is_flat(triangle.normal(), &n[i]) => {
                    self.shading_normals.push(n[i]);
                    self.shading_normals.len() as u32 - 1
                }
                _ => FLAT,
            };
            self.triangles.push(Triangle {
                material,
                light,
                shading,
                ..triangle
            });
        }
        Ok(())
    }

    /// [`add_smooth_mesh`](Self::add_smooth_mesh) with texture coordinates for each
    /// triangle's corners (`uvs` parallel to `tris`; non-finite values are an error).
    pub fn add_uv_mesh(
        &mut self,
        tris: Vec<[Vec3; 3]>,
        normals: Option<Vec<VertexNormals>>,
        uvs: Vec<[Vec2; 3]>,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        if uvs.len() != tris.len() || uvs.iter().flatten().any(|t| !t.is_finite()) {
            let message = "texture coordinates must be finite, one set per triangle";
            return Err(at.error(Part::Geometry, message.into()));
        }
        let cost = MeshCost::mesh(tris.len() as u64, normals.is_some(), true, false);
        self.check_geometry(cost, "this shape", at)?;
        let first = self.triangles.len();
        self.add_smooth_mesh(tris, normals, surface, at)?;
        self.uvs.resize(first, [Vec2::ZERO; 3]);
        self.uvs.extend(uvs);
        Ok(())
    }
}

/// The 12 outward-facing triangles of the box `min..max` turned `degrees` about +y around its
/// centre: per face, a corner (in units of the size) and two edges whose cross product is the
/// outward normal.
fn box_triangles(min: Vec3, max: Vec3, degrees: f32) -> Vec<[Vec3; 3]> {
    const X: [f32; 3] = [1.0, 0.0, 0.0];
    const Y: [f32; 3] = [0.0, 1.0, 0.0];
    const Z: [f32; 3] = [0.0, 0.0, 1.0];
    const O: [f32; 3] = [0.0; 3];
    const FACES: [[[f32; 3]; 3]; 6] = [
        [X, Y, Z],
        [O, Z, Y],
        [Y, Z, X],
        [O, X, Z],
        [Z, X, Y],
        [O, Y, X],
    ];
    let (size, centre) = (max - min, 0.5 * (min + max));
    let rotation = Mat3::from_rotation_y(degrees.to_radians());
    let mut tris = Vec::with_capacity(12);
    for [o, u, v] in FACES.map(|f| f.map(|a| Vec3::from(a) * size)) {
        let q = [o, o + u, o + u + v, o + v].map(|p| centre + rotation * (min + p - centre));
        tris.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
    }
    tris
}
