"""compute pair/polyhedral/local's vector 4-8: what the pair loop did with its neighbour pairs (pairs in reach of
each other; skipped as still apart, within the gap found before or behind the plane that parted them; evaluated
into a contact; found apart by the slab or a parting plane; found apart after the whole path). Two cubes, tilted so
that no faces are flush, approach, collide and part again, printed every step: the counts add up exactly, the
contacts are the per-step contacts summed, and the parted pair is skipped on later steps; and none of the contacts
of these convex bodies has its depth capped at 3 V / A (element 11: a pair touching at several spots)."""
import pytest

import decks

EDGE = 0.01
MATERIALS = ("fix m1 all property/global youngsModulus peratomtype 5e6\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.3\n")


def two_cubes_deck(half_width=0.05, precision="double"):
    return (decks.header(boundary="f f f", lo=-half_width, hi=half_width) +
            "neighbor 0.004 bin\nneigh_modify delay 0\n" + MATERIALS +
            decks.template("cube", "cube.stl", scale=EDGE) +
            f"pair_style polyhedral/volumetric tangential off damping off precision {precision}\npair_coeff * *\n"
            "create_polyhedron cube -0.0062 0 0 quat 0.99 0.1 0.05 0 vel 0.5 0 0\n"
            "create_polyhedron cube 0.0062 0 0 quat 0.98 0 0.1 0.15 vel -0.5 0 0\n"
            "fix integrate all nve/polyhedron\ncompute ev all pair/polyhedral/local\n"
            "variable reach equal c_ev[4]\nvariable hinted equal c_ev[5]\nvariable touching equal c_ev[6]\n"
            "variable parted equal c_ev[7]\nvariable missed equal c_ev[8]\nvariable capped equal c_ev[11]\n"
            "thermo_style custom step c_ev v_reach v_hinted v_touching v_parted v_missed v_capped\n"
            "thermo_modify format float %.15g\nthermo 1\ntimestep 1e-6\nrun 8000\n")


@pytest.mark.parametrize("precision", ["double", "single"])
def test_the_pair_loop_counts_add_up(run_deck, precision):
    result = run_deck(two_cubes_deck(precision=precision))
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "c_ev", "v_reach", "v_hinted", "v_touching", "v_parted", "v_missed", "v_capped")
    reach, hinted, touching, parted, missed = (table[c][-1] for c in
                                               ("v_reach", "v_hinted", "v_touching", "v_parted", "v_missed"))
    print(f"\ntwo cubes: in reach {reach:.0f}, skipped by their plane {hinted:.0f}, contacts {touching:.0f}, "
          f"parted by the slab or a plane {parted:.0f}, near misses {missed:.0f}")
    assert reach == hinted + touching + parted + missed
    # Convex bodies touch at one spot, whose extent never exceeds 3 V / A: no contact is counted as capped (11),
    # in single precision neither (its rounding alone puts the extent up to 1e-4 over it: 73 % of a settled bed's
    # contacts, counted so with a test of 1 + 1e-6 instead of 1.001).
    assert table["v_capped"][-1] == 0
    # One pair, one evaluation a step (the run's set-up evaluation is step 0's): the contacts are the steps
    # whose evaluation found the pair touching.
    assert touching == sum(table["c_ev"]) and touching > 100
    assert reach <= len(table["Step"])
    assert table["c_ev"][0] == 0 and table["c_ev"][-1] == 0  # apart before and after
    # Apart in reach before the collision and after it: most of those steps the parting plane still parts them.
    assert hinted > 0.5 * (reach - touching)
    # The counts only grow.
    for name in ("v_reach", "v_hinted", "v_touching", "v_parted", "v_missed"):
        assert all(b >= a for a, b in zip(table[name], table[name][1:])), name
