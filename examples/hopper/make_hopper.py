#!/usr/bin/env python3
"""Writes the wedge hopper and its gate as ASCII STL files (metres) for in.hopper / in.hopper_spheres.

    python3 make_hopper.py [--Do 0.12] [--L 0.12] [--Wt 0.28] [--alpha 30] [--Hbin 0.25] [--outdir mesh]

Geometry (a planar wedge hopper with a slot outlet, symmetric about x = 0 and y = 0):
  * the outlet is the slot |x| <= Do/2, |y| <= L/2 in the plane z = 0;
  * two inclined walls at `alpha` degrees from the vertical run from the outlet edges x = +-Do/2 (z = 0) up to
    x = +-Wt/2 at z = Hw = (Wt - Do) / (2 tan alpha);
  * two vertical walls x = +-Wt/2 continue from Hw to Hw + Hbin (the bin, where the particles are inserted);
  * two end walls y = +-L/2 close the wedge and the bin (hexagons, split into triangles).
hopper.stl: every triangle's normal (right-hand rule on its corners) points into the hopper, where the
particles are, as fix wall/polyhedral wants; neighbouring triangles share their corners and run their shared
edges in opposite directions. gate.stl: a flat rectangle in z = 0, normal +z, closing the slot with a margin
of `--margin` (default Do/4) on every side, a mesh of its own so that the deck can remove it.

Prints the derived numbers (Hw, the wedge's volume) as `key = value` lines.
"""
import argparse
import math
import os


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def unit(n):
    s = math.sqrt(sum(x * x for x in n))
    return [x / s for x in n]


def facing(tri, inside):
    """The triangle with its corners ordered so that its normal points towards the point `inside`."""
    a, b, c = tri
    n = normal(a, b, c)
    centre = [(a[i] + b[i] + c[i]) / 3 for i in range(3)]
    if sum(n[i] * (inside[i] - centre[i]) for i in range(3)) < 0:
        return (a, c, b)
    return (a, b, c)


def write_stl(path, name, triangles):
    with open(path, "w") as f:
        f.write("solid %s\n" % name)
        for a, b, c in triangles:
            f.write("facet normal %.9g %.9g %.9g\nouter loop\n" % tuple(unit(normal(a, b, c))))
            for p in (a, b, c):
                f.write("vertex %.12g %.12g %.12g\n" % tuple(p))
            f.write("endloop\nendfacet\n")
        f.write("endsolid %s\n" % name)


def quad(p0, p1, p2, p3):
    return [(p0, p1, p2), (p0, p2, p3)]


def hopper(Do, L, Wt, alpha, Hbin):
    Hw = (Wt - Do) / (2 * math.tan(math.radians(alpha)))
    Ht = Hw + Hbin
    y0, y1 = -L / 2, L / 2
    tris = []
    for s in (-1, 1):                     # the inclined and the vertical wall on each side
        xo, xt = s * Do / 2, s * Wt / 2
        tris += quad((xo, y0, 0.0), (xo, y1, 0.0), (xt, y1, Hw), (xt, y0, Hw))
        tris += quad((xt, y0, Hw), (xt, y1, Hw), (xt, y1, Ht), (xt, y0, Ht))
    for y in (y0, y1):                    # end walls: hexagon outlet - wedge top - bin top, fan from the centre
        ring = [(-Do / 2, y, 0.0), (Do / 2, y, 0.0), (Wt / 2, y, Hw), (Wt / 2, y, Ht), (-Wt / 2, y, Ht),
                (-Wt / 2, y, Hw)]
        # a fan from the ring's corner (-Do/2, y, 0) keeps every corner on the ring (no new vertex)
        tris += [(ring[0], ring[i], ring[i + 1]) for i in range(1, len(ring) - 1)]
    inside = (0.0, 0.0, Hw / 2)
    tris = [facing(t, inside) for t in tris]
    return tris, Hw


def gate(Do, L, margin):
    x, y = Do / 2 + margin, L / 2 + margin
    return [facing(t, (0.0, 0.0, 1.0)) for t in quad((-x, -y, 0.0), (x, -y, 0.0), (x, y, 0.0), (-x, y, 0.0))]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--Do", type=float, default=0.12, help="outlet (slot) width, m")
    parser.add_argument("--L", type=float, default=0.12, help="hopper length (slot length), m")
    parser.add_argument("--Wt", type=float, default=0.28, help="width at the top of the wedge and of the bin, m")
    parser.add_argument("--alpha", type=float, default=30.0, help="wall angle from the vertical, degrees")
    parser.add_argument("--Hbin", type=float, default=0.25, help="height of the vertical bin above the wedge, m")
    parser.add_argument("--margin", type=float, default=None, help="gate overhang, m (default Do/4)")
    parser.add_argument("--outdir", default="mesh")
    a = parser.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    tris, Hw = hopper(a.Do, a.L, a.Wt, a.alpha, a.Hbin)
    write_stl(os.path.join(a.outdir, "hopper.stl"), "hopper", tris)
    write_stl(os.path.join(a.outdir, "gate.stl"), "gate", gate(a.Do, a.L, a.Do / 4 if a.margin is None else a.margin))
    print("Hw = %.9g" % Hw)
    print("wedge_volume = %.9g" % ((a.Do + a.Wt) / 2 * Hw * a.L))
    print("triangles = %d" % len(tris))


if __name__ == "__main__":
    main()
