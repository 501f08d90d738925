#!/bin/bash
# GPU narrow-phase throughput on a packed bed's pair mix (doc/gpu.md, "Narrow-phase throughput"):
#
#   bash tools/bench_gpu.sh [pairs] [precisions] [shapes]
#   bash tools/bench_gpu.sh 1000000 "double single mixed" "schoenhardt cube tetrahedron rock_10 rock_40 rock_70 icosphere_80"
#                                                          (the defaults; about 6 minutes on one H100)
#   bash tools/bench_gpu.sh --variants                     (where nvcc is: builds the launch-bound variants below)
#
# For each shape and precision, build/tests/gpu_agreement SHAPES PAIRS PRECISION bed SHAPE: PAIRS pairs scaled by
# 8 / triangles (10^6 Schoenhardt polyhedra, 1.1e5 70-triangle rocks), each of two particles of its own, half in
# contact with an overlap of 0.1-3 % of the particle volume, half with touching bounding spheres but bodies apart
# (what a settled bed's neighbour list holds besides its contacts). One step after a warm-up; prints pairs per
# second of the kernels alone (pre-filter, overlap and contact law, per-particle sums) and of the whole step
# (poses up and forces down included, which for 2 particles per pair weigh more than in a bed). With only that
# shape uploaded (a deck of one template), by the default choice of contact kernel and by each of the two
# forced (POLY_GPU_PAIR_KERNEL=thread|warp); then with all ten reference shapes uploaded (a deck with a large
# template beside small ones), default against the thread kernel.
#
# Then, when built (--variants, needs nvcc and a `make`d tree), the same for Schoenhardt polyhedra with the
# contact kernel compiled for 3 and 4 blocks per SM (POLY_GPU_CONTACT_MIN_BLOCKS: at most 168 and 128 registers,
# with spills) instead of the default 2 (255 registers, no spills): which launch bound is fastest is measured
# here, not guessed. Needs only the built tree and a GPU (no compiler) to run; prints the GPU, the commit, and
# whether the sources differ from it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
variants_dir="$root/build/bench"

if [ "${1:-}" = "--variants" ]; then
  # The toolkit and runtime the Makefile found.
  info="$(make -s -C "$root" info)"
  nvcc="$(echo "$info" | sed -n 's/.* NVCC=\([^ ]*\) .*/\1/p')"
  cudart="$(echo "$info" | sed -n 's/.* CUDART_STATIC=\([^ ]*\) .*/\1/p')"
  [ -n "$nvcc" ] && [ -n "$cudart" ] || { echo "no nvcc or libcudart_static.a: $info" >&2; exit 1; }
  mkdir -p "$variants_dir"
  for blocks in 3 4; do
    "$nvcc" -std=c++14 -O3 -arch="${CUDA_ARCH:-sm_90}" -Xcompiler -fPIC -I"$root/src" -I"$root/gpu" \
      -DPOLY_GPU_CONTACT_MIN_BLOCKS=$blocks --resource-usage -c "$root/gpu/poly_gpu.cu" \
      -o "$variants_dir/poly_gpu_blocks$blocks.o" 2>&1 | grep -A2 "properties for .*contact_kernel" | grep "registers\|stack" || true
    g++ -std=c++11 -O2 -I"$root/src" -I"$root/gpu" "$root/tests/unit/gpu_agreement.cpp" \
      "$variants_dir/poly_gpu_blocks$blocks.o" "$root"/build/obj/poly_{mesh_read,overlap,shape}.o "$cudart" \
      -ldl -lrt -lpthread -lm -o "$variants_dir/gpu_agreement_blocks$blocks"
    echo "built $variants_dir/gpu_agreement_blocks$blocks"
  done
  exit 0
fi

pairs="${1:-1000000}"
precisions="${2:-double single mixed}"
shapes="${3:-schoenhardt cube tetrahedron rock_10 rock_40 rock_70 icosphere_80}"
agreement="$root/build/tests/gpu_agreement"
[ -x "$agreement" ] || { echo "no $agreement: run make (with nvcc) first" >&2; exit 1; }

. "$root/tools/bench_gpu_common.sh"
echo "commit: $commit; pairs $pairs (scaled by 8 / triangles)"
echo
start=$SECONDS
# Kernels' pairs per second from a gpu_agreement bed line, or the FAIL line.
rate() { sed -n 's/.*GPU \([0-9.e+]*\) pairs\/s in the kernels.*/\1/p; /FAIL/p'; }
echo "One shape uploaded (a deck of one template): pairs/s in the kernels with the default choice of contact"
echo "kernel (doc/gpu.md, \"Contact kernels\"), and with each forced by POLY_GPU_PAIR_KERNEL"
for precision in $precisions; do
  for shape in $shapes; do
    line="$("$agreement" "$root/examples/shapes" "$pairs" "$precision" bed "$shape" | grep "bed pairs\|FAIL")"
    thread="$(POLY_GPU_PAIR_KERNEL=thread "$agreement" "$root/examples/shapes" "$pairs" "$precision" bed "$shape" | rate)"
    warp="$(POLY_GPU_PAIR_KERNEL=warp "$agreement" "$root/examples/shapes" "$pairs" "$precision" bed "$shape" | rate)"
    echo "$line"
    echo "    thread kernel $thread, warp kernel $warp"
  done
done
echo
echo "All 10 reference shapes uploaded (a deck with a large template beside small ones: the thread kernel's"
echo "workspaces go to global memory), each shape's bed in turn: default choice, then the thread kernel forced"
for precision in $precisions; do
  paste -d ' ' <("$agreement" "$root/examples/shapes" "$pairs" "$precision" bed | grep "bed pairs\|FAIL" | \
                   sed 's/ bed pairs.*GPU \([0-9.e+]*\) pairs\/s in the kernels.*/: default \1/') \
               <(POLY_GPU_PAIR_KERNEL=thread "$agreement" "$root/examples/shapes" "$pairs" "$precision" bed | rate | \
                   sed 's/^/thread /')
done
for variant in "$variants_dir"/gpu_agreement_blocks*; do
  [ -x "$variant" ] || continue
  echo
  echo "contact kernel variant $(basename "$variant"):"
  for precision in double single; do
    "$variant" "$root/examples/shapes" "$pairs" "$precision" bed schoenhardt | grep -v "^device memory\|^OK$"
  done
done
echo
echo "total $((SECONDS - start)) s"
