/* The parting search: a plane between two bodies that neither the centre line's slab nor a supporting triangle
 * parts (the host's general path and its clipping path; on the GPU, the pre-filter before the contact kernels).
 * Included by poly_overlap_impl.h once per precision (no include guard).
 *
 * Why: of the pairs whose bounding spheres meet, some are apart and yet not parted by those filters (two rocks edge
 * to edge: no face plane and not the centre line separates them), and each such near miss paid the whole general
 * path to find a volume of 0 (6.5 % of the converted movingMeshGran's pair evaluations, 8 % of the hopper's), and
 * again at the next step, having proved no gap for the pair style to wait on (skip_apart).
 *
 * How: each body lies in the convex hull of its vertices, so a plane between the two hulls parts the bodies. The
 * hulls' closest points are found by GJK on the Minkowski difference B - A (its support along u is B's lowest
 * vertex along u less A's highest, the slab's own extremes: highest_vertex and its table), stopping once a
 * direction's separation is half the distance the simplex still leaves, or after POLY_PARTING_STEPS. What is
 * decided rests only on the slab's test along each direction tried (any direction is valid): the separation of the
 * extremes, in double, as overlap_slab_extremes computes it, the best kept; the simplex's arithmetic only steers,
 * so its rounding can cost a miss (the general path then decides) but never a wrong answer. */

#ifndef POLY_PARTING_STEPS
#define POLY_PARTING_STEPS 10
#endif

/* The simplex cut to its points keep[0..n). */
POLY_INLINE void POLY_FN(parting_keep)(double (*w)[3], int *count, const int *keep, int n)
{
  double kept[4][3];
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++) kept[i][k] = w[keep[i]][k];
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++) w[i][k] = kept[i][k];
  *count = n;
}

POLY_INLINE double POLY_FN(parting_dot)(const double *x, const double *y)
{
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}

/* parting_triangle's answers: a corner's region (the corner itself, keeping corner i), and an edge's (the point
 * at t along it from `from`, keeping corners i and j). */
POLY_INLINE int POLY_FN(parting_at_corner)(const double *corner, int i, double *v, int *keep)
{
  for (int k = 0; k < 3; k++) v[k] = corner[k];
  keep[0] = i;
  return 1;
}

POLY_INLINE int POLY_FN(parting_on_edge)(const double *from, const double *along, double t, int i, int j, double *v,
                                         int *keep)
{
  for (int k = 0; k < 3; k++) v[k] = from[k] + t * along[k];
  keep[0] = i, keep[1] = j;
  return 2;
}

/* Nearest point to the origin of triangle (p, q, r), its region as the corners it keeps (into keep, returns their
 * count). 0 when the triangle is degenerate (its face region's weights not positive). */
POLY_INLINE int POLY_FN(parting_triangle)(const double *p, const double *q, const double *r, double *v, int *keep)
{
  double pq[3], pr[3], qr[3];
  for (int k = 0; k < 3; k++) {
    pq[k] = q[k] - p[k];
    pr[k] = r[k] - p[k];
    qr[k] = r[k] - q[k];
  }
  const double d1 = -POLY_FN(parting_dot)(pq, p), d2 = -POLY_FN(parting_dot)(pr, p);
  if (d1 <= 0.0 && d2 <= 0.0) return POLY_FN(parting_at_corner)(p, 0, v, keep);
  const double d3 = -POLY_FN(parting_dot)(pq, q), d4 = -POLY_FN(parting_dot)(pr, q);
  if (d3 >= 0.0 && d4 <= d3) return POLY_FN(parting_at_corner)(q, 1, v, keep);
  const double weight_r = d1 * d4 - d3 * d2;
  if (weight_r <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0)
    return POLY_FN(parting_on_edge)(p, pq, d1 / (d1 - d3), 0, 1, v, keep);
  const double d5 = -POLY_FN(parting_dot)(pq, r), d6 = -POLY_FN(parting_dot)(pr, r);
  if (d6 >= 0.0 && d5 <= d6) return POLY_FN(parting_at_corner)(r, 2, v, keep);
  const double weight_q = d5 * d2 - d1 * d6;
  if (weight_q <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0)
    return POLY_FN(parting_on_edge)(p, pr, d2 / (d2 - d6), 0, 2, v, keep);
  const double weight_p = d3 * d6 - d5 * d4;
  if (weight_p <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
    return POLY_FN(parting_on_edge)(q, qr, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 1, 2, v, keep);
  const double total = weight_p + weight_r + weight_q;
  if (!(total > 0.0)) return 0;
  const double s = weight_q / total, t = weight_r / total;
  for (int k = 0; k < 3; k++) v[k] = p[k] + s * pq[k] + t * pr[k];
  keep[0] = 0, keep[1] = 1, keep[2] = 2;
  return 3;
}

/* The point of the simplex w[0..count) nearest the origin, into *v; the simplex is cut to the least of its points
 * whose hull holds that point. Returns 0 when the origin is in it (or the simplex is flat and the origin maybe so):
 * the hulls may meet. Ericson's regions (Real-Time Collision Detection, 5.1.5 and 5.1.6), the origin as the query. */
POLY_INLINE int POLY_FN(parting_nearest)(double (*w)[3], int *count, double *v)
{
  int keep[3];
  if (*count == 1) {
    for (int k = 0; k < 3; k++) v[k] = w[0][k];
    return 1;
  }
  if (*count == 2) {
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = w[1][k] - w[0][k];
    const double along = -POLY_FN(parting_dot)(w[0], d), length2 = POLY_FN(parting_dot)(d, d);
    if (along > 0.0 && along < length2) {
      const double t = along / length2;
      for (int k = 0; k < 3; k++) v[k] = w[0][k] + t * d[k];
      return 1;
    }
    keep[0] = along > 0.0 ? 1 : 0;
    POLY_FN(parting_keep)(w, count, keep, 1);
    for (int k = 0; k < 3; k++) v[k] = w[0][k];
    return 1;
  }
  if (*count == 3) {
    const int n = POLY_FN(parting_triangle)(w[0], w[1], w[2], v, keep);
    if (!n) return 0;
    POLY_FN(parting_keep)(w, count, keep, n);
    return 1;
  }
  /* A tetrahedron: the faces the origin lies beyond (strictly: a flat one parts nothing), the nearest of theirs. */
  static const int face[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  double best = INFINITY;
  int best_keep[3], best_n = 0;
  for (int f = 0; f < 4; f++) {
    const double *p = w[face[f][0]], *q = w[face[f][1]], *r = w[face[f][2]], *o = w[face[f][3]];
    double pq[3], pr[3], po[3], n[3];
    for (int k = 0; k < 3; k++) {
      pq[k] = q[k] - p[k];
      pr[k] = r[k] - p[k];
      po[k] = o[k] - p[k];
    }
    poly_cross3_d(pq, pr, n);
    const double origin_side = -POLY_FN(parting_dot)(p, n), opposite_side = POLY_FN(parting_dot)(po, n);
    if (!(origin_side * opposite_side < 0.0)) continue;
    double u[3];
    int k3[3];
    const int m = POLY_FN(parting_triangle)(p, q, r, u, k3);
    if (!m) continue;
    const double d2 = POLY_FN(parting_dot)(u, u);
    if (d2 < best) {
      best = d2;
      best_n = m;
      for (int k = 0; k < 3; k++) v[k] = u[k];
      for (int i = 0; i < m; i++) best_keep[i] = face[f][k3[i]];
    }
  }
  if (!best_n) return 0;
  POLY_FN(parting_keep)(w, count, best_keep, best_n);
  return 1;
}

/* A direction along which the bodies are apart: GJK on B - A, its first support point that of the centre line's slab
 * (`extreme_a`, `extreme_b`: A's highest and B's lowest vertex along it, overlap_slab_extremes'), which did not part
 * them. Returns 1 when a direction parts them by more than a supporting triangle must (support_reach: bodies that
 * touch by less, or overlap, are left to the general path), with *separation that gap (B's lowest place along it
 * less A's highest). */
POLY_INLINE int POLY_FN(parting_search)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                        const double *rotation, const double *translation, int extreme_a,
                                        int extreme_b, double *separation)
{
  const double size = (double)a->bounding_radius + (double)b->bounding_radius, reach = POLY_FN(support_reach)(a, b);
  double w[4][3], v[3];
  int count = 0;
  double best = -INFINITY;
  for (int step = 0; step < POLY_PARTING_STEPS; step++) {
    /* The support point of B - A along -v, in A's frame. */
    const R *x = b->vertices + 3 * extreme_b, *y = a->vertices + 3 * extreme_a;
    double support[3];
    for (int k = 0; k < 3; k++)
      support[k] = rotation[3 * k] * x[0] + rotation[3 * k + 1] * x[1] + rotation[3 * k + 2] * x[2] +
                   translation[k] - (double)y[k];
    /* No point of B - A nearer the origin along v than v itself (to its rounding): v is the nearest. */
    if (count > 0) {
      const double nearest2 = POLY_FN(parting_dot)(v, v);
      if (nearest2 - POLY_FN(parting_dot)(v, support) <= 1e-12 * nearest2) break;
    }
    for (int k = 0; k < 3; k++) w[count][k] = support[k];
    count++;
    if (!POLY_FN(parting_nearest)(w, &count, v)) break;
    const double length2 = POLY_FN(parting_dot)(v, v);
    if (!(length2 > 1e-24 * size * size) || !(length2 < INFINITY)) break;
    /* The slab along u, computed as overlap_slab_extremes computes it, which also gives the next support point. */
    const double inverse = 1.0 / sqrt(length2);
    const double u[3] = {v[0] * inverse, v[1] * inverse, v[2] * inverse};
    double turned[3];
    for (int i = 0; i < 3; i++) turned[i] = -(rotation[i] * u[0] + rotation[3 + i] * u[1] + rotation[6 + i] * u[2]);
    const double shift = u[0] * translation[0] + u[1] * translation[1] + u[2] * translation[2];
    const double high_a = POLY_FN(highest_vertex)(a, u, -0.0, &extreme_a);
    const double low_b = -POLY_FN(highest_vertex)(b, turned, -shift, &extreme_b);
    if (low_b - high_a > best) best = low_b - high_a;
    if (best > reach && best >= 0.5 * sqrt(length2)) break;
  }
  *separation = best;
  return best > reach;
}

/* The centre line's slab, then (with `search`) the parting search: 1 when either parts the bodies, with
 * *separation the gap it leaves. The clipping path's filter on the host and the GPU's pre-filter. */
POLY_INLINE int POLY_FN(slab_or_parting)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                         const double *rotation, const double *translation, int search,
                                         double *separation)
{
  double axis[3], extent_a, extent_b;
  int extreme_a, extreme_b;
  int apart = POLY_FN(overlap_slab_extremes)(a, b, rotation, translation, axis, &extent_a, &extent_b, &extreme_a,
                                             &extreme_b);
  *separation = extent_b - extent_a;
  if (!apart && search)
    apart = POLY_FN(parting_search)(a, b, rotation, translation, extreme_a, extreme_b, separation);
  return apart;
}
