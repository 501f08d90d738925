"""examples/mill: the mill mesh (closed, normals into the mill), report.py's shoulder/toe and power analysis on
synthetic data with known answers, and a smoke run at a tiny size: run.py writes the mesh and runs 45 rock
polyhedra (rock_40) and 45 Hertz spheres of equal volume through fill, settling and 0.6 revolutions of the mill
at 75 % of the critical speed; the numbers must be in a sane range (about 30 s on 2 cores)."""
import importlib.util
import math
import subprocess
import sys

import pytest

from conftest import ROOT

np = pytest.importorskip("numpy")

EXAMPLE = ROOT / "examples" / "mill"


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


report = load("mill_report", EXAMPLE / "report.py")
make_mill = load("make_mill", EXAMPLE / "make_mill.py")

SMOKE = dict(N=45, d=0.03, L=0.08, J=0.2, speed=0.75, revs=0.6, dt=1.5e-4, steady=0.25)


@pytest.mark.parametrize("lifters,height,width,face,cells,cell", [
    (8, 0.02, 0.02, 20.0, 6, 0.025),     # the default
    (0, 0.0, 0.0, 0.0, 48, 0.02),        # a plain drum
    (12, 0.03, 0.01, 5.0, 4, 0.02),      # tall narrow bars
    (4, 0.04, 0.03, 30.0, 10, 0.03),     # few wide trapezoids
])
def test_mill_mesh_is_closed_and_faces_the_particles(lifters, height, width, face, cells, cell):
    """Every edge is shared by two triangles running it in opposite directions (closed, consistently
    oriented), the signed volume is minus the mill's free volume (so the normals point inwards), the end plates
    face into the mill, and the outline has the lifters asked for."""
    D, L = 0.3, 0.1
    tris, ring = make_mill.mill_triangles(D, L, lifters, height, width, face, cells, cell)
    edges = {}
    for a, b, c in tris:
        for e in ((a, b), (b, c), (c, a)):
            edges[e] = edges.get(e, 0) + 1
    assert all(v == 1 for v in edges.values())
    assert all((b, a) in edges for a, b in edges)
    signed = sum(np.dot(a, np.cross(b, c)) for a, b, c in tris) / 6
    free = make_mill.polygon_area(ring) * L
    assert signed == pytest.approx(-free, rel=1e-9)
    lifter_area = lifters * height * (width + height * math.tan(math.radians(face)))  # trapezoids, about
    assert free == pytest.approx((math.pi * (D / 2) ** 2 - lifter_area) * L, rel=0.02)
    for tri in tris:
        n = make_mill.unit(make_mill.normal(*tri))
        y = [p[1] for p in tri]
        if max(y) - min(y) < 1e-12:                   # an end plate: normal along the axis, into the mill
            assert n[1] == pytest.approx(-1.0 if y[0] > 0 else 1.0)
    if lifters:
        tops = [p for p in ring if math.hypot(*p) < D / 2 - height / 2]
        assert len(tops) == 2 * lifters


def test_undercut_lifters_are_refused():
    """A rectangular bar (face angle 0) hides its side faces from the axis: the end plates cannot be made."""
    with pytest.raises(SystemExit):
        make_mill.outline(0.15, 8, 0.03, 0.01, 0.0, 6)


def band_points(toe, shoulder, R, band, n, rng, background=0.0):
    """Centres spread uniformly over the band inside the shell between the angles toe and shoulder (degrees from
    the bottom, towards -x), and a sparse background all round."""
    theta = np.radians(rng.uniform(toe, shoulder, n))
    if background:
        theta = np.concatenate([theta, np.radians(rng.uniform(-180, 180, int(background * n)))])
    r = R - band * rng.uniform(0.0, 1.0, theta.size)
    return -r * np.sin(theta), -r * np.cos(theta)


@pytest.mark.parametrize("toe,shoulder", [(-50.0, 140.0), (-100.0, 95.0), (30.0, 250.0)])
def test_shoulder_and_toe_of_a_synthetic_charge(toe, shoulder):
    """Centres uniform over a known arc of the band (plus 5 % scattered all round, cataracting particles): the
    recovered toe and shoulder lie within a third of a bin (5 degrees) of the arc's ends; the third case wraps
    past the top (theta = 180)."""
    rng = np.random.default_rng(7)
    x, z = band_points(toe, shoulder, 0.15, 0.04, 200000, rng, background=0.05)
    st = report.shoulder_toe(x, z, 0.15, 0.04, bin_deg=5.0, level=0.5)
    assert st is not None
    found_toe = st["toe"] if abs(st["toe"] - toe) < 180 else st["toe"] - 360
    assert found_toe == pytest.approx(toe, abs=5.0 / 3)
    assert st["shoulder"] - st["toe"] == pytest.approx(shoulder - toe, abs=2 * 5.0 / 3)
    # centres inside the band only: the same charge seen 5 cm further in is ignored
    x2, z2 = band_points(toe + 90, shoulder + 90, 0.10, 0.02, 200000, rng)
    st2 = report.shoulder_toe(np.concatenate([x, x2]), np.concatenate([z, z2]), 0.15, 0.04)
    assert st2["toe"] == pytest.approx(st["toe"], abs=1e-9)


def test_power_statistics_and_torque_arm_on_synthetic_series():
    """A torque of -2 N m with a ripple, at omega = 6 rad/s: P = 12 W in the mean over whole revolutions, the
    first revolution (a start-up ramp) left out; one mean per whole revolution."""
    omega = 6.0
    period = 2 * math.pi / omega
    t = np.arange(0.0, 3.5 * period, 0.002)
    torque = -2.0 * np.minimum(1.0, t / (0.5 * period)) + 0.7 * np.sin(2 * math.pi * 4 * t / period)
    stats = report.power_stats(t, -torque * omega, period, 1.0)
    assert stats["mean"] == pytest.approx(12.0, rel=2e-3)
    assert len(stats["rev_means"]) == 2 and all(abs(m - 12.0) < 0.05 for m in stats["rev_means"])
    assert stats["std"] == pytest.approx(0.7 * omega / math.sqrt(2), rel=0.02)
    # a charge of 3 kg held with its centre of mass 4 cm to the rising side (x < 0): P_arm = M g 0.04 omega
    assert -3.0 * report.G * -0.04 * omega == pytest.approx(7.0632, rel=1e-4)


@pytest.fixture(scope="module")
def mill_run(launcher, tmp_path_factory):
    out = tmp_path_factory.mktemp("mill")
    s = SMOKE
    run = subprocess.run([sys.executable, str(EXAMPLE / "run.py"), "--N", str(s["N"]), "--d", str(s["d"]),
                          "--L", str(s["L"]), "--J", str(s["J"]), "--speed", str(s["speed"]), "--revs", str(s["revs"]),
                          "--dt", str(s["dt"]), "--round", "0.12", "--settle", "0.15", "--M", "20", "--S", "100",
                          "--jobs", "2", "--launcher", str(launcher), "--out", str(out), "--no-report"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    args = type("Args", (), dict(steady=s["steady"], band=0.0, bin=5.0, level=0.5, lifters=8, height=0.02))
    results = {name: report.analyse(str(out), name, log, tag, args) for name, log, tag in report.RUNS}
    return out, results


def test_mill_smoke_run(mill_run):
    out, results = mill_run
    s = SMOKE
    R = 0.15
    for name, r in results.items():
        st = r["shoulder_toe"] or {"toe": float("nan"), "shoulder": float("nan")}
        print("\nmill smoke %s: P %.3g W (torque arm %.3g W), toe %.1f deg, shoulder %.1f deg, farthest centre %.4f m"
              % (name, r["stats"]["mean"], r["arm_mean"], st["toe"], st["shoulder"], r["rmax"]))
    for name, r in results.items():
        mass = s["N"] * 2700 * math.pi / 6 * s["d"] ** 3
        assert r["N"] == s["N"] and r["inserted"] == s["N"], name        # the fill rounds placed all N
        assert r["atoms_min"] == s["N"] and r["atoms_end"] == s["N"], name  # none lost
        assert r["mass"] == pytest.approx(mass, rel=1e-6), name
        # no centre through the shell or the end plates: the mesh holds the charge
        assert r["rmax"] < R and r["ymax"] < s["L"] / 2, name
        # the speed is the fraction of N_c = sqrt(g / (R - d/2)) / (2 pi) asked for
        assert r["omega"] == pytest.approx(s["speed"] * math.sqrt(9.81 / (R - s["d"] / 2)), rel=1e-9), name
        assert r["revs"] == pytest.approx(s["revs"], abs=0.01), name
        steady = r["t"] >= r["stats"]["t0"]
        # the mill does work on the charge once it turns: positive mean power, lifted to the rising side
        assert r["stats"]["mean"] > 0, name
        assert np.mean(r["arm"][steady]) > 0, name
        # within a factor 3 of the torque arm of the charge at rest turned to 45 degrees
        rough = mass * 9.81 * r["rc_rest"] * math.sin(math.radians(45)) * r["omega"]
        assert rough / 3 < r["stats"]["mean"] < 3 * rough, (name, r["stats"]["mean"], rough)
        st = r["shoulder_toe"]
        assert st is not None, name
        # the charge rides up the rising side: the shoulder lies past the bottom in the sense of rotation, the
        # arc in contact with the shell is turned that way, and it is less than the whole shell
        assert st["shoulder"] > 30.0 and st["toe"] < st["shoulder"], (name, st)
        assert (st["toe"] + st["shoulder"]) / 2 > 0.0, (name, st)
        assert 30.0 < st["shoulder"] - st["toe"] < 330.0, (name, st)
    # the torque fix mesh/surface/stress puts on the mill is minus the torque the particles feel from the walls,
    # which fix wall/polyhedral sums on its own
    rock = results["rock"]
    assert rock["torque_scale"] > 0.1
    assert rock["torque_difference"] < 1e-9 * rock["torque_scale"], (rock["torque_difference"], rock["torque_scale"])


def test_mill_report_writes_tables_and_plots(mill_run):
    out, _ = mill_run
    run = subprocess.run([sys.executable, str(EXAMPLE / "report.py"), str(out), "--L", str(SMOKE["L"]),
                          "--steady", str(SMOKE["steady"])], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "| rock (rock_40.obj) | 45 | 45 |" in run.stdout and "| spheres (sphere) | 45 | 45 |" in run.stdout
    assert (out / "report.md").exists()
    if "matplotlib missing" not in run.stdout:
        assert (out / "mill_power.png").stat().st_size > 10000
        assert (out / "mill_section.png").stat().st_size > 10000
