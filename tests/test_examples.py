"""Smoke runs of the example decks at a tiny size: they run as documented, lose no particle
(thermo_modify lost error) and their numbers are in a sane range."""
import os
import shutil
import subprocess
import sys

import pytest

from conftest import MPI_ENV, ROOT


@pytest.mark.parametrize("wall", ["0", "1"], ids=["floor-particles", "plane-wall"])
def test_gravity_packing_smoke(tmp_path, launcher, wall):
    """300 Schönhardt polyhedra for 3000 steps (0.03 s), the floor of fixed particles or the plane."""
    work = tmp_path / "gravity_packing"
    shutil.copytree(ROOT / "examples" / "gravity_packing", work, ignore=shutil.ignore_patterns("results", "post", "data"))
    (work / "post").mkdir()
    made = subprocess.run([sys.executable, "make_packing.py", "300", "--outdir", "data"] +
                          (["--floor", "none"] if wall == "1" else []), cwd=work, capture_output=True, text=True)
    assert made.returncode == 0, made.stdout + made.stderr
    run = subprocess.run([str(ROOT / "build" / "bin" / "liggghts-poly"), "-in", "in.packing", "-var", "N", "300",
                          "-var", "steps", "3000", "-var", "M", "500", "-var", "wall", wall,
                          "-var", "SHAPES", str(ROOT / "examples" / "shapes"), "-log", "log.smoke"],
                         cwd=work, capture_output=True, text=True, env=dict(os.environ, **MPI_ENV), timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    rows = [line.split() for line in run.stdout.splitlines() if line.split()[:1] and line.split()[0].isdigit()]
    header = next(line.split() for line in run.stdout.splitlines() if line.split()[:2] == ["Step", "Atoms"])
    table = [dict(zip(header, row)) for row in rows if len(row) == len(header)]
    assert table and int(table[-1]["Step"]) == 3000
    print(f"\ngravity packing smoke (wall {wall}): {table[-1]}")
    assert int(table[0]["Atoms"]) == int(table[-1]["Atoms"])  # nothing lost
    assert float(table[-1]["KinEng"]) > 0
    assert 0 < int(float(table[-1]["contacts"])) < 3 * 300  # the first layers have landed
