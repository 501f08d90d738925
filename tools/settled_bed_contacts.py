#!/usr/bin/env python3
"""The contacts of tests/data/settled_bed_N2000.data (2000 Schoenhardt polyhedra settled on their plane wall) as
the pair style finds them at set-up, through examples/gravity_packing/in.packing:

    python3 tools/settled_bed_contacts.py [LIGGGHTS] [double|single|mixed]

(LIGGGHTS: a liggghts-poly, default build/bin/liggghts-poly.) Prints the contacts, those with a depth above 1 % of
the bounding diameter (the set-up's warning's depth) and what their volumes and depths are: a pair touching at
spots a particle size apart is one contact whose extent along its normal is the spots' spread, and its normal
force, which grows with sqrt(V delta), was that of a one-spot contact 1e-5 m deep with delta / 1e-5 m times its
volume while the depth was the extent (723 of 5385 contacts above 1 %, up to 12 mm deep). The depth is now at
most 3 V / A (doc/pair_polyhedral_volumetric.md, Depth), and none is above 1 %. Also prints how many contact
evaluations had their depth so capped, their extent over 1.001 times 3 V / A (compute pair/polyhedral/local's 11th
element: pairs touching at several spots), over the set-ups of in.packing's runs and its step."""
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
BOUNDING_DIAMETER = 2 * 0.0186287969  # schoenhardt.stl at in.packing's scale (the bounding radius the template prints)


def main():
    default = ROOT / "build" / "bin" / "liggghts-poly"
    launcher = str(pathlib.Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else default)
    precision = sys.argv[2] if len(sys.argv) > 2 else "double"
    deck = (ROOT / "examples" / "gravity_packing" / "in.packing").read_text()
    run = 'if "${split} > 0" then'
    assert run in deck
    deck = deck.replace(run, "dump contacts all local 1 contacts.txt c_pairs[1] c_pairs[2] c_pairs[3] c_pairs[4]\n"
                             "dump_modify contacts first yes\n" + run)
    # compute pair/polyhedral/local's counts since the pair style was defined (evaluations of the two runs'
    # set-ups and the step): contacts evaluated (6) and those whose depth the cap 3 V / A took (11, several spots).
    deck += ("undump contacts\nvariable evals equal c_pairs[6]\nvariable capped equal c_pairs[11]\n"
             "thermo_style custom step v_evals v_capped\nrun 0\n")
    with tempfile.TemporaryDirectory() as work:
        (pathlib.Path(work) / "in.deck").write_text(deck)
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        result = subprocess.run([launcher, "-in", "in.deck", "-log", "log.lammps", "-screen", "none",
                                 "-var", "N", "2000", "-var", "wall", "1", "-var", "steps", "1", "-var", "count", "1",
                                 "-var", "final", "0", "-var", "precision", precision,
                                 "-var", "SHAPES", str(ROOT / "examples" / "shapes"),
                                 "-var", "data", str(ROOT / "tests" / "data" / "settled_bed_N2000.data")],
                                cwd=work, capture_output=True, text=True, env=env)
        if result.returncode != 0:
            sys.exit(result.stdout + result.stderr)
        lines = (pathlib.Path(work) / "contacts.txt").read_text().splitlines()
        log = (pathlib.Path(work) / "log.lammps").read_text().splitlines()
    header = max(i for i, line in enumerate(log) if line.split()[:3] == ["Step", "evals", "capped"])
    evaluated, capped = (float(w) for w in log[header + 1].split()[1:3])
    start = lines.index("ITEM: TIMESTEP")
    count = int(lines[start + 3])
    rows = [[float(w) for w in line.split()] for line in lines[start + 9:start + 9 + count]]
    deep = [row for row in rows if row[3] > 0.01 * BOUNDING_DIAMETER]
    print(f"settled bed, {precision}, step {lines[start + 1]}: {len(rows)} contacts, median volume "
          f"{statistics.median(r[2] for r in rows):.3g} m^3, median depth "
          f"{statistics.median(r[3] for r in rows):.3g} m")
    print(f"contacts whose extent is over 1.001 times their depth 3 V / A (several spots; compute "
          f"pair/polyhedral/local's 11th element): {capped:.0f} of {evaluated:.0f} contact evaluations "
          f"({100 * capped / evaluated:.1f} %)")
    if deep:
        print(f"{len(deep)} deeper than 1 % of the bounding diameter: depths {min(r[3] for r in deep):.3g} to "
              f"{max(r[3] for r in deep):.3g} m, volumes median {statistics.median(r[2] for r in deep):.3g} m^3; "
              f"sqrt(V delta) of a 1e-5 m deep contact with {min(r[3] for r in deep) / 1e-5:.0f} to "
              f"{max(r[3] for r in deep) / 1e-5:.0f} times their volume")


if __name__ == "__main__":
    main()
