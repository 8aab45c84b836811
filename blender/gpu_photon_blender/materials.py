"""Blender materials (their Cycles node trees) as the renderer's material kinds.

The surface shader linked to the Material Output (Cycles' target) is translated node by node:

- Principled BSDF: glTF's metallic-roughness BSDF (base colour, metallic, roughness, the
  dielectric's F0 and the thin-walled transmission); with transmission 1 and metallic 0 a
  dielectric boundary (smooth glass when smooth and white). Cycles 3.x reads F0 as
  ``0.08 specular mix(1, tint, specular_tint)``, 4.x as ``((ior - 1)/(ior + 1))^2 2 level``
  times the specular tint (F90 1 in 3.x, ``min(2 level, 1)`` in 4.x). Emission colour x strength, alpha (stochastic), a normal map;
  subsurface, sheen, clearcoat and anisotropy are not rendered (a warning says so);
- Diffuse: Lambertian (its roughness, Oren-Nayar, is not rendered); Glossy: a conductor of
  Fresnel 1 tinted by its colour (GGX, alpha = roughness^2); Glass and Refraction: a
  dielectric; Emission: an emitter (two-sided, as Cycles' mesh lights); Transparent: a
  boundary light passes straight through;
- Mix Shader: with a Transparent BSDF, the other shader with alpha; with an Emission, the
  other with that emission added; Diffuse with Diffuse, their mean; Diffuse with Glossy, a
  Phong material (kd, ks by the factor, exponent 2/alpha^2 - 2), or, mixed by a Fresnel node,
  the metallic-roughness BSDF of that IOR; Add Shader likewise;
- any other shader, or a mix the above does not cover: a warning in Blender's report and the
  fallback: a Lambertian of the node's ``Color`` input (else grey 0.8); a mix takes its
  heavier side. A material without nodes renders as Cycles does, a Lambertian of its
  viewport colour; an object without a material as Cycles' default surface (grey 0.8).

Image Texture nodes drive the base colour, metallic, roughness, transmission, emission colour
and alpha inputs, and the Normal Map node (tangent space); an input another node drives uses
its unlinked value (with a warning, :mod:`nodes`).
"""

import bpy
import numpy as np

from .nodes import Driven, colour, grey, read, source

DEFAULT_GREY = [0.8, 0.8, 0.8]
V4 = bpy.app.version >= (4, 0, 0)


def _clamp01(c):
    if isinstance(c, list):
        return [min(max(x, 0.0), 1.0) for x in c]
    return min(max(c, 0.0), 1.0)


def phong_exponent(roughness):
    """The Phong exponent of a GGX lobe of perceptual ``roughness`` (Walter et al. 2007:
    ``n = 2 / alpha^2 - 2``), at most 10^4."""
    a = max(roughness * roughness, 0.01)
    return min(2.0 / (a * a) - 2.0, 1.0e4)


def f0_of_ior(ior):
    return ((ior - 1.0) / (ior + 1.0)) ** 2


class Materials:
    """Materials added to a builder, by Blender material (and the emitters lights need)."""

    def __init__(self, builder, images, report):
        self.builder = builder
        self.images = images
        self.report = report
        self.ids = {}

    def emitter(self, radiance):
        """A material that reflects nothing and emits ``radiance`` from its front face."""
        key = ("emitter",) + tuple(radiance)
        if key not in self.ids:
            spec = {"kind": "black", "emission": list(radiance)}
            self.ids[key] = self.builder.add_material(f"emitter{len(self.ids)}", spec)
        return self.ids[key]

    def index(self, material):
        """The builder's index of Blender ``material`` (None: Cycles' default surface)."""
        key = material.name if material is not None else None
        if key not in self.ids:
            spec = self.translate(material)
            self.ids[key] = self.builder.add_material(key or "default", spec)
        return self.ids[key]

    def needs_tangents(self, material):
        """Whether ``material`` reads a normal map (its meshes then need tangents)."""
        if material is None or not material.use_nodes or material.node_tree is None:
            return False
        return any(n.type == "NORMAL_MAP" and n.space == "TANGENT" and n.inputs["Color"].is_linked
                   for n in material.node_tree.nodes)

    # --- a material ---------------------------------------------------------------------

    def translate(self, material):
        if material is None:
            return {"kind": "diffuse", "colour": DEFAULT_GREY}
        if not material.use_nodes or material.node_tree is None:
            return {"kind": "diffuse", "colour": _clamp01(list(material.diffuse_color)[:3])}
        tree = material.node_tree
        out = tree.get_output_node("CYCLES")
        where = f"material {material.name}"
        if out is None:
            self.report.warn(f"{where}: no Material Output; rendered black")
            return {"kind": "black"}
        if out.inputs["Volume"].is_linked:
            self.report.warn(f"{where}: its volume is not rendered")
        if out.inputs["Displacement"].is_linked:
            self.report.warn(f"{where}: its displacement is not rendered")
        surface = source(out.inputs["Surface"])
        if surface is None:
            return {"kind": "black"}
        spec = self.shader(surface.node, where)
        return self.finish(spec, where)

    def finish(self, spec, where):
        """Textures as texture indices, and the emitter's sidedness."""
        spec = dict(spec)
        if isinstance(spec.get("colour"), Driven):
            spec["colour_texture"], spec["colour"] = spec["colour"], [1.0, 1.0, 1.0]
        if max(spec.get("emission", [0.0])) > 0.0:
            spec["two_sided_emission"] = True
        for key in [k for k in spec if isinstance(spec[k], Driven)]:
            spec[key] = self._texture(spec[key], key, where)
        return {k: v for k, v in spec.items() if v is not None}

    def _texture(self, driven, key, where):
        node = driven.node
        if key == "normal_texture":
            strength = driven.read

            def tangent_space(t):
                t = t.copy()
                t[:, :, :2] = 0.5 + (t[:, :, :2] - 0.5) * strength
                return t

            return self.images.add(node, f"normal{strength}", tangent_space)
        if key == "metallic_roughness_texture":
            return self.images.add(node, "mr" + driven.read, self._mr_transform(driven.read))
        if key == "alpha_texture":
            return self.images.add(node, "colour")
        if key == "transmission_texture":
            ch = driven.read

            def red(t):
                t = t.copy()
                t[:, :, 0] = _channel(t, ch)
                return t

            return self.images.add(node, f"transmission{ch}", red)
        return self.images.add(node, "colour")

    @staticmethod
    def _mr_transform(read_spec):
        """Packs the roughness (green) and metalness (blue) channels read as ``read_spec``
        (``"<metal>|<rough>"``, each a channel, "grey", or "-" for 1)."""
        metal, rough = read_spec.split("|")

        def pack(t):
            out = np.ones_like(t)
            out[:, :, 1] = 1.0 if rough == "-" else _channel(t, _parse(rough))
            out[:, :, 2] = 1.0 if metal == "-" else _channel(t, _parse(metal))
            return out

        return pack

    # --- shader nodes ---------------------------------------------------------------------

    def shader(self, node, where):
        """The material dict of shader ``node`` (textures still :class:`Driven`)."""
        where = f"{where}: node {node.name}"
        t = node.type
        if t == "BSDF_PRINCIPLED":
            return self.principled(node, where)
        if t == "BSDF_DIFFUSE":
            return {"kind": "diffuse", "colour": self.colour(node, "Color", where)}
        if t in ("BSDF_GLOSSY", "BSDF_ANISOTROPIC"):
            c = self.flat_colour(node, "Color", where)
            r = self.number(node, "Roughness", where)
            if getattr(node, "distribution", "") == "SHARP":
                r = 0.0
            return {"kind": "conductor", "colour": c, "roughness": r}
        if t in ("BSDF_GLASS", "BSDF_REFRACTION"):
            if t == "BSDF_REFRACTION":
                self.report.warn(f"{where}: Refraction BSDF rendered as a Glass BSDF")
            r = 0.0 if getattr(node, "distribution", "") == "SHARP" else \
                self.number(node, "Roughness", where)
            ior = self.number(node, "IOR", where, clamp=False)
            return {"kind": "dielectric", "ior": max(ior, 1e-3),
                    "roughness": r, "tint": self.flat_colour(node, "Color", where)}
        if t == "EMISSION":
            c = self.flat_colour(node, "Color", where, clamp=False)
            s = self.number(node, "Strength", where, clamp=False)
            return {"kind": "black", "emission": [max(x * s, 0.0) for x in c]}
        if t == "BSDF_TRANSPARENT":
            c = self.flat_colour(node, "Color", where)
            if min(c) < 0.999:
                self.report.warn(f"{where}: a tinted Transparent BSDF is rendered untinted")
            return {"kind": "transparent"}
        if t == "MIX_SHADER":
            return self.mix(node, where)
        if t == "ADD_SHADER":
            return self.add(node, where)
        return self.fallback(node, where)

    def fallback(self, node, where):
        c = DEFAULT_GREY
        if "Color" in node.inputs:
            c = self.flat_colour(node, "Color", where)
        self.report.warn(f"{where}: {node.bl_label} is not translated; rendered as a diffuse "
                         "surface of its colour")
        return {"kind": "diffuse", "colour": c}

    def branch(self, socket, where):
        out = source(socket)
        if out is None:
            return {"kind": "black"}
        return self.shader(out.node, where)

    def principled(self, node, where):
        i = node.inputs
        base = self.colour(node, "Base Color", where)
        metallic = self.value(node, "Metallic", where)
        roughness = self.value(node, "Roughness", where)
        ior = max(self.number(node, "IOR", where, clamp=False), 1.0)
        transmission = self.value(node, "Transmission Weight" if V4 else "Transmission", where)
        alpha = self.value(node, "Alpha", where)
        em_name = "Emission Color" if V4 else "Emission"
        emission = self.colour(node, em_name, where, clamp=False)
        strength = self.number(node, "Emission Strength", where, clamp=False)
        ignored = [("Subsurface Weight", "subsurface"), ("Sheen Weight", "sheen"),
                   ("Coat Weight", "coat")] if V4 else \
            [("Subsurface", "subsurface"), ("Sheen", "sheen"), ("Clearcoat", "clearcoat")]
        ignored.append(("Anisotropic", "anisotropy"))
        for name, what in ignored:
            if name in i and (i[name].is_linked or i[name].default_value > 0.0):
                self.report.warn(f"{where}: {what} is not rendered")
        if V4:
            level = self.number(node, "Specular IOR Level", where, clamp=False)
            tint = self.flat_colour(node, "Specular Tint", where)
            f0 = [min(f0_of_ior(ior) * 2.0 * level * c, 1.0) for c in tint]
            f90 = min(2.0 * level, 1.0)
        else:
            specular = self.number(node, "Specular", where, clamp=False)
            spec_tint = self.number(node, "Specular Tint", where)
            b = base if isinstance(base, list) else [1.0, 1.0, 1.0]
            lum = grey(b)
            tint = [x / lum for x in b] if lum > 0.0 else [1.0, 1.0, 1.0]
            f0 = [min(0.08 * specular * (1.0 - spec_tint + spec_tint * c), 1.0) for c in tint]
            # Cycles 3.x's Fresnel goes to white at grazing angles whatever the specular.
            f90 = 1.0
        spec = {}
        const = lambda v: v if not isinstance(v, Driven) else None  # noqa: E731
        if const(transmission) == 1.0 and const(metallic) == 0.0:
            r = const(roughness) if const(roughness) is not None else 0.5
            if not V4:
                tr = self.number(node, "Transmission Roughness", where)
                r = 1.0 - (1.0 - r) * (1.0 - tr)
            spec = {"kind": "dielectric", "ior": ior, "roughness": r,
                    "tint": self.flat(base, where, "Base Color")}
        else:
            if const(transmission) not in (0.0, None):
                self.report.warn(f"{where}: partial transmission ({transmission:g}) is rendered "
                                 "thin-walled")
            spec = {"kind": "metallic_roughness", "f0": f0, "f90": f90}
            spec["base"] = [1.0, 1.0, 1.0] if isinstance(base, Driven) else base
            if isinstance(base, Driven):
                spec["colour_texture"] = base
            spec["metallic"], spec["roughness"] = self._mr(metallic, roughness, spec, where)
            if isinstance(transmission, Driven):
                spec["transmission"] = 1.0
                spec["transmission_texture"] = Driven(transmission.node, transmission.read)
            else:
                spec["transmission"] = transmission
        em = [max(c * strength, 0.0) for c in emission] if not isinstance(emission, Driven) \
            else [strength] * 3
        if max(em) > 0.0:
            spec["emission"] = em
            if isinstance(emission, Driven):
                spec["emission_texture"] = emission
        self._alpha(spec, alpha)
        normal = self.normal_map(i["Normal"], where)
        if normal is not None:
            spec["normal_texture"] = normal
        return spec

    def _mr(self, metallic, roughness, spec, where):
        """The metalness and roughness factors; a texture on either goes into one packed
        metallic-roughness texture (channels read from one image)."""
        m_tex, r_tex = isinstance(metallic, Driven), isinstance(roughness, Driven)
        if not (m_tex or r_tex):
            return metallic, roughness
        if m_tex and r_tex and metallic.node.image != roughness.node.image:
            self.report.warn(f"{where}: metallic and roughness read different images; the "
                             "metallic image's mean is used")
            metallic = float(np.mean(_channel(self.images_texels(metallic.node),
                                              _parse(metallic.read))))
            m_tex = False
        node = metallic.node if m_tex else roughness.node
        read_spec = f"{metallic.read if m_tex else '-'}|{roughness.read if r_tex else '-'}"
        spec["metallic_roughness_texture"] = Driven(node, read_spec)
        return (1.0 if m_tex else metallic), (1.0 if r_tex else roughness)

    def images_texels(self, node):
        from .images import texels
        return texels(node.image)

    @staticmethod
    def _alpha(spec, alpha):
        if isinstance(alpha, Driven):
            spec["alpha"] = 1.0
            spec["alpha_texture"] = alpha
            spec["alpha_luminance"] = alpha.read != "alpha"
        elif alpha < 1.0:
            spec["alpha"] = max(alpha, 0.0)

    def normal_map(self, socket, where):
        out = source(socket)
        if out is None:
            return None
        node = out.node
        if node.type != "NORMAL_MAP" or node.space != "TANGENT":
            self.report.warn(f"{where}: its Normal input is driven by a {node.bl_label} node "
                             "(only a tangent-space Normal Map is rendered)")
            return None
        image = source(node.inputs["Color"])
        if image is None or image.node.type != "TEX_IMAGE" or image.node.image is None:
            return None
        strength = node.inputs["Strength"].default_value
        return Driven(image.node, float(strength))

    # --- mixing ---------------------------------------------------------------------------

    def mix(self, node, where):
        fac_socket = node.inputs[0]
        a = self.branch(node.inputs[1], where)
        b = self.branch(node.inputs[2], where)
        fac_src = source(fac_socket)
        if fac_src is not None and fac_src.node.type == "FRESNEL" and \
                a["kind"] == "diffuse" and b["kind"] == "conductor":
            ior = max(fac_src.node.inputs["IOR"].default_value, 1.0)
            spec = {"kind": "metallic_roughness", "base": a["colour"], "metallic": 0.0,
                    "roughness": b["roughness"], "f0": [f0_of_ior(ior)] * 3, "f90": 1.0,
                    "transmission": 0.0}
            if isinstance(a["colour"], Driven):
                spec["base"], spec["colour_texture"] = [1.0] * 3, a["colour"]
            return spec
        fac = self.number(node, "Fac", where)
        return self.combine(a, 1.0 - fac, b, fac, where, "Mix Shader")

    def add(self, node, where):
        a = self.branch(node.inputs[0], where)
        b = self.branch(node.inputs[1], where)
        return self.combine(a, 1.0, b, 1.0, where, "Add Shader")

    def combine(self, a, wa, b, wb, where, what):
        """``wa a + wb b`` in one of the renderer's kinds (module documentation)."""
        if wb <= 0.0:
            return a
        if wa <= 0.0:
            return b
        for x, wx, y, wy in ((a, wa, b, wb), (b, wb, a, wa)):
            if y["kind"] == "transparent":
                out = dict(x)
                out["alpha"] = out.get("alpha", 1.0) * min(wx / (wx + wy), 1.0)
                return out
            if y["kind"] == "black" and "emission" in y and x["kind"] != "black":
                out = dict(x)
                e = [wy * c for c in y["emission"]]
                out["emission"] = [p + q for p, q in zip(out.get("emission", [0.0] * 3), e)]
                return out
        kinds = {a["kind"], b["kind"]}
        if kinds == {"black"}:
            e = [wa * p + wb * q for p, q in zip(a.get("emission", [0.0] * 3),
                                                 b.get("emission", [0.0] * 3))]
            return {"kind": "black", "emission": e}
        flat = lambda c: c if isinstance(c, list) else None  # noqa: E731
        if kinds == {"diffuse"} and flat(a["colour"]) and flat(b["colour"]):
            c = [wa * p + wb * q for p, q in zip(a["colour"], b["colour"])]
            return {"kind": "diffuse", "colour": _clamp01(c)}
        if kinds == {"diffuse", "conductor"}:
            d, g = (a, b) if a["kind"] == "diffuse" else (b, a)
            wd, wg = (wa, wb) if a["kind"] == "diffuse" else (wb, wa)
            if flat(d["colour"]):
                kd = [wd * c for c in d["colour"]]
                ks = [wg * c for c in g["colour"]]
                total = max(p + q for p, q in zip(kd, ks))
                if total > 1.0:
                    kd, ks = [c / total for c in kd], [c / total for c in ks]
                return {"kind": "phong", "kd": kd, "ks": ks,
                        "exponent": phong_exponent(g["roughness"])}
        heavier = a if wa >= wb else b
        self.report.warn(f"{where}: a {what} of {a['kind']} and {b['kind']} is rendered as "
                         f"its heavier side ({heavier['kind']})")
        return heavier

    # --- inputs ---------------------------------------------------------------------------

    def value(self, node, name, where):
        """A number input, or its :class:`Driven` texture."""
        v = read(node.inputs[name], self.report, where)
        if isinstance(v, Driven):
            return v
        return _clamp01(grey(v))

    def number(self, node, name, where, clamp=True):
        v = read(node.inputs[name], self.report, where)
        if isinstance(v, Driven):
            self.report.warn(f"{where}: {name} is textured, which is not rendered; its "
                             "unlinked value is used")
            v = node.inputs[name].default_value
        v = grey(v)
        return _clamp01(v) if clamp else v

    def colour(self, node, name, where, clamp=True):
        """A colour input, or its :class:`Driven` texture."""
        v = read(node.inputs[name], self.report, where)
        if isinstance(v, Driven):
            if v.read != "rgb":
                self.report.warn(f"{where}: {name} reads one channel of an image; its colour "
                                 "is used")
            return Driven(v.node, "rgb")
        v = colour(v)
        return _clamp01(v) if clamp else v

    def flat_colour(self, node, name, where, clamp=True):
        return self.flat(self.colour(node, name, where, clamp), where, name)

    def flat(self, c, where, name):
        """``c`` as a constant colour: a texture's mean (with a warning)."""
        if not isinstance(c, Driven):
            return c
        self.report.warn(f"{where}: {name} is textured, which this kind does not take; the "
                         "image's mean colour is used")
        t = self.images_texels(c.node)
        if t is None:
            return DEFAULT_GREY
        return _clamp01([float(x) for x in t[:, :, :3].reshape(-1, 3).mean(axis=0)])


def _parse(read_spec):
    return int(read_spec) if read_spec.isdigit() else read_spec


def _channel(t, read_spec):
    """The (H, W) values ``read_spec`` reads of texels ``t``."""
    if read_spec == "alpha":
        return t[:, :, 3]
    if read_spec == "grey" or read_spec == "rgb":
        return 0.2126 * t[:, :, 0] + 0.7152 * t[:, :, 1] + 0.0722 * t[:, :, 2]
    return t[:, :, int(read_spec)]

