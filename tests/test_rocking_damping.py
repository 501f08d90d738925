"""Rocking damping (src/poly_contact.h, poly_rocking_couple): the normal damping spread over the overlap, whose
resultant is the old -gamma_n u_n n and which adds a couple -(gamma_n/V) (tr(Q_t) P - Q_t) w on the relative
rotation w and a twist couple -(gamma_t/V) tr(Q_t) (w.n) n.

Measured here as tools/bench_rocking.py measures it (doc/benchmarks.md, "Rocking"): a 1 cm cube (E 5 MPa,
e 0.3, mu 0.5) set on its edge, tilted 10 degrees, on a zplane wall and on a 2-triangle mesh floor, rocks
back onto its face. With the old law (rocking_damping off) small rocking on the face keeps 0.93 of its
amplitude per half-cycle and the cube rests (kinetic energy below 1e-6 of its peak) after 0.25 s; LIGGGHTS'
27-sphere multisphere cube keeps 0.30-0.55 (its face-impact-matched variant 0.55) and rests after 0.11-0.16 s.
The couple's prediction for a face (the rocking mode has the normal mode's damping ratio over sqrt 5) is 0.57.
Asserted: with rocking_damping on, the tail ratio is below 0.7 and the cube rests within 0.16 s; with it off,
the ratio stays above 0.85 (the switch works and the effect is the couple's). The sphere tests of
tests/test_contact_physics.py run with the default (on) and keep their tolerances: translation and equal
spins give no couple.
"""
import pathlib
import sys
import types

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tools"))
import bench_rocking as bench  # noqa: E402


@pytest.mark.parametrize("floor", ["plane", "mesh"])
def test_cube_on_an_edge_rocks_to_rest(launcher, tmp_path, floor):
    bench.write_floor_stl(tmp_path / "floor.stl")
    results = {}
    for rocking in ("on", "off"):
        args = types.SimpleNamespace(time=0.25, dt=5e-6, every=4, drop=0.005, matched_e=0.55, rocking=rocking)
        workdir = tmp_path / rocking
        workdir.mkdir()
        (workdir / "floor.stl").write_bytes((tmp_path / "floor.stl").read_bytes())
        results[rocking] = bench.rocking_case(("poly", "cube", floor, 10, "edge"), args, workdir)
    on, off = results["on"], results["off"]
    print(f"\ncube on an edge, {floor}: tail ratio {on['r_tail']:.3f} ({on['n_tail']}) with rocking damping, "
          f"{off['r_tail']:.3f} ({off['n_tail']}) without; at rest after {on['t_rest']} s / {off['t_rest']} s")
    assert on["n_tail"] >= 3 and on["r_tail"] < 0.7, on["r_tail"]
    assert on["t_rest"] is not None and on["t_rest"] < 0.16, on["t_rest"]
    assert off["r_tail"] > 0.85, off["r_tail"]
