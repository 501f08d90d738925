#!/bin/bash
# The narrow phase on a settled pile's own pairs (doc/benchmarks.md, "Piles against multisphere"):
#
#   bash tools/bench_pile_pairs.sh [cube|rock] [repeats]      (about 15 s for the pile, then the timing)
#
# Forms the pile of tools/bench_vs_multisphere.sh (examples/bench_multisphere/in.pile_poly, 150 particles, 25000
# steps) with build/bin/liggghts-poly, dumps its poses, then times tools/bench_pile_pairs.c on every pair of it
# (built by tools/bench_c.sh). The results hash it prints is the same for builds that give the same bits.
# BENCH_LAUNCHER: another liggghts-poly for the pile (as tools/bench_decks.py).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case="${1:-cube}"
repeats="${2:-7}"
case "$case" in
  cube) shape=cube.stl ;;
  rock) shape=rock_40.obj ;;
  *) echo "bench_pile_pairs.sh: unknown pile '$case' (cube or rock)" >&2; exit 2 ;;
esac
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The deck up to its timed run, then the poses of the settled pile.
sed '/^run *\${steps}/d' "$root/examples/bench_multisphere/in.pile_poly" > "$work/in.pile"
cat >> "$work/in.pile" <<'DECK'
compute pose all property/polyhedron quatw quati quatj quatk
dump settled all custom 1 pile.dump id x y z c_pose[1] c_pose[2] c_pose[3] c_pose[4]
dump_modify settled format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run 0
DECK
(cd "$work" && "${BENCH_LAUNCHER:-$root/build/bin/liggghts-poly}" -in in.pile -var SHAPE "$root/examples/shapes/$shape" \
  -var SCALE 0.01 -log log.pile > screen.txt 2>&1) || { tail -20 "$work/screen.txt"; exit 1; }
bash "$root/tools/bench_c.sh" bench_pile_pairs "$shape" 0.01 "$work/pile.dump" "$repeats"
