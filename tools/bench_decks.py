#!/usr/bin/python3
"""Whole-deck benchmarks: polyhedral particles against LIGGGHTS' own alternatives, one core, one after the
other in the same invocation, as time per particle and step ("Loop time" / (particles x steps)) and their
ratio. Not a test: it prints numbers (doc/benchmarks.md, "Whole decks against LIGGGHTS' alternatives").
Called by tools/bench_vs_multisphere.sh and tools/bench_tutorial_decks.sh:

  bench_decks.py multisphere [--quick] [cube] [rock]
      examples/bench_multisphere: a pile of 150 particles poured into a 10 x 10 cm box of 5 plane walls
      (in.pile_poly: fix wall/polyhedral; in.pile_multisphere: fix wall/gran), E 1e7, nu 0.25, e 0.5, mu 0.5,
      2500 kg/m^3, dt 1e-5; `settle` steps (25000) to form the pile, then a timed `run` of 25000 steps.
        cube  cube.stl at scale 0.01 against ../rocking/cube27.multisphere (27 spheres),
        rock  rock_40.obj at scale 0.01 (volume-equivalent diameter 1 cm) against rock40.multisphere (25 spheres
              inside the mesh, tools/fit_multisphere.py).
      The multisphere particle gets the polyhedron's mass and inertia tensor (fix particletemplate/multisphere
      ... mass ... inertia_tensor ... use_density), so both piles have the same particles but for the shape.
      --quick: 15000 + 2500 steps, the pile still falling (a smoke check, about a minute).

  bench_decks.py tutorial [--quick] [--steps S | --all] [--chute-steps C] [--chute-shape F]
                          [movingMeshGran] [hopper] [chute_wear]
      movingMeshGran: LIGGGHTS' tutorial as Debian ships it (liggghts-doc), spheres as shipped against the same
        deck with its particle lines converted to rock_40 of the spheres' volume (convert_to_polyhedra: atom
        style, pair style, template, integrator, wall fixes, erotate compute, orientation random at insertion);
        both without their dump lines, and both cut after the first S steps of the schedule (default 12000: the
        insertion stage, 8000 steps, and the first 4000 of the settling; --all: the whole deck, 70000 steps,
        68 min here today; --quick: 2000).
      hopper: examples/hopper/run.py (300 rock_40 of 2 cm against Hertz spheres of their volume; fill 4500
        steps, discharge 6000), one run after the other (--quick: fill 0.1 s, discharge 0.05 s).
      chute_wear (only when named): LIGGGHTS' tutorial (a stream poured onto a static mesh chute with wear),
        spheres as shipped against the deck converted by tools/convert_deck.py to --chute-shape (default
        schoenhardt.stl) of the spheres' volume, cut after the first C steps (default 40000; --quick 4000).

LIGGGHTS' own decks take a second or ten, so their loop times scatter most on a shared machine: they run
--repeat times (3; --quick 1) and each stage counts with the median (the table gives min-max); the polyhedral
decks run once. Runs in --workdir (default examples/bench_multisphere/post), Debian's `liggghts` for the
references and build/bin/liggghts-poly (make -j2 all) for the polyhedra. Prints the machine, the LIGGGHTS
version, the commit and whether the package sources differ from it or are newer than the build; at the end
the wall and CPU seconds of all runs (the loop times are wall times: a CPU share well below 100 % means the
machine was busy).
"""
import argparse
import os
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))

# BENCH_LAUNCHER=path: another build's launcher for the polyhedra (a before/after comparison).
POLY = pathlib.Path(os.environ.get("BENCH_LAUNCHER", ROOT / "build" / "bin" / "liggghts-poly")).resolve()
STOCK = shutil.which("liggghts") or str(POLY)
EXAMPLE = ROOT / "examples" / "bench_multisphere"
SHAPES = ROOT / "examples" / "shapes"
TUTORIALS = pathlib.Path("/usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public")
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
PACKAGE_SOURCES = ["src", "gpu", "Makefile", "Makefile.package"]


# machine, commit ---------------------------------------------------------------------------------------

def shell(command):
    result = subprocess.run(command, shell=True, capture_output=True, text=True, cwd=ROOT)
    return result.stdout.strip()


def print_header():
    model = shell("lscpu | sed -n 's/^Model name:[[:space:]]*//p'")
    print(f"machine: {os.cpu_count()} CPUs ({shell('nproc')} usable); {model}; load average "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())} at the start")
    version = shell("dpkg-query -W -f='${Version}' liggghts") or "unknown"
    print(f"LIGGGHTS: Debian {version} ({STOCK}); "
          f"polyhedra: {POLY.relative_to(ROOT) if ROOT in POLY.parents else POLY}")
    commit = shell("git rev-parse --short HEAD") or "unknown"
    modified = shell("git status --porcelain -- " + " ".join(PACKAGE_SOURCES))
    last = shell("git log -1 --format=%h -- " + " ".join(PACKAGE_SOURCES))
    state = f"package sources as committed, last changed in {last}" if not modified else \
        "package sources modified: " + ", ".join(line[3:] for line in modified.splitlines())
    print(f"commit: {commit} ({state})")
    library = ROOT / "build" / "lib" / "libpolyhedral.so"
    sources = [p for d in ("src", "gpu") for p in (ROOT / d).iterdir() if p.is_file()]
    if not library.exists() or not POLY.exists():
        raise SystemExit("no build: run `make -j2 all` first")
    newer = [p.name for p in sources if p.stat().st_mtime > library.stat().st_mtime]
    if newer:
        print(f"WARNING: the build is older than {', '.join(sorted(newer))}: run `make -j2 all`")
    print()
    sys.stdout.flush()


# running and reading LIGGGHTS ---------------------------------------------------------------------------

BUSY = {"wall": 0.0, "cpu": 0.0}


def timed(command, **kwargs):
    """subprocess.run(command) and its wall and CPU (user + sys, children included) seconds. The loop times
    LIGGGHTS prints are wall times: CPU well below wall means the shared machine took the core away."""
    before, start = resource.getrusage(resource.RUSAGE_CHILDREN), time.time()
    result = subprocess.run(command, env=dict(os.environ, **MPI_ENV), **kwargs)
    after, wall = resource.getrusage(resource.RUSAGE_CHILDREN), time.time() - start
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    BUSY["wall"] += wall
    BUSY["cpu"] += cpu
    return result, wall, cpu


def print_busy():
    share = BUSY["cpu"] / BUSY["wall"] if BUSY["wall"] else 1.0
    print(f"runs: {BUSY['wall']:.0f} s wall, {BUSY['cpu']:.0f} s CPU ({share:.0%})" +
          ("" if share > 0.9 else ": WARNING, the machine was busy; loop times are wall times and include the wait"))


def run_liggghts(executable, deck, workdir, log, variables=(), runs_needed=None):
    """Runs `executable -in deck` in workdir (screen output to log + '.screen': LIGGGHTS 3.8 crashes reading
    an STL with -screen none); returns the runs of the log, the wall and the CPU time. runs_needed: an error
    after that many runs is let pass (a build older than what the deck's tail asks of it)."""
    command = [str(executable), "-in", str(deck), "-log", log]
    for name, value in variables:
        command += ["-var", name, str(value)]
    with open(workdir / (log + ".screen"), "w") as screen:
        result, wall, cpu = timed(command, cwd=workdir, stdout=screen, stderr=subprocess.STDOUT)
    text = (workdir / log).read_text(errors="replace") if (workdir / log).exists() else ""
    runs = parse_log(text)
    if (result.returncode != 0 or "ERROR" in text) and not (runs_needed and len(runs) >= runs_needed):
        tail = (workdir / (log + ".screen")).read_text(errors="replace")[-3000:]
        raise SystemExit(f"{' '.join(command)} (in {workdir}) failed ({result.returncode}):\n{tail}")
    return runs, wall, cpu


LOOP = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")
PAIR = re.compile(r"^Pair +time \(%\) = \S+ \((\S+)\)")
NEIGHS = re.compile(r"^Ave neighs/atom = (\S+)")


def parse_log(text):
    """[{'columns': [...], 'rows': [[float...]], 'loop': s, 'steps': n, 'atoms': n, 'pair': % of the loop in
    the pair style, 'neighs': neighbour-list pairs per particle at the end}] per `run` command."""
    runs, columns, rows = [], None, []
    for line in text.splitlines():
        words = line.split()
        match = LOOP.match(line)
        pair, neighs = PAIR.match(line), NEIGHS.match(line)
        if pair and runs:
            runs[-1]["pair"] = float(pair.group(1))
        elif neighs and runs:
            runs[-1]["neighs"] = float(neighs.group(1))
        elif match:
            runs.append({"columns": columns, "rows": rows, "loop": float(match.group(1)),
                         "procs": int(match.group(2)), "steps": int(match.group(3)), "atoms": int(match.group(4))})
            columns, rows = None, []
        elif words[:1] == ["Step"]:
            columns, rows = words, []
        elif columns and len(words) == len(columns):
            try:
                rows.append([float(w) for w in words])
            except ValueError:
                pass
    return runs


def column(run, name):
    k = run["columns"].index(name)
    return [row[k] for row in run["rows"]]


def median_runs(repeats):
    """The runs of the first of several identical runs of a deck, each with the median of its loop times
    ('loop') and all of them ('loops')."""
    merged = []
    for k, run in enumerate(repeats[0]):
        loops = sorted(r[k]["loop"] for r in repeats)
        merged.append(dict(run, loop=loops[len(loops) // 2] if len(loops) % 2 else
                           (loops[len(loops) // 2 - 1] + loops[len(loops) // 2]) / 2, loops=loops))
    return merged


def spread(run):
    """' (min-max)' of a run's repeated loop times, '' for one."""
    loops = run.get("loops", [])
    return f" ({loops[0]:.3g}-{loops[-1]:.3g})" if len(loops) > 1 else ""


def particle_steps(run, per_particle=1):
    """Particles x steps of one run from its thermo rows: each interval between outputs counted with the
    particles at its end (insertion happens on the first step of an interval)."""
    steps, atoms = column(run, "Step"), column(run, "Atoms")
    total = sum((steps[i] - steps[i - 1]) * atoms[i] for i in range(1, len(steps)))
    return total / per_particle


def us(seconds):
    return f"{seconds * 1e6:.3g}"


# multisphere piles -------------------------------------------------------------------------------------

PILE = {"N": 150, "rho": 2500.0, "scale": 0.01, "box": 0.05, "top": 0.06}
CASES = {
    "cube": {"mesh": SHAPES / "cube.stl", "template": ROOT / "examples" / "rocking" / "cube27.multisphere"},
    "rock": {"mesh": SHAPES / "rock_40.obj", "template": EXAMPLE / "rock40.multisphere"},
}


def multisphere_variables(case):
    """-var pairs of in.pile_multisphere: the template, its sphere count, the mesh's mass and inertia tensor
    about its centre of mass, and the template's volume coverage of the mesh."""
    import fit_multisphere  # numpy: only the multisphere piles need it (tools/bench_gpu_decks.py runs without)
    vertices, triangles = fit_multisphere.read_mesh(case["mesh"])
    volume, centre, inertia = fit_multisphere.mass_properties(vertices, triangles)
    centres, radii, _ = fit_multisphere.read_template(case["template"])
    covered = fit_multisphere.coverage(vertices - centre, triangles, centres, radii, 64)
    rho, s = PILE["rho"], PILE["scale"]
    i = inertia * rho * s ** 5
    variables = [("TEMPLATE", case["template"]), ("NS", len(radii)), ("SCALE", s),
                 ("MASS", repr(volume * rho * s ** 3))]
    variables += [(name, repr(i[j, k])) for name, j, k in
                  (("IXX", 0, 0), ("IXY", 0, 1), ("IXZ", 0, 2), ("IYY", 1, 1), ("IYZ", 1, 2), ("IZZ", 2, 2))]
    return variables, len(radii), covered


def pile_result(runs, per_particle, quick):
    """Numbers and checks of one pile: [settle run, timed run]."""
    settle, timed = runs
    ke = column(settle, "ke") + column(timed, "ke")
    last = dict(zip(timed["columns"], timed["rows"][-1]))
    particles = round(last["Atoms"] / per_particle)
    box, top = PILE["box"], PILE["top"]
    inside = (-box < last["xmin"] and last["xmax"] < box and -box < last["ymin"] and last["ymax"] < box
              and last["zmin"] > 0)
    peak = max(ke)
    result = {"particles": particles, "lost": PILE["N"] - particles, "peak": peak,
              "ke_start": column(timed, "ke")[0] / peak, "ke_end": ke[-1] / peak,
              "zmax": last["zmax"], "inside": inside, "loop": timed["loop"], "spread": spread(timed),
              "steps": timed["steps"],
              "per": timed["loop"] / (particles * timed["steps"])}
    problems = []
    if result["lost"]:
        problems.append(f"{result['lost']} lost")
    if not inside:
        problems.append("centres outside the box")
    if result["ke_end"] > 1e-3:
        problems.append("kinetic energy above 1e-3 of its peak")
    if result["zmax"] > top:
        problems.append(f"a centre above {top * 1000:.0f} mm")
    if not problems:
        result["formed"] = "yes"
    else:
        result["formed"] = ("(--quick: still falling) " if quick else "NO: ") + "; ".join(problems)
    return result


def bench_multisphere(a, workdir):
    settle, steps = (15000, 2500) if a.quick else (25000, 25000)
    print(f"Piles of {PILE['N']} particles (volume-equivalent diameter 1 cm, 2500 kg/m^3) in a 10 x 10 cm box of 5 "
          f"plane walls, E 1e7, nu 0.25, e 0.5, mu 0.5, dt 1e-5: {settle} steps to form the pile, then {steps} "
          "timed steps (the second run's Loop time). KE: translational + rotational, as a fraction of its peak.")
    print()
    header = ("| shape | model | particles (lost) | KE peak [J] | KE at start / end of the timed run | top centre [mm] "
              "| timed run: Loop time [s] | per particle-step [us] | pile formed |")
    rows, ratios = [header, "|---|---|---|---|---|---|---|---|---|"], []
    for name in a.cases:
        case = CASES[name]
        variables, nspheres, covered = multisphere_variables(case)
        common = [("N", PILE["N"]), ("settle", settle), ("steps", steps)]
        poly_runs, poly_wall, poly_cpu = run_liggghts(POLY, EXAMPLE / "in.pile_poly", workdir, f"log.{name}_poly",
                                            common + [("SHAPE", case["mesh"]), ("SCALE", PILE["scale"])])
        repeats, ms_wall, ms_cpu = [], 0.0, 0.0
        for k in range(a.repeat):
            runs, wall, cpu = run_liggghts(STOCK, EXAMPLE / "in.pile_multisphere", workdir,
                                           f"log.{name}_multisphere" + (f".{k + 1}" if k else ""), common + variables)
            repeats.append(runs)
            ms_wall, ms_cpu = ms_wall + wall, ms_cpu + cpu
        ms_runs = median_runs(repeats)
        results = [("polyhedral, " + case["mesh"].name, pile_result(poly_runs, 1, a.quick), poly_wall, poly_cpu),
                   (f"multisphere, {nspheres} spheres ({covered:.1%} of the volume)",
                    pile_result(ms_runs, nspheres, a.quick), ms_wall, ms_cpu)]
        for model, r, wall, cpu in results:
            rows.append(f"| {name} | {model} | {r['particles']} ({r['lost']}) | {r['peak']:.3g} | "
                        f"{r['ke_start']:.1e} / {r['ke_end']:.1e} | {r['zmax'] * 1000:.1f} | "
                        f"{r['loop']:.2f}{r['spread']} "
                        f"(whole run: {wall:.0f} wall, {cpu:.0f} CPU) | {us(r['per'])} | {r['formed']} |")
        ratios.append((name, results[0][1]["per"] / results[1][1]["per"]))
        print(f"{name}: polyhedral {us(results[0][1]['per'])} us, multisphere {us(results[1][1]['per'])} us per "
              f"particle-step: ratio {ratios[-1][1]:.1f}")
        sys.stdout.flush()
    print()
    print("\n".join(rows))
    print()
    for name, ratio in ratios:
        print(f"ratio polyhedral / multisphere, {name}: {ratio:.1f}x per particle-step")


# tutorial decks ----------------------------------------------------------------------------------------

def convert_to_polyhedra(deck, shape, shapes_dir):
    """The sphere deck's particle lines as polyhedra of `shape` with the spheres' volume (rock_40 and the
    icospheres have volume pi/6: scale = diameter): atom style, pair style, sphere template, integrator,
    wall/gran (primitive and mesh; the model keywords go), compute erotate/sphere, and `orientation random`
    for the insertion fixes. Everything else stays as written."""
    out = []
    for line in deck.splitlines():
        words = line.split("#")[0].split()
        style = words[3] if len(words) > 3 and words[0] in ("fix", "compute") else None
        if words[:1] == ["atom_style"]:
            line = "atom_style polyhedron"
        elif words[:1] == ["pair_style"] and words[1:2] == ["gran"]:
            line = "pair_style polyhedral/volumetric"
        elif style == "nve/sphere":
            line = " ".join(words[:3] + ["nve/polyhedron"] + words[4:])
        elif style == "wall/gran":
            start = min(words.index(k) for k in ("primitive", "mesh") if k in words)
            line = " ".join(words[:3] + ["wall/polyhedral"] + words[start:])
        elif style == "particletemplate/sphere":
            k = words.index("radius")
            if words[k + 1] != "constant":
                raise SystemExit(f"only `radius constant R` converts: {line}")
            rest = words[k + 3:]
            line = " ".join(words[:3] + ["particletemplate/polyhedron"] + words[4:k] +
                            ["file", str(shapes_dir / shape), "scale", repr(2 * float(words[k + 2]))] + rest)
        elif style == "erotate/sphere":
            line = " ".join(words[:3] + ["erotate/polyhedron"] + words[4:])
        elif style and style.startswith("insert/") and "orientation" not in line:
            line = line.replace(" distributiontemplate ", " orientation random distributiontemplate ", 1)
        out.append(line)
    return "\n".join(out) + "\n"


def strip_dumps(deck):
    """The deck without its dump and undump lines (output, not simulation)."""
    return "\n".join(line for line in deck.splitlines() if line.split()[:1] not in (["dump"], ["undump"])) + "\n"


def cut_schedule(deck, limit):
    """The deck up to its first `limit` steps: `run N [upto]` lines counted (N may be a ${variable} of a
    `variable NAME equal NUMBER` line above it), the one crossing `limit` shortened (as `run M upto`),
    everything after it dropped. limit None: the whole deck."""
    if limit is None:
        return deck
    values, out, step = {}, [], 0
    for line in deck.splitlines():
        words = line.split("#")[0].split()
        if words[:1] == ["variable"] and len(words) == 4 and words[2] == "equal":
            try:
                values[words[1]] = float(words[3])
            except ValueError:
                pass
        if words[:1] == ["run"]:
            count = int(float(re.sub(r"\$\{(\w+)\}", lambda m: repr(values[m.group(1)]), words[1])))
            end = count if "upto" in words[2:] else step + count
            if end >= limit:
                out.append(f"run {limit} upto")
                return "\n".join(out) + "\n"
            step = end
        out.append(line)
    return "\n".join(out) + "\n"


def stage_names(deck):
    """A name per `run` line: the last comment above it other than `#run` (the tutorials label their stages)."""
    names, comment = [], ""
    for line in deck.splitlines():
        if line.startswith("#") and line.strip("# ") not in ("", "run"):
            comment = line.strip("# ")
        elif line.split()[:1] == ["run"]:
            names.append(comment or f"run {len(names) + 1}")
    return names


def stage_table(deck, names, rocks, spheres, extra=None, target=None):
    """Prints one row per `run` of the two logs (stage name, steps, particles, rocks' and spheres' loop time
    and time per particle-step, their ratio, the share of the pair style and the neighbour-list pairs per
    particle) and a row for all runs; `extra` (name, function of a run) adds a column of both. Returns the
    ratio over all runs."""
    extra_head = f" {extra[0]}: rocks / spheres |" if extra else ""
    print("| stage | steps | particles: rocks / spheres |" + extra_head + " rocks: loop [s], per particle-step [us] | "
          "spheres: loop [s], per particle-step [us] | ratio | rocks / spheres: Pair %, neighbours per particle |")
    print("|---|---:|---|" + ("---|" if extra else "") + "---|---|---:|---|")
    totals = [[0.0, 0.0], [0.0, 0.0]]
    for k, pair in enumerate(zip(rocks, spheres)):
        per = []
        for total, run in zip(totals, pair):
            work = particle_steps(run)
            total[0] += run["loop"]
            total[1] += work
            per.append(run["loop"] / work if work else None)
        r, s = pair
        ratio = f"{per[0] / per[1]:.1f}" if per[0] and per[1] and r["steps"] > 1 else "-"
        cells = [names[k] if k < len(names) else str(k + 1), str(r["steps"]), f"{r['atoms']} / {s['atoms']}"]
        if extra:
            cells.append(f"{extra[1](r)} / {extra[1](s)}")
        cells += [f"{run['loop']:.2f}{spread(run)}, {us(t) if t else '-'}" for run, t in zip(pair, per)]
        cells += [ratio, f"{r.get('pair', 0):.0f} / {s.get('pair', 0):.0f}, "
                         f"{r.get('neighs', 0):.1f} / {s.get('neighs', 0):.1f}"]
        print("| " + " | ".join(cells) + " |")
    per = [loop / work for loop, work in totals]
    cells = ["all", str(sum(r["steps"] for r in rocks)), ""] + ([""] if extra else [])
    cells += [f"{loop:.2f}, {us(t)}" for (loop, _), t in zip(totals, per)] + [f"**{per[0] / per[1]:.1f}**", ""]
    print("| " + " | ".join(cells) + " |")
    print()
    print(f"ratio rocks / spheres, {deck}: {per[0] / per[1]:.1f}x per particle-step" +
          (f" (target: at most {target})" if target else ""))
    return per[0] / per[1]


def bench_moving_mesh(a, workdir):
    limit = 2000 if a.quick else (None if a.all else a.steps)
    bench_tutorial_deck(a, workdir, "movingMeshGran", limit, "rock_40.obj",
                        lambda spheres, here: convert_to_polyhedra(spheres, "rock_40.obj", SHAPES), target=5)


def bench_chute(a, workdir):
    def convert(spheres, here):
        result = subprocess.run([sys.executable, str(ROOT / "tools" / "convert_deck.py"), "in.spheres", "in.rocks",
                                 "--shape", a.chute_shape, "--shapes-dir", str(SHAPES)], cwd=here,
                                capture_output=True, text=True)
        if result.returncode != 0:
            raise SystemExit(f"ERROR: chute_wear with --chute-shape {a.chute_shape}: tools/convert_deck.py said:\n"
                             f"{(result.stdout + result.stderr).strip()}")
        return (here / "in.rocks").read_text()
    bench_tutorial_deck(a, workdir, "chute_wear", 4000 if a.quick else a.chute_steps, a.chute_shape, convert)


# Appended to a converted deck after its schedule: the pair loop's evaluation statistics (compute
# pair/polyhedral/local's vector 4-10) printed by one `run 0`, which the timed runs before it do not see; then, by a
# second, the contacts whose depth is capped at 3 V / A (11: several spots; a build before it stops there).
EVALUATIONS = """
compute ev all pair/polyhedral/local
thermo_style custom step atoms c_ev[4] c_ev[5] c_ev[6] c_ev[7] c_ev[8] c_ev[9] c_ev[10]
thermo_modify format float %.10g
run 0
thermo_style custom step atoms c_ev[6] c_ev[11]
thermo_modify format float %.10g
run 0
"""


def evaluation_breakdown(log_text):
    """The rocks' pair evaluations over the deck from EVALUATIONS' thermo line: a sentence, or None."""
    lines = log_text.splitlines()
    for k, line in enumerate(lines):
        if "ev[4]" in line and line.split()[:1] == ["Step"] and k + 1 < len(lines):
            try:
                candidates, hinted, contacts, parted, misses, cached, cached_misses = (
                    float(w) for w in lines[k + 1].split()[2:9])
            except ValueError:
                return None
            if candidates <= 0:
                return None
            share = lambda n: f"{100 * n / candidates:.1f} %"
            # (contacts, of them capped) of the second run 0, which evaluated the pairs once more
            capped = next(((float(after.split()[2]), float(after.split()[3]))
                           for before, after in zip(lines[k + 2:], lines[k + 3:])
                           if "ev[11]" in before and before.split()[:1] == ["Step"] and len(after.split()) > 3), None)
            return (f"the rocks' neighbour pairs in reach of each other, summed over the steps: {candidates:.4g}; "
                    f"skipped as still apart (within their gap, or behind the plane that parted them) {share(hinted)}, "
                    f"evaluated into a contact {share(contacts)}, found apart by the slab or a parting plane "
                    f"{share(parted)}, found apart "
                    f"by the whole path (near misses) {share(misses)}; from the crossing cache "
                    f"{100 * cached / max(contacts, 1):.1f} % of the contacts and "
                    f"{100 * cached_misses / max(misses, 1):.1f} % of the near misses" +
                    ("" if capped is None else
                     f"; their depth capped at 3 V / A (several spots) {100 * capped[1] / max(capped[0], 1):.1f} % "
                     "of the contacts") + " (compute pair/polyhedral/local's vector)")
    return None


def bench_tutorial_deck(a, workdir, deck, limit, shape, convert, target=None):
    """A tutorial of liggghts-doc as shipped (spheres) against its particle lines converted to `shape`
    (convert(sphere deck, directory) -> polyhedral deck), both cut after `limit` steps, without dumps."""
    source = TUTORIALS / deck / f"in.{deck}"
    if not source.exists():
        raise SystemExit(f"{source} missing: install Debian's liggghts-doc (tools/debian_deps.sh)")
    spheres = cut_schedule(strip_dumps(source.read_text()), limit)
    here = workdir / deck
    if here.exists():
        shutil.rmtree(here)
    shutil.copytree(source.parent / "meshes", here / "meshes")
    (here / "post").mkdir()
    (here / "in.spheres").write_text(spheres)
    (here / "in.rocks").write_text(convert(spheres, here) + EVALUATIONS)
    print(f"{deck} ({source}), {'the whole deck' if limit is None else f'its first {limit} steps'}: "
          f"spheres as shipped against {shape} of their volume (decks in {here}; `diff in.spheres in.rocks` shows "
          "the conversion)")
    sys.stdout.flush()
    runs = {}
    for name, executable, count in (("rocks", POLY, 1), ("spheres", STOCK, a.repeat)):
        repeats = []
        for k in range(count):
            log = f"log.{name}" + (f".{k + 1}" if k else "")
            # The rocks' deck ends with EVALUATIONS, which builds before its counts cannot print.
            logs, wall, cpu = run_liggghts(executable, here / f"in.{name}", here, log,
                                           runs_needed=len(stage_names(spheres)) if name == "rocks" else None)
            repeats.append(logs)
            print(f"  {name}: {wall:.0f} s wall, {cpu:.0f} s CPU")
            sys.stdout.flush()
        runs[name] = median_runs(repeats)
    print()
    counts = runs["rocks"][-1]["atoms"], runs["spheres"][-1]["atoms"]
    if counts[0] != counts[1]:
        print(f"the insertion placed {counts[0]} rocks and {counts[1]} spheres in the same region (the rocks' overlap "
              "check and all_in go by the shape): the ratios are per particle-step")
        print()
    stage_table(deck, stage_names(spheres), runs["rocks"], runs["spheres"], target=target)
    breakdown = evaluation_breakdown((here / "log.rocks").read_text(errors="replace"))
    if breakdown:
        print(breakdown)
    print()
    sys.stdout.flush()


def bench_hopper(a, workdir):
    out = workdir / "hopper"
    command = [sys.executable, str(ROOT / "examples" / "hopper" / "run.py"), "--no-report",
               "--out", str(out), "--launcher", str(POLY), "--liggghts", STOCK]
    if a.quick:
        command += ["--settle", "0.1", "--discharge", "0.05"]
    print(f"hopper (examples/hopper/run.py{' --settle 0.1 --discharge 0.05' if a.quick else ''}; output in {out}): "
          "300 rock_40 of 2 cm against Hertz spheres of their volume, one run after the other")
    sys.stdout.flush()
    runs = {}
    for skip, name, count in (("spheres", "rock", 1), ("rock", "spheres", a.repeat)):
        repeats = []
        for _ in range(count):
            result, wall, cpu = timed(command + ["--skip", skip], capture_output=True, text=True)
            if result.returncode != 0:
                raise SystemExit(f"{' '.join(command)} failed:\n{(result.stdout + result.stderr)[-3000:]}")
            print(f"  {name}: {wall:.0f} s wall, {cpu:.0f} s CPU")
            repeats.append(parse_log((out / f"log.hopper_{name}").read_text(errors="replace")))
        runs[name] = median_runs(repeats)
    print()
    rocks, spheres = runs["rock"], runs["spheres"]
    stage_table("hopper", ["fill", "discharge"], rocks, spheres,
                extra=("discharged at its end", lambda run: f"{column(run, 'ndis')[-1]:.0f}"), target=10)
    print()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--workdir", default=str(EXAMPLE / "post"),
                        help="where the runs go (examples/bench_multisphere/post)")
    common.add_argument("--quick", action="store_true", help="short runs: a smoke check")
    common.add_argument("--repeat", type=int, default=None,
                        help="runs of each LIGGGHTS reference deck, their loop times the median (3; --quick 1)")
    sub = p.add_subparsers(dest="command", required=True)
    ms = sub.add_parser("multisphere", parents=[common],
                        help="piles of cubes and rocks against LIGGGHTS multisphere particles")
    ms.add_argument("cases", nargs="*", help="cube, rock (default both)")
    tu = sub.add_parser("tutorial", parents=[common],
                        help="movingMeshGran and the hopper example, rocks against spheres")
    tu.add_argument("--steps", type=int, default=12000, help="movingMeshGran: the first STEPS steps (12000)")
    tu.add_argument("--all", action="store_true", help="movingMeshGran: the whole deck (70000 steps)")
    tu.add_argument("--chute-steps", type=int, default=40000, help="chute_wear: the first STEPS steps (40000)")
    tu.add_argument("--chute-shape", default="schoenhardt.stl", help="chute_wear: the particle mesh (schoenhardt.stl)")
    tu.add_argument("decks", nargs="*", help="movingMeshGran, hopper, chute_wear (default the first two)")
    a = p.parse_args()
    if a.repeat is None:
        a.repeat = 1 if a.quick else 3
    workdir = pathlib.Path(a.workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    print_header()
    start = time.time()
    if a.command == "multisphere":
        a.cases = a.cases or ["cube", "rock"]
        if set(a.cases) - set(CASES):
            p.error(f"unknown case: {' '.join(sorted(set(a.cases) - set(CASES)))} (cube, rock)")
        bench_multisphere(a, workdir)
    else:
        a.decks = a.decks or ["movingMeshGran", "hopper"]
        unknown = set(a.decks) - {"movingMeshGran", "hopper", "chute_wear"}
        if unknown:
            p.error(f"unknown deck: {' '.join(sorted(unknown))} (movingMeshGran, hopper, chute_wear)")
        if "movingMeshGran" in a.decks:
            bench_moving_mesh(a, workdir)
        if "hopper" in a.decks:
            bench_hopper(a, workdir)
        if "chute_wear" in a.decks:
            bench_chute(a, workdir)
    print_busy()
    print(f"benchmark: {time.time() - start:.0f} s wall")


if __name__ == "__main__":
    main()
