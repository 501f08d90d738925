#!/bin/bash
# CPU narrow-phase benchmark (doc/benchmarks.md, "CPU narrow phase"):
#
#   bash tools/bench_overlap.sh [poses] [repeats]        (defaults 64 and 5; about a minute)
#
# Builds tools/bench_overlap.c with the package's C flags (-std=c11 -O2) into a
# temporary directory, prints the machine and the commit, then the table: the
# cost of one poly_overlap call for pairs of one shape in packed-bed poses
# (overlap 0.1-3 % of the particle volume), double and single precision, with
# and without the half-space triangle filter.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

gcc -std=c11 -O2 -Wall -Wextra -I"$root/src" "$root/tools/bench_overlap.c" "$root/src/poly_overlap.c" \
  "$root/src/poly_shape.c" "$root/src/poly_mesh_read.c" "$root/src/poly_convex.c" -lm -o "$work/bench_overlap"

echo "machine: $(nproc) CPUs; $(lscpu | sed -n 's/^Model name:[[:space:]]*//p')"
echo "compiler: $(gcc --version | head -1), -std=c11 -O2"
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
# The files this benchmark compiles, headers included: are any of them uncommitted?
sources="$(gcc -std=c11 -MM -I"$root/src" "$root/src/poly_overlap.c" "$root/src/poly_shape.c" \
  "$root/src/poly_mesh_read.c" "$root/src/poly_convex.c" | tr -d '\\' | tr ' ' '\n' | grep "^$root/src/" | sort -u)"
# shellcheck disable=SC2086
if [ -n "$(git -C "$root" status --porcelain -- $sources 2>/dev/null)" ]; then commit="$commit (modified)"; fi
echo "commit: $commit"
echo
"$work/bench_overlap" "$root/examples/shapes" "${1:-64}" "${2:-5}"
