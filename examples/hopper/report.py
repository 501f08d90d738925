#!/usr/bin/env python3
"""Mass flow rate of the hopper discharge (in.hopper, in.hopper_spheres) against Beverloo's slot correlation.

    python3 report.py OUT [--alpha 30] [--window 0.15 0.65] [--k 1.5]

Reads OUT/log.hopper_rock and OUT/log.hopper_spheres (either may be missing) and the settled fills
OUT/post/*_release.dump (or OUT/), prints Markdown tables and writes OUT/hopper_discharge.png (matplotlib, Agg; skipped
without it) and OUT/report.md (the same tables).

Per run:
  * the fill stage: particles inserted, mass, discharged count at the end of the fill (the gate must hold: 0),
    the lowest particle centre above the gate;
  * the discharge: mdis(t), the mass of the particles whose centre is below z = -d, against the time since the
    release; the steady mass flow rate W is the slope of a least-squares line through the outputs whose mdis
    lies in the window (default 15 % to 65 % of the total mass), with its R^2 and the slopes of the window's
    first and second halves (a steady flow has them equal); t_90 = time to 90 % of the mass;
  * the bulk density rho_b of the settled fill in the wedge: particle mass (mass / volume from the dump; the
    centres counted) between z = d above the gate and z_top - d, z_top the 90th percentile of the centre
    heights (capped at the bin's top), over the hopper's volume between these heights (width Do + 2 z tan alpha
    in the wedge, Wt above it, times L);
  * Beverloo for a slot of width Do and length L: W = C rho_b sqrt(g) L (Do - k d)^1.5. One outlet size cannot
    separate C and k: k is assumed (--k, default 1.5, the usual value for spheres) and C is fitted,
    C = W / (rho_b sqrt(g) L (Do - k d)^1.5). The end walls are not corrected for (no L - k d).
"""
import argparse
import math
import os
import re
import sys

import numpy as np

G = 9.81
RUNS = (("rock", "log.hopper_rock", "rock polyhedra"), ("spheres", "log.hopper_spheres", "Hertz spheres"))


def parse_log(path):
    """{'fill': table, 'release': table, 'geometry': {...}, 'shape': str, 'N': int, 'loop': [s, ...]}"""
    text = open(path, errors="replace").read().splitlines()
    out = {"loop": [], "steps": []}
    stage = None
    header = None
    for line in text:
        m = re.match(r"^hopper: stage (fill|release)", line)
        if m:
            stage = m.group(1)
            out[stage] = {}
            header = None
            words = line.split()
            if stage == "fill":
                out["N"] = int(words[words.index("N") + 1])
                out["shape"] = words[words.index("shape") + 1]
            continue
        m = re.match(r"^hopper: geometry (.*)", line)
        if m:
            w = m.group(1).split()
            out["geometry"] = {w[i]: float(w[i + 1]) for i in range(0, len(w), 2)}
            continue
        m = re.match(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps", line)
        if m:
            out["loop"].append(float(m.group(1)))
            out["steps"].append(int(m.group(3)))
            header = None
            continue
        words = line.split()
        if stage and words and words[0] == "Step":
            header = words
            continue
        if stage and header and len(words) == len(header) and re.match(r"^\d+$", words[0]):
            for name, value in zip(header, words):
                out[stage].setdefault(name, []).append(float(value))
    for stage in ("fill", "release"):
        out[stage] = {k: np.array(v) for k, v in out.get(stage, {}).items()}
    return out


def read_dump(path):
    lines = open(path).read().splitlines()
    i = max(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[i].split()[2:]
    data = np.array([[float(x) for x in l.split()] for l in lines[i + 1:] if l.strip()])
    return {c: data[:, j] for j, c in enumerate(cols)}


def bulk_density(dump, geo, alpha):
    d, Do, L, Wt, Hw, Hbin, rho = (geo[k] for k in ("d", "Do", "L", "Wt", "Hw", "Hbin", "rho"))
    z = dump["z"]
    z1 = d
    z2 = min(np.percentile(z, 90), Hw + Hbin) - d
    if z2 <= z1:
        return float("nan"), z1, z2
    tan = math.tan(math.radians(alpha))

    def area_integral(a, b):  # L * int width dz from a to b
        def wedge(z):
            return Do * z + tan * z * z
        lo, hi = min(a, Hw), min(b, Hw)
        v = wedge(hi) - wedge(lo) if hi > lo else 0.0
        v += Wt * max(0.0, b - max(a, Hw))
        return L * v
    inside = (z >= z1) & (z < z2)
    return float(np.sum(dump["mass"][inside]) / rho / area_integral(z1, z2) * rho), z1, z2


def analyse(out, name, log, alpha, window, k):
    run = parse_log(os.path.join(out, log))
    geo = run["geometry"]
    fill, rel = run["fill"], run["release"]
    t0 = rel["t"][0]
    t = rel["t"] - t0
    m = rel["mdis"]
    mall = rel["mall"][-1]
    lo, hi = window
    sel = (m >= lo * mall) & (m <= hi * mall)
    r = {"name": name, "N": run["N"], "shape": run["shape"], "geo": geo, "t": t, "m": m, "mall": mall,
         "inserted": int(fill["Atoms"][-1]), "atoms_end": int(rel["Atoms"][-1]),
         "fill_discharged": int(fill["ndis"].max()), "fill_zmin": float(fill["zmin"][-1]),
         "ke_release": float(fill["KinEng"][-1]), "discharged_end": int(rel["ndis"][-1]),
         "loop": sum(run["loop"]), "steps": sum(run["steps"]), "npoints": int(sel.sum())}
    # start of the discharge: first output with any mass below the outlet
    started = np.nonzero(m > 0)[0]
    r["t_first"] = float(t[started[0]]) if len(started) else float("nan")
    reached = np.nonzero(m >= 0.9 * mall)[0]
    r["t90"] = float(t[reached[0]]) if len(reached) else float("nan")
    if sel.sum() >= 3:
        W, b = np.polyfit(t[sel], m[sel], 1)
        pred = W * t[sel] + b
        r["W"], r["b"] = float(W), float(b)
        r["R2"] = float(1 - np.sum((m[sel] - pred) ** 2) / np.sum((m[sel] - m[sel].mean()) ** 2))
        idx = np.nonzero(sel)[0]
        half = len(idx) // 2
        r["W1"] = float(np.polyfit(t[idx[:half + 1]], m[idx[:half + 1]], 1)[0]) if half >= 1 else float("nan")
        r["W2"] = float(np.polyfit(t[idx[half:]], m[idx[half:]], 1)[0]) if len(idx) - half >= 2 else float("nan")
        r["tfit"] = (float(t[sel][0]), float(t[sel][-1]))
    else:
        r.update(W=float("nan"), b=float("nan"), R2=float("nan"), W1=float("nan"), W2=float("nan"),
                 tfit=(float("nan"),) * 2)
    dump = [os.path.join(folder, log.split(".", 1)[1] + "_release.dump") for folder in (out, os.path.join(out, "post"))]
    dump = [f for f in dump if os.path.exists(f)]
    if dump:
        r["rho_b"], r["z1"], r["z2"] = bulk_density(read_dump(dump[0]), geo, alpha)
    else:
        r["rho_b"], r["z1"], r["z2"] = float("nan"), float("nan"), float("nan")
    d, Do, L = geo["d"], geo["Do"], geo["L"]
    r["k"] = k
    r["beverloo_unit"] = r["rho_b"] * math.sqrt(G) * L * max(Do - k * d, 0.0) ** 1.5
    r["C"] = r["W"] / r["beverloo_unit"] if r["beverloo_unit"] > 0 else float("nan")
    return r


def tables(results, alpha):
    geo = results[0]["geo"]
    lines = ["**Hopper**: slot outlet Do = %.4g m (%.3g d), length L = %.4g m (%.3g d), walls at %.4g deg from the "
             "vertical, top width %.4g m, wedge height %.4g m; d = %.4g m (volume-equivalent), particle density "
             "%.4g kg/m^3, E = %.3g Pa, dt = %.3g s" % (
                 geo["Do"], geo["Do"] / geo["d"], geo["L"], geo["L"] / geo["d"], alpha, geo["Wt"], geo["Hw"],
                 geo["d"], geo["rho"], geo["E"], geo["dt"]), "",
             "| run | N inserted | mass kg | discharged during fill | lowest centre at release m | KE at release J "
             "| discharged at end | atoms at end | steps | wall s |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        lines.append("| %s (%s) | %d | %.4g | %d | %.4g | %.3g | %d | %d | %d | %.1f |" % (
            r["name"], r["shape"], r["inserted"], r["mall"], r["fill_discharged"], r["fill_zmin"], r["ke_release"],
            r["discharged_end"], r["atoms_end"], r["steps"], r["loop"]))
    lines += ["", "| run | first discharge s | fit window s | points | W kg/s | R^2 | W 1st half | W 2nd half "
              "| t_90 s | rho_b kg/m^3 (z from-to m) | k (assumed) | C fitted |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        lines.append("| %s | %.3g | %.3g-%.3g | %d | %.4g | %.4f | %.4g | %.4g | %.3g | %.4g (%.3g-%.3g) | %.2g | %.3g |"
                     % (r["name"], r["t_first"], r["tfit"][0], r["tfit"][1], r["npoints"], r["W"], r["R2"],
                        r["W1"], r["W2"], r["t90"], r["rho_b"], r["z1"], r["z2"], r["k"], r["C"]))
    if len(results) == 2:
        a, b = results
        lines += ["", "W(%s) / W(%s) = %.3f; C(%s) / C(%s) = %.3f" % (a["name"], b["name"], a["W"] / b["W"],
                                                                     a["name"], b["name"], a["C"] / b["C"])]
    return "\n".join(lines)


def plot(results, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib missing: no plot)")
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for r, colour, offset in zip(results, ("tab:brown", "tab:blue"), ((8, -14), (-110, 6))):
        ax.plot(r["t"], r["m"], "-", color=colour, label="%s (N = %d)" % (r["name"], r["N"]))
        if not math.isnan(r["W"]):
            tt = np.linspace(r["tfit"][0], r["tfit"][1], 2)
            ax.plot(tt, r["W"] * tt + r["b"], "--", color="k", lw=1)
            ax.annotate("W = %.3g kg/s" % r["W"], (tt[1], r["W"] * tt[1] + r["b"]), textcoords="offset points",
                        xytext=offset, color=colour)
    ax.set_xlabel("time since the gate was removed (s)")
    ax.set_ylabel("discharged mass (kg)")
    ax.set_title("Wedge hopper, slot outlet: discharge")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print("wrote %s" % path)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out")
    p.add_argument("--alpha", type=float, default=30.0)
    p.add_argument("--window", type=float, nargs=2, default=(0.15, 0.65))
    p.add_argument("--k", type=float, default=1.5)
    a = p.parse_args()
    results = [analyse(a.out, name, log, a.alpha, a.window, a.k) for name, log, _ in RUNS
               if os.path.exists(os.path.join(a.out, log))]
    if not results:
        sys.exit("no log.hopper_rock or log.hopper_spheres in %s" % a.out)
    text = tables(results, a.alpha)
    print(text)
    open(os.path.join(a.out, "report.md"), "w").write(text + "\n")
    plot(results, os.path.join(a.out, "hopper_discharge.png"))


if __name__ == "__main__":
    main()
