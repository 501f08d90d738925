#!/usr/bin/env python3
"""Writes the reference polyhedral shapes of examples/shapes/.

    python3 tools/make_shapes.py [outdir]      (default: examples/shapes)

Standard library only. The output is byte-for-byte reproducible on any
machine: the geometry uses only + - * / and sqrt (all correctly rounded in
IEEE 754), a private integer random generator and private sine/cosine and cube
root, never the platform's libm or Python-version-dependent float sums.
Numbers are written with %.17g, so what a reader gets back is exactly what was
computed here (binary STL: float32).
"""
import math
import os
import struct
import sys

PI = math.pi
SPHERE_VOLUME = PI / 6.0  # volume of the sphere of diameter 1


# ---------------------------------------------------------------- arithmetic

def cos_sin(angle):
    """Cosine and sine by Taylor series after reduction to [-pi, pi]."""
    x = angle - 2.0 * PI * round(angle / (2.0 * PI))
    c, s = 0.0, 0.0
    term = 1.0  # x^k / k!
    k = 0
    while abs(term) > 1e-30 or k < 4:
        if k % 4 == 0:
            c += term
        elif k % 4 == 1:
            s += term
        elif k % 4 == 2:
            c -= term
        else:
            s -= term
        k += 1
        term = term * x / k
    return c, s


def cube_root(x):
    """Newton iteration; converges to the correctly rounded value or a neighbour, deterministically."""
    y = 1.0
    while y * y * y < x:
        y *= 2.0
    while y * y * y > 8.0 * x:
        y *= 0.5
    for _ in range(200):
        y_next = y - (y * y * y - x) / (3.0 * y * y)
        if y_next == y:
            break
        y = y_next
    return y


class SplitMix64:
    """Tiny fixed random generator, independent of Python's random module."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFFFFFFFFFF

    def next_u64(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & 0xFFFFFFFFFFFFFFFF
        return z ^ (z >> 31)

    def uniform(self, lo, hi):
        return lo + (hi - lo) * ((self.next_u64() >> 11) * (1.0 / 9007199254740992.0))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def scaled(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def normalized(a):
    return scaled(a, 1.0 / math.sqrt(dot(a, a)))


def orient(a, b, c, d):
    """Six times the signed volume of tetrahedron abcd; > 0 when d is on the side
    that triangle abc's counter-clockwise normal points to."""
    return dot(cross(sub(b, a), sub(c, a)), sub(d, a))


def volume(vertices, triangles):
    """Enclosed volume (divergence theorem), summed in a fixed order."""
    reference = vertices[triangles[0][0]]
    total = 0.0
    for i, j, k in triangles:
        total += dot(sub(vertices[i], reference), cross(sub(vertices[j], reference), sub(vertices[k], reference)))
    return total / 6.0


def scale_to_volume(vertices, triangles, target):
    factor = cube_root(target / volume(vertices, triangles))
    return [scaled(v, factor) for v in vertices]


# ---------------------------------------------------------------- convex hull

def convex_hull(points):
    """Incremental 3D hull; returns outward counter-clockwise index triangles.
    Assumes no four points are exactly coplanar on the hull (true for the
    point sets used here; checked through F = 2V - 4 by the callers)."""
    extent = 0.0
    for p in points:
        extent = max(extent, abs(p[0]), abs(p[1]), abs(p[2]))
    eps = 1e-13 * extent * extent * extent
    i0 = 0
    i1 = max(range(len(points)), key=lambda i: dot(sub(points[i], points[i0]), sub(points[i], points[i0])))
    i2 = max(range(len(points)),
             key=lambda i: dot(cross(sub(points[i1], points[i0]), sub(points[i], points[i0])),
                               cross(sub(points[i1], points[i0]), sub(points[i], points[i0]))))
    i3 = max(range(len(points)), key=lambda i: abs(orient(points[i0], points[i1], points[i2], points[i])))
    if orient(points[i0], points[i1], points[i2], points[i3]) > 0:
        i1, i2 = i2, i1
    faces = [(i0, i1, i2), (i0, i3, i1), (i1, i3, i2), (i2, i3, i0)]
    for p in range(len(points)):
        if p in (i0, i1, i2, i3):
            continue
        visible = [f for f in faces if orient(points[f[0]], points[f[1]], points[f[2]], points[p]) > eps]
        if not visible:
            continue
        visible_edges = set()
        for a, b, c in visible:
            visible_edges.update(((a, b), (b, c), (c, a)))
        horizon = []
        for a, b, c in visible:
            for edge in ((a, b), (b, c), (c, a)):
                if (edge[1], edge[0]) not in visible_edges:
                    horizon.append(edge)
        visible_set = set(visible)
        faces = [f for f in faces if f not in visible_set] + [(a, b, p) for a, b in horizon]
    return faces


def hull_volume(points):
    return volume(points, convex_hull(points))


def reflex_edge_count(vertices, triangles):
    """Edges whose dihedral angle, seen from inside, exceeds 180 degrees."""
    opposite = {}
    for t in triangles:
        for k in range(3):
            opposite[(t[k], t[(k + 1) % 3])] = t[(k + 2) % 3]
    count = 0
    for (a, b), c in opposite.items():
        if a < b:
            d = opposite[(b, a)]
            if orient(vertices[a], vertices[b], vertices[c], vertices[d]) > 1e-12:
                count += 1
    return count


def check_closed_oriented(vertices, triangles, name):
    directed = set()
    for t in triangles:
        for k in range(3):
            edge = (t[k], t[(k + 1) % 3])
            assert edge not in directed, f"{name}: edge {edge} used twice in the same direction"
            directed.add(edge)
    for a, b in directed:
        assert (b, a) in directed, f"{name}: edge {(a, b)} is open"
    assert volume(vertices, triangles) > 0, f"{name}: inward orientation"


# ---------------------------------------------------------------- writers

def fmt(x):
    return "%.17g" % x


def facet_normal(vertices, t):
    n = cross(sub(vertices[t[1]], vertices[t[0]]), sub(vertices[t[2]], vertices[t[0]]))
    return normalized(n)


def write_stl_ascii(path, name, vertices, triangles):
    lines = [f"solid {name}"]
    for t in triangles:
        lines.append("  facet normal " + " ".join(fmt(x) for x in facet_normal(vertices, t)))
        lines.append("    outer loop")
        for i in t:
            lines.append("      vertex " + " ".join(fmt(x) for x in vertices[i]))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def stl_binary_bytes(header, vertices, triangles):
    data = bytearray(header.encode("ascii").ljust(80, b" ")[:80])
    data += struct.pack("<I", len(triangles))
    for t in triangles:
        corners = [c for i in t for c in vertices[i]]
        data += struct.pack("<12fH", *facet_normal(vertices, t), *corners, 0)
    return bytes(data)


def write_stl_binary(path, header, vertices, triangles):
    with open(path, "wb") as f:
        f.write(stl_binary_bytes(header, vertices, triangles))


def write_obj(path, comment, vertices, triangles):
    lines = [f"# {comment}", f"# {len(vertices)} vertices, {len(triangles)} triangles"]
    lines += ["v " + " ".join(fmt(x) for x in v) for v in vertices]
    lines += [f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}" for t in triangles]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def write_off(path, comment, vertices, faces):
    lines = ["OFF", f"# {comment}", f"{len(vertices)} {len(faces)} 0"]
    lines += [" ".join(fmt(x) for x in v) for v in vertices]
    lines += [" ".join(str(i) for i in [len(f)] + list(f)) for f in faces]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


# ---------------------------------------------------------------- shapes

def cube_mesh(edge=1.0):
    """Unit cube [0,edge]^3: 8 vertices, 12 outward triangles."""
    vertices = [(x * edge, y * edge, z * edge) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return vertices, quads


def fan(quads):
    return [(q[0], q[i], q[i + 1]) for q in quads for i in range(1, len(q) - 1)]


def box_mesh(a, b, c):
    vertices, quads = cube_mesh()
    return [(x * a, y * b, z * c) for x, y, z in vertices], quads


def tetrahedron_mesh():
    s = 1.0 / (2.0 * math.sqrt(2.0))  # edge 2*sqrt(2)*s = 1
    vertices = [(s, s, s), (s, -s, -s), (-s, s, -s), (-s, -s, s)]
    triangles = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    return vertices, triangles


def schoenhardt_mesh():
    """Equilateral triangles of edge 1 in z = 0 and z = 1, the top one turned by
    30 degrees; each side quadrilateral split along its reflex diagonal."""
    radius = 1.0 / math.sqrt(3.0)
    bottom, top = [], []
    for i in range(3):
        c, s = cos_sin(2.0 * PI * i / 3.0)
        bottom.append((radius * c, radius * s, 0.0))
        c, s = cos_sin(2.0 * PI * i / 3.0 + PI / 6.0)
        top.append((radius * c, radius * s, 1.0))
    vertices = bottom + top  # a_i = i, b_i = 3 + i
    caps = [(0, 2, 1), (3, 4, 5)]
    # Quad a_i, a_i+1, b_i+1, b_i is counter-clockwise seen from outside.
    split_a = [t for i in range(3) for t in ((i, (i + 1) % 3, 3 + (i + 1) % 3), (i, 3 + (i + 1) % 3, 3 + i))]
    split_b = [t for i in range(3) for t in ((i, (i + 1) % 3, 3 + i), ((i + 1) % 3, 3 + (i + 1) % 3, 3 + i))]
    volume_a, volume_b = volume(vertices, caps + split_a), volume(vertices, caps + split_b)
    triangles = caps + (split_a if volume_a < volume_b else split_b)
    hull = hull_volume(vertices)
    check_closed_oriented(vertices, triangles, "schoenhardt")
    # The reflex diagonals cut wedges off the convex hull; the other split is the hull itself.
    assert volume(vertices, triangles) < 0.99 * hull, "schoenhardt: chosen diagonals are not reflex"
    assert abs(max(volume_a, volume_b) - hull) < 1e-12 * hull
    assert reflex_edge_count(vertices, triangles) == 3
    return vertices, triangles


def icosphere_mesh(subdivisions):
    """Icosahedron subdivided `subdivisions` times, projected onto the unit sphere,
    then scaled to volume pi/6 (volume-equivalent diameter 1)."""
    g = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [normalized(v) for v in [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
                                        (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]]
    triangles = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
                 (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
                 (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoint = {}

        def middle(i, j):
            key = (min(i, j), max(i, j))
            if key not in midpoint:
                midpoint[key] = len(vertices)
                vertices.append(normalized(scaled(tuple(a + b for a, b in zip(vertices[i], vertices[j])), 0.5)))
            return midpoint[key]

        refined = []
        for a, b, c in triangles:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        triangles = refined
    check_closed_oriented(vertices, triangles, "icosphere")
    return scale_to_volume(vertices, triangles, SPHERE_VOLUME), triangles


def fibonacci_directions(n):
    golden_angle = PI * (3.0 - math.sqrt(5.0))
    directions = []
    for i in range(n):
        z = 1.0 - (2.0 * i + 1.0) / n
        r = math.sqrt(1.0 - z * z)
        c, s = cos_sin(i * golden_angle)
        directions.append((r * c, r * s, z))
    return directions


def legendre(l, x):
    p0, p1 = 1.0, x
    for k in range(1, l):
        p0, p1 = p1, ((2 * k + 1) * x * p1 - k * p0) / (k + 1)
    return p1 if l >= 1 else p0


ROCK_SEED = 20240611
# The dent is centred on the first direction of the 7-vertex sampling, so even
# the coarsest rock has a vertex pushed below its neighbours (two reflex edges).
DENT_DIRECTION = (math.sqrt(13.0) / 7.0, 0.0, 6.0 / 7.0)
DENT_HALF_ANGLE_COSINE = 0.5   # a 60-degree cap
DENT_DEPTH = 0.55


def rock_harmonics():
    """Five zonal harmonics of degree 2 and 3 about random axes: a lumpy, elongated body."""
    rng = SplitMix64(ROCK_SEED)
    harmonics = []
    for degree in (2, 2, 3, 3, 2):
        z = rng.uniform(-1.0, 1.0)
        c, s = cos_sin(rng.uniform(0.0, 2.0 * PI))
        axis = (math.sqrt(1.0 - z * z) * c, math.sqrt(1.0 - z * z) * s, z)
        harmonics.append((degree, axis, rng.uniform(-0.12, 0.12)))
    return harmonics


def rock_radius(direction, harmonics):
    r = 1.0
    for degree, axis, amplitude in harmonics:
        r += amplitude * legendre(degree, dot(axis, direction))
    t = dot(DENT_DIRECTION, direction)
    if t > DENT_HALF_ANGLE_COSINE:
        w = (t - DENT_HALF_ANGLE_COSINE) / (1.0 - DENT_HALF_ANGLE_COSINE)
        r -= DENT_DEPTH * w * w
    return r


def rock_mesh(num_vertices):
    """Star-shaped rock: r(direction) sampled on a Fibonacci sphere, triangulated
    by the convex hull of the directions, scaled to volume pi/6."""
    directions = fibonacci_directions(num_vertices)
    triangles = convex_hull(directions)
    assert len(triangles) == 2 * num_vertices - 4, "hull of the directions is not a full triangulation"
    harmonics = rock_harmonics()
    vertices = [scaled(u, rock_radius(u, harmonics)) for u in directions]
    for i, j, k in triangles:
        # Positive orientation about the origin keeps the radial surface embedded.
        assert dot(vertices[i], cross(vertices[j], vertices[k])) > 0
    check_closed_oriented(vertices, triangles, "rock")
    vertices = scale_to_volume(vertices, triangles, SPHERE_VOLUME)
    assert volume(vertices, triangles) < 0.97 * hull_volume(vertices), "rock is nearly convex"
    assert reflex_edge_count(vertices, triangles) >= 2
    return vertices, triangles


# ---------------------------------------------------------------- main

ROCK_VERTEX_COUNTS = {10: 7, 20: 12, 40: 22, 70: 37, 1000: 502}
ICOSPHERE_SUBDIVISIONS = {20: 0, 80: 1, 320: 2, 1280: 3, 5120: 4}


def main(outdir):
    os.makedirs(outdir, exist_ok=True)
    rows = []

    def row(filename, vertices, triangles, convention, vertex_text=None):
        rows.append((filename, len(triangles), vertex_text or str(len(vertices)), volume(vertices, triangles),
                     convention))

    v, t = schoenhardt_mesh()
    write_stl_ascii(os.path.join(outdir, "schoenhardt.stl"), "schoenhardt", v, t)
    row("schoenhardt.stl", v, t, "edge-1 triangles in z=0 and z=1, top turned 30 deg (ascii STL)")

    v, quads = cube_mesh()
    t = fan(quads)
    write_stl_binary(os.path.join(outdir, "cube.stl"), "polyhedral reference shape: unit cube [0,1]^3", v, t)
    row("cube.stl", v, t, "edge 1, corner at origin (binary STL)", "8 (36 in file)")

    v, t = tetrahedron_mesh()
    write_obj(os.path.join(outdir, "tetrahedron.obj"), "regular tetrahedron, edge 1, centroid at origin", v, t)
    row("tetrahedron.obj", v, t, "regular, edge 1, centroid at origin")

    v, quads = box_mesh(1.0, 2.0, 3.0)
    write_off(os.path.join(outdir, "box_1x2x3.off"), "box [0,1]x[0,2]x[0,3], quad faces", v, quads)
    row("box_1x2x3.off", v, fan(quads), "[0,1]x[0,2]x[0,3], 6 quads")

    for faces, level in ICOSPHERE_SUBDIVISIONS.items():
        v, t = icosphere_mesh(level)
        assert abs(volume(v, t) - SPHERE_VOLUME) < 1e-14 * SPHERE_VOLUME
        name = f"icosphere_{faces}.off"
        write_off(os.path.join(outdir, name), f"icosahedron subdivided {level}x, volume pi/6", v, t)
        row(name, v, t, "volume pi/6: volume-equivalent diameter 1")

    for faces, count in ROCK_VERTEX_COUNTS.items():
        v, t = rock_mesh(count)
        assert len(t) == faces
        name = f"rock_{faces}.obj"
        write_obj(os.path.join(outdir, name), f"non-convex rock, seed {ROCK_SEED}, volume pi/6", v, t)
        row(name, v, t, "volume pi/6: volume-equivalent diameter 1")

    write_readme(os.path.join(outdir, "README.md"), rows)


def write_readme(path, rows):
    lines = [
        "# Reference shapes",
        "",
        "Generated by `tools/make_shapes.py`; do not edit by hand. Regenerate with",
        "",
        "    python3 tools/make_shapes.py examples/shapes",
        "",
        "The output is byte-for-byte reproducible (`tests/test_shape_core.py` checks it).",
        "Volumes are in file units; `scale D` on a shape of volume pi/6 gives a particle",
        "of volume-equivalent diameter D.",
        "",
        "| file | triangles | vertices | volume | size convention |",
        "|---|---:|---:|---:|---|",
    ]
    for filename, triangles, vertices, vol, convention in rows:
        lines.append(f"| `{filename}` | {triangles} | {vertices} | {vol:.12g} | {convention} |")
    lines += [
        "",
        "- `schoenhardt.stl`: the Schoenhardt polyhedron, the simplest non-convex",
        "  polyhedron that cannot be split into tetrahedra without new vertices. Its two",
        "  equilateral triangles (edge 1, circumradius 1/sqrt(3)) lie in z = 0 and z = 1;",
        "  the top one is turned by 30 degrees and each side quadrilateral is split along",
        "  its reflex diagonal, so the three side edges are reflex (volume below the hull's).",
        "- `rock_*.obj`: one star-shaped rock (five random degree-2/3 zonal harmonics plus a",
        "  60-degree dent, fixed seed) sampled at 7, 22, 37 and 502 Fibonacci-sphere",
        "  directions, triangulated by the convex hull of the directions. Every resolution is",
        "  non-convex; the generator asserts it.",
        "- `icosphere_*.off`: subdivided icosahedra projected onto the sphere, then scaled",
        "  so the polyhedron (not its circumsphere) has volume pi/6.",
        "- Vertex counts are after welding; STL stores every corner of every triangle, and",
        "  loading welds the cube's 36 corners into 8 vertices.",
    ]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("examples", "shapes"))
