#!/bin/bash
# CPU mesh-wall narrow phase: (particle, prism) pieces per second on one core (doc/benchmarks.md, "Mesh walls
# on the CPU"):
#
#   bash tools/bench_mesh_pieces.sh [particles] [repeats]        (defaults 2000 and 5; about a minute)
#
# Builds tools/bench_mesh_pieces.c with the package's C flags (-std=c11 -O2) into a temporary directory and
# prints the machine, the commit and the table.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sources=("$root/src/poly_overlap.c" "$root/src/poly_shape.c" "$root/src/poly_mesh_read.c" "$root/src/poly_mesh_shell.c"
  "$root/src/poly_convex.c")
gcc -std=c11 -O2 -Wall -Wextra -I"$root/src" "$root/tools/bench_mesh_pieces.c" "${sources[@]}" -lm \
  -o "$work/bench_mesh_pieces"
echo "machine: $(nproc) CPUs; $(lscpu | sed -n 's/^Model name:[[:space:]]*//p')"
echo "compiler: $(gcc --version | head -1), -std=c11 -O2"
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git -C "$root" status --porcelain -- src 2>/dev/null)" ]; then commit="$commit (modified)"; fi
echo "commit: $commit"
echo
"$work/bench_mesh_pieces" "$root/examples/shapes" "${1:-2000}" "${2:-5}"
