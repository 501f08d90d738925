/* Instruction count of poly_overlap_d per call, for cost comparisons on shared
 * machines where wall time is noise (callgrind counts instructions, the same
 * on every run of the same binary):
 *
 *   gcc -std=c11 -O2 -g -Isrc tools/overlap_instructions.c src/poly_overlap.c src/poly_shape.c \
 *       src/poly_mesh_read.c src/poly_convex.c -lm -o /tmp/overlap_instructions
 *   valgrind --tool=callgrind --toggle-collect='measure*' --callgrind-out-file=/tmp/cg.out \
 *       /tmp/overlap_instructions examples/shapes/cube.stl 200 [deep|flush|shallow|resting] [second]
 *   callgrind_annotate /tmp/cg.out | head -30      (PROGRAM TOTALS divided by the pair count; per function)
 *
 * Pairs of one shape (fixed seed), B's centre along a random direction:
 * - deep (default): both orientations random, 1.1-1.7 bounding radii away;
 * - flush: both at the identity, B moved along x (every pair has flush side faces);
 * - shallow: both orientations random, at the distance (bisected) where the
 *   overlap is 0.1-3 % of the particle volume (log-uniform), the poses of
 *   tools/bench_overlap.c;
 * - resting: A at the identity, B above it along z turned about z by a random
 *   angle and tilted by up to 0.01 rad, moved sideways by up to a tenth of the
 *   size, 1e-4 of the size deep (for cubes: a face resting on a face, as in a
 *   pile).
 * Only the calls in measure() are counted (--toggle-collect), not the set-up.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_overlap.h"

static unsigned long long state = 12345;

static double uniform(void)
{
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(state >> 11) * (1.0 / 9007199254740992.0);
}

static void random_quaternion(double *q)
{
  double norm = 0.0;
  for (int k = 0; k < 4; k++) {
    q[k] = 2.0 * uniform() - 1.0;
    norm += q[k] * q[k];
  }
  for (int k = 0; k < 4; k++) q[k] /= sqrt(norm);
}

__attribute__((noinline)) static double measure(const poly_shape_view_d *view, const poly_pose *a,
                                                const poly_pose *b, int pairs, poly_overlap_workspace_d *ws,
                                                int *smoothed)
{
  double volume = 0.0;
  for (int p = 0; p < pairs; p++) {
    poly_overlap_result result;
    poly_overlap_d(view, &a[p], view, &b[p], ws, &result);
    volume += result.volume;
    *smoothed += result.smoothed;
  }
  return volume;
}

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: %s SHAPE_FILE PAIRS [deep|flush|shallow|resting] [second]\n", argv[0]);
    return 2;
  }
  poly_shape shape;
  char message[512];
  if (poly_shape_load(argv[1], 1.0, &shape, message, sizeof message) != POLY_OK) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  int pairs = atoi(argv[2]);
  const char *mode = argc > 3 ? argv[3] : "deep"; /* deep | flush | shallow | resting */
  int flush = !strcmp(mode, "flush"), shallow = !strcmp(mode, "shallow"), resting = !strcmp(mode, "resting");
  poly_shape_view_d view = poly_shape_view_of(&shape);
  poly_overlap_workspace_d ws;
  if (poly_overlap_workspace_create_d(&ws, shape.num_vertices, shape.num_triangles) != 0) return 1;
  ws.want_second_moment = argc > 4 && !strcmp(argv[4], "second"); /* as the rocking damping asks */
  poly_pose *poses_a = calloc((size_t)pairs, sizeof(poly_pose)), *poses_b = calloc((size_t)pairs, sizeof(poly_pose));
  for (int p = 0; p < pairs; p++) {
    poly_pose *a = &poses_a[p], *b = &poses_b[p];
    a->quaternion[0] = b->quaternion[0] = 1.0;
    double direction[3] = {1.0, 0.0, 0.0}, distance = 1.0 - 0.01 * uniform();
    if (!flush) {
      random_quaternion(a->quaternion);
      random_quaternion(b->quaternion);
      double norm = 0.0;
      for (int k = 0; k < 3; k++) {
        direction[k] = 2.0 * uniform() - 1.0;
        norm += direction[k] * direction[k];
      }
      for (int k = 0; k < 3; k++) direction[k] /= sqrt(norm);
      distance = 2.0 * shape.bounding_radius * (0.55 + 0.3 * uniform());
    }
    if (resting) {
      double turn = 6.283185307179586 * uniform(), tilt = 0.01 * uniform(), tilt_axis = 6.283185307179586 * uniform();
      double qz[4] = {cos(0.5 * turn), 0, 0, sin(0.5 * turn)};
      double qt[4] = {cos(0.5 * tilt), sin(0.5 * tilt) * cos(tilt_axis), sin(0.5 * tilt) * sin(tilt_axis), 0};
      b->quaternion[0] = qt[0] * qz[0] - qt[3] * qz[3];
      b->quaternion[1] = qt[1] * qz[0] + qt[2] * qz[3];
      b->quaternion[2] = qt[2] * qz[0] - qt[1] * qz[3];
      b->quaternion[3] = qt[3] * qz[0] + qt[0] * qz[3];
      double size = 2.0 * shape.bounding_radius / sqrt(3.0);
      direction[0] = 0.1 * size * (2 * uniform() - 1);
      direction[1] = 0.1 * size * (2 * uniform() - 1);
      direction[2] = size * (1.0 - 1e-4);
      distance = 1.0;
    }
    if (shallow) {
      double target = shape.volume * pow(10.0, -3.0 + log10(30.0) * uniform());
      double near = 0.0, far = 2.0 * shape.bounding_radius;
      for (int iteration = 0; iteration < 50; iteration++) {
        double middle = 0.5 * (near + far);
        for (int k = 0; k < 3; k++) b->position[k] = middle * direction[k];
        poly_overlap_result result;
        poly_overlap_d(&view, a, &view, b, &ws, &result);
        if (result.volume > target) near = middle;
        else far = middle;
      }
      distance = near;
    }
    for (int k = 0; k < 3; k++) b->position[k] = distance * direction[k];
  }
  int smoothed = 0;
  double volume = measure(&view, poses_a, poses_b, pairs, &ws, &smoothed);
  printf("%d pairs (%s), summed volume %.6g, %d with flush faces smoothed\n", pairs, mode, volume, smoothed);
  free(poses_a);
  free(poses_b);
  poly_overlap_workspace_destroy_d(&ws);
  return 0;
}
