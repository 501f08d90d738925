#!/bin/bash
# The narrow phase on a settled pile's own pairs (doc/benchmarks.md, "Piles against multisphere"):
#
#   bash tools/bench_pile_pairs.sh [cube|rock] [repeats]      (about 15 s for the pile, then the timing)
#
# Forms the pile of tools/bench_vs_multisphere.sh (examples/bench_multisphere/in.pile_poly, 150 particles, 25000
# steps) with build/bin/liggghts-poly and dumps its poses (tools/pile_poses.sh), then times
# tools/bench_pile_pairs.c on every pair of it (built by tools/bench_c.sh). The results hash it prints is the same for builds that give the same bits.
# BENCH_LAUNCHER: another liggghts-poly for the pile (as tools/bench_decks.py).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case="${1:-cube}"
repeats="${2:-7}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
bash "$root/tools/pile_poses.sh" "$case" "$work"
bash "$root/tools/bench_c.sh" bench_pile_pairs "$(cat "$work/shape")" 0.01 "$work/pile.dump" "$repeats"
