"""The crossing cache of the general path (poly_crossing_cache; src/poly_overlap_cache_impl.h): a contact whose
crossings are certified unchanged since its last search is evaluated from them, by the same functions in the same
order, so every result bit must be the search's.

- tests/unit/crossing_cache.c moves pairs in contact step by step (random walks from 1e-7 to 1e-3 of the size a
  step, with jumps) and evaluates each step with a cache kept from step to step and without one: every result
  field the same bits, in double, single and mixed precision, with many steps taken from the cache. Built with
  its certificates inflated a thousandfold (POLY_CACHE_MARGIN_SCALE), the same driver must find differences: the
  comparison can fail.
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


def build_driver(directory, defines=()):
    if not shutil.which("gcc"):
        pytest.skip("skipped: no C compiler (a GPU host running a prebuilt tree)")
    binary = str(directory / "crossing_cache")
    sources = [os.path.join(ROOT, "tests", "unit", "crossing_cache.c")] + [
        os.path.join(ROOT, "src", name) for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
    subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", *defines,
                    "-I" + os.path.join(ROOT, "src")] + sources + ["-lm", "-o", binary], check=True)
    return binary


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    return build_driver(tmp_path_factory.mktemp("cache"))


def run(binary, shape, precision, sequences=40, steps=200, start="contact"):
    out = subprocess.run([binary, os.path.join(SHAPES, shape), str(sequences), str(steps), precision]
                         + (["near"] if start == "near" else []), capture_output=True, text=True, check=True)
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
