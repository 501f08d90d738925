#!/usr/bin/env python3
"""Power draw, shoulder and toe of the tumbling mill (in.mill, in.mill_spheres) against a torque-arm estimate.

    python3 report.py OUT [--D 0.3 --L 0.1 --lifters 8 --height 0.02 --width 0.02 --face-angle 20 --cells 6]
                          [--steady 1.0] [--bin 5] [--level 0.5]

Reads OUT/log.mill_rock and OUT/log.mill_spheres (either may be missing; .gz too) and the position dumps
OUT/post/mill_*.dump (.gz too), prints Markdown tables, writes them to OUT/report.md, and draws
OUT/mill_power.png, OUT/mill_section.png and OUT/mill_band.png (the band profile) (matplotlib, Agg; skipped without it). The mill options are those of
make_mill.py (only for drawing the mill's outline).

Conventions: the mill turns about +y with angular velocity omega; in the cross-section (x, z) an angle theta is
measured at the axis from the lowest point of the shell, positive in the direction of rotation (towards -x, the
side where the charge is lifted).
  * Power: P = -T_y omega, T_y the torque on the mill about its axis from fix mesh/surface/stress (the torque the
    motor must overcome). The steady part is everything after --steady revolutions; its mean, standard
    deviation, and the spread of the means of its whole revolutions.
  * Torque arm (reference): a steadily turning charge of mass M whose centre of mass sits at x_cm holds the
    torque M g x_cm against the mill, so P_arm = -M g x_cm omega; averaged over the same steady part it differs
    from P only by the change of the charge's angular momentum. Hogg-Fuerstenau's form of it, from the charge
    at rest: P_HF = M g r_c sin(alpha) omega with r_c the distance of the settled charge's centre of mass from
    the axis and alpha the inclination of the chord from toe to shoulder, (theta_S + theta_T) / 2; and the
    other way round, the alpha that would give the measured P ("alpha from P").
  * Shoulder and toe: particle centres within --band (default lifter height + d) inside the shell, over the
    steady snapshots, binned by theta (--bin degrees). The charge's contact with the shell is the longest run of
    bins whose count is at least --level (one half) of the typical count (the 90th percentile of the bins); the
    toe theta_T is where the run starts (the shell enters under the charge), the shoulder theta_S where it ends
    (the charge leaves the shell), both interpolated linearly between bin centres.
"""
import argparse
import gzip
import math
import os
import pathlib
import re
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import make_mill  # noqa: E402

G = 9.81
RUNS = (("rock", "log.mill_rock", "mill_rock"), ("spheres", "log.mill_spheres", "mill_spheres"))


def parse_log(path):
    """{'geometry': {...}, 'speed': {...}, 'N', 'shape', 'inserted', 'settle': table, 'mill': table, 'loop',
    'steps'}; a table maps column name to an array. A column name that repeats (LIGGGHTS prints f_ID[4..6] of a
    fix as ID three times) gets '#1', '#2', ... in the order of its columns."""
    out = {"loop": 0.0, "steps": 0, "settle": {}, "mill": {}}
    stage, header = None, None
    opener = gzip.open if str(path).endswith(".gz") else open
    for line in opener(path, "rt", errors="replace"):
        words = line.split()
        m = re.match(r"^mill: (geometry|speed) ", line)
        if m:
            # "mill: geometry D 0.3 L ..." and "mill: speed 0.75 omega_c ...": name-value pairs
            w = words[2:] if m.group(1) == "geometry" else words[1:]
            out[m.group(1)] = {w[i]: float(w[i + 1]) for i in range(0, len(w) - 1, 2)}
            continue
        m = re.match(r"^mill: stage (\w+)", line)
        if m:
            stage, header = m.group(1), None
            if stage == "settle":
                out["N"], out["shape"] = int(words[words.index("N") + 1]), words[words.index("shape") + 1]
                out["inserted"] = int(words[words.index("inserted") + 1])
            continue
        m = re.match(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps", line)
        if m:
            out["loop"] += float(m.group(1))
            out["steps"] += int(m.group(3))
            header = None
            continue
        if words and words[0] == "Step":
            seen = {}
            header = []
            for w in words:
                seen[w] = seen.get(w, 0) + 1
                header.append(w if words.count(w) == 1 else "%s#%d" % (w, seen[w]))
            continue
        if stage in ("settle", "mill") and header and len(words) == len(header) and re.match(r"^\d+$", words[0]):
            for name, value in zip(header, words):
                out[stage].setdefault(name, []).append(float(value))
    for stage in ("settle", "mill"):
        out[stage] = {k: np.array(v) for k, v in out[stage].items()}
    return out


def read_dumps(path):
    """[(step, {column: array}), ...] of a LAMMPS text dump with several snapshots (plain or gzip)."""
    opener = gzip.open if str(path).endswith(".gz") else open
    snapshots = []
    with opener(path, "rt") as f:
        lines = f.read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            n = int(lines[i + 3])
            cols = lines[i + 8].split()[2:]
            data = np.array([[float(x) for x in l.split()] for l in lines[i + 9:i + 9 + n]]).reshape(n, len(cols))
            snapshots.append((step, {c: data[:, j] for j, c in enumerate(cols)}))
            i += 9 + n
        else:
            i += 1
    return snapshots


def find_dump(out, name):
    for folder in (os.path.join(out, "post"), out):
        for suffix in (".dump", ".dump.gz"):
            path = os.path.join(folder, name + suffix)
            if os.path.exists(path):
                return path
    return None


def theta_of(x, z):
    """Angle (degrees) from the lowest point of the shell, positive in the direction of rotation (towards -x)."""
    return np.degrees(np.arctan2(-x, -z))


def shoulder_toe(x, z, R, band, bin_deg=5.0, level=0.5):
    """Toe and shoulder angles (degrees, shoulder > toe) of the charge from particle centres (x, z) pooled over
    snapshots; see the module's docstring. Returns a dict with the profile for plotting, or None when no run
    of bins reaches the level."""
    r = np.hypot(x, z)
    theta = theta_of(x[r >= R - band], z[r >= R - band])
    nbins = int(round(360.0 / bin_deg))
    counts, edges = np.histogram(theta, bins=nbins, range=(-180.0, 180.0))
    centres = (edges[:-1] + edges[1:]) / 2
    typical = np.percentile(counts, 90)
    threshold = level * typical
    above = counts >= threshold
    if typical <= 0 or above.all() or not above.any():
        return None
    # longest circular run of bins at or above the threshold
    start = int(np.argmin(above))          # a bin below: runs are then contiguous from here on
    order = [(start + k) % nbins for k in range(nbins)]
    best, run_start, length = (0, 0), None, 0
    for k, b in enumerate(order):
        if above[b]:
            run_start = k if length == 0 else run_start
            length += 1
            if length > best[0]:
                best = (length, run_start)
        else:
            length = 0
    length, first = best
    i_first, i_last = order[first], order[first + length - 1]

    def crossing(inside, outside, sign):
        # linear between the bin centres of the last bin inside and the first bin outside the run
        c_in, c_out = counts[inside], counts[outside]
        frac = (c_in - threshold) / (c_in - c_out) if c_in != c_out else 0.5
        return centres[inside] + sign * frac * bin_deg

    toe = crossing(i_first, (i_first - 1) % nbins, -1.0)
    shoulder = crossing(i_last, (i_last + 1) % nbins, 1.0)
    while shoulder <= toe:
        shoulder += 360.0
    if toe <= -180.0:
        toe, shoulder = toe + 360.0, shoulder + 360.0
    return {"toe": float(toe), "shoulder": float(shoulder), "centres": centres, "counts": counts,
            "threshold": float(threshold)}


def power_stats(t, power, period, steady_revs):
    """Mean and standard deviation of the power after `steady_revs` revolutions, and the means of the whole
    revolutions after that (their spread says how steady the mean is)."""
    t0 = steady_revs * period
    sel = t >= t0
    if sel.sum() < 2:
        return {"mean": float("nan"), "std": float("nan"), "rev_means": [], "t0": t0, "points": int(sel.sum())}
    rev_means = []
    k = 0
    while t0 + (k + 1) * period <= t[-1] + 1e-9:
        block = (t >= t0 + k * period) & (t < t0 + (k + 1) * period)
        if block.any():
            rev_means.append(float(power[block].mean()))
        k += 1
    return {"mean": float(power[sel].mean()), "std": float(power[sel].std()), "rev_means": rev_means, "t0": t0,
            "points": int(sel.sum())}


def find_log(out, log):
    for path in (os.path.join(out, log), os.path.join(out, log + ".gz")):
        if os.path.exists(path):
            return path
    return None


def analyse(out, name, log, tag, a):
    run = parse_log(find_log(out, log))
    geo, speed = run["geometry"], run["speed"]
    mill, settle = run["mill"], run["settle"]
    omega, period = speed["omega"], speed["period"]
    R, L, d = geo["D"] / 2, geo["L"], geo["d"]
    t = mill["t"] - mill["t"][0]
    mass = float(mill["mall"][-1])
    power = mill["power"]
    arm = -mass * G * mill["xcm"] * omega
    r = {"name": name, "geo": geo, "omega": omega, "period": period, "speed": speed["speed"], "N": run["N"],
         "shape": run["shape"], "inserted": run["inserted"], "mass": mass, "t": t, "power": power, "arm": arm,
         "atoms_min": int(min(settle["Atoms"].min(), mill["Atoms"].min())),
         "atoms_end": int(mill["Atoms"][-1]), "rmax": float(mill["rmax"].max()), "ymax": float(mill["ymax"].max()),
         "loop": run["loop"], "steps": run["steps"], "revs": t[-1] / period, "step0": int(mill["Step"][0])}
    r["stats"] = power_stats(t, power, period, a.steady)
    sel = t >= r["stats"]["t0"]
    r["arm_mean"] = float(arm[sel].mean()) if sel.any() else float("nan")
    r["torque_mean"] = -r["stats"]["mean"] / omega
    # fix mesh/surface/stress against fix wall/polyhedral's own sum (rocks only); the first row of a run is
    # printed before the forces of its first step
    if "walls[5]" in mill:
        mesh = np.array([mill["millmesh#%d" % k] for k in (1, 2, 3)]).T[1:]
        walls = np.array([mill["walls[%d]" % k] for k in (5, 6, 7)]).T[1:]
        r["torque_difference"] = float(np.abs(mesh - walls).max())
        r["torque_scale"] = float(np.abs(mesh).max())
    # the settled charge's centre of mass (the last row of the settle stage)
    r["rc_rest"] = float(math.hypot(settle["xcm"][-1], settle["zcm"][-1]))
    band = a.band if a.band else (a.height if a.lifters else 0.0) + d
    r["band"] = band
    r["shoulder_toe"] = None
    path = find_dump(out, tag)
    if path:
        steady = [(s, snap) for s, snap in read_dumps(path)
                  if (s - r["step0"]) * geo["dt"] >= r["stats"]["t0"] - 1e-9]
        if steady:
            x = np.concatenate([snap["x"] for _, snap in steady])
            z = np.concatenate([snap["z"] for _, snap in steady])
            r["snapshots"] = len(steady)
            r["shoulder_toe"] = shoulder_toe(x, z, R, band, a.bin, a.level)
            r["last"] = steady[-1]
    st = r["shoulder_toe"]
    if st:
        alpha = math.radians((st["shoulder"] + st["toe"]) / 2)
        r["alpha"] = math.degrees(alpha)
        r["hf"] = mass * G * r["rc_rest"] * math.sin(alpha) * omega
    else:
        r["alpha"], r["hf"] = float("nan"), float("nan")
    # the angle the resting charge would have to be turned by to draw the measured power
    ratio = r["stats"]["mean"] / (mass * G * r["rc_rest"] * omega)
    r["alpha_power"] = math.degrees(math.asin(ratio)) if -1.0 <= ratio <= 1.0 else float("nan")
    return r


def tables(results):
    geo = results[0]["geo"]
    res = results[0]
    lines = ["**Mill**: D = %.4g m, L = %.4g m, lifter height %.4g m; d = %.4g m (volume-equivalent), density "
             "%.4g kg/m^3, E = %.3g Pa, mu = %.3g, dt = %.3g s; speed %.3g of critical: omega = %.4g rad/s, "
             "period %.4g s" % (geo["D"], geo["L"], geo["h"], geo["d"], geo["rho"], geo["E"], geo["mu"], geo["dt"],
                                res["speed"], res["omega"], res["period"]), "",
             "| run | N asked | inserted | atoms min / end | mass kg | farthest centre from axis m (R) "
             "| from mid-plane m (L/2) | revolutions | steps | wall s |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        lines.append("| %s (%s) | %d | %d | %d / %d | %.4g | %.4f (%.4g) | %.4f (%.4g) | %.3g | %d | %.1f |" % (
            r["name"], r["shape"], r["N"], r["inserted"], r["atoms_min"], r["atoms_end"], r["mass"], r["rmax"],
            r["geo"]["D"] / 2, r["ymax"], r["geo"]["L"] / 2, r["revs"], r["steps"], r["loop"]))
    lines += ["", "| run | steady from s | points | P mean W | P std W | P per revolution W | torque N m "
              "| P_arm W (torque arm, same window) | P / P_arm | theta_T toe deg | theta_S shoulder deg "
              "| snapshots | alpha deg | r_c at rest m | P_HF W | P / P_HF | alpha from P deg |",
              "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        s, st = r["stats"], r["shoulder_toe"]
        lines.append("| %s | %.3g | %d | %.4g | %.3g | %s | %.4g | %.4g | %.3f | %s | %s | %d | %.3g | %.4g | %.4g "
                     "| %.3f | %.3g |" % (
                         r["name"], s["t0"], s["points"], s["mean"], s["std"],
                         ", ".join("%.3g" % v for v in s["rev_means"]) or "-", r["torque_mean"], r["arm_mean"],
                         s["mean"] / r["arm_mean"], "%.1f" % st["toe"] if st else "-",
                         "%.1f" % st["shoulder"] if st else "-", r.get("snapshots", 0), r["alpha"], r["rc_rest"],
                         r["hf"], s["mean"] / r["hf"], r["alpha_power"]))
    for r in results:
        if "torque_difference" in r:
            lines += ["", "%s: torque on the mill from fix mesh/surface/stress minus the particles' wall torque "
                      "(fix wall/polyhedral): largest difference %.2g N m (largest torque %.3g N m)" % (
                          r["name"], r["torque_difference"], r["torque_scale"])]
    if len(results) == 2:
        a, b = results
        lines += ["", "P(%s) / P(%s) = %.3f" % (a["name"], b["name"], a["stats"]["mean"] / b["stats"]["mean"])]
    return "\n".join(lines)


def mill_outline(a, angle):
    """The mill's cross-section (x, z) turned by `angle` (radians, in the direction of rotation)."""
    ring = make_mill.outline(a.D / 2, a.lifters, a.height, a.width, a.face_angle, a.cells)
    pts = [make_mill.polar_to_xz(make_mill.angle_of(p) + angle, math.hypot(*p), 0.0) for p in ring]
    return np.array(pts + pts[:1])


def plot(results, a, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib missing: no plot)")
        return
    colours = {"rock": "tab:brown", "spheres": "tab:blue"}
    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    for r in results:
        c = colours[r["name"]]
        ax.plot(r["t"], r["power"], "-", color=c, lw=0.5, alpha=0.3, label="%s: P = -T omega" % r["name"])
        # running mean over a tenth of a revolution, to see through the contact noise
        width = min(len(r["t"]), max(1, int(round(0.1 * r["period"] / max(np.diff(r["t"]).mean(), 1e-12)))))
        smooth = np.convolve(r["power"], np.ones(width) / width, mode="valid")
        ax.plot(r["t"][width // 2:width // 2 + len(smooth)], smooth, "-", color=c, lw=1.2,
                label="%s: P, running mean over 0.1 revolution" % r["name"])
        ax.plot(r["t"], r["arm"], ":", color=c, lw=1.2, label="%s: torque arm -M g x_cm omega" % r["name"])
        s = r["stats"]
        if not math.isnan(s["mean"]):
            ax.hlines(s["mean"], s["t0"], r["t"][-1], colors=c, lw=2,
                      label="%s: steady mean %.3g W" % (r["name"], s["mean"]))
    ax.axvline(results[0]["stats"]["t0"], color="k", lw=0.8, ls="--")
    # the start-up kick (the charge at rest meets the turning lifters) would flatten the rest of the plot
    every = np.concatenate([r["power"] for r in results] + [r["arm"] for r in results])
    ax.set_ylim(min(0.0, np.percentile(every, 0.5)) * 1.2, np.percentile(every, 99.5) * 1.2)
    ax.set_xlabel("time since the mill started (s)")
    ax.set_ylabel("power draw (W)")
    ax.set_title("Mill power draw, %.0f %% of critical speed" % (100 * results[0]["speed"]))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right", ncol=1)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "mill_power.png"), dpi=100)
    plt.close(fig)
    shown = [r for r in results if "last" in r]
    if not shown:
        return
    fig, axes = plt.subplots(1, len(shown), figsize=(4.6 * len(shown), 4.8), squeeze=False)
    for ax, r in zip(axes[0], shown):
        step, snap = r["last"]
        t = (step - r["step0"]) * r["geo"]["dt"]
        outline = mill_outline(a, r["omega"] * t)
        ax.plot(outline[:, 0], outline[:, 1], "k-", lw=1)
        size = (72 * r["geo"]["d"] / 0.34 * 2.2) ** 2 / 4       # roughly the particle's diameter in points
        ax.scatter(snap["x"], snap["z"], s=size, color=colours[r["name"]], alpha=0.6, lw=0)
        st = r["shoulder_toe"]
        R = r["geo"]["D"] / 2
        if st:
            for key, label in (("toe", "toe"), ("shoulder", "shoulder")):
                th = math.radians(st[key])
                ax.plot([0, -R * 1.08 * math.sin(th)], [0, -R * 1.08 * math.cos(th)], "k--", lw=1)
                ax.annotate("%s %.0f deg" % (label, st[key]), (-R * 1.1 * math.sin(th), -R * 1.1 * math.cos(th)),
                            ha="center", fontsize=8)
        # the sense of rotation, as an arc below the mill
        tail, head = (R * 1.18 * math.sin(0.3), -R * 1.18 * math.cos(0.3)), (-R * 1.18 * math.sin(0.3),
                                                                          -R * 1.18 * math.cos(0.3))
        ax.annotate("", xy=head, xytext=tail, arrowprops=dict(arrowstyle="->", color="0.3",
                                                              connectionstyle="arc3,rad=-0.15"))
        ax.set_title("%s, %.2f s after the start (%d particles)" % (r["name"], t, len(snap["x"])), fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlim(-R * 1.3, R * 1.3)
        ax.set_ylim(-R * 1.3, R * 1.3)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "mill_section.png"), dpi=120)
    plt.close(fig)
    # the band profile behind the shoulder and toe
    fig, ax = plt.subplots(figsize=(7.0, 3.4))
    for r in shown:
        st = r["shoulder_toe"]
        if not st:
            continue
        c = colours[r["name"]]
        share = st["counts"] / st["counts"].sum()
        ax.step(st["centres"], share, where="mid", color=c, label="%s (%d snapshots)" % (r["name"], r["snapshots"]))
        ax.axhline(st["threshold"] / st["counts"].sum(), color=c, ls=":", lw=1)
        for key in ("toe", "shoulder"):
            ax.axvline((st[key] + 180) % 360 - 180, color=c, ls="--", lw=1)
    ax.set_xlabel("theta: angle from the bottom of the shell, in the sense of rotation (deg)")
    ax.set_ylabel("share of centres in the band")
    ax.set_title("Centres within h + d of the shell; dotted: half the typical level; dashed: toe, shoulder",
                 fontsize=9)
    ax.set_xlim(-180, 180)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "mill_band.png"), dpi=100)
    plt.close(fig)
    print("wrote %s, %s and %s" % tuple(os.path.join(out, "mill_%s.png" % k) for k in ("power", "section", "band")))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out")
    make_mill.add_arguments(p)
    p.add_argument("--steady", type=float, default=1.0, help="revolutions left out before the steady part")
    p.add_argument("--band", type=float, default=0.0, help="band inside the shell, m (default lifter height + d)")
    p.add_argument("--bin", type=float, default=5.0, help="angular bin, degrees")
    p.add_argument("--level", type=float, default=0.5, help="fraction of the typical count at toe and shoulder")
    a = p.parse_args()
    results = [analyse(a.out, name, log, tag, a) for name, log, tag in RUNS if find_log(a.out, log)]
    if not results:
        sys.exit("no log.mill_rock or log.mill_spheres in %s" % a.out)
    text = tables(results)
    print(text)
    open(os.path.join(a.out, "report.md"), "w").write(text + "\n")
    plot(results, a, a.out)


if __name__ == "__main__":
    main()
