#!/usr/bin/env python3
"""Writes the calibration rig of document 000, sec. 6.3, as ASCII STL files (metres) for in.rig.

    python3 make_rig.py [--scale 1] [--Hbin 0.165] [--outdir mesh]

The rig is a channel of width W (y in [0, W], closed by the plane walls y = 0 and y = W of the deck), seen
from the side (x horizontal, z up):

  * bottom plate z = 0 from the back wall x = 0 to the end wall x = Lp (plane walls of the deck, not meshes);
  * tilted plane: a slab `plate_t` thick whose top face rises at `theta` degrees from its lower lip
    (x_lip, z_lip) over a length Lt in +x; the rocks slide down it towards the back wall and drop off the lip
    into the corner, where the heap forms and spreads in +x;
  * hopper: a wedge with a slot outlet of width Do at height z_out, centred at x = xh above the tilted plane,
    walls at `alpha` degrees from the vertical up to the width Wt, then a vertical bin Hbin high;
  * two trap doors closing the outlet, hinged at its edges x = xh -+ Do/2, each Do/2 wide; the deck swings
    them down about their hinges (fix move/mesh rotate) to open the hopper.

Every triangle's normal points to where the rocks are (into the hopper, up from the doors, out of the slab)
as fix wall/polyhedral wants. Every length is the default times --scale; table A.2 of document 000 gives the
materials but not the rig's dimensions, so these are chosen here: about 150 rocks of 5-10 mm at scale 1
(the bin's default height is what run.py makes for 150 rocks).
Prints the derived positions as `key = value` lines (in.rig's -var values).
"""
import argparse
import math
import os
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "hopper"))
from make_hopper import facing, quad, write_stl  # noqa: E402

DEFAULTS = dict(W=0.045, Lp=0.30, x_lip=0.03, z_lip=0.09, theta=45.0, Lt=0.16, plate_t=0.015,
                xh=0.10, Do=0.04, Wt=0.10, alpha=30.0, z_out=0.21, Hbin=0.165)
ANGLES = ("theta", "alpha")


def rig_dimensions(scale=1.0, **overrides):
    """The rig's dimensions (metres, degrees) and the derived heights, from DEFAULTS, overrides and scale."""
    dims = dict(DEFAULTS, **{k: v for k, v in overrides.items() if v is not None})
    dims = {k: (v if k in ANGLES else v * scale) for k, v in dims.items()}
    dims["Hw"] = (dims["Wt"] - dims["Do"]) / (2 * math.tan(math.radians(dims["alpha"])))
    t = math.radians(dims["theta"])
    dims["x_top"] = dims["x_lip"] + dims["Lt"] * math.cos(t)
    dims["z_top"] = dims["z_lip"] + dims["Lt"] * math.sin(t)
    dims["z_bin"] = dims["z_out"] + dims["Hw"]
    dims["z_roof"] = dims["z_bin"] + dims["Hbin"]
    hinge_right = dims["xh"] + dims["Do"] / 2
    plane_under_door = dims["z_lip"] + (hinge_right - dims["x_lip"]) * math.tan(t)
    if dims["z_out"] - dims["Do"] / 2 <= plane_under_door:
        raise SystemExit("an open door would reach into the tilted plane: raise z_out")
    if not dims["x_lip"] < dims["xh"] - dims["Wt"] / 2 or dims["x_top"] < hinge_right:
        raise SystemExit("the tilted plane must run from left of the hopper to under its right door")
    return dims


def hopper(d):
    """Two inclined walls and the two vertical walls of the bin; the channel's side walls close the ends."""
    tris = []
    y0, y1 = 0.0, d["W"]
    for s in (-1, 1):
        xo, xt = d["xh"] + s * d["Do"] / 2, d["xh"] + s * d["Wt"] / 2
        tris += quad((xo, y0, d["z_out"]), (xo, y1, d["z_out"]), (xt, y1, d["z_bin"]), (xt, y0, d["z_bin"]))
        tris += quad((xt, y0, d["z_bin"]), (xt, y1, d["z_bin"]), (xt, y1, d["z_roof"]), (xt, y0, d["z_roof"]))
    inside = (d["xh"], d["W"] / 2, d["z_bin"])
    return [facing(t, inside) for t in tris]


def door(d, side):
    """The closed door on `side` (-1 left, +1 right): from its hinge to the outlet's centre, normal +z."""
    x_hinge = d["xh"] + side * d["Do"] / 2
    z = d["z_out"]
    rect = quad((x_hinge, 0.0, z), (d["xh"], 0.0, z), (d["xh"], d["W"], z), (x_hinge, d["W"], z))
    return [facing(t, (d["xh"], d["W"] / 2, z + 1.0)) for t in rect]


def tilted_plane(d):
    """A closed slab, normals outwards: the rocks slide on its top face, and one that touches its underside
    or its lip from below is pushed out of the slab, not through it."""
    t = math.radians(d["theta"])
    along = (math.cos(t), math.sin(t))
    down = (math.sin(t) * d["plate_t"], -math.cos(t) * d["plate_t"])   # from the top face into the slab
    lip = (d["x_lip"], d["z_lip"])
    top = (lip[0] + d["Lt"] * along[0], lip[1] + d["Lt"] * along[1])
    corners = [lip, top, (top[0] + down[0], top[1] + down[1]), (lip[0] + down[0], lip[1] + down[1])]
    y0, y1 = 0.0, d["W"]
    front = [(x, y0, z) for x, z in corners]
    back = [(x, y1, z) for x, z in corners]
    tris = []
    for i in range(4):
        j = (i + 1) % 4
        tris += quad(front[i], front[j], back[j], back[i])
    tris += quad(*front) + quad(*back)
    centre = [sum(p[k] for p in front + back) / 8 for k in range(3)]
    outward = []
    for a, b, c in tris:
        mid = [(a[k] + b[k] + c[k]) / 3 for k in range(3)]
        away = [2 * mid[k] - centre[k] for k in range(3)]   # a point outside, beyond the face's centre
        outward.append(facing((a, b, c), away))
    return outward


def write_rig(dims, outdir):
    os.makedirs(outdir, exist_ok=True)
    write_stl(os.path.join(outdir, "hopper.stl"), "hopper", hopper(dims))
    write_stl(os.path.join(outdir, "door_left.stl"), "door_left", door(dims, -1))
    write_stl(os.path.join(outdir, "door_right.stl"), "door_right", door(dims, +1))
    write_stl(os.path.join(outdir, "plane.stl"), "plane", tilted_plane(dims))


def write_rock_20(outdir):
    """rock_20.obj: the rock of examples/shapes at 12 directions, by tools/make_shapes.py's own functions."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
    import make_shapes
    vertices, triangles = make_shapes.rock_mesh(12)
    assert len(triangles) == 20
    make_shapes.write_obj(os.path.join(outdir, "rock_20.obj"),
                          f"non-convex rock, seed {make_shapes.ROCK_SEED}, volume pi/6", vertices, triangles)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scale", type=float, default=1.0, help="multiplies every length")
    for key, value in DEFAULTS.items():
        parser.add_argument("--" + key, type=float, default=None, help="default %g" % value)
    parser.add_argument("--outdir", default="mesh")
    parser.add_argument("--rock20", action="store_true", help="also write rock_20.obj into outdir")
    a = parser.parse_args()
    dims = rig_dimensions(a.scale, **{k: getattr(a, k) for k in DEFAULTS})
    write_rig(dims, a.outdir)
    if a.rock20:
        write_rock_20(a.outdir)
    for key in sorted(dims):
        print("%s = %.9g" % (key, dims[key]))


if __name__ == "__main__":
    main()
