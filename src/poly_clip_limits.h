/* Sizes of the clipping path (src/poly_clip.h), apart so that the host-only shape code can use them without
 * the inline geometry. */
#ifndef POLY_CLIP_LIMITS_H
#define POLY_CLIP_LIMITS_H

#define POLY_CLIP_MAX_FACES 16     /* faces of a shape the clipping path takes */
#define POLY_CLIP_MAX_VERTICES 32  /* vertices of a shape */
#define POLY_CLIP_MAX_LOOP 16      /* corners of one face */
#define POLY_CLIP_MAX_POLYGON (POLY_CLIP_MAX_LOOP + POLY_CLIP_MAX_FACES)
#ifndef POLY_CLIP_MAX_NODES        /* polygon corners kept for the depth (a GPU thread's stack holds them) */
#ifdef __CUDACC__
#define POLY_CLIP_MAX_NODES 96
#else
#define POLY_CLIP_MAX_NODES 256
#endif
#endif
#define POLY_CLIP_FLUSH 1e-9

#endif
