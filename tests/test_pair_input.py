"""pair_style polyhedral/volumetric: bad input gives a clear ERROR line, like pair_style gran."""
import pytest

import decks

MATERIALS = {
    "youngsModulus": "fix m1 all property/global youngsModulus peratomtype 5e6\n",
    "poissonsRatio": "fix m2 all property/global poissonsRatio peratomtype 0.25\n",
    "coefficientRestitution": "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n",
    "coefficientFriction": "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n",
}


def deck(pair="pair_style polyhedral/volumetric\npair_coeff * *\n", leave_out=(), header=None, extra=""):
    text = header or (decks.header(boundary="f f f") + "neigh_modify delay 0\n")
    text += "".join(line for name, line in MATERIALS.items() if name not in leave_out)
    text += decks.template("cube", "cube.stl", scale=0.1)
    text += pair + "create_polyhedron cube 0.5 0.5 0.5\nfix integrate all nve/polyhedron\n" + extra + "run 1\n"
    return text


@pytest.mark.parametrize("missing", list(MATERIALS))
def test_missing_material_is_reported_like_pair_gran(run_deck, missing):
    result = run_deck(deck(leave_out=(missing,)))
    assert result.returncode != 0
    assert any(f"Could not locate a fix/property storing value(s) for {missing} as requested by "
               "polyhedral/volumetric" in line for line in result.error_lines()), result.output


def test_scene_needs_only_the_materials_its_model_uses(run_deck):
    """tangential off needs no friction, damping off no restitution."""
    result = run_deck(deck(pair="pair_style polyhedral/volumetric tangential off damping off\npair_coeff * *\n",
                           leave_out=("coefficientRestitution", "coefficientFriction")))
    assert result.returncode == 0, result.output


@pytest.mark.parametrize("pair, expected", [
    ("pair_style polyhedral/volumetric rolling on\npair_coeff * *\n", "unknown keyword 'rolling'"),
    ("pair_style polyhedral/volumetric tangential sometimes\npair_coeff * *\n", "invalid value 'sometimes' for 'tangential'"),
    ("pair_style polyhedral/volumetric damping\npair_coeff * *\n", "keyword 'damping' needs a value"),
    ("pair_style polyhedral/volumetric precision quad\npair_coeff * *\n", "invalid value 'quad' for 'precision'"),
    ("pair_style polyhedral/volumetric crossing_cache yes\npair_coeff * *\n", "invalid value 'yes' for 'crossing_cache'"),
    ("pair_style polyhedral/volumetric parting_search 1\npair_coeff * *\n", "invalid value '1' for 'parting_search'"),
    ("pair_style polyhedral/volumetric\npair_coeff 1 1 0.5\n", "use 'pair_coeff * *'"),
])
def test_bad_pair_arguments(run_deck, pair, expected):
    result = run_deck(deck(pair=pair))
    assert result.returncode != 0
    assert any(expected in line for line in result.error_lines()), result.output


def test_bad_material_values(run_deck):
    text = deck().replace("coefficientRestitution peratomtypepair 1 0.5", "coefficientRestitution peratomtypepair 1 1.5")
    result = run_deck(text)
    assert result.returncode != 0
    assert any("coefficientRestitution must be in (0, 1]" in line for line in result.error_lines()), result.output


def test_wrong_atom_style(run_deck):
    header = ("atom_style sphere\natom_modify sort 0 0\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
              "region box block 0 1 0 1 0 1\ncreate_box 1 box\n")
    text = (header + "".join(MATERIALS.values()) + "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "create_atoms 1 single 0.5 0.5 0.5\nrun 1\n")
    result = run_deck(text)
    assert result.returncode != 0
    assert any("requires atom_style polyhedron" in line for line in result.error_lines()), result.output


def test_missing_ghost_velocities_and_newton(run_deck):
    no_vel = deck().replace("communicate single vel yes\n", "")
    result = run_deck(no_vel)
    assert result.returncode != 0
    assert any("communicate single vel yes" in line for line in result.error_lines()), result.output
    newton_on = deck().replace("newton off\n", "newton on\n")
    result = run_deck(newton_on)
    assert result.returncode != 0
    assert any("requires newton pair off" in line for line in result.error_lines()), result.output


def test_compute_needs_the_pair_style(run_deck):
    text = (decks.header() + decks.template("cube", "cube.stl", scale=0.1) +
            "create_polyhedron cube 0.5 0.5 0.5\ncompute c all pair/polyhedral/local\n"
            "thermo_style custom step c_c\nrun 0\n")
    result = run_deck(text)
    assert result.returncode != 0
    assert any("requires pair_style polyhedral/volumetric" in line for line in result.error_lines()), result.output


def test_contact_records_follow_the_output_schedule(run_deck):
    """Contacts are recorded only on the steps output asks for; fix print schedules its own steps too
    (LIGGGHTS' timeflag mechanism), so a count printed on step 3, off the thermo schedule, is current."""
    extra = ("compute c all pair/polyhedral/local\nthermo_style custom step c_c\nthermo 10\n"
             "variable n equal c_c\nfix p all print 3 \"contacts at step 3: ${n}\"\n")
    result = run_deck(deck(extra=extra).replace("run 1\n", "run 5\n"))
    assert result.returncode == 0, result.output
    assert "contacts at step 3: 0" in result.output, result.output


def test_two_contact_computes_on_different_schedules(run_deck):
    """Each compute pair/polyhedral/local gets its contacts on its own output steps (thermo every 10,
    a dump every 7)."""
    extra = ("compute c1 all pair/polyhedral/local\ncompute c2 all pair/polyhedral/local\n"
             "thermo_style custom step c_c1\nthermo 10\n"
             "dump d all local 7 contacts.txt c_c2[1] c_c2[2]\n")
    result = run_deck(deck(extra=extra).replace("run 1\n", "run 30\n"))
    assert result.returncode == 0, result.output[-2000:]
    assert (result.workdir / "contacts.txt").read_text().count("ITEM: TIMESTEP") == 5  # steps 0, 7, 14, 21, 28


def test_large_time_step_is_flagged(run_deck):
    text = deck(extra="timestep 1e-2\n")
    result = run_deck(text)
    assert result.returncode == 0, result.output
    assert any("Rayleigh time" in line for line in result.warning_lines()), result.output
    quiet = run_deck(deck(extra="timestep 1e-6\n"))
    assert not any("Rayleigh time" in line for line in quiet.warning_lines()), quiet.output


def test_no_false_time_step_warning_after_read_data(run_deck, tmp_path):
    """Particles read from a data file get their masses when atom_style polyhedron initialises, after
    the pair style's time-step check; the check uses the shapes, so it does not see zero masses (it
    used to warn of a Rayleigh time of 0)."""
    first = run_deck(deck() + "write_data state.data\n", workdir=tmp_path / "first")
    assert first.returncode == 0, first.output
    second = run_deck(deck().replace("create_polyhedron cube 0.5 0.5 0.5\n", "").replace(
        "create_box 1 box\n", "").replace("region box block 0.0 1.0 0.0 1.0 0.0 1.0\n", "read_data ../first/state.data\n"),
        workdir=tmp_path / "second")
    assert second.returncode == 0, second.output
    assert not [w for w in second.warning_lines() if "time step" in w], second.warning_lines()


# LIGGGHTS' contact-model keywords as a converted deck keeps them (issue 16).
LIGGGHTS_PAIR = "pair_style polyhedral/volumetric model hertz tangential history cohesion off rolling_friction off " \
                "surface default\npair_coeff * *\n"
FALL = ("fix gravity all gravity 9.81 vector 0 0 -1\n"
        "thermo_style custom step ke\nthermo_modify format float %.15g\nthermo 500\nrun 3000\n")


def wall_deck(pair, wall):
    """Two cubes dropped onto a plane wall and onto each other: pair and wall contacts, friction, damping."""
    text = decks.header(boundary="f f f", ntypes=1) + "neigh_modify delay 0\n" + "".join(MATERIALS.values())
    text += decks.template("cube", "cube.stl", scale=0.1)
    text += pair + ("create_polyhedron cube 0.5 0.5 0.08 quat 0.9 0.1 0.2 0.3\n"
                    "create_polyhedron cube 0.53 0.5 0.24 quat 0.8 -0.3 0.1 0.2\n"
                    "fix integrate all nve/polyhedron\n" + wall + "timestep 1e-5\n" + FALL)
    return text


def test_liggghts_model_keywords_are_accepted(run_deck, tmp_path):
    """`model hertz tangential history cohesion off rolling_friction off surface default` on the pair style and
    `model hertz tangential history` on fix wall/polyhedral say what the volumetric law does anyway: the run is
    the plain one, bit for bit."""
    plain = run_deck(wall_deck("pair_style polyhedral/volumetric\npair_coeff * *\n",
                               "fix wall all wall/polyhedral primitive type 1 zplane 0.0\n"), workdir=tmp_path / "a")
    kept = run_deck(wall_deck(LIGGGHTS_PAIR, "fix wall all wall/polyhedral model hertz tangential history "
                                             "primitive type 1 zplane 0.0\n"), workdir=tmp_path / "b")
    assert plain.returncode == 0 and kept.returncode == 0, plain.output[-2000:] + kept.output[-2000:]
    a, b = plain.thermo("Step", "KinEng"), kept.thermo("Step", "KinEng")
    assert len(a["Step"]) == 7 and max(a["KinEng"]) > 0.0
    assert a == b


@pytest.mark.parametrize("keywords, expected", [
    ("model hooke", "model hooke: the volumetric law is Hertz-Mindlin generalised to overlap volumes and has no "
                    "linear (Hooke) variant; use model hertz"),
    ("model hertz/stiffness", "has no such variant; use model hertz"),
    ("tangential no_history", "tangential no_history (a viscous tangential force without a spring) has no counterpart"),
    ("rolling_friction cdt", "rolling_friction cdt: polyhedra roll over their edges and vertices, so their shape "
                             "resists rolling"),
    ("cohesion sjkr2", "cohesion sjkr2 is not available for polyhedra"),
    ("surface multicontact", "surface multicontact has no counterpart here"),
])
@pytest.mark.parametrize("where", ["pair", "wall"])
def test_liggghts_model_keywords_without_a_meaning_here_are_errors(run_deck, keywords, expected, where):
    """Those that would change the law, or ask for one not provided, stop with an ERROR naming the alternative,
    on the pair style and on the wall fix alike."""
    if where == "pair":
        text = wall_deck(f"pair_style polyhedral/volumetric {keywords}\npair_coeff * *\n",
                         "fix wall all wall/polyhedral primitive type 1 zplane 0.0\n")
        caller = "Pair polyhedral/volumetric"
    else:
        text = wall_deck("pair_style polyhedral/volumetric\npair_coeff * *\n",
                         f"fix wall all wall/polyhedral {keywords} primitive type 1 zplane 0.0\n")
        caller = "Fix wall/polyhedral"
    result = run_deck(text)
    assert result.returncode != 0
    assert any(line.startswith(f"ERROR: {caller}: ") and expected in line for line in result.error_lines()), \
        result.output[-3000:]
