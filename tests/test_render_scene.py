"""tools/render_scene.py: a deck writing particles (dump polyhedron/vtk) and a mesh floor (LIGGGHTS' dump
mesh/vtk ... stress) is rendered to PNG, by matplotlib and, where Debian's python3-paraview and xvfb are
installed, by ParaView offscreen; the legacy VTK of the mesh is read back as LIGGGHTS wrote it."""
import importlib.util
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import decks
import meshes
from conftest import MPI_ENV, ROOT, SHAPES

sys.path.insert(0, str(ROOT / "tools"))
import render_scene  # noqa: E402

CELLS = 4  # the floor: 4 x 4 cells of 2 triangles, [-0.1, 0.1]^2 at z = 0
STEPS = 1500


@pytest.fixture(scope="module")
def scene(launcher, tmp_path_factory):
    workdir = tmp_path_factory.mktemp("scene")
    meshes.write_stl(workdir / "floor.stl", meshes.grid(CELLS, 0.1))
    (workdir / "post").mkdir()
    deck = (decks.header(boundary="f f f", lo=-0.12, hi=0.2, ntypes=2) +
            "neighbor 0.003 bin\nneigh_modify delay 0\n"
            "fix m1 all property/global youngsModulus peratomtype 5e6 5e6\n"
            "fix m2 all property/global poissonsRatio peratomtype 0.25 0.25\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n" +
            decks.template("rock", "rock_70.obj", scale=0.03, density=2700) +
            decks.template("cube", "cube.stl", scale=0.025, density=2700, seed=15485867) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "fix floor_mesh all mesh/surface/stress file floor.stl type 2\n"
            "fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh\n"
            "create_polyhedron rock -0.03 0 0.03 quat 0.92 0.38 0 0\n"
            "create_polyhedron cube 0.03 0.02 0.05 quat 0.9 0.3 -0.2 0.25\n"
            "create_polyhedron rock 0.0 -0.04 0.08 vel 0 0 -0.5\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
            "timestep 1e-4\n"
            "dump d1 all mesh/vtk 500 post/mesh_*.vtk stress\n"
            "dump d2 all polyhedron/vtk 500 post/particles_*.vtp\n"
            "dump d3 all polyhedron/vtk 500 post/pieces_*.pvtp\n"
            f"run {STEPS}\n")
    (workdir / "in.scene").write_text(deck)
    result = subprocess.run([str(launcher), "-in", "in.scene", "-log", "log.lammps", "-var", "SHAPES", str(SHAPES)],
                            cwd=workdir, capture_output=True, text=True, env=dict(os.environ, **MPI_ENV), timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr
    return workdir


def check_picture(path, width, height):
    import matplotlib.image

    image = matplotlib.image.imread(str(path))
    assert image.shape[:2] == (height, width)
    rgb = image[:, :, :3].reshape(-1, 3)
    colours = np.unique(np.round(rgb * 255).astype(int), axis=0)
    assert rgb.std() > 0.03, "picture is blank"
    assert len(colours) > 50, f"only {len(colours)} colours"
    return image


def test_dump_mesh_vtk_is_read_back(scene):
    steps = [0, 500, 1000, 1500]
    assert sorted(p.name for p in (scene / "post").glob("mesh_*.vtk")) == sorted(f"mesh_{s}.vtk" for s in steps)
    text = (scene / "post" / "mesh_1500.vtk").read_text()
    assert text.startswith("# vtk DataFile Version 5.1\n") and "OFFSETS vtktypeint64" in text
    points, polygons, cell_data, point_data = render_scene.read_legacy_vtk(scene / "post" / "mesh_1500.vtk")
    triangles, _ = render_scene.mesh_triangles(points, polygons)
    assert len(polygons) == len(triangles) == 2 * CELLS ** 2 and point_data == {}
    assert points.shape == (3 * len(triangles), 3)  # LIGGGHTS writes three points per triangle
    assert set(cell_data) == {"normal_stress_average", "shear_stress_average"}
    assert all(len(values) == len(triangles) for values in cell_data.values())
    # The STL as written: the floor at z = 0 spanning [-0.1, 0.1]^2, each triangle normal +z.
    corners = points[triangles]
    assert np.allclose(points[:, 2], 0.0) and np.allclose(points.min(axis=0)[:2], -0.1)
    assert np.allclose(points.max(axis=0)[:2], 0.1)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert np.all(normals[:, 2] > 0)
    # The rocks rest on the floor by now: some triangles carry their weight.
    assert cell_data["normal_stress_average"].max() > 0


def test_legacy_reader_takes_the_older_format(tmp_path):
    path = tmp_path / "old.vtk"
    path.write_text("# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n"
                    "0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 1 5\n4 0 1 2 3\n"
                    "CELL_DATA 1\nSCALARS p float 1\nLOOKUP_TABLE default\n2.5\n")
    points, polygons, cell_data, _ = render_scene.read_legacy_vtk(path)
    triangles, owners = render_scene.mesh_triangles(points, polygons)
    assert triangles.tolist() == [[0, 1, 2], [0, 2, 3]] and owners.tolist() == [0, 0]
    assert cell_data["p"].tolist() == [2.5]


def render(scene, *arguments):
    return subprocess.run([sys.executable, str(ROOT / "tools" / "render_scene.py"), *arguments],
                          cwd=scene, capture_output=True, text=True, timeout=300)


def test_matplotlib_renders_particles_and_mesh(scene):
    result = render(scene, "mpl.png", "post/particles_1500.vtp", "post/mesh_1500.vtk", "--backend", "matplotlib",
                    "--size", "640", "480", "--colour", "speed")
    assert result.returncode == 0, result.stdout + result.stderr
    check_picture(scene / "mpl.png", 640, 480)


def paraview_usable():
    try:
        found = importlib.util.find_spec("paraview.simple") is not None
    except ImportError:
        found = False
    return found and bool(os.environ.get("DISPLAY") or shutil.which("xvfb-run"))


@pytest.mark.skipif(not paraview_usable(), reason="needs python3-paraview and xvfb (or a DISPLAY)")
def test_paraview_renders_the_series_and_writes_a_state(scene):
    result = render(scene, "pv.png", "post/particles_*.vtp", "post/mesh_*.vtk", "--backend", "paraview",
                    "--size", "800", "600", "--state", "scene.pvsm")
    assert result.returncode == 0, result.stdout + result.stderr
    image = check_picture(scene / "pv.png", 800, 600)
    # Not just the background and colour bars: the middle of the picture has the scene.
    middle = image[150:450, 100:600, :3].reshape(-1, 3)
    assert np.mean(np.any(np.abs(middle - 1.0) > 0.05, axis=1)) > 0.1
    state = (scene / "scene.pvsm").read_text()
    for step in (0, 500, 1000, 1500):
        assert str(scene / "post" / f"particles_{step}.vtp") in state
        assert str(scene / "post" / f"mesh_{step}.vtk") in state


@pytest.mark.skipif(not paraview_usable(), reason="needs python3-paraview and xvfb (or a DISPLAY)")
def test_paraview_renders_a_series_of_pieces(scene):
    """dump polyhedron/vtk's .pvtp (an index and a piece per rank, through VTK's parallel writer) in ParaView."""
    result = render(scene, "pieces.png", "post/pieces_*.pvtp", "--backend", "paraview", "--size", "640", "480",
                    "--colour", "speed", "--state", "pieces.pvsm")
    assert result.returncode == 0, result.stdout + result.stderr
    check_picture(scene / "pieces.png", 640, 480)
    assert str(scene / "post" / "pieces_1500.pvtp") in (scene / "pieces.pvsm").read_text()
