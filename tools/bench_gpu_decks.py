#!/usr/bin/python3
"""Small decks on a GPU host: the same polyhedral deck with the CPU pair style and with `-suffix gpu`, one
rank each, as time per step and the ratio GPU / CPU (issue 15: `-suffix gpu` never slower than the CPU path on
small decks, at least 3x faster from 5,000 particles up). Not a test: it prints numbers (doc/benchmarks.md,
"Small decks with -suffix gpu"). Needs a CUDA build (make -j2 all with nvcc) and a GPU.

  bench_gpu_decks.py [--steps S] [--hopper N[,N...]] [--hopper-settle T] [--gpu-only] [DECK ...]

DECKs: LIGGGHTS' tutorials as Debian's liggghts-doc ships them (chute_wear, conveyor, movingMeshGran, meshGran;
default all four), converted to rock_40 of the spheres' volume by their particle lines (tools/bench_decks.py's
convert_to_polyhedra; their `fix check/timestep/gran` and its thermo columns go too, since that fix accepts
only pair gran; the insertion extrude_length of conveyor and meshGran a bounding radius longer, EDITS), without dumps, cut after their first S steps (default 20000). --hopper N: also
examples/hopper/run.py with N rock_40 (the bin sized for N) for --hopper-settle s of filling (default 0.1 s,
1000 steps), no discharge.

--gpu-only adds a run of each with nothing left to the host however small the work (POLY_GPU_MIN_PAIRS=0
POLY_GPU_MIN_PIECES=0, doc/gpu.md "Small decks"). The CPU runs go side by side on their own cores (--jobs, default 4) while the GPU runs go one after the other,
so a run shares its machine the same way each time; each GPU run's log ends with the style's own account of
its GPU time (pair uploads, kernels, downloads, mesh-wall calls), printed here. Runs in --workdir (default
examples/bench_multisphere/post/gpu_decks). The tutorials come from /usr/share/doc/liggghts or, on a host
without Debian's archive, from the runtime bundle (tools/bundle_runtime.sh --with-tests, doc/gpu.md).
"""
import argparse
import concurrent.futures
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import bench_decks  # noqa: E402
from bench_decks import POLY, SHAPES, convert_to_polyhedra, cut_schedule, strip_dumps  # noqa: E402

DECKS = ["chute_wear", "conveyor", "movingMeshGran", "meshGran"]
TUTORIAL_DIRS = [bench_decks.TUTORIALS,
                 pathlib.Path(os.environ.get("POLY_RUNTIME_DIR", "/tmp/liggghts-poly-runtime")) /
                 "usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public"]
# Edits the conversion needs beyond the particle lines: insert/stream wants extrude_length of at least three
# bounding radii, and rock_40's bounding radius is 1.34 times the volume-equivalent sphere's.
EDITS = {"conveyor": [("extrude_length 0.1", "extrude_length 0.11")],
         "meshGran": [("extrude_length 0.02", "extrude_length 0.021")]}
GPU_LINES = re.compile(r"^(Pair polyhedral/volumetric/gpu|Fix wall/polyhedral meshes on the GPU)")


def tutorials():
    for folder in TUTORIAL_DIRS:
        if (folder / "chute_wear").is_dir():
            return folder
    raise SystemExit("LIGGGHTS' tutorials not found in " + " or ".join(map(str, TUTORIAL_DIRS)) +
                     ": install Debian's liggghts-doc (tools/debian_deps.sh) or source a runtime bundle made with "
                     "--with-tests")


def without_timestep_check(deck):
    """The deck without `fix ID all check/timestep/gran ...` and the thermo columns f_ID[...] that read it."""
    ids, out = set(), []
    for line in deck.splitlines():
        words = line.split("#")[0].split()
        if words[:1] == ["fix"] and len(words) > 3 and words[3] == "check/timestep/gran":
            ids.add(words[1])
            continue
        out.append(line)
    text = "\n".join(out) + "\n"
    for fix_id in ids:
        text = re.sub(r"[ \t]+f_%s\[\d+\]" % re.escape(fix_id), "", text)
    return text


def prepare_tutorial(name, steps, workdir):
    source = tutorials() / name / f"in.{name}"
    here = workdir / name
    if here.exists():
        shutil.rmtree(here)
    shutil.copytree(source.parent / "meshes", here / "meshes")
    (here / "post").mkdir()
    deck = cut_schedule(without_timestep_check(strip_dumps(source.read_text())), steps)
    rocks = convert_to_polyhedra(deck, "rock_40.obj", SHAPES)
    for old, new in EDITS.get(name, []):
        if old not in rocks:
            raise SystemExit(f"{source}: `{old}` not found")
        rocks = rocks.replace(old, new)
    (here / "in.rocks").write_text(rocks)
    return here


# The GPU runs: the style as it chooses, and (--gpu-only) with everything on the GPU however small.
GPU_ONLY = {"POLY_GPU_MIN_PAIRS": "0", "POLY_GPU_MIN_PIECES": "0"}


def run_deck(here, variant):
    suffix, env, tag = variant
    log = f"log.{tag}"
    command = [str(POLY)] + (["-suffix", suffix] if suffix else []) + ["-in", "in.rocks", "-log", log]
    with open(here / (log + ".screen"), "w") as screen:
        start = time.time()
        result = subprocess.run(command, cwd=here, stdout=screen, stderr=subprocess.STDOUT,
                                env=dict(os.environ, **bench_decks.MPI_ENV, **env))
        wall = time.time() - start
    text = (here / log).read_text(errors="replace") if (here / log).exists() else ""
    if result.returncode != 0 or "ERROR" in text:
        tail = (here / (log + ".screen")).read_text(errors="replace")[-3000:]
        raise SystemExit(f"{' '.join(command)} (in {here}) failed ({result.returncode}):\n{tail}")
    return text, wall


def run_hopper(n, settle, out, variant):
    suffix, env, _ = variant
    command = [sys.executable, str(ROOT / "examples" / "hopper" / "run.py"), "--no-report", "--skip", "spheres",
               "--N", str(n), "--settle", repr(settle), "--discharge", "0", "--out", str(out),
               "--launcher", str(POLY)] + (["--suffix", suffix] if suffix else [])
    start = time.time()
    result = subprocess.run(command, capture_output=True, text=True,
                            env=dict(os.environ, **bench_decks.MPI_ENV, **env))
    wall = time.time() - start
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{(result.stdout + result.stderr)[-3000:]}")
    return (out / "log.hopper_rock").read_text(errors="replace"), wall


def summary(text):
    runs = bench_decks.parse_log(text)
    loop = sum(r["loop"] for r in runs)
    steps = sum(r["steps"] for r in runs)
    work = sum(bench_decks.particle_steps(r) for r in runs if r["columns"] and "Atoms" in r["columns"])
    return {"loop": loop, "steps": steps, "atoms": runs[-1]["atoms"] if runs else 0, "work": work,
            "gpu": [line.strip() for line in text.splitlines() if GPU_LINES.match(line)]}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("decks", nargs="*", help=", ".join(DECKS) + " (default all)")
    p.add_argument("--steps", type=int, default=20000, help="the tutorials' first STEPS steps (20000)")
    p.add_argument("--hopper", default="", help="comma-separated particle counts of hopper runs (none)")
    p.add_argument("--hopper-settle", type=float, default=0.1, help="the hopper runs' filling time, s (0.1)")
    p.add_argument("--jobs", type=int, default=4, help="CPU runs side by side (4)")
    p.add_argument("--gpu-only", action="store_true",
                   help="also run -suffix gpu with POLY_GPU_MIN_PAIRS=0 POLY_GPU_MIN_PIECES=0 (nothing on the host)")
    p.add_argument("--workdir", default=str(ROOT / "examples" / "bench_multisphere" / "post" / "gpu_decks"))
    a = p.parse_args()
    decks = a.decks if a.decks else ([] if a.hopper else DECKS)
    unknown = set(decks) - set(DECKS)
    if unknown:
        p.error(f"unknown deck: {' '.join(sorted(unknown))} ({', '.join(DECKS)})")
    hoppers = [int(n) for n in a.hopper.split(",") if n.strip()]
    workdir = pathlib.Path(a.workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    bench_decks.print_header()
    print(f"nvidia-smi: {bench_decks.shell('nvidia-smi --query-gpu=name,driver_version --format=csv,noheader')}")
    print(f"tutorials: {tutorials() if decks else '-'}; their first {a.steps} steps, rock_40; hopper: N = "
          f"{', '.join(map(str, hoppers)) or '-'}, {a.hopper_settle} s of filling")
    print()
    sys.stdout.flush()

    variants = [(None, {}, "cpu"), ("gpu", {}, "gpu")] + ([("gpu", GPU_ONLY, "gpu_only")] if a.gpu_only else [])
    cases = []  # (name, function(variant) -> (log text, wall))
    for name in decks:
        here = prepare_tutorial(name, a.steps, workdir)
        cases.append((name, lambda variant, here=here: run_deck(here, variant)))
    for n in hoppers:
        cases.append((f"hopper N={n}", lambda variant, n=n: run_hopper(n, a.hopper_settle,
                                                                       workdir / f"hopper_{n}_{variant[2]}", variant)))
    start = time.time()
    with concurrent.futures.ThreadPoolExecutor(max(1, a.jobs)) as pool:
        cpu_runs = [pool.submit(case, variants[0]) for _, case in cases]
        gpu_runs = {variant[2]: [] for variant in variants[1:]}
        for name, case in cases:
            for variant in variants[1:]:
                gpu_runs[variant[2]].append(case(variant))
                print(f"  {name}: -suffix gpu {variant[2]} done ({gpu_runs[variant[2]][-1][1]:.0f} s wall)")
                sys.stdout.flush()
        cpu_runs = [f.result() for f in cpu_runs]
    print()
    heads = {"gpu": "-suffix gpu", "gpu_only": "-suffix gpu, nothing on the host"}
    print("| deck | steps | particles at the end | CPU style: loop [s], per step [ms] | " +
          " | ".join(f"{heads[v[2]]}: loop [s], per step [ms] | GPU / CPU" for v in variants[1:]) + " |")
    print("|---|---:|---:|---|" + "---|---:|" * (len(variants) - 1))
    details = []
    for k, ((name, _), (cpu_text, _)) in enumerate(zip(cases, cpu_runs)):
        c = summary(cpu_text)
        cells = [name, str(c["steps"]), "", f"{c['loop']:.2f}, {1e3 * c['loop'] / c['steps']:.3g}"]
        for variant in variants[1:]:
            g = summary(gpu_runs[variant[2]][k][0])
            if c["atoms"] != g["atoms"]:
                details.append(f"{name}: {c['atoms']} particles on the CPU, {g['atoms']} with {variant[2]} at the end")
            cells[2] = str(g["atoms"])
            cells += [f"{g['loop']:.2f}, {1e3 * g['loop'] / g['steps']:.3g}", f"**{g['loop'] / c['loop']:.2f}**"]
            details += [f"{name}, {variant[2]}: {line}" for line in g["gpu"]]
        print("| " + " | ".join(cells) + " |")
    print()
    print("\n".join(details))
    print(f"benchmark: {time.time() - start:.0f} s wall")


if __name__ == "__main__":
    main()
