#!/bin/bash
# How long contacts keep their crossing structure in a settled pile (doc/benchmarks.md, "Eleventh step: the crossing
# cache"):
#
#   bash tools/coherence_study.sh [cube|rock] [steps] [settle]     (defaults rock, 200, 50000; about a minute)
#
# Runs the pile of tools/bench_vs_multisphere.sh (examples/bench_multisphere/in.pile_poly, 150 particles) for
# `settle` steps (25000: the start of that benchmark's timed run, the pile still slumping; 50000: its end) with
# build/bin/liggghts-poly (tools/pile_poses.sh), dumps the poses of every one of the next `steps` steps, then runs
# tools/coherence_study.c on them (built by tools/bench_c.sh). BENCH_LAUNCHER: another liggghts-poly.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case="${1:-rock}"
steps="${2:-200}"
settle="${3:-50000}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
bash "$root/tools/pile_poses.sh" "$case" "$work" "$settle" "$steps"
bash "$root/tools/bench_c.sh" coherence_study "$(cat "$work/shape")" 0.01 "$work/pile.dump"
