#!/usr/bin/env bash
# Packed-bed benchmark: time per step of a settled bed of T^2 x CELL (10115) Schoenhardt polyhedra against the same bed
# of LIGGGHTS Hertz spheres (issue 4, benchmark 2: "10^6 particles in a packed bed").
#
#   PAIR=polyhedral/volumetric/gpu bash bed.sh 10 16      # 1011500 particles, 16 MPI ranks
#   bash bed.sh 1 2                                       # 10115 particles, the settled cell itself, CPU
#
# 1. prepare: a cell of 17 x 17 x 35 particles (table A.3's proportions, periodic in x and y) falls onto a plane
#    wall and settles (in.packing -var wall 1, fall time + SETTLE seconds), polyhedra and spheres each with
#    their own deck; the final dumps are tiled T x T times (tile_bed.py) into data/{packing,spheres}_N<T^2 10115>_nofloor.data.
# 2. run: both beds, at rest under gravity, for STEPS steps; report.py prints the table.
#
# Environment: PAIR, PRECISION (as run.sh), STEPS (default 500), SETTLE (default 0.05 s), STAGE (prepare, run or
# all; default all), CELL_RANKS (ranks for the settling cell, default: the ranks given), LIGGGHTS, MPIRUN, PYTHON.
set -euo pipefail
cd "$(dirname "$0")"

TILES=${1:-10}
RANKS=${2:-2}
PAIR=${PAIR:-polyhedral/volumetric}
PRECISION=${PRECISION:-double}
STEPS=${STEPS:-500}
SETTLE=${SETTLE:-0.05}
STAGE=${STAGE:-all}
CELL_RANKS=${CELL_RANKS:-$RANKS}
LIGGGHTS=${LIGGGHTS:-../../build/bin/liggghts-poly}
MPIRUN=${MPIRUN:-mpirun}
PYTHON=${PYTHON:-python3}
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
CELL=${CELL:-10115}   # 17 x 17 x 35; smaller only to try the script out
N=$((TILES * TILES * CELL))
pair_tag=$(echo "$PAIR" | tr / _)_${PRECISION}
mkdir -p post data
echo "== $(date -u +%FT%TZ) $(hostname) nproc $(nproc) commit $(git rev-parse --short HEAD 2>/dev/null || echo ?)"

if [ "$STAGE" != run ]; then
  "$PYTHON" make_packing.py "$CELL" --layers 35 --floor none --outdir data
  cell=(-var N "$CELL" -var wall 1 -var settle "$SETTLE" -var count 0 -var M 1000)
  start=$SECONDS
  "$MPIRUN" -np "$CELL_RANKS" "$LIGGGHTS" -in in.packing "${cell[@]}" -var pair "$PAIR" -var precision "$PRECISION" \
    -log post/log.cell_packing_${pair_tag} -screen none
  "$MPIRUN" -np "$CELL_RANKS" "$LIGGGHTS" -in in.packing_spheres "${cell[@]}" -log post/log.cell_spheres -screen none
  echo "== settled cells in $((SECONDS - start)) s; kinetic energy at the start and the end (J):"
  for log in post/log.cell_packing_${pair_tag} post/log.cell_spheres; do
    awk -v name="$log" '$1 == "Step" {table = 1; next} table && $1 ~ /^[0-9]+$/ {if (!first) first = $3; last = $3}
      /^Loop time/ {table = 0} END {printf "   %s: %s -> %s\n", name, first, last}' "$log"
  done
  "$PYTHON" tile_bed.py post/final_packing_N${CELL}_plane.dump "$TILES" --outdir data
  "$PYTHON" tile_bed.py post/final_spheres_N${CELL}_plane.dump "$TILES" --outdir data
fi

if [ "$STAGE" != prepare ]; then
  bed=(-var N "$N" -var wall 1 -var steps "$STEPS" -var M $((STEPS / 5)) -var final 0)
  logs=(post/log.bed_N${N}_${pair_tag}_np${RANKS} post/log.bed_spheres_N${N}_np${RANKS})
  start=$SECONDS
  "$MPIRUN" -np "$RANKS" "$LIGGGHTS" -in in.packing "${bed[@]}" -var pair "$PAIR" -var precision "$PRECISION" \
    -log "${logs[0]}" -screen none
  echo "== polyhedra bed: $((SECONDS - start)) s"
  start=$SECONDS
  "$MPIRUN" -np "$RANKS" "$LIGGGHTS" -in in.packing_spheres "${bed[@]}" -log "${logs[1]}" -screen none
  echo "== spheres bed: $((SECONDS - start)) s"
  "$PYTHON" report.py "${logs[@]}" | tee post/report_bed_N${N}_np${RANKS}.md
fi
