#!/usr/bin/env python3
"""The shell of prisms behind a mesh wall at a convex 90-degree edge whose cells are narrower than the
shell is thick: where the prisms miscount the solid, and what that does to a particle's overlap volume.

    /usr/bin/python3 tools/mesh_edge_study.py [--before COMMIT] [--cells 2 3 4 6 8 12 16 24] [--poses 6]

The mesh is that of tests/test_mesh_shell.py: the top z = 0 (x < 0) and the side x = 0 (z < 0) of the
quarter space x < 0, z < 0, each a grid of n x n cells 4 r wide (r the particle's bounding radius), the
shell 2 r thick (H), so a cell is w = 4 r / n wide, w / H = 2 / n. --before COMMIT builds that commit's
src/poly_mesh_shell.c instead of the working tree's (the rest of the core from the working tree), for the
numbers before a change. Prints:

1. The worst pose of the 12 x 12 mesh (tests/test_mesh_shell.py's test_very_narrow_cells_at_a_convex_edge,
   the L shape's third pose): the reference volume, the mesh's, and every prism whose piece the overlap core
   gives differently from the signed (winding-number weighted) volume of the particle's part of it, with
   the prism's own signed volume.
2. Per grid: the prisms that are inside out somewhere (a region of winding number -1; sampled), their
   signed volumes summed; the shallowest point (distance behind the nearer face, over w) where the pieces
   the core counts (each prism's winding number, negative ones as 0: what the core returns) do not add up
   to the quarter space; and the worst relative error of the mesh's overlap volume against the quarter
   space for particles (the five shapes of the tests, --poses random poses each) sunk d into the top face,
   d = 0.1 r and d = 0.25, 0.5, 0.75, 1.0, 1.5 w (where d < H cos 45, the full-depth shell's reach behind the
   edge; the shallowest miscounted point likewise only among points less than that behind the faces).

Uses the tests' ctypes shim over the C core (tests/test_overlap_geometry.py) and their Python reference
clipping (tests/overlap_reference.py). About 3 minutes on 2 cores with the defaults.
"""
import argparse
import ctypes
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import overlap_reference as ref  # noqa: E402
import test_overlap_geometry as geometry  # noqa: E402
from test_mesh_shell import SHAPE_NAMES, clipped, corner_case, edge_mesh, sunk_at_a_convex_edge  # noqa: E402

EXTRA_SOURCE = r"""
#include <math.h>
#include <string.h>

/* Every prism of the shell behind the soup, world corners (18 doubles) and triangles (24 ints); ok[t] = 0 where
 * poly_mesh_shell_prism refuses one. */
int study_prisms(const double *corners, int n, double h, double *vertices, int *triangles, int *ok)
{
  poly_mesh_shell shell;
  char message[256];
  if (poly_mesh_shell_build(corners, n, h, 1e-8, &shell, message, sizeof message) != 0) return -1;
  for (int t = 0; t < n; t++) {
    double nodes[3][3];
    for (int c = 0; c < 9; c++) nodes[c / 3][c % 3] = corners[9 * t + c];
    poly_mesh_prism prism;
    ok[t] = poly_mesh_shell_prism(&shell, t, nodes, &prism) == 0;
    if (!ok[t]) continue;
    for (int i = 0; i < 18; i++) vertices[18 * t + i] = prism.vertices[i] + prism.origin[i % 3];
    for (int i = 0; i < 24; i++) triangles[24 * t + i] = prism.triangles[i];
  }
  poly_mesh_shell_free(&shell);
  return 0;
}

/* The core's overlap volume of the shape at pose with prism t of the shell (0 where refused). */
double study_piece(const void *a, const double *pose, const double *corners, int n, double h, int t)
{
  poly_mesh_shell shell;
  char message[256];
  if (poly_mesh_shell_build(corners, n, h, 1e-8, &shell, message, sizeof message) != 0) return -1.0;
  double nodes[3][3];
  for (int c = 0; c < 9; c++) nodes[c / 3][c % 3] = corners[9 * t + c];
  poly_mesh_prism prism;
  double volume = 0.0;
  if (poly_mesh_shell_prism(&shell, t, nodes, &prism) == 0) {
    poly_pose pa, pb = {{prism.origin[0], prism.origin[1], prism.origin[2]}, {1.0, 0.0, 0.0, 0.0}};
    for (int k = 0; k < 3; k++) pa.position[k] = pose[k];
    for (int k = 0; k < 4; k++) pa.quaternion[k] = pose[3 + k];
    poly_overlap_result r;
    workspace_d.use_filter = 1;
    poly_overlap_d(&((const shim_shape *)a)->view_d, &pa, &prism.view, &pb, &workspace_d, &r);
    volume = r.volume;
  }
  poly_mesh_shell_free(&shell);
  return volume;
}
"""


def build(directory, shell_source):
    """The shim library, with src/poly_mesh_shell.c replaced by `shell_source` (a path) if given."""
    sources = list(geometry.SOURCES)
    if shell_source:
        sources = [shell_source if os.path.basename(s) == "poly_mesh_shell.c" else s for s in sources]
    shim = os.path.join(directory, "study_shim.c")
    with open(shim, "w") as out:
        out.write(geometry.SHIM_SOURCE + EXTRA_SOURCE)
    library = os.path.join(directory, "libmesh_edge_study.so")
    subprocess.run(["gcc", "-std=c11", "-O2", "-fPIC", "-shared", "-I" + os.path.join(ROOT, "src")] + sources +
                   [shim, "-lm", "-o", library], check=True)
    lib = geometry.Library(library)
    doubles, ints = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
    lib.lib.study_prisms.argtypes = [doubles, ctypes.c_int, ctypes.c_double, doubles, ints, ints]
    lib.lib.study_piece.argtypes = [ctypes.c_void_p, doubles, doubles, ctypes.c_int, ctypes.c_double, ctypes.c_int]
    lib.lib.study_piece.restype = ctypes.c_double
    return lib


def corner_array(mesh):
    flat = np.asarray(mesh, dtype=float).reshape(-1)
    return (ctypes.c_double * len(flat))(*flat), len(flat) // 9


def prisms(lib, mesh, h):
    corners, n = corner_array(mesh)
    vertices, triangles, ok = (ctypes.c_double * (18 * n))(), (ctypes.c_int * (24 * n))(), (ctypes.c_int * n)()
    assert lib.lib.study_prisms(corners, n, h, vertices, triangles, ok) == 0
    return (np.array(vertices[:]).reshape(n, 6, 3), np.array(triangles[:]).reshape(n, 8, 3),
            np.array(ok[:], dtype=bool))


def piece(lib, shape, pose, mesh, h, t):
    corners, n = corner_array(mesh)
    packed = (ctypes.c_double * 7)(*[float(x) for x in list(pose[0]) + list(pose[1])])
    return lib.lib.study_piece(shape.handle, packed, corners, n, h, t)


def winding(points, vertices, triangles):
    """Winding numbers of a closed triangle surface at the points (solid angles, Van Oosterom-Strackee)."""
    total = np.zeros(len(points))
    for a, b, c in triangles:
        p, q, s = vertices[a] - points, vertices[b] - points, vertices[c] - points
        lp, lq, ls = (np.linalg.norm(x, axis=1) for x in (p, q, s))
        numerator = np.einsum("ij,ij->i", p, np.cross(q, s))
        denominator = (lp * lq * ls + np.einsum("ij,ij->i", p, q) * ls + np.einsum("ij,ij->i", q, s) * lp +
                       np.einsum("ij,ij->i", s, p) * lq)
        total += 2.0 * np.arctan2(numerator, denominator)
    return total / (4.0 * np.pi)


def signed_intersection(vertices_a, triangles_a, vertices_b, triangles_b):
    """The integral over the shape's inside of the prism's winding number (overlap_reference's tetrahedron
    sums, without clipping the result at zero)."""
    tets_a, sign_a = ref.fan(vertices_a, triangles_a)
    tets_b, sign_b = ref.fan(vertices_b, triangles_b)
    planes_a, planes_b = ref.tet_planes(tets_a), ref.tet_planes(tets_b)
    volume6 = 0.0
    for i in range(len(tets_a)):
        for j in range(len(tets_b)):
            v6, _ = ref._convex_intersection(tets_a[i], (planes_a[0][i], planes_a[1][i]), tets_b[j],
                                             (planes_b[0][j], planes_b[1][j]))
            volume6 += sign_a[i] * sign_b[j] * v6
    return volume6 / 6.0


def load_shapes(lib, directory):
    l_path = os.path.join(directory, "l_shape.obj")
    with open(l_path, "w") as out:
        out.write(geometry.L_SHAPE_OBJ)
    paths = {"cube": "cube.stl", "schoenhardt": "schoenhardt.stl", "rock_40": "rock_40.obj",
             "icosphere_320": "icosphere_320.off"}
    shapes = {name: lib.shape(os.path.join(geometry.SHAPES, file)) for name, file in paths.items()}
    shapes["l_shape"] = lib.shape(l_path)
    return shapes


def worst_pose(lib, shapes):
    shape = shapes["l_shape"]
    r = shape.radius
    rng = np.random.default_rng(8)
    pose = [corner_case(shape, rng, "convex", 0.1) for _ in range(3)][2]
    mesh, h, big = edge_mesh("convex", 4.0 * r, 12), 2.0 * r, 40.0 * r
    exact, _ = clipped(shape, pose, (-big, -big, -big), (0.0, big, 0.0))
    result = lib.mesh_wall(shape, pose, mesh, h)
    print(f"1. L shape, third pose, 12 x 12 cells: quarter space V = {exact:.6e}, mesh V = {result.volume:.6e} "
          f"({result.volume / exact - 1:+.2e})")
    vertices, triangles, ok = prisms(lib, mesh, h)
    world = shape.world(pose)
    lo, hi = world.min(axis=0), world.max(axis=0)
    print("   prism  face  top corners (x, y, z) / r                      core piece / V   signed piece / V"
          "   prism's own signed volume / r^3")
    for t in np.nonzero(ok)[0]:
        if np.any(vertices[t].min(axis=0) > hi) or np.any(vertices[t].max(axis=0) < lo):
            continue
        core = piece(lib, shape, pose, mesh, h, t)
        signed = signed_intersection(world, shape.triangles, vertices[t], triangles[t])
        own, _ = ref.mesh_mass(vertices[t], triangles[t])
        if abs(core) < 1e-9 * exact and abs(signed) < 1e-9 * exact:
            continue
        top = " ".join("(%.2f, %.2f, %.2f)" % tuple(c / r) for c in vertices[t, :3])
        face = "top" if t < len(mesh) // 2 else "side"
        print(f"   {t:5d}  {face:4s}  {top:46s} {core / exact:14.3e} {signed / exact:18.3e} {own / r ** 3:16.3e}")


def grid_table(lib, shapes, cells, poses):
    r, h = 1.0, 2.0
    rng = np.random.default_rng(1)
    rows = []
    for n in cells:
        w = 4.0 * r / n
        mesh = edge_mesh("convex", 4.0 * r, n)
        vertices, triangles, ok = prisms(lib, mesh, h)
        inside_out, inside_out_volume = 0, 0.0
        points = np.column_stack([rng.uniform(-1.3 * w, 0, 60000), rng.uniform(-1.0, 1.0, 60000),
                                  rng.uniform(-1.3 * w, 0, 60000)])
        counted = np.zeros(len(points))
        for t in np.nonzero(ok)[0]:
            lo, hi = vertices[t].min(axis=0), vertices[t].max(axis=0)
            probe = rng.uniform(lo, hi, (4000, 3))
            if (np.round(winding(probe, vertices[t], triangles[t])) < 0).any():
                inside_out += 1
                inside_out_volume += ref.mesh_mass(vertices[t], triangles[t])[0]
            near = np.all((points >= lo - 1e-12) & (points <= hi + 1e-12), axis=1)
            if near.any():
                counted[near] += np.maximum(np.round(winding(points[near], vertices[t], triangles[t])), 0.0)
        # The edge's vertices (x = z = 0, |y| <= 2 r): how far their bottoms are behind the faces.
        top = vertices[ok][:, :3].reshape(-1, 3)
        bottom = vertices[ok][:, 3:].reshape(-1, 3)
        on_edge = (np.abs(top[:, 0]) < 1e-12) & (np.abs(top[:, 2]) < 1e-12) & (np.abs(top[:, 1]) <= 2.0 * r + 1e-12)
        edge_depth = np.minimum(-bottom[on_edge, 0], -bottom[on_edge, 2]).min() / w
        behind = np.minimum(-points[:, 0], -points[:, 2])
        wrong = (counted != 1) & (behind < h * np.sqrt(0.5))  # the full-depth shell reaches H cos 45 behind the edge
        onset = f"{behind[wrong].min() / w:.2f}" if wrong.any() else "none"
        depths = [0.1 * r] + [f * w for f in (0.25, 0.5, 0.75, 1.0, 1.5)]
        worst = []
        for depth in depths:
            if depth >= h * np.sqrt(0.5):  # deeper than the full-depth shell reaches behind the edge
                worst.append(None)
                continue
            error = 0.0
            for name in SHAPE_NAMES:
                shape = shapes[name]
                scale, big = shape.radius, 40.0 * shape.radius
                scaled_mesh = edge_mesh("convex", 4.0 * scale, n)
                for _ in range(poses):
                    pose = sunk_at_a_convex_edge(shape, rng, depth * scale)
                    exact, _ = clipped(shape, pose, (-big, -big, -big), (0.0, big, 0.0))
                    result = lib.mesh_wall(shape, pose, scaled_mesh, h * scale)
                    if exact > 0.0:  # else its lowest part is beyond the edge, over the side face
                        error = max(error, abs(result.volume / exact - 1))
                    else:
                        error = max(error, result.volume / shape.volume)
            worst.append(error)
        rows.append((n, w / h, inside_out, inside_out_volume, edge_depth, onset, worst))
        print(f"   {n}x{n} done", file=sys.stderr)
    print("\n2. Per grid (H = 2 r, w = 4 r / n):\n")
    print("| cells | w / H | inside-out prisms (their signed volume / H^3) | edge vertices' bottoms behind the faces"
          " (e) / w | shallowest miscounted point / w |"
          " V error, d = 0.1 r | d = 0.25 w | 0.5 w | 0.75 w | 1.0 w | 1.5 w |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n, ratio, count, volume, edge_depth, onset, worst in rows:
        print(f"| {n}x{n} | {ratio:.3f} | {count} ({volume / h ** 3:+.3f}) | {edge_depth:.2f} | {onset} | " +
              " | ".join("-" if e is None else f"{e:.1e}" for e in worst) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", help="build this commit's src/poly_mesh_shell.c")
    parser.add_argument("--cells", type=int, nargs="+", default=[2, 3, 4, 6, 8, 12, 16, 24])
    parser.add_argument("--poses", type=int, default=6)
    args = parser.parse_args()
    directory = tempfile.mkdtemp(prefix="mesh_edge_study")
    try:
        shell_source = None
        if args.before:
            shell_source = os.path.join(directory, "poly_mesh_shell.c")
            with open(shell_source, "w") as out:
                out.write(subprocess.run(["git", "show", f"{args.before}:src/poly_mesh_shell.c"], cwd=ROOT,
                                         check=True, capture_output=True, text=True).stdout)
        lib = build(directory, shell_source)
        print(f"poly_mesh_shell.c of {args.before or 'the working tree'}\n")
        shapes = load_shapes(lib, directory)
        worst_pose(lib, shapes)
        grid_table(lib, shapes, args.cells, args.poses)
    finally:
        shutil.rmtree(directory, ignore_errors=True)


if __name__ == "__main__":
    main()
