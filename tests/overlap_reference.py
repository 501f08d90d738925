"""Independent reference for the volume and centroid of the intersection of two
closed, consistently oriented triangle meshes (numpy only; shares no algorithm
with src/poly_overlap_impl.h).

Method: the indicator of a closed oriented mesh is a signed sum of tetrahedra,
the fan of every triangle from one apex point p,

    chi_A(x) = sum_i s_i chi_{T_i}(x),   T_i = (p, a_i, b_i, c_i),  s_i = sign det(a_i-p, b_i-p, c_i-p)

(the winding number of a closed oriented surface; valid for non-convex meshes
and for any apex, inside or outside). Hence

    V(A n B)     = sum_ij s_i s_j V(T_i n T_j)
    M(A n B)     = sum_ij s_i s_j V(T_i n T_j) c(T_i n T_j)

and every T_i n T_j is convex. Its boundary consists of (each face of T_i
clipped by the four half-spaces of T_j) and (each face of T_j clipped by the
half-spaces of T_i): Sutherland-Hodgman clipping of a triangle, no ordering of
cap polygons needed. Volume and first moment of that closed polygon set follow
from cones to a reference point. Pairs separated by a face plane of either
tetrahedron are rejected in bulk first. In generic poses this is exact to
rounding (~1e-14 relative); coplanar faces of the two fans would be counted
twice, so use it on generic configurations and the closed forms below otherwise.

Closed forms: axis-aligned boxes (box_intersection), and the volume/centroid
of one closed mesh (mesh_mass) for self-checks.
"""
import numpy as np


def quaternion_matrix(q):
    """Row-major rotation matrix of the unit quaternion (w, i, j, k), body -> world."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def to_world(vertices, position, quaternion):
    return np.asarray(vertices, dtype=float) @ quaternion_matrix(quaternion).T + np.asarray(position, dtype=float)


def mesh_mass(vertices, triangles):
    """Volume and centroid of one closed oriented mesh (cones to its vertex mean)."""
    v = np.asarray(vertices, dtype=float)
    r = v.mean(axis=0)
    a, b, c = (v[np.asarray(triangles)[:, k]] - r for k in range(3))
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    volume = det.sum() / 6.0
    centroid = r + (det[:, None] * (a + b + c)).sum(axis=0) / (24.0 * volume)
    return volume, centroid


def box_intersection(low_a, high_a, low_b, high_b):
    """Volume and centroid of the intersection of two axis-aligned boxes (centroid None if empty)."""
    low = np.maximum(low_a, low_b)
    high = np.minimum(high_a, high_b)
    if np.any(high <= low):
        return 0.0, None
    return float(np.prod(high - low)), 0.5 * (low + high)


def fan(vertices, triangles, apex=None):
    """Positively oriented tetrahedra (n, 4, 3) of the fan from `apex` and their signs (n,)."""
    v = np.asarray(vertices, dtype=float)
    t = np.asarray(triangles)
    p = v.mean(axis=0) if apex is None else np.asarray(apex, dtype=float)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    det = np.einsum("ij,ij->i", a - p, np.cross(b - p, c - p))
    keep = det != 0.0
    a, b, c, det = a[keep], b[keep], c[keep], det[keep]
    sign = np.sign(det)
    # Swap b and c on negative ones so that every tetrahedron is positively oriented.
    b2 = np.where(sign[:, None] > 0, b, c)
    c2 = np.where(sign[:, None] > 0, c, b)
    tets = np.stack([np.broadcast_to(p, a.shape), a, b2, c2], axis=1)
    return tets, sign


# Faces of a positively oriented tetrahedron (0, 1, 2, 3), counter-clockwise seen from outside.
_TET_FACES = ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))


def tet_planes(tets):
    """Outward unit normals (n, 4, 3) and offsets (n, 4): inside is normal . x <= offset."""
    normals = np.empty(tets.shape[:1] + (4, 3))
    offsets = np.empty(tets.shape[:1] + (4,))
    for f, (i, j, k) in enumerate(_TET_FACES):
        n = np.cross(tets[:, j] - tets[:, i], tets[:, k] - tets[:, i])
        n /= np.linalg.norm(n, axis=1)[:, None]
        normals[:, f] = n
        # Offset from the mean of the face's corners: the same number whichever corner is first.
        offsets[:, f] = np.einsum("ij,ij->i", n, (tets[:, i] + tets[:, j] + tets[:, k]) / 3.0)
    return normals, offsets


def _clip(polygon, normal, offset):
    """Sutherland-Hodgman: the part of a planar polygon (list of points) with normal . x <= offset."""
    out = []
    count = len(polygon)
    if count == 0:
        return out
    dist = [float(normal @ p) - offset for p in polygon]
    for k in range(count):
        p, q = polygon[k], polygon[(k + 1) % count]
        dp, dq = dist[k], dist[(k + 1) % count]
        if dp <= 0.0:
            out.append(p)
        if (dp < 0.0 < dq) or (dq < 0.0 < dp):
            out.append(p + (dp / (dp - dq)) * (q - p))
    return out


def _convex_intersection(tet_a, planes_a, tet_b, planes_b):
    """6 V and 24 V c (about the origin) of tet_a n tet_b."""
    polygons = []
    for tet, (normals, offsets) in ((tet_a, planes_b), (tet_b, planes_a)):
        for face in _TET_FACES:
            polygon = [tet[face[0]], tet[face[1]], tet[face[2]]]
            for f in range(4):
                polygon = _clip(polygon, normals[f], offsets[f])
                if len(polygon) < 3:
                    break
            if len(polygon) >= 3:
                polygons.append(polygon)
    if not polygons:
        return 0.0, np.zeros(3)
    points = np.array([p for polygon in polygons for p in polygon])
    r = points.mean(axis=0)
    volume6 = 0.0
    moment24 = np.zeros(3)
    for polygon in polygons:
        p0 = polygon[0] - r
        for k in range(1, len(polygon) - 1):
            p1, p2 = polygon[k] - r, polygon[k + 1] - r
            d = float(p0 @ np.cross(p1, p2))
            volume6 += d
            moment24 += d * (p0 + p1 + p2)
    # Shift the cone sums from r to the origin: 24 V c = 24 V r + sum d (p0 + p1 + p2).
    return volume6, moment24 + 4.0 * volume6 * r


def _separated(tets_x, normals_y, offsets_y):
    """(ny, nx) boolean: all corners of tet x beyond one face plane of tet y."""
    # dist[y, f, x, c] = normals_y[y, f] . tets_x[x, c] - offsets_y[y, f]
    dist = np.einsum("yfk,xck->yfxc", normals_y, tets_x) - offsets_y[:, :, None, None]
    return np.any(np.all(dist >= 0.0, axis=3), axis=1)


def intersection(vertices_a, triangles_a, vertices_b, triangles_b, apex_a=None, apex_b=None):
    """Volume and centroid (None if empty) of the intersection of two closed
    oriented meshes given in one common frame."""
    tets_a, sign_a = fan(vertices_a, triangles_a, apex_a)
    tets_b, sign_b = fan(vertices_b, triangles_b, apex_b)
    normals_a, offsets_a = tet_planes(tets_a)
    normals_b, offsets_b = tet_planes(tets_b)
    disjoint = _separated(tets_b, normals_a, offsets_a) | _separated(tets_a, normals_b, offsets_b).T
    volume6 = 0.0
    moment24 = np.zeros(3)
    for i, j in zip(*np.nonzero(~disjoint)):
        v6, m24 = _convex_intersection(tets_a[i], (normals_a[i], offsets_a[i]), tets_b[j],
                                       (normals_b[j], offsets_b[j]))
        s = sign_a[i] * sign_b[j]
        volume6 += s * v6
        moment24 += s * m24
    volume = volume6 / 6.0
    if volume <= 0.0:
        return 0.0, None
    return volume, moment24 / (24.0 * volume)
