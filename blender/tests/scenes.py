"""Test scenes built with bpy from an empty factory scene: the Cornell box with a glass and a
mirror sphere (under an area light, or under an emissive quad for the glTF round trip), and a
diffuse plane under one light for the analytic irradiance tests."""

import math

import bpy


def empty_scene(width, height):
    """Removes every object (and the data of earlier test scenes) and sets the resolution
    (100%) and a black world."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for data in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(data):
            data.remove(block)
    scene = bpy.context.scene
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    for node in list(world.node_tree.nodes):
        if node.type not in ("BACKGROUND", "OUTPUT_WORLD"):
            world.node_tree.nodes.remove(node)
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    return scene


# Principled BSDF inputs renamed in Blender 4.0 (the v2 node), for the same meaning at the
# values the tests use: "Specular" 0.5 (F0 0.04 at IOR 1.5) and 0 are "Specular IOR Level" 0.5
# (the IOR's own F0) and 0.
PRINCIPLED_V4 = {"Transmission": "Transmission Weight", "Specular": "Specular IOR Level"}


def material(name, kind, **params):
    """A node material: ``kind`` is "diffuse", "glass", "mirror", "emission" or
    "principled" (then ``params`` are Principled inputs by name)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    out = nodes["Material Output"]
    for n in list(nodes):
        if n != out:
            nodes.remove(n)
    if kind == "principled":
        node = nodes.new("ShaderNodeBsdfPrincipled")
        for key, value in params.items():
            if bpy.app.version >= (4, 0, 0):
                key = PRINCIPLED_V4.get(key, key)
            node.inputs[key].default_value = value
    elif kind == "diffuse":
        node = nodes.new("ShaderNodeBsdfDiffuse")
        node.inputs["Color"].default_value = (*params["colour"], 1.0)
    elif kind == "glass":
        node = nodes.new("ShaderNodeBsdfGlass")
        node.inputs["IOR"].default_value = params.get("ior", 1.5)
        node.inputs["Roughness"].default_value = 0.0
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    elif kind == "mirror":
        node = nodes.new("ShaderNodeBsdfGlossy")
        node.inputs["Roughness"].default_value = 0.0
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    elif kind == "emission":
        node = nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        node.inputs["Strength"].default_value = params["strength"]
    else:
        raise ValueError(kind)
    links.new(node.outputs[0], out.inputs["Surface"])
    return m


def mesh_object(name, verts, faces, mat, smooth=False):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    for p in me.polygons:
        p.use_smooth = smooth
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    if mat is not None:
        obj.data.materials.append(mat)
    return obj


def quad(name, corners, mat):
    return mesh_object(name, corners, [(0, 1, 2, 3)], mat)


def sphere(name, centre, radius, mat, segments=48, rings=24):
    """A smooth UV sphere (its own mesh, built without operators)."""
    verts = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(segments):
            p = 2.0 * math.pi * j / segments
            verts.append((radius * math.sin(t) * math.cos(p), radius * math.sin(t) * math.sin(p),
                          radius * math.cos(t)))
    verts.append((0.0, 0.0, -radius))
    faces = []
    last = len(verts) - 1
    for j in range(segments):
        faces.append((0, 1 + j, 1 + (j + 1) % segments))
    for i in range(rings - 2):
        a, b = 1 + i * segments, 1 + (i + 1) * segments
        for j in range(segments):
            k = (j + 1) % segments
            faces.append((a + j, b + j, b + k, a + k))
    base = 1 + (rings - 2) * segments
    for j in range(segments):
        faces.append((base + j, last, base + (j + 1) % segments))
    verts = [(x + centre[0], y + centre[1], z + centre[2]) for x, y, z in verts]
    return mesh_object(name, verts, faces, mat, smooth=True)


def camera(location, target, lens=35.0):
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    obj = bpy.data.objects.new("Camera", cam)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    direction = (target[0] - location[0], target[1] - location[1], target[2] - location[2])
    from mathutils import Vector
    obj.rotation_euler = Vector(direction).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.camera = obj
    return obj


def area_light(name, location, size, power, shape="SQUARE", size_y=None):
    light = bpy.data.lights.new(name, "AREA")
    light.energy = power
    light.shape = shape
    light.size = size
    if size_y is not None:
        light.size_y = size_y
    obj = bpy.data.objects.new(name, light)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    return obj


def cornell_box(width=64, height=64, principled=False, light="area"):
    """The Cornell box: [-1, 1] x [-1, 1] x [0, 2], open towards -Y where the camera is,
    white floor, ceiling and back wall, red left and green right wall; a glass sphere and a
    mirror sphere on the floor. ``light`` "area": a 0.5 m square area light of 40 W under
    the ceiling; "lamp": a box of the same size under the ceiling whose bottom face emits
    radiance 40; "point": a 100 W point light at z = 1.8. ``principled``: every material a Principled BSDF (what glTF exports)."""
    scene = empty_scene(width, height)
    if principled:
        def diffuse(name, c):
            return material(name, "principled", **{"Base Color": (*c, 1.0), "Specular": 0.0,
                                                   "Roughness": 1.0})
        glass = material("Glass", "principled", **{"Transmission": 1.0, "Roughness": 0.0,
                                                   "IOR": 1.5, "Specular": 0.5,
                                                   "Base Color": (1.0, 1.0, 1.0, 1.0)})
        _gltf_thickness(glass, 0.7)
        mirror = material("Mirror", "principled", **{"Metallic": 1.0, "Roughness": 0.0,
                                                     "Base Color": (1.0, 1.0, 1.0, 1.0)})
    else:
        def diffuse(name, c):
            return material(name, "diffuse", colour=c)
        glass = material("Glass", "glass", ior=1.5)
        mirror = material("Mirror", "mirror")
    white = diffuse("White", (0.8, 0.8, 0.8))
    red = diffuse("Red", (0.8, 0.1, 0.1))
    green = diffuse("Green", (0.1, 0.8, 0.1))
    quad("Floor", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], white)
    quad("Ceiling", [(-1, -1, 2), (-1, 1, 2), (1, 1, 2), (1, -1, 2)], white)
    quad("Back", [(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)], white)
    quad("Left", [(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)], red)
    quad("Right", [(1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0)], green)
    sphere("GlassSphere", (0.4, -0.25, 0.35), 0.35, glass)
    sphere("MirrorSphere", (-0.4, 0.3, 0.35), 0.35, mirror)
    if light == "area":
        lamp = area_light("Light", (0.0, 0.0, 1.98), 0.5, 40.0)
        lamp.visible_camera = True  # as ours: gpu-photon's emitters are seen by the camera
    elif light == "point":
        point = bpy.data.lights.new("Light", "POINT")
        point.energy, point.shadow_soft_size = 100.0, 0.0
        obj = bpy.data.objects.new("Light", point)
        bpy.context.scene.collection.objects.link(obj)
        obj.location = (0.0, 0.0, 1.8)
    else:
        # Its black is an Emission of strength 0: black in Blender and in glTF alike.
        black = material("LampBlack", "emission", strength=0.0)
        lamp_box(black, material("Lamp", "emission", strength=40.0))
    camera((0.0, -3.6, 1.0), (0.0, 0.0, 1.0), lens=35.0)
    return scene


def lamp_box(black, emit):
    """A 0.5 x 0.5 x 0.02 m box under the ceiling, black but for its emissive bottom face: a
    lamp that glTF's one-sided emission and Cycles' two-sided one render alike."""
    lo, hi, h = -0.25, 0.25, 1.96
    top = 1.98
    verts = [(lo, lo, h), (hi, lo, h), (hi, hi, h), (lo, hi, h),
             (lo, lo, top), (hi, lo, top), (hi, hi, top), (lo, hi, top)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    obj = mesh_object("Lamp", verts, faces, black)
    obj.data.materials.append(emit)
    obj.data.polygons[0].material_index = 1
    return obj


def _gltf_thickness(mat, thickness):
    """The glTF exporter's "glTF Material Output" group with a Thickness, so that the glass
    is exported as a volume (KHR_materials_volume), not thin-walled."""
    group = bpy.data.node_groups.get("glTF Material Output")
    if group is None:
        group = bpy.data.node_groups.new("glTF Material Output", "ShaderNodeTree")
        if hasattr(group, "interface"):
            group.interface.new_socket("Thickness", in_out="INPUT", socket_type="NodeSocketFloat")
        else:
            group.inputs.new("NodeSocketFloat", "Thickness")
    node = mat.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.inputs["Thickness"].default_value = thickness


def plane_under(light_obj, size=4.0, albedo=0.5):
    """A diffuse plane z = 0 of ``size`` and ``albedo``, the only surface in the scene."""
    mat = material("Plane", "diffuse", colour=(albedo, albedo, albedo))
    h = 0.5 * size
    return quad("Plane", [(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], mat)
