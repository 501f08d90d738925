"""The crossing cache of the general path (poly_crossing_cache; src/poly_overlap_cache_impl.h): a contact whose
crossings are certified unchanged since its last search is evaluated from them, by the same functions in the same
order, so every result bit must be the search's.

- tests/unit/crossing_cache.c moves pairs in contact step by step (random walks from 1e-7 to 1e-3 of the size a
  step, with jumps) and evaluates each step with a cache kept from step to step and without one: every result
  field the same bits, in double, single and mixed precision, with many steps taken from the cache. Built with
  its certificates inflated a thousandfold (POLY_CACHE_MARGIN_SCALE), the same driver must find differences: the
  comparison can fail.
- the same driver with `apart` evaluates as the pair style does pairs not touching at their last evaluation (the
  parting search, also after a replay the certificate does not take): the same bits with and without the cache, and
  every volume the same bits as with the former filters, while the search parts some near misses.
- tests/unit/crossing_cache_edge.c moves pairs of other shapes and sizes by 0.5 to 0.999 of their certificate's
  margin: the search's bits, and differences when the certificates are inflated only twice.
- the same driver with `recheck` rechecks the watched pairs past their margins and moves B to 0.5-0.999 of the
  rechecks' margins from there: the search's bits, and differences when those margins are made twice as long.
- tests/unit/crossing_cache_thin.c certifies a tiny tetrahedron by a face of a rock and moves it through the face
  in one evaluation (the same crossings, none, but inside or out): the search's volume, and a wrong one in a build
  without the outside vertices that watched pairs need (POLY_CACHE_OUTSIDE_CHECKS=0).
- A pile of 80 rock_40 (examples/bench_multisphere/in.pile_poly, fewer particles and steps) with `crossing_cache on`
  and `off`, on one rank and on two: the same thermo output to the digits printed, and compute
  pair/polyhedral/local's ninth and tenth elements counting contacts and near misses evaluated from the cache (none
  with it off).

Run with Debian's python3:  /usr/bin/python3 -m pytest tests/test_crossing_cache.py -q
"""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")


def build_driver(directory, defines=(), name="crossing_cache"):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(directory / (name + "".join(d.split("=")[-1] for d in defines)))
    sources = [os.path.join(ROOT, "tests", "unit", name + ".c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", *defines,
                    "-I" + os.path.join(ROOT, "src")] + sources + ["-lm", "-o", binary], check=True)
    return binary


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    return build_driver(tmp_path_factory.mktemp("cache"))


def run(binary, shape, precision, sequences=40, steps=200, start="contact", apart=False):
    out = subprocess.run([binary, os.path.join(SHAPES, shape), str(sequences), str(steps), precision]
                         + (["near"] if start == "near" else []) + (["apart"] if apart else []),
                         capture_output=True, text=True, check=True)
    words = out.stdout.split()
    return dict(zip(words[0::2], (int(w) for w in words[1::2]))), out.stderr


# Shapes whose pairs take the general path (crossing records) in these precisions: rocks in all three, the
# Schoenhardt polyhedron in single and mixed (in double it takes the clipping path, which keeps no cache).
CASES = [(shape, precision) for shape in ("rock_40.obj", "rock_70.obj") for precision in ("double", "single", "mixed")]
CASES += [("schoenhardt.stl", "single"), ("rock_20.obj", "single")]


@pytest.mark.parametrize("shape,precision", CASES)
def test_evaluations_from_the_cache_give_the_search_bits(driver, shape, precision):
    counts, errors = run(driver, shape, precision)
    print(f"\n{shape} {precision}: {counts}")
    assert counts["differ"] == 0, errors
    assert counts["contacts"] == counts["evaluations"]
    # Slow sequences keep their certificates for many steps: a good part of the evaluations come from the cache.
    assert counts["hits"] > 0.3 * counts["evaluations"]
    assert counts["hits"] + counts["searches"] == counts["evaluations"]


@pytest.mark.parametrize("shape,precision", [("rock_40.obj", "double"), ("rock_40.obj", "single"),
                                             ("rock_70.obj", "double")])
def test_near_misses_from_the_cache_give_the_search_bits(driver, shape, precision):
    """Walks from just beyond touching: near misses (apart, though the filter does not part them) keep their empty
    search under a certificate as contacts keep their crossings, and come out the same bits."""
    counts, errors = run(driver, shape, precision, start="near")
    print(f"\n{shape} {precision}, from near misses: {counts}")
    assert counts["differ"] == 0, errors
    assert counts["misses"] > 0.2 * counts["evaluations"]
    assert counts["contacts"] > 0.2 * counts["evaluations"]
    assert counts["miss_hits"] > 0.2 * counts["misses"]


@pytest.mark.parametrize("shape,precision", [("rock_40.obj", "double"), ("rock_40.obj", "mixed"),
                                             ("rock_70.obj", "double")])
@pytest.mark.parametrize("start", ["contact", "near"])
def test_the_parting_search_with_the_cache_gives_the_same_bits(driver, shape, precision, start):
    """Pairs evaluated as the pair style does those not touching at their last evaluation (the parting search, also
    where a contact's certificate does not take the replay): the cache's results are the search's, and every volume
    is the same bits as with the former filters, while the search parts some of the walks' near misses."""
    counts, errors = run(driver, shape, precision, start=start, apart=True)
    print(f"\n{shape} {precision}, from {start}, parting search: {counts}")
    assert counts["differ"] == 0, errors
    assert counts["volumes_differ"] == 0
    if start == "near":
        assert counts["searched"] > 0.05 * counts["evaluations"]


@pytest.mark.parametrize("shape", ["rock_1000.obj", "cube.stl"])
def test_pairs_the_cache_does_not_take_are_unchanged(driver, shape):
    """rock_1000's contacts cross more edges than a cache holds, the cube's take the convex path: no hits."""
    counts, errors = run(driver, shape, "double", sequences=6, steps=40)
    assert counts["differ"] == 0, errors
    assert counts["hits"] == 0


def test_an_inflated_certificate_is_caught(tmp_path):
    binary = build_driver(tmp_path, ["-DPOLY_CACHE_MARGIN_SCALE=1000"])
    counts, _ = run(binary, "rock_40.obj", "double")
    assert counts["differ"] > 0


def test_the_watched_pairs_are_decided_again(tmp_path):
    """A certificate reaches 8 caps and leaves the pairs of smaller margins to be decided again as B moves: a
    build that skips those decisions must give other results."""
    binary = build_driver(tmp_path, ["-DPOLY_CACHE_WATCH_CHECKS=0"])
    differ = sum(run(binary, shape, "double", start=start)[0]["differ"]
                 for shape in ("rock_40.obj", "rock_70.obj") for start in ("contact", "near"))
    assert differ > 0


def test_the_watched_pairs_rechecks_are_checked(tmp_path):
    """Watched pairs decided again at a pose keep their decisions while B moves by less than their margins from there
    (cache_recheck): a build with those margins made 1000 times as long must give other results in the walks."""
    binary = build_driver(tmp_path, ["-DPOLY_CACHE_RECHECK_SCALE=1000"])
    differ = sum(run(binary, shape, "double", start=start)[0]["differ"]
                 for shape in ("rock_40.obj", "rock_70.obj") for start in ("contact", "near"))
    assert differ > 0


RECHECK_CASES = [("rock_40.obj", 1, "rock_70.obj", 0.5, "double", "contact"),
                 ("rock_40.obj", 1, "rock_40.obj", 1, "double", "near"),
                 ("rock_70.obj", 1, "rock_20.obj", 0.2, "single", "contact"),
                 ("rock_40.obj", 1, "rock_40.obj", 1, "single", "contact")]


def test_poses_at_the_edge_of_the_rechecks_give_the_search_bits(tmp_path):
    """B moved past a watched pair's margin, the reached pairs rechecked there, then moved from that pose by 0.5 to
    0.999 of the rechecks' least margin (tests/unit/crossing_cache_edge.c's `recheck`): every result the search's,
    most of them with the decisions spared; with the rechecks' margins twice as long the same poses differ."""
    binary = build_driver(tmp_path, name="crossing_cache_edge")
    inflated = build_driver(tmp_path, ["-DPOLY_CACHE_RECHECK_SCALE=2"], name="crossing_cache_edge")
    differ_inflated = 0
    for a, scale_a, b, scale_b, precision, start in RECHECK_CASES:
        command = [os.path.join(SHAPES, a), str(scale_a), os.path.join(SHAPES, b), str(scale_b), "200", "20",
                   precision] + (["near"] if start == "near" else []) + ["recheck"]
        counts, errors = run_words([binary] + command)
        print(f"\n{a} {b} {precision} {start}: {counts}")
        assert counts["differ"] == 0, errors
        assert counts["rechecked"] > 1000 and counts["spared"] > 0.3 * counts["tested"]
        differ_inflated += run_words([inflated] + command)[0]["differ"]
    assert differ_inflated > 0


def run_words(command):
    out = subprocess.run(command, capture_output=True, text=True, check=True)
    words = out.stdout.split()
    return dict(zip(words[0::2], (int(w) for w in words[1::2]))), out.stderr


# Pairs of shapes and sizes (A file, scale, B file, scale, precision, start) for the edge of the certificates.
EDGE_CASES = [("rock_40.obj", 1, "rock_70.obj", 0.5, "double", "contact"),
              ("rock_40.obj", 1, "rock_40.obj", 1, "double", "near"),
              ("rock_70.obj", 1, "rock_20.obj", 0.2, "single", "contact"),
              ("rock_40.obj", 1, "rock_70.obj", 2, "double", "near"),
              ("rock_40.obj", 1, "rock_40.obj", 1, "single", "contact")]


def run_edge(binary, case):
    a, scale_a, b, scale_b, precision, start = case
    return run_words([binary, os.path.join(SHAPES, a), str(scale_a), os.path.join(SHAPES, b), str(scale_b), "300",
                      "40", precision] + (["near"] if start == "near" else []))


def test_poses_at_the_edge_of_the_certificates_give_the_search_bits(tmp_path):
    """B moved by 0.5 to 0.999 of the certificate's margin (a turn and a shift in random directions), for shapes of
    other sizes too: every result the search's. With the certificates inflated twice the same poses differ, so the
    margins are not loose by that much and the comparison can tell."""
    binary = build_driver(tmp_path, name="crossing_cache_edge")
    inflated = build_driver(tmp_path, ["-DPOLY_CACHE_MARGIN_SCALE=2"], name="crossing_cache_edge")
    differ_inflated = 0
    for case in EDGE_CASES:
        counts, errors = run_edge(binary, case)
        print(f"\n{case}: {counts}")
        assert counts["differ"] == 0, errors
        assert counts["hits"] > 0.3 * counts["tested"]
        differ_inflated += run_edge(inflated, case)[0]["differ"]
    assert differ_inflated > 0


def test_a_body_thinner_than_the_reach_does_not_pass_through_unseen(tmp_path):
    """A tiny tetrahedron by each face of a rock, certified just outside it and just inside, then moved through the
    face in one evaluation: every crossing is again what it was (none), but B has gone in or out. The cached
    evaluation must give the search's volume; a build without the outside vertices that watched pairs need gets it
    wrong."""
    binary = build_driver(tmp_path, name="crossing_cache_thin")
    unchecked = build_driver(tmp_path, ["-DPOLY_CACHE_OUTSIDE_CHECKS=0"], name="crossing_cache_thin")
    command = [os.path.join(SHAPES, "rock_70.obj"), os.path.join(SHAPES, "tetrahedron.obj"), "1e-3"]
    for build, expect_wrong in ((binary, False), (unchecked, True)):
        out = subprocess.run([build] + command, capture_output=True, text=True, check=True).stdout
        print("\n" + out)
        rows = {line.split()[0]: dict(zip(line.split()[1::2], (int(w) for w in line.split()[2::2])))
                for line in out.splitlines()}
        assert rows["into"]["tried"] > 50 and rows["out"]["tried"] > 50
        wrong = rows["into"]["wrong"] + rows["out"]["wrong"]
        assert (wrong > 0) if expect_wrong else (wrong == 0)


def pile_deck(cache):
    text = open(os.path.join(ROOT, "examples", "bench_multisphere", "in.pile_poly")).read()
    assert "pair_style      polyhedral/volumetric\n" in text
    text = text.replace("pair_style      polyhedral/volumetric\n",
                        f"pair_style      polyhedral/volumetric crossing_cache {cache}\n")
    text = text.replace("pair_coeff      * *\n", "pair_coeff      * *\ncompute ev all pair/polyhedral/local\n")
    return text + ("thermo_style custom step atoms c_ev[6] c_ev[8] c_ev[9] c_ev[10]\n"
                   "thermo_modify format float %.15g\nrun 1\n")


@pytest.mark.parametrize("nprocs", [1, 2])
def test_a_pile_of_rocks_runs_the_same_with_and_without_the_cache(run_deck, tmp_path, nprocs):
    variables = {"SHAPE": os.path.join(SHAPES, "rock_40.obj"), "N": 80, "settle": 25000, "steps": 10000,
                 "every": 1000, "ZFILL": 0.08}
    outputs, counts = {}, {}
    for cache in ("on", "off"):
        result = run_deck(pile_deck(cache), nprocs=nprocs, variables=variables, workdir=tmp_path / cache)
        assert result.returncode == 0, result.output[-3000:]
        # The deck's own thermo columns (kinetic energy, extent of the centres), then the counts' table.
        outputs[cache] = result.thermo("Step", "v_ke", "v_xmin", "v_xmax", "v_ymin", "v_ymax", "v_zmin", "v_zmax")
        table = result.thermo("Step", "c_ev[6]", "c_ev[8]", "c_ev[9]", "c_ev[10]")
        counts[cache] = tuple(table[column][-1] for column in ("c_ev[6]", "c_ev[9]", "c_ev[8]", "c_ev[10]"))
    print(f"\n{nprocs} rank(s): contacts, those from the cache, near misses, those from the cache: "
          f"on {counts['on']}, off {counts['off']}")
    assert len(outputs["on"]["Step"]) > 10
    assert outputs["on"] == outputs["off"]
    assert counts["off"][1] == 0 and counts["off"][3] == 0
    assert counts["on"][0] == counts["off"][0]
    assert counts["on"][2] == counts["off"][2]
    # Near misses at rest keep their empty search too.
    assert counts["on"][3] > 0.15 * counts["on"][2]
    # The pile comes to rest in the last third of the run: a good part of its contacts from the cache (29 % here).
    assert counts["on"][1] > 0.15 * counts["on"][0]
