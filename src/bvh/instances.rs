//! The top level of a scene with instances (`crate::scene::instances`): a binary SAH tree
//! over the instances' world boxes, built by [`Bvh::over_boxes`], above one wide hierarchy
//! per mesh (its own [`WideBvh`], built once however many instances place it). A ray that
//! enters an instance's box is carried into its object space (`to_object`, its direction
//! renormalised and distances scaled by the same factor) and walks the mesh's hierarchy;
//! a hit comes back to world space: the point by `to_world`, normals by the inverse
//! transpose (right under non-uniform scales), a normal map's tangent by `to_world`.
//!
//! Scenes without instances build none of it (`WideBvh::instances` is `None`).
//!
//! Twin: `walk_instances` in `src/bvh/instances.wgsl` (over the layout of `gpu_instances.rs`).

use super::surface::{geometric_hit, shading_frame, tangent_at, tangent_fallback, uv_partials};
use super::{BuildCosts, Bvh, Hit, WideBvh, SPHERE_BIT};
use crate::math::geometry::Ray;
use crate::scene::{Instance, Scene};
use glam::Vec3;

/// The two-level hierarchy's top level and the meshes' hierarchies.
#[derive(Clone, Debug)]
pub struct InstanceBvh {
    /// Over the instances' world boxes; leaves list instance indices.
    pub top: Bvh,
    /// One per mesh of `Scene::instancing`.
    pub meshes: Vec<WideBvh>,
}

/// `ray` in the object space of `inst` with unit direction, and the factor object-space
/// distances are of world ones (`t_object = k * t_world`).
#[inline]
pub fn object_ray(inst: &Instance, ray: &Ray) -> (Ray, f32) {
    let d = inst.to_object.transform_vector3(ray.dir);
    let k = d.length();
    let r = Ray {
        origin: inst.to_object.transform_point3(ray.origin),
        dir: d / k,
    };
    (r, k)
}

impl InstanceBvh {
    /// The hierarchies of `scene`'s instances; `None` when it has none.
    pub fn build(scene: &Scene) -> Option<Self> {
        let inst = &scene.instancing;
        if inst.is_empty() {
            return None;
        }
        let meshes: Vec<WideBvh> = inst.meshes.iter().map(WideBvh::build).collect();
        let boxes = inst.world_boxes();
        let placed = (boxes.iter().copied().zip(0u32..)).filter(|(b, _)| b.min.cmple(b.max).all());
        let top = Bvh::over_boxes(placed, boxes.len(), BuildCosts::CPU);
        Some(InstanceBvh { top, meshes })
    }

    /// Bytes the hierarchies take (the top level's nodes and ids, each mesh's once).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let top = self.top.nodes.len() * size_of::<super::BvhNode>() + self.top.prim_ids.len() * 4;
        top + self.meshes.iter().map(WideBvh::memory_bytes).sum::<usize>()
    }

    /// Instance `i` of `scene`, its mesh and the mesh's hierarchy, and `ray` in its object
    /// space with the distance factor ([`object_ray`]).
    #[inline]
    fn enter<'a>(
        &'a self,
        scene: &'a Scene,
        i: u32,
        ray: &Ray,
    ) -> (&'a Instance, &'a Scene, &'a WideBvh, Ray, f32) {
        let inst = &scene.instancing.instances[i as usize];
        let (r, k) = object_ray(inst, ray);
        let m = inst.mesh as usize;
        (inst, &scene.instancing.meshes[m], &self.meshes[m], r, k)
    }

    /// The nearest instance hit along `ray` before `t_max`: (instance, primitive id, world
    /// `t`, object-space `t`, `u`, `v`).
    pub fn closest(
        &self,
        scene: &Scene,
        ray: &Ray,
        t_max: f32,
    ) -> Option<(u32, u32, f32, f32, f32, f32)> {
        let mut best = None;
        self.top.walk(
            ray,
            |i, t_lim| {
                let (_, mesh, bvh, r, k) = self.enter(scene, i, ray);
                let (id, t, u, v) = bvh.closest(mesh, &r, t_lim * k)?;
                let tw = (t / k).min(t_lim);
                best = Some((i, id, tw, t, u, v));
                Some(tw)
            },
            t_max,
        );
        best
    }

    /// Nearest instance hit along `ray` before `t_max`, in world space.
    pub fn intersect(&self, scene: &Scene, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (i, id, tw, t, u, v) = self.closest(scene, ray, t_max)?;
        let (inst, mesh, _, r, _) = self.enter(scene, i, ray);
        let local = geometric_hit(mesh, &r, id, t, u, v);
        let nm = inst.normal_matrix();
        let mut hit = Hit {
            t: tw,
            position: inst.to_world.transform_point3(local.position),
            normal: (nm * local.normal).normalize_or_zero(),
            shading: (nm * local.shading).normalize_or_zero(),
            ..local
        };
        if id & SPHERE_BIT != 0 && !scene.textures.is_empty() {
            // The mesh holds no textures, so its sphere left the uv out.
            hit.uv = mesh.spheres[(id & !SPHERE_BIT) as usize].uv(local.normal);
        }
        let flips = inst.to_world.matrix3.determinant() < 0.0;
        // Tangents are directions: the instance's linear part carries them.
        let (dp_du, flipped) = tangent_at(mesh, id, u, v, local.normal);
        let fallback = tangent_fallback(mesh, id, local.normal);
        let to_world = |d: Vec3| inst.to_world.transform_vector3(d);
        let partials = || {
            let (pu, pv) = uv_partials(mesh, id, local.normal);
            (to_world(pu), to_world(pv))
        };
        Some(shading_frame(
            scene,
            hit,
            ray.dir,
            (to_world(dp_du), flipped ^ flips),
            to_world(fallback),
            partials,
        ))
    }

    /// Whether some instance blocks `ray` before `t_max`.
    pub fn occluded(&self, scene: &Scene, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        self.top.walk(
            ray,
            |i, t_lim| {
                let (_, mesh, bvh, r, k) = self.enter(scene, i, ray);
                if bvh.occluded(mesh, &r, t_lim * k) {
                    hit = true;
                    return Some(-1.0);
                }
                None
            },
            t_max,
        );
        hit
    }
}
