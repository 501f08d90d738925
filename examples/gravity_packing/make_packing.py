#!/usr/bin/env python3
"""Initial state of the gravity-packing benchmark: LIGGGHTS data files for in.packing and in.packing_spheres.

    python3 make_packing.py [N] [--layers NZ] [--seed S] [--outdir data] [--floor particles|none]

writes, for N falling particles (default 2000),

    data/packing_N<N>.data   atom_style polyhedron: Schoenhardt polyhedra (shape 1), random orientations
    data/spheres_N<N>.data   atom_style granular: spheres of the same volume, same positions and velocities

Scene (document 000, sec. 7.1 and table A.3, scaled to N):
  * particles of volume-equivalent diameter D = 20 mm, density 2500 kg/m^3 (neither is given in table A.3);
  * a square lattice of nx x ny x nz sites, periodic in x and y. By default the lattice keeps the
    169 x 169 x 35 proportions of table A.3 (nz = round(35 (N / 169^2 35)^(1/3)), nx = ny = ceil(sqrt(N / nz)),
    the top layer filled partly so that there are exactly N particles); N = 999635 gives table A.3's grid;
  * lattice spacing a = 1.05 bounding diameters of the polyhedron (1.956 D), each site jittered by less than
    half the gap, so no two bounding spheres touch whatever the orientations;
  * all particles move down at V0 = 3.92 m/s (the speed after the 0.4 s free fall to the first impact of
    table A.3) plus a uniform random +-0.1 m/s in each component; no initial spin. The free fall before the
    first impact (40000 contact-free steps in document 000) is skipped: the lowest layer starts half a
    spacing above the floor;
  * the floor (type 2, the "W" material of table A.3) is a square lattice of fixed particles of the same kind,
    spacing Lx / ceil(Lx / D) <= D, tops at z = 0: upright Schoenhardt polyhedra (3-fold axis vertical) under
    the polyhedra, spheres under the spheres. Floor particles overlap their neighbours; the decks exclude
    floor-floor pairs. `--floor none` leaves the floor out and writes data/packing_N<N>_nofloor.data and
    data/spheres_N<N>_nofloor.data, for the plane wall at z = 0 of the decks' `-var wall 1`.

Standard library only, so it runs on a bare GPU host. The box: x, y in [0, Lx], [0, Ly]; z from -2 D to
the top of the lattice plus one spacing.
"""
import argparse
import math
import os
import random

D = 0.02                      # volume-equivalent diameter (m)
DENSITY = 2500.0              # kg/m^3
SCHOENHARDT_VOLUME = 0.288675134595   # examples/shapes/schoenhardt.stl (edge 1, height 1), file units
SCALE = D / (6.0 * SCHOENHARDT_VOLUME / math.pi) ** (1.0 / 3.0)   # scale for the template: volume pi/6 D^3
BOUNDING_RADIUS = SCALE * math.sqrt(1.0 / 3.0 + 0.25)   # vertices at circumradius 1/sqrt(3), height +-1/2
SPACING = 1.05 * 2.0 * BOUNDING_RADIUS                   # lattice spacing of the falling particles
V0 = 3.92                     # m/s: g * 0.4 s, the speed of the first impacts of table A.3
DV = 0.1                      # m/s: random part of each velocity component
A3_GRID = (169, 169, 35)      # table A.3
UPRIGHT = (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0)   # body x (the 3-fold axis, smallest moment) to world z


def lattice_shape(n, layers=None):
    if layers is None:
        total = A3_GRID[0] * A3_GRID[1] * A3_GRID[2]
        layers = max(1, int(round(A3_GRID[2] * (n / total) ** (1.0 / 3.0))))
    side = int(math.ceil(math.sqrt(n / layers)))
    layers = int(math.ceil(n / (side * side)))   # no empty top layer
    return side, side, layers


def random_quaternion(rng):
    """Uniform random rotation (Shoemake)."""
    u1, u2, u3 = rng.random(), rng.random(), rng.random()
    a, b = math.sqrt(1.0 - u1), math.sqrt(u1)
    return (b * math.cos(2 * math.pi * u3), a * math.sin(2 * math.pi * u2),
            a * math.cos(2 * math.pi * u2), b * math.sin(2 * math.pi * u3))


def falling_particles(n, nx, ny, nz, rng):
    """[(x, y, z, quaternion, velocity)] on the lattice, layer by layer from the bottom."""
    jitter = 0.45 * (SPACING - 2.0 * BOUNDING_RADIUS)
    z0 = BOUNDING_RADIUS + 0.5 * SPACING   # lowest centres: half a spacing above the floor tops (z = 0)
    particles = []
    for k in range(nz):
        for i in range(nx):
            for j in range(ny):
                if len(particles) == n:
                    return particles
                pos = ((i + 0.5) * SPACING + rng.uniform(-jitter, jitter),
                       (j + 0.5) * SPACING + rng.uniform(-jitter, jitter),
                       z0 + k * SPACING + rng.uniform(-jitter, jitter))
                vel = (rng.uniform(-DV, DV), rng.uniform(-DV, DV), -V0 + rng.uniform(-DV, DV))
                particles.append((pos, random_quaternion(rng), vel))
    return particles


# ---------------------------------------------------------------- floor
# Everything about the floor is here and in the FLOOR block of the decks; `--floor none` with the decks'
# `-var wall 1` puts a plane wall at z = 0 in its place (fix wall/polyhedral, fix wall/gran).

def floor_sites(lx, ly):
    """Square lattice of floor sites covering the periodic box; spacing <= D."""
    mx, my = int(math.ceil(lx / D)), int(math.ceil(ly / D))
    bx, by = lx / mx, ly / my
    return [((i + 0.5) * bx, (j + 0.5) * by) for i in range(mx) for j in range(my)], (bx, by)


def floor_polyhedra(lx, ly):
    """Upright Schoenhardt polyhedra, tops (height SCALE) at z = 0."""
    sites, spacing = floor_sites(lx, ly)
    return [((x, y, -0.5 * SCALE), UPRIGHT) for x, y in sites], spacing


def floor_spheres(lx, ly):
    """Spheres of diameter D, tops at z = 0."""
    sites, spacing = floor_sites(lx, ly)
    return [(x, y, -0.5 * D) for x, y in sites], spacing

# ---------------------------------------------------------------- files


def header(title, count, lx, ly, zhi):
    return ("LIGGGHTS data file: %s\n\n%d atoms\n2 atom types\n\n"
            "0 %.17g xlo xhi\n0 %.17g ylo yhi\n%.17g %.17g zlo zhi\n\n" % (title, count, lx, ly, -2.0 * D, zhi))


def write_polyhedra(path, particles, floor, lx, ly, zhi, comment):
    with open(path, "w") as out:
        out.write(header("gravity packing, Schoenhardt polyhedra; " + comment, len(particles) + len(floor),
                         lx, ly, zhi))
        # atom-ID atom-type shape density x y z quatw quati quatj quatk
        out.write("Atoms\n\n")
        lines = []
        for n, (pos, q, _) in enumerate(particles):
            lines.append("%d 1 1 %g %.9g %.9g %.9g %.9f %.9f %.9f %.9f\n" % ((n + 1, DENSITY) + pos + q))
        for m, (pos, q) in enumerate(floor):
            lines.append("%d 2 1 %g %.9g %.9g %.9g %.9f %.9f %.9f %.9f\n"
                         % ((len(particles) + m + 1, DENSITY) + pos + q))
        out.write("".join(lines))
        # atom-ID vx vy vz Lx Ly Lz
        out.write("\nVelocities\n\n")
        lines = ["%d %.6f %.6f %.6f 0 0 0\n" % ((n + 1,) + vel) for n, (_, _, vel) in enumerate(particles)]
        lines += ["%d 0 0 0 0 0 0\n" % (len(particles) + m + 1) for m in range(len(floor))]
        out.write("".join(lines))


def write_spheres(path, particles, floor, lx, ly, zhi, comment):
    with open(path, "w") as out:
        out.write(header("gravity packing, spheres; " + comment, len(particles) + len(floor), lx, ly, zhi))
        # atom-ID atom-type diameter density x y z
        out.write("Atoms\n\n")
        lines = ["%d 1 %g %g %.9g %.9g %.9g\n" % ((n + 1, D, DENSITY) + pos)
                 for n, (pos, _, _) in enumerate(particles)]
        lines += ["%d 2 %g %g %.9g %.9g %.9g\n" % ((len(particles) + m + 1, D, DENSITY) + pos)
                  for m, pos in enumerate(floor)]
        out.write("".join(lines))
        # atom-ID vx vy vz wx wy wz
        out.write("\nVelocities\n\n")
        lines = ["%d %.6f %.6f %.6f 0 0 0\n" % ((n + 1,) + vel) for n, (_, _, vel) in enumerate(particles)]
        lines += ["%d 0 0 0 0 0 0\n" % (len(particles) + m + 1) for m in range(len(floor))]
        out.write("".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("N", nargs="?", type=int, default=2000, help="number of falling particles")
    parser.add_argument("--layers", type=int, default=None, help="lattice layers (default: table A.3 proportions)")
    parser.add_argument("--seed", type=int, default=20200601)
    parser.add_argument("--outdir", default="data")
    parser.add_argument("--floor", choices=["particles", "none"], default="particles")
    args = parser.parse_args()

    nx, ny, nz = lattice_shape(args.N, args.layers)
    rng = random.Random(args.seed)
    particles = falling_particles(args.N, nx, ny, nz, rng)
    lx, ly = nx * SPACING, ny * SPACING
    zhi = max(p[0][2] for p in particles) + SPACING
    if args.floor == "particles":
        floor_p, spacing = floor_polyhedra(lx, ly)
        floor_s, _ = floor_spheres(lx, ly)
    else:
        floor_p, floor_s, spacing = [], [], (0.0, 0.0)
    comment = ("N %d lattice %d x %d x %d spacing %.6g D %g scale %.9g floor %d (spacing %.6g) seed %d"
               % (args.N, nx, ny, nz, SPACING, D, SCALE, len(floor_p), spacing[0], args.seed))
    os.makedirs(args.outdir, exist_ok=True)
    suffix = "" if args.floor == "particles" else "_nofloor"
    poly_path = os.path.join(args.outdir, "packing_N%d%s.data" % (args.N, suffix))
    sphere_path = os.path.join(args.outdir, "spheres_N%d%s.data" % (args.N, suffix))
    write_polyhedra(poly_path, particles, floor_p, lx, ly, zhi, comment)
    write_spheres(sphere_path, particles, floor_s, lx, ly, zhi, comment)
    print("%s, %s: %s; box %.4f x %.4f x %.4f m" % (poly_path, sphere_path, comment, lx, ly, zhi + 2.0 * D))


if __name__ == "__main__":
    main()
