/* The overlap of two shapes by clipping (convex shapes of few faces, and
 * shapes that split into convex pieces, below): each body's face
 * polygons clipped by the other's face planes give the whole boundary of the
 * intersection (B's faces inside A, then A's faces inside B, the latter being
 * "A's surface inside B" of eq. 4.19), and the divergence theorem over those
 * polygons gives volume, centroid and second moment, with the same fan
 * tetrahedra sums as the other paths. No edge-triangle tests and no side
 * table: for a pair of cubes in a pile this is a few times cheaper than the
 * blocks path (doc/benchmarks.md).
 *
 * Header-only C (double), for the CPU overlap entry and the CUDA contact
 * kernel alike. The faces come from poly_shape_find_faces (poly_clip_faces:
 * per face its plane and its corners in order, counter-clockwise seen from
 * outside). Any vertex of one body within POLY_CLIP_FLUSH of the size of a
 * plane of the other (a piece's inner planes included) hands the pair back
 * (returns 0): flush faces take the
 * general path, whose smoothing makes the area continuous there; that test
 * is a superset of the general path's own flush test (2^-34 of the size).
 *
 * Shapes that are not convex take it too, through convex pieces: A's boundary
 * inside B is the union over B's pieces of A's faces clipped by the piece's
 * planes, and B's inside A likewise, so each body's own faces are clipped by
 * the other's pieces and the pieces' inner planes never make a polygon. Only
 * pairs of pieces that no plane of either parts are clipped.
 *
 * For pieces the polygons are summed as they come; their corners are kept for
 * the depth (the extent along the normal, known only at the end) up to
 * POLY_CLIP_MAX_NODES, and past that the clipping runs a second time for the
 * extent alone. Convex pairs keep all corners and sum them at the end (more
 * corners than that go to the general path, as flush faces do). */
#ifndef POLY_CLIP_H
#define POLY_CLIP_H

#include <math.h>
#if defined(__SSE2__) && !defined(__CUDACC__)
#include <emmintrin.h>
#endif

#include "poly_clip_limits.h"
#include "poly_clip_polygon.h"
#include "poly_rigid.h"

POLY_INLINE poly_clip_mask poly_clip_mask_of(const poly_clip_words *words)
{
#if defined(__CUDACC__) || defined(POLY_CLIP_WIDE_MASKS)
  return (poly_clip_mask)words->low | ((poly_clip_mask)words->high << 64);
#else
  return words->low;
#endif
}

POLY_INLINE int poly_clip_lowest_bit(unsigned mask)
{
#ifdef __CUDA_ARCH__
  return __ffs((int)mask) - 1;
#else
  return __builtin_ctz(mask);
#endif
}

/* A shape's faces and convex pieces, body frame. */
typedef struct poly_clip_faces {
  int num_faces, num_vertices;
  const double *vertices;  /* 3 per vertex (for pieces that cut the triangles, their new corners after them) */
  const double *planes;    /* 4 per plane: unit outward normal n and offset d, n.x = d on it (see below) */
  const int *loop_start;   /* num_faces + 1 offsets into loop */
  const int *loop;         /* corners of each face in order, counter-clockwise seen from outside */
  const int *triangle;     /* per face its lowest triangle (for the separation hint's code) */
  /* Convex pieces whose union is the body, interiors apart: one for a convex shape (its faces' planes); for
   * one that is not, the cells of a partition of space by its face planes inside it, or cones from the centre of
   * mass over patches of its surface (poly_shape_find_faces, poly_convex_partition_impl.h). Each
   * piece is the intersection of half-spaces of the shape's planes: `planes` holds num_planes of them (the
   * faces' planes first for a convex shape), a piece lies behind the planes of its piece_front mask and in
   * front of those of its piece_back mask. */
  int num_planes, num_pieces;
  const poly_clip_words *piece_front, *piece_back;
  const int *piece_point_start, *piece_points;  /* per piece its corners; index num_vertices is the origin (cones) */
  const int *piece_face_start, *piece_faces;    /* per piece the faces on its surface */
  /* Per plane the index in the shape's supporting triangles (poly_shape's support) of one on it, or -1, and the
   * mask of the planes that have one: a body wholly in front of such a plane is apart (pieces only). */
  const int *plane_support;
  poly_clip_words support_planes;
  const int *face_plane;  /* per face the index of its plane among `planes` (pieces only; NULL: not known) */
  int many_faces;         /* 1: the host takes these pieces whatever their faces (the mesh walls' pieces) */
  int facets;             /* 1: each face is all of its piece on its plane (a mesh wall's prism: poly_clip_mesh.h) */
} poly_clip_faces;

/* What the clipping gives, in A's body frame (the caller turns it to world). */
typedef struct poly_clip_result {
  double volume, centroid[3], normal[3], depth, area, projected_area, second_moment[6];
  int num_nodes;
  int separating;  /* apart: the plane that parts them as poly_overlap_result's code ((triangle << 1) | of_b); else -1 */
} poly_clip_result;

/* Where the clipping leaves the intersection's corners when a caller asks (the mesh walls, whose contact depth is
 * the extent of the union of several overlaps' corners): `count` corners (each corner once per polygon that has
 * it) relative to `origin`, A's frame; count -1 when more than `capacity` or when the pieces' corners overflowed
 * (the extent came from a second pass). */
typedef struct poly_clip_corners {
  double *points;
  int capacity, count;
  double origin[3];
} poly_clip_corners;

/* Hands `count` corners relative to `origin` to `corners` (when given). */
POLY_INLINE void poly_clip_keep_corners(const double *nodes, int count, const double *origin, poly_clip_corners *corners)
{
  if (!corners) return;
  corners->count = count <= corners->capacity ? count : -1;
  for (int k = 0; k < 3; k++) corners->origin[k] = origin[k];
  for (int c = 0; c < 3 * count && count <= corners->capacity; c++) corners->points[c] = nodes[c];
}

typedef struct poly_clip_sums {
  double volume6, moment24[3], second120[6], area_vector[3], area;
  int want_second;
} poly_clip_sums;

/* The boundary polygons' sums, from the first polygon's first corner (so shallow overlaps lose no digits to a
 * distant origin), and their corners for the depth; in the second pass (depth_pass) only the extent along
 * `direction`. */
typedef struct poly_clip_accumulator {
  poly_clip_sums sums;
  double reference[3];
  int num_corners, num_kept, overflow, depth_pass;
  double direction[3], low, high;
  double nodes[3 * POLY_CLIP_MAX_NODES];
} poly_clip_accumulator;

/* Adds the fan tetrahedron of triangle (p0, p1, p2) from the origin; with `on_a`, also its area vector and area. */
POLY_INLINE void poly_clip_add_triangle(const double *p0, const double *p1, const double *p2, int on_a,
                                        poly_clip_sums *sums)
{
  double det = p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
               p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
  sums->volume6 += det;
  for (int k = 0; k < 3; k++) sums->moment24[k] += det * (p0[k] + p1[k] + p2[k]);
  if (sums->want_second) poly_second_moment_add(sums->second120, det, p0, p1, p2);
  if (on_a) {
    double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (int k = 0; k < 3; k++) sums->area_vector[k] += 0.5 * c[k];
    sums->area += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  }
}

/* Adds a boundary polygon (outward counter-clockwise) as fan tetrahedra from the origin; with `on_a`, also
 * its area vector and area (A's surface inside B). */
POLY_INLINE void poly_clip_add_polygon(const double *polygon, int count, int on_a, poly_clip_sums *sums)
{
  for (int i = 1; i + 1 < count; i++) poly_clip_add_triangle(polygon, polygon + 3 * i, polygon + 3 * (i + 1), on_a, sums);
}

/* The extent of `count` corners along `normal`, widening [*low, *high]. In locals, two corners a turn: through the
 * pointers (which may alias `nodes`) each corner waited on the last one's store, a fifth of a Schoenhardt pair's
 * clipping (doc/benchmarks.md); min and max are exact, so the order changes no bit. */
POLY_INLINE void poly_clip_extent(const double *nodes, int count, const double *normal, double *low, double *high)
{
  const double n0 = normal[0], n1 = normal[1], n2 = normal[2];
  double low_even = *low, high_even = *high, low_odd = *low, high_odd = *high;
  int p = 0;
  for (; p + 1 < count; p += 2) {
    const double *x = nodes + 3 * p;
    const double even = n0 * x[0] + n1 * x[1] + n2 * x[2], odd = n0 * x[3] + n1 * x[4] + n2 * x[5];
    low_even = even < low_even ? even : low_even;
    high_even = even > high_even ? even : high_even;
    low_odd = odd < low_odd ? odd : low_odd;
    high_odd = odd > high_odd ? odd : high_odd;
  }
  if (p < count) {
    const double *x = nodes + 3 * p;
    const double last = n0 * x[0] + n1 * x[1] + n2 * x[2];
    low_even = last < low_even ? last : low_even;
    high_even = last > high_even ? last : high_even;
  }
  *low = low_odd < low_even ? low_odd : low_even;
  *high = high_odd > high_even ? high_odd : high_even;
}

POLY_INLINE void poly_clip_accumulator_start(poly_clip_accumulator *acc, int want_second)
{
  acc->sums.volume6 = acc->sums.area = 0.0;
  for (int k = 0; k < 3; k++) acc->sums.moment24[k] = acc->sums.area_vector[k] = 0.0;
  for (int e = 0; e < 6; e++) acc->sums.second120[e] = 0.0;
  acc->sums.want_second = want_second;
  acc->num_corners = acc->num_kept = acc->overflow = acc->depth_pass = 0;
}

/* One boundary polygon (`polygon`, a work buffer it may change): summed, its corners kept; or, in the depth
 * pass, its extent along the normal. */
POLY_INLINE void poly_clip_accumulate(poly_clip_accumulator *acc, double *polygon, int n, int on_a)
{
  if (acc->num_corners == 0)
    for (int k = 0; k < 3; k++) acc->reference[k] = polygon[k];
  const double r0 = acc->reference[0], r1 = acc->reference[1], r2 = acc->reference[2];
  acc->num_corners += n;
  /* The corners from the reference straight into the kept ones where they fit (one pass, not two), else in place. */
  const int keep = !acc->depth_pass && acc->num_kept + n <= POLY_CLIP_MAX_NODES;
  double *corners = keep ? acc->nodes + 3 * acc->num_kept : polygon;
  for (int c = 0; c < n; c++) {
    const double x = polygon[3 * c] - r0, y = polygon[3 * c + 1] - r1, z = polygon[3 * c + 2] - r2;
    corners[3 * c] = x, corners[3 * c + 1] = y, corners[3 * c + 2] = z;
  }
  if (acc->depth_pass) {
    poly_clip_extent(corners, n, acc->direction, &acc->low, &acc->high);
    return;
  }
  poly_clip_add_polygon(corners, n, on_a, &acc->sums);
  if (keep) acc->num_kept += n;
  else acc->overflow = 1;
}

/* The faces of `body` (vertices `x`, already in A's frame) clipped by `planes` of the other body (A's frame),
 * `front[v]` the vertices' masks of the planes they are in front of: each surviving polygon's corners are
 * appended to `nodes` and its corner count to `counts` (negative for A's faces). Returns 0 when the buffers
 * are full. Convex pairs keep every corner this way (no second pass), which a GPU thread runs faster than
 * summing each polygon as it comes. */
POLY_INLINE int poly_clip_body(const poly_clip_faces *body, const double *x, const double *planes,
                               const unsigned *front, int on_a, double *nodes, int *num_nodes, int *counts,
                               int *num_polygons)
{
  double work[2][3 * POLY_CLIP_MAX_POLYGON];
  for (int f = 0; f < body->num_faces; f++) {
    const int *loop = body->loop + body->loop_start[f];
    const int count = body->loop_start[f + 1] - body->loop_start[f];
    /* A plane every corner is in front of leaves nothing of the face; one some corner is in front of cuts it. */
    unsigned all_front = ~0u, some_front = 0u;
    for (int c = 0; c < count; c++) {
      all_front &= front[loop[c]];
      some_front |= front[loop[c]];
    }
    if (all_front) continue;
    int most = count;  /* corners after the clipping: at most one more per cutting plane */
    for (unsigned m = some_front; m; m &= m - 1) most++;
    if (*num_nodes + most > POLY_CLIP_MAX_NODES || *num_polygons == 2 * POLY_CLIP_MAX_PLANES) return 0;
    double *polygon = nodes + 3 * *num_nodes;
    int n = count;
    if (!some_front) {
      for (int c = 0; c < count; c++)
        for (int k = 0; k < 3; k++) polygon[3 * c + k] = x[3 * loop[c] + k];
    } else {
      /* The last clipping writes into `polygon` itself, within the room left there. */
      const int room = POLY_CLIP_MAX_NODES - *num_nodes;
      int clips_left = most - count;
      double *in = work[0];
      for (int c = 0; c < count; c++)
        for (int k = 0; k < 3; k++) in[3 * c + k] = x[3 * loop[c] + k];
      for (unsigned m = some_front; m && n >= 3; m &= m - 1) {
        const int last = --clips_left == 0;
        double *out = last ? polygon : in == work[0] ? work[1] : work[0];
        n = poly_clip_polygon(in, n, planes + 4 * poly_clip_lowest_bit(m), out,
                              last && room < POLY_CLIP_MAX_POLYGON ? room : POLY_CLIP_MAX_POLYGON);
        if (n < 0) return 0;
        in = out;
      }
      if (n < 3) continue;
    }
    *num_nodes += n;
    counts[(*num_polygons)++] = on_a ? -n : n;
  }
  return 1;
}

/* Masks of the planes each of `count` points `x` is in front of, into `front`, and in `*parting` the planes every
 * point is in front of; 0 when a point is within `flush` of a plane (the pair goes to the general path). */
#if defined(__SSE2__) && !defined(__CUDACC__)
/* On a core, two planes at a time (SSE2, in every x86-64), in a loop of a fixed length so that it unrolls: the same
 * sums in the same order, so the same bits as the loop below, in fewer instructions and without a branch per plane;
 * this was the convex path's largest cost in a pile of cubes (doc/benchmarks.md, "Eighth step"). */
#define POLY_CLIP_SIDES_PADDED ((POLY_CLIP_MAX_PLANES + 1) / 2 * 2) /* every convex shape's faces, even */
/* The planes' columns for the loops below, from num_planes to `padded` filled with planes every point lies far
 * behind (their bits are masked off). */
POLY_INLINE void poly_clip_plane_columns(const double *planes, int num_planes, int padded, double *nx, double *ny,
                                         double *nz, double *d)
{
  for (int k = 0; k < padded; k++) {
    const int real = k < num_planes;
    nx[k] = real ? planes[4 * k] : 0.0, ny[k] = real ? planes[4 * k + 1] : 0.0;
    nz[k] = real ? planes[4 * k + 2] : 0.0, d[k] = real ? planes[4 * k + 3] : 1e300;
  }
}

/* The point's sides of planes k and k + 1: n.p - d, summed in the scalar loop's order. */
static inline __attribute__((always_inline)) __m128d poly_clip_side_pair(const double *nx, const double *ny,
                                                                         const double *nz, const double *d, int k,
                                                                         __m128d px, __m128d py, __m128d pz)
{
  __m128d s = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(nx + k), px), _mm_mul_pd(_mm_loadu_pd(ny + k), py));
  return _mm_sub_pd(_mm_add_pd(s, _mm_mul_pd(_mm_loadu_pd(nz + k), pz)), _mm_loadu_pd(d + k));
}

static inline __attribute__((always_inline)) int poly_clip_sides_columns(const double *x, int count, const double *nx,
                                                                         const double *ny, const double *nz,
                                                                         const double *d, int pairs, double flush,
                                                                         unsigned valid, unsigned *front,
                                                                         unsigned *parting)
{
  const __m128d zero = _mm_setzero_pd(), limit = _mm_set1_pd(flush), sign = _mm_set1_pd(-0.0);
  __m128d close = zero;
  unsigned all = valid;
  for (int v = 0; v < count; v++) {
    const __m128d px = _mm_set1_pd(x[3 * v]), py = _mm_set1_pd(x[3 * v + 1]), pz = _mm_set1_pd(x[3 * v + 2]);
    unsigned mask = 0;
#pragma GCC unroll 8
    for (int j = 0; j < pairs; j++) {
      const __m128d s = poly_clip_side_pair(nx, ny, nz, d, 2 * j, px, py, pz);
      mask |= (unsigned)_mm_movemask_pd(_mm_cmpgt_pd(s, zero)) << (2 * j);
      close = _mm_or_pd(close, _mm_cmple_pd(_mm_andnot_pd(sign, s), limit));
    }
    front[v] = mask & valid;
    all &= mask;
  }
  *parting = all;
  return !_mm_movemask_pd(close);
}

POLY_INLINE int poly_clip_sides(const double *x, int count, const double *planes, int num_planes, double flush,
                                unsigned *front, unsigned *parting)
{
  double nx[POLY_CLIP_SIDES_PADDED], ny[POLY_CLIP_SIDES_PADDED], nz[POLY_CLIP_SIDES_PADDED], d[POLY_CLIP_SIDES_PADDED];
  /* Loops of 6 planes (boxes, hexagonal prisms), 8 or all: a box padded to 8 spent a quarter of its sides on pads. */
  const int padded = num_planes <= 6 ? 6 : num_planes <= 8 ? 8 : POLY_CLIP_SIDES_PADDED;
  poly_clip_plane_columns(planes, num_planes, padded, nx, ny, nz, d);
  const unsigned valid = (1u << num_planes) - 1u;
  if (padded == 6) return poly_clip_sides_columns(x, count, nx, ny, nz, d, 3, flush, valid, front, parting);
  return padded == 8 ? poly_clip_sides_columns(x, count, nx, ny, nz, d, 4, flush, valid, front, parting)
                     : poly_clip_sides_columns(x, count, nx, ny, nz, d, POLY_CLIP_SIDES_PADDED / 2, flush, valid,
                                               front, parting);
}
#else
POLY_INLINE int poly_clip_sides(const double *x, int count, const double *planes, int num_planes, double flush,
                                unsigned *front, unsigned *parting)
{
  unsigned all = (1u << num_planes) - 1u;
  for (int v = 0; v < count; v++) {
    unsigned mask = 0;
    for (int k = 0; k < num_planes; k++) {
      const double *plane = planes + 4 * k, *p = x + 3 * v;
      double s = plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3];
      if (s > 0.0) mask |= 1u << k;
      if (fabs(s) <= flush) return 0;
    }
    front[v] = mask;
    all &= mask;
  }
  *parting = all;
  return 1;
}
#endif

/* Volume, centroid, second moment, area and normal of the intersection from its boundary's sums (taken from
 * `reference`); 0 when there is no volume. */
POLY_INLINE int poly_clip_result_from_sums(const poly_clip_sums *sums, const double *reference, int num_corners,
                                           const double *translation, poly_clip_result *out)
{
  double volume = sums->volume6 / 6.0;
  if (!(volume > 0.0)) return 0;
  out->volume = volume;
  out->num_nodes = num_corners;
  double from_reference[3];
  for (int k = 0; k < 3; k++) {
    from_reference[k] = sums->moment24[k] / (24.0 * volume);
    out->centroid[k] = from_reference[k] + reference[k];
  }
  out->area = sums->area;
  if (sums->want_second) {
    for (int e = 0; e < 6; e++) out->second_moment[e] = sums->second120[e] / 120.0;
    poly_second_moment_to_centroid(out->second_moment, volume, from_reference);
  }
  /* Normal (eq. 4.19): A's surface inside B; the centre line when it sums to nothing. */
  double length = sqrt(sums->area_vector[0] * sums->area_vector[0] + sums->area_vector[1] * sums->area_vector[1] +
                       sums->area_vector[2] * sums->area_vector[2]);
  out->projected_area = length;
  if (length > 1e-9 * sums->area && length > 0.0) {
    for (int k = 0; k < 3; k++) out->normal[k] = sums->area_vector[k] / length;
  } else {
    double t = sqrt(translation[0] * translation[0] + translation[1] * translation[1] + translation[2] * translation[2]);
    for (int k = 0; k < 3; k++) out->normal[k] = t > 0.0 ? translation[k] / t : (k == 2 ? 1.0 : 0.0);
  }
  return 1;
}

/* The accumulated sums' result and the depth from the kept corners; returns 0 when corners were not kept
 * (overflow) and the depth needs the second pass. */
POLY_INLINE int poly_clip_finish(poly_clip_accumulator *acc, const double *translation, poly_clip_result *out)
{
  if (acc->num_corners == 0 || !poly_clip_result_from_sums(&acc->sums, acc->reference, acc->num_corners, translation, out))
    return 1;
  acc->low = 1e300, acc->high = -1e300;
  for (int k = 0; k < 3; k++) acc->direction[k] = out->normal[k];
  if (acc->overflow) {
    acc->depth_pass = 1;
    acc->num_corners = 0;  /* the second pass sets the same reference again */
    return 0;
  }
  poly_clip_extent(acc->nodes, acc->num_kept, out->normal, &acc->low, &acc->high);
  out->depth = acc->high > acc->low ? acc->high - acc->low : 0.0;
  return 1;
}

POLY_INLINE void poly_clip_finish_depth(const poly_clip_accumulator *acc, poly_clip_result *out)
{
  out->depth = acc->high > acc->low ? acc->high - acc->low : 0.0;
}

/* Point `p` against `num_planes` planes: the planes it is in front of into *ahead, behind into *behind; returns 1
 * when it is within `flush` of one. */
POLY_INLINE int poly_clip_point_sides(const double *p, const double *planes, int num_planes, double flush,
                                      poly_clip_mask *ahead, poly_clip_mask *behind)
{
  poly_clip_mask front = 0, back = 0;
  int near = 0;
  for (int k = 0; k < num_planes; k++) {
    const double *plane = planes + 4 * k;
    double s = plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3];
    if (s > 0.0) front |= (poly_clip_mask)1 << k;
    if (s < 0.0) back |= (poly_clip_mask)1 << k;
    near |= fabs(s) <= flush;
  }
  *ahead = front;
  *behind = back;
  return near;
}

/* Each of `count` points `x` (and the point `apex` after them) against `num_planes` planes (poly_clip_point_sides),
 * and in *all_ahead the planes all `count` points are in front of; 0 when one of the points (not the apex) is
 * within `flush` of a plane (the pair goes to the general path). */
#if defined(__SSE2__) && !defined(__CUDACC__)
/* On a core, two planes at a time as poly_clip_sides above (the same sums, so the same bits). */
POLY_INLINE int poly_clip_sides_of_planes(const double *x, int count, const double *apex, const double *planes,
                                          int num_planes, double flush, poly_clip_mask *ahead, poly_clip_mask *behind,
                                          poly_clip_mask *all_ahead)
{
  double nx[POLY_CLIP_MAX_SHAPE_PLANES + 1], ny[POLY_CLIP_MAX_SHAPE_PLANES + 1], nz[POLY_CLIP_MAX_SHAPE_PLANES + 1],
      d[POLY_CLIP_MAX_SHAPE_PLANES + 1];
  poly_clip_plane_columns(planes, num_planes, num_planes + 1, nx, ny, nz, d);
  const poly_clip_mask valid = num_planes == POLY_CLIP_MAX_SHAPE_PLANES ? ~(poly_clip_mask)0
                                                                        : ((poly_clip_mask)1 << num_planes) - 1;
  const __m128d zero = _mm_setzero_pd(), limit = _mm_set1_pd(flush), sign = _mm_set1_pd(-0.0);
  poly_clip_mask all = ~(poly_clip_mask)0;
  for (int v = 0; v <= count; v++) {
    const double *p = v < count ? x + 3 * v : apex;
    const __m128d px = _mm_set1_pd(p[0]), py = _mm_set1_pd(p[1]), pz = _mm_set1_pd(p[2]);
    poly_clip_mask front = 0, back = 0;
    __m128d close = zero;
    for (int k = 0; k < num_planes; k += 2) {
      const __m128d s = poly_clip_side_pair(nx, ny, nz, d, k, px, py, pz);
      front |= (poly_clip_mask)_mm_movemask_pd(_mm_cmpgt_pd(s, zero)) << k;
      back |= (poly_clip_mask)_mm_movemask_pd(_mm_cmplt_pd(s, zero)) << k;
      close = _mm_or_pd(close, _mm_cmple_pd(_mm_andnot_pd(sign, s), limit));
    }
    ahead[v] = front & valid;
    behind[v] = back & valid;
    if (v < count) {
      if (_mm_movemask_pd(close)) return 0;
      all &= front;
    }
  }
  *all_ahead = all & valid;
  return 1;
}
#else
POLY_INLINE int poly_clip_sides_of_planes(const double *x, int count, const double *apex, const double *planes,
                                          int num_planes, double flush, poly_clip_mask *ahead, poly_clip_mask *behind,
                                          poly_clip_mask *all_ahead)
{
  poly_clip_mask all = ~(poly_clip_mask)0;
  for (int v = 0; v <= count; v++) {
    if (poly_clip_point_sides(v < count ? x + 3 * v : apex, planes, num_planes, flush, ahead + v, behind + v) &&
        v < count)
      return 0;
    if (v < count) all &= ahead[v];
  }
  *all_ahead = all;
  return 1;
}
#endif

/* The planes of the other body's piece (behind those of `front`, ahead of those of `back`) that some corner of face
 * `face` of `body` is outside of, and in *all_out those every corner is outside of (nothing of the face is left). */
POLY_INLINE poly_clip_mask poly_clip_face_cuts(const poly_clip_faces *body, int face, const poly_clip_mask *ahead,
                                               const poly_clip_mask *behind, poly_clip_mask front, poly_clip_mask back,
                                               poly_clip_mask *all_out)
{
  const int *loop = body->loop + body->loop_start[face];
  const int count = body->loop_start[face + 1] - body->loop_start[face];
  poly_clip_mask all = ~(poly_clip_mask)0, some = 0;
  for (int c = 0; c < count; c++) {
    poly_clip_mask out = (ahead[loop[c]] & front) | (behind[loop[c]] & back);
    all &= out;
    some |= out;
  }
  *all_out = all;
  return some;
}

/* Face `face` of `body` (vertices `x` in A's frame, their sides `ahead` and `behind` of the other body's `planes`
 * in A's frame) clipped by the piece of the other body behind the planes of `front` and ahead of those of
 * `back`, in the work buffers (`capacity` corners each): returns the corner count (0: nothing left; -1: it
 * outgrew the buffers) and in *result the buffer holding them. */
POLY_INLINE int poly_clip_face_by_piece(const poly_clip_faces *body, int face, const double *x,
                                        const poly_clip_mask *ahead, const poly_clip_mask *behind,
                                        const double *planes, poly_clip_mask front, poly_clip_mask back,
                                        double *work_in, double *work_out, int capacity, double **result)
{
  const int *loop = body->loop + body->loop_start[face];
  const int count = body->loop_start[face + 1] - body->loop_start[face];
  poly_clip_mask all_out;
  const poly_clip_mask some_out = poly_clip_face_cuts(body, face, ahead, behind, front, back, &all_out);
  if (all_out) return 0;
  if (count > capacity) return -1;
  for (int c = 0; c < count; c++)
    for (int k = 0; k < 3; k++) work_in[3 * c + k] = x[3 * loop[c] + k];
  return poly_clip_by_planes(work_in, work_out, count, planes, some_out, back, capacity, result);
}

/* The faces `faces` of `body` clipped by a piece of the other body (as poly_clip_face_by_piece); each surviving
 * polygon accumulated. Returns 0 when a polygon outgrew the work buffers (the pair goes to the general
 * path). */
POLY_INLINE int poly_clip_faces_by_piece(const poly_clip_faces *body, const int *faces, int num_faces,
                                          const double *x, const poly_clip_mask *ahead, const poly_clip_mask *behind,
                                          const double *planes, poly_clip_mask front, poly_clip_mask back,
                                          poly_clip_mask piece_aside, int on_a, poly_clip_accumulator *acc)
{
  double work[2][3 * POLY_CLIP_MAX_POLYGON], *polygon = 0;
  for (int i = 0; i < num_faces; i++) {
    /* The other piece wholly on one side of the face's plane: the face, on that plane, cannot meet it. */
    if (body->face_plane && ((piece_aside >> body->face_plane[faces[i]]) & 1)) continue;
    int n = poly_clip_face_by_piece(body, faces[i], x, ahead, behind, planes, front, back, work[0], work[1],
                                    POLY_CLIP_MAX_POLYGON, &polygon);
    if (n < 0) return 0;
    if (n >= 3) poly_clip_accumulate(acc, polygon, n, on_a);
  }
  return 1;
}

/* The pieces' sides: per piece, the planes all its points are in front of, and behind. */
POLY_INLINE void poly_clip_piece_sides(const poly_clip_faces *body, const poly_clip_mask *ahead,
                                       const poly_clip_mask *behind, poly_clip_mask *all_ahead,
                                       poly_clip_mask *all_behind)
{
  for (int i = 0; i < body->num_pieces; i++) {
    poly_clip_mask front = ~(poly_clip_mask)0, back = ~(poly_clip_mask)0;
    for (int p = body->piece_point_start[i]; p < body->piece_point_start[i + 1]; p++) {
      front &= ahead[body->piece_points[p]];
      back &= behind[body->piece_points[p]];
    }
    all_ahead[i] = front;
    all_behind[i] = back;
  }
}

/* Shapes that are not both convex: for each pair of pieces that no plane of either parts, B's faces on B's
 * piece clipped by A's piece, and A's faces on A's piece by B's piece (twice when the corners overflow). */
POLY_INLINE int poly_clip_pieces_overlap(const poly_clip_faces *a, const poly_clip_faces *b, const double *xb,
                                         const double *rotation, const double *translation, double flush,
                                         poly_clip_accumulator *acc, poly_clip_result *out,
                                         poly_clip_corners *corners)
{
  double planes_b[4 * POLY_CLIP_MAX_SHAPE_PLANES];
  poly_clip_mask ahead_a[POLY_CLIP_MAX_VERTICES + 1], behind_a[POLY_CLIP_MAX_VERTICES + 1];
  poly_clip_mask ahead_b[POLY_CLIP_MAX_VERTICES + 1], behind_b[POLY_CLIP_MAX_VERTICES + 1];
  poly_clip_mask piece_ahead_a[POLY_CLIP_MAX_PIECES], piece_behind_a[POLY_CLIP_MAX_PIECES];
  poly_clip_mask piece_ahead_b[POLY_CLIP_MAX_PIECES], piece_behind_b[POLY_CLIP_MAX_PIECES];
  for (int f = 0; f < b->num_planes; f++) {
    double *plane = planes_b + 4 * f;
    poly_matrix_apply(rotation, b->planes + 4 * f, plane);
    plane[3] = b->planes[4 * f + 3] + plane[0] * translation[0] + plane[1] * translation[1] + plane[2] * translation[2];
  }
  /* A supporting plane of one with every point of the other in front of it parts them: the code of its triangle
   * is the pair style's hint for the next step (poly_overlap_still_separated), as for convex pairs. */
  const double origin[3] = {0.0, 0.0, 0.0};
  poly_clip_mask parting;
  if (!poly_clip_sides_of_planes(xb, b->num_vertices, translation, a->planes, a->num_planes, flush, ahead_b,
                                 behind_b, &parting))
    return 0;
  if (a->plane_support && (parting &= poly_clip_mask_of(&a->support_planes))) {
    out->separating = a->plane_support[poly_clip_mask_lowest(parting)] << 1;
    return 1;
  }
  if (!poly_clip_sides_of_planes(a->vertices, a->num_vertices, origin, planes_b, b->num_planes, flush, ahead_a,
                                 behind_a, &parting))
    return 0;
  if (b->plane_support && (parting &= poly_clip_mask_of(&b->support_planes))) {
    out->separating = (b->plane_support[poly_clip_mask_lowest(parting)] << 1) | 1;
    return 1;
  }
  poly_clip_piece_sides(b, ahead_b, behind_b, piece_ahead_b, piece_behind_b);
  poly_clip_piece_sides(a, ahead_a, behind_a, piece_ahead_a, piece_behind_a);
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < a->num_pieces; i++) {
      const poly_clip_mask front_a = poly_clip_mask_of(a->piece_front + i), back_a = poly_clip_mask_of(a->piece_back + i);
      for (int j = 0; j < b->num_pieces; j++) {
        const poly_clip_mask front_b = poly_clip_mask_of(b->piece_front + j),
                             back_b = poly_clip_mask_of(b->piece_back + j);
        if ((piece_ahead_b[j] & front_a) | (piece_behind_b[j] & back_a) | (piece_ahead_a[i] & front_b) |
            (piece_behind_a[i] & back_b))
          continue;  /* a plane of one piece has the other wholly outside */
        if (!poly_clip_faces_by_piece(b, b->piece_faces + b->piece_face_start[j],
                                      b->piece_face_start[j + 1] - b->piece_face_start[j], xb, ahead_b, behind_b,
                                      a->planes, front_a, back_a, piece_ahead_a[i] | piece_behind_a[i], 0, acc) ||
            !poly_clip_faces_by_piece(a, a->piece_faces + a->piece_face_start[i],
                                      a->piece_face_start[i + 1] - a->piece_face_start[i], a->vertices, ahead_a,
                                      behind_a, planes_b, front_b, back_b, piece_ahead_b[j] | piece_behind_b[j], 1,
                                      acc))
          return 0;
      }
    }
    if (pass == 0 && poly_clip_finish(acc, translation, out)) {
      const double none[3] = {0.0, 0.0, 0.0};  /* no corners: no reference either */
      poly_clip_keep_corners(acc->nodes, acc->num_kept, acc->num_corners ? acc->reference : none, corners);
      return 1;
    }
  }
  poly_clip_finish_depth(acc, out);
  if (corners) corners->count = -1;
  return 1;
}

/* Two convex shapes (one piece each): each body's vertices against the other's planes; a plane with every vertex
 * of the other body in front of it parts them, and its code is the separation hint. Then each body's faces
 * clipped by the other's planes, all corners kept (0, the general path, when they do not fit), and summed from
 * the first corner. */
POLY_INLINE int poly_clip_convex_overlap(const poly_clip_faces *a, const poly_clip_faces *b, const double *xb,
                                         const double *rotation, const double *translation, double flush,
                                         int want_second, poly_clip_result *out, poly_clip_corners *corners)
{
  double planes_b[4 * POLY_CLIP_MAX_PLANES];
  unsigned front_a[POLY_CLIP_MAX_VERTICES], front_b[POLY_CLIP_MAX_VERTICES], parting = 0;
  const int fa = a->num_faces, fb = b->num_faces;
  for (int f = 0; f < fb; f++) {
    double *plane = planes_b + 4 * f;
    poly_matrix_apply(rotation, b->planes + 4 * f, plane);
    plane[3] = b->planes[4 * f + 3] + plane[0] * translation[0] + plane[1] * translation[1] + plane[2] * translation[2];
  }
  if (!poly_clip_sides(xb, b->num_vertices, a->planes, fa, flush, front_b, &parting)) return 0;
  if (parting) {
    out->separating = a->triangle[poly_clip_lowest_bit(parting)] << 1;
    return 1;
  }
  if (!poly_clip_sides(a->vertices, a->num_vertices, planes_b, fb, flush, front_a, &parting)) return 0;
  if (parting) {
    out->separating = (b->triangle[poly_clip_lowest_bit(parting)] << 1) | 1;
    return 1;
  }
  double nodes[3 * POLY_CLIP_MAX_NODES];
  int counts[2 * POLY_CLIP_MAX_PLANES], num_nodes = 0, num_polygons = 0;
  if (!poly_clip_body(b, xb, a->planes, front_b, 0, nodes, &num_nodes, counts, &num_polygons) ||
      !poly_clip_body(a, a->vertices, planes_b, front_a, 1, nodes, &num_nodes, counts, &num_polygons))
    return 0;
  if (num_nodes == 0) return 1;
  double reference[3] = {nodes[0], nodes[1], nodes[2]};
  for (int p = 0; p < num_nodes; p++)
    for (int k = 0; k < 3; k++) nodes[3 * p + k] -= reference[k];
  poly_clip_sums sums;
  sums.volume6 = sums.area = 0.0;
  for (int k = 0; k < 3; k++) sums.moment24[k] = sums.area_vector[k] = 0.0;
  for (int e = 0; e < 6; e++) sums.second120[e] = 0.0;
  sums.want_second = want_second;
  for (int q = 0, first = 0; q < num_polygons; q++) {
    int n = counts[q] < 0 ? -counts[q] : counts[q];
    poly_clip_add_polygon(nodes + 3 * first, n, counts[q] < 0, &sums);
    first += n;
  }
  if (!poly_clip_result_from_sums(&sums, reference, num_nodes, translation, out)) return 1;
  double low = 1e300, high = -1e300;
  poly_clip_extent(nodes, num_nodes, out->normal, &low, &high);
  out->depth = high > low ? high - low : 0.0;
  poly_clip_keep_corners(nodes, num_nodes, reference, corners);
  return 1;
}

/* Does the host's clipping path take this shape: clip faces, no more planes than the masks hold, and (pieces) no
 * more faces than POLY_CLIP_HOST_PIECE_FACES, unless they are the mesh walls' pieces (poly_shape_wall_pieces)? */
POLY_INLINE int poly_clip_takes(const poly_clip_faces *faces)
{
  return faces->num_faces > 0 && faces->num_planes <= POLY_CLIP_MAX_SHAPE_PLANES &&
         (faces->num_pieces == 1 || faces->num_faces <= POLY_CLIP_HOST_PIECE_FACES || faces->many_faces);
}

/* poly_clip_overlap; with `pieces` 0 (a constant, so that a GPU kernel for convex shapes carries no stack for
 * pieces) pairs of shapes with several pieces are handed back. With `corners` (else NULL), the intersection's
 * corners too (count 0 when apart). */
POLY_INLINE int poly_clip_overlap_of(const poly_clip_faces *a, const poly_clip_faces *b, const double *rotation,
                                     const double *translation, double size, int want_second, int pieces,
                                     poly_clip_result *out, poly_clip_corners *corners)
{
  if (!pieces && (a->num_pieces != 1 || b->num_pieces != 1)) return 0;
  double xb[3 * POLY_CLIP_MAX_VERTICES];
  const double flush = POLY_CLIP_FLUSH * size;
  for (int v = 0; v < b->num_vertices; v++) {
    poly_matrix_apply(rotation, b->vertices + 3 * v, xb + 3 * v);
    for (int k = 0; k < 3; k++) xb[3 * v + k] += translation[k];
  }
  out->volume = out->depth = out->area = out->projected_area = 0.0;
  out->num_nodes = 0;
  out->separating = -1;
  for (int e = 0; e < 6; e++) out->second_moment[e] = 0.0;
  if (corners) corners->count = 0;
  if (a->num_pieces == 1 && b->num_pieces == 1)
    return poly_clip_convex_overlap(a, b, xb, rotation, translation, flush, want_second, out, corners);
  poly_clip_accumulator acc;
  poly_clip_accumulator_start(&acc, want_second);
  return poly_clip_pieces_overlap(a, b, xb, rotation, translation, flush, &acc, out, corners);
}

/* The overlap of A and B, B's body frame taken to A's by `rotation` (row-major) and `translation`. Returns 1
 * with `out` filled (volume 0: apart), or 0 when the pair must take the general path (flush faces). */
POLY_INLINE int poly_clip_overlap(const poly_clip_faces *a, const poly_clip_faces *b, const double *rotation,
                                  const double *translation, double size, int want_second, poly_clip_result *out,
                                  poly_clip_corners *corners)
{
  return poly_clip_overlap_of(a, b, rotation, translation, size, want_second, 1, out, corners);
}

#endif
