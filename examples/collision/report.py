#!/usr/bin/env python3
"""Tables and plots of an examples/collision run (run.py's OUT folder).

    /usr/bin/python3 report.py [OUT] [--no-plots]          # OUT: default post

Reads OUT/data/*.npz and OUT/run.json. For every case (shape, Young's modulus) the normalised kinetic energy
E_k/E_k0 (translational + rotational of both particles, over its initial value) is averaged over the orientation
pairs at every output step; printed as Markdown:

  * the extrema of document 000's fig. 6.4: the minimum of the mean curve and the maximum of the standard
    deviation, with their times (t = 0: the volume-equivalent spheres touch), per shape and modulus;
  * per case also the contact time (steps with a contact), the restitution along x (relative velocity after over
    before) and E_k/E_k0 at the end, mean and standard deviation over the orientations, the pairs still in
    contact at the end and the CPU seconds of the runs;
  * the perfect-sphere references: LIGGGHTS' Hertz spheres and the volumetric law on exact spheres.

Plots (matplotlib, Agg), in OUT: collision_spheres.png (mean and standard deviation against time, one column per
modulus: figs. 6.2 and 6.3), collision_convergence.png (the extrema against triangles: fig. 6.4),
collision_rocks.png (figs. 6.6 and 6.7).
"""
import argparse
import json
import pathlib
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent


def load(out):
    cases, references = [], {}
    for path in sorted((out / "data").glob("*.npz")):
        data = dict(np.load(path, allow_pickle=False))
        data = {k: (v.item() if v.ndim == 0 else v) for k, v in data.items()}
        if path.name.startswith("hertz_"):
            references[data["youngs"]] = data
        else:
            cases.append(data)
    cases.sort(key=lambda c: (c["family"] != "sphere", c["youngs"], c["triangles"]))
    return cases, references


def statistics(case):
    """Mean and standard deviation over the orientations at each output step (population std, ddof 0)."""
    ek = case["ek"]
    return ek.mean(axis=0), ek.std(axis=0)


def minimum(t, y):
    """Smallest value of a sampled curve and its time, refined by the parabola through the lowest sample and its
    neighbours: near the turn-around E_k ~ (t - t0)^2, so the sampled minimum alone would be set by the time step
    (up to ~1e-4 here), not by the collision."""
    i = int(y.argmin())
    if 0 < i < len(y) - 1:
        curvature = y[i - 1] - 2.0 * y[i] + y[i + 1]
        if curvature > 0.0:
            shift = 0.5 * (y[i - 1] - y[i + 1]) / curvature
            return max(y[i] - 0.25 * (y[i - 1] - y[i + 1]) * shift, 0.0), t[i] + shift * (t[i + 1] - t[i])
    return y[i], t[i]


def extrema(case):
    """(min of the mean, its time, max of the standard deviation, its time)."""
    mean, std = statistics(case)
    j = int(std.argmax())
    return minimum(case["t"], mean) + (std[j], case["t"][j])


def number(x):
    return f"{x:.4f}" if x >= 0.01 else f"{x:.2e}"


def spread(values, digits):
    """'mean +- standard deviation' of an array."""
    return f"{values.mean():.{digits}f} +- {values.std():.{digits}f}"


def mpa(youngs):
    return f"{youngs / 1e6:g}"


def label(case):
    return {"ico": "icosphere", "fib": "Fibonacci sphere", "roc": "rock"}[case["shape"][:3]] + f" {case['triangles']}"


def tables(cases, references, meta):
    print(f"{meta.get('machine', '')}")
    print(f"command: `{' '.join(meta.get('argv', []))}` ({meta.get('jobs', '?')} processes), "
          f"run time {meta.get('seconds', float('nan')):.0f} s")
    p = meta.get("parameters", {})
    if p:
        print(f"D = {p['diameter']} m, v = +-{p['speed']} m/s, rho = {p['density']:g} kg/m^3, nu = {p['poisson']}, "
              f"e = {p['restitution']}, tangential {p['tangential']}, precision {p['precision']}, "
              f"dt = Hertz time / {p['steps_per_contact']:g}, output every {p['every']} step(s); orientation seed "
              f"{p['seed']}; polyhedra: `{meta['polyhedra']}`, spheres: `{meta['spheres']}`")

    print("\n**Perfect spheres** (LIGGGHTS `pair_style gran model hertz tangential history`; the volumetric law "
          "integrated on two exact spheres, the limit of the polyhedral spheres)\n")
    print("| E [MPa] | Hertz time [ms] | dt [us] | LIGGGHTS: contact time [ms] | max overlap / D | min E_k/E_k0 | "
          "E_k/E_k0 at the end | law on exact spheres: contact time [ms] | min E_k/E_k0 |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for youngs, r in sorted(references.items()):
        diameter = meta.get("parameters", {}).get("diameter", float("nan"))
        print(f"| {mpa(youngs)} | {1e3 * r['t_hertz']:.2f} | {1e6 * r['dt']:.1f} | {1e3 * r['contact_time']:.2f} | "
              f"{r['max_overlap'] / diameter:.3f} | {minimum(r['t'], r['ek'])[0]:.1e} | {r['ek'][-1]:.6f} | "
              f"{1e3 * r['lens_contact_time']:.2f} | {minimum(r['lens_t'], r['lens_ek'])[0]:.1e} |")

    print("\n**Extrema of the orientation averages** (document 000, fig. 6.4: the minimum of the mean normalised "
          "kinetic energy and the maximum of its standard deviation over the orientations, with their times)\n")
    print("| particle | triangles | E [MPa] | orientations | min of mean E_k/E_k0 | at t [ms] | max of std | "
          "at t [ms] |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for c in cases:
        low, t_low, high, t_high = extrema(c)
        print(f"| {label(c).rsplit(' ', 1)[0]} | {c['triangles']} | {mpa(c['youngs'])} | {len(c['ek'])} | "
              f"{number(low)} | {1e3 * t_low:.2f} | {number(high)} | {1e3 * t_high:.2f} |")

    print("\n**Per collision** (mean +- standard deviation over the orientations; contact time: steps with a contact; "
          "restitution: relative x velocity after over before; for the perfect spheres 1 and the contact time above)\n")
    print("| particle | triangles | E [MPa] | contact time [ms] | restitution (x) | E_k/E_k0 at the end | "
          "max depth / D | in contact at the end | run time [s] |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for c in cases:
        diameter = meta.get("parameters", {}).get("diameter", float("nan"))
        cells = [label(c).rsplit(" ", 1)[0], str(c["triangles"]), mpa(c["youngs"]),
                 spread(1e3 * c["contact_time"], 2), spread(c["restitution"], 4), spread(c["ek"][:, -1], 4),
                 f"{c['max_depth'].mean() / diameter:.3f}", f"{int(c['touching_at_end'].sum())} of {len(c['ek'])}",
                 f"{c['seconds']:.1f}"]
        print("| " + " | ".join(cells) + " |")


def active(case):
    """(first, last) time at which the energy of some orientation differs from its start or end value by 1e-4:
    the part of the run the plots show."""
    ek = case["ek"]
    moving = np.flatnonzero((np.abs(ek - ek[:, :1]) > 1e-4).any(axis=0))
    settled = np.flatnonzero((np.abs(ek - ek[:, -1:]) > 1e-4).any(axis=0))
    t = case["t"]
    return (t[moving[0]] if len(moving) else t[0]), (t[settled[-1]] if len(settled) else t[-1])


def plots(cases, references, out, title):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\nmatplotlib missing: no plots")
        return []
    written = []
    colours = plt.get_cmap("viridis")
    for family, name in (("sphere", "collision_spheres.png"), ("rock", "collision_rocks.png")):
        chosen = [c for c in cases if c["family"] == family]
        if not chosen:
            continue
        moduli = sorted({c["youngs"] for c in chosen})
        shapes = sorted({(c["triangles"], c["shape"]) for c in chosen})
        figure, axes = plt.subplots(2, len(moduli), figsize=(4.6 * len(moduli), 7.2), squeeze=False)
        for col, youngs in enumerate(moduli):
            for k, (_, shape) in enumerate(shapes):
                for c in chosen:
                    if c["shape"] == shape and c["youngs"] == youngs:
                        mean, std = statistics(c)
                        colour = colours(k / max(len(shapes) - 1, 1) * 0.9)
                        axes[0, col].plot(1e3 * c["t"], mean, color=colour, lw=1.2, label=label(c))
                        axes[1, col].plot(1e3 * c["t"], std, color=colour, lw=1.2, label=label(c))
            r = references.get(youngs)
            if r is not None and family == "sphere":
                axes[0, col].plot(1e3 * r["t"], r["ek"], "k:", lw=1.4, label="LIGGGHTS Hertz spheres")
                axes[0, col].plot(1e3 * r["lens_t"], r["lens_ek"], "--", color="0.5", lw=1.0,
                                  label="volumetric law, exact spheres")
                axes[1, col].axhline(0.0, color="k", ls=":", lw=1.4, label="perfect sphere")
            window = [active(c) for c in chosen if c["youngs"] == youngs]
            low, high = min(w[0] for w in window), max(w[1] for w in window)
            for row in range(2):
                axes[row, col].set_xlim(1e3 * (low - 0.1 * (high - low)), 1e3 * (high + 0.15 * (high - low)))
            axes[0, col].set_title(f"E = {mpa(youngs)} MPa")
            axes[0, col].set_ylabel("mean of $E_k/E_k^0$")
            axes[1, col].set_ylabel("standard deviation of $E_k/E_k^0$")
            axes[1, col].set_xlabel("t [ms] (0: volume-equivalent spheres touch)")
            for row in range(2):
                axes[row, col].grid(alpha=0.3)
        handles = {}
        for axis in (axes[0, 0], axes[1, 0]):
            for handle, text in zip(*axis.get_legend_handles_labels()):
                handles.setdefault(text, handle)
        figure.legend(list(handles.values()), list(handles), fontsize=8, loc="lower center",
                      ncol=min(len(handles), 4), frameon=False)
        n = min(len(c["ek"]) for c in chosen)
        figure.suptitle(f"head-on collisions, {'polyhedral spheres' if family == 'sphere' else 'irregular rock'}, "
                        f"{n}{'+' if any(len(c['ek']) > n for c in chosen) else ''} random orientation pairs\n{title}",
                        fontsize=8)
        figure.tight_layout(rect=(0, 0.06 + 0.025 * ((len(handles) - 1) // 4), 1, 1))
        figure.savefig(out / name, dpi=100)
        plt.close(figure)
        written.append(out / name)

    spheres = [c for c in cases if c["family"] == "sphere"]
    if spheres:
        figure, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        for k, youngs in enumerate(sorted({c["youngs"] for c in spheres})):
            rows = sorted((c["triangles"], extrema(c)) for c in spheres if c["youngs"] == youngs)
            colour = plt.get_cmap("plasma")(k / 3.0)
            triangles = [t for t, _ in rows]
            axes[0].plot(triangles, [max(e[0], 1e-9) for _, e in rows], "o-", color=colour,
                         label=f"E = {mpa(youngs)} MPa")
            axes[1].plot(triangles, [e[2] for _, e in rows], "o-", color=colour, label=f"E = {mpa(youngs)} MPa")
            r = references.get(youngs)
            if r is not None:
                axes[0].axhline(max(minimum(r["t"], r["ek"])[0], 1e-9), color=colour, ls=":", lw=1.0)
        axes[0].set_ylabel("minimum of the mean $E_k/E_k^0$")
        axes[1].set_ylabel("maximum standard deviation of $E_k/E_k^0$")
        for axis in axes:
            axis.set_xscale("log")
            axis.set_yscale("log")
            axis.set_xlabel("triangles per sphere")
            axis.grid(alpha=0.3, which="both")
            axis.legend(fontsize=8)
        axes[0].set_title("dotted: LIGGGHTS Hertz spheres (values below 1e-9 drawn at 1e-9)", fontsize=8)
        figure.suptitle(f"convergence of the polyhedral spheres\n{title}", fontsize=8)
        figure.tight_layout()
        figure.savefig(out / "collision_convergence.png", dpi=100)
        plt.close(figure)
        written.append(out / "collision_convergence.png")
    return written


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default=str(HERE / "post"))
    parser.add_argument("--no-plots", action="store_true")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    meta_path = out / "run.json"
    meta = json.loads(meta_path.read_text()) if meta_path.exists() else {}
    cases, references = load(out)
    if not cases:
        sys.exit(f"no results in {out}/data: run run.py first")
    tables(cases, references, meta)
    if not args.no_plots:
        for path in plots(cases, references, out, meta.get("machine", "")):
            print(f"\nplot: {path.name}")


if __name__ == "__main__":
    main()
