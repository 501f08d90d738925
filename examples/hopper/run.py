#!/usr/bin/env python3
"""Hopper discharge of rock polyhedra and of LIGGGHTS' Hertz spheres of equal volume: writes the meshes, runs
in.hopper and in.hopper_spheres side by side, then report.py. See doc/hopper.md.

    /usr/bin/python3 run.py [--N 300] [--out post] [--jobs 2]

Sizes (all in volume-equivalent diameters d of the rock, default d = 0.02 m): outlet slot width --Do 6 d,
length --L 6 d, top width of the wedge --Wt 14 d, walls at --alpha 30 degrees from the vertical. The bin above
the wedge, where insert/pack places the particles (bounding spheres inside the region and not overlapping), is
made tall enough for N bounding spheres of the rock at a volume fraction of --fill (0.35) of the region that
their centres can reach; the spheres go into the same region. The catch floor lies 0.3 m below the outlet, deeper
for large N. The run has --settle s of filling and settling with the gate closed, then --discharge s after the
gate is removed.

--launcher runs the rocks (default ../../build/bin/liggghts-poly), --liggghts the spheres (default Debian's
`liggghts` when on PATH, else the launcher); their screen output is discarded (not `-screen none`: LIGGGHTS
3.8 crashes reading an STL without a screen). Output in OUT: mesh/, log.hopper_rock, log.hopper_spheres, the
settled fills (post/*_release.dump), and report.py's report.md and hopper_discharge.png.
"""
import argparse
import concurrent.futures
import math
import os
import pathlib
import shutil
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT / "tools"))
import make_hopper  # noqa: E402
import shape_files  # noqa: E402

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def read_obj(path):
    """Vertices and triangles of a shape file (tools/shape_files.py; OBJ, OFF or STL)."""
    return shape_files.read_mesh(path)


def bounding_radius(path):
    """Largest distance of a vertex from the centre of mass (file units), as the template computes it."""
    vertices, triangles = shape_files.read_mesh(path)
    _, centre, _ = shape_files.mass_properties(vertices, triangles)
    return shape_files.bounding_radius(vertices, centre)


def geometry(a):
    d = a.d
    rb = bounding_radius(ROOT / "examples" / "shapes" / a.shape) * d
    Do, L, Wt = a.Do * d, a.L * d, a.Wt * d
    area = (Wt - 2 * rb) * (L - 2 * rb)
    if area <= 0:
        raise SystemExit("the bin is narrower than a particle's bounding sphere")
    Hbin = 2 * rb + a.N * 4 / 3 * math.pi * rb ** 3 / (a.fill * area)
    Hw = (Wt - Do) / (2 * math.tan(math.radians(a.alpha)))
    # catch basin: the box's floor area is (Wt + 0.1)(L + 0.1); room for a heap three times its mean height
    heap = a.N * math.pi / 6 * d ** 3 / 0.6 / ((Wt + 0.1) * (L + 0.1))
    catch = max(0.3, 0.1 + 3 * heap)
    return dict(d=d, Do=Do, L=L, Wt=Wt, Hbin=Hbin, Hw=Hw, catch=catch, rb=rb)


def run(command, cwd, log):
    start = time.time()
    result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, env=dict(os.environ, **MPI_ENV),
                            errors="backslashreplace")
    if result.returncode != 0:
        raise SystemExit("%s failed (%d):\n%s" % (" ".join(command), result.returncode,
                                                  (result.stdout + result.stderr)[-3000:]))
    return log, time.time() - start


def parse_runner_arguments(p, here):
    """The options every rocks-and-spheres example shares (jobs, skip, launchers, output, report); parses the
    command line and makes OUT/mesh. Returns the arguments and OUT."""
    p.add_argument("--jobs", type=int, default=2, help="run rocks and spheres side by side (2) or in turn (1)")
    p.add_argument("--skip", choices=["rock", "spheres"], default=None, help="leave one of the runs out")
    p.add_argument("--launcher", default=str(ROOT / "build" / "bin" / "liggghts-poly"))
    p.add_argument("--liggghts", default=shutil.which("liggghts"))
    p.add_argument("--suffix", default=None, help="run the rocks with -suffix SUFFIX (gpu: on the GPU)")
    p.add_argument("--out", default=str(here / "post"))
    p.add_argument("--no-report", action="store_true")
    a = p.parse_args()
    a.liggghts = a.liggghts or a.launcher
    out = pathlib.Path(a.out).resolve()
    (out / "mesh").mkdir(parents=True, exist_ok=True)
    return a, out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--N", type=int, default=300)
    p.add_argument("--shape", default="rock_40.obj")
    p.add_argument("--d", type=float, default=0.02, help="volume-equivalent diameter, m")
    p.add_argument("--Do", type=float, default=6.0, help="outlet width / d")
    p.add_argument("--L", type=float, default=6.0, help="hopper (slot) length / d")
    p.add_argument("--Wt", type=float, default=14.0, help="top width / d")
    p.add_argument("--alpha", type=float, default=30.0, help="wall angle from the vertical, degrees")
    p.add_argument("--fill", type=float, default=0.35, help="bounding-sphere volume fraction of the insertion")
    p.add_argument("--settle", type=float, default=0.45, help="s before the release")
    p.add_argument("--discharge", type=float, default=0.6, help="s after the release")
    p.add_argument("--dt", type=float, default=1e-4)
    p.add_argument("--E", type=float, default=1e7)
    p.add_argument("--M", type=int, default=100, help="thermo output every M steps")
    a, out = parse_runner_arguments(p, HERE)
    g = geometry(a)
    tris, _ = make_hopper.hopper(g["Do"], g["L"], g["Wt"], a.alpha, g["Hbin"])
    make_hopper.write_stl(out / "mesh" / "hopper.stl", "hopper", tris)
    make_hopper.write_stl(out / "mesh" / "gate.stl", "gate", make_hopper.gate(g["Do"], g["L"], g["Do"] / 4))
    common = ["-var", "N", a.N, "-var", "d", a.d, "-var", "Do", g["Do"], "-var", "L", g["L"], "-var", "Wt", g["Wt"],
              "-var", "Hbin", g["Hbin"], "-var", "Hw", g["Hw"], "-var", "catch", g["catch"], "-var", "E", a.E,
              "-var", "dt", a.dt, "-var", "settle", a.settle, "-var", "discharge", a.discharge, "-var", "M", a.M,
              "-var", "MESH", "mesh"]
    common = [repr(x) if isinstance(x, float) else str(x) for x in common]
    jobs = []
    if a.skip != "rock":
        suffix = ["-suffix", a.suffix] if a.suffix else []
        jobs.append(([a.launcher] + suffix + ["-in", str(HERE / "in.hopper")] + common +
                     ["-var", "shape", a.shape, "-var", "SHAPES", str(ROOT / "examples" / "shapes"),
                      "-log", "log.hopper_rock"], "log.hopper_rock"))
    if a.skip != "spheres":
        jobs.append(([a.liggghts, "-in", str(HERE / "in.hopper_spheres")] + common +
                     ["-log", "log.hopper_spheres"], "log.hopper_spheres"))
    print("geometry: " + ", ".join("%s %.6g m" % kv for kv in g.items()))
    for command, _ in jobs:
        print("$ (cd %s && %s)" % (out, " ".join(command)))
    sys.stdout.flush()
    with concurrent.futures.ThreadPoolExecutor(max(1, a.jobs)) as pool:
        for log, seconds in pool.map(lambda j: run(j[0], out, j[1]), jobs):
            print("%s: %.1f s wall" % (log, seconds))
    if not a.no_report:
        sys.stdout.flush()
        subprocess.run([sys.executable, str(HERE / "report.py"), str(out), "--alpha", repr(a.alpha)], check=True)


if __name__ == "__main__":
    main()
