"""compute wall/polyhedral/local: one row per contact of a fix wall/polyhedral, for dump local (issue 16)."""
import pytest

import decks

PLATE = ("solid plate\n"
         " facet normal 0 0 1\n  outer loop\n   vertex 0.0 0.0 0.0\n   vertex 0.2 0.0 0.0\n   vertex 0.2 0.2 0.0\n"
         "  endloop\n endfacet\n"
         " facet normal 0 0 1\n  outer loop\n   vertex 0.0 0.0 0.0\n   vertex 0.2 0.2 0.0\n   vertex 0.0 0.2 0.0\n"
         "  endloop\n endfacet\nendsolid plate\n")


def deck(wall):
    """Two cubes of 2 cm resting on a wall (a plane or a two-triangle mesh), a third falling towards it."""
    return (decks.header(boundary="f f f", lo=-0.05, hi=0.25, ntypes=2) + "neighbor 0.002 bin\nneigh_modify delay 0\n"
            + decks.materials() + decks.template("cube", "cube.stl", scale=0.02) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "create_polyhedron cube 0.05 0.05 0.0101\n"
            "create_polyhedron cube 0.15 0.05 0.0101\ncreate_polyhedron cube 0.1 0.15 0.05\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n" + wall +
            "compute w all wall/polyhedral/local wall\n"
            "dump rows all local 500 rows.dump c_w[1] c_w[2] c_w[3] c_w[4] c_w[5] c_w[6] c_w[7] c_w[8] c_w[9] c_w[10]\n"
            "dump_modify rows format '" + " ".join(["%.17g"] * 10) + "'\n"
            "thermo_style custom step f_wall[1] f_wall[2] f_wall[3] f_wall[4]\nthermo_modify format float %.15g\n"
            "thermo 500\ntimestep 1e-5\nrun 3000\n")


def last_rows(path):
    lines = path.read_text().splitlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ENTRIES"))
    return [[float(w) for w in line.split()] for line in lines[start + 1:] if line.strip()]


@pytest.mark.parametrize("kind", ["plane", "mesh"])
def test_rows_sum_to_the_wall_force(run_deck, tmp_path, kind):
    """At the last output the rows are the wall's contacts: as many as its contact count (f_wall[4]), their
    forces on the particles summing to minus the force on the wall (f_wall[1..3]), each with the particle's tag,
    the mesh (1, or 0 for a plane), a triangle of that mesh (its id, -1 for a plane), a contact point at the wall and a
    positive overlap volume."""
    if kind == "plane":
        wall = "fix wall all wall/polyhedral primitive type 2 zplane 0.0\n"
    else:
        (tmp_path / "plate.stl").write_text(PLATE)
        wall = ("fix plate all mesh/surface file plate.stl type 2\n"
                "fix wall all wall/polyhedral mesh n_meshes 1 meshes plate\n")
    result = run_deck(deck(wall), workdir=tmp_path)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "f_wall[1]", "f_wall[2]", "f_wall[3]", "f_wall[4]")
    rows = last_rows(tmp_path / "rows.dump")
    print(rows)
    assert len(rows) == table["f_wall[4]"][-1] == 2
    assert sorted(int(r[0]) for r in rows) == [1, 2]
    for r in rows:
        assert r[1] == (0 if kind == "plane" else 1)
        assert r[2] == -1 if kind == "plane" else r[2] in (0, 1)
        assert r[5] > 0 and abs(r[8]) < 1e-3 and r[9] > 0
    for k in range(3):
        total = sum(r[3 + k] for r in rows)
        assert total == pytest.approx(-table[f"f_wall[{k + 1}]"][-1], rel=1e-9, abs=1e-12)


def test_needs_a_wall_fix(run_deck, tmp_path):
    result = run_deck(deck("fix wall all wall/polyhedral primitive type 2 zplane 0.0\n").replace(
        "wall/polyhedral/local wall", "wall/polyhedral/local nowall"), workdir=tmp_path)
    assert result.returncode != 0
    assert any("no fix wall/polyhedral with ID 'nowall'" in line for line in result.error_lines()), result.output[-2000:]
