/* Cylinder-wall benchmark: cost of one poly_cylinder_overlap call (src/poly_cylinder.h) per particle-wall
 * contact.
 *
 *   bash tools/bench_cylinder.sh [poses] [repeats]      (builds this file and runs it)
 *   bench_cylinder SHAPES_DIR [poses] [repeats] [shape]
 *
 * With a shape (a file name of examples/shapes without its extension), only that one, its poses drawn first.
 * With 0 repeats, one untimed pass over each side's poses: the instructions per call, the same on every run,
 * are then those counted by
 *   valgrind --tool=callgrind --toggle-collect=run_contacts bench_cylinder examples/shapes 32 0 cube
 * divided by 64 (2 sides of 32 poses).
 *
 * For each shape (at scale 1; d its volume-equivalent diameter), `poses` contacts with a zcylinder of
 * radius R = 10 d about the z axis, as fix wall/polyhedral computes them: the polygon's facet count from the
 * fix's default sagitta (1e-6 of the particle's bounding radius), a random orientation, the centre at a
 * random angle about the axis and a random height, its distance from the axis bisected so that the overlap
 * volume is a target fraction of the particle volume, drawn log-uniformly in [0.1 %, 3 %]. Both sides of the
 * wall: the drum (the particle inside, the solid r > R) and the pillar (outside, the solid r < R). The pose
 * set is timed whole, repeated until a repeat takes >= 20 ms; the table shows the fastest and the median
 * of `repeats` repeats, in microseconds per call (on a shared machine the fastest is the one to compare).
 * `sum V` (the summed overlap volumes, relative to the particle volume) lets two builds be compared for the
 * same results on the same poses.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <string.h>

#include "bench_common.h"
#include "poly_cylinder.h"

static const char *const SHAPE_FILES[] = {"schoenhardt.stl", "cube.stl",       "tetrahedron.obj",
                                          "rock_10.obj",     "rock_40.obj",    "rock_70.obj",
                                          "icosphere_80.off", "icosphere_320.off", "icosphere_1280.off",
                                          "rock_1000.obj"};
#define NUM_SHAPES (int)(sizeof SHAPE_FILES / sizeof SHAPE_FILES[0])

static const double DRUM_DIAMETERS = 10.0; /* R / d */
static const double SAGITTA = 1e-6;        /* of the bounding radius: fix wall/polyhedral's default */

typedef struct contact {
  double rotation[9], position[3];
} contact;

static volatile double sink;

/* One pass over the contacts of one shape and side (kept out of line for callgrind's --toggle-collect). */
typedef struct contact_set {
  const poly_shape_view_d *view;
  const contact *contacts;
  int count, facets;
  double radius;
} contact_set;

__attribute__((noinline)) static void run_contacts(void *context)
{
  static const double axis[2] = {0.0, 0.0};
  const contact_set *set = (const contact_set *)context;
  poly_overlap_result result;
  double sum = 0.0;
  for (int p = 0; p < set->count; p++) {
    poly_cylinder_overlap(set->view, set->contacts[p].rotation, set->contacts[p].position, axis, set->radius,
                          set->facets, &result);
    sum += result.volume;
  }
  sink = sum;
}

/* `count` contacts of the shape with the side `drum` of the cylinder; returns the summed overlap volume. */
static double make_contacts(const poly_shape_view_d *view, double particle_volume, double radius, int facets,
                            int drum, contact *contacts, int count)
{
  static const double axis[2] = {0.0, 0.0};
  double reach = view->bounding_radius, total = 0.0;
  for (int p = 0; p < count; p++) {
    double q[4], angle = 2.0 * PI * uniform(), height = 2.0 * uniform() - 1.0;
    random_quaternion(q);
    poly_quat_to_matrix(q, contacts[p].rotation);
    double target = particle_volume * pow(10.0, -3.0 + log10(30.0) * uniform());
    /* The overlap grows as the centre moves towards the shell from the free side. */
    double free_side = drum ? radius - reach : radius + reach, shell = radius;
    poly_overlap_result result;
    for (int iteration = 0; iteration < 60; iteration++) {
      double middle = 0.5 * (free_side + shell);
      double position[3] = {middle * cos(angle), middle * sin(angle), height};
      poly_cylinder_overlap(view, contacts[p].rotation, position, axis, radius, facets, &result);
      if (result.volume > target) shell = middle;
      else free_side = middle;
    }
    double distance = 0.5 * (free_side + shell);
    contacts[p].position[0] = distance * cos(angle);
    contacts[p].position[1] = distance * sin(angle);
    contacts[p].position[2] = height;
    poly_cylinder_overlap(view, contacts[p].rotation, contacts[p].position, axis, radius, facets, &result);
    total += result.volume;
  }
  return total;
}

int main(int argc, char **argv)
{
  int num_poses, repeats;
  if (read_arguments(argc, argv, &num_poses, &repeats, 0)) return 2;

  contact *contacts = (contact *)malloc(sizeof(contact) * (size_t)num_poses);
  printf("poly_cylinder_overlap per contact, zcylinder R = %g d (d: volume-equivalent diameter), sagitta %g of "
         "the bounding radius, %d poses per shape and side (overlap 0.1-3 %% of the particle volume), fastest "
         "and median of %d repeats\n\n", DRUM_DIAMETERS, SAGITTA, num_poses, repeats);
  printf("| shape | triangles | facets N | drum: mean V/V_p | drum, fastest (us) | drum, median (us) | "
         "pillar: mean V/V_p | pillar, fastest (us) | pillar, median (us) | sum V/V_p drum, pillar |\n");
  printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  double total_start = now();
  const char *only = argc > 4 ? argv[4] : NULL;
  for (int i = 0; i < NUM_SHAPES; i++) {
    const char *name = strrchr(SHAPE_FILES[i], '.');
    if (only && (strlen(only) != (size_t)(name - SHAPE_FILES[i]) || strncmp(only, SHAPE_FILES[i], strlen(only))))
      continue;
    poly_shape shape;
    if (load_shape(argv[1], SHAPE_FILES[i], 1.0, &shape)) return 1;
    poly_shape_view_d view = poly_shape_view_of(&shape);
    double diameter = cbrt(6.0 * shape.volume / PI), radius = DRUM_DIAMETERS * diameter;
    int facets = poly_cylinder_facets(radius, SAGITTA * view.bounding_radius);
    double sum[2], median[2], fastest[2];
    for (int drum = 1; drum >= 0; drum--) {
      sum[!drum] = make_contacts(&view, shape.volume, radius, facets, drum, contacts, num_poses) / shape.volume;
      contact_set set = {&view, contacts, num_poses, facets, radius};
      median[!drum] = fastest[!drum] = 0.0;
      if (repeats == 0) run_contacts(&set);
      else median[!drum] = median_time_us(run_contacts, &set, num_poses, repeats, &fastest[!drum]);
    }
    printf("| %.*s | %d | %d | %.2f %% | %.2f | %.2f | %.2f %% | %.2f | %.2f | %.12f, %.12f |\n",
           (int)(name - SHAPE_FILES[i]), SHAPE_FILES[i], shape.num_triangles, facets, 100.0 * sum[0] / num_poses,
           fastest[0], median[0], 100.0 * sum[1] / num_poses, fastest[1], median[1], sum[0], sum[1]);
    fflush(stdout);
    poly_shape_free(&shape);
  }
  printf("\ntotal %.1f s\n", now() - total_start);
  free(contacts);
  return 0;
}
