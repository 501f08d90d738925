#!/usr/bin/env python3
"""Renders one time step of a scene, particles (`dump polyhedron/vtk`, .vtp) and mesh walls (LIGGGHTS'
`dump mesh/vtk`, legacy .vtk), to a PNG, and optionally writes a ParaView state (.pvsm) of it.

    python3 tools/render_scene.py scene.png post/particles_2500.vtp post/mesh_2500.vtk
    python3 tools/render_scene.py scene.png 'post/particles_*.vtp' 'post/mesh_*.vtk' --state scene.pvsm

Files ending in .vtp or .pvtp (a piece per rank) are particles, files ending in .vtk are meshes; a quoted pattern with `*` is a time
series (in the state file) and the picture shows its last step. Two renderers:

- `paraview` (default when Debian's `python3-paraview` is installed, which `liggghts` recommends): ParaView's
  own Python (`paraview.simple`) from python3 or pvbatch, offscreen under Xvfb; without a DISPLAY the script
  runs itself again under `xvfb-run -a` (package `xvfb`).
- `matplotlib`: no ParaView needed; the same scene with Lambert-shaded facets, painter's order.

Particles are coloured by a cell field of the .vtp (`--colour shape|type|id|speed|v|omega`), meshes are
translucent (`--opacity`) and coloured by a cell field of the .vtk when it has one (`--mesh-colour`, default
`normal_stress_average` of `dump mesh/vtk ... stress` if present, else grey).
"""
import argparse
import glob
import importlib.util
import os
import re
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_vtp import AZIMUTH, ELEVATION, frame_axes, read_vtp  # noqa: E402


def read_legacy_vtk(path):
    """An ASCII legacy VTK POLYDATA file as LIGGGHTS' `dump mesh/vtk` writes it (format 5.1, OFFSETS and
    CONNECTIVITY; the older count-prefixed POLYGONS too): (points (n, 3), polygons [index arrays],
    cell data {name: array}, point data {name: array})."""
    with open(path) as stream:
        lines = stream.read().splitlines()
    if not lines or not lines[0].startswith("# vtk DataFile"):
        raise ValueError(f"{path}: not a legacy VTK file")
    if lines[2].strip().upper() != "ASCII":
        raise ValueError(f"{path}: only ASCII legacy VTK is read")
    words = " ".join(lines[3:]).split()
    position = 0

    def take(count, dtype=float):
        nonlocal position
        values = np.array(words[position:position + count], dtype=dtype)
        if len(values) != count:
            raise ValueError(f"{path}: file ends early")
        position += count
        return values

    points = np.zeros((0, 3))
    polygons = []
    data = {"CELL_DATA": {}, "POINT_DATA": {}}
    section = "CELL_DATA"
    while position < len(words):
        keyword = words[position].upper()
        position += 1
        if keyword == "DATASET":
            if words[position].upper() != "POLYDATA":
                raise ValueError(f"{path}: DATASET {words[position]}, not POLYDATA")
            position += 1
        elif keyword == "POINTS":
            count = int(words[position])
            position += 2
            points = take(3 * count).reshape(count, 3)
        elif keyword in ("POLYGONS", "TRIANGLE_STRIPS", "LINES", "VERTICES"):
            count, size = int(words[position]), int(words[position + 1])
            position += 2
            if words[position].upper() == "OFFSETS":  # format 5.1: count = cells + 1
                position += 2
                offsets = take(count, int)
                if words[position].upper() != "CONNECTIVITY":
                    raise ValueError(f"{path}: OFFSETS without CONNECTIVITY")
                position += 2
                connectivity = take(size, int)
                cells = [connectivity[a:b] for a, b in zip(offsets[:-1], offsets[1:])]
            else:  # format <= 4.2: each cell is its vertex count, then its vertices
                flat = take(size, int)
                cells, at = [], 0
                while at < len(flat):
                    cells.append(flat[at + 1:at + 1 + flat[at]])
                    at += 1 + flat[at]
            if keyword == "POLYGONS":
                polygons += cells
        elif keyword in ("CELL_DATA", "POINT_DATA"):
            section = keyword
            position += 1
        elif keyword == "FIELD":
            arrays = int(words[position + 1])
            position += 2
            for _ in range(arrays):
                name, components, tuples = words[position], int(words[position + 1]), int(words[position + 2])
                position += 4
                values = take(components * tuples)
                data[section][name] = values.reshape(tuples, components) if components > 1 else values
        elif keyword in ("SCALARS", "VECTORS", "NORMALS"):
            name = words[position]
            position += 2
            if keyword == "SCALARS":
                components = 1
                if words[position].upper() != "LOOKUP_TABLE":
                    components = int(words[position])
                    position += 1
                position += 2  # LOOKUP_TABLE name
            else:
                components = 3
            count = len(polygons) if section == "CELL_DATA" else len(points)
            values = take(components * count)
            data[section][name] = values.reshape(count, components) if components > 1 else values
        elif keyword == "METADATA":  # written by VTK 9 writers, not by LIGGGHTS: skip to the blank line
            raise ValueError(f"{path}: METADATA blocks are not read")
        else:
            raise ValueError(f"{path}: unexpected '{words[position - 1]}'")
    return points, polygons, data["CELL_DATA"], data["POINT_DATA"]


def mesh_triangles(points, polygons):
    """The polygons fanned into triangles, (m, 3) indices, and for each triangle its polygon's index."""
    triangles, owners = [], []
    for index, polygon in enumerate(polygons):
        for k in range(1, len(polygon) - 1):
            triangles.append((polygon[0], polygon[k], polygon[k + 1]))
            owners.append(index)
    return np.array(triangles, dtype=int).reshape(-1, 3), np.array(owners, dtype=int)


def expand(pattern):
    """A file or a `*` pattern, sorted by the number in the name (the time step)."""
    if "*" not in pattern:
        return [pattern]
    files = glob.glob(pattern)
    if not files:
        raise SystemExit(f"render_scene.py: no files match {pattern}")
    number = re.compile(r"(\d+)(?=\.[^.]*$)")
    return sorted(files, key=lambda f: (int(number.search(f).group(1)) if number.search(f) else -1, f))


def particle_values(cell_data, name):
    if name == "speed":
        return np.linalg.norm(cell_data["v"], axis=1)
    values = cell_data[name]
    return np.linalg.norm(values, axis=1) if values.ndim > 1 else values


def view_direction():
    elevation, azimuth = np.radians(ELEVATION), np.radians(AZIMUTH)
    return np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)])


def render_matplotlib(args, particle_series, mesh_series):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    light = np.array([0.4, -0.5, 0.75]) / np.linalg.norm([0.4, -0.5, 0.75])

    def shaded(corners, colours):
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
        colours[:, :3] *= (0.35 + 0.65 * np.abs(normals @ light))[:, None]
        return colours

    def mapped(values, cmap):
        span = values.max() - values.min()
        return cmap((values - values.min()) / span if span > 0 else np.zeros_like(values))

    figure = plt.figure(figsize=(args.size[0] / 100, args.size[1] / 100), dpi=100)
    axes = figure.add_subplot(projection="3d")
    all_points, polygons_drawn, particles_drawn = [], 0, 0
    for files in mesh_series:
        points, polygons, cell_data, _ = read_legacy_vtk(files[-1])
        triangles, owners = mesh_triangles(points, polygons)
        field = args.mesh_colour or ("normal_stress_average" if "normal_stress_average" in cell_data else None)
        if field and field != "none":
            values = cell_data[field]
            values = np.linalg.norm(values, axis=1) if values.ndim > 1 else values
            colours = mapped(values[owners], plt.cm.inferno)
        else:
            colours = np.tile([0.7, 0.7, 0.72, 1.0], (len(triangles), 1))
        colours = shaded(points[triangles], colours)
        colours[:, 3] = args.opacity
        axes.add_collection3d(Poly3DCollection(points[triangles], facecolors=colours,
                                               edgecolors=(0, 0, 0, 0.25 * args.opacity), linewidths=0.3))
        all_points.append(points)
        polygons_drawn += len(polygons)
    for files in particle_series:
        points, triangles, cell_data = read_vtp(files[-1])
        colours = shaded(points[triangles], mapped(particle_values(cell_data, args.colour), plt.cm.viridis))
        axes.add_collection3d(Poly3DCollection(points[triangles], facecolors=colours,
                                               edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
        all_points.append(points)
        particles_drawn += len(np.unique(cell_data["id"]))
    frame_axes(axes, np.vstack(all_points))
    axes.set_title(args.title or f"{particles_drawn} particles, {polygons_drawn} mesh triangles")
    figure.subplots_adjust(left=0, right=1, bottom=0, top=0.95)
    figure.savefig(args.png, dpi=100)


def black_scalar_bar(simple, lut, view, title):
    bar = simple.GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]


def render_paraview(args, particle_series, mesh_series):
    from paraview import simple

    view = simple.CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 1
    try:  # ParaView >= 5.10: the palette sets the background unless told not to
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = [1.0, 1.0, 1.0]
    sources = []
    for files in mesh_series:
        reader = simple.LegacyVTKReader(registrationName=os.path.basename(files[0]).split("_")[0] + "_mesh",
                                        FileNames=[os.path.abspath(f) for f in files])
        display = simple.Show(reader, view)
        field = args.mesh_colour or ("normal_stress_average"
                                     if "normal_stress_average" in reader.CellData.keys() else None)
        if field and field != "none":
            simple.ColorBy(display, ("CELLS", field))
            lut = simple.GetColorTransferFunction(field)
            lut.ApplyPreset("Inferno (matplotlib)", True)
            black_scalar_bar(simple, lut, view, field)
            display.SetScalarBarVisibility(view, True)
        else:
            simple.ColorBy(display, None)
            display.AmbientColor = display.DiffuseColor = [0.7, 0.7, 0.72]
        display.Opacity = args.opacity
        sources.append(reader)
    for files in particle_series:
        read = simple.XMLPartitionedPolydataReader if files[0].endswith(".pvtp") else simple.XMLPolyDataReader
        reader = read(registrationName=os.path.basename(files[0]).split("_")[0],
                      FileName=[os.path.abspath(f) for f in files])
        display = simple.Show(reader, view)
        if args.colour == "speed":
            simple.ColorBy(display, ("CELLS", "v", "Magnitude"))
            name = "v"
        else:
            name = args.colour
            simple.ColorBy(display, ("CELLS", name, "Magnitude") if name in ("v", "omega") else ("CELLS", name))
        lut = simple.GetColorTransferFunction(name)
        lut.ApplyPreset("Viridis (matplotlib)", True)
        black_scalar_bar(simple, lut, view, args.colour)
        display.SetScalarBarVisibility(view, True)
        sources.append(reader)
    # The last step of the series; file lists without time values count 0, 1, 2, ...
    times = [t for s in sources for t in (s.TimestepValues or [])] if any(
        len(files) > 1 for files in particle_series + mesh_series) else []
    if times:
        scene = simple.GetAnimationScene()
        scene.UpdateAnimationUsingDataTimeSteps()
        scene.AnimationTime = max(times)
        view.ViewTime = max(times)
    for source in sources:
        source.UpdatePipeline(view.ViewTime)
        simple.GetDisplayProperties(source, view).RescaleTransferFunctionToDataRange(False, True)
    bounds = np.array([s.GetDataInformation().GetBounds() for s in sources]).reshape(-1, 3, 2)
    low, high = bounds[:, :, 0].min(axis=0), bounds[:, :, 1].max(axis=0)
    centre = 0.5 * (low + high)
    view.CameraFocalPoint = list(centre)
    view.CameraPosition = list(centre + np.linalg.norm(high - low) * 2.0 * view_direction())
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    simple.SaveScreenshot(args.png, view, ImageResolution=list(args.size))
    if args.state:
        simple.SaveState(args.state)


def paraview_available():
    try:
        return importlib.util.find_spec("paraview.simple") is not None
    except ImportError:
        return False


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("png")
    parser.add_argument("files", nargs="+",
                        help=".vtp or .pvtp particle and .vtk mesh files (or quoted '*' patterns)")
    parser.add_argument("--colour", default="shape", help="shape, type, id, speed, v or omega (default shape)")
    parser.add_argument("--mesh-colour", default=None,
                        help="a cell field of the mesh files, or none (default normal_stress_average if present)")
    parser.add_argument("--opacity", type=float, default=0.35, help="of the meshes (default 0.35)")
    parser.add_argument("--size", type=int, nargs=2, default=(800, 600), metavar=("W", "H"))
    parser.add_argument("--title", default=None, help="matplotlib only")
    parser.add_argument("--backend", default="auto", choices=["auto", "paraview", "matplotlib"])
    parser.add_argument("--state", default=None, help="also write a ParaView state file (paraview only)")
    args = parser.parse_args()

    series = [expand(pattern) for pattern in args.files]
    particle_series = [s for s in series if s[0].endswith((".vtp", ".pvtp"))]
    mesh_series = [s for s in series if s[0].endswith(".vtk")]
    if len(particle_series) + len(mesh_series) != len(series):
        parser.error("files must end in .vtp or .pvtp (particles) or .vtk (meshes)")

    backend = args.backend
    if backend == "auto":
        backend = "paraview" if paraview_available() and (os.environ.get("DISPLAY") or shutil.which("xvfb-run")) \
            else "matplotlib"
    if args.state and backend != "paraview":
        parser.error("--state needs the paraview renderer (python3-paraview)")
    if backend == "paraview" and not os.environ.get("DISPLAY") and \
            os.path.basename(sys.executable).startswith("python"):
        # Debian's ParaView renders through X: give it a virtual one.
        if not shutil.which("xvfb-run"):
            raise SystemExit("render_scene.py: no DISPLAY and no xvfb-run (apt-get install xvfb), "
                             "or use --backend matplotlib")
        argv, skip = [], False
        for a in sys.argv[1:]:
            if not skip and not a.startswith("--backend"):
                argv.append(a)
            skip = a == "--backend"
        # -noreset: by default an X server resets when its last client disconnects and refuses connections
        # while it does; ParaView opens and closes a display before opening its render window's, and that open
        # then failed now and then ("bad X server connection", seen in the test suite; with a loop of
        # XOpenDisplay/XCloseDisplay under xvfb-run, 23 of 300 opens failed without -noreset and none with it).
        first = str(100 + os.getpid() % 20000)
        command = ["xvfb-run", "-a", "-n", first, "-s", "-screen 0 1600x1200x24 -noreset", sys.executable,
                   os.path.abspath(__file__)]
        command += argv + ["--backend", "paraview"]
        sys.exit(subprocess.call(command))
    if backend == "paraview":
        render_paraview(args, particle_series, mesh_series)
    else:
        render_matplotlib(args, particle_series, mesh_series)


if __name__ == "__main__":
    main()
