"""Mesh walls on the clipping path (src/poly_clip.h): a prism of a wall's shell has clip faces
(src/poly_mesh_shell.c): a convex prism as one piece of its merged faces, one that is not (a twisted side quad folds
inward for one of its two prisms, as over any curved or creased stretch of mesh) as the three tetrahedra of its
split. So a particle with clip faces (convex, or in convex pieces: Schönhardt, rock_10; rock_40 by the pieces the
walls take instead of its cones, poly_shape_wall_pieces) meets it by clipping, which keeps the intersection's corners
for the contact's depth (ws.want_nodes, as fix wall/polyhedral asks); any other particle of at most 1024 vertices
(rock_70, icospheres, rock_1000) by the mesh path (src/poly_clip_mesh.h: its triangles clipped by the prism's
pieces, the prism's faces inside it from its cross-sections by their planes).
tests/unit/wall_clip_paths.c combines each particle's pieces into its contact with the wall
(poly_mesh_contact_combine) by that path and by the general path (ws.use_clip = 0) and prints the worst
differences: volume, centroid and second moment relative to the particle (as tests/test_convex_path.py's clipping
tolerances, 1e-13), normal and depth weighed by the summed area vector's length over the area (a particle deep in
the shell has its area vectors nearly cancel; measured: at most 4.7e-14 over the plane, 1.4e-14 over the height
field). Over a plane every prism is convex; over a random height field most are split (a prism whose three side
diagonals run in a cycle has no such split and keeps the general path, and so does one whose split has a
tetrahedron turned inside out, which the prism's certification can pass: test_splits_are_partitions). The
host's workspace holds the clipping path's corners (capacity_corners, 256), more than the general path's nodes (92
for Schönhardt against a prism, as on the GPU): with only those, 3.0 % of Schönhardt's pieces over the height field
were handed to the general path. Each shape the clipping path takes runs both ways (the prisms' clip views and
their mesh views: fix wall/polyhedral takes either, by the triangle's size), the others by the mesh path."""
import os
import re
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")
TOLERANCE = {"volume": 1e-13, "centroid": 1e-13, "normal": 1e-13, "depth": 1e-13, "second": 1e-13}


def build_unit(tmp_path_factory, name):
    """tests/unit/NAME.c with the C core, built into a temporary directory."""
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(tmp_path_factory.mktemp(name) / name)
    sources = [os.path.join(ROOT, "tests", "unit", name + ".c")] + [
        os.path.join(ROOT, "src", source)
        for source in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c", "poly_mesh_shell.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I" + os.path.join(ROOT, "src")] +
                   sources + ["-lm", "-o", binary], check=True)
    return binary


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    return build_unit(tmp_path_factory, "wall_clip_paths")


def run(driver, shape, count, flat, mesh=False):
    out = subprocess.run([driver, os.path.join(SHAPES, shape), str(count)] + (["flat"] if flat else []) +
                         (["mesh"] if mesh else []), capture_output=True, text=True, check=True).stdout
    values = {key: float(value) for key, value in re.findall(r"([a-z_]+) ([-0-9.e+]+)", out)}
    return values, out


@pytest.mark.parametrize("flat", [True, False], ids=["plane", "height-field"])
@pytest.mark.parametrize("shape, mesh", [(shape, False) for shape in ("schoenhardt.stl", "rock_10.obj", "cube.stl",
                                                                      "tetrahedron.obj", "rock_40.obj")] +
                         [(shape, True) for shape in ("schoenhardt.stl", "rock_10.obj", "cube.stl", "rock_40.obj",
                                                      "rock_70.obj", "icosphere_320.off")])
def test_clipped_wall_contacts_agree_with_the_general_path(driver, shape, mesh, flat):
    values, out = run(driver, shape, 300, flat, mesh)
    assert values["contacts"] >= 250, out
    for quantity, limit in TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{out}"
    # The path under test was taken: every prism has clip faces but those whose diagonals cycle (over the plane,
    # all are convex: one piece each; over the height field most are split), and all but flush pairs are clipped.
    offered, handed_back = values["clip_offered"], values["clip_handed_back"]
    assert values["clip_prisms"] >= 0.95 * values["of"] and offered >= 0.95 * values["pieces"], out
    if flat:
        assert values["clip_prisms"] == values["of"] and values["split_prisms"] == 0, out
    else:
        assert values["split_prisms"] >= 0.5 * values["of"], out
    assert handed_back <= 0.01 * offered, out


def test_splits_are_partitions(driver):
    """Steep height fields (40 of them, 200 triangles each: heights up to a cell, a shell three cells thick): every
    prism given three tetrahedra must be partitioned by them (their unsigned volumes sum to the prism's). Some
    prisms there pass the shell's certification by its star-shaped test while their split has a tetrahedron inside
    out (13 in these fields, found by review; clipped by them, a Schönhardt overlap came out 0.21 of the particle's
    volume too large): those keep the general path."""
    out = subprocess.run([driver, "splits", "40"], capture_output=True, text=True, check=True).stdout
    values = {key: float(value) for key, value in re.findall(r"([a-z_]+) ([-0-9.e+]+)", out)}
    assert values["split"] >= 0.8 * values["prisms"] and values["not_partitions"] == 0, out


def test_shapes_beyond_the_mesh_path_keep_the_general_path(driver):
    """icosphere_5120 (2562 vertices) is beyond the mesh path's buffers (1024 vertices) as well as the clipping
    path's: its pieces are never offered to either, and the two runs are the same general path, bit for bit."""
    values, out = run(driver, "icosphere_5120.off", 4, True, mesh=True)
    assert values["clip_offered"] == 0 and values["contacts"] >= 3, out
    assert all(values[quantity] == 0.0 for quantity in TOLERANCE), out


@pytest.fixture(scope="module")
def cases_driver(tmp_path_factory):
    binary = build_unit(tmp_path_factory, "mesh_path_cases")
    out = subprocess.run([binary, SHAPES], capture_output=True, text=True, check=True).stdout
    cases = {}
    for line in out.splitlines():
        fields = line.split()
        cases[fields[1]] = {key: float(value) for key, value in zip(fields[2::2], fields[3::2])}
    return cases, out


def test_mesh_path_hard_cases(cases_driver):
    """The mesh path (src/poly_clip_mesh.h) on its own hard cases (tests/unit/mesh_path_cases.c), against the
    general path: a prism wholly inside an icosphere (no cross-section meets a face's edge, so each face is decided
    by the winding about its corner) gives the prism's own volume and centroid, and rock_70 wholly inside a large
    prism (no face's plane crosses it) its own; an icosphere resting with a vertex
    on the triangle's plane is handed back (flush) and so is the general path's to the bit; rock_70 1e4 particle
    sizes from the origin and at scales 1e-6 and 1e3 agrees with the general path as in the random poses, and the
    two scales give the same relative volume."""
    cases, out = cases_driver
    inside = cases["inside"]
    assert inside["clipped"] == 1, out
    assert abs(inside["mesh"] - inside["exact"]) <= 1e-13 * inside["exact"], out
    assert inside["exact_centroid"] <= 1e-13 and inside["volume"] <= 1e-13, out
    engulfed = cases["engulfed"]
    assert engulfed["clipped"] == 1 and abs(engulfed["mesh"] - 1.0) <= 1e-13, out
    assert engulfed["exact_centroid"] <= 1e-13 and engulfed["volume"] <= 1e-13, out
    flush = cases["flush"]
    assert flush["clipped"] == 0 and flush["volume"] == flush["centroid"] == flush["depth"] == 0.0, out
    for name in ("far", "tiny", "huge"):
        case = cases[name]
        assert case["clipped"] == 1 and case["mesh"] > 0.01, out
        assert max(case["volume"], case["centroid"], case["depth"]) <= 1e-13, out
    assert abs(cases["tiny"]["mesh"] - cases["huge"]["mesh"]) <= 1e-12 * cases["huge"]["mesh"], out
