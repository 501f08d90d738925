"""fix wall/polyhedral primitive zcylinder R CX CY: the overlap geometry of src/poly_cylinder.h against an
independent reference of the exact cylinder, and the wall as a user runs it.

Geometry reference (numpy, shares nothing with the C code): the volume and first moment of (particle n wall
solid) integrate the particle's vertical chords, found by casting vertical rays at its triangles, over the
wall's part of the xy plane (midpoint rule on a polar grid over the radii and angles that the triangles
reaching the wall span); the contact normal is the area vector of the cap (the cylinder surface inside the
particle), from the chords on the circle. Its own error, measured by doubling the grid (800 to 1600 per
direction, test_the_reference_converges) on a cube and an icosphere 1 and 10 % of the bounding radius deep:
volume 4e-7 relative, centroid 4e-8 of the particle size, normal 1e-11. The approximant's, at the fix's default sagitta (1e-6 of the bounding
radius), is of the same order, so the comparisons use 1e-4 (volume), 1e-5 (centroid) and 1e-4 (normal).
"""
import ctypes
import math
import os
import subprocess
import time

import numpy as np
import pytest

import decks
from test_walls import DENSITY, EDGE, G, POISSON, YOUNGS, check_crosses_ranks, scene
import overlap_reference as ref
from test_overlap_geometry import SHAPES, SHIM_SOURCE, SOURCES, Library, random_quaternion

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CYLINDER_SHIM = r"""
#include "poly_cylinder.h"

int shim_cylinder_facets(double radius, double max_sagitta) { return poly_cylinder_facets(radius, max_sagitta); }
double shim_cylinder_sagitta(double radius, int facets) { return poly_cylinder_sagitta(radius, facets); }

/* out: volume, centroid (3), normal (3), depth, area, num_nodes, num_inconsistent, filtered_out,
 * projected_area */
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
  out[12] = r.projected_area;
}

/* out: whether the ends are inside the polygon (2), the crossing count, then t, facet and enter of each. */
void shim_cylinder_crossings(double radius, int facets, const double *a, const double *d, double *out)
{
  poly_cylinder_polygon g = poly_cylinder_polygon_of(radius, facets);
  int inside_a = poly_cylinder_in_polygon(&g, a[0], a[1]), inside_b = poly_cylinder_in_polygon(&g, a[0] + d[0], a[1] + d[1]);
  double t[2];
  int facet[2], enter[2], count = poly_cylinder_edge_crossings(&g, a, d, inside_a, inside_b, t, facet, enter, NULL);
  out[0] = inside_a, out[1] = inside_b, out[2] = count;
  for (int k = 0; k < count; k++) out[3 + 3 * k] = t[k], out[4 + 3 * k] = facet[k], out[5 + 3 * k] = enter[k];
}

/* out: volume, moment (3), area, area vector (3) of triangle p's part in the polygon's solid (p: 3 corners
 * relative to the axis), the fast way or by the clipping. */
void shim_cylinder_triangle(const double *p, double radius, int facets, int drum, int fast, double *out)
{
  poly_cylinder_polygon g = poly_cylinder_polygon_of(radius, facets);
  poly_cylinder_sums sums = {0.0, {0.0, 0.0, 0.0}, 0.0, {0.0, 0.0, 0.0}};
  poly_cylinder_edge_memo memo;
  poly_cylinder_edge_memo_clear(&memo);
  const int corners[3] = {0, 1, 2};
  poly_cylinder_triangle((const double (*)[3])p, corners, &memo, &g, drum, fast, &sums);
  out[0] = sums.volume, out[4] = sums.area;
  for (int k = 0; k < 3; k++) out[1 + k] = sums.moment[k], out[5 + k] = sums.area_vector[k];
}

void shim_cylinder_reference(const void *a, const double *pose, const double *axis, double radius, int facets,
                             double *out)
{
  double rotation[9];
  poly_quat_to_matrix(pose + 3, rotation);
  poly_overlap_result r;
  poly_cylinder_overlap_reference(&((const shim_shape *)a)->view_d, rotation, pose, axis, radius, facets, &r);
  shim_write_result(&r, out);
  out[12] = r.projected_area;
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
    lib.lib.shim_cylinder_reference.argtypes = lib.lib.shim_cylinder.argtypes
    lib.lib.shim_cylinder_reference.restype = None
    lib.lib.shim_cylinder_crossings.argtypes = [ctypes.c_double, ctypes.c_int, DOUBLES, DOUBLES, DOUBLES]
    lib.lib.shim_cylinder_crossings.restype = None
    lib.lib.shim_cylinder_triangle.argtypes = [DOUBLES, ctypes.c_double, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                                               DOUBLES]
    lib.lib.shim_cylinder_triangle.restype = None
    lib.lib.shim_cylinder_facets.argtypes = [ctypes.c_double, ctypes.c_double]
    lib.lib.shim_cylinder_facets.restype = ctypes.c_int
    lib.lib.shim_cylinder_sagitta.argtypes = [ctypes.c_double, ctypes.c_int]
    lib.lib.shim_cylinder_sagitta.restype = ctypes.c_double
    return lib


def cylinder(lib, shape, pose, radius, facets, axis=(0.0, 0.0), reference=False):
    out = (ctypes.c_double * 13)()
    call = lib.lib.shim_cylinder_reference if reference else lib.lib.shim_cylinder
    call(shape.handle, (ctypes.c_double * 7)(*[float(x) for x in list(pose[0]) + list(pose[1])]),
         (ctypes.c_double * 2)(*axis), float(radius), int(facets), out)
    return {"volume": out[0], "centroid": np.array(out[1:4]), "normal": np.array(out[4:7]), "depth": out[7],
            "area": out[8], "nodes": int(out[9]), "filtered_out": int(out[11]), "projected_area": out[12]}


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
    """Volume, centroid, contact normal and cap area of (shape n wall solid) for the exact cylinder about the z axis.
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
    cap_area = on_circle.sum() * radius * (a_high - a_low) / (20 * samples)
    return volume, centroid, cap / np.linalg.norm(cap) * (1.0 if drum else -1.0), cap_area


def pose_near_the_shell(shape, rng, radius, drum, depth_fraction, q=None):
    """A random orientation (or q), the centre at a random angle, pushed so that the deepest vertex reaches
    depth_fraction of the bounding radius into the wall solid (radially)."""
    q = random_quaternion(rng) if q is None else q
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
            for name, file, scale in (("cube", "cube.stl", 0.02), ("icosphere_1280", "icosphere_1280.off", 0.02),
                                      ("rock_40", "rock_40.obj", 0.02))}


@pytest.mark.parametrize("name", ["cube", "icosphere_1280"])
def test_the_reference_converges(particles, name):
    """The chord reference on grids of 800 and 1600 points per direction, 1 and 10 % of the bounding radius
    deep in the drum: volume within 1e-5 relative, centroid within 1e-6 of the particle size, normal 1e-6,
    well below the tolerances of the comparison with the C code."""
    shape = particles[name]
    size = shape.volume ** (1 / 3)
    rng = np.random.default_rng(3)
    for depth_fraction in (0.01, 0.1):
        pose = pose_near_the_shell(shape, rng, 0.1, True, depth_fraction)
        coarse, fine = (chord_reference(shape.world(pose), shape.triangles, 0.1, True, samples=n) for n in (800, 1600))
        differences = (abs(coarse[0] / fine[0] - 1), np.abs(coarse[1] - fine[1]).max() / size,
                       np.abs(coarse[2] - fine[2]).max())
        print(f"\nreference, {name} {depth_fraction} deep, 800 vs 1600: V {differences[0]:.1e}, centroid "
              f"{differences[1]:.1e} L, normal {differences[2]:.1e}")
        assert differences[0] < 1e-5 and differences[1] < 1e-6 and differences[2] < 1e-6, differences


@pytest.mark.parametrize("name", ["cube", "icosphere_1280", "rock_40"])
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
    worst, cost, plane_cost = [0.0, 0.0, 0.0], 0.0, math.inf
    for depth_fraction in (0.005, 0.03, 0.2, 0.02, 0.1):
        pose = pose_near_the_shell(shape, rng, radius, drum, depth_fraction)
        fastest = math.inf
        for _ in range(20):   # the fastest of 20 calls (through ctypes; a plane for scale): the machine may be busy
            started = time.perf_counter()
            got = cylinder(cylinder_lib, shape, pose, radius, facets)
            fastest = min(fastest, time.perf_counter() - started)
            started = time.perf_counter()
            cylinder_lib.halfspace(shape, pose, (0.0, 1.0, 0.0), 0.0)
            plane_cost = min(plane_cost, time.perf_counter() - started)
        cost = max(cost, fastest)
        volume, centroid, normal, _ = chord_reference(shape.world(pose), shape.triangles, radius, drum)
        worst[0] = max(worst[0], abs(got["volume"] / volume - 1))
        worst[1] = max(worst[1], np.abs(got["centroid"] - centroid).max() / size)
        worst[2] = max(worst[2], np.abs(got["normal"] - normal).max())
        assert got["normal"][2] == 0.0
    print(f"\n{name} {'inside' if drum else 'outside'} ({facets} facets): worst V {worst[0]:.1e}, "
          f"centroid {worst[1]:.1e} L, normal {worst[2]:.1e}; slowest pose {cost * 1e6:.0f} us a call "
          f"(a plane: {plane_cost * 1e6:.0f} us)")
    assert worst[0] < 1e-4 and worst[1] < 1e-5 and worst[2] < 1e-4, worst


@pytest.mark.parametrize("name,drum", [("cube", True), ("rock_40", False)], ids=["cube-inside", "rock-outside"])
def test_error_follows_the_sagitta_bound(cylinder_lib, particles, name, drum):
    """Sagitta tolerances 1e-2 .. 1e-6 of the bounding radius: the volume error against the exact cylinder
    stays below the bound s * A_cap (s the polygon's largest radial departure from the circle, A_cap the
    area of the cylinder surface inside the particle), and falls with s (the polygon is fixed in space, so
    the error does not average out for one pose). Reference: the chord quadrature."""
    shape = particles[name]
    radius = 0.1 if drum else 0.05
    rng = np.random.default_rng(11)
    for depth_fraction in (0.01, 0.1):
        pose = pose_near_the_shell(shape, rng, radius, drum, depth_fraction)
        volume, _, _, cap_area = chord_reference(shape.world(pose), shape.triangles, radius, drum, samples=1200)
        rows = []
        for tolerance in (1e-2, 1e-3, 1e-4, 1e-5, 1e-6):
            facets = cylinder_lib.lib.shim_cylinder_facets(radius, tolerance * shape.radius)
            sagitta = cylinder_lib.lib.shim_cylinder_sagitta(radius, facets)
            assert sagitta <= tolerance * shape.radius
            got = cylinder(cylinder_lib, shape, pose, radius, facets)
            rows.append((tolerance, facets, abs(got["volume"] - volume), sagitta * cap_area))
        print(f"\n{name} {depth_fraction} deep: " + ", ".join(f"tol {t:.0e} ({n} facets): |dV|/V {e / volume:.1e} "
                                                            f"(bound {b / volume:.1e})" for t, n, e, b in rows))
        for tolerance, facets, error, bound in rows:
            assert error <= bound + 2e-5 * volume, (tolerance, error, bound)   # 2e-5: the reference's own error
        assert rows[-1][2] < 0.05 * rows[0][2]


@pytest.mark.parametrize("facets", [8, 13, 6866, 100003])
def test_edge_crossings_match_all_facets(cylinder_lib, facets):
    """poly_cylinder_edge_crossings, which tries only the five facets about where a segment crosses the corner
    circle, against all the polygon's facets (entry: the largest parameter of the lines it crosses inwards, exit:
    the smallest outwards): segments between random points within a few facets of the boundary, segments through
    corners and nearly tangent to the facets, R = 0.1. The same crossings, each on its facet within its span,
    except where an end or the chord is within 1e-12 R of the boundary (rounding may go either way there)."""
    radius, rng = 0.1, np.random.default_rng(facets)
    step = 2 * math.pi / facets
    h = radius * math.sqrt((step / 2) / math.tan(step / 2))
    corner = h / math.cos(step / 2)
    normals = np.stack([np.cos((np.arange(facets) + 0.5) * step), np.sin((np.arange(facets) + 0.5) * step)], axis=1)
    width = 2 * corner * math.sin(step / 2)
    checked, skipped = 0, 0
    for n in range(3000):
        kind = n % 3
        if kind == 0:   # two random points within a few facet widths (at most a tenth of R) of the boundary
            spread = min(4 * width, 0.1 * radius)
            angle = rng.uniform(0, 2 * math.pi)
            a = (corner + rng.uniform(-1, 1) * spread) * np.array([math.cos(angle), math.sin(angle)])
            b = a + rng.uniform(-1, 1, 2) * 2 * spread
        else:           # through or near a corner, along its facets' directions to within 1e-6 .. 1 rad
            j = int(rng.integers(facets))
            c = corner * np.array([math.cos(j * step), math.sin(j * step)])
            along = (j + 0.5 + (0.5 if kind == 1 else -0.5)) * step + math.pi / 2 + rng.choice([-1, 1]) * 10 ** rng.uniform(-6, 0)
            direction = np.array([math.cos(along), math.sin(along)]) * width * rng.uniform(0.1, 3)
            offset = rng.normal(size=2) * width * 10 ** rng.uniform(-9, -1)
            a, b = c + offset - direction * rng.uniform(0, 1), c + offset + direction * rng.uniform(0, 1)
        d = b - a
        out = (ctypes.c_double * 9)()
        cylinder_lib.lib.shim_cylinder_crossings(radius, facets, (ctypes.c_double * 2)(*a), (ctypes.c_double * 2)(*d), out)
        along_d, at_a = normals @ d, normals @ a
        margin_a, margin_b = (normals @ a).max() - h, (normals @ b).max() - h
        with np.errstate(divide="ignore"):
            t = (h - at_a) / along_d
        t_in = t[along_d < 0].max(initial=-np.inf)
        t_out = t[along_d > 0].min(initial=np.inf)
        expected = []
        if t_in < t_out:
            expected += [(t_in, 1)] if 0 < t_in < 1 else []
            expected += [(t_out, 0)] if 0 < t_out < 1 else []
        chord = (min(t_out, 1) - max(t_in, 0)) * np.linalg.norm(d)
        if min(abs(margin_a), abs(margin_b)) < 1e-12 * radius or (t_in < t_out and abs(chord) < 1e-12 * radius):
            skipped += 1
            continue
        checked += 1
        assert (out[0], out[1]) == (margin_a <= 0, margin_b <= 0), (n, out[:2], margin_a, margin_b)
        assert int(out[2]) == len(expected), (n, list(out), expected)
        for k, (t_expected, enter) in enumerate(expected):
            t_got, facet, got_enter = out[3 + 3 * k], int(out[4 + 3 * k]), int(out[5 + 3 * k])
            point = a + t_got * d
            assert got_enter == enter
            assert abs(normals[facet] @ point - h) < 1e-12 * radius, (n, k, facet)
            angle = math.atan2(point[1], point[0]) % (2 * math.pi)
            offset = (angle - facet * step + math.pi) % (2 * math.pi) - math.pi
            assert -1e-9 < offset < step + 1e-9, (n, k, facet, angle / step)
            assert np.linalg.norm(point - (a + t_expected * d)) < 1e-11 * radius or abs(along_d[facet]) < 1e-3 * np.linalg.norm(d)
    print(f"\n{facets} facets: {checked} segments checked, {skipped} within 1e-12 R of the boundary")
    assert skipped < 0.01 * checked


@pytest.mark.parametrize("facets", [8, 9, 64, 65, 1405, 6866])
def test_triangles_passing_the_axis(cylinder_lib, facets):
    """Triangles with an edge passing 1e-9 .. 0.1 R from the axis, the rest of the triangle away from it (its
    part inside the polygon, and the arc of the polygon through it, span up to half a turn; the triangles of a
    particle larger than the drum, or near a thin pillar's axis), in either winding, flat to nearly vertical:
    the fast path against the clipping, triangle by triangle, drum and pillar. Volume, moments, area and area
    vector within 1e-11 of the whole triangle's (its area times its distance from the axis and its height)."""
    radius, rng = 1.0, np.random.default_rng(facets)
    checked = 0
    for n in range(400):
        foot_angle, offset = rng.uniform(0, 2 * math.pi), radius * 10 ** rng.uniform(-9, -1)
        normal = np.array([math.cos(foot_angle), math.sin(foot_angle)])   # from the axis towards the triangle
        along = np.array([-normal[1], normal[0]])
        foot = offset * normal
        corners = [foot - along * radius * rng.uniform(0.3, 1.5), foot + along * radius * rng.uniform(0.3, 1.5),
                   foot + normal * radius * rng.uniform(0.05, 2.0) + along * radius * rng.uniform(-1, 1)]
        if n % 2:
            corners = corners[::-1]
        height = radius * 10 ** rng.uniform(-1, 3)   # up to 1000 R: nearly vertical triangles
        p = np.array([[c[0], c[1], rng.uniform(-1, 1) * height] for c in corners])
        scale = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0])) * (np.abs(p).max() + radius)
        for drum in (1, 0):
            got = []
            for fast in (1, 0):
                out = (ctypes.c_double * 8)()
                cylinder_lib.lib.shim_cylinder_triangle((ctypes.c_double * 9)(*p.ravel()), radius, facets, drum, fast, out)
                got.append(np.array(out))
            difference = np.abs(got[0] - got[1])
            # volume and area vector ~ area x size, moments ~ area x size^2, area ~ area
            bound = 1e-11 * np.array([scale, scale * height, scale * height, scale * height, scale, scale, scale, scale])
            assert (difference <= bound).all(), (n, drum, difference / bound, got)
            checked += got[1][4] > 0
    print(f"\n{facets} facets: {checked} triangle pieces compared")
    assert checked > 300


def tilted_quaternion(rng):
    """The identity (the shape's faces vertical or horizontal), turned about z, then tipped by 1e-9 .. 0.1 rad
    about a horizontal axis: triangles nearly vertical, which the fast path leaves to the clipping."""
    turn, tip, axis = rng.uniform(0, 2 * math.pi), 10 ** rng.uniform(-9, -1), rng.uniform(0, 2 * math.pi)
    about_z = np.array([math.cos(turn / 2), 0.0, 0.0, math.sin(turn / 2)])
    tipped = np.array([math.cos(tip / 2), math.sin(tip / 2) * math.cos(axis), math.sin(tip / 2) * math.sin(axis), 0.0])
    w1, v1, w2, v2 = tipped[0], tipped[1:], about_z[0], about_z[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


@pytest.mark.parametrize("name,file", [("cube", "cube.stl"), ("schoenhardt", "schoenhardt.stl"),
                                       ("tetrahedron", "tetrahedron.obj"), ("box", "box_1x2x3.off"),
                                       ("rock_10", "rock_10.obj"), ("rock_70", "rock_70.obj"),
                                       ("icosphere_80", "icosphere_80.off"), ("rock_1000", "rock_1000.obj")])
def test_fast_path_matches_the_reference(cylinder_lib, name, file):
    """poly_cylinder_overlap (the corners of the polygon walked along each crossing triangle's piece, its moments
    from its boundary) against poly_cylinder_overlap_reference (each crossing triangle clipped sector by sector,
    the computation before) on 240 poses: random orientations, axis-aligned ones and ones tipped from them by
    1e-9 .. 0.1 rad (vertical and nearly vertical triangles: the fast path's 3D variant); drum and pillar; R = 10 and 3 particle sizes and 0.6 bounding radii (triangles around
    the axis); sagitta 1e-6 and 1e-3; the deepest vertex 1e-4 .. 0.3 or 0.5 .. 1 bounding radii into the wall
    or 1e-3 short of it. Volume and area within 1e-9 relative, centroid 1e-9 of the particle size,
    normal 1e-9, with a floor of 1e-14 R L sqrt(A) for the rounding of coordinates of size R (A the area in the
    wall: a volume of 1e-12 of the particle's is the sum of terms 1e4 times larger; for the normal, 1e-14 R
    sqrt(A) over the length of the area vector); depth and node count equal."""
    shape = cylinder_lib.shape(os.path.join(SHAPES, file), 0.02)
    size = shape.volume ** (1 / 3)
    rng = np.random.default_rng(sum(map(ord, name)))
    worst, overlaps = [0.0] * 4, 0
    for n in range(240):
        kind = n % 4
        q = random_quaternion(rng) if kind < 2 else (np.array([1.0, 0, 0, 0]) if kind == 2 else tilted_quaternion(rng))
        radius = (10 * size, 3 * size, 0.6 * shape.radius)[n // 4 % 3]
        drum = n // 12 % 2 == 0
        facets = cylinder_lib.lib.shim_cylinder_facets(radius, (1e-3 if n % 7 == 0 else 1e-6) * shape.radius)
        into = 10 ** rng.uniform(-4, math.log10(0.3)) if n % 9 else (rng.uniform(0.5, 1.0) if n % 2 else -1e-3)
        centre, q = pose_near_the_shell(shape, rng, radius, drum, into, q)
        axis = (0.013, -0.021)
        centre = centre + np.array([axis[0], axis[1], 0.0])
        fast = cylinder(cylinder_lib, shape, (centre, q), radius, facets, axis)
        reference = cylinder(cylinder_lib, shape, (centre, q), radius, facets, axis, reference=True)
        assert fast["depth"] == pytest.approx(reference["depth"], rel=0, abs=1e-12 * size)
        assert fast["nodes"] == reference["nodes"] and fast["filtered_out"] == reference["filtered_out"]
        if reference["volume"] == 0.0:
            assert fast["volume"] == 0.0 or fast["volume"] < 1e-14 * radius * size * math.sqrt(fast["area"])
            continue
        overlaps += 1
        floor = 1e-14 * radius * math.sqrt(reference["area"])
        errors = (abs(fast["volume"] - reference["volume"]) / (1e-9 * reference["volume"] + floor * size),
                  np.abs(fast["centroid"] - reference["centroid"]).max() * reference["volume"] /
                  (1e-9 * size * reference["volume"] + floor * size * size),
                  np.abs(fast["normal"] - reference["normal"]).max() / (1e-9 + floor / reference["projected_area"]),
                  abs(fast["area"] - reference["area"]) / (1e-9 * reference["area"] + floor))
        worst = [max(w, e) for w, e in zip(worst, errors)]
        assert max(errors) <= 1.0, (n, errors, fast, reference)
    print(f"\n{name}: {overlaps} overlaps, worst difference / tolerance: volume {worst[0]:.2f}, "
          f"centroid {worst[1]:.2f}, normal {worst[2]:.2f}, area {worst[3]:.2f}")
    assert overlaps > 150


# ---------------------------------------------------------------------------------------------
# The wall as a user runs it (decks through liggghts-poly). A drum of radius 0.1 m about the z axis,
# gravity along -y: the bottom of the drum is at y = -0.1.

DRUM = 0.1
WALL = f"fix floor all wall/polyhedral primitive type 2 zcylinder {DRUM} 0.0 0.0\n"


def drum_scene(pose, wall=WALL, gravity="0 -1 0", steps=30000, extra=""):
    """The cube deck of tests/test_walls.py (materials, thermo of f_floor) in the drum, with the cube's y."""
    deck = scene(wall, pose, extra=extra, steps=steps, gravity=gravity)
    return deck.replace("variable x equal x[1]\n", "variable x equal x[1]\nvariable y equal y[1]\n").replace(
        "thermo_style custom step v_x v_z", "thermo_style custom step v_x v_y v_z")


def resting_height():
    """y of the cube's centre when its two lower edges (along z) touch the drum."""
    return -(math.sqrt(DRUM ** 2 - (EDGE / 2) ** 2) - EDGE / 2)


def test_cube_rests_inside_the_drum(run_deck):
    """The cube dropped from 50 um onto the bottom of the drum rests on its two lower edges: the drum
    carries its weight (force on the wall -mg along y, within 1e-4, nothing along x and z beyond 1e-6 mg)
    and the contact, one per particle, stays."""
    result = run_deck(drum_scene(f"0 {resting_height() + 5e-5} 0.01"))
    assert result.returncode == 0, result.output[-3000:]
    table = result.thermo("Step", "v_y", "f_floor[1]", "f_floor[2]", "f_floor[3]", "f_floor[4]")
    weight = DENSITY * EDGE ** 3 * G
    settled = np.array(table["Step"]) >= 10000
    force = [np.array(table[f"f_floor[{k}]"])[settled] for k in (1, 2, 3)]
    sink = resting_height() - np.array(table["v_y"])[settled]
    print(f"\ncube in the drum: wall force / weight = ({force[0].mean() / weight:.1e}, -1 {force[1].mean() / weight + 1:+.1e}, "
          f"{force[2].mean() / weight:.1e}), largest |F_x| / weight {np.abs(force[0]).max() / weight:.1e}, "
          f"edges sunk {sink.mean():.3e} m")
    assert all(c == 1 for c in np.array(table["f_floor[4]"])[settled])
    assert abs(-force[1].mean() / weight - 1) < 1e-4, force[1].mean()
    assert np.abs(force[0]).max() < 1e-6 * weight and np.abs(force[2]).max() < 1e-6 * weight
    assert 0 < sink.mean() < 1e-4


def test_icosphere_impact_inside_the_drum_matches_liggghts_hertz_sphere(run_deck, tmp_path):
    """As check_wall_impact of tests/test_walls.py, on the inside of the drum: an icosphere of 1280 triangles
    (volume-equivalent diameter 20 mm) hits the bottom of the drum at 1 m/s, and LIGGGHTS' sphere of the same
    diameter and density hits `fix wall/gran model hertz tangential history primitive type 2 zcylinder`.
    Contact duration within 2 % and restitution within 1.5 %, the plane test's tolerances."""
    diameter, dt = 0.02, 2e-6
    start = -(DRUM - diameter / 2 - 0.0005)
    materials = (f"fix m1 all property/global youngsModulus peratomtype {YOUNGS} {YOUNGS}\n"
                 f"fix m2 all property/global poissonsRatio peratomtype {POISSON} {POISSON}\n"
                 "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.8 0.8 0.8 0.8\n"
                 "fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5\n")
    variables = "variable y equal y[1]\nvariable vy equal vy[1]\n"
    common = f"thermo_modify format float %.15g\nthermo 1\ntimestep {dt}\nrun 3000\n"
    sphere = run_deck("atom_style granular\natom_modify map array sort 0 0\nboundary f f f\nnewton off\n"
                      "communicate single vel yes\nunits si\nregion box block -0.15 0.15 -0.15 0.15 -0.15 0.15\n"
                      "create_box 2 box\nneighbor 0.002 bin\nneigh_modify delay 0\n" + materials +
                      "pair_style gran model hertz tangential history\npair_coeff * *\n"
                      f"fix wall all wall/gran model hertz tangential history primitive type 2 zcylinder {DRUM} 0 0\n"
                      f"create_atoms 1 single 0 {start} 0\nset atom 1 diameter {diameter} density {DENSITY}\n"
                      "velocity all set 0 -1 0\nfix integrate all nve/sphere\n" +
                      variables + "thermo_style custom step v_y v_vy\n" + common, workdir=tmp_path / "sphere")
    assert sphere.returncode == 0, sphere.output[-3000:]
    shape = run_deck(decks.header(boundary="f f f", lo=-0.15, hi=0.15, ntypes=2) +
                     "neighbor 0.002 bin\nneigh_modify delay 0\n" + materials +
                     decks.template("ball", "icosphere_1280.off", scale=diameter) +
                     "pair_style polyhedral/volumetric\npair_coeff * *\n" + WALL +
                     f"create_polyhedron ball 0 {start} 0 quat 0.9 0.3 -0.2 0.25 vel 0 -1 0\n"
                     "fix integrate all nve/polyhedron\n" +
                     variables + "thermo_style custom step v_y v_vy f_floor[4]\n" + common, workdir=tmp_path / "shape")
    assert shape.returncode == 0, shape.output[-3000:]
    a = sphere.thermo("Step", "v_y", "v_vy")
    b = shape.thermo("Step", "v_y", "v_vy", "f_floor[4]")
    sphere_steps = sum(1 for y in a["v_y"][1:] if y < -(DRUM - diameter / 2))
    shape_steps = sum(1 for c in b["f_floor[4]"][1:] if c > 0)
    shape_e, sphere_e = b["v_vy"][-1] / -b["v_vy"][0], a["v_vy"][-1] / -a["v_vy"][0]
    print(f"\ndrum impact: contact {shape_steps} steps (icosphere) vs {sphere_steps} (LIGGGHTS sphere), "
          f"restitution {shape_e:.4f} vs {sphere_e:.4f}")
    assert sphere_steps > 300 and a["v_y"][-1] > -(DRUM - diameter / 2) and b["f_floor[4]"][-1] == 0
    assert abs(shape_steps / sphere_steps - 1) < 0.02, (shape_steps, sphere_steps)
    assert abs(shape_e / sphere_e - 1) < 0.015, (shape_e, sphere_e)


def turned_gravity(angle, ramp_steps):
    """fix gravity turned quasi-statically over ramp_steps from -y to `angle` degrees towards +x, then held."""
    tilt = math.radians(angle)
    return ("unfix gravity\n"
            f"variable gx equal sin({angle}*PI/180*ramp(0,1))\nvariable gy equal -cos({angle}*PI/180*ramp(0,1))\n"
            f"fix gravity all gravity {G} vector v_gx v_gy 0\nrun {ramp_steps}\nunfix gravity\n"
            f"fix gravity all gravity {G} vector {math.sin(tilt)!r} {-math.cos(tilt)!r} 0\n")


def test_drum_contact_history_survives_a_restart(run_deck, tmp_path):
    """The cube in the drum, gravity turned 20 degrees (below the friction angle: held by the tangential
    spring), restarted mid-hold: the resumed run follows the unbroken one to 1e-12 m."""
    setup = drum_scene(f"0 {resting_height() + 5e-5} 0", steps=5000) + turned_gravity(20.0, 10000)
    unbroken = run_deck(setup + "run 5000\n", workdir=tmp_path / "unbroken")
    first = run_deck(setup + "write_restart half.restart\n", workdir=tmp_path / "first")
    assert unbroken.returncode == 0 and first.returncode == 0, unbroken.output[-2000:] + first.output[-2000:]
    body = setup[setup.index("neighbor"):setup.index("create_polyhedron")]
    body += setup[setup.index("fix integrate"):setup.index("fix gravity")]
    body += setup[setup.index(WALL):setup.index("run 5000\n")]
    tilt = math.radians(20.0)
    resumed = ("atom_modify map array sort 0 0\nread_restart ../first/half.restart\nnewton off\n"
               "communicate single vel yes\n" + body +
               f"fix gravity all gravity {G} vector {math.sin(tilt)!r} {-math.cos(tilt)!r} 0\nrun 5000\n")
    second = run_deck(resumed, workdir=tmp_path / "second")
    assert second.returncode == 0, second.output[-3000:]
    a, b = unbroken.thermo("Step", "v_x", "f_floor[4]"), second.thermo("Step", "v_x", "f_floor[4]")
    assert a["Step"][-len(b["Step"]):] == b["Step"] and all(c == 1 for c in b["f_floor[4]"])
    difference = np.abs(np.array(a["v_x"][-len(b["Step"]):]) - np.array(b["v_x"])).max()
    print(f"\nrestart in the drum: largest x difference {difference:.1e} m (cube at x = {b['v_x'][-1]:.6f} m)")
    assert difference < 1e-12


def test_drum_contact_crosses_ranks(run_deck, tmp_path):
    """Gravity turned to 35 degrees (above the friction angle) from -y towards +x: the cube slides up the
    drum from x = -5 mm across the boundary x = 0 between two ranks (processors 2 1 1) and follows the
    single-rank run to round-off."""
    distance = -resting_height() - 5e-5
    turn = math.asin(-0.005 / distance)   # the resting pose turned about the axis, to x = -5 mm
    pose = (f"{-0.005!r} {-distance * math.cos(turn)!r} 0 quat {math.cos(turn / 2)!r} 0 0 {math.sin(turn / 2)!r}")
    deck = drum_scene(pose, steps=2000) + turned_gravity(35.0, 2000) + "run 10000\n"
    check_crosses_ranks(run_deck, tmp_path, deck, "drum contact")


@pytest.mark.parametrize("wall,message", [
    ("primitive type 2 zcylinder 0.1 0.0", "expected 'primitive type T zcylinder R CX CY'"),
    ("primitive type 2 zcylinder 0.0 0.0 0.0", "zcylinder radius R must be positive"),
    ("primitive type 2 zcylinder -0.1 0.0 0.0", "zcylinder radius R must be positive"),
    ("sagitta 0 primitive type 2 zcylinder 0.1 0.0 0.0", "sagitta must be between 0 and 1"),
    ("primitive type 2 ycylinder 0.1 0.0 0.0", "unknown primitive 'ycylinder' (xplane, yplane, zplane and zcylinder"),
])
def test_bad_cylinder_input_is_a_clear_error(run_deck, wall, message):
    result = run_deck(drum_scene(f"0 {resting_height()} 0", wall=f"fix floor all wall/polyhedral {wall}\n", steps=10))
    assert result.returncode != 0
    assert any(message in line for line in result.error_lines()), result.output[-2000:]
