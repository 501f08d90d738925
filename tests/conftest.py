"""Shared fixtures: build the package once, run LIGGGHTS decks with liggghts-poly."""
import os
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
LAUNCHER = ROOT / "build" / "bin" / "liggghts-poly"
SHAPES = ROOT / "examples" / "shapes"
BAD_MESHES = ROOT / "tests" / "data" / "bad"

# OpenMPI refuses root without these, and a 2-core CI machine needs oversubscription for 4 ranks.
MPI_ENV = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    "OMPI_MCA_btl_vader_single_copy_mechanism": "none",
}


@pytest.fixture(scope="session")
def launcher():
    """Builds (incrementally) and returns the launcher path. POLY_PREBUILT=1 uses build/ as it
    is (a GPU host that got build/ and tools/bundle_runtime.sh's runtime, but no compilers)."""
    if os.environ.get("POLY_PREBUILT") != "1":
        result = subprocess.run(["make", "-s", "-j2"], cwd=ROOT, capture_output=True, text=True)
        assert result.returncode == 0, result.stdout + result.stderr
    return LAUNCHER


class DeckResult:
    def __init__(self, returncode, output, workdir):
        self.returncode = returncode
        self.output = output
        self.workdir = workdir

    def error_lines(self):
        return [line for line in self.output.splitlines() if line.startswith("ERROR")]

    def warning_lines(self):
        return [line for line in self.output.splitlines() if line.startswith("WARNING")]

    def thermo(self, *columns):
        """Rows of the thermo table whose header starts with 'Step'; returns {column: [values]}."""
        table = {}
        header = None
        for line in self.output.splitlines():
            words = line.split()
            if words and words[0] == "Step":
                header = words
                continue
            if header and line.startswith("WARNING"):  # said mid-run: the table goes on after it
                continue
            if header and len(words) == len(header) and re.match(r"^-?\d+$", words[0]):
                for name, value in zip(header, words):
                    table.setdefault(name, []).append(float(value))
            elif header and not (words and re.match(r"^-?\d+$", words[0])):
                header = None
        # LIGGGHTS prints a compute column c_NAME as NAME.
        return {c: table[c] if c in table else table[c[2:]] for c in columns} if columns else table


@pytest.fixture
def run_deck(launcher, tmp_path):
    """run_deck(text, nprocs=1, variables=None, workdir=None) -> DeckResult."""

    def run(text, nprocs=1, variables=None, workdir=None, timeout=600):
        workdir = pathlib.Path(workdir or tmp_path)
        workdir.mkdir(parents=True, exist_ok=True)
        deck = workdir / "in.deck"
        deck.write_text(text)
        command = [str(launcher), "-in", str(deck), "-log", "log.lammps", "-echo", "screen",
                   "-var", "SHAPES", str(SHAPES), "-var", "BAD", str(BAD_MESHES)]
        for name, value in (variables or {}).items():
            command += ["-var", name, str(value)]
        env = dict(os.environ, **MPI_ENV)
        if nprocs > 1:
            command = ["mpirun", "-np", str(nprocs)] + command
        result = subprocess.run(command, cwd=workdir, capture_output=True, text=True, env=env,
                                timeout=timeout, errors="backslashreplace")
        return DeckResult(result.returncode, result.stdout + result.stderr, workdir)

    return run
