//! Instancing (Mitsuba's `shapegroup` + `instance`): a mesh stored once in its own object
//! space, placed any number of times by an affine transform. The scene keeps each mesh (a
//! [`Scene`] holding only geometry: triangles, their normals, uvs and tangents, spheres) and
//! the list of [`Instance`]s; the backends trace them through a two-level hierarchy
//! (`crate::bvh::instances`), so memory grows with mesh + instances, not their product.
//!
//! The builder's side is `group_build.rs`: geometry added between
//! [`SceneBuilder::begin_shape_group`] and [`SceneBuilder::end_shape_group`] goes into a new
//! mesh instead of the world; [`SceneBuilder::add_instance`] places one. As in Mitsuba, a
//! shape group holds no emitter (its shapes would be lights of unknown number and place) and
//! no other group. A scene without instances has an empty [`Instancing`] and pays nothing.

use super::{Scene, Sphere, Triangle, VertexNormals, VertexTangents};
use crate::math::geometry::Aabb;
use glam::{Affine3A, Mat3, Mat4, Vec2, Vec3};

/// A mesh of [`Instancing::meshes`], as [`SceneBuilder::end_shape_group`] returns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshId(pub u32);

/// One placement of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Object to world.
    pub to_world: Affine3A,
    /// World to object (the inverse of `to_world`).
    pub to_object: Affine3A,
    /// Index into [`Instancing::meshes`].
    pub mesh: u32,
}

/// Bytes one instance takes in the scene (the budget counts them).
pub use super::cost::INSTANCE_BYTES;
const _: () = assert!(std::mem::size_of::<Instance>() as u64 == INSTANCE_BYTES);

impl Instance {
    /// The instance of `mesh` placed by `to_world`; `None` when it is not finite or not
    /// invertible (its determinant's magnitude below 1e-12 of its scale cubed).
    pub fn new(to_world: Mat4, mesh: u32) -> Option<Self> {
        let a = Affine3A::from_mat4(to_world);
        let scale =
            a.matrix3.x_axis.length() + a.matrix3.y_axis.length() + a.matrix3.z_axis.length();
        let det = a.matrix3.determinant();
        let ok = a.is_finite() && det.is_finite() && det.abs() > 1e-12 * scale * scale * scale;
        (ok && to_world.row(3) == glam::Vec4::W).then(|| Instance {
            to_world: a,
            to_object: a.inverse(),
            mesh,
        })
    }
    /// The matrix normals are transformed by: the inverse transpose of `to_world`'s linear
    /// part (right for non-uniform scales; normalise after).
    pub fn normal_matrix(&self) -> Mat3 {
        Mat3::from(self.to_object.matrix3).transpose()
    }
    /// The world box around `b` (object space) placed by this instance.
    pub fn world_box(&self, b: Aabb) -> Aabb {
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            out = out.grow(self.to_world.transform_point3(c));
        }
        out
    }
}

/// The meshes and their instances; empty in a scene without instancing.
#[derive(Clone, Debug, Default)]
pub struct Instancing {
    /// Meshes in object space (only their geometry fields are used; `material` indices are
    /// the enclosing scene's).
    pub meshes: Vec<Scene>,
    /// Placements.
    pub instances: Vec<Instance>,
}

impl Instancing {
    /// Whether the scene has no instance.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }
    /// Object-space bounds of mesh `m` (`Aabb::EMPTY` when it has nothing).
    pub fn mesh_box(&self, m: u32) -> Aabb {
        let mesh = &self.meshes[m as usize];
        let tris = mesh.triangles.iter().map(Aabb::of_triangle);
        let balls = mesh.spheres.iter().map(Aabb::of_sphere);
        tris.chain(balls).fold(Aabb::EMPTY, Aabb::union)
    }
    /// World bounds of every instance (`Aabb::EMPTY` for a mesh without geometry).
    pub fn world_boxes(&self) -> Vec<Aabb> {
        let boxes: Vec<Aabb> = (0..self.meshes.len() as u32)
            .map(|m| self.mesh_box(m))
            .collect();
        let placed = |i: &Instance| {
            let b = boxes[i.mesh as usize];
            if b.min.cmple(b.max).all() {
                i.world_box(b)
            } else {
                Aabb::EMPTY
            }
        };
        self.instances.iter().map(placed).collect()
    }
    /// The world box of every instance together; `None` without instances.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let b = self
            .world_boxes()
            .into_iter()
            .fold(Aabb::EMPTY, Aabb::union);
        b.min.cmple(b.max).all().then_some((b.min, b.max))
    }
    /// The area of the instances' surfaces whose material `stores` photons: each mesh's
    /// area times each instance's area scale `|det|^(2/3)` (exact for similarity transforms,
    /// an estimate for others; it only sizes photon search radii).
    pub fn storing_area(&self, stores: impl Fn(u32) -> bool) -> f32 {
        let per_mesh: Vec<f32> = (self.meshes.iter())
            .map(|m| {
                let tris: f32 = (m.triangles.iter())
                    .filter(|t| stores(t.material))
                    .map(Triangle::area)
                    .sum();
                let balls: f32 = (m.spheres.iter())
                    .filter(|s| stores(s.material))
                    .map(|s| 4.0 * std::f32::consts::PI * s.radius * s.radius)
                    .sum();
                tris + balls
            })
            .collect();
        (self.instances.iter())
            .map(|i| {
                per_mesh[i.mesh as usize] * i.to_world.matrix3.determinant().abs().powf(2.0 / 3.0)
            })
            .sum()
    }
}

/// The world geometry set aside while a shape group is being recorded.
#[derive(Debug, Default)]
pub(crate) struct GroupStash {
    pub(super) triangles: Vec<Triangle>,
    pub(super) shading_normals: Vec<VertexNormals>,
    pub(super) uvs: Vec<[Vec2; 3]>,
    pub(super) tangents: Vec<VertexTangents>,
    pub(super) spheres: Vec<Sphere>,
    pub(super) sdf_grids: Vec<super::sdf_grid::SdfGrid>,
}
