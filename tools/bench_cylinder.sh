#!/bin/bash
# Cylinder-wall benchmark (doc/benchmarks.md, "Cylinder walls"):
#
#   bash tools/bench_cylinder.sh [poses] [repeats]        (defaults 64 and 5; about 10 s)
#
# Builds tools/bench_cylinder.c with the package's C flags (-std=c11 -O3) into a
# temporary directory, prints the machine and the commit, then the table: the
# cost of one poly_cylinder_overlap call per particle-wall contact for each
# reference shape against a zcylinder of radius 10 particle diameters, inside
# (drum) and outside (pillar), overlap 0.1-3 % of the particle volume, at the
# default sagitta of fix wall/polyhedral (tools/bench_c.sh builds and runs it).
exec bash "$(dirname "${BASH_SOURCE[0]}")/bench_c.sh" bench_cylinder "${1:-64}" "${2:-5}"
