#!/bin/bash
# How long contacts keep their crossing structure in a settled pile (doc/benchmarks.md, "Temporal coherence in a
# settled pile"):
#
#   bash tools/coherence_study.sh [cube|rock] [steps] [settle]     (defaults rock, 200, 50000; about a minute)
#
# Runs the pile of tools/bench_vs_multisphere.sh (examples/bench_multisphere/in.pile_poly, 150 particles) for
# `settle` steps (25000: the start of that benchmark's timed run, the pile still slumping; 50000: its end) with
# build/bin/liggghts-poly, dumps the poses of every one of the next `steps` steps, then runs
# tools/coherence_study.c on them (built by tools/bench_c.sh). BENCH_LAUNCHER: another liggghts-poly.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case="${1:-rock}"
steps="${2:-200}"
settle="${3:-50000}"
case "$case" in
  cube) shape=cube.stl ;;
  rock) shape=rock_40.obj ;;
  *) echo "coherence_study.sh: unknown pile '$case' (cube or rock)" >&2; exit 2 ;;
esac
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sed '/^run *\${steps}/d' "$root/examples/bench_multisphere/in.pile_poly" > "$work/in.pile"
cat >> "$work/in.pile" <<'DECK'
compute pose all property/polyhedron quatw quati quatj quatk
dump steps all custom 1 steps.dump id x y z c_pose[1] c_pose[2] c_pose[3] c_pose[4]
dump_modify steps sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run ${dumped}
DECK
(cd "$work" && "${BENCH_LAUNCHER:-$root/build/bin/liggghts-poly}" -in in.pile -var SHAPE "$root/examples/shapes/$shape" \
  -var SCALE 0.01 -var settle "$settle" -var dumped "$steps" -log log.pile > screen.txt 2>&1) || { tail -20 "$work/screen.txt"; exit 1; }
bash "$root/tools/bench_c.sh" coherence_study "$shape" 0.01 "$work/steps.dump"
