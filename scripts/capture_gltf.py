#!/usr/bin/env python3
"""Writes tests/data/capture/materials.gltf (+ .bin): glTF's metallic-roughness material with
every parameter texture the importer reads (base colour, metallic-roughness, transmission,
specular, specular colour, normal, emissive), both alpha modes and the three punctual light
types, for scripts/capture.sh's byte-for-byte checks of a restructuring. Standard library only;
the textures are the checker.png beside it."""
import json
import math
import struct
from pathlib import Path

out = Path(__file__).resolve().parent.parent / "tests" / "data" / "capture"

# One unit quad in the xy plane facing +z: positions, normals, uvs, indices.
pos = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
nrm = [(0, 0, 1)] * 4
uv = [(0, 1), (1, 1), (1, 0), (0, 0)]
idx = [0, 1, 2, 0, 2, 3]
blob = b"".join(struct.pack("<3f", *p) for p in pos)
blob += b"".join(struct.pack("<3f", *n) for n in nrm)
blob += b"".join(struct.pack("<2f", *t) for t in uv)
blob += struct.pack("<6H", *idx) + b"\0\0"
(out / "materials.bin").write_bytes(blob)

tex = lambda i: {"index": 0, "texCoord": 0} if i is None else {"index": 0, **i}
materials = [
    {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1],
     "metallicFactor": 0, "roughnessFactor": 1}},
    {"name": "textured-mr", "pbrMetallicRoughness": {"baseColorTexture": tex(None),
     "metallicRoughnessTexture": tex(None), "metallicFactor": 0.6, "roughnessFactor": 0.5}},
    {"name": "transmission", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.95, 1, 1],
     "metallicFactor": 0, "roughnessFactor": 0.2},
     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.8,
                                                   "transmissionTexture": tex(None)},
                    "KHR_materials_ior": {"ior": 1.4}}},
    {"name": "specular", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.8, 1],
     "metallicFactor": 0, "roughnessFactor": 0.3},
     "extensions": {"KHR_materials_specular": {"specularFactor": 0.7,
                                               "specularTexture": tex(None),
                                               "specularColorFactor": [1, 0.8, 0.6],
                                               "specularColorTexture": tex(None)}}},
    {"name": "normal-mask", "alphaMode": "MASK", "alphaCutoff": 0.4,
     "normalTexture": {"index": 0, "scale": 0.8},
     "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 0.7],
     "baseColorTexture": tex(None), "metallicFactor": 0.3, "roughnessFactor": 0.4}},
    {"name": "blend", "alphaMode": "BLEND",
     "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.8, 0.3, 0.5],
     "metallicFactor": 1, "roughnessFactor": 0.25}},
    {"name": "emissive", "emissiveFactor": [1, 0.8, 0.5], "emissiveTexture": tex(None),
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}},
     "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1]}},
]

def rot_x(deg):
    h = math.radians(deg) / 2
    return [math.sin(h), 0, 0, math.cos(h)]

def rot_y(deg):
    h = math.radians(deg) / 2
    return [0, math.sin(h), 0, math.cos(h)]

nodes = [
    {"name": "floor", "mesh": 0, "translation": [0, -1, 0], "rotation": rot_x(-90),
     "scale": [3, 3, 1]},
    {"name": "camera", "camera": 0, "translation": [0, 0.6, 4.5], "rotation": rot_x(-10)},
    {"name": "sun", "rotation": rot_x(-60), "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "spot", "translation": [0, 2.5, 1.5], "rotation": rot_x(-70),
     "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"name": "point", "translation": [-2, 1, 2], "extensions": {"KHR_lights_punctual": {"light": 2}}},
]
for i in range(1, len(materials)):
    x = -2.0 + (i - 1) % 3 * 2.0
    y = -0.4 + (i - 1) // 3 * 1.5
    nodes.append({"name": materials[i]["name"], "mesh": i, "translation": [x, y, 0],
                  "rotation": rot_y(15 * ((i % 3) - 1)), "scale": [0.7, 0.6, 1]})

gltf = {
    "asset": {"version": "2.0", "generator": "scripts/capture_gltf.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
                       "KHR_materials_specular", "KHR_materials_emissive_strength"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "color": [1, 0.95, 0.9], "intensity": 1500},
        {"type": "spot", "color": [1, 1, 1], "intensity": 8000,
         "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}},
        {"type": "point", "color": [0.6, 0.7, 1], "intensity": 4000},
    ]}},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05,
                                                        "aspectRatio": 1.0}}],
    "materials": materials,
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                "indices": 3, "material": i}]} for i in range(len(materials))],
    "images": [{"uri": "checker.png"}],
    "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
    "textures": [{"source": 0, "sampler": 0}],
    "buffers": [{"byteLength": len(blob), "uri": "materials.bin"}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 96, "target": 34962},
        {"buffer": 0, "byteOffset": 96, "byteLength": 32, "target": 34962},
        {"buffer": 0, "byteOffset": 128, "byteLength": 12, "target": 34963},
    ],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [-1, -1, 0], "max": [1, 1, 0]},
        {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ],
}
(out / "materials.gltf").write_text(json.dumps(gltf, indent=1) + "\n")
print(f"wrote {out / 'materials.gltf'}")
