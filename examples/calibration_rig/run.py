#!/usr/bin/env python3
"""Calibration rig (document 000, sec. 6.3): writes the meshes, runs in.rig for each rock shape and seed, then
report.py. See doc/calibration_rig.md.

    /usr/bin/python3 run.py [--N 150] [--shapes rock_10.obj,rock_20.obj,rock_40.obj,rock_70.obj] [--seeds 2]

Materials from table A.2 of document 000: E = 2e7 Pa (rocks) and 1e8 Pa (walls), nu = 0.25, friction 0.39
(rock-rock) and 0.35 (rock-wall), and the damping coefficients gamma = 0.453619 and 0.382097 of eq. 4.5
(F = 2 gamma sqrt(m* k_n) v_n), turned into the restitution coefficient that gives the same damping in this
package's law (restitution_for_damping). Sizes: the truncated normal of table A.2 (middle bounding-box edge,
mean 10 mm, sd 5 mm, cut to 5-10 mm) in three classes of equal width, by mass (size_classes).
The bin above the hopper is made tall enough for N bounding spheres of the largest class at --fill of the
volume their centres can reach. --scale multiplies the rig (make_rig.py) for larger N.

Output in OUT/<shape stem>_<seed>/: log.rig, post/rig_final.dump and post/rig_final_*.vtp; OUT/mesh/ and
OUT/runs.json (what was run, with the rig's dimensions); then report.py OUT writes report.md and the plots.
"""
import argparse
import importlib.util
import json
import math
import pathlib
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.stats import truncnorm

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
import make_rig  # noqa: E402

# the hopper example's OBJ reader, bounding radius and deck runner, loaded by path (both scripts are run.py)
_spec = importlib.util.spec_from_file_location("hopper_run", ROOT / "examples" / "hopper" / "run.py")
hopper_run = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hopper_run)
bounding_radius, read_obj = hopper_run.bounding_radius, hopper_run.read_obj

# insert/pack seeds: primes above 10000, as LIGGGHTS wants
SEEDS = [86028121, 86028157, 104395301, 122949823, 141650939, 160481183, 179424673, 198491317, 217645177,
         236887691, 256203161]
TABLE_A2 = dict(Ep=2.0e7, Ew=1.0e8, mupp=0.39, mupw=0.35, gamma_pp=0.453619, gamma_pw=0.382097)


def restitution_for_damping(gamma):
    """Restitution of a clamped Hertz contact whose damping force is 2 gamma sqrt(m* k_n) v_n (document 000,
    eq. 4.5). This package writes it 2 sqrt(5/6) beta sqrt(k_n m*) (LIGGGHTS' form), so beta = gamma sqrt(6/5),
    and its rebound in Hertz units obeys X'' = -X^1.5 - sqrt(5) beta X^0.25 X' (force >= 0), X(0) = 0,
    X'(0) = 1 (src/poly_contact.h); the restitution is -X' when X returns to 0."""
    c = math.sqrt(5.0) * gamma * math.sqrt(6.0 / 5.0)

    def rhs(_, s):
        x, v = max(s[0], 0.0), s[1]
        return [v, -max(x ** 1.5 + c * x ** 0.25 * v, 0.0)]

    def back_at_zero(t, s):
        return s[0] if t > 1e-3 else 1.0
    back_at_zero.terminal, back_at_zero.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1e3), [0.0, 1.0], events=back_at_zero, rtol=1e-11, atol=1e-13, max_step=1e-2)
    if not sol.t_events[0].size:
        return 0.0
    return -sol.y_events[0][0][1]


def middle_extent(shape_path):
    """The middle edge of the shape's axis-aligned bounding box (file axes), in file units."""
    verts, _ = read_obj(shape_path)
    v = np.array(verts)
    return float(np.sort(v.max(axis=0) - v.min(axis=0))[1])


def size_classes(shape_path, classes=3, mean=10e-3, sd=5e-3, low=5e-3, high=10e-3):
    """Volume-equivalent diameters and mass fractions of `classes` equal-width bins of table A.2's truncated
    normal of the middle bounding-box edge; the shape file has volume pi/6 (diameter 1)."""
    edges = np.linspace(low, high, classes + 1)
    dist = truncnorm((low - mean) / sd, (high - mean) / sd, loc=mean, scale=sd)
    number = np.diff(dist.cdf(edges))
    middle = 0.5 * (edges[:-1] + edges[1:])
    mass = number * middle ** 3
    return middle / middle_extent(shape_path), mass / mass.sum(), middle


def shape_path(shape, mesh_dir):
    """rock_20.obj is written by make_rig.py into the mesh folder; the others are in examples/shapes."""
    local = mesh_dir / shape
    return local if local.exists() else ROOT / "examples" / "shapes" / shape


def deck_variables(a, shape, seed, dims, mesh_dir):
    path = shape_path(shape, mesh_dir)
    diameters, weights, _ = size_classes(path)
    var = dict(N=a.N, shape=path.name, SHAPES=path.parent, rho=a.rho, seed=seed, dt=a.dt, settle=a.settle,
               open=a.open, flow=a.flow, M=a.M, MESH=mesh_dir, Ep=a.E or TABLE_A2["Ep"], Ew=TABLE_A2["Ew"],
               epp="%.4f" % restitution_for_damping(TABLE_A2["gamma_pp"]),
               epw="%.4f" % restitution_for_damping(TABLE_A2["gamma_pw"]),
               mupp=TABLE_A2["mupp"], mupw=TABLE_A2["mupw"])
    for k in range(3):
        var["d%d" % (k + 1)] = "%.7g" % diameters[k]
        var["w%d" % (k + 1)] = "%.4f" % weights[k]
    for key in ("W", "Lp", "xh", "Do", "Wt", "z_out", "z_bin", "z_roof", "z_lip"):
        var[key] = "%.9g" % dims[key]
    return var


STUDY_SHAPES = "rock_10.obj,rock_20.obj,rock_40.obj,rock_70.obj"


def bin_height(a, dims, mesh_dir, shapes):
    """Bin height for N bounding spheres of the largest class of the roomiest shape, at --fill. The shapes of
    the study count too, so that a call for some of them builds the same rig as one for all."""
    rb = 0.0
    for shape in set(shapes) | set(STUDY_SHAPES.split(",")):
        path = shape_path(shape, mesh_dir)
        rb = max(rb, bounding_radius(path) * size_classes(path)[0][-1])
    area = (dims["Wt"] - 2 * rb) * (dims["W"] - 2 * rb)
    return 2 * rb + a.N * 4 / 3 * math.pi * rb ** 3 / (a.fill * area)


def run_deck(a, var, workdir):
    """Runs in.rig in workdir; returns the wall time in seconds."""
    workdir.mkdir(parents=True, exist_ok=True)
    command = [a.launcher, "-in", str(HERE / "in.rig"), "-log", "log.rig"]
    for key, value in var.items():
        command += ["-var", key, str(value)]
    return hopper_run.run(command, workdir, None)[1]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--N", type=int, default=150)
    p.add_argument("--shapes", default=STUDY_SHAPES)
    p.add_argument("--seeds", type=int, default=2, help="runs per shape (the first SEEDS)")
    p.add_argument("--first-seed", type=int, default=0, help="index in SEEDS of the first seed")
    p.add_argument("--scale", type=float, default=1.0, help="multiplies the rig's lengths (make_rig.py)")
    p.add_argument("--rig", action="append", default=[], metavar="KEY=VALUE",
                   help="a dimension of make_rig.DEFAULTS (m or degrees, before --scale); repeatable")
    p.add_argument("--fill", type=float, default=0.35, help="bounding-sphere volume fraction of the insertion")
    p.add_argument("--rho", type=float, default=2700.0, help="rock density, kg/m^3 (not in table A.2)")
    p.add_argument("--E", type=float, default=None, help="rock Young's modulus, Pa (table A.2: 2e7)")
    p.add_argument("--dt", type=float, default=2.5e-5)
    p.add_argument("--settle", type=float, default=0.2)
    p.add_argument("--open", type=float, default=0.05, help="s for the doors' quarter turn")
    p.add_argument("--flow", type=float, default=0.6, help="s after the doors opened")
    p.add_argument("--M", type=int, default=200, help="thermo output every M steps")
    p.add_argument("--launcher", default=str(ROOT / "build" / "bin" / "liggghts-poly"))
    p.add_argument("--out", default=str(HERE / "post"))
    p.add_argument("--no-report", action="store_true")
    a = p.parse_args()
    out = pathlib.Path(a.out).resolve()
    mesh_dir = out / "mesh"
    mesh_dir.mkdir(parents=True, exist_ok=True)
    make_rig.write_rock_20(mesh_dir)
    shapes = a.shapes.split(",")
    overrides = {key: float(value) for key, value in (item.split("=") for item in a.rig)}
    unknown = set(overrides) - set(make_rig.DEFAULTS)
    if unknown:
        raise SystemExit("--rig: unknown dimension(s) %s" % ", ".join(sorted(unknown)))
    dims = make_rig.rig_dimensions(a.scale, **overrides)
    overrides["Hbin"] = bin_height(a, dims, mesh_dir, shapes) / a.scale
    dims = make_rig.rig_dimensions(a.scale, **overrides)
    make_rig.write_rig(dims, mesh_dir)
    record_path = out / "runs.json"
    earlier = json.loads(record_path.read_text())["runs"] if record_path.exists() else []
    runs = []
    for shape in shapes:
        for seed in SEEDS[a.first_seed:a.first_seed + a.seeds]:
            var = deck_variables(a, shape, seed, dims, mesh_dir)
            name = "%s_%d" % (pathlib.Path(shape).stem, seed)
            print("run.py: %s ..." % name, flush=True)
            wall = run_deck(a, var, out / name)
            print("run.py: %s done in %.1f s" % (name, wall), flush=True)
            runs.append(dict(name=name, shape=shape, seed=seed, wall_s=round(wall, 1), argv=sys.argv[1:],
                             variables={k: str(v) for k, v in var.items()}))
            # runs of earlier calls into the same OUT (other shapes or seeds) are kept
            kept = [r for r in earlier if r["name"] not in {n["name"] for n in runs}]
            record = dict(dims=dims, N=a.N, scale=a.scale, runs=kept + runs)
            record_path.write_text(json.dumps(record, indent=1))
    if not a.no_report:
        subprocess.run([sys.executable, str(HERE / "report.py"), str(out)], check=True)


if __name__ == "__main__":
    main()
