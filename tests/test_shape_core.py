"""Shape core: mesh input, validation, mass properties (src/poly_shape.c,
src/poly_mesh_read.c) and the reference shape generators (tools/).

The C unit tests live in tests/unit/test_shape.c, one program whose first
argument picks a case; each case is one parametrized test here. Runs with
Debian's python3 and gcc only:  /usr/bin/python3 -m pytest tests/test_shape_core.py -q
"""
import filecmp
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCES = [os.path.join(ROOT, "src", name) for name in ("poly_shape.c", "poly_mesh_read.c", "poly_convex.c")]
TEST_SOURCE = os.path.join(ROOT, "tests", "unit", "test_shape.c")
CFLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I" + os.path.join(ROOT, "src")]

CASES = ["cube", "tetrahedron", "box", "box_rotated", "icospheres", "schoenhardt", "rocks", "bad_meshes",
         "stl_ascii_binary", "obj_forms", "off_forms", "parse_errors", "weld", "eigen", "free_safety",
         "stl_solid_header", "mutations", "degenerate_axes"]
# Cases that exercise error paths and odd input: rerun under AddressSanitizer/UBSan.
SANITIZED_CASES = ["bad_meshes", "parse_errors", "obj_forms", "off_forms", "free_safety", "mutations", "rocks"]


def compile_test(output, extra_flags):
    command = ["gcc"] + CFLAGS + extra_flags + SOURCES + [TEST_SOURCE, "-lm", "-o", output]
    result = subprocess.run(command, capture_output=True, text=True)
    assert result.returncode == 0, "compiling the shape unit tests failed:\n" + " ".join(command) + "\n" + result.stderr
    return output


@pytest.fixture(scope="session")
def test_binary(tmp_path_factory):
    return compile_test(str(tmp_path_factory.mktemp("shape_unit") / "test_shape"), ["-O2"])


@pytest.fixture(scope="session")
def sanitized_binary(tmp_path_factory):
    directory = tmp_path_factory.mktemp("shape_asan")
    flags = ["-O1", "-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=undefined"]
    probe = directory / "probe.c"
    probe.write_text("#include <stdlib.h>\nint main(void) { free(malloc(1)); return 0; }\n")
    built = subprocess.run(["gcc"] + flags + [str(probe), "-o", str(directory / "probe")], capture_output=True)
    if built.returncode != 0 or subprocess.run([str(directory / "probe")], capture_output=True).returncode != 0:
        pytest.skip("gcc cannot build or run AddressSanitizer programs here")
    return compile_test(str(directory / "test_shape"), flags)


def run_case(binary, case, tmp_path, env=None):
    result = subprocess.run([binary, case, ROOT, str(tmp_path)], capture_output=True, text=True, env=env)
    failed = [line for line in result.stdout.splitlines() if line.startswith("FAIL")]
    assert result.returncode == 0 and not failed, (
        f"case {case}: exit {result.returncode}\n" + "\n".join(failed) + "\n--- output ---\n" + result.stdout
        + result.stderr)


def test_case_list_matches(test_binary):
    listed = subprocess.run([test_binary, "--list"], capture_output=True, text=True, check=True).stdout.split()
    assert listed == CASES


@pytest.mark.parametrize("case", CASES)
def test_shape_case(test_binary, case, tmp_path):
    run_case(test_binary, case, tmp_path)


@pytest.mark.parametrize("case", SANITIZED_CASES)
def test_shape_case_sanitized(sanitized_binary, case, tmp_path):
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0", UBSAN_OPTIONS="print_stacktrace=1")
    run_case(sanitized_binary, case, tmp_path, env)


def test_sources_compile_as_cxx():
    """The C++ glue includes the header; the C sources stay valid C++ as well."""
    for source in SOURCES:
        result = subprocess.run(["g++", "-x", "c++", "-fsyntax-only", "-Wall", "-Wextra", "-I" + os.path.join(ROOT, "src"),
                                 source], capture_output=True, text=True)
        assert result.returncode == 0, result.stderr


def generated_matches_committed(script, committed, tmp_path):
    result = subprocess.run([sys.executable, os.path.join(ROOT, "tools", script), str(tmp_path)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    generated = sorted(os.listdir(tmp_path))
    assert generated == sorted(name for name in os.listdir(committed) if not name.startswith(".")), \
        f"{script} writes a different set of files than {committed} holds"
    different = [name for name in generated
                 if not filecmp.cmp(os.path.join(committed, name), os.path.join(tmp_path, name), shallow=False)]
    assert different == [], f"regenerated files differ from the committed ones: {different}"


def test_make_shapes_is_reproducible(tmp_path):
    generated_matches_committed("make_shapes.py", os.path.join(ROOT, "examples", "shapes"), tmp_path)


def test_make_bad_meshes_is_reproducible(tmp_path):
    generated_matches_committed("make_bad_meshes.py", os.path.join(ROOT, "tests", "data", "bad"), tmp_path)


# ------------------------------------------------------------------ bad shapes that used to pass

LOAD_DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include "poly_shape.h"
int main(int argc, char **argv)
{
  char message[1024];
  poly_shape shape;
  poly_status status = poly_shape_load(argv[1], argc > 2 ? atof(argv[2]) : 1.0, &shape, message, sizeof message);
  printf("%d\n%s\n", (int)status, status == POLY_OK ? "ok" : message);
  if (status == POLY_OK) printf("%.17g %.17g %.17g %.17g\n", shape.volume, shape.principal_moments[0],
                                shape.principal_moments[1], shape.principal_moments[2]);
  poly_shape_free(&shape);
  return 0;
}
"""
POLY_OK, POLY_ERROR_VOLUME, POLY_ERROR_SELF_INTERSECTION, POLY_ERROR_MASS = 0, 9, 11, 12

CUBE_VERTICES = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_TRIANGLES = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
                  (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]


def write_off(path, vertices, triangles):
    lines = ["OFF", f"{len(vertices)} {len(triangles)} 0"]
    lines += [" ".join(repr(float(c)) for c in v) for v in vertices]
    lines += ["3 " + " ".join(str(i) for i in t) for t in triangles]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


@pytest.fixture(scope="session")
def load_driver(tmp_path_factory):
    directory = tmp_path_factory.mktemp("shape_load")
    source = directory / "load.c"
    source.write_text(LOAD_DRIVER)
    return compile_test_program(str(directory / "load"), str(source))


def compile_test_program(output, source):
    command = ["gcc"] + CFLAGS + ["-O2"] + SOURCES + [source, "-lm", "-o", output]
    result = subprocess.run(command, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return output


def load(driver, path, scale=1.0):
    out = subprocess.run([driver, path, repr(scale)], capture_output=True, text=True, check=True).stdout.splitlines()
    return int(out[0]), out[1], ([float(x) for x in out[2].split()] if len(out) > 2 else None)


def cube_with_corner_at(corner):
    vertices = list(CUBE_VERTICES)
    vertices[6] = corner
    return vertices


@pytest.mark.parametrize("name", sorted(f for f in os.listdir(os.path.join(ROOT, "examples", "shapes"))
                                        if f.endswith((".stl", ".obj", ".off"))))
def test_example_shapes_do_not_intersect_themselves(load_driver, name):
    status, message, _ = load(load_driver, os.path.join(ROOT, "examples", "shapes", name))
    assert status == POLY_OK, message


@pytest.mark.parametrize("corner", [(0.3, 0.4, -0.5),   # pulled through the opposite face z = 0
                                    (0.3, 0.4, 0.0),    # onto it: touching counts, and triangle 1-2-6 now
                                                        # lies flat on the bottom face (coplanar overlap)
                                    (-0.5, 0.5, 0.5),   # through the side face x = 0
                                    (0.5, -0.5, 0.5)])  # through the side face y = 0
def test_cube_with_a_corner_pulled_through_is_rejected(load_driver, tmp_path, corner):
    path = write_off(tmp_path / "pulled.off", cube_with_corner_at(corner), CUBE_TRIANGLES)
    status, message, _ = load(load_driver, path)
    assert status == POLY_ERROR_SELF_INTERSECTION, message
    assert "pulled.off" in message and "intersects itself" in message and "triangles " in message, message


def test_cube_with_a_corner_pushed_in_but_not_through_is_accepted(load_driver, tmp_path):
    path = write_off(tmp_path / "dented.off", cube_with_corner_at((0.6, 0.6, 0.6)), CUBE_TRIANGLES)
    status, message, mass = load(load_driver, path)
    assert status == POLY_OK, message
    assert all(m > 0 for m in mass[1:]) and mass[1] + mass[2] >= mass[3]


@pytest.mark.parametrize("scale, expected", [(1e-70, "principal moment is not positive"),
                                             (1e-110, "out of the range"), (1e-300, "out of the range"),
                                             (1e200, "out of the range"), (1e70, "not finite")])
def test_extreme_scale_is_rejected(load_driver, scale, expected):
    """Moments scale as scale^5: they underflow to 0 or overflow long before the coordinates do."""
    status, message, mass = load(load_driver, os.path.join(ROOT, "examples", "shapes", "rock_70.obj"), scale)
    assert status == POLY_ERROR_MASS, (message, mass)
    assert "rock_70.obj" in message and expected in message, message


def test_moderate_scales_still_load(load_driver):
    for scale in (1e-6, 1e-3, 1e3, 1e6):
        status, message, mass = load(load_driver, os.path.join(ROOT, "examples", "shapes", "rock_70.obj"), scale)
        assert status == POLY_OK, (scale, message)
