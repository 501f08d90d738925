#!/usr/bin/env python3
"""A large packed bed from a small settled one: copies a final dump of the gravity-packing decks side by side.

    python3 tile_bed.py post/final_packing_N10115_plane.dump 10 --outdir data
    python3 tile_bed.py post/final_spheres_N10115_plane.dump 10 --outdir data

The decks are periodic in x and y, so a settled bed of box Lx x Ly tiled T x T times is a settled bed of
box T Lx x T Ly with no seams: each copy's particles touch the next copy's as they touched their own
periodic images. The copies start at rest (no Velocities section), which is what a packed bed under gravity
is up to the small residual motion of the settling run.

Input: the last snapshot of a `dump final` of in.packing (columns id type x y z c_orient[1..4]) or of
in.packing_spheres (id type x y z radius). Output, for the T^2 n particles of type 1 (floor particles of
type 2 are copied too):

    data/packing_N<T^2 n>_nofloor.data   (from a polyhedron dump) or
    data/spheres_N<T^2 n>_nofloor.data   (from a sphere dump)

named so that the decks' `-var N <T^2 n> -var wall 1` read them. The z extent of the box is the dump's.
Standard library only, so it runs on a bare GPU host.
"""
import argparse
import os

DENSITY = 2500.0   # make_packing.py's density


def last_snapshot(path):
    with open(path) as stream:
        lines = stream.read().splitlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    bounds = max(i for i, line in enumerate(lines[:start]) if line.startswith("ITEM: BOX BOUNDS"))
    box = [tuple(float(v) for v in lines[bounds + 1 + k].split()[:2]) for k in range(3)]
    columns = lines[start].split()[2:]
    rows = [line.split() for line in lines[start + 1:] if line and not line.startswith("ITEM")]
    return box, columns, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dump", help="final dump of in.packing or in.packing_spheres (plane floor)")
    parser.add_argument("tiles", type=int, help="copies along x and along y")
    parser.add_argument("--outdir", default="data")
    args = parser.parse_args()

    box, columns, rows = last_snapshot(args.dump)
    polyhedra = "c_orient[1]" in columns
    if not polyhedra and "radius" not in columns:
        raise SystemExit("%s: neither c_orient[1..4] (in.packing) nor radius (in.packing_spheres) columns" % args.dump)
    col = {name: columns.index(name) for name in columns}
    (xlo, xhi), (ylo, yhi), (zlo, zhi) = box
    lx, ly = xhi - xlo, yhi - ylo
    tiles = args.tiles
    moving = sum(1 for row in rows if row[col["type"]] == "1")
    count = tiles * tiles * len(rows)
    n_moving = tiles * tiles * moving

    lines = []
    atom_id = 0
    for a in range(tiles):
        for b in range(tiles):
            for row in rows:
                atom_id += 1
                x = float(row[col["x"]]) + a * lx
                y = float(row[col["y"]]) + b * ly
                z = row[col["z"]]
                if polyhedra:
                    # atom-ID atom-type shape density x y z quatw quati quatj quatk
                    quat = " ".join(row[col["c_orient[%d]" % k]] for k in range(1, 5))
                    lines.append("%d %s 1 %g %.9g %.9g %s %s\n" % (atom_id, row[col["type"]], DENSITY, x, y, z, quat))
                else:
                    # atom-ID atom-type diameter density x y z
                    diameter = 2.0 * float(row[col["radius"]])
                    lines.append("%d %s %.9g %g %.9g %.9g %s\n" % (atom_id, row[col["type"]], diameter, DENSITY,
                                                                    x, y, z))
    kind = "packing" if polyhedra else "spheres"
    os.makedirs(args.outdir, exist_ok=True)
    path = os.path.join(args.outdir, "%s_N%d_nofloor.data" % (kind, n_moving))
    with open(path, "w") as out:
        out.write("LIGGGHTS data file: gravity packing, %s; %d x %d copies of the settled bed %s\n\n"
                  % (kind, tiles, tiles, os.path.basename(args.dump)))
        out.write("%d atoms\n2 atom types\n\n" % count)
        out.write("%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n%.17g %.17g zlo zhi\n\n"
                  % (xlo, xlo + tiles * lx, ylo, ylo + tiles * ly, zlo, zhi))
        out.write("Atoms\n\n")
        out.write("".join(lines))
    print("%s: %d particles (%d moving), box %.4f x %.4f x %.4f m" % (path, count, n_moving, tiles * lx, tiles * ly,
                                                                      zhi - zlo))


if __name__ == "__main__":
    main()
