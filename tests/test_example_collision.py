"""Smoke run of examples/collision at a tiny size: run.py runs the decks as documented (polyhedral spheres, a rock,
the LIGGGHTS Hertz spheres), report.py makes its tables and plots, and the numbers are in a sane range."""
import importlib.util
import subprocess
import sys

import pytest

from conftest import ROOT

np = pytest.importorskip("numpy")

EXAMPLE = ROOT / "examples" / "collision"
_spec = importlib.util.spec_from_file_location("collision_report", EXAMPLE / "report.py")
report = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(report)

SPHERES = ["fib40", "ico320", "ico1280"]
YOUNGS = [2.15e7, 4.64e8]
ORIENTATIONS = 6


@pytest.fixture(scope="module")
def collision_run(launcher, tmp_path_factory):
    """3 polyhedral spheres and rock_70 at 21.5 and 464 MPa, 6 orientation pairs each (about 10 s on 2 cores)."""
    out = tmp_path_factory.mktemp("collision")
    run = subprocess.run([sys.executable, str(EXAMPLE / "run.py"), "--spheres", *SPHERES, "--rocks", "rock70",
                          "--youngs", *map(str, YOUNGS), "--orientations", str(ORIENTATIONS), "--jobs", "2",
                          "--launcher", str(launcher), "--liggghts", str(launcher), "--out", str(out)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    cases, references = report.load(out)
    return out, run.stdout, {(c["shape"], c["youngs"]): c for c in cases}, references


def test_all_cases_ran(collision_run):
    out, stdout, cases, references = collision_run
    assert sorted(cases) == sorted((s, y) for s in SPHERES + ["rock70"] for y in YOUNGS)
    assert sorted(references) == YOUNGS
    for case in cases.values():
        assert case["ek"].shape == (ORIENTATIONS, len(case["t"]))
        assert not case["touching_at_end"].any()          # every collision over within the run
        assert (case["contact_time"] > 0).all()             # and every pair touched
    # the report: the three tables, one row per case, and the plots
    assert stdout.count("| icosphere | 1280 |") == 2 * len(YOUNGS)
    assert "**Perfect spheres**" in stdout and "**Extrema of the orientation averages**" in stdout
    if "matplotlib missing" not in stdout:
        for name in ("collision_spheres.png", "collision_rocks.png", "collision_convergence.png"):
            assert (out / name).stat().st_size > 10000


def test_energy_normalised_and_spread(collision_run):
    _, _, cases, references = collision_run
    for (shape, youngs), case in cases.items():
        mean, std = report.statistics(case)
        assert np.all(case["ek"][:, 0] == 1.0)
        assert (std >= 0.0).all() and std[0] == 0.0
        # before the bounding spheres can touch nothing acts: the energy stays at 1 (bounding gap 0.01 D)
        free = case["t"] < -(case["bound"] - 0.1) / 5.0
        assert free.sum() > 3 and np.abs(case["ek"][:, free] - 1.0).max() < 1e-9
        assert 0.0 <= mean.min() < 1.0 and case["ek"].max() < 1.2
    for youngs, r in references.items():
        assert r["ek"][0] == 1.0 and abs(r["ek"][-1] - 1.0) < 1e-4 and abs(r["restitution"] - 1.0) < 1e-4
        assert report.minimum(r["t"], r["ek"])[0] < 1e-5
        # LIGGGHTS' elastic Hertz contact lasts the Hertz time
        assert abs(r["contact_time"] / r["t_hertz"] - 1.0) < 0.01


def test_finest_sphere_matches_perfect_sphere(collision_run):
    _, _, cases, references = collision_run
    for youngs in YOUNGS:
        fine, reference = cases[("ico1280", youngs)], references[youngs]
        # the elastic collision of the finest sphere: restitution, energy at the end and contact time as
        # LIGGGHTS' Hertz spheres (the volumetric law on exact spheres lasts 0.6% (21.5 MPa) and 0.3% longer)
        assert abs(fine["restitution"].mean() - reference["restitution"]) < 0.005
        assert np.abs(fine["ek"][:, -1] - 1.0).max() < 0.005
        assert abs(fine["contact_time"].mean() / reference["contact_time"] - 1.0) < 0.02
        low, t_low, high, _ = report.extrema(fine)
        assert low < 1e-3 and high < 0.02
        assert abs(t_low - report.minimum(reference["t"], reference["ek"])[1]) < 0.03 * reference["t_hertz"]


def test_convergence_and_stiffness(collision_run):
    """Document 000, sec. 6.1 and 6.2: the spread falls with resolution, grows with stiffness; the rock's mean
    energy does not approach zero and spreads more than the spheres."""
    _, _, cases, _ = collision_run
    for youngs in YOUNGS:
        spread = [report.extrema(cases[(s, youngs)])[2] for s in SPHERES]
        assert spread[0] > spread[1] > spread[2]
        assert report.extrema(cases[("rock70", youngs)])[0] > 0.1
        assert report.extrema(cases[("rock70", youngs)])[2] > 10 * spread[-1]
    for shape in SPHERES:
        assert report.extrema(cases[(shape, YOUNGS[1])])[2] > report.extrema(cases[(shape, YOUNGS[0])])[2]
