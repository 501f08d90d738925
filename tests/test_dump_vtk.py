"""dump polyhedron/vtk: surfaces in world coordinates, valid VTK XML PolyData."""
import xml.etree.ElementTree as ElementTree

import numpy as np

import decks
from test_rigid_body import rotation_matrix


def read_vtp(path):
    root = ElementTree.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "PolyData"
    piece = root.find("PolyData/Piece")
    arrays = {}
    for array in piece.iter("DataArray"):
        values = np.array(array.text.split(), dtype=float)
        components = int(array.get("NumberOfComponents", "1"))
        arrays[array.get("Name") or "points"] = values.reshape(-1, components) if components > 1 else values
    return int(piece.get("NumberOfPoints")), int(piece.get("NumberOfPolys")), arrays


def test_surfaces_are_template_vertices_rotated_and_translated(run_deck, tmp_path):
    q = np.array([0.7, -0.2, 0.5, 0.4])
    q /= np.linalg.norm(q)
    centre = np.array([0.3, 0.6, 0.45])
    deck = (decks.header(ntypes=2) + decks.template("rock", "rock_70.obj", scale=0.1) +
            decks.template("cube", "cube.stl", scale=0.05, atom_type=2) +
            "create_polyhedron rock 0.5 0.5 0.5\n"
            "create_polyhedron rock %.17g %.17g %.17g quat %.17g %.17g %.17g %.17g vel 1 2 3 omega 4 5 6\n"
            % (tuple(centre) + tuple(q)) +
            "create_polyhedron cube 0.2 0.2 0.2\n"
            "fix integrate all nve/polyhedron\ndump surfaces all polyhedron/vtk 5 shapes_*.vtp\n"
            "timestep 1e-12\nrun 5\n")
    result = run_deck(deck, nprocs=2)
    assert result.returncode == 0, result.output
    assert sorted(p.name for p in result.workdir.glob("shapes_*.vtp")) == ["shapes_0.vtp", "shapes_5.vtp"]
    points_count, cells, arrays = read_vtp(result.workdir / "shapes_0.vtp")
    points = arrays["points"]
    # rock_70: 70 triangles, 37 vertices; cube: 12 triangles, 8 vertices.
    assert (points_count, cells) == (2 * 37 + 8, 2 * 70 + 12)
    assert points.shape == (points_count, 3)
    assert len(arrays["connectivity"]) == 3 * cells
    assert np.array_equal(arrays["offsets"], 3 * np.arange(1, cells + 1))
    assert arrays["connectivity"].max() == points_count - 1
    # Particle 1 sits at identity orientation, so its points are body-frame vertices + centre.
    body = points[:37] - np.array([0.5, 0.5, 0.5])
    expected = body @ rotation_matrix(q).T + centre
    assert np.max(np.abs(points[37:74] - expected)) < 1e-9
    # Per-cell data, particles in id order.
    assert np.array_equal(arrays["id"], np.repeat([1, 2, 3], [70, 70, 12]))
    assert np.array_equal(arrays["type"], np.repeat([1, 1, 2], [70, 70, 12]))
    assert np.array_equal(arrays["shape"], np.repeat([1, 1, 2], [70, 70, 12]))
    assert np.allclose(arrays["v"][70], [1, 2, 3]) and np.allclose(arrays["omega"][70], [4, 5, 6])
    # The body frame is the centre-of-mass frame: the mean of the triangle-weighted surface is not
    # needed; the vertices of the cube must be +-0.025 about its centre.
    cube = points[74:] - np.array([0.2, 0.2, 0.2])
    assert np.allclose(np.sort(np.abs(cube).ravel()), 0.025, atol=1e-12)


def test_group_selects_particles(run_deck):
    deck = (decks.header() + decks.template("cube", "cube.stl", scale=0.05) +
            "create_polyhedron cube 0.2 0.2 0.2\ncreate_polyhedron cube 0.7 0.7 0.7\n"
            "group second id 2\nfix integrate all nve/polyhedron\n"
            "dump surfaces second polyhedron/vtk 1 second_*.vtp\nrun 0\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output
    points_count, cells, arrays = read_vtp(result.workdir / "second_0.vtp")
    assert (points_count, cells) == (8, 12)
    assert np.all(arrays["id"] == 2)
