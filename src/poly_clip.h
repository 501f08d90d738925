/* The overlap of two convex shapes of few faces by clipping: each body's face
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
 * plane of the other hands the pair back (returns 0): flush faces take the
 * general path, whose smoothing makes the area continuous there; that test
 * is a superset of the general path's own flush test (2^-34 of the size). */
#ifndef POLY_CLIP_H
#define POLY_CLIP_H

#include <math.h>

#include "poly_clip_limits.h"
#include "poly_rigid.h"

/* A convex shape's faces, body frame. */
typedef struct poly_clip_faces {
  int num_faces, num_vertices;
  const double *vertices;  /* 3 per vertex */
  const double *planes;    /* 4 per face: unit outward normal n and offset d, n.x = d on the face */
  const int *loop_start;   /* num_faces + 1 offsets into loop */
  const int *loop;         /* corners of each face in order, counter-clockwise seen from outside */
  const int *triangle;     /* per face its lowest triangle (for the separation hint's code) */
} poly_clip_faces;

/* What the clipping gives, in A's body frame (the caller turns it to world). */
typedef struct poly_clip_result {
  double volume, centroid[3], normal[3], depth, area, projected_area, second_moment[6];
  int num_nodes;
  int separating;  /* apart: the plane that parts them as poly_overlap_result's code ((triangle << 1) | of_b); else -1 */
} poly_clip_result;

typedef struct poly_clip_sums {
  double volume6, moment24[3], second120[6], area_vector[3], area;
  int want_second;
} poly_clip_sums;

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

/* Adds a boundary polygon (outward counter-clockwise) as fan tetrahedra from the origin; with `on_a`, also
 * its area vector and area (A's surface inside B). */
POLY_INLINE void poly_clip_add_polygon(const double *polygon, int count, int on_a, poly_clip_sums *sums)
{
  const double *p0 = polygon;
  for (int i = 1; i + 1 < count; i++) {
    const double *p1 = polygon + 3 * i, *p2 = polygon + 3 * (i + 1);
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
}

/* The faces of `body` (vertices `x`, already in A's frame) clipped by `planes` of the other body (A's frame),
 * `front[v]` the vertices' masks of the planes they are in front of: each surviving polygon's corners are
 * appended to `nodes` and its corner count to `counts` (negative for A's faces). Returns 0 when the buffers
 * are full. */
POLY_INLINE int poly_clip_body(const poly_clip_faces *body, const double *x, const double *planes, int other_faces,
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
    if (*num_nodes + most > POLY_CLIP_MAX_NODES || *num_polygons == 2 * POLY_CLIP_MAX_FACES) return 0;
    double *polygon = nodes + 3 * *num_nodes;
    int n = count;
    if (!some_front) {
      for (int c = 0; c < count; c++)
        for (int k = 0; k < 3; k++) polygon[3 * c + k] = x[3 * loop[c] + k];
    } else {
      double *in = work[0], *out = work[1];
      for (int c = 0; c < count; c++)
        for (int k = 0; k < 3; k++) in[3 * c + k] = x[3 * loop[c] + k];
      for (int k = 0; k < other_faces && n >= 3; k++)
        if (some_front & (1u << k)) {
          n = poly_clip_polygon(in, n, planes + 4 * k, out);
          double *swap = in;
          in = out;
          out = swap;
        }
      if (n < 3) continue;
      for (int c = 0; c < 3 * n; c++) polygon[c] = in[c];
    }
    *num_nodes += n;
    counts[(*num_polygons)++] = on_a ? -n : n;
  }
  return 1;
}

/* Masks of the planes each of `count` points `x` is in front of, into `front`, and in `*parting` the planes every
 * point is in front of; 0 when a point is within `flush` of a plane (the pair goes to the general path). */
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

POLY_INLINE int poly_clip_lowest_bit(unsigned mask)
{
  int k = 0;
  while (!(mask & (1u << k))) k++;
  return k;
}

/* The overlap of A and B, B's body frame taken to A's by `rotation` (row-major) and `translation`. Returns 1
 * with `out` filled (volume 0: apart), or 0 when the pair must take the general path (flush faces, or more
 * polygon corners than the node buffer holds). */
POLY_INLINE int poly_clip_overlap(const poly_clip_faces *a, const poly_clip_faces *b, const double *rotation,
                                  const double *translation, double size, int want_second, poly_clip_result *out)
{
  double xb[3 * POLY_CLIP_MAX_VERTICES], planes_b[4 * POLY_CLIP_MAX_FACES];
  unsigned front_a[POLY_CLIP_MAX_VERTICES], front_b[POLY_CLIP_MAX_VERTICES];
  const int fa = a->num_faces, fb = b->num_faces, na = a->num_vertices, nb = b->num_vertices;
  const double flush = POLY_CLIP_FLUSH * size;
  for (int v = 0; v < nb; v++) {
    poly_matrix_apply(rotation, b->vertices + 3 * v, xb + 3 * v);
    for (int k = 0; k < 3; k++) xb[3 * v + k] += translation[k];
  }
  for (int f = 0; f < fb; f++) {
    double *plane = planes_b + 4 * f;
    poly_matrix_apply(rotation, b->planes + 4 * f, plane);
    plane[3] = b->planes[4 * f + 3] + plane[0] * translation[0] + plane[1] * translation[1] + plane[2] * translation[2];
  }
  out->volume = out->depth = out->area = out->projected_area = 0.0;
  out->num_nodes = 0;
  out->separating = -1;
  for (int e = 0; e < 6; e++) out->second_moment[e] = 0.0;
  /* Each body's vertices against the other's planes; a plane with every vertex of the other body in front of it
   * parts them, and its code is the separation hint. */
  unsigned parting = 0;
  if (!poly_clip_sides(xb, nb, a->planes, fa, flush, front_b, &parting)) return 0;
  if (parting) {
    out->separating = a->triangle[poly_clip_lowest_bit(parting)] << 1;
    return 1;
  }
  if (!poly_clip_sides(a->vertices, na, planes_b, fb, flush, front_a, &parting)) return 0;
  if (parting) {
    out->separating = (b->triangle[poly_clip_lowest_bit(parting)] << 1) | 1;
    return 1;
  }

  double nodes[3 * POLY_CLIP_MAX_NODES];
  int counts[2 * POLY_CLIP_MAX_FACES], num_nodes = 0, num_polygons = 0;
  if (!poly_clip_body(b, xb, a->planes, fa, front_b, 0, nodes, &num_nodes, counts, &num_polygons) ||
      !poly_clip_body(a, a->vertices, planes_b, fb, front_a, 1, nodes, &num_nodes, counts, &num_polygons))
    return 0;
  if (num_nodes == 0) return 1;
  /* Sums from a corner of the intersection, so shallow overlaps lose no digits to a distant origin. */
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
  double volume = sums.volume6 / 6.0;
  if (!(volume > 0.0)) return 1;
  out->volume = volume;
  out->num_nodes = num_nodes;
  double from_reference[3];
  for (int k = 0; k < 3; k++) {
    from_reference[k] = sums.moment24[k] / (24.0 * volume);
    out->centroid[k] = from_reference[k] + reference[k];
  }
  out->area = sums.area;
  if (want_second) {
    for (int e = 0; e < 6; e++) out->second_moment[e] = sums.second120[e] / 120.0;
    poly_second_moment_to_centroid(out->second_moment, volume, from_reference);
  }
  /* Normal (eq. 4.19): A's surface inside B; the centre line when it sums to nothing. */
  double length = sqrt(sums.area_vector[0] * sums.area_vector[0] + sums.area_vector[1] * sums.area_vector[1] +
                       sums.area_vector[2] * sums.area_vector[2]);
  out->projected_area = length;
  if (length > 1e-9 * sums.area && length > 0.0) {
    for (int k = 0; k < 3; k++) out->normal[k] = sums.area_vector[k] / length;
  } else {
    double t = sqrt(translation[0] * translation[0] + translation[1] * translation[1] + translation[2] * translation[2]);
    for (int k = 0; k < 3; k++) out->normal[k] = t > 0.0 ? translation[k] / t : (k == 2 ? 1.0 : 0.0);
  }
  double low = 1e300, high = -1e300;
  for (int p = 0; p < num_nodes; p++) {
    const double *x = nodes + 3 * p;
    double along = out->normal[0] * x[0] + out->normal[1] * x[1] + out->normal[2] * x[2];
    low = along < low ? along : low;
    high = along > high ? along : high;
  }
  out->depth = high > low ? high - low : 0.0;
  return 1;
}

#endif
