/* Loads shape files with poly_shape_load and checks the outcome (tools/fuzz_shapes.py,
 * tests/test_fuzz_readers.py). Built with -fsanitize=address,undefined.
 *
 *   fuzz_shapes_driver [--timeout SECONDS] [--scale S] [--list FILE] [PATH ...]
 *
 * For each path it prints "FILE path" (flushed, so a crash names the file), then one of
 *   OK volume radius           POLY_OK and every checked quantity finite and positive
 *   ERROR status message       a non-OK status with a non-empty message
 *   BAD what                   POLY_OK with a non-finite / non-positive quantity, or an error without message
 *   NONPHYSICAL what           POLY_OK, all finite, but principal moments no solid body can have
 * A file that takes longer than the timeout prints "TIMEOUT path" and aborts (exit 3). */
#define _POSIX_C_SOURCE 200809L
#include "poly_shape.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *current_path = "";

static void on_alarm(int signal_number)
{
  (void)signal_number;
  static const char prefix[] = "TIMEOUT ";
  if (write(1, prefix, sizeof prefix - 1) < 0 || write(1, current_path, strlen(current_path)) < 0 ||
      write(1, "\n", 1) < 0) {
  }
  _exit(3);
}

static int finite_array(const double *values, int count)
{
  for (int i = 0; i < count; ++i)
    if (!isfinite(values[i])) return 0;
  return 1;
}

static const char *check_shape(const poly_shape *shape)
{
  if (!(isfinite(shape->volume) && shape->volume > 0.0)) return "volume not finite and positive";
  if (!(isfinite(shape->bounding_radius) && shape->bounding_radius > 0.0)) return "bounding radius not finite and positive";
  for (int k = 0; k < 3; ++k)
    if (!isfinite(shape->principal_moments[k])) return "principal moment not finite";
  if (!finite_array(shape->centre_of_mass, 3)) return "centre of mass not finite";
  if (!finite_array(shape->principal_axes, 9)) return "principal axes not finite";
  if (shape->num_vertices < 4 || shape->num_triangles < 4 || shape->num_edges < 6) return "fewer than a tetrahedron";
  if (!finite_array(shape->vertices, 3 * shape->num_vertices)) return "vertex not finite";
  if (!finite_array(shape->face_normals, 3 * shape->num_triangles)) return "face normal not finite";
  for (int i = 0; i < 3 * shape->num_triangles; ++i)
    if (shape->triangles[i] < 0 || shape->triangles[i] >= shape->num_vertices) return "triangle index out of range";
  if (2 * shape->num_edges != 3 * shape->num_triangles) return "edge count is not 3/2 of the triangle count";
  return NULL;
}

/* A solid body's principal moments are positive and obey I0 + I1 >= I2 (ascending). A closed, oriented but
 * self-intersecting surface can break both; such a shape is "NONPHYSICAL". */
static const char *check_physical(const poly_shape *shape)
{
  const double *m = shape->principal_moments;
  if (!(m[0] > 0.0 && m[1] > 0.0 && m[2] > 0.0)) return "principal moment not positive";
  if (!(m[0] + m[1] >= m[2] * (1.0 - 1e-9))) return "principal moments violate I0 + I1 >= I2";
  return NULL;
}

static void load(const char *path, double scale, unsigned timeout)
{
  current_path = path;
  printf("FILE %s\n", path);
  fflush(stdout);
  alarm(timeout);
  poly_shape shape;
  memset(&shape, 0, sizeof shape);
  char message[512];
  message[0] = '\0';
  poly_status status = poly_shape_load(path, scale, &shape, message, sizeof message);
  alarm(0);
  if (status == POLY_OK) {
    const char *problem = check_shape(&shape);
    const char *physical = problem ? NULL : check_physical(&shape);
    if (physical)
      printf("NONPHYSICAL %s (volume %.17g, moments %.17g %.17g %.17g)\n", physical, shape.volume,
             shape.principal_moments[0], shape.principal_moments[1], shape.principal_moments[2]);
    else if (problem)
      printf("BAD %s (volume %.17g, radius %.17g, moments %.17g %.17g %.17g)\n", problem, shape.volume,
             shape.bounding_radius, shape.principal_moments[0], shape.principal_moments[1],
             shape.principal_moments[2]);
    else
      printf("OK %.17g %.17g\n", shape.volume, shape.bounding_radius);
    poly_shape_free(&shape);
  } else if (message[0] == '\0' || memchr(message, '\0', sizeof message) == NULL) {
    printf("BAD status %d without a message\n", (int)status);
  } else {
    for (char *c = message; *c; ++c)
      if (*c == '\n') *c = ' ';
    printf("ERROR %d %s\n", (int)status, message);
  }
  fflush(stdout);
}

int main(int argc, char **argv)
{
  unsigned timeout = 5;
  double scale = 1.0;
  signal(SIGALRM, on_alarm);
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--timeout") == 0 && i + 1 < argc) {
      timeout = (unsigned)ceil(atof(argv[++i]));
    } else if (strcmp(argv[i], "--scale") == 0 && i + 1 < argc) {
      scale = atof(argv[++i]);
    } else if (strcmp(argv[i], "--list") == 0 && i + 1 < argc) {
      FILE *list = fopen(argv[++i], "r");
      if (!list) {
        perror(argv[i]);
        return 2;
      }
      char line[4096];
      while (fgets(line, sizeof line, list)) {
        line[strcspn(line, "\n")] = '\0';
        if (line[0]) load(line, scale, timeout);
      }
      fclose(list);
    } else {
      load(argv[i], scale, timeout);
    }
  }
  return 0;
}
