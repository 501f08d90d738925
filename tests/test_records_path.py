"""The crossing records of the overlap pass (src/poly_overlap_records_impl.h) against the reference path.

The records path decides each crossing of an edge with a triangle once and derives the vertices' inside
states and the triangle pairs' chords from those decisions; the reference path (ws.use_records = 0: a ray's
parity per vertex, every kept triangle pair examined) decides them again where it needs them. The decisions
are the same predicates on the same numbers and the sums are taken in the same order, so the two must give
the same bits: volume, centroid, normal, area, depth, second moment and the flags (filtered, smoothed flush
faces, re-evaluated, inconsistent, node count), for random poses from deep to grazing and degenerate ones
(flush faces, touching vertices and edges, identical bodies), in double, single and mixed precision
(tests/unit/records_paths.c). With the records' capacity cut to 2, every overlapping pass must fall back
to the reference path, and still give the same bits. Every pose a filter rejects before the sums (the
centre line's slab, the supporting triangles, the blocks' face masks) or that a supporting triangle's code
of poly_overlap_still_separated declares apart (the pair style's hint from the step before) must have no
volume when evaluated without any filter.

Run with Debian's python3:  /usr/bin/python3 -m pytest tests/test_records_path.py -q
"""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")
SHAPE_FILES = ["cube.stl", "schoenhardt.stl", "tetrahedron.obj", "box_1x2x3.off", "rock_10.obj", "rock_40.obj",
               "icosphere_80.off", "rock_1000.obj"]
QUANTITIES = ["volume", "centroid", "normal", "area", "depth", "second_moment"]


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(tmp_path_factory.mktemp("records") / "records_paths")
    sources = [os.path.join(ROOT, "tests", "unit", "records_paths.c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I" + os.path.join(ROOT, "src")] +
                   sources + ["-lm", "-o", binary], check=True)
    return binary


def run(driver, shape, poses, precision, capacity=None):
    command = [driver, os.path.join(SHAPES, shape), str(poses), precision] + ([str(capacity)] if capacity else [])
    out = subprocess.run(command, capture_output=True, text=True, check=True)
    values = {}
    for line in out.stdout.splitlines():
        words = line.split()
        if words[0] == "poses":
            values.update(poses=int(words[1]), overlapping=int(words[3]), smoothed=int(words[5]))
        elif words[0] == "convex":
            values.update(convex=int(words[1]), fallbacks=int(words[3]))
        else:
            values[words[0]] = float(words[1])
    return values, out.stderr


@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
@pytest.mark.parametrize("shape", SHAPE_FILES)
def test_records_path_gives_the_reference_bits(driver, shape, precision):
    values, log = run(driver, shape, 400, precision)
    assert values["overlapping"] >= 100, "too few overlapping poses to test anything"
    assert values["overflows"] <= 0.05 * values["poses"], "the records path was not taken"
    for quantity in QUANTITIES:
        assert values[quantity] == 0.0, f"{quantity} differs by {values[quantity]:g}\n{log}"
    assert values["flag_differences"] == 0, log
    # What the filters reject (the slab, the supporting triangles, and a supporting triangle named by a code
    # as the pair style's hint from the step before) has no overlap without them.
    assert values["filtered"] >= 20, "too few rejected poses to test the filters"
    assert values["hinted"] >= 5, "too few poses parted by a code to test poly_overlap_still_separated"
    assert values["wrongly_filtered"] == 0, log


def test_flush_poses_are_exercised(driver):
    values, _ = run(driver, "cube.stl", 400, "double")
    assert values["smoothed"] >= 10


@pytest.mark.parametrize("precision", ["double", "single"])
def test_fallback_when_records_do_not_fit(driver, precision):
    values, log = run(driver, "cube.stl", 200, precision, capacity=2)
    assert values["overflows"] >= values["overlapping"]
    for quantity in QUANTITIES:
        assert values[quantity] == 0.0, f"{quantity} differs by {values[quantity]:g}\n{log}"
    assert values["flag_differences"] == 0, log
