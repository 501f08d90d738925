#!/bin/bash
# Mesh-wall narrow phase on the GPU (doc/benchmarks.md, "Mesh walls on the GPU"): for each shape alone (a deck of
# one template) and precision, build/tests/gpu_wall_agreement SHAPES COUNT PRECISION SHAPE_FILE, which places
# COUNT particles on a creased 12 x 12 grid mesh, sends every (particle, prism) candidate through
# poly_gpu_wall_overlaps and the host's code, checks their agreement, and prints pieces per second (GPU: the
# fastest of three calls, pieces up, overlaps and nodes down; one CPU core). With the default kernel choice
# and with each kernel forced (POLY_GPU_WALL_KERNEL=thread|warp).
#
#   bash tools/bench_gpu_walls.sh [count] [precisions] [shape files]
#   bash tools/bench_gpu_walls.sh 2000 "double mixed" "schoenhardt.stl cube.stl tetrahedron.obj icosphere_80.off icosphere_320.off rock_10.obj rock_40.obj rock_70.obj"
#                                                    (the defaults; about 2 minutes on one H100)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
count="${1:-2000}"
precisions="${2:-double mixed}"
shapes="${3:-schoenhardt.stl cube.stl tetrahedron.obj icosphere_80.off icosphere_320.off rock_10.obj rock_40.obj rock_70.obj}"
agreement="$root/build/tests/gpu_wall_agreement"
[ -x "$agreement" ] || { echo "no $agreement: run make (with nvcc) first" >&2; exit 1; }
. "$root/tools/bench_gpu_common.sh"
echo "commit: $commit; $count particles per shape"
echo
start=$SECONDS
# "GPU pieces/s (handed back; CPU pieces/s; worst difference)" from a gpu_wall_agreement line, or its FAIL line.
rates() { sed -n 's/.*worst relative difference \([0-9.e+-]*\) .*pieces\/s: GPU \([0-9.e+]*\) .*; \([0-9]*\) handed.*one CPU core \([0-9.e+]*\).*/GPU \2 (handed back \3; CPU core \4; worst difference \1)/p; /FAIL/p'; }
echo "| shape | precision | pieces (touching) | default | thread per piece | lanes per piece |"
echo "|---|---|---|---|---|---|"
for precision in $precisions; do
  for shape in $shapes; do
    out="$("$agreement" "$root/examples/shapes" "$count" "$precision" "$shape" || true)"
    pieces="$(echo "$out" | sed -n 's/.*particles, *\([0-9]*\) pieces ( *\([0-9]*\) touching).*/\1 (\2)/p')"
    status="$(echo "$out" | tail -n 1)"
    thread="$(POLY_GPU_WALL_KERNEL=thread "$agreement" "$root/examples/shapes" "$count" "$precision" "$shape" | rates || true)"
    warp="$(POLY_GPU_WALL_KERNEL=warp "$agreement" "$root/examples/shapes" "$count" "$precision" "$shape" | rates || true)"
    echo "| $shape | $precision | $pieces | $(echo "$out" | rates) $status | $thread | $warp |"
  done
done
echo
echo "total $((SECONDS - start)) s"
