#!/usr/bin/env bash
# The packed bed on several GPUs of one host, against one GPU of the same host in the same script run.
#
#   bash gpus.sh [G] [R]        # G GPUs (default 2), R MPI ranks per GPU (default 8)
#
# Stages (STAGE, default "prepare agree scale"):
#   prepare  the settled 10115-particle cell (bed.sh's first stage, -var wall 1) tiled T x T: T = 10 (1,011,500
#            particles), T = TW (default the integer nearest 10 sqrt(G): about G times as many) and T = 3 (91,035)
#   agree    per precision: the 91,035 bed, STEPS_AGREE (100, a multiple of 10) steps with G R ranks on one GPU
#            and on G GPUs; the final positions compared; the G-GPU run writes a restart which a one-GPU run
#            reads back and runs 10 steps on, compared with the G GPUs running all the steps with the run split
#            at the restart's step (in.packing's `split`: a restart continues as such a split run does, to the bit,
#            tests/test_parallel_restart.py; an unbroken run differs, each `run` setting up with full-step
#            velocities, the damping's forces among them)
#   scale    per precision: 10^6 on one GPU (R ranks), about G x 10^6 on G GPUs (G R ranks), 10^6 on G GPUs (G R
#            ranks), STEPS (500) steps each: ms per step; weak scaling t(1 GPU, 10^6) / t(G GPUs, G x 10^6)
#            (per particle), strong scaling t(1 GPU) / (G t(G GPUs)) at 10^6
#
# GPUs are chosen with CUDA_VISIBLE_DEVICES (0 for one GPU, 0,...,G-1 for G); each rank takes GPU (node-local
# rank mod visible GPUs), the pair style's own mapping, over LIGGGHTS' own decomposition (processors * * 1).
# MPS=1 (default) runs one MPS daemon for all GPUs (doc/gpu.md). PRECISIONS (default "double mixed"),
# LIGGGHTS, MPIRUN, PYTHON as bed.sh. Everything goes to post/gpus_G<G>_R<R>.md and the logs beside it.
set -euo pipefail
cd "$(dirname "$0")"

G=${1:-2}
R=${2:-8}
STAGE=${STAGE:-"prepare agree scale"}
PRECISIONS=${PRECISIONS:-"double mixed"}
STEPS=${STEPS:-500}
STEPS_AGREE=${STEPS_AGREE:-100}
SETTLE=${SETTLE:-0.05}
CELL=${CELL:-10115}
TW=${TW:-$(awk -v g="$G" 'BEGIN {printf "%d", 10 * sqrt(g) + 0.5}')}
MPS=${MPS:-1}
PAIR=${PAIR:-polyhedral/volumetric/gpu}
LIGGGHTS=${LIGGGHTS:-../../build/bin/liggghts-poly}
MPIRUN=${MPIRUN:-mpirun}
PYTHON=${PYTHON:-python3}
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
mkdir -p post data
report=post/gpus_G${G}_R${R}.md
all_gpus=$(seq -s, 0 $((G - 1)))
echo "# $(date -u +%FT%TZ) $(hostname), commit $(git rev-parse --short HEAD 2>/dev/null || echo ?), G=$G R=$R, PAIR=$PAIR" | tee -a "$report"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=index,name,memory.total --format=csv,noheader | sed 's/^/# GPU /' | tee -a "$report"

if [ "$MPS" = 1 ] && command -v nvidia-cuda-mps-control >/dev/null; then
  export CUDA_MPS_PIPE_DIRECTORY=/tmp/mps CUDA_MPS_LOG_DIRECTORY=/tmp/mps-log
  mkdir -p "$CUDA_MPS_PIPE_DIRECTORY" "$CUDA_MPS_LOG_DIRECTORY"
  nvidia-cuda-mps-control -d 2>/dev/null || true
  trap 'echo quit | nvidia-cuda-mps-control 2>/dev/null || true' EXIT
  echo "# MPS on" | tee -a "$report"
fi

# run GPUS RANKS LOG ARGS...: in.packing on the GPUs listed (CUDA_VISIBLE_DEVICES), printing ms per step.
run() {
  local gpus=$1 ranks=$2 log=$3; shift 3
  CUDA_VISIBLE_DEVICES=$gpus "$MPIRUN" -np "$ranks" -x CUDA_VISIBLE_DEVICES "$LIGGGHTS" -in in.packing \
    -var pair "$PAIR" -var wall 1 -var count 0 "$@" -log "$log" -screen none > /dev/null
  awk '/^Loop time of/ {t = $4; s = $9} END {printf "%.2f", 1000 * t / s}' "$log"
}

if [[ " $STAGE " == *" prepare "* ]]; then
  STAGE=prepare TILES=10 CELL=$CELL SETTLE=$SETTLE PAIR=$PAIR LIGGGHTS=$LIGGGHTS MPIRUN=$MPIRUN PYTHON=$PYTHON \
    bash bed.sh 10 "$R" > post/gpus_prepare.txt
  for t in "$TW" 3; do "$PYTHON" tile_bed.py "post/final_packing_N${CELL}_plane.dump" "$t" --outdir data; done
fi

if [[ " $STAGE " == *" agree "* ]]; then
  [ $((STEPS_AGREE % 10)) -eq 0 ] || { echo "gpus.sh: STEPS_AGREE must be a multiple of 10" >&2; exit 2; }
  n=$((9 * CELL)); ranks=$((G * R))
  for precision in $PRECISIONS; do
    common=(-var N "$n" -var precision "$precision" -var steps "$STEPS_AGREE" -var M 10)
    one=$(run 0 "$ranks" "post/log.gpus_agree_1gpu_$precision" "${common[@]}" \
          -var finalname "post/gpus_agree_1gpu_$precision.dump")
    many=$(run "$all_gpus" "$ranks" "post/log.gpus_agree_${G}gpu_$precision" "${common[@]}" \
           -var finalname "post/gpus_agree_${G}gpu_$precision.dump" -var save 1 \
           -var restartfile "post/gpus_agree_$precision.restart")
    back=$(run 0 "$ranks" "post/log.gpus_restart_1gpu_$precision" -var N "$n" -var precision "$precision" \
           -var resume 1 -var restartfile "post/gpus_agree_$precision.restart" -var steps 10 -var M 10 \
           -var finalname "post/gpus_restart_1gpu_$precision.dump")
    split=$(run "$all_gpus" "$ranks" "post/log.gpus_split_${G}gpu_$precision" -var N "$n" \
            -var precision "$precision" -var steps $((STEPS_AGREE + 10)) -var split "$STEPS_AGREE" -var M 10 \
            -var finalname "post/gpus_split_${G}gpu_$precision.dump")
    "$PYTHON" - "$precision" "$G" "$one" "$many" "$back" >> "$report" <<'EOF'
import sys
precision, gpus, one_ms, many_ms, back_ms = sys.argv[1:]

def snapshots(path):
    lines, found, i = open(path).read().splitlines(), {}, 0
    while i < len(lines):
        if lines[i] == "ITEM: TIMESTEP":
            step, count = int(lines[i + 1]), int(lines[i + 3])
            rows = (line.split() for line in lines[i + 9:i + 9 + count])
            found[step] = {int(w[0]): tuple(float(x) for x in w[2:5]) for w in rows}
            i += 9 + count
        else:
            i += 1
    return found

def worst(a, b):
    assert sorted(a) == sorted(b), "different particles"
    return max(max(abs(p - q) for p, q in zip(a[k], b[k])) for k in a)

one = snapshots(f"post/gpus_agree_1gpu_{precision}.dump")
many = snapshots(f"post/gpus_agree_{gpus}gpu_{precision}.dump")
back = snapshots(f"post/gpus_restart_1gpu_{precision}.dump")
split = snapshots(f"post/gpus_split_{gpus}gpu_{precision}.dump")
last, end = max(many), max(back)
print(f"- agree, {precision}: {len(many[last])} particles, step {last}: largest position difference 1 GPU vs "
      f"{gpus} GPUs {worst(one[max(one)], many[last]):.3g} m (particle size 0.02 m); restart written on {gpus} "
      f"GPUs at step {last}, read on 1 GPU: at step {last} {worst(back[last], many[last]):.3g} m, at step {end} "
      f"against {gpus} GPUs running on with the run split there {worst(back[end], split[end]):.3g} m "
      f"({one_ms} / {many_ms} / {back_ms} ms per step)")
EOF
    tail -1 "$report"
  done
fi

if [[ " $STAGE " == *" scale "* ]]; then
  n1=$((100 * CELL)); nw=$((TW * TW * CELL))
  for precision in $PRECISIONS; do
    common=(-var precision "$precision" -var steps "$STEPS" -var M $((STEPS / 5)) -var final 0)
    t1=$(run 0 "$R" "post/log.gpus_N${n1}_1gpu_np${R}_$precision" -var N "$n1" "${common[@]}")
    tw=$(run "$all_gpus" $((G * R)) "post/log.gpus_N${nw}_${G}gpu_np$((G * R))_$precision" -var N "$nw" "${common[@]}")
    ts=$(run "$all_gpus" $((G * R)) "post/log.gpus_N${n1}_${G}gpu_np$((G * R))_$precision" -var N "$n1" "${common[@]}")
    awk -v p="$precision" -v g="$G" -v r="$R" -v n1="$n1" -v nw="$nw" -v t1="$t1" -v tw="$tw" -v ts="$ts" 'BEGIN {
      printf "| %s | 1 GPU, %d ranks, %d particles | %.2f ms |\n", p, r, n1, t1
      printf "| %s | %d GPUs, %d ranks, %d particles | %.2f ms | weak scaling (per GPU'"'"'s particles) %.1f %% |\n", p, g, g * r, nw, tw, 100 * (t1 / n1) / (g * tw / nw)
      printf "| %s | %d GPUs, %d ranks, %d particles | %.2f ms | strong scaling %.1f %% |\n", p, g, g * r, n1, ts, 100 * t1 / (g * ts)
    }' | tee -a "$report"
  done
fi
