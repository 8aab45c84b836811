"""Blender images as the renderer's textures: linear RGBA float texels, handed over once per
image and use.

``Image.pixels`` holds a byte image's values as stored (sRGB-encoded for an sRGB image) and a
float image's as scene-linear; an sRGB byte image is decoded here (IEC 61966-2-1), a
``Non-Color`` one is data. Rows go from the bottom of the image up, as Blender's v does, which
is the renderer's row order by v (row 0 at v = 0), so neither rows nor uvs are flipped.
"""

import numpy as np

# Colour spaces whose texels are data, not colour.
DATA_SPACES = {"Non-Color", "Raw", "Linear", "Linear Rec.709", "Linear CIE-XYZ E", "XYZ"}


def srgb_to_linear(c):
    """IEC 61966-2-1's decoding of sRGB values in [0, 1]."""
    c = np.clip(c, 0.0, None)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def texels(image):
    """Linear RGBA float32 texels (H, W, 4) of Blender ``image``, or None when it has none."""
    w, h = image.size
    if w == 0 or h == 0:
        return None
    n = w * h * image.channels
    data = np.empty(n, dtype=np.float32)
    image.pixels.foreach_get(data)
    data = data.reshape(h, w, image.channels)
    if image.channels != 4:
        rgba = np.ones((h, w, 4), dtype=np.float32)
        k = min(image.channels, 3)
        rgba[:, :, :k] = data[:, :, :k]
        if image.channels < 3:
            rgba[:, :, 1:3] = data[:, :, :1]
        data = rgba
    space = image.colorspace_settings.name
    if not image.is_float and space not in DATA_SPACES:
        data[:, :, :3] = srgb_to_linear(data[:, :, :3])
    return np.ascontiguousarray(data, dtype=np.float32)


class Images:
    """Textures added to a builder, by image and the transform of their texels."""

    def __init__(self, builder, report):
        self.builder = builder
        self.report = report
        self.ids = {}

    def add(self, node, purpose="colour", transform=None):
        """The texture index of Image Texture ``node``'s image, its texels through
        ``transform`` (a function of the (H, W, 4) array, named by ``purpose``); None when
        the image has no pixels."""
        image = node.image
        if image is None:
            return None
        key = (image.name, purpose)
        if key in self.ids:
            return self.ids[key]
        rgba = texels(image)
        if rgba is None:
            self.report.warn(f"image {image.name}: no pixels (not found?); not rendered")
            self.ids[key] = None
            return None
        if transform is not None:
            rgba = np.ascontiguousarray(transform(rgba), dtype=np.float32)
        if node.projection != "FLAT":
            self.report.warn(f"image {image.name}: {node.projection} projection is read as FLAT")
        if node.inputs["Vector"].is_linked:
            self.report.warn(f"image {image.name}: its Vector input is not read (the active "
                             "render UV map is)")
        interpolation = "closest" if node.interpolation == "Closest" else "linear"
        extension = {"REPEAT": "repeat", "MIRROR": "mirror"}.get(node.extension, "clamp")
        tid = self.builder.add_texture(f"{image.name}:{purpose}", rgba, interpolation, extension)
        self.ids[key] = tid
        return tid
