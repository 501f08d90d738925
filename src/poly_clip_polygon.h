/* One Sutherland-Hodgman step (poly_clip_polygon_impl.h, in double and float), apart from poly_clip.h so that the
 * shape code (poly_convex.c, which cuts the triangles of a shape's convex pieces with it) needs none of the
 * rigid-body headers. */
#ifndef POLY_CLIP_POLYGON_H
#define POLY_CLIP_POLYGON_H

#include "poly_clip_limits.h"

#include "poly_inline.h"

/* The lowest set bit of a mask of planes. */
POLY_INLINE int poly_clip_mask_lowest(poly_clip_mask mask)
{
#if defined(__CUDACC__) || defined(POLY_CLIP_WIDE_MASKS)
  unsigned long long low = (unsigned long long)mask, high = (unsigned long long)(mask >> 64);
#else
  unsigned long long low = mask, high = 0;
#endif
#ifdef __CUDA_ARCH__
  return low ? __ffsll((long long)low) - 1 : 64 + __ffsll((long long)high) - 1;
#else
  return low ? __builtin_ctzll(low) : 64 + __builtin_ctzll(high);
#endif
}

#define POLY_CLIP_REAL double
#define POLY_CLIP_FN(name) name
#include "poly_clip_polygon_impl.h"
#undef POLY_CLIP_REAL
#undef POLY_CLIP_FN
#define POLY_CLIP_REAL float
#define POLY_CLIP_FN(name) name##_f
#include "poly_clip_polygon_impl.h"
#undef POLY_CLIP_REAL
#undef POLY_CLIP_FN

#endif
