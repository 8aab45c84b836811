#!/usr/bin/env bash
# Submits a progressive render as a Slurm job array of N slices plus the merge job that
# depends on it, and prints the two job ids (`ARRAY_ID MERGE_ID`).
#
#   examples/slurm/submit.sh SCENE PASSES N OUTDIR [render options...]
#
# The array runs render-slice.sbatch as tasks 0..N-1 (slice I of N of the passes 0..PASSES,
# into OUTDIR/slice-I.exr); merge.sbatch then writes OUTDIR/merged.exr, byte for byte the
# image of `gpu-photon render SCENE --passes PASSES` when every slice holds one pass
# (N = PASSES), and equal to it up to float rounding otherwise. Logs go to OUTDIR/logs.
#
# TASKS=2,5 resubmits only those tasks (after they failed or were cancelled), with a new
# merge job depending on them; give the same other arguments. SBATCH_ARGS adds sbatch
# options to both jobs (e.g. "--account=art --partition=render"), SLICE_ARGS to the array
# only (e.g. "--gres=gpu:1 --time=2:00:00"). The job scripts are taken from beside this
# one; GPU_PHOTON names the binary (default: gpu-photon on the PATH of the jobs).
set -euo pipefail
if [ $# -lt 4 ]; then
    echo "usage: $0 SCENE PASSES N OUTDIR [render options...]" >&2
    exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scene=$1 passes=$2 slices=$3 outdir=$4
shift 4
mkdir -p "$outdir/logs"
tasks=${TASKS:-0-$((slices - 1))}
# shellcheck disable=SC2086 # SBATCH_ARGS and SLICE_ARGS are lists of options
array=$(sbatch --parsable ${SBATCH_ARGS:-} ${SLICE_ARGS:-} --array="$tasks" \
    --output="$outdir/logs/slice-%a-%A.out" \
    "$here/render-slice.sbatch" "$scene" "$passes" "$slices" "$outdir" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes --output="$outdir/logs/merge-%j.out" \
    "$here/merge.sbatch" "$outdir")
merge=${merge%%;*}
echo "$array $merge"
