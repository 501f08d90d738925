#!/usr/bin/env python3
"""Icosphere collisions under pair_style polyhedral/volumetric against LIGGGHTS'
own `pair_style gran model hertz tangential history` on true spheres.

    python3 tools/sphere_collision_study.py [--triangles 80 320 1280 5120] [--orientations 4]

Runs a head-on and two oblique (offset, friction) collisions of two equal particles
of volume-equivalent diameter D: icospheres of each resolution in several
orientations, LIGGGHTS spheres of diameter D with the same materials, and an
independent point-contact integration of the volumetric law on exact spheres. Prints
contact duration, maximum overlap, normal restitution and rebound angular velocity
with their relative errors against the LIGGGHTS run, as Markdown tables (pasted into
doc/contact_verification.md). Build first (`make`). A few minutes on 2 cores.

tests/test_contact_physics.py imports the deck builders and the analysis below,
so the test and the study measure the same way.
"""
import argparse
import math
import os
import pathlib
import random
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
LAUNCHER = ROOT / "build" / "bin" / "liggghts-poly"
SHAPES = ROOT / "examples" / "shapes"

# The collision: two particles of volume-equivalent diameter D approach along x at
# SPEED each. Soft material, so the maximum overlap is ~6% of D and the contact
# spans many facets of the finer icospheres.
D = 0.02
SPEED = 1.0
DENSITY = 2500.0
YOUNGS = 1.0e7
POISSON = 0.25
GAP = 0.001          # surface gap of the equivalent spheres at t = 0
SKIN = 0.002
# Generic orientations, so no facet of one icosphere is parallel to a facet of the other.
QUAT_1 = (0.9, 0.3, -0.2, 0.25)
QUAT_2 = (0.7, -0.1, 0.5, 0.4)

DUMP_FORMAT = " ".join(["%d"] + ["%.17g"] * 9)


def _materials(restitution, friction):
    return (f"fix m1 all property/global youngsModulus peratomtype {YOUNGS}\n"
            f"fix m2 all property/global poissonsRatio peratomtype {POISSON}\n"
            f"fix m3 all property/global coefficientRestitution peratomtypepair 1 {restitution}\n"
            f"fix m4 all property/global coefficientFriction peratomtypepair 1 {friction}\n")


def start_positions(offset):
    """Centres of particles 1 and 2: offset `offset` (in y) between the lines of flight."""
    s = 0.5 * (math.sqrt(D * D - offset * offset) + GAP)
    return (-s, -0.5 * offset, 0.0), (s, 0.5 * offset, 0.0)


def contact_normal(offset):
    """Unit vector from centre 1 to centre 2 when equivalent spheres first touch."""
    return (math.sqrt(D * D - offset * offset) / D, offset / D, 0.0)


def hertz_time():
    """Duration of an elastic Hertz impact of the equivalent spheres, head-on."""
    mass = DENSITY * math.pi / 6.0 * D ** 3
    m_eff, r_eff = 0.5 * mass, 0.25 * D
    e_eff = YOUNGS / (2.0 * (1.0 - POISSON ** 2))
    return 2.868 * (m_eff ** 2 / (r_eff * e_eff ** 2 * 2.0 * SPEED)) ** 0.2


def orientation_pairs(count):
    """(quat_1, quat_2) pairs: the fixed pair of the tests first, then pseudo-random ones (fixed seed)."""
    rng = random.Random(2020)
    pairs = [(QUAT_1, QUAT_2)]
    while len(pairs) < count:
        pairs.append(tuple(tuple(round(rng.uniform(-1.0, 1.0), 4) for _ in range(4)) for _ in range(2)))
    return pairs


def collision_deck(shape, offset=0.0, restitution=0.8, friction=0.5, dt=2e-6, steps=None,
                   tangential="history", damping="on", precision="double", quats=(QUAT_1, QUAT_2),
                   limit_force=False):
    """Deck of one collision. shape: 'sphere' for LIGGGHTS spheres, or an icosphere
    triangle count (80, 320, 1280, 5120). Writes state.txt (every step) and, for
    polyhedra, contacts.txt (compute pair/polyhedral/local, every step).
    limit_force (spheres): LIGGGHTS' `limitForce on` (no attractive normal force). Off by
    default: LIGGGHTS' damping reproduces the restitution coefficient only without it, and
    polyhedral/volumetric reproduces it with its own clamp (src/poly_contact.h)."""
    if steps is None:
        # approach over the gap, a slow (e ~ 0.5) contact, and a margin after separation
        steps = int(round((GAP / (2.0 * SPEED) + 1.6 * hertz_time() + 2e-4) / dt))
    p1, p2 = start_positions(offset)
    lines = [f"atom_style {'sphere' if shape == 'sphere' else 'polyhedron'}",
             "atom_modify map array sort 0 0", "boundary f f f", "newton off",
             "communicate single vel yes", "units si",
             "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
             f"neighbor {SKIN} bin", "neigh_modify delay 0"]
    deck = "\n".join(lines) + "\n" + _materials(restitution, friction)
    if shape == "sphere":
        pair = "pair_style gran model hertz tangential " + ("history" if tangential == "history" else "no_history")
        if limit_force:
            pair += " limitForce on"
        deck += (f"{pair}\npair_coeff * *\n"
                 f"create_atoms 1 single {p1[0]!r} {p1[1]!r} {p1[2]!r} units box\n"
                 f"create_atoms 1 single {p2[0]!r} {p2[1]!r} {p2[2]!r} units box\n"
                 f"set group all diameter {D} density {DENSITY}\n"
                 "group one id 1\ngroup two id 2\n"
                 f"velocity one set {SPEED} 0 0 units box\nvelocity two set {-SPEED} 0 0 units box\n"
                 "fix integrate all nve/sphere\n")
    else:
        deck += (f"fix shape all particletemplate/polyhedron 15485863 atom_type 1 density constant {DENSITY} "
                 f"file {SHAPES}/icosphere_{int(shape)}.off scale {D}\n"
                 f"pair_style polyhedral/volumetric tangential {tangential} damping {damping} "
                 f"precision {precision}\npair_coeff * *\n"
                 "create_polyhedron shape %r %r %r quat %g %g %g %g vel %g 0 0\n" % (p1 + quats[0] + (SPEED,)) +
                 "create_polyhedron shape %r %r %r quat %g %g %g %g vel %g 0 0\n" % (p2 + quats[1] + (-SPEED,)) +
                 "fix integrate all nve/polyhedron\n"
                 "compute erot all erotate/polyhedron\n"
                 "compute contacts all pair/polyhedral/local\n"
                 "dump contacts all local 1 contacts.txt " + " ".join(f"c_contacts[{k}]" for k in range(1, 17)) +
                 "\n")
    deck += (f"timestep {dt}\n"
             "dump state all custom 1 state.txt id x y z vx vy vz omegax omegay omegaz\n"
             f"dump_modify state format \"{DUMP_FORMAT}\" sort id\n"
             f"thermo_style custom step atoms ke {'' if shape == 'sphere' else 'c_erot'}\nthermo 500\n"
             "thermo_modify format float %.15g\n"
             f"run {steps}\n")
    return deck


def _dump_frames(path, parse_rows):
    """{step: parse_rows(row lines)} for every snapshot of a LIGGGHTS dump file."""
    lines = pathlib.Path(path).read_text().splitlines()
    frames, i = {}, 0
    while i < len(lines):
        if lines[i] == "ITEM: TIMESTEP":
            step, count = int(lines[i + 1]), int(lines[i + 3])
            frames[step] = parse_rows(lines[i + 9:i + 9 + count])
            i += 9 + count
        else:
            i += 1
    return frames


def read_state(path):
    """{step: {id: [x y z vx vy vz wx wy wz]}} from the every-step dump custom."""
    def rows(lines):
        return {int(line.split()[0]): [float(w) for w in line.split()[1:]] for line in lines}
    return _dump_frames(path, rows)


def read_local(path):
    """{step: [rows of floats]} from a `dump local` file."""
    return _dump_frames(path, lambda lines: [[float(w) for w in line.split()] for line in lines])


def kinetic_energies(log_path):
    """Total kinetic energy (translational `ke` plus rotational c_erot where present) at the first and
    the last thermo row of log.lammps."""
    header, rows = None, []
    for line in pathlib.Path(log_path).read_text().splitlines():
        words = line.split()
        if words and words[0] == "Step":
            header = words
        elif header and len(words) == len(header) and words[0].isdigit():
            rows.append(dict(zip(header, map(float, words))))
        elif words:
            header = None

    def total(row):
        return row["KinEng"] + row.get("erot", row.get("c_erot", 0.0))

    return total(rows[0]), total(rows[-1])


def measure(workdir, shape, offset=0.0, dt=2e-6):
    """Contact duration (steps with overlap; for polyhedra, steps with a row of compute
    pair/polyhedral/local), maximum overlap (spheres: from the positions; polyhedra: the depth
    column), normal restitution along the first-contact normal, rebound spin about z and the
    kinetic energy before and after, of one finished collision run."""
    workdir = pathlib.Path(workdir)
    frames = read_state(workdir / "state.txt")
    steps = sorted(frames)
    if shape == "sphere":
        depth = {s: D - math.dist(frames[s][1][:3], frames[s][2][:3]) for s in steps}
        touching = [s for s in steps if depth[s] > 0.0]
    else:
        rows = read_local(workdir / "contacts.txt")
        touching = [s for s in steps if rows.get(s)]
        depth = {s: max(r[3] for r in rows[s]) for s in touching}
    n = contact_normal(offset)
    first, last = frames[steps[0]], frames[steps[-1]]

    def relative_normal_velocity(frame):
        return sum((frame[2][3 + k] - frame[1][3 + k]) * n[k] for k in range(3))

    return {
        "touching_steps": touching,
        # contact still on, or a second contact, at the end of the run: the caller asserts on it
        "separated": bool(touching) and touching[-1] < steps[-1] and
        len(touching) == touching[-1] - touching[0] + 1,
        "duration": len(touching) * dt,
        "max_overlap": max(depth[s] for s in touching) if touching else 0.0,
        "restitution": -relative_normal_velocity(last) / relative_normal_velocity(first),
        "omega": 0.5 * (last[1][8] + last[2][8]),           # z spin, equal for both by symmetry
        "omega_difference": abs(last[1][8] - last[2][8]),
        "kinetic": kinetic_energies(workdir / "log.lammps"),
    }


def clamped_hertz_restitution(beta, dt=2e-4):
    """Restitution of the clamped Hertz contact with damping 2 sqrt(5/6) beta sqrt(k_n m*), in units of
    the impact speed and Hertz length/time: X'' = -X^1.5 - sqrt(5) beta X^0.25 X', force >= 0."""
    c, x, v, t = math.sqrt(5.0) * beta, 0.0, 1.0, 0.0

    def acc(x, v):
        return 0.0 if x <= 0.0 else -max(x ** 1.5 + c * x ** 0.25 * v, 0.0)

    while True:
        k1 = (v, acc(x, v))
        k2 = (v + 0.5 * dt * k1[1], acc(x + 0.5 * dt * k1[0], v + 0.5 * dt * k1[1]))
        k3 = (v + 0.5 * dt * k2[1], acc(x + 0.5 * dt * k2[0], v + 0.5 * dt * k2[1]))
        k4 = (v + dt * k3[1], acc(x + dt * k3[0], v + dt * k3[1]))
        x_next = x + dt / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v_next = v + dt / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        t += dt
        if x_next <= 0.0 and t > 0.1:
            return -(v + (v_next - v) * x / (x - x_next))
        x, v = x_next, v_next


def law_damping_beta(restitution):
    """beta of src/poly_contact.h: the clamped Hertz contact rebounds with exactly `restitution`
    (bisection; an independent implementation of the same definition)."""
    low, high = 0.0, 64.0
    for _ in range(45):
        middle = 0.5 * (low + high)
        if clamped_hertz_restitution(middle) > restitution:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def point_contact_spheres(offset=0.0, restitution=0.8, friction=0.5, dt=2e-6, tangential="liggghts",
                          volume="hertz", clamp=None):
    """The collision of two true spheres by an independent point-contact integration (plain Python, planar:
    positions and velocities in x-y, spin about z), for the two tangential springs in question:

    tangential="liggghts":    LIGGGHTS' `tangential history`: the spring force is -k_t(now) times the
                              accumulated tangential displacement, so it follows k_t up and down;
    tangential="incremental": document 000 eqs. 4.8/4.9 as in src/poly_contact.h: F_te += -k_t u_t dt,
                              scaled by k_t/k_t_old only while the normal force decreases.

    volume="hertz": V = pi delta^2 R* (LIGGGHTS' `model hertz`); volume="lens": the exact lens volume of
    two equal spheres, V = pi delta^2 R* (1 - delta/(6R)): the volumetric law on perfect spheres, the limit
    of the icospheres. clamp: no attractive normal force (LIGGGHTS `limitForce on`); by default off for
    "liggghts" (with LIGGGHTS' beta(e)) and on for "incremental" (the law, with its beta, law_damping_beta).
    Velocity Verlet as `fix nve/sphere`. Returns the measures of measure() that exist here."""
    radius, mass = 0.5 * D, DENSITY * math.pi / 6.0 * D ** 3
    inertia = 0.4 * mass * radius * radius
    youngs_eff = 1.0 / (2.0 * (1.0 - POISSON ** 2) / YOUNGS)
    shear_eff = 1.0 / (2.0 * 2.0 * (2.0 - POISSON) * (1.0 + POISSON) / YOUNGS)
    r_eff, m_eff = 0.5 * radius, 0.5 * mass
    if clamp is None:
        clamp = tangential != "liggghts"
    if tangential == "liggghts":
        log_e = math.log(restitution)
        beta = abs(log_e) / math.sqrt(log_e ** 2 + math.pi ** 2)
    else:
        beta = law_damping_beta(restitution)
    damping = 2.0 * math.sqrt(5.0 / 6.0) * beta
    p1, p2 = start_positions(offset)
    x = [list(p1[:2]), list(p2[:2])]
    v = [[SPEED, 0.0], [-SPEED, 0.0]]
    w = [0.0, 0.0]
    spring = [0.0, 0.0, 0.0, 0.0]  # tangential spring (displacement or force), k_t and F_n of the last step

    def forces():
        d = [x[1][0] - x[0][0], x[1][1] - x[0][1]]
        distance = math.hypot(*d)
        delta = D - distance
        if delta <= 0.0:
            spring[:] = [0.0, 0.0, 0.0, 0.0]
            return None
        n = [d[0] / distance, d[1] / distance]
        arm = radius - 0.5 * delta                    # centre to contact point (lens centroid)
        # velocity of 2 relative to 1 at the contact point; omega x (a n) = omega a (-n_y, n_x)
        u = [v[1][0] + w[1] * arm * n[1] - v[0][0] + w[0] * arm * n[1],
             v[1][1] - w[1] * arm * n[0] - v[0][1] - w[0] * arm * n[0]]
        u_n = u[0] * n[0] + u[1] * n[1]
        u_t = [u[0] - u_n * n[0], u[1] - u_n * n[1]]
        if volume == "lens":
            vol = math.pi * delta ** 2 * r_eff * (1.0 - delta / (6.0 * radius))
        else:
            vol = math.pi * delta ** 2 * r_eff
        root = math.sqrt(vol / (math.pi * delta))     # sqrt(R* delta) for V = pi delta^2 R*
        k_n, k_t = 2.0 * youngs_eff * root, 8.0 * shear_eff * root
        f_n = 4.0 / (3.0 * math.sqrt(math.pi)) * youngs_eff * math.sqrt(vol * delta)
        f_n -= damping * math.sqrt(k_n * m_eff) * u_n
        if clamp:
            f_n = max(f_n, 0.0)
        gamma_t = damping * math.sqrt(k_t * m_eff)
        if tangential == "liggghts":
            s = [spring[0] + u_t[0] * dt, spring[1] + u_t[1] * dt]
            along = s[0] * n[0] + s[1] * n[1]
            s = [s[0] - along * n[0], s[1] - along * n[1]]
            f_t = [-k_t * s[0], -k_t * s[1]]
            size = math.hypot(*f_t)
            if size > friction * abs(f_n):
                scale = friction * abs(f_n) / size
                f_t = [f_t[0] * scale, f_t[1] * scale]
                s = [-f_t[0] / k_t, -f_t[1] / k_t]
            else:
                f_t = [f_t[0] - gamma_t * u_t[0], f_t[1] - gamma_t * u_t[1]]
            spring[0], spring[1] = s
        else:
            e = spring[0:2]
            before = math.hypot(*e)
            along = e[0] * n[0] + e[1] * n[1]
            e = [e[0] - along * n[0], e[1] - along * n[1]]
            after = math.hypot(*e)
            if after > 0.0:
                e = [e[0] * before / after, e[1] * before / after]
            if f_n < spring[3] and spring[2] > 0.0:
                e = [e[0] * k_t / spring[2], e[1] * k_t / spring[2]]
            e = [e[0] - k_t * u_t[0] * dt, e[1] - k_t * u_t[1] * dt]
            size = math.hypot(*e)
            if size > friction * f_n:
                scale = friction * f_n / size if size > 0.0 else 0.0
                e = [e[0] * scale, e[1] * scale]
                f_t = list(e)
            else:
                f_t = [e[0] - gamma_t * u_t[0], e[1] - gamma_t * u_t[1]]
            spring[0], spring[1], spring[2], spring[3] = e[0], e[1], k_t, f_n
        f2 = [f_n * n[0] + f_t[0], f_n * n[1] + f_t[1]]     # on sphere 2; sphere 1 gets -f2
        torque = -arm * (n[0] * f2[1] - n[1] * f2[0])       # on each: (-a n) x f2 = (a n) x (-f2)
        return f2, torque, delta

    def kick(state):
        if state is None:
            return
        f2, torque, _ = state
        for k in range(2):
            v[0][k] -= 0.5 * dt * f2[k] / mass
            v[1][k] += 0.5 * dt * f2[k] / mass
        w[0] += 0.5 * dt * torque / inertia
        w[1] += 0.5 * dt * torque / inertia

    steps = int(round((GAP / (2.0 * SPEED) + 1.6 * hertz_time() + 2e-4) / dt))
    state, touching, max_overlap = forces(), 0, 0.0
    for _ in range(steps):
        kick(state)
        for i in range(2):
            for k in range(2):
                x[i][k] += dt * v[i][k]
        state = forces()
        kick(state)
        if state is not None:
            touching += 1
            max_overlap = max(max_overlap, state[2])
    n = contact_normal(offset)
    approach = -2.0 * SPEED * n[0]
    return {"duration": touching * dt, "max_overlap": max_overlap,
            "restitution": -((v[1][0] - v[0][0]) * n[0] + (v[1][1] - v[0][1]) * n[1]) / approach,
            "omega": 0.5 * (w[0] + w[1]), "separated": state is None}


def run_collision(shape, workdir, offset=0.0, dt=2e-6, **options):
    """Runs one collision deck with the launcher (no pytest) and measures it."""
    workdir = pathlib.Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(collision_deck(shape, offset=offset, dt=dt, **options))
    result = subprocess.run([str(LAUNCHER), "-in", "in.deck", "-log", "log.lammps", "-echo", "none",
                             "-screen", "none"], cwd=workdir, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"{shape}: exit {result.returncode}\n" + (workdir / "log.lammps").read_text()[-3000:])
    return measure(workdir, shape, offset, dt)


def _relative(value, reference):
    return (value - reference) / abs(reference) if reference else float("nan")


def _machine():
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                           capture_output=True, text=True).stdout.splitlines()
    dirty = [line[3:] for line in dirty]
    changes = f" with uncommitted changes to {', '.join(dirty)}" if dirty else ""
    return f"{cpu}, {os.cpu_count()} cores; commit {commit}{changes}"


MEASURES = (("duration", "contact duration [ms]", 1e3), ("max_overlap", "max overlap [mm]", 1e3),
            ("restitution", "normal restitution", 1.0), ("omega", "rebound omega_z [rad/s]", 1.0))


def _cells(runs, reference, oblique):
    """Mean over the orientations, its relative error and the largest relative error of a single run."""
    cells = []
    for key, _, factor in MEASURES:
        if key == "omega" and not oblique:
            cells.append("-")
            continue
        values = [m[key] for m in runs]
        mean = sum(values) / len(values)
        text = f"{mean * factor:.4f}"
        if runs[0] is not reference:
            text += f" ({100.0 * _relative(mean, reference[key]):+.2f}%"
            if len(values) > 1:
                text += f", max {100.0 * max(abs(_relative(v, reference[key])) for v in values):.2f}%"
            text += ")"
        cells.append(text)
    return cells


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--triangles", type=int, nargs="+", default=[80, 320, 1280, 5120])
    parser.add_argument("--orientations", type=int, default=4,
                        help="orientation pairs per icosphere resolution (the first is the tests' pair)")
    parser.add_argument("--dt", type=float, default=2e-6)
    parser.add_argument("--offsets", type=float, nargs="+", default=[0.0, 0.8, 0.5],
                        help="offsets between the lines of flight, as fractions of D (0: head-on)")
    parser.add_argument("--restitution", type=float, default=0.8)
    parser.add_argument("--friction", type=float, default=0.5)
    args = parser.parse_args()
    if not LAUNCHER.exists():
        sys.exit(f"{LAUNCHER} missing: run `make` first")
    start = time.time()
    print(f"machine: {_machine()}")
    print(f"D = {D} m, v = +-{SPEED} m/s, E = {YOUNGS:g} Pa, nu = {POISSON}, rho = {DENSITY:g} kg/m^3, "
          f"e = {args.restitution}, mu = {args.friction}, dt = {args.dt:g} s "
          f"(elastic Hertz contact time {hertz_time() * 1e3:.3f} ms)")
    print(f"icospheres: mean over {args.orientations} orientation pairs; in parentheses the relative error "
          "of the mean against the LIGGGHTS sphere run and the largest relative error of a single orientation")
    with tempfile.TemporaryDirectory(prefix="sphere_collision_study_") as scratch:
        for fraction in args.offsets:
            offset, oblique = fraction * D, fraction > 0.0
            options = dict(offset=offset, dt=args.dt, restitution=args.restitution, friction=args.friction)
            name = f"oblique, offset {fraction:g} D" if oblique else "head-on"
            t0 = time.time()
            reference = run_collision("sphere", os.path.join(scratch, f"{fraction}_sphere"), **options)
            rows = [("LIGGGHTS `model hertz tangential history`, spheres", [reference], time.time() - t0)]
            law = point_contact_spheres(offset, args.restitution, args.friction, args.dt,
                                        tangential="incremental", volume="lens")
            rows.append(("volumetric law on exact spheres (Python)", [law], None))
            for triangles in args.triangles:
                t0 = time.time()
                runs = [run_collision(triangles, os.path.join(scratch, f"{fraction}_{triangles}_{k}"),
                                      quats=quats, **options)
                        for k, quats in enumerate(orientation_pairs(args.orientations))]
                rows.append((f"icosphere_{triangles}", runs, (time.time() - t0) / len(runs)))
            print(f"\n{name}\n")
            print("| particles | " + " | ".join(label for _, label, _ in MEASURES) + " | run [s] |")
            print("|---" * (len(MEASURES) + 2) + "|")
            for label, runs, seconds in rows:
                cells = _cells(runs, reference, oblique)
                if not all(m["separated"] for m in runs):
                    cells[0] += " (not separated)"
                print(f"| {label} | " + " | ".join(cells) + f" | {'' if seconds is None else f'{seconds:.1f}'} |")
    print(f"\ntotal run time {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
