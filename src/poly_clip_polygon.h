/* One Sutherland-Hodgman step, apart from poly_clip.h so that the shape code (poly_convex.c, which cuts the
 * triangles of a shape's convex pieces with it) needs none of the rigid-body headers. */
#ifndef POLY_CLIP_POLYGON_H
#define POLY_CLIP_POLYGON_H

#include "poly_clip_limits.h"

#ifndef POLY_INLINE
#ifdef __CUDACC__
#define POLY_INLINE static inline __host__ __device__
#else
#define POLY_INLINE static inline
#endif
#endif

/* Clips polygon `in` (count corners, 3 each) by the half-space n.x <= d into `out`; returns the new count.
 * Each corner's side is computed once. */
POLY_INLINE int poly_clip_polygon(const double *in, int count, const double *plane, double *out)
{
  double side[POLY_CLIP_MAX_POLYGON];
  for (int i = 0; i < count; i++)
    side[i] = plane[0] * in[3 * i] + plane[1] * in[3 * i + 1] + plane[2] * in[3 * i + 2] - plane[3];
  int n = 0;
  for (int i = 0; i < count; i++) {
    int j = i + 1 == count ? 0 : i + 1;
    const double *p = in + 3 * i, *q = in + 3 * j;
    double sp = side[i], sq = side[j];
    if (sp <= 0.0) {
      out[3 * n] = p[0], out[3 * n + 1] = p[1], out[3 * n + 2] = p[2];
      n++;
    }
    if ((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0)) {
      double t = sp / (sp - sq);
      out[3 * n] = p[0] + t * (q[0] - p[0]), out[3 * n + 1] = p[1] + t * (q[1] - p[1]),
      out[3 * n + 2] = p[2] + t * (q[2] - p[2]);
      n++;
    }
  }
  return n;
}

#endif
