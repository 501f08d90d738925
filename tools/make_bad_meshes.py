#!/usr/bin/env python3
"""Writes the defective meshes of tests/data/bad/, one defect per file.

    python3 tools/make_bad_meshes.py [outdir]      (default: tests/data/bad)

Each file triggers exactly one poly_status in poly_shape_load (see
tests/unit/test_shape.c); all other properties of the mesh are valid, so the
test also proves that the checks run in their documented order.
Deterministic, standard library only.
"""
import os
import sys

import make_shapes as shapes


def outward_tetrahedron(vertices, i, j, k, l):
    """The four faces of tetrahedron ijkl, counter-clockwise seen from outside."""
    if shapes.orient(vertices[i], vertices[j], vertices[k], vertices[l]) > 0:
        j, k = k, j
    return [(i, j, k), (i, l, j), (j, l, k), (k, l, i)]


def cube_triangles():
    vertices, quads = shapes.cube_mesh()
    return vertices, shapes.fan(quads)


def write_text(path, text):
    with open(path, "w", newline="\n") as f:
        f.write(text)


def main(outdir):
    os.makedirs(outdir, exist_ok=True)
    join = lambda name: os.path.join(outdir, name)

    v, t = cube_triangles()
    shapes.write_stl_ascii(join("open.stl"), "open_cube", v, t[:-1])

    reversed_one = list(t)
    a, b, c = reversed_one[4]
    reversed_one[4] = (a, c, b)
    shapes.write_off(join("inconsistent.off"), "unit cube, triangle 5 reversed", v, reversed_one)
    shapes.write_off(join("inward.off"), "unit cube, every triangle reversed (inward normals)", v,
                     [(a, c, b) for a, b, c in t])

    # Two tetrahedra on either side of the shared edge (0,0,0)-(1,0,0).
    v = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.5, 1.0, 0.25), (0.5, 0.5, 1.0), (0.5, -1.0, 0.25), (0.5, -0.5, -1.0)]
    t = outward_tetrahedron(v, 0, 1, 2, 3) + outward_tetrahedron(v, 0, 1, 4, 5)
    shapes.write_off(join("nonmanifold_edge.off"), "two tetrahedra sharing exactly one edge", v, t)

    # Two tetrahedra touching at the origin only.
    v = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0),
         (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]
    t = outward_tetrahedron(v, 0, 1, 2, 3) + outward_tetrahedron(v, 0, 4, 5, 6)
    shapes.write_off(join("pinched_vertex.off"), "two tetrahedra sharing exactly one vertex", v, t)

    # A closed, consistently oriented tetrahedron whose face ABC is split at the
    # midpoint M of AB; the sliver A-B-M (three collinear points) closes it.
    v = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
    faces = outward_tetrahedron(v, 0, 1, 2, 3)
    abc = faces[0]
    a, b, c = abc
    v.append(tuple(0.5 * (p + q) for p, q in zip(v[a], v[b])))
    t = faces[1:] + [(a, 4, c), (4, b, c), (a, b, 4)]
    shapes.check_closed_oriented(v, t, "degenerate")
    shapes.write_obj(join("degenerate.obj"), "closed tetrahedron with a zero-area triangle (collinear corners)", v, t)

    v = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0),
         (3.0, 0.0, 0.0), (4.0, 0.0, 0.0), (3.0, 1.0, 0.0), (3.0, 0.0, 1.0)]
    t = outward_tetrahedron(v, 0, 1, 2, 3) + outward_tetrahedron(v, 4, 5, 6, 7)
    shapes.write_obj(join("disconnected.obj"), "two separate tetrahedra", v, t)

    write_text(join("garbage.obj"),
               "# tetrahedron whose last face references vertex 9 of 4\n"
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
               "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 9\n")

    v, t = cube_triangles()
    cube_bytes = shapes.stl_binary_bytes("unit cube, cut inside its 6th triangle", v, t)
    with open(join("truncated.stl"), "wb") as f:
        f.write(cube_bytes[:84 + 50 * 5 + 17])

    write_text(join("empty.off"), "OFF\n# no vertices, no faces\n0 0 0\n")
    write_text(join("unknown.xyz"), "0 0 0\n1 0 0\n0 1 0\n0 0 1\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("tests", "data", "bad"))
