"""Pairs found apart wait (pair_style polyhedral/volumetric `skip_apart on`, the default): a filtered-out evaluation
proves a gap (poly_overlap_result's gap, src/poly_overlap_impl.h's proved_gap) and the pair style does not evaluate
the pair again while its two particles may have moved, summed, less than that (their travel: |dx| + 2 r |dq| a
step).

- tests/unit/apart_gap.c finds pairs apart at random poses, of shapes of several kinds and sizes (the general path,
  the clipping path's slab, the supporting triangles; double, single and mixed precision; near the origin and 1e3
  sizes from it) and moves them by 0.5 to 0.999 of their gap, split between B's shift towards A, A's shift and both
  turns: neither the pair style's evaluation nor one without any filter may find a volume (some pairs parted by a
  supporting triangle moved by the gap of poly_overlap_still_separated, the pair style's hint, instead). At three
  times the gap they must find some.
- A pile of 80 rock_40 (examples/bench_multisphere/in.pile_poly, fewer particles and steps), with `skip_apart on`
  and `off`, on one rank and on two (ghost particles' travel), in a box periodic in x and y on two ranks (ghost
  images across the boundary), and in mixed precision: the same thermo output to the digits printed and the same
  contacts, with most evaluations of apart pairs skipped.
- The parting search (`parting_search on`, the default; src/poly_overlap_parting_impl.h): the same random pairs
  evaluated with it, so that pairs no filter parts are searched for a parting plane: no pair it parts has a volume by
  the evaluation without any filter, and its gaps hold as the filters' do. The pile with `parting_search on` and `off`:
  the same thermo output and contacts, fewer near misses (rock_40, the general path), and for Schoenhardt polyhedra
  (the clipping path, which finds apart pairs apart without a gap) fewer evaluations of apart pairs.

Run with Debian's python3:  /usr/bin/python3 -m pytest tests/test_skip_apart.py -q
"""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(tmp_path_factory.mktemp("apart") / "apart_gap")
    sources = [os.path.join(ROOT, "tests", "unit", "apart_gap.c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I" + os.path.join(ROOT, "src")]
                   + sources + ["-lm", "-o", binary], check=True)
    return binary


def apart_gap(binary, pair, precision, factor, far=False, cases=600, seek=False):
    a, scale_a, b, scale_b = pair
    out = subprocess.run([binary, os.path.join(SHAPES, a), str(scale_a), os.path.join(SHAPES, b), str(scale_b),
                          str(cases), precision, str(factor)] + (["far"] if far else []) + (["seek"] if seek else []),
                         capture_output=True, text=True, check=True).stdout
    words = out.split()
    return dict(zip(words[0::2], (int(w) for w in words[1::2])))


# rock_40 pairs (general path, supporting triangles), Schoenhardt pairs (the clipping path's slab in double),
# different shapes and sizes, tiny and huge.
PAIRS = [("rock_40.obj", 1, "rock_40.obj", 1), ("schoenhardt.stl", 1, "schoenhardt.stl", 1),
         ("cube.stl", 1, "rock_70.obj", 0.3), ("rock_20.obj", 1e3, "icosphere_80.off", 2e3),
         ("schoenhardt.stl", 1e-3, "rock_40.obj", 2e-3)]


@pytest.mark.parametrize("pair", PAIRS, ids=lambda p: f"{p[0]}-{p[2]}")
@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
def test_pairs_moved_less_than_their_gap_do_not_overlap(driver, pair, precision):
    by_hint = 0
    for far in (False, True):
        counts = apart_gap(driver, pair, precision, 0.999, far=far)
        assert counts["apart"] > 100, counts
        assert counts["overlapping"] == 0 and counts["overlapping_unfiltered"] == 0, counts
        by_hint += counts["by_hint"]
    if pair[0] == "rock_40.obj" and precision != "mixed":
        assert by_hint > 5  # the hint's gaps (poly_overlap_still_separated) were tried too


@pytest.mark.parametrize("pair", PAIRS[:3], ids=lambda p: f"{p[0]}-{p[2]}")
def test_pairs_moved_three_times_their_gap_do(driver, pair):
    counts = apart_gap(driver, pair, "double", 3.0)
    assert counts["overlapping"] > 0.02 * counts["tested"], counts
    assert counts["overlapping_unfiltered"] == counts["overlapping"], counts


@pytest.mark.parametrize("pair", PAIRS, ids=lambda p: f"{p[0]}-{p[2]}")
@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
def test_pairs_parted_by_the_search_do_not_overlap_nor_within_their_gap(driver, pair, precision):
    by_search = 0
    for far in (False, True):
        counts = apart_gap(driver, pair, precision, 0.999, far=far, cases=1500, seek=True)
        assert counts["apart"] > 250, counts
        assert counts["by_search_overlapping"] == 0 and counts["by_search_moved_overlapping"] == 0, counts
        assert counts["overlapping"] == 0 and counts["overlapping_unfiltered"] == 0, counts
        by_search += counts["by_search"]
    # The general path's pairs and the clipping path's (Schoenhardt pairs in double and mixed: the search gives
    # them the gap the clipping does not prove).
    assert by_search >= 5, by_search


def test_gaps_of_the_search_are_tight(driver):
    # Of the pairs only the search parted, moved by three times its gap, some overlap (without any filter).
    counts = apart_gap(driver, PAIRS[0], "double", 3.0, cases=1500, seek=True)
    assert counts["by_search_tested"] > 40, counts
    assert counts["by_search_moved_overlapping"] > 0.02 * counts["by_search_tested"], counts


def pile_deck(skip, periodic, precision, parting="on"):
    text = open(os.path.join(ROOT, "examples", "bench_multisphere", "in.pile_poly")).read()
    for old in ("pair_style      polyhedral/volumetric\n", "boundary        f f f\n"):
        assert old in text
    text = text.replace("pair_style      polyhedral/volumetric\n",
                        f"pair_style      polyhedral/volumetric skip_apart {skip} precision {precision} "
                        f"parting_search {parting}\n")
    if periodic:
        # Periodic in x and y: the side walls go, the box's sides are the period.
        text = text.replace("boundary        f f f\n", "boundary        p p f\n")
        text = "\n".join(line for line in text.splitlines()
                         if not line.startswith(("fix xlo", "fix xhi", "fix ylo", "fix yhi"))) + "\n"
    text = text.replace("pair_coeff      * *\n", "pair_coeff      * *\ncompute ev all pair/polyhedral/local\n")
    return text + ("thermo_style custom step atoms c_ev[4] c_ev[5] c_ev[6] c_ev[7] c_ev[8]\n"
                   "thermo_modify format float %.15g\nrun 1\n")


@pytest.mark.parametrize("nprocs,periodic,precision", [(1, False, "double"), (2, False, "double"),
                                                        (2, True, "double"), (1, False, "mixed")])
def test_a_pile_of_rocks_runs_the_same_with_and_without_the_skip(run_deck, tmp_path, nprocs, periodic, precision):
    variables = {"SHAPE": os.path.join(SHAPES, "rock_40.obj"), "N": 80, "settle": 20000, "steps": 10000,
                 "every": 500, "ZFILL": 0.08}
    outputs, counts = {}, {}
    for skip in ("on", "off"):
        result = run_deck(pile_deck(skip, periodic, precision), nprocs=nprocs, variables=variables,
                          workdir=tmp_path / skip)
        assert result.returncode == 0, result.output[-3000:]
        outputs[skip] = result.thermo("Step", "v_ke", "v_xmin", "v_xmax", "v_ymin", "v_ymax", "v_zmin", "v_zmax")
        table = result.thermo("Step", "c_ev[4]", "c_ev[5]", "c_ev[6]", "c_ev[7]", "c_ev[8]")
        counts[skip] = {name: table[f"c_ev[{k}]"][-1]
                        for k, name in ((4, "candidates"), (5, "skipped"), (6, "contacts"), (7, "parted"),
                                        (8, "near misses"))}
    print(f"\n{nprocs} rank(s){', periodic' if periodic else ''}, {precision}: on {counts['on']}, off {counts['off']}")
    assert len(outputs["on"]["Step"]) > 8
    assert outputs["on"] == outputs["off"]
    for name in ("candidates", "contacts"):
        assert counts["on"][name] == counts["off"][name], name
    # Without the skip only a parting plane that still parts a pair skips it; with it, most apart pairs wait.
    assert counts["on"]["skipped"] > counts["off"]["skipped"] + 0.5 * counts["off"]["parted"]
    assert counts["on"]["parted"] < 0.2 * counts["off"]["parted"]


@pytest.mark.parametrize("shape", ["rock_40.obj", "schoenhardt.stl"])
def test_a_pile_of_rocks_runs_the_same_with_and_without_the_parting_search(run_deck, tmp_path, shape):
    """rock_40 takes the general path, whose near misses the search parts; Schoenhardt polyhedra the clipping path,
    which finds its apart pairs apart but proves no gap: the search's gaps let them wait (skip_apart)."""
    variables = {"SHAPE": os.path.join(SHAPES, shape), "N": 80, "settle": 20000, "steps": 10000,
                 "every": 500, "ZFILL": 0.08}
    outputs, counts = {}, {}
    for parting in ("on", "off"):
        result = run_deck(pile_deck("on", False, "double", parting), variables=variables, workdir=tmp_path / parting)
        assert result.returncode == 0, result.output[-3000:]
        outputs[parting] = result.thermo("Step", "v_ke", "v_xmin", "v_xmax", "v_ymin", "v_ymax", "v_zmin", "v_zmax")
        table = result.thermo("Step", "c_ev[4]", "c_ev[6]", "c_ev[7]", "c_ev[8]")
        counts[parting] = {name: table[f"c_ev[{k}]"][-1]
                           for k, name in ((4, "candidates"), (6, "contacts"), (7, "parted"), (8, "near misses"))}
    print(f"\n{shape}: parting search on {counts['on']}, off {counts['off']}")
    assert len(outputs["on"]["Step"]) > 8
    assert outputs["on"] == outputs["off"]
    for name in ("candidates", "contacts"):
        assert counts["on"][name] == counts["off"][name], name
    if shape == "rock_40.obj":
        assert counts["on"]["near misses"] < 0.5 * counts["off"]["near misses"]
    else:
        # (its few near misses are pairs with flush faces, which the clipping hands to the general path)
        assert counts["on"]["parted"] < 0.7 * counts["off"]["parted"]
