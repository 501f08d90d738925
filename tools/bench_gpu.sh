#!/bin/bash
# GPU narrow-phase throughput on a packed bed's pair mix (doc/gpu.md, "Narrow-phase throughput"):
#
#   bash tools/bench_gpu.sh [pairs] [precisions] [shapes]
#   bash tools/bench_gpu.sh 1000000 "double single mixed" "schoenhardt cube tetrahedron rock_10 rock_40 rock_70 icosphere_80"
#                                                          (the defaults; about 6 minutes on one H100)
#   bash tools/bench_gpu.sh --variants                     (where nvcc is: builds the launch-bound variants below)
#   bash tools/bench_gpu.sh --clip-variants [pairs]        (the clipping warp kernel's variants alone)
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
# with spills) instead of the default 2 (255 registers, no spills), and with the clipping warp kernel compiled
# for 2, 3, 5 and 6 blocks per SM (POLY_CLIP_WARP_MIN_BLOCKS, default 4): which launch bound is fastest is measured
# here, not guessed (--clip-variants: the clipping kernel's alone, on the shapes with pieces, against the default
# build). Each variant is the Makefile's build in build/bench/NAME. Needs only the built tree and a GPU (no
# compiler) to run; prints the GPU, the commit, and whether the sources differ from it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
variants_dir="$root/build/bench"

if [ "${1:-}" = "--variants" ]; then
  # Each variant is the Makefile's build with one define more, in its own build directory.
  info="$(make -s -C "$root" info)"
  arch="$(echo "$info" | sed -n 's/.* CUDA_ARCH=\([^ ]*\) .*/\1/p')"
  [ -n "$arch" ] || { echo "no CUDA in this build: $info" >&2; exit 1; }
  mkdir -p "$variants_dir"
  build_variant() {  # name define kernel
    make -s -C "$root" -j"$(nproc)" BUILD="build/bench/$1" \
      NVCCFLAGS="-std=c++14 -O3 -arch=$arch -Xcompiler -fPIC -Isrc -Igpu $2 --resource-usage" \
      "build/bench/$1/tests/gpu_agreement" 2>&1 | grep -A2 "properties for .*$3" | grep "registers\|stack" | head -2 || true
    echo "built $variants_dir/$1/tests/gpu_agreement"
  }
  for blocks in 3 4; do build_variant "blocks$blocks" "-DPOLY_GPU_CONTACT_MIN_BLOCKS=$blocks" contact_kernel; done
  # The clipping warp kernel's register bound (POLY_CLIP_WARP_MIN_BLOCKS, 4 by default: 128 registers).
  for blocks in 2 3 5 6; do build_variant "clipblocks$blocks" "-DPOLY_CLIP_WARP_MIN_BLOCKS=$blocks" clip_warp_kernel; done
  exit 0
fi

# The clipping warp kernel's variants alone (after --variants), against the default build, alternately.
if [ "${1:-}" = "--clip-variants" ]; then
  pairs="${2:-1000000}"
  . "$root/tools/bench_gpu_common.sh"
  echo "commit: $commit; pairs $pairs (scaled by 8 / triangles), double; kernel pairs/s"
  for shape in schoenhardt rock_10 rock_40; do
    for round in 1 2; do
      for variant in "$root/build/tests/gpu_agreement" "$variants_dir"/clipblocks*/tests/gpu_agreement; do
        [ -x "$variant" ] || continue
        printf '%-12s %-40s %s\n' "$shape" "${variant#$root/}" \
          "$("$variant" "$root/examples/shapes" "$pairs" double bed "$shape" | sed -n 's/.*GPU \([0-9.e+]*\) pairs\/s in the kernels.*/\1/p')"
      done
    done
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
# One run after the other (two process substitutions under paste would run both at once on the one GPU).
for precision in $precisions; do
  defaults="$("$agreement" "$root/examples/shapes" "$pairs" "$precision" bed | grep "bed pairs\|FAIL" | \
              sed 's/ bed pairs.*GPU \([0-9.e+]*\) pairs\/s in the kernels.*/: default \1/')"
  threads="$(POLY_GPU_PAIR_KERNEL=thread "$agreement" "$root/examples/shapes" "$pairs" "$precision" bed | rate | \
             sed 's/^/thread /')"
  paste -d ' ' <(echo "$defaults") <(echo "$threads")
done
for variant in "$variants_dir"/blocks*/tests/gpu_agreement "$variants_dir"/clipblocks*/tests/gpu_agreement; do
  [ -x "$variant" ] || continue
  echo
  echo "variant ${variant#$root/}:"
  for precision in double single; do
    "$variant" "$root/examples/shapes" "$pairs" "$precision" bed schoenhardt | grep -v "^device memory\|^OK$"
  done
done
echo
echo "total $((SECONDS - start)) s"
