"""Overlap geometry core (src/poly_overlap.c, poly_overlap_impl.h) against an
independent reference (tests/overlap_reference.py: signed tetrahedron fans and
convex clipping) and closed forms.

The C sources are built once per session into a shared library (gcc -O2 -fPIC)
together with a small shim over the public API (SHIM_SOURCE), called through
ctypes with plain arrays only. Run with Debian's python3:

    /usr/bin/python3 -m pytest tests/test_overlap_geometry.py -q

Tolerances (L = cube root of the smaller particle volume, V_s = its volume; "d" double, "f" single,
"m" mixed: single geometry, double sums; held to the single-precision tolerances):
  random poses vs the reference, V_ref > 1e-3 V_s: |V - V_ref| / V_ref and |c - c_ref| / L below
      1e-10 (d) and 1e-4 (f); every pose, grazing ones (1e-6..1e-3 V_s) included:
      |V - V_ref| / V_s below 1e-12 (d) and 1e-6 (f); num_inconsistent == 0
  separated poses (reference V exactly 0): V, depth, area and normal exactly 0
  axis-aligned boxes vs closed forms (V, centroid, normal by eq. 4.19, depth, area): 1e-10 (d), 1e-4 (f)
  cube pressed into a face of a box 120 times its size: normal and depth 1e-12 (d), 1e-4 (f, m);
      V and centroid 1e-10 (d), 1e-4 (f, m)
  symmetry A,B vs B,A (double): V 1e-12 relative, normal(A,B) = -normal(B,A) to 1e-9, depth 1e-12 L;
  filter on/off: V, normal, depth to 1e-12; both particles moved 1e3 L: V 1e-9 relative, centroid 1e-9 L
      (relative to max(V, 1e-3 V_s))
  degenerate configurations: finite, num_inconsistent == 0, V within 1e-12 L^3 of the exact value (d) and
      1e-4 L^3 (f), and (d) |V(perturbed) - V| <= 1e-9 L^3 for B moved by +-1e-12 along each axis or
      turned by +-1e-12 rad
The worst errors measured are printed at the end of the session.
"""
import ctypes
import math
import os
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import overlap_reference as ref  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "examples", "shapes")
SOURCES = [os.path.join(ROOT, "src", name)
           for name in ("poly_overlap.c", "poly_shape.c", "poly_mesh_read.c", "poly_mesh_shell.c",
                        "poly_convex.c")]

# ---------------------------------------------------------------------------------------------
# A small C shim over the public API (poly_shape_load, views, workspaces, poly_overlap_d/f),
# so that ctypes sees only plain arrays and no struct layout has to be mirrored here.

SHIM_SOURCE = r"""
#include <stdlib.h>
#include "poly_contact.h"
#include "poly_overlap.h"
#include "poly_halfspace.h"
#include "poly_mesh_shell.h"

typedef struct shim_shape {
  poly_shape shape;
  poly_shape_view_d view_d;
  poly_shape_view_f view_f;
} shim_shape;

static poly_overlap_workspace_d workspace_d;
static poly_overlap_workspace_f workspace_f;

int shim_init(int max_vertices, int max_triangles)
{
  return poly_overlap_workspace_create_d(&workspace_d, max_vertices, max_triangles) ||
         poly_overlap_workspace_create_f(&workspace_f, max_vertices, max_triangles);
}

void *shim_load(const char *path, double scale, char *message, size_t message_size)
{
  shim_shape *s = (shim_shape *)calloc(1, sizeof *s);
  if (!s) return 0;
  if (poly_shape_load(path, scale, &s->shape, message, message_size) != POLY_OK ||
      poly_shape_view_make_f(&s->shape, &s->view_f) != 0) {
    free(s);
    return 0;
  }
  s->view_d = poly_shape_view_of(&s->shape);
  return s;
}

/* counts: vertices, triangles; properties: volume, bounding radius, centre of mass (3),
 * principal axes (9, row-major). */
void shim_describe(const void *handle, int *counts, double *properties)
{
  const poly_shape *shape = &((const shim_shape *)handle)->shape;
  counts[0] = shape->num_vertices;
  counts[1] = shape->num_triangles;
  properties[0] = shape->volume;
  properties[1] = shape->bounding_radius;
  for (int k = 0; k < 3; k++) properties[2 + k] = shape->centre_of_mass[k];
  for (int k = 0; k < 9; k++) properties[5 + k] = shape->principal_axes[k];
}

void shim_mesh(const void *handle, double *vertices, int *triangles)
{
  const poly_shape *shape = &((const shim_shape *)handle)->shape;
  for (int i = 0; i < 3 * shape->num_vertices; i++) vertices[i] = shape->vertices[i];
  for (int i = 0; i < 3 * shape->num_triangles; i++) triangles[i] = shape->triangles[i];
}

static void shim_write_result(const poly_overlap_result *r, double *out)
{
  out[0] = r->volume;
  for (int k = 0; k < 3; k++) { out[1 + k] = r->centroid[k]; out[4 + k] = r->normal[k]; }
  out[7] = r->depth;
  out[8] = r->area;
  out[9] = r->num_nodes;
  out[10] = r->num_inconsistent;
  out[11] = r->filtered_out;
  out[12] = r->projected_area;
}

/* The depth the pair style's contact law takes (poly_contact_pair_depth). */
double shim_pair_depth(double volume, double depth, double projected_area)
{
  return poly_contact_pair_depth(volume, depth, projected_area);
}

/* poses: position (3) and quaternion (4) each; out: volume, centroid (3), normal (3), depth,
 * area, num_nodes, num_inconsistent, filtered_out, projected_area. */
void shim_overlap(const void *a, const double *pose_a, const void *b, const double *pose_b, int single,
                  int use_filter, double *out)
{
  poly_pose pa, pb;
  for (int k = 0; k < 3; k++) { pa.position[k] = pose_a[k]; pb.position[k] = pose_b[k]; }
  for (int k = 0; k < 4; k++) { pa.quaternion[k] = pose_a[3 + k]; pb.quaternion[k] = pose_b[3 + k]; }
  const shim_shape *sa = (const shim_shape *)a, *sb = (const shim_shape *)b;
  poly_overlap_result r;
  if (single == 2) {
    workspace_f.use_filter = use_filter;
    poly_overlap_m(&sa->view_f, &pa, &sb->view_f, &pb, &workspace_f, &r);
  } else if (single) {
    workspace_f.use_filter = use_filter;
    poly_overlap_f(&sa->view_f, &pa, &sb->view_f, &pb, &workspace_f, &r);
  } else {
    workspace_d.use_filter = use_filter;
    poly_overlap_d(&sa->view_d, &pa, &sb->view_d, &pb, &workspace_d, &r);
  }
  shim_write_result(&r, out);
}

/* The shape at `pose` against the shell of thickness h behind a triangle soup (9 doubles per triangle),
 * as fix wall/polyhedral's mesh walls: out as shim_overlap, out[12] the pieces, out[13] the projected
 * area. Returns 0, or -1 if the shell cannot be built. */
int shim_mesh_wall(const void *a, const double *pose, const double *corners, int num_triangles, double thickness,
                   double *out)
{
  poly_mesh_shell shell;
  char message[256];
  if (poly_mesh_shell_build(corners, num_triangles, thickness, 1e-8, &shell, message, sizeof message) != 0) return -1;
  poly_pose pa;
  for (int k = 0; k < 3; k++) pa.position[k] = pose[k];
  for (int k = 0; k < 4; k++) pa.quaternion[k] = pose[3 + k];
  poly_overlap_result *pieces = (poly_overlap_result *)malloc(sizeof(poly_overlap_result) * num_triangles);
  int *first = (int *)malloc(sizeof(int) * num_triangles), *count = (int *)malloc(sizeof(int) * num_triangles);
  int used = 0, capacity = 1024, num_pieces = 0;
  double *nodes = (double *)malloc(sizeof(double) * 3 * capacity);
  workspace_d.use_filter = 1;
  workspace_d.want_nodes = 1;  /* as the wall: the clipping path's corners too */
  for (int t = 0; t < num_triangles; t++) {
    double triangle[3][3];
    for (int c = 0; c < 9; c++) triangle[c / 3][c % 3] = corners[9 * t + c];
    poly_mesh_prism prism;
    if (poly_mesh_shell_prism(&shell, t, triangle, &prism) != 0) continue;
    const poly_shape_view_d *prism_view = poly_mesh_prism_view(&prism, &((const shim_shape *)a)->view_d);
    poly_pose pb = {{prism.origin[0], prism.origin[1], prism.origin[2]}, {1.0, 0.0, 0.0, 0.0}};
    poly_overlap_result r;
    poly_overlap_d(&((const shim_shape *)a)->view_d, &pa, prism_view, &pb, &workspace_d, &r);
    if (!(r.volume > 0.0)) continue;
    while (used + workspace_d.num_points > capacity) {
      capacity *= 2;
      nodes = (double *)realloc(nodes, sizeof(double) * 3 * capacity);
    }
    pieces[num_pieces] = r;
    first[num_pieces] = used;
    count[num_pieces] = poly_overlap_nodes_d(&workspace_d, &pa, nodes + 3 * used, capacity - used);
    if (count[num_pieces] > 0) used += count[num_pieces];
    num_pieces++;
  }
  poly_overlap_result contact;
  poly_mesh_contact_combine(pieces, nodes, first, count, num_pieces, &contact);
  workspace_d.want_nodes = 0;
  shim_write_result(&contact, out);
  out[12] = num_pieces;
  out[13] = contact.projected_area;
  free(pieces);
  free(first);
  free(count);
  free(nodes);
  poly_mesh_shell_free(&shell);
  return 0;
}

/* The shape at `pose` against the wall solid {x : normal.x < offset}; out as shim_overlap. */
void shim_halfspace(const void *a, const double *pose, const double *normal, double offset, double *out)
{
  double rotation[9];
  poly_quat_to_matrix(pose + 3, rotation);
  poly_overlap_result r;
  poly_halfspace_overlap(&((const shim_shape *)a)->view_d, rotation, pose, normal, offset, 1, &r);
  shim_write_result(&r, out);
}
"""

DOUBLES = ctypes.POINTER(ctypes.c_double)


class Result:
    """poly_overlap_result as read back from the shim."""

    def __init__(self, out):
        self.volume = out[0]
        self.centroid = list(out[1:4])
        self.normal = list(out[4:7])
        self.depth, self.area = out[7], out[8]
        self.num_nodes, self.num_inconsistent, self.filtered_out = int(out[9]), int(out[10]), int(out[11])
        self.projected_area = out[12]


class Library:
    """The overlap core (built with the shim) loaded through ctypes."""

    MAX_VERTICES, MAX_TRIANGLES = 700, 1400

    def __init__(self, path):
        lib = self.lib = ctypes.CDLL(path)
        lib.shim_init.argtypes = [ctypes.c_int, ctypes.c_int]
        lib.shim_load.argtypes = [ctypes.c_char_p, ctypes.c_double, ctypes.c_char_p, ctypes.c_size_t]
        lib.shim_load.restype = ctypes.c_void_p
        lib.shim_describe.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_int), DOUBLES]
        lib.shim_mesh.argtypes = [ctypes.c_void_p, DOUBLES, ctypes.POINTER(ctypes.c_int)]
        lib.shim_overlap.argtypes = [ctypes.c_void_p, DOUBLES, ctypes.c_void_p, DOUBLES, ctypes.c_int, ctypes.c_int,
                                     DOUBLES]
        lib.shim_overlap.restype = None
        lib.shim_halfspace.argtypes = [ctypes.c_void_p, DOUBLES, DOUBLES, ctypes.c_double, DOUBLES]
        lib.shim_halfspace.restype = None
        lib.shim_mesh_wall.argtypes = [ctypes.c_void_p, DOUBLES, DOUBLES, ctypes.c_int, ctypes.c_double, DOUBLES]
        lib.shim_mesh_wall.restype = ctypes.c_int
        lib.shim_pair_depth.argtypes = [ctypes.c_double] * 3
        lib.shim_pair_depth.restype = ctypes.c_double
        assert lib.shim_init(self.MAX_VERTICES, self.MAX_TRIANGLES) == 0
        self.shapes = {}

    def shape(self, path, scale=1.0):
        key = (path, scale)
        if key not in self.shapes:
            self.shapes[key] = LoadedShape(self.lib, path, scale)
        return self.shapes[key]

    def overlap(self, a, pose_a, b, pose_b, precision="d", use_filter=1):
        poses = [(ctypes.c_double * 7)(*[float(x) for x in list(p[0]) + list(p[1])]) for p in (pose_a, pose_b)]
        out = (ctypes.c_double * 13)()
        self.lib.shim_overlap(a.handle, poses[0], b.handle, poses[1], "dfm".index(precision), use_filter, out)
        return Result(list(out))

    def pair_depth(self, result):
        """The depth the pair style's law takes for this overlap (poly_contact_pair_depth)."""
        return self.lib.shim_pair_depth(result.volume, result.depth, result.projected_area)

    def mesh_wall(self, a, pose, triangles, thickness):
        """a at pose against the shell of thickness `thickness` behind the triangles ((3, 3) arrays)."""
        corners = np.asarray(triangles, dtype=float).reshape(-1)
        out = (ctypes.c_double * 14)()
        status = self.lib.shim_mesh_wall(a.handle, (ctypes.c_double * 7)(*[float(x) for x in list(pose[0]) + list(pose[1])]),
                                         (ctypes.c_double * len(corners))(*corners), len(corners) // 9,
                                         float(thickness), out)
        assert status == 0
        result = Result(list(out))
        result.pieces, result.projected_area = int(out[12]), out[13]
        return result

    def halfspace(self, a, pose, normal, offset):
        """a at pose against the wall solid {x : normal.x < offset}."""
        out = (ctypes.c_double * 13)()
        self.lib.shim_halfspace(a.handle, (ctypes.c_double * 7)(*[float(x) for x in list(pose[0]) + list(pose[1])]),
                                (ctypes.c_double * 3)(*[float(x) for x in normal]), float(offset), out)
        return Result(list(out))


class LoadedShape:
    def __init__(self, lib, path, scale):
        self.name = os.path.splitext(os.path.basename(path))[0]
        message = ctypes.create_string_buffer(512)
        self.handle = lib.shim_load(path.encode(), scale, message, len(message))
        assert self.handle, message.value.decode()
        counts, properties = (ctypes.c_int * 2)(), (ctypes.c_double * 14)()
        lib.shim_describe(self.handle, counts, properties)
        num_vertices, num_triangles = counts
        assert num_vertices <= Library.MAX_VERTICES and num_triangles <= Library.MAX_TRIANGLES
        vertices, triangles = (ctypes.c_double * (3 * num_vertices))(), (ctypes.c_int * (3 * num_triangles))()
        lib.shim_mesh(self.handle, vertices, triangles)
        self.vertices = np.array(vertices[:]).reshape(-1, 3)
        self.triangles = np.array(triangles[:]).reshape(-1, 3)
        self.volume, self.radius = properties[0], properties[1]
        self.centre_of_mass = np.array(properties[2:5])
        self.principal_axes = np.array(properties[5:14]).reshape(3, 3)

    def world(self, pose):
        return ref.to_world(self.vertices, *pose)


# ---------------------------------------------------------------------------------------------
# fixtures and helpers

class ErrorLog:
    """Worst error per (category, precision), printed at the end of the session."""

    def __init__(self):
        self.worst = {}

    def add(self, category, precision, value):
        key = (category, precision)
        self.worst[key] = max(self.worst.get(key, 0.0), float(value))


@pytest.fixture(scope="session")
def errors(request):
    log = ErrorLog()
    yield log
    reporter = request.config.pluginmanager.getplugin("terminalreporter")
    capture = request.config.pluginmanager.getplugin("capturemanager")
    if reporter and capture and log.worst:
        with capture.global_and_fixture_disabled():
            reporter.write_line("")
            reporter.write_line("overlap geometry: worst errors measured (precision d = double, f = single, m = mixed)")
            for (category, precision), value in sorted(log.worst.items()):
                reporter.write_line(f"  {category:<44s} {precision}  {value:.2e}")


@pytest.fixture(scope="session")
def overlap_lib(tmp_path_factory):
    directory = tmp_path_factory.mktemp("overlap_lib")
    shim = directory / "overlap_shim.c"
    shim.write_text(SHIM_SOURCE)
    library = directory / "libpoly_overlap_test.so"
    command = (["gcc", "-std=c11", "-O2", "-fPIC", "-shared", "-Wall", "-Wextra", "-Werror",
                "-I" + os.path.join(ROOT, "src")] + SOURCES + [str(shim), "-lm", "-o", str(library)])
    built = subprocess.run(command, capture_output=True, text=True)
    assert built.returncode == 0, " ".join(command) + "\n" + built.stderr
    return Library(str(library))


L_SHAPE_OBJ = """# L-shaped prism: the L polygon (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), extruded over z in [0,1]
v 0 0 0
v 2 0 0
v 2 1 0
v 1 1 0
v 1 2 0
v 0 2 0
v 0 0 1
v 2 0 1
v 2 1 1
v 1 1 1
v 1 2 1
v 0 2 1
f 7 8 9
f 7 9 10
f 7 10 11
f 7 11 12
f 1 3 2
f 1 4 3
f 1 5 4
f 1 6 5
f 1 2 8
f 1 8 7
f 2 3 9
f 2 9 8
f 3 4 10
f 3 10 9
f 4 5 11
f 4 11 10
f 5 6 12
f 5 12 11
f 6 1 7
f 6 7 12
"""


@pytest.fixture(scope="session")
def shapes(overlap_lib, tmp_path_factory):
    directory = tmp_path_factory.mktemp("overlap_shapes")
    l_path = directory / "l_shape.obj"
    l_path.write_text(L_SHAPE_OBJ)
    out = {}
    for name in ("cube.stl", "tetrahedron.obj", "box_1x2x3.off", "schoenhardt.stl", "icosphere_80.off",
                 "icosphere_320.off", "rock_10.obj", "rock_40.obj", "rock_70.obj"):
        shape = overlap_lib.shape(os.path.join(SHAPES, name))
        out[shape.name] = shape
    out["l_shape"] = overlap_lib.shape(str(l_path))
    out["big_box"] = overlap_lib.shape(os.path.join(SHAPES, "box_1x2x3.off"), 40.0)
    out["small_cube"] = overlap_lib.shape(os.path.join(SHAPES, "cube.stl"), 0.25)
    return out


IDENTITY = (1.0, 0.0, 0.0, 0.0)


def random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def random_direction(rng):
    d = rng.normal(size=3)
    return d / np.linalg.norm(d)


def size_of(a, b):
    return min(a.volume, b.volume) ** (1.0 / 3.0)


def reference(a, pose_a, b, pose_b):
    return ref.intersection(a.world(pose_a), a.triangles, b.world(pose_b), b.triangles)


def overlapping_poses(a, b, count, seed, tiny_fraction=1e-3):
    """Random poses (both orientations random, B's centre at a random distance along a random
    direction) whose reference overlap exceeds tiny_fraction of the smaller volume; returns
    [(pose_a, pose_b, V_ref, c_ref)]. Also returns the poses with smaller, nonzero overlaps."""
    rng = np.random.default_rng(seed)
    small = min(a.volume, b.volume)
    found, tiny = [], []
    for _ in range(50 * count):
        pose_a = (rng.uniform(-0.5, 0.5, 3), random_quaternion(rng))
        distance = rng.uniform(0.05, 1.0) * (a.radius + b.radius)
        pose_b = (pose_a[0] + distance * random_direction(rng), random_quaternion(rng))
        volume, centroid = reference(a, pose_a, b, pose_b)
        if volume > tiny_fraction * small:
            found.append((pose_a, pose_b, volume, centroid))
        elif volume > 0.0:
            tiny.append((pose_a, pose_b, volume, centroid))
        if len(found) == count:
            return found, tiny
    raise AssertionError(f"{a.name}-{b.name}: only {len(found)} overlapping poses found")


def assert_finite(result, what):
    values = [result.volume, result.depth, result.area] + list(result.centroid) + list(result.normal)
    assert all(math.isfinite(v) for v in values), f"{what}: non-finite result {values}"


def quaternion_about(axis, angle):
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    return np.concatenate([[math.cos(0.5 * angle)], math.sin(0.5 * angle) * axis])


def quaternion_product(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def matrix_quaternion(m):
    """Unit quaternion of a proper rotation matrix (Shepperd: divide by the largest component)."""
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    k = int(np.argmax([trace, m[0, 0], m[1, 1], m[2, 2]]))
    if k == 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif k == 1:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif k == 2:
        s = 2.0 * math.sqrt(1.0 - m[0, 0] + m[1, 1] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 - m[0, 0] - m[1, 1] + m[2, 2])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def file_frame_pose(shape):
    """The pose that puts a shape's vertices back at their file coordinates."""
    return shape.centre_of_mass, matrix_quaternion(shape.principal_axes)


# ---------------------------------------------------------------------------------------------
# the reference itself

def test_reference_matches_closed_forms(shapes):
    """The fan/clipping reference reproduces box intersections and single-mesh mass
    properties, with apexes inside and outside (negative tetrahedra)."""
    cube, box = shapes["cube"], shapes["box_1x2x3"]
    rng = np.random.default_rng(7)
    for _ in range(5):
        shift = rng.uniform(-1.2, 1.2, 3)
        va, vb = cube.vertices, box.vertices + shift
        volume, centroid = ref.intersection(va, cube.triangles, vb, box.triangles,
                                            apex_a=rng.uniform(-3, 3, 3), apex_b=rng.uniform(-3, 3, 3))
        exact, exact_centroid = ref.box_intersection(va.min(0), va.max(0), vb.min(0), vb.max(0))
        assert abs(volume - exact) < 1e-13
        if exact > 0:
            assert np.abs(centroid - exact_centroid).max() < 1e-12
    for name in ("l_shape", "schoenhardt", "rock_70"):
        shape = shapes[name]
        volume, centroid = ref.intersection(shape.vertices, shape.triangles, 5.0 * box.vertices, box.triangles,
                                            apex_a=[2.5, -1.7, 0.9])
        assert abs(volume - shape.volume) < 1e-13 * shape.volume
        assert np.abs(centroid).max() < 1e-13  # body frame: centre of mass at the origin
        assert abs(ref.mesh_mass(shape.vertices, shape.triangles)[0] - shape.volume) < 1e-13 * shape.volume


def test_l_shape_and_file_frame_pose(shapes):
    """The L-shaped prism loads with volume 3 and file_frame_pose puts it back in its file frame."""
    l_shape = shapes["l_shape"]
    assert abs(l_shape.volume - 3.0) < 1e-13
    world = l_shape.world(file_frame_pose(l_shape))
    assert np.abs(world.min(0) - [0, 0, 0]).max() < 1e-13 and np.abs(world.max(0) - [2, 2, 1]).max() < 1e-13


# ---------------------------------------------------------------------------------------------
# exact geometry against the reference, random poses

PAIRS = [("cube", "cube"), ("box_1x2x3", "cube"), ("box_1x2x3", "box_1x2x3"), ("tetrahedron", "tetrahedron"),
         ("tetrahedron", "cube"), ("schoenhardt", "schoenhardt"), ("rock_70", "rock_40"), ("l_shape", "l_shape"),
         ("l_shape", "rock_40"), ("schoenhardt", "l_shape")]
POSES_PER_PAIR = 8
GRAZING_PER_PAIR = 4
TOLERANCE = {"d": 1e-10, "f": 1e-4, "m": 1e-4}           # relative V, and centroid / L, for V_ref > 1e-3 V_s
TINY_TOLERANCE = {"d": 1e-12, "f": 1e-6, "m": 1e-6}      # |V - V_ref| / V_s for every pose
_POSE_CACHE = {}


def grazing_poses(lib, a, b, count, seed):
    """Random orientations and directions; the centre distance bisected (on the double
    overlap) to an overlap of 1e-6..1e-3 of the smaller volume, as in a packed bed."""
    rng = np.random.default_rng(seed)
    small = min(a.volume, b.volume)
    out = []
    while len(out) < count:
        qa, qb, direction = random_quaternion(rng), random_quaternion(rng), random_direction(rng)
        target = small * 10.0 ** rng.uniform(-6, -3)
        near, far = 0.0, a.radius + b.radius
        for _ in range(60):
            middle = 0.5 * (near + far)
            if lib.overlap(a, ((0, 0, 0), qa), b, (middle * direction, qb)).volume > target:
                near = middle
            else:
                far = middle
        pose_a, pose_b = ((0.0, 0.0, 0.0), qa), (near * direction, qb)
        volume, centroid = reference(a, pose_a, b, pose_b)
        if volume > 0:
            out.append((pose_a, pose_b, volume, centroid))
    return out


def pair_poses(lib, shapes, names):
    if names not in _POSE_CACHE:
        a, b = shapes[names[0]], shapes[names[1]]
        seed = sum(map(ord, names[0] + names[1]))
        found, tiny = overlapping_poses(a, b, POSES_PER_PAIR, seed)
        grazing = grazing_poses(lib, a, b, GRAZING_PER_PAIR, seed + 1)
        _POSE_CACHE[names] = (found, tiny + grazing)
    return _POSE_CACHE[names]


@pytest.mark.parametrize("precision", ["d", "f"])
@pytest.mark.parametrize("names", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_volume_and_centroid_match_reference(overlap_lib, shapes, errors, names, precision):
    a, b = shapes[names[0]], shapes[names[1]]
    found, small_overlaps = pair_poses(overlap_lib, shapes, names)
    size, small = size_of(a, b), min(a.volume, b.volume)
    worst_volume = worst_centroid = worst_absolute = 0.0
    for pose_a, pose_b, volume, centroid in found:
        result = overlap_lib.overlap(a, pose_a, b, pose_b, precision)
        assert_finite(result, names)
        assert result.num_inconsistent == 0
        worst_volume = max(worst_volume, abs(result.volume - volume) / volume)
        worst_centroid = max(worst_centroid, np.abs(np.array(result.centroid[:]) - centroid).max() / size)
    for pose_a, pose_b, volume, centroid in found + small_overlaps:
        result = overlap_lib.overlap(a, pose_a, b, pose_b, precision)
        assert result.num_inconsistent == 0
        worst_absolute = max(worst_absolute, abs(result.volume - volume) / small)
    errors.add("V relative, V > 1e-3 V_s", precision, worst_volume)
    errors.add("centroid / L, V > 1e-3 V_s", precision, worst_centroid)
    errors.add("|V - V_ref| / V_s, all overlaps", precision, worst_absolute)
    assert worst_volume < TOLERANCE[precision]
    assert worst_centroid < TOLERANCE[precision]
    assert worst_absolute < TINY_TOLERANCE[precision]


@pytest.mark.parametrize("names", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_symmetry_filter_and_translation(overlap_lib, shapes, errors, names):
    """V(A,B) = V(B,A), normal(A,B) = -normal(B,A), depth(A,B) = depth(B,A); the triangle
    filter changes nothing; moving both particles 1e3 sizes away changes nothing (double)."""
    a, b = shapes[names[0]], shapes[names[1]]
    found, small_overlaps = pair_poses(overlap_lib, shapes, names)
    size, small = size_of(a, b), min(a.volume, b.volume)
    rng = np.random.default_rng(11)
    worst = {"symmetry V": 0.0, "symmetry normal": 0.0, "symmetry depth": 0.0, "filter on/off V": 0.0,
             "filter on/off normal, depth": 0.0, "translation 1e3 V": 0.0, "translation 1e3 centroid": 0.0}
    for pose_a, pose_b, volume, _ in found + small_overlaps:
        # Relative to V, or to 1e-3 V_s for the small overlaps (absolute there).
        volume = max(volume, 1e-3 * small)
        ab = overlap_lib.overlap(a, pose_a, b, pose_b)
        ba = overlap_lib.overlap(b, pose_b, a, pose_a)
        unfiltered = overlap_lib.overlap(a, pose_a, b, pose_b, use_filter=0)
        worst["symmetry V"] = max(worst["symmetry V"], abs(ab.volume - ba.volume) / volume)
        worst["symmetry normal"] = max(worst["symmetry normal"],
                                       np.abs(np.array(ab.normal[:]) + np.array(ba.normal[:])).max())
        worst["symmetry depth"] = max(worst["symmetry depth"], abs(ab.depth - ba.depth) / size)
        worst["filter on/off V"] = max(worst["filter on/off V"], abs(ab.volume - unfiltered.volume) / volume)
        worst["filter on/off normal, depth"] = max(
            worst["filter on/off normal, depth"], np.abs(np.array(ab.normal[:]) - unfiltered.normal[:]).max(),
            abs(ab.depth - unfiltered.depth) / size)
        shift = 1e3 * size * random_direction(rng)
        moved = overlap_lib.overlap(a, (pose_a[0] + shift, pose_a[1]), b, (pose_b[0] + shift, pose_b[1]))
        worst["translation 1e3 V"] = max(worst["translation 1e3 V"], abs(moved.volume - ab.volume) / volume)
        worst["translation 1e3 centroid"] = max(
            worst["translation 1e3 centroid"], np.abs(np.array(moved.centroid[:]) - shift - ab.centroid[:]).max() / size)
    for key, value in worst.items():
        errors.add(key, "d", value)
    assert worst["symmetry V"] < 1e-12, worst
    assert worst["symmetry normal"] < 1e-9, worst
    assert worst["symmetry depth"] < 1e-12
    assert worst["filter on/off V"] < 1e-12
    assert worst["filter on/off normal, depth"] < 1e-12
    assert worst["translation 1e3 V"] < 1e-9
    assert worst["translation 1e3 centroid"] < 1e-9


@pytest.mark.parametrize("precision", ["d", "f"])
@pytest.mark.parametrize("names", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_separated_poses_give_zero(overlap_lib, shapes, names, precision):
    """Poses whose bounding spheres overlap but whose reference volume is exactly zero."""
    a, b = shapes[names[0]], shapes[names[1]]
    rng = np.random.default_rng(sum(map(ord, names[0] + names[1])) + 2)
    checked = 0
    while checked < 4:
        pose_a = (rng.uniform(-0.5, 0.5, 3), random_quaternion(rng))
        distance = rng.uniform(0.5, 1.0) * (a.radius + b.radius)
        pose_b = (pose_a[0] + distance * random_direction(rng), random_quaternion(rng))
        if reference(a, pose_a, b, pose_b)[0] != 0.0:
            continue
        for first, pose_first, second, pose_second in ((a, pose_a, b, pose_b), (b, pose_b, a, pose_a)):
            result = overlap_lib.overlap(first, pose_first, second, pose_second, precision)
            assert result.volume == 0.0 and result.depth == 0.0 and result.area == 0.0
            assert list(result.normal) == [0.0, 0.0, 0.0]
        checked += 1


def test_cube_in_the_notch_of_the_l_shape(overlap_lib, shapes):
    """Convex hulls overlap, the solids do not: a cube in the notch of the L, 0.01 from its walls."""
    l_shape, cube = shapes["l_shape"], shapes["cube"]
    pose_l = file_frame_pose(l_shape)
    small = shapes["small_cube"]
    turned = quaternion_about((1, 2, 3), 0.9)
    for precision in "df":
        for centre in ((1.51, 1.51, 0.5), (1.6, 1.55, 0.8), (1.51, 2.2, 0.5)):
            result = overlap_lib.overlap(l_shape, pose_l, cube, (centre, IDENTITY), precision)
            assert result.volume == 0.0 and result.num_inconsistent == 0
        for centre in ((1.5, 1.5, 0.5), (1.25, 1.25, 0.3)):  # a turned cube of edge 0.25, 0.01 clear at least
            result = overlap_lib.overlap(l_shape, pose_l, small, (centre, turned), precision)
            assert result.volume == 0.0 and result.num_inconsistent == 0
        # Pushed 0.05 into the inner corner (top and bottom faces coplanar with the L's):
        # two slabs of the cube inside the L's arms.
        result = overlap_lib.overlap(l_shape, pose_l, cube, ((1.45, 1.45, 0.5), IDENTITY), precision)
        volume = 0.05 * 1.0 + 0.05 * 0.95
        assert abs(result.volume - volume) < TOLERANCE[precision] * volume
        # One contact for the two spots: the L's faces x = 1 and y = 1 inside the cube, 0.95 x 1 each (area
        # vector (0.95, 0.95, 0); the top and bottom faces, flush, cancel), and the extent of the two slabs along
        # (1, 1, 0) / sqrt 2 is their spread, 1.05 / sqrt 2, where each slab is 0.05 deep. The law takes at most
        # 3 V / A (poly_contact_pair_depth): 3 x 0.0975 / (0.95 sqrt 2) = 0.218, four times a slab's depth
        # rather than fifteen.
        area = 0.95 * math.sqrt(2.0)
        assert abs(result.projected_area - area) < TOLERANCE[precision] * area
        assert abs(result.depth - 1.05 / math.sqrt(2.0)) < TOLERANCE[precision]
        law_depth = overlap_lib.pair_depth(result)
        assert abs(law_depth - (1.0 + 1e-6) * 3.0 * volume / area) < TOLERANCE[precision] * law_depth  # its slack


CONVEX_PAIRS = [("cube", "cube"), ("box_1x2x3", "cube"), ("box_1x2x3", "box_1x2x3"), ("tetrahedron", "tetrahedron"),
                ("tetrahedron", "cube"), ("icosphere_80", "icosphere_80"), ("icosphere_320", "tetrahedron")]


@pytest.mark.parametrize("names", CONVEX_PAIRS, ids=["-".join(p) for p in CONVEX_PAIRS])
def test_convex_overlaps_keep_their_extent_as_the_law_depth(overlap_lib, shapes, names):
    """The pair style's law takes the depth min(extent, 3 V / A) (poly_contact_pair_depth). A convex overlap holds
    the two cones from its extreme points along the normal over its intersection curve, of volume A delta / 3, so
    its extent never exceeds 3 V / A and the law keeps it: bit for bit in double, over random and grazing poses
    (overlaps of 1e-6 to 1 of the smaller volume). A vertex pressed into a face is such a cone (3 V / (A delta) = 1
    to rounding), so the bound is tight: in single precision rounding takes some such poses past the cap's 1e-6 of
    slack, and the law's depth is the extent to within the single-precision tolerance (1e-4) where the overlap is
    more than 1e-3 of the smaller volume (the tolerance of V itself, test_volume_and_centroid_match_reference)."""
    a, b = shapes[names[0]], shapes[names[1]]
    found, small_overlaps = pair_poses(overlap_lib, shapes, names)
    small = min(a.volume, b.volume)
    tightest, worst_single = math.inf, 0.0
    for pose_a, pose_b, _, _ in found + small_overlaps:
        for precision in "df":
            result = overlap_lib.overlap(a, pose_a, b, pose_b, precision)
            if not result.volume > 0.0:
                continue
            law_depth = overlap_lib.pair_depth(result)
            if precision == "d":
                assert law_depth == result.depth, (result.volume, result.depth, result.projected_area)
                tightest = min(tightest, 3.0 * result.volume / (result.projected_area * result.depth))
            elif result.volume > 1e-3 * small:
                worst_single = max(worst_single, 1.0 - law_depth / result.depth)
    print(f"\n{'-'.join(names)}: smallest 3 V / (A delta) {tightest:.9f} in double; law depth below the extent by "
          f"{worst_single:.1e} at most in single")
    assert tightest >= 1.0 - 1e-6
    assert worst_single < TOLERANCE["f"]


@pytest.mark.parametrize("name", ["tetrahedron", "small_cube", "box_1x2x3", "icosphere_80"])
def test_a_vertex_pressed_into_a_face_is_at_the_cap(overlap_lib, shapes, name):
    """The equality of the cap's bound: a convex body turned at random, its lowest vertex pressed 1e-3 of its size
    into the top face of a cube four times larger, overlaps in a pyramid over the face, V = A delta / 3 exactly.
    Rounding must leave the law's depth the extent, bit for bit in double (the cap's 1e-6 of slack) and within the
    single-precision tolerance in single, over twenty orientations."""
    big = overlap_lib.shape(os.path.join(SHAPES, "cube.stl"), 4.0)  # axis-aligned, faces at +-2
    body = shapes[name]
    rng = np.random.default_rng(sum(map(ord, name)))
    size = body.volume ** (1.0 / 3.0)
    press = 1e-3 * size
    tested = 0
    while tested < 20:
        turn = random_quaternion(rng)
        heights = np.sort(body.world(((0.0, 0.0, 0.0), turn))[:, 2])
        if heights[1] - heights[0] < 3.0 * press:
            continue  # the next vertex would reach the face too: not a single cone
        pose = ((0.1, -0.2, 2.0 - press - heights[0]), turn)
        double = overlap_lib.overlap(big, ((0.0, 0.0, 0.0), IDENTITY), body, pose, "d")
        ratio = 3.0 * double.volume / (double.projected_area * double.depth)
        assert abs(ratio - 1.0) < 1e-9, ratio
        assert abs(double.depth - press) < 1e-12 * size
        assert overlap_lib.pair_depth(double) == double.depth
        single = overlap_lib.overlap(big, ((0.0, 0.0, 0.0), IDENTITY), body, pose, "f")
        assert abs(overlap_lib.pair_depth(single) / single.depth - 1.0) < TOLERANCE["f"]
        tested += 1


# ---------------------------------------------------------------------------------------------
# axis-aligned boxes and a half-space: closed forms for V, centroid, normal (eq. 4.19), depth

# Exact quaternions: identity and cyclic permutations of the axes.
AXIS_QUATERNIONS = [IDENTITY, (0.5, 0.5, 0.5, 0.5), (0.5, -0.5, -0.5, -0.5), (0.0, 1.0, 0.0, 0.0)]


def box_by_hand(low_a, high_a, low_b, high_b):
    """Eq. 4.19 by hand for A n B of two axis-aligned boxes: A's faces inside B are the
    faces of the intersection where A's side is the inner one. Returns V, centroid,
    normal, depth (extent of the intersection along the normal) and A's area inside B."""
    low, high = np.maximum(low_a, low_b), np.minimum(high_a, high_b)
    lengths = high - low
    area_normal = np.zeros(3)
    area = 0.0
    for k in range(3):
        face = np.prod(np.delete(lengths, k))
        if high_a[k] < high_b[k]:
            area_normal[k] += face
            area += face
        if low_a[k] > low_b[k]:
            area_normal[k] -= face
            area += face
    normal = area_normal / np.linalg.norm(area_normal)
    return np.prod(lengths), 0.5 * (low + high), normal, float(np.abs(normal) @ lengths), area


@pytest.mark.parametrize("precision", ["d", "f", "m"])
def test_axis_aligned_boxes(overlap_lib, shapes, errors, precision):
    rng = np.random.default_rng(5)
    tolerance = TOLERANCE[precision]
    worst = {"box V relative": 0.0, "box centroid / L": 0.0, "box normal": 0.0, "box depth / L": 0.0,
             "box area relative": 0.0}
    count = 0
    while count < 40:
        a = shapes[("cube", "box_1x2x3")[rng.integers(2)]]
        b = shapes[("cube", "box_1x2x3")[rng.integers(2)]]
        pose_a = (rng.uniform(-1, 1, 3), AXIS_QUATERNIONS[rng.integers(4)])
        pose_b = (pose_a[0] + rng.uniform(-2, 2, 3), AXIS_QUATERNIONS[rng.integers(4)])
        world_a, world_b = a.world(pose_a), b.world(pose_b)
        low_a, high_a, low_b, high_b = world_a.min(0), world_a.max(0), world_b.min(0), world_b.max(0)
        small = min(a.volume, b.volume)
        if np.prod(np.clip(np.minimum(high_a, high_b) - np.maximum(low_a, low_b), 0, None)) < 1e-3 * small:
            continue
        if (np.any(np.abs(high_a - high_b) < 1e-3) or np.any(np.abs(low_a - low_b) < 1e-3)
                or np.all(high_a <= high_b) and np.all(low_a >= low_b)):
            continue  # coplanar faces and containment are degenerate cases, tested below
        volume, centroid, normal, depth, area = box_by_hand(low_a, high_a, low_b, high_b)
        result = overlap_lib.overlap(a, pose_a, b, pose_b, precision)
        size = size_of(a, b)
        worst["box V relative"] = max(worst["box V relative"], abs(result.volume - volume) / volume)
        worst["box centroid / L"] = max(worst["box centroid / L"],
                                        np.abs(np.array(result.centroid[:]) - centroid).max() / size)
        worst["box normal"] = max(worst["box normal"], np.abs(np.array(result.normal[:]) - normal).max())
        worst["box depth / L"] = max(worst["box depth / L"], abs(result.depth - depth) / size)
        worst["box area relative"] = max(worst["box area relative"], abs(result.area - area) / area)
        count += 1
    for key, value in worst.items():
        errors.add(key, precision, value)
    assert max(worst.values()) < tolerance, worst


@pytest.mark.parametrize("precision", ["d", "f", "m"])
def test_cube_pressed_into_a_half_space(overlap_lib, shapes, errors, precision):
    """A cube in random orientation pressed 0.15..0.45 into the flat top face of a box
    40 x 80 x 120: normal = -(face normal) from the cube into the box, depth = penetration,
    V and centroid against the reference; and the same with the roles swapped. Single and
    mixed precision within 1e-4 (measured 4.4e-5 in both): the boundary tetrahedra have their
    vertices on the overlap, not on the box's far corners or the centre line, so they do not
    cancel (before, single precision's float sums of them lost 9.2e-4)."""
    cube, big = shapes["cube"], shapes["big_box"]
    top = big.vertices[:, 2].max()
    pose_big = ((0.0, 0.0, -top), IDENTITY)  # top face at z = 0, normal +z
    rng = np.random.default_rng(9)
    worst_normal = worst_depth = worst_volume = 0.0
    for _ in range(8):
        q = random_quaternion(rng)
        penetration = rng.uniform(0.15, 0.45)
        lowest = cube.world(((0, 0, 0), q))[:, 2].min()
        pose_cube = ((rng.uniform(-3, 3), rng.uniform(-3, 3), -lowest - penetration), q)
        volume, centroid = reference(cube, pose_cube, big, pose_big)
        assert volume > 1e-3 * cube.volume
        for first, pose_first, second, pose_second, expected in ((cube, pose_cube, big, pose_big, -1.0),
                                                                 (big, pose_big, cube, pose_cube, 1.0)):
            result = overlap_lib.overlap(first, pose_first, second, pose_second, precision)
            worst_normal = max(worst_normal, np.abs(np.array(result.normal[:]) - [0, 0, expected]).max())
            worst_depth = max(worst_depth, abs(result.depth - penetration))
            worst_volume = max(worst_volume, abs(result.volume - volume) / volume,
                               np.abs(np.array(result.centroid[:]) - centroid).max())
    errors.add("half-space normal", precision, worst_normal)
    errors.add("half-space depth / L", precision, worst_depth)
    errors.add("half-space V relative, centroid / L", precision, worst_volume)
    assert worst_normal < {"d": 1e-12, "f": 1e-4, "m": 1e-4}[precision]
    assert worst_depth < {"d": 1e-12, "f": 1e-4, "m": 1e-4}[precision]
    assert worst_volume < {"d": 1e-10, "f": 1e-4, "m": 1e-4}[precision]


# ---------------------------------------------------------------------------------------------
# degenerate configurations: finite, consistent, continuous

PERTURBATION = 1e-12
CONTINUITY = 1e-9  # |V(perturbed) - V| <= CONTINUITY * L^3


def perturbed_poses(pose, rng):
    """B moved by +-1e-12 along each axis, and turned by +-1e-12 rad about a random axis."""
    position, quaternion = np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float)
    out = []
    for sign in (1.0, -1.0):
        for k in range(3):
            moved = position.copy()
            moved[k] += sign * PERTURBATION
            out.append((moved, quaternion))
        out.append((position, quaternion_product(quaternion,
                                                 quaternion_about(random_direction(rng), sign * PERTURBATION))))
    return out


def degenerate_cases(shapes):
    """name -> (A, pose A, B, pose B, expected volume or None for the reference)."""
    cube, tetrahedron = shapes["cube"], shapes["tetrahedron"]
    cases = {}
    # A vertex exactly on a face: the regular tetrahedron turned upside down (exact quaternion)
    # with its lowest vertex on the cube's top face, and a cube standing on a corner.
    flipped = (0.0, 1.0, 0.0, 0.0)
    lowest = tetrahedron.world(((0, 0, 0), flipped))[:, 2].min()
    cases["vertex on face (tetrahedron)"] = (cube, ((0, 0, 0), IDENTITY), tetrahedron,
                                             ((0.1, 0.2, 0.5 - lowest), flipped), 0.0)
    corner_down = quaternion_product(quaternion_about((1, 0, 0), math.atan(math.sqrt(0.5))),
                                     quaternion_about((0, 0, 1), math.pi / 4))
    lowest = cube.world(((0, 0, 0), corner_down))[:, 2].min()
    cases["vertex on face (cube on a corner)"] = (cube, ((0, 0, 0), IDENTITY), cube,
                                                  ((0.1, -0.2, 0.5 - lowest), corner_down), 0.0)
    # Edge on edge: two cubes turned 45 degrees about x and about y, top edge across bottom edge.
    about_x, about_y = quaternion_about((1, 0, 0), math.pi / 4), quaternion_about((0, 1, 0), math.pi / 4)
    cases["crossed edges touching"] = (cube, ((0, 0, 0), about_x), cube, ((0, 0, math.sqrt(2.0)), about_y), 0.0)
    cases["crossed edges 1e-3 deep"] = (cube, ((0, 0, 0), about_x), cube,
                                        ((0, 0, math.sqrt(2.0) - 1e-3), about_y), None)
    # Coplanar faces: cubes face to face, shifted sideways (their y faces coplanar too).
    cases["coplanar faces, 1e-3 overlap"] = (cube, ((0, 0, 0), IDENTITY), cube, ((0.3, 0, 0.999), IDENTITY),
                                             0.7e-3)
    cases["coplanar faces, touching"] = (cube, ((0, 0, 0), IDENTITY), cube, ((0.3, 0, 1.0), IDENTITY), 0.0)
    cases["coplanar faces, stacked"] = (cube, ((0, 0, 0), IDENTITY), cube, ((0, 0, 1.0), IDENTITY), 0.0)
    # Identical shapes in identical poses, at the identity and turned.
    turned = quaternion_about((1, 2, 3), 0.7)
    for name in ("cube", "schoenhardt", "rock_70", "icosphere_320", "l_shape"):
        shape = shapes[name]
        cases[f"identical {name}"] = (shape, ((0, 0, 0), IDENTITY), shape, ((0, 0, 0), IDENTITY), shape.volume)
        cases[f"identical {name}, turned"] = (shape, ((0.1, 0.2, 0.3), turned), shape, ((0.1, 0.2, 0.3), turned),
                                              shape.volume)
    # One shape inside the other.
    small, sphere = shapes["small_cube"], shapes["icosphere_320"]
    inner = ((0.05, 0.0, 0.02), quaternion_about((1, 1, 0), 0.3))
    cases["cube inside icosphere"] = (sphere, ((0, 0, 0), IDENTITY), small, inner, small.volume)
    cases["icosphere around cube"] = (small, inner, sphere, ((0, 0, 0), IDENTITY), small.volume)
    cases["cube inside icosphere, concentric"] = (sphere, ((0, 0, 0), IDENTITY), small, ((0, 0, 0), IDENTITY),
                                                  small.volume)
    # Deep overlap: centres 0.1 apart.
    cases["deep rock_70-rock_40"] = (shapes["rock_70"], ((0, 0, 0), quaternion_about((1, 0, 0), 0.3)),
                                     shapes["rock_40"], ((0.1, 0, 0), quaternion_about((0, 1, 0), 0.5)), None)
    cases["deep cube-cube"] = (cube, ((0, 0, 0), IDENTITY), cube, ((0.06, 0.08, 0), IDENTITY), 0.94 * 0.92)
    cases["deep schoenhardt-l_shape"] = (shapes["schoenhardt"], ((0.5, 0.4, 0.3), turned), shapes["l_shape"],
                                         ((0.55, 0.45, 0.3), IDENTITY), None)
    return cases


DEGENERATE = ["vertex on face (tetrahedron)", "vertex on face (cube on a corner)", "crossed edges touching",
              "crossed edges 1e-3 deep", "coplanar faces, 1e-3 overlap", "coplanar faces, touching",
              "coplanar faces, stacked"] + [
    f"identical {name}{turned}" for name in ("cube", "schoenhardt", "rock_70", "icosphere_320", "l_shape")
    for turned in ("", ", turned")] + [
    "cube inside icosphere", "icosphere around cube", "cube inside icosphere, concentric", "deep rock_70-rock_40",
    "deep cube-cube", "deep schoenhardt-l_shape"]


@pytest.mark.parametrize("case", DEGENERATE)
def test_degenerate_configuration(overlap_lib, shapes, errors, case):
    """Double precision: finite, no inconsistent edge, V as expected (exact value, closed
    form, or the reference where the pose is generic enough for it), and V continuous:
    moving or turning B by 1e-12 changes V by at most 1e-9 L^3."""
    a, pose_a, b, pose_b, expected = degenerate_cases(shapes)[case]
    size = size_of(a, b)
    if expected is None:
        expected = reference(a, pose_a, b, pose_b)[0]
    result = overlap_lib.overlap(a, pose_a, b, pose_b)
    assert_finite(result, case)
    assert result.num_inconsistent == 0
    value_error = abs(result.volume - expected) / size ** 3
    continuity = 0.0
    for pose in perturbed_poses(pose_b, np.random.default_rng(3)):
        moved = overlap_lib.overlap(a, pose_a, b, pose)
        assert_finite(moved, case)
        assert moved.num_inconsistent == 0
        continuity = max(continuity, abs(moved.volume - result.volume) / size ** 3)
    errors.add("degenerate |V - V_exact| / L^3", "d", value_error)
    errors.add("degenerate |dV| / L^3 for 1e-12 moves", "d", continuity)
    assert value_error < 1e-12
    assert continuity < CONTINUITY
    if case.startswith("identical"):
        assert np.abs(np.array(result.centroid[:]) - pose_a[0]).max() < 1e-12 * size


@pytest.mark.parametrize("case", DEGENERATE)
def test_degenerate_configuration_single(overlap_lib, shapes, errors, case):
    """Single precision: finite, consistent, and V within 1e-4 L^3 of the expected value,
    at the configuration and after the same perturbations (which single precision mostly
    cannot resolve: they test that rounding of the pose does not switch the topology)."""
    a, pose_a, b, pose_b, expected = degenerate_cases(shapes)[case]
    size = size_of(a, b)
    if expected is None:
        expected = reference(a, pose_a, b, pose_b)[0]
    worst = 0.0
    for pose in [pose_b] + perturbed_poses(pose_b, np.random.default_rng(3)):
        result = overlap_lib.overlap(a, pose_a, b, pose, "f")
        assert_finite(result, case)
        assert result.num_inconsistent == 0
        worst = max(worst, abs(result.volume - expected) / size ** 3)
    errors.add("degenerate |V - V_exact| / L^3", "f", worst)
    assert worst < 1e-4


@pytest.mark.parametrize("precision", ["d", "f"])
@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_tiny_and_huge_particles(overlap_lib, scale, precision):
    """Micrometre grains and kilometre blocks: the same pose scaled gives V * s^3 and the centroid,
    depth and area scaled, with the errors of the unit-size case (nothing depends on absolute size)."""
    rock = os.path.join(SHAPES, "rock_70.obj")
    unit_a, unit_b = overlap_lib.shape(rock, 1.0), overlap_lib.shape(rock, 1.0)
    big_a, big_b = overlap_lib.shape(rock, scale), overlap_lib.shape(rock, scale)
    q_a, q_b = [0.9, 0.1, -0.3, 0.2], [0.3, 0.8, 0.1, -0.4]
    norm = lambda q: [x / math.sqrt(sum(y * y for y in q)) for x in q]  # noqa: E731
    centre = [0.3, -0.2, 0.1]
    offset = [0.6, 0.15, -0.1]
    unit = overlap_lib.overlap(unit_a, (centre, norm(q_a)), unit_b,
                               ([c + o for c, o in zip(centre, offset)], norm(q_b)), precision)
    scaled = overlap_lib.overlap(big_a, ([scale * c for c in centre], norm(q_a)), big_b,
                                 ([scale * (c + o) for c, o in zip(centre, offset)], norm(q_b)), precision)
    assert unit.volume > 1e-3 * unit_a.volume  # a real overlap
    tolerance = 1e-12 if precision == "d" else 1e-5
    assert abs(scaled.volume / scale ** 3 - unit.volume) <= tolerance * unit.volume, (scaled.volume, unit.volume)
    assert abs(scaled.depth / scale - unit.depth) <= tolerance * unit.depth
    assert abs(scaled.area / scale ** 2 - unit.area) <= tolerance * unit.area
    for k in range(3):
        assert abs(scaled.centroid[k] / scale - unit.centroid[k]) <= tolerance
        assert abs(scaled.normal[k] - unit.normal[k]) <= 10 * tolerance
    assert scaled.num_inconsistent == 0


# ---------------------------------------------------------------------------------------------
# half-space (plane wall): src/poly_halfspace.h

def rotation_taking_z_to(normal):
    """A unit quaternion whose rotation maps +z onto `normal`."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, normal)
    s, c = np.linalg.norm(axis), float(np.dot(z, normal))
    if s < 1e-12:
        return (1.0, 0.0, 0.0, 0.0) if c > 0 else (0.0, 1.0, 0.0, 0.0)
    half = 0.5 * math.atan2(s, c)
    return (math.cos(half), *(math.sin(half) * axis / s))


@pytest.mark.parametrize("name", ["cube", "tetrahedron", "schoenhardt", "rock_40", "icosphere_320", "l_shape"])
def test_halfspace_matches_reference(overlap_lib, shapes, errors, name):
    """A particle in random orientation cut by a plane of random normal, 2..60% of its bounding radius
    deep: V, centroid (1e-10 relative, / L), normal (exactly -n), depth (deepest vertex, 1e-12 L) and
    area against the reference clipping of the particle by a box 40 x 80 x 120 whose top face is the
    plane; at 10^3 L from the origin the same to 1e-9."""
    shape, big = shapes[name], shapes["big_box"]
    top = big.vertices[:, 2].max()
    rng = np.random.default_rng(17)
    size = shape.volume ** (1.0 / 3.0)
    worst_volume = worst_centroid = worst_depth = worst_far = 0.0
    for _ in range(12):
        q, normal = random_quaternion(rng), random_direction(rng)
        centre = rng.uniform(-0.5, 0.5, 3)
        world = shape.world((centre, q))
        lowest = (world @ normal).min()
        offset = lowest + rng.uniform(0.02, 0.6) * shape.radius
        q_box = rotation_taking_z_to(normal)
        foot = centre + (offset - centre @ normal) * normal
        box_position = foot - ref.quaternion_matrix(q_box) @ np.array([0.0, 0.0, top])
        volume, centroid = reference(shape, (centre, q), big, (box_position, q_box))
        result = overlap_lib.halfspace(shape, (centre, q), normal, offset)
        assert volume > 0
        worst_volume = max(worst_volume, abs(result.volume - volume) / volume)
        worst_centroid = max(worst_centroid, np.abs(np.array(result.centroid) - centroid).max() / size)
        assert np.abs(np.array(result.normal) + normal).max() == 0.0
        worst_depth = max(worst_depth, abs(result.depth - (offset - lowest)) / size)
        far = np.array([1e3, -2e3, 1.5e3]) * size
        moved = overlap_lib.halfspace(shape, (centre + far, q), normal, offset + far @ normal)
        worst_far = max(worst_far, abs(moved.volume - result.volume) / result.volume,
                        np.abs(np.array(moved.centroid) - far - np.array(result.centroid)).max() / size)
    errors.add("half-space wall V relative", "d", worst_volume)
    errors.add("half-space wall centroid / L", "d", worst_centroid)
    errors.add("half-space wall depth / L", "d", worst_depth)
    errors.add("half-space wall 1e3 L away", "d", worst_far)
    assert worst_volume < 1e-10 and worst_centroid < 1e-10 and worst_depth < 1e-12, \
        (worst_volume, worst_centroid, worst_depth)
    assert worst_far < 1e-9, worst_far


def test_halfspace_closed_forms(overlap_lib, shapes):
    """Unit cube (edge 1, centred) resting flat h deep: V = h, centroid at h/2 below the plane,
    area = 1 + 4h; turned 45 degrees about x, edge down, h deep: a prism of volume h^2; a face exactly
    on the plane, and the plane a hair below the lowest vertex: no overlap."""
    cube = shapes["cube"]
    edge = cube.volume ** (1.0 / 3.0)
    up = (0.0, 0.0, 1.0)
    for h in (1e-9, 1e-3, 0.1, 0.5, 0.99):
        r = overlap_lib.halfspace(cube, ((0.3, -0.2, 0.5 * edge - h * edge), (1, 0, 0, 0)), up, 0.0)
        assert abs(r.volume - h * edge ** 3) < 1e-12 * edge ** 3, (h, r.volume)
        assert abs(r.centroid[2] + 0.5 * h * edge) < 1e-12 * edge and abs(r.centroid[0] - 0.3) < 1e-12
        assert abs(r.area - (1 + 4 * h) * edge ** 2) < 1e-12 * edge ** 2
        assert abs(r.depth - h * edge) < 1e-12 * edge
    c = math.cos(math.pi / 8)
    turned = (c, math.sin(math.pi / 8), 0.0, 0.0)  # 45 degrees about x: an edge points down
    half_diagonal = edge / math.sqrt(2.0)
    for h in (1e-3, 0.05, 0.2):
        r = overlap_lib.halfspace(cube, ((0.0, 0.0, half_diagonal - h * edge), turned), up, 0.0)
        assert abs(r.volume - (h * edge) ** 2 * edge) < 1e-12 * edge ** 3, (h, r.volume)
        assert abs(r.centroid[2] + h * edge / 3.0) < 1e-12 * edge
    for z in (0.5 * edge, 0.5 * edge + 1e-12 * edge):
        r = overlap_lib.halfspace(cube, ((0.0, 0.0, z), (1, 0, 0, 0)), up, 0.0)
        assert r.volume == 0.0 and r.depth == 0.0 and r.normal == [0.0, 0.0, 0.0]
