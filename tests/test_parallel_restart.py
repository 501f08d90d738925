"""atom_style polyhedron across MPI ranks, restart files, data files and delete_atoms.

Without contacts the particles fly freely, so any difference between 1 and 2
ranks, or between a restarted and an unbroken run, is a bug in how the
polyhedral per-particle fields travel (migration, ghosts, restart, data); the
settled bed's test has contacts, and compares a restart with the same run
split at its step."""
import pathlib
import random

import numpy as np

import decks

COLUMNS = "id type x y z vx vy vz omegax omegay omegaz angmomx angmomy angmomz " \
          "c_p[1] c_p[2] c_p[3] c_p[4] c_p[5] ix iy iz"
FORMAT = " ".join(["%d", "%d"] + ["%.17g"] * 17 + ["%d"] * 3)


def cloud(n=60, seed=7):
    """Random particles of three templates with random orientation, velocity and spin.
    Box 0..1 periodic; velocities of ~1 m/s over 0.4 s carry every particle across
    the rank boundary at x = 0.5 (and across the periodic faces) several times."""
    rng = random.Random(seed)
    lines = []
    for k in range(n):
        template = ["cube", "rock", "schoenhardt"][k % 3]
        q = [rng.uniform(-1, 1) for _ in range(4)]
        position = [rng.uniform(0.0, 1.0) for _ in range(3)]
        velocity = [rng.uniform(-1.5, 1.5) for _ in range(3)]
        omega = [rng.uniform(-30, 30) for _ in range(3)]
        lines.append("create_polyhedron %s %.6f %.6f %.6f quat %.6f %.6f %.6f %.6f vel %.6f %.6f %.6f "
                     "omega %.6f %.6f %.6f\n" % tuple([template] + position + q + velocity + omega))
    return "".join(lines)


def templates():
    return (decks.template("cube", "cube.stl", scale=0.03) +
            decks.template("rock", "rock_70.obj", scale=0.04, density=2700.0) +
            decks.template("schoenhardt", "schoenhardt.stl", scale=0.03, density=1500.0, atom_type=2))


def integration(dump_every):
    return ("fix integrate all nve/polyhedron\n"
            "compute p all property/polyhedron shape quatw quati quatj quatk\n"
            "timestep 1e-4\n"
            f"dump state all custom {dump_every} state.txt {COLUMNS}\n"
            f"dump_modify state format \"{FORMAT}\" sort id\n")


def compare(rows_a, rows_b, tolerance):
    assert sorted(rows_a) == sorted(rows_b)
    worst = 0.0
    for atom_id in rows_a:
        a, b = np.array(rows_a[atom_id]), np.array(rows_b[atom_id])
        worst = max(worst, float(np.max(np.abs(a - b))))
    assert worst <= tolerance, worst
    return worst


def test_one_and_two_ranks_give_the_same_trajectories(run_deck, tmp_path):
    deck = decks.header(ntypes=2, processors="* 1 1") + templates() + cloud() + integration(1000) + "run 4000\n"
    serial = run_deck(deck, workdir=tmp_path / "serial")
    parallel = run_deck(deck, nprocs=2, workdir=tmp_path / "parallel")
    assert serial.returncode == 0, serial.output
    assert parallel.returncode == 0, parallel.output
    assert "2 by 1 by 1 MPI processor grid" in parallel.output
    snapshots_serial = decks.read_all_dump_snapshots(serial.workdir / "state.txt")
    snapshots_parallel = decks.read_all_dump_snapshots(parallel.workdir / "state.txt")
    assert len(snapshots_serial) == len(snapshots_parallel) == 5
    # The cloud really moves between the two ranks' halves (x < 0.5, x >= 0.5) between snapshots,
    # and across the periodic faces (image flags change).
    x_column = snapshots_serial[0][1].index("x")
    crossings = sum(1 for (_, _, before), (_, _, after) in zip(snapshots_serial, snapshots_serial[1:])
                    for atom_id in before if (before[atom_id][x_column] < 0.5) != (after[atom_id][x_column] < 0.5))
    print(f"particles changing rank half between snapshots: {crossings}")
    assert crossings >= 20, crossings
    ix = snapshots_serial[0][1].index("ix")
    wrapped = sum(1 for row in snapshots_serial[-1][2].values() if row[ix] != 0)
    assert wrapped >= 10, wrapped
    for (step_a, _, rows_a), (step_b, _, rows_b) in zip(snapshots_serial, snapshots_parallel):
        assert step_a == step_b
        assert len(rows_a) == 60  # no particle lost
        # Free flight does the same arithmetic on every rank: identical to the last bit.
        compare(rows_a, rows_b, 0.0)


def test_restart_continues_exactly_like_an_unbroken_run(run_deck, tmp_path):
    unbroken = run_deck(decks.header(ntypes=2) + templates() + cloud() + integration(2000) + "run 2000\n",
                        workdir=tmp_path / "unbroken")
    assert unbroken.returncode == 0, unbroken.output
    first = run_deck(decks.header(ntypes=2) + templates() + cloud() + integration(1000) +
                     "run 1000\nwrite_restart half.restart\n", nprocs=2, workdir=tmp_path / "first")
    assert first.returncode == 0, first.output
    second = run_deck("atom_modify sort 0 0\nread_restart ../first/half.restart\n" + templates() +
                      integration(1000) + "run 1000\n", workdir=tmp_path / "second")
    assert second.returncode == 0, second.output
    _, rows_unbroken = decks.read_dump(unbroken.workdir / "state.txt")
    _, rows_restarted = decks.read_dump(second.workdir / "state.txt")
    compare(rows_unbroken, rows_restarted, 0.0)


def test_restart_with_templates_in_the_wrong_order_is_an_error(run_deck, tmp_path):
    first = run_deck(decks.header(ntypes=2) + templates() + cloud(6) + integration(10) +
                     "run 10\nwrite_restart half.restart\n", workdir=tmp_path / "first")
    assert first.returncode == 0, first.output
    swapped = (decks.template("rock", "rock_70.obj", scale=0.04, density=2700.0) +
               decks.template("cube", "cube.stl", scale=0.03) +
               decks.template("schoenhardt", "schoenhardt.stl", scale=0.03, density=1500.0, atom_type=2))
    second = run_deck("atom_modify sort 0 0\nread_restart ../first/half.restart\n" + swapped +
                      integration(10) + "run 10\n", workdir=tmp_path / "second")
    assert second.returncode != 0
    assert any("does not match shape" in line for line in second.error_lines()), second.output


def test_write_data_read_data_round_trip(run_deck, tmp_path):
    first = run_deck(decks.header(ntypes=2) + templates() + cloud(12) + integration(100) +
                     "run 100\nwrite_data state.data\n", workdir=tmp_path / "first")
    assert first.returncode == 0, first.output
    second = run_deck("atom_style polyhedron\natom_modify map array sort 0 0\nnewton off\n"
                      "communicate single vel yes\nread_data ../first/state.data\n" + templates() +
                      integration(100) + "run 0\n", workdir=tmp_path / "second")
    assert second.returncode == 0, second.output
    _, rows_written = decks.read_dump(first.workdir / "state.txt")
    _, rows_read = decks.read_dump(second.workdir / "state.txt")
    # The data file prints 17 significant digits; omega is rebuilt from angmom.
    compare(rows_written, rows_read, 1e-12)


def test_delete_atoms_keeps_the_fields_of_the_survivors(run_deck):
    deck = (decks.header(ntypes=2) + templates() + cloud(30) + integration(1) +
            "run 0\nundump state\nregion left block 0 0.5 INF INF INF INF\ndelete_atoms region left compress no\n" +
            "dump after all custom 1 after.txt %s\ndump_modify after format \"%s\" sort id\nrun 0\n"
            % (COLUMNS, FORMAT))
    result = run_deck(deck)
    assert result.returncode == 0, result.output
    _, before = decks.read_dump(result.workdir / "state.txt")
    _, after = decks.read_dump(result.workdir / "after.txt")
    survivors = {i: row for i, row in before.items() if row[2] >= 0.5}
    assert 0 < len(after) < len(before)
    compare(survivors, after, 0.0)


def test_restart_of_a_settled_bed_continues_as_the_same_run_split_there(run_deck, tmp_path):
    """With contacts: the settled bed of decks.settled_bed_energies (2000 Schoenhardt polyhedra on their plane
    wall, friction, damping, rocking damping), examples/gravity_packing/in.packing's own restart path (save, then
    resume), on one rank (on two, the sums' order differs: 5e-13 m). A restart keeps every per-particle and
    per-contact field, so 10 steps written to a restart and 10 more after reading it give the positions, to the
    bit, of one deck that runs the same `run` commands without the file (in.packing's `split 10`: `run 0` and
    `run 10`, twice). Against one unbroken run of 20 steps they differ (measured 4.9e-8 m): each `run` sets up
    with forces at full-step velocities, the damping's among them, where the unbroken run had half-step ones, as
    in LIGGGHTS' own granular styles."""
    root = pathlib.Path(__file__).resolve().parent.parent
    deck = (root / "examples" / "gravity_packing" / "in.packing").read_text()
    common = {"N": 2000, "wall": 1, "M": 10, "count": 0, "final": 1,
              "data": root / "tests" / "data" / "settled_bed_N2000.data"}

    def positions(path):
        lines = pathlib.Path(path).read_text().splitlines()
        last = max(k for k, line in enumerate(lines) if line == "ITEM: TIMESTEP")
        step, count = int(lines[last + 1]), int(lines[last + 3])
        return step, {int(w.split()[0]): tuple(float(x) for x in w.split()[2:5])
                      for w in lines[last + 9:last + 9 + count]}

    first = run_deck(deck, workdir=tmp_path / "first", variables=dict(
        common, steps=10, save=1, restartfile="half.restart", finalname="first.dump"))
    assert first.returncode == 0, first.output[-3000:]
    second = run_deck(deck, workdir=tmp_path / "second", variables=dict(
        common, steps=10, resume=1, restartfile="../first/half.restart", finalname="second.dump"))
    assert second.returncode == 0, second.output[-3000:]
    whole = run_deck(deck, workdir=tmp_path / "split", variables=dict(common, steps=20, split=10,
                                                                       finalname="split.dump"))
    assert whole.returncode == 0, whole.output[-3000:]
    step_a, restarted = positions(tmp_path / "second" / "second.dump")
    step_b, unbroken = positions(tmp_path / "split" / "split.dump")
    assert step_a == step_b == 20 and len(restarted) == 2000
    worst = max(max(abs(p - q) for p, q in zip(restarted[k], unbroken[k])) for k in unbroken)
    moved = max(max(abs(p - q) for p, q in zip(restarted[k], positions(tmp_path / "first" / "first.dump")[1][k]))
                for k in restarted)
    print(f"\nsettled bed: restart against the split run {worst:.3g} m; moved over the last 10 steps up to "
          f"{moved:.3g} m")
    assert moved > 0.0
    assert worst == 0.0, worst
