#!/bin/bash
# LIGGGHTS decks with their spheres turned into rock_40 polyhedra, against the spheres, one core
# (doc/benchmarks.md, "Whole decks against LIGGGHTS' alternatives"):
#
#   bash tools/bench_tutorial_decks.sh [--quick] [--steps S | --all] [movingMeshGran] [hopper]
#   bash tools/bench_tutorial_decks.sh [--chute-steps C] [--chute-shape FILE] chute_wear
#
# movingMeshGran: the tutorial as Debian's liggghts-doc ships it, its particle lines converted to rock_40 of the
# spheres' volume (tools/bench_decks.py, convert_to_polyhedra), both without dumps and cut after the first S
# steps (default 12000, about 6 min here; --all the whole 70000, 68 min today). hopper: examples/hopper/run.py
# (300 rocks against 300 spheres, fill and discharge; about 1.5 min). Per stage and in all: LIGGGHTS' Loop time
# / (particles x steps) for rocks and spheres and their ratio (targets: movingMeshGran at most 5, hopper at
# most 10); the sphere decks run 3 times (--repeat N), their median counts. --quick: 2000 steps of
# movingMeshGran and a 0.15 s hopper, about 20 s. chute_wear (only when named): the tutorial's stream onto a static
# mesh chute, converted by tools/convert_deck.py to FILE (schoenhardt.stl) of the spheres' volume, the first C
# steps (40000, about a minute). For movingMeshGran and chute_wear also where the rocks' pair evaluations went
# (compute pair/polyhedral/local's vector 4-10, printed by a `run 0` appended to the converted deck): skipped by
# their parting plane, contacts, parted early, near misses, those from the crossing cache; and by a second `run 0`
# the contacts at several spots (element 11). BENCH_LAUNCHER=path runs another build's
# liggghts-poly (before/after).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exec /usr/bin/python3 "$root/tools/bench_decks.py" tutorial "$@"
