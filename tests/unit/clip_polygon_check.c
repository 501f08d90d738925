/* Checks poly_clip_polygon (src/poly_clip_polygon.h) against a reference Sutherland-Hodgman step that keeps the
 * corners' sides in an array (the function's earlier form): convex polygons of 3 to 48 corners (more than that
 * array's 32) in random planes, clipped by random planes one after another. Each step must give the reference's
 * corners bit for bit; with its output's capacity set to the corner count it must give them too, and with one
 * less it must say -1. The float instance (poly_clip_polygon_f) must give a float reference's corners bit for bit
 * on the same polygons rounded to float. Prints the counts; exit status 1 on any failure. Run by
 * tests/test_convex_path.py. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_clip_polygon.h"

#define MAX_CORNERS 64

/* The reference step for a scalar type: the corners' sides in an array first. */
#define REFERENCE_CLIP(name, real)                                                                                   \
  static int name(const real *in, int count, const real *plane, real *out)                                           \
  {                                                                                                                  \
    real side[MAX_CORNERS];                                                                                          \
    for (int i = 0; i < count; i++)                                                                                  \
      side[i] = plane[0] * in[3 * i] + plane[1] * in[3 * i + 1] + plane[2] * in[3 * i + 2] - plane[3];               \
    int n = 0;                                                                                                       \
    for (int i = 0; i < count; i++) {                                                                                \
      int j = i + 1 == count ? 0 : i + 1;                                                                            \
      const real *p = in + 3 * i, *q = in + 3 * j;                                                                   \
      real sp = side[i], sq = side[j];                                                                               \
      if (sp <= 0) {                                                                                                 \
        out[3 * n] = p[0], out[3 * n + 1] = p[1], out[3 * n + 2] = p[2];                                             \
        n++;                                                                                                         \
      }                                                                                                              \
      if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) {                                                                \
        real t = sp / (sp - sq);                                                                                     \
        out[3 * n] = p[0] + t * (q[0] - p[0]), out[3 * n + 1] = p[1] + t * (q[1] - p[1]),                            \
        out[3 * n + 2] = p[2] + t * (q[2] - p[2]);                                                                   \
        n++;                                                                                                         \
      }                                                                                                              \
    }                                                                                                                \
    return n;                                                                                                        \
  }
REFERENCE_CLIP(reference_clip, double)
REFERENCE_CLIP(reference_clip_f, float)

static double uniform(void) { return rand() / (RAND_MAX + 1.0); }

static void unit_vector(double *v)
{
  double norm;
  do {
    for (int k = 0; k < 3; k++) v[k] = 2.0 * uniform() - 1.0;
    norm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  } while (norm < 0.1 || norm > 1.0);
  for (int k = 0; k < 3; k++) v[k] /= norm;
}

/* A convex polygon: `count` points on a circle at increasing angles, in a random plane through a random centre. */
static void random_polygon(int count, double *polygon)
{
  double normal[3], e1[3], e2[3], centre[3], angle[MAX_CORNERS];
  unit_vector(normal);
  unit_vector(e1);
  double along = e1[0] * normal[0] + e1[1] * normal[1] + e1[2] * normal[2];
  for (int k = 0; k < 3; k++) e1[k] -= along * normal[k];
  double norm = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (int k = 0; k < 3; k++) e1[k] /= norm;
  e2[0] = normal[1] * e1[2] - normal[2] * e1[1];
  e2[1] = normal[2] * e1[0] - normal[0] * e1[2];
  e2[2] = normal[0] * e1[1] - normal[1] * e1[0];
  for (int k = 0; k < 3; k++) centre[k] = uniform() - 0.5;
  for (int i = 0; i < count; i++) angle[i] = 6.283185307179586 * (i + 0.9 * uniform()) / count;
  for (int i = 0; i < count; i++)
    for (int k = 0; k < 3; k++) polygon[3 * i + k] = centre[k] + cos(angle[i]) * e1[k] + sin(angle[i]) * e2[k];
}

int main(void)
{
  srand(12345);
  long steps = 0, mismatches = 0, capacity_failures = 0, grew = 0, float_mismatches = 0;
  for (int trial = 0; trial < 20000; trial++) {
    const int count = 3 + trial % 46;
    double polygon[3 * MAX_CORNERS], mine[3 * MAX_CORNERS], theirs[3 * MAX_CORNERS], bounded[3 * MAX_CORNERS];
    random_polygon(count, polygon);
    int n = count;
    for (int cut = 0; cut < 8 && n >= 3; cut++) {
      double plane[4];
      unit_vector(plane);
      plane[3] = plane[0] * polygon[0] + plane[1] * polygon[1] + plane[2] * polygon[2] + 0.6 * (uniform() - 0.5);
      const int expected = reference_clip(polygon, n, plane, theirs);
      const int got = poly_clip_polygon(polygon, n, plane, mine, MAX_CORNERS);
      steps++;
      if (got != expected || memcmp(mine, theirs, sizeof(double) * 3 * (size_t)expected) != 0) mismatches++;
      if (poly_clip_polygon(polygon, n, plane, bounded, expected) != expected ||
          memcmp(bounded, theirs, sizeof(double) * 3 * (size_t)expected) != 0)
        capacity_failures++;
      if (expected > 0 && poly_clip_polygon(polygon, n, plane, bounded, expected - 1) != -1) capacity_failures++;
      /* The float instance (the GPU's mixed-precision clipping) on the same corners rounded to float. */
      float polygon_f[3 * MAX_CORNERS], plane_f[4], mine_f[3 * MAX_CORNERS], theirs_f[3 * MAX_CORNERS];
      for (int c = 0; c < 3 * n; c++) polygon_f[c] = (float)polygon[c];
      for (int c = 0; c < 4; c++) plane_f[c] = (float)plane[c];
      const int expected_f = reference_clip_f(polygon_f, n, plane_f, theirs_f);
      if (poly_clip_polygon_f(polygon_f, n, plane_f, mine_f, MAX_CORNERS) != expected_f ||
          memcmp(mine_f, theirs_f, sizeof(float) * 3 * (size_t)expected_f) != 0)
        float_mismatches++;
      if (expected > n) grew++;
      memcpy(polygon, theirs, sizeof(double) * 3 * (size_t)expected);
      n = expected;
    }
  }
  printf("steps %ld mismatches %ld capacity_failures %ld grew %ld float_mismatches %ld\n", steps, mismatches,
         capacity_failures, grew, float_mismatches);
  return mismatches || capacity_failures || float_mismatches ? 1 : 0;
}
