#!/usr/bin/env python3
"""Angle of repose and flow-phase kinetic energy of the calibration-rig runs in OUT (written by run.py):
Markdown tables on stdout and in OUT/report.md, the plots OUT/calibration_rig_resolution.png (as fig. 6.10 of
document 000) and OUT/calibration_rig_heaps.png (height maps and fitted sigmoids, as fig. 6.9).

    /usr/bin/python3 report.py OUT [--bins 20] [--xmap 0.15]

Height map (document 000, sec. 6.3): the bottom plate from the back wall x = 0 to x = --xmap (default half the
plate, times the rig's scale) in --bins bins along the flow; h_i = the highest surface vertex in bin i of the
rocks whose centre lies below the lip of the tilted plane (the rocks on the plate). Eq. 6.1,
h(x) = c / (1 + exp(a (x - b))), is fitted with scipy's curve_fit; the angle of repose is the steepest slope of
the fit on the map, atan(|a| c / 4) at x = b (or, when b falls off the map, the slope at the map's end
nearest to it; the table marks those runs).
Cross-check: the angle of a straight line through the flank, the bins from the highest one on in +x down to
the heap's toe (20 % of the highest) less those above 80 % of it.
Flow phase: from the opening of the doors until 95 % of the rocks have their centre below the lip; its kinetic
energy is the mean of the translational plus rotational energy over the thermo outputs in it.
"""
import argparse
import importlib.util
import json
import math
import pathlib
import re
import sys

import numpy as np
from scipy.optimize import curve_fit

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent.parent / "tools"))
import render_vtp  # noqa: E402

# the hopper example's reader of LIGGGHTS dump files
_spec = importlib.util.spec_from_file_location("hopper_report", pathlib.Path(__file__).resolve().parent.parent
                                               / "hopper" / "report.py")
hopper_report = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hopper_report)
read_dump = hopper_report.read_dump

EXPERIMENTAL_RANGE = (33.0, 42.0)   # degrees, document 000, sec. 6.3


def sigmoid(x, a, b, c):
    return c / (1.0 + np.exp(np.clip(a * (x - b), -700, 700)))


def fit_repose_angle(x, h):
    """Fits eq. 6.1 to the height map; returns (a, b, c, angle in degrees). The angle is that of the steepest
    slope of the fit on the map, x[0] <= x <= x[-1]: atan(|a| c / 4) at x = b when b is on the map, else the
    slope at the map's end nearest to b (a heap against the back wall may have no plateau, and then the fit's
    inflection can fall behind the wall, where there is no heap to measure)."""
    x, h = np.asarray(x, float), np.asarray(h, float)
    c0 = h.max()
    half = x[np.argmax(h < c0 / 2)] if (h < c0 / 2).any() else x[-1]
    a0 = 4 * math.tan(math.radians(35.0)) / c0      # a steepest slope of 35 degrees to start from
    (a, b, c), _ = curve_fit(sigmoid, x, h, p0=(a0, half, c0), maxfev=20000)
    e = math.exp(min(a * (min(max(b, x[0]), x[-1]) - b), 700.0))
    steepest = abs(a * c) * e / (1.0 + e) ** 2
    return a, b, c, math.degrees(math.atan(steepest))


def flank_angle(x, h, low=0.2, high=0.8):
    """A cross-check without the sigmoid: the angle of the least-squares line through the heap's flank, the
    bins from the highest one on in +x down to the first below `low` of its height, less those above `high`
    of it (nan with fewer than 3 such bins). Stray rocks beyond the heap's toe do not count."""
    x, h = np.asarray(x, float), np.asarray(h, float)
    top = int(np.argmax(h))
    end = top
    while end < len(h) and h[end] >= low * h[top]:
        end += 1
    flank = np.arange(top, end)
    flank = flank[h[flank] <= high * h[top]]
    if flank.size < 3:
        return float("nan")
    return math.degrees(math.atan(abs(np.polyfit(x[flank], h[flank], 1)[0])))


def height_map(points, x_hi, bins):
    """Bin centres and the highest z in each bin of (x, z) points with 0 <= x < x_hi (0 for an empty bin)."""
    edges = np.linspace(0.0, x_hi, bins + 1)
    index = np.digitize(points[:, 0], edges) - 1
    heights = np.zeros(bins)
    for i in range(bins):
        inside = points[index == i, 2]
        heights[i] = inside.max() if inside.size else 0.0
    return 0.5 * (edges[:-1] + edges[1:]), heights


def read_vtp(path):
    """Points (n x 3) and, for each point, the id of its particle, from a dump polyhedron/vtk snapshot."""
    points, triangles, arrays = render_vtp.read_vtp(path)
    owner = np.zeros(len(points), int)
    owner[triangles] = arrays["id"][:, None]
    return points, owner


def read_thermo(log):
    """The thermo rows of a LIGGGHTS log as {column: array}, all runs of it in order (repeated steps once).
    Every run of in.rig prints the same columns."""
    columns, in_table, rows, seen = None, False, [], set()
    for line in open(log):
        words = line.split()
        if words[:1] == ["Step"]:
            columns, in_table = words, True
        elif in_table and len(words) == len(columns) and re.match(r"^\d+$", words[0]):
            if words[0] not in seen:
                seen.add(words[0])
                rows.append([float(w) for w in words])
        else:
            in_table = False
    table = np.array(rows)
    return {name: table[:, k] for k, name in enumerate(columns)}


def analyse(out, run, dims, bins, xmap):
    work = out / run["name"]
    var = run["variables"]
    thermo = read_thermo(work / "log.rig")
    final = read_dump(work / "post" / "rig_final.dump")
    points, owner = read_vtp(sorted((work / "post").glob("rig_final_*.vtp"))[-1])
    z_lip = dims["z_lip"]
    on_plate = set(final["id"][final["z"] < z_lip].astype(int))
    plate_points = points[np.isin(owner, list(on_plate))]
    x, h = height_map(plate_points, xmap, bins)
    a, b, c, angle = fit_repose_angle(x, h)

    t, ke = thermo["t"], thermo["KinEng"] + thermo["erot"]
    inserted = int(thermo["Atoms"].max())
    release = float(var["settle"])
    arrived = np.nonzero((t >= release) & (thermo["nheap"] >= 0.95 * inserted))[0]
    flow_end = t[arrived[0]] if arrived.size else t[-1]
    window = (t >= release) & (t <= flow_end)
    mass = float(final["mass"].sum())
    at_release = np.argmin(abs(t - release))
    return dict(run=run["name"], shape=run["shape"], triangles=int(re.search(r"_(\d+)", run["shape"]).group(1)),
                seed=run["seed"], inserted=inserted, atoms_end=int(thermo["Atoms"][-1]), mass=mass,
                on_plate=len(on_plate), in_hopper_end=int(thermo["nhopper"][-1]),
                ke_release=float(ke[at_release]), flow_start=release, flow_end=float(flow_end),
                ke_flow=float(ke[window].mean()), ke_max=float(ke.max()), ke_end=float(ke[-1]),
                ke_last_tenth=float(ke[t >= t[-1] - 0.1 * (t[-1] - release)].mean()),
                xmax_end=float(final["x"].max()), a=a, b=b, c=c, angle=angle, b_on_map=bool(x[0] <= b <= x[-1]),
                flank=flank_angle(x, h), wall_s=run["wall_s"],
                map_x=x.tolist(), map_h=h.tolist(), t=t.tolist(), ke=ke.tolist())


def tables(results):
    lines = ["| run | inserted | atoms at end | mass kg | on plate | KE at release J | flow phase s "
             "| mean KE flow J | KE flow J/kg | KE end J | c mm | b mm | a 1/m | angle deg | flank deg | wall s |",
             "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    # b off the map: the inflection of the fit lies outside the mapped plate (marked *)
    for r in results:
        lines.append("| %s | %d | %d | %.4g | %d | %.3g | %.3g-%.3g | %.4g | %.4g | %.3g | %.1f | %.1f%s | %.0f | %.1f "
                     "| %.1f | %.0f |" % (r["run"], r["inserted"], r["atoms_end"], r["mass"], r["on_plate"],
                                   r["ke_release"], r["flow_start"], r["flow_end"], r["ke_flow"],
                                   r["ke_flow"] / r["mass"], r["ke_end"], 1e3 * r["c"], 1e3 * r["b"],
                                   "" if r["b_on_map"] else "*", r["a"],
                                   r["angle"], r["flank"], r["wall_s"]))
    lines += ["", "| shape | triangles | runs | angle deg mean | sd | min-max | in 33-42 | flank deg mean "
              "| KE flow J/kg mean | sd |", "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|"]
    for tri in sorted({r["triangles"] for r in results}):
        group = [r for r in results if r["triangles"] == tri]
        angles = np.array([r["angle"] for r in group])
        energy = np.array([r["ke_flow"] / r["mass"] for r in group])
        inside = sum(EXPERIMENTAL_RANGE[0] <= x <= EXPERIMENTAL_RANGE[1] for x in angles)
        lines.append("| %s | %d | %d | %.1f | %.1f | %.1f-%.1f | %d | %.1f | %.4g | %.2g |" % (
            group[0]["shape"], tri, len(group), angles.mean(), angles.std(ddof=1) if len(group) > 1 else 0.0,
            angles.min(), angles.max(), inside, np.nanmean([r["flank"] for r in group]), energy.mean(),
            energy.std(ddof=1) if len(group) > 1 else 0.0))
    return "\n".join(lines)


def plots(results, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    triangles = sorted({r["triangles"] for r in results})
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key, label in ((axes[0], "ke_flow", "mean kinetic energy in the flow phase, J/kg"),
                           (axes[1], "angle", "angle of repose, degrees")):
        values = {tri: np.array([r[key] / (r["mass"] if key == "ke_flow" else 1.0)
                                 for r in results if r["triangles"] == tri]) for tri in triangles}
        for tri in triangles:
            ax.plot([tri] * len(values[tri]), values[tri], "o", color="k", ms=4)
        mean = np.array([values[tri].mean() for tri in triangles])
        sd = np.array([values[tri].std(ddof=1) if len(values[tri]) > 1 else 0.0 for tri in triangles])
        ax.plot(triangles, mean, ":", color="k", label="mean")
        ax.fill_between(triangles, mean - sd, mean + sd, color="0.8", label="mean +- sd")
        if key == "angle":
            for n, tri in enumerate(triangles):
                ax.plot([tri] * len(values[tri]), [r["flank"] for r in results if r["triangles"] == tri], "x",
                        color="tab:blue", ms=5, label="flank angle (cross-check)" if n == 0 else None)
            ax.axhspan(*EXPERIMENTAL_RANGE, color="tab:green", alpha=0.15, label="experiments, 33-42")
        ax.set_xlabel("triangles per rock")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "calibration_rig_resolution.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(triangles), figsize=(3.2 * len(triangles), 3.2), sharey=True, squeeze=False)
    for ax, tri in zip(axes[0], triangles):
        for r in (r for r in results if r["triangles"] == tri):
            x = np.array(r["map_x"])
            line, = ax.plot(1e3 * x, 1e3 * np.array(r["map_h"]), "o", ms=3)
            fine = np.linspace(0, x[-1] + x[0], 200)
            ax.plot(1e3 * fine, 1e3 * sigmoid(fine, r["a"], r["b"], r["c"]), "-", color=line.get_color(),
                    label="seed %d: %.1f deg" % (r["seed"], r["angle"]))
        ax.set_title("%d triangles" % tri)
        ax.set_xlabel("x from the back wall, mm")
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("heap height, mm")
    fig.tight_layout()
    fig.savefig(out / "calibration_rig_heaps.png", dpi=110)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out")
    p.add_argument("--bins", type=int, default=20)
    p.add_argument("--xmap", type=float, default=None, help="end of the height map, m (default Lp / 2)")
    p.add_argument("--no-plots", action="store_true")
    a = p.parse_args()
    out = pathlib.Path(a.out)
    record = json.loads((out / "runs.json").read_text())
    dims = record["dims"]
    xmap = a.xmap or dims["Lp"] / 2
    results = [analyse(out, run, dims, a.bins, xmap) for run in record["runs"]]
    text = ("Height map: %d bins over x = 0-%.3g m; flow phase: doors opening until 95 %% of the rocks are "
            "below the lip.\n\n" % (a.bins, xmap)) + tables(results)
    print(text)
    (out / "report.md").write_text(text + "\n")
    (out / "results.json").write_text(json.dumps([{k: v for k, v in r.items() if k not in ("t", "ke")}
                                                   for r in results], indent=1))
    if not a.no_plots:
        plots(results, out)


if __name__ == "__main__":
    main()
