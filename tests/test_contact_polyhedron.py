"""compute contact/polyhedron: the coordination number of each particle (LIGGGHTS' compute contact/atom for
polyhedra), from the contacts pair_style polyhedral/volumetric found (issue 16)."""
import pytest

import decks
from test_pair_parallel import MATERIALS, particles, templates


def stack():
    """Three cubes of 1 cm: two overlapping by 0.1 mm face to face, one apart; no gravity."""
    return (decks.header(boundary="f f f", lo=0.0, hi=0.1, ntypes=2) + "neigh_modify delay 0\n" + decks.materials() +
            decks.template("cube", "cube.stl", scale=0.01) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "create_polyhedron cube 0.05 0.05 0.05\ncreate_polyhedron cube 0.05 0.05 0.0599\n"
            "create_polyhedron cube 0.02 0.02 0.02\n"
            "fix integrate all nve/polyhedron\ncompute coord all contact/polyhedron\n"
            "dump counts all custom 1 counts.dump id c_coord\ntimestep 1e-7\nrun 1\n")


def test_counts_touching_neighbours(run_deck, tmp_path):
    result = run_deck(stack(), workdir=tmp_path)
    assert result.returncode == 0, result.output[-3000:]
    columns, rows = decks.read_dump(tmp_path / "counts.dump")
    counts = {i: row[columns.index("c_coord")] for i, row in rows.items()}
    assert counts == {1: 1.0, 2: 1.0, 3: 0.0}, counts


@pytest.mark.parametrize("nprocs", [1, 2])
def test_sum_is_twice_the_contacts_while_a_bed_forms(run_deck, tmp_path, nprocs):
    """200 particles falling onto a bed of fixed cubes, on 1 and 2 ranks: at every output the counts summed over
    all particles are twice the contacts compute pair/polyhedral/local lists (each contact has two ends, also
    across ranks), and there are contacts to count."""
    deck = (decks.header(boundary="p p f", lo=0.0, hi=0.12, ntypes=2,
                         processors="2 1 1" if nprocs == 2 else None).replace(
        "region box block 0.0 0.12 0.0 0.12 0.0 0.12", "region box block 0.0 0.12 0.0 0.12 -0.01 0.5") +
        MATERIALS + templates() + "pair_style polyhedral/volumetric\npair_coeff * *\n" + particles() +
        "group moving type 1\nfix integrate moving nve/polyhedron\nfix gravity moving gravity 9.81 vector 0 0 -1\n"
        "compute coord all contact/polyhedron\ncompute total all reduce sum c_coord\n"
        "compute contacts all pair/polyhedral/local\nthermo_style custom step c_total c_contacts\n"
        "thermo 400\ntimestep 2e-5\nrun 4000\n")
    result = run_deck(deck, nprocs=nprocs, workdir=tmp_path)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "c_total", "c_contacts")
    print(table)
    assert table["c_total"] == [2.0 * c for c in table["c_contacts"]]
    assert max(table["c_contacts"]) >= 20


def test_needs_polyhedra(run_deck):
    deck = ("atom_style granular\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
            "units si\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\ncompute coord all contact/polyhedron\nrun 0\n")
    result = run_deck(deck)
    assert result.returncode != 0
    assert any("requires atom_style polyhedron" in line for line in result.error_lines()), result.output[-2000:]


def test_liggghts_contact_atom_is_an_error_with_polyhedra_only(run_deck, tmp_path):
    """LIGGGHTS' compute contact/atom would count bounding spheres: under atom_style polyhedron it stops with an
    ERROR naming compute contact/polyhedron; with spheres it is LIGGGHTS' own and runs."""
    polyhedra = stack().replace("compute coord all contact/polyhedron", "compute coord all contact/atom")
    result = run_deck(polyhedra, workdir=tmp_path / "polyhedra")
    assert result.returncode != 0
    assert any("use compute contact/polyhedron" in line for line in result.error_lines()), result.output[-2000:]
    spheres = ("atom_style granular\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
               "units si\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
               "fix m1 all property/global youngsModulus peratomtype 1e7\n"
               "fix m2 all property/global poissonsRatio peratomtype 0.25\n"
               "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n"
               "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n"
               "pair_style gran model hertz tangential history\npair_coeff * *\n"
               "create_atoms 1 single 0.5 0.5 0.5\ncreate_atoms 1 single 0.5 0.5 0.519\n"
               "set atom * diameter 0.02 density 2500\nfix integrate all nve/sphere\n"
               "compute coord all contact/atom\ncompute total all reduce sum c_coord\n"
               "thermo_style custom step c_total\ntimestep 1e-7\nrun 1\n")
    result = run_deck(spheres, workdir=tmp_path / "spheres")
    assert result.returncode == 0, result.output[-2000:]
    assert result.thermo("c_total")["c_total"][-1] == 2.0
