#!/usr/bin/env bash
# Installs the gpu-photon render engine for the `blender` on PATH (or --blender PATH) and
# enables it in that user's preferences:
#   - builds the `gpu_photon` Python package's wheel (an abi3 wheel: it imports on Blender's
#     Python, 3.9 or later) from this checkout with pip and maturin (Rust needed), unless
#     --wheel names one;
#   - installs it into Blender's user script modules (`bpy.utils.user_resource('SCRIPTS')`/
#     addons/modules, which Blender puts on sys.path), and NumPy there if Blender's Python
#     has none (Debian's blender: the python3-numpy package);
#   - copies the add-on `gpu_photon_blender` into the user add-ons and enables it (saved in
#     the user preferences).
# BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG, if set, choose where, as they do for Blender.
# Usage: bash blender/install.sh [--blender PATH] [--wheel FILE]
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(dirname "$here")
blender=$(command -v blender || true)
wheel=""
while [ $# -gt 0 ]; do
    case "$1" in
        --blender) blender=$2; shift 2 ;;
        --wheel) wheel=$2; shift 2 ;;
        -h|--help) sed -n '2,15p' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) echo "install.sh: unknown argument $1 (expected --blender PATH, --wheel FILE)" >&2; exit 2 ;;
    esac
done
if [ -z "$blender" ] || ! [ -x "$(command -v "$blender")" ]; then
    echo "install.sh: no blender found (put it on PATH, or pass --blender PATH; Debian: apt-get install blender)" >&2
    exit 1
fi

# What this Blender is: its version, Python, user script directory and whether NumPy imports.
query='
import sys, bpy
try:
    import numpy
    has_numpy = 1
except ImportError:
    has_numpy = 0
print("GPQ version=%d.%d.%d" % bpy.app.version)
print("GPQ python=%d.%d" % sys.version_info[:2])
print("GPQ prefix=%s" % sys.prefix)
print("GPQ scripts=%s" % bpy.utils.user_resource("SCRIPTS"))
print("GPQ numpy=%d" % has_numpy)
'
info=$("$blender" -b --factory-startup --python-expr "$query" 2>/dev/null | sed -n 's/^GPQ //p')
field() { printf '%s\n' "$info" | sed -n "s/^$1=//p"; }
version=$(field version)
py=$(field python)
scripts=$(field scripts)
if [ -z "$scripts" ]; then
    echo "install.sh: $blender did not run its Python (is it Blender 3.4 or later?)" >&2
    exit 1
fi
echo "install.sh: Blender $version (Python $py) at $blender; user scripts in $scripts"
modules="$scripts/addons/modules"
mkdir -p "$modules" "$scripts/addons"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m venv "$work/venv"
pip=("$work/venv/bin/pip" -q --disable-pip-version-check)

if [ -z "$wheel" ]; then
    command -v cargo >/dev/null || { echo "install.sh: building the wheel needs Rust (cargo); or pass --wheel FILE" >&2; exit 1; }
    echo "install.sh: building the gpu_photon wheel (release)"
    "${pip[@]}" wheel --no-deps -w "$work/dist" "$repo/python"
    wheel=$(ls "$work"/dist/gpu_photon-*.whl)
fi
echo "install.sh: installing $(basename "$wheel") into $modules"
rm -rf "$modules"/gpu_photon "$modules"/gpu_photon-*.dist-info
"${pip[@]}" install --no-deps --upgrade --target "$modules" "$wheel"

if [ "$(field numpy)" != 1 ]; then
    if [ "$(field prefix)" = /usr ] && command -v apt-get >/dev/null; then
        sudo=()
        [ "$(id -u)" -ne 0 ] && sudo=(sudo)
        echo "install.sh: Blender's Python has no NumPy: installing python3-numpy"
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends python3-numpy
    else
        echo "install.sh: Blender's Python has no NumPy: installing it into $modules"
        "${pip[@]}" install --target "$modules" --only-binary=:all: --python-version "$py" numpy
    fi
fi

rm -rf "$scripts/addons/gpu_photon_blender"
cp -r "$here/gpu_photon_blender" "$scripts/addons/"
find "$scripts/addons/gpu_photon_blender" -name __pycache__ -prune -exec rm -rf {} +

enable='
import addon_utils, bpy
mod = addon_utils.enable("gpu_photon_blender", default_set=True, persistent=True)
if mod is None:
    raise SystemExit("the add-on did not load")
bpy.ops.wm.save_userpref()
import gpu_photon
print("GPQ enabled", gpu_photon.__file__)
'
if ! "$blender" -b --python-exit-code 1 --python-expr "$enable" 2>&1 | grep -q "^GPQ enabled"; then
    echo "install.sh: enabling the add-on failed; Blender said:" >&2
    "$blender" -b --python-exit-code 1 --python-expr "$enable" >&2 || true
    exit 1
fi
echo "install.sh: gpu-photon is installed and enabled: Render Properties > Render Engine > gpu-photon"
