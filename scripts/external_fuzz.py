#!/usr/bin/env python3
"""External fuzzing of `gpu-photon render`, as a new user's fuzzer would do it (issue 44).

Mutated copies of scenes from the project (scenes/, tests/data/, the in-process fuzzer's seeds
and a generated 77,792-triangle glTF/GLB sphere) are rendered by the release binary, one
process per case, under a 4 GiB address-space limit (`ulimit -v 4194304`) and a 20 s deadline,
tiny (8x8, 1 spp, 2,000 photons, one classic pass, CPU backend). The mutator is this file's
own, written independently of tests/fuzz/mutate.rs: token edits (numbers, strings, lines),
tree edits of JSON (repeated or shared list items, values of other types) and of XML (repeated
or nested elements, attribute values), byte and word edits of binary files, GLB chunks rebuilt.

Each case's outcome: `rendered` (exit 0), `refused` (exit 1 with one `error: ...` line),
`unescaped` (a message split over lines or holding a control character), `panic` ("panicked"
on stderr, or exit 101), `abort` (killed by SIGABRT: a failed allocation under the limit, or
an abort), `crash` (another signal), `hang` (past the deadline), `other` (any other exit).
Every case but `rendered` and `refused` is a failure, kept in --keep. Prints a table per format.

    python3 scripts/external_fuzz.py --cases 500 --seed 1         # 500 per format
    python3 scripts/external_fuzz.py --cases 50 --formats gltf,glb --keep /tmp/kept
    python3 scripts/external_fuzz.py --write-sphere DIR --segments 64 --rings 33

Python 3.11 standard library only. Cases are reproducible from (--seed, format, case number).
"""

import argparse
import json
import math
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FORMATS = ["toml", "xml", "gltf", "glb", "ply", "obj"]
ADDRESS_SPACE = 4194304 * 1024  # `ulimit -v 4194304` (KiB)
DEADLINE = 20.0
RENDER = ["--backend", "cpu", "--width", "8", "--height", "8", "--spp", "1", "--photons",
          "2000", "--caustic-photons", "1000", "--passes", "0", "-q"]

# ---------------------------------------------------------------------------------------------
# Seeds


def sphere(segments, rings):
    """A UV sphere of radius 1: positions and normals (float32 xyz), u32 triangle indices;
    2 * segments * (rings - 1) triangles (the poles' rows kept, degenerate triangles and all)."""
    pos = []
    for r in range(rings):
        theta = math.pi * r / (rings - 1)
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            pos.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                        math.sin(theta) * math.sin(phi)))
    idx = []
    row = segments + 1
    for r in range(rings - 1):
        for s in range(segments):
            a, b = r * row + s, r * row + s + 1
            c, d = a + row, b + row
            idx += [a, c, b, b, c, d]
    return pos, idx


def sphere_gltf(segments, rings, bin_name):
    """A glTF document (dict) and its buffer for a Lambertian sphere lit by a point light,
    with a camera."""
    pos, idx = sphere(segments, rings)
    p = b"".join(struct.pack("<3f", *v) for v in pos)
    n = p  # unit sphere: the normal is the position
    i = struct.pack(f"<{len(idx)}I", *idx)
    buf = p + n + i
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 1, 1], "intensity": 50}]}},
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 0, 4]},
            {"translation": [2, 2, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1,
                                                             "aspectRatio": 1.0}}],
        # Lambertian (no specular lobe): no caustic map to aim at it, so each case is cheap.
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                    "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": len(buf)} | ({"uri": bin_name} if bin_name else {})],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(p), "target": 34962},
            {"buffer": 0, "byteOffset": len(p), "byteLength": len(n), "target": 34962},
            {"buffer": 0, "byteOffset": 2 * len(p), "byteLength": len(i), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
    }
    return doc, buf


def glb(json_bytes, bin_bytes):
    """A GLB container of a JSON chunk and (when not empty) a BIN chunk, padded to 4 bytes."""
    json_bytes += b" " * (-len(json_bytes) % 4)
    bin_bytes += b"\0" * (-len(bin_bytes) % 4)
    total = 12 + 8 + len(json_bytes) + (8 + len(bin_bytes) if bin_bytes else 0)
    out = b"glTF" + struct.pack("<II", 2, total)
    out += struct.pack("<I", len(json_bytes)) + b"JSON" + json_bytes
    if bin_bytes:
        out += struct.pack("<I", len(bin_bytes)) + b"BIN\0" + bin_bytes
    return out


def glb_chunks(data):
    """A GLB file's JSON and BIN payloads, or None when it is not one."""
    if data[:4] != b"glTF" or len(data) < 20:
        return None
    n = struct.unpack_from("<I", data, 12)[0]
    js = data[20:20 + n]
    rest = data[20 + n:]
    binary = b""
    if len(rest) >= 8:
        m = struct.unpack_from("<I", rest, 0)[0]
        binary = rest[8:8 + m]
    return js, binary


def write_sphere(directory, segments, rings, as_glb):
    directory.mkdir(parents=True, exist_ok=True)
    if as_glb:
        doc, buf = sphere_gltf(segments, rings, None)
        (directory / "scene.glb").write_bytes(glb(json.dumps(doc).encode(), buf))
    else:
        doc, buf = sphere_gltf(segments, rings, "scene.bin")
        (directory / "scene.gltf").write_text(json.dumps(doc, indent=1) + "\n")
        (directory / "scene.bin").write_bytes(buf)


class Seed:
    """A directory to copy for each case, the scene file to render and the files to mutate
    (paths relative to the directory)."""

    def __init__(self, directory, entry, targets):
        self.dir, self.entry, self.targets = Path(directory), entry, targets


def seeds(work):
    """The seeds of each format. The generated sphere (221 segments, 177 rings: 77,792
    triangles, the size of the Khronos model of the issue) is written under `work`."""
    t = ROOT / "tests/data"
    fz = t / "fuzz"
    out = {f: [] for f in FORMATS}
    for scene in sorted((ROOT / "scenes").glob("*.toml")):
        out["toml"].append(Seed(ROOT / "scenes", scene.name, [scene.name]))
    for d in sorted((fz / "toml").iterdir()):
        out["toml"].append(Seed(d, "scene.toml", ["scene.toml"]))
    out["toml"].append(Seed(fz / "obj/hexagon", "scene.toml", ["scene.toml"]))
    for scene in sorted((ROOT / "scenes/mitsuba").glob("*.xml")):
        out["xml"].append(Seed(ROOT / "scenes/mitsuba", scene.name, [scene.name]))
    for name in ["caustics-small-light.xml", "cornell-diffuse.xml", "point-light-plane.xml"]:
        out["xml"].append(Seed(t, name, [name]))
    idiomatic = t / "cornell-idiomatic"
    frags = sorted(str(p.relative_to(idiomatic)) for p in idiomatic.rglob("*.xml"))
    out["xml"].append(Seed(idiomatic, "cornell.xml", frags))
    for d in sorted((fz / "xml").iterdir()):
        out["xml"].append(Seed(d, "scene.xml", ["scene.xml"]))
    big = work / "seeds"
    write_sphere(big / "sphere-gltf", 221, 177, False)
    write_sphere(big / "sphere-glb", 221, 177, True)
    out["gltf"].append(Seed(fz / "gltf/quad", "scene.gltf", ["scene.gltf", "scene.bin"]))
    out["gltf"].append(Seed(big / "sphere-gltf", "scene.gltf", ["scene.gltf", "scene.bin"]))
    out["glb"].append(Seed(fz / "glb/quad", "scene.glb", ["scene.glb"]))
    out["glb"].append(Seed(big / "sphere-glb", "scene.glb", ["scene.glb"]))
    for d in sorted((fz / "ply").iterdir()):
        entry = next(p.name for p in d.iterdir() if p.name.startswith("scene."))
        out["ply"].append(Seed(d, entry, ["mesh.ply"]))
    light = big / "light-ply"
    light.mkdir(parents=True, exist_ok=True)
    shutil.copy(t / "light.ply", light / "light.ply")
    (light / "scene.toml").write_text(
        (fz / "ply/ascii/scene.toml").read_text().replace("mesh.ply", "light.ply"))
    out["ply"].append(Seed(light, "scene.toml", ["light.ply"]))
    out["obj"].append(Seed(fz / "obj/hexagon", "scene.toml", ["mesh.obj"]))
    out["obj"].append(Seed(ROOT / "scenes", "mesh-light.toml", ["meshes/light.obj"]))
    return out


# ---------------------------------------------------------------------------------------------
# The mutator

INTERESTING = [
    "0", "-0", "1", "-1", "2", "3", "255", "256", "-129", "65535", "65536", "2147483647",
    "2147483648", "-2147483648", "-2147483649", "4294967295", "4294967296",
    "9223372036854775807", "9223372036854775808", "-9223372036854775808",
    "-9223372036854775809", "18446744073709551615", "18446744073709551616",
    "-18446744073709551616", "1e308", "1e309", "-1e309", "1e-320", "1e-400", "2e38", "3.5e38",
    "1e99999999", "0.0", "-0.0", "nan", "NaN", "inf", "-inf", "Infinity", "1e", ".", "-",
    "0x7fffffff", "9" * 400,
]
CONTROL = ["\t", "\n", "\r", "\x00", "\x01", "\x07", "\x08", "\x1b", "\x7f", "\x85", "\x9b",
           "\u2028", "\u202e"]
NUMBER = re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")
STRING = re.compile(rb'"([^"\n\\]*)"')
U32 = [0, 1, 2, 3, 0x7F, 0x80, 0xFF, 0x100, 0xFFFF, 0x10000, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF,
       0xFFFFFFFE, 0x7FC00000, 0x7F800000, 0xFF800000, 0x7F7FFFFF, 0x00800000, 0x80000000]


def escape_for(fmt, ch):
    """`ch` as the format writes it inside a string."""
    cp = ord(ch)
    if fmt == "xml":
        return f"&#x{cp:x};".encode() if cp not in (0,) else b"&#x0;"
    if fmt in ("json", "toml"):
        return f"\\u{cp:04x}".encode()
    return ch.encode("utf-8", "surrogatepass")


def kind_of(name, data):
    if name.endswith((".gltf",)):
        return "json"
    if name.endswith(".xml"):
        return "xml"
    if name.endswith(".toml"):
        return "toml"
    if name.endswith(".obj"):
        return "obj"
    if name.endswith(".ply"):
        return "ply"
    return "bin"


def m_number(rng, data, fmt):
    spans = [m.span() for m in NUMBER.finditer(data)]
    if not spans:
        return m_bytes(rng, data, fmt)
    a, b = rng.choice(spans)
    old = data[a:b]
    if rng.random() < 0.3:
        # Every number of the line (all of a face's indices, a vector's components).
        start = data.rfind(b"\n", 0, a) + 1
        end = data.find(b"\n", b)
        end = len(data) if end < 0 else end
        new = rng.choice(INTERESTING).encode()
        return data[:start] + NUMBER.sub(lambda m: new, data[start:end]) + data[end:]
    if re.fullmatch(rb"-?\d+", old) and rng.random() < 0.5:
        if rng.random() < 0.5:
            v = int(old) + rng.choice([-1, 1, -(2 ** 31), 2 ** 32, 2 ** 63, -(2 ** 64)])
        else:
            v = rng.choice([-(2 ** 63), 2 ** 63 - 1, 2 ** 64 - 1, -(2 ** 31), 2 ** 32 - 1])
        new = str(v).encode()
    else:
        new = rng.choice(INTERESTING).encode()
    return data[:a] + new + data[b:]


def m_string(rng, data, fmt):
    spans = [m.span(1) for m in STRING.finditer(data)]
    if not spans:
        # OBJ, PLY: names are words after a keyword; put the character in a word.
        spans = [m.span() for m in re.finditer(rb"[A-Za-z_][A-Za-z0-9_]*", data)]
    if not spans:
        return m_bytes(rng, data, fmt)
    a, b = rng.choice(spans)
    at = rng.randint(a, b)
    r = rng.random()
    if r < 0.15:
        piece = rng.choice([b"\xff", b"\xc3", b"\x80", b"\xed\xa0\x80", b"\xf8\x88\x80\x80\x80"])
    elif r < 0.3:
        piece = rng.choice(CONTROL).encode()
    else:
        piece = b"".join(escape_for(fmt, rng.choice(CONTROL)) for _ in range(rng.randint(1, 3)))
    if rng.random() < 0.2:
        return data[:a] + piece + data[b:]  # the whole value replaced
    return data[:at] + piece + data[at:]


def m_lines(rng, data, fmt):
    lines = data.split(b"\n")
    i = rng.randrange(len(lines))
    r = rng.random()
    if r < 0.5:
        k = rng.choice([1, 2, 10, 100, 1000])
        lines[i:i + 1] = [lines[i]] * (k + 1)
    elif r < 0.75:
        del lines[i]
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def m_bytes(rng, data, fmt):
    data = bytearray(data)
    r = rng.random()
    if not data or r < 0.2:
        at = rng.randint(0, len(data))
        data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
    elif r < 0.5:
        for _ in range(rng.randint(1, 4)):
            i = rng.randrange(len(data))
            data[i] ^= 1 << rng.randrange(8)
    elif r < 0.75:
        a = rng.randrange(len(data))
        del data[a:a + rng.randint(1, 32)]
    elif r < 0.9:
        a = rng.randrange(len(data))
        data[a:a] = data[a:a + rng.randint(1, 64)] * rng.choice([2, 16, 256])
    else:
        del data[rng.randrange(len(data)):]
    return bytes(data)


def m_word(rng, data, fmt):
    """An aligned 32-bit (or 16, 8-bit) word of a binary file set to a value that matters."""
    if len(data) < 4:
        return m_bytes(rng, data, fmt)
    data = bytearray(data)
    at = rng.randrange(len(data) // 4) * 4
    v = rng.choice(U32) if rng.random() < 0.8 else rng.getrandbits(32)
    width = rng.choice([4, 4, 2, 1])
    data[at:at + width] = v.to_bytes(4, "little")[:width]
    return bytes(data)


def walk(value, path=()):
    """Every (path, value) of a JSON tree."""
    yield path, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield from walk(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from walk(v, path + (i,))


def at_path(tree, path):
    for p in path:
        tree = tree[p]
    return tree


def m_json(rng, data, fmt):
    """A tree edit of JSON text: list items repeated (index lists favoured) or shared, values
    replaced by others of another type or by extreme numbers, members removed or copied."""
    try:
        tree = json.loads(data)
    except (ValueError, UnicodeDecodeError, RecursionError):
        return m_number(rng, data, fmt)
    nodes = list(walk(tree))
    lists = [(p, v) for p, v in nodes if isinstance(v, list) and v]
    int_lists = [(p, v) for p, v in lists if all(type(x) is int for x in v)]
    r = rng.random()
    if r < 0.4 and (int_lists or lists):
        path, lst = rng.choice(int_lists if int_lists and rng.random() < 0.7 else lists)
        k = rng.choice([2, 10, 1000, 1000, 10000])
        if rng.random() < 0.5:
            lst[:] = [rng.choice(lst)] * k  # one item, k times
        else:
            lst[:] = lst * min(k, max(1, 100000 // len(lst)))
    elif r < 0.55 and int_lists:
        # Sharing: an index list names an index found elsewhere in the file.
        ints = [v for _, v in nodes if type(v) is int]
        path, lst = rng.choice(int_lists)
        lst[rng.randrange(len(lst))] = rng.choice(ints)
    elif r < 0.8:
        path, _ = rng.choice(nodes[1:] or nodes)
        if not path:
            return m_number(rng, data, fmt)
        parent = at_path(tree, path[:-1])
        parent[path[-1]] = rng.choice([
            None, True, -1, 0, 2 ** 63, -(2 ** 63), 2 ** 64 - 1, 1e308, -0.0, "", "x" * 100,
            [], {}, [0] * 4, rng.choice(INTERESTING), {"a": [1]},
        ])
    else:
        dicts = [(p, v) for p, v in nodes if isinstance(v, dict) and v]
        if not dicts:
            return m_number(rng, data, fmt)
        path, d = rng.choice(dicts)
        key = rng.choice(list(d))
        if rng.random() < 0.5:
            del d[key]
        else:
            other = rng.choice(dicts)[1]
            other[key + rng.choice(["", "2"])] = json.loads(json.dumps(d[key]))
    try:
        indent = 1 if b"\n" in data[:200] else None
        return json.dumps(tree, indent=indent).encode()
    except (ValueError, RecursionError):
        return data


def m_xml(rng, data, fmt):
    """A tree edit of XML text: an element repeated, nested in itself or removed, an
    attribute's value replaced by another of the file's or by one with a control character."""
    try:
        root = ET.fromstring(data)
    except Exception:  # ParseError, an unknown encoding, ...
        return m_number(rng, data, fmt)
    parents = [(p, c) for p in root.iter() for c in list(p)]
    if not parents:
        return m_number(rng, data, fmt)
    parent, child = rng.choice(parents)
    r = rng.random()
    if r < 0.3:
        k = rng.choice([2, 10, 100, 1000])
        at = list(parent).index(child)
        for _ in range(k - 1):
            parent.insert(at, child)
    elif r < 0.45:
        copy = ET.fromstring(ET.tostring(child))
        child.append(copy)
    elif r < 0.55:
        parent.remove(child)
    else:
        elems = [e for e in root.iter() if e.attrib]
        if not elems:
            return m_number(rng, data, fmt)
        e = rng.choice(elems)
        key = rng.choice(list(e.attrib))
        values = [v for x in root.iter() for v in x.attrib.values()]
        if rng.random() < 0.5:
            e.set(key, rng.choice(values))
        else:
            v = e.get(key)
            at = rng.randint(0, len(v))
            e.set(key, v[:at] + rng.choice(CONTROL[:3] + ["\x85", "\x7f"]) + v[at:])
    return ET.tostring(root)


def mutate(rng, name, data):
    """1 to 4 edits of the file `name`."""
    g = glb_chunks(data) if name.endswith(".glb") else None
    if g is not None and rng.random() < 0.6:
        js, binary = g
        if rng.random() < 0.8:
            js = mutate(rng, "chunk.gltf", js)
        else:
            binary = mutate(rng, "chunk.bin", binary)
        return glb(js, binary)
    fmt = kind_of(name, data)
    text = fmt in ("json", "xml", "toml", "obj") or (fmt == "ply" and b"format ascii" in data[:200])
    for _ in range(rng.choice([1, 1, 2, 3, 4])):
        if text:
            edits = [m_number] * 5 + [m_string] * 3 + [m_lines] * 2 + [m_bytes] * 2
            if fmt == "json":
                edits += [m_json] * 5
            if fmt == "xml":
                edits += [m_xml] * 4
        else:
            edits = [m_word] * 5 + [m_bytes] * 3
            if fmt == "ply":  # the binary PLY's ASCII header
                edits += [m_number] * 2 + [m_lines]
        form = {"json": "json", "xml": "xml", "toml": "toml"}.get(fmt, "raw")
        try:
            data = rng.choice(edits)(rng, data, form)
        except Exception:  # a parser of this script choking on an earlier edit's result
            data = m_bytes(rng, data, form)
        if len(data) > 64 << 20:
            data = data[: 64 << 20]
    return data


# ---------------------------------------------------------------------------------------------
# Running a case


def unprintable(c):
    """Whether a message must not hold `c` as it is: a C0 or C1 control, DEL, a line or
    paragraph separator, a bidirectional formatting character."""
    cp = ord(c)
    return (cp < 0x20 or 0x7F <= cp <= 0x9F or cp in (0x2028, 0x2029, 0x200E, 0x200F)
            or 0x202A <= cp <= 0x202E or 0x2066 <= cp <= 0x2069)


def classify(rc, stderr, hung):
    if hung:
        return "hang"
    text = stderr.decode("utf-8", "replace")
    if "panicked" in text or rc == 101:
        return "panic"
    if rc < 0:
        return "abort" if -rc == signal.SIGABRT else "crash"
    if rc == 0:
        bad = [ln for ln in text.split("\n")[:-1] if not ln.startswith("warning: ")]
    elif rc == 1:
        lines = text.split("\n")[:-1]
        bad = [ln for ln in lines if not ln.startswith(("warning: ", "error: "))]
        if sum(ln.startswith("error: ") for ln in lines) != 1:
            bad.append("(no single error line)")
    else:
        return "other"
    if bad or any(unprintable(c) for c in text.replace("\n", "")):
        return "unescaped"
    return "rendered" if rc == 0 else "refused"


def run_case(binary, seed, fmt, n, base_seed, root):
    rng = random.Random(f"{base_seed}:{fmt}:{n}")
    s = rng.choice(SEEDS[fmt])
    target = rng.choice(s.targets)
    case = root / f"{fmt}-{n}"
    shutil.copytree(s.dir, case)
    data = (s.dir / target).read_bytes()
    (case / target).write_bytes(mutate(rng, target, data))
    out = case / "out.png"
    start = time.monotonic()
    hung = False
    try:
        # The shell sets the limit (a preexec_fn is not safe beside the pool's threads).
        cmd = ["bash", "-c", f'ulimit -v {ADDRESS_SPACE >> 10} && exec "$@"', "case",
               str(binary), "render", str(case / s.entry), "-o", str(out)] + RENDER
        env = dict(os.environ, RUST_BACKTRACE="0")
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             start_new_session=True, env=env)
        try:
            _, err = p.communicate(timeout=DEADLINE)
        except subprocess.TimeoutExpired:
            hung = True
            os.killpg(p.pid, signal.SIGKILL)
            _, err = p.communicate()
        rc = p.returncode
    except OSError as e:
        return fmt, n, "other", str(e), 0.0, case
    took = time.monotonic() - start
    return fmt, n, classify(rc, err, hung), err.decode("utf-8", "replace"), took, case


SEEDS = {}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=500, help="cases per format")
    ap.add_argument("--first", type=int, default=0, help="number of the first case")
    ap.add_argument("--seed", default="1", help="the run's seed (any string)")
    ap.add_argument("--formats", default=",".join(FORMATS))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--binary", default=str(ROOT / "target/release/gpu-photon"))
    ap.add_argument("--keep", default=None, help="where failing cases are copied")
    ap.add_argument("--write-sphere", default=None, help="write a sphere seed there and stop")
    ap.add_argument("--segments", type=int, default=64)
    ap.add_argument("--rings", type=int, default=33)
    ap.add_argument("--glb", action="store_true", help="with --write-sphere: one .glb")
    a = ap.parse_args()
    if a.write_sphere:
        write_sphere(Path(a.write_sphere), a.segments, a.rings, a.glb)
        return 0
    work = Path(tempfile.mkdtemp(prefix="gpu-photon-xfuzz-"))
    SEEDS.update(seeds(work))
    formats = a.formats.split(",")
    binary = Path(a.binary)
    tally = {f: {} for f in formats}
    slowest = {f: (0.0, None) for f in formats}
    failures = []
    t0 = time.monotonic()
    jobs = [(f, n) for f in formats for n in range(a.first, a.first + a.cases)]
    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = [pool.submit(run_case, binary, a.seed, f, n, a.seed, work) for f, n in jobs]
        for fut in futures:
            fmt, n, outcome, err, took, case = fut.result()
            tally[fmt][outcome] = tally[fmt].get(outcome, 0) + 1
            if took > slowest[fmt][0]:
                slowest[fmt] = (took, n)
            if outcome not in ("rendered", "refused"):
                lines = [ln for ln in err.split("\n") if ln.strip()]
                key = [i for i, ln in enumerate(lines)
                       if "panicked" in ln or "memory allocation" in ln or ln.startswith("error")]
                first = key[0] if key else 0
                what = " | ".join(lines[first:first + 2])[:400]
                failures.append(f"{fmt} case {n}: {outcome}: {what!r}")
                if a.keep:
                    dest = Path(a.keep) / f"{fmt}-{n}"
                    shutil.rmtree(dest, ignore_errors=True)
                    shutil.copytree(case, dest)
            shutil.rmtree(case, ignore_errors=True)
    shutil.rmtree(work, ignore_errors=True)
    cols = ["rendered", "refused", "unescaped", "panic", "abort", "crash", "hang", "other"]
    print(f"external fuzz: seed {a.seed}, cases {a.first}..{a.first + a.cases - 1} per format, "
          f"{time.monotonic() - t0:.0f} s, {a.jobs} job(s), limit {ADDRESS_SPACE >> 30} GiB, "
          f"{DEADLINE:.0f} s")
    print("| format | cases | " + " | ".join(cols) + " | slowest case (s) |")
    print("|---|" + "---|" * (len(cols) + 2))
    for f in formats:
        row = [str(tally[f].get(c, 0)) for c in cols]
        print(f"| {f} | {sum(tally[f].values())} | " + " | ".join(row)
              + f" | {slowest[f][0]:.2f} (case {slowest[f][1]}) |")
    for line in failures:
        print(line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
