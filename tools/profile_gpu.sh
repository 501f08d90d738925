#!/bin/bash
# Nsight Compute figures of the GPU contact kernels (issue 15; doc/benchmarks.md, "Nsight Compute"):
#
#   bash tools/profile_gpu.sh [pairs] [precision] [shapes]
#   bash tools/profile_gpu.sh 200000 double "schoenhardt rock_10 rock_40 cube tetrahedron"   (the defaults)
#   bash tools/profile_gpu.sh --sass [pairs] [shape] [precision]   (where the warp clipping kernel's stall samples fall)
#
# --sass: ncu's SourceCounters of clip_warp_kernel on the bed pairs of one shape (default 200000, schoenhardt, double),
# its SASS page cut into windows of 250 instructions in program order, and per window holding at least 1 % of the
# stall samples: that share, the warp instructions executed and the threads per instruction (32: none idle),
# then the windows' five hottest instructions. Which source a window is (the clipping loop: its side products,
# DMUL and DFMA, and corner stores, STL; the contact law: one thread an instruction) is read from them.
#
# For each shape, `ncu` profiles the pre-filter and the contact kernels of build/tests/gpu_agreement SHAPES PAIRS
# PRECISION bed SHAPE (the packed bed's pair mix of tools/bench_gpu.sh; the driver's first launch, a warm-up, is
# skipped, then two launches of each) and prints per kernel: registers per thread, theoretical and achieved occupancy, active
# threads per warp instruction (32: none diverged or finished), the FP64 pipe's busy share of the SM's active
# cycles, the double-precision operations executed (an FMA counts 2) per second of the kernel, and that as a
# share of 3.4e13/s (an H100's FP64 peak without tensor cores), and the kernel's duration. Then the stall reasons
# of the first kernel of each shape (ncu's WarpStateStats section). Needs a built tree, a GPU and ncu on the PATH
# (the lent GPU machines have it); leaves the clocks alone (--clock-control none). Prints the GPU and the commit.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "${1:-}" = "--sass" ]; then
  pairs="${2:-200000}"
  shape="${3:-schoenhardt}"
  sass_precision="${4:-double}"
  command -v ncu > /dev/null || { echo "ncu (Nsight Compute) is not on the PATH" >&2; exit 1; }
  source "$root/tools/bench_gpu_common.sh"
  echo "commit: $commit; $pairs bed pairs of $shape, $sass_precision; clip_warp_kernel's stall samples by SASS window"
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  ncu --clock-control none --kernel-name clip_warp_kernel --launch-skip 1 --launch-count 1 --section SourceCounters \
    -o "$work/report" "$root/build/tests/gpu_agreement" "$root/examples/shapes" "$pairs" "$sass_precision" bed "$shape" > /dev/null
  ncu -i "$work/report.ncu-rep" --page source --csv --print-source sass > "$work/sass.csv"
  exec /usr/bin/env python3 "$root/tools/profile_sass_windows.py" "$work/sass.csv"
fi
pairs="${1:-200000}"
precision="${2:-double}"
shapes="${3:-schoenhardt rock_10 rock_40 cube tetrahedron}"
driver="$root/build/tests/gpu_agreement"
[ -x "$driver" ] || { echo "build/tests/gpu_agreement is missing: make all (with CUDA) first" >&2; exit 1; }
command -v ncu > /dev/null || { echo "ncu (Nsight Compute) is not on the PATH" >&2; exit 1; }
source "$root/tools/bench_gpu_common.sh"
echo "commit: $commit; $pairs bed pairs, $precision"
# The pre-filter too: since the parting search (doc/benchmarks.md) it is more than a sphere and slab test.
kernels='regex:^(bounding_kernel|clip_warp_kernel|clip_contact_kernel|contact_kernel|warp_contact_kernel)'
metrics=launch__registers_per_thread,sm__maximum_warps_per_active_cycle_pct,sm__warps_active.avg.pct_of_peak_sustained_active
metrics=$metrics,smsp__thread_inst_executed_per_inst_executed.ratio,sm__pipe_fp64_cycles_active.avg.pct_of_peak_sustained_active
metrics=$metrics,smsp__sass_thread_inst_executed_op_dfma_pred_on.sum,smsp__sass_thread_inst_executed_op_dadd_pred_on.sum
metrics=$metrics,smsp__sass_thread_inst_executed_op_dmul_pred_on.sum,gpu__time_duration.sum
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%-12s %-28s %5s %7s %7s %8s %7s %10s %8s %9s\n' shape kernel regs occ_th occ_ach thr/warp fp64% DP_op/s of_peak time_us
for shape in $shapes; do
  ncu --clock-control none --kernel-name "$kernels" --launch-skip 1 --launch-count 4 --metrics "$metrics" --csv \
    --page raw "$driver" "$root/examples/shapes" "$pairs" "$precision" bed "$shape" > "$work/$shape.csv" 2> "$work/$shape.err" ||
    { echo "$shape: ncu failed:"; tail -5 "$work/$shape.err"; continue; }
  /usr/bin/env python3 - "$work/$shape.csv" "$shape" <<'EOF'
import csv, sys
rows = [r for r in csv.reader(open(sys.argv[1])) if r]
start = next(i for i, r in enumerate(rows) if "Kernel Name" in r)
header, body = rows[start], rows[start + 2:]  # the row after the header holds the units
col = {name: header.index(name) for name in header}
def value(row, name):
    text = row[col[name]].replace(",", "")
    return float(text) if text not in ("", "n/a") else float("nan")
for row in body:
    if len(row) < len(header):
        continue
    seconds = value(row, "gpu__time_duration.sum") * 1e-9  # ncu reports ns
    ops = (2 * value(row, "smsp__sass_thread_inst_executed_op_dfma_pred_on.sum")
           + value(row, "smsp__sass_thread_inst_executed_op_dadd_pred_on.sum")
           + value(row, "smsp__sass_thread_inst_executed_op_dmul_pred_on.sum"))
    rate = ops / seconds if seconds > 0 else float("nan")
    name = row[col["Kernel Name"]].split("(")[0]
    print("%-12s %-28s %5d %6.1f%% %6.1f%% %8.1f %6.1f%% %10.3g %7.2f%% %9.1f" % (
        sys.argv[2], name[:28], value(row, "launch__registers_per_thread"),
        value(row, "sm__maximum_warps_per_active_cycle_pct"),
        value(row, "sm__warps_active.avg.pct_of_peak_sustained_active"),
        value(row, "smsp__thread_inst_executed_per_inst_executed.ratio"),
        value(row, "sm__pipe_fp64_cycles_active.avg.pct_of_peak_sustained_active"), rate, 100 * rate / 3.4e13,
        seconds * 1e6))
EOF
done
for shape in $shapes; do
  echo "== stalls, $shape (first profiled kernel)"
  ncu --clock-control none --kernel-name "${kernels/bounding_kernel|/}" --launch-skip 1 --launch-count 1 \
    --section WarpStateStats \
    "$driver" "$root/examples/shapes" "$pairs" "$precision" bed "$shape" 2>&1 |
    grep -iE -A2 'warp cycles per|active threads|being stalled|^  [a-z_]+' | grep -v -- '^--$' | cut -c1-160 | head -24 || true
done
