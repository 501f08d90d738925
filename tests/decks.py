"""Deck fragments shared by the LIGGGHTS-level tests."""

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
