//! The scene in device buffers (group 0): geometry, BVH, materials, lights with their photon
//! budgets, the caustic bounds, one parameter slot per camera sample, and the stats counters.

use super::bindings::{bind_group, Layouts, PARAMS, SCENE_GROUP};
use super::buffers::storage_buffer;
use super::codes::STATS_LEN;
use super::context::GpuContext;
use super::host::PARAMS_STRIDE;
use super::types::*;
use crate::bvh::{Bvh, BvhNode};
use crate::light::LightTable;
use crate::scene::Scene;

/// The scene in device buffers, with the group-0 bind group.
pub struct SceneBuffers {
    /// One `Params` slot per camera sample, PARAMS_STRIDE apart (`params`).
    pub params: wgpu::Buffer,
    /// The lights with their photon budgets, rewritten per pass (`lights`).
    pub lights: wgpu::Buffer,
    /// The bound counters, `STAT_*` (`stats`).
    pub stats: wgpu::Buffer,
    /// Group 0 over these buffers.
    pub bind_group: wgpu::BindGroup,
}

impl SceneBuffers {
    /// Uploads the scene; `lights` already carry their budgets, `params` goes to slot 0 and
    /// `samples` slots are made room for.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        scene: &Scene,
        bvh: &Bvh,
        table: &LightTable,
        lights: &[GpuLight],
        bounds: &[GpuAabb],
        params: &GpuParams,
        samples: u32,
    ) -> Self {
        let dev = &ctx.device;
        let none = wgpu::BufferUsages::empty();
        let tris: Vec<GpuTriangle> = scene.triangles.iter().map(GpuTriangle::from).collect();
        let spheres: Vec<GpuSphere> = scene.spheres.iter().map(GpuSphere::from).collect();
        let mats: Vec<GpuMaterial> = scene.materials.iter().map(GpuMaterial::from).collect();
        // One placeholder when every triangle is flat (a binding cannot be empty).
        let mut normals: Vec<GpuShadingNormals> = scene
            .shading_normals
            .iter()
            .map(GpuShadingNormals::from)
            .collect();
        if normals.is_empty() {
            normals.push(GpuShadingNormals::default());
        }
        let nodes: &[BvhNode] = &bvh.nodes;
        let triangles = storage_buffer(dev, "triangles", &tris, none);
        let spheres = storage_buffer(dev, "spheres", &spheres, none);
        let nodes = storage_buffer(dev, "bvh nodes", nodes, none);
        let prim_ids = storage_buffer(dev, "bvh prim ids", &bvh.prim_ids, none);
        let node_links = storage_buffer(dev, "bvh node links", &bvh.links(), none);
        let materials = storage_buffer(dev, "materials", &mats, none);
        let lights = storage_buffer(dev, "lights", lights, wgpu::BufferUsages::COPY_DST);
        let light_cdf = storage_buffer(dev, "light cdf", &table.tri_cdf, none);
        let spec_bounds = storage_buffer(dev, "specular bounds", bounds, none);
        let shading_normals = storage_buffer(dev, "shading normals", &normals, none);
        // One PARAMS_STRIDE slot per camera sample: a pass's gathers are all recorded into
        // one submission, each dispatch reading its sample's slot (dynamic offset).
        let params_buf = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: PARAMS_STRIDE * samples.max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&params_buf, 0, bytemuck::bytes_of(params));
        let stats = storage_buffer(
            dev,
            "stats",
            &[0u32; STATS_LEN],
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let params_slot = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &params_buf,
            offset: 0,
            size: std::num::NonZeroU64::new(std::mem::size_of::<GpuParams>() as u64),
        });
        let bind_group = bind_group(
            dev,
            "scene bind group",
            &layouts.scene,
            &SCENE_GROUP,
            vec![
                ("triangles", triangles.as_entire_binding()),
                ("spheres", spheres.as_entire_binding()),
                ("nodes", nodes.as_entire_binding()),
                ("prim_ids", prim_ids.as_entire_binding()),
                ("materials", materials.as_entire_binding()),
                ("lights", lights.as_entire_binding()),
                ("light_cdf", light_cdf.as_entire_binding()),
                ("spec_bounds", spec_bounds.as_entire_binding()),
                (PARAMS, params_slot),
                ("stats", stats.as_entire_binding()),
                ("shading_normals", shading_normals.as_entire_binding()),
                ("node_links", node_links.as_entire_binding()),
            ],
        );
        SceneBuffers {
            lights,
            params: params_buf,
            stats,
            bind_group,
        }
    }
}
