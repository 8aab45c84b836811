"""The scene's camera and image size as Cycles reads them (``intern/cycles/blender/camera.cpp``):
the output size is the render resolution times its percentage; the sensor fits the image's
wider side (``AUTO``: horizontal when width > height) or the side ``sensor_fit`` names, its
field of view ``2 atan(sensor / (2 lens))`` (an orthographic camera's view ``ortho_scale``
wide on that side); depth of field's aperture radius is
``lens / (2 f-stop)`` (lens in metres), focused at ``focus_distance`` or at the focus
object's depth along the view axis. The camera looks along its object's -Z axis, +Y up."""

import math


def resolution(scene):
    """The image size in pixels (resolution times percentage, at least 1 x 1)."""
    r = scene.render
    scale = r.resolution_percentage / 100.0
    return max(1, int(r.resolution_x * scale)), max(1, int(r.resolution_y * scale))


def camera_args(scene, camera_obj, width, height, report):
    """Keyword arguments of ``SceneBuilder.set_camera`` for ``camera_obj`` (evaluated)."""
    cam = camera_obj.data
    m = camera_obj.matrix_world
    eye = list(m.translation)
    forward = list(-m.col[2].xyz.normalized())
    up = list(m.col[1].xyz.normalized())
    r = scene.render
    xratio = width * r.pixel_aspect_x
    yratio = height * r.pixel_aspect_y
    if cam.type == "PANO":
        report.warn(f"camera {cam.name}: a panoramic camera is rendered as a perspective one "
                    "of the same lens")
    if cam.shift_x != 0.0 or cam.shift_y != 0.0:
        report.warn(f"camera {cam.name}: lens shift is not rendered")
    if cam.sensor_fit == "AUTO":
        horizontal, sensor = xratio > yratio, cam.sensor_width
    elif cam.sensor_fit == "HORIZONTAL":
        horizontal, sensor = True, cam.sensor_width
    else:
        horizontal, sensor = False, cam.sensor_height
    tan_half = sensor / (2.0 * cam.lens)
    if horizontal:
        tan_half *= yratio / xratio
    fov_y = math.degrees(2.0 * math.atan(tan_half))
    ortho = None
    if cam.type == "ORTHO":
        ortho = cam.ortho_scale * (yratio / xratio if horizontal else 1.0)
        if cam.dof.use_dof:
            report.warn(f"camera {cam.name}: an orthographic camera's depth of field is not "
                        "rendered")
        return dict(eye=eye, forward=forward, up=up, fov_y=fov_y, width=width, height=height,
                    orthographic_height=ortho)
    aperture, focus = 0.0, 1.0
    if cam.dof.use_dof:
        fstop = max(cam.dof.aperture_fstop, 1e-5)
        aperture = cam.lens * 1e-3 / (2.0 * fstop)
        target = cam.dof.focus_object
        if target is not None:
            view = m.col[2].xyz.normalized()
            focus = abs(view.dot(m.translation - target.matrix_world.translation))
        else:
            focus = cam.dof.focus_distance
        focus = max(focus, 1e-4)
    return dict(eye=eye, forward=forward, up=up, fov_y=fov_y, width=width, height=height,
                aperture_radius=aperture, focus_distance=focus)
