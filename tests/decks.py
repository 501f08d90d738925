"""Deck fragments shared by the LIGGGHTS-level tests."""
import math

HEADER = """\
atom_style polyhedron
atom_modify map array sort 0 0
{processors}boundary {boundary}
newton off
communicate single vel yes
units si
region box block {lo} {hi} {lo} {hi} {lo} {hi}
create_box {ntypes} box
"""

TEMPLATE = ("fix {id} all particletemplate/polyhedron {seed} atom_type {atom_type} "
            "density constant {density} file ${{SHAPES}}/{file} scale {scale}\n")


def header(boundary="p p p", lo=0.0, hi=1.0, ntypes=1, processors=None):
    """processors: e.g. "2 1 1" to fix the decomposition (LIGGGHTS picks one otherwise)."""
    grid = f"processors {processors}\n" if processors else ""
    return HEADER.format(boundary=boundary, lo=lo, hi=hi, ntypes=ntypes, processors=grid)


def template(id, file, scale=1.0, density=2500.0, atom_type=1, seed=15485863):
    return TEMPLATE.format(id=id, file=file, scale=scale, density=density, atom_type=atom_type, seed=seed)


def materials(youngs="1e7", poisson=0.25, restitution=0.5, friction=0.5):
    """fix property/global for two atom types of one material (particles and walls)."""
    return (f"fix m1 all property/global youngsModulus peratomtype {youngs} {youngs}\n"
            f"fix m2 all property/global poissonsRatio peratomtype {poisson} {poisson}\n"
            "fix m3 all property/global coefficientRestitution peratomtypepair 2" + f" {restitution}" * 4 + "\n"
            "fix m4 all property/global coefficientFriction peratomtypepair 2" + f" {friction}" * 4 + "\n")


def held_gravity(group, angle):
    """fix gravity (ID gravity) of `group`, `angle` degrees from -z towards +x."""
    tilt = math.radians(angle)
    return f"fix gravity {group} gravity 9.81 vector {math.sin(tilt)!r} 0 {-math.cos(tilt)!r}\n"


def tilted_gravity(group, angle, ramp_steps=10000):
    """Turns the vertical fix gravity (ID gravity) of `group` quasi-statically, over `ramp_steps` steps,
    to `angle` degrees from -z towards +x, and leaves it there; the deck goes on with its `run`."""
    return ("unfix gravity\n"
            f"variable gx equal sin({angle}*PI/180*ramp(0,1))\n"
            f"variable gz equal -cos({angle}*PI/180*ramp(0,1))\n"
            f"fix gravity {group} gravity 9.81 vector v_gx 0 v_gz\nrun {ramp_steps}\nunfix gravity\n" +
            held_gravity(group, angle))


def read_dump(path):
    """Last snapshot of a `dump custom` text file as {id: [values...]} plus the column names."""
    lines = open(path).read().splitlines()
    start = max(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    columns = lines[start].split()[2:]
    rows = {}
    for line in lines[start + 1:]:
        if line.startswith("ITEM"):
            break
        values = [float(word) for word in line.split()]
        rows[int(values[0])] = values
    return columns, rows


def read_all_dump_snapshots(path):
    """[(timestep, columns, {id: values})] of a `dump custom` text file."""
    lines = open(path).read().splitlines()
    snapshots = []
    i = 0
    while i < len(lines):
        if lines[i] == "ITEM: TIMESTEP":
            step = int(lines[i + 1])
            count = int(lines[i + 3])
            j = i + 4
            while not lines[j].startswith("ITEM: ATOMS"):
                j += 1
            columns = lines[j].split()[2:]
            rows = {}
            for line in lines[j + 1:j + 1 + count]:
                values = [float(word) for word in line.split()]
                rows[int(values[0])] = values
            snapshots.append((step, columns, rows))
            i = j + 1 + count
        else:
            i += 1
    return snapshots


def settled_bed_energies(run_deck, workdir, pair, precision, steps=300, every=30, count=0, spin=False):
    """examples/gravity_packing/in.packing on tests/data/settled_bed_N2000.data (2000 Schoenhardt polyhedra of
    20 mm settled on its plane wall in double: examples/gravity_packing/gpus.sh's first stage with CELL=2000
    SETTLE=0.01 on the CPU, its final dump tiled once by tile_bed.py), from rest, for `steps` steps in
    `precision`: the thermo rows {"Step", "KinEng", "erot"} every `every` steps. count=1 also counts contacts;
    spin=True adds "c_spin", the largest squared angular velocity of a particle (rad^2/s^2)."""
    import pathlib
    root = pathlib.Path(__file__).resolve().parent.parent
    deck = (root / "examples" / "gravity_packing" / "in.packing").read_text()
    if spin:
        run = 'if "${split} > 0" then'
        deck = deck.replace(run, "compute omega all property/atom omegax omegay omegaz\n"
                            "variable omega2 atom c_omega[1]^2+c_omega[2]^2+c_omega[3]^2\n"
                            "compute spin all reduce max v_omega2\n"
                            "thermo_style custom step ke c_erot c_spin\n" + run)
        assert "c_spin" in deck
    result = run_deck(deck, workdir=workdir, variables={
        "N": 2000, "wall": 1, "steps": steps, "M": every, "pair": pair, "precision": precision, "final": 0,
        "count": count, "data": root / "tests" / "data" / "settled_bed_N2000.data"})
    assert result.returncode == 0, result.output[-3000:]
    return result.thermo("Step", "KinEng", "c_erot", *(("c_spin",) if spin else ()))


def largest_spins_on_settled_bed(run_deck, tmp_path, pair):
    """settled_bed_energies in single and in double with `pair`, 300 steps, every step: the largest squared angular
    velocity of any particle at any step in each, printed. The sliver overlaps single precision makes are dropped
    by the centroid rule, and the pair style says so once in its log; double precision makes none."""
    fastest = {}
    for precision in ("single", "double"):
        rows = settled_bed_energies(run_deck, tmp_path / precision, pair, precision, every=1, spin=True)
        fastest[precision] = max(rows["c_spin"])
        said = (tmp_path / precision / "log.lammps").read_text().count("centroid fell outside")
        assert said == (1 if precision == "single" else 0), (precision, said)
    print(f"\nsettled bed, {pair}: largest omega^2 {fastest['single']:.1f} (single) against "
          f"{fastest['double']:.1f} (double)")
    assert fastest["double"] > 0.0
    return fastest["single"], fastest["double"]


def mixed_against_double_on_settled_bed(run_deck, tmp_path, pair):
    """settled_bed_energies in double and in mixed with `pair`: the largest relative difference of KinEng and erot
    between them over the thermo rows (rows at rest in both skipped), printed with the end's kinetic energies."""
    double = settled_bed_energies(run_deck, tmp_path / "double", pair, "double")
    mixed = settled_bed_energies(run_deck, tmp_path / "mixed", pair, "mixed")
    assert double["Step"] == mixed["Step"] and max(double["KinEng"]) > 0.0
    apart = max(abs(b - a) / max(abs(a), abs(b)) for column in ("KinEng", "c_erot")
                for a, b in zip(double[column], mixed[column]) if a != 0.0 or b != 0.0)
    print(f"\nsettled bed, {pair}: mixed against double, energies at most {apart:.2e} apart; kinetic energy at the "
          f"end {double['KinEng'][-1]:.3e} / {mixed['KinEng'][-1]:.3e} J")
    return apart
