"""Overlap volume and centroid (src/poly_overlap_impl.h, all three precisions) against an exact
reference: tests/unit/exact_overlap_cgal.cpp, CGAL's exact corefinement of the two placed meshes
(Exact_predicates_exact_constructions_kernel, PMP::corefine_and_compute_intersection, exact volume
and first moment). It shares no code with the package and is exact in every configuration, coplanar
faces, shared edges and vertices and identical meshes included.

The reference sees the configuration the package sees: A's body-frame vertices (as loaded, in
double) and B's placed by the relative pose the package computes in double (R_A^T R_B and
R_A^T (x_B - x_A), poly_overlap_relative_pose), applied exactly. Its centroid goes to the world
frame as the package's does (R_A c + x_A). Single and mixed precision compute with both meshes'
vertices rounded to float: the degenerate families' reference takes those rounded vertices, the random
poses' the double ones (the floor below covers the difference there).

The program is built with g++ -O2 on first use (30-60 s on 2 cores) and kept in pytest's cache
(.pytest_cache/d/exact_overlap_cgal, named by a hash of source and command), so later runs do not
build it; without the cache plugin it goes to the session's tmp dir. Skipped when the CGAL headers
are missing (libcgal-dev, a test-only dependency: tools/debian_deps.sh installs it).

    /usr/bin/python3 -m pytest tests/test_exact_reference.py -q

Tolerances (L = cube root of the smaller volume, V_s = the smaller volume; errors taken relative to
max(V_ref, floor V_s), so that a sliver V_ref is judged by what a face one unit in the last place off
does, about eps V_s; centroid errors |c - c_ref| / L weighted by min(1, V_ref / (floor V_s))):
  degenerate families: V and centroid below 1e-12 (d; floor 1e-4) and 1e-5 (f, m; floor 1e-2; the
      reference then takes the vertices rounded to float, as the package does); num_inconsistent == 0
  random poses: below 1e-10 (d) and 1e-5 (f, m), floor 1e-3; num_inconsistent == 0
Failing cases are listed in the assertion message (case, V, V_ref, both errors, num_inconsistent).
"""
import hashlib
import math
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_overlap_geometry import (IDENTITY, L_SHAPE_OBJ, ROOT, SHAPES, quaternion_about,  # noqa: E402
                                   random_direction, random_quaternion, size_of)
# The overlap core and its shim, the shapes and the error summary: test_overlap_geometry's fixtures.
from test_overlap_geometry import errors, overlap_lib, shapes  # noqa: E402,F401

SOURCE = os.path.join(ROOT, "tests", "unit", "exact_overlap_cgal.cpp")
COMPILE = ["g++", "-std=c++17", "-O2", "-DNDEBUG"]
LINK = ["-lgmp", "-lmpfr"]
TOLERANCE = {"d": 1e-12, "f": 1e-5, "m": 1e-5}          # degenerate families
RANDOM_TOLERANCE = {"d": 1e-10, "f": 1e-5, "m": 1e-5}   # random poses (rounding of the pose)
# Errors relative to max(V_ref, floor V_s), for the slivers that rounding the offset (or, in single
# precision, rounding the vertices) leaves of a flush contact: a face one unit in the last place off
# moves V by about eps V_s (1.1e-16 in double, 6e-8 in single).
FLOOR = {"d": 1e-4, "f": 1e-2, "m": 1e-2}               # degenerate families
RANDOM_FLOOR = 1e-3                                      # random poses
PRECISIONS = ["d", "f", "m"]


# ---------------------------------------------------------------------------------------------
# the reference program

@pytest.fixture(scope="session")
def exact_reference(request, tmp_path_factory):
    if not shutil.which("g++"):
        pytest.skip("g++ not found: the exact reference (CGAL) cannot be built")
    with open(SOURCE, "rb") as f:
        source = f.read()
    compiler = subprocess.run(["g++", "--version"], capture_output=True, text=True).stdout
    key = hashlib.sha256(source + " ".join(COMPILE + LINK).encode() + compiler.encode()).hexdigest()[:16]
    cache = getattr(request.config, "cache", None)
    if cache is not None:
        directory = (getattr(cache, "mkdir", None) or cache.makedir)("exact_overlap_cgal")
    else:
        directory = tmp_path_factory.mktemp("exact_overlap_cgal")
    binary = os.path.join(str(directory), "exact_overlap_cgal-" + key)
    if not os.path.exists(binary):
        probe = subprocess.run(["g++", "-std=c++17", "-x", "c++", "-fsyntax-only", "-"],
                               input="#include <CGAL/version.h>\n#include <gmp.h>\n#include <mpfr.h>\n",
                               capture_output=True, text=True)
        if probe.returncode != 0:
            pytest.skip("CGAL, GMP or MPFR headers missing (libcgal-dev libgmp-dev libmpfr-dev; "
                        "tools/debian_deps.sh installs them): " + probe.stderr.strip().splitlines()[0])
        partial = binary + ".%d.tmp" % os.getpid()
        command = COMPILE + [SOURCE, "-o", partial] + LINK
        built = subprocess.run(command, capture_output=True, text=True)
        assert built.returncode == 0, " ".join(command) + "\n" + built.stderr[-4000:]
        os.replace(partial, binary)
    return ExactReference(binary)


class ExactReference:
    """Runs the CGAL program on batches of cases (each mesh sent once per batch, the batch split over
    up to WORKERS processes), remembering every case's answer."""

    WORKERS = max(1, min(4, os.cpu_count() or 1))

    def __init__(self, binary):
        self.binary = binary
        self.known = {}    # (mesh key A, mesh key B, relative pose) -> (V, centroid in A's frame)
        self.meshes = {}   # mesh key -> (vertices, triangles) as sent, and the shape (keeps its id taken)

    def mesh_key(self, shape, single):
        """The vertices the package computes with: as loaded (double), or rounded to float (single, mixed:
        poly_shape_view_make_f). Where rounding changes nothing, the same key as double."""
        vertices = shape.vertices
        if single:
            rounded = vertices.astype(np.float32).astype(np.float64)
            if not np.array_equal(rounded, vertices):
                vertices = rounded
        key = (id(shape), vertices is not shape.vertices)
        self.meshes.setdefault(key, (vertices, shape.triangles, shape))
        return key

    def __call__(self, cases, single=False):
        """[(V_ref, world centroid or None)] for cases [(a, pose_a, b, pose_b)]: A n B as the package sees it
        in double (single=False) or in single and mixed precision (single=True: vertices rounded to float)."""
        keys, frames = [], []
        for a, pose_a, b, pose_b in cases:
            rotation_a, rotation, translation = relative_pose(pose_a, pose_b)
            keys.append((self.mesh_key(a, single), self.mesh_key(b, single), tuple(rotation + translation)))
            frames.append((rotation_a, [float(x) for x in pose_a[0]]))
        missing = list(dict.fromkeys(key for key in keys if key not in self.known))
        if missing:
            chunks = [missing[k::self.WORKERS] for k in range(self.WORKERS)]
            with ThreadPoolExecutor(self.WORKERS) as pool:
                for chunk, answers in zip(chunks, pool.map(self.run, chunks)):
                    self.known.update(zip(chunk, answers))
        out = []
        for key, (rotation_a, position_a) in zip(keys, frames):
            volume, local = self.known[key]
            out.append((volume, None if local is None else
                        np.array([sum(rotation_a[3 * i + j] * local[j] for j in range(3)) + position_a[i]
                                  for i in range(3)])))
        return out

    def run(self, keys):
        """[(V, centroid or None)] in A's body frame, one process for all of keys."""
        if not keys:
            return []
        numbers, lines = {}, []
        identity = "1 0 0 0 1 0 0 0 1 0 0 0"
        for key_a, key_b, placement in keys:
            for key in (key_a, key_b):
                if key not in numbers:
                    numbers[key] = len(numbers)
                    vertices, triangles, _ = self.meshes[key]
                    lines.append("mesh %d %d %s %s" % (len(vertices), len(triangles),
                                                       " ".join(map(repr, vertices.ravel().tolist())),
                                                       " ".join(map(str, triangles.ravel().tolist()))))
            lines.append("case %d %s %d %s" % (numbers[key_a], identity, numbers[key_b],
                                               " ".join(map(repr, placement))))
        done = subprocess.run([self.binary], input="\n".join(lines) + "\n", capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        out = []
        for line in done.stdout.splitlines():
            words = line.split()
            volume = float(words[0])
            out.append((volume, None if volume == 0.0 else [float(x) for x in words[1:4]]))
        assert len(out) == len(keys), done.stdout
        return out


def quaternion_to_matrix(q):
    """As poly_quat_to_matrix (src/poly_rigid.h), operation for operation."""
    w, x, y, z = (float(c) for c in q)
    return [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
            2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
            2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)]


def relative_pose(pose_a, pose_b):
    """R_A, R_A^T R_B and R_A^T (x_B - x_A) in double, as poly_overlap_relative_pose."""
    ra, rb = quaternion_to_matrix(pose_a[1]), quaternion_to_matrix(pose_b[1])
    rotation = [ra[i] * rb[j] + ra[3 + i] * rb[3 + j] + ra[6 + i] * rb[6 + j] for i in range(3) for j in range(3)]
    d = [float(pose_b[0][k]) - float(pose_a[0][k]) for k in range(3)]
    translation = [ra[k] * d[0] + ra[3 + k] * d[1] + ra[6 + k] * d[2] for k in range(3)]
    return ra, rotation, translation


# ---------------------------------------------------------------------------------------------
# comparison

def compare(lib, cases, references, precision, tolerance, floor):
    """Rows (name, V, V_ref, volume error, centroid error, num_inconsistent) and the failing ones.
    Volume error |V - V_ref| / max(V_ref, floor V_s); centroid error |c - c_ref| / L, weighted by
    min(1, V_ref / (floor V_s)) (the centroid of a sliver is as uncertain as its volume)."""
    rows, failing = [], []
    for (name, a, pose_a, b, pose_b), (volume, centroid) in zip(cases, references):
        result = lib.overlap(a, pose_a, b, pose_b, precision)
        size, small = size_of(a, b), min(a.volume, b.volume)
        volume_error = abs(result.volume - volume) / max(volume, floor * small)
        centroid_error = 0.0
        if volume > 0:
            weight = min(1.0, volume / (floor * small))
            centroid_error = float(np.abs(np.array(result.centroid) - centroid).max()) / size * weight
        if not math.isfinite(volume_error) or not math.isfinite(centroid_error):
            volume_error = centroid_error = math.inf
        row = (name, result.volume, volume, volume_error, centroid_error, result.num_inconsistent)
        rows.append(row)
        if not (volume_error < tolerance and centroid_error < tolerance) or result.num_inconsistent != 0:
            failing.append(row)
    return rows, failing


def describe(failing, limit=40):
    lines = ["%d cases fail:" % len(failing),
             "  %-70s %24s %24s %9s %9s %s" % ("case", "V", "V_ref", "V err", "c err", "incons.")]
    for name, volume, reference, volume_error, centroid_error, inconsistent in failing[:limit]:
        lines.append("  %-70s %24.17g %24.17g %9.2e %9.2e %d" % (name, volume, reference, volume_error,
                                                                  centroid_error, inconsistent))
    if len(failing) > limit:
        lines.append("  ... and %d more" % (len(failing) - limit))
    return "\n".join(lines)


_CASES = {}


def cached(key, make):
    if key not in _CASES:
        _CASES[key] = make()
    return _CASES[key]


def named_shape(lib, shapes, name, scale=1.0):
    if scale == 1.0 and name in shapes:
        return shapes[name]
    extension = {"cube": "stl", "schoenhardt": "stl", "box_1x2x3": "off", "tetrahedron": "obj"}
    path = os.path.join(SHAPES, name + "." + extension.get(name, "off" if name.startswith("icosphere") else "obj"))
    return lib.shape(path, scale)


# ---------------------------------------------------------------------------------------------
# (a) random poses of pairs of shipped shapes: overlaps from 1e-6 of the smaller volume to deep

RANDOM_SHAPES = ["cube", "tetrahedron", "schoenhardt", "rock_20", "rock_40", "box_1x2x3", "icosphere_80"]
RANDOM_PAIRS = [(RANDOM_SHAPES[i], RANDOM_SHAPES[j]) for i in range(len(RANDOM_SHAPES))
                for j in range(i, len(RANDOM_SHAPES))]
TARGETS = (1e-6, 1e-4, 1e-2, 0.2)  # overlap / V_s; and one pose with the centres 0.05 L apart
FAR = 1e3                          # the first and the deepest pose also repeated FAR L from the origin


def random_cases(lib, shapes, names):
    """Random orientations and directions; the centre distance bisected on the package's double overlap
    (only to place the poses: the reference decides) to each target fraction of the smaller volume."""
    a, b = named_shape(lib, shapes, names[0]), named_shape(lib, shapes, names[1])
    rng = np.random.default_rng(sum(map(ord, names[0] + names[1])) + 31)
    small, size = min(a.volume, b.volume), size_of(a, b)
    cases = []
    for target in TARGETS:
        qa, qb, direction = random_quaternion(rng), random_quaternion(rng), random_direction(rng)
        near, far = 0.0, a.radius + b.radius
        for _ in range(60):
            middle = 0.5 * (near + far)
            if lib.overlap(a, ((0, 0, 0), qa), b, (middle * direction, qb)).volume > target * small:
                near = middle
            else:
                far = middle
        centre = rng.uniform(-0.5, 0.5, 3) * size
        cases.append((f"{names[0]}-{names[1]} V~{target:g} V_s", a, (centre, qa), b, (centre + near * direction, qb)))
    qa, qb, direction = random_quaternion(rng), random_quaternion(rng), random_direction(rng)
    cases.append((f"{names[0]}-{names[1]} deep", a, ((0, 0, 0), qa), b, (0.05 * size * direction, qb)))
    shift = FAR * size * random_direction(rng)
    for name, a_, (pa, qa), b_, (pb, qb) in (cases[0], cases[-1]):
        cases.append((name + f", {FAR:g} L away", a_, (pa + shift, qa), b_, (pb + shift, qb)))
    return cases


@pytest.mark.parametrize("precision", PRECISIONS)
@pytest.mark.parametrize("names", RANDOM_PAIRS, ids=["-".join(p) for p in RANDOM_PAIRS])
def test_random_poses_match_exact_reference(overlap_lib, shapes, exact_reference, errors, names, precision):
    """Double-precision vertices for the reference in all three precisions (the floor covers float
    vertices at these generic poses)."""
    cases = cached(("random",) + names, lambda: random_cases(overlap_lib, shapes, names))
    references = exact_reference([case[1:] for case in cases])
    assert all(volume > 0 for volume, _ in references), references
    rows, failing = compare(overlap_lib, cases, references, precision, RANDOM_TOLERANCE[precision], RANDOM_FLOOR)
    errors.add("exact ref: random V error", precision, max(r[3] for r in rows))
    errors.add("exact ref: random centroid error", precision, max(r[4] for r in rows))
    assert not failing, describe(failing)


# ---------------------------------------------------------------------------------------------
# (b) degenerate families: identity or exact quaternions (FLIP) and translations that are exact
# where the size allows (at 1e-3 and at the far offset some only nearly: the reference is exact for
# whatever the package sees, slivers included)

SIZES = (1e-3, 1.0, 100.0, 1e4)
CUBE_SIZES = (1e-3, 1.0, 100.0, 1e3, 1e4)
OFFSETS = ((0.0, 0.0, 0.0), (0.25, -0.75, 0.5), (1e3, -2e3, 1.5e3))  # in units of the size
FLIP = (0.0, 1.0, 0.0, 0.0)  # 180 degrees about x, exact
TURNED = tuple(quaternion_about((1, 2, 3), 0.7))


def extent(shape):
    return shape.vertices.min(0), shape.vertices.max(0)


def moved_directions():
    """The axes, the diagonal and eight fixed random directions."""
    rng = np.random.default_rng(1)
    return ([(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), tuple(np.ones(3) / math.sqrt(3.0))] +
            [tuple(random_direction(rng)) for _ in range(8)])


def family_configurations(lib, shapes, family, s):
    """[(name, A, q_A, B, q_B, t)]: B's centre at A's centre + t, both at A's offset."""
    cube = named_shape(lib, shapes, "cube", s)
    h = extent(cube)[1][0]  # half the edge, exact
    out = []
    if family == "cube in box, 4 faces flush":
        # The case: box_1x2x3 is [-1.5,1.5]x[-1,1]x[-0.5,0.5] in its body frame (at sizes 1e-3 and
        # 1e4 its loaded vertices are a few ulp off those: nearly flush there).
        box = named_shape(lib, shapes, "box_1x2x3", s)
        low, high = extent(box)
        out.append(("+x+y corner", box, IDENTITY, cube, IDENTITY, (high[0] - h, high[1] - h, 0.0)))
        out.append(("-x-y corner", box, IDENTITY, cube, IDENTITY, (low[0] + h, low[1] + h, 0.0)))
        out.append(("+x-y corner", box, IDENTITY, cube, IDENTITY, (high[0] - h, low[1] + h, 0.0)))
        out.append(("-x+y corner (body frame), both flipped", box, FLIP, cube, FLIP, (low[0] + h, -(high[1] - h), 0.0)))
    elif family == "cubes flush in two planes, half overlap":
        # The case: flush in both planes of one axis, shifted half an edge along the other two.
        for k, axis in enumerate("xyz"):
            for sign_1, sign_2 in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                t = [0.0, 0.0, 0.0]
                t[(k + 1) % 3], t[(k + 2) % 3] = sign_1 * h, sign_2 * h
                out.append((f"flush in {axis}, shifted ({sign_1:+d},{sign_2:+d})h", cube, IDENTITY, cube, IDENTITY,
                            tuple(t)))
            t = [0.0, 0.0, 0.0]
            t[k] = h
            out.append((f"shifted h along {axis} (flush in four planes)", cube, IDENTITY, cube, IDENTITY, tuple(t)))
    elif family == "identical shapes moved 1e-10..1e-9":
        directions = moved_directions()
        for name in ("tetrahedron", "rock_20"):
            shape = named_shape(lib, shapes, name, s)
            size = shape.volume ** (1.0 / 3.0)
            for k, d in enumerate(directions):
                for qname, q in (("", IDENTITY), (", flipped", FLIP), (", turned", TURNED)):
                    eps = (1e-10, 1e-9)[k % 2]
                    out.append((f"{name} {eps:g} L along d{k}{qname}", shape, q, shape, q,
                                tuple(eps * size * c for c in d)))
    elif family == "flush faces at lateral offsets":
        out.append(("stacked, half a face touching", cube, IDENTITY, cube, IDENTITY, (h, 0.0, 2 * h)))
        out.append(("stacked, quarter face touching", cube, IDENTITY, cube, IDENTITY, (h, h, 2 * h)))
        out.append(("stacked, half a face, 1/4 deep", cube, IDENTITY, cube, IDENTITY, (h, 0.0, 1.5 * h)))
        out.append(("stacked, half a face, 1/1024 deep", cube, IDENTITY, cube, IDENTITY, (h, 0.0, 2 * h - h / 512)))
        out.append(("stacked, 3/4 x 1/4 face, 1/4 deep", cube, IDENTITY, cube, IDENTITY, (0.5 * h, 1.5 * h, 1.5 * h)))
    elif family == "shared edges and vertices":
        out.append(("cubes sharing an edge", cube, IDENTITY, cube, IDENTITY, (2 * h, 2 * h, 0.0)))
        out.append(("cubes sharing half an edge", cube, IDENTITY, cube, IDENTITY, (2 * h, 2 * h, h)))
        out.append(("cubes sharing a vertex", cube, IDENTITY, cube, IDENTITY, (2 * h, 2 * h, 2 * h)))
        out.append(("cubes, quarter overlap, flush in z", cube, IDENTITY, cube, IDENTITY, (h, h, 0.0)))
        out.append(("cubes, eighth overlap (corner at centre)", cube, IDENTITY, cube, IDENTITY, (h, h, h)))
        box = named_shape(lib, shapes, "box_1x2x3", s)
        low, high = extent(box)
        out.append(("cube on the box's corner (vertex)", box, IDENTITY, cube, IDENTITY, tuple(high + h)))
        out.append(("cube on the box's edge", box, IDENTITY, cube, IDENTITY, (high[0] + h, high[1] + h, 0.0)))
    elif family == "identical poses":
        for name in ("cube", "tetrahedron", "rock_20", "box_1x2x3", "schoenhardt"):
            shape = named_shape(lib, shapes, name, s)
            for qname, q in (("", IDENTITY), (", flipped", FLIP), (", turned", TURNED)):
                out.append((f"{name}{qname}", shape, q, shape, q, (0.0, 0.0, 0.0)))
    elif family == "nearly identical poses":
        for name in ("cube", "tetrahedron", "rock_20"):
            shape = named_shape(lib, shapes, name, s)
            size = shape.volume ** (1.0 / 3.0)
            for angle in (1e-12, 1e-9):
                out.append((f"{name}, B turned {angle:g} rad", shape, IDENTITY, shape,
                            tuple(quaternion_about((0.36, 0.48, 0.8), angle)), (0.0, 0.0, 0.0)))
            out.append((f"{name}, B moved 1e-12 L", shape, IDENTITY, shape, IDENTITY, (1e-12 * size, 0.0, 0.0)))
    else:
        raise KeyError(family)
    return out


FAMILIES = ["cube in box, 4 faces flush", "cubes flush in two planes, half overlap",
            "identical shapes moved 1e-10..1e-9", "flush faces at lateral offsets", "shared edges and vertices",
            "identical poses", "nearly identical poses"]
# Families whose reference is costly (rocks, nearly coincident surfaces): one offset per configuration
# and size, in turn, instead of all three.
OFFSETS_IN_TURN = {"identical shapes moved 1e-10..1e-9", "identical poses", "nearly identical poses"}


def family_cases(lib, shapes, family):
    """Every configuration at every size and offset, in both argument orders."""
    cases = []
    sizes = CUBE_SIZES if family.startswith("cubes") else SIZES
    for i, s in enumerate(sizes):
        for j, (name, a, qa, b, qb, t) in enumerate(family_configurations(lib, shapes, family, s)):
            offsets = [OFFSETS[(i + j) % len(OFFSETS)]] if family in OFFSETS_IN_TURN else OFFSETS
            for offset in offsets:
                origin = np.array(offset) * s
                pose_a, pose_b = (origin, qa), (origin + np.array(t), qb)
                where = f"size {s:g}, offset {offset[0]:g} s"
                cases.append((f"{name}, {where}", a, pose_a, b, pose_b))
                cases.append((f"{name}, {where} (B,A)", b, pose_b, a, pose_a))
    return cases


@pytest.mark.parametrize("precision", PRECISIONS)
@pytest.mark.parametrize("family", FAMILIES)
def test_degenerate_family_matches_exact_reference(overlap_lib, shapes, exact_reference, errors, family, precision):
    cases = cached(("family", family), lambda: family_cases(overlap_lib, shapes, family))
    references = exact_reference([case[1:] for case in cases], single=precision != "d")
    rows, failing = compare(overlap_lib, cases, references, precision, TOLERANCE[precision], FLOOR[precision])
    errors.add(f"exact ref: {family[:22]} V", precision, max(r[3] for r in rows))
    errors.add(f"exact ref: {family[:22]} centroid", precision, max(r[4] for r in rows))
    assert not failing, describe(failing)


# ---------------------------------------------------------------------------------------------
# the reference itself

class PlainMesh:
    """A mesh as given (no loading: no centring, no principal axes), for the reference alone."""

    def __init__(self, name, vertices, triangles):
        self.name, self.vertices, self.triangles = name, np.array(vertices, dtype=float), np.array(triangles)


def test_reference_closed_forms(shapes, exact_reference):
    """The CGAL reference reproduces closed forms to the last bits of the printed doubles: cubes
    overlapping by half, a cube flush in a box, touching cubes (0), identical shapes (volume and
    centre of mass to the loader's rounding), and an L-shaped prism against itself turned 180 degrees
    about z, whose intersection is two boxes sharing an edge: not a manifold, so the union path."""
    cube, box = shapes["cube"], shapes["box_1x2x3"]
    lines = L_SHAPE_OBJ.splitlines()
    l_shape = PlainMesh("l_shape", [line.split()[1:] for line in lines if line.startswith("v ")],
                        [[int(k) - 1 for k in line.split()[1:]] for line in lines if line.startswith("f ")])
    half_turn_z = (0.0, 0.0, 0.0, 1.0)
    cases = [(cube, ((0, 0, 0), IDENTITY), cube, ((0.5, 0, 0), IDENTITY), 0.5, (0.25, 0, 0)),
             (box, ((0, 0, 0), IDENTITY), cube, ((1.0, 0.5, 0), IDENTITY), 1.0, (1.0, 0.5, 0)),
             (cube, ((0, 0, 0), IDENTITY), cube, ((1.0, 0, 0), IDENTITY), 0.0, None),
             (cube, ((0, 0, 0), IDENTITY), cube, ((1.0, 1.0, 1.0), IDENTITY), 0.0, None),
             (l_shape, ((0, 0, 0), IDENTITY), l_shape, ((2.0, 2.0, 0.0), half_turn_z), 2.0, (1.0, 1.0, 0.5))]
    for name in ("tetrahedron", "schoenhardt", "rock_40", "icosphere_80"):
        shape = shapes[name]
        cases.append((shape, ((0, 0, 0), IDENTITY), shape, ((0, 0, 0), IDENTITY), shape.volume, (0, 0, 0)))
    references = exact_reference([case[:4] for case in cases])
    for (a, _, b, _, volume, centroid), (v_ref, c_ref) in zip(cases, references):
        assert abs(v_ref - volume) <= 1e-14 * max(volume, 1.0), (a.name, b.name, v_ref, volume)
        if centroid is None:
            assert c_ref is None
        else:
            assert np.abs(c_ref - centroid).max() <= 1e-14, (a.name, c_ref, centroid)
