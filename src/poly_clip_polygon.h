/* One Sutherland-Hodgman step, apart from poly_clip.h so that the shape code (poly_convex.c, which cuts the
 * triangles of a shape's convex pieces with it) needs none of the rigid-body headers. */
#ifndef POLY_CLIP_POLYGON_H
#define POLY_CLIP_POLYGON_H

#include "poly_clip_limits.h"

#include "poly_inline.h"

/* Clips polygon `in` (count corners, 3 each) by the half-space n.x <= d into `out`; returns the new count, or -1
 * when it would exceed `capacity` corners (the caller hands the work on). Each corner's side is computed once and
 * carried to the next edge rather than kept in an array: on the GPU such an array lives in local memory, which the
 * warp kernel's lanes wait on (doc/benchmarks.md, Nsight Compute). */
POLY_INLINE double poly_clip_side(const double *plane, const double *p)
{
  return plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3];
}

POLY_INLINE int poly_clip_polygon(const double *in, int count, const double *plane, double *out, int capacity)
{
  if (count <= 0) return 0;
  const double first = poly_clip_side(plane, in);
  double sp = first;
  int n = 0;
  for (int i = 0; i < count; i++) {
    const int last = i + 1 == count;
    const double *p = in + 3 * i, *q = last ? in : p + 3;
    const double sq = last ? first : poly_clip_side(plane, q);
    if (sp <= 0.0) {
      if (n == capacity) return -1;
      out[3 * n] = p[0], out[3 * n + 1] = p[1], out[3 * n + 2] = p[2];
      n++;
    }
    if ((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0)) {
      if (n == capacity) return -1;
      double t = sp / (sp - sq);
      out[3 * n] = p[0] + t * (q[0] - p[0]), out[3 * n + 1] = p[1] + t * (q[1] - p[1]),
      out[3 * n + 2] = p[2] + t * (q[2] - p[2]);
      n++;
    }
    sp = sq;
  }
  return n;
}

#endif
