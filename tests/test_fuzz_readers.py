"""Mutation fuzzing of the shape readers (issue 13 part 4): poly_shape_load on thousands of mutated copies
of the shapes in examples/shapes, in a driver built with -fsanitize=address,undefined (tools/fuzz_shapes.py,
tools/fuzz_shapes_driver.c). Deterministic: fixed seed, files in pytest's tmp dir.

Each file must either load (POLY_OK, every quantity finite, volume, bounding radius and moments positive)
or be rejected with an error message; a crash, a hang (5 s per file), a sanitizer report (ASan, UBSan,
LeakSanitizer) or an error without a message fails test_mutated_files_load_or_fail_cleanly.
test_mutated_files_that_load_have_physical_moments also asks that a loaded shape's principal moments be
ones a solid can have (positive, I0 + I1 >= I2): a closed, consistently oriented but self-intersecting
surface (a permutation of an OBJ's vertex lines is enough) breaks that, and poly_shape_build does not catch it.
Each failure names its file, which reproduces it:  build-asan/fuzz/fuzz_shapes_driver FILE
"""
import pathlib
import sys

import pytest

from conftest import BAD_MESHES, ROOT, SHAPES

sys.path.insert(0, str(ROOT / "tools"))
import fuzz_shapes  # noqa: E402

COUNT = 6000
SEED = 20261123


@pytest.fixture(scope="session")
def driver():
    return fuzz_shapes.build_driver()


@pytest.fixture(scope="session")
def fuzz_run(driver, tmp_path_factory):
    paths = fuzz_shapes.generate(tmp_path_factory.mktemp("fuzz_shapes"), COUNT, SEED)
    counts, failures, nonphysical = fuzz_shapes.run(driver, paths)
    print(f"\n{COUNT} mutated files: {counts['ok']} loaded, {counts['error']} rejected with a message, "
          f"{len(failures)} failures, {len(nonphysical)} loaded with non-physical moments")
    return paths, counts, failures, nonphysical


def describe(found, limit=10):
    lines = []
    for path, reason, output in found[:limit]:
        lines.append(f"{path}: {reason}")
        if path and pathlib.Path(path).exists() and pathlib.Path(path).stat().st_size < 4000:
            lines.append("    content: " + repr(pathlib.Path(path).read_bytes()[:600]))
        if output:
            lines.append(output[:3000])
    return "\n".join(lines) + (f"\n... and {len(found) - limit} more" if len(found) > limit else "")


def test_shipped_and_bad_shapes_under_sanitizers(driver):
    """The shipped shapes load with physical moments; tests/data/bad's meshes give errors with messages,
    except inward.off, which loads turned inside out."""
    shipped = sorted(p for p in SHAPES.iterdir() if p.suffix.lower() in (".stl", ".obj", ".off"))
    counts, failures, nonphysical = fuzz_shapes.run(driver, shipped)
    assert not failures and not nonphysical, describe(failures + nonphysical)
    assert counts == {"ok": len(shipped), "error": 0}
    bad = sorted(BAD_MESHES.iterdir())
    counts, failures, nonphysical = fuzz_shapes.run(driver, bad)
    assert not failures and not nonphysical, describe(failures + nonphysical)
    assert counts == {"ok": 1, "error": len(bad) - 1}


def test_mutated_files_load_or_fail_cleanly(fuzz_run):
    paths, counts, failures, _ = fuzz_run
    assert not failures, describe(failures)
    assert counts["ok"] + counts["error"] == len(paths)
    # the mutations reach past the parsers: some files still load, most are rejected
    assert counts["ok"] > len(paths) // 50 and counts["error"] > len(paths) // 2, counts


def test_mutated_files_that_load_have_physical_moments(fuzz_run):
    """Fails while poly_shape_build accepts self-intersecting surfaces with negative principal moments
    (doc/fix_particletemplate_polyhedron.md: "Self-intersecting meshes are not detected"); e.g.
    examples/shapes/rock_10.obj with its lines 4 (a vertex) and 14 (a face) swapped loads as volume 0.0132,
    bounding radius 6.99, principal moments/density -0.516 -0.512 0.00301."""
    _, _, _, nonphysical = fuzz_run
    assert not nonphysical, describe(nonphysical)
