"""Smoke run of examples/hopper at a tiny size: run.py writes the meshes and runs 60 rock polyhedra (rock_40) and 60
Hertz spheres of equal volume through the wedge hopper (fill with the gate closed, release, discharge), report.py
reads the logs; the numbers must be in a sane range (about 25 s on 2 cores)."""
import importlib.util
import math
import subprocess
import sys

import pytest

from conftest import ROOT

np = pytest.importorskip("numpy")

EXAMPLE = ROOT / "examples" / "hopper"
_spec = importlib.util.spec_from_file_location("hopper_report", EXAMPLE / "report.py")
report = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(report)
_spec = importlib.util.spec_from_file_location("make_hopper", EXAMPLE / "make_hopper.py")
make_hopper = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_hopper)

N = 60
SETTLE = 0.3
DISCHARGE = 0.4


@pytest.fixture(scope="module")
def hopper_run(launcher, tmp_path_factory):
    out = tmp_path_factory.mktemp("hopper")
    run = subprocess.run([sys.executable, str(EXAMPLE / "run.py"), "--N", str(N), "--settle", str(SETTLE),
                          "--discharge", str(DISCHARGE), "--M", "20", "--jobs", "2", "--launcher", str(launcher),
                          "--out", str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    results = {name: report.analyse(str(out), name, log, 30.0, (0.15, 0.65), 1.5) for name, log, _ in report.RUNS}
    return out, run.stdout, results


def test_hopper_mesh_faces_the_particles():
    """Every triangle's normal points into the hopper (towards the axis x = y = 0 or upwards), the gate's up."""
    tris, Hw = make_hopper.hopper(0.12, 0.12, 0.28, 30.0, 0.2)
    assert len(tris) == 16 and abs(Hw - 0.08 / math.tan(math.radians(30))) < 1e-12
    for tri in tris:
        n = make_hopper.unit(make_hopper.normal(*tri))
        c = [sum(p[i] for p in tri) / 3 for i in range(3)]
        assert -n[0] * c[0] - n[1] * c[1] > 0.01 * math.hypot(c[0], c[1]), (tri, n)
    # each interior edge is used once in each direction (consistent orientation)
    edges = {}
    for a, b, c in tris:
        for e in ((a, b), (b, c), (c, a)):
            edges[e] = edges.get(e, 0) + 1
    assert all(v == 1 for v in edges.values())
    shared = sum(1 for (a, b) in edges if (b, a) in edges)
    assert len(edges) - shared == 8                 # rims: top (4 edges) and outlet (4): open there only
    for tri in make_hopper.gate(0.12, 0.12, 0.03):
        assert make_hopper.unit(make_hopper.normal(*tri))[2] == pytest.approx(1.0)


def test_fill_release_discharge(hopper_run):
    out, stdout, results = hopper_run
    for name, r in results.items():
        assert r["inserted"] == N, name                          # insert/pack placed all N
        assert r["atoms_end"] == N, name                         # none lost (the catch basin is closed)
        assert r["mall"] == pytest.approx(N * 2500 * math.pi / 6 * 0.02 ** 3, rel=1e-6), name
        assert r["fill_discharged"] == 0, name                   # the gate holds them before the release
        # settled on the gate: lowest centre above the gate plane, less than a bounding radius above it
        assert 0.0 < r["fill_zmin"] < 0.0135, (name, r["fill_zmin"])
        assert r["ke_release"] < 0.05, (name, r["ke_release"])   # settled (a 60-particle fill has ~0.1 J of
        # potential energy per cm of fall)
        assert r["discharged_end"] == N, name                    # everything left the hopper
        # the discharge starts after the release, not at once: a centre on the gate must go down by more than d
        # (free fall 0.064 s; the load above speeds the bottom layer up, so half of that), and within 0.15 s
        assert 0.5 * math.sqrt(2 * 0.02 / 9.81) < r["t_first"] < 0.15, (name, r["t_first"])
        assert r["npoints"] >= 4 and r["W"] > 0, name
        # Beverloo's order of magnitude for the bulk density of a packing (rho_b ~ 1500 kg/m^3) and C ~ 0.3..3
        unit = 1500 * math.sqrt(9.81) * 0.12 * (0.12 - 1.5 * 0.02) ** 1.5
        assert 0.3 * unit < r["W"] < 3 * unit, (name, r["W"], unit)
    assert "| rock (rock_40.obj) | 60 |" in stdout and "| spheres (sphere) | 60 |" in stdout
    if "matplotlib missing" not in stdout:
        assert (out / "hopper_discharge.png").stat().st_size > 10000


def test_discharged_mass_never_decreases(hopper_run):
    _, _, results = hopper_run
    for name, r in results.items():
        assert np.all(np.diff(r["m"]) >= 0), name
        assert r["m"][0] == 0.0, name
