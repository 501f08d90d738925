#!/usr/bin/env python3
"""Tumbling mill with lifters, charged with rock polyhedra and with LIGGGHTS' Hertz spheres of equal volume:
writes the mill mesh, runs in.mill and in.mill_spheres side by side, then report.py. See doc/mill.md.

    /usr/bin/python3 run.py [--J 0.3] [--speed 0.75] [--revs 2.5] [--out post]

The charge: N particles (default: enough for a bed filling --J of the mill's free volume at a solids fraction
--phi); the spheres get the same N. Insertion is in rounds into the part of the mill above the settled bed's
estimated top (a circular segment of area J pi R^2), because the mill cannot take N non-overlapping bounding
spheres at once; --rounds is sized from that region's capacity (fix insert/pack reaches about 35 % of bounding
sphere volume). The rock run uses --np MPI ranks (mpirun), the sphere run one.

--launcher runs the rocks (default ../../build/bin/liggghts-poly), --liggghts the spheres (default Debian's
`liggghts` when on PATH, else the launcher); screen output is discarded (not `-screen none`: LIGGGHTS 3.8
crashes reading an STL without a screen). Output in OUT: mesh/mill.stl, log.mill_rock, log.mill_spheres,
post/*.dump, and report.py's report.md and PNG plots.
"""
import argparse
import concurrent.futures
import importlib.util
import math
import os
import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
import make_mill  # noqa: E402

_spec = importlib.util.spec_from_file_location("hopper_run", ROOT / "examples" / "hopper" / "run.py")
hopper_run = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hopper_run)

INSERT_PACKING = 0.35   # bounding-sphere volume fraction that fix insert/pack reaches in one round


def segment_top(R, J):
    """Height z of the flat top of a circular segment (the bottom of a circle of radius R about the origin)
    whose area is J pi R^2."""
    lo, hi = 0.0, math.pi              # half-angle of the segment, seen from the centre
    for _ in range(60):
        psi = (lo + hi) / 2
        if (2 * psi - math.sin(2 * psi)) / (2 * math.pi) < J:
            lo = psi
        else:
            hi = psi
    return -R * math.cos((lo + hi) / 2)


def charge(a):
    """N, bounding radius, insertion cut and rounds for the options."""
    rb_rock = hopper_run.bounding_radius(ROOT / "examples" / "shapes" / a.shape) * a.d
    R = a.D / 2
    tris, ring = make_mill.mill_triangles(a.D, a.L, a.lifters, a.height, a.width, a.face_angle, a.cells, a.cell)
    free_volume = make_mill.polygon_area(ring) * a.L
    particle_volume = math.pi / 6 * a.d ** 3
    N = a.N or int(round(a.J * free_volume * a.phi / particle_volume))
    zcut = segment_top(R - a.height / 2, a.J) + rb_rock
    # capacity of one round: the centres' region (inside the lifter tips less rb, above zcut) at INSERT_PACKING
    r_in = R - a.height - 0.002 - rb_rock
    if zcut >= r_in:
        raise SystemExit("no room above the bed for the insertion: smaller --J")
    psi = math.acos(max(-1.0, zcut / r_in))
    cap_area = r_in ** 2 * (psi - math.sin(psi) * math.cos(psi))
    capacity = INSERT_PACKING * cap_area * (a.L - 2 * rb_rock) / (4 / 3 * math.pi * rb_rock ** 3)
    rounds = a.rounds or min(11, int(math.ceil(N / max(capacity, 1.0))) + 2)
    return dict(N=N, rb=rb_rock, zcut=zcut, rounds=rounds, free_volume=free_volume, tris=tris,
                capacity=capacity)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    make_mill.add_arguments(p)
    p.add_argument("--N", type=int, default=0, help="particles (default: from --J and --phi)")
    p.add_argument("--J", type=float, default=0.3, help="fraction of the mill's free volume the bed fills")
    p.add_argument("--phi", type=float, default=0.6, help="solids fraction of the bed assumed for N")
    p.add_argument("--shape", default="rock_40.obj")
    p.add_argument("--d", type=float, default=0.025, help="volume-equivalent diameter, m")
    p.add_argument("--rho", type=float, default=2700.0)
    p.add_argument("--speed", type=float, default=0.75, help="fraction of the critical speed")
    p.add_argument("--revs", type=float, default=2.5, help="mill revolutions")
    p.add_argument("--E", type=float, default=1e7)
    p.add_argument("--mu", type=float, default=0.5)
    p.add_argument("--dt", type=float, default=1e-4)
    p.add_argument("--rounds", type=int, default=0, help="insertion rounds (default: from the capacity, at most 11)")
    p.add_argument("--round", type=float, default=0.2, help="s per insertion round")
    p.add_argument("--settle", type=float, default=0.3, help="s of settling before the mill turns")
    p.add_argument("--M", type=int, default=50, help="thermo output every M steps")
    p.add_argument("--S", type=int, default=500, help="positions dumped every S steps while the mill turns")
    p.add_argument("--np", type=int, default=1,
                   help="MPI ranks of the rock run (on a busy 2-core machine 2 ranks are slower than 1)")
    a, out = hopper_run.parse_runner_arguments(p, HERE)
    c = charge(a)
    make_mill.write_stl(out / "mesh" / "mill.stl", "mill", c["tris"])
    common = ["-var", "N", c["N"], "-var", "d", a.d, "-var", "rho", a.rho, "-var", "D", a.D, "-var", "L", a.L,
              "-var", "h", a.height if a.lifters else 0.0, "-var", "zcut", c["zcut"], "-var", "speed", a.speed,
              "-var", "revs", a.revs, "-var", "E", a.E, "-var", "mu", a.mu, "-var", "dt", a.dt,
              "-var", "rounds", c["rounds"], "-var", "round", a.round, "-var", "settle", a.settle,
              "-var", "M", a.M, "-var", "S", a.S, "-var", "MESH", "mesh"]
    common = [repr(x) if isinstance(x, float) else str(x) for x in common]
    mill_geometry = ["--D", a.D, "--L", a.L, "--lifters", a.lifters, "--height", a.height, "--width", a.width,
                     "--face-angle", a.face_angle, "--cells", a.cells]
    jobs = []
    if a.skip != "rock":
        mpi = ["mpirun", "-np", str(a.np)] if a.np > 1 else []
        suffix = ["-suffix", a.suffix] if a.suffix else []
        jobs.append((mpi + [a.launcher] + suffix + ["-in", str(HERE / "in.mill")] + common +
                     ["-var", "rb", repr(c["rb"]), "-var", "shape", a.shape,
                      "-var", "SHAPES", str(ROOT / "examples" / "shapes"), "-log", "log.mill_rock"], "log.mill_rock"))
    if a.skip != "spheres":
        jobs.append(([a.liggghts, "-in", str(HERE / "in.mill_spheres")] + common + ["-log", "log.mill_spheres"],
                     "log.mill_spheres"))
    print("charge: N %d, d %.4g m, bounding radius %.4g m, insertion above z = %.4g m, about %.0f per round, "
          "%d rounds; mill %d triangles, free volume %.4g m^3" % (c["N"], a.d, c["rb"], c["zcut"], c["capacity"],
                                                               c["rounds"], len(c["tris"]), c["free_volume"]))
    for command, _ in jobs:
        print("$ (cd %s && %s)" % (out, " ".join(command)))
    sys.stdout.flush()
    with concurrent.futures.ThreadPoolExecutor(max(1, a.jobs)) as pool:
        for log, seconds in pool.map(lambda j: hopper_run.run(j[0], out, j[1]), jobs):
            print("%s: %.1f s wall" % (log, seconds))
    if not a.no_report:
        sys.stdout.flush()
        subprocess.run([sys.executable, str(HERE / "report.py"), str(out)] + [str(x) for x in mill_geometry],
                       check=True)


if __name__ == "__main__":
    main()
