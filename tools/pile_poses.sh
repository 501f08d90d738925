#!/bin/bash
# The piles of tools/bench_vs_multisphere.sh (examples/bench_multisphere/in.pile_poly, 150 particles) formed by
# build/bin/liggghts-poly (or BENCH_LAUNCHER) and their poses dumped, for tools/bench_pile_pairs.sh and
# tools/coherence_study.sh:
#
#   bash tools/pile_poses.sh cube|rock WORK [settle] [dumped]
#
# Runs the deck for `settle` steps (default 25000, where its timed run starts), then dumps the poses (id x y z
# quatw quati quatj quatk) at that step and at each of the next `dumped` steps (default 0) into WORK/pile.dump,
# and writes the shape file's name into WORK/shape.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case="$1"
work="$2"
settle="${3:-25000}"
dumped="${4:-0}"
case "$case" in
  cube) shape=cube.stl ;;
  rock) shape=rock_40.obj ;;
  *) echo "pile_poses.sh: unknown pile '$case' (cube or rock)" >&2; exit 2 ;;
esac
echo "$shape" > "$work/shape"
sed '/^run *\${steps}/d' "$root/examples/bench_multisphere/in.pile_poly" > "$work/in.pile"
cat >> "$work/in.pile" <<'DECK'
compute pose all property/polyhedron quatw quati quatj quatk
dump poses all custom 1 pile.dump id x y z c_pose[1] c_pose[2] c_pose[3] c_pose[4]
dump_modify poses format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run ${dumped}
DECK
(cd "$work" && "${BENCH_LAUNCHER:-$root/build/bin/liggghts-poly}" -in in.pile -var SHAPE "$root/examples/shapes/$shape" \
  -var SCALE 0.01 -var settle "$settle" -var dumped "$dumped" -log log.pile > screen.txt 2>&1) ||
  { tail -20 "$work/screen.txt"; exit 1; }
