#!/bin/bash
# Polyhedral particles against LIGGGHTS' multisphere particles, one core (doc/benchmarks.md, "Whole decks
# against LIGGGHTS' alternatives"):
#
#   bash tools/bench_vs_multisphere.sh [--quick] [cube] [rock]      (about 4 min; --quick 25 s)
#
# Piles of 150 cubes (cube.stl against the 27-sphere cube of examples/rocking/cube27.multisphere) and 150
# rock_40 (against the 25 spheres fitted inside it, examples/bench_multisphere/rock40.multisphere, by
# tools/fit_multisphere.py) poured into a 10 x 10 cm box of 5 plane walls: decks in examples/bench_multisphere,
# same particles (mass, inertia, material) but for the shape. After 25000 steps that form the pile, a second
# `run 25000` is timed: LIGGGHTS' Loop time / (particles x steps) for each, and the ratio polyhedral/multisphere.
# Prints the machine, the commit, whether the package sources are modified, and checks that no particle was
# lost and that the piles formed. The multisphere decks run 3 times (--repeat N), their median counts. Needs
# `make -j2 all`, Debian's liggghts and python3-numpy.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exec /usr/bin/python3 "$root/tools/bench_decks.py" multisphere "$@"
