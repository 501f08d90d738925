#!/usr/bin/python3
"""Particle shapes from multisphere clumps and from dense meshes, at the resolution a scene needs
(doc/shapes_from_clumps.md), with VTK's filters (Debian's python3-paraview ships VTK 9):

    tools/make_shape.py clump STONE.multisphere OUT.obj [--grid 64] [--triangles T | --volume-error E]
    tools/make_shape.py simplify IN.(obj|off|stl) OUT.obj (--triangles T | --volume-error E)

clump: the surface of the union of the clump's spheres (rows `x y z r`, as LIGGGHTS' particletemplate/multisphere
reads them): the union's implicit function min_k(|x - c_k|^2 - r_k^2) sampled on a grid of --grid cells along the
longest side of the clump's box, contoured at zero (flying edges: a closed, consistently oriented surface), then
simplified as below. simplify: quadric decimation (vtkQuadricDecimation, volume-preserving) to T triangles, or to
the fewest triangles whose volume differs from the input's by at most E (relative; bisection on the reduction).

Each output is checked by the package's own shape validator (build/bin/liggghts-poly loads it as a
particletemplate/polyhedron: closed, consistently oriented, no self-intersection), and the tool prints the
triangle count and the relative errors of the volume and of the principal moments against the input (the
clump: against the fine surface before simplification). Exit status 1 when the validator refuses the result.
"""
import argparse
import math
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from shape_files import mass_properties as shape_mass_properties, read_mesh  # noqa: E402

from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkImplicitBoolean, vtkPolyData, vtkSphere  # noqa: E402
from vtkmodules.vtkFiltersCore import (vtkCleanPolyData, vtkFlyingEdges3D, vtkQuadricDecimation,  # noqa: E402
                                       vtkTriangleFilter)
from vtkmodules.vtkImagingHybrid import vtkSampleFunction  # noqa: E402


def read_clump(path):
    spheres = []
    for line in open(path):
        words = line.split("#")[0].split()
        if len(words) >= 4:
            spheres.append(tuple(float(w) for w in words[:4]))
    if not spheres:
        raise SystemExit(f"ERROR: {path}: no sphere rows 'x y z r'")
    return spheres


def to_polydata(vertices, triangles):
    points, cells = vtkPoints(), vtkCellArray()
    for v in vertices:
        points.InsertNextPoint(*v)
    for t in triangles:
        cells.InsertNextCell(3, t)
    mesh = vtkPolyData()
    mesh.SetPoints(points)
    mesh.SetPolys(cells)
    return mesh


def from_polydata(mesh):
    vertices = [mesh.GetPoint(i) for i in range(mesh.GetNumberOfPoints())]
    triangles = []
    ids = mesh.GetPolys()
    ids.InitTraversal()
    from vtkmodules.vtkCommonCore import vtkIdList
    cell = vtkIdList()
    while ids.GetNextCell(cell):
        if cell.GetNumberOfIds() == 3:
            triangles.append(tuple(cell.GetId(k) for k in range(3)))
    return vertices, triangles


def clump_surface(spheres, grid):
    union = vtkImplicitBoolean()
    union.SetOperationTypeToUnion()
    low = [min(s[k] - s[3] for s in spheres) for k in range(3)]
    high = [max(s[k] + s[3] for s in spheres) for k in range(3)]
    for x, y, z, r in spheres:
        sphere = vtkSphere()
        sphere.SetCenter(x, y, z)
        sphere.SetRadius(r)
        union.AddFunction(sphere)
    size = max(h - l for l, h in zip(low, high))
    step = size / grid
    margin = 2 * step
    sample = vtkSampleFunction()
    sample.SetImplicitFunction(union)
    sample.SetModelBounds(low[0] - margin, high[0] + margin, low[1] - margin, high[1] + margin,
                          low[2] - margin, high[2] + margin)
    sample.SetSampleDimensions(*(int(math.ceil((h - l + 2 * margin) / step)) + 1 for l, h in zip(low, high)))
    sample.ComputeNormalsOff()
    contour = vtkFlyingEdges3D()
    contour.SetInputConnection(sample.GetOutputPort())
    contour.SetValue(0, 0.0)
    contour.ComputeNormalsOff()
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(contour.GetOutputPort())
    # Flying edges leaves slivers where the surface passes a sample within rounding of a grid point (at grid 200,
    # the stone had a triangle of 1e-13 of its size squared, which the validator refuses): merging points closer
    # than a thousandth of a cell collapses them, and their cells (now lines or points) are dropped.
    clean = vtkCleanPolyData()
    clean.SetInputConnection(triangles.GetOutputPort())
    clean.ToleranceIsAbsoluteOn()
    clean.SetAbsoluteTolerance(1e-3 * step)
    clean.Update()
    vertices, triangles = from_polydata(clean.GetOutput())
    if mass_properties(vertices, triangles)[0] < 0.0:  # the contour faces into the union: outward for the package
        triangles = [(t[0], t[2], t[1]) for t in triangles]
    return vertices, triangles


def decimate(vertices, triangles, target):
    """Quadric decimation to about `target` triangles."""
    mesh = to_polydata(vertices, triangles)
    reduction = max(0.0, min(0.999, 1.0 - target / len(triangles)))
    decimation = vtkQuadricDecimation()
    decimation.SetInputData(mesh)
    decimation.SetTargetReduction(reduction)
    decimation.VolumePreservationOn()
    clean = vtkCleanPolyData()
    clean.SetInputConnection(decimation.GetOutputPort())
    clean.Update()
    return from_polydata(clean.GetOutput())


def mass_properties(vertices, triangles):
    """Volume and principal moments per unit density (tools/shape_files.py)."""
    volume, _, moments = shape_mass_properties(vertices, triangles)
    return volume, moments


def write_obj(path, vertices, triangles, comment):
    with open(path, "w") as out:
        out.write(f"# {comment}\n")
        for v in vertices:
            out.write("v %.9g %.9g %.9g\n" % tuple(v))
        for t in triangles:
            out.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def validate(path):
    """The package's validator on the shape: '' if it loads, else its ERROR line."""
    launcher = ROOT / "build" / "bin" / "liggghts-poly"
    if not launcher.exists():
        return "no build/bin/liggghts-poly to validate with (make -j2 all)"
    deck = ("atom_style polyhedron\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
            "units si\nregion box block -1 1 -1 1 -1 1\ncreate_box 1 box\n"
            f"fix t all particletemplate/polyhedron 15485863 atom_type 1 density constant 1 file {path} scale 1\n")
    with tempfile.TemporaryDirectory() as work:
        (pathlib.Path(work) / "in.check").write_text(deck)
        result = subprocess.run([str(launcher), "-in", "in.check", "-log", "none"], cwd=work, capture_output=True,
                                text=True, env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
                                                    OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
    errors = [line for line in result.stdout.splitlines() if line.startswith("ERROR")]
    return errors[0] if errors or result.returncode else ""


def errors_against(reference, vertices, triangles):
    volume, moments = mass_properties(vertices, triangles)
    ref_volume, ref_moments = reference
    return abs(volume / ref_volume - 1.0), max(abs(m / r - 1.0) for m, r in zip(moments, ref_moments))


def simplify(vertices, triangles, reference, target, volume_error):
    if target:
        return decimate(vertices, triangles, target)
    low, high, best = 4, len(triangles), (vertices, triangles)
    while high - low > max(4, low // 50):
        middle = (low + high) // 2
        candidate = decimate(vertices, triangles, middle)
        if errors_against(reference, *candidate)[0] <= volume_error:
            high, best = middle, candidate
        else:
            low = middle
    return best


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    for name in ("clump", "simplify"):
        s = sub.add_parser(name)
        s.add_argument("input")
        s.add_argument("output")
        s.add_argument("--triangles", type=int, default=0, help="target triangle count")
        s.add_argument("--volume-error", type=float, default=0.0, help="largest relative volume error")
        if name == "clump":
            s.add_argument("--grid", type=int, default=64, help="grid cells along the clump's longest side (64)")
    a = p.parse_args()
    if a.command == "simplify" and not (a.triangles or a.volume_error):
        p.error("simplify needs --triangles T or --volume-error E")
    if a.command == "clump":
        vertices, triangles = clump_surface(read_clump(a.input), a.grid)
        source = f"union of the spheres of {pathlib.Path(a.input).name}, grid {a.grid}"
    else:
        vertices, triangles = read_mesh(pathlib.Path(a.input))
        source = pathlib.Path(a.input).name
    reference = mass_properties(vertices, triangles)
    print(f"{source}: {len(triangles)} triangles, volume {reference[0]:.6g}")
    if a.triangles or a.volume_error:
        vertices, triangles = simplify(vertices, triangles, reference, a.triangles, a.volume_error)
    volume_error, moment_error = errors_against(reference, vertices, triangles)
    write_obj(a.output, vertices, triangles, f"{source}, {len(triangles)} triangles (tools/make_shape.py)")
    problem = validate(pathlib.Path(a.output).resolve())
    print(f"{a.output}: {len(triangles)} triangles, volume error {volume_error:.2e}, principal moments error "
          f"{moment_error:.2e}; validator: {problem or 'accepted'}")
    return 1 if problem else 0


if __name__ == "__main__":
    sys.exit(main())
