"""fix particletemplate/polyhedron with LIGGGHTS' insertion: fix particledistribution/discrete and
fix insert/pack, insert/stream, insert/rate/region.

A polydisperse mix of three templates (rock, Schönhardt, cube; three sizes) is inserted; checked:
the particle count, the template proportions against the number fractions LIGGGHTS prints for the
distribution, the mass, bounding radius and inertia of each particle from its shape, no overlapping
pair at insertion (exact overlap volumes through compute pair/polyhedral/local), random or constant
orientations as asked, the insertion velocity, and 1 against 2 MPI ranks.
"""
import math
import re

import numpy as np
import pytest

import decks

TEMPLATES = (("t1", "rock_40.obj", 0.01), ("t2", "schoenhardt.stl", 0.012), ("t3", "cube.stl", 0.008))
DENSITY = 2500.0


def scene(insertion, run="run 1\n"):
    seeds = (15485863, 32452843, 49979687)
    return (decks.header(boundary="f f f", lo=-0.1, hi=0.1, ntypes=2).replace(
                "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1", "region box block -0.1 0.1 -0.1 0.1 0 0.6") +
            "neighbor 0.002 bin\nneigh_modify delay 0\n"
            "fix m1 all property/global youngsModulus peratomtype 1e7 1e7\n"
            "fix m2 all property/global poissonsRatio peratomtype 0.25 0.25\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n" +
            "".join(decks.template(name, path, scale=scale, density=DENSITY, seed=seed)
                    for (name, path, scale), seed in zip(TEMPLATES, seeds)) +
            "fix pdd all particledistribution/discrete 15485867 3 t1 0.5 t2 0.3 t3 0.2\n"
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"
            "region ins block -0.09 0.09 -0.09 0.09 0.01 0.59\n" + insertion +
            "fix integrate all nve/polyhedron\nfix gravity all gravity 9.81 vector 0 0 -1\n"
            "compute contacts all pair/polyhedral/local\n"
            "compute props all property/polyhedron shape quatw quati quatj quatk inertiax inertiay inertiaz\n"
            "thermo_style custom step atoms c_contacts\ntimestep 1e-5\n"
            "dump d all custom 1 particles.txt id type c_props[1] mass radius vz c_props[2] c_props[3] "
            "c_props[4] c_props[5] c_props[6] c_props[7] c_props[8]\n"
            "dump_modify d format \"%d %d" + " %.17g" * 11 + "\"\n" + run)


def particles(result):
    """The last dump frame as an array: id type shape mass radius vz qw qi qj qk Ix Iy Iz."""
    columns, rows = decks.read_dump(result.workdir / "particles.txt")
    return np.array([rows[k] for k in sorted(rows)], dtype=float)


def number_fractions(output):
    """number% per template as LIGGGHTS printed it for the distribution."""
    block = output[output.index("distribution based on number%"):]
    return [float(x) / 100.0 for x in re.findall(r"number%=([0-9.]+)%", block)[:3]]


def write_face(directory):
    """insert/stream's entry: a square face (a mesh/surface of two triangles) at z = 0.35."""
    (directory / "face.stl").write_text(
        "solid face\n" + "".join(
            "facet normal 0 0 -1\nouter loop\n" + "".join(f"vertex {x} {y} 0.35\n" for x, y in tri) +
            "endloop\nendfacet\n" for tri in (((-0.09, -0.09), (0.09, 0.09), (0.09, -0.09)),
                                                ((-0.09, -0.09), (-0.09, 0.09), (0.09, 0.09)))) +
        "endsolid face\n")


def check_mix(result, count):
    assert result.returncode == 0, result.output[-3000:]
    table = particles(result)
    assert len(table) == count
    expected = number_fractions(result.output)
    shapes = table[:, 2].astype(int)
    for shape, fraction in zip((1, 2, 3), expected):
        n = int(np.sum(shapes == shape))
        sigma = math.sqrt(count * fraction * (1 - fraction))
        assert abs(n - count * fraction) < 4 * sigma, (shape, n, count * fraction)
    return table, expected


def test_insert_pack_polydisperse_mix(run_deck):
    """2000 particles of three templates with random orientations, falling at 0.5 m/s."""
    result = run_deck(scene("fix ins all insert/pack seed 86028121 distributiontemplate pdd insert_every once "
                            "overlapcheck yes orientation random vel constant 0. 0. -0.5 all_in yes "
                            "particles_in_region 2000 region ins\n"))
    table, expected = check_mix(result, 2000)
    log = result.output
    volumes = {int(m.group(1)): float(m.group(2)) for m in
               re.finditer(r"shape (\d+) from .*?volume ([0-9.e+-]+), bounding radius", log)}
    radii = {int(m.group(1)): float(m.group(2)) for m in
             re.finditer(r"shape (\d+) from .*?bounding radius ([0-9.e+-]+),", log)}
    moments = {int(m.group(1)): [float(x) for x in m.group(2).split()] for m in
               re.finditer(r"shape (\d+) from .*?principal moments/density ([0-9.e+ -]+)\n", log)}
    for row in table:
        shape = int(row[2])
        # the log prints volume and radius to 10 significant digits, the moments to 6
        assert abs(row[3] - DENSITY * volumes[shape]) < 1e-9 * row[3]
        assert abs(row[4] - radii[shape]) < 1e-9 * row[4]
        assert np.allclose(row[10:13], DENSITY * np.array(moments[shape]), rtol=1e-5)
    quaternions = table[:, 6:10]
    assert np.allclose(np.linalg.norm(quaternions, axis=1), 1.0, atol=1e-12)
    # Random orientations: the body z axis points everywhere (mean of its world z ~ 0, spread ~ 1/sqrt 3).
    qw, qi, qj, qk = quaternions.T
    body_z_world_z = 1 - 2 * (qi ** 2 + qj ** 2)
    print(f"\n2000 inserted: shapes {[int(np.sum(table[:, 2] == s)) for s in (1, 2, 3)]} for number fractions "
          f"{expected}; body z . world z mean {body_z_world_z.mean():+.3f}, std {body_z_world_z.std():.3f}")
    assert abs(body_z_world_z.mean()) < 0.1 and abs(body_z_world_z.std() - 1 / math.sqrt(3)) < 0.05
    # Inserted at 0.5 m/s downwards; one step of gravity later
    assert np.allclose(table[:, 5], -0.5, atol=1e-3)
    # Bounding spheres do not overlap, so no contact at all after the first step.
    contacts = result.thermo("Step", "c_contacts")
    assert contacts["c_contacts"][-1] == 0, contacts


def test_orientation_constant_and_template(run_deck, tmp_path):
    common = ("fix ins all insert/pack seed 86028121 distributiontemplate pdd insert_every once overlapcheck yes "
              "{orientation} all_in yes particles_in_region 200 region ins\n")
    q = (math.cos(0.2), 0.0, math.sin(0.2), 0.0)
    constant = run_deck(scene(common.format(orientation="orientation constant %r %r %r %r" % q)),
                        workdir=tmp_path / "constant")
    template = run_deck(scene(common.format(orientation="")), workdir=tmp_path / "template")
    for result, expected in ((constant, q), (template, (1.0, 0.0, 0.0, 0.0))):
        table, _ = check_mix(result, 200)
        assert np.allclose(table[:, 6:10], expected, atol=1e-12), table[:3, 6:10]


def test_one_and_two_ranks_insert_the_same_mix(run_deck, tmp_path):
    insertion = ("fix ins all insert/pack seed 86028121 distributiontemplate pdd insert_every once overlapcheck yes "
                 "orientation random all_in yes particles_in_region 1000 region ins\n")
    one = run_deck(scene(insertion, run="run 200\n"), workdir=tmp_path / "one")
    two = run_deck(scene(insertion, run="run 200\n"), nprocs=2, workdir=tmp_path / "two")
    a, _ = check_mix(one, 1000)
    b, _ = check_mix(two, 1000)
    assert one.thermo("Step", "c_contacts")["c_contacts"][0] == two.thermo("Step", "c_contacts")["c_contacts"][0] == 0
    # Total mass within the binomial spread of the mix.
    print(f"\n1 rank: mass {a[:, 3].sum():.6g} kg, 2 ranks: {b[:, 3].sum():.6g} kg")
    assert abs(a[:, 3].sum() / b[:, 3].sum() - 1) < 0.05


@pytest.mark.parametrize("insertion", [
    "fix ins all insert/rate/region seed 86028121 distributiontemplate pdd nparticles 150 particlerate 150000 "
    "insert_every 100 overlapcheck yes orientation random vel constant 0. 0. -0.2 region ins\n",
    "fix face all mesh/surface file face.stl type 2\n"
    "fix ins all insert/stream seed 86028121 distributiontemplate pdd nparticles 150 particlerate 150000 "
    "overlapcheck yes orientation random vel constant 0. 0. -0.5 insertion_face face "
    "extrude_length 0.2\n",
], ids=["rate-region", "stream"])
def test_rate_and_stream_insertion(run_deck, tmp_path, insertion):
    write_face(tmp_path)
    result = run_deck(scene(insertion, run="run 300\n"), workdir=tmp_path)
    table, _ = check_mix(result, 150)
    assert set(table[:, 2].astype(int)) == {1, 2, 3}
