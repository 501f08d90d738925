#!/bin/bash
# CPU narrow-phase benchmark (doc/benchmarks.md, "CPU narrow phase"):
#
#   bash tools/bench_overlap.sh [poses] [repeats]        (defaults 64 and 5; about a minute)
#
# Builds tools/bench_overlap.c with the package's C flags (-std=c11 -O3) into a
# temporary directory, prints the machine and the commit, then the table: the
# cost of one poly_overlap call for pairs of one shape in packed-bed poses
# (overlap 0.1-3 % of the particle volume), double and single precision, with
# and without the half-space triangle filter (tools/bench_c.sh builds and runs it).
exec bash "$(dirname "${BASH_SOURCE[0]}")/bench_c.sh" bench_overlap "${1:-64}" "${2:-5}"
