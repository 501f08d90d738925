"""Bad input gives one clear ERROR: line naming the problem and a non-zero exit, never a crash."""
import re

import pytest

import decks

BOX = "atom_style polyhedron\natom_modify sort 0 0\nboundary f f f\nregion box block 0 1 0 1 0 1\ncreate_box 2 box\n"


def template_line(path, extra=""):
    return f"fix t all particletemplate/polyhedron 15485863 atom_type 1 density constant 1000 file {path}{extra}\n"


def test_bad_pieces_choice_is_an_error(run_deck, monkeypatch):
    """POLY_PIECES_BY_CONES (the convex pieces by cones instead of the partition, for comparisons) takes 0 or 1;
    anything else stops the shape's loading with an ERROR naming it, not a silent choice."""
    monkeypatch.setenv("POLY_PIECES_BY_CONES", "yes")
    result = run_deck(BOX + template_line("${SHAPES}/schoenhardt.stl", " scale 0.01"))
    assert result.returncode != 0
    assert any("POLY_PIECES_BY_CONES=yes: expected 0 or 1" in line for line in result.error_lines()), result.output
    monkeypatch.setenv("POLY_PIECES_BY_CONES", "0")
    assert run_deck(BOX + template_line("${SHAPES}/schoenhardt.stl", " scale 0.01")).returncode == 0


@pytest.mark.parametrize("mesh, expected", [
    ("open.stl", ["open.stl", "is open", "belongs to only one triangle"]),
    ("inconsistent.off", ["inconsistent.off", "inconsistent orientation"]),
    ("nonmanifold_edge.off", ["nonmanifold_edge.off", "non-manifold", "shared by 4 triangles"]),
    ("pinched_vertex.off", ["pinched_vertex.off", "non-manifold", "pinched vertex"]),
    ("degenerate.obj", ["degenerate.obj", "degenerate triangle", "zero area"]),
    ("disconnected.obj", ["disconnected.obj", "more than one connected component"]),
    ("garbage.obj", ["garbage.obj", "line 9", "references vertex 9"]),
    ("truncated.stl", ["truncated.stl", "binary STL truncated"]),
    ("empty.off", ["empty.off", "no triangles"]),
    ("unknown.xyz", ["unknown.xyz", "unknown extension"]),
    ("does_not_exist.stl", ["does_not_exist.stl"]),
])
def test_bad_shape_mesh_is_an_error_naming_file_and_defect(run_deck, mesh, expected):
    result = run_deck(BOX + template_line("${BAD}/" + mesh))
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert errors[0].startswith("ERROR: Fix particletemplate/polyhedron (id t):")
    for fragment in expected:
        assert fragment in errors[0], errors[0]
    assert "Segmentation" not in result.output and "signal" not in result.output


def test_inward_mesh_is_flipped_with_a_warning(run_deck):
    result = run_deck(BOX + template_line("${BAD}/inward.off") +
                      "create_polyhedron t 0.5 0.5 0.5\ncompute p all property/polyhedron volume\n"
                      "variable v equal c_p[1]\nfix integrate all nve/polyhedron\n"
                      "dump d all custom 1 volume.txt id c_p\nrun 0\n")
    assert result.returncode == 0, result.output
    assert any("inward.off" in w and "flipped" in w for w in result.warning_lines()), result.output
    _, rows = decks.read_dump(result.workdir / "volume.txt")
    assert abs(rows[1][1] - 1.0) < 1e-12  # the unit cube, with positive volume


@pytest.mark.parametrize("line, expected", [
    (template_line("${SHAPES}/cube.stl", " colour red"), "unknown keyword"),
    ("fix t all particletemplate/polyhedron 15485863 atom_type 1 file ${SHAPES}/cube.stl\n", "have to define 'density'"),
    ("fix t all particletemplate/polyhedron 15485863 atom_type 1 density constant 1\n", "missing keyword 'file'"),
    ("fix t all particletemplate/polyhedron 15485863 atom_type 3 density constant 1 file ${SHAPES}/cube.stl\n",
     "atom type exceeds"),
    (template_line("${SHAPES}/cube.stl", " scale -2"), "scale must be > 0"),
    ("fix t all particletemplate/polyhedron 15485863 atom_type 1 density uniform 1 2 file ${SHAPES}/cube.stl\n",
     "invalid density random style"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron nothere 0.5 0.5 0.5\n",
     "'nothere' is not the ID of a fix particletemplate/polyhedron"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 2.5 0.5 0.5\n", "outside the simulation box"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 spin 1 2 3\n", "unknown keyword 'spin'"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 quat 0 0 0 0\n", "must not be zero"),
    ("compute e all erotate/polyhedron extra\n", "takes no arguments"),
    ("compute p all property/polyhedron colour\n", "unknown keyword"),
    ("fix n all nve/polyhedron extra\n", "takes no arguments"),
    ("dump d all polyhedron/vtk 10 no_star.vtp\n", "needs a '*'"),
    (template_line("${SHAPES}/cube.stl") + template_line("${SHAPES}/rock_70.obj"), "cannot be redefined"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 1.0\n", "outside the simulation box"),
    ("fix w all wall/polyhedral primitive type 2 zplane 0.0 tangential\n", "keyword 'tangential' needs a value"),
    ("fix w all wall/polyhedral primitive type 2 zplane 0.0 model hertz\n",
     "unknown keyword 'model' after the wall (LIGGGHTS' model, rolling_friction and surface keywords go before"),
])
def test_bad_command_is_an_error(run_deck, line, expected):
    result = run_deck(BOX + line)
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1 and expected in errors[0], result.output


@pytest.mark.parametrize("deck, expected", [
    ("atom_style sphere\natom_modify sort 0 0\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
     "fix t all particletemplate/polyhedron 15485863 atom_type 1 density constant 1 file ${SHAPES}/cube.stl\n"
     "create_polyhedron t 0.5 0.5 0.5\n", "create_polyhedron requires atom_style polyhedron"),
    ("atom_style sphere\natom_modify sort 0 0\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
     "create_atoms 1 single 0.5 0.5 0.5\nfix n all nve/polyhedron\nrun 0\n", "requires atom_style polyhedron"),
    (BOX + "create_atoms 1 single 0.5 0.5 0.5\nrun 0\n", "has shape 0, but 0 fix particletemplate/polyhedron"),
])
def test_wrong_atom_style_or_missing_shape(run_deck, deck, expected):
    result = run_deck(deck)
    assert result.returncode != 0
    assert any(expected in line for line in result.error_lines()), result.output


def test_set_density_changes_mass_not_shape(run_deck):
    """`set density` is honoured: the mass follows density x template volume."""
    result = run_deck(BOX + template_line("${SHAPES}/cube.stl", " scale 0.1") +
                      "create_polyhedron t 0.5 0.5 0.5\nset atom 1 density 3000\n"
                      "fix integrate all nve/polyhedron\ndump d all custom 1 mass.txt id mass\nrun 0\n")
    assert result.returncode == 0, result.output
    _, rows = decks.read_dump(result.workdir / "mass.txt")
    assert abs(rows[1][1] - 3000 * 0.1 ** 3) < 1e-12


CONTACT_MATERIAL = ("fix m1 all property/global youngsModulus peratomtype 1e7\n"
                    "fix m2 all property/global poissonsRatio peratomtype 0.3\n"
                    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n"
                    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n")


def two_cubes_deck(boundary="f f f", gap=-0.005, extent=1.0):
    return ("atom_style polyhedron\natom_modify map array sort 0 0\n"
            f"boundary {boundary}\nnewton off\ncommunicate single vel yes\nunits si\n"
            f"region box block -{extent} {extent} -{extent} {extent} -{extent} {extent}\ncreate_box 1 box\n" +
            CONTACT_MATERIAL +
            "fix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
            "file ${SHAPES}/cube.stl scale 0.1\n"
            "pair_style polyhedral/volumetric tangential history damping on\npair_coeff * *\n"
            f"create_polyhedron cube 0 0 0\ncreate_polyhedron cube {0.1 + gap!r} 0 0\n"
            "fix integrate all nve/polyhedron\ntimestep 1e-6\n")


def test_compute_pair_local_leaves_no_invalid_access_at_exit(launcher, tmp_path):
    """The compute's destructor used to read force->pair after LIGGGHTS had deleted force (valgrind:
    invalid read and write at exit); an uncomputed recorder must not be left in the pair style either."""
    import os
    import shutil
    import subprocess
    from conftest import MPI_ENV, SHAPES
    if not shutil.which("valgrind"):
        pytest.skip("valgrind is not installed")
    deck = tmp_path / "in.valgrind"
    deck.write_text(two_cubes_deck() + "compute contacts all pair/polyhedral/local\n"
                    "compute other all pair/polyhedral/local\nthermo_style custom step c_contacts\n"
                    "thermo 5\nrun 10\nuncompute other\nrun 10\n")
    result = subprocess.run(["valgrind", "--error-exitcode=9", str(launcher), "-in", str(deck), "-echo", "none",
                             "-log", "none", "-var", "SHAPES", str(SHAPES)], cwd=tmp_path, capture_output=True,
                            text=True, env=dict(os.environ, **MPI_ENV), timeout=600)
    output = result.stdout + result.stderr
    assert "Invalid read" not in output and "Invalid write" not in output, output[-6000:]
    assert result.returncode == 0, output[-6000:]


PULLED_CUBE_OFF = """OFF
8 12 0
0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n0.3 0.4 -0.5\n0 1 1
3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4
3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7
"""


def test_self_intersecting_shape_is_an_error_naming_two_triangles(run_deck, tmp_path):
    """A cube with one corner pulled through the opposite face: closed, manifold, consistently
    oriented, but its mass properties are meaningless (it used to gain 2400x its energy)."""
    (tmp_path / "pulled.off").write_text(PULLED_CUBE_OFF)
    result = run_deck(BOX + template_line("pulled.off"))
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert "pulled.off" in errors[0] and "intersects itself" in errors[0], errors[0]
    assert re.search(r"triangles \d+ and \d+ of 12", errors[0]), errors[0]


@pytest.mark.parametrize("scale, expected", [("1e-70", "principal moment is not positive"),
                                             ("1e70", "principal moment is not finite"),
                                             ("1e-110", "out of the range of double precision")])
def test_extreme_scale_is_an_error(run_deck, scale, expected):
    result = run_deck(BOX + template_line("${SHAPES}/rock_70.obj", f" scale {scale}"))
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert "rock_70.obj" in errors[0] and expected in errors[0], errors[0]


def restart_pair_decks(second_template, nprocs=1):
    """A restart written with a cube template 'grain'; read with `second_template` as 'grain'."""
    first = (decks.header() + decks.template("grain", "cube.stl", scale=0.03) +
             "create_polyhedron grain 0.3 0.3 0.3\ncreate_polyhedron grain 0.7 0.7 0.7 vel 0.1 0 0\n"
             "fix integrate all nve/polyhedron\ntimestep 1e-4\nrun 10\nwrite_restart state.restart\n")
    second = ("atom_modify sort 0 0\nread_restart ../first/state.restart\n" + second_template +
              "fix integrate all nve/polyhedron\ntimestep 1e-4\nrun 10\n")
    return first, second


@pytest.mark.parametrize("nprocs", [1, 2])
def test_restart_with_another_shape_of_the_same_volume_is_an_error(run_deck, tmp_path, nprocs):
    """The mass check cannot see this: a 1x2x3 box scaled to the cube's volume has the same mass."""
    box_scale = 0.03 / 6.0 ** (1.0 / 3.0)
    first, second = restart_pair_decks(decks.template("grain", "box_1x2x3.off", scale=box_scale), nprocs)
    written = run_deck(first, nprocs=nprocs, workdir=tmp_path / "first")
    assert written.returncode == 0, written.output
    read = run_deck(second, nprocs=nprocs, workdir=tmp_path / "second")
    assert read.returncode != 0, read.output
    errors = read.error_lines()
    assert errors, read.output
    assert "does not match shape 1" in errors[0] and "'grain'" in errors[0] and "box_1x2x3.off" in errors[0], errors


def test_restart_with_another_scale_is_an_error_and_the_same_template_is_not(run_deck, tmp_path):
    first, second_other = restart_pair_decks(decks.template("grain", "cube.stl", scale=0.031, density=2500.0 *
                                                            (0.03 / 0.031) ** 3))
    written = run_deck(first, workdir=tmp_path / "first")
    assert written.returncode == 0, written.output
    read = run_deck(second_other, workdir=tmp_path / "second")
    assert read.returncode != 0 and any("another mesh or scale" in e for e in read.error_lines()), read.output
    _, second_same = restart_pair_decks(decks.template("grain", "cube.stl", scale=0.03))
    same = run_deck(second_same, workdir=tmp_path / "same")
    assert same.returncode == 0, same.output


@pytest.mark.parametrize("boundary, length, fails", [("p p p", 0.15, True),    # cube 0.1: diameter 0.173
                                                     ("f p f", 0.15, True),
                                                     ("f f f", 0.15, False),   # not periodic: no image
                                                     ("p p p", 0.18, False)])
def test_periodic_box_narrower_than_a_particle_is_an_error(run_deck, boundary, length, fails):
    deck = ("atom_style polyhedron\natom_modify map array sort 0 0\n"
            f"boundary {boundary}\nnewton off\ncommunicate single vel yes\nunits si\n"
            f"region box block 0 {length} 0 {length} 0 {length}\ncreate_box 1 box\n" + CONTACT_MATERIAL +
            "fix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
            "file ${SHAPES}/cube.stl scale 0.1\n"
            "pair_style polyhedral/volumetric tangential history damping on\npair_coeff * *\n"
            f"create_polyhedron cube {length / 2} {length / 2} {length / 2}\n"
            "fix integrate all nve/polyhedron\ntimestep 1e-6\nrun 10\n")
    result = run_deck(deck)
    if not fails:
        assert result.returncode == 0, result.output
        return
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert "Periodic box length 0.15" in errors[0] and "'cube'" in errors[0] and "own periodic image" in errors[0], \
        errors[0]


@pytest.mark.parametrize("gap, warned", [(-0.005, True), (-0.0005, False), (0.001, False)])
def test_overlapping_particles_at_setup_give_a_warning(run_deck, gap, warned):
    """Two 10 cm cubes overlapping by 5 mm (2.9 % of the bounding diameter) used to fly apart silently."""
    result = run_deck(two_cubes_deck(gap=gap) + "run 10\nrun 10\n")
    assert result.returncode == 0, result.output
    warnings = [w for w in result.warning_lines() if "overlapping particle pairs" in w]
    if not warned:
        assert not warnings, warnings
        return
    assert warnings, result.output
    assert "1 of 1 overlapping particle pairs" in warnings[0] and "deeper than 1%" in warnings[0], warnings[0]
    assert "the deepest by 0.005 (2.89% of it)" in warnings[0], warnings[0]


def settled_stack_deck(pair_style):
    """Two 10 cm cubes dropped 1 mm onto a floor and onto each other, of a soft material (E 1.2e5 Pa): settled
    after the first run, both contacts deeper than 1 % of the bounding diameter; a second run of 10 steps."""
    edge, gap = 0.1, 0.001
    return ("atom_style polyhedron\natom_modify map array sort 0 0\nboundary f f f\nnewton off\n"
            "communicate single vel yes\nunits si\nregion box block -0.5 0.5 -0.5 0.5 -0.1 0.5\ncreate_box 2 box\n"
            "fix m1 all property/global youngsModulus peratomtype 1.2e5 1.2e5\n"
            "fix m2 all property/global poissonsRatio peratomtype 0.3 0.3\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.3 0.3 0.3 0.3\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n"
            "fix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
            "file ${SHAPES}/cube.stl scale 0.1\n"
            f"pair_style {pair_style}\npair_coeff * *\n"
            f"create_polyhedron cube 0 0 {edge / 2 + gap!r}\ncreate_polyhedron cube 0 0 {1.5 * edge + 2 * gap!r}\n"
            "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\ntimestep 1e-4\n"
            "variable zb equal z[1]\nvariable zt equal z[2]\n"
            "thermo_style custom step ke v_zb v_zt\nthermo_modify format float %.10g\nthermo 2000\n"
            "run 12000\nrun 10\n")


def check_settled_stack(result):
    """Both contacts of settled_stack_deck deeper than 1 % of the bounding diameter, and no warning of violent
    overlaps at the second run."""
    assert result.returncode == 0, result.output[-3000:]
    rows = result.thermo("Step", "v_zb", "v_zt")
    edge = 0.1
    bottom, top, diameter = rows["v_zb"][-1], rows["v_zt"][-1], edge * 3 ** 0.5
    wall_depth, pair_depth = edge / 2 - bottom, bottom + edge - top
    print(f"settled: wall contact {wall_depth / diameter:.2%}, pair contact {pair_depth / diameter:.2%} of the "
          "bounding diameter")
    assert wall_depth > 0.01 * diameter and pair_depth > 0.01 * diameter, (wall_depth, pair_depth)
    warnings = [w for w in result.warning_lines() if "violently" in w]
    assert not warnings, warnings


def test_settled_deep_contacts_give_no_warning_at_a_later_run(run_deck):
    """A settled stack of a soft material rests deeper than 1 % of the bounding diameter, as a tutorial's bed of
    E 5e6 Pa does at its bottom. The next run used to warn that pair and wall contacts 'will be pushed apart
    violently' (at every later run of such a deck); they were in contact at the step before and carry their
    load, so neither warns now. (test_gpu.py runs the same with the GPU style.)"""
    check_settled_stack(run_deck(settled_stack_deck("polyhedral/volumetric")))


def test_settled_deep_contacts_give_no_warning_after_a_restart(run_deck, tmp_path):
    """The settled stack written to a restart file and read back: its contacts' history comes back with it (the
    pair's touch flags, the wall's spring), so the resumed run, its contacts as deep, does not warn either."""
    deck = settled_stack_deck("polyhedral/volumetric").replace("run 10\n", "write_restart stack.restart\n")
    first = run_deck(deck, workdir=tmp_path / "first")
    assert first.returncode == 0, first.output[-3000:]
    body = deck[deck.index("fix m1 "):]
    resumed = ("atom_modify map array sort 0 0\nnewton off\ncommunicate single vel yes\n"
               "read_restart ../first/stack.restart\n" + body[:body.index("create_polyhedron")] +
               body[body.index("fix floor"):body.index("run 12000")] + "run 10\n")
    check_settled_stack(run_deck(resumed, workdir=tmp_path / "second"))


def test_overlap_warning_on_two_ranks(run_deck):
    deck = two_cubes_deck(gap=-0.005).replace("units si\n", "units si\nprocessors 2 1 1\n")
    result = run_deck(deck + "run 10\n", nprocs=2)
    assert result.returncode == 0, result.output
    warnings = [w for w in result.warning_lines() if "overlapping particle pairs" in w]
    assert len(warnings) == 1 and "1 of 1 overlapping" in warnings[0], result.output


@pytest.mark.parametrize("line, expected", [
    (template_line("${SHAPES}/cube.stl", " scale abc"),
     "Fix particletemplate/polyhedron (id t): 'scale' needs a finite number, got 'abc'"),
    ("fix t all particletemplate/polyhedron 15485863 atom_type 1 density constant heavy file ${SHAPES}/cube.stl\n",
     "Fix particletemplate/polyhedron (id t): 'density constant' needs a finite number, got 'heavy'"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 vel 0 0 fast\n",
     "create_polyhedron: 'vel' needs a finite number, got 'fast'"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 omega 1 x 0\n",
     "create_polyhedron: 'omega' needs a finite number, got 'x'"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 quat 1 0 0 zero\n",
     "create_polyhedron: 'quat' needs a finite number, got 'zero'"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 half 0.5\n",
     "create_polyhedron: position y needs a finite number, got 'half'"),
])
def test_bad_number_names_its_keyword(run_deck, line, expected):
    result = run_deck(BOX + line)
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert expected in errors[0], errors[0]


def test_settled_bed_of_non_convex_particles_gives_no_overlap_warning(run_deck, tmp_path):
    """tests/data/settled_bed_N2000.data (2000 Schoenhardt polyhedra at rest) read by examples/gravity_packing's
    deck: one contact per pair, and for a pair touching at spots a particle size apart its extent along the normal
    is the spots' spread, millimetres for a volume of 3e-16 m^3 (tools/settled_bed_contacts.py). 723 of its 5385
    overlapping pairs had such depths above 1 % of the bounding diameter, and the set-up used to warn that they
    would be pushed apart violently; they hold far less than 1 % of a cube that deep, and gave no warning since;
    the pair style's depth is now also capped at 3 V / A, which leaves none of them above 1 % (the cubes pushed
    5 mm into each other above still warn)."""
    import pathlib
    root = pathlib.Path(__file__).resolve().parent.parent
    deck = (root / "examples" / "gravity_packing" / "in.packing").read_text()
    result = run_deck(deck, workdir=tmp_path, variables={
        "N": 2000, "wall": 1, "steps": 10, "M": 10, "final": 0, "count": 1,
        "data": root / "tests" / "data" / "settled_bed_N2000.data"})
    assert result.returncode == 0, result.output[-3000:]
    assert max(result.thermo("c_contacts")["c_contacts"]) > 5000
    warnings = [w for w in result.warning_lines() if "overlapping particle pairs" in w]
    assert not warnings, warnings


MATERIALS_2 = ("fix m1 all property/global youngsModulus peratomtype {E} {E}\n"
               "fix m2 all property/global poissonsRatio peratomtype 0.3 0.3\n"
               "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
               "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n")
CUBE_PAIR = (template_line("${SHAPES}/cube.stl", " scale 0.1") + "pair_style polyhedral/volumetric\npair_coeff * *\n")
MESH = "fix mp all mesh/surface file ${SHAPES}/cube.stl type 2\n"
CONTACT_BOX = BOX.replace("region", "newton off\ncommunicate single vel yes\nregion")  # what the pair style needs
WALL = "fix w all wall/polyhedral "


def data_file(density="2500", quaternion="1 0 0 0", shape="1"):
    """Two cubes in a data file of atom_style polyhedron (atom-ID type shape density x y z quatw quati quatj
    quatk), the first with the columns given."""
    return ("LAMMPS data file\n\n2 atoms\n2 atom types\n\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms\n\n"
            f"1 1 {shape} {density} 0.5 0.5 0.5 {quaternion} 0 0 0\n2 1 1 2500 0.7 0.5 0.5 1 0 0 0 0 0 0\n")


# Input each of which ran without a word before, with wrong results: a doubled wall force, a wall replaced or
# ignored, a wall at infinity, NaN velocities, a truncated number, a setting that the next run overwrote, or the
# last of two values taken.
@pytest.mark.parametrize("line, expected", [
    (MESH + WALL + "mesh n_meshes 2 meshes mp mp\n", "mesh 'mp' is listed twice"),
    (MESH + WALL + "mesh n_meshes 1 meshes mp mesh n_meshes 1 meshes mp\n", "mesh 'mp' is listed twice"),
    (WALL + "primitive type 2 zplane 0.0 primitive type 2 zplane 0.5\n", "one 'primitive' a fix"),
    (WALL + "primitive type 2 zcylinder 0.3 0.5 0.5 primitive type 2 zplane 0.0\n", "one 'primitive' a fix"),
    (WALL + "primitive type 2 zplane 1e400\n", "zplane needs a finite number, got '1e400'"),
    (WALL + "primitive type 2 zcylinder 1e400 0.5 0.5\n", "zcylinder R needs a finite number, got '1e400'"),
    (WALL + "primitive type 2 zcylinder 0.3 0.5 1e400\n", "zcylinder CY needs a finite number, got '1e400'"),
    (MESH + WALL + "mesh n_meshes 1 meshes mp thickness 1e400\n", "thickness needs a finite number, got '1e400'"),
    (WALL + "primitive type 2 zplane 0.0 thickness 0.01\n", "'thickness' and 'closed_side' are for mesh walls"),
    (WALL + "closed_side inside primitive type 2 zplane 0.0\n", "'thickness' and 'closed_side' are for mesh walls"),
    (WALL + "primitive type 2 zplane 0.0 sagitta 0.1\n", "'sagitta' is for 'primitive ... zcylinder' walls"),
    (CONTACT_BOX + MATERIALS_2.format(E="1e400") + CUBE_PAIR + "create_polyhedron t 0.5 0.5 0.5\nrun 0\n",
     "youngsModulus must be a finite number > 0"),
    ("fix ct all check/timestep/polyhedral 1 inf 0.1\n", "the two fractions must be finite positive numbers"),
    ("fix ct all check/timestep/polyhedral 4294967297 0.1 0.1\n", "nevery must be a positive integer"),
    (template_line("${SHAPES}/cube.stl", " scale 0.1").replace("1000", "1e-320"),
     "density 9.99989e-321 gives the shape (volume 0.001) no finite positive mass and inertia"),
    (template_line("${SHAPES}/cube.stl", " scale 10").replace("1000", "1e306"),
     "density 1e+306 gives the shape (volume 1000) no finite positive mass and inertia"),
    (CONTACT_BOX + MATERIALS_2.format(E="1e7") + CUBE_PAIR +
     "create_polyhedron t 0.5 0.5 0.5\nset atom 1 density 1e400\nrun 0\n",
     "Particle 1: density inf gives shape 1"),
    (CUBE_PAIR + "create_polyhedron t 0.5 0.5 0.5\nset atom 1 diameter 0.5\n", "Set diameter: a polyhedron's size"),
    (CUBE_PAIR + "create_polyhedron t 0.5 0.5 0.5\nset atom 1 mass 5\n", "Set mass: a polyhedron's mass"),
    (template_line("${SHAPES}/cube.stl", " file ${SHAPES}/rock_40.obj"), "keyword 'file' given twice"),
    (template_line("${SHAPES}/cube.stl", " scale 0.1 scale 0.2"), "keyword 'scale' given twice"),
    (template_line("${SHAPES}/cube.stl", " density constant 3000"), "keyword 'density' given twice"),
    ("pair_style polyhedral/volumetric tangential history tangential off\n", "keyword 'tangential' given twice"),
    (template_line("${SHAPES}/cube.stl") + "create_polyhedron t 0.5 0.5 0.5 vel 1 0 0 vel 0 0 0\n",
     "create_polyhedron: 'vel' given twice"),
])
def test_input_that_gave_wrong_results_silently_is_an_error(run_deck, line, expected):
    result = run_deck(line if line.startswith("atom_style") else BOX + line)
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1, result.output
    assert expected in errors[0], errors[0]


@pytest.mark.parametrize("columns, expected", [
    ({"density": "1e400"}, "Invalid density in Atoms section of data file (must be a finite number > 0)"),
    ({"density": "2500x"}, "Invalid density in Atoms section of data file (must be a finite number > 0)"),
    ({"shape": "1.7"}, "Invalid shape in Atoms section of data file (must be an integer >= 1)"),
    ({"quaternion": "1e400 0 0 0"}, "Invalid quaternion in Atoms section of data file (four finite numbers)"),
    ({"quaternion": "0 0 0 0"}, "Invalid quaternion in Atoms section of data file (all zero)"),
])
def test_bad_data_file_column_is_an_error(run_deck, tmp_path, columns, expected):
    """read_data takes the package's columns whole and finite: atof read "2500x" as 2500 and "1.7" as shape 1,
    and an infinite density or quaternion gave NaN velocities."""
    (tmp_path / "bad.data").write_text(data_file(**columns))
    deck = ("atom_style polyhedron\natom_modify map array sort 0 0\nboundary f f f\n"
            f"read_data {tmp_path / 'bad.data'}\n" + template_line("${SHAPES}/cube.stl", " scale 0.1") + "run 0\n")
    result = run_deck(deck)
    assert result.returncode != 0
    assert any(expected in line for line in result.error_lines()), result.output


def test_huge_and_tiny_quaternions_keep_their_orientation(run_deck, tmp_path):
    """A quaternion's size does not matter, even near the ends of the double range: 1e200 1e200 0 0 (whose
    squares overflow) is a quarter turn about x, w = i = 0.7071, from a data file, and so is 1e-200 1e-200 0 0 (whose
    squares vanish) from create_polyhedron; they came out as the identity, or an error that it was zero."""
    (tmp_path / "big.data").write_text(data_file(quaternion="1e200 1e200 0 0"))
    for source in (f"read_data {tmp_path / 'big.data'}\n" + template_line("${SHAPES}/cube.stl", " scale 0.1"),
                   BOX + template_line("${SHAPES}/cube.stl", " scale 0.1") +
                   "create_polyhedron t 0.5 0.5 0.5 quat 1e-200 1e-200 0 0\n"):
        deck = ("atom_style polyhedron\natom_modify map array sort 0 0\nboundary f f f\n" if "read_data" in source
                else "") + source + ("compute q all property/polyhedron quatw quati quatj quatk\n"
                                     "dump d all custom 1 q.txt id c_q[1] c_q[2] c_q[3] c_q[4]\n"
                                     'dump_modify d format "%d %.17g %.17g %.17g %.17g"\nrun 0\n')
        result = run_deck(deck, workdir=tmp_path / ("data" if "read_data" in source else "create"))
        assert result.returncode == 0, result.output
        _, rows = decks.read_dump(result.workdir / "q.txt")
        assert rows[1][1:] == pytest.approx([0.5 ** 0.5, 0.5 ** 0.5, 0.0, 0.0], abs=1e-15), rows
