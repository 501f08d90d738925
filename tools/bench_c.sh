#!/bin/bash
# Builds and runs one of the CPU benchmarks (tools/bench_overlap.sh, tools/bench_cylinder.sh,
# tools/bench_mesh_pieces.sh):
#
#   bash tools/bench_c.sh NAME [args...]
#
# Compiles tools/NAME.c and the C core with the package's C flags (-std=c11 -O3, no -march) into a temporary
# directory, prints the machine, the compiler and the commit (marked "(modified)" when a file it compiles,
# headers included, has uncommitted changes), then runs it on examples/shapes with the arguments.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
name="$1"
shift
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

sources=("$root/tools/$name.c" "$root/src/poly_overlap.c" "$root/src/poly_shape.c" "$root/src/poly_mesh_read.c"
  "$root/src/poly_convex.c" "$root/src/poly_mesh_shell.c")
# BENCH_DEFINES="-DNAME ...": extra defines for the build (e.g. -DPOLY_CLIP_WIDE_MASKS, the GPU's 128-bit plane masks).
# shellcheck disable=SC2086
gcc -std=c11 -O3 -Wall -Wextra ${BENCH_DEFINES:-} -I"$root/src" "${sources[@]}" -lm -o "$work/$name"

echo "machine: $(nproc) CPUs; $(lscpu | sed -n 's/^Model name:[[:space:]]*//p')"
echo "compiler: $(gcc --version | head -1), -std=c11 -O3 ${BENCH_DEFINES:-}"
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
files="$(gcc -std=c11 -MM -I"$root/src" "${sources[@]}" | tr -d '\\' | tr ' ' '\n' | grep "^$root/" | sort -u)"
# shellcheck disable=SC2086
if [ -n "$(git -C "$root" status --porcelain -- $files 2>/dev/null)" ]; then commit="$commit (modified)"; fi
echo "commit: $commit"
echo
"$work/$name" "$root/examples/shapes" "$@"
