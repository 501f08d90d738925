#!/usr/bin/env python3
"""Renders a dump polyhedron/vtk snapshot (.vtp) to a PNG with matplotlib, no ParaView needed.

    python3 tools/render_vtp.py particles_1000.vtp picture.png [--colour shape|type|id|speed]
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_vtp(path):
    """Points, triangles and per-triangle arrays of a dump polyhedron/vtk snapshot (.vtp, or .pvtp with its
    pieces), read by VTK's own XML readers (ParaView's Python, python3-paraview), whatever the encoding."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader

    reader = vtkXMLPPolyDataReader() if str(path).endswith(".pvtp") else vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise OSError(f"VTK could not read {path}")
    surfaces = reader.GetOutput()
    points = vtk_to_numpy(surfaces.GetPoints().GetData()).astype(float)
    polys = surfaces.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    if not np.all(np.diff(offsets) == 3):
        raise ValueError(f"{path}: not all cells are triangles")
    triangles = vtk_to_numpy(polys.GetConnectivityArray()).astype(int).reshape(-1, 3)
    cell_data = surfaces.GetCellData()
    arrays = {cell_data.GetArrayName(k): vtk_to_numpy(cell_data.GetArray(k)).copy()
              for k in range(cell_data.GetNumberOfArrays())}
    return points, triangles, arrays


# The view: elevation and azimuth of the camera (degrees); tools/render_scene.py uses the same.
ELEVATION, AZIMUTH = 22.0, -60.0


def frame_axes(axes, points):
    """Cubic limits around the points, axes in metres, the standard view."""
    low, high = points.min(axis=0), points.max(axis=0)
    centre, half = 0.5 * (low + high), 0.5 * np.max(high - low)
    for setter, c in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), centre):
        setter(c - half, c + half)
    axes.set_box_aspect((1, 1, 1))
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_zlabel("z (m)")
    axes.view_init(elev=ELEVATION, azim=AZIMUTH)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("vtp")
    parser.add_argument("png")
    parser.add_argument("--colour", default="shape", choices=["shape", "type", "id", "speed"])
    parser.add_argument("--title", default=None)
    args = parser.parse_args()

    points, triangles, cell_data = read_vtp(args.vtp)
    if args.colour == "speed":
        values = np.linalg.norm(cell_data["v"], axis=1)
    else:
        values = cell_data[args.colour]
    span = values.max() - values.min()
    colours = plt.cm.viridis((values - values.min()) / span if span > 0 else np.zeros_like(values))

    # Lambert shading from a fixed light so the facets read as solids.
    corners = points[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    light = np.array([0.4, -0.5, 0.75]) / np.linalg.norm([0.4, -0.5, 0.75])
    shade = 0.35 + 0.65 * np.clip(normals @ light, 0.0, 1.0)
    colours[:, :3] *= shade[:, None]

    figure = plt.figure(figsize=(7, 6), dpi=110)
    axes = figure.add_subplot(projection="3d")
    axes.add_collection3d(Poly3DCollection(corners, facecolors=colours, edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
    frame_axes(axes, points)
    axes.set_title(args.title or f"{len(np.unique(cell_data['id']))} particles, {len(triangles)} triangles")
    figure.tight_layout()
    figure.savefig(args.png)


if __name__ == "__main__":
    main()
