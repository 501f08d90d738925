"""The style hooks into Debian's prebuilt libliggghts (src/polyhedral_register.cpp).

If a future LIGGGHTS build stops calling the hooked methods through the PLT, or
stops keeping creator maps, these tests fail with the launcher's own ERROR line
or with LIGGGHTS' "Invalid ... style" errors.
"""
import subprocess

import decks


def test_launcher_verifies_hooks_and_runs_an_empty_input(launcher, tmp_path):
    (tmp_path / "in.empty").write_text("")
    result = subprocess.run([str(launcher), "-in", "in.empty", "-log", "none"], cwd=tmp_path,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "ERROR" not in result.stdout + result.stderr
    assert "LIGGGHTS" in result.stdout


def test_launcher_links_libpolyhedral_before_libliggghts(launcher):
    needed = [line.split()[-1] for line in
              subprocess.run(["readelf", "-d", str(launcher)], capture_output=True, text=True).stdout.splitlines()
              if "(NEEDED)" in line]
    names = [n.strip("[]") for n in needed]
    assert names.index("libpolyhedral.so") < names.index("libliggghts.so.3"), names


def one_cube_simulation(speed, dump_name):
    return (decks.header(hi=10.0) + decks.template("cube", "cube.stl", scale=0.5, density=2000.0) +
            f"create_polyhedron cube 5 5 5 vel {speed} 0 0\n"
            "fix integrate all nve/polyhedron\n"
            "compute erot all erotate/polyhedron\n"
            "compute props all property/polyhedron shape volume\n"
            "thermo_style custom step atoms ke c_erot\n"
            f"dump shapes all polyhedron/vtk 10 {dump_name}_*.vtp\n"
            "timestep 1e-3\nrun 10\n")


def test_every_style_is_available_again_after_clear(run_deck):
    result = run_deck(one_cube_simulation(1.0, "first") + "clear\n" + one_cube_simulation(2.0, "second"))
    assert result.returncode == 0, result.output
    ke = result.thermo("KinEng")["KinEng"]
    mass = 2000.0 * 0.5 ** 3
    # Two thermo tables (2 rows each); kinetic energies of the first and second simulation.
    assert len(ke) == 4
    assert abs(ke[0] - 0.5 * mass * 1.0) < 1e-9 * mass
    assert abs(ke[-1] - 0.5 * mass * 4.0) < 1e-9 * mass
    assert (result.workdir / "first_10.vtp").exists() and (result.workdir / "second_10.vtp").exists()


def test_stock_styles_and_errors_are_untouched(run_deck):
    result = run_deck("atom_style sphere\natom_modify sort 0 0\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
                      "create_atoms 1 single 0.5 0.5 0.5\nset atom 1 diameter 0.1 density 1000\n"
                      "fix integrate all nve/sphere\nrun 0\nclear\natom_style no_such_style\n")
    assert result.returncode != 0
    assert any("Invalid atom style" in line for line in result.error_lines()), result.output
    assert "Setting up run" in result.output  # the sphere run before `clear` worked


def test_unknown_dump_style_still_reported_by_liggghts(run_deck):
    result = run_deck(decks.header() + "dump d all polyhedron/nope 1 x_*.vtp\n")
    assert result.returncode != 0
    assert any("Invalid dump style" in line for line in result.error_lines()), result.output


def test_error_lines_carry_no_liggghts_tip_of_the_day(run_deck):
    """LIGGGHTS appends a dangling-pointer "tip" to errors of builds whose version says
    PUBLIC; the hook changes that word's case. write_data prints the version string."""
    result = run_deck(decks.header() + "write_data version.data\n")
    assert result.returncode == 0, result.output
    first_line = (result.workdir / "version.data").read_text().splitlines()[0]
    assert "LIGGGHTS-Public" in first_line and "PUBLIC" not in first_line, first_line


def test_help_lists_the_polyhedral_styles_after_liggghts_own(launcher, tmp_path):
    """`liggghts-poly -h` prints LIGGGHTS' own help, then the styles this package registers: every style that
    src/polyhedral_register.cpp puts into LIGGGHTS' maps (but the internal contact-history fix), plus the atom
    style and the dump style that come through the interposed methods."""
    import re
    from conftest import ROOT
    result = subprocess.run([str(launcher), "-h"], cwd=tmp_path, capture_output=True, text=True)
    assert result.returncode == 1, result.stdout + result.stderr  # LIGGGHTS' own -h exits with 1 too
    text = result.stdout
    assert "* Fix styles" in text and "* Polyhedral styles" in text
    assert text.index("* Fix styles") < text.index("* Polyhedral styles")
    ours = set(text[text.index("* Polyhedral styles"):].split())
    source = (ROOT / "src" / "polyhedral_register.cpp").read_text()
    body = source[source.index("void register_styles"):]
    registered = set(re.findall(r'(?:fixes|computes|commands|pair_map\))\["([^"]+)"\]', body))
    assert len(registered) >= 10, registered
    for name in registered | {"polyhedron", "polyhedron/vtk"}:
        assert name in ours, (name, sorted(ours))
