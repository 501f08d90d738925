"""make install, the launcher's switches, and the build settings."""
import os
import subprocess

from conftest import MPI_ENV, ROOT


def test_install_tree_runs_from_its_prefix(launcher, tmp_path):
    prefix = tmp_path / "prefix"
    result = subprocess.run(["make", "-s", "install", f"PREFIX={prefix}"], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    installed = prefix / "bin" / "liggghts-poly"
    assert installed.exists() and (prefix / "lib" / "libpolyhedral.so").exists()
    # The launcher finds its library through its rpath ($ORIGIN/../lib), not through the build tree.
    (tmp_path / "in.deck").write_text("atom_style polyhedron\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
                                      "print \"value ${answer}\"\n")
    env = dict(os.environ, **MPI_ENV)
    env.pop("LD_LIBRARY_PATH", None)
    run = subprocess.run(["mpirun", "-np", "2", str(installed), "-in", "in.deck", "-var", "answer", "42",
                          "-log", "none", "-echo", "none", "-screen", "screen.txt"],
                         cwd=tmp_path, capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stdout + run.stderr
    screen = (tmp_path / "screen.txt").read_text()
    assert "value 42" in screen and "1 by 1 by 2 MPI processor grid" in screen, screen


def test_build_settings_are_reported_and_cuda_can_be_switched_off():
    auto = subprocess.run(["make", "-s", "info"], cwd=ROOT, capture_output=True, text=True)
    off = subprocess.run(["make", "-s", "info", "CUDA=off", "PRECISION=single"], cwd=ROOT, capture_output=True,
                         text=True)
    assert auto.returncode == 0 and off.returncode == 0
    assert "CUDA=off" in off.stdout and "PRECISION=single" in off.stdout, off.stdout
    has_nvcc = subprocess.run(["bash", "-c", "command -v nvcc || ls /usr/local/cuda/bin/nvcc"],
                              capture_output=True).returncode == 0
    assert ("CUDA=on" in auto.stdout) == has_nvcc, auto.stdout
