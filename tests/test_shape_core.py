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
SOURCES = [os.path.join(ROOT, "src", "poly_shape.c"), os.path.join(ROOT, "src", "poly_mesh_read.c")]
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
