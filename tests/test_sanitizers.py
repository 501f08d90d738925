"""The package under AddressSanitizer + UndefinedBehaviorSanitizer (issue 13 part 4, "keep it that way").

`make sanitize` builds build-asan/bin/liggghts-poly (CUDA off, -O1 -g -fsanitize=address,undefined,
doc/building.md); a handful of short decks covering the package's code paths run under it on one rank
(no mpirun: OpenMPI's singleton start is quiet under ASan, mpirun is not needed here):

* pair: rocks, Schönhardt polyhedra and a cube colliding in double, single and mixed precision, a plane
  wall, compute property/polyhedron and erotate/polyhedron, dump polyhedron/vtk, write_restart, `clear`,
  read_restart and a further run;
* mesh: the rotating drum of tests/test_mesh_walls.py (fix mesh/surface/stress, move/mesh, wall/polyhedral);
* insertion: fix insert/pack and insert/stream of a mix of three templates with a zplane wall;
* pile: examples/pile trimmed to one layer and 3000 steps (the layer lands on the bed), as shipped otherwise (with its dumps and
  compute pair/polyhedral/local).

A test fails on any sanitizer report ("ERROR: AddressSanitizer", "runtime error:", ...) or a non-zero
exit. LIGGGHTS and OpenMPI are not instrumented, and leak detection is off (detect_leaks=0): their
allocations at exit would drown ours.

Known bug (being fixed separately): ComputePairPolyhedralLocal's destructor reads force->pair after
LIGGGHTS deleted `force` (heap-use-after-free at exit). Only that exact report, at exit, makes the
decks that define compute pair/polyhedral/local xfail; any other report fails them.
"""
import os
import pathlib
import re
import subprocess

import pytest

import decks
import meshes
from conftest import BAD_MESHES, MPI_ENV, ROOT, SHAPES

ASAN_LAUNCHER = ROOT / "build-asan" / "bin" / "liggghts-poly"
SANITIZER_ENV = {
    "ASAN_OPTIONS": "detect_leaks=0:halt_on_error=1:abort_on_error=0:detect_stack_use_after_return=1:"
                    "strict_init_order=1:check_initialization_order=1",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1",
}
REPORT = re.compile(r"ERROR: AddressSanitizer|ERROR: LeakSanitizer|runtime error:|"
                    r"SUMMARY: (AddressSanitizer|UndefinedBehaviorSanitizer)")
KNOWN_EXIT_BUG = ("ComputePairPolyhedralLocal::~ComputePairPolyhedralLocal",
                  "compute pair/polyhedral/local's destructor reads force->pair after LIGGGHTS deleted force "
                  "(heap-use-after-free at exit; fixed on another branch)")


@pytest.fixture(scope="session")
def asan_launcher():
    """`make sanitize` once per session (incremental; about a minute from scratch on 2 cores)."""
    if os.environ.get("POLY_PREBUILT") == "1" and not ASAN_LAUNCHER.exists():
        pytest.skip("POLY_PREBUILT=1 and no build-asan/ (the sanitizer build needs compilers)")
    if os.environ.get("POLY_PREBUILT") != "1":
        result = subprocess.run(["make", "-s", "-j2", "sanitize"], cwd=ROOT, capture_output=True, text=True)
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return ASAN_LAUNCHER


def run_sanitized(launcher, deck, workdir, variables=None, timeout=300):
    workdir = pathlib.Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    command = [str(launcher), "-in", "in.deck", "-log", "log.lammps", "-echo", "screen",
               "-var", "SHAPES", str(SHAPES), "-var", "BAD", str(BAD_MESHES)]
    for name, value in (variables or {}).items():
        command += ["-var", name, str(value)]
    env = dict(os.environ, **MPI_ENV, **SANITIZER_ENV)
    result = subprocess.run(command, cwd=workdir, capture_output=True, text=True, env=env, timeout=timeout,
                            errors="backslashreplace")
    return result.returncode, result.stdout + result.stderr


def check_clean(returncode, output, allow_known_exit_bug=False):
    """No sanitizer report and exit status 0. With allow_known_exit_bug, the one known report at exit
    (use after free in ~ComputePairPolyhedralLocal called from ~LAMMPS) makes the test xfail instead."""
    match = REPORT.search(output)
    if match and allow_known_exit_bug:
        report = output[match.start():]
        frames = [line for line in report.splitlines() if line.lstrip().startswith("#")]
        if ("heap-use-after-free" in report and frames and KNOWN_EXIT_BUG[0] in frames[0]
                and any("LAMMPS::~LAMMPS" in frame for frame in frames)):
            pytest.xfail(KNOWN_EXIT_BUG[1])
    assert not match, "sanitizer report:\n" + output[match.start():match.start() + 6000] if match else ""
    assert returncode == 0, output[-3000:]
    assert not re.search(r"^ERROR", output, re.M), output[-3000:]


MATERIALS = ("communicate single vel yes\nneighbor 0.002 bin\nneigh_modify delay 0\n"
             "fix m1 all property/global youngsModulus peratomtype 1e7 1e7\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.25 0.25\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n")


def pair_deck(precision):
    templates = (decks.template("rock", "rock_40.obj", scale=0.01) +
                 decks.template("sch", "schoenhardt.stl", scale=0.012, seed=32452843) +
                 decks.template("cube", "cube.stl", scale=0.01, seed=49979687))
    dynamics = (f"pair_style polyhedral/volumetric precision {precision}\npair_coeff * *\n"
                "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
                "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"
                "compute props all property/polyhedron shape quatw quati quatj quatk\n"
                "compute erot all erotate/polyhedron\n"
                "thermo_style custom step atoms ke c_erot\nthermo 100\ntimestep 1e-5\n")
    return (decks.header(boundary="f f f", lo=-0.05, hi=0.05, ntypes=2) + MATERIALS + templates +
            "create_polyhedron rock -0.006 0 0.006 quat 0.9 0.3 -0.2 0.25 vel 0.4 0 -0.2\n"
            "create_polyhedron sch 0.006 0.001 0.007 quat 0.7 -0.1 0.6 0.2 vel -0.4 0 -0.2\n"
            "create_polyhedron cube 0.0 0.0 0.02 vel 0 0 -0.5\n"
            "create_polyhedron rock 0.0 0.015 0.02 quat 0.2 0.8 0.1 0.5 omega 0 30 0\n" + dynamics +
            "dump d all custom 200 particles.txt id type x y z c_props[1] c_props[2]\n"
            "dump s all polyhedron/vtk 400 particles_*.vtp\n"
            "run 800\nwrite_restart pair.restart\n"
            "clear\natom_modify sort 0 0\nread_restart pair.restart\n" +
            "newton off\n" + MATERIALS + templates + dynamics + "run 300\n")


@pytest.mark.parametrize("precision", ["double", "single", "mixed"])
def test_pair_and_plane_wall_under_sanitizers(asan_launcher, tmp_path, precision):
    code, output = run_sanitized(asan_launcher, pair_deck(precision), tmp_path)
    check_clean(code, output)
    assert "Loop time" in output, output[-3000:]


def test_mesh_drum_under_sanitizers(asan_launcher, tmp_path):
    meshes.write_stl(tmp_path / "drum.stl", meshes.drum(0.05, 0.04, 32))
    cubes = "".join(f"create_polyhedron cube {x} {y} {z} quat 0.9 0.3 -0.2 0.25\n"
                    for x in (-0.02, 0.0, 0.02) for y in (-0.008, 0.008) for z in (-0.04, -0.027))
    deck = (decks.header(boundary="f f f", lo=-0.07, hi=0.07, ntypes=2) + MATERIALS +
            decks.template("cube", "cube.stl", scale=0.01) +
            decks.template("rock", "rock_70.obj", scale=0.012, seed=32452843) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "fix dmesh all mesh/surface/stress file ../drum.stl type 2\n"
            "fix drum all wall/polyhedral mesh n_meshes 1 meshes dmesh\n"
            "fix spin all move/mesh mesh dmesh rotate origin 0 0 0 axis 0 1 0 period 0.5\n" + cubes +
            "create_polyhedron rock 0 0 0.01 quat 0.2 0.8 0.1 0.5\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
            "thermo_style custom step atoms ke f_drum[4] f_drum[5] f_drum[6] f_drum[7] f_dmesh[4]\n"
            "thermo 500\ntimestep 1e-5\nrun 6000\n")
    code, output = run_sanitized(asan_launcher, deck, tmp_path / "run")
    check_clean(code, output)
    assert "Loop time" in output, output[-3000:]


def test_insertion_under_sanitizers(asan_launcher, tmp_path):
    (tmp_path / "face.stl").write_text(
        "solid face\n" + "".join(
            "facet normal 0 0 -1\nouter loop\n" + "".join(f"vertex {x} {y} 0.35\n" for x, y in tri) +
            "endloop\nendfacet\n" for tri in (((-0.09, -0.09), (0.09, 0.09), (0.09, -0.09)),
                                                ((-0.09, -0.09), (-0.09, 0.09), (0.09, 0.09)))) +
        "endsolid face\n")
    header = decks.header(boundary="f f f", lo=-0.1, hi=0.1, ntypes=2).replace(
        "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1", "region box block -0.1 0.1 -0.1 0.1 0 0.4")
    deck = (header + MATERIALS +
            decks.template("t1", "rock_40.obj", scale=0.01, seed=15485863) +
            decks.template("t2", "schoenhardt.stl", scale=0.012, seed=32452843) +
            decks.template("t3", "cube.stl", scale=0.008, seed=49979687) +
            "fix pdd all particledistribution/discrete 15485867 3 t1 0.5 t2 0.3 t3 0.2\n"
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"
            "region ins block -0.09 0.09 -0.09 0.09 0.01 0.2\n"
            "fix ins all insert/pack seed 86028121 distributiontemplate pdd insert_every once overlapcheck yes "
            "orientation random vel constant 0. 0. -0.5 all_in yes particles_in_region 150 region ins\n"
            "fix face all mesh/surface file ../face.stl type 1\n"
            "fix stream all insert/stream seed 86028157 distributiontemplate pdd nparticles 40 "
            "massrate 0.1 overlapcheck yes orientation random vel constant 0 0 -0.5 "
            "insertion_face face extrude_length 0.04\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
            "thermo_style custom step atoms ke\nthermo 500\ntimestep 1e-5\nrun 3000\n")
    code, output = run_sanitized(asan_launcher, deck, tmp_path / "run")
    check_clean(code, output)
    atoms = [int(line.split()[1]) for line in output.splitlines() if re.match(r"^\s*3000\s+\d+\s", line)]
    assert atoms and atoms[-1] >= 150, output[-3000:]


def test_example_pile_under_sanitizers(asan_launcher, tmp_path):
    """examples/pile with one layer (16 falling particles on the 36 cubes), 3000 steps, dumps every 1000."""
    deck = (ROOT / "examples" / "pile" / "in.pile").read_text()
    for old, new in (("\nrun 20000", "\nrun 3000"), ("thermo          2000", "thermo 500"),
                     ("polyhedron/vtk 5000", "polyhedron/vtk 1000"), ("all local 5000", "all local 1000")):
        assert old in deck, old
        deck = deck.replace(old, new)
    (tmp_path / "post").mkdir()
    code, output = run_sanitized(asan_launcher, deck, tmp_path, variables={"LAYERS": 1})
    assert "Loop time" in output, output[-3000:]
    assert list((tmp_path / "post").glob("particles_*.vtp")), output[-3000:]
    contacts = [float(line.split()[-1]) for line in output.splitlines() if re.match(r"^\s*\d+\s+52\s", line)]
    assert len(contacts) == 7 and max(contacts) > 0, output[-3000:]  # the falling layer reached the bed
    check_clean(code, output, allow_known_exit_bug=True)
