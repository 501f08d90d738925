#!/usr/bin/env python3
"""Writes a tumbling mill with lifters as one closed ASCII STL (metres) for in.mill / in.mill_spheres.

    python3 make_mill.py [--D 0.3] [--L 0.1] [--lifters 8] [--height 0.02] [--width 0.02] [--face-angle 20]
                         [--cells 6] [--out mesh/mill.stl]

Geometry: the mill axis is the y axis, the cross-section is the x-z plane (gravity along -z).
  * the shell is a cylinder of diameter D, from y = -L/2 to y = L/2, made of flat panels;
  * `lifters` bars run along the whole length, evenly spaced around the shell (the first centred on the
    bottom, angle 0 = the point (0, -D/2)); each is a trapezoid in cross-section: `height` from the shell
    to its top face, `width` across its top face, and both side faces leaning `face-angle` degrees from the
    lifter's radial centre line (0: a rectangular bar), so the base is width + 2 height tan(face-angle) wide;
  * two flat end plates close the mill at y = +-L/2 (fans from the axis to the cross-section's outline).
Each shell arc between two lifters is split into `cells` panels. The cross-section's outline is star-shaped
about the axis, so the end-plate fans do not overlap. Every triangle's normal (right-hand rule on its corners)
points into the mill, where the particles are, and every edge is shared by exactly two triangles running it
in opposite directions (a closed, consistently oriented surface).

Prints the derived numbers (triangles, base width, the free volume inside the shell) as `key = value` lines.
"""
import argparse
import importlib.util
import math
import os
import pathlib

# the STL writer and triangle normals of the hopper example (standard library only, like this script)
_spec = importlib.util.spec_from_file_location(
    "make_hopper", pathlib.Path(__file__).resolve().parent.parent / "hopper" / "make_hopper.py")
_make_hopper = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_make_hopper)
normal, unit, write_stl = _make_hopper.normal, _make_hopper.unit, _make_hopper.write_stl


def lifter_outline(radius, height, width, face_angle_deg, centre_angle):
    """The four corners (x, z) of one lifter, in the order of increasing angle about the axis: base, top,
    top, base. The base corners lie on the shell circle, the top face is flat, `height` inside the shell
    along the lifter's centre line. Angles are measured from the bottom point (0, -radius) towards -x."""
    base_half = width / 2 + height * math.tan(math.radians(face_angle_deg))
    if base_half >= radius:
        raise SystemExit("the lifter is wider than the mill")
    base_along = math.sqrt(radius * radius - base_half * base_half)
    top_along = radius - height
    return [polar_to_xz(centre_angle, base_along, -base_half), polar_to_xz(centre_angle, top_along, -width / 2),
            polar_to_xz(centre_angle, top_along, width / 2), polar_to_xz(centre_angle, base_along, base_half)]


def polar_to_xz(angle, along, across):
    """Point `along` the radial direction at `angle` (from the bottom, towards -x) and `across` it (positive
    in the direction of increasing angle)."""
    radial = (-math.sin(angle), -math.cos(angle))
    tangent = (-math.cos(angle), math.sin(angle))
    return (along * radial[0] + across * tangent[0], along * radial[1] + across * tangent[1])


def angle_of(point):
    x, z = point
    return math.atan2(-x, -z)


def outline(radius, lifters, height, width, face_angle_deg, cells):
    """The mill's cross-section as a closed polygon (x, z), in the order of increasing angle."""
    points = []
    if lifters == 0:
        return [polar_to_xz(2 * math.pi * k / cells, radius, 0.0) for k in range(cells)]
    pitch = 2 * math.pi / lifters
    for k in range(lifters):
        corners = lifter_outline(radius, height, width, face_angle_deg, k * pitch)
        nxt = lifter_outline(radius, height, width, face_angle_deg, (k + 1) * pitch)
        points += corners
        start, end = angle_of(corners[3]), angle_of(nxt[0])
        if end <= start:
            end += 2 * math.pi
        if end - start <= 0:
            raise SystemExit("lifters overlap: fewer, narrower or lower lifters")
        points += [polar_to_xz(start + (end - start) * i / cells, radius, 0.0) for i in range(1, cells)]
    angles = [angle_of(p) % (2 * math.pi) for p in points]
    unwrapped = [(a - angles[0]) % (2 * math.pi) for a in angles]
    if any(b <= a for a, b in zip(unwrapped, unwrapped[1:])):
        raise SystemExit("the lifter profile is undercut (outline not star-shaped about the axis)")
    return points


def ring_of(radius, count, phase):
    return [polar_to_xz(phase + 2 * math.pi * k / count, radius, 0.0) for k in range(count)]


def signed_area(a, b, c):
    """Positive for corners that run with increasing angle about the axis, seen from the same side as the
    outline."""
    return ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2


def zip_rings(outer, inner):
    """Triangles (x, z) filling the band between two closed rings that both run with increasing angle: walking
    round both, each step closes a triangle on the outer or on the inner ring, whichever is not folded over
    (negative area); if both would do, the one with the shorter new edge."""
    base = angle_of(outer[0])
    shift = min(range(len(inner)), key=lambda k: abs(math.remainder(angle_of(inner[k]) - base, 2 * math.pi)))
    inner = inner[shift:] + inner[:shift]
    n, m = len(outer), len(inner)
    sign = 1.0 if signed_area(outer[0], outer[1 % n], (0.0, 0.0)) > 0 else -1.0
    tris, i, j = [], 0, 0
    while i < n or j < m:
        o0, o1, i0, i1 = outer[i % n], outer[(i + 1) % n], inner[j % m], inner[(j + 1) % m]
        outer_ok = i < n and sign * signed_area(o0, o1, i0) > 0
        inner_ok = j < m and sign * signed_area(o0, i1, i0) > 0
        if outer_ok and inner_ok:
            outer_ok = math.dist(o1, i0) <= math.dist(o0, i1)
        if outer_ok:
            tris.append((o0, o1, i0))
            i += 1
        elif inner_ok:
            tris.append((o0, i1, i0))
            j += 1
        else:
            raise SystemExit("cannot triangulate the end plate: make --cell smaller")
    return tris


def end_plate(ring, radius, height, cell):
    """The flat disc bounded by the outline `ring`, as triangles (x, z) of about `cell` across: a collar of the
    outline's own angles just inside the lifters' tips, then concentric circles of fewer points towards the
    axis, a fan at the centre."""
    r = radius - height - cell
    collar = [polar_to_xz(angle_of(p), r, 0.0) for p in ring]
    n = len(ring)
    tris = []
    for k in range(n):
        tris += [(ring[k], ring[(k + 1) % n], collar[k]), (ring[(k + 1) % n], collar[(k + 1) % n], collar[k])]
    outer, r = collar, r - cell
    while r > cell:
        inner = ring_of(r, max(6, int(round(2 * math.pi * r / cell))), angle_of(ring[0]))
        tris += zip_rings(outer, inner)
        outer, r = inner, r - cell
    tris += [(outer[k], outer[(k + 1) % len(outer)], (0.0, 0.0)) for k in range(len(outer))]
    return tris


def mill_triangles(D, L, lifters, height, width, face_angle_deg, cells, cell):
    """Triangles of the whole mill: the shell and lifters in panels of at most `cell` along the axis, the end
    plates in triangles of about `cell`. Normals point into the mill."""
    ring = outline(D / 2, lifters, height, width, face_angle_deg, cells)
    n = len(ring)
    slices = max(1, int(math.ceil(L / cell)))
    ys = [-L / 2 + L * i / slices for i in range(slices + 1)]
    tris = []
    for k in range(n):
        (xa, za), (xb, zb) = ring[k], ring[(k + 1) % n]
        for y0, y1 in zip(ys, ys[1:]):
            a0, b0, b1, a1 = (xa, y0, za), (xb, y0, zb), (xb, y1, zb), (xa, y1, za)
            # the outline runs with increasing angle (clockwise seen from +y): this corner order puts the
            # normals towards the axis
            tris += [(a0, b1, b0), (a0, a1, b1)]
    for y, inward in ((ys[0], 1.0), (ys[-1], -1.0)):
        for a, b, c in end_plate(ring, D / 2, height if lifters else 0.0, cell):
            tri = ((a[0], y, a[1]), (b[0], y, b[1]), (c[0], y, c[1]))
            if normal(*tri)[1] * inward < 0:
                tri = (tri[0], tri[2], tri[1])
            tris.append(tri)
    return tris, ring


def polygon_area(ring):
    return 0.5 * abs(sum(ring[k][0] * ring[(k + 1) % len(ring)][1] - ring[(k + 1) % len(ring)][0] * ring[k][1]
                         for k in range(len(ring))))


def add_arguments(parser):
    parser.add_argument("--D", type=float, default=0.3, help="shell diameter, m")
    parser.add_argument("--L", type=float, default=0.1, help="mill length (inside, between the end plates), m")
    parser.add_argument("--lifters", type=int, default=8, help="number of lifter bars (0: a plain drum)")
    parser.add_argument("--height", type=float, default=0.02, help="lifter height above the shell, m")
    parser.add_argument("--width", type=float, default=0.02, help="width of the lifter's top face, m")
    parser.add_argument("--face-angle", type=float, default=20.0,
                        help="lean of the lifter's side faces from its radial centre line, degrees")
    parser.add_argument("--cells", type=int, default=6, help="shell panels between two lifters")
    parser.add_argument("--cell", type=float, default=0.025,
                        help="size of the triangles along the axis and on the end plates, m (compact triangles "
                             "keep fix wall/polyhedral's candidate lists short)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_arguments(parser)
    parser.add_argument("--out", default="mesh/mill.stl")
    a = parser.parse_args()
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    tris, ring = mill_triangles(a.D, a.L, a.lifters, a.height, a.width, a.face_angle, a.cells, a.cell)
    write_stl(a.out, "mill", tris)
    print("triangles = %d" % len(tris))
    print("lifter_base_width = %.9g" % (a.width + 2 * a.height * math.tan(math.radians(a.face_angle))))
    print("free_volume = %.9g" % (polygon_area(ring) * a.L))


if __name__ == "__main__":
    main()
