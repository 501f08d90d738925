#!/usr/bin/python3
"""Fits a LIGGGHTS multisphere template inside a closed triangle mesh (OBJ, STL or OFF) and writes it for
`fix particletemplate/multisphere ... spheres file F scale S`:

    /usr/bin/python3 tools/fit_multisphere.py examples/shapes/rock_40.obj 25 \
        examples/bench_multisphere/rock40.multisphere

Greedy, every sphere inside the mesh: the candidate centres are the interior points of a grid over the
mesh's bounding box (--grid cells along its longest side), each with the largest radius that stays inside
(its distance to the surface); radii below --min-radius (a fraction of the volume-equivalent diameter) are
left out. The volume is sampled on the same grid; each step takes the candidate that covers the most samples
not yet covered, until N spheres. The template's coordinates are relative to the mesh's centre of mass, which
is where LIGGGHTS puts a multisphere body's centre of mass when `mass` and `inertia_tensor` are given (file
units, scaled by the template's `scale`). The header states the mesh's volume, its inertia tensor per unit
density about the centre of mass (for `inertia_tensor`, times density and scale^5) and the fit: the fraction
of the mesh's volume the spheres cover (measured on a grid twice as fine as the fit's) and how far the mesh's
vertices lie outside the spheres. tools/bench_vs_multisphere.sh reads the header.

numpy is needed (Debian's python3-numpy: use /usr/bin/python3).
"""
import argparse
import pathlib
import struct
import sys

import numpy as np


# meshes ------------------------------------------------------------------------------------------------

def read_mesh(path):
    """(vertices (n, 3), triangles (m, 3) of vertex indices) of an OBJ, OFF or STL (ASCII or binary) file;
    STL corners are welded by exact coordinates."""
    path = pathlib.Path(path)
    data = path.read_bytes()
    suffix = path.suffix.lower()
    if suffix == ".obj":
        vertices, triangles = [], []
        for line in data.decode().splitlines():
            words = line.split()
            if words[:1] == ["v"]:
                vertices.append([float(w) for w in words[1:4]])
            elif words[:1] == ["f"]:
                idx = [int(w.split("/")[0]) - 1 for w in words[1:]]
                triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1)]
        return np.array(vertices), np.array(triangles)
    if suffix == ".off":
        words = " ".join(line.split("#")[0] for line in data.decode().splitlines()).split()
        if words[0] != "OFF":
            raise SystemExit(f"{path}: not an OFF file")
        nv, nf = int(words[1]), int(words[2])
        pos = 4
        vertices = np.array(words[pos:pos + 3 * nv], dtype=float).reshape(nv, 3)
        pos += 3 * nv
        triangles = []
        for _ in range(nf):
            k = int(words[pos])
            idx = [int(w) for w in words[pos + 1:pos + 1 + k]]
            pos += 1 + k
            triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, k - 1)]
        return vertices, np.array(triangles)
    if suffix == ".stl":
        if data[:5] == b"solid" and b"facet" in data[:1000]:
            corners = [[float(w) for w in line.split()[1:4]] for line in data.decode().splitlines()
                       if line.split()[:1] == ["vertex"]]
        else:
            count = struct.unpack_from("<I", data, 80)[0]
            corners = []
            for k in range(count):
                values = struct.unpack_from("<12f", data, 84 + 50 * k)
                corners += [values[3:6], values[6:9], values[9:12]]
        corners = np.array(corners, dtype=float)
        vertices, index = np.unique(corners, axis=0, return_inverse=True)
        return vertices, index.reshape(-1, 3)
    raise SystemExit(f"{path}: unknown mesh format (OBJ, OFF or STL)")


def mass_properties(vertices, triangles):
    """Volume, centre of mass and inertia tensor per unit density about the centre of mass (the tensor's
    off-diagonal entries -int x y dV, as LIGGGHTS' inertia_tensor) of a closed, outward-wound mesh."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    v6 = np.einsum("ij,ij->i", a, np.cross(b, c))
    volume = v6.sum() / 6
    centre = (v6[:, None] * (a + b + c)).sum(axis=0) / (24 * volume)
    a, b, c = a - centre, b - centre, c - centre
    # second moments int x_i x_j dV over each tetrahedron (origin, a, b, c)
    second = np.zeros((3, 3))
    for i in range(3):
        for j in range(3):
            s = (2 * (a[:, i] * a[:, j] + b[:, i] * b[:, j] + c[:, i] * c[:, j]) +
                 a[:, i] * b[:, j] + a[:, j] * b[:, i] + a[:, i] * c[:, j] + a[:, j] * c[:, i] +
                 b[:, i] * c[:, j] + b[:, j] * c[:, i])
            second[i, j] = (v6 * s).sum() / 120
    inertia = np.trace(second) * np.eye(3) - second
    return volume, centre, inertia


def winding_number(points, vertices, triangles):
    """Generalised winding number of each point (1 inside a closed outward mesh, 0 outside)."""
    result = np.zeros(len(points))
    for start in range(0, len(points), 20000):
        p = points[start:start + 20000, None, :]
        a, b, c = (vertices[triangles[:, k]][None, :, :] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
        det = np.einsum("pti,pti->pt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("pti,pti->pt", a, b) * lc + np.einsum("pti,pti->pt", b, c) * la +
               np.einsum("pti,pti->pt", c, a) * lb)
        result[start:start + 20000] = 2 * np.arctan2(det, den).sum(axis=1) / (4 * np.pi)
    return result


def surface_distance(points, vertices, triangles):
    """Distance of each point to the nearest point of the triangles (closest point on a triangle, Ericson's
    region tests, vectorised over points x triangles)."""
    result = np.full(len(points), np.inf)
    a0, b0, c0 = (vertices[triangles[:, k]] for k in range(3))
    for start in range(0, len(points), 5000):
        p = points[start:start + 5000, None, :]
        a, b, c = a0[None], b0[None], c0[None]
        ab, ac, ap = b - a, c - a, p - a
        d1, d2 = (ab * ap).sum(2), (ac * ap).sum(2)
        bp = p - b
        d3, d4 = (ab * bp).sum(2), (ac * bp).sum(2)
        cp = p - c
        d5, d6 = (ab * cp).sum(2), (ac * cp).sum(2)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        with np.errstate(divide="ignore", invalid="ignore"):
            denom = 1.0 / (va + vb + vc)
            v, w = vb * denom, vc * denom
            closest = a + ab * v[..., None] + ac * w[..., None]  # inside the face
            t = d1 / (d1 - d3)  # edge ab
            edge_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
            closest = np.where(edge_ab[..., None], a + ab * t[..., None], closest)
            t = d2 / (d2 - d6)  # edge ac
            edge_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
            closest = np.where(edge_ac[..., None], a + ac * t[..., None], closest)
            t = (d4 - d3) / ((d4 - d3) + (d5 - d6))  # edge bc
            edge_bc = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
            closest = np.where(edge_bc[..., None], b + (c - b) * t[..., None], closest)
        closest = np.where(((d1 <= 0) & (d2 <= 0))[..., None], a, closest)
        closest = np.where(((d3 >= 0) & (d4 <= d3))[..., None], b, closest)
        closest = np.where(((d6 >= 0) & (d5 <= d6))[..., None], c, closest)
        result[start:start + 5000] = np.linalg.norm(closest - p, axis=2).min(axis=1)
    return result


def interior_grid(vertices, triangles, cells):
    """Centres of the cells of a cubic grid over the bounding box (`cells` along its longest side) that lie
    inside the mesh, and the cell's edge."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    h = (hi - lo).max() / cells
    axes = [lo[k] + h * (np.arange(int(np.ceil((hi[k] - lo[k]) / h))) + 0.5) for k in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return grid[winding_number(grid, vertices, triangles) > 0.5], h


# fit ---------------------------------------------------------------------------------------------------

def fit(vertices, triangles, count, cells, min_radius):
    """Greedy: `count` spheres inside the mesh, each covering the most of the volume not yet covered.
    Returns centres (count, 3) and radii."""
    samples, _ = interior_grid(vertices, triangles, cells)
    radii = surface_distance(samples, vertices, triangles)
    candidates = radii >= min_radius
    centres, radii = samples[candidates], radii[candidates]
    cover = np.empty((len(centres), len(samples)), dtype=bool)
    for start in range(0, len(centres), 500):
        d2 = ((centres[start:start + 500, None, :] - samples[None, :, :]) ** 2).sum(axis=2)
        cover[start:start + 500] = d2 <= radii[start:start + 500, None] ** 2
    uncovered = np.ones(len(samples), dtype=bool)
    chosen = []
    for _ in range(count):
        gain = cover[:, uncovered].sum(axis=1)
        best = int(np.argmax(gain))
        if gain[best] == 0:
            break
        chosen.append(best)
        uncovered &= ~cover[best]
    return centres[chosen], radii[chosen]


def coverage(vertices, triangles, centres, radii, cells):
    """Fraction of the mesh's volume inside the union of the spheres, on an interior grid of `cells`."""
    samples, _ = interior_grid(vertices, triangles, cells)
    inside = np.zeros(len(samples), dtype=bool)
    for c, r in zip(centres, radii):
        inside |= ((samples - c) ** 2).sum(axis=1) <= r * r
    return inside.mean()


def vertex_gaps(vertices, centres, radii):
    """Distance of each mesh vertex outside the union of the spheres (0 if inside one)."""
    gap = np.sqrt(((vertices[:, None, :] - centres[None, :, :]) ** 2).sum(axis=2)) - radii[None, :]
    return np.maximum(gap.min(axis=1), 0.0)


def read_template(path):
    """(centres, radii, header dict) of a template written by this tool; the header gives volume (float),
    inertia (3x3, per unit density) and d_eq."""
    header, rows = {}, []
    for line in open(path):
        if line.startswith("#"):
            words = line[1:].split()
            if words[:1] == ["volume"]:
                header["volume"] = float(words[1])
            elif words[:1] == ["inertia_per_density"]:
                xx, xy, xz, yy, yz, zz = (float(w) for w in words[1:7])
                header["inertia"] = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
            elif words[:1] == ["coverage"]:
                header["coverage"] = float(words[1])
        elif line.strip():
            rows.append([float(w) for w in line.split()[:4]])
    rows = np.array(rows)
    return rows[:, :3], rows[:, 3], header


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("mesh")
    p.add_argument("count", type=int, help="number of spheres")
    p.add_argument("output")
    p.add_argument("--grid", type=int, default=40, help="grid cells along the longest side of the bounding box")
    p.add_argument("--min-radius", type=float, default=0.1,
                   help="smallest sphere radius as a fraction of the volume-equivalent diameter")
    a = p.parse_args()
    vertices, triangles = read_mesh(a.mesh)
    volume, centre, inertia = mass_properties(vertices, triangles)
    if volume <= 0:
        raise SystemExit(f"{a.mesh}: volume {volume} (not closed, or wound inward)")
    d_eq = (6 * volume / np.pi) ** (1 / 3)
    vertices = vertices - centre
    centres, radii = fit(vertices, triangles, a.count, a.grid, a.min_radius * d_eq)
    covered = coverage(vertices, triangles, centres, radii, 2 * a.grid)
    gaps = vertex_gaps(vertices, centres, radii)
    name = pathlib.Path(a.mesh).name
    lines = [
        f"# {len(radii)} spheres inside {name}, fitted by tools/fit_multisphere.py "
        f"(greedy, grid {a.grid}, min radius {a.min_radius} d_eq): x y z r in the mesh's units,",
        "# relative to its centre of mass (give fix particletemplate/multisphere the mesh's mass and inertia_tensor).",
        f"# volume {volume:.12g}",
        f"# d_eq {d_eq:.12g}",
        "# inertia_per_density {:.12g} {:.12g} {:.12g} {:.12g} {:.12g} {:.12g}".format(
            inertia[0, 0], inertia[0, 1], inertia[0, 2], inertia[1, 1], inertia[1, 2], inertia[2, 2]),
        f"# coverage {covered:.4f} of the volume (grid {2 * a.grid}); sphere volume sum "
        f"{(4 / 3 * np.pi * radii ** 3).sum() / volume:.4f} of it",
        f"# vertices outside the spheres by {gaps.mean() / d_eq:.4f} d_eq on average, {gaps.max() / d_eq:.4f} at most; "
        f"radii {radii.min() / d_eq:.4f} to {radii.max() / d_eq:.4f} d_eq",
    ]
    lines += [f"{c[0]:.9f} {c[1]:.9f} {c[2]:.9f} {r:.9f}" for c, r in zip(centres, radii)]
    pathlib.Path(a.output).write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:7]))
    if len(radii) < a.count:
        print(f"only {len(radii)} spheres: nothing left to cover", file=sys.stderr)


if __name__ == "__main__":
    main()
