/* CPU narrow-phase benchmark: cost of one poly_overlap call per particle pair.
 *
 *   bash tools/bench_overlap.sh [poses] [repeats]      (builds this file and runs it)
 *   bench_overlap SHAPES_DIR [poses] [repeats]
 *
 * For each shape, `poses` pairs of that shape are placed as in a packed bed:
 * both orientations uniformly random, B's centre along a random direction at
 * the distance (bisected on the double-precision overlap) where the overlap
 * volume is a target fraction of the particle volume, drawn log-uniformly in
 * [0.1 %, 3 %]. Each configuration (double/single, triangle filter on/off)
 * times the whole pose set, repeated until a repeat takes >= 20 ms; the table
 * shows the median over `repeats` repeats, in microseconds per call.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "poly_overlap.h"

static const char *const SHAPE_FILES[] = {"schoenhardt.stl", "cube.stl",  "icosphere_80.off",
                                          "icosphere_320.off", "icosphere_1280.off", "rock_10.obj",
                                          "rock_40.obj", "rock_70.obj", "rock_1000.obj"};
#define NUM_DEFAULT_SHAPES (int)(sizeof SHAPE_FILES / sizeof SHAPE_FILES[0])
#define MAX_SHAPES 32

static void random_direction(double d[3])
{
  double z = 2.0 * uniform() - 1.0, phi = 2.0 * PI * uniform(), r = sqrt(1.0 - z * z);
  d[0] = r * cos(phi); d[1] = r * sin(phi); d[2] = z;
}

typedef struct bench_shape {
  poly_shape shape;
  poly_shape_view_d view_d;
  poly_shape_view_f view_f;
} bench_shape;

static volatile double sink;

/* One pass over the pose set in one configuration. */
typedef struct pose_set {
  const bench_shape *shape;
  const poly_pose *poses_a, *poses_b;
  int num_poses, single;
  poly_overlap_workspace_d *ws_d;
  poly_overlap_workspace_f *ws_f;
} pose_set;

static void run_pose_set(void *context)
{
  const pose_set *set = (const pose_set *)context;
  poly_overlap_result result;
  double sum = 0.0;
  for (int p = 0; p < set->num_poses; p++) {
    if (set->single)
      poly_overlap_f(&set->shape->view_f, &set->poses_a[p], &set->shape->view_f, &set->poses_b[p], set->ws_f, &result);
    else poly_overlap_d(&set->shape->view_d, &set->poses_a[p], &set->shape->view_d, &set->poses_b[p], set->ws_d, &result);
    sum += result.volume;
  }
  sink = sum;
}

/* Median over `repeats` of the time per call (microseconds) of the whole pose set. */
static double time_configuration(const bench_shape *s, const poly_pose *poses_a, const poly_pose *poses_b,
                                 int num_poses, int single, int use_filter, poly_overlap_workspace_d *ws_d,
                                 poly_overlap_workspace_f *ws_f, int repeats)
{
  ws_d->use_filter = use_filter;
  ws_f->use_filter = use_filter;
  pose_set set = {s, poses_a, poses_b, num_poses, single, ws_d, ws_f};
  return median_time_us(run_pose_set, &set, num_poses, repeats, NULL);
}

int main(int argc, char **argv)
{
  int num_poses, repeats;
  if (read_arguments(argc, argv, &num_poses, &repeats, 1)) return 2;

  // BENCH_SHAPE_FILES="a.obj b.off ...": these files (relative to SHAPES_DIR unless absolute) instead of the
  // reference shapes, e.g. the simplified shapes of tools/make_shape.py (doc/shapes_from_clumps.md).
  const char *files[MAX_SHAPES];
  int num_shapes = 0;
  static char listed[8192];
  const char *chosen = getenv("BENCH_SHAPE_FILES");
  if (chosen && *chosen) {
    snprintf(listed, sizeof listed, "%s", chosen);
    for (char *word = strtok(listed, " "); word && num_shapes < MAX_SHAPES; word = strtok(NULL, " "))
      files[num_shapes++] = word;
  } else {
    for (int i = 0; i < NUM_DEFAULT_SHAPES; i++) files[num_shapes++] = SHAPE_FILES[i];
  }
  bench_shape shapes[MAX_SHAPES];
  int max_vertices = 0, max_triangles = 0;
  for (int i = 0; i < num_shapes; i++) {
    if (load_shape(argv[1], files[i], 1.0, &shapes[i].shape)) return 1;
    shapes[i].view_d = poly_shape_view_of(&shapes[i].shape);
    if (poly_shape_view_make_f(&shapes[i].shape, &shapes[i].view_f) != 0) return 1;
    if (shapes[i].shape.num_vertices > max_vertices) max_vertices = shapes[i].shape.num_vertices;
    if (shapes[i].shape.num_triangles > max_triangles) max_triangles = shapes[i].shape.num_triangles;
  }
  poly_overlap_workspace_d ws_d;
  poly_overlap_workspace_f ws_f;
  if (poly_overlap_workspace_create_d(&ws_d, max_vertices, max_triangles) ||
      poly_overlap_workspace_create_f(&ws_f, max_vertices, max_triangles))
    return 1;

  poly_pose *poses_a = (poly_pose *)malloc(sizeof(poly_pose) * (size_t)num_poses);
  poly_pose *poses_b = (poly_pose *)malloc(sizeof(poly_pose) * (size_t)num_poses);
  printf("poly_overlap per pair, %d poses per shape (overlap 0.1-3 %% of the particle volume), "
         "median of %d repeats\n\n", num_poses, repeats);
  printf("| shape | triangles | mean V/V_p | double, filter (us) | double, no filter (us) | single, filter (us) | "
         "single, no filter (us) | filter speed-up (double) |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  double total_start = now();
  for (int i = 0; i < num_shapes; i++) {
    const bench_shape *s = &shapes[i];
    double volume = s->shape.volume, reach = 2.0 * s->shape.bounding_radius, fraction_sum = 0.0;
    ws_d.use_filter = 1;
    for (int p = 0; p < num_poses; p++) {
      double direction[3];
      memset(&poses_a[p], 0, sizeof poses_a[p]);
      random_quaternion(poses_a[p].quaternion);
      random_quaternion(poses_b[p].quaternion);
      random_direction(direction);
      double target = volume * pow(10.0, -3.0 + log10(30.0) * uniform());
      double near = 0.0, far = reach;
      poly_overlap_result result;
      for (int iteration = 0; iteration < 50; iteration++) {
        double middle = 0.5 * (near + far);
        for (int k = 0; k < 3; k++) poses_b[p].position[k] = middle * direction[k];
        poly_overlap_d(&s->view_d, &poses_a[p], &s->view_d, &poses_b[p], &ws_d, &result);
        if (result.volume > target) near = middle;
        else far = middle;
      }
      for (int k = 0; k < 3; k++) poses_b[p].position[k] = near * direction[k];
      poly_overlap_d(&s->view_d, &poses_a[p], &s->view_d, &poses_b[p], &ws_d, &result);
      fraction_sum += result.volume / volume;
    }
    double t[4];
    for (int c = 0; c < 4; c++)
      t[c] = time_configuration(s, poses_a, poses_b, num_poses, c / 2, !(c % 2), &ws_d, &ws_f, repeats);
    const char *base = strrchr(files[i], '/') ? strrchr(files[i], '/') + 1 : files[i];
    const char *name = strrchr(base, '.') ? strrchr(base, '.') : base + strlen(base);
    printf("| %.*s | %d | %.2f %% | %.2f | %.2f | %.2f | %.2f | %.1fx |\n", (int)(name - base), base,
           s->shape.num_triangles, 100.0 * fraction_sum / num_poses, t[0], t[1], t[2], t[3],
           t[1] / t[0]);
    fflush(stdout);
  }
  printf("\ntotal %.1f s\n", now() - total_start);

  free(poses_a);
  free(poses_b);
  poly_overlap_workspace_destroy_d(&ws_d);
  poly_overlap_workspace_destroy_f(&ws_f);
  for (int i = 0; i < num_shapes; i++) {
    poly_shape_view_free_f(&shapes[i].view_f);
    poly_shape_free(&shapes[i].shape);
  }
  return 0;
}
