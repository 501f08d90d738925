"""Flush coplanar faces (src/poly_overlap_impl.h, overlap_local): a face of one body in the plane of a
face of the other, as blocks on a lattice, stacked bricks and a block in a corner have them.

Volume and centroid are continuous there; the area vector of A's surface inside B (the normal, eq. 4.19)
is not: a flush face's strip counts wholly or not at all, as the symbolic perturbation decides. The core
takes the mean of the two one-sided limits (the pair evaluated with B shifted by +h and -h along the
perturbation direction, h = 2^-36 of the size in double, 2^-16 in single). These tests hold it to:
  - axis-aligned boxes against the closed form in which a flush face of A counts half: V and centroid
    1e-12 (relative to V and to the size) in double; in single and mixed V 1e-6 of the particle's volume
    and centroid 1e-4 of its size (test_overlap_geometry's single-precision tolerances); normal 1e-9 in double
    (the smoothing's O(h) bias is 2e-11 here), 1e-4 in single and mixed (its bias is 2e-5 there);
  - symmetry: the same configurations turned as a whole by 100 random rotations and by the 24 rotations
    of the cube, and with B alone turned by the cube's 24 rotations (the same solid): V / L^3,
    centroid / L and normal equal to 1e-12 in double; in single and mixed V / L^3 to 1e-6, centroid / L
    and normal to 1e-4;
  - the core built with the perturbation direction negated (-DPOLY_PERTURBATION_SIGN=-1): the same
    results to 1e-12;
  - as a user runs it: two cubes meeting head on with flush side faces keep the normal along x to 1e-9 at
    every step, leave without spin (rotational energy below 1e-12 J) and with their kinetic energy to
    1e-4; a column of five cubes stands on a plane and on a 2-triangle mesh floor for 1 s with lateral
    drift below 1e-9 m.
"""
import itertools
import math
import os
import subprocess

import numpy as np
import pytest

import decks
import meshes
from overlap_reference import quaternion_matrix as matrix
from test_overlap_geometry import (IDENTITY, L_SHAPE_OBJ, SHAPES, SHIM_SOURCE, SOURCES, Library, file_frame_pose,
                                   quaternion_product)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOX_HALF = {"cube": np.array([0.5, 0.5, 0.5]), "box_1x2x3": np.array([1.5, 1.0, 0.5])}
FILES = {"cube": "cube.stl", "box_1x2x3": "box_1x2x3.off"}
TOLERANCE = {"d": (1e-12, 1e-12, 1e-9), "f": (1e-6, 1e-4, 1e-4), "m": (1e-6, 1e-4, 1e-4)}  # V, centroid, normal
SYMMETRY = {"d": (1e-12, 1e-12, 1e-12), "f": (1e-6, 1e-4, 1e-4), "m": (1e-6, 1e-4, 1e-4)}  # V / L^3, c / L, n


def build(directory, sign):
    shim = directory / "shim.c"
    shim.write_text(SHIM_SOURCE)
    library = directory / f"libflush{'_negated' if sign < 0 else ''}.so"
    command = (["gcc", "-std=c11", "-O2", "-fPIC", "-shared", f"-DPOLY_PERTURBATION_SIGN={sign}",
                "-I" + os.path.join(ROOT, "src")] + SOURCES + [str(shim), "-lm", "-o", str(library)])
    built = subprocess.run(command, capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    return Library(str(library))


@pytest.fixture(scope="module")
def libraries(tmp_path_factory):
    directory = tmp_path_factory.mktemp("flush")
    return build(directory, 1), build(directory, -1)


@pytest.fixture(scope="module")
def l_shape_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("l_shape") / "l_shape.obj"
    path.write_text(L_SHAPE_OBJ)
    return str(path)


def box_closed_form(half_a, centre_a, half_b, centre_b):
    """V, centroid and normal of A n B for axis-aligned boxes, the area vector of A's surface inside B
    with a face of A flush with a face of B (same plane, either way round) counted half."""
    lo_a, hi_a, lo_b, hi_b = centre_a - half_a, centre_a + half_a, centre_b - half_b, centre_b + half_b
    low, high = np.maximum(lo_a, lo_b), np.minimum(hi_a, hi_b)
    extent = np.clip(high - low, 0.0, None)
    area_vector = np.zeros(3)
    for k in range(3):
        others = [j for j in range(3) if j != k]
        face = extent[others[0]] * extent[others[1]]
        for side, plane in ((1.0, hi_a[k]), (-1.0, lo_a[k])):
            # flush to within the rounding of the positions counts as flush, as it does in the core
            flush = min(abs(plane - lo_b[k]), abs(plane - hi_b[k])) <= 1e-12 * (half_a[k] + half_b[k])
            weight = 0.5 if flush else (1.0 if lo_b[k] < plane < hi_b[k] else 0.0)
            area_vector[k] += side * weight * face
    return float(np.prod(extent)), 0.5 * (low + high), area_vector / np.linalg.norm(area_vector)


def box_cases():
    """name -> (shape A, centre A, shape B, centre B) in units of the size; every case has flush faces."""
    d = 1e-3
    return {
        "head on": ("cube", (0, 0, 0), "cube", (1 - d, 0, 0)),
        "half a face sideways": ("cube", (0, 0, 0), "cube", (1 - d, 0.5, 0)),
        "quarter, z faces flush": ("cube", (0, 0, 0), "cube", (0.5, 0.5, 0)),
        "stacked": ("cube", (0, 0, 0), "cube", (0, 0, 1 - d)),
        "stacked, offset": ("cube", (0, 0, 0), "cube", (0.25, -0.125, 1 - d)),
        "cube in a corner of the box": ("box_1x2x3", (0, 0, 0), "cube", (-1.0, -0.5, 0)),
        "box around a cube in its corner": ("cube", (-1.0, -0.5, 0), "box_1x2x3", (0, 0, 0)),
        "cube along the box's edge": ("box_1x2x3", (0, 0, 0), "cube", (1.0 + d, 0.5, 0)),
        "box against a flush cube": ("box_1x2x3", (0, 0, 0), "cube", (0.25, 1.5 - d, 0)),
    }


CASES = list(box_cases())
SIZES = [1e-3, 1.0, 1e4]


@pytest.mark.parametrize("precision", ["d", "f", "m"])
@pytest.mark.parametrize("case", CASES)
def test_flush_boxes_match_the_mean_of_the_one_sided_limits(libraries, case, precision):
    library = libraries[0]
    name_a, centre_a, name_b, centre_b = box_cases()[case]
    volume_tolerance, centroid_tolerance, normal_tolerance = TOLERANCE[precision]
    for size, origin in itertools.product(SIZES, [(0, 0, 0), (3.25, -7.5, 1.125)]):
        a = library.shape(os.path.join(SHAPES, FILES[name_a]), size)
        b = library.shape(os.path.join(SHAPES, FILES[name_b]), size)
        pa = (np.array(centre_a, float) + origin) * size
        pb = (np.array(centre_b, float) + origin) * size
        volume, centroid, normal = box_closed_form(BOX_HALF[name_a] * size, pa, BOX_HALF[name_b] * size, pb)
        result = library.overlap(a, (pa, IDENTITY), b, (pb, IDENTITY), precision)
        where = f"{case}, size {size}, origin {origin}, {precision}"
        assert result.num_inconsistent == 0, where
        # single precision rounds the positions to 6e-8 of the size, so its V is held to the particle's volume
        scale = volume if precision == "d" else size ** 3
        assert abs(result.volume - volume) <= volume_tolerance * scale, (where, result.volume, volume)
        assert np.abs(np.array(result.centroid) - centroid).max() <= centroid_tolerance * size, (
            where, result.centroid, centroid)
        assert np.abs(np.array(result.normal) - normal).max() <= normal_tolerance, (where, result.normal, normal)


def cube_rotations():
    """The 24 rotations of the cube as unit quaternions (w, x, y, z)."""
    h = math.sqrt(0.5)
    rotations = [(1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)]
    rotations += [(h, s * h, 0, 0) for s in (1, -1)] + [(h, 0, s * h, 0) for s in (1, -1)]
    rotations += [(h, 0, 0, s * h) for s in (1, -1)]
    rotations += [(0, h, s * h, 0) for s in (1, -1)] + [(0, h, 0, s * h) for s in (1, -1)]
    rotations += [(0, 0, h, s * h) for s in (1, -1)]
    rotations += [(0.5, sx * 0.5, sy * 0.5, sz * 0.5) for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)]
    assert len(rotations) == 24
    return [np.array(q, float) for q in rotations]


def random_rotations(count, seed):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        q = rng.normal(size=4)
        out.append(q / np.linalg.norm(q))
    return out


def symmetry_cases(library, l_shape_file, size):
    """(name, A, pose A, B, pose B) with flush faces: the box cases, and a cube pressed 1e-3 into both
    faces of the notch of an L-shaped prism, its z faces flush (a block in a corner of two others)."""
    out = []
    for case, (name_a, centre_a, name_b, centre_b) in box_cases().items():
        a = library.shape(os.path.join(SHAPES, FILES[name_a]), size)
        b = library.shape(os.path.join(SHAPES, FILES[name_b]), size)
        out.append((case, a, (np.array(centre_a, float) * size, IDENTITY),
                    b, (np.array(centre_b, float) * size, IDENTITY)))
    l_shape = library.shape(l_shape_file, size)
    cube = library.shape(os.path.join(SHAPES, "cube.stl"), size)
    out.append(("cube in the notch", l_shape, file_frame_pose(l_shape),
                cube, (np.array([1.5 - 1e-3, 1.5 - 1e-3, 0.5]) * size, IDENTITY)))
    return out


def path_of(shape, l_shape_file):
    return l_shape_file if shape.name == "l_shape" else os.path.join(SHAPES, FILES[shape.name])


def differences(result, reference, rotation, size):
    return (abs(result.volume - reference.volume) / size ** 3,
            np.abs(np.array(result.centroid) - rotation @ np.array(reference.centroid)).max() / size,
            np.abs(np.array(result.normal) - rotation @ np.array(reference.normal)).max())


def turned_whole(pose, q):
    return matrix(q) @ np.asarray(pose[0], float), quaternion_product(q, pose[1])


@pytest.mark.parametrize("precision", ["d", "f", "m"])
def test_flush_results_are_equivariant(libraries, l_shape_file, precision):
    library, negated = libraries
    tolerance = SYMMETRY[precision]
    worst = np.zeros(3)
    for size in SIZES:
        for case, a, pose_a, b, pose_b in symmetry_cases(library, l_shape_file, size):
            reference = library.overlap(a, pose_a, b, pose_b, precision)
            assert reference.volume > 0.0, case
            checks = []
            for q in random_rotations(100, 7) + cube_rotations():
                turned = library.overlap(a, turned_whole(pose_a, q), b, turned_whole(pose_b, q), precision)
                checks.append((f"whole turned by {q}", turned, matrix(q)))
            if b.name == "cube":
                for q in cube_rotations():
                    checks.append((f"B turned by {q}", library.overlap(a, pose_a, b, (pose_b[0], q), precision),
                                   np.eye(3)))
            a_negated = negated.shape(path_of(a, l_shape_file), size)
            b_negated = negated.shape(path_of(b, l_shape_file), size)
            checks.append(("perturbation negated", negated.overlap(a_negated, pose_a, b_negated, pose_b, precision),
                           np.eye(3)))
            for what, result, rotation in checks:
                error = differences(result, reference, rotation, size)
                worst = np.maximum(worst, error)
                assert all(e <= t for e, t in zip(error, tolerance)), (case, size, precision, what, error)
    print(f"\nflush faces, {precision}: worst |dV|/L^3 {worst[0]:.1e}, |dc|/L {worst[1]:.1e}, |dn| {worst[2]:.1e}")


def test_cube_in_the_notch_is_symmetric(libraries, l_shape_file):
    """The notch of the L-shaped prism is symmetric about the plane x = y: the normal has equal x and y
    components and no z component (the z faces are flush); V = (2 d - d^2) L^3 for a cube pressed d into
    both faces of the notch."""
    library = libraries[0]
    d = 1e-3
    for size in SIZES:
        (_, a, pose_a, b, pose_b), = [c for c in symmetry_cases(library, l_shape_file, size)
                                      if c[0] == "cube in the notch"]
        for precision in "dfm":
            volume_tolerance, _, normal_tolerance = TOLERANCE[precision]
            result = library.overlap(a, pose_a, b, pose_b, precision)
            scale = result.volume if precision == "d" else size ** 3
            assert abs(result.volume - (2 * d - d * d) * size ** 3) <= volume_tolerance * scale
            n = result.normal
            assert abs(n[0] - n[1]) <= normal_tolerance and abs(n[2]) <= normal_tolerance, (size, precision, n)


def test_flush_cube_on_a_two_triangle_floor(libraries):
    """A cube flat on a floor of two triangles (the mesh wall's shell of prisms, 0.5 L thick): centred, its
    vertical edges in the plane of the diagonal the two prisms share; with a side face flush with the
    floor's border; and in the floor's corner. The shell there is the box [-L, L]^2 x [-0.5 L, 0], so V,
    centroid and normal are the closed form's: exact, the flush strip counted half."""
    library = libraries[0]
    size, d, thickness = 0.01, 1e-5, 0.005
    cube = library.shape(os.path.join(SHAPES, "cube.stl"), size)
    floor = meshes.grid(1, size)
    for centre in ((0.0, 0.0), (0.5 * size, 0.0), (0.5 * size, 0.5 * size)):
        position = np.array([centre[0], centre[1], 0.5 * size - d])
        volume, centroid, normal = box_closed_form(BOX_HALF["cube"] * size, position,
                                                   np.array([size, size, 0.5 * thickness]),
                                                   np.array([0.0, 0.0, -0.5 * thickness]))
        result = library.mesh_wall(cube, (position, IDENTITY), floor, thickness)
        assert result.num_inconsistent == 0
        assert abs(result.volume - volume) <= 1e-12 * volume, (centre, result.volume, volume)
        assert np.abs(np.array(result.centroid) - centroid).max() <= 1e-12 * size, (centre, result.centroid)
        assert np.abs(np.array(result.normal) - normal).max() <= 1e-9, (centre, result.normal, normal)


# As a user runs it -------------------------------------------------------------------------------------

EDGE = 0.01
MATERIALS = ("fix m1 all property/global youngsModulus peratomtype 5e6\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.3\n")


def test_head_on_cubes_with_flush_sides(run_deck, tmp_path):
    """Two 1 cm cubes, E 5 MPa, no damping, no friction, meet head on at +-0.5 m/s, dt 1e-6. Before the
    flush faces were smoothed: normal (0.99973, 0.0163, 0.0163), 1.46e-6 J of spin, +0.31 % energy."""
    deck = (decks.header(boundary="f f f", lo=-0.05, hi=0.05) + "neighbor 0.002 bin\nneigh_modify delay 0\n" +
            MATERIALS + decks.template("cube", "cube.stl", scale=EDGE) +
            "pair_style polyhedral/volumetric tangential off damping off\npair_coeff * *\n"
            "create_polyhedron cube -0.0055 0 0 vel 0.5 0 0\ncreate_polyhedron cube 0.0055 0 0 vel -0.5 0 0\n"
            "fix integrate all nve/polyhedron\ncompute contacts all pair/polyhedral/local\n"
            "compute erot all erotate/polyhedron\n"
            "dump normals all local 1 normals.txt c_contacts[5] c_contacts[6] c_contacts[7]\n"
            "variable smoothed equal c_contacts[1]\nvariable wrong equal c_contacts[3]\n"
            "thermo_style custom step ke c_erot c_contacts v_smoothed v_wrong\n"
            "thermo_modify format float %.15g\nthermo 500\n"
            "timestep 1e-6\nrun 3000\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output[-3000:]
    rows = [list(map(float, line.split())) for line in (result.workdir / "normals.txt").read_text().splitlines()
            if line and not line.startswith("ITEM") and len(line.split()) == 3]
    assert len(rows) > 500  # the contact lasts about 770 steps
    worst = max(max(abs(row[0] - 1.0), abs(row[1]), abs(row[2])) for row in rows)
    table = result.thermo("Step", "KinEng", "c_erot", "c_contacts", "v_smoothed", "v_wrong")
    assert table["c_contacts"][-1] == 0  # apart again
    # the statistics: every evaluation in contact was smoothed (the contact lasts ~770 steps), none
    # needed re-evaluating
    assert table["v_smoothed"][-1] >= len(rows) and table["v_wrong"][-1] == 0, table
    energy_change = abs(table["KinEng"][-1] / table["KinEng"][0] - 1.0)
    print(f"\nhead-on flush cubes: normal off x by {worst:.1e}, spin {table['c_erot'][-1]:.1e} J, "
          f"energy change {energy_change:.1e}")
    assert worst < 1e-9
    assert table["c_erot"][-1] < 1e-12
    assert energy_change < 1e-4


@pytest.mark.parametrize("floor", ["plane", "mesh"])
def test_column_of_five_cubes_stands(run_deck, tmp_path, floor):
    """Five 1 cm cubes stacked with 0.2 mm gaps (all side faces flush) fall onto a zplane wall or a
    2-triangle mesh floor, settle, and stand for 1 s: the sum of their lateral displacements stays below
    1e-9 m (before the smoothing, the tilted normal drove them sideways)."""
    if floor == "plane":
        wall = "fix floor all wall/polyhedral primitive type 1 zplane 0.0\n"
    else:
        meshes.write_stl(tmp_path / "floor.stl", meshes.grid(1, 0.05))
        wall = ("fix floor_mesh all mesh/surface file ../floor.stl type 1\n"
                "fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh\n")
    x0, y0 = 0.001, 0.002
    cubes = "".join(f"create_polyhedron cube {x0} {y0} {0.0051 + 0.0102 * i:.4f}\n" for i in range(5))
    drift = " + ".join(f"abs(x[{i}]-{x0}) + abs(y[{i}]-{y0})" for i in range(1, 6))
    deck = (decks.header(boundary="f f f", lo=-0.05, hi=0.1) + "neighbor 0.002 bin\nneigh_modify delay 0\n" +
            MATERIALS + "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n" +
            decks.template("cube", "cube.stl", scale=EDGE) + "pair_style polyhedral/volumetric\npair_coeff * *\n" +
            cubes + "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n" + wall +
            f"variable drift equal \"{drift}\"\nvariable top equal z[5]\n"
            "thermo_style custom step ke v_drift v_top\nthermo_modify format float %.15g\nthermo 5000\n"
            "timestep 2e-5\nrun 50000\n")
    result = run_deck(deck, workdir=tmp_path / floor)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "KinEng", "v_drift", "v_top")
    print(f"\ncolumn on the {floor}: lateral drift {max(table['v_drift']):.1e} m, top cube at "
          f"{table['v_top'][-1]:.6f} m")
    assert table["v_top"][-1] > 0.044  # still a column: five cubes on top of each other
    assert max(table["v_drift"]) < 1e-9
