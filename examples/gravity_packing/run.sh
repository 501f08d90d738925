#!/usr/bin/env bash
# Gravity-packing benchmark: generate the initial state, run the polyhedra and the spheres, report.
#
#   bash run.sh [N] [ranks]                       # default 2000 particles, 2 MPI ranks, CPU pair style
#   PAIR=polyhedral/volumetric/gpu PRECISION=single bash run.sh 100000 16
#
# Environment:
#   PAIR       pair style of the polyhedra: polyhedral/volumetric (default) or polyhedral/volumetric/gpu
#   PRECISION  double (default), single or mixed
#   STEPS      number of steps (default: the decks' own, fall time of the highest particle + SETTLE)
#   SETTLE     seconds of settling after the fall (default 0.02)
#   M          thermo output every M steps (default 200)
#   WALL       1: a plane wall at z = 0 instead of the floor of fixed particles (default 0)
#   SPHERES    0 to skip the sphere run (default 1);  POLYHEDRA  0 to skip the polyhedra (default 1)
#   LIGGGHTS   the launcher (default ../../build/bin/liggghts-poly; Debian's liggghts runs the spheres too)
#   MPIRUN     default mpirun;  PYTHON  default python3 (report.py draws its plot only with matplotlib)
# Output in post/: log.packing_N<N>_<pair>_<precision>_np<ranks>, log.spheres_N<N>_np<ranks>,
# final_*_N<N>_<particles|plane>.dump, report_N<N>_np<ranks>.md and ms_per_step_N<N>_np<ranks>.png (with _wall before
# _np<ranks> for WALL=1).
set -euo pipefail
cd "$(dirname "$0")"

N=${1:-2000}
RANKS=${2:-2}
PAIR=${PAIR:-polyhedral/volumetric}
PRECISION=${PRECISION:-double}
M=${M:-200}
SETTLE=${SETTLE:-0.02}
WALL=${WALL:-0}
SPHERES=${SPHERES:-1}
POLYHEDRA=${POLYHEDRA:-1}
LIGGGHTS=${LIGGGHTS:-../../build/bin/liggghts-poly}
MPIRUN=${MPIRUN:-mpirun}
PYTHON=${PYTHON:-python3}
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
common=(-var N "$N" -var M "$M" -var settle "$SETTLE" -var wall "$WALL")
floor=(); tag=""
[ "$WALL" = 1 ] && floor=(--floor none) && tag=_wall
[ -n "${STEPS:-}" ] && common+=(-var steps "$STEPS")

mkdir -p post data
echo "== $(date -u +%FT%TZ) $(hostname) nproc $(nproc) commit $(git rev-parse --short HEAD 2>/dev/null || echo ?)"
"$PYTHON" make_packing.py "$N" --outdir data "${floor[@]}"

logs=()
if [ "$POLYHEDRA" = 1 ]; then
  log=post/log.packing_N${N}_$(echo "$PAIR" | tr / _)_${PRECISION}${tag}_np${RANKS}
  echo "== polyhedra: $MPIRUN -np $RANKS $LIGGGHTS -in in.packing ${common[*]} -var pair $PAIR -var precision $PRECISION -log $log"
  start=$SECONDS
  "$MPIRUN" -np "$RANKS" "$LIGGGHTS" -in in.packing "${common[@]}" -var pair "$PAIR" -var precision "$PRECISION" \
    -log "$log" -screen none
  echo "   $((SECONDS - start)) s"
  logs+=("$log")
fi
if [ "$SPHERES" = 1 ]; then
  log=post/log.spheres_N${N}${tag}_np${RANKS}
  echo "== spheres: $MPIRUN -np $RANKS $LIGGGHTS -in in.packing_spheres ${common[*]} -log $log"
  start=$SECONDS
  "$MPIRUN" -np "$RANKS" "$LIGGGHTS" -in in.packing_spheres "${common[@]}" -log "$log" -screen none
  echo "   $((SECONDS - start)) s"
  logs+=("$log")
fi
"$PYTHON" report.py "${logs[@]}" --png post/ms_per_step_N${N}${tag}_np${RANKS}.png | tee post/report_N${N}${tag}_np${RANKS}.md
