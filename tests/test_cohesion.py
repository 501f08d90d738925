"""cohesion sjkr (issue 16): LIGGGHTS' simplified JKR cohesion, an attraction k A with k the material's
cohesionEnergyDensity and A the contact area, here the overlap's cross-section that the volumetric model
computes (its projected area), which for two spheres is LIGGGHTS' contact circle. Checked against LIGGGHTS' own
cohesion sjkr on spheres and against the circle of a plane's cut, with fine icospheres (1280 triangles)."""
import math

import pytest

MATERIALS = ("fix m1 all property/global youngsModulus peratomtype 1e7 1e7\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.25 0.25\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n"
             "fix m5 all property/global cohesionEnergyDensity peratomtypepair 2 1e5 1e5 1e5 1e5\n")
HEAD = ("atom_modify map array{sort}\nboundary f f f\nnewton off\ncommunicate single vel yes\nunits si\n"
        "region box block 0 1 0 1 0 1\ncreate_box 2 box\nneighbor 0.002 bin\n")
R, DEPTH, K = 0.01, 0.001, 1e5


def pair_force(run_deck, workdir, spheres, cohesion):
    """The normal force on the upper of two 2 cm particles at rest overlapping by 1 mm, from the local compute."""
    if spheres:
        deck = ("atom_style granular\n" + HEAD.format(sort="") + MATERIALS +
                f"pair_style gran model hertz tangential history cohesion {cohesion}\npair_coeff * *\n"
                f"create_atoms 1 single 0.5 0.5 0.5\ncreate_atoms 1 single 0.5 0.5 {0.5 + 2 * R - DEPTH!r}\n"
                "set atom * diameter 0.02 density 2500\nfix integrate all nve/sphere\n"
                "compute c all pair/gran/local force\ndump d all local 1 out.dump c_c[3]\n")
    else:
        deck = ("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") + MATERIALS +
                "fix ball all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
                "file ${SHAPES}/icosphere_1280.off scale 0.02\n"
                f"pair_style polyhedral/volumetric cohesion {cohesion}\npair_coeff * *\n"
                f"create_polyhedron ball 0.5 0.5 0.5\ncreate_polyhedron ball 0.5 0.5 {0.5 + 2 * R - DEPTH!r}\n"
                "fix integrate all nve/polyhedron\ncompute c all pair/polyhedral/local\n"
                "dump d all local 1 out.dump c_c[13]\n")
    deck += "dump_modify d format '%.17g'\ntimestep 1e-7\nrun 0\n"
    result = run_deck(deck, workdir=workdir)
    assert result.returncode == 0, result.output[-3000:]
    value = float((workdir / "out.dump").read_text().split()[-1])
    return abs(value)


def test_pair_cohesion_matches_liggghts_sjkr(run_deck, tmp_path):
    """Two spheres of 1 cm radius overlapping by 1 mm, at rest: cohesion lowers LIGGGHTS' normal force by
    k pi a^2 (its contact circle, a^2 = R^2 - (d/2)^2), to rounding; and the polyhedral pair's by the same
    within 1 % (the icospheres' facets at this depth)."""
    circle = K * math.pi * (R * R - (R - DEPTH / 2) ** 2)
    spheres = pair_force(run_deck, tmp_path / "s0", True, "off") - pair_force(run_deck, tmp_path / "s1", True, "sjkr")
    ours = pair_force(run_deck, tmp_path / "p0", False, "off") - pair_force(run_deck, tmp_path / "p1", False, "sjkr")
    print(f"cohesive force: LIGGGHTS spheres {spheres:.6g} N, polyhedra {ours:.6g} N, k pi a^2 {circle:.6g} N")
    assert spheres == pytest.approx(circle, rel=1e-9)
    assert ours == pytest.approx(spheres, rel=0.01)


@pytest.mark.parametrize("where", ["pair", "wall"])
def test_wall_cohesion_follows_the_pair_style_or_its_own_keyword(run_deck, tmp_path, where):
    """A fine icosphere pressed 1 mm into a plane: cohesion (from the pair style's `cohesion sjkr`, or the wall's
    own keyword) lowers the wall's force by k times the cut's circle, pi (2 R delta - delta^2), within 1 %."""
    forces = []
    for n, on in enumerate((False, True)):
        pair_cohesion = "sjkr" if on and where == "pair" else "off"
        wall_cohesion = " cohesion sjkr" if on and where == "wall" else ""
        deck = ("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") + MATERIALS +
                "fix ball all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
                "file ${SHAPES}/icosphere_1280.off scale 0.02\n"
                f"pair_style polyhedral/volumetric cohesion {pair_cohesion}\npair_coeff * *\n"
                f"create_polyhedron ball 0.5 0.5 {R - DEPTH!r}\nfix integrate all nve/polyhedron\n"
                f"fix wall all wall/polyhedral{wall_cohesion} primitive type 2 zplane 0.0\n"
                "thermo_style custom step f_wall[3]\nthermo_modify format float %.17g\ntimestep 1e-7\nrun 0\n")
        result = run_deck(deck, workdir=tmp_path / str(n))
        assert result.returncode == 0, result.output[-3000:]
        forces.append(result.thermo("f_wall[3]")["f_wall[3]"][-1])
    circle = K * math.pi * (2 * R * DEPTH - DEPTH ** 2)
    print(f"wall force without / with cohesion {forces}, k A {circle:.6g}")
    assert abs(forces[0]) - abs(forces[1]) == pytest.approx(circle, rel=0.01)


def test_cohesion_needs_its_material_and_a_known_model(run_deck, tmp_path):
    deck = ("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") + MATERIALS.replace(
        "fix m5 all property/global cohesionEnergyDensity peratomtypepair 2 1e5 1e5 1e5 1e5\n", "") +
        "fix ball all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
        "file ${SHAPES}/icosphere_80.off scale 0.02\npair_style polyhedral/volumetric cohesion sjkr\npair_coeff * *\n"
        "create_polyhedron ball 0.5 0.5 0.5\nfix integrate all nve/polyhedron\nrun 0\n")
    result = run_deck(deck, workdir=tmp_path / "missing")
    assert result.returncode != 0
    assert any("cohesionEnergyDensity" in line for line in result.error_lines()), result.output[-2000:]
    result = run_deck(deck.replace("cohesion sjkr", "cohesion sjkr2"), workdir=tmp_path / "model")
    assert result.returncode != 0
    assert any("cohesion sjkr2 is not available for polyhedra" in line for line in result.error_lines()), \
        result.output[-2000:]
