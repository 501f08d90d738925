/* Sizes of the clipping path (src/poly_clip.h), apart so that the host-only shape code can use them without
 * the inline geometry. */
#ifndef POLY_CLIP_LIMITS_H
#define POLY_CLIP_LIMITS_H

#define POLY_CLIP_MAX_PLANES 16    /* planes of one convex piece (a bit each in the side masks) */
#define POLY_CLIP_MAX_FACES 96     /* faces of a shape the clipping path takes */
#define POLY_CLIP_MAX_VERTICES 40  /* vertices of a shape */
#define POLY_CLIP_MAX_PIECES 32    /* convex pieces of a shape that is not convex */
#define POLY_CLIP_MAX_SHAPE_PLANES 64 /* planes of all the pieces of a shape (a bit each in a mask) */
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

#endif
