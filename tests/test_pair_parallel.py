"""pair polyhedral/volumetric across MPI ranks and restarts.

A bed of 36 fixed cubes (no time integration) and 164 rocks and Schönhardt
polyhedra falling onto it and onto each other under gravity: contacts between
particles on different ranks, ghosts, migration and contact history all in play."""
import random

import decks

MATERIALS = """\
neighbor 0.004 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 5e6 5e6
fix m2 all property/global poissonsRatio peratomtype 0.25 0.25
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5
fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
"""


def templates():
    return (decks.template("bed", "cube.stl", scale=0.02, atom_type=2) +
            decks.template("rock", "rock_40.obj", scale=0.018, density=2700.0) +
            decks.template("schoenhardt", "schoenhardt.stl", scale=0.015, density=2500.0))


def particles(seed=11):
    rng = random.Random(seed)
    lines = []
    for i in range(6):
        for j in range(6):
            lines.append("create_polyhedron bed %.4f %.4f 0.01\n" % (0.02 + 0.02 * i, 0.02 + 0.02 * j))
    # Bounding spheres  start apart: spacing 0.026 (bounding radii 0.012 and 0.0115).
    spots = [(0.015 + 0.03 * i, 0.015 + 0.03 * j, 0.034 + 0.026 * k)
             for i in range(4) for j in range(4) for k in range(11)]
    rng.shuffle(spots)
    for n, (x, y, z) in enumerate(spots[:164]):
        q = [rng.uniform(-1, 1) for _ in range(4)]
        v = [rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-1.0, -0.5)]
        lines.append("create_polyhedron %s %.5f %.5f %.5f quat %.4f %.4f %.4f %.4f vel %.4f %.4f %.4f\n"
                     % (("rock" if n % 2 else "schoenhardt"), x, y, z, *q, *v))
    return "".join(lines)


def simulation():
    return """\
group moving type 1
fix integrate moving nve/polyhedron
fix gravity moving gravity 9.81 vector 0 0 -1
compute contacts all pair/polyhedral/local
compute erot all erotate/polyhedron
thermo_style custom step atoms ke c_erot c_contacts
thermo_modify format float %.15g
thermo 400
timestep 2e-5
"""


def setup(processors="* * 1"):
    return (decks.header(boundary="p p f", lo=0.0, hi=0.12, ntypes=2, processors=processors).replace(
        "region box block 0.0 0.12 0.0 0.12 0.0 0.12", "region box block 0.0 0.12 0.0 0.12 -0.01 0.5") +
        MATERIALS + templates() + "pair_style polyhedral/volumetric\npair_coeff * *\n" + particles() + simulation())


def test_one_two_four_ranks_agree(run_deck, tmp_path):
    runs = {}
    for ranks in (1, 2, 4):
        result = run_deck(setup() + "run 4800\n", nprocs=ranks, workdir=tmp_path / f"ranks{ranks}")
        assert result.returncode == 0, result.output
        runs[ranks] = result.thermo("Step", "Atoms", "KinEng", "c_erot", "c_contacts")
    serial = runs[1]
    assert serial["Atoms"][-1] == 200  # nothing lost
    assert max(serial["c_contacts"]) >= 80, serial["c_contacts"]  # a real pile, not a free fall
    for ranks in (2, 4):
        other = runs[ranks]
        assert other["Step"] == serial["Step"] and other["Atoms"][-1] == 200
        # Contact counts identical. Energies agree to round-off growth: on several ranks
        # the contact forces on a particle are summed in another order, and colliding
        # grains amplify 1e-16 differences (measured: about 1e-8 relative after 4800 steps).
        assert other["c_contacts"] == serial["c_contacts"], (ranks, other["c_contacts"], serial["c_contacts"])
        worst = max(abs(a - b) / max(abs(a), 1e-12) for column in ("KinEng", "c_erot")
                    for a, b in zip(serial[column], other[column]))
        print(f"{ranks} ranks: largest relative energy difference to 1 rank {worst:.2e}")
        assert worst <= 1e-6, (ranks, worst)


def test_restart_continues_identically(run_deck, tmp_path):
    # The reference continues in the same process across a run boundary at the same
    # step: every `run` starts by recomputing forces from the current velocities, and
    # damping forces depend on them, so any run boundary (restart or not) changes the
    # trajectory slightly; a restart must change nothing beyond that.
    unbroken = run_deck(setup() + "run 2400\nrun 2400\n", nprocs=2, workdir=tmp_path / "unbroken")
    assert unbroken.returncode == 0, unbroken.output
    first = run_deck(setup() + "run 2400\nwrite_restart half.restart\n", nprocs=2, workdir=tmp_path / "first")
    assert first.returncode == 0, first.output
    resumed = ("atom_modify sort 0 0\nread_restart ../first/half.restart\nnewton off\ncommunicate single vel yes\n" + MATERIALS + templates() +
               "pair_style polyhedral/volumetric\npair_coeff * *\n" + simulation() + "run 2400\n")
    second = run_deck(resumed, nprocs=2, workdir=tmp_path / "second")
    assert second.returncode == 0, second.output
    whole = unbroken.thermo("Step", "KinEng", "c_erot", "c_contacts")
    tail = second.thermo("Step", "KinEng", "c_erot", "c_contacts")
    start = len(whole["Step"]) - 1 - whole["Step"][::-1].index(2400.0)  # the second run's table
    assert tail["Step"] == whole["Step"][start:]
    assert max(tail["c_contacts"]) > 0
    # Same ranks, same decomposition, history restored: identical contacts, and energies
    # equal up to round-off (read_restart hands particles to the ranks in another order,
    # so forces are summed in another order; measured about 1e-13 relative).
    assert tail["c_contacts"] == whole["c_contacts"][start:]
    worst = max(abs(a - b) / abs(b) for column in ("KinEng", "c_erot")
                for a, b in zip(tail[column], whole[column][start:]))
    print(f"restart: largest relative energy difference {worst:.2e}")
    assert worst <= 1e-8, worst  # measured 3.5e-10
