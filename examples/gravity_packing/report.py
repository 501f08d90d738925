#!/usr/bin/env python3
"""Tables and a plot from gravity-packing logs (in.packing, in.packing_spheres).

    python3 report.py LOG [LOG ...] [--rows 10] [--png post/ms_per_step_vs_contacts.png] [--best]

For each log (the main run: the thermo block with the most steps):
  * time per step over intervals: the wall time (thermo `CPU`, seconds since the run started) between thermo
    outputs, grouped into --rows intervals; contact pairs at the interval (mean of the thermo outputs in
    it, both ends included); ranks x us per contact = ms/step x ranks / contacts x 1000 (core-microseconds
    per contact on the CPU);
  * the final state: kinetic energy, contact pairs, and the packing fraction of the bed from the final dump
    (post/final_*_N<N>_<floor>.dump, the `dump final` line of the log);
  * the GPU pair style's own timing line (pair/pose uploads, kernels, downloads, device memory), if any;
  * LIGGGHTS' timing breakdown: Pair, Neigh, Comm, Outpt (output) and Other in % of the loop time.
    LIGGGHTS 3.8 has no Modify line: the fixes (integration, gravity, contact history) are in Other.
    Logs of newer LAMMPS-style tables (Section | ... | %total) are read too, Modify included.

--best merges repeats of the same run (same kind, N, ranks and steps: the trajectory is the same): each thermo
interval counts with the smallest wall time among the repeats, which removes most of what other jobs on a shared
machine add; the breakdown is the fastest repeat's.

Packing fraction (floor tops at z = 0, particles of volume pi/6 D^3, D from make_packing.py):
  * phi_bed = n V_p / (A H), with A = Lx Ly the periodic floor area and H = 2 <z_c> the bed height, <z_c> the
    mean centre height of the n falling particles: for a bed of uniform solid fraction between 0 and H the mean
    centre height is H/2 (a square monolayer of spheres on a plane gives H = D and phi = pi/6);
  * phi_slab = n_slab V_p / (A (H - 2D)), the n_slab particles with centres in [D, H - D], away from floor and
    surface; only when H >= 4 D.
Particles whose centres are above H + 2 D (still bouncing) are counted and listed as `airborne`.
Bounding-sphere pairs at the end: pairs of particles, not both floor, whose bounding spheres (radius D/2 for
spheres, the Schoenhardt polyhedron's 0.931 D for polyhedra) overlap in the final dump, i.e. the pairs the
narrow phase examines (the dump's 6 significant digits make it approximate for touching spheres).

The plot (matplotlib, Agg) has ms/step (log scale) against contact pairs, one point per thermo interval and
one series per log; without matplotlib the
tables are printed and the plot skipped.
"""
import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_packing import BOUNDING_RADIUS, D  # noqa: E402

TIMING_OLD = re.compile(r"^(Pair|Neigh|Comm|Outpt|Modify|Other)\s+time \(%\) = (\S+) \((\S+)\)")
TIMING_NEW = re.compile(r"^(Pair|Neigh|Comm|Output|Modify|Other)\s*\|.*\|\s*(\S+)\s*$")
LOOP = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")
LABEL = re.compile(r"^gravity packing( \(spheres\))?: N (\d+)(?: pair (\S+) precision (\S+))? steps (\d+)"
                   r"(?: floor (\S+))?")
GPU = re.compile(r"^Pair polyhedral/volumetric/gpu .*")
DUMP = re.compile(r"^dump\s+final\s+all\s+custom\s+\d+\s+(\S+\.dump)")


def parse_log(path):
    lines = open(path, errors="replace").read().splitlines()
    blocks, label, dump, gpu = [], {}, None, None
    i = 0
    while i < len(lines):
        line = lines[i]
        m = LABEL.match(line)
        if m:
            label = {"spheres": bool(m.group(1)), "N": int(m.group(2)), "pair": m.group(3) or "gran hertz",
                     "precision": m.group(4) or "double", "floor": m.group(6) or "particles"}
        if GPU.match(line):
            gpu = line.strip()
        m = DUMP.match(line.strip())
        if m and "${" not in m.group(1):
            dump = m.group(1)
        words = line.split()
        if words and words[0] == "Step" and "CPU" in words:
            columns = words
            rows = []
            i += 1
            while i < len(lines) and not lines[i].startswith("Loop time"):
                values = lines[i].split()
                if len(values) == len(columns):
                    try:
                        rows.append([float(v) for v in values])
                    except ValueError:
                        pass
                i += 1
            block = {"columns": columns, "rows": rows, "timing": {}}
            if i < len(lines):
                m = LOOP.match(lines[i])
                if m:
                    block.update(loop=float(m.group(1)), ranks=int(m.group(2)), steps=int(m.group(3)),
                                 atoms=int(m.group(4)))
                i += 1
                while i < len(lines) and not lines[i].startswith("Nlocal"):
                    t = TIMING_OLD.match(lines[i]) or TIMING_NEW.match(lines[i])
                    if t:
                        name = {"Outpt": "Output"}.get(t.group(1), t.group(1))
                        block["timing"][name] = float(t.group(t.lastindex))
                    i += 1
            blocks.append(block)
            continue
        i += 1
    if not blocks:
        raise SystemExit("%s: no thermo output with a CPU column" % path)
    run = max(blocks, key=lambda b: b.get("steps", 0))
    run.update(label)
    run["path"] = path
    run["dump"] = dump
    run["gpu"] = gpu
    return run


def column(run, *names):
    for name in names:
        if name in run["columns"]:
            return [row[run["columns"].index(name)] for row in run["rows"]]
    return None


def intervals(run, rows):
    """[(step0, step1, ms/step, mean contacts)] over `rows` groups of thermo intervals."""
    steps = column(run, "Step")
    cpu = column(run, "CPU")
    contacts = column(run, "contacts", "c_contacts", "v_contacts")
    n = len(steps) - 1
    if n < 1:
        return []
    groups = min(rows, n)
    out = []
    for g in range(groups):
        a, b = g * n // groups, (g + 1) * n // groups
        ms = 1000.0 * (cpu[b] - cpu[a]) / (steps[b] - steps[a])
        c = sum(contacts[a:b + 1]) / (b - a + 1) if contacts else float("nan")
        out.append((int(steps[a]), int(steps[b]), ms, c))
    return out


def per_output(run):
    """ms/step of each thermo interval and the mean contact count at its two ends (for the plot)."""
    steps, cpu = column(run, "Step"), column(run, "CPU")
    contacts = column(run, "contacts", "c_contacts", "v_contacts")
    if not contacts:
        return [], []
    xs, ys = [], []
    for k in range(1, len(steps)):
        xs.append(0.5 * (contacts[k - 1] + contacts[k]))
        ys.append(1000.0 * (cpu[k] - cpu[k - 1]) / (steps[k] - steps[k - 1]))
    return xs, ys


def read_last_snapshot(path):
    lines = open(path).read().splitlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    bounds = max(i for i, line in enumerate(lines[:start]) if line.startswith("ITEM: BOX BOUNDS"))
    box = [[float(v) for v in lines[bounds + k].split()[:2]] for k in (1, 2, 3)]
    columns = lines[start].split()[2:]
    rows = [[float(v) for v in line.split()] for line in lines[start + 1:] if line and not line.startswith("ITEM")]
    return box, columns, rows


def find_dump(run):
    if not run["dump"]:
        return None
    logdir = os.path.dirname(os.path.abspath(run["path"]))
    for base in (os.getcwd(), os.path.dirname(logdir), logdir):
        for candidate in (os.path.join(base, run["dump"]), os.path.join(base, os.path.basename(run["dump"]))):
            if os.path.exists(candidate):
                return candidate
    return None


def bounding_pairs(box, columns, rows, radius):
    """Pairs of particles (not both floor) whose bounding spheres overlap: the narrow phase's pairs."""
    ix, iy, iz, it = (columns.index(c) for c in ("x", "y", "z", "type"))
    lx, ly = box[0][1] - box[0][0], box[1][1] - box[1][0]
    cut = 2.0 * radius
    nx, ny = max(1, int(lx // cut)), max(1, int(ly // cut))
    cx, cy = lx / nx, ly / ny
    cells = {}
    for n, row in enumerate(rows):
        key = (int((row[ix] - box[0][0]) // cx) % nx, int((row[iy] - box[1][0]) // cy) % ny,
               int((row[iz] - box[2][0]) // cut))
        cells.setdefault(key, []).append(n)
    count = 0
    for (kx, ky, kz), members in cells.items():
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    other = cells.get(((kx + dx) % nx, (ky + dy) % ny, kz + dz))
                    if not other:
                        continue
                    for a in members:
                        ra = rows[a]
                        for b in other:
                            if b <= a:
                                continue
                            rb = rows[b]
                            if ra[it] == 2 and rb[it] == 2:
                                continue
                            ddx, ddy, ddz = ra[ix] - rb[ix], ra[iy] - rb[iy], ra[iz] - rb[iz]
                            ddx -= lx * round(ddx / lx)
                            ddy -= ly * round(ddy / ly)
                            if ddx * ddx + ddy * ddy + ddz * ddz < cut * cut:
                                count += 1
    return count


def packing_fraction(path, radius):
    box, columns, rows = read_last_snapshot(path)
    it, iz = columns.index("type"), columns.index("z")
    z = [row[iz] for row in rows if int(row[it]) == 1]
    area = (box[0][1] - box[0][0]) * (box[1][1] - box[1][0])
    volume = math.pi / 6.0 * D ** 3
    height = 2.0 * sum(z) / len(z)
    result = {"n": len(z), "H": height, "phi_bed": len(z) * volume / (area * height),
              "airborne": sum(1 for v in z if v > height + 2.0 * D), "phi_slab": None,
              "pairs": bounding_pairs(box, columns, rows, radius)}
    if height >= 4.0 * D:
        inside = sum(1 for v in z if D <= v <= height - D)
        result["phi_slab"] = inside * volume / (area * (height - 2.0 * D))
    return result


def name(run):
    label = "spheres (gran hertz)" if run.get("spheres") else \
        "polyhedra (%s, %s)" % (run.get("pair", "?"), run.get("precision", "?"))
    if run.get("floor") == "plane":
        label += ", plane floor"
    return label + (", best of %d" % run["repeats"] if run.get("repeats", 1) > 1 else "")


def best_of(runs):
    """Repeats of one run (same kind, N, ranks, steps and thermo steps) merged: for each thermo interval the
    smallest wall time of the repeats; the breakdown, dump and counts of the fastest repeat."""
    groups = {}
    for run in runs:
        key = (name(run), run.get("N"), run.get("ranks"), run.get("steps"), tuple(column(run, "Step")))
        groups.setdefault(key, []).append(run)
    merged = []
    for group in groups.values():
        fastest = min(group, key=lambda r: r.get("loop", float("inf")))
        if len(group) > 1:
            k = fastest["columns"].index("CPU")
            cpus = [column(r, "CPU") for r in group]
            total, rows = 0.0, []
            for i, row in enumerate(fastest["rows"]):
                if i:
                    total += min(c[i] - c[i - 1] for c in cpus)
                rows.append(row[:k] + [total] + row[k + 1:])
            fastest = dict(fastest, rows=rows, loop=total, repeats=len(group))
        merged.append(fastest)
    return merged


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("logs", nargs="+")
    parser.add_argument("--rows", type=int, default=10, help="intervals per run in the first table")
    parser.add_argument("--png", default="post/ms_per_step_vs_contacts.png")
    parser.add_argument("--best", action="store_true",
                        help="merge repeats of a run: the smallest wall time of each thermo interval (shared machines)")
    args = parser.parse_args()
    runs = [parse_log(path) for path in args.logs]
    if args.best:
        runs = best_of(runs)

    for run in runs:
        print("\n## %s: %s, N = %s, %d ranks, %d steps (%s)"
              % (os.path.basename(run["path"]), name(run), run.get("N", "?"), run.get("ranks", 0),
                 run.get("steps", 0), run["path"]))
        print("\n| steps | ms/step | contact pairs | ranks x us per contact |\n|---|---:|---:|---:|")
        for a, b, ms, c in intervals(run, args.rows):
            per = ms * run.get("ranks", 1) * 1000.0 / c if c and c == c and c > 0 else float("nan")
            print("| %d-%d | %.2f | %.0f | %s |" % (a, b, ms, c, "-" if per != per else "%.1f" % per))
        if run["gpu"]:
            print("\n" + run["gpu"])

    print("\n## Summary\n")
    print("| run | particles (+floor) | ranks | steps | wall s | mean ms/step | ms/step last 10% | contacts at end "
          "| bounding-sphere pairs at end | KE at end (J) | bed height H (mm) | phi_bed | phi_slab | airborne "
          "| Pair % | Neigh % | Comm % | Modify % | Output % | Other % |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for run in runs:
        steps, cpu = column(run, "Step"), column(run, "CPU")
        contacts = column(run, "contacts", "c_contacts", "v_contacts")
        ke = column(run, "KinEng")
        n = len(steps) - 1
        k = max(0, n - max(1, n // 10))
        last = 1000.0 * (cpu[n] - cpu[k]) / (steps[n] - steps[k]) if n > 0 else float("nan")
        mean = 1000.0 * run.get("loop", cpu[-1]) / max(1, run.get("steps", 1))
        packing = None
        dump = find_dump(run)
        if dump:
            packing = packing_fraction(dump, D / 2.0 if run.get("spheres") else BOUNDING_RADIUS)
        t = run["timing"]
        floor = run.get("atoms", 0) - (run.get("N") or 0)

        def pct(key):
            return "%.1f" % t[key] if key in t else "-"
        print("| %s | %s (+%d) | %d | %d | %.1f | %.2f | %.2f | %s | %s | %.3g | %s | %s | %s | %s | %s | %s | %s "
              "| %s "
              "| %s | %s |"
              % (name(run), run.get("N", "?"), floor, run.get("ranks", 0), run.get("steps", 0),
                 run.get("loop", float("nan")), mean, last, "%.0f" % contacts[-1] if contacts else "-",
                 packing["pairs"] if packing else "-",
                 ke[-1] if ke else float("nan"),
                 "%.1f" % (1000 * packing["H"]) if packing else "-",
                 "%.3f" % packing["phi_bed"] if packing else "-",
                 "%.3f" % packing["phi_slab"] if packing and packing["phi_slab"] else "-",
                 packing["airborne"] if packing else "-",
                 pct("Pair"), pct("Neigh"), pct("Comm"), pct("Modify"), pct("Output"), pct("Other")))
    print("\nphi_bed = n (pi/6) D^3 / (Lx Ly H), H = 2 <z_centre> (floor tops at z = 0); phi_slab: centres in "
          "[D, H - D] (H >= 4 D only). LIGGGHTS 3.8 prints no Modify time: fixes are in Other.")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\n(no matplotlib: plot skipped)")
        return
    fig, ax = plt.subplots(figsize=(7, 5))
    for run in runs:
        xs, ys = per_output(run)
        if xs:
            ax.plot(xs, ys, "o-", ms=3, lw=0.8,
                    label="%s, N=%s, %d ranks" % (name(run), run.get("N", "?"), run.get("ranks", 0)))
    ax.set_yscale("log")
    ax.set_xlabel("contact pairs")
    ax.set_ylabel("wall time per step (ms)")
    ax.set_title("Gravity packing: time per step against contact pairs")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print("\nplot: %s" % args.png)


if __name__ == "__main__":
    main()
