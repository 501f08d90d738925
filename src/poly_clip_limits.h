/* Sizes of the clipping path (src/poly_clip.h), apart so that the host-only shape code can use them without
 * the inline geometry. */
#ifndef POLY_CLIP_LIMITS_H
#define POLY_CLIP_LIMITS_H

#define POLY_CLIP_MAX_PLANES 16    /* planes of one convex piece (a bit each in the side masks) */
#define POLY_CLIP_MAX_FACES 96     /* faces of a shape the clipping path takes */
#define POLY_CLIP_MAX_VERTICES 40  /* vertices of a shape */
#define POLY_CLIP_MAX_PIECES 32    /* convex pieces of a shape that is not convex */
#define POLY_CLIP_SHAPE_PLANES 128  /* planes of all the pieces of a shape (a bit each in a stored mask) */
#define POLY_CLIP_MAX_LOOP 16      /* corners of one face */
#define POLY_CLIP_MAX_POLYGON (POLY_CLIP_MAX_LOOP + POLY_CLIP_MAX_PLANES)
#define POLY_CLIP_MAX_POLYGONS 64  /* clipped polygons of one pair */
#ifndef POLY_CLIP_MAX_NODES        /* polygon corners kept for the depth (a GPU thread's stack holds them) */
#ifdef __CUDACC__
#define POLY_CLIP_MAX_NODES 96
#else
#define POLY_CLIP_MAX_NODES 256
#endif
#endif
#define POLY_CLIP_FLUSH 1e-9

/* A piece's planes as stored: bit k of the shape's plane k, in two words. */
typedef struct poly_clip_words {
  unsigned long long low, high;
} poly_clip_words;

/* The masks the clipping computes with: 128 bits on the GPU (rock_40's pieces have 79 planes, and the warp kernel
 * takes them 4.6x faster than the general path), 64 on the host, where 128-bit masks cost Schoenhardt pairs a
 * quarter and rock_40's pieces are slower than its general path (doc/benchmarks.md): there, shapes of more
 * planes take the general path. POLY_CLIP_WIDE_MASKS gives the host the GPU's (the tests). */
#if defined(__CUDACC__) || defined(POLY_CLIP_WIDE_MASKS)
__extension__ typedef unsigned __int128 poly_clip_mask;
#define POLY_CLIP_MAX_SHAPE_PLANES 128
#else
typedef unsigned long long poly_clip_mask;
#define POLY_CLIP_MAX_SHAPE_PLANES 64
#endif

#endif
