"""dump polyhedron/vtk: surfaces in world coordinates, written by VTK's XML writers and read back by VTK's readers
(ParaView's Python) in every encoding; one file from rank 0 or a piece per rank."""
import pathlib
import sys

import numpy as np
import pytest

import decks
from test_rigid_body import rotation_matrix

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tools"))
from render_vtp import read_vtp as read_surfaces  # noqa: E402


def read_vtp(path):
    points, triangles, arrays = read_surfaces(path)
    arrays = dict(arrays, points=points, connectivity=triangles.ravel(),
                  offsets=3 * np.arange(1, len(triangles) + 1))
    return len(points), len(triangles), arrays


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


PILE = (decks.header(boundary="f f f", ntypes=2, processors="2 1 1") + decks.materials() +
        decks.template("rock", "rock_40.obj", scale=0.1) +
        decks.template("cube", "cube.stl", scale=0.08, atom_type=1, seed=32452843) +
        "pair_style polyhedral/volumetric\npair_coeff * *\n"
        "fix floor all wall/polyhedral primitive type 1 zplane 0.0\n"
        "region fill block 0.1 0.9 0.1 0.9 0.05 0.45\n"
        "fix shapes all particledistribution/discrete 49979687 2 rock 0.5 cube 0.5\n"
        "fix put all insert/pack seed 67867967 distributiontemplate shapes insert_every once overlapcheck yes "
        "orientation random all_in yes particles_in_region 40 region fill\n"
        "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
        "neighbor 0.02 bin\nneigh_modify delay 0\ntimestep 1e-4\nrun 4000\n"
        "compute contacts all contact/polyhedron\n")


def test_encodings_and_pieces_hold_the_same_surfaces_and_fields(run_deck):
    """One settling pile on 2 ranks, dumped at the same step as ASCII, raw binary, zlib and lz4 .vtp files and as
    a .pvtp with a piece per rank: VTK reads all back to the same arrays; force and contact count are those of
    dump custom and compute contact/polyhedron; the .pvtp's pieces are the ranks' particles."""
    deck = (PILE +
            "dump text all custom 1 state.txt id fx fy fz c_contacts\ndump_modify text format \"%d %.17g %.17g %.17g %g\"\n"
            "dump ascii all polyhedron/vtk 1 ascii_*.vtp\ndump_modify ascii binary no\n"
            "dump raw all polyhedron/vtk 1 raw_*.vtp\ndump_modify raw compressor none\n"
            "dump zlib all polyhedron/vtk 1 zlib_*.vtp\n"
            "dump lz4 all polyhedron/vtk 1 lz4_*.vtp\ndump_modify lz4 compressor lz4\n"
            "dump zlib9 all polyhedron/vtk 1 zlib9_*.vtp\ndump_modify zlib9 compression_level 9\n"
            "dump ranks all polyhedron/vtk 1 ranks_*.pvtp\n"
            "run 0\n")
    result = run_deck(deck, nprocs=2)
    assert result.returncode == 0, result.output
    work = result.workdir
    step = 4000
    reference = read_surfaces(work / f"ascii_{step}.vtp")
    points, triangles, arrays = reference
    assert set(arrays) == {"id", "type", "shape", "v", "omega", "f", "contacts"}
    for name in ("raw", "zlib", "lz4", "zlib9"):
        other_points, other_triangles, other = read_surfaces(work / f"{name}_{step}.vtp")
        assert np.array_equal(other_triangles, triangles)
        assert np.allclose(other_points, points, rtol=0, atol=1e-14)
        for key in arrays:
            assert np.allclose(other[key], arrays[key], rtol=1e-14, atol=0), (name, key)
    sizes = {name: (work / f"{name}_{step}.vtp").stat().st_size for name in ("ascii", "raw", "zlib", "lz4")}
    assert sizes["zlib"] < 0.5 * sizes["raw"] and sizes["zlib"] < 0.5 * sizes["ascii"], sizes
    assert (work / f"zlib9_{step}.vtp").stat().st_size < sizes["zlib"]

    # Force and contact count per particle, as dump custom and compute contact/polyhedron give them.
    columns, rows = decks.read_dump(work / "state.txt")
    first = np.unique(arrays["id"], return_index=True)[1]
    ids = arrays["id"][first].astype(int)
    assert len(ids) == 40 and sorted(rows) == sorted(ids)
    expected_force = np.array([rows[i][1:4] for i in ids])
    assert np.allclose(arrays["f"][first], expected_force, rtol=1e-9, atol=1e-12)
    expected_contacts = np.array([rows[i][4] for i in ids])
    assert np.array_equal(arrays["contacts"][first], expected_contacts)
    assert expected_contacts.sum() > 10    # a pile, so the comparison is not of zeros (18 contact ends at 4000)
    assert np.abs(expected_force).max() > 0

    # The .pvtp: an index and one piece per rank, together the same particles.
    index = work / f"ranks_{step}.pvtp"
    pieces = sorted(work.glob(f"ranks_{step}_*.vtp"))
    assert len(pieces) == 2, sorted(p.name for p in work.iterdir())
    piece_ids = [np.unique(read_surfaces(piece)[2]["id"]) for piece in pieces]
    assert len(piece_ids[0]) > 0 and len(piece_ids[1]) > 0
    assert not set(piece_ids[0]) & set(piece_ids[1])
    all_points, all_triangles, all_arrays = read_surfaces(index)
    order = np.argsort(all_arrays["id"], kind="stable")
    assert np.array_equal(all_arrays["id"][order], arrays["id"])
    assert np.allclose(all_arrays["f"][order], arrays["f"], rtol=1e-14, atol=0)
    # Each triangle's corner points, compared in id order.
    corners = all_points[all_triangles][order]
    assert np.allclose(corners, points[triangles], rtol=0, atol=1e-14)


@pytest.mark.parametrize("lines, message", [
    ("dump d all polyhedron/vtk 10 wrong_*.vtu\n", "must end in .vtp"),
    ("dump d all polyhedron/vtk 10 d_*.vtp\ndump_modify d compressor bzip2\n", "compressor zlib|lz4|none"),
    ("dump d all polyhedron/vtk 10 d_*.vtp\ndump_modify d binary maybe\n", "binary yes|no"),
    ("dump d all polyhedron/vtk 10 d_*.vtp\ndump_modify d compression_level 12\n", "compression_level 1-9"),
    # The deck file itself stands where a directory should be (VTK creates missing directories).
    ("dump d all polyhedron/vtk 10 in.deck/d_*.vtp\n", "could not write in.deck/d_0.vtp"),
])
def test_bad_dump_input_is_an_error(run_deck, lines, message):
    deck = (decks.header() + decks.template("cube", "cube.stl", scale=0.05) +
            "create_polyhedron cube 0.5 0.5 0.5\nfix integrate all nve/polyhedron\n" + lines + "run 0\n")
    result = run_deck(deck)
    assert result.returncode != 0
    assert "ERROR" in result.output and message in result.output, result.output[-2000:]
