"""The convex and blocks paths of the overlap (src/poly_overlap_convex_impl.h, src/poly_overlap_blocks_impl.h)
against the general path.

Shapes found convex when built (poly_shape_find_faces) take the convex path (icosphere_80), or the blocks path
when they have at most 64 faces and vertices (cube, box, tetrahedron: the same clipping from a table of every
vertex against every face, with face masks, and no half-space filter): the vertices' sides of the other
body's faces in one table, each ridge clipped by those faces, the crossings turned into the general path's
records and summed by the same code. Different arithmetic (whole faces, no crossing tests against triangle
edges), so not the same bits: tests/unit/records_paths.c `convex` compares it with the general records path
(ws.use_convex = 0) on random poses from deep to grazing, resting ones (a face on a face, slightly tilted,
1e-4 to 1e-2 of the size deep) and degenerate ones (flush faces, touching vertices and edges, identical
bodies), in double, single and mixed precision. Stated tolerances, relative to
the particle size (volume, centroid, area and second moment weighted by the overlap's share of the particle
volume, so a tiny overlap's relative error does not swamp them; normal and depth where the normal is
well-conditioned, the area vector at least a tenth of the area): double 1e-13, single and mixed 1e-5 for the
normal and the depth, 1e-6 for the rest (measured: double <= 1.7e-15, single <= 1.2e-6 for the normal,
<= 6.4e-8 for the rest). The flags (filtered, smoothed, re-evaluated, inconsistent) must be the same; the
node counts may differ (the convex path does not clip the diagonals of flat faces, whose crossings lie on
chords between other nodes). Flush faces and undecidable contacts must have been left to the general path,
and most contacts not.

Run with Debian's python3:  /usr/bin/python3 -m pytest tests/test_convex_path.py -q
"""
import os
import random
import shutil
import subprocess

import pytest

from test_records_path import ROOT, driver, run  # noqa: F401  (the fixture builds tests/unit/records_paths.c)

CONVEX_SHAPES = ["cube.stl", "box_1x2x3.off", "tetrahedron.obj", "icosphere_80.off"]
TOLERANCE = {"double": {"volume": 1e-13, "centroid": 1e-13, "normal": 1e-13, "area": 1e-13, "depth": 1e-13,
                        "second_moment": 1e-13},
             "single": {"volume": 1e-6, "centroid": 1e-6, "normal": 1e-5, "area": 1e-6, "depth": 1e-5,
                        "second_moment": 1e-6}}
TOLERANCE["mixed"] = TOLERANCE["single"]


@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
@pytest.mark.parametrize("shape", CONVEX_SHAPES)
def test_convex_path_agrees_with_the_general_path(driver, shape, precision):  # noqa: F811
    values, log = run(driver, shape, 600, precision, capacity="convex")
    assert values["convex"] == 1, f"{shape} was not found convex"
    assert values["overlapping"] >= 150
    for quantity, limit in TOLERANCE[precision].items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0, log
    # Flush faces go to the general path (which smooths them); most contacts do not.
    assert values["fallbacks"] >= values["smoothed"]
    assert values["fallbacks"] <= 0.4 * values["poses"]


@pytest.mark.parametrize("shape", ["schoenhardt.stl", "rock_40.obj"])
def test_non_convex_shapes_keep_the_general_path(driver, shape):  # noqa: F811
    values, _ = run(driver, shape, 20, "double", capacity="convex")
    assert values["convex"] == 0
    assert values["fallbacks"] == 0


CLIP_TOLERANCE = {"volume": 1e-13, "centroid": 1e-13, "area": 1e-13, "depth": 1e-13, "second_moment": 1e-13,
                  "normal_scaled": 1e-13}


@pytest.mark.parametrize("shape", ["cube.stl", "box_1x2x3.off", "tetrahedron.obj"])
def test_clipping_path_agrees_with_the_general_path(driver, shape):  # noqa: F811
    """The clipping path (src/poly_clip.h: each body's face polygons clipped by the other's planes, the divergence
    theorem over them), which double-precision pairs of convex shapes of at most 16 faces take, against the general
    records path on the same poses as above. Same tolerances, relative to the size and weighted as above, except
    the normal: computed from polygons of extent L whose corners are known to rounding of the size, it is good to
    about 1e-16 size / L, so its difference is weighed by L / size (sqrt of the area); measured: <= 3.2e-15, and
    unweighted 5e-12 on overlaps of 1e-8 of the size squared. Flush faces (and a wider band around them: any vertex
    within 1e-9 of the size of a plane of the other body) go to the general path."""
    values, log = run(driver, shape, 2000, "double", capacity="clip")
    assert values["clip_faces"] >= 4 and values["overlapping"] >= 800
    for quantity, limit in CLIP_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    assert values["smoothed"] <= values["fallbacks"] <= 0.25 * values["poses"]


def build_driver(tmp_path_factory, name, defines):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(tmp_path_factory.mktemp(name) / "records_paths")
    sources = [os.path.join(ROOT, "tests", "unit", "records_paths.c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror"] + defines +
                   ["-I" + os.path.join(ROOT, "src")] + sources + ["-lm", "-o", binary], check=True)
    return binary


@pytest.fixture(scope="module")
def wide_driver(tmp_path_factory):
    """records_paths with the GPU's 128-bit plane masks (POLY_CLIP_WIDE_MASKS), so that rock_40's pieces (79 planes),
    which only the GPU clips, are checked here too."""
    return build_driver(tmp_path_factory, "wide", ["-DPOLY_CLIP_WIDE_MASKS"])


@pytest.mark.parametrize("shape,wide", [("schoenhardt.stl", False), ("rock_10.obj", False), ("rock_20.obj", False),
                                        ("schoenhardt.stl", True), ("rock_40.obj", True)])
def test_pieces_path_agrees_with_the_general_path(driver, wide_driver, shape, wide):  # noqa: F811
    """Shapes that are not convex take the clipping path through convex pieces (a partition of space by the
    shape's own face planes, src/poly_convex_partition_impl.h; the triangles cut where the pieces meet on them):
    each body's faces clipped by each of the other's pieces that no plane parts from one of its own. Against the
    general records path on the same poses and tolerances as the convex shapes above, with the host's 64-bit plane
    masks and the GPU's 128-bit ones (rock_40, whose partition has a piece of more than 16 planes, through its
    cones from the centre of mass and their 79 planes). The pieces' inner planes widen the flush band (identical bodies at the same orientation put vertices on
    them), so more pairs go to the general path, still few."""
    values, log = run(wide_driver if wide else driver, shape, 2000, "double", capacity="clip")
    assert values["clip_faces"] >= 8 and values["clip_pieces"] >= 2 and values["overlapping"] >= 800
    for quantity, limit in CLIP_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    assert values["smoothed"] <= values["fallbacks"] <= 0.1 * values["poses"]
    # Pairs a supporting plane parts say which (the pair style's hint), and the code names a plane that parts them.
    assert values["codes_given"] >= 10 and values["codes_holding"] == values["codes_given"], log


CLIP_MIXED_TOLERANCE = {"volume": 1e-6, "centroid": 1e-6, "area": 1e-6, "depth": 1e-5, "second_moment": 1e-6,
                        "normal_scaled": 1e-5}


@pytest.mark.parametrize("shape", ["cube.stl", "schoenhardt.stl", "rock_10.obj"])
def test_mixed_precision_clips_in_double(driver, shape):  # noqa: F811
    """Mixed precision (single-precision geometry, double contact law) takes the clipping path in double for the
    shapes that have it, single precision does not: against the general path in mixed precision, the differences
    are the single-precision geometry's own (single's limits, the normal weighted as above; measured <= 3.1e-7),
    and in single precision nothing takes it."""
    values, log = run(driver, shape, 2000, "mixed", capacity="clip")
    for quantity, limit in CLIP_MIXED_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["volume"] > 0, "mixed precision did not take the clipping path"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    single, _ = run(driver, shape, 200, "single", capacity="clip")
    assert single["volume"] == 0 and single["normal_scaled"] == 0


@pytest.fixture(scope="module")
def few_nodes_driver(tmp_path_factory):
    """records_paths with room for 12 polygon corners, so most overlaps find their depth in the clipping path's
    second pass (the extent along the normal, clipped again) rather than from the kept corners."""
    return build_driver(tmp_path_factory, "few_nodes", ["-DPOLY_CLIP_MAX_NODES=12"])


@pytest.mark.parametrize("shape", ["cube.stl", "schoenhardt.stl", "rock_10.obj"])
def test_clipping_corners_overflow(few_nodes_driver, driver, shape):  # noqa: F811
    """The same comparison with the corners' buffer cut to 12. Pairs of pieces (Schoenhardt, rock_10) then find
    their depth in a second clipping pass, which must agree with the general path as closely and leave the
    general path no more pairs; pairs of convex shapes (the cube), which keep all their corners, go to the
    general path instead, which must then give the answer."""
    values, log = run(few_nodes_driver, shape, 1000, "double", capacity="clip")
    full, _ = run(driver, shape, 1000, "double", capacity="clip")
    for quantity, limit in CLIP_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    if values["clip_pieces"] > 1:
        assert values["fallbacks"] == full["fallbacks"]
    else:
        assert values["fallbacks"] > 2 * full["fallbacks"]


def test_shapes_beyond_the_clipping_path_keep_the_others(driver):  # noqa: F811
    """icosphere_80 (80 faces, 42 vertices) is convex but has more faces than one piece and more vertices than the
    clipping path takes; rock_70 is not convex, its partition has a piece of more than 16 planes and its cones
    need more than 128 planes. rock_40's partition has such a piece too, so it has the cones' 19 pieces of 79
    planes, more than the host's 64-bit masks hold: the host keeps the general path for it (the same bits)."""
    for shape in ("icosphere_80.off", "rock_70.obj"):
        values, _ = run(driver, shape, 10, "double", capacity="clip")
        assert values["clip_faces"] == 0 and values["clip_pieces"] == 0
    values, _ = run(driver, "rock_40.obj", 200, "double", capacity="clip")
    assert values["clip_pieces"] == 19 and values["clip_planes"] == 79
    assert values["volume"] == 0 and values["centroid"] == 0 and values["fallbacks"] == 0


def u_prism_obj():
    """A U-shaped prism: the U (0,0) (3,0) (3,1) (3,3) (2,3) (2,1) (1,1) (1,3) (0,3) (0,1) extruded over z in [0, 1].
    Its centre of mass, (1.5, 1.357), lies in the gap between the arms, so it is not star-shaped from there."""
    outline = [(0, 0), (3, 0), (3, 1), (3, 3), (2, 3), (2, 1), (1, 1), (1, 3), (0, 3), (0, 1)]
    lines = [f"v {x} {y} {z}" for z in (0, 1) for x, y in outline]
    n = len(outline)
    cap = [(0, 1, 2), (0, 2, 5), (0, 5, 6), (0, 6, 9), (9, 6, 7), (9, 7, 8), (5, 2, 3), (5, 3, 4)]
    faces = [(c, b, a) for a, b, c in cap] + [(a + n, b + n, c + n) for a, b, c in cap]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def test_partition_takes_shapes_not_star_shaped(driver, tmp_path):  # noqa: F811
    """The cones from the centre of mass cannot split a U-shaped prism (its centre is outside it); the partition by
    its face planes can, into the fewest convex pieces, 3 (the bar and the two arms), and they give the general
    path's overlaps (same tolerances as above). Their planes are the shape's own: the U's 9 distinct face planes
    (the two ends of the arms share one), Schoenhardt's 8 (the cones had 20)."""
    path = tmp_path / "u_prism.obj"
    path.write_text(u_prism_obj())
    values, log = run(driver, str(path), 2000, "double", capacity="clip")
    assert values["clip_pieces"] == 3 and values["clip_planes"] == 9 and values["overlapping"] >= 800, log
    for quantity, limit in CLIP_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    assert values["smoothed"] <= values["fallbacks"] <= 0.1 * values["poses"], log
    values, _ = run(driver, "schoenhardt.stl", 10, "double", capacity="clip")
    assert values["clip_pieces"] >= 2 and values["clip_planes"] == 8


def dented_cube_obj(seed):
    """A unit cube with one or two corners pulled toward its centre (a dent: not convex; the other faces' two
    triangles stay coplanar), each face split along a random diagonal."""
    rng = random.Random(100 + seed)
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    index = {c: i for i, c in enumerate(corners)}
    quads = [((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),
             ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),
             ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1))]
    points = [list(c) for c in corners]
    for corner in rng.sample(range(8), 1 + seed % 2):
        pull = rng.uniform(0.3, 0.7)
        points[corner] = [0.5 + (c - 0.5) * pull for c in points[corner]]
    triangles = []
    for quad in quads:
        a, b, c, d = (index[q] for q in quad)
        triangles += [(a, b, c), (a, c, d)] if rng.random() < 0.5 else [(a, b, d), (b, c, d)]
    return ("".join("v %r %r %r\n" % tuple(p) for p in points) +
            "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in triangles))


@pytest.mark.parametrize("seed", range(8))
def test_partition_of_dented_cubes(driver, tmp_path, seed):  # noqa: F811
    """Cubes with one or two corners dented in: the partition splits each into 2-4 pieces on its own face planes
    (some with new corners where a cut crosses a triangle), and they give the general path's overlaps on 1000
    poses within the same tolerances as above (measured <= 3.7e-15); every separating code given parts its pose."""
    path = tmp_path / ("dented_cube_%d.obj" % seed)
    path.write_text(dented_cube_obj(seed))
    values, log = run(driver, str(path), 1000, "double", capacity="clip")
    assert 2 <= values["clip_pieces"] <= 8 and values["clip_planes"] <= 12 and values["overlapping"] >= 300, log
    for quantity, limit in CLIP_TOLERANCE.items():
        assert values[quantity] <= limit, f"{quantity} differs by {values[quantity]:g} (limit {limit:g})\n{log}"
    assert values["flag_differences"] == 0 and values["wrongly_filtered"] == 0, log
    assert values["smoothed"] <= values["fallbacks"] <= 0.1 * values["poses"], log
    assert values["codes_given"] >= 10 and values["codes_holding"] == values["codes_given"], log


def test_clip_polygon_matches_the_reference_step_and_its_capacity(tmp_path):
    """poly_clip_polygon (src/poly_clip_polygon.h) carries each corner's side to the next edge instead of keeping
    an array of them (which on the GPU was local memory the warp kernel waited on, and on the host could be
    overrun by the partition's polygons of more than 32 corners), and takes its output's capacity. Against the
    array form on convex polygons of 3 to 48 corners clipped by up to 8 planes each: the same corners bit for bit,
    the same with the capacity set to the corner count, -1 with one less; the float instance likewise against the
    array form in float (tests/unit/clip_polygon_check.c)."""
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(tmp_path / "clip_polygon_check")
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I" + os.path.join(ROOT, "src"),
                    os.path.join(ROOT, "tests", "unit", "clip_polygon_check.c"), "-lm", "-o", binary], check=True)
    result = subprocess.run([binary], capture_output=True, text=True)
    counts = dict(zip(result.stdout.split()[0::2], map(int, result.stdout.split()[1::2])))
    assert counts["steps"] > 50000 and counts["grew"] > 1000, result.stdout  # the cases it is meant to cover
    assert counts["mismatches"] == 0 and counts["capacity_failures"] == 0, result.stdout
    assert counts["float_mismatches"] == 0, result.stdout  # the float instance (the GPU's mixed clipping)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("defines, shapes", [
    ([], ["cube.stl", "tetrahedron.obj", "box_1x2x3.off", "schoenhardt.stl", "rock_10.obj", "rock_20.obj"]),
    (["-DPOLY_CLIP_WIDE_MASKS"], ["cube.stl", "schoenhardt.stl", "rock_20.obj"])], ids=["host masks", "wide masks"])
def test_clipping_sides_two_planes_at_a_time_keep_the_bits(tmp_path, defines, shapes):
    """On x86-64 the clipping path sides the vertices two planes at a time (SSE2, src/poly_clip.h); the scalar loop
    stays for the GPU and other machines. Only the masks and the flush decision leave the sides, so both must give
    the same results to the bit: tests/unit/clip_sides_bits.c, built as is and with -U__SSE2__ (the scalar loop),
    must hash every bit of every result field the same over random and resting poses of shapes that take the convex
    path and the pieces (with the GPU's 128-bit masks too), and the poses must touch often enough to mean something.
    (A mask bit put in the wrong place fails it; a different order of the sums, which moves no sign here, does
    not.)"""
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    sources = [os.path.join(ROOT, "tests", "unit", "clip_sides_bits.c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    outputs = []
    for variant in ([], ["-U__SSE2__"]):
        binary = str(tmp_path / ("scalar" if variant else "sse2"))
        subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror"] + defines + variant +
                       ["-I" + os.path.join(ROOT, "src")] + sources + ["-lm", "-o", binary], check=True)
        run_ = subprocess.run([binary, os.path.join(ROOT, "examples", "shapes"), "400"] + shapes,
                              capture_output=True, text=True, check=True)
        outputs.append(run_.stdout)
    print(outputs[0])
    assert outputs[0] == outputs[1], outputs
    for line in outputs[0].splitlines():
        assert int(line.split()[2]) >= 80, line
