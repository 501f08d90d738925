"""Could a shape that is not convex take the convex clipping path through its convex hull? (doc/benchmarks.md,
"What a contact costs in the flows, and two paths tried at afb2160, not kept")

    /usr/bin/python3 tools/hull_pocket_study.py [--poses N] [--seed S] [--write-hulls DIR] [SHAPE ...]

A shape is its convex hull less its pockets (the parts of the hull outside the shape). Where the overlap of the two
hulls meets no pocket of either body, the overlap of the shapes is the overlap of the hulls, and a convex path
would give it exactly. This prints, per shape, the hull, the pockets (the shape's triangles that lie on no hull facet,
joined across their edges inside the hull; each pocket is covered by the convex hull of its triangles' corners) and,
over N touching poses (B turned at random, moved towards A along a random direction until the hulls touch, then on
by up to 1 % of the shape's size), the share of poses whose hull overlap meets no pocket's cover: by a linear
programme on the half-spaces of both hulls and of the cover, with a margin of 1e-9 of the size (a lower bound where
a pocket is not convex, as its cover then takes in some of the shape), and by the cheap test a clipping path would
run (some face plane of the other hull with every corner of the pocket in front of it). With --write-hulls, each
shape's hull as an OBJ file (for timing a convex path on the hulls). Reads what tools/shape_files.py reads.
"""
import argparse
import pathlib
import sys

import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation

from shape_files import read_mesh

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHAPES = ROOT / "examples" / "shapes"
NOT_CONVEX = ["schoenhardt.stl", "rock_10.obj", "rock_20.obj", "rock_40.obj", "rock_70.obj"]


def pockets_of(vertices, triangles, hull, size):
    """The corners of each pocket: the triangles on no hull facet, joined across edges that lie inside the hull."""
    planes = hull.equations
    on_hull = lambda points: np.all(np.abs(points @ planes[:, :3].T + planes[:, 3]) < 1e-9 * size, axis=0)
    recessed = [t for t, corners in enumerate(triangles) if not np.any(on_hull(vertices[corners]))]
    parent = {t: t for t in recessed}

    def root(t):
        while parent[t] != t:
            parent[t] = parent[parent[t]]
            t = parent[t]
        return t

    by_edge = {}
    for t in recessed:
        a, b, c = triangles[t]
        for edge in ((a, b), (b, c), (c, a)):
            by_edge.setdefault(tuple(sorted(edge)), []).append(t)
    for (a, b), sharing in by_edge.items():
        middle = 0.5 * (vertices[a] + vertices[b])
        if np.max(middle @ planes[:, :3].T + planes[:, 3]) > -1e-9 * size:
            continue  # an edge on the hull's surface: two pockets meet there, at most
        for t in sharing[1:]:
            parent[root(t)] = root(sharing[0])
    groups = {}
    for t in recessed:
        groups.setdefault(root(t), set()).update(triangles[t])
    return [np.array(sorted(corners)) for corners in groups.values()], len(recessed)


def disjoint(planes_list, size):
    """No point strictly inside all the half-spaces (planes a.x + d <= 0) by 1e-9 of the size."""
    planes = np.vstack(planes_list)
    result = linprog(np.zeros(3), A_ub=planes[:, :3], b_ub=-planes[:, 3] - 1e-9 * size, bounds=[(None, None)] * 3,
                     method="highs")
    return result.status == 2


def parted(corners, planes, size):
    """Some plane (a.x + d <= 0 inside) with every corner in front of it by more than 1e-9 of the size."""
    return np.any(np.all(corners @ planes[:, :3].T + planes[:, 3] > 1e-9 * size, axis=0))


def study(path, poses, rng, write_hulls=None):
    """The table's row for the shape at `path`; returns (pockets' corner lists, volume / hull's, the exact and the
    face planes' shares of `poses` touching poses whose hull overlap meets no pocket)."""
    vertices, triangles = (np.array(a) for a in read_mesh(path))
    vertices = vertices - vertices.mean(axis=0)
    size = float(np.ptp(vertices, axis=0).max())
    hull = ConvexHull(vertices)
    pockets, num_recessed = pockets_of(vertices, triangles, hull, size)
    pocket_planes = [ConvexHull(vertices[p]).equations for p in pockets]
    if write_hulls:
        write_hull(vertices, hull, pathlib.Path(write_hulls) / f"hull_{path.stem}.obj")
    exact = cheap = 0
    for _ in range(poses):
        turned = vertices @ Rotation.random(random_state=rng).as_matrix().T
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        turned_planes = ConvexHull(turned).equations
        low, high = 0.0, float(np.max(vertices @ direction) + np.max(-turned @ direction))
        for _ in range(30):  # the shift along `direction` at which the hulls touch
            middle = 0.5 * (low + high)
            shifted = turned_planes.copy()
            shifted[:, 3] -= shifted[:, :3] @ (direction * middle)
            if disjoint([hull.equations, shifted], 0.0):
                high = middle
            else:
                low = middle
        shift = direction * (low - 0.01 * size * rng.random())
        b_vertices = turned + shift
        b_planes = turned_planes.copy()
        b_planes[:, 3] -= b_planes[:, :3] @ shift
        b_pockets = [ConvexHull(b_vertices[p]).equations for p in pockets]
        exact += all(disjoint([hull.equations, b_planes, p], size) for p in pocket_planes + b_pockets)
        cheap += all(parted(vertices[p], b_planes, size) for p in pockets) and \
            all(parted(b_vertices[p], hull.equations, size) for p in pockets)
    volume = abs(sum(np.dot(vertices[a], np.cross(vertices[b], vertices[c])) for a, b, c in triangles)) / 6.0
    print(f"| {path.name} | {len(triangles)} | {len(hull.simplices)} | {volume / hull.volume:.3f} | {num_recessed} | "
          f"{len(pockets)} ({', '.join(str(len(p)) for p in pockets)}) | {exact / poses:.3f} | {cheap / poses:.3f} |")
    return pockets, volume / hull.volume, exact / poses, cheap / poses


def write_hull(vertices, hull, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    index = {v: i for i, v in enumerate(hull.vertices)}
    lines = ["v %.17g %.17g %.17g" % tuple(vertices[v]) for v in hull.vertices]
    for corners, plane in zip(hull.simplices, hull.equations):
        a, b, c = vertices[corners]
        if np.dot(np.cross(b - a, c - a), plane[:3]) < 0:
            corners = corners[[0, 2, 1]]
        lines.append("f %d %d %d" % tuple(index[v] + 1 for v in corners))
    path.write_text("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shapes", nargs="*", default=NOT_CONVEX, help="files in examples/shapes (default: %(default)s)")
    parser.add_argument("--poses", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--write-hulls", metavar="DIR")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"{args.poses} touching poses per shape (hulls overlapping by up to 1 % of the size), seed {args.seed}\n")
    print("| shape | triangles | hull facets | volume / hull's | triangles off the hull | pockets (corners) | "
          "hull overlap meets no pocket's cover | by the face planes' test |")
    print("|---|---:|---:|---:|---:|---|---:|---:|")
    for name in args.shapes:
        path = pathlib.Path(name)
        study(path if path.is_absolute() else SHAPES / name, args.poses, rng, args.write_hulls)
    return 0


if __name__ == "__main__":
    sys.exit(main())
