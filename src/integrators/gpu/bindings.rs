//! The bind groups by name: one table per group, each entry named as its WGSL global, with
//! its binding number and access. The layouts are built from these tables, bind groups are
//! filled by name through them, and tests/gpu_layout.rs checks them against naga's reflection
//! of every kernel (so a buffer bound in the wrong place fails a test, not a render).
//!
//! No binding is a uniform buffer, on purpose: lavapipe (Mesa 22.3) inlines uniform values
//! into the shader and compiles a new copy of the pipeline, never freed, each time a bind
//! group holding a uniform buffer is bound: about 2.3 MB and 23 ms per gather dispatch.
//! Read-only storage buffers carry the parameters instead.

use crate::integrators::gpu::shaders::Kernel;

/// How a kernel may access a storage binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// `var<storage, read>`.
    Read,
    /// `var<storage, read_write>`.
    ReadWrite,
}

/// One binding of a group: the WGSL global's name, its binding number and access.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// Name of the WGSL global bound here.
    pub name: &'static str,
    /// `@binding(n)`.
    pub binding: u32,
    /// Read-only or read-write storage.
    pub access: Access,
    /// Bound with a dynamic offset (one slot per camera sample).
    pub dynamic: bool,
}

/// One bind group's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GroupTable {
    /// `@group(n)`.
    pub group: u32,
    /// Label of the layout (and prefix of its bind groups' labels).
    pub label: &'static str,
    /// Every binding of the group.
    pub entries: &'static [Binding],
}

impl GroupTable {
    /// The entry named `name`.
    pub fn entry(&self, name: &str) -> Option<&Binding> {
        self.entries.iter().find(|b| b.name == name)
    }
}

const fn ro(name: &'static str, binding: u32) -> Binding {
    Binding {
        name,
        binding,
        access: Access::Read,
        dynamic: false,
    }
}

const fn rw(name: &'static str, binding: u32) -> Binding {
    Binding {
        name,
        binding,
        access: Access::ReadWrite,
        dynamic: false,
    }
}

/// Name of the per-sample parameters in the scene group (bound with a dynamic offset).
pub const PARAMS: &str = "params";

/// Group 0, the scene (src/integrators/gpu/scene.wgsl), bound by every kernel.
pub const SCENE_GROUP: GroupTable = GroupTable {
    group: 0,
    label: "scene",
    entries: &[
        ro("triangles", 0),
        ro("spheres", 1),
        ro("nodes", 2),
        ro("leaf_prims", 3),
        ro("materials", 4),
        ro("lights", 5),
        ro("light_cdf", 6),
        ro("spec_bounds", 7),
        Binding {
            name: PARAMS,
            binding: 8,
            access: Access::Read,
            dynamic: true,
        },
        rw("stats", 9),
        ro("shading_normals", 10),
        ro("bsdfs", 11),
        ro("bsdf_tables", 12),
        ro("uvs", 13),
        ro("tex_table", 14),
        ro("tex_words", 15),
        ro("media", 16),
        ro("material_media", 17),
    ],
};

/// Group 1 of the map-building kernels (src/integrators/gpu/map.wgsl): one photon map, and the
/// volume photons every map's paths add to (participating media; placeholders without).
pub const MAP_GROUP: GroupTable = GroupTable {
    group: 1,
    label: "photon map",
    entries: &[
        rw("photons", 0),
        rw("counters", 1),
        rw("cell_count", 2),
        rw("cell_start", 3),
        rw("sorted", 4),
        rw("block_sums", 5),
        rw("map_params", 6),
        rw("volume", 7),
        rw("volume_count", 8),
        rw("volume_grid", 9),
    ],
};

/// The gather group's bindings of each photon map slot ([`crate::integrators::plan::MapKind`] order):
/// its sorted photons, cell starts and parameters (WGSL names them statically, so a new
/// kind of map is one more row here and in `src/integrators/estimate.wgsl`).
pub const MAP_SLOTS: [[&str; 3]; 2] = [
    ["g_photons", "g_cells", "g_map"],
    ["c_photons", "c_cells", "c_map"],
];

/// Group 1 of the gather and the probes (src/integrators/estimate.wgsl, gather.wgsl): both
/// maps' sorted photons, cell starts and parameters, the image accumulator, and the radiance
/// cache (parallel to the global map's sorted photons: written by the cache build, read by the
/// gather) with the list of its points (small stand-ins outside mode gather), and the volume
/// map (its photons, the grid's entries and cells, its layout; placeholders without media).
pub const GATHER_GROUP: GroupTable = GroupTable {
    group: 1,
    label: "gather",
    entries: &[
        ro("g_photons", 0),
        ro("g_cells", 1),
        ro("g_map", 2),
        ro("c_photons", 3),
        ro("c_cells", 4),
        ro("c_map", 5),
        rw("accum", 6),
        rw("cache", 7),
        rw("cache_list", 8),
        ro("v_photons", 9),
        ro("v_refs", 10),
        ro("v_cells", 11),
        ro("v_grid", 12),
        rw("branch_stacks", 13),
    ],
};

/// The groups a kernel's pipelines bind, in group order.
pub fn groups_of(kernel: Kernel) -> [&'static GroupTable; 2] {
    match kernel {
        Kernel::TracePhotons | Kernel::BuildGrid => [&SCENE_GROUP, &MAP_GROUP],
        Kernel::Gather => [&SCENE_GROUP, &GATHER_GROUP],
    }
}

/// The bind-group layout of `table`.
pub fn layout(dev: &wgpu::Device, table: &GroupTable) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = table
        .entries
        .iter()
        .map(|b| wgpu::BindGroupLayoutEntry {
            binding: b.binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage {
                    read_only: b.access == Access::Read,
                },
                has_dynamic_offset: b.dynamic,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("{} layout", table.label)),
        entries: &entries,
    })
}

/// The bind-group layouts, declared once per render: group 0 (scene) for every kernel,
/// group 1 for the map-building kernels or for the gather.
#[derive(Clone)]
pub struct Layouts {
    /// Layout of [`SCENE_GROUP`].
    pub scene: wgpu::BindGroupLayout,
    /// Layout of [`MAP_GROUP`].
    pub map: wgpu::BindGroupLayout,
    /// Layout of [`GATHER_GROUP`].
    pub gather: wgpu::BindGroupLayout,
}

impl Layouts {
    /// Creates the three layouts from their tables.
    pub fn new(dev: &wgpu::Device) -> Self {
        Layouts {
            scene: layout(dev, &SCENE_GROUP),
            map: layout(dev, &MAP_GROUP),
            gather: layout(dev, &GATHER_GROUP),
        }
    }
}

/// A bind group of `table` with each binding's resource given by the name of its WGSL
/// global. Every table entry must be given exactly once (a missing or unknown name is a bug
/// in the caller, caught on the first render of any test).
pub fn bind_group(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    table: &GroupTable,
    resources: Vec<(&str, wgpu::BindingResource<'_>)>,
) -> wgpu::BindGroup {
    for (name, _) in &resources {
        assert!(
            table.entry(name).is_some(),
            "bind group {label}: `{name}` is not a binding of group {}",
            table.label
        );
    }
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .into_iter()
        .map(|(name, resource)| wgpu::BindGroupEntry {
            binding: table.entry(name).map_or(u32::MAX, |b| b.binding),
            resource,
        })
        .collect();
    assert_eq!(
        entries.len(),
        table.entries.len(),
        "bind group {label}: every binding of group {} needs a resource",
        table.label
    );
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}
