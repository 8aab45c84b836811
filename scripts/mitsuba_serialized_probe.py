"""Mitsuba 3.9.1's reading of a `serialized` mesh, for tests/mitsuba_serialized.rs.

Run: python3 scripts/mitsuba_serialized_probe.py [FILE] (pip mitsuba==3.9.1; FILE defaults
to the suite's tests/data/mitsuba-suite/tests/serialized/rectangle_normals_uv.serialized).
Prints the mesh Mitsuba loads (identity to_world): its vertex positions, normals, texture
coordinates and faces, as `mi.traverse` gives them.
"""
import sys
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
default = (Path(__file__).parent.parent / "tests/data/mitsuba-suite/tests/serialized"
           / "rectangle_normals_uv.serialized")
path = sys.argv[1] if len(sys.argv) > 1 else str(default)
params = mi.traverse(mi.load_dict({"type": "serialized", "filename": path}))
for key in ["vertex_positions", "vertex_normals", "vertex_texcoords", "faces"]:
    print(key, np.array(params[key]).tolist())
