#!/usr/bin/env bash
# Ray throughput of the CPU backend's BVHs against Intel Embree 3, per ray kind, one thread:
# `gpu-photon bench SCENE --rays` on the example scenes and on the Cornell box with a
# generated 1M-triangle mesh, built with the `embree` feature (Debian's libembree-dev,
# installed here when missing). Writes DIR/rays-NAME.json beside the printed tables.
#
#   bash scripts/ray_bench.sh [DIR] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-target/ray-bench}
runs=${2:-5}
if ! [ -e /usr/include/embree3/rtcore.h ]; then
    apt-get install -y libembree-dev
fi
cargo build --release --features embree
bin=target/release/gpu-photon
mkdir -p "$dir"
echo "load: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) CPUs: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
for scene in scenes/cornell-box.toml scenes/cornell-caustics.toml scenes/mitsuba/materials.xml; do
    name=$(basename "${scene%.*}")
    "$bin" bench "$scene" --rays --width 256 --height 256 --runs "$runs" --json "$dir/rays-$name.json"
done
"$bin" bench scenes/cornell-box.toml --rays --mesh 1000000 --width 256 --height 256 \
    --runs "$runs" --json "$dir/rays-mesh-1m.json"
