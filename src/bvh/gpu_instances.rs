//! The GPU's two-level hierarchy (`trace_ray` in src/bvh/intersect.wgsl walks it, the top
//! level and the instances' meshes through `walk_instances` in src/bvh/instances.wgsl): for a
//! scene with instances, the `nodes` binding holds, after the world's hierarchy, each
//! mesh's hierarchy once (its own [`GpuBvhFrame`] and both copies of its nodes, in the
//! layout of src/bvh/gpu_layout.rs), the top level over the instances' world boxes, and one
//! [`GpuInstance`] record per instance; `leaf_prims` holds every level's leaf entries (a
//! top-level entry's id is its instance). The meshes' triangles and spheres are appended to
//! the scene's own (in object space, ids offset), so the shader reads a mesh's triangle,
//! normals and uvs as any other's ([`merged_geometry`]). A frame's `next` word links the
//! levels: the world's names the top level's frame, the top level's the first record.
//!
//! A scene without instances uploads exactly its world hierarchy ([`GpuGeometry::of`]).

use super::gpu_layout::{leaf_prims, traversal_nodes, GpuLeafPrim, TraversalLayout, GPU_COSTS};
use super::gpu_layout::{FRAME_WORDS, LEAF_COUNT_SHIFT, NODE_WORDS};
use super::gpu_sdf::{rows, SdfWords};
use super::{Bvh, SPHERE_BIT};
use crate::scene::{Scene, FLAT};
use bytemuck::{Pod, Zeroable};
use glam::Vec2;

/// Twin of WGSL `InstanceRecord`: an instance's maps as rows (`xyz` the linear part's row,
/// `w` the translation's) and the word of its mesh's frame in `nodes`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    /// World to object.
    pub to_object: [[f32; 4]; 3],
    /// Object to world.
    pub to_world: [[f32; 4]; 3],
    /// Word of the mesh's `GpuBvhFrame`.
    pub frame: u32,
    /// Padding.
    pub _pad0: u32,
    /// Padding.
    pub _pad1: u32,
    /// Padding.
    pub _pad2: u32,
}

/// 16-byte words per [`GpuInstance`].
pub const INSTANCE_WORDS: u32 = (std::mem::size_of::<GpuInstance>() / 16) as u32;
const _: () = assert!(std::mem::size_of::<GpuInstance>().is_multiple_of(16));

/// What the `nodes`, `leaf_prims` bindings and the geometry buffers get.
pub struct GpuGeometry {
    /// The `nodes` binding's bytes.
    pub nodes: Vec<u8>,
    /// The `leaf_prims` binding's leaf entries.
    pub leaf_prims: Vec<GpuLeafPrim>,
    /// The words that follow them in the binding: the SDF grids' (`super::gpu_sdf`).
    pub sdf: Vec<[u32; 4]>,
    /// The scene's geometry with its meshes' appended ([`merged_geometry`]); `None` without
    /// instances (the scene's own is uploaded).
    pub merged: Option<Scene>,
}

impl GpuGeometry {
    /// The hierarchies of `scene`, whose world hierarchy is `bvh`; `None` when one does not
    /// fit the traversal layout.
    pub fn of(scene: &Scene, bvh: &Bvh) -> Option<Self> {
        let world = traversal_nodes(bvh)?;
        if scene.instancing.is_empty() {
            let mut prims = leaf_prims(bvh, scene);
            return Some(GpuGeometry {
                nodes: world.bytes(),
                sdf: SdfWords::fill(scene, &mut prims)?,
                leaf_prims: prims,
                merged: None,
            });
        }
        let (merged, offsets) = merged_geometry(scene);
        let inst = &scene.instancing;
        let meshes: Vec<Bvh> = (inst.meshes.iter())
            .map(|m| Bvh::build_with(m, GPU_COSTS))
            .collect();
        let layouts: Vec<TraversalLayout> =
            meshes.iter().map(traversal_nodes).collect::<Option<_>>()?;
        let boxes = inst.world_boxes();
        let placed = (boxes.iter().copied().zip(0u32..)).filter(|(b, _)| b.min.cmple(b.max).all());
        let top = Bvh::over_boxes(placed, boxes.len(), GPU_COSTS);
        let top_layout = traversal_nodes(&top)?;
        // Words of each level, in order: world, meshes, top level, records.
        let words = |l: &TraversalLayout| FRAME_WORDS + NODE_WORDS * l.nodes.len() as u32;
        let mut at = words(&world);
        let mesh_word: Vec<u32> = (layouts.iter())
            .map(|l| {
                let w = at;
                at += words(l);
                w
            })
            .collect();
        let top_word = at;
        let records_word = at + words(&top_layout);
        let mut nodes = Vec::with_capacity(
            16 * (records_word + INSTANCE_WORDS * inst.instances.len() as u32) as usize,
        );
        let mut prims = leaf_prims(bvh, scene);
        let mut emit =
            |layout: &TraversalLayout, walked: bool, next: u32, prims_at: usize| -> Option<()> {
                let mut frame = layout.frame;
                // A hierarchy without primitives has a placeholder node that is never walked.
                frame.nodes = if walked { frame.nodes } else { 0 };
                frame.next = next;
                nodes.extend_from_slice(bytemuck::bytes_of(&frame));
                for n in &layout.nodes {
                    let mut n = *n;
                    if n.link >> LEAF_COUNT_SHIFT != 0 {
                        let first = (n.link & ((1 << LEAF_COUNT_SHIFT) - 1)) as usize + prims_at;
                        if first >= 1 << LEAF_COUNT_SHIFT {
                            return None;
                        }
                        n.link = (n.link & !((1 << LEAF_COUNT_SHIFT) - 1)) | first as u32;
                    }
                    nodes.extend_from_slice(bytemuck::bytes_of(&n));
                }
                Some(())
            };
        emit(&world, !bvh.prim_ids.is_empty(), top_word, 0)?;
        for (m, (b, layout)) in meshes.iter().zip(&layouts).enumerate() {
            emit(layout, !b.prim_ids.is_empty(), 0, prims.len())?;
            let (tri_at, sphere_at) = offsets[m];
            let mut p = leaf_prims(b, &inst.meshes[m]);
            for p in &mut p {
                p.id = match p.id & SPHERE_BIT {
                    0 => p.id + tri_at,
                    _ => ((p.id & !SPHERE_BIT) + sphere_at) | SPHERE_BIT,
                };
            }
            prims.extend(p);
        }
        emit(
            &top_layout,
            !top.prim_ids.is_empty(),
            records_word,
            prims.len(),
        )?;
        prims.extend((top.prim_ids.iter()).map(|&id| GpuLeafPrim {
            id,
            ..GpuLeafPrim::default()
        }));
        for i in &inst.instances {
            let record = GpuInstance {
                to_object: rows(&i.to_object),
                to_world: rows(&i.to_world),
                frame: mesh_word[i.mesh as usize],
                ..GpuInstance::default()
            };
            nodes.extend_from_slice(bytemuck::bytes_of(&record));
        }
        Some(GpuGeometry {
            nodes,
            sdf: SdfWords::fill(scene, &mut prims)?,
            leaf_prims: prims,
            merged: Some(merged),
        })
    }
}

/// The geometry of `scene` with each mesh's appended after it (triangles, their normals,
/// uvs and tangents, spheres; every other field empty), and where each mesh's triangles and
/// spheres start.
pub fn merged_geometry(scene: &Scene) -> (Scene, Vec<(u32, u32)>) {
    let meshes = &scene.instancing.meshes;
    let mut g = Scene::empty();
    g.triangles = scene.triangles.clone();
    g.shading_normals = scene.shading_normals.clone();
    g.uvs = scene.uvs.clone();
    g.tangents = scene.tangents.clone();
    g.spheres = scene.spheres.clone();
    let uvs = !scene.uvs.is_empty() || meshes.iter().any(|m| !m.uvs.is_empty());
    let tangents = !scene.tangents.is_empty() || meshes.iter().any(|m| !m.tangents.is_empty());
    let mut offsets = Vec::with_capacity(meshes.len());
    for m in meshes {
        let (first, normals) = (g.triangles.len(), g.shading_normals.len() as u32);
        offsets.push((first as u32, g.spheres.len() as u32));
        g.triangles
            .extend(m.triangles.iter().map(|t| match t.shading {
                FLAT => *t,
                s => crate::scene::Triangle {
                    shading: s + normals,
                    ..*t
                },
            }));
        g.shading_normals.extend_from_slice(&m.shading_normals);
        if uvs {
            g.uvs.resize(first, [Vec2::ZERO; 3]);
            g.uvs.extend_from_slice(&m.uvs);
        }
        if tangents {
            g.tangents.resize(first, Default::default());
            g.tangents.extend_from_slice(&m.tangents);
        }
        g.spheres.extend_from_slice(&m.spheres);
    }
    if uvs {
        g.uvs.resize(g.triangles.len(), [Vec2::ZERO; 3]);
    }
    if tangents {
        g.tangents.resize(g.triangles.len(), Default::default());
    }
    (g, offsets)
}
