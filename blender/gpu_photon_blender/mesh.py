"""Meshes from the evaluated depsgraph: modifiers applied (``Object.to_mesh``), triangulated
(``loop_triangles``), with the corner (custom split) normals, the active render UV map, the
tangents a normal map needs (Blender's MikkTSpace, ``calc_tangents``) and each triangle's
material slot, as NumPy arrays in object space. :func:`add_placements` places one in the scene.
"""

from dataclasses import dataclass

import bpy
import numpy as np

# Blender 4.1 removed calc_normals_split: corner normals are always there (Mesh.corner_normals).
HAS_CORNER_NORMALS = bpy.app.version >= (4, 1, 0)


@dataclass
class MeshData:
    """One evaluated mesh, in object space."""

    positions: np.ndarray  # (N, 3) float32
    triangles: np.ndarray  # (T, 3) uint32 vertex indices
    slots: np.ndarray  # (T,) material slot of each triangle
    normals: np.ndarray  # (3T, 3) float32 corner normals
    uvs: object  # (3T, 2) float32 or None
    tangents: object  # (3T, 4) float32 or None

    @property
    def triangle_count(self):
        return len(self.triangles)


def _get(collection, attr, count, width, dtype=np.float32):
    out = np.empty(count * width, dtype=dtype)
    collection.foreach_get(attr, out)
    return out.reshape(count, width) if width > 1 else out


def mesh_data(obj, want_tangents):
    """The arrays of evaluated object ``obj``'s mesh, or None when it has no triangles."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        mesh.calc_loop_triangles()
        tris = mesh.loop_triangles
        t = len(tris)
        if t == 0:
            return None
        positions = _get(mesh.vertices, "co", len(mesh.vertices), 3)
        triangles = _get(tris, "vertices", t, 3, np.uint32)
        loops = _get(tris, "loops", t, 3, np.int64).reshape(-1)
        slots = _get(tris, "material_index", t, 1, np.int64)
        uv_layer = next((u for u in mesh.uv_layers if u.active_render), None)
        uv_name = (uv_layer or mesh.uv_layers.active).name if len(mesh.uv_layers) else None
        tangents = None
        if want_tangents and uv_name is not None:
            try:
                mesh.calc_tangents(uvmap=uv_name)
                tan = _get(mesh.loops, "tangent", len(mesh.loops), 3)
                sign = _get(mesh.loops, "bitangent_sign", len(mesh.loops), 1)
                tangents = np.concatenate([tan, sign[:, None]], axis=1)[loops]
            except RuntimeError:
                tangents = None
        if HAS_CORNER_NORMALS:
            normals = _get(mesh.corner_normals, "vector", len(mesh.loops), 3)
        else:
            if tangents is None:
                mesh.calc_normals_split()
            normals = _get(mesh.loops, "normal", len(mesh.loops), 3)
        normals = normals[loops]
        uvs = None
        if uv_name is not None:
            # Looked up again: computing normals or tangents reallocates the loop layers, and
            # a layer's earlier Python reference then reads stale memory.
            uvs = _get(mesh.uv_layers[uv_name].data, "uv", len(mesh.loops), 2)[loops]
        return MeshData(positions, triangles, slots, np.ascontiguousarray(normals), uvs,
                        None if tangents is None else np.ascontiguousarray(tangents,
                                                                           dtype=np.float32))
    finally:
        obj.to_mesh_clear()


class Budget:
    """The triangles the scene stores so far against the scene's budget."""

    def __init__(self, limit):
        self.limit = limit
        self.used = 0

    def take(self, name, count):
        if self.used + count > self.limit:
            raise RuntimeError(
                f"{name}: the scene would store {self.used + count} triangles, more than the "
                f"budget of {self.limit} (Render Properties > gpu-photon > Triangle Budget; "
                "a mesh placed many times counts once unless its materials emit or are "
                "alpha-tested)")
        self.used += count


def add_placements(builder, data, materials, places, budget):
    """Places mesh ``data`` with ``materials`` (builder indices by slot) at each of ``places``
    ((name, object-to-world matrix) pairs): the one place instances are made. A mesh placed
    twice or more whose materials may be instanced (neither emissive nor alpha-tested:
    ``SceneBuilder.material_instanceable``) is stored once as a mesh group, gpu-photon's
    two-level BVH, and placed by instances; otherwise each placement is a copy in world
    space. The budget counts the triangles stored."""
    slots = np.clip(data.slots, 0, max(len(materials) - 1, 0))
    per_triangle = np.asarray(materials, dtype=np.uint32)[slots]
    arrays = dict(normals=data.normals, uvs=data.uvs, tangents=data.tangents)
    used = {int(m) for m in np.unique(per_triangle)}
    if len(places) >= 2 and all(builder.material_instanceable(m) for m in used):
        name = places[0][0]
        budget.take(name, data.triangle_count)
        group = builder.add_mesh_group(name, data.positions, data.triangles, per_triangle,
                                       **arrays)
        for name, matrix in places:
            builder.add_instance(name, group, np.array(matrix, dtype=np.float32))
        return
    for name, matrix in places:
        budget.take(name, data.triangle_count)
        builder.add_mesh(name, data.positions, data.triangles, per_triangle,
                         transform=np.array(matrix, dtype=np.float32), **arrays)
