//! The scene in device buffers (group 0): geometry, BVH, materials, lights with their photon
//! budgets, the caustic bounds, one parameter slot per camera sample, and the stats counters.

use crate::bvh::gpu_instances::GpuGeometry;
use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::integrators::gpu::bindings::{bind_group, Layouts, PARAMS, SCENE_GROUP};
use crate::integrators::gpu::buffers::storage_buffer;
use crate::integrators::gpu::codes::STATS_LEN;
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::host::PARAMS_STRIDE;
use crate::integrators::gpu::textures::PackedTextures;
use crate::integrators::gpu::types::*;
use crate::lights::table::LightTable;
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
    /// Every binding's buffer but `params`, by binding name.
    buffers: Vec<(&'static str, wgpu::Buffer)>,
}

impl SceneBuffers {
    /// Uploads the scene; `lights` already carry their budgets, `params` goes to slot 0 and
    /// `samples` slots are made room for. Fails when a scene buffer would exceed the
    /// device's largest storage binding.
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
    ) -> Result<Self> {
        let dev = &ctx.device;
        let none = wgpu::BufferUsages::empty();
        let geometry = GpuGeometry::of(scene, bvh).ok_or_else(|| {
            Error::Gpu(format!(
                "the scene's BVH ({} nodes over {} primitives) does not fit the GPU's traversal layout (too many nodes, or coordinates beyond about 1e34); use --backend cpu",
                bvh.nodes.len(),
                bvh.prim_ids.len()
            ))
        })?;
        // A scene with instances uploads its meshes' primitives after its own.
        let geo = geometry.merged.as_ref().unwrap_or(scene);
        let tris: Vec<GpuTriangle> = geo.triangles.iter().map(GpuTriangle::from).collect();
        let spheres: Vec<GpuSphere> = geo.spheres.iter().map(GpuSphere::from).collect();
        let (mats, packed) = materials(scene);
        let uvs = triangle_uvs(geo);
        let textures = PackedTextures::pack(&scene.textures, ctx.max_binding)?;
        // One placeholder when every triangle is flat (a binding cannot be empty).
        let mut normals: Vec<GpuShadingNormals> = geo
            .shading_normals
            .iter()
            .map(GpuShadingNormals::from)
            .collect();
        if normals.is_empty() {
            normals.push(GpuShadingNormals::default());
        }
        let node_bytes = geometry.nodes;
        // The SDF grids' words follow the leaf entries (bvh/gpu_sdf.rs).
        let mut leaf_prims: Vec<u8> = bytemuck::cast_slice(&geometry.leaf_prims).to_vec();
        leaf_prims.extend_from_slice(bytemuck::cast_slice(&geometry.sdf));
        let sizes = [
            ("triangles", std::mem::size_of_val(&tris[..])),
            ("nodes", node_bytes.len()),
            ("leaf_prims", leaf_prims.len()),
            ("shading_normals", std::mem::size_of_val(&normals[..])),
            ("uvs", std::mem::size_of_val(&uvs[..])),
        ];
        if let Some((name, bytes)) = sizes.iter().find(|s| s.1 as u64 > ctx.max_binding) {
            return Err(Error::Gpu(format!(
                "the scene's {} triangles need {} MiB in `{name}`, over this device's {} MiB storage binding limit; use --backend cpu",
                tris.len(),
                bytes >> 20,
                ctx.max_binding >> 20
            )));
        }
        let triangles = storage_buffer(dev, "triangles", &tris, none);
        let spheres = storage_buffer(dev, "spheres", &spheres, none);
        let nodes = storage_buffer(dev, "bvh traversal nodes", &node_bytes, none);
        let leaf_prims = storage_buffer(dev, "bvh leaf primitives", &leaf_prims, none);
        let materials = storage_buffer(dev, "materials", &mats, none);
        let lights = storage_buffer(dev, "lights", lights, wgpu::BufferUsages::COPY_DST);
        // An image environment's distribution follows the triangle CDFs.
        let mut cdf = table.tri_cdf.clone();
        if let (Some(env), Some(d)) = (scene.environment(), &table.env) {
            cdf.extend(d.gpu_words(env));
        }
        let light_cdf = storage_buffer(dev, "light cdf", &cdf, none);
        let spec_bounds = storage_buffer(dev, "specular bounds", bounds, none);
        let shading_normals = storage_buffer(dev, "shading normals", &normals, none);
        let bsdfs = storage_buffer(dev, "bsdfs", &packed.words, none);
        let bsdf_tables = storage_buffer(dev, "bsdf tables", &packed.tables, none);
        let uvs = storage_buffer(dev, "triangle uvs", &uvs, none);
        let textures = textures.upload(ctx)?;
        // Placeholders (a binding cannot be empty) when the scene has no media.
        let mut media: Vec<GpuMedium> = scene
            .media
            .iter()
            .map(|m| GpuMedium {
                sigma_t: m.sigma_t.to_array(),
                g: m.phase.g,
                sigma_s: m.sigma_s().to_array(),
                grid: crate::media::NO_MEDIUM,
            })
            .collect();
        if media.is_empty() {
            media.push(GpuMedium::default());
        }
        // Heterogeneous media's grids follow the table in the same buffer (media/gpu.rs).
        let table = (media.len() * std::mem::size_of::<GpuMedium>() / 16) as u64;
        let (grids, records) = crate::media::gpu::pack(&scene.media, table, ctx.max_binding)
            .map_err(|bytes| {
                Error::Gpu(format!(
                    "the scene's media grids need {} MiB, over this device's {} MiB storage binding limit; use --backend cpu",
                    bytes >> 20,
                    ctx.max_binding >> 20
                ))
            })?;
        for (m, r) in media.iter_mut().zip(records) {
            m.grid = r;
        }
        let mut words: Vec<[f32; 4]> = bytemuck::cast_slice(&media).to_vec();
        words.extend(grids);
        let media = storage_buffer(dev, "media and their grids", &words, none);
        let mut interfaces: Vec<[u32; 2]> = scene
            .materials
            .iter()
            .map(|m| [m.media.interior, m.media.exterior])
            .collect();
        if interfaces.is_empty() {
            interfaces.push([crate::media::NO_MEDIUM; 2]);
        }
        let material_media = storage_buffer(dev, "material media", &interfaces, none);
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
        let buffers = vec![
            ("triangles", triangles),
            ("spheres", spheres),
            ("nodes", nodes),
            ("leaf_prims", leaf_prims),
            ("materials", materials),
            ("lights", lights.clone()),
            ("light_cdf", light_cdf),
            ("spec_bounds", spec_bounds),
            ("stats", stats.clone()),
            ("shading_normals", shading_normals),
            ("bsdfs", bsdfs),
            ("bsdf_tables", bsdf_tables),
            ("uvs", uvs),
            ("tex_table", textures.table),
            ("tex_words", textures.words),
            ("media", media),
            ("material_media", material_media),
        ];
        let bind_group = group(dev, layouts, &buffers, &params_buf, None);
        Ok(SceneBuffers {
            lights,
            params: params_buf,
            stats,
            bind_group,
            buffers,
        })
    }
}

impl SceneBuffers {
    /// Group 0 over these buffers with `nodes` bound in place of the scene's hierarchy (the
    /// ray benchmark's other layout, src/bench/gpu_rays.rs).
    pub fn bind_group_with_nodes(
        &self,
        dev: &wgpu::Device,
        layouts: &Layouts,
        nodes: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        group(dev, layouts, &self.buffers, &self.params, Some(nodes))
    }

    /// The buffer bound as `name` (any binding of group 0 but `params`).
    pub fn buffer(&self, name: &str) -> Option<&wgpu::Buffer> {
        (self.buffers.iter()).find_map(|(n, b)| (*n == name).then_some(b))
    }
}

/// Group 0 over `buffers` and one `params` slot, with `nodes` in place of theirs if given.
fn group(
    dev: &wgpu::Device,
    layouts: &Layouts,
    buffers: &[(&'static str, wgpu::Buffer)],
    params: &wgpu::Buffer,
    nodes: Option<&wgpu::Buffer>,
) -> wgpu::BindGroup {
    let params_slot = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer: params,
        offset: 0,
        size: std::num::NonZeroU64::new(std::mem::size_of::<GpuParams>() as u64),
    });
    let mut entries: Vec<(&str, wgpu::BindingResource)> = buffers
        .iter()
        .map(|(name, b)| match (*name, nodes) {
            ("nodes", Some(n)) => (*name, n.as_entire_binding()),
            _ => (*name, b.as_entire_binding()),
        })
        .collect();
    entries.push((PARAMS, params_slot));
    bind_group(
        dev,
        "scene bind group",
        &layouts.scene,
        &SCENE_GROUP,
        entries,
    )
}
