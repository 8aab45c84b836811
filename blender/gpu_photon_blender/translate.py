"""The evaluated depsgraph as a ``gpu_photon.SceneBuilder`` scene, without a file: every
visible object instance (meshes and what evaluates to a mesh: curves, text, metaballs,
geometry-node instances), the lights, the scene camera at the render resolution and the world.
"""

from . import camera, lights, mesh, world
from .images import Images
from .materials import Materials

# Object types that evaluate to a mesh through Object.to_mesh.
GEOMETRY = {"MESH", "CURVE", "SURFACE", "FONT", "META", "CURVES_LEGACY"}


class Report:
    """Warnings for Blender's report, each once."""

    def __init__(self, engine=None):
        self.engine = engine
        self.seen = []

    def warn(self, message):
        if message in self.seen:
            return
        self.seen.append(message)
        if self.engine is not None:
            self.engine.report({"WARNING"}, f"gpu-photon: {message}")
        else:
            print(f"gpu-photon: warning: {message}")


def _slot_materials(obj, materials):
    """Builder material indices of ``obj``'s slots (at least one: the default surface)."""
    slots = [s.material for s in obj.material_slots] or [None]
    return [materials.index(m) for m in slots]


def build(depsgraph, report, max_triangles):
    """The ``gpu_photon.Scene`` of ``depsgraph`` and the count of triangles it stores (a mesh
    placed many times and stored once as a mesh group counts once)."""
    import gpu_photon

    scene = depsgraph.scene
    builder = gpu_photon.SceneBuilder(f"blender:{scene.name}")
    images = Images(builder, report)
    materials = Materials(builder, images, report)
    budget = mesh.Budget(max_triangles)
    shared = {}
    # Each mesh's placements, in the depsgraph's order: (key, name, object-to-world).
    placements = {}
    count = 0
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type in GEOMETRY:
            # A mesh placed many times (collection instances, particles, geometry nodes)
            # is read once: its evaluated data is the key.
            slots = [s.material for s in obj.material_slots]
            data_id = obj.data.as_pointer() if obj.data is not None else obj.as_pointer()
            key = (data_id, tuple(m.name if m else None for m in slots))
            if key not in shared:
                tangents = any(materials.needs_tangents(m) for m in slots)
                shared[key] = (mesh.mesh_data(obj, tangents), _slot_materials(obj, materials))
            if shared[key][0] is None:
                continue
            count += 1
            name = f"{obj.name}#{count}" if inst.is_instance else obj.name
            placements.setdefault(key, []).append((name, inst.matrix_world.copy()))
        elif obj.type == "LIGHT":
            lights.add_light(builder, materials, obj.name, _Placed(obj, inst), report)
        elif obj.type not in ("CAMERA", "EMPTY", "ARMATURE", "LATTICE", "SPEAKER",
                              "LIGHT_PROBE"):
            report.warn(f"object {obj.name}: type {obj.type} is not rendered")
    for key, places in placements.items():
        data, slot_ids = shared[key]
        mesh.add_placements(builder, data, slot_ids, places, budget)
    width, height = camera.resolution(scene)
    cam = scene.camera
    if cam is None:
        raise RuntimeError("the scene has no camera")
    cam = cam.evaluated_get(depsgraph)
    builder.set_camera(**camera.camera_args(scene, cam, width, height, report))
    world.add_world(builder, scene.world, report)
    return builder.finish(), budget.used


class _Placed:
    """A light object seen through one of its instances: its data and the instance's
    world matrix."""

    def __init__(self, obj, inst):
        self.data = obj.data
        self.matrix_world = inst.matrix_world.copy()

