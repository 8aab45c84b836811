"""A `blender` command line on top of the `bpy` module (Blender as a Python module, `pip install
bpy`), so the add-on's tests (run.sh, install.sh) run against the Blender versions PyPI
publishes (4.x) where only Debian's Blender 3.4 is installed.

    PATH=$(python3 blender/tests/bpy_as_blender.py --shim DIR):$PATH bash blender/tests/run.sh

`--shim DIR` writes `DIR/blender`, a script that runs this file with the Python it was run
with (the one that imports `bpy`), and prints DIR. The emulated command line is the subset
run.sh and install.sh use, in Blender's order of evaluation: `-b`, `--factory-startup`,
`--version`, `--python-exit-code N`, `--python FILE`, `--python-expr EXPR`, a `.blend` file,
`-E ENGINE`, `-o PATH`, `-F FORMAT`, `-f N`. Anything else is refused with exit status 2.
"""

import os
import runpy
import stat
import sys
import traceback


def shim(directory):
    """Writes `directory/blender` running this file with this Python; returns `directory`."""
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, "blender")
    with open(path, "w") as f:
        f.write(f'#!/bin/sh\nexec "{sys.executable}" "{os.path.abspath(__file__)}" "$@"\n')
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    return directory


def frame_file(path, frame):
    """Blender's `-o PATH` for frame `frame`: the last run of `#` replaced by the frame number
    padded to its length, else the number appended in four digits (the extension follows)."""
    import re

    runs = list(re.finditer(r"#+", path))
    if not runs:
        return f"{path}{frame:04d}"
    m = runs[-1]
    return path[: m.start()] + str(frame).zfill(m.end() - m.start()) + path[m.end():]


def enable_user_addons(bpy):
    """Enables every add-on in the user scripts' `addons` folder."""
    import addon_utils

    folder = os.path.join(bpy.utils.user_resource("SCRIPTS"), "addons")
    for name in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
        if name != "modules" and os.path.isfile(os.path.join(folder, name, "__init__.py")):
            addon_utils.enable(name, default_set=True)


def main(argv):
    if argv[:1] == ["--shim"] and len(argv) == 2:
        print(shim(argv[1]))
        return 0
    import bpy

    exit_code = 0
    factory = False
    frame_args = {}
    actions = []
    i = 0
    while i < len(argv):
        a = argv[i]
        value = argv[i + 1] if i + 1 < len(argv) else None
        if a in ("-b", "--background"):
            i += 1
        elif a == "--factory-startup":
            factory = True
            i += 1
        elif a in ("-v", "--version"):
            print("Blender %s (bpy module)" % bpy.app.version_string)
            return 0
        elif a == "--python-exit-code" and value is not None:
            exit_code = int(value)
            i += 2
        elif a in ("-P", "--python") and value is not None:
            actions.append(("file", value))
            i += 2
        elif a == "--python-expr" and value is not None:
            actions.append(("expr", value))
            i += 2
        elif a in ("-E", "--engine") and value is not None:
            frame_args["engine"] = value
            i += 2
        elif a in ("-o", "--render-output") and value is not None:
            frame_args["output"] = value
            i += 2
        elif a in ("-F", "--render-format") and value is not None:
            frame_args["format"] = value
            i += 2
        elif a in ("-f", "--render-frame") and value is not None:
            actions.append(("frame", int(value)))
            i += 2
        elif a.endswith(".blend"):
            actions.insert(0, ("open", a))
            i += 1
        else:
            print(f"bpy_as_blender: unsupported argument {a!r}", file=sys.stderr)
            return 2

    if factory and not any(kind == "open" for kind, _ in actions):
        bpy.ops.wm.read_factory_settings(use_empty=False)
    elif not factory:
        # Blender without --factory-startup loads the user's preferences and enables the
        # add-ons saved there. The module reads no preferences (wm.read_userpref crashes in
        # 4.2), so every add-on installed in the user scripts stands for the saved ones.
        enable_user_addons(bpy)
    for kind, value in actions:
        try:
            if kind == "open":
                bpy.ops.wm.open_mainfile(filepath=value, load_ui=False)
            elif kind == "file":
                sys.argv = [value]
                runpy.run_path(value, run_name="__main__")
            elif kind == "expr":
                exec(compile(value, "<string>", "exec"), {"__name__": "__main__"})
            elif kind == "frame":
                scene = bpy.context.scene
                if "engine" in frame_args:
                    scene.render.engine = frame_args["engine"]
                if "output" in frame_args:
                    scene.render.filepath = frame_file(frame_args["output"], value)
                if "format" in frame_args:
                    scene.render.image_settings.file_format = frame_args["format"]
                scene.frame_set(value)
                bpy.ops.render.render(write_still=True, animation=False)
                print("Saved: frame %d" % value)
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
            if code != 0:
                return code if exit_code == 0 else exit_code
        except Exception:
            traceback.print_exc()
            if exit_code:
                return exit_code
    return 0


if __name__ == "__main__":
    code = main(sys.argv[1:])
    # Blender exits without Python's teardown; the module's teardown can crash after a glTF
    # export (4.2), which is not the test's outcome.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
