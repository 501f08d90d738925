#!/usr/bin/env python3
"""Orientation-averaged head-on collisions of two equal polyhedral particles (document 000, sec. 6.1 and 6.2):
polyhedral spheres and an irregular rock at several resolutions and Young's moduli, against LIGGGHTS' own
Hertz spheres. See doc/collision.md.

    /usr/bin/python3 run.py [--orientations 16] [--jobs 2] [--out post]

For every shape and Young's modulus, `--orientations` pairs of uniformly random orientations (the same pairs for
every shape and modulus) collide head-on: two particles of volume-equivalent diameter D approach at +-v along
x, centres on one line. All pairs of a case run side by side in one LIGGGHTS box (in.collision), each pair on
its own line, far enough apart never to meet; the orientations of a case are split over several runs, and the
runs go to `--jobs` processes. The dumps give, per pair and output step, the kinetic energy (translational and
rotational, 0.5 m v^2 + 0.5 L.omega) over its initial value; run.py keeps that, the restitution along x and the
contact time of every pair in OUT/data/<case>.npz (numpy), with the perfect-sphere references: LIGGGHTS'
`pair_style gran model hertz tangential history` (in.collision_spheres, Debian's `liggghts` when on PATH,
else this package's launcher) and the volumetric law integrated on two exact spheres. Then report.py prints
the Markdown tables and writes the PNG plots into OUT.

Time zero is the moment the volume-equivalent spheres would touch; the polyhedra start with a gap of
`--gap` D between their bounding spheres. The time step of a modulus is the elastic Hertz contact time of the
equivalent spheres over --steps-per-contact, the same for every shape. A run lasts until `--after` Hertz times
after the latest possible first touch (centre distance twice the shape's inscribed radius).

Shapes: icoN (examples/shapes/icosphere_N.off: N = 20, 80, 320, 1280, 5120), fibN (convex hull of (N+4)/2
Fibonacci-sphere directions, N = 40, 84, 180 ...: the resolutions of document 000's fig. 6.1; written to OUT/shapes
by tools/make_shapes.py's functions), rockN (examples/shapes/rock_N.obj: 10, 40, 70, 1000), every one of volume
pi/6 (scaled by D). Needs numpy; report.py also matplotlib (Debian: /usr/bin/python3).
"""
import argparse
import concurrent.futures
import contextlib
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import make_shapes  # noqa: E402
import sphere_collision_study as study  # noqa: E402
import speed_error_study  # noqa: E402

LAUNCHER = ROOT / "build" / "bin" / "liggghts-poly"
SHAPES = ROOT / "examples" / "shapes"
DEFAULT_SPHERES = ["fib40", "ico80", "ico320", "ico1280", "ico5120"]
DEFAULT_ROCKS = ["rock10", "rock40", "rock70", "rock1000"]
DEFAULT_YOUNGS = [1e6, 2.15e7, 4.64e8]
ICOSPHERE_LEVELS = {20 * 4 ** level: level for level in range(7)}


# ------------------------------------------------------------------ shapes

def shape_file(name, shapes_dir):
    """Mesh file of a shape name (icoN, fibN, rockN), generated into shapes_dir where examples/shapes lacks it."""
    kind, count = name[:3] if name.startswith(("ico", "fib")) else name[:4], int(name.lstrip("icofbrk"))
    if kind == "ico":
        path = SHAPES / f"icosphere_{count}.off"
        if path.exists():
            return path
        if count not in ICOSPHERE_LEVELS:
            raise SystemExit(f"{name}: icospheres have 20 * 4^k triangles")
        vertices, faces = make_shapes.icosphere_mesh(ICOSPHERE_LEVELS[count])
        comment = f"icosahedron subdivided {ICOSPHERE_LEVELS[count]}x, volume pi/6"
    elif kind == "fib":
        if count < 4 or count % 2:
            raise SystemExit(f"{name}: a Fibonacci sphere has an even number (2n - 4) of triangles")
        path = shapes_dir / f"fibsphere_{count}.off"
        if path.exists():
            return path
        directions = make_shapes.fibonacci_directions((count + 4) // 2)
        faces = make_shapes.convex_hull(directions)
        assert len(faces) == count, f"{name}: hull has {len(faces)} triangles"
        make_shapes.check_closed_oriented(directions, faces, name)
        vertices = make_shapes.scale_to_volume(directions, faces, make_shapes.SPHERE_VOLUME)
        comment = f"convex hull of {(count + 4) // 2} Fibonacci-sphere directions, volume pi/6"
    elif kind == "rock":
        path = SHAPES / f"rock_{count}.obj"
        if not path.exists():
            raise SystemExit(f"{name}: {path} missing (rocks: {sorted(make_shapes.ROCK_VERTEX_COUNTS)})")
        return path
    else:
        raise SystemExit(f"{name}: shapes are icoN, fibN or rockN")
    shapes_dir.mkdir(parents=True, exist_ok=True)
    path = shapes_dir / (f"icosphere_{count}.off" if kind == "ico" else path.name)
    make_shapes.write_off(str(path), comment, vertices, faces)
    return path


def read_mesh(path):
    """(vertices, triangles) of an OFF or OBJ file as written by tools/make_shapes.py (triangles or fans)."""
    words_lines = [line.split() for line in pathlib.Path(path).read_text().splitlines()]
    words_lines = [w for w in words_lines if w and not w[0].startswith("#")]
    vertices, triangles = [], []
    if path.suffix == ".off":
        nv, nf = int(words_lines[1][0]), int(words_lines[1][1])
        vertices = [[float(x) for x in w[:3]] for w in words_lines[2:2 + nv]]
        polygons = [[int(i) for i in w[1:1 + int(w[0])]] for w in words_lines[2 + nv:2 + nv + nf]]
    else:
        vertices = [[float(x) for x in w[1:4]] for w in words_lines if w[0] == "v"]
        polygons = [[int(i.split("/")[0]) - 1 for i in w[1:]] for w in words_lines if w[0] == "f"]
    for p in polygons:
        triangles += [(p[0], p[k], p[k + 1]) for k in range(1, len(p) - 1)]
    return np.array(vertices), np.array(triangles)


def mesh_radii(path, samples=12):
    """(bounding radius, inscribed radius) about the centre of mass, in the mesh's units (diameter 1 for volume
    pi/6). The inscribed radius is the distance from the centre to the nearest of samples (samples + 1) / 2
    points on each triangle, less the largest spacing of those points: a lower bound."""
    v, t = read_mesh(path)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    signed = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0        # tetrahedra with the origin
    centre = (signed[:, None] * (a + b + c) / 4.0).sum(axis=0) / signed.sum()
    weights = np.array([(i, j, samples - i - j) for i in range(samples + 1) for j in range(samples + 1 - i)])
    points = np.einsum("wk,tkd->twd", weights / samples, np.stack([a, b, c], axis=1))
    spacing = max(np.linalg.norm(b - a, axis=1).max(), np.linalg.norm(c - b, axis=1).max(),
                  np.linalg.norm(a - c, axis=1).max()) / samples
    nearest = np.linalg.norm(points - centre, axis=2).min()
    return float(np.linalg.norm(v - centre, axis=1).max()), float(max(nearest - spacing, 0.0))


# ------------------------------------------------------------------ set-up

@contextlib.contextmanager
def study_constants(**values):
    """tools/sphere_collision_study.py reads the collision from module constants (D, SPEED, DENSITY, YOUNGS,
    POISSON); set them for one computation and restore them."""
    saved = {name: getattr(study, name) for name in values}
    for name, value in values.items():
        setattr(study, name, value)
    try:
        yield
    finally:
        for name, value in saved.items():
            setattr(study, name, value)


def hertz_time(args, youngs):
    """Elastic Hertz contact time of the equivalent spheres (sphere_collision_study.hertz_time)."""
    with study_constants(D=args.diameter, SPEED=args.speed, DENSITY=args.density, YOUNGS=youngs,
                         POISSON=args.poisson):
        return study.hertz_time()


def random_quaternions(count, seed):
    """count x 2 unit quaternions (w, i, j, k), uniform on SO(3) (Shoemake's subgroup algorithm)."""
    u1, u2, u3 = np.random.default_rng(seed).random((3, count, 2))
    a, b = np.sqrt(1.0 - u1), np.sqrt(u1)
    return np.stack([b * np.cos(2 * np.pi * u3), a * np.sin(2 * np.pi * u2), a * np.cos(2 * np.pi * u2),
                     b * np.sin(2 * np.pi * u3)], axis=-1)


def case_geometry(args, shape_path, youngs):
    """Start distance, time offset, steps and box of one (shape, E): a dictionary."""
    bound, inscribed = mesh_radii(shape_path)
    bound, inscribed = bound * args.diameter, inscribed * args.diameter
    t_hertz = hertz_time(args, youngs)
    dt = t_hertz / args.steps_per_contact
    start = 2.0 * bound + args.gap * args.diameter                         # centre distance at t = 0
    offset = (start - args.diameter) / (2.0 * args.speed)                  # simulation time of "time zero"
    latest = max(0.0, (args.diameter - 2.0 * inscribed) / (2.0 * args.speed))
    after = args.after_rocks if shape_path.name.startswith("rock") else args.after
    steps = int(math.ceil((offset + latest + after * t_hertz) / dt))
    duration = steps * dt
    drift = 1.5 * args.speed * duration                                    # sqrt(2) v: all the energy in one
    spacing = 2.0 * bound + 2.0 * drift + 4.0 * args.skin
    return {"bound": bound, "inscribed": inscribed, "t_hertz": t_hertz, "dt": dt, "start": start,
            "offset": offset, "steps": steps, "spacing": spacing, "xl": 0.5 * start + drift + 2.0 * bound}


def pairs_file(path, quats, geometry, speed):
    """create_polyhedron lines for the pairs of one run; returns the box half-widths (XL, YL, ZL)."""
    n = len(quats)
    ny = int(math.ceil(math.sqrt(n)))
    nz = int(math.ceil(n / ny))
    s, x = geometry["spacing"], 0.5 * geometry["start"]
    lines = []
    for k, (q1, q2) in enumerate(quats):
        y, z = (k % ny - 0.5 * (ny - 1)) * s, (k // ny - 0.5 * (nz - 1)) * s
        for sign, q in ((-1.0, q1), (1.0, q2)):
            lines.append(f"create_polyhedron shape {sign * x!r} {y!r} {z!r} quat {q[0]!r} {q[1]!r} {q[2]!r} "
                         f"{q[3]!r} vel {-sign * speed!r} 0 0")
    pathlib.Path(path).write_text("\n".join(lines) + "\n")
    return geometry["xl"], 0.5 * ny * s, 0.5 * nz * s


def fmt_value(x):
    return f"{x:.10g}"


# ------------------------------------------------------------------ runs

def launch(launcher, deck, variables, workdir, log):
    command = [str(launcher), "-in", str(HERE / deck), "-log", str(log), "-echo", "none", "-screen", "none"]
    for name, value in variables.items():
        command += ["-var", name, str(value)]
    start = time.time()
    result = subprocess.run(command, cwd=workdir, capture_output=True, text=True, errors="replace")
    if result.returncode != 0:
        text = pathlib.Path(log).read_text(errors="replace")[-3000:] if pathlib.Path(log).exists() else ""
        raise RuntimeError(f"{' '.join(command)}: exit {result.returncode}\n{result.stdout[-2000:]}"
                           f"{result.stderr[-2000:]}{text}")
    return command, time.time() - start


def energy_per_particle(row, polyhedron):
    """0.5 m v^2 + rotational energy: 0.5 L.omega (polyhedra, from the dumped angular momentum) or 0.2 m r^2
    omega^2 (solid spheres). row: the dumped floats after the id."""
    if polyhedron:
        m, vx, vy, vz, wx, wy, wz, lx, ly, lz = row
        return 0.5 * m * (vx * vx + vy * vy + vz * vz) + 0.5 * (lx * wx + ly * wy + lz * wz)
    m, r, _, vx, vy, vz, wx, wy, wz = row
    return 0.5 * m * (vx * vx + vy * vy + vz * vz) + 0.2 * m * r * r * (wx * wx + wy * wy + wz * wz)


def run_polyhedra(job):
    """One run of in.collision (a chunk of the orientation pairs of a case); returns its measures."""
    work = pathlib.Path(job["work"])
    work.mkdir(parents=True, exist_ok=True)
    g = job["geometry"]
    xl, yl, zl = pairs_file(work / "pairs.in", job["quats"], g, job["speed"])
    variables = dict(job["material"], SHAPE=job["shape_path"], PAIRS=work / "pairs.in", OUT=work / "run",
                     dt=fmt_value(g["dt"]), steps=g["steps"], every=job["every"], XL=fmt_value(xl),
                     YL=fmt_value(yl), ZL=fmt_value(zl), skin=job["skin"])
    command, seconds = launch(job["launcher"], "in.collision", variables, work, work / "log.lammps")
    frames = study.read_state(work / "run.state")
    steps = sorted(frames)
    n = len(job["quats"])
    ids = [(2 * k + 1, 2 * k + 2) for k in range(n)]
    energy = np.array([[energy_per_particle(frames[s][a], True) + energy_per_particle(frames[s][b], True)
                        for s in steps] for a, b in ids])
    first, last = frames[steps[0]], frames[steps[-1]]
    restitution = np.array([-(last[b][1] - last[a][1]) / (first[b][1] - first[a][1]) for a, b in ids])
    contacts = study.read_local(work / "run.contacts")
    touching = np.zeros((n, len(steps)), dtype=bool)
    depth = np.zeros(n)
    index = {s: i for i, s in enumerate(steps)}
    for s, rows in contacts.items():
        for row in rows:
            a, b = sorted((int(row[0]), int(row[1])))
            if a % 2 == 0 or b != a + 1:
                raise RuntimeError(f"{work}: particles {a} and {b} of different pairs touched at step {s}")
            touching[(a - 1) // 2, index[s]] = True
            depth[(a - 1) // 2] = max(depth[(a - 1) // 2], row[3])
    if not job["keep"]:
        for name in ("run.state", "run.contacts"):
            (work / name).unlink()
    return {"case": job["case"], "chunk": job["chunk"], "energy": energy, "steps": np.array(steps),
            "restitution": restitution, "touching": touching, "depth": depth, "seconds": seconds,
            "command": " ".join(map(str, command))}


def run_spheres(job):
    """in.collision_spheres at one Young's modulus: the LIGGGHTS Hertz reference."""
    work = pathlib.Path(job["work"])
    work.mkdir(parents=True, exist_ok=True)
    g = job["geometry"]
    variables = dict(job["material"], v=job["speed"], gap=fmt_value(job["gap"]), OUT=work / "spheres",
                     dt=fmt_value(g["dt"]), steps=g["steps"], every=job["every"])
    command, seconds = launch(job["launcher"], "in.collision_spheres", variables, work, work / "log.lammps")
    frames = study.read_state(work / "spheres.state")
    steps = sorted(frames)
    energy = np.array([energy_per_particle(frames[s][1], False) + energy_per_particle(frames[s][2], False)
                       for s in steps])
    diameter = float(job["material"]["D"])
    overlap = np.array([diameter - (frames[s][2][2] - frames[s][1][2]) for s in steps])
    first, last = frames[steps[0]], frames[steps[-1]]
    if not job["keep"]:
        (work / "spheres.state").unlink()
    return {"case": job["case"], "energy": energy, "steps": np.array(steps), "overlap": overlap,
            "restitution": -(last[2][3] - last[1][3]) / (first[2][3] - first[1][3]), "seconds": seconds,
            "command": " ".join(map(str, command))}


def lens_law(args, youngs, dt, steps, offset):
    """The volumetric law (normal, elastic) on two exact spheres: V = pi delta^2 R* (1 - delta/(6R)) of the lens,
    F = 4/(3 sqrt(pi)) E* sqrt(V delta), integrated by velocity Verlet on the overlap delta with the runs' dt;
    returns (time from first touch, normalised kinetic energy, contact time): the limit of the polyhedral spheres."""
    radius = 0.5 * args.diameter
    mass = args.density * math.pi / 6.0 * args.diameter ** 3
    m_eff, r_eff = 0.5 * mass, 0.5 * radius
    e_eff = youngs / (2.0 * (1.0 - args.poisson ** 2))

    def acceleration(delta):
        if delta <= 0.0:
            return 0.0
        volume = math.pi * delta * delta * r_eff * (1.0 - delta / (6.0 * radius))
        return -4.0 / (3.0 * math.sqrt(math.pi)) * e_eff * math.sqrt(volume * delta) / m_eff

    delta, rate = -2.0 * args.speed * offset, 2.0 * args.speed
    acc, energy, touching = acceleration(delta), [1.0], 0
    for _ in range(steps):
        rate += 0.5 * dt * acc
        delta += dt * rate
        acc = acceleration(delta)
        rate += 0.5 * dt * acc
        energy.append((rate / (2.0 * args.speed)) ** 2)
        touching += delta > 0.0
    return np.arange(steps + 1) * dt - offset, np.array(energy), touching * dt


# ------------------------------------------------------------------ main

def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spheres", nargs="*", default=DEFAULT_SPHERES, help="polyhedral spheres: icoN, fibN")
    parser.add_argument("--rocks", nargs="*", default=DEFAULT_ROCKS, help="irregular particles: rockN")
    parser.add_argument("--youngs", type=float, nargs="+", default=DEFAULT_YOUNGS, help="Young's moduli [Pa]")
    parser.add_argument("--orientations", type=int, default=16, help="orientation pairs per case")
    parser.add_argument("--fewer", nargs="*", default=[], metavar="SHAPE:COUNT",
                        help="fewer orientation pairs for some shapes (the first COUNT), e.g. ico5120:4")
    parser.add_argument("--seed", type=int, default=2020, help="seed of the orientations")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="LIGGGHTS processes at a time")
    parser.add_argument("--chunks", type=int, default=0,
                        help="runs per case (orientations split between them; default: --jobs)")
    parser.add_argument("--diameter", type=float, default=0.2, help="volume-equivalent diameter D [m]")
    parser.add_argument("--speed", type=float, default=5.0, help="approach speed of each particle [m/s]")
    parser.add_argument("--density", type=float, default=2500.0)
    parser.add_argument("--poisson", type=float, default=0.25)
    parser.add_argument("--restitution", type=float, default=1.0, help="1: elastic (document 000)")
    parser.add_argument("--friction", type=float, default=0.5)
    parser.add_argument("--tangential", default="off", choices=["off", "history"],
                        help="tangential force of the polyhedra (document 000: off)")
    parser.add_argument("--precision", default="double", choices=["double", "single", "mixed"])
    parser.add_argument("--steps-per-contact", type=float, default=150.0,
                        help="time step = elastic Hertz contact time / this")
    parser.add_argument("--after", type=float, default=1.6,
                        help="spheres: run until this many Hertz times after the latest possible first touch")
    parser.add_argument("--after-rocks", type=float, default=5.0,
                        help="the same for rocks (some turn and touch for several Hertz times)")
    parser.add_argument("--gap", type=float, default=0.01, help="gap between the bounding spheres at the start [D]")
    parser.add_argument("--skin", type=float, default=0.01, help="neighbour skin [m]")
    parser.add_argument("--every", type=int, default=1, help="output interval [steps]")
    parser.add_argument("--launcher", default=str(LAUNCHER), help="liggghts-poly for the polyhedra")
    parser.add_argument("--liggghts", default=shutil.which("liggghts") or str(LAUNCHER),
                        help="LIGGGHTS for the Hertz spheres (default: Debian's liggghts on PATH, else --launcher)")
    parser.add_argument("--out", default=str(HERE / "post"), help="output folder")
    parser.add_argument("--keep", action="store_true", help="keep the raw dumps in OUT/runs")
    parser.add_argument("--dry-run", action="store_true", help="write the PAIRS files, print the commands, run nothing")
    parser.add_argument("--no-report", action="store_true", help="do not run report.py at the end")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    out = pathlib.Path(args.out).resolve()
    # the runs start in their own folders: programs named by a path get an absolute one
    args.launcher = str(pathlib.Path(args.launcher).resolve())
    if "/" in args.liggghts:
        args.liggghts = str(pathlib.Path(args.liggghts).resolve())
    for program in (args.launcher, args.liggghts):
        if not shutil.which(program):
            sys.exit(f"{program} missing: run `make` first" if program == args.launcher else f"{program} missing")
    fewer = {name: int(count) for name, count in (item.split(":") for item in args.fewer)}
    (out / "data").mkdir(parents=True, exist_ok=True)
    for old in (out / "data").glob("*.npz"):
        old.unlink()
    chunks = args.chunks or args.jobs
    quats = random_quaternions(args.orientations, args.seed)
    material = {"D": fmt_value(args.diameter), "rho": fmt_value(args.density), "nu": fmt_value(args.poisson),
                "e": fmt_value(args.restitution), "mu": fmt_value(args.friction)}
    header = speed_error_study.machine()
    started = time.time()
    print(header)
    print(f"command: {' '.join([os.path.basename(sys.executable)] + (argv if argv is not None else sys.argv))}")
    print(f"polyhedra: {args.launcher}; spheres: {args.liggghts}", flush=True)

    cases, jobs, sphere_jobs = {}, [], []
    for family, names in (("sphere", args.spheres), ("rock", args.rocks)):
        for name in names:
            path = shape_file(name, out / "shapes")
            count = min(fewer.get(name, args.orientations), args.orientations)
            for youngs in args.youngs:
                case = f"{name}_E{youngs:g}"
                geometry = case_geometry(args, path, youngs)
                cases[case] = {"family": family, "shape": name, "file": str(path), "youngs": youngs,
                               "triangles": int(name.lstrip("icofbrk")), "orientations": count, "geometry": geometry}
                bounds = np.linspace(0, count, min(chunks, count) + 1).round().astype(int)
                for k in range(len(bounds) - 1):
                    jobs.append({"case": case, "chunk": k, "work": out / "runs" / case / f"chunk{k}",
                                 "quats": quats[bounds[k]:bounds[k + 1]].tolist(), "geometry": geometry,
                                 "shape_path": path, "material": dict(material, E=fmt_value(youngs),
                                                                      tangential=args.tangential,
                                                                      precision=args.precision),
                                 "speed": args.speed, "every": args.every, "skin": args.skin,
                                 "launcher": args.launcher, "keep": args.keep})
    for youngs in args.youngs:
        t_hertz = hertz_time(args, youngs)
        gap = args.gap * args.diameter
        dt = t_hertz / args.steps_per_contact
        offset = gap / (2.0 * args.speed)
        geometry = {"dt": dt, "offset": offset, "t_hertz": t_hertz,
                    "steps": int(math.ceil((offset + args.after * t_hertz) / dt))}
        sphere_jobs.append({"case": f"hertz_E{youngs:g}", "youngs": youngs, "work": out / "runs" / f"hertz_E{youngs:g}",
                            "geometry": geometry, "gap": gap, "material": dict(material, E=fmt_value(youngs)),
                            "speed": args.speed, "every": args.every, "launcher": args.liggghts, "keep": args.keep})

    if args.dry_run:
        for job in jobs:
            g = job["geometry"]
            work = pathlib.Path(job["work"])
            work.mkdir(parents=True, exist_ok=True)
            xl, yl, zl = pairs_file(work / "pairs.in", job["quats"], g, args.speed)
            print(f"cd {HERE} && {args.launcher} -in in.collision -var SHAPE {job['shape_path']} -var PAIRS "
                  f"{work / 'pairs.in'} -var OUT {work / 'run'} -var E {job['material']['E']} -var dt "
                  f"{fmt_value(g['dt'])} -var steps {g['steps']} -var XL {fmt_value(xl)} -var YL {fmt_value(yl)} "
                  f"-var ZL {fmt_value(zl)} -var tangential {args.tangential} -var e {material['e']}")
        for job in sphere_jobs:
            g = job["geometry"]
            print(f"cd {HERE} && {args.liggghts} -in in.collision_spheres -var E {job['material']['E']} -var dt "
                  f"{fmt_value(g['dt'])} -var steps {g['steps']} -var OUT {pathlib.Path(job['work']) / 'spheres'}")
        return

    # the most expensive runs first, so that the pool ends together
    def cost(job):
        g = cases[job["case"]]["geometry"]
        return len(job["quats"]) * g["steps"] * cases[job["case"]]["triangles"] * g["t_hertz"]

    jobs.sort(key=cost, reverse=True)
    results = {}
    with concurrent.futures.ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_spheres, job): job for job in sphere_jobs}
        futures.update({pool.submit(run_polyhedra, job): job for job in jobs})
        for future in concurrent.futures.as_completed(futures):
            result = future.result()
            results.setdefault(result["case"], []).append(result)
            print(f"  {result['case']}" + (f" chunk {result['chunk']}" if "chunk" in result else "") +
                  f": {result['seconds']:.1f} s", flush=True)

    for job in sphere_jobs:
        r, g = results[job["case"]][0], job["geometry"]
        lens_t, lens_ek, lens_contact = lens_law(args, job["youngs"], g["dt"], g["steps"], g["offset"])
        touching = r["overlap"] > 0.0
        np.savez_compressed(out / "data" / f"{job['case']}.npz", youngs=job["youngs"], dt=g["dt"], t_hertz=g["t_hertz"],
                            t=r["steps"] * g["dt"] - g["offset"], ek=r["energy"] / r["energy"][0],
                            restitution=r["restitution"], contact_time=touching.sum() * g["dt"] * args.every,
                            max_overlap=r["overlap"].max(), seconds=r["seconds"], lens_t=lens_t, lens_ek=lens_ek,
                            lens_contact_time=lens_contact,
                            command=r["command"])
    for case, info in cases.items():
        parts = sorted(results[case], key=lambda r: r["chunk"])
        g = info["geometry"]
        energy = np.concatenate([r["energy"] for r in parts])
        touching = np.concatenate([r["touching"] for r in parts])
        np.savez_compressed(
            out / "data" / f"{case}.npz", family=info["family"], shape=info["shape"], mesh=info["file"],
            triangles=info["triangles"], youngs=info["youngs"], dt=g["dt"], t_hertz=g["t_hertz"],
            bound=g["bound"], t=parts[0]["steps"] * g["dt"] - g["offset"], ek=energy / energy[:, :1],
            restitution=np.concatenate([r["restitution"] for r in parts]),
            contact_time=touching.sum(axis=1) * g["dt"] * args.every, touching_at_end=touching[:, -1],
            max_depth=np.concatenate([r["depth"] for r in parts]), seconds=sum(r["seconds"] for r in parts),
            runs=len(parts), command=parts[0]["command"])
    elapsed = time.time() - started
    (out / "run.json").write_text(json.dumps({
        "machine": header, "argv": [os.path.basename(sys.executable)] + (argv if argv is not None else sys.argv),
        "seconds": elapsed, "jobs": args.jobs, "polyhedra": args.launcher, "spheres": args.liggghts,
        "parameters": {k: v for k, v in vars(args).items() if k not in ("out", "dry_run", "no_report", "keep")},
        "orientations": args.orientations}, indent=1))
    if not args.keep:
        shutil.rmtree(out / "runs", ignore_errors=True)
    print(f"total run time {elapsed:.0f} s; results in {out}/data", flush=True)
    if not args.no_report:
        report = subprocess.run([sys.executable, str(HERE / "report.py"), str(out)], text=True,
                                capture_output=True)
        (out / "report.md").write_text(report.stdout)
        sys.stdout.write(report.stdout)
        if report.returncode != 0:
            sys.exit(report.stderr)


if __name__ == "__main__":
    main()
