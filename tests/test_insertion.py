"""fix particletemplate/polyhedron with LIGGGHTS' insertion: fix particledistribution/discrete and
fix insert/pack, insert/stream, insert/rate/region.

A polydisperse mix of three templates (rock, Schönhardt, cube; three sizes) is inserted; checked:
the particle count, the template proportions against the number fractions LIGGGHTS prints for the
distribution, the mass, bounding radius and inertia of each particle from its shape, no overlapping
pair at insertion (exact overlap volumes through compute pair/polyhedral/local), random or constant
orientations as asked, the insertion velocity, and 1 against 2 MPI ranks.

Issue 12 (insertion by the shape, not the bounding sphere): 300 particles of 1 cm^3 (cubes, rock_40) in an
8.4 x 8.4 x 28 cm column with insert/pack all_in yes on 1 and 2 ranks, a second insert/pack around existing
particles, and insert/stream; checked: the count, no overlapping pair, every vertex inside the region.
"""
import math
import re

import numpy as np
import pytest

import decks
from test_dump_vtk import read_vtp

TEMPLATES = (("t1", "rock_40.obj", 0.01), ("t2", "schoenhardt.stl", 0.012), ("t3", "cube.stl", 0.008))
DENSITY = 2500.0


def box(lo, hi, z_lo, z_hi, ntypes):
    """A box with fixed walls, [lo, hi] in x and y and [z_lo, z_hi] in z, and the materials of `ntypes` types."""
    return (decks.header(boundary="f f f", lo=lo, hi=hi, ntypes=ntypes).replace(
                f"region box block {lo} {hi} {lo} {hi} {lo} {hi}", f"region box block {lo} {hi} {lo} {hi} {z_lo} {z_hi}") +
            "neighbor 0.002 bin\nneigh_modify delay 0\n"
            f"fix m1 all property/global youngsModulus peratomtype{' 1e7' * ntypes}\n"
            f"fix m2 all property/global poissonsRatio peratomtype{' 0.25' * ntypes}\n"
            f"fix m3 all property/global coefficientRestitution peratomtypepair {ntypes}{' 0.5' * ntypes ** 2}\n"
            f"fix m4 all property/global coefficientFriction peratomtypepair {ntypes}{' 0.5' * ntypes ** 2}\n")


def scene(insertion, run="run 1\n"):
    seeds = (15485863, 32452843, 49979687)
    return (box(-0.1, 0.1, 0, 0.6, ntypes=2) +
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
                            "particles_in_region 2000 region ins\n", run="run 1\nrun 0\n"))
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
    # No overlap (exact volumes) where they were inserted: no contact. The insertion's messages break the thermo
    # table of `run 1`; `run 0` prints the row of step 1.
    contacts = result.thermo("Step", "c_contacts")
    assert contacts["Step"][-1] == 1 and contacts["c_contacts"][-1] == 0, contacts


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
    one = run_deck(scene(insertion, run="run 200\nrun 0\n"), workdir=tmp_path / "one")
    two = run_deck(scene(insertion, run="run 200\nrun 0\n"), nprocs=2, workdir=tmp_path / "two")
    a, _ = check_mix(one, 1000)
    b, _ = check_mix(two, 1000)
    # Inserted without overlap, falling together: no contact at step 200 (printed by the `run 0`).
    for result in (one, two):
        contacts = result.thermo("Step", "c_contacts")
        assert contacts["Step"][-1] == 200 and contacts["c_contacts"][-1] == 0, contacts
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


# Issue 12: a column of 300 particles of 1 cm^3, cubes of edge 1 cm and rock_40 scaled to the same volume, in an
# 8.4 x 8.4 x 28 cm region. By bounding spheres (diameters 1.73 and 1.67 cm) insert/pack fitted about 200.
COLUMN_LO, COLUMN_HI = np.array([0.0, 0.0, 0.0]), np.array([0.084, 0.084, 0.28])
COLUMN_SHAPES = {"cube": ("cube.stl", 0.01), "rock_40": ("rock_40.obj", 0.0124)}
PACK = ("fix {id} all insert/pack seed {seed} distributiontemplate pdd insert_every once overlapcheck yes "
        "orientation random all_in yes particles_in_region {n} region column\n")


def column(shape, insertion, run="run 1\n"):
    """`run` inserts; a `run 0` then prints the thermo row of the insertion step (the insertion's messages break
    the table of the run that inserts, so DeckResult.thermo does not see that row)."""
    file, scale = COLUMN_SHAPES[shape]
    return (box(-0.01, 0.094, -0.01, 0.29, ntypes=1) + decks.template("t1", file, scale=scale) +
            "fix pdd all particledistribution/discrete 15485867 1 t1 1.0\n"
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "region column block 0 0.084 0 0.084 0 0.28\n" + insertion +
            "fix integrate all nve/polyhedron\ncompute contacts all pair/polyhedral/local\n"
            "thermo_style custom step atoms c_contacts\ntimestep 1e-5\n"
            "dump centres all custom 1 centres.txt id x y z\ndump_modify centres format \"%d %.17g %.17g %.17g\"\n"
            "dump surfaces all polyhedron/vtk 1 surfaces_*.vtp\n" + run + "run 0\n")


def check_column(result, count, all_in=True):
    """`count` particles, none overlapping another (exact overlap volumes through compute pair/polyhedral/local),
    with all_in every vertex inside the region; returns the smallest distance of a centre from the region's walls
    over the bounding radius."""
    assert result.returncode == 0, result.output[-3000:]
    assert "Less insertions than requested" not in result.output
    contacts = result.thermo("Step", "c_contacts")
    assert contacts["c_contacts"][-1] == 0, contacts
    step = int(contacts["Step"][-1])
    _, _, arrays = read_vtp(result.workdir / f"surfaces_{step}.vtp")
    assert len(set(arrays["id"].astype(int))) == count
    points = arrays["points"]
    if all_in:
        assert np.all(points >= COLUMN_LO) and np.all(points <= COLUMN_HI), (points.min(axis=0), points.max(axis=0))
    _, rows = decks.read_dump(result.workdir / "centres.txt")
    centres = np.array(list(rows.values()))[:, 1:4]
    radius = float(re.search(r"bounding radius ([0-9.e+-]+),", result.output).group(1))
    return np.minimum(centres - COLUMN_LO, COLUMN_HI - centres).min() / radius


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("shape", list(COLUMN_SHAPES))
def test_insert_pack_column_by_shape(run_deck, shape, nprocs):
    """All 300 inserted, on 1 and 2 ranks (the column is split in z): exact overlaps, all_in by the vertices."""
    result = run_deck(column(shape, PACK.format(id="ins", seed=86028121, n=300)), nprocs=nprocs)
    assert "inserted 300 particle templates" in result.output
    closest = check_column(result, 300)
    print(f"\n{shape} on {nprocs} rank(s): 300 inserted; closest centre {closest:.2f} bounding radii from a wall")
    # Particles touch the walls closer than their bounding spheres would let them.
    assert closest < 0.9


def test_insert_pack_around_existing_particles(run_deck):
    """A second insert/pack adds 50 cubes to 250 already in the column, on 2 ranks: the existing particles (owned
    and ghost) are found in the atom arrays with their shapes and orientations. Were their bounding spheres
    taken instead, 11 to 13 would fit."""
    deck = column("cube", PACK.format(id="first", seed=86028121, n=250),
                  run="run 1\nunfix first\n" + PACK.format(id="second", seed=32452867, n=300) + "run 1\n")
    result = run_deck(deck, nprocs=2)
    assert "second: inserted 50 particle templates" in result.output
    check_column(result, 300)


def test_insert_stream_checks_exact_overlap(run_deck, tmp_path):
    """insert/stream: 100 cubes a step into the extruded face (8.4 x 8.4 x 5 cm above the face): the particles
    inserted in the same step are checked by their shapes. By bounding spheres 57 fitted."""
    (tmp_path / "face.stl").write_text(
        "solid face\n" + "".join(
            "facet normal 0 0 1\nouter loop\n" + "".join(f"vertex {x} {y} 0.23\n" for x, y in tri) +
            "endloop\nendfacet\n" for tri in (((0, 0), (0.084, 0.084), (0.084, 0)),
                                                ((0, 0), (0, 0.084), (0.084, 0.084)))) +
        "endsolid face\n")
    insertion = ("fix face all mesh/surface file face.stl type 1\n"
                 "fix ins all insert/stream seed 86028121 distributiontemplate pdd nparticles 100 particlerate 2000 "
                 "overlapcheck yes orientation random vel constant 0 0 -1 insertion_face face extrude_length 0.05\n")
    result = run_deck(column("cube", insertion), workdir=tmp_path)
    assert "inserted 100 particle templates" in result.output
    check_column(result, 100, all_in=False)


def test_screen_none_with_insert_pack_in_a_cylinder(launcher, tmp_path):
    """`-screen none` left LIGGGHTS' screen NULL, and fix insert/pack in a cylinder region writes to it unguarded
    (Region::reset_random): a segmentation fault on the first run, Debian's own liggghts included. The launcher
    sends the screen to /dev/null instead: the run completes and the log has it all."""
    import os
    import subprocess

    from conftest import MPI_ENV, SHAPES
    deck = (box(-0.1, 0.1, 0, 0.3, ntypes=2) + decks.template("t1", "rock_40.obj", scale=0.01) +
            "fix pdd all particledistribution/discrete 15485867 1 t1 1.0\n"
            "pair_style polyhedral/volumetric\npair_coeff * *\n"
            "region column cylinder z 0 0 0.05 0.01 0.25\n"
            "fix ins all insert/pack seed 86028121 distributiontemplate pdd insert_every once overlapcheck yes "
            "orientation random all_in yes particles_in_region 20 region column\n"
            "fix integrate all nve/polyhedron\ntimestep 1e-5\nrun 10\n")
    (tmp_path / "in.deck").write_text(deck)
    result = subprocess.run([str(launcher), "-in", "in.deck", "-log", "log.deck", "-screen", "none",
                             "-var", "SHAPES", str(SHAPES)], cwd=tmp_path, capture_output=True, text=True,
                            env=dict(os.environ, **MPI_ENV), timeout=120)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    log = (tmp_path / "log.deck").read_text()
    assert "inserted 20 particle templates" in log and "Loop time of" in log
