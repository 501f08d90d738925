# Sourced by the GPU benchmarks (tools/bench_gpu.sh, tools/bench_gpu_walls.sh): prints the GPU and the commit
# (with "(modified)" when the sources differ from it) and sets `commit`. Needs `root`.
echo "GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo unknown)"
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git -C "$root" status --porcelain -- src gpu tests/unit 2>/dev/null)" ]; then commit="$commit (modified)"; fi
