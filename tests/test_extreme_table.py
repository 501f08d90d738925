"""The slab's extreme vertices from a shape's table of directions (src/poly_extremes.h) give the bits of a scan of
every vertex (overlap_slab_extremes in src/poly_overlap_impl.h).

tests/unit/extreme_table.c compares, for shapes with a table (more than POLY_EXTREME_MIN_VERTICES vertices), the slab
of double, single and mixed precision with the table and without it over poses of random turns and centre lines, and
of centre lines on the cube map's cell edges and corners, its diagonals and the coordinate axes (where a direction's
cell is decided by rounding and symmetric shapes have tied vertices): axis, extents and extreme vertices must be the
same bits. A build whose lists are made for cells a quarter as wide must differ: the test can see a list that misses
the highest vertex (half as wide is still caught by no pose: the bound is within a factor of 2 to 4 of tight).

Run with Debian's python3:  /usr/bin/python3 -m pytest tests/test_extreme_table.py -q
"""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")
TABLED = ["rock_40.obj", "rock_70.obj", "rock_1000.obj", "icosphere_80.off", "icosphere_320.off"]


def build(directory, defines=()):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(directory / ("extreme_table" + "".join(d.split("=")[-1] for d in defines)))
    sources = [os.path.join(ROOT, "tests", "unit", "extreme_table.c")] + [
        os.path.join(ROOT, "src", name)
        for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c", "poly_mesh_shell.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", *defines,
                    "-I" + os.path.join(ROOT, "src")] + sources + ["-lm", "-o", binary], check=True)
    return binary


def differences(binary, poses, shapes):
    out = subprocess.run([binary, str(poses)] + shapes, capture_output=True, text=True, check=True,
                         cwd=SHAPES).stdout
    lines = out.splitlines()
    compared = sum(int(line.split("; ")[1].split()[0]) for line in lines if "slabs compared" in line)
    return int(lines[-1].split()[-1]), compared, out


def test_table_gives_the_scan_bits(tmp_path):
    differ, compared, out = differences(build(tmp_path), 20000, TABLED + ["schoenhardt.stl"])
    assert compared == 3 * 20000 * len(TABLED), out
    assert "schoenhardt.stl: no table" in out, out
    assert differ == 0, out


def test_narrower_lists_are_caught(tmp_path):
    differ, compared, out = differences(build(tmp_path, ["-DPOLY_EXTREME_REACH_SCALE=0.25"]), 20000,
                                        ["rock_40.obj", "rock_70.obj", "icosphere_80.off"])
    assert compared == 3 * 20000 * 3, out
    assert differ > 0, out
