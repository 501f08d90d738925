"""fix wall/polyhedral with LIGGGHTS triangle meshes (fix mesh/surface, mesh/surface/stress, fix move/mesh).

The construction (src/poly_mesh_shell.h): each triangle owns the prism of the shell behind it, built
from vertex directions shared by neighbouring triangles, so the prisms partition the shell and a flat
wall tessellated into any number of triangles is the same solid as one plane. Here as a user runs it:
a cube resting on floors of 2 and 200 triangles against the plane primitive and the weight; stick and
slide on a mesh floor; an icosphere impact on a mesh floor against LIGGGHTS' sphere on the same mesh;
a particle shaken in a closed box; the torque a drum's particles put on it; bad input.
"""
import math

import numpy as np
import pytest

import decks
import meshes
from test_walls import DENSITY, EDGE, G, scene, static_depth

MASS = DENSITY * EDGE ** 3


def mesh_wall(stl, stress=False, extra=""):
    """The mesh fix (ID floor_mesh) and the wall (ID floor, as the plane tests name it)."""
    style = "mesh/surface/stress" if stress else "mesh/surface"
    return (f"fix floor_mesh all {style} file {stl} type 2{extra}\n"
            "fix floor all wall/polyhedral mesh n_meshes 1 meshes floor_mesh\n")


@pytest.mark.parametrize("cells", [1, 10, 7], ids=["2-triangles", "200-triangles", "98-triangles-offset"])
def test_cube_rests_on_a_mesh_floor_as_on_a_plane(run_deck, tmp_path, cells):
    """The cube of tests/test_walls.py (20 mm, turned 0.6 rad about z) at rest on a floor of 2, 200
    and 98 triangles (10 x 10 and 7 x 7 grids of 20 and 28.6 mm cells, so the cube's face covers
    shared edges and vertices): the wall carries the weight and the cube sinks by the closed-form
    depth, within 1%, as on the zplane primitive; and the mesh floor gives the plane's depth to 1e-6."""
    stl = meshes.write_stl(tmp_path / "floor.stl", meshes.grid(cells, 0.1))
    pose = f"0.003 -0.002 {EDGE / 2} quat {math.cos(0.3)} 0 0 {math.sin(0.3)}"
    results = {}
    for name, wall in (("plane", "fix floor all wall/polyhedral primitive type 2 zplane 0.0\n"),
                       ("mesh", mesh_wall("../floor.stl"))):
        result = run_deck(scene(wall, pose, steps=20000), workdir=tmp_path / name)
        assert result.returncode == 0, result.output[-3000:]
        table = result.thermo("Step", "v_z", "f_floor[3]", "f_floor[4]")
        settled = [i for i, step in enumerate(table["Step"]) if step >= 10000]
        results[name] = (np.array(table["f_floor[3]"])[settled], EDGE / 2 - np.array(table["v_z"])[settled],
                         np.array(table["f_floor[4]"])[settled])
    force, depth, contacts = results["mesh"]
    print(f"\ncube on {2 * cells * cells} triangles: force / weight - 1 = {-force.mean() / (MASS * G) - 1:.2e}, "
          f"depth / closed form - 1 = {depth.mean() / static_depth(MASS) - 1:.2e}, "
          f"depth / plane's - 1 = {depth.mean() / results['plane'][1].mean() - 1:.2e}")
    assert all(c == 1 for c in contacts)
    assert abs(-force.mean() / (MASS * G) - 1) < 0.01, force.mean()
    assert abs(depth.mean() / static_depth(MASS) - 1) < 0.01, depth.mean()
    assert abs(depth.mean() / results["plane"][1].mean() - 1) < 1e-6
