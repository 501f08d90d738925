"""Mesh walls whichever way their triangles are wound (issue 13), on the meshes of LIGGGHTS' own tutorials
as Debian ships them (package liggghts-doc, installed by tools/debian_deps.sh): the chute of `chute_wear`,
whose 1616 Gmsh triangles face away from the particles, and the open box of `conveyor`, whose normals
face outward. Polyhedral particles dropped onto each mesh as shipped and onto a copy with every triangle
reversed follow the same trajectories to round-off, none is lost through the wall, and the log states
the mesh's kind."""
import math
import pathlib

import numpy as np
import pytest

import decks

TUTORIALS = pathlib.Path("/usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public")
CHUTE = TUTORIALS / "chute_wear" / "meshes" / "simple_chute.stl"
BOX = TUTORIALS / "conveyor" / "meshes" / "box.stl"

needs_doc = pytest.mark.skipif(not CHUTE.exists() or not BOX.exists(),
                               reason="liggghts-doc is not installed (tools/debian_deps.sh installs it)")


def reverse_stl(source, target):
    """A copy of the ASCII STL `source` with every facet's corners in the opposite order (v0, v2, v1) and its
    normal negated."""
    lines, out, loop = open(source).read().splitlines(), [], []
    for line in lines:
        words = line.split()
        if words[:2] == ["facet", "normal"]:
            out.append("facet normal " + " ".join(repr(-float(w)) for w in words[2:5]))
        elif words[:1] == ["vertex"]:
            loop.append(line)
            if len(loop) == 3:
                out += [loop[0], loop[2], loop[1]]
                loop = []
        else:
            out.append(line)
    pathlib.Path(target).write_text("\n".join(out) + "\n")
    return target


def deck(stl, lo, hi, positions, shape, scale, steps, velocity="0 0 -1"):
    """Particles of one template at `positions`, falling onto the mesh `stl` (type 1, walls and particles of
    one material as in the tutorials); a text dump of every particle at the end."""
    text = (decks.header(boundary="f f f", lo=0.0, hi=1.0, ntypes=1).replace(
                "region box block 0.0 1.0 0.0 1.0 0.0 1.0",
                "region box block {} {} {} {} {} {}".format(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])) +
            "neighbor 0.005 bin\nneigh_modify delay 0\n"
            "fix m1 all property/global youngsModulus peratomtype 5e6\n"
            "fix m2 all property/global poissonsRatio peratomtype 0.45\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n" +
            decks.template("shape", shape, scale=scale, atom_type=1) +
            "pair_style polyhedral/volumetric\npair_coeff * *\n")
    for k, (x, y, z) in enumerate(positions):
        angle = 0.37 * k
        text += (f"create_polyhedron shape {x!r} {y!r} {z!r} quat {math.cos(angle)!r} {0.6 * math.sin(angle)!r} "
                 f"0 {0.8 * math.sin(angle)!r} vel {velocity}\n")
    text += (f"fix wall_mesh all mesh/surface file {stl} type 1\n"
             "fix wall all wall/polyhedral mesh n_meshes 1 meshes wall_mesh\n"
             "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
             "thermo_style custom step atoms ke f_wall[3] f_wall[4]\nthermo_modify lost ignore norm no\n"
             "thermo_modify format float %.15g\nthermo 500\ntimestep 1e-5\n"
             "dump out all custom 1000000 final.dump id x y z vx vy vz\ndump_modify out sort id format \"%d" + " %.17g" * 6 + "\"\n"
             f"run {steps}\n")
    return text


def run_both_windings(run_deck, tmp_path, stl, **kwargs):
    results = {}
    for winding in ("shipped", "reversed"):
        path = stl if winding == "shipped" else reverse_stl(stl, tmp_path / ("reversed_" + stl.name))
        result = run_deck(deck(path, **kwargs), workdir=tmp_path / winding)
        assert result.returncode == 0, result.output[-3000:]
        columns, rows = decks.read_dump(result.workdir / "final.dump")
        results[winding] = (result, rows)
    return results


def compare(results, count, what):
    (shipped, a), (reversed_, b) = results["shipped"], results["reversed"]
    assert sorted(a) == sorted(b) == list(range(1, count + 1)), f"{what}: particles lost"
    worst = max(np.abs(np.array(a[i][1:4]) - np.array(b[i][1:4])).max() for i in a)
    contacts = shipped.thermo("f_wall[4]")["f_wall[4]"]
    ke = shipped.thermo("KinEng")["KinEng"]
    print(f"\n{what}: {count} particles kept, {max(contacts):.0f} wall contacts at most, final KE {ke[-1]:.3e} J, "
          f"shipped vs reversed winding: largest position difference {worst:.1e} m")
    assert max(contacts) > 0, "the particles never reached the wall"
    assert worst < 1e-9, worst
    return shipped


@needs_doc
def test_chute_wear_chute_either_winding(run_deck, tmp_path):
    """27 rock_40 (about 2 cm) thrown onto the chute of chute_wear (1616 triangles, normals facing away
    from the particles as shipped): the same trajectories with the STL reversed, none lost."""
    positions = [(-0.03 + 0.03 * i, -0.03 + 0.03 * j, -0.075 + 0.025 * k)
                 for i in range(3) for j in range(3) for k in range(3)]
    results = run_both_windings(run_deck, tmp_path, CHUTE, lo=(-0.5, -0.2, -0.4), hi=(0.1, 0.2, 0.15),
                                positions=positions, shape="rock_40.obj", scale=0.02, steps=6000,
                                velocity="0 0 -1.5")
    shipped = compare(results, len(positions), "chute_wear chute")
    assert "mesh 'wall_mesh': open, 1616 triangles" in shipped.output
    for _, rows in results.values():
        assert all(rows[i][3] > -0.2 for i in rows), "a particle went through the chute"


@needs_doc
def test_conveyor_open_box_either_winding(run_deck, tmp_path):
    """18 cubes (3 cm) dropped into the corner of the conveyor tutorial's open box (10 triangles, normals
    outward as shipped), against its floor and two walls: the same with the STL reversed, none lost."""
    positions = [(-0.45 + 0.04 * i, 0.12 + 0.04 * j, -0.17 + 0.04 * k)
                 for i in range(3) for j in range(2) for k in range(3)]
    results = run_both_windings(run_deck, tmp_path, BOX, lo=(-0.55, -0.25, -0.25), hi=(0.55, 0.25, 0.4),
                                positions=positions, shape="cube.stl", scale=0.03, steps=6000,
                                velocity="-0.5 0.5 -1")
    shipped = compare(results, len(positions), "conveyor open box")
    assert "mesh 'wall_mesh': open, 10 triangles" in shipped.output
    for _, rows in results.values():
        assert all(-0.5 < rows[i][1] and rows[i][2] < 0.2 and rows[i][3] > -0.2 for i in rows), \
            "a particle went through the box"


@needs_doc
def test_chute_energy_as_with_spheres(run_deck, tmp_path):
    """The chute's rocks against LIGGGHTS' own spheres of the same volume (radius 10 mm) on the same mesh as
    shipped (`fix wall/gran model hertz tangential history`, same material, positions and velocities): no
    sphere or rock is lost, and the rocks end with no more than 3 times the spheres' kinetic energy. Before the
    winding fix they ended with 99 times (5.88 J against 0.0596 J), two of them through the chute."""
    positions = [(-0.03 + 0.03 * i, -0.03 + 0.03 * j, -0.075 + 0.025 * k)
                 for i in range(3) for j in range(3) for k in range(3)]
    rocks = run_deck(deck(CHUTE, lo=(-0.5, -0.2, -0.4), hi=(0.1, 0.2, 0.15), positions=positions,
                          shape="rock_40.obj", scale=0.02, steps=6000, velocity="0 0 -1.5"),
                     workdir=tmp_path / "rocks")
    assert rocks.returncode == 0, rocks.output[-3000:]
    spheres_deck = ("atom_style granular\natom_modify map array sort 0 0\nboundary f f f\nnewton off\n"
                    "communicate single vel yes\nunits si\nregion box block -0.5 0.1 -0.2 0.2 -0.4 0.15\n"
                    "create_box 1 box\nneighbor 0.005 bin\nneigh_modify delay 0\n"
                    "fix m1 all property/global youngsModulus peratomtype 5e6\n"
                    "fix m2 all property/global poissonsRatio peratomtype 0.45\n"
                    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n"
                    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n"
                    "pair_style gran model hertz tangential history\npair_coeff * *\n" +
                    "".join(f"create_atoms 1 single {x!r} {y!r} {z!r}\n" for x, y, z in positions) +
                    "set group all diameter 0.02 density 2500\nvelocity all set 0 0 -1.5\n"
                    f"fix wall_mesh all mesh/surface file {CHUTE} type 1\n"
                    "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes wall_mesh\n"
                    "fix integrate all nve/sphere\nfix gravity all gravity 9.81 vector 0 0 -1\n"
                    "thermo_style custom step atoms ke\nthermo_modify lost ignore norm no\n"
                    "thermo_modify format float %.15g\nthermo 500\ntimestep 1e-5\nrun 6000\n")
    spheres = run_deck(spheres_deck, workdir=tmp_path / "spheres")
    assert spheres.returncode == 0, spheres.output[-3000:]
    a, b = rocks.thermo("Atoms", "KinEng"), spheres.thermo("Atoms", "KinEng")
    ratio = a["KinEng"][-1] / b["KinEng"][-1]
    print(f"\nchute: rocks end with {a['KinEng'][-1]:.3e} J, spheres with {b['KinEng'][-1]:.3e} J (ratio {ratio:.2f})")
    assert a["Atoms"][-1] == b["Atoms"][-1] == len(positions)
    assert ratio < 3.0, ratio
