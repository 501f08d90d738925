/* Instruction count of poly_overlap_d per call, for cost comparisons on shared
 * machines where wall time is noise (callgrind counts instructions, the same
 * on every run of the same binary):
 *
 *   gcc -std=c11 -O2 -Isrc tools/overlap_instructions.c src/poly_overlap.c src/poly_shape.c \
 *       src/poly_mesh_read.c -lm -o /tmp/overlap_instructions
 *   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.out /tmp/overlap_instructions \
 *       examples/shapes/cube.stl 200 [flush]
 *   callgrind_annotate /tmp/cg.out | grep poly_overlap_d      (divide by the pair count)
 *
 * Pairs of one shape, both orientations random (or, with `flush`, both at the
 * identity with B moved along x: every pair has flush side faces), B's centre
 * 1.1-1.7 bounding radii away along a random direction (fixed seed).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: %s SHAPE_FILE PAIRS [flush]\n", argv[0]);
    return 2;
  }
  poly_shape shape;
  char message[512];
  if (poly_shape_load(argv[1], 1.0, &shape, message, sizeof message) != POLY_OK) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  int pairs = atoi(argv[2]), flush = argc > 3;
  poly_shape_view_d view = poly_shape_view_of(&shape);
  poly_overlap_workspace_d ws;
  if (poly_overlap_workspace_create_d(&ws, shape.num_vertices, shape.num_triangles) != 0) return 1;
  double volume = 0.0;
  int smoothed = 0;
  for (int p = 0; p < pairs; p++) {
    poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}}, b = {{0, 0, 0}, {1, 0, 0, 0}};
    double direction[3] = {1.0, 0.0, 0.0}, distance = 1.0 - 0.01 * uniform();
    if (!flush) {
      random_quaternion(a.quaternion);
      random_quaternion(b.quaternion);
      double norm = 0.0;
      for (int k = 0; k < 3; k++) {
        direction[k] = 2.0 * uniform() - 1.0;
        norm += direction[k] * direction[k];
      }
      for (int k = 0; k < 3; k++) direction[k] /= sqrt(norm);
      distance = 2.0 * shape.bounding_radius * (0.55 + 0.3 * uniform());
    }
    for (int k = 0; k < 3; k++) b.position[k] = distance * direction[k];
    poly_overlap_result result;
    poly_overlap_d(&view, &a, &view, &b, &ws, &result);
    volume += result.volume;
    smoothed += result.smoothed;
  }
  printf("%d pairs, summed volume %.6g, %d with flush faces smoothed\n", pairs, volume, smoothed);
  poly_overlap_workspace_destroy_d(&ws);
  return 0;
}
