#!/usr/bin/env bash
# GPU narrow-phase throughput: candidate pairs per second of one poly_gpu_compute step (poses up, kernels,
# per-particle forces down) for every reference shape, in double, single and mixed precision, as a Markdown
# table. Pairs: random orientations, centre distance 0.8 to 1.7 bounding radii (mostly overlapping, as in a
# packed bed); COUNT pairs scaled by 8 / triangles per shape (at least 2000). Needs a GPU and `make`.
#
#   bash tools/bench_gpu.sh [COUNT]          # default 1000000
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-1000000}
echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo ?), $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), COUNT $count"
for precision in double single mixed; do
  build/tests/gpu_agreement examples/shapes "$count" "$precision" gpu-only > "/tmp/bench_gpu_$precision.txt"
done
echo
echo "| shape | pairs | contacts | double (pairs/s) | single (pairs/s) | mixed (pairs/s) |"
echo "|---|---:|---:|---:|---:|---:|"
paste -d'|' /tmp/bench_gpu_double.txt /tmp/bench_gpu_single.txt /tmp/bench_gpu_mixed.txt | grep "pairs/s" |
  awk -F'|' '{
    split($1, d, /[ ,:;]+/); split($2, s, /[ ,:;]+/); split($3, m, /[ ,:;]+/);
    sub(/\..*/, "", d[1]);
    printf "| %s | %s | %s | %s | %s | %s |\n", d[1], d[3], d[5], d[8], s[8], m[8] }'
