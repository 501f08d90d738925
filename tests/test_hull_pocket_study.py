"""tools/hull_pocket_study.py, whose table doc/benchmarks.md quotes: its pockets are those of known shapes (the
Schoenhardt polyhedron's three tetrahedra, whose volumes make up what the hull has beyond the shape; none for a
cube), and a convex shape's touching poses all meet no pocket."""
import pathlib
import sys

import numpy as np
from scipy.spatial import ConvexHull

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import hull_pocket_study as study  # noqa: E402

SHAPES = ROOT / "examples" / "shapes"


def test_schoenhardt_pockets_are_its_three_tetrahedra():
    vertices, triangles = (np.array(a) for a in study.read_mesh(SHAPES / "schoenhardt.stl"))
    hull = ConvexHull(vertices)
    pockets, num_recessed = study.pockets_of(vertices, triangles, hull, float(np.ptp(vertices, axis=0).max()))
    assert num_recessed == 6
    assert sorted(len(p) for p in pockets) == [4, 4, 4]
    volume = sum(np.dot(vertices[a], np.cross(vertices[b], vertices[c])) for a, b, c in triangles) / 6.0
    pocket_volume = sum(ConvexHull(vertices[p]).volume for p in pockets)
    assert abs(hull.volume - volume - pocket_volume) < 1e-12 * hull.volume


def test_a_convex_shape_has_no_pocket_and_every_pose_takes_the_hull():
    pockets, ratio, exact, cheap = study.study(SHAPES / "cube.stl", 5, np.random.default_rng(3))
    assert pockets == [] and abs(ratio - 1.0) < 1e-12
    assert exact == 1.0 and cheap == 1.0


def test_schoenhardt_touching_poses_all_reach_a_pocket():
    pockets, ratio, exact, cheap = study.study(SHAPES / "schoenhardt.stl", 5, np.random.default_rng(3))
    assert 0.5 < ratio < 0.6
    assert exact == 0.0 and cheap <= exact
