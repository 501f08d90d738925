/* One Sutherland-Hodgman step and a face's clipping by several planes, written once for a scalar type: included
 * by poly_clip_polygon.h with POLY_CLIP_REAL double (names as they are) and float (names with _f: with
 * POLY_GPU_MIXED_CLIP=single the GPU's warp clipping kernel clips its faces in single in mixed precision and sums
 * them in double, a benchmark's opt-in; doc/gpu.md). */
#if !defined(POLY_CLIP_REAL) || !defined(POLY_CLIP_FN)
#error "define POLY_CLIP_REAL and POLY_CLIP_FN before including poly_clip_polygon_impl.h"
#endif

/* Clips polygon `in` (count corners, 3 each) by the half-space n.x <= d into `out`; returns the new count, or -1
 * when it would exceed `capacity` corners (the caller hands the work on). Each corner's side is computed once and
 * carried to the next edge rather than kept in an array: on the GPU such an array lives in local memory, which the
 * warp kernel's lanes wait on (doc/benchmarks.md, Nsight Compute). */
POLY_INLINE POLY_CLIP_REAL POLY_CLIP_FN(poly_clip_side)(const POLY_CLIP_REAL *plane, const POLY_CLIP_REAL *p)
{
  return plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3];
}

POLY_INLINE int POLY_CLIP_FN(poly_clip_polygon)(const POLY_CLIP_REAL *in, int count, const POLY_CLIP_REAL *plane,
                                                POLY_CLIP_REAL *out, int capacity)
{
  if (count <= 0) return 0;
  const POLY_CLIP_REAL first = POLY_CLIP_FN(poly_clip_side)(plane, in);
  POLY_CLIP_REAL sp = first;
  int n = 0;
  for (int i = 0; i < count; i++) {
    const int last = i + 1 == count;
    const POLY_CLIP_REAL *p = in + 3 * i, *q = last ? in : p + 3;
    const POLY_CLIP_REAL sq = last ? first : POLY_CLIP_FN(poly_clip_side)(plane, q);
    if (sp <= 0) {
      if (n == capacity) return -1;
      out[3 * n] = p[0], out[3 * n + 1] = p[1], out[3 * n + 2] = p[2];
      n++;
    }
    if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) {
      if (n == capacity) return -1;
      POLY_CLIP_REAL t = sp / (sp - sq);
      out[3 * n] = p[0] + t * (q[0] - p[0]), out[3 * n + 1] = p[1] + t * (q[1] - p[1]),
      out[3 * n + 2] = p[2] + t * (q[2] - p[2]);
      n++;
    }
    sp = sq;
  }
  return n;
}

/* Polygon `in` (count corners) clipped by the planes of mask `cut` among `planes` (4 each), lowest first, the
 * planes of mask `back` turned about (the polygon kept in front of them), alternately into `in` and `out`
 * (`capacity` corners each): returns the corner count (0: nothing left; -1: it outgrew the buffers) and in
 * *result the buffer holding them. */
POLY_INLINE int POLY_CLIP_FN(poly_clip_by_planes)(POLY_CLIP_REAL *in, POLY_CLIP_REAL *out, int count, const POLY_CLIP_REAL *planes,
                                                  poly_clip_mask cut, poly_clip_mask back, int capacity,
                                                  POLY_CLIP_REAL **result)
{
  int n = count;
  for (poly_clip_mask m = cut; m && n >= 3; m &= m - 1) {
    int k = poly_clip_mask_lowest(m);
    const POLY_CLIP_REAL *plane = planes + 4 * k;
    POLY_CLIP_REAL flipped[4] = {-plane[0], -plane[1], -plane[2], -plane[3]};
    n = POLY_CLIP_FN(poly_clip_polygon)(in, n, (back >> k) & 1 ? flipped : plane, out, capacity);
    if (n < 0) return -1;
    POLY_CLIP_REAL *swap = in;
    in = out;
    out = swap;
  }
  *result = in;
  return n >= 3 ? n : 0;
}
