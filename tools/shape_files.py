#!/usr/bin/python3
"""Mesh files of particle shapes (OBJ, OFF, ASCII or binary STL) and their mass properties, in pure Python (no
numpy), for tools/convert_deck.py, tools/make_shape.py and the examples' run scripts."""
import math
import pathlib
import struct


def read_mesh(path):
    """Vertices and triangles of an OBJ, OFF or (ASCII or binary) STL file."""
    path = pathlib.Path(path)
    data = path.read_bytes()
    suffix = path.suffix.lower()
    vertices, triangles = [], []
    if suffix == ".obj":
        for line in data.decode(errors="replace").splitlines():
            w = line.split()
            if w[:1] == ["v"]:
                vertices.append(tuple(float(x) for x in w[1:4]))
            elif w[:1] == ["f"]:
                idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
                triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1)]
    elif suffix == ".off":
        words = [w for line in data.decode(errors="replace").splitlines()
                 for w in line.split("#")[0].split()]
        if words[0].upper() == "OFF":
            words = words[1:]
        nv, nf = int(words[0]), int(words[1])
        k = 3
        for _ in range(nv):
            vertices.append(tuple(float(x) for x in words[k:k + 3]))
            k += 3
        for _ in range(nf):
            n = int(words[k])
            idx = [int(x) for x in words[k + 1:k + 1 + n]]
            triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, n - 1)]
            k += 1 + n
    elif suffix == ".stl":
        corners = []
        if data[:5].lower() == b"solid" and b"facet" in data[:1000]:
            for line in data.decode(errors="replace").splitlines():
                w = line.split()
                if w[:1] == ["vertex"]:
                    corners.append(tuple(float(x) for x in w[1:4]))
        else:
            count = struct.unpack("<I", data[80:84])[0]
            for t in range(count):
                values = struct.unpack("<12f", data[84 + 50 * t:84 + 50 * t + 48])
                corners += [values[3:6], values[6:9], values[9:12]]
        index = {}
        for c in corners:
            index.setdefault(c, len(index))
        vertices = list(index)
        triangles = [(index[corners[i]], index[corners[i + 1]], index[corners[i + 2]])
                     for i in range(0, len(corners) - 2, 3)]
    else:
        raise ValueError(f"{path}: not an OBJ, OFF or STL file")
    return vertices, triangles


def mass_properties(vertices, triangles):
    """Volume (positive for outward winding), centroid, and the principal moments per unit density about the
    centroid (ascending)."""
    volume, first = 0.0, [0.0, 0.0, 0.0]
    second = [[0.0] * 3 for _ in range(3)]
    for i, j, k in triangles:
        a, b, c = vertices[i], vertices[j], vertices[k]
        v6 = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
              a[2] * (b[0] * c[1] - b[1] * c[0]))
        volume += v6 / 6.0
        for p in range(3):
            first[p] += v6 / 24.0 * (a[p] + b[p] + c[p])
            for q in range(3):
                second[p][q] += v6 / 120.0 * (a[p] * a[q] + b[p] * b[q] + c[p] * c[q] +
                                              (a[p] + b[p] + c[p]) * (a[q] + b[q] + c[q]))
    centre = [f / volume for f in first]
    covariance = [[second[p][q] - volume * centre[p] * centre[q] for q in range(3)] for p in range(3)]
    trace = covariance[0][0] + covariance[1][1] + covariance[2][2]
    inertia = [[(trace if p == q else 0.0) - covariance[p][q] for q in range(3)] for p in range(3)]
    return volume, centre, sorted(eigenvalues_symmetric(inertia))


def eigenvalues_symmetric(m):
    """Eigenvalues of a symmetric 3x3 matrix (the trigonometric closed form)."""
    p1 = m[0][1] ** 2 + m[0][2] ** 2 + m[1][2] ** 2
    q = (m[0][0] + m[1][1] + m[2][2]) / 3.0
    if p1 == 0.0:
        return [m[0][0], m[1][1], m[2][2]]
    p2 = sum((m[k][k] - q) ** 2 for k in range(3)) + 2 * p1
    p = math.sqrt(p2 / 6.0)
    b = [[(m[r][c] - (q if r == c else 0.0)) / p for c in range(3)] for r in range(3)]
    det = (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
           b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]))
    phi = math.acos(max(-1.0, min(1.0, det / 2.0))) / 3.0
    e1 = q + 2 * p * math.cos(phi)
    e3 = q + 2 * p * math.cos(phi + 2 * math.pi / 3)
    return [e1, 3 * q - e1 - e3, e3]


def bounding_radius(vertices, centre):
    """The largest distance of a vertex from `centre` (the template's bounding radius about its centroid)."""
    return max(math.dist(v, centre) for v in vertices)
