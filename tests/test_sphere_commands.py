"""LIGGGHTS commands that assume spheres stop with an ERROR: under atom_style polyhedron (issue 13),
naming the polyhedral replacement (src/polyhedral_guard.cpp); the volume-equivalent radius of
compute property/polyhedron."""
import math

import pytest

import decks

BOX = decks.header(boundary="f f f", ntypes=1)
MATERIALS = ("fix m1 all property/global youngsModulus peratomtype 1e7\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.3\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.8\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n")
CUBE = decks.template("cube", "cube.stl", scale=0.2) + "create_polyhedron cube 0.5 0.5 0.5\n"
TEMPLATE_FIX = "particletemplate/polyhedron"


@pytest.mark.parametrize("lines, replacement", [
    ("fix wall all wall/gran model hertz tangential history primitive type 1 zplane 0.0\n",
     "fix wall/polyhedral"),
    ("fix mesh all mesh/surface file ${SHAPES}/cube.stl type 1 scale 0.5\n"
     "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes mesh\n",
     "fix wall/polyhedral"),
    ("variable d equal 0.3\nfix grow all adapt 1 atom diameter v_d\n",
     "'scale' keyword of fix " + TEMPLATE_FIX),
    ("fix euler all ave/euler nevery 10 cell_size_relative 4 parallel no\n",
     "compute property/polyhedron volume"),
    ("fix euler all ave/euler/stress nevery 10 cell_size_relative 4 parallel no\n",
     "compute property/polyhedron volume"),
    ("fix pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.01\n",
     "use fix " + TEMPLATE_FIX),
    ("fix pts all particletemplate/multisphere 15485863 atom_type 1 density constant 2500 nspheres 2 "
     "ntry 1000000 spheres 0 0 0 0.01 0.01 0 0 0.01 type 1\n",
     "use fix " + TEMPLATE_FIX),
    ("fix pts all particletemplate/multiplespheres 15485863 atom_type 1 density constant 2500 nspheres 2 "
     "ntry 1000000 spheres 0 0 0 0.01 0.01 0 0 0.01\n",
     "use fix " + TEMPLATE_FIX),
])
def test_sphere_command_is_an_error_naming_the_replacement(run_deck, lines, replacement):
    result = run_deck(BOX + MATERIALS + CUBE + lines + "run 1\n")
    assert result.returncode != 0, result.output[-2000:]
    errors = result.error_lines()
    assert len(errors) == 1 and replacement in errors[0], result.output[-2000:]


def test_sphere_template_feeding_an_insertion_stops_before_any_particle_is_made(run_deck):
    """A converted insertion deck: the sphere template is refused at its own line, before
    fix particledistribution/discrete and fix insert/pack can insert shapeless particles."""
    deck = (BOX + MATERIALS +
            "fix pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.01\n"
            "fix pdd all particledistribution/discrete 32452843 1 pts 1.0\n"
            "region ins block 0.1 0.9 0.1 0.9 0.1 0.9\n"
            "fix ins all insert/pack seed 49979687 distributiontemplate pdd insert_every once "
            "overlapcheck yes particles_in_region 10 region ins\n"
            "fix integrate all nve/polyhedron\nrun 1\n")
    result = run_deck(deck)
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1 and "fix particletemplate/sphere" in errors[0].lower(), result.output[-2000:]
    assert TEMPLATE_FIX in errors[0]
    assert "particledistribution/discrete" not in result.output  # the deck stopped at the template line


def test_guard_survives_clear_and_leaves_sphere_decks_alone(run_deck):
    """After `clear` the styles are registered again, the guard with them; fix wall/gran and fix
    adapt ... diameter still work for LIGGGHTS' own spheres, and fix adapt of other attributes
    is not refused under atom_style polyhedron."""
    sphere = ("atom_style granular\natom_modify map array sort 0 0\nboundary f f f\nnewton off\n"
              "communicate single vel yes\nunits si\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n" +
              MATERIALS + "pair_style gran model hertz tangential history\npair_coeff * *\n"
              "fix wall all wall/gran model hertz tangential history primitive type 1 zplane 0.0\n"
              "create_atoms 1 single 0.5 0.5 0.5\nset atom 1 diameter 0.1 density 2500\n"
              "variable d equal 0.12\nfix grow all adapt 1 atom diameter v_d\n"
              "fix integrate all nve/sphere\nrun 1\n")
    result = run_deck(sphere + "clear\n" + BOX + MATERIALS + CUBE +
                      "variable q equal 0\nfix other all adapt 1 atom charge v_q\n"
                      "fix wall all wall/gran model hertz tangential history primitive type 1 zplane 0.0\n")
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1 and "wall/polyhedral" in errors[0], result.output[-2000:]
    assert result.output.count("Loop time") == 1, result.output[-3000:]


def test_volume_equivalent_and_bounding_radius_of_a_cube(run_deck):
    edge = 0.2
    result = run_deck(BOX + CUBE +
                      "compute p all property/polyhedron radius_volume boundradius volume\n"
                      "fix integrate all nve/polyhedron\n"
                      "dump d all custom 1 radii.txt id radius c_p[1] c_p[2] c_p[3]\n"
                      'dump_modify d format "%d %.17g %.17g %.17g %.17g"\nrun 0\n')
    assert result.returncode == 0, result.output[-2000:]
    columns, rows = decks.read_dump(result.workdir / "radii.txt")
    _, radius, radius_volume, boundradius, volume = rows[1]
    assert volume == pytest.approx(edge ** 3, rel=1e-12)
    assert radius_volume == pytest.approx((3 / (4 * math.pi)) ** (1 / 3) * edge, rel=1e-12)
    # dump custom's `radius` is the bounding radius: half the cube's space diagonal.
    assert boundradius == pytest.approx(math.sqrt(3) / 2 * edge, rel=1e-9)
    assert radius == pytest.approx(boundradius, rel=1e-12)


def test_error_on_two_ranks_is_one_line(run_deck):
    result = run_deck(BOX + MATERIALS + CUBE +
                      "fix wall all wall/gran model hertz tangential history primitive type 1 zplane 0.0\n", nprocs=2)
    assert result.returncode != 0
    errors = result.error_lines()
    assert len(errors) == 1 and "fix wall/polyhedral" in errors[0], result.output[-2000:]
