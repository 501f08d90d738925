"""Deterministic mutation fuzzing of the shape readers (poly_shape_load: STL ascii/binary, OBJ, OFF).

    python3 tools/fuzz_shapes.py [--count N] [--seed S] [--keep DIR]

Mutates the shapes shipped in examples/shapes (byte flips, truncations, duplicated, deleted and swapped
lines, perturbed numbers, huge/NaN/inf values, swapped or out-of-range indices, inflated counts), writes
them to a directory and loads each with poly_shape_load in a driver built with
-fsanitize=address,undefined (tools/fuzz_shapes_driver.c, compiled into build-asan/fuzz/). Every file must
either load (POLY_OK with finite, positive volume, bounding radius and mass properties) or give an error
with a message; a crash, a hang (5 s per file), or a sanitizer report is a bug. tests/test_fuzz_readers.py
runs it in the suite; a failing file is kept and named in the report, so it is its own reproducer:

    build-asan/fuzz/fuzz_shapes_driver FILE
"""
import argparse
import os
import pathlib
import random
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHAPES = ROOT / "examples" / "shapes"
DRIVER_SOURCE = ROOT / "tools" / "fuzz_shapes_driver.c"
DRIVER = ROOT / "build-asan" / "fuzz" / "fuzz_shapes_driver"
SANITIZE = ["-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=undefined"]
SANITIZER_ENV = {
    # allocator_may_return_null: a file that asks for 10^12 vertices must get NULL from malloc (and the
    # reader's out-of-memory error), not an ASan abort on the allocation size.
    "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:allocator_may_return_null=1:abort_on_error=0",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1",
}
REPORT = re.compile(r"ERROR: AddressSanitizer|ERROR: LeakSanitizer|runtime error:|"
                    r"SUMMARY: (AddressSanitizer|UndefinedBehaviorSanitizer)")
# Keep big inputs out: the seeds are the shipped shapes up to this size (bytes).
MAX_SEED_SIZE = 60000

NUMBER = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
SPECIAL_NUMBERS = [b"nan", b"-nan", b"inf", b"-inf", b"1e308", b"-1e308", b"1e309", b"1e-320", b"0", b"-0",
                   b"2147483647", b"2147483648", b"-2147483648", b"4294967296", b"99999999999999999999",
                   b"-1", b"1e1000000", b"0x10", b"1.#INF", b"", b"1e", b"--1", b"3.", b"NaN(1)"]


def build_driver(cc="gcc"):
    """Compiles the driver with the readers (src/poly_mesh_read.c, src/poly_shape.c) under the sanitizers."""
    DRIVER.parent.mkdir(parents=True, exist_ok=True)
    sources = [DRIVER_SOURCE, ROOT / "src" / "poly_mesh_read.c", ROOT / "src" / "poly_shape.c", ROOT / "src" / "poly_convex.c"]
    if DRIVER.exists() and all(DRIVER.stat().st_mtime > s.stat().st_mtime for s in sources + [ROOT / "src" / "poly_shape.h"]):
        return DRIVER
    command = [cc, "-std=c11", "-O1", "-g", *SANITIZE, "-Isrc", *map(str, sources), "-lm", "-o", str(DRIVER)]
    subprocess.run(command, cwd=ROOT, check=True, capture_output=True, text=True)
    return DRIVER


def seeds():
    return [p for p in sorted(SHAPES.iterdir())
            if p.suffix.lower() in (".stl", ".obj", ".off") and p.stat().st_size <= MAX_SEED_SIZE]


def _lines(data):
    return data.split(b"\n")


def mutate(data, rng):
    """One to three random mutations of `data` (bytes)."""
    for _ in range(rng.choice((1, 1, 1, 2, 3))):
        data = rng.choice(MUTATIONS)(data, rng)
    return data


def byte_flip(data, rng):
    if not data:
        return data
    data = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        i = rng.randrange(len(data))
        data[i] ^= 1 << rng.randrange(8) if rng.random() < 0.7 else rng.randrange(256)
    return bytes(data)


def truncate(data, rng):
    return data[:rng.randrange(len(data) + 1)]


def duplicate_line(data, rng):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    lines[i:i] = [lines[i]] * rng.randint(1, 3)
    return b"\n".join(lines)


def delete_line(data, rng):
    lines = _lines(data)
    for _ in range(rng.randint(1, 3)):
        if lines:
            del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def swap_lines(data, rng):
    lines = _lines(data)
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def _numbers(data):
    return list(NUMBER.finditer(data))


def _replace_number(data, rng, make):
    numbers = _numbers(data)
    if not numbers:
        return data
    for _ in range(rng.randint(1, 4)):
        numbers = _numbers(data)
        if not numbers:
            break
        m = rng.choice(numbers)
        data = data[:m.start()] + make(m.group(0), rng) + data[m.end():]
    return data


def perturb_number(data, rng):
    def make(text, rng):
        try:
            value = float(text)
        except ValueError:
            return text
        if rng.random() < 0.5:
            value += rng.gauss(0.0, 1e-9 if rng.random() < 0.5 else 1.0)
        else:
            value *= rng.choice((-1.0, 0.0, 0.5, 2.0, 1e-12, 1e12))
        if re.fullmatch(rb"[-+]?\d+", text) and rng.random() < 0.7:
            return str(int(value)).encode()
        return repr(value).encode()
    return _replace_number(data, rng, make)


def special_number(data, rng):
    return _replace_number(data, rng, lambda text, rng: rng.choice(SPECIAL_NUMBERS))


def index_shuffle(data, rng):
    """OBJ faces / OFF polygons: swap two indices of a face, or set one out of range / negative / zero."""
    lines = _lines(data)
    faces = [i for i, line in enumerate(lines)
             if line.startswith(b"f ") or re.match(rb"^\s*[3-9]\s+\d+\s+\d+\s+\d+", line)]
    if not faces:
        return perturb_number(data, rng)
    i = rng.choice(faces)
    words = lines[i].split()
    if len(words) < 3:
        return data
    choice = rng.random()
    if choice < 0.4:
        a, b = rng.sample(range(1, len(words)), 2)
        words[a], words[b] = words[b], words[a]
    elif choice < 0.7:
        words[rng.randrange(1, len(words))] = rng.choice((b"0", b"-1", b"-999999", b"999999", b"2147483647",
                                                          b"-2147483648", b"1/2/3", b"1//", b"/", b"x"))
    elif choice < 0.85:
        j = rng.randrange(1, len(words))
        words[j] = words[rng.randrange(1, len(words))]  # repeated vertex
    else:
        words = words + words[1:] if rng.random() < 0.5 else words[:rng.randint(1, 3)]
    lines[i] = b" ".join(words)
    return b"\n".join(lines)


def header_count(data, rng):
    """Inflate or break counts: the OFF header line, binary STL's triangle count."""
    if len(data) >= 84 and b"\0" in data[80:200]:  # binary STL
        value = rng.choice((0, 1, 2 ** 31 - 1, 2 ** 31, 2 ** 32 - 1, (len(data) - 84) // 50 + 1,
                            (len(data) - 84) // 50 - 1, rng.randrange(2 ** 32)))
        return data[:80] + value.to_bytes(4, "little") + data[84:]
    lines = _lines(data)
    for i, line in enumerate(lines):
        if re.match(rb"^\s*\d+\s+\d+(\s+\d+)?\s*$", line):
            words = line.split()
            k = rng.randrange(len(words))
            words[k] = rng.choice((b"0", b"-1", b"2147483647", b"4294967297", b"1000000000", b"99999999999999",
                                   str(int(words[k]) + rng.choice((-1, 1, 1000))).encode()))
            lines[i] = b" ".join(words)
            return b"\n".join(lines)
    return special_number(data, rng)


def insert_garbage(data, rng):
    i = rng.randrange(len(data) + 1)
    junk = rng.choice((b"\0", b"\r", b"\r\n", b"\t", b" " * 5000, b"#", b"\xff\xfe", b"v 1 2\n", b"f 1\n",
                       b"vertex 1 2 3\n", b"endloop\n", b"endsolid\n", b"solid x\n", b"OFF\n", b"3 0 1\n",
                       b"f 1 2 3 4 5 6 7 8 9 10 11 12\n", bytes(rng.randrange(256) for _ in range(16)),
                       b"x" * 70000))
    return data[:i] + junk + data[i:]


def cross_format(data, rng):
    """Content of one format under another extension is made by the caller; here: all CR line ends,
    no final newline, or a doubled file."""
    return rng.choice((data.replace(b"\n", b"\r"), data.rstrip(b"\n"), data + data, b"", data[:1]))


MUTATIONS = [byte_flip, byte_flip, truncate, duplicate_line, delete_line, swap_lines, perturb_number,
             perturb_number, special_number, special_number, index_shuffle, index_shuffle, header_count,
             insert_garbage, cross_format]


def generate(directory, count, seed=20261123):
    """Writes `count` mutated files into `directory`; returns their paths. Deterministic for a seed."""
    rng = random.Random(seed)
    sources = [(p, p.read_bytes()) for p in seeds()]
    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for n in range(count):
        source, data = sources[n % len(sources)]
        suffix = source.suffix
        if rng.random() < 0.03:  # another format's content under this extension
            suffix = rng.choice((".stl", ".obj", ".off", ".STL"))
        path = directory / f"{n:05d}_{source.stem}{suffix}"
        path.write_bytes(mutate(data, rng))
        paths.append(path)
    return paths


def run(driver, paths, timeout=5.0, scale=1.0):
    """Loads every file; returns (counts {"ok", "error"}, failures, nonphysical), each a list of
    (path, reason, output). failures: crashes, hangs, sanitizer reports, non-finite results, errors without
    a message; nonphysical: loaded shapes whose principal moments no solid has (a self-intersecting surface).
    After a crash the driver is restarted behind the failing file, so one run reports every failing file."""
    env = dict(os.environ, **SANITIZER_ENV)
    counts = {"ok": 0, "error": 0}
    failures = []
    nonphysical = []
    remaining = list(paths)
    while remaining:
        with tempfile.NamedTemporaryFile("w", suffix=".list", delete=False) as listing:
            listing.write("\n".join(str(p) for p in remaining) + "\n")
        try:
            result = subprocess.run([str(driver), "--timeout", str(timeout), "--scale", repr(scale),
                                     "--list", listing.name], capture_output=True, text=True, env=env,
                                    errors="backslashreplace", timeout=60 + timeout * 4)
            output = result.stdout + result.stderr
        except subprocess.TimeoutExpired as expired:
            output = (expired.stdout or b"").decode(errors="replace") if isinstance(expired.stdout, bytes) \
                else (expired.stdout or "")
            result = None
        finally:
            os.unlink(listing.name)
        done = 0
        current = None
        for line in result.stdout.splitlines() if result else output.splitlines():
            if line.startswith("FILE "):
                current = line[5:]
            elif line.startswith("OK ") or line.startswith("ERROR "):
                counts["ok" if line.startswith("OK ") else "error"] += 1
                done += 1
                current = None
            elif line.startswith("BAD "):
                failures.append((current, line[4:], ""))
                done += 1
                current = None
            elif line.startswith("NONPHYSICAL "):
                nonphysical.append((current, line[12:], ""))
                counts["ok"] += 1
                done += 1
                current = None
        if result is not None and result.returncode == 0 and done == len(remaining) and not REPORT.search(output):
            break
        # the driver stopped at `current` (crash, sanitizer report, timeout) or the output shows a report
        if current is None:
            failures.append((None, f"driver exit {result.returncode if result else 'timeout'} after all files",
                             output[-4000:]))
            break
        report = REPORT.search(output)
        reason = ("sanitizer report" if report else
                  "hang (timeout)" if "TIMEOUT" in output else f"crash (exit {result.returncode if result else '?'})")
        failures.append((current, reason, output[report.start():report.start() + 4000] if report else output[-2000:]))
        index = [str(p) for p in remaining].index(current)
        remaining = remaining[index + 1:]
    return counts, failures, nonphysical


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=4000)
    parser.add_argument("--seed", type=int, default=20261123)
    parser.add_argument("--keep", help="write the mutated files here (default: a temporary directory)")
    args = parser.parse_args(argv)
    driver = build_driver()
    directory = args.keep or tempfile.mkdtemp(prefix="fuzz_shapes_")
    paths = generate(directory, args.count, args.seed)
    counts, failures, nonphysical = run(driver, paths)
    print(f"{len(paths)} files in {directory}: {counts['ok']} loaded, {counts['error']} rejected with a message, "
          f"{len(failures)} failures, {len(nonphysical)} loaded with non-physical principal moments")
    for path, reason, output in failures + nonphysical:
        print(f"\n{path}: {reason}\n{output}")
    return 1 if failures or nonphysical else 0


if __name__ == "__main__":
    sys.exit(main())
