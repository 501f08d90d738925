"""fix check/timestep/polyhedral: LIGGGHTS' fix check/timestep/gran for polyhedra (issue 16), checked against
LIGGGHTS' own fix on spheres of the same volume, mass, material and speeds."""
import math

import pytest

import decks

SPEEDS = [(1.0, 0.0, 0.0), (0.0, -2.0, 0.0), (0.0, 0.0, 0.5)]
SPOTS = [(0.2, 0.2, 0.2), (0.5, 0.5, 0.5), (0.8, 0.8, 0.8)]
MATERIALS = ("fix m1 all property/global youngsModulus peratomtype 5e6\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.45\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n")
OUTPUT = "thermo_style custom step f_ts[1] f_ts[2] f_ts[3]\nthermo_modify format float %.15g norm no\nthermo 1\n"


def polyhedra(extra="", check="fix ts all check/timestep/polyhedral 1 0.1 0.1\n"):
    """Three fine icospheres of diameter 2 cm (volume-equivalent, icosphere_1280 has volume pi/6) flying apart."""
    lines = [decks.HEADER.format(boundary="f f f", lo=0.0, hi=1.0, ntypes=1, processors=""), "neighbor 0.002 bin\n",
             MATERIALS, decks.template("ball", "icosphere_1280.off", scale=0.02).replace("atom_type 2", "atom_type 1"),
             "pair_style polyhedral/volumetric\npair_coeff * *\ntimestep 1e-5\n"]
    for (x, y, z), (vx, vy, vz) in zip(SPOTS, SPEEDS):
        lines.append(f"create_polyhedron ball {x} {y} {z} vel {vx} {vy} {vz}\n")
    lines += ["fix integrate all nve/polyhedron\n", extra, check, OUTPUT, "run 2\n"]
    return "".join(lines)


def spheres(check="fix ts all check/timestep/gran 1 0.1 0.1\n"):
    """The same scene as LIGGGHTS spheres (atom_style granular, pair gran hertz), its own timestep fix."""
    lines = ["atom_style granular\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
             "units si\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\nneighbor 0.002 bin\n", MATERIALS,
             "pair_style gran model hertz tangential history\npair_coeff * *\ntimestep 1e-5\n"]
    for n, ((x, y, z), (vx, vy, vz)) in enumerate(zip(SPOTS, SPEEDS), start=1):
        lines.append(f"create_atoms 1 single {x} {y} {z}\n")
        lines.append(f"set atom {n} diameter 0.02 density 2500 vx {vx} vy {vy} vz {vz}\n")
    lines += ["fix integrate all nve/sphere\n", check, OUTPUT, "run 2\n"]
    return "".join(lines)


def last_row(result):
    table = result.thermo("Step", "f_ts[1]", "f_ts[2]", "f_ts[3]")
    assert table["Step"][-1] == 2.0, result.output[-2000:]
    return [table[c][-1] for c in ("f_ts[1]", "f_ts[2]", "f_ts[3]")]


def test_fractions_match_liggghts_on_spheres(run_deck, tmp_path):
    """The Rayleigh, Hertz and skin fractions of three fine icospheres equal those LIGGGHTS' fix
    check/timestep/gran prints for spheres of the same volume, density, material and velocities (the
    volume-equivalent radius is the sphere's radius; the speeds are the same), to 1e-9; and they are
    the Rayleigh fraction is the formula's for the sphere of the particles' volume."""
    ours = run_deck(polyhedra(), workdir=tmp_path / "polyhedra")
    theirs = run_deck(spheres(), workdir=tmp_path / "spheres")
    assert ours.returncode == 0, ours.output[-3000:]
    assert theirs.returncode == 0, theirs.output[-3000:]
    a, b = last_row(ours), last_row(theirs)
    print(f"polyhedra {a}, LIGGGHTS spheres {b}")
    for x, y in zip(a, b):
        assert y > 0.0 and abs(x - y) <= 1e-9 * y, (a, b)
    # Rayleigh time of a 1 cm radius, 2500 kg/m^3, E 5 MPa, nu 0.45 particle, by its formula.
    shear = 5e6 / (2.0 * 1.45)
    rayleigh = math.pi * 0.01 * math.sqrt(2500.0 / shear) / (0.1631 * 0.45 + 0.8766)
    assert a[0] == pytest.approx(1e-5 / rayleigh, rel=1e-9)
    # The speeds: 2 x 2 m/s x 1e-5 s against the 2 mm skin.
    assert a[2] == pytest.approx(4.0 * 1e-5 / 0.002, rel=1e-12)


def test_moving_mesh_speeds_up_the_hertz_estimate(run_deck, tmp_path):
    """With a mesh wall moving at 3 m/s (fix move/mesh), the approach speed is the particles' fastest 2 m/s
    plus the wall's, 5 m/s, instead of twice the fastest, 4 m/s: the Hertz fraction grows by (5/4)^(1/5),
    as in LIGGGHTS' fix."""
    mesh = tmp_path / "plate.stl"
    mesh.write_text("solid plate\n"
                    " facet normal 0 0 1\n  outer loop\n   vertex 0.05 0.05 0.02\n   vertex 0.95 0.05 0.02\n"
                    "   vertex 0.95 0.95 0.02\n  endloop\n endfacet\n"
                    " facet normal 0 0 1\n  outer loop\n   vertex 0.05 0.05 0.02\n   vertex 0.95 0.95 0.02\n"
                    "   vertex 0.05 0.95 0.02\n  endloop\n endfacet\nendsolid plate\n")
    wall = (f"fix plate all mesh/surface file {mesh} type 1\n"
            "fix move all move/mesh mesh plate linear 3.0 0.0 0.0\n"
            "fix wall all wall/polyhedral mesh n_meshes 1 meshes plate\n")
    still = run_deck(polyhedra(), workdir=tmp_path / "still")
    moving = run_deck(polyhedra(extra=wall), workdir=tmp_path / "moving")
    assert still.returncode == 0, still.output[-3000:]
    assert moving.returncode == 0, moving.output[-3000:]
    a, b = last_row(still), last_row(moving)
    assert b[0] == pytest.approx(a[0], rel=1e-12)
    assert b[1] / a[1] == pytest.approx((5.0 / 4.0) ** 0.2, rel=1e-9)
    assert b[2] / a[2] == pytest.approx(5.0 / 4.0, rel=1e-12)


def test_warns_as_liggghts_does(run_deck, tmp_path):
    """Limits below the fractions: a WARNING line for the Rayleigh and for the Hertz time; warn no silences."""
    loud = run_deck(polyhedra(check="fix ts all check/timestep/polyhedral 1 0.001 0.001\n"), workdir=tmp_path / "loud")
    quiet = run_deck(polyhedra(check="fix ts all check/timestep/polyhedral 1 0.001 0.001 warn no\n"),
                     workdir=tmp_path / "quiet")
    assert loud.returncode == 0 and quiet.returncode == 0, loud.output[-2000:] + quiet.output[-2000:]
    warnings = [line for line in loud.warning_lines() if "check/timestep/polyhedral" in line]
    assert any("Rayleigh time" in line for line in warnings), warnings
    assert any("Hertz time" in line for line in warnings), warnings
    assert not [line for line in quiet.warning_lines() if "check/timestep/polyhedral" in line]


@pytest.mark.parametrize("check,expected", [
    ("fix ts all check/timestep/polyhedral 1 0.1\n", "expected 'nevery fraction_rayleigh fraction_hertz"),
    ("fix ts all check/timestep/polyhedral 0 0.1 0.1\n", "nevery must be a positive integer"),
    ("fix ts all check/timestep/polyhedral 1 0.1 x\n", "the two fractions must be finite positive numbers"),
    ("fix ts all check/timestep/polyhedral 1 0.1 0.1 warn maybe\n", "the only one is 'warn yes|no'"),
    ("fix ts all check/timestep/gran 1 0.1 0.1\n", "check/timestep/polyhedral")])
def test_bad_input_is_a_clear_error(run_deck, tmp_path, check, expected):
    """Wrong arguments, and LIGGGHTS' sphere fix under atom_style polyhedron, stop with an ERROR naming the fix
    (and, for the sphere fix, its polyhedral replacement)."""
    result = run_deck(polyhedra(check=check), workdir=tmp_path / "bad")
    assert result.returncode != 0
    assert any(expected in line for line in result.error_lines()), result.output[-3000:]
