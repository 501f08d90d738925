/* Orientation of four points with an exact sign.
 *
 * The overlap computation decides its topology (which edge crosses which
 * face, which vertex is inside) from orientation signs alone. If rounding
 * could flip a sign, two neighbouring faces could disagree about a nearly
 * degenerate configuration (faces touching to within round-off, a vertex a
 * few ulps from a plane) and a whole region would be counted wrongly. So the
 * sign is exact: a floating-point evaluation with a forward error bound
 * decides almost every case, and the rare uncertain ones are recomputed
 * exactly with floating-point expansions (Dekker's two-sum and an FMA-based
 * two-product), which need no wider type. Header-only, usable from CUDA.
 */
#ifndef POLY_EXACT_H
#define POLY_EXACT_H

#include <math.h>

#include "poly_rigid.h"

/* x + y = a + b exactly, |y| <= ulp(x)/2. */
POLY_INLINE void poly_two_sum(double a, double b, double *x, double *y)
{
  double sum = a + b, b_virtual = sum - a, a_virtual = sum - b_virtual;
  *x = sum;
  *y = (a - a_virtual) + (b - b_virtual);
}

/* x + y = a * b exactly. */
POLY_INLINE void poly_two_product(double a, double b, double *x, double *y)
{
  double product = a * b;
  *x = product;
  *y = fma(a, b, -product);
}

/* Adds b to the non-overlapping expansion e[0..n) (least significant first);
 * returns the new length. Zero components are dropped. */
POLY_INLINE int poly_grow_expansion(double *e, int n, double b)
{
  double q = b;
  int m = 0;
  for (int i = 0; i < n; i++) {
    double sum, error;
    poly_two_sum(q, e[i], &sum, &error);
    q = sum;
    if (error != 0.0) e[m++] = error;
  }
  if (q != 0.0) e[m++] = q;
  return m;
}

/* Exact sign of det(r0, r1, r2) with row r = high[r] - low[r] (low[r] null: the
 * row is high[r] itself). */
POLY_INLINE int poly_det_sign_exact(const double *const high[3], const double *const low[3])
{
  /* Each entry as a two-term expansion; the low part is usually zero (nearby
   * coordinates subtract exactly), and zero parts are skipped. */
  double parts[3][3][2];
  int count[3][3];
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) {
      double hi = high[r][k], lo = 0.0;
      if (low[r]) poly_two_sum(high[r][k], -low[r][k], &hi, &lo);
      int n = 0;
      if (hi != 0.0) parts[r][k][n++] = hi;
      if (lo != 0.0) parts[r][k][n++] = lo;
      count[r][k] = n;
    }
  /* det = sum over permutations (i, j, k) of sign * r0[i] r1[j] r2[k]. */
  const int permutations[6][4] = {{0, 1, 2, 1}, {1, 2, 0, 1}, {2, 0, 1, 1},
                                         {0, 2, 1, -1}, {1, 0, 2, -1}, {2, 1, 0, -1}};
  double expansion[6 * 8 * 4];
  int length = 0;
  for (int s = 0; s < 6; s++) {
    int i = permutations[s][0], j = permutations[s][1], k = permutations[s][2];
    double sign = permutations[s][3];
    for (int u = 0; u < count[0][i]; u++)
      for (int v = 0; v < count[1][j]; v++)
        for (int w = 0; w < count[2][k]; w++) {
          double hi, lo, h1, l1, h2, l2;
          poly_two_product(parts[0][i][u], parts[1][j][v], &hi, &lo);
          poly_two_product(hi, parts[2][k][w], &h1, &l1);
          poly_two_product(lo, parts[2][k][w], &h2, &l2);
          length = poly_grow_expansion(expansion, length, sign * h1);
          if (l1 != 0.0) length = poly_grow_expansion(expansion, length, sign * l1);
          if (h2 != 0.0) length = poly_grow_expansion(expansion, length, sign * h2);
          if (l2 != 0.0) length = poly_grow_expansion(expansion, length, sign * l2);
        }
  }
  /* The most significant component of a non-overlapping expansion has the sign of the sum. */
  if (length == 0) return 0;
  return expansion[length - 1] > 0.0 ? 1 : -1;
}

/* Exact sign of det(a - d, b - d, c - d). */
POLY_INLINE int poly_orient_sign_exact(const double *a, const double *b, const double *c, const double *d)
{
  const double *high[3] = {a, b, c}, *low[3] = {d, d, d};
  return poly_det_sign_exact(high, low);
}

/* det(a - d, b - d, c - d) with a guaranteed sign: the floating-point value
 * when its error bound proves the sign, otherwise a value of the exact sign
 * (0 exactly when the points are coplanar). */
POLY_INLINE double poly_orient(const double *a, const double *b, const double *c, const double *d)
{
  double ax = a[0] - d[0], ay = a[1] - d[1], az = a[2] - d[2];
  double bx = b[0] - d[0], by = b[1] - d[1], bz = b[2] - d[2];
  double cx = c[0] - d[0], cy = c[1] - d[1], cz = c[2] - d[2];
  double bycz = by * cz, bzcy = bz * cy, bzcx = bz * cx, bxcz = bx * cz, bxcy = bx * cy, bycx = by * cx;
  double det = ax * (bycz - bzcy) + ay * (bzcx - bxcz) + az * (bxcy - bycx);
  double permanent = fabs(ax) * (fabs(bycz) + fabs(bzcy)) + fabs(ay) * (fabs(bzcx) + fabs(bxcz)) +
                     fabs(az) * (fabs(bxcy) + fabs(bycx));
  /* Shewchuk's bound for this evaluation order is (7 + 56 eps) eps; 8 eps is safe. */
  const double bound = 8.0 * 1.1102230246251565e-16 * permanent;
  if (det > bound || -det > bound) return det;
  int sign = poly_orient_sign_exact(a, b, c, d);
  if (sign == 0) return 0.0;
  double magnitude = fabs(det) > 0.0 ? fabs(det) : 1e-300;
  return sign > 0 ? magnitude : -magnitude;
}

#endif
