#!/bin/bash
# CPU mesh-wall narrow phase: (particle, prism) pieces per second on one core (doc/benchmarks.md, "Mesh walls
# on the CPU"):
#
#   bash tools/bench_mesh_pieces.sh [particles] [repeats] [shape] [cells]
#
# (defaults 2000, 5, all, 12; about a minute.) Builds and runs tools/bench_mesh_pieces.c (tools/bench_c.sh: the
# package's C flags, machine and commit); `shape` (e.g. rock_40.obj) runs that one alone, `all` every one; `cells`
# sets the mesh's cells a side (the triangles' legs are 6 / cells particle radii; 2: larger than the particle).
exec bash "$(dirname "${BASH_SOURCE[0]}")/bench_c.sh" bench_mesh_pieces "${1:-2000}" "${2:-5}" "${3:-all}" ${4:+"$4"}
