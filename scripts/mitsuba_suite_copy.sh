#!/usr/bin/env bash
# Copies what Mitsuba 3's render-regression suite (mitsuba-renderer/mitsuba-data, tests/scenes/,
# run by mitsuba3's src/render/tests/test_renders.py) needs into tests/data/mitsuba-suite/,
# keeping the repository's own folder layout so that every scene's relative paths
# (`<path value="../../../common"/>`, `../../obj/...`) resolve as they do there.
# Only the 41 scenes' XML (and the fragments they include), the meshes, textures and volumes
# they name, and each scene's RGB reference and variance image (`refs/*_ref_rgb.exr`,
# `refs/*_ref_rgb_var.exr`) are copied: not the mono/spectral references, not the unused
# meshes and textures of common/.
#
#   scripts/mitsuba_suite_copy.sh MITSUBA_DATA_CHECKOUT [DEST]
#
# MITSUBA_DATA_CHECKOUT is a checkout (a work tree) of mitsuba-data at the commit named in
# tests/data/mitsuba-suite/README.md; DEST defaults to tests/data/mitsuba-suite.
set -euo pipefail
src=${1:?usage: $0 MITSUBA_DATA_CHECKOUT [DEST]}
dest=${2:-$(dirname "$0")/../tests/data/mitsuba-suite}
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
cd "$src"
files=(
    common/meshes/rectangle.obj
    common/meshes/sphere.obj
    common/textures/carrot.png
    common/textures/floor_tiles_bumpmap.png
    common/textures/floor_tiles_normalmap.jpg
    common/textures/flower.bmp
    common/textures/leaf_mask.png
    common/textures/museum.exr
    common/textures/wood.jpg
    docs/scenes/sdfgrid/torus_sdfgrid.vol
    tests/obj/rectangle_normals_uv.obj
    tests/ply/rectangle_normals_uv.ply
    tests/serialized/rectangle_normals_uv.serialized
)
# The scenes and what sits beside them (fragments, includes, meshes, textures, volumes),
# without the generators (*.py) and the other colour modes' references.
while IFS= read -r f; do files+=("$f"); done < <(
    find tests/scenes -type f \( -name '*.xml' -o -name '*.obj' -o -name '*.ply' \
        -o -name '*.png' -o -name '*.vol' -o -name '*_ref_rgb.exr' -o -name '*_ref_rgb_var.exr' \) \
        -not -path '*/error_output/*' | sort)
for f in "${files[@]}"; do
    mkdir -p "$dest/$(dirname "$f")"
    cp "$f" "$dest/$f"
done
echo "copied ${#files[@]} files to $dest ($(du -sh "$dest" | cut -f1))"
