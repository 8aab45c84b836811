"""Reading a Cycles node tree's inputs: a socket's constant, or the image texture (and the
channel of it) that drives it, looking through reroutes and Separate RGB/Color nodes. What
cannot be read (a procedural texture, a math node) falls back to the socket's own unlinked
value, with a warning naming the node and the input."""

from dataclasses import dataclass


@dataclass
class Driven:
    """An input driven by an Image Texture: the node, and what of it is read ("rgb" for the
    colour, "alpha", or a channel 0..2; "grey" for a colour read as a number)."""

    node: object
    read: str


def source(socket):
    """The output socket linked to ``socket`` (through reroutes), or None."""
    seen = 0
    while socket.is_linked and seen < 64:
        link = socket.links[0]
        if not link.is_valid or link.is_muted:
            return None
        out = link.from_socket
        if out.node.type != "REROUTE":
            return out
        socket = out.node.inputs[0]
        seen += 1
    return None


def _plain(value):
    """A socket value as a float or an rgb list."""
    try:
        return [float(v) for v in value][:3]
    except TypeError:
        return float(value)


def read(socket, report, where):
    """The value of input ``socket``: a float, an rgb list, or a :class:`Driven` texture."""
    out = source(socket)
    if out is None:
        return _plain(socket.default_value)
    node = out.node
    number = socket.type == "VALUE"
    if node.type == "TEX_IMAGE" and node.image is not None:
        if out.name == "Alpha":
            return Driven(node, "alpha")
        return Driven(node, "grey" if number else "rgb")
    if node.type in ("RGB", "VALUE"):
        return _plain(out.default_value)
    if node.type in ("SEPRGB", "SEPARATE_COLOR") and number:
        inner = source(node.inputs[0])
        channel = {"R": 0, "Red": 0, "G": 1, "Green": 1, "B": 2, "Blue": 2}.get(out.name)
        mode = getattr(node, "mode", "RGB")
        if inner is not None and inner.node.type == "TEX_IMAGE" and inner.name == "Color" \
                and channel is not None and mode == "RGB" and inner.node.image is not None:
            return Driven(inner.node, channel)
    report.warn(f"{where}: input {socket.name} is driven by a {node.bl_label} node, which is "
                "not translated; its unlinked value is used")
    return _plain(socket.default_value)


def constant(value, report, where, name, images_mean=None):
    """``value`` as a constant: a texture's mean (a warning says so) where a constant is all
    the material kind takes."""
    if isinstance(value, Driven):
        report.warn(f"{where}: {name} is textured, which this material kind does not take; "
                    "the image's mean is used")
        mean = images_mean(value) if images_mean else None
        return mean if mean is not None else ([1.0, 1.0, 1.0] if name != "grey" else 1.0)
    return value


def grey(value):
    """A colour read as a number (Cycles' colour-to-float: the Rec. 709 luminance)."""
    if isinstance(value, list):
        return 0.2126 * value[0] + 0.7152 * value[1] + 0.0722 * value[2]
    return value


def colour(value):
    """A number read as a colour (grey)."""
    return value if isinstance(value, list) else [value] * 3
