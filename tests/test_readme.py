"""The input script of README.md runs as printed: two placed rocks and an insertion topping the region up
to 200 particles, walls on five sides, no particle lost (thermo_modify lost error), the floor carrying
the weight once the rocks have settled."""
import re

from conftest import ROOT


def test_readme_input_script_runs(run_deck, tmp_path):
    text = (ROOT / "README.md").read_text()
    script = re.search(r"## An input script\n\n```\n(.*?)```", text, re.S).group(1)
    (tmp_path / "post").mkdir()
    (tmp_path / "examples").mkdir()
    (tmp_path / "examples" / "shapes").symlink_to(ROOT / "examples" / "shapes")
    result = run_deck(script.replace("run 2500", "run 2500\nrun 7500"), workdir=tmp_path)
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "Atoms", "c_contacts", "f_floor[3]", "f_floor[4]")
    assert table["Atoms"][-1] == 200
    mass = 200 * 2700 * 4.18879020479 * 0.01 ** 3  # 200 rocks of volume-equivalent diameter 20 mm
    print(f"\nREADME script: {table['Atoms'][-1]} particles, {table['c_contacts'][-1]} contacts, floor force "
          f"{table['f_floor[3]'][-1]:.3f} N against a weight of {mass * 9.81:.3f} N")
    assert table["f_floor[4]"][-1] > 50
    # Settled after 1 s: the floor carries the weight, less what friction on the side walls holds (< 25%)
    assert 0.75 * mass * 9.81 < -table["f_floor[3]"][-1] < 1.05 * mass * 9.81
