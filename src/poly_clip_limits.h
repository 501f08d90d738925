/* Sizes of the clipping path (src/poly_clip.h), apart so that the host-only shape code can use them without
 * the inline geometry. */
#ifndef POLY_CLIP_LIMITS_H
#define POLY_CLIP_LIMITS_H

#define POLY_CLIP_MAX_PLANES 16    /* faces of a convex shape (a bit each in the side masks), planes of a cone */
#define POLY_CLIP_MAX_FACES 96     /* faces of a shape the clipping path takes */
#define POLY_CLIP_MAX_VERTICES 64  /* vertices of a shape (its pieces' new corners included) */
#define POLY_CLIP_MAX_PIECES 32    /* convex pieces of a shape that is not convex */
#define POLY_CLIP_SHAPE_PLANES 128  /* planes of all the pieces of a shape (a bit each in a stored mask) */
#define POLY_CLIP_MAX_LOOP 16      /* corners of one face */
/* Planes of one piece of a shape that is not convex. A shape's own pieces have at most POLY_CLIP_PIECE_PLANES: a
 * triangle clipped by a piece of more planes can outgrow the GPU warp kernel's 12-corner polygons (rock_40's
 * partition has a piece of 30, which a trial build handed mostly to the one-thread kernel; its cones' pieces have at
 * most 8: doc/benchmarks.md). The pieces the host's mesh walls take instead of cones (poly_shape_wall_pieces) have
 * up to POLY_CLIP_WALL_PIECE_PLANES: against a prism, rock_40's partition clips 1.6x faster than its general path
 * does. POLY_CLIP_MAX_PIECE_PLANES sizes the buffers (the GPU's for its own pieces only). */
#ifndef POLY_CLIP_PIECE_PLANES
#define POLY_CLIP_PIECE_PLANES 16
#endif
#define POLY_CLIP_WALL_PIECE_PLANES 32
#ifdef __CUDACC__
#define POLY_CLIP_MAX_PIECE_PLANES POLY_CLIP_PIECE_PLANES
#else
#define POLY_CLIP_MAX_PIECE_PLANES POLY_CLIP_WALL_PIECE_PLANES
#endif
#define POLY_CLIP_MAX_POLYGON (POLY_CLIP_MAX_LOOP + POLY_CLIP_MAX_PIECE_PLANES)
#define POLY_CLIP_MAX_POLYGONS 64  /* clipped polygons of one pair */
/* Polygon corners kept for the depth: a GPU thread's stack holds them; on the host the mesh walls' pieces need
 * them too (want_nodes), and against a triangle larger than the particle the mesh path's corners of icosphere_320,
 * rock_70 or icosphere_80 outgrew 256, which handed the piece to the general path (3.5x, 1.4x, 1.4x slower at
 * `bash tools/bench_mesh_pieces.sh 2000 3 all 2`, doc/benchmarks.md). */
#ifndef POLY_CLIP_MAX_NODES
#ifdef __CUDACC__
#define POLY_CLIP_MAX_NODES 96
#else
#define POLY_CLIP_MAX_NODES 1024
#endif
#endif
#define POLY_CLIP_FLUSH 1e-9
/* The host clips the pieces of shapes of at most this many faces (their triangles' parts): rock_20's 34 as fast as
 * its cones, which beat its general path; with more (rock_40's partition: 67 faces, 12.1 us a pair against 8.6 by
 * the general path) the general path is faster on a core (doc/benchmarks.md). The GPU takes all. */
#ifndef POLY_CLIP_HOST_PIECE_FACES
#define POLY_CLIP_HOST_PIECE_FACES 48
#endif

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
