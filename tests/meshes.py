"""ASCII STL meshes for the mesh-wall tests: floors, a closed box, a drum shell. Each triangle's normal
(right-hand rule on its corners) points into the free space where the particles are."""
import math


def write_stl(path, triangles, name="mesh"):
    """triangles: [((x, y, z), (x, y, z), (x, y, z)), ...], counter-clockwise seen from the free side."""
    lines = [f"solid {name}"]
    for a, b, c in triangles:
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        length = math.sqrt(sum(x * x for x in n))
        lines.append("  facet normal %.17g %.17g %.17g" % tuple(x / length for x in n))
        lines.append("    outer loop")
        lines += ["      vertex %.17g %.17g %.17g" % p for p in (a, b, c)]
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")
    return path


def grid(n, half, z=0.0, up=True, diagonal_flip=False):
    """A square [-half, half]^2 at height z as an n x n grid of 2 n^2 triangles, normals +z (or -z)."""
    step = 2.0 * half / n
    triangles = []
    for i in range(n):
        for j in range(n):
            x0, y0 = -half + i * step, -half + j * step
            p = [(x0, y0, z), (x0 + step, y0, z), (x0 + step, y0 + step, z), (x0, y0 + step, z)]
            if diagonal_flip and (i + j) % 2:
                pair = [(p[0], p[1], p[3]), (p[1], p[2], p[3])]
            else:
                pair = [(p[0], p[1], p[2]), (p[0], p[2], p[3])]
            triangles += pair if up else [(a, c, b) for a, b, c in pair]
    return triangles


def box(lo, hi, n=1):
    """The six faces of the box [lo, hi]^3 (each an n x n grid), normals pointing into the box."""
    triangles = []
    for axis in range(3):
        for side, value in ((1, lo), (-1, hi)):
            # A grid on the plane axis = value, facing +axis (side 1) or -axis (side -1).
            for a, b, c in grid(n, 0.5):
                corners = []
                for p in (a, b, c):
                    q = [0.0, 0.0, 0.0]
                    u, v = (axis + 1) % 3, (axis + 2) % 3
                    q[u] = lo + (p[0] + 0.5) * (hi - lo)
                    q[v] = lo + (p[1] + 0.5) * (hi - lo)
                    q[axis] = value
                    corners.append(tuple(q))
                triangles.append(tuple(corners) if side == 1 else (corners[0], corners[2], corners[1]))
    return triangles


def drum(radius, length, segments):
    """A cylinder shell about the y axis, y in [-length/2, length/2], with closed flat ends, all normals
    pointing inwards: a closed container."""
    triangles = []
    h = length / 2.0
    ring = [(radius * math.cos(2 * math.pi * k / segments), radius * math.sin(2 * math.pi * k / segments))
            for k in range(segments)]
    for k in range(segments):
        (x0, z0), (x1, z1) = ring[k], ring[(k + 1) % segments]
        a, b, c, d = (x0, -h, z0), (x1, -h, z1), (x1, h, z1), (x0, h, z0)
        triangles += [(a, b, c), (a, c, d)]
        triangles.append(((0.0, -h, 0.0), (x1, -h, z1), (x0, -h, z0)))
        triangles.append(((0.0, h, 0.0), (x0, h, z0), (x1, h, z1)))
    return triangles
