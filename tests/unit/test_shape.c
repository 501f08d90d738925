/* Unit tests of src/poly_shape.c and src/poly_mesh_read.c.
 *
 *   test_shape CASE [REPO_ROOT [TMPDIR]]     run one case (see `test_shape --list`)
 *
 * Every check prints what it compares and the numbers; the exit status is the
 * number of failed checks (capped at 100).
 */
#include "poly_shape.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TEST_PI 3.14159265358979323846

static int failures;
static const char *repo_root = ".";
static const char *temp_dir = "/tmp";

static void check_close(const char *what, double actual, double expected, double tolerance)
{
  double error = fabs(actual - expected);
  int ok = error <= tolerance;  /* false for NaN */
  printf("%s %s: %.17g (expected %.17g, error %.3g, tolerance %.3g)\n", ok ? "ok  " : "FAIL", what, actual,
         expected, error, tolerance);
  failures += !ok;
}

static void check_relative(const char *what, double actual, double expected, double relative)
{
  check_close(what, actual, expected, relative * fabs(expected));
}

static void check_int(const char *what, long actual, long expected)
{
  int ok = actual == expected;
  printf("%s %s: %ld (expected %ld)\n", ok ? "ok  " : "FAIL", what, actual, expected);
  failures += !ok;
}

static void check_at_least(const char *what, double actual, double minimum)
{
  int ok = actual >= minimum;
  printf("%s %s: %.17g (at least %.17g)\n", ok ? "ok  " : "FAIL", what, actual, minimum);
  failures += !ok;
}

static void check_contains(const char *what, const char *text, const char *needle)
{
  int ok = strstr(text, needle) != NULL;
  printf("%s %s: message contains '%s': \"%s\"\n", ok ? "ok  " : "FAIL", what, needle, text);
  failures += !ok;
}

static const char *path_in(const char *directory, const char *name)
{
  static char buffers[4][1024];
  static int next;
  char *path = buffers[next++ % 4];
  if (snprintf(path, sizeof buffers[0], "%s/%s", directory, name) >= (int)sizeof buffers[0]) {
    printf("FAIL path too long: %s/%s\n", directory, name);
    exit(100);
  }
  return path;
}

static const char *shape_path(const char *name)
{
  static char directory[1024];
  if (snprintf(directory, sizeof directory, "%s/examples/shapes", repo_root) >= (int)sizeof directory) exit(100);
  return path_in(directory, name);
}

static void write_file(const char *path, const char *text)
{
  FILE *file = fopen(path, "wb");
  if (!file || fputs(text, file) < 0) {
    printf("FAIL cannot write %s\n", path);
    failures++;
  }
  if (file) fclose(file);
}

static poly_status load(const char *path, double scale, poly_shape *shape)
{
  char message[512];
  poly_status status = poly_shape_load(path, scale, shape, message, sizeof message);
  if (status != POLY_OK) printf("     load %s: %s\n", path, message);
  return status;
}

static poly_status read_welded(const char *path, poly_mesh *mesh)
{
  char message[512];
  poly_status status = poly_mesh_read(path, mesh, message, sizeof message);
  if (status != POLY_OK)
    printf("     read %s: %s\n", path, message);
  else
    poly_mesh_weld(mesh, 1e-9);
  return status;
}

/* Rotation by `angle` about the unit axis along `axis` (Rodrigues), row-major. */
static void rotation(const double axis[3], double angle, double r[9])
{
  double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  double x = axis[0] / n, y = axis[1] / n, z = axis[2] / n, c = cos(angle), s = sin(angle), t = 1 - c;
  double m[9] = {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
                 t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
                 t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  memcpy(r, m, sizeof m);
}

static void transform_mesh(poly_mesh *mesh, const double r[9], const double shift[3])
{
  for (int i = 0; i < mesh->num_vertices; i++) {
    double *p = mesh->vertices + 3 * i, q[3];
    for (int k = 0; k < 3; k++) q[k] = r[3 * k] * p[0] + r[3 * k + 1] * p[1] + r[3 * k + 2] * p[2] + shift[k];
    memcpy(p, q, sizeof q);
  }
}

static double determinant3(const double m[9])
{
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/* |cos| of the angle between column `column` of the row-major `axes` and `direction`. */
static double axis_alignment(const double axes[9], int column, const double direction[3])
{
  return fabs(axes[column] * direction[0] + axes[3 + column] * direction[1] + axes[6 + column] * direction[2]);
}

/* Properties every valid shape has, whatever its geometry. */
static void check_shape_invariants(const char *name, const poly_shape *shape)
{
  char what[256];
  snprintf(what, sizeof what, "%s Euler characteristic V - E + F", name);
  check_int(what, shape->num_vertices - shape->num_edges + shape->num_triangles, 2);
  snprintf(what, sizeof what, "%s principal axes determinant", name);
  check_close(what, determinant3(shape->principal_axes), 1.0, 1e-14);

  /* Body frame: the mass properties of the stored vertices are diagonal, centred. */
  poly_mass_properties body;
  poly_mass_properties_compute(shape->vertices, shape->triangles, shape->num_triangles, &body);
  double largest = shape->principal_moments[2], off_diagonal = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      if (i != j && fabs(body.inertia[3 * i + j]) > off_diagonal) off_diagonal = fabs(body.inertia[3 * i + j]);
  snprintf(what, sizeof what, "%s body-frame inertia off-diagonal / largest moment", name);
  check_close(what, off_diagonal / largest, 0.0, 1e-12);
  for (int k = 0; k < 3; k++) {
    snprintf(what, sizeof what, "%s body-frame inertia [%d][%d] = principal moment", name, k, k);
    check_relative(what, body.inertia[4 * k], shape->principal_moments[k], 1e-12);
    snprintf(what, sizeof what, "%s body-frame centroid[%d] / bounding radius", name, k);
    check_close(what, body.centroid[k] / shape->bounding_radius, 0.0, 1e-13);
  }
  snprintf(what, sizeof what, "%s ascending moments: min(I1 - I0, I2 - I1)", name);
  check_at_least(what, fmin(shape->principal_moments[1] - shape->principal_moments[0],
                            shape->principal_moments[2] - shape->principal_moments[1]), 0.0);

  /* Edges: lo < hi, the first triangle runs lo -> hi, the second hi -> lo. */
  int bad_edges = 0;
  for (int e = 0; e < shape->num_edges; e++) {
    int lo = shape->edges[2 * e], hi = shape->edges[2 * e + 1];
    for (int side = 0; side < 2; side++) {
      const int *t = shape->triangles + 3 * shape->edge_triangles[2 * e + side];
      int from = side == 0 ? lo : hi, to = side == 0 ? hi : lo, found = 0;
      for (int k = 0; k < 3; k++) found |= t[k] == from && t[(k + 1) % 3] == to;
      bad_edges += !found || lo >= hi;
    }
  }
  snprintf(what, sizeof what, "%s edges violating lo < hi / triangle direction", name);
  check_int(what, bad_edges, 0);

  /* Vertex-triangle adjacency lists each incidence exactly once. */
  int bad_incidences = shape->vertex_triangle_offsets[shape->num_vertices] != 3 * shape->num_triangles;
  for (int v = 0; v < shape->num_vertices; v++)
    for (int i = shape->vertex_triangle_offsets[v]; i < shape->vertex_triangle_offsets[v + 1]; i++) {
      const int *t = shape->triangles + 3 * shape->vertex_triangles[i];
      bad_incidences += t[0] != v && t[1] != v && t[2] != v;
    }
  snprintf(what, sizeof what, "%s bad vertex-triangle incidences", name);
  check_int(what, bad_incidences, 0);

  /* A closed surface: the area-weighted unit normals sum to zero. */
  double sum[3] = {0, 0, 0}, area_total = 0.0, worst_unit = 0.0;
  for (int t = 0; t < shape->num_triangles; t++) {
    const double *a = shape->vertices + 3 * shape->triangles[3 * t];
    const double *b = shape->vertices + 3 * shape->triangles[3 * t + 1];
    const double *c = shape->vertices + 3 * shape->triangles[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    double area2 = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double *unit = shape->face_normals + 3 * t;
    double norm = sqrt(unit[0] * unit[0] + unit[1] * unit[1] + unit[2] * unit[2]);
    worst_unit = fmax(worst_unit, fabs(norm - 1.0));
    for (int k = 0; k < 3; k++) sum[k] += area2 * unit[k];
    area_total += area2;
  }
  snprintf(what, sizeof what, "%s worst | |face normal| - 1 |", name);
  check_close(what, worst_unit, 0.0, 1e-15);
  snprintf(what, sizeof what, "%s |sum of area * normal| / total area", name);
  check_close(what, sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) / area_total, 0.0, 1e-14);
}

/* ------------------------------------------------------------------ cases */

static void case_cube(void)
{
  poly_shape shape = {0};
  check_int("cube.stl load status", load(shape_path("cube.stl"), 1.0, &shape), POLY_OK);
  check_int("triangles", shape.num_triangles, 12);
  check_int("vertices after welding", shape.num_vertices, 8);
  check_int("vertices removed by welding", shape.num_welded, 28);
  check_int("edges", shape.num_edges, 18);
  check_relative("volume", shape.volume, 1.0, 1e-12);
  for (int k = 0; k < 3; k++) {
    check_relative("centre of mass (0.5 each)", shape.centre_of_mass[k], 0.5, 1e-12);
    check_relative("principal moment (1/6 each)", shape.principal_moments[k], 1.0 / 6.0, 1e-12);
  }
  check_relative("bounding radius sqrt(3)/2", shape.bounding_radius, sqrt(3.0) / 2.0, 1e-12);
  check_int("was flipped", shape.was_flipped, 0);
  check_shape_invariants("cube", &shape);
  poly_shape_free(&shape);
}

/* Degenerate moments leave the axes free; they must then follow the file axes
 * (a cube stays axis-aligned), and a square prism keeps its unique axis. */
static void case_degenerate_axes(void)
{
  static const char *isotropic[3] = {"cube.stl", "tetrahedron.obj", "icosphere_80.off"};
  for (int f = 0; f < 3; f++) {
    poly_shape shape = {0};
    check_int("isotropic shape load status", load(shape_path(isotropic[f]), 1.0, &shape), POLY_OK);
    for (int k = 0; k < 9; k++)
      check_close("principal axes = file axes for isotropic inertia", shape.principal_axes[k], k % 4 == 0 ? 1.0 : 0.0,
                  1e-12);
    poly_shape_free(&shape);
  }
  /* Square prism 1 x 1 x 2, turned about z by 0.3 rad: moments ascending put the
   * long (unique) axis first; the degenerate pair must be the file's x, y turned
   * into the plane normal to it, i.e. columns (z, x, y). */
  double vertices[24], r[9], z_axis[3] = {0, 0, 1}, shift[3] = {0, 0, 0};
  int triangles[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                       1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  for (int i = 0; i < 8; i++) {
    vertices[3 * i] = ((i + 1) / 2) % 2;
    vertices[3 * i + 1] = (i / 2) % 2;
    vertices[3 * i + 2] = 2.0 * (i / 4);
  }
  poly_mesh mesh = {8, 12, vertices, triangles};
  rotation(z_axis, 0.3, r);
  transform_mesh(&mesh, r, shift);
  poly_shape shape = {0};
  char message[256];
  check_int("prism build status", poly_shape_build(&mesh, 1.0, "prism", &shape, message, sizeof message), POLY_OK);
  double x_axis[3] = {1, 0, 0}, y_axis[3] = {0, 1, 0};
  check_close("prism axis 1 is z", axis_alignment(shape.principal_axes, 0, z_axis), 1.0, 1e-12);
  check_close("prism axis 2 is x", axis_alignment(shape.principal_axes, 1, x_axis), 1.0, 1e-12);
  check_close("prism axis 3 is y", axis_alignment(shape.principal_axes, 2, y_axis), 1.0, 1e-12);
  check_close("prism axes right-handed", determinant3(shape.principal_axes), 1.0, 1e-12);
  poly_shape_free(&shape);
}

static void case_tetrahedron(void)
{
  poly_shape shape = {0};
  check_int("tetrahedron.obj load status", load(shape_path("tetrahedron.obj"), 1.0, &shape), POLY_OK);
  double volume = 1.0 / (6.0 * sqrt(2.0));
  check_relative("volume 1/(6 sqrt 2)", shape.volume, volume, 1e-12);
  for (int k = 0; k < 3; k++) {
    check_close("centre of mass at origin", shape.centre_of_mass[k], 0.0, 1e-15);
    /* Regular tetrahedron of edge a: I = m a^2 / 20 about every axis through the centroid. */
    check_relative("principal moment m a^2/20", shape.principal_moments[k], volume / 20.0, 1e-12);
  }
  check_relative("bounding radius sqrt(6)/4", shape.bounding_radius, sqrt(6.0) / 4.0, 1e-12);
  check_shape_invariants("tetrahedron", &shape);
  poly_shape_free(&shape);
}

/* Box 1 x 2 x 3: I = m (b^2 + c^2)/12 etc.; ascending 2.5 (about z), 5 (y), 6.5 (x). */
static const double box_moments[3] = {2.5, 5.0, 6.5};
static const double box_axis_directions[3][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};

static void case_box(void)
{
  poly_shape shape = {0};
  check_int("box_1x2x3.off load status", load(shape_path("box_1x2x3.off"), 1.0, &shape), POLY_OK);
  check_int("triangles from 6 quads", shape.num_triangles, 12);
  check_relative("volume", shape.volume, 6.0, 1e-12);
  const double centre[3] = {0.5, 1.0, 1.5};
  for (int k = 0; k < 3; k++) {
    check_relative("centre of mass", shape.centre_of_mass[k], centre[k], 1e-12);
    check_relative("principal moment", shape.principal_moments[k], box_moments[k], 1e-12);
    check_close("|axis . expected direction|", axis_alignment(shape.principal_axes, k, box_axis_directions[k]), 1.0,
                1e-14);
  }
  check_relative("bounding radius sqrt(14)/2", shape.bounding_radius, sqrt(14.0) / 2.0, 1e-12);
  check_shape_invariants("box", &shape);
  poly_shape_free(&shape);
}

static void case_box_rotated(void)
{
  poly_mesh mesh;
  poly_shape shape = {0};
  char message[512];
  const double axis[3] = {1.0, 2.0, 3.0}, shift[3] = {1e3, -2e3, 5e2};
  double r[9];
  rotation(axis, 0.7, r);
  check_int("box read status", read_welded(shape_path("box_1x2x3.off"), &mesh), POLY_OK);
  transform_mesh(&mesh, r, shift);
  check_int("rotated box build status", poly_shape_build(&mesh, 1.0, "rotated box", &shape, message, sizeof message),
            POLY_OK);
  const double centre[3] = {0.5, 1.0, 1.5};
  check_relative("volume", shape.volume, 6.0, 1e-12);
  for (int k = 0; k < 3; k++) {
    double expected = r[3 * k] * centre[0] + r[3 * k + 1] * centre[1] + r[3 * k + 2] * centre[2] + shift[k];
    check_close("centre of mass = R c + t (absolute, box size ~3)", shape.centre_of_mass[k], expected, 1e-11);
    check_relative("principal moment", shape.principal_moments[k], box_moments[k], 1e-12);
    const double *e = box_axis_directions[k];
    double rotated[3];
    for (int i = 0; i < 3; i++) rotated[i] = r[3 * i] * e[0] + r[3 * i + 1] * e[1] + r[3 * i + 2] * e[2];
    check_close("|principal axis . R e|", axis_alignment(shape.principal_axes, k, rotated), 1.0, 1e-12);
  }
  check_shape_invariants("rotated box", &shape);
  poly_shape_free(&shape);
  poly_mesh_free(&mesh);
}

static void case_icospheres(void)
{
  static const int faces[5] = {20, 80, 320, 1280, 5120};
  const double sphere_volume = TEST_PI / 6.0;
  const double sphere_moment = 0.4 * sphere_volume * 0.25;  /* 2/5 m r^2, r = 1/2 */
  double previous_error = 0.0;
  for (int i = 0; i < 5; i++) {
    char name[64], what[128];
    poly_shape shape = {0};
    snprintf(name, sizeof name, "icosphere_%d.off", faces[i]);
    check_int(name, load(shape_path(name), 1.0, &shape), POLY_OK);
    check_int("triangles", shape.num_triangles, faces[i]);
    check_relative("volume pi/6", shape.volume, sphere_volume, 1e-12);
    double spread = (shape.principal_moments[2] - shape.principal_moments[0]) / shape.principal_moments[1];
    /* Icosahedral symmetry makes the inertia tensor exactly isotropic. */
    check_close("isotropy (I2 - I0) / I1", spread, 0.0, 1e-12);
    /* At fixed volume the ball has the smallest polar moment, so the excess is
     * positive. Radial sag ~ h^2 changes the moment only at second order (first
     * order is fixed by the volume): each subdivision (h/2) divides it by ~16. */
    double error = shape.principal_moments[1] / sphere_moment - 1.0;
    snprintf(what, sizeof what, "%s relative excess over the sphere's 2/5 m r^2", name);
    check_at_least(what, error, 0.0);
    check_close(what, error, 0.0, 0.012 / pow(13.0, i));
    if (i > 0) check_close("excess reduction per subdivision (h^4: about 16)", previous_error / error, 15.0, 2.0);
    previous_error = error;
    check_shape_invariants(name, &shape);
    poly_shape_free(&shape);
  }
}

/* Mass properties must follow an arbitrary rigid motion of the input exactly. */
static void check_rigid_motion_invariance(const char *file)
{
  poly_mesh mesh;
  poly_shape plain = {0}, moved = {0};
  char message[512];
  const double axis[3] = {-0.3, 0.8, 0.5}, shift[3] = {-37.0, 250.0, 1e3};
  double r[9];
  rotation(axis, 2.1, r);
  check_int("load status", load(shape_path(file), 1.0, &plain), POLY_OK);
  check_int("read status", read_welded(shape_path(file), &mesh), POLY_OK);
  transform_mesh(&mesh, r, shift);
  check_int("moved build status", poly_shape_build(&mesh, 1.0, file, &moved, message, sizeof message), POLY_OK);
  check_int("was flipped", plain.was_flipped, 0);
  check_at_least("volume", plain.volume, 1e-3);
  check_relative("moved volume", moved.volume, plain.volume, 1e-10);
  check_relative("moved bounding radius", moved.bounding_radius, plain.bounding_radius, 1e-10);
  for (int k = 0; k < 3; k++) {
    check_relative("moved principal moment", moved.principal_moments[k], plain.principal_moments[k], 1e-10);
    const double *c = plain.centre_of_mass;
    double expected = r[3 * k] * c[0] + r[3 * k + 1] * c[1] + r[3 * k + 2] * c[2] + shift[k];
    check_close("moved centre of mass = R c + t", moved.centre_of_mass[k], expected, 1e-10 * plain.bounding_radius * 1e3);
  }
  check_shape_invariants(file, &plain);
  check_shape_invariants("moved", &moved);
  poly_shape_free(&plain);
  poly_shape_free(&moved);
  poly_mesh_free(&mesh);
}

/* Reflex edges: the far corner of one neighbour lies outside the other's plane. */
static int reflex_edges(const poly_shape *shape)
{
  int count = 0;
  for (int e = 0; e < shape->num_edges; e++) {
    const int *t0 = shape->triangles + 3 * shape->edge_triangles[2 * e];
    const int *t1 = shape->triangles + 3 * shape->edge_triangles[2 * e + 1];
    int far = t1[0] + t1[1] + t1[2] - shape->edges[2 * e] - shape->edges[2 * e + 1];
    const double *p = shape->vertices + 3 * far, *a = shape->vertices + 3 * t0[0];
    const double *n = shape->face_normals + 3 * (t0 - shape->triangles) / 3;
    double height = n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2]);
    count += height > 1e-9 * shape->bounding_radius;
  }
  return count;
}

static void case_schoenhardt(void)
{
  poly_shape shape = {0};
  check_rigid_motion_invariance("schoenhardt.stl");
  check_int("schoenhardt load status", load(shape_path("schoenhardt.stl"), 1.0, &shape), POLY_OK);
  check_int("triangles", shape.num_triangles, 8);
  check_int("vertices", shape.num_vertices, 6);
  check_int("reflex edges (the three split diagonals)", reflex_edges(&shape), 3);
  poly_shape_free(&shape);
}

static void case_rocks(void)
{
  static const char *files[4] = {"rock_10.obj", "rock_40.obj", "rock_70.obj", "rock_1000.obj"};
  static const int faces[4] = {10, 40, 70, 1000};
  for (int i = 0; i < 4; i++) {
    poly_shape shape = {0};
    printf("---- %s\n", files[i]);
    check_rigid_motion_invariance(files[i]);
    check_int("load status", load(shape_path(files[i]), 2.0, &shape), POLY_OK);
    check_int("triangles", shape.num_triangles, faces[i]);
    check_int("vertices (F = 2V - 4)", shape.num_vertices, faces[i] / 2 + 2);
    check_relative("volume at scale 2: pi/6 * 8", shape.volume, TEST_PI / 6.0 * 8.0, 1e-12);
    check_at_least("reflex edges (non-convex)", reflex_edges(&shape), 2);
    poly_shape_free(&shape);
  }
}

typedef struct bad_mesh_case {
  const char *file;
  poly_status status;
  const char *keyword;
} bad_mesh_case;

static void case_bad_meshes(void)
{
  static const bad_mesh_case cases[] = {
      {"open.stl", POLY_ERROR_OPEN, "only one triangle"},
      {"inconsistent.off", POLY_ERROR_ORIENTATION, "inconsistent orientation"},
      {"nonmanifold_edge.off", POLY_ERROR_NONMANIFOLD, "shared by 4 triangles"},
      {"pinched_vertex.off", POLY_ERROR_NONMANIFOLD, "pinched vertex (0,0,0)"},
      {"degenerate.obj", POLY_ERROR_DEGENERATE, "degenerate triangle 6"},
      {"disconnected.obj", POLY_ERROR_DISCONNECTED, "connected component"},
      {"garbage.obj", POLY_ERROR_PARSE, "line 9: face references vertex 9"},
      {"truncated.stl", POLY_ERROR_PARSE, "truncated"},
      {"empty.off", POLY_ERROR_EMPTY, "no triangles"},
      {"unknown.xyz", POLY_ERROR_FILE, "unknown extension"},
      {"does_not_exist.stl", POLY_ERROR_FILE, "cannot open"},
  };
  char directory[1024], message[512];
  if (snprintf(directory, sizeof directory, "%s/tests/data/bad", repo_root) >= (int)sizeof directory) exit(100);
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    poly_shape shape = {0};
    const char *path = path_in(directory, cases[i].file);
    poly_status status = poly_shape_load(path, 1.0, &shape, message, sizeof message);
    printf("---- %s\n", cases[i].file);
    check_int("status", status, cases[i].status);
    check_contains("names the file", message, path);
    check_contains("names the defect", message, cases[i].keyword);
    check_int("failed load leaves no triangles", shape.num_triangles, 0);
    poly_shape_free(&shape);
  }
  poly_shape shape = {0};
  const char *inward = path_in(directory, "inward.off");
  printf("---- inward.off\n");
  check_int("status", poly_shape_load(inward, 1.0, &shape, message, sizeof message), POLY_OK);
  check_int("was flipped", shape.was_flipped, 1);
  check_relative("volume after flipping", shape.volume, 1.0, 1e-12);
  check_shape_invariants("inward.off", &shape);
  poly_shape_free(&shape);
}

static void write_ascii_stl(const char *path, const poly_mesh *mesh)
{
  FILE *file = fopen(path, "w");
  if (!file) {
    printf("FAIL cannot write %s\n", path);
    failures++;
    return;
  }
  fprintf(file, "solid cube\n");
  for (int t = 0; t < mesh->num_triangles; t++) {
    fprintf(file, "facet normal 0 0 0\n outer loop\n");
    for (int k = 0; k < 3; k++) {
      const double *p = mesh->vertices + 3 * mesh->triangles[3 * t + k];
      fprintf(file, "  vertex %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    fprintf(file, " endloop\nendfacet\n");
  }
  fprintf(file, "endsolid cube\n");
  fclose(file);
}

static void case_stl_ascii_binary(void)
{
  poly_mesh mesh;
  char message[512];
  check_int("binary cube read status", poly_mesh_read(shape_path("cube.stl"), &mesh, message, sizeof message), POLY_OK);
  check_int("binary STL vertices before welding", mesh.num_vertices, 36);
  const char *ascii_path = path_in(temp_dir, "cube_ascii.STL");  /* upper-case extension on purpose */
  write_ascii_stl(ascii_path, &mesh);
  check_int("weld removes", poly_mesh_weld(&mesh, 1e-9), 28);
  check_int("vertices after welding", mesh.num_vertices, 8);
  poly_mesh_free(&mesh);

  poly_shape binary = {0}, ascii = {0};
  check_int("binary load", load(shape_path("cube.stl"), 1.0, &binary), POLY_OK);
  check_int("ascii load", load(ascii_path, 1.0, &ascii), POLY_OK);
  check_int("same vertex count", ascii.num_vertices, binary.num_vertices);
  check_int("same triangle count", ascii.num_triangles, binary.num_triangles);
  check_int("identical vertices (memcmp)", memcmp(ascii.vertices, binary.vertices, sizeof(double) * 3 * 8), 0);
  check_int("identical triangles (memcmp)", memcmp(ascii.triangles, binary.triangles, sizeof(int) * 3 * 12), 0);
  check_close("same volume", ascii.volume, binary.volume, 0.0);
  for (int k = 0; k < 3; k++) check_close("same principal moment", ascii.principal_moments[k], binary.principal_moments[k], 0.0);
  poly_shape_free(&binary);
  poly_shape_free(&ascii);
}

static void check_unit_cube_file(const char *name, const char *text)
{
  poly_shape shape = {0};
  const char *path = path_in(temp_dir, name);
  write_file(path, text);
  printf("---- %s\n", name);
  check_int("load status", load(path, 1.0, &shape), POLY_OK);
  check_int("triangles", shape.num_triangles, 12);
  check_int("vertices", shape.num_vertices, 8);
  check_relative("volume", shape.volume, 1.0, 1e-12);
  check_relative("principal moment 1/6", shape.principal_moments[0], 1.0 / 6.0, 1e-12);
  poly_shape_free(&shape);
}

/* Quads, v/vt/vn corners, negative indices, CRLF, statements to ignore; unused vertex 9. */
static void case_obj_forms(void)
{
  check_unit_cube_file("forms.obj",
                       "# cube\r\nmtllib none.mtl\r\no cube\r\ng side\r\n"
                       "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\n"
                       "v 9 9 9\r\nvt 0 0\r\nvn 0 0 1\r\ns off\r\nusemtl stone\r\n"
                       "f 1/1/1 4/1/1 3/1/1 2/1/1\r\nf 5//1 6//1 7//1 8//1\r\nf 1/1 2/1 6/1 5/1\r\n"
                       "f -6 -2 -3 -7\r\nf 1 5 8 4\r\nf 2 3 7 6\r\n");
}

/* Comments everywhere, counts on the header line, quads with trailing colours. */
static void case_off_forms(void)
{
  check_unit_cube_file("forms.off",
                       "OFF 8 6 12 # counts on the header line\n# vertices\n"
                       "0 0 0\n1 0 0\n1 1 0\n0 1 0\n\n0 0 1\n1 0 1\n1 1 1 # corner\n0 1 1\n"
                       "4 0 3 2 1 255 0 0\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 0 4 7 3\n4 1 2 6 5\n");
}

static void case_parse_errors(void)
{
  static const struct {
    const char *name, *text;
    poly_status status;
    const char *keyword;
  } cases[] = {
      {"bad_number.obj", "v 0 0 0\n\nv 1 x 0\n", POLY_ERROR_PARSE, "line 3"},
      {"short_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", POLY_ERROR_PARSE, "line 4: face has 2 vertices"},
      {"zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", POLY_ERROR_PARSE, "line 4: bad face vertex index"},
      {"negative_index.obj", "v 0 0 0\nf -1 -2 -3\n", POLY_ERROR_PARSE, "line 2: face references vertex -2"},
      {"no_header.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", POLY_ERROR_PARSE, "missing 'OFF' header"},
      {"few_vertices.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", POLY_ERROR_PARSE, "file ends before vertex 3 of 3"},
      {"bad_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", POLY_ERROR_PARSE, "line 6: face 1 needs 3"},
      {"two_corners.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
       POLY_ERROR_PARSE, "line 6: unexpected 'endloop'"},
      {"unfinished.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", POLY_ERROR_PARSE,
       "line 3: file ends inside"},
      {"short.stl", "not an STL file\n", POLY_ERROR_PARSE, "truncated"},
      {"nothing.obj", "", POLY_ERROR_EMPTY, "empty"},
      {"pillow.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", POLY_ERROR_VOLUME, "zero volume"},
      {"only_vertices.obj", "v 0 0 0\nv 1 0 0\n", POLY_ERROR_EMPTY, "no triangles"},
  };
  char message[512];
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    poly_shape shape = {0};
    const char *path = path_in(temp_dir, cases[i].name);
    write_file(path, cases[i].text);
    printf("---- %s\n", cases[i].name);
    check_int("status", poly_shape_load(path, 1.0, &shape, message, sizeof message), cases[i].status);
    check_contains("names the file", message, path);
    check_contains("names the defect", message, cases[i].keyword);
    poly_shape_free(&shape);
  }
  poly_mesh mesh;
  memset(&mesh, 0, sizeof mesh);
  poly_shape shape = {0};
  check_int("build from an empty mesh", poly_shape_build(&mesh, 1.0, "x", &shape, message, sizeof message),
            POLY_ERROR_EMPTY);
  check_int("cube read", read_welded(shape_path("cube.stl"), &mesh), POLY_OK);
  check_int("build with scale -1", poly_shape_build(&mesh, -1.0, "x", &shape, message, sizeof message),
            POLY_ERROR_VOLUME);
  check_contains("scale message", message, "scale -1 must be positive");
  check_int("build with scale 1e-3", poly_shape_build(&mesh, 1e-3, "x", &shape, message, sizeof message), POLY_OK);
  check_relative("volume at scale 1e-3", shape.volume, 1e-9, 1e-12);
  check_relative("moment at scale 1e-3 (scales as s^5)", shape.principal_moments[0], 1e-15 / 6.0, 1e-12);
  poly_shape_free(&shape);
  poly_mesh_free(&mesh);
  check_int("tiny message buffer", poly_shape_load("missing.obj", 1.0, &shape, message, 8), POLY_ERROR_FILE);
  check_int("tiny message buffer is terminated", (long)strlen(message), 7);
}

static void case_weld(void)
{
  double vertices[] = {0, 0, 0, 1, 0, 0, 1e-12, 0, 0, 0, 1, 0, 1 + 1e-12, -1e-12, 0, 0, 1e-6, 0, 0, 0, 1};
  int triangles[] = {2, 4, 3, 0, 1, 5, 6, 2, 4};
  poly_mesh mesh;
  mesh.num_vertices = 7;
  mesh.num_triangles = 3;
  mesh.vertices = (double *)malloc(sizeof vertices);
  mesh.triangles = (int *)malloc(sizeof triangles);
  if (!mesh.vertices || !mesh.triangles) exit(100);
  memcpy(mesh.vertices, vertices, sizeof vertices);
  memcpy(mesh.triangles, triangles, sizeof triangles);
  /* Tolerance 1e-9 * diagonal sqrt(3): merges the 1e-12 copies, keeps the 1e-6 neighbour. */
  check_int("removed", poly_mesh_weld(&mesh, 1e-9), 2);
  check_int("vertices", mesh.num_vertices, 5);
  const int expected[9] = {0, 1, 2, 0, 1, 3, 4, 0, 1};
  for (int i = 0; i < 9; i++) check_int("renumbered corner", mesh.triangles[i], expected[i]);
  check_close("kept the first copy's position", mesh.vertices[3], 1.0, 0.0);
  check_close("1e-6 neighbour kept", mesh.vertices[10], 1e-6, 0.0);
  check_int("second weld removes nothing", poly_mesh_weld(&mesh, 1e-9), 0);
  poly_mesh_free(&mesh);

  /* Far from the origin the tolerance is still relative to the mesh size. */
  poly_mesh far;
  check_int("icosphere read", read_welded(shape_path("icosphere_5120.off"), &far), POLY_OK);
  for (int i = 0; i < 3 * far.num_vertices; i++) far.vertices[i] += 1e6;
  check_int("shifted icosphere weld removes nothing", poly_mesh_weld(&far, 1e-9), 0);
  poly_mesh_free(&far);
}

static void check_eigen(const char *name, const double matrix[9], const double expected_values[3])
{
  double values[3], vectors[9];
  poly_symmetric_eigen3(matrix, values, vectors);
  double scale = fmax(fabs(values[0]), fabs(values[2])) + 1e-300, worst = 0.0, worst_orthogonality = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double rebuilt = 0.0, gram = 0.0;
      for (int k = 0; k < 3; k++) {
        rebuilt += vectors[3 * i + k] * values[k] * vectors[3 * j + k];
        gram += vectors[3 * k + i] * vectors[3 * k + j];
      }
      worst = fmax(worst, fabs(rebuilt - matrix[3 * i + j]) / scale);
      worst_orthogonality = fmax(worst_orthogonality, fabs(gram - (i == j)));
    }
  printf("---- %s\n", name);
  for (int k = 0; k < 3; k++) check_close("eigenvalue", values[k], expected_values[k], 1e-14 * scale);
  check_close("|V diag(l) V^T - A| / |l|max", worst, 0.0, 1e-14);
  check_close("|V^T V - 1|", worst_orthogonality, 0.0, 1e-14);
  check_close("det V", determinant3(vectors), 1.0, 1e-14);
}

static void case_eigen(void)
{
  const double diagonal[9] = {3, 0, 0, 0, 1, 0, 0, 0, 2}, zero[9] = {0}, sphere[9] = {2, 0, 0, 0, 2, 0, 0, 0, 2};
  check_eigen("diagonal", diagonal, (const double[3]){1, 2, 3});
  check_eigen("zero", zero, (const double[3]){0, 0, 0});
  check_eigen("isotropic", sphere, (const double[3]){2, 2, 2});
  double values[3], vectors[9];
  poly_symmetric_eigen3(sphere, values, vectors);
  check_close("isotropic keeps the identity: V[0][0]", vectors[0], 1.0, 0.0);
  /* R diag(l) R^T for a generic rotation, with a distinct and a repeated spectrum. */
  const double axis[3] = {0.2, -1.0, 0.7};
  const double spectra[2][3] = {{-1.5, 0.25, 4.0}, {1.0, 1.0, 7.0}};
  double r[9];
  rotation(axis, 1.1, r);
  for (int s = 0; s < 2; s++) {
    double m[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        m[3 * i + j] = 0.0;
        for (int k = 0; k < 3; k++) m[3 * i + j] += r[3 * i + k] * spectra[s][k] * r[3 * j + k];
      }
    check_eigen(s == 0 ? "rotated distinct" : "rotated repeated", m, spectra[s]);
  }
}

static void case_free_safety(void)
{
  poly_shape shape = {0};
  poly_mesh mesh = {0, 0, NULL, NULL};
  char message[256];
  poly_shape_free(&shape);
  poly_shape_free(&shape);
  poly_shape_free(NULL);
  poly_mesh_free(&mesh);
  poly_mesh_free(NULL);
  check_int("build from an empty mesh", poly_shape_build(&mesh, 1.0, "empty", &shape, message, sizeof message),
            POLY_ERROR_EMPTY);
  check_contains("empty message", message, "'empty' is empty");
  poly_shape_free(&shape);
  check_int("load into the same struct twice", load(shape_path("cube.stl"), 1.0, &shape), POLY_OK);
  poly_shape_free(&shape);
  check_int("then a failing load", poly_shape_load(shape_path("nope.obj"), 1.0, &shape, message, sizeof message),
            POLY_ERROR_FILE);
  check_int("nothing left after the failure", shape.num_vertices, 0);
  poly_shape_free(&shape);
  /* Out-of-range indices handed to build directly are reported, not dereferenced. */
  double vertices[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  int triangles[3] = {0, 1, 5};
  poly_mesh bad = {3, 1, vertices, triangles};
  check_int("index out of range", poly_shape_build(&bad, 1.0, "bad", &shape, message, sizeof message), POLY_ERROR_PARSE);
  check_contains("out of range message", message, "references vertex 5");
}

static char *read_all(const char *path, long *size)
{
  FILE *file = fopen(path, "rb");
  char *data = NULL;
  if (file && fseek(file, 0, SEEK_END) == 0 && (*size = ftell(file)) > 0 && fseek(file, 0, SEEK_SET) == 0 &&
      (data = (char *)malloc((size_t)*size)) != NULL && fread(data, 1, (size_t)*size, file) != (size_t)*size) {
    free(data);
    data = NULL;
  }
  if (file) fclose(file);
  return data;
}

/* Some exporters start binary headers with "solid": the size rule must win. */
static void case_stl_solid_header(void)
{
  long size = 0;
  char *data = read_all(shape_path("cube.stl"), &size);
  const char *path = path_in(temp_dir, "solid_header.stl");
  FILE *out = fopen(path, "wb");
  if (!data || size < 84 || !out) exit(100);
  memcpy(data, "solid cube", 10);
  fwrite(data, 1, (size_t)size, out);
  fclose(out);
  free(data);
  poly_shape shape = {0};
  check_int("binary STL with a 'solid' header", load(path, 1.0, &shape), POLY_OK);
  check_int("triangles", shape.num_triangles, 12);
  check_relative("volume", shape.volume, 1.0, 1e-12);
  poly_shape_free(&shape);
}

/* Truncated and byte-mutated copies of valid files: every load must either
 * succeed with a sane shape or fail with a message naming the file (run it
 * under -fsanitize=address to also catch out-of-bounds access and leaks). */
static void case_mutations(void)
{
  static const char *files[4] = {"cube.stl", "schoenhardt.stl", "rock_40.obj", "box_1x2x3.off"};
  static const char replacements[] = "0-9 \n/x#.e\0";
  unsigned long long random_state = 12345;
  int insane = 0, loaded = 0, rejected = 0;
  for (int f = 0; f < 4; f++) {
    long size = 0;
    char *original = read_all(shape_path(files[f]), &size);
    if (!original) {
      printf("FAIL cannot read %s\n", files[f]);
      failures++;
      continue;
    }
    char name[64];
    snprintf(name, sizeof name, "mutated_%s", files[f]);
    const char *path = path_in(temp_dir, name);
    for (int trial = 0; trial < 150; trial++) {
      random_state = random_state * 6364136223846793005ull + 1442695040888963407ull;
      unsigned long long r = random_state >> 17;
      long length = trial % 3 == 0 ? (long)(r % (unsigned long long)size) : size;
      char *copy = (char *)malloc((size_t)size);
      if (!copy) exit(100);
      memcpy(copy, original, (size_t)size);
      if (trial % 3 != 0) copy[r % (unsigned long long)size] = replacements[(r >> 20) % (sizeof replacements - 1)];
      FILE *out = fopen(path, "wb");
      if (!out || fwrite(copy, 1, (size_t)length, out) != (size_t)length) exit(100);
      fclose(out);
      free(copy);
      poly_shape shape = {0};
      char message[512] = "";
      poly_status status = poly_shape_load(path, 1.0, &shape, message, sizeof message);
      if (status == POLY_OK) {
        loaded++;
        insane += !(shape.num_triangles > 0 && shape.volume > 0 && shape.bounding_radius > 0);
      } else {
        rejected++;
        insane += strstr(message, path) == NULL || shape.num_triangles != 0;
      }
      poly_shape_free(&shape);
    }
    free(original);
  }
  printf("     %d mutated files loaded, %d rejected\n", loaded, rejected);
  check_int("loads with an insane shape or an unnamed error", insane, 0);
  check_at_least("mutations rejected", rejected, 100);
}

typedef struct test_case {
  const char *name;
  void (*run)(void);
} test_case;

static const test_case cases[] = {
    {"cube", case_cube},
    {"tetrahedron", case_tetrahedron},
    {"box", case_box},
    {"box_rotated", case_box_rotated},
    {"icospheres", case_icospheres},
    {"schoenhardt", case_schoenhardt},
    {"rocks", case_rocks},
    {"bad_meshes", case_bad_meshes},
    {"stl_ascii_binary", case_stl_ascii_binary},
    {"obj_forms", case_obj_forms},
    {"off_forms", case_off_forms},
    {"parse_errors", case_parse_errors},
    {"weld", case_weld},
    {"eigen", case_eigen},
    {"free_safety", case_free_safety},
    {"stl_solid_header", case_stl_solid_header},
    {"mutations", case_mutations},
    {"degenerate_axes", case_degenerate_axes},
};

int main(int argc, char **argv)
{
  size_t count = sizeof cases / sizeof cases[0];
  if (argc < 2) {
    fprintf(stderr, "usage: %s CASE|--list [REPO_ROOT [TMPDIR]]\n", argv[0]);
    return 2;
  }
  if (strcmp(argv[1], "--list") == 0) {
    for (size_t i = 0; i < count; i++) printf("%s\n", cases[i].name);
    return 0;
  }
  if (argc > 2) repo_root = argv[2];
  if (argc > 3) temp_dir = argv[3];
  for (size_t i = 0; i < count; i++)
    if (strcmp(argv[1], cases[i].name) == 0) {
      cases[i].run();
      printf("%s: %d failed check(s)\n", cases[i].name, failures);
      return failures > 100 ? 100 : failures;
    }
  fprintf(stderr, "unknown case '%s'\n", argv[1]);
  return 2;
}
