#!/usr/bin/env python3
"""Rocking benchmark (issue 12 part 2, "Rocking blocks are barely damped"): how fast does a block that lands
on an edge or a corner come to rest under the volumetric law, against Housner's rocking model and against
LIGGGHTS' own multisphere cube? Not a test: it prints the tables of doc/benchmarks.md, "Rocking".

Rocking cases: a 1 cm cube and rock_40 (scale 0.01: volume-equivalent diameter 1 cm), tilted by 5, 10, 20 and
30 deg from a resting face (the rock: its stable hull facet that tips at the largest angle, leaning on that
facet's edge farthest from the foot of the centre of mass), then
  edge   set on the edge it leans on (tilt about y, lowest point at z = 0, zero overlap, zero velocity) and let
         tip back: planar free rocking,
  drop   tilted about a horizontal axis 30 deg from y (a corner lowest) and dropped from --drop (5 mm),
  flat   (cube only, no tilt) dropped flat from --drop: the restitution of a face impact,
onto
  plane  `fix wall/polyhedral primitive zplane 0`,
  mesh   a 2-triangle STL floor (`fix mesh/surface` + `fix wall/polyhedral mesh`),
  slab   a 10 cm polyhedral cube, not integrated (1000 times the 1 cm cube's mass), through the pair style.
References (examples/rocking/in.rocking_spheres): a cube of 27 overlapping spheres (`fix
particletemplate/multisphere` with the cube's mass and inertia, `fix multisphere`, `pair_style gran model hertz
tangential history`) on `fix wall/gran` plane / mesh and, as the heavy block, a frozen LIGGGHTS sphere of
diameter 1 m; the same cube with coefficientRestitution --matched-e (0.55), whose face impact then rebounds as
the polyhedral cube's (LIGGGHTS damps each sphere contact with the body's mass, so 9 sphere contacts damp a face
impact far more than one contact would); and Housner's r. Material everywhere: E 5 MPa, nu 0.3, e 0.3,
mu 0.5, 2500 kg/m^3; dt 2 us (the multisphere's: 1% of the Rayleigh time of its 2 mm spheres).

Measured per case, from omega about the tilt axis every --every steps:
  p1        the first peak: the largest |omega| of the first half-cycle (stretch of one sign of omega)
  r1 r2 r3  p2/p1, p3/p2, p4/p3: successive half-cycle peaks. In Housner's model each half-cycle holds one
            impact, and each impact leaves r = 1 - 1.5 sin^2 alpha of the angular velocity (0.25 for a cube)
  r tail    geometric mean of p(k+1)/p(k) over the half-cycles whose peaks lie between 10% and 0.1% of p1
            (small rocking on the face, without lift-off), and their number
  t_rest    time after which the kinetic energy (translation + rotation) stays below 1e-6 of its peak
            ('>' the simulated time when it never does)
Housner's r of the rock is the planar estimate for rocking about the leaning edge: with its distance b_A from
the foot of the centre of mass, the far side of the facet at b_B, the centre's height h and I_c the moment
about the tilt axis, r = (I_c + m (h^2 - b_A b_B)) / (I_c + m (h^2 + b_B^2)) (1 - 1.5 sin^2 alpha for a cube).

The pile (examples/rocking/in.pile, in.pile_spheres): 100 cubes of 1 cm inserted at once with random
orientations into a 10 x 10 cm box of 5 plane walls, polyhedral vs multisphere (e 0.3): the times after which
the pile's kinetic energy stays below 1e-4 ... 1e-8 of its peak and their ratio (issue target at 1e-6:
polyhedral within twice the multisphere pile's time).

  python3 tools/bench_rocking.py              # everything; about 4 min on 2 idle cores (the polyhedral pile)
  python3 tools/bench_rocking.py --quick      # cube only, 10 and 30 deg, zplane and mesh, no pile; 20 s
  python3 tools/bench_rocking.py --no-pile    # the rocking tables only; about 2 min
  python3 tools/bench_rocking.py --peaks      # also each case's half-cycle peaks and its spin at the end
Runs in examples/rocking/post/bench (--workdir); needs build/bin/liggghts-poly (make -j2 all) and Debian's
liggghts.
"""
import argparse
import concurrent.futures
import math
import os
import pathlib
import platform
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "rocking"
POLY = ROOT / "build" / "bin" / "liggghts-poly"
STOCK = "liggghts"

EDGE, DENSITY = 0.01, 2500.0
MATERIAL = {"E": 5e6, "nu": 0.3, "e": 0.3, "mu": 0.5, "rho": DENSITY}
PILE_LEVELS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
DROP_AZIMUTH = 30.0  # deg: the drop cases tilt about a horizontal axis 30 deg from y, so a corner lands first
SPHERE_OFFSET, SPHERE_RADIUS = 0.3 * EDGE, 0.2 * EDGE  # cube27.multisphere at scale EDGE
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMPI_MCA_btl_vader_single_copy_mechanism": "none"}


# geometry -----------------------------------------------------------------------------------------------

def read_obj(path):
    vertices, triangles = [], []
    for line in open(path):
        words = line.split()
        if words and words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif words and words[0] == "f":
            triangles.append([int(w.split("/")[0]) - 1 for w in words[1:4]])
    return np.array(vertices), np.array(triangles)


def mass_properties(vertices, triangles):
    """Volume, centroid and inertia tensor per unit density (signed tetrahedra from the origin)."""
    volume, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for a, b, c in vertices[triangles]:
        v = np.dot(a, np.cross(b, c)) / 6.0
        s = a + b + c
        volume += v
        first += v * s / 4.0
        second += v / 20.0 * (np.outer(a, a) + np.outer(b, b) + np.outer(c, c) + np.outer(s, s))
    centroid = first / volume
    second -= volume * np.outer(centroid, centroid)
    return volume, centroid, np.trace(second) * np.eye(3) - second


def body_frame(vertices, triangles):
    """The template's body frame (src/poly_shape.c): centroid at the origin, principal axes ascending,
    the largest component of the first two axes positive, the third right-handed. Degenerate moments
    (the cube) keep the file axes. Returns volume, moments per unit density, body-frame vertices."""
    volume, centroid, inertia = mass_properties(vertices, triangles)
    moments, axes = np.linalg.eigh(inertia)
    if np.ptp(moments) <= 1e-9 * abs(moments[2]):
        axes = np.eye(3)
    else:
        columns = [axes[:, i].copy() for i in range(3)]
        for i in range(2):
            if columns[i][np.argmax(np.abs(columns[i]))] < 0:
                columns[i] = -columns[i]
        columns[2] = np.cross(columns[0], columns[1])
        axes = np.array(columns).T
    return volume, moments, (vertices - centroid) @ axes


def hull_facets(points):
    """Facets of the convex hull of `points` (around the origin): [(outward normal, distance, vertex ids)]."""
    n = len(points)
    facets = {}
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                normal = np.cross(points[j] - points[i], points[k] - points[i])
                if np.linalg.norm(normal) < 1e-14:
                    continue
                normal /= np.linalg.norm(normal)
                d = np.dot(normal, points[i])
                if d < 0:
                    normal, d = -normal, -d
                side = points @ normal - d
                if np.all(side <= 1e-12):
                    key = tuple(np.round(np.r_[normal, d], 9))
                    facets.setdefault(key, (normal, d, set()))[2].update(np.nonzero(side > -1e-12)[0].tolist())
    return list(facets.values())


def quaternion(m):
    """Unit quaternion (w, x, y, z) of the rotation matrix m (Shepperd's method)."""
    trace = np.trace(m)
    candidates = [trace, m[0, 0], m[1, 1], m[2, 2]]
    k = int(np.argmax(candidates))
    if k == 0:
        w = math.sqrt(1.0 + trace) / 2.0
        q = [w, (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w)]
    else:
        i, j, l = k - 1, k % 3, (k + 1) % 3
        s = math.sqrt(1.0 + m[i, i] - m[j, j] - m[l, l]) * 2.0
        q = [0.0] * 4
        q[0] = (m[l, j] - m[j, l]) / s
        q[1 + i] = s / 4.0
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + l] = (m[l, i] + m[i, l]) / s
    q = np.array(q)
    return q / np.linalg.norm(q) * (1 if q[0] >= 0 else -1)


def tilt_matrix(angle, azimuth=0.0):
    """Rotation by `angle` about the horizontal axis (-sin(azimuth), cos(azimuth), 0): the world y axis
    for azimuth 0, where +angle lowers the +x side."""
    axis = np.array([-math.sin(azimuth), math.cos(azimuth), 0.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def tilt_axis(azimuth_deg):
    return np.array([-math.sin(math.radians(azimuth_deg)), math.cos(math.radians(azimuth_deg)), 0.0])


def leaning_facet(body):
    """The stable hull facet of `body` (vertices around the centre of mass) that tips at the largest angle, and
    its edge farthest from the foot of the centre of mass. Returns `rest` (rows: the world axes in body
    coordinates; the facet down, that edge along y on the +x side), the centre's height h above the facet, the
    edge's distance b_a from the foot and the facet's extent b_b from the foot towards -x."""
    best = None
    for normal, d, ids in hull_facets(body):
        foot = normal * d
        polygon = body[sorted(ids)]
        u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
        u /= np.linalg.norm(u)
        q = np.c_[(polygon - foot) @ u, (polygon - foot) @ np.cross(normal, u)]
        order = np.argsort(np.arctan2(q[:, 1], q[:, 0]))
        q, polygon = q[order], polygon[order]
        # signed distance of the foot from each edge, positive inside
        edges = [(np.cross(q[(i + 1) % len(q)] - q[i], -q[i]) / np.linalg.norm(q[(i + 1) % len(q)] - q[i]), i)
                 for i in range(len(q))]
        nearest = min(e[0] for e in edges)
        if nearest > 0 and (best is None or math.atan(nearest / d) > best[0]):
            best = (math.atan(nearest / d), normal, d, polygon) + max(edges)
    _, normal, d, polygon, b_a, i = best
    along = polygon[(i + 1) % len(polygon)] - polygon[i]
    y_axis = along - np.dot(along, normal) * normal
    y_axis /= np.linalg.norm(y_axis)
    x_axis = np.cross(y_axis, -normal)
    if np.dot(polygon[i] - normal * d, x_axis) < 0:  # the leaning edge on +x
        y_axis, x_axis = -y_axis, -x_axis
    rest = np.array([x_axis, y_axis, -normal])
    b_b = -np.min((polygon - normal * d) @ x_axis)
    return rest, d, b_a, b_b


class Shape:
    """A particle shape set on its resting facet (the cube: its -z face, leaning on the +x edge; other shapes:
    leaning_facet); a tilt by +angle about y then leans it on that edge. `housner`: the planar Housner
    coefficient for rocking about that edge."""

    def __init__(self, name, vertices, triangles, scale, template_file):
        self.name, self.file, self.scale = name, template_file, scale
        if name == "cube":  # unit cube: the template keeps the file axes (degenerate moments)
            self.body = (vertices - 0.5) * scale
            volume, moments = scale ** 3, np.full(3, scale ** 5 / 6.0)
            self.rest, self.h, self.b_a, self.b_b = np.eye(3), scale / 2, scale / 2, scale / 2
        else:
            volume, moments, self.body = body_frame(vertices * scale, triangles)
            self.rest, self.h, self.b_a, self.b_b = leaning_facet(self.body)
        self.mass = DENSITY * volume
        self.inertia_body = np.diag(moments) * DENSITY
        i_c = (self.rest @ self.inertia_body @ self.rest.T)[1, 1]
        h, b_a, b_b, m = self.h, self.b_a, self.b_b, self.mass
        self.housner = (i_c + m * (h * h - b_a * b_b)) / (i_c + m * (h * h + b_b * b_b))
        self.tip_angle = math.degrees(math.atan(b_a / h))

    def pose(self, angle_deg, azimuth_deg=0.0):
        """quaternion (body to world) and centre height for the tilted block touching z = 0, zero overlap."""
        rotation = tilt_matrix(math.radians(angle_deg), math.radians(azimuth_deg)) @ self.rest
        z0 = -np.min((rotation @ self.body.T)[2])
        return quaternion(rotation), z0


def multisphere_pose(angle_deg, azimuth_deg=0.0):
    rotation = tilt_matrix(math.radians(angle_deg), math.radians(azimuth_deg))
    centres = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)]) * SPHERE_OFFSET
    return quaternion(rotation), -np.min((rotation @ centres.T)[2]) + SPHERE_RADIUS


def write_floor_stl(path, half=0.05):
    corners = [(-half, -half, 0.0), (half, -half, 0.0), (half, half, 0.0), (-half, half, 0.0)]
    lines = ["solid floor"]
    for a, b, c in ((corners[0], corners[1], corners[2]), (corners[0], corners[2], corners[3])):
        lines += ["  facet normal 0 0 1", "    outer loop"] + \
                 ["      vertex %.17g %.17g %.17g" % p for p in (a, b, c)] + ["    endloop", "  endfacet"]
    lines.append("endsolid floor")
    pathlib.Path(path).write_text("\n".join(lines) + "\n")


# runs ---------------------------------------------------------------------------------------------------

def run_liggghts(command, workdir, log):
    env = dict(os.environ, **MPI_ENV)
    start = time.time()
    result = subprocess.run(command, cwd=EXAMPLE, capture_output=True, text=True, env=env, errors="replace")
    (workdir / log).write_text(result.stdout + result.stderr)
    if result.returncode != 0 or "ERROR" in result.stdout:
        raise RuntimeError(f"{' '.join(command)} failed:\n" + (result.stdout + result.stderr)[-3000:])
    return time.time() - start


def variables(values):
    out = []
    for name, value in values.items():
        out += ["-var", name, value if isinstance(value, str) else repr(value)]
    return out


def rocking_case(case, args, workdir):
    kind, shape_name, floor, angle, mode = case
    prefix = workdir / f"{kind}_{shape_name}_{floor}_{angle:g}_{mode}"
    azimuth, height = {"edge": (0.0, 0.0), "drop": (DROP_AZIMUTH, args.drop), "flat": (0.0, args.drop)}[mode]
    steps = int(round(args.time / args.dt))
    values = dict(MATERIAL, dt=args.dt, steps=steps, every=args.every, OUT=str(prefix), MESH=str(workdir / "floor.stl"),
                  FLOOR=floor, ROCKING=getattr(args, "rocking", "on"))
    if kind == "poly":
        shape = SHAPES[shape_name]
        q, z0 = shape.pose(angle, azimuth)
        values.update(SHAPE=str(shape.file), SCALE=shape.scale, QW=q[0], QX=q[1], QY=q[2], QZ=q[3], Z0=z0 + height)
        command = [str(POLY), "-in", "in.rocking", "-log", str(prefix) + ".log"] + variables(values)
    else:
        if kind == "msm":  # multisphere with its face-impact restitution matched to the polyhedral cube's
            values["e"] = args.matched_e
        q, z0 = multisphere_pose(angle, azimuth)
        values.update(EDGE=EDGE, QW=q[0], QX=q[1], QY=q[2], QZ=q[3], Z0=z0 + height)
        command = [STOCK, "-in", "in.rocking_spheres", "-log", str(prefix) + ".log"] + variables(values)
    wall = run_liggghts(command, workdir, prefix.name + ".out")
    series = np.loadtxt(str(prefix) + ".series")
    if mode == "flat":
        return face_restitution(series) | {"wall": wall}
    return analyse(series, args.time, tilt_axis(azimuth)) | {"wall": wall}


def face_restitution(series):
    """Rebound of a block dropped flat on a face: the largest upward speed within 3 ms after the fastest
    downward speed (the face contact lasts about 1 ms) over that downward speed."""
    t, vz = series[:, 0], series[:, 7]
    landing = int(np.argmin(vz))
    window = (t >= t[landing]) & (t <= t[landing] + 3e-3)
    return {"restitution": vz[window].max() / -vz[landing], "impact_speed": -vz[landing]}


def analyse(series, duration, axis):
    t, ke, omega = series[:, 0], series[:, 1], series[:, 3:6]
    w = omega @ axis  # about the tilt axis
    peak_ke = ke.max()
    above = np.nonzero(ke > 1e-6 * peak_ke)[0]
    rest = t[above[-1] + 1] if above[-1] + 1 < len(t) else None
    # half-cycles: stretches of one sign of w (from the first sample that moves)
    moving = np.nonzero(w != 0.0)[0]
    peaks, start = [], moving[0]
    for i in range(start + 1, len(w) + 1):
        if i == len(w) or (np.sign(w[i]) != np.sign(w[start]) and w[i] != 0.0):
            k = start + np.argmax(np.abs(w[start:i]))
            peaks.append((abs(w[k]), t[k]))
            start = i
    values = np.array([p for p, _ in peaks])
    ratios = values[1:] / values[:-1]
    first = [ratios[k] if k < len(ratios) else float("nan") for k in range(3)]
    # the tail: half-cycles whose peaks lie between 10% and 0.1% of the first
    tail = [k for k in range(len(ratios)) if values[k] < 0.1 * values[0] and values[k + 1] > 1e-3 * values[0]]
    r_tail = float(np.exp(np.mean(np.log(ratios[tail])))) if tail else float("nan")
    below = np.nonzero(values < 1e-3 * values[0])[0]
    return {"peaks": peaks, "r": first, "r_tail": r_tail, "n_tail": len(tail),
            "n_to_1e-3": int(below[0]) if len(below) else None, "t_rest": rest, "duration": duration,
            "peak_ke": peak_ke, "ke_end": ke[-1] / peak_ke,
            "spin_end": np.abs(omega[-len(t) // 20:]).max(axis=0)}


def pile_case(kind, args, workdir):
    prefix = workdir / f"pile_{kind}"
    steps = int(round(args.pile_time / args.pile_dt))
    values = dict(MATERIAL, dt=args.pile_dt, steps=steps, every=100, OUT=str(prefix), N=args.pile_n)
    if kind == "poly":
        values["ROCKING"] = args.rocking
        command = [str(POLY), "-in", "in.pile", "-log", str(prefix) + ".log"] + variables(values)
        if args.pile_np > 1:
            command = ["mpirun", "-np", str(args.pile_np)] + command
    else:
        command = [STOCK, "-in", "in.pile_spheres", "-log", str(prefix) + ".log"] + variables(values)
    wall = run_liggghts(command, workdir, prefix.name + ".out")
    series = np.loadtxt(str(prefix) + ".thermo")
    t, ke = series[:, 0], series[:, 1] + series[:, 2]
    peak = ke.max()
    below = {}
    for level in PILE_LEVELS:
        above = np.nonzero(ke > level * peak)[0]
        below[level] = t[above[-1] + 1] if above[-1] + 1 < len(t) else None
    return {"t_rest": below[1e-6], "below": below, "tail": ke[t >= t[-1] - 0.1] / peak, "peak_ke": peak, "ke_end": ke[-1] / peak, "duration": args.pile_time, "wall": wall,
            "t_peak": t[np.argmax(ke)], "movers": movers(str(prefix) + ".final", kind, peak)}


def movers(path, kind, peak_ke):
    """Particles of the final snapshot whose own kinetic energy exceeds 1e-8 of the pile's peak, and what
    they do: 'spin' (|omega_z| the largest component) or 'rock' (a horizontal component the largest)."""
    rows = [line.split() for line in open(path).read().split("ITEM: ATOMS")[1].splitlines()[1:] if line.strip()]
    data = np.array(rows, float)
    if kind == "ms":  # one row per sphere, 27 per body, ids in insertion order
        data = data[np.argsort(data[:, 0])].reshape(-1, 27, data.shape[1]).mean(axis=1)
    mass, inertia = DENSITY * EDGE ** 3, DENSITY * EDGE ** 5 / 6.0
    energy = 0.5 * mass * (data[:, 4:7] ** 2).sum(axis=1) + 0.5 * inertia * (data[:, 7:10] ** 2).sum(axis=1)
    moving = data[energy > 1e-8 * peak_ke]
    spin = sum(1 for row in moving if np.argmax(np.abs(row[7:10])) == 2)
    return f"{len(moving)} ({spin} spinning about z, {len(moving) - spin} other)"


# report -------------------------------------------------------------------------------------------------

def fmt_rest(result):
    return f"{result['t_rest']:.3f}" if result["t_rest"] is not None else f"> {result['duration']:.2f}"


def pile_summary(args, results):
    poly, ms = results[("pile", "poly")], results[("pile", "ms")]
    print(f"\npile of {args.pile_n} cubes, {args.pile_time:g} s at dt {args.pile_dt:g} s; time after which the kinetic "
          "energy stays below the given fraction of its peak:\n")
    print("| pile | peak KE [J] at [s] | " + " | ".join(f"{level:g}" for level in PILE_LEVELS) +
          " | KE / peak, last 0.1 s | moving at the end (KE > 1e-8 of the peak) | run [s] |")
    print("|---|---|" + "---|" * len(PILE_LEVELS) + "---|---|---|")
    for name, r in (("polyhedral", poly), ("multisphere-27", ms)):
        times = " | ".join(f"{r['below'][level]:.3f}" if r["below"][level] is not None else f"> {r['duration']:g}"
                           for level in PILE_LEVELS)
        print(f"| {name} | {r['peak_ke']:.3g} at {r['t_peak']:.3f} | {times} | {r['tail'].min():.1e} .. "
              f"{r['tail'].max():.1e} | {r['movers']} | {r['wall']:.0f} |")
    print()
    for level in PILE_LEVELS:
        a, b = poly["below"][level], ms["below"][level]
        if a is not None and b is not None:
            print(f"ratio polyhedral / multisphere at {level:g}: {a / b:.2f}" + (" (issue target <= 2)" if level == 1e-6 else ""))
        elif b is not None:
            print(f"ratio polyhedral / multisphere at {level:g}: > {poly['duration'] / b:.2f}" +
                  (" (issue target <= 2)" if level == 1e-6 else ""))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="cube only, 10 and 30 deg, zplane and mesh, no pile")
    parser.add_argument("--no-pile", action="store_true")
    parser.add_argument("--only-pile", action="store_true")
    parser.add_argument("--jobs", type=int, default=2, help="parallel runs (default 2)")
    parser.add_argument("--time", type=float, default=0.4, help="simulated time per rocking case [s]")
    parser.add_argument("--dt", type=float, default=2e-6, help="time step of the rocking cases [s]")
    parser.add_argument("--every", type=int, default=10, help="output interval of the rocking cases [steps]")
    parser.add_argument("--drop", type=float, default=0.005,
                        help="drop height of the lowest point in the 'drop' cases [m]")
    parser.add_argument("--matched-e", type=float, default=0.55,
                        help="coefficientRestitution of the 'matched' multisphere cube, whose face impact then "
                             "rebounds as the polyhedral cube's (default 0.55: 0.263 vs 0.265)")
    parser.add_argument("--pile-time", type=float, default=1.5, help="simulated time of the piles [s]")
    parser.add_argument("--pile-dt", type=float, default=1e-5, help="time step of the piles [s]")
    parser.add_argument("--pile-n", type=int, default=100, help="cubes in the pile")
    parser.add_argument("--pile-np", type=int, default=1, help="MPI ranks of the polyhedral pile")
    parser.add_argument("--workdir", default=str(EXAMPLE / "post" / "bench"))
    parser.add_argument("--peaks", action="store_true", help="print each case's peak sequence")
    parser.add_argument("--rocking", choices=("on", "off"), default="on",
                        help="rocking_damping of the polyhedral runs (off: the law before it)")
    args = parser.parse_args()
    workdir = pathlib.Path(args.workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    write_floor_stl(workdir / "floor.stl")
    if not POLY.exists():
        sys.exit(f"{POLY} missing: run `make -j2 all` first")

    angles = [10, 30] if args.quick else [5, 10, 20, 30]
    shapes = ["cube"] if args.quick else ["cube", "rock"]
    floors = ("plane", "mesh") if args.quick else ("plane", "mesh", "slab")
    cases = []
    if not args.only_pile:
        for shape in shapes:
            for floor in floors:
                cases += [("poly", shape, floor, angle, "edge") for angle in angles]
        for floor in ("plane", "mesh") if args.quick else ("plane", "mesh", "ball"):
            cases += [("ms", "cube", floor, angle, "edge") for angle in angles]
        if not args.quick:
            cases += [("msm", "cube", "plane", angle, "edge") for angle in angles]
            for kind, shape in (("poly", "cube"), ("poly", "rock"), ("ms", "cube"), ("msm", "cube")):
                cases += [(kind, shape, "plane", angle, "drop") for angle in angles]
        flats = [("poly", "cube", "plane", 0, "flat"), ("poly", "cube", "slab", 0, "flat"),
                 ("ms", "cube", "plane", 0, "flat"), ("ms", "cube", "ball", 0, "flat"),
                 ("msm", "cube", "plane", 0, "flat")]
        cases += flats if not args.quick else flats[::2]
    piles = [] if (args.no_pile or args.quick) else ["poly", "ms"]

    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")),
               platform.processor())
    print(f"machine: {cpu}, {os.cpu_count()} cores; commit {commit}; rocking: dt {args.dt:g} s, {args.time:g} s "
          f"per case; drop cases: lowest point {1e3 * args.drop:g} mm up, tilt axis {DROP_AZIMUTH:g} deg from y")
    for name in shapes:
        sh = SHAPES[name]
        print(f"{name}: mass {sh.mass:.4g} kg; on its resting facet the centre is {1e3 * sh.h:.3f} mm up, the leaning "
              f"edge {1e3 * sh.b_a:.3f} mm and the far side {1e3 * sh.b_b:.3f} mm from its foot; tips over beyond "
              f"{sh.tip_angle:.1f} deg; Housner r = {sh.housner:.3f}")

    start = time.time()
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        # the piles first: they take longest
        futures = {pool.submit(pile_case, kind, args, workdir): ("pile", kind) for kind in piles}
        futures.update({pool.submit(rocking_case, case, args, workdir): case for case in cases})
        for future in concurrent.futures.as_completed(futures):
            results[futures[future]] = future.result()

    if cases:
        print("\n| particle | floor | start | tilt [deg] | p1 [rad/s] | r1 | r2 | r3 | r tail (n) | Housner r | "
              "t_rest [s] | run [s] |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        labels = {("poly", "cube"): "cube, polyhedral", ("poly", "rock"): "rock_40, polyhedral",
                  ("ms", "cube"): "cube, multisphere-27",
                  ("msm", "cube"): f"cube, multisphere-27, e {args.matched_e:g}"}
        floor_names = {"plane": "zplane", "mesh": "2-triangle mesh", "slab": "frozen 10 cm cube",
                       "ball": "frozen 1 m sphere"}
        for case in cases:
            kind, shape, floor, angle, mode = case
            if mode == "flat":
                continue
            r = results[case]
            ratios = " | ".join(f"{x:.3f}" for x in r["r"])
            tail = f"{r['r_tail']:.3f} ({r['n_tail']})" if r["n_tail"] else "-"
            print(f"| {labels[(kind, shape)]} | {floor_names[floor]} | {mode} | {angle} | {r['peaks'][0][0]:.2f} | "
                  f"{ratios} | {tail} | {SHAPES[shape].housner:.3f} | {fmt_rest(r)} | {r['wall']:.1f} |")
            if args.peaks:
                print("    peaks:", " ".join(f"{p:.3g}@{t:.4f}" for p, t in r["peaks"][:16]),
                      "| |omega| in the last 5%:", " ".join(f"{x:.1e}" for x in r["spin_end"]))
        print(f"\nface impact: the cube dropped flat, lowest face {1e3 * args.drop:g} mm above the floor "
              f"(requested restitution {MATERIAL['e']}):\n")
        print("| particle | floor | impact speed [m/s] | restitution |")
        print("|---|---|---|---|")
        for case in cases:
            kind, shape, floor, angle, mode = case
            if mode == "flat":
                r = results[case]
                print(f"| {labels[(kind, shape)]} | {floor_names[floor]} | {r['impact_speed']:.3f} | "
                      f"{r['restitution']:.3f} |")
    if piles:
        pile_summary(args, results)
    print(f"\ntotal {time.time() - start:.0f} s")


UNIT_CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
SHAPES = {"cube": Shape("cube", UNIT_CUBE, None, EDGE, ROOT / "examples" / "shapes" / "cube.stl"),
          "rock": Shape("rock", *read_obj(ROOT / "examples" / "shapes" / "rock_40.obj"), 0.01,
                        ROOT / "examples" / "shapes" / "rock_40.obj")}

if __name__ == "__main__":
    main()
