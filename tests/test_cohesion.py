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


# A 1 cm cube on a cohesive plane, no gravity, pulled up by a constant force.
CUBE_L, CUBE_K, E_STAR = 0.01, 1e3, 1e7 / (2.0 * (1.0 - 0.25 ** 2))


def cube_on_cohesive_plane(run_deck, workdir, k, height, quaternion, pull, timestep, steps):
    """A 1 cm cube at rest, its centre at `height` over a cohesive plane (zplane 0), no gravity, pulled up by
    `pull` N: the last thermo row's centre height, vertical velocity and force on the wall."""
    deck = ("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") +
            MATERIALS.replace("2 1e5 1e5 1e5 1e5", f"2 {k} {k} {k} {k}") +
            "fix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
            f"file ${{SHAPES}}/cube.stl scale {CUBE_L}\n"
            "pair_style polyhedral/volumetric cohesion sjkr\npair_coeff * *\n"
            f"create_polyhedron cube 0.5 0.5 {height!r} quat {' '.join(repr(q) for q in quaternion)}\n"
            "fix integrate all nve/polyhedron\nfix wall all wall/polyhedral primitive type 2 zplane 0.0\n"
            f"fix pull all addforce 0 0 {pull!r}\n"
            "variable z equal z[1]\nvariable vz equal vz[1]\n"
            "thermo_style custom step v_z v_vz f_wall[3]\nthermo_modify format float %.17g\nthermo 200\n"
            f"timestep {timestep}\nrun {steps}\n")
    result = run_deck(deck, workdir=workdir)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("v_z", "v_vz", "f_wall[3]")
    return table["v_z"][-1], table["v_vz"][-1], table["f_wall[3]"][-1]


@pytest.mark.parametrize("alpha", [0.0, 0.9, 1.1])
def test_cube_on_a_cohesive_plane_holds_until_the_pull_exceeds_k_times_its_face(run_deck, tmp_path, alpha):
    """The analytic cases of a cohesive contact (document 004's normal contact with cohesion, for sjkr): a face
    flat on a plane has the cross-section A = L^2 at any depth, so the cohesion k L^2 is constant in contact and
    the volumetric law is linear in the depth (V = L^2 delta: F_n = 4/(3 sqrt(pi)) E* L delta). Pulled by
    alpha k L^2, the cube settles at delta* = 3 sqrt(pi) (1 - alpha) k L / (4 E*) when alpha < 1, and leaves the
    plane when alpha > 1 (sjkr holds only in contact: a swing out of it lets go). 20 ms of damped motion (the
    contact's period is 1.6 ms)."""
    pull = alpha * CUBE_K * CUBE_L ** 2
    expected = 3.0 * math.sqrt(math.pi) * (1.0 - alpha) * CUBE_K * CUBE_L / (4.0 * E_STAR)
    # Held: start 1.5 delta* deep, so the damped swing (e = 0.5) stays in contact; pulled off: 1 um deep.
    start_depth = 1.5 * expected if alpha < 1.0 else 1e-6
    z, vz, wall = cube_on_cohesive_plane(run_deck, tmp_path / "face", CUBE_K, CUBE_L / 2 - start_depth,
                                         (1, 0, 0, 0), pull, 1e-5, 2000)
    if alpha < 1.0:
        depth = CUBE_L / 2 - z
        print(f"alpha {alpha}: depth {depth:.6e} m, expected {expected:.6e} m; wall force {wall:.6g} N")
        assert depth == pytest.approx(expected, rel=1e-3)
        assert abs(vz) < 1e-6
        assert wall == pytest.approx(pull, rel=1e-3, abs=1e-9)    # the force on the wall
    else:
        print(f"alpha {alpha}: centre {z - CUBE_L / 2:.3e} m above contact, rising at {vz:.3g} m/s")
        assert z - CUBE_L / 2 > 1e-3 and vz > 0.0 and wall == 0.0


@pytest.mark.parametrize("alpha", [0.0, 0.9, 1.1])
def test_cube_edge_on_a_cohesive_plane_holds_up_to_its_analytic_pull_off(run_deck, tmp_path, alpha):
    """A cube edge down (turned 45 degrees about x) on a cohesive plane: the overlap is a prism of depth delta, cross
    section delta^2 and width 2 delta over the edge length L, so V = L delta^2, A = 2 L delta, and the law gives
    F_n = c delta^1.5 with c = 4/(3 sqrt(pi)) E* sqrt(L) against the cohesion 2 k L delta. Unlike a face, an edge
    has a finite pull-off: P(delta) = 2 k L delta - c delta^1.5 peaks at P_max, at delta_m = (4 k L / (3 c))^2.
    Unloaded it rests at delta_0 = (2 k L / c)^2; pulled by alpha P_max < P_max at the root of P(delta) = alpha P_max
    beyond delta_m (the stable one), where it starts; pulled harder, it leaves."""
    k, length = 1e5, CUBE_L
    c = 4.0 / (3.0 * math.sqrt(math.pi)) * E_STAR * math.sqrt(length)
    delta_m = (4.0 * k * length / (3.0 * c)) ** 2
    p_max = 2.0 * k * length * delta_m - c * delta_m ** 1.5
    pull = alpha * p_max
    lo, hi = delta_m, (2.0 * k * length / c) ** 2    # P(delta) - pull falls from >= 0 to <= 0 on [delta_m, delta_0]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if 2.0 * k * length * mid - c * mid ** 1.5 > pull else (lo, mid)
    expected = 0.5 * (lo + hi)
    start_depth = expected if alpha < 1.0 else delta_m
    half_diagonal = CUBE_L / math.sqrt(2.0)
    turn = math.radians(45.0) / 2.0
    z, vz, wall = cube_on_cohesive_plane(run_deck, tmp_path / "edge", k, half_diagonal - start_depth,
                                         (math.cos(turn), math.sin(turn), 0, 0), pull, 1e-6,
                                         5000 if alpha < 1.0 else 30000)
    depth = half_diagonal - z
    print(f"alpha {alpha}: depth {depth:.6e} m, expected {expected:.6e} m (delta_m {delta_m:.3e}, "
          f"P_max {p_max:.4g} N), vz {vz:.3g}")
    if alpha < 1.0:
        assert depth == pytest.approx(expected, rel=1e-3)
        assert wall == pytest.approx(pull, rel=1e-3, abs=1e-9)
    else:
        assert depth < 0.0 and vz > 0.0


# Column collapse: 123 particles settle in a tube of 3.5 cm radius on a floor (0.24 s), the tube goes, the column
# slumps for 0.48 s. Every wall and pair is cohesive as the pair style says. A fence far out (19 cm) keeps the
# grains that roll away (spheres and 80-facet icospheres roll far) in the box.
COLLAPSE = """\
{head}region box block -0.2 0.2 -0.2 0.2 -0.01 0.2
create_box 2 box
neighbor 0.002 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 1e7 1e7
fix m2 all property/global poissonsRatio peratomtype 0.25 0.25
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.3 0.3 0.3 0.3
fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
fix m5 all property/global cohesionEnergyDensity peratomtypepair 2 {k} {k} {k} {k}
{template}
fix shapes all particledistribution/discrete 49979687 1 grain 1.0
pair_style {pair} cohesion sjkr
pair_coeff * *
fix floor all {wall} primitive type 2 zplane 0.0
fix tube all {wall} primitive type 2 zcylinder 0.035 0.0 0.0
fix fence all {wall} primitive type 2 zcylinder 0.19 0.0 0.0
region column cylinder z 0 0 0.034 0.002 0.19
fix put all insert/pack seed 67867967 distributiontemplate shapes insert_every once overlapcheck yes {orientation}all_in yes particles_in_region 123 region column
fix integrate all {integrator}
fix gravity all gravity 9.81 vector 0 0 -1
thermo_style custom step atoms ke
thermo 2000
timestep 4e-5
run 6000
unfix put
unfix tube
run 12000
dump final all custom 1 final.dump id x y z
dump_modify final format "%d %.9g %.9g %.9g"
run 0
"""


def heap_angle(run_deck, workdir, polyhedra, k):
    """The collapsed heap's angle atan(H / R90), H the highest centre, R90 the radius holding 90 % of the centres."""
    if polyhedra:
        fields = dict(head="atom_style polyhedron\n" + HEAD.split("region")[0].format(sort=" sort 0 0"),
                      template="fix grain all particletemplate/polyhedron 15485863 atom_type 1 density constant "
                               "2500 file ${SHAPES}/icosphere_80.off scale 0.009",
                      pair="polyhedral/volumetric", wall="wall/polyhedral", orientation="orientation random ",
                      integrator="nve/polyhedron")
    else:
        fields = dict(head="atom_style granular\n" + HEAD.split("region")[0].format(sort=""),
                      template="fix grain all particletemplate/sphere 15485863 atom_type 1 density constant 2500 "
                               "radius constant 0.0045",
                      pair="gran model hertz tangential history", wall="wall/gran model hertz tangential history",
                      orientation="", integrator="nve/sphere")
    result = run_deck(COLLAPSE.format(k=k, **fields), workdir=workdir)
    assert result.returncode == 0, result.output[-3000:]
    assert result.thermo("Atoms")["Atoms"][-1] == 123, "particles lost or not inserted"
    lines = (workdir / "final.dump").read_text().splitlines()
    start = max(n for n, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    centres = [[float(w) for w in line.split()[1:4]] for line in lines[start + 1:]]
    radii = sorted(math.hypot(x, y) for x, y, _ in centres)
    height = max(z for _, _, z in centres)
    return math.degrees(math.atan(height / radii[int(0.9 * len(radii))])), result.output


def test_heap_angle_rises_with_cohesion_as_liggghts_spheres_do(run_deck, tmp_path):
    """A column of 123 icosphere_80 polyhedra (9 mm) collapses into a heap far steeper with cohesion sjkr at
    k = 3e5 J/m^3 than without, as LIGGGHTS' own spheres of that size do in the same deck (there from about 6 to
    47 degrees; the facets give the polyhedra rolling resistance, so their cohesionless heap is steeper). k = 3e5
    against E* = 5.3e6 is past the depth warning (faces sink 7 % of their size), which the deck must print."""
    angles = {}
    for polyhedra in (True, False):
        for k in (0, 300000):
            angles[polyhedra, k], output = heap_angle(run_deck, tmp_path / f"{polyhedra}_{k}", polyhedra, k)
            if polyhedra and k:
                assert "faces held by cohesion alone sink 7 % of their size" in output
    print("heap angles (degrees):", {("polyhedra" if p else "spheres", k): round(a, 1) for (p, k), a in angles.items()})
    for polyhedra in (True, False):
        assert angles[polyhedra, 300000] > angles[polyhedra, 0] + 10.0
    assert angles[True, 0] > angles[False, 0]


def test_cohesion_deeper_than_the_law_allows_is_an_error(run_deck, tmp_path):
    """k/E* above 0.15 would sink cohesive faces past 20 % of their size (3 sqrt(pi)/4 k/E*): a column of rocks
    at k = 3e6, E* = 5.3e6 (faces sinking 75 %) half merges. An ERROR."""
    deck = ("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") +
            MATERIALS.replace("2 1e5 1e5 1e5 1e5", "2 3e6 3e6 3e6 3e6") +
            "fix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
            "file ${SHAPES}/cube.stl scale 0.01\npair_style polyhedral/volumetric cohesion sjkr\npair_coeff * *\n"
            "create_polyhedron cube 0.5 0.5 0.5\nfix integrate all nve/polyhedron\nrun 0\n")
    result = run_deck(deck, workdir=tmp_path)
    assert result.returncode != 0
    assert any("sink 75 % of their size" in line and "keep k/E* below 0.15" in line
               for line in result.error_lines()), result.output[-2000:]


def test_cohesion_survives_a_restart_file(run_deck, tmp_path):
    """The cube of the face test at rest on its cohesive equilibrium depth: written to a restart file and read
    back without a pair_style line, the pair style still has cohesion sjkr (a cube resting on a second cube, the
    pair's contact carrying the cohesion): the force on the upper cube stays the cohesive balance, zero, and
    it stays at its depth. With cohesion lost it would be pushed out."""
    depth = 3.0 * math.sqrt(math.pi) * CUBE_K * CUBE_L / (4.0 * E_STAR)
    setup = ("fix m1 all property/global youngsModulus peratomtype 1e7 1e7\n"
             "fix m2 all property/global poissonsRatio peratomtype 0.25 0.25\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n"
             f"fix m5 all property/global cohesionEnergyDensity peratomtypepair 2 {CUBE_K} {CUBE_K} {CUBE_K} "
             f"{CUBE_K}\nfix cube all particletemplate/polyhedron 15485863 atom_type 1 density constant 2500 "
             f"file ${{SHAPES}}/cube.stl scale {CUBE_L}\n")
    probe = ("group upper id 2\nfix integrate upper nve/polyhedron\nvariable z equal z[2]\n"
             "variable fz equal fcm(upper,z)\n"
             "thermo_style custom step v_z v_fz\nthermo_modify format float %.17g\ntimestep 1e-6\n")
    first = run_deck("atom_style polyhedron\n" + HEAD.format(sort=" sort 0 0") + setup +
                     "pair_style polyhedral/volumetric cohesion sjkr\npair_coeff * *\n"
                     f"create_polyhedron cube 0.5 0.5 0.5\ncreate_polyhedron cube 0.5 0.5 {0.5 + CUBE_L - depth!r}\n"
                     + probe + "run 0\nwrite_restart cohesive.restart\n", workdir=tmp_path / "first")
    assert first.returncode == 0, first.output[-3000:]
    second = run_deck("atom_modify map array sort 0 0\nread_restart ../first/cohesive.restart\nnewton off\n"
                      "communicate single vel yes\n" + setup + probe + "run 100\n", workdir=tmp_path / "second")
    assert second.returncode == 0, second.output[-3000:]
    for result in (first, second):
        table = result.thermo("v_z", "v_fz")
        weight_free_force = table["v_fz"][-1]
        assert abs(weight_free_force) < 1e-6 * CUBE_K * CUBE_L ** 2, (table, result.workdir)
        assert table["v_z"][-1] == pytest.approx(0.5 + CUBE_L - depth, abs=1e-12)
