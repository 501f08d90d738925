"""fix wall/polyhedral: plane walls (primitive xplane|yplane|zplane) with the volumetric contact law.

The overlap geometry (src/poly_halfspace.h) is tested against the reference clipping in
tests/test_overlap_geometry.py; here the fix as a user runs it: a cube at rest on a plane against
the closed form of the law and the weight, the same cube on a frozen particle floor, a cube on a
tilted plane sticking below the friction angle and sliding above it, bad input.
"""
import math

import numpy as np
import pytest

import decks

G = 9.81
EDGE, DENSITY, FRICTION = 0.02, 2500.0, 0.5
YOUNGS, POISSON = 1e7, 0.25


def scene(wall, pose, extra="", steps=30000, gravity="0 0 -1", dt=1e-5):
    """One cube (type 1) and a plane wall of material type 2; thermo: the cube's z and the wall fix's
    vector (force on the wall, contacts)."""
    return (decks.header(boundary="f f f", lo=-0.3, hi=0.3, ntypes=2) +
            "neighbor 0.002 bin\nneigh_modify delay 0\n"
            f"fix m1 all property/global youngsModulus peratomtype {YOUNGS} {YOUNGS}\n"
            f"fix m2 all property/global poissonsRatio peratomtype {POISSON} {POISSON}\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
            f"fix m4 all property/global coefficientFriction peratomtypepair 2 {FRICTION} {FRICTION} "
            f"{FRICTION} {FRICTION}\n" +
            decks.template("cube", "cube.stl", scale=EDGE, atom_type=1) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            f"create_polyhedron cube {pose}\n"
            "fix integrate all nve/polyhedron\n"
            f"fix gravity all gravity {G} vector {gravity}\n" + wall +
            "variable x equal x[1]\nvariable z equal z[1]\nvariable vx equal vx[1]\n"
            "thermo_style custom step v_x v_z v_vx f_floor[1] f_floor[2] f_floor[3] f_floor[4]\n"
            "thermo_modify format float %.15g\nthermo 1000\n"
            f"timestep {dt}\n" + extra + f"run {steps}\n")


def check_crosses_ranks(run_deck, tmp_path, deck, what):
    """The deck on one rank and on two (processors 2 1 1): the cube moves from x < 0 to x > 0 across the
    ranks' boundary, keeps its one wall contact throughout on two ranks, and follows the single-rank run
    to round-off."""
    one = run_deck(deck, workdir=tmp_path / "one")
    two = run_deck(deck.replace("boundary f f f\n", "processors 2 1 1\nboundary f f f\n"), nprocs=2,
                   workdir=tmp_path / "two")
    assert one.returncode == 0 and two.returncode == 0, one.output[-2000:] + two.output[-2000:]
    a, b = one.thermo("Step", "v_x", "f_floor[4]"), two.thermo("Step", "v_x", "f_floor[4]")
    assert a["v_x"][0] < 0 < a["v_x"][-1], a["v_x"]
    assert all(c == 1 for c in b["f_floor[4]"][1:])
    worst = max(abs(x - y) for x, y in zip(a["v_x"], b["v_x"]))
    print(f"\n{what} across ranks: x from {a['v_x'][0]:.4f} to {a['v_x'][-1]:.4f} m, largest 1 vs 2 rank "
          f"difference {worst:.1e} m")
    assert worst < 1e-12, worst


def static_depth(mass):
    """Closed form of the law for a flat face of area A sunk by delta into a plane: V = A delta,
    F = 4/(3 sqrt(pi)) E* sqrt(V delta) = 4/(3 sqrt(pi)) E* sqrt(A) delta, with E* of the two
    materials."""
    youngs_eff = 1.0 / (2.0 * (1.0 - POISSON ** 2) / YOUNGS)
    return mass * G / (4.0 / (3.0 * math.sqrt(math.pi)) * youngs_eff * EDGE)


@pytest.mark.parametrize("plane", ["zplane 0.0", "zplane -0.1"])
def test_cube_rests_on_a_plane_wall(run_deck, plane):
    position = float(plane.split()[1])
    result = run_deck(scene(f"fix floor all wall/polyhedral primitive type 2 {plane}\n",
                            f"0.01 -0.02 {position + EDGE / 2} quat {math.cos(0.3)} 0 0 {math.sin(0.3)}"))
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "v_z", "f_floor[3]", "f_floor[4]")
    mass = DENSITY * EDGE ** 3
    settled = [i for i, step in enumerate(table["Step"]) if step >= 10000]
    force = np.array(table["f_floor[3]"])[settled]
    depth = position + EDGE / 2 - np.array(table["v_z"])[settled]
    print(f"\ncube on {plane}: wall force / weight - 1 = {force.mean() / (mass * G) + 1:.2e}, "
          f"depth / closed form - 1 = {depth.mean() / static_depth(mass) - 1:.2e}, depth spread {np.ptp(depth):.1e} m")
    assert all(c == 1 for c in np.array(table["f_floor[4]"])[settled])
    assert abs(-force.mean() / (mass * G) - 1) < 0.01, force.mean()  # the wall is pushed down by mg
    assert abs(depth.mean() / static_depth(mass) - 1) < 0.01, depth.mean()
    assert np.ptp(depth) < 1e-3 * static_depth(mass), np.ptp(depth)


def test_xplane_and_yplane_walls_hold_from_either_side(run_deck):
    """Gravity along -x and +y: the cube rests in the corner of the xplane wall at -0.1 (from above)
    and the yplane wall at 0.1 (from below); frictionless, so each carries exactly its weight component
    (with friction the corner is statically indeterminate)."""
    tilt = math.radians(30.0)
    walls = ("fix floor all wall/polyhedral tangential off primitive type 2 xplane -0.1\n"
             "fix side all wall/polyhedral tangential off primitive type 2 yplane 0.1\n")
    deck = scene(walls, f"{-0.1 + EDGE / 2} {0.1 - EDGE / 2} 0", gravity=f"-{math.cos(tilt)} {math.sin(tilt)} 0")
    deck = deck.replace("f_floor[4]\n", "f_floor[4] f_side[2]\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "f_floor[1]", "f_side[2]")
    mass = DENSITY * EDGE ** 3
    assert abs(-table["f_floor[1]"][-1] / (mass * G * math.cos(tilt)) - 1) < 0.01, table["f_floor[1]"][-1]
    assert abs(table["f_side[2]"][-1] / (mass * G * math.sin(tilt)) - 1) < 0.01, table["f_side[2]"][-1]


@pytest.mark.parametrize("angle,pair_options,wall_options", [
    (20.0, "", ""), (35.0, "", ""),
    (20.0, " tangential off", "tangential history "),  # the wall's own switch, with its own friction table
], ids=["20deg", "35deg", "20deg-wall-friction-only"])
def test_cube_on_a_tilted_plane_sticks_or_slides(run_deck, angle, pair_options, wall_options):
    """As the block-on-slope test of tests/test_contact_physics.py, on a plane wall: gravity turns
    quasi-statically (0.1 s ramp after 0.05 s of settling) to `angle` from the wall normal, then holds
    for 0.45 s. tan(26.6 deg) = mu = 0.5: at 20 deg the cube must not creep (tangential spring of the
    particle's wall contact, kept per particle); at 35 deg it slides with a = g (sin - mu cos)."""
    deck = scene(f"fix floor all wall/polyhedral {wall_options}primitive type 2 zplane 0.0\n", f"0 0 {EDGE / 2}",
                 steps=5000).replace("pair_style polyhedral/volumetric\n", f"pair_style polyhedral/volumetric{pair_options}\n")
    deck += decks.tilted_gravity("all", angle) + "thermo 200\nrun 45000\n"
    result = run_deck(deck)
    assert result.returncode == 0, result.output[-3000:]
    check_stick_or_slide(result, angle, "")


def check_stick_or_slide(result, angle, label):
    """The cube under gravity turned to `angle`: no creep below the friction angle, a = g (sin - mu cos)
    above it (within 1% of mu). Returns the thermo table."""
    tilt = math.radians(angle)
    table = result.thermo("Step", "v_x", "v_vx")
    t = np.array(table["Step"]) * 1e-5
    x, vx = np.array(table["v_x"]), np.array(table["v_vx"])
    if math.tan(tilt) < FRICTION:
        # The end of the ramp leaves the cube rocking at ~1e-6 m/s, decaying twofold every ~20 ms
        # (measured); the window starts 0.3 s into the hold. The elastic deflection is ~3 um; 1 nm of
        # creep in 0.15 s would be a slipping contact.
        window = t >= 0.45
        print(f"\nsticks at {angle} deg{label}: x moves {np.ptp(x[window]):.2e} m over 0.15 s, "
              f"max speed {np.abs(vx[window]).max():.2e} m/s")
        assert np.ptp(x[window]) < 1e-9, np.ptp(x[window])
        assert np.abs(vx[window]).max() < 1e-7
    else:
        window = (t >= 0.17) & (t <= 0.3)
        acceleration = np.polyfit(t[window], vx[window], 1)[0]
        mu_effective = math.tan(tilt) - acceleration / (G * math.cos(tilt))
        print(f"\nslides at {angle} deg{label} from x = {x[0]:.3f} to {x[-1]:.3f} m: a = {acceleration:.5f} m/s^2, "
              f"expected {G * (math.sin(tilt) - FRICTION * math.cos(tilt)):.5f}, effective mu {mu_effective:.5f}")
        assert abs(mu_effective - FRICTION) < 0.01 * FRICTION, acceleration
    return table


@pytest.mark.parametrize("wall,message", [
    ("fix floor all wall/polyhedral primitive type 3 zplane 0\n", "wall type out of range"),
    ("fix floor all wall/polyhedral primitive type 2 zcone 0\n", "unknown primitive 'zcone'"),
    ("fix floor all wall/polyhedral sideways 1 primitive type 2 zplane 0\n", "unknown keyword 'sideways'"),
    ("fix floor all wall/polyhedral tangential maybe primitive type 2 zplane 0\n", "invalid value 'maybe'"),
    ("fix floor all wall/polyhedral tangential off\n", "no wall given"),
    ("fix floor all wall/polyhedral mesh n_meshes 1 meshes hopper\n", "mesh 'hopper' does not exist"),
])
def test_bad_wall_input_is_a_clear_error(run_deck, wall, message):
    result = run_deck(scene(wall, f"0 0 {EDGE / 2}", steps=10))
    assert result.returncode != 0
    assert any(message in line for line in result.error_lines()), result.output[-2000:]


def test_wall_needs_the_polyhedral_pair_style(run_deck):
    deck = scene("fix floor all wall/polyhedral primitive type 2 zplane 0\n", f"0 0 {EDGE / 2}", steps=10)
    deck = deck.replace("pair_style polyhedral/volumetric\npair_coeff * *\n", "")
    result = run_deck(deck)
    assert result.returncode != 0
    assert any("requires pair_style polyhedral/volumetric" in line for line in result.error_lines()), result.output


def restart_on_a_wall(run_deck, tmp_path, wall, x):
    """The cube held by friction with gravity at 20 deg on a wall (fix commands `wall`), restarted
    mid-hold. Returns the largest x difference between the resumed run and the unbroken one."""
    gravity = decks.held_gravity("all", 20.0)
    setup = scene(wall, f"{x} 0 {EDGE / 2}", steps=5000)
    ramp = decks.tilted_gravity("all", 20.0) + "run 10000\n"
    unbroken = run_deck(setup + ramp + "run 5000\n", workdir=tmp_path / "unbroken")
    first = run_deck(setup + ramp + "write_restart half.restart\n", workdir=tmp_path / "first")
    assert unbroken.returncode == 0 and first.returncode == 0, unbroken.output[-2000:] + first.output[-2000:]
    body = setup[setup.index("neighbor"):]
    body = body[:body.index("create_polyhedron")] + body[body.index("fix integrate"):]
    body = body.replace(f"fix gravity all gravity {G} vector 0 0 -1\n", gravity).replace("run 5000\n", "")
    resumed = ("atom_modify map array sort 0 0\nread_restart ../first/half.restart\nnewton off\n"
               "communicate single vel yes\n" + body + "run 5000\n")
    second = run_deck(resumed, workdir=tmp_path / "second")
    assert second.returncode == 0, second.output[-3000:]
    a, b = unbroken.thermo("Step", "v_x"), second.thermo("Step", "v_x")
    assert a["Step"][-len(b["Step"]):] == b["Step"]
    return np.abs(np.array(a["v_x"][-len(b["Step"]):]) - np.array(b["v_x"])).max()


def test_wall_history_survives_a_restart(run_deck, tmp_path):
    """The cube held by friction on a 20 deg tilted plane, restarted mid-hold: the tangential spring
    comes back from the restart file (fix property/atom of the wall), so the resumed run follows the
    unbroken one; without the spring the cube would slip on resuming."""
    difference = restart_on_a_wall(run_deck, tmp_path, "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n", 0)
    print(f"\nrestart on a wall: largest x difference {difference:.1e} m")
    assert difference < 1e-12


def check_wall_impact(run_deck, tmp_path, label, sphere_wall, shape_wall, mesh=""):
    """An icosphere of 1280 triangles (volume-equivalent diameter 20 mm) hits a wall at 1 m/s, and
    LIGGGHTS' own sphere of the same diameter and density hits it with `fix wall/gran model hertz
    tangential history` (sphere_wall: its wall arguments), same materials (E 10 MPa, e 0.8).
    shape_wall: fix wall/polyhedral's arguments; mesh: commands both runs need before the walls.
    Contact duration within 2% and restitution within 1.5%, the tolerances of the particle-particle
    test (tests/test_contact_physics.py), whose study table shows the facets' share at this resolution."""
    diameter, dt = 0.02, 2e-6
    materials = (f"fix m1 all property/global youngsModulus peratomtype {YOUNGS} {YOUNGS}\n"
                 f"fix m2 all property/global poissonsRatio peratomtype {POISSON} {POISSON}\n"
                 "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.8 0.8 0.8 0.8\n"
                 "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n" + mesh)
    variables = "variable z equal z[1]\nvariable vz equal vz[1]\n"
    common = f"thermo_modify format float %.15g\nthermo 1\ntimestep {dt}\nrun 3000\n"
    sphere = run_deck("atom_style granular\natom_modify map array sort 0 0\nboundary f f f\nnewton off\n"
                      "communicate single vel yes\nunits si\nregion box block -0.1 0.1 -0.1 0.1 -0.1 0.1\n"
                      "create_box 2 box\nneighbor 0.002 bin\nneigh_modify delay 0\n" + materials +
                      "pair_style gran model hertz tangential history\npair_coeff * *\n"
                      f"fix wall all wall/gran model hertz tangential history {sphere_wall}\n"
                      f"create_atoms 1 single 0 0 {diameter / 2 + 0.0005}\n"
                      f"set atom 1 diameter {diameter} density {DENSITY}\n"
                      "velocity all set 0 0 -1\nfix integrate all nve/sphere\n" +
                      variables + "thermo_style custom step v_z v_vz\n" + common, workdir=tmp_path / "sphere")
    assert sphere.returncode == 0, sphere.output[-3000:]
    shape = run_deck(decks.header(boundary="f f f", lo=-0.1, hi=0.1, ntypes=2) +
                     "neighbor 0.002 bin\nneigh_modify delay 0\n" + materials +
                     decks.template("ball", "icosphere_1280.off", scale=diameter) +
                     "pair_style polyhedral/volumetric\npair_coeff * *\n"
                     f"fix floor all wall/polyhedral {shape_wall}\n"
                     f"create_polyhedron ball 0 0 {diameter / 2 + 0.0005} quat 0.9 0.3 -0.2 0.25 vel 0 0 -1\n"
                     "fix integrate all nve/polyhedron\n" +
                     variables + "thermo_style custom step v_z v_vz f_floor[4]\n" + common, workdir=tmp_path / "shape")
    assert shape.returncode == 0, shape.output[-3000:]
    a = sphere.thermo("Step", "v_z", "v_vz")
    b = shape.thermo("Step", "v_z", "v_vz", "f_floor[4]")
    sphere_steps = sum(1 for z in a["v_z"][1:] if z < diameter / 2)
    shape_steps = sum(1 for c in b["f_floor[4]"][1:] if c > 0)
    shape_e, sphere_e = b["v_vz"][-1] / -b["v_vz"][0], a["v_vz"][-1] / -a["v_vz"][0]
    print(f"\n{label}: contact {shape_steps} steps (icosphere) vs {sphere_steps} (LIGGGHTS sphere), "
          f"restitution {shape_e:.4f} vs {sphere_e:.4f}")
    assert sphere_steps > 300 and a["v_z"][-1] > diameter / 2 and b["f_floor[4]"][-1] == 0
    assert abs(shape_steps / sphere_steps - 1) < 0.02, (shape_steps, sphere_steps)
    assert abs(shape_e / sphere_e - 1) < 0.015, (shape_e, sphere_e)


def test_icosphere_impact_on_a_plane_matches_liggghts_hertz_sphere_on_a_wall(run_deck, tmp_path):
    """check_wall_impact on a zplane primitive. Measured: +1.6% duration and +0.46% restitution
    (against a plane the overlap is twice as deep relative to R* as between two spheres, so the
    lens-volume difference of the law from Hertz weighs more)."""
    check_wall_impact(run_deck, tmp_path, "wall impact", "primitive type 2 zplane 0.0", "primitive type 2 zplane 0.0")


def test_wall_contact_crosses_ranks(run_deck, tmp_path):
    """The cube slides down a plane tilted 35 degrees from x = -5 mm across the boundary x = 0 between
    two ranks (processors 2 1 1): its wall contact and tangential spring migrate with it, and the run
    follows the single-rank one (same arithmetic, so to round-off)."""
    tilt = math.radians(35.0)
    deck = scene("fix floor all wall/polyhedral primitive type 2 zplane 0.0\n", f"-0.005 0 {EDGE / 2}",
                 gravity=f"{math.sin(tilt)!r} 0 {-math.cos(tilt)!r}", steps=15000)
    check_crosses_ranks(run_deck, tmp_path, deck, "wall contact")


@pytest.mark.parametrize("sunk,warns", [(0.004, True), (0.0, False)])
def test_particle_created_inside_a_wall_is_reported(run_deck, tmp_path, sunk, warns):
    """A cube (20 mm) created 4 mm into the floor is pushed out violently: the wall warns at set-up with the
    count and the deepest overlap (4 mm of the 34.6 mm bounding diameter: 11.5 %); a cube
    resting on it does not warn."""
    result = run_deck(scene("fix floor all wall/polyhedral primitive type 2 zplane 0.0\n",
                            f"0 0 {EDGE / 2 - sunk!r}", steps=10))
    assert result.returncode == 0, result.output[-3000:]
    lines = [w for w in result.warning_lines() if "particle-wall contacts at the start" in w]
    assert bool(lines) == warns, result.warning_lines()
    if warns:
        assert "1 of 1 particle-wall contacts" in lines[0] and "11.5%" in lines[0], lines[0]
