"""fix wall/polyhedral primitive zcylinder R CX CY: the overlap geometry of src/poly_cylinder.h against an
independent reference of the exact cylinder, and the wall as a user runs it.

Geometry reference (numpy, shares nothing with the C code): the volume and first moment of (particle n
wall solid) as integrals over the wall's part of the xy plane of the particle's vertical chords, found by
casting vertical rays at the particle's triangles, with the midpoint rule on a polar grid over the band of
the cylinder the particle reaches. Its own error, measured by doubling the grid, is below 1e-4 of the
volume and 1e-4 of the particle size (centroid) in these cases, so the comparisons use 5e-4; the
approximant's error (sagitta 1e-6 of the bounding radius, the fix's default) is far below that.
"""
import ctypes
import math
import os
import subprocess

import numpy as np
import pytest

import decks
import overlap_reference as ref
from test_overlap_geometry import SHAPES, SHIM_SOURCE, SOURCES, Library, random_quaternion

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CYLINDER_SHIM = r"""
#include "poly_cylinder.h"

int shim_cylinder_facets(double radius, double max_sagitta) { return poly_cylinder_facets(radius, max_sagitta); }
double shim_cylinder_sagitta(double radius, int facets) { return poly_cylinder_sagitta(radius, facets); }

/* out: volume, centroid (3), normal (3), depth, area, num_nodes, num_inconsistent, filtered_out */
void shim_cylinder(const void *a, const double *pose, const double *axis, double radius, int facets, double *out)
{
  poly_pose p;
  for (int k = 0; k < 3; k++) p.position[k] = pose[k];
  for (int k = 0; k < 4; k++) p.quaternion[k] = pose[3 + k];
  double rotation[9];
  poly_quat_to_matrix(p.quaternion, rotation);
  poly_overlap_result r;
  poly_cylinder_overlap(&((const shim_shape *)a)->view_d, rotation, p.position, axis, radius, facets, &r);
  shim_write_result(&r, out);
}
"""

DOUBLES = ctypes.POINTER(ctypes.c_double)


@pytest.fixture(scope="module")
def cylinder_lib(tmp_path_factory):
    directory = tmp_path_factory.mktemp("cylinder_lib")
    shim = directory / "cylinder_shim.c"
    shim.write_text(SHIM_SOURCE + CYLINDER_SHIM)
    library = directory / "libpoly_cylinder_test.so"
    command = (["gcc", "-std=c11", "-O2", "-fPIC", "-shared", "-Wall", "-Wextra", "-Werror",
                "-I" + os.path.join(ROOT, "src")] + SOURCES + [str(shim), "-lm", "-o", str(library)])
    built = subprocess.run(command, capture_output=True, text=True)
    assert built.returncode == 0, " ".join(command) + "\n" + built.stderr
    lib = Library(str(library))
    lib.lib.shim_cylinder.argtypes = [ctypes.c_void_p, DOUBLES, DOUBLES, ctypes.c_double, ctypes.c_int, DOUBLES]
    lib.lib.shim_cylinder.restype = None
    lib.lib.shim_cylinder_facets.argtypes = [ctypes.c_double, ctypes.c_double]
    lib.lib.shim_cylinder_facets.restype = ctypes.c_int
    lib.lib.shim_cylinder_sagitta.argtypes = [ctypes.c_double, ctypes.c_int]
    lib.lib.shim_cylinder_sagitta.restype = ctypes.c_double
    return lib


def cylinder(lib, shape, pose, radius, facets, axis=(0.0, 0.0)):
    out = (ctypes.c_double * 12)()
    lib.lib.shim_cylinder(shape.handle, (ctypes.c_double * 7)(*[float(x) for x in list(pose[0]) + list(pose[1])]),
                          (ctypes.c_double * 2)(*axis), float(radius), int(facets), out)
    return {"volume": out[0], "centroid": np.array(out[1:4]), "normal": np.array(out[4:7]), "depth": out[7],
            "area": out[8], "filtered_out": int(out[11])}


def nearest_to_the_axis(p):
    """Smallest distance in the xy plane from the z axis to the projected triangles p (T, 3, 3)."""
    best = np.inf
    for tri in p[:, :, :2]:
        for k in range(3):
            a, b = tri[k], tri[(k + 1) % 3]
            t = np.clip(-(a @ (b - a)) / max((b - a) @ (b - a), 1e-300), 0.0, 1.0)
            best = min(best, np.linalg.norm(a + t * (b - a)))
        sides = [np.cross(tri[k], tri[(k + 1) % 3]) for k in range(3)]
        if min(sides) >= 0 or max(sides) <= 0:
            return 0.0
    return best


def vertical_chords(p, x, y):
    """Length of the particle (triangles p, (T, 3, 3)) along the vertical lines through (x, y), and the
    integral of z over it: sums over the triangles above each point of sign(n_z) z and sign(n_z) z^2 / 2."""
    length, z_moment = np.zeros_like(x), np.zeros_like(x)
    for a, b, c in p:
        e1, e2 = b - a, c - a
        det = e1[0] * e2[1] - e1[1] * e2[0]
        if det == 0.0:
            continue
        px, py = x - a[0], y - a[1]
        u = (px * e2[1] - py * e2[0]) / det
        v = (e1[0] * py - e1[1] * px) / det
        hit = (u >= 0) & (v >= 0) & (u + v <= 1)
        z = a[2] + u[hit] * e1[2] + v[hit] * e2[2]
        sign = math.copysign(1.0, det)
        length[hit] += sign * z
        z_moment[hit] += sign * z * z / 2
    return length, z_moment


def chord_reference(world, triangles, radius, drum, samples=800):
    """Volume, centroid and contact normal of (shape n wall solid) for the exact cylinder about the z axis.
    V and the first moment integrate the particle's vertical chords over the wall's part of the xy plane
    (polar midpoint grid, samples x samples, over the radii and angles of the triangles that reach the
    wall); the normal is the area vector of the cap, the cylinder surface inside the particle, from the
    chords on the circle r = R."""
    p = world[triangles]                        # (T, 3, 3)
    r = np.hypot(p[:, :, 0], p[:, :, 1])
    if drum:
        p = p[r.max(axis=1) > radius]
        r_low, r_high = radius, r.max()
    else:
        p = p[[nearest_to_the_axis(tri[None]) < radius for tri in p]]
        r_low, r_high = nearest_to_the_axis(p), radius
    # The angles of the wall's part of the projection are extreme at its corners: projected vertices in the
    # wall and crossings of projected edges with the circle.
    corners = [q[:2] for q in p.reshape(-1, 3) if (np.hypot(*q[:2]) > radius) == drum]
    for tri in p[:, :, :2]:
        for k in range(3):
            a, e = tri[k], tri[(k + 1) % 3] - tri[k]
            qa, qb, qc = e @ e, 2 * a @ e, a @ a - radius ** 2
            disc = qb * qb - 4 * qa * qc
            if qa > 0 and disc >= 0:
                corners += [a + t * e for t in ((-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa))
                            if 0 <= t <= 1]
    corners = np.array(corners)
    centre_angle = math.atan2(corners[:, 1].mean(), corners[:, 0].mean())
    offsets = np.angle(np.exp(1j * (np.arctan2(corners[:, 1], corners[:, 0]) - centre_angle)))
    a_low, a_high = centre_angle + offsets.min(), centre_angle + offsets.max()
    dr, da = (r_high - r_low) / samples, (a_high - a_low) / samples
    rr = r_low + (np.arange(samples) + 0.5) * dr
    aa = a_low + (np.arange(samples) + 0.5) * da
    R, A = np.meshgrid(rr, aa, indexing="ij")
    x, y = (R * np.cos(A)).ravel(), (R * np.sin(A)).ravel()
    weight = (R * dr * da).ravel()
    length, z_moment = vertical_chords(p, x, y)
    volume = (length * weight).sum()
    centroid = np.array([(x * length * weight).sum(), (y * length * weight).sum(), (z_moment * weight).sum()]) / volume
    fine = a_low + (np.arange(20 * samples) + 0.5) * (a_high - a_low) / (20 * samples)
    on_circle, _ = vertical_chords(p, radius * np.cos(fine), radius * np.sin(fine))
    cap = np.array([(on_circle * np.cos(fine)).sum(), (on_circle * np.sin(fine)).sum(), 0.0])
    return volume, centroid, cap / np.linalg.norm(cap) * (1.0 if drum else -1.0)


def pose_near_the_shell(shape, rng, radius, drum, depth_fraction):
    """A random orientation, the centre at a random angle, pushed so that the deepest vertex reaches
    depth_fraction of the bounding radius into the wall solid (radially)."""
    q = random_quaternion(rng)
    body = ref.to_world(shape.vertices, np.zeros(3), q)
    angle = rng.uniform(0, 2 * math.pi)
    direction = np.array([math.cos(angle), math.sin(angle), 0.0])
    target = depth_fraction * shape.radius
    low, high = radius - 3 * shape.radius, radius + 3 * shape.radius
    for _ in range(100):   # bisection on the centre's distance from the axis
        middle = 0.5 * (low + high)
        r = np.hypot(*(body + middle * direction)[:, :2].T)
        reach = (r.max() - radius) if drum else (radius - r.min())
        if (reach > target) == drum:
            high = middle
        else:
            low = middle
    centre = 0.5 * (low + high) * direction + np.array([0.0, 0.0, rng.uniform(-1, 1)])
    return centre, q


@pytest.fixture(scope="module")
def particles(cylinder_lib):
    return {name: cylinder_lib.shape(os.path.join(SHAPES, file), scale)
            for name, file, scale in (("cube", "cube.stl", 0.02), ("icosphere_320", "icosphere_320.off", 0.02),
                                      ("rock_40", "rock_40.obj", 0.02))}


@pytest.mark.parametrize("name", ["cube", "icosphere_320", "rock_40"])
@pytest.mark.parametrize("drum", [True, False], ids=["inside", "outside"])
def test_overlap_matches_the_exact_cylinder(cylinder_lib, particles, name, drum):
    """Random orientations near the shell (drum R = 0.1 m, pillar R = 0.05 m; particles of 20 mm), 0.5..20 %
    of the bounding radius deep: volume within 1e-4 relative, centroid within 1e-5 of the particle size,
    normal within 1e-4 of the cap's, against the chord reference of the exact cylinder."""
    shape = particles[name]
    radius = 0.1 if drum else 0.05
    facets = cylinder_lib.lib.shim_cylinder_facets(radius, 1e-6 * shape.radius)
    size = shape.volume ** (1 / 3)
    rng = np.random.default_rng(7 if drum else 8)
    worst = [0.0, 0.0, 0.0]
    for depth_fraction in (0.005, 0.03, 0.2, 0.02, 0.1):
        pose = pose_near_the_shell(shape, rng, radius, drum, depth_fraction)
        got = cylinder(cylinder_lib, shape, pose, radius, facets)
        volume, centroid, normal = chord_reference(shape.world(pose), shape.triangles, radius, drum)
        worst[0] = max(worst[0], abs(got["volume"] / volume - 1))
        worst[1] = max(worst[1], np.abs(got["centroid"] - centroid).max() / size)
        worst[2] = max(worst[2], np.abs(got["normal"] - normal).max())
        assert got["normal"][2] == 0.0
    print(f"\n{name} {'inside' if drum else 'outside'} ({facets} facets): worst V {worst[0]:.1e}, "
          f"centroid {worst[1]:.1e} L, normal {worst[2]:.1e}")
    assert worst[0] < 1e-4 and worst[1] < 1e-5 and worst[2] < 1e-4, worst
