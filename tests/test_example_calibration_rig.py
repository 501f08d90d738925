"""examples/calibration_rig: the sigmoid fit of eq. 6.1 on synthetic heaps of known angle, the rig's meshes, and a
smoke run at a tiny size (run.py with 60 rock_10 rocks in a 30 mm wide channel: fill, doors opening, flow down the tilted plane, heap on
the bottom plate; report.py reads the log and the final surfaces). About 40 s on 2 idle cores."""
import importlib.util
import json
import math
import subprocess
import sys

import pytest

from conftest import ROOT

np = pytest.importorskip("numpy")
pytest.importorskip("scipy")

EXAMPLE = ROOT / "examples" / "calibration_rig"


def load(name, example=EXAMPLE):
    spec = importlib.util.spec_from_file_location(example.name + "_" + name, example / (name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


report = load("report")
make_rig = load("make_rig")
make_hopper = load("make_hopper", ROOT / "examples" / "hopper")   # its normal() and unit()

N = 60
SETTLE = 0.25
FLOW = 0.55   # long enough for the heap to come to rest (test_smoke_angle_and_energy_are_sane)


@pytest.mark.parametrize("angle", [20.0, 37.0, 50.0])
def test_sigmoid_fit_recovers_the_angle_of_a_sigmoid_heap(angle):
    """A 20-bin height map sampled from eq. 6.1 with 0.5 mm of noise: the fitted steepest slope is the true one."""
    c = 0.04
    a = 4 * math.tan(math.radians(angle)) / c
    x = (np.arange(20) + 0.5) * 0.15 / 20
    h = report.sigmoid(x, a, 0.06, c) + np.random.default_rng(7).uniform(-5e-4, 5e-4, x.size)
    fitted_a, b, fitted_c, fitted = report.fit_repose_angle(x, h)
    assert abs(fitted - angle) < 1.5, (fitted, angle)
    assert abs(b - 0.06) < 0.004 and abs(fitted_c - c) < 0.002


def test_height_map_of_a_point_cloud_under_a_ramp():
    """Points filling a heap with a plateau, a straight 35-degree flank and nothing beyond: height_map takes the
    highest point per bin, and the sigmoid's steepest slope lies between the flank's and 1.3 times it (the fit
    rounds the two corners off and steepens the middle); the straight-line cross-check gives the flank's angle."""
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 0.15, 200000)
    top = np.clip(0.04 - math.tan(math.radians(35.0)) * (x - 0.03), 0.0, 0.04)
    points = np.column_stack([x, np.zeros_like(x), rng.uniform(0.0, 1.0, x.size) ** 0.05 * top])
    centres, heights = report.height_map(points, 0.15, 20)
    assert np.allclose(centres, (np.arange(20) + 0.5) * 0.0075)
    edge_top = np.clip(0.04 - math.tan(math.radians(35.0)) * (centres - 0.0075 / 2 - 0.03), 0.0, 0.04)
    assert np.all(heights <= edge_top + 1e-12) and np.all(heights > edge_top - 1e-3)
    angle = report.fit_repose_angle(centres, heights)[3]
    assert 35.0 <= angle <= math.degrees(math.atan(1.3 * math.tan(math.radians(35.0)))), angle
    assert report.flank_angle(centres, heights) == pytest.approx(35.0, abs=1.0)   # the straight flank itself


def test_rig_meshes_face_the_rocks():
    dims = make_rig.rig_dimensions(1.0)
    for side in (-1, 1):
        for tri in make_rig.door(dims, side):
            n = make_hopper.unit(make_hopper.normal(*tri))
            assert n[2] == pytest.approx(1.0)
    for tri in make_rig.hopper(dims):   # the wedge and the bin: normals towards the hopper's axis x = xh
        n = make_hopper.unit(make_hopper.normal(*tri))
        centre = sum(p[0] for p in tri) / 3
        assert n[0] * (dims["xh"] - centre) > 0.0 and abs(n[1]) < 1e-12
    slab = make_rig.tilted_plane(dims)
    assert len(slab) == 12
    directed = [(p, q) for a, b, c in slab for p, q in ((a, b), (b, c), (c, a))]
    assert sorted(directed) == sorted((q, p) for p, q in directed), "the slab is not closed and consistent"
    volume = sum(np.dot(a, np.cross(b, c)) for a, b, c in (np.array(t) for t in slab)) / 6
    assert volume == pytest.approx(dims["Lt"] * dims["plate_t"] * dims["W"], rel=1e-9)   # > 0: normals outwards
    theta = math.radians(dims["theta"])
    sliding_face = [t for t in slab if np.allclose(make_hopper.unit(make_hopper.normal(*t)),
                                                   (-math.sin(theta), 0.0, math.cos(theta)))]
    assert len(sliding_face) == 2


def test_damping_of_table_a2_as_restitution():
    """Document 000's gamma (eq. 4.5) turned into this package's restitution: no damping is e = 1, more damping
    rebounds less, and table A.2's two values give restitutions of 0.30 and 0.35."""
    run = load("run")
    assert run.restitution_for_damping(0.0) == pytest.approx(1.0, abs=1e-6)
    e_pp, e_pw = run.restitution_for_damping(0.453619), run.restitution_for_damping(0.382097)
    assert 0.0 < e_pp < e_pw < 1.0
    assert e_pp == pytest.approx(0.300, abs=0.002) and e_pw == pytest.approx(0.350, abs=0.002)


@pytest.fixture(scope="module")
def rig_run(launcher, tmp_path_factory):
    out = tmp_path_factory.mktemp("rig")
    run = subprocess.run([sys.executable, str(EXAMPLE / "run.py"), "--N", str(N), "--shapes", "rock_10.obj",
                          "--seeds", "1", "--settle", str(SETTLE), "--flow", str(FLOW), "--rig", "W=0.03",
                          "--launcher", str(launcher), "--out", str(out)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    results = json.loads((out / "results.json").read_text())
    assert len(results) == 1
    return out, run.stdout, results[0]


def test_smoke_rocks_are_conserved_and_leave_the_hopper(rig_run):
    out, _, r = rig_run
    assert r["inserted"] == N and r["atoms_end"] == N           # thermo_modify lost error: none may leave
    assert r["in_hopper_end"] == 0
    # nearly at rest on the closed doors before they open: rms speed under 5 cm/s (about 1 m/s in the flow)
    assert math.sqrt(2 * r["ke_release"] / r["mass"]) < 0.05
    assert r["flow_end"] < SETTLE + FLOW                         # 95 % reach the plate within the run


def test_smoke_heap_on_the_plate(rig_run):
    out, _, r = rig_run
    assert r["on_plate"] >= 0.95 * N
    heights = np.array(r["map_h"])
    assert heights[0] > 0.0 and heights.max() > 0.015       # more than a layer of 4-7 mm rocks at the back wall
    assert r["xmax_end"] < 0.2                               # nothing has rolled on to the end wall (0.3 m)


def test_smoke_angle_and_energy_are_sane(rig_run):
    out, stdout, r = rig_run
    assert math.isfinite(r["angle"]) and 10.0 < r["angle"] < 70.0, r["angle"]
    # The fitted sigmoid falls away from the back wall (a, c > 0); its midpoint b may lie behind the wall, which
    # report.py handles (a heap with no plateau: the slope is taken at the map's end). A heap of 60 rocks is
    # chaotic: rounding-level changes of a contact give another heap (this seed: 15 deg, b = 0.037 before the mesh
    # walls' mesh path, 14 deg and b = 0.017 with it). With a flow of 0.45 s the last tenth's energy was 0.008 to
    # 0.021 of the peak over seeds 1-4 of either build (a last rock still rolling: the criterion's 0.02 inside
    # that scatter); at 0.55 s it is 0.0004-0.0009, both builds.
    assert r["b"] < 0.15 and r["a"] > 0.0 and r["c"] > 0.0
    assert r["ke_flow"] > 10 * r["ke_end"] and r["ke_last_tenth"] < 0.02 * r["ke_max"]
    assert "| rock_10_" in stdout and (out / "calibration_rig_resolution.png").stat().st_size > 10000
    assert (out / "calibration_rig_heaps.png").stat().st_size > 10000
