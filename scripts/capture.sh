#!/usr/bin/env bash
# Renders every example scene (scenes/*.toml, scenes/mitsuba/*.xml) and the capture scenes of
# tests/data/capture/ (every BSDF kind, wrapper, texture and light kind of the Mitsuba and
# glTF importers) on both backends in three modes at 48x48 into DIR (one EXR each), so a
# restructuring can be checked byte for byte: run it before and after into two directories,
# then `cmp` the files (scripts/capture.sh DIR [BINARY]). CAPTURE_ONLY=REGEX limits the scenes.
set -euo pipefail
out=${1:?usage: capture.sh DIR [BINARY]}
bin=${2:-target/release/gpu-photon}
mkdir -p "$out"
for scene in scenes/*.toml scenes/mitsuba/*.xml tests/data/capture/*.xml tests/data/capture/*.gltf \
    tests/data/fuzz/toml/room/scene.toml; do
    if [ -n "${CAPTURE_ONLY:-}" ] && ! [[ $scene =~ $CAPTURE_ONLY ]]; then
        continue
    fi
    name=$(echo "${scene%.*}" | sed 's|^scenes/||; s|^tests/data/||; s|/|-|g')
    for backend in cpu gpu; do
        "$bin" render "$scene" -o "$out/$name-$backend-default.exr" --backend "$backend" \
            --width 48 --height 48 --passes 2 -q
        "$bin" render "$scene" -o "$out/$name-$backend-photon.exr" --backend "$backend" \
            --width 48 --height 48 --mode photon --passes 1 --spp 4 --photons 20000 -q
        "$bin" render "$scene" -o "$out/$name-$backend-direct.exr" --backend "$backend" \
            --width 48 --height 48 --mode direct --passes 1 --spp 4 --photons 20000 -q
    done
done
