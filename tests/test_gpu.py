"""pair_style polyhedral/volumetric/gpu.

Without a GPU (CI) the CUDA sources must still compile and link, the style must
stop with a clear ERROR, and every test that needs a GPU reports "skipped: no
GPU" (skips do not count as passed). On a GPU host the same command runs them:
see doc/gpu.md for running there from a bundle."""
import os
import random
import re
import shutil
import subprocess

import pytest

import decks
from conftest import MPI_ENV, ROOT
from test_mesh_walls import drum_deck
from test_bad_input import check_settled_stack, settled_stack_deck
from test_contact_physics import check_wedged_cube, wedged_cube_deck
from test_pair_parallel import MATERIALS, particles, templates


def cuda_built():
    """After the launcher fixture has built: was the CUDA part built (nvcc found)?"""
    return (ROOT / "build" / "obj" / "poly_gpu.o").exists()


def gpu_available():
    smi = shutil.which("nvidia-smi")
    if not smi:
        return False
    listing = subprocess.run([smi, "-L"], capture_output=True, text=True)
    return listing.returncode == 0 and "GPU" in listing.stdout


needs_gpu = pytest.mark.skipif(not gpu_available(), reason="skipped: no GPU")


def run_agreement(driver, *arguments, **environment):
    """Runs build/tests/DRIVER (gpu_agreement or gpu_wall_agreement) on examples/shapes with `arguments` and the
    given environment variables set; prints its output, which must end with OK (the driver's own checks passed),
    and returns it."""
    run = subprocess.run([str(ROOT / "build" / "tests" / driver), str(ROOT / "examples" / "shapes")] + list(arguments),
                         capture_output=True, text=True, env=dict(os.environ, **environment))
    print(run.stdout)
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.strip().endswith("OK")
    return run.stdout


@pytest.fixture(autouse=True)
def everything_on_the_gpu(monkeypatch):
    """These tests check the GPU's code, so no work goes back to the host however small (doc/gpu.md, "Small
    decks"); test_small_work_runs_on_the_host checks the defaults."""
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", "0")
    monkeypatch.setenv("POLY_GPU_MIN_PIECES", "0")


def test_cuda_sources_compile_and_link(launcher):
    if not cuda_built():
        pytest.skip("skipped: built without CUDA (no nvcc)")
    library = ROOT / "build" / "lib" / "libpolyhedral.so"
    symbols = subprocess.run(["nm", "-D", "--defined-only", str(library)], capture_output=True, text=True).stdout
    for name in ("poly_gpu_init", "poly_gpu_compute", "poly_gpu_clear", "poly_gpu_wall_overlaps"):
        assert name in symbols, name
    assert (ROOT / "build" / "tests" / "gpu_agreement").exists()
    assert (ROOT / "build" / "tests" / "gpu_wall_agreement").exists()


def test_gpu_code_paths_on_the_cpu(tmp_path):
    """tests/unit/gpu_paths.c: the GPU's pre-filter (poly_overlap_slab on the relative pose) drops only
    pairs that the overlap without its filter finds apart, and the overlap in a workspace carved from a
    block of POLY_GPU_LOCAL_WORKSPACE_REALS scalars (the contact kernel's local-memory array) is the
    host's bit for bit, for the shapes gpu/poly_gpu.h says fit; random pairs of the reference shapes,
    double, single and mixed. Runs without a GPU."""
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = tmp_path / "gpu_paths"
    sources = [ROOT / "tests" / "unit" / "gpu_paths.c"] + [ROOT / "src" / name for name in
                                                          ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c",
                                                           "poly_convex.c")]
    build = subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I" + str(ROOT / "src"),
                            "-I" + str(ROOT / "gpu")] + [str(s) for s in sources] + ["-lm", "-o", str(binary)],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(binary), str(ROOT / "examples" / "shapes")], capture_output=True, text=True)
    print(run.stdout)
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.strip().endswith("OK")
    assert re.search(r"schoenhardt\.stl +_d: 2000 pairs, .* local memory", run.stdout), run.stdout


def small_deck(pair):
    return (decks.header(boundary="f f f") + "neigh_modify delay 0\n" + MATERIALS.replace(" 5e6 5e6", " 5e6")
            .replace(" 0.25 0.25", " 0.25").replace("peratomtypepair 2 0.5 0.5 0.5 0.5", "peratomtypepair 1 0.5") +
            decks.template("cube", "cube.stl", scale=0.1) + pair + "pair_coeff * *\n"
            "create_polyhedron cube 0.5 0.5 0.5\nfix integrate all nve/polyhedron\nrun 1\n")


@pytest.mark.skipif(gpu_available(), reason="a GPU is present")
def test_gpu_style_without_gpu_is_a_clear_error(run_deck):
    result = run_deck(small_deck("pair_style polyhedral/volumetric/gpu\n"))
    assert result.returncode != 0
    expected = "no usable CUDA GPU" if cuda_built() else "no CUDA support"
    assert any(expected in line for line in result.error_lines()), result.output


@pytest.mark.parametrize("variable,value,expected", [
    ("POLY_GPU_PAIR_KERNEL", "fast", "POLY_GPU_PAIR_KERNEL=fast: expected thread or warp"),
    ("POLY_GPU_PAIR_LANES", "12", "POLY_GPU_PAIR_LANES=12: expected 8, 16 or 32"),
    ("POLY_GPU_WALL_KERNEL", "lanes", "POLY_GPU_WALL_KERNEL=lanes: expected thread or warp"),
    ("POLY_GPU_CLIP_KERNEL", "block", "POLY_GPU_CLIP_KERNEL=block: expected thread or warp"),
    ("POLY_GPU_MIXED_CLIP", "half", "POLY_GPU_MIXED_CLIP=half: expected single or double"),
    ("POLY_GPU_CARVEOUT", "50", "POLY_GPU_CARVEOUT=50: expected tight or driver"),
    ("POLY_GPU_MIN_PAIRS", "-3", "POLY_GPU_MIN_PAIRS=-3: expected a whole number, 0 or more"),
    ("POLY_GPU_MIN_PIECES", "1e3", "POLY_GPU_MIN_PIECES=1e3: expected a whole number, 0 or more")])
def test_bad_contact_kernel_choice_is_a_clear_error(run_deck, monkeypatch, variable, value, expected):
    """A mistyped POLY_GPU_* choice (kernels, lanes, the host's share of small work) stops the GPU style with an
    ERROR naming it (checked before the GPU is looked for, so hosts without one test it too), not a silent
    default."""
    if not cuda_built():
        pytest.skip("built without CUDA: the style stops for that reason first")
    monkeypatch.setenv(variable, value)
    result = run_deck(small_deck("pair_style polyhedral/volumetric/gpu\n"))
    assert result.returncode != 0
    assert any(expected in line for line in result.error_lines()), result.output


def test_suffix_gpu_selects_the_gpu_style(run_deck, tmp_path):
    deck = small_deck("pair_style polyhedral/volumetric\n")
    result = run_deck(deck, workdir=tmp_path / "suffix")
    assert result.returncode == 0, result.output
    (tmp_path / "suffix" / "in.deck").write_text(deck)
    run = subprocess.run([str(ROOT / "build" / "bin" / "liggghts-poly"), "-in", "in.deck", "-suffix", "gpu",
                          "-log", "none", "-var", "SHAPES", str(ROOT / "examples" / "shapes")], cwd=tmp_path / "suffix", capture_output=True, text=True,
                         errors="backslashreplace", env=dict(os.environ, **MPI_ENV))
    if gpu_available():
        assert run.returncode == 0, run.stdout + run.stderr
    else:
        assert run.returncode != 0
        assert "polyhedral/volumetric/gpu" in run.stdout, run.stdout  # the /gpu style was chosen, and said why not


@needs_gpu
@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
def test_gpu_and_cpu_agree_pair_by_pair(launcher, precision):
    """10^4 random overlapping pairs of every reference shape: V, centroid, normal, depth, forces,
    torques and history from the GPU against the host code; relative difference below 1e-10 in double
    and 1e-4 in single and mixed (the driver exits non-zero above that; its header says which scale each
    quantity is measured against, e.g. grazing overlaps below 1e-3 of the particle volume). The
    per-particle force sums of the fast path must equal the per-pair forces exactly."""
    run_agreement("gpu_agreement", "10000", precision)


@needs_gpu
@pytest.mark.parametrize("kernel,lanes", [("thread", "32"), ("warp", "32"), ("warp", "8")])
def test_both_contact_kernels_agree_with_cpu(launcher, kernel, lanes):
    """The two contact kernels (doc/gpu.md, "Two contact kernels"), each forced by POLY_GPU_PAIR_KERNEL for
    every shape that fits it (the warp kernel with 32 and with 8 lanes a pair, POLY_GPU_PAIR_LANES), against
    the host code in double (2000 pairs per shape, 1 in 8 with flush faces); the warp kernel hands the cube's
    flush pairs to the one-thread kernel, which must then be counted, and the thread kernel never hands any."""
    stdout = run_agreement("gpu_agreement", "2000", "double", POLY_GPU_PAIR_KERNEL=kernel, POLY_GPU_PAIR_LANES=lanes)
    handed = {line.split()[0]: int(re.search(r"; (\d+) pairs handed", line).group(1))
              for line in stdout.splitlines() if "pairs handed" in line}
    assert len(handed) == 10, stdout
    if kernel == "warp":
        assert handed["cube.stl"] > 0, handed
    else:
        assert not any(handed.values()), handed


@needs_gpu
@pytest.mark.parametrize("kernel", ["thread", "warp"])
def test_both_clipping_kernels_agree_with_cpu(launcher, kernel):
    """The clipping path's two kernels (doc/gpu.md, "Clipping kernels"), each forced by POLY_GPU_CLIP_KERNEL, for
    the shapes that have clip faces (cube, tetrahedron, box; Schoenhardt polyhedra and rock_10 through their
    convex pieces) against the host code in double, 2000 pairs per shape (1 in 8 with flush faces, which both
    hand to the one-thread kernel)."""
    run_agreement("gpu_agreement", "2000", "double", POLY_GPU_CLIP_KERNEL=kernel)


@needs_gpu
@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
def test_gpu_and_cpu_agree_on_shallow_contacts(launcher, precision):
    """2000 pairs of every shape in contact by 1e-6 to 1e-4 of the particle volume, where rounding weighs most
    (float corners are about 6e-8 of the size off, against an overlap a thousandth of it deep): V from the GPU
    against the host's, each against its own V, at most 1e-10 in double, and in single and mixed a median of 1e-4
    and a worst of 9e-2 and 3e-2 (the accuracy the pair style's page states for such contacts), with
    the driver's usual checks."""
    stdout = run_agreement("gpu_agreement", "2000", precision, "shallow")
    assert stdout.count("shallow contacts") == 10, stdout


@needs_gpu
@pytest.mark.parametrize("clip", ["single", "double"])
def test_mixed_precision_clipping_in_single_and_in_double_agree_with_cpu(launcher, clip):
    """In mixed precision the warp clipping kernel clips the faces in double, as the host's mixed precision does;
    POLY_GPU_MIXED_CLIP=single clips them in single and sums them in double (doc/gpu.md, "Clipping": a benchmark's
    opt-in, test_gpu_mixed_precision_keeps_a_settled_bed_as_double_does says why). Both within
    the mixed tolerance (1e-4) of the host for 2000 pairs of every shape; Schoenhardt polyhedra (the warp kernel's
    shape) differ from the host by float's rounding with single (more than 1e-9) and by double's without (less than
    1e-10): the choice takes effect."""
    stdout = run_agreement("gpu_agreement", "2000", "mixed", POLY_GPU_MIXED_CLIP=clip)
    worst = float(re.search(r"^schoenhardt\.stl .*worst relative difference ([0-9.e+-]+)", stdout,
                            re.MULTILINE).group(1))
    if clip == "single":
        assert 1e-9 < worst < 1e-4, worst
    else:
        assert worst < 1e-10, worst


@needs_gpu
def test_gpu_parting_search_leaves_the_contacts(launcher):
    """The pre-filter's parting search (pair_style polyhedral/volumetric's `parting_search`, on the GPU for pairs
    not in contact at their last evaluation): on the bed's pair mix (half the pairs apart with touching bounding
    spheres) it must leave fewer pairs to the contact kernels than the centre line's slab alone, and the same
    contacts; POLY_GPU_PARTING_SEARCH=0 turns it off. Its pairs' agreement with the host is
    test_gpu_and_cpu_agree_pair_by_pair's (the first call after the pairs are set searches every pair)."""
    def bed(search):
        run = subprocess.run([str(ROOT / "build" / "tests" / "gpu_agreement"), str(ROOT / "examples" / "shapes"),
                              "20000", "double", "bed", "schoenhardt"], capture_output=True, text=True,
                             env=dict(os.environ, POLY_GPU_PARTING_SEARCH=search))
        assert run.returncode == 0, run.stdout + run.stderr
        match = re.search(r"(\d+) contacts, +(\d+) past the pre-filter", run.stdout)
        assert match, run.stdout
        return int(match.group(1)), int(match.group(2))
    contacts_on, kept_on = bed("1")
    contacts_off, kept_off = bed("0")
    print("contacts %d / %d, past the pre-filter %d with the search, %d without" % (contacts_on, contacts_off,
                                                                                     kept_on, kept_off))
    assert contacts_on == contacts_off
    assert contacts_on <= kept_on < kept_off


def thousand_particles(seed=3):
    """A bed of 12 x 12 fixed cubes and 856 rocks and Schönhardt polyhedra above it: 1000 particles."""
    rng = random.Random(seed)
    lines = ["create_polyhedron bed %.4f %.4f 0.01\n" % (0.01 + 0.02 * i, 0.01 + 0.02 * j)
             for i in range(12) for j in range(12)]
    spots = [(0.015 + 0.03 * i, 0.015 + 0.03 * j, 0.034 + 0.026 * k) for k in range(14) for i in range(8)
             for j in range(8)][:856]
    for n, (x, y, z) in enumerate(spots):
        q = [rng.uniform(-1, 1) for _ in range(4)]
        v = [rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-1.0, -0.5)]
        lines.append("create_polyhedron %s %.5f %.5f %.5f quat %.4f %.4f %.4f %.4f vel %.4f %.4f %.4f\n"
                     % (("rock" if n % 2 else "schoenhardt"), x, y, z, *q, *v))
    return "".join(lines)


def packing(pair, many=False, records=True):
    """records=False: no compute pair/polyhedral/local, so the GPU style takes its fast path (forces
    summed on the device, history kept there between rebuilds) except on thermo steps."""
    width = 0.24 if many else 0.12
    contacts = "compute contacts all pair/polyhedral/local\n" if records else ""
    return (decks.header(boundary="p p f", lo=0.0, hi=0.12, ntypes=2).replace(
        "region box block 0.0 0.12 0.0 0.12 0.0 0.12", f"region box block 0.0 {width} 0.0 {width} -0.01 0.5") +
        MATERIALS + templates() + pair + "pair_coeff * *\n" + (thousand_particles() if many else particles()) +
        "group moving type 1\nfix integrate moving nve/polyhedron\nfix gravity moving gravity 9.81 vector 0 0 -1\n"
        + contacts + "compute erot all erotate/polyhedron\n"
        "thermo_style custom step atoms ke c_erot" + (" c_contacts" if records else "") +
        "\nthermo_modify format float %.15g\nthermo 400\n"
        "timestep 2e-5\n")


@needs_gpu
@pytest.mark.parametrize("records", [True, False], ids=["per-pair", "fast"])
def test_gpu_packing_matches_cpu(run_deck, tmp_path, records):
    """1000 particles, 2000 steps, CPU and GPU. per-pair: with compute pair/polyhedral/local, so every
    pair's result comes back to the host (and the contact counts are compared); fast: forces summed on
    the device, the history staying there between the neighbour-list rebuilds of the run."""
    cpu = run_deck(packing("pair_style polyhedral/volumetric\n", many=True, records=records) + "run 2000\n",
                   workdir=tmp_path / "cpu")
    gpu = run_deck(packing("pair_style polyhedral/volumetric/gpu\n", many=True, records=records) + "run 2000\n",
                   workdir=tmp_path / "gpu")
    assert cpu.returncode == 0, cpu.output
    assert gpu.returncode == 0, gpu.output
    columns = ("Step", "Atoms", "KinEng", "c_erot") + (("c_contacts",) if records else ())
    a = cpu.thermo(*columns)
    b = gpu.thermo(*columns)
    assert a["Step"] == b["Step"] and a["Atoms"][-1] == b["Atoms"][-1] == 1000
    if records:
        print(f"contacts CPU {a['c_contacts']}")
        assert max(a["c_contacts"]) >= 100
        # Same double-precision code, but nvcc contracts other multiply-adds: round-off differences that
        # colliding grains amplify, as between 1 and several MPI ranks (tests/test_pair_parallel.py).
        assert a["c_contacts"] == b["c_contacts"], (a["c_contacts"], b["c_contacts"])
    else:
        assert "pair uploads" in gpu.output, gpu.output  # the style's timing summary
    worst = max(abs(x - y) / max(abs(x), 1e-12) for column in ("KinEng", "c_erot") for x, y in zip(a[column], b[column]))
    print(f"GPU vs CPU packing ({'per-pair' if records else 'fast'} path): largest relative energy difference {worst:.2e}")
    assert worst <= 1e-6, worst


@needs_gpu
@pytest.mark.parametrize("records", [True, False], ids=["per-pair", "fast"])
def test_gpu_history_survives_restart(run_deck, tmp_path, records):
    pair = "pair_style polyhedral/volumetric/gpu\n"
    deck = packing(pair, records=records)
    unbroken = run_deck(deck + "run 2400\nrun 2400\n", workdir=tmp_path / "unbroken")
    first = run_deck(deck + "run 2400\nwrite_restart half.restart\n", workdir=tmp_path / "first")
    assert unbroken.returncode == 0 and first.returncode == 0, unbroken.output + first.output
    resumed = ("atom_modify sort 0 0\nread_restart ../first/half.restart\nnewton off\ncommunicate single vel yes\n" +
               MATERIALS + templates() + pair + "pair_coeff * *\n" + deck[deck.index("group moving"):] + "run 2400\n")
    second = run_deck(resumed, workdir=tmp_path / "second")
    assert second.returncode == 0, second.output
    columns = ("Step", "KinEng") + (("c_contacts",) if records else ())
    whole = unbroken.thermo(*columns)
    tail = second.thermo(*columns)
    start = len(whole["Step"]) - 1 - whole["Step"][::-1].index(2400.0)
    if records:
        assert tail["c_contacts"] == whole["c_contacts"][start:]
    worst = max(abs(x - y) / abs(y) for x, y in zip(tail["KinEng"], whole["KinEng"][start:]))
    print(f"restart ({'per-pair' if records else 'fast'} path): largest relative kinetic energy difference {worst:.2e}")
    assert worst <= 1e-8, worst


@needs_gpu
def test_gpu_mixed_precision_keeps_a_settled_bed_as_double_does(run_deck, tmp_path, monkeypatch):
    """test_single_precision's settled bed on the GPU style (forces summed on the device): 300 steps from rest in
    double and in mixed precision, the kinetic and rotational energies within 10 % of double's at every thermo
    step. With the clipping kernel's faces clipped in single (POLY_GPU_MIXED_CLIP=single, the default for a stop)
    a bed of 91,035 such particles went from 0.02 J to 0.77 J in 300 steps where double stayed at 0.02 J."""
    monkeypatch.delenv("POLY_GPU_MIXED_CLIP", raising=False)
    apart = decks.mixed_against_double_on_settled_bed(run_deck, tmp_path, "polyhedral/volumetric/gpu")
    assert apart <= 0.1, apart


@needs_gpu
def test_gpu_single_precision_spins_no_particle_of_a_settled_bed_up(run_deck, tmp_path):
    """test_single_precision's settled bed on the GPU style: the largest squared angular velocity of any particle
    in single precision within 3 times double's over 300 steps (an overlap whose centroid falls outside its
    particles is no contact on the GPU as on the host: poly_contact_centroid_within; the kernels count them and the
    style warns as the host's does, which it did not before 2026-11-28); and double's largest below 40, as on the
    host (one H200: 11.9 in single, 11.8 in double)."""
    fastest_single, fastest_double = decks.largest_spins_on_settled_bed(run_deck, tmp_path,
                                                                        "polyhedral/volumetric/gpu")
    assert fastest_single <= 3.0 * fastest_double, (fastest_single, fastest_double)
    assert fastest_double < 40.0, fastest_double


@needs_gpu
def test_gpu_settled_deep_contacts_give_no_warning_at_a_later_run(run_deck, monkeypatch):
    """test_bad_input's settled stack with the GPU style, all its pairs on the device: the contacts were in
    contact at the step before (the host's touch flags at set-up), so the second run does not warn."""
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", "0")
    monkeypatch.setenv("POLY_GPU_MIN_PIECES", "0")
    check_settled_stack(run_deck(settled_stack_deck("polyhedral/volumetric/gpu")))


@needs_gpu
@pytest.mark.parametrize("shift, warnings", [(0.0, 1), (2e-6, 0)], ids=["both walls", "one wall"])
def test_gpu_says_a_cube_wedged_across_the_slot(run_deck, tmp_path, monkeypatch, shift, warnings):
    """test_contact_physics' wedged cube with the GPU style, its pair on the device: the kernels count contacts at
    spots facing apart (poly_contact_spots_facing_apart) and the style says it once, as the host's does."""
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", "0")
    result = run_deck(wedged_cube_deck(tmp_path, shift, "polyhedral/volumetric/gpu"))
    check_wedged_cube(result, warnings)
    on_gpu, on_host, _ = gpu_summary(result.output)
    assert on_gpu > 0 and on_host == 0, (on_gpu, on_host)


@needs_gpu
def test_gpu_history_kept_on_device_matters(run_deck, tmp_path):
    """The fast path's agreement above could hide lost history if friction did not matter here: the
    same packing with tangential off must differ from it by far more than the 1e-6 tolerance."""
    on = run_deck(packing("pair_style polyhedral/volumetric/gpu\n", many=True, records=False) + "run 2000\n",
                  workdir=tmp_path / "on")
    off = run_deck(packing("pair_style polyhedral/volumetric/gpu tangential off\n", many=True, records=False) +
                   "run 2000\n", workdir=tmp_path / "off")
    assert on.returncode == 0 and off.returncode == 0, on.output + off.output
    a, b = on.thermo("KinEng"), off.thermo("KinEng")
    worst = max(abs(x - y) / max(abs(x), 1e-12) for x, y in zip(a["KinEng"], b["KinEng"]))
    print(f"tangential history on vs off: largest relative kinetic energy difference {worst:.2e}")
    assert worst > 1e-3, worst


@needs_gpu
@pytest.mark.parametrize("precision,kernel", [("double", "warp"), ("single", "warp"), ("mixed", "warp"),
                                              ("double", "thread")])
def test_gpu_and_cpu_agree_on_mesh_wall_pieces(launcher, precision, kernel):
    """fix wall/polyhedral's mesh narrow phase on the GPU (gpu/poly_gpu_wall.cu; lanes per piece, the
    default, and one thread per piece, forced by POLY_GPU_WALL_KERNEL) against the host code: 2000 particles
    of each of 8 reference shapes in random poses on a mesh with a concave and a convex crease; every
    (particle, prism) piece's V and centroid, and every particle's contact combined from its pieces and
    their nodes (V, centroid, normal, depth), within 1e-10 in double and 1e-4 in single and mixed (the
    driver exits non-zero above that; its header gives the scales)."""
    run_agreement("gpu_wall_agreement", "2000", precision, POLY_GPU_WALL_KERNEL=kernel)


@needs_gpu
@pytest.mark.parametrize("precision", ["double", "mixed"])
@pytest.mark.parametrize("shape", ["rock_1000.obj", "icosphere_1280.off"])
def test_gpu_and_cpu_agree_on_large_shapes_mesh_wall_pieces(launcher, precision, shape):
    """Shapes whose one-thread workspaces do not fit local memory take a warp per piece with its block in global
    memory (gpu/poly_gpu_wall.cu, large_pieces_by_warp), alone as in a deck of one template: 300 particles on
    the creased mesh, the same checks and tolerances as above."""
    run_agreement("gpu_wall_agreement", "300", precision, shape)


@needs_gpu
def test_gpu_mesh_walls_match_cpu(run_deck, tmp_path):
    """The rotating drum of tests/test_mesh_walls.py (12 cubes, 128 triangles, fix mesh/surface/stress)
    with the /gpu pair style, whose mesh-wall overlaps then run on the GPU, against the CPU style, 12000
    steps on one rank: the same wall contact count at every output, torque on the drum and kinetic energy
    within 1e-6 relative, and on the GPU too the torque of fix mesh/surface/stress equals the one summed
    from the particles' side."""
    runs = {}
    for name, pair in (("cpu", "pair_style polyhedral/volumetric\n"), ("gpu", "pair_style polyhedral/volumetric/gpu\n")):
        (tmp_path / name).mkdir()
        result = run_deck(drum_deck(tmp_path / name, pair=pair, processors="1 1 1"), workdir=tmp_path / name / "run")
        assert result.returncode == 0, result.output[-3000:]
        runs[name] = result.thermo("Step", "Atoms", "KinEng", *[f"f_drum[{k}]" for k in range(4, 8)],
                                   *[f"f_dmesh[{k}]" for k in range(4, 7)])
    cpu, gpu = runs["cpu"], runs["gpu"]
    assert cpu["Step"] == gpu["Step"] and gpu["Atoms"][-1] == 12
    assert cpu["f_drum[4]"] == gpu["f_drum[4]"], (cpu["f_drum[4]"], gpu["f_drum[4]"])
    assert max(cpu["f_drum[4]"]) >= 4
    worst = 0.0
    for column in ["KinEng"] + [f"f_dmesh[{k}]" for k in range(4, 7)]:
        scale = max(abs(x) for x in cpu[column])
        worst = max(worst, max(abs(x - y) for x, y in zip(cpu[column], gpu[column])) / scale)
    own = max(abs(gpu[f"f_drum[{k + 1}]"][n] - gpu[f"f_dmesh[{k}]"][n]) for k in range(4, 7)
              for n in range(1, len(gpu["Step"])))
    scale = max(abs(x) for k in range(4, 7) for x in gpu[f"f_dmesh[{k}]"])
    print(f"drum, GPU walls vs CPU: largest relative difference of kinetic energy and drum torque {worst:.2e}; "
          f"GPU: mesh/surface/stress torque vs the particles' side {own:.1e} of {scale:.2e} N m")
    assert worst <= 1e-6, worst
    assert own < 1e-9 * scale, (own, scale)


def gpu_summary(output):
    """Steps of the pair style on the GPU and on the host, and the mesh walls' GPU calls (0 without the line),
    from the style's summary at the end of a run."""
    pair = re.search(r"(\d+) steps on the GPU .*?, (\d+) on the host", output)
    walls = re.search(r"meshes on the GPU \(summed over ranks\): (\d+) calls", output)
    assert pair, output[-3000:]
    return int(pair.group(1)), int(pair.group(2)), int(walls.group(1)) if walls else 0


@needs_gpu
def test_small_work_runs_on_the_host(run_deck, tmp_path, monkeypatch):
    """doc/gpu.md, "Small decks": below POLY_GPU_MIN_PAIRS (a rank's neighbour-list pairs, those in contact
    counting 32, at each rebuild) and POLY_GPU_MIN_PIECES (a step's mesh-wall pieces) the GPU style runs the
    host's code. With both out of reach, the packing of 200 particles and the rotating drum (mesh walls)
    give the CPU style's thermo bit for bit and no GPU call; with a POLY_GPU_MIN_PAIRS between the
    packing's first and last pair counts, its steps are split between host and GPU over its rebuilds, the
    history passing between them through LIGGGHTS' lists, and it agrees with the CPU within the GPU packing
    test's 1e-6."""
    columns = ("Step", "Atoms", "KinEng", "c_erot", "c_contacts")
    deck = "run 2000\n"
    cpu = run_deck(packing("pair_style polyhedral/volumetric\n") + deck, workdir=tmp_path / "cpu")
    assert cpu.returncode == 0, cpu.output
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", "1000000000")
    monkeypatch.setenv("POLY_GPU_MIN_PIECES", "1000000000")
    host = run_deck(packing("pair_style polyhedral/volumetric/gpu\n") + deck, workdir=tmp_path / "host")
    assert host.returncode == 0, host.output
    assert cpu.thermo(*columns) == host.thermo(*columns)
    assert gpu_summary(host.output)[:1] == (0,), gpu_summary(host.output)
    drum = {}
    for name, pair in (("cpu", "pair_style polyhedral/volumetric\n"), ("host", "pair_style polyhedral/volumetric/gpu\n")):
        (tmp_path / ("drum_" + name)).mkdir()
        result = run_deck(drum_deck(tmp_path / ("drum_" + name), pair=pair, processors="1 1 1"),
                          workdir=tmp_path / ("drum_" + name) / "run")
        assert result.returncode == 0, result.output[-3000:]
        drum[name] = result
    drum_columns = ("Step", "Atoms", "KinEng", "f_drum[4]", "f_dmesh[4]", "f_dmesh[5]", "f_dmesh[6]")
    assert drum["cpu"].thermo(*drum_columns) == drum["host"].thermo(*drum_columns)
    assert gpu_summary(drum["host"].output)[0] == 0 and gpu_summary(drum["host"].output)[2] == 0

    # Split: the packing's pairs grow as it settles; a threshold between its smallest and largest work.
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", "0")
    all_gpu = run_deck(packing("pair_style polyhedral/volumetric/gpu\n") + deck, workdir=tmp_path / "gpu")
    assert all_gpu.returncode == 0, all_gpu.output
    mean = float(re.search(r"steps on the GPU \((\d+) pairs per step", all_gpu.output).group(1))
    monkeypatch.setenv("POLY_GPU_MIN_PAIRS", str(int(mean)))
    split = run_deck(packing("pair_style polyhedral/volumetric/gpu\n") + deck, workdir=tmp_path / "split")
    assert split.returncode == 0, split.output
    on_gpu, on_host, _ = gpu_summary(split.output)
    print(f"packing, POLY_GPU_MIN_PAIRS={int(mean)}: {on_gpu} steps on the GPU, {on_host} on the host")
    assert on_gpu > 0 and on_host > 0
    a, b = cpu.thermo(*columns), split.thermo(*columns)
    assert a["Step"] == b["Step"] and a["c_contacts"] == b["c_contacts"]
    worst = max(abs(x - y) / max(abs(x), 1e-12) for column in ("KinEng", "c_erot") for x, y in zip(a[column], b[column]))
    print(f"split between host and GPU vs CPU: largest relative energy difference {worst:.2e}")
    assert worst <= 1e-6, worst


@needs_gpu
def test_contact_counts_come_back_from_the_gpu(run_deck, tmp_path):
    """compute contact/polyhedron with the GPU style's fast path (history and touch flags on the device between
    rebuilds): the counts summed over the particles at every output are those of the CPU style (whose sums are
    twice its contacts, tests/test_contact_polyhedron.py)."""
    tail = ("compute coord all contact/polyhedron\ncompute total all reduce sum c_coord\n"
            "thermo_style custom step c_total\nthermo_modify format float %.15g\nthermo 400\nrun 2000\n")
    runs = {}
    for name, pair in (("cpu", "pair_style polyhedral/volumetric\n"), ("gpu", "pair_style polyhedral/volumetric/gpu\n")):
        deck = packing(pair, many=True, records=False).replace("thermo 400\n", "") + tail
        result = run_deck(deck, workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        runs[name] = result.thermo("Step", "c_total")
    print(runs)
    assert runs["cpu"] == runs["gpu"]
    assert max(runs["gpu"]["c_total"]) >= 200


@needs_gpu
def test_gpu_cohesion_matches_cpu(run_deck, tmp_path):
    """cohesion sjkr on the GPU (the shared law with the overlap's projected area from either contact kernel):
    the cohesive pair of tests/test_cohesion.py gives the CPU style's normal force to 1e-10."""
    from test_cohesion import pair_force
    cpu = pair_force(run_deck, tmp_path / "cpu", False, "sjkr")
    gpu = pair_force(lambda deck, workdir: run_deck(deck.replace("polyhedral/volumetric cohesion",
                                                                 "polyhedral/volumetric/gpu cohesion"), workdir=workdir),
                     tmp_path / "gpu", False, "sjkr")
    off = pair_force(run_deck, tmp_path / "off", False, "off")
    print(f"normal force with cohesion: CPU {cpu!r}, GPU {gpu!r}; without {off!r}")
    assert gpu == pytest.approx(cpu, rel=1e-10) and off - cpu > 1.0


@needs_gpu
def test_dump_vtk_fields_from_the_gpu_style(run_deck, tmp_path):
    """dump polyhedron/vtk (.pvtp, a piece per rank; ASCII, read here without VTK, which GPU hosts may lack) with
    the GPU style on its fast path: the per-particle force and contact count it writes are the CPU style's
    (forces to 1e-6 relative after 1000 steps of a falling packing, where the two styles' sums differ in order
    only; counts equal)."""
    import xml.etree.ElementTree as ElementTree

    import numpy as np
    fields = {}
    for name, pair in (("cpu", "pair_style polyhedral/volumetric\n"), ("gpu", "pair_style polyhedral/volumetric/gpu\n")):
        deck = (packing(pair, many=True, records=False) +
                "dump d all polyhedron/vtk 1000 post/p_*.pvtp\ndump_modify d binary no\nrun 1000\n")
        result = run_deck(deck, nprocs=2, workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        rows = {}
        for piece in sorted((tmp_path / name / "post").glob("p_1000_*.vtp")):
            arrays = {a.get("Name"): np.array(a.text.split(), dtype=float)
                      for a in ElementTree.parse(piece).getroot().iter("DataArray") if a.get("Name")}
            for k, particle in enumerate(arrays["id"].astype(int)):
                rows[particle] = (tuple(arrays["f"][3 * k:3 * k + 3]), arrays["contacts"][k])
        fields[name] = rows
    assert sorted(fields["cpu"]) == sorted(fields["gpu"]) and len(fields["cpu"]) > 500
    ids = sorted(fields["cpu"])
    force = {name: np.array([fields[name][i][0] for i in ids]) for name in fields}
    contacts = {name: np.array([fields[name][i][1] for i in ids]) for name in fields}
    assert np.array_equal(contacts["cpu"], contacts["gpu"]) and contacts["gpu"].sum() > 100
    # 1e-6: the fields are passed through, so a bug is O(1); the trajectories themselves part by the order of
    # sums over 1000 steps of a packing (within 1e-8 on an H100), which other GPUs and compilers may change.
    assert np.abs(force["gpu"] - force["cpu"]).max() <= 1e-6 * np.abs(force["cpu"]).max()
