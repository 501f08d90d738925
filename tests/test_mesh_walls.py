"""fix wall/polyhedral with LIGGGHTS triangle meshes (fix mesh/surface, mesh/surface/stress, fix move/mesh).

The construction (src/poly_mesh_shell.h): each triangle owns the prism of the shell behind it, built
from vertex directions shared by neighbouring triangles, so the prisms partition the shell and a flat
wall tessellated into any number of triangles is the same solid as one plane. Here as a user runs it:
a cube resting on floors of 2 and 200 triangles against the plane primitive and the weight; stick and
slide on a mesh floor; an icosphere impact on a mesh floor against LIGGGHTS' sphere on the same mesh;
a particle shaken in a closed box; the torque a drum's particles put on it; bad input.
"""
import math
import re

import numpy as np
import pytest

import decks
import meshes
from test_walls import (DENSITY, EDGE, FRICTION, G, check_crosses_ranks, check_stick_or_slide, check_wall_impact, restart_on_a_wall,
                        scene, static_depth)

MASS = DENSITY * EDGE ** 3


def mesh_wall(stl, stress=False, extra=""):
    """The mesh fix (ID floor_mesh) and the wall (ID floor, as the plane tests name it)."""
    style = "mesh/surface/stress" if stress else "mesh/surface"
    return (f"fix floor_mesh all {style} file {stl} type 2{extra}\n"
            "fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh\n")


@pytest.mark.parametrize("cells", [1, 10, 7], ids=["2-triangles", "200-triangles", "98-triangles-offset"])
def test_cube_rests_on_a_mesh_floor_as_on_a_plane(run_deck, tmp_path, cells):
    """The cube of tests/test_walls.py (20 mm, turned 0.6 rad about z) at rest on a floor of 2, 200
    and 98 triangles (10 x 10 and 7 x 7 grids of 20 and 28.6 mm cells, so the cube's face covers
    shared edges and vertices): the wall carries the weight and the cube sinks by the closed-form
    depth, within 1%, as on the zplane primitive; and the mesh floor gives the plane's depth to 1e-6."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(cells, 0.1))
    pose = f"0.003 -0.002 {EDGE / 2} quat {math.cos(0.3)} 0 0 {math.sin(0.3)}"
    results = {}
    for name, wall in (("plane", "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"),
                       ("mesh", mesh_wall("../floor.stl"))):
        result = run_deck(scene(wall, pose, steps=20000), workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        table = result.thermo("Step", "v_z", "f_floor[3]", "f_floor[4]")
        settled = [i for i, step in enumerate(table["Step"]) if step >= 10000]
        results[name] = (np.array(table["f_floor[3]"])[settled], EDGE / 2 - np.array(table["v_z"])[settled],
                         np.array(table["f_floor[4]"])[settled])
    force, depth, contacts = results["mesh"]
    print(f"\ncube on {2 * cells * cells} triangles: force / weight - 1 = {-force.mean() / (MASS * G) - 1:.2e}, "
          f"depth / closed form - 1 = {depth.mean() / static_depth(MASS) - 1:.2e}, "
          f"depth / plane's - 1 = {depth.mean() / results['plane'][1].mean() - 1:.2e}")
    assert all(c == 1 for c in contacts)
    assert abs(-force.mean() / (MASS * G) - 1) < 0.01, force.mean()
    assert abs(depth.mean() / static_depth(MASS) - 1) < 0.01, depth.mean()
    assert abs(depth.mean() / results["plane"][1].mean() - 1) < 1e-6


def one_mesh_and_separate(tmp_path, name, parts):
    """parts: {part: triangles}, written as one mesh (NAME.stl) and as a mesh each (PART.stl): the wall fix
    (ID floor) on either, {"one mesh": lines, "separate meshes": lines}."""
    meshes.write_stl(tmp_path / f"{name}.stl", [t for triangles in parts.values() for t in triangles])
    for part, triangles in parts.items():
        meshes.write_stl(tmp_path / f"{part}.stl", triangles)
    ids = " ".join(f"mesh_{part}" for part in parts)
    return {"one mesh": mesh_wall(f"../{name}.stl"),
            "separate meshes": "".join(f"fix mesh_{part} all mesh/surface file ../{part}.stl type 2\n"
                                       for part in parts) +
                               f"fix floor all wall/polyhedral mesh n_meshes {len(parts)} meshes {ids}\n"}


def run_walls(run_deck, tmp_path, walls, make_deck, *columns):
    """Each of `walls` ({name: wall lines}) in the deck make_deck(wall), in a directory of its own: {name: the
    thermo columns}; a run must end cleanly and without warnings."""
    tables = {}
    for name, wall in walls.items():
        result = run_deck(make_deck(wall), workdir=tmp_path / name.replace(" ", "_"))
        assert result.returncode == 0, result.output[-3000:]
        assert "WARNING" not in result.output, result.output[-3000:]
        tables[name] = result.thermo(*columns)
    return tables


def corner_faces(size=0.1):
    """The corner of a box at the origin: floor z = 0, walls x = 0 and y = 0, squares of side `size`, two
    triangles each, sharing the corner's edges; each face's triangles counter-clockwise seen from inside."""
    o, a = 0.0, size
    floor = [((o, o, o), (a, o, o), (a, a, o)), ((o, o, o), (a, a, o), (o, a, o))]
    wall_x = [((o, o, o), (o, a, o), (o, a, a)), ((o, o, o), (o, a, a), (o, o, a))]
    wall_y = [((o, o, o), (o, o, a), (a, o, a)), ((o, o, o), (a, o, a), (a, o, o))]
    return floor, wall_x, wall_y


def test_cube_in_a_corner_of_one_mesh_is_held_as_by_its_faces_as_separate_meshes(run_deck, tmp_path):
    """The cube pushed by gravity along (-1, -1, -1) into the corner of a box, frictionless: the corner as one mesh
    (floor and two walls, triangles sharing the corner's edges) and as three meshes; at rest each face carries
    m g / sqrt 3 at the closed-form depth of a face, to 1 %, in both. One contact per particle and mesh
    had the depth of its three spots' spread along their mean normal, a good part of the cube's edge for a
    sub-micron overlap, so the corner held the cube far too stiffly (it sat too high) and pushed it out of any
    deeper overlap violently. Now each plane of a mesh that a particle touches is a contact of its own, with its
    own tangential spring."""
    walls = one_mesh_and_separate(tmp_path, "corner", dict(zip(("floor", "wall_x", "wall_y"), corner_faces())))
    pose = f"{EDGE / 2} {EDGE / 2} {EDGE / 2}"

    def frictionless(wall):  # so that each face's normal force is the weight's component along its normal
        deck = scene(wall, pose, steps=20000, gravity="-1 -1 -1")
        deck = deck.replace(f"coefficientFriction peratomtypepair 2 {FRICTION} {FRICTION} {FRICTION} {FRICTION}",
                            "coefficientFriction peratomtypepair 2 0 0 0 0")
        assert "peratomtypepair 2 0 0 0 0" in deck
        return deck
    runs = run_walls(run_deck, tmp_path, walls, frictionless, "Step", "v_x", "v_z", "f_floor[1]", "f_floor[3]",
                     "f_floor[4]")
    third = MASS * G / math.sqrt(3.0)
    depth = static_depth(MASS / math.sqrt(3.0))
    for name, table in runs.items():
        settled = [i for i, step in enumerate(table["Step"]) if step >= 10000]
        force_x = -np.array(table["f_floor[1]"])[settled].mean()
        force_z = -np.array(table["f_floor[3]"])[settled].mean()
        sunk = EDGE / 2 - np.array(table["v_z"])[settled].mean()
        print(f"\n{name}: force / (m g / sqrt 3) - 1 = {force_x / third - 1:.2e} (x), {force_z / third - 1:.2e} (z); "
              f"depth / closed form - 1 = {sunk / depth - 1:.2e}; contacts {table['f_floor[4]'][-1]}")
        assert abs(force_x / third - 1) < 0.01 and abs(force_z / third - 1) < 0.01, (force_x, force_z, third)
        assert abs(sunk / depth - 1) < 0.01, (sunk, depth)
        assert table["f_floor[4]"][-1] == 3


@pytest.mark.parametrize("segments", [64, 360])
def test_cube_impact_on_a_tessellated_drum_as_on_the_cylinder_primitive(run_deck, tmp_path, segments):
    """The cube (20 mm, face first) thrown at 1 m/s against the inside of a drum of radius 0.1 m: the drum as a
    mesh of 64 or 360 sides (tests/meshes.py's drum, turned to the z axis) and as the zcylinder primitive give one
    contact and the same rebound, to 1 %. The mesh's facets meet at 5.6 and 1 degree, within the 20 degrees that
    make them one surface: one contact per plane of the mesh gave up to 6 contacts and half the rebound (gravity
    along -y, so the cube's largest vy is its rebound)."""
    radius = 0.1
    drum = [tuple((x, z, y) for x, y, z in triangle) for triangle in meshes.drum(radius, 0.1, segments)]
    meshes.write_stl(tmp_path / "drum.stl", drum)
    pose = f"0 {-radius + EDGE / 2 + 0.002} 0 vel 0 -1 0"
    rebound = {}
    for name, wall in (("primitive", f"fix floor all wall/polyhedral primitive type 2 zcylinder {radius} 0 0\n"),
                       ("mesh", mesh_wall("../drum.stl"))):
        deck = scene(wall, pose, steps=6000, gravity="0 -1 0").replace(
            "variable vx equal vx[1]\n", "variable vx equal vy[1]\n").replace("thermo 1000\n", "thermo 10\n")
        result = run_deck(deck, workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        table = result.thermo("Step", "v_vx", "f_floor[4]")
        assert max(table["f_floor[4]"]) == 1, table["f_floor[4]"]
        rebound[name] = max(table["v_vx"])  # as it leaves the wall (gravity then slows it by 1e-3 m/s a row)
    print(f"\ndrum of {segments} sides: rebound {rebound['mesh']:.4f} m/s against the primitive's "
          f"{rebound['primitive']:.4f}")
    assert rebound["primitive"] > 0.3
    assert abs(rebound["mesh"] / rebound["primitive"] - 1) < 0.01, rebound


def test_cube_sliding_onto_a_convex_crease_of_one_mesh_as_onto_two_meshes(run_deck, tmp_path):
    """The cube (20 mm, friction 0.5) slides at 0.5 m/s along a floor towards its edge, where a slope falls away at
    30 degrees, and stops with its front over the crease: floor and slope as one mesh and as two meshes give the same
    path, to 0.1 mm. On the crease the two contacts (floor and slope, 30 degrees apart) both have the normal of the
    cube's face; their tangential springs, matched by that normal, swapped every few steps, and the one mesh's cube
    was braked to a stop 3 mm short, tipped and rocked back."""
    slope = math.tan(math.radians(30.0))
    floor = [((-0.1, -0.05, 0), (0, -0.05, 0), (0, 0.05, 0)), ((-0.1, -0.05, 0), (0, 0.05, 0), (-0.1, 0.05, 0))]
    ramp = [((0, -0.05, 0), (0.1, -0.05, -0.1 * slope), (0.1, 0.05, -0.1 * slope)),
            ((0, -0.05, 0), (0.1, 0.05, -0.1 * slope), (0, 0.05, 0))]
    walls = one_mesh_and_separate(tmp_path, "crease", {"floor": floor, "ramp": ramp})
    paths = run_walls(run_deck, tmp_path, walls,
                      lambda wall: scene(wall, f"-0.03 0 {EDGE / 2} vel 0.5 0 0", steps=12000).replace(
                          "thermo 1000\n", "thermo 100\n"), "Step", "v_x", "v_z")
    one, two = paths["one mesh"], paths["separate meshes"]
    worst = max(abs(a - b) for a, b in zip(one["v_x"] + one["v_z"], two["v_x"] + two["v_z"]))
    print(f"\ncrease: final x {one['v_x'][-1]:.6f} (one mesh) against {two['v_x'][-1]:.6f} (two meshes); "
          f"largest difference {worst:.2e} m")
    assert -0.01 < two["v_x"][-1] < 0.0, two["v_x"][-1]
    assert worst < 1e-4, worst


def test_cube_between_two_walls_of_one_mesh_as_between_two_meshes(run_deck, tmp_path):
    """The cube held between two parallel walls 2e-5 and 1e-5 m into it, no gravity: the walls as one mesh (wound
    either way) and as two meshes give two contacts and the same net force at the first step (its x component the
    difference of the two faces' pushes), to 1e-9 N. Taken as parallel whichever way they face, they were one
    surface: one contact of 1.97 N where the net force is 0.80."""
    h = EDGE / 2

    def wall_x(x, flip):
        pair = [((x, -0.05, -0.05), (x, 0.05, -0.05), (x, 0.05, 0.05)), ((x, -0.05, -0.05), (x, 0.05, 0.05),
                                                                          (x, -0.05, 0.05))]
        return [tuple(reversed(t)) for t in pair] if flip else pair
    left, right = wall_x(-(h - 2e-5), False), wall_x(h - 1e-5, True)
    walls = one_mesh_and_separate(tmp_path, "both", {"left": left, "right": right})

    def weightless(wall):
        deck = scene(wall, "0 0 0", steps=1).replace(f"fix gravity all gravity {G} vector 0 0 -1\n", "")
        assert "gravity" not in deck
        return deck
    tables = run_walls(run_deck, tmp_path, walls, weightless, "Step", "f_floor[1]", "f_floor[4]")
    first = {name: (table["f_floor[1]"][0], table["f_floor[4]"][0]) for name, table in tables.items()}
    print(f"\nslot: force on the walls {first['one mesh'][0]:.6g} N, {first['one mesh'][1]:g} contacts (one mesh); "
          f"{first['separate meshes'][0]:.6g} N, {first['separate meshes'][1]:g} (two meshes)")
    assert first["one mesh"][1] == first["separate meshes"][1] == 2
    assert abs(first["one mesh"][0] - first["separate meshes"][0]) < 1e-9, first


@pytest.mark.parametrize("angle", [20.0, 35.0])
def test_cube_sticks_or_slides_on_a_mesh_floor(run_deck, tmp_path, angle):
    """tests/test_walls.py's tilted-plane test on a floor of 392 triangles (20 mm cells): gravity
    turns to `angle` from the normal; tan(26.6 deg) = mu = 0.5. At 20 deg no creep (the particle's
    spring for the mesh is one per particle and mesh, so crossing no edge loses it); at 35 deg the
    cube slides over many shared edges with a = g (sin - mu cos), within 1% of mu."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(14, 0.14))
    deck = scene(mesh_wall("../floor.stl"), f"-0.12 0.003 {EDGE / 2}", steps=5000)
    deck += decks.tilted_gravity("all", angle) + "thermo 200\nrun 45000\n"
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = check_stick_or_slide(result, angle, " on a mesh")
    assert all(c == 1 for c in result.thermo("f_floor[4]")["f_floor[4]"][1:])  # from the first step on
    if angle > 30:
        assert table["v_x"][-1] - table["v_x"][0] > 0.04   # over at least two cells


def test_icosphere_impact_on_a_mesh_matches_liggghts_sphere_on_the_same_mesh(run_deck, tmp_path):
    """tests/test_walls.py's check_wall_impact on a floor of 200 triangles, hitting at a shared vertex: the
    icosphere of 1280 triangles with fix wall/polyhedral against LIGGGHTS' sphere with `fix wall/gran
    model hertz tangential history mesh` on the same mesh. Same tolerances as on the plane (2%
    duration, 1.5% restitution), whose measured +1.6% / +0.46% the mesh must reproduce."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(10, 0.1))
    walls = "mesh n_meshes 1 meshes floor_mesh"
    check_wall_impact(run_deck, tmp_path, "mesh impact", walls, walls,
                      mesh="fix floor_mesh all mesh/surface file ../floor.stl type 2\n")


def test_conveyor_mesh_carries_the_cube_at_its_speed(run_deck, tmp_path):
    """A floor moving at 0.1 m/s along x (fix move/mesh linear): the resting cube is dragged by
    friction and ends at the floor's speed; the wall velocity at the contact comes from the mesh's
    vertex velocities."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(4, 0.25))
    deck = scene(mesh_wall("../floor.stl") + "fix belt all move/mesh mesh floor_mesh linear 0.1 0 0\n",
                 f"0 0 {EDGE / 2}", steps=20000)
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "v_x", "v_vx", "f_floor[1]")
    # Once carried, the cube rocks on its tangential spring (+-1% in vx, weakly damped, as on a plane);
    # over the second half of the run it moves with the belt.
    half = table["Step"].index(10000)
    speed = (table["v_x"][-1] - table["v_x"][half]) / ((table["Step"][-1] - table["Step"][half]) * 1e-5)
    print(f"\nconveyor: cube's mean speed {speed:.7f} m/s over the last 0.1 s, floor 0.1")
    assert abs(speed / 0.1 - 1) < 1e-3, speed
    assert table["f_floor[1]"][1] < 0  # the belt is held back while it accelerates the cube


def test_a_mesh_that_starts_moving_carries_the_cube(run_deck, tmp_path):
    """The wall keeps each triangle's prism from step to step while the triangle's corners stay the same (a
    static mesh's are made once). A floor at rest for 0.1 s, then lifted at 0.05 m/s (fix move/mesh added for
    a second run): the kept prisms must give way to ones at the floor's new place, and the resting cube rises
    with it by 5 mm in 0.1 s (it follows within 0.3 mm: its sinking changes little under the small pull-up)."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(4, 0.25))
    deck = scene(mesh_wall("../floor.stl"), f"0 0 {EDGE / 2}", steps=10000)
    deck += "fix lift all move/mesh mesh floor_mesh linear 0 0 0.05\nrun 10000\n"
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "v_z", "f_floor[4]")
    rest, end = table["Step"].index(10000), len(table["Step"]) - 1
    rise = table["v_z"][end] - table["v_z"][rest]
    print(f"\nlifted floor: the cube rose {rise * 1e3:.4f} mm, the floor 5 mm")
    assert abs(rise - 0.005) < 3e-4, rise
    assert all(c == 1 for c in table["f_floor[4]"][rest:])


def test_cube_stays_inside_a_shaken_closed_box(run_deck, tmp_path):
    """A closed box of 48 triangles (100 mm, normals inwards) shaken by fix move/mesh wiggle (10 mm
    at 50 Hz along x, 5 mm along z: up to 3 m/s) with the cube inside under gravity, 10^5 steps: the
    cube's centre stays inside the moving box at every step printed, and it really is thrown about."""
    meshes.write_stl(tmp_path / "box.stl", meshes.box(-0.05, 0.05, 2))
    deck = scene("fix box_mesh all mesh/surface file ../box.stl type 2\n"
                 "fix floor all wall/polyhedral mesh n_meshes 1 meshes box_mesh\n"
                 "fix shake all move/mesh mesh box_mesh wiggle amplitude 0.01 0 0.005 period 0.02\n",
                 "0.01 0.02 -0.02 quat 0.9 0.3 -0.2 0.25", steps=100000)
    deck = deck.replace("thermo 1000\n", "thermo 100\n").replace(
        "thermo_style custom step", "variable y equal y[1]\nthermo_style custom step atoms v_y")
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "Atoms", "v_x", "v_y", "v_z", "v_vx")
    t = np.array(table["Step"]) * 1e-5
    phase = np.sin(2 * math.pi * t / 0.02)
    inside_x = np.abs(np.array(table["v_x"]) - 0.01 * phase)
    inside_z = np.abs(np.array(table["v_z"]) - 0.005 * phase)
    inside_y = np.abs(np.array(table["v_y"]))
    deepest = max(inside_x.max(), inside_y.max(), inside_z.max())
    print(f"\nshaken box: largest centre offset from the box centre {deepest * 1e3:.2f} mm (wall at 50 mm), "
          f"largest |vx| {np.abs(table['v_vx']).max():.2f} m/s")
    assert all(n == 1 for n in table["Atoms"])
    assert deepest < 0.05
    assert np.abs(table["v_vx"]).max() > 0.5


def drum_deck(tmp_path, pair="pair_style polyhedral/volumetric\n", processors="2 1 1", steps=12000):
    """12 cubes of 10 mm in a closed drum (radius 50 mm, 40 mm long, 128 triangles, fix mesh/surface/stress
    dmesh, wall fix drum) turning about y with period 0.5 s; thermo every 500 steps: atoms, kinetic energy,
    f_drum[4..7] and f_dmesh[4..6]."""
    meshes.write_stl(tmp_path / "drum.stl", meshes.drum(0.05, 0.04, 32))
    cubes = "".join(f"create_polyhedron cube {x} {y} {z} quat 0.9 0.3 -0.2 0.25\n"
                    for x in (-0.02, 0.0, 0.02) for y in (-0.008, 0.008) for z in (-0.03, -0.012))
    deck = (decks.header(boundary="f f f", lo=-0.07, hi=0.07, ntypes=2, processors=processors) +
            "neighbor 0.002 bin\nneigh_modify delay 0\n" +
            decks.materials() +
            decks.template("cube", "cube.stl", scale=0.01, atom_type=1) +
            pair + "pair_coeff * *\n"
            "fix dmesh all mesh/surface/stress file ../drum.stl type 2\n"
            "fix drum all wall/polyhedral mesh n_meshes 1 meshes dmesh\n"
            "fix spin all move/mesh mesh dmesh rotate origin 0 0 0 axis 0 1 0 period 0.5\n" + cubes +
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
            "thermo_style custom step atoms ke f_drum[4] f_drum[5] f_drum[6] f_drum[7] "
            "f_dmesh[4] f_dmesh[5] f_dmesh[6]\n"
            "thermo_modify format float %.15g\nthermo 500\ntimestep 1e-5\n" + f"run {steps}\n")
    return deck


def test_drum_torque_from_mesh_stress_is_minus_the_torque_on_the_particles(run_deck, tmp_path):
    """A closed drum (radius 50 mm, 40 mm long, 128 triangles) turning about y (fix move/mesh rotate,
    period 0.5 s) with 12 cubes of 10 mm in two layers, on 2 ranks: the torque fix mesh/surface/stress reports
    (f_dmesh[4..6], about the origin) equals the torque on the wall that fix wall/polyhedral
    sums from the particles' side (f_drum[5..7]) at every step printed, and the drum lifts the charge
    (torque about y of the sign of the rotation's resistance)."""
    deck = drum_deck(tmp_path)
    result = run_deck(deck, nprocs=2, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "Atoms", *[f"f_drum[{k}]" for k in range(4, 8)],
                          *[f"f_dmesh[{k}]" for k in range(4, 7)])
    ours = np.array([table[f"f_drum[{k}]"] for k in (5, 6, 7)]).T[1:]
    stress = np.array([table[f"f_dmesh[{k}]"] for k in (4, 5, 6)]).T[1:]
    scale = np.abs(stress).max()
    worst = np.abs(ours - stress).max()
    print(f"\ndrum: torque about y {stress[-5:, 1].mean():.3e} N m (mean of the last 5 outputs), largest "
          f"difference between fix mesh/surface/stress and the particles' side {worst:.1e} N m")
    assert all(n == 12 for n in table["Atoms"])
    assert table["f_drum[4]"][-1] >= 4  # the bottom layer of cubes rests on the drum
    assert worst < 1e-9 * scale, (worst, scale)
    assert scale > 1e-4


def test_mesh_wall_history_survives_a_restart(run_deck, tmp_path):
    """The cube held by friction on a mesh floor with gravity at 20 deg, restarted mid-hold: the
    spring of its mesh contact comes back from the restart file, so the resumed run follows the
    unbroken one (as tests/test_walls.py checks for the plane)."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(10, 0.1))
    difference = restart_on_a_wall(run_deck, tmp_path, mesh_wall("../floor.stl"), 0.005)
    print(f"\nrestart on a mesh: largest x difference {difference:.1e} m")
    assert difference < 1e-12


def test_mesh_contact_crosses_ranks(run_deck, tmp_path):
    """The cube slides at 35 deg over a 392-triangle floor across the boundary x = 0 between two
    ranks: its contact (pieces summed in global triangle order) and spring migrate with it, and the
    run follows the single-rank one to round-off."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(14, 0.14))
    tilt = math.radians(35.0)
    deck = scene(mesh_wall("../floor.stl"), f"-0.008 0 {EDGE / 2}",
                 gravity=f"{math.sin(tilt)!r} 0 {-math.cos(tilt)!r}", steps=15000)
    check_crosses_ranks(run_deck, tmp_path, deck, "mesh contact")


def pentagonal_pit(centre_x, radius=0.05):
    """An inverted pyramid of five triangles, its apex at (centre_x, 0, 0), faces at 45 degrees: their normals
    49 degrees apart, so a ball resting in it touches five surfaces of one mesh."""
    corners = [(centre_x + radius * math.cos(2 * math.pi * k / 5), radius * math.sin(2 * math.pi * k / 5), radius)
               for k in range(5)]
    return [((centre_x, 0.0, 0.0), corners[(k + 1) % 5], corners[k]) for k in range(5)]


@pytest.mark.parametrize("ranks", [1, 2])
def test_more_surfaces_than_slots_is_said_from_any_rank(run_deck, tmp_path, ranks):
    """A ball (icosphere_80, 20 mm) dropped into a five-sided pit lands on five surfaces of one mesh, one more than
    the contact slots (kMeshContactSlots): the fifth contact has no tangential spring, and a warning says so, once,
    on the screen and in the log file. The pit lies at x = 0.1, on the second rank of `processors 2 1 1`: LIGGGHTS
    opens the log file on rank 0 only, so until the warning was shared over the ranks the two-rank run's log said
    nothing (and with `-screen none` nothing said it at all)."""
    meshes.write_stl(tmp_path / "pit.stl", pentagonal_pit(0.1))
    deck = (decks.header(boundary="f f f", lo=-0.3, hi=0.3, ntypes=2,
                         processors="2 1 1" if ranks == 2 else None) +
            "neighbor 0.002 bin\nneigh_modify delay 0\n" + decks.materials() +
            decks.template("ball", "icosphere_80.off", scale=0.02, atom_type=1) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "create_polyhedron ball 0.1 0 0.02\n"
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n" +
            mesh_wall("../pit.stl") +
            "thermo_style custom step f_floor[3] f_floor[4]\nthermo 10\ntimestep 1e-5\nrun 5000\n")
    result = run_deck(deck, nprocs=ranks, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    contacts = result.thermo("Step", "f_floor[4]")["f_floor[4]"]
    assert max(contacts) == 5, contacts
    warning = "touches more than 4 surfaces of mesh 'floor_mesh'"
    log = (tmp_path / "run" / "log.lammps").read_text()
    assert result.output.count(warning) == 1 and log.count(warning) == 1, result.output[-3000:]


def flipped_grid():
    """A 4 x 4 grid with one triangle of an inner cell turned over: its three edges disagree."""
    triangles = meshes.grid(4, 0.1)
    a, b, c = triangles[10]
    triangles[10] = (a, c, b)
    return triangles


@pytest.mark.parametrize("wall,mesh,line", [
    ("fix floor all wall/polyhedral mesh n_meshes 1 meshes gravity\n", None,
     "ERROR: Fix wall/polyhedral: fix 'gravity' is a gravity, not a fix mesh/surface"),
    ("fix floor all wall/polyhedral mesh n_meshes 2 meshes floor_mesh\n", meshes.grid(1, 0.1),
     "ERROR: Fix wall/polyhedral: 'n_meshes 2' but 1 mesh ID after 'meshes'"),
    ("fix floor all wall/polyhedral mesh n_meshes 0 meshes floor_mesh\n", meshes.grid(1, 0.1),
     "ERROR: Fix wall/polyhedral: 'mesh n_meshes K meshes' needs K >= 1 mesh IDs"),
    ("fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh primitive type 2 zplane 0\n",
     meshes.grid(1, 0.1), "ERROR: Fix wall/polyhedral: either 'primitive' or 'mesh', not both"),
    ("fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh\n", flipped_grid(),
     "WARNING: Fix wall/polyhedral: mesh 'floor_mesh': 3 shared edges run the same way in both triangles"),
    ("fix floor all wall/polyhedral thickness 0.01 mesh n_meshes 1 meshes floor_mesh\n", meshes.grid(1, 0.1),
     "WARNING: Fix wall/polyhedral: thickness 0.01 is less than the largest particle's bounding diameter"),
])
def test_bad_mesh_wall_input_is_reported(run_deck, tmp_path, wall, mesh, line):
    """Clear ERROR lines for a mesh ID that is not a mesh, a wrong mesh count and two kinds of wall in
    one fix; WARNING lines (the run goes on) for inconsistently oriented triangles and a shell thinner
    than the particles."""
    mesh_fix = ""
    if mesh is not None:
        meshes.write_stl(tmp_path / "floor.stl", mesh)
        mesh_fix = "fix floor_mesh all mesh/surface file ../floor.stl type 2\n"
    deck = scene(mesh_fix + wall, f"0 0 {EDGE / 2}", steps=10)
    # The gravity fix must exist before the wall names it.
    deck = deck.replace(f"fix gravity all gravity {G} vector 0 0 -1\n", "")
    deck = deck.replace(mesh_fix + wall, f"fix gravity all gravity {G} vector 0 0 -1\n" + mesh_fix + wall)
    result = run_deck(deck, workdir=tmp_path / "run")
    matching = [text for text in result.output.splitlines() if text.startswith(line)]
    assert matching, result.output[-3000:]
    assert (result.returncode != 0) == line.startswith("ERROR"), result.output[-2000:]


def test_mesh_walls_need_binned_neighbour_lists(run_deck, tmp_path):
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(1, 0.1))
    deck = scene(mesh_wall("../floor.stl"), f"0 0 {EDGE / 2}", steps=10).replace("neighbor 0.002 bin", "neighbor 0.002 nsq")
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode != 0
    assert any("bin" in text for text in result.error_lines()), result.output[-2000:]


def test_particle_much_larger_than_the_skin_still_meets_the_mesh(run_deck, tmp_path):
    """The mesh neighbour lists reach bounding radius + skin, so a particle far larger than the skin needs
    no special setting: the 20 mm cube, dropped from 5 mm above a 200-triangle floor with a skin of
    10 um (1/2000 of the cube), lands (LIGGGHTS reports no dangerous neighbour-list build) and rests with
    the wall carrying its weight within 1 %."""
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(10, 0.1))
    pose = f"0.003 -0.002 {EDGE / 2 + 0.005} quat {math.cos(0.3)} 0 0 {math.sin(0.3)}"
    deck = scene(mesh_wall("../floor.stl"), pose, steps=30000).replace("neighbor 0.002 bin", "neighbor 0.00001 bin")
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "v_z", "f_floor[3]", "f_floor[4]")
    settled = [i for i, step in enumerate(table["Step"]) if step >= 20000]
    force = np.array(table["f_floor[3]"])[settled]
    print(f"\nskin 1/2000 of the cube: force / weight - 1 = {-force.mean() / (MASS * G) - 1:.2e}, lowest z "
          f"{min(table['v_z']) * 1e3:.4f} mm")
    assert min(table["v_z"]) > EDGE / 2 - 1e-4  # it never fell through
    assert all(table["f_floor[4]"][i] == 1 for i in settled)
    assert abs(-force.mean() / (MASS * G) - 1) < 0.01, force.mean()
    dangerous = re.search(r"Dangerous builds\s*=\s*(\d+)", result.output)
    assert dangerous and int(dangerous.group(1)) == 0, result.output[-2000:]


# Winding (issue 13): the solid is on the far side of the mesh from each particle, whichever way the file's
# triangles run (doc/fix_wall_polyhedral.md, "Which side is solid").

def reversed_triangles(triangles, every=1):
    """Every `every`-th triangle turned over (corners (a, c, b)); every=1: the whole mesh."""
    return [(a, c, b) if k % every == 0 else (a, b, c) for k, (a, b, c) in enumerate(triangles)]


def cubes_deck(wall_stl, positions, steps, lo=-0.1, hi=0.1, velocity="0.8 -0.5 -1.2", turn=0.41):
    """10 mm cubes at `positions` thrown (each at `velocity`) at the mesh `wall_stl` (fix wall/polyhedral
    ID wall); a text dump of every particle at the end."""
    text = (decks.header(boundary="f f f", lo=lo, hi=hi, ntypes=2) +
            "neighbor 0.002 bin\nneigh_modify delay 0\n" +
            decks.materials() +
            decks.template("cube", "cube.stl", scale=0.01, atom_type=1) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n")
    for k, (x, y, z) in enumerate(positions):
        angle = turn * k
        text += (f"create_polyhedron cube {x!r} {y!r} {z!r} quat {math.cos(angle)!r} {0.6 * math.sin(angle)!r} 0 "
                 f"{0.8 * math.sin(angle)!r} vel {velocity}\n")
    text += (f"fix wall_mesh all mesh/surface file {wall_stl} type 2\n"
             "fix wall all wall/polyhedral mesh n_meshes 1 meshes wall_mesh\n"
             "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
             "thermo_style custom step atoms ke f_wall[3] f_wall[4]\nthermo_modify lost ignore norm no\n"
             "thermo_modify format float %.15g\nthermo 500\ntimestep 1e-5\n"
             "dump out all custom 1000000 final.dump id x y z vx vy vz\n"
             "dump_modify out sort id format \"%d" + " %.17g" * 6 + "\"\n" + f"run {steps}\n")
    return text


def run_windings(run_deck, tmp_path, variants, positions, steps, **kwargs):
    """{name: (result, final rows)} for each {name: triangles}."""
    out = {}
    for name, triangles in variants.items():
        keywords = ""
        if isinstance(triangles, tuple):   # (triangles, wall keywords)
            triangles, keywords = triangles
        meshes.write_stl(tmp_path / f"{name}.stl", triangles)
        text = cubes_deck(f"../{name}.stl", positions, steps, **kwargs).replace(
            "wall/polyhedral mesh", f"wall/polyhedral {keywords}mesh")
        result = run_deck(text, workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        out[name] = (result, decks.read_dump(result.workdir / "final.dump")[1])
    return out


def largest_difference(a, b):
    assert sorted(a) == sorted(b)
    return max(np.abs(np.array(a[i][1:7]) - np.array(b[i][1:7])).max() for i in a)


@pytest.mark.parametrize("where", ["inside", "outside"])
def test_closed_box_either_winding(run_deck, tmp_path, where):
    """A closed box of 48 triangles (100 mm) as tests/meshes.py winds it (normals inward) and reversed
    (outward): 8 cubes thrown about inside it (a container), or 6 thrown onto its lid and sides from outside
    (a solid body), follow the same trajectories to round-off, stay on their side, and the log states the
    mesh closed with the file's normals inward or outward. `closed_side inside|outside`, which fixes the side
    instead of deciding it per particle, gives the same."""
    box = meshes.box(-0.05, 0.05, 2)
    if where == "inside":
        positions = [(x, y, z) for x in (-0.02, 0.02) for y in (-0.02, 0.02) for z in (-0.02, 0.02)]
        kwargs = dict(velocity="0.8 -0.5 -1.2")
    else:
        positions = [(-0.02, 0.01, 0.065), (0.02, -0.01, 0.075), (0.0, 0.02, 0.09), (0.065, 0.0, 0.02),
                     (-0.07, 0.01, 0.0), (0.01, 0.066, 0.03)]
        kwargs = dict(velocity="0 0 -0.5", lo=-0.15, hi=0.15)
    fixed = (reversed_triangles(box), f"closed_side {where} ")
    runs = run_windings(run_deck, tmp_path, {"inward": box, "outward": reversed_triangles(box), "fixed": fixed},
                        positions, steps=5000, **kwargs)
    worst = largest_difference(runs["inward"][1], runs["outward"][1])
    assert largest_difference(runs["inward"][1], runs["fixed"][1]) < 1e-9
    assert f"particles {where} (closed_side {where})" in runs["fixed"][0].output
    del runs["fixed"]
    contacts = max(runs["inward"][0].thermo("f_wall[4]")["f_wall[4]"])
    print(f"\nclosed box, cubes {where}: {contacts:.0f} wall contacts at most, inward vs outward winding: "
          f"largest difference {worst:.1e}")
    assert contacts > 0
    assert worst < 1e-9, worst
    for name, (result, rows) in runs.items():
        assert f"mesh 'wall_mesh': closed, 48 triangles in 1 surface, normals {name}" in result.output
        assert len(rows) == len(positions)
        for values in rows.values():
            inside = max(abs(v) for v in values[1:4]) < 0.05
            assert inside == (where == "inside"), (name, values)


def test_mixed_winding_warns_and_works(run_deck, tmp_path):
    """A floor of 200 triangles with every third turned over warns (its shared edges disagree) and still
    works: 6 cubes thrown onto it follow the same trajectories as on the consistently wound floor, to
    round-off, and none falls through."""
    floor = meshes.grid(10, 0.1)
    positions = [(x, y, 0.012) for x in (-0.04, 0.0, 0.04) for y in (-0.03, 0.03)]
    runs = run_windings(run_deck, tmp_path, {"consistent": floor, "mixed": reversed_triangles(floor, 3)},
                        positions, steps=5000, velocity="0.5 0.2 -0.5")
    mixed = runs["mixed"][0]
    assert any("shared edges run the same way in both triangles" in line for line in mixed.warning_lines()), \
        mixed.output[-2000:]
    assert "mesh 'wall_mesh': open, 200 triangles in 1 connected surface" in mixed.output
    worst = largest_difference(runs["consistent"][1], runs["mixed"][1])
    print(f"\nmixed winding: largest difference from the consistent floor {worst:.1e}")
    assert worst < 1e-9, worst
    assert all(values[3] > 0.0 for values in runs["mixed"][1].values())


@pytest.mark.parametrize("up", [True, False], ids=["normals-up", "normals-down"])
def test_open_sheet_holds_particles_on_both_sides(run_deck, tmp_path, up):
    """A single open sheet (200 triangles) with a 10 mm cube resting on it and another pressed up against
    its underside (its gravity reversed), at the same (x, y) up to 1 mm, both square to the sheet (so they
    do not meet each other through it): each meets the solid on the far
    side of the sheet from its centre, so both rest, the sheet carrying each one's weight, whichever way
    the sheet's triangles are wound."""
    meshes.write_stl(tmp_path / "sheet.stl", meshes.grid(10, 0.1, up=up))
    deck = cubes_deck("../sheet.stl", [(0.001, 0.0, 0.0052), (0.0, 0.001, -0.0052)], steps=20000, velocity="0 0 0",
                      turn=0.0)
    deck = deck.replace("fix gravity all gravity 9.81 vector 0 0 -1\n",
                        "group top id 1\ngroup bottom id 2\nfix gravity top gravity 9.81 vector 0 0 -1\n"
                        "fix lift bottom gravity 9.81 vector 0 0 1\n"
                        "variable z1 equal z[1]\nvariable z2 equal z[2]\n")
    deck = deck.replace("thermo_style custom step atoms ke", "thermo_style custom step atoms ke v_z1 v_z2")
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("v_z1", "v_z2", "f_wall[3]", "f_wall[4]")
    print(f"\nsheet, normals {'up' if up else 'down'}: cube above at z = {table['v_z1'][-1] * 1e3:.4f} mm, "
          f"below at {table['v_z2'][-1] * 1e3:.4f} mm, net force on the sheet {table['f_wall[3]'][-1]:.2e} N")
    assert 0.0045 < table["v_z1"][-1] < 0.0051 and -0.0051 < table["v_z2"][-1] < -0.0045
    assert table["f_wall[4]"][-1] == 2
    weight = 2500 * 1e-6 * 9.81
    assert abs(table["f_wall[3]"][-1]) < 0.01 * weight   # the two weights cancel on the sheet


def test_closed_side_keyword_checks_its_value(run_deck, tmp_path):
    meshes.write_stl(tmp_path / "floor.stl", meshes.grid(1, 0.1))
    deck = scene(mesh_wall("../floor.stl").replace("wall/polyhedral mesh", "wall/polyhedral closed_side below mesh"),
                 f"0 0 {EDGE / 2}", steps=10)
    result = run_deck(deck, workdir=tmp_path / "run")
    assert result.returncode != 0
    assert any("invalid value 'below' for 'closed_side' (auto, inside or outside)" in line
               for line in result.error_lines()), result.output[-2000:]
