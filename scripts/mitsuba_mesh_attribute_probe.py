"""Mitsuba 3.9.1's PLY attribute grouping, for tests/ply.rs
(`custom_attributes_group_as_mitsuba_groups_them`).

Run: python3 scripts/mitsuba_mesh_attribute_probe.py (pip mitsuba==3.9.1). Writes the test's
PLY (its quad as two triangles: Mitsuba's reader takes triangles only) to a temporary
directory and prints the mesh attributes Mitsuba makes of it (`mi.traverse`).
"""
import os
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
property float temp_0
property float uv_x
property float uv_y
property float w_1
property float w_2
property float w_3
property float bad
element face 2
property list uchar int vertex_indices
property float color_r
property float color_g
property float color_b
property float weight_0
end_header
0 0 0 255 128 0 1.5 1 2 1 2 3 9
1 0 0 0 0 0 2.5 1 2 4 5 6 9
1 1 0 0 0 0 3.5 1 2 7 8 9 9
0 1 0 0 0 0 4.5 1 2 1 1 1 9
3 0 1 2 0.1 0.2 0.3 0.7
3 0 2 3 0.1 0.2 0.3 0.7
"""
path = os.path.join(tempfile.mkdtemp(), "a.ply")
with open(path, "w") as f:
    f.write(PLY)
params = mi.traverse(mi.load_dict({"type": "ply", "filename": path}))
for key in params.keys():
    if key.startswith(("vertex_", "face_")) and key not in (
            "vertex_count", "face_count", "vertex_positions", "vertex_normals",
            "vertex_texcoords", "faces"):
        print(key, np.array(params[key]).round(6).tolist())
