/* The crossing cache of the records path (poly_crossing_cache in poly_overlap.h). Included by
 * poly_overlap_records_impl.h once per precision (no include guard).
 *
 * A resting contact keeps the same edge-triangle crossings for hundreds of steps (tools/coherence_study.sh: in
 * the settled pile of rock_40, 90 % of the contacts through 1000 steps), while the search that finds them is half
 * of the general path's time. After a search, a certificate bounds how far B may move relative to A (in A's body
 * frame) before any decision of that search can change: each (edge, triangle) decision rests on orientation
 * determinants det(x, y, z) of differences of the bodies' points; a motion m of B moves such a difference by at
 * most m (a point of each body), |v| m / r_B (two of B: its turn) or only by rounding (two of A), and so the
 * determinant by at most the first-order terms |dx||y x z| + ... and the products of two or three changes
 * (cache_det_margin), so a determinant whose value, less its rounding bound, exceeds that keeps its sign, and its
 * exact predicate its decision. A crossing
 * needs all five of its determinants (both ends' sides of the triangle's plane, the three edge orientations), a
 * miss one reason (both ends on one side, two orientations that disagree, boxes apart). While B's motion stays
 * under the least of these margins (but for the watched pairs, decided again: cache_watch) the crossings stay
 * those of the search, and so do the vertices inside the
 * other body (a vertex changes sides only where an edge of it changes crossings) and the edges with inside parts.
 * The next evaluations then skip the filter, the search and the inside states: each crossing's parameter comes
 * from the same predicates, and the same functions sum the same parts in the same order (cache_replay), so every
 * bit is the search's. A near miss (no crossing, no vertex inside: bodies apart that the filter did not part) is
 * certified the same way, and its evaluations return the empty pass. */

/* The crossing cache's cap: POLY_CACHE_CAP of the two bounding radii (3e-4 and 3e-3 did no better in the rock
 * pile of tools/bench_vs_multisphere.sh before the watched pairs below); certificates are made for pairs that
 * moved by less than POLY_CACHE_GATE of it since their last search. */
#ifndef POLY_CACHE_CAP
#define POLY_CACHE_CAP 1e-3
#endif
/* Tests only (tests/test_crossing_cache.py): certificates inflated by this factor must be caught. */
#ifndef POLY_CACHE_MARGIN_SCALE
#define POLY_CACHE_MARGIN_SCALE 1
#endif
/* Tests only: 0 skips the watched pairs' decisions, or the outside vertices they need (cache_outside_vertices);
 * tests/test_crossing_cache.py must then find differences. */
#ifndef POLY_CACHE_WATCH_CHECKS
#define POLY_CACHE_WATCH_CHECKS 1
#endif
#ifndef POLY_CACHE_OUTSIDE_CHECKS
#define POLY_CACHE_OUTSIDE_CHECKS 1
#endif
/* Tests only: the watched pairs' rechecks (cache_replay) made this many times as long must be caught. */
#ifndef POLY_CACHE_RECHECK_SCALE
#define POLY_CACHE_RECHECK_SCALE 1
#endif
#ifndef POLY_CACHE_GATE
#define POLY_CACHE_GATE 1.0
#endif
/* A certificate reaches POLY_CACHE_REACH caps: the pairs whose margins fall below it (at most POLY_CACHE_WATCH, the
 * least) are watched, decided again once B's motion reaches their margins, instead of ending the certificate
 * there. */
#ifndef POLY_CACHE_REACH
#define POLY_CACHE_REACH 8.0
#endif
/* How a vector of a decision's determinant moves with B's motion m (cache_motion: |R - R0|_F r_B + |T - T0| and
 * the rounding) in A's frame: a difference of two points of A not at all, one of two points of B by its turn, at
 * most |v| |R - R0|_F <= |v| m / r_B, one of a point of each body by at most m; each also by the coordinates'
 * rounding in both poses (the caller's `fixed`). */
#ifndef POLY_CACHE_OF_A
#define POLY_CACHE_OF_A 0
#define POLY_CACHE_OF_B 1
#define POLY_CACHE_ACROSS 2
#endif

typedef struct POLY_FN(det_growth) {
  double n[3], c[3], rate[3]; /* the vectors' lengths, the cross products' opposite them, their rates */
  double rounding, at_rest;   /* the value's rounding bound; F at m = 0 */
} POLY_FN(det_growth);

/* What of cache_det_margin's margin (below) depends on the vectors only, so that one determinant's margins for two
 * slacks (the flush test's and none) are made from one. */
POLY_INLINE void POLY_FN(cache_det_growth)(const R *x, const R *y, const R *z, const int *kind, double inv_rb,
                                           double fixed, POLY_FN(det_growth) *g)
{
  const double eps = (double)POLY_FN(epsilon)();
  const R *v[3] = {x, y, z};
  double w[3][3];
  for (int i = 0; i < 3; i++) {
    for (int k = 0; k < 3; k++) w[i][k] = (double)v[i][k];
    /* Lengths and cross products in double, padded for their rounding and for that of the differences themselves
     * (made in the type R: a sliver's cross product may be far smaller than the product of its lengths). */
    g->n[i] = (1.0 + 1e-9 + 4.0 * eps) * sqrt(w[i][0] * w[i][0] + w[i][1] * w[i][1] + w[i][2] * w[i][2]);
    g->rate[i] = kind[i] == POLY_CACHE_OF_A ? 0.0 : (kind[i] == POLY_CACHE_OF_B ? 1.001 * g->n[i] * inv_rb : 1.001);
  }
  for (int i = 0; i < 3; i++) {
    const double *p = w[i == 2 ? 0 : i + 1], *q = w[i == 0 ? 2 : i - 1];
    const double cx = p[1] * q[2] - p[2] * q[1], cy = p[2] * q[0] - p[0] * q[2], cz = p[0] * q[1] - p[1] * q[0];
    g->c[i] = (1.0 + 1e-9) * sqrt(cx * cx + cy * cy + cz * cz) +
              4.0 * eps * g->n[i == 2 ? 0 : i + 1] * g->n[i == 0 ? 2 : i - 1];
  }
  const double b = fixed;
  g->at_rest = b * (g->c[0] + g->c[1] + g->c[2]) + b * b * (g->n[0] + g->n[1] + g->n[2]) + b * b * b;
  g->rounding = 128.0 * eps * (double)POLY_FN(norm1)(x) * (double)POLY_FN(norm1)(y) * (double)POLY_FN(norm1)(z);
}

POLY_INLINE double POLY_FN(cache_det_room)(const POLY_FN(det_growth) *g, double fixed, double value, double slack,
                                           double least, int *ok)
{
  const double room = fabs(value) - slack - g->rounding - 1.001 * g->at_rest;
  *ok = room > 0.0;
  if (!(room > 0.0)) return 0.0;
  const double b = fixed;
  double d[3];
  for (int i = 0; i < 3; i++) d[i] = g->rate[i] * least + b;
  const double slope = g->rate[0] * (g->c[0] + d[1] * g->n[2] + g->n[1] * d[2] + d[1] * d[2]) +
                       g->rate[1] * (g->c[1] + d[0] * g->n[2] + g->n[0] * d[2] + d[0] * d[2]) +
                       g->rate[2] * (g->c[2] + d[0] * g->n[1] + g->n[0] * d[1] + d[0] * d[1]);
  return room >= least * slope ? least : room / slope;
}

/* The motion below which det(x, y, z), of value `value`, keeps its sign: x, y, z change by at most
 * delta_i = rate_i m + fixed (rate by `kind`, above), and det changes by at most
 * F = d0 |y x z| + d1 |z x x| + d2 |x x y| + d0 d1 |z| + d0 |y| d2 + |x| d1 d2 + d0 d1 d2, whose slope in m up to
 * `least` is sum_i rate_i dF/dd_i at delta(least). The room is |value| less its rounding bound (generous: the
 * predicates' fast filters use 32 units of the type's roundoff on the same products of 1-norms), `slack` and F at
 * m = 0. Returns `least` itself when that is within it (no division: the caller keeps the least over its pairs), 0
 * when the room is not positive (*ok 0: the value's sign is not certain). */
POLY_INLINE double POLY_FN(cache_det_margin)(const R *x, const R *y, const R *z, const int *kind, double inv_rb,
                                             double fixed, double value, double slack, double least, int *ok)
{
  POLY_FN(det_growth) g;
  POLY_FN(cache_det_growth)(x, y, z, kind, inv_rb, fixed, &g);
  return POLY_FN(cache_det_room)(&g, fixed, value, slack, least, ok);
}

/* The motion that leaves the decision on edge p0 p1 against triangle `tri` (vertices `q`) unchanged, or any
 * value >= `least` when that one is (the caller keeps the least over the pairs); `gap`: the margin their boxes'
 * gap gives (0 when they meet); `tolerance` > 0: the flush test's, whose reach (tolerance |plane|_1) one end of
 * the edge must stay beyond. */
POLY_INLINE double POLY_FN(cache_pair_margin)(const R *p0, const R *p1, const R *q, const int *tri, double tolerance,
                                              double gap, int mine_is_b, double inv_rb, double fixed, double least)
{
  const R *q0 = q + 3 * tri[0], *q1 = q + 3 * tri[1], *q2 = q + 3 * tri[2];
  R e1[3], e2[3], c0[3], c1[3], d[3];
  POLY_FN(sub)(q1, q0, e1);
  POLY_FN(sub)(q2, q0, e2);
  POLY_FN(sub)(p0, q0, c0);
  POLY_FN(sub)(p1, q0, c1);
  const double s0 = (double)POLY_FN(det)(e1, e2, c0), s1 = (double)POLY_FN(det)(e1, e2, c1);
  /* The triangle's edges are the other body's, the edge's its own; the rest joins a point of each. */
  const int of_triangle = mine_is_b ? POLY_CACHE_OF_A : POLY_CACHE_OF_B;
  const int plane_kinds[3] = {of_triangle, of_triangle, POLY_CACHE_ACROSS};
  const int edge_kinds[3] = {mine_is_b ? POLY_CACHE_OF_B : POLY_CACHE_OF_A, POLY_CACHE_ACROSS, POLY_CACHE_ACROSS};
  int ok0, ok1;
  POLY_FN(det_growth) g0, g1;
  POLY_FN(cache_det_growth)(e1, e2, c0, plane_kinds, inv_rb, fixed, &g0);
  POLY_FN(cache_det_growth)(e1, e2, c1, plane_kinds, inv_rb, fixed, &g1);
  const double m0 = POLY_FN(cache_det_room)(&g0, fixed, s0, 0.0, least, &ok0);
  const double m1 = POLY_FN(cache_det_room)(&g1, fixed, s1, 0.0, least, &ok1);
  double flush = 1e300;
  if (tolerance > 0.0) {
    R plane[3];
    POLY_FN(cross)(e1, e2, plane);
    /* Twice the reach: B's turn changes its planes' 1-norms (by far less than their size). */
    const double reach = 2.0 * tolerance * (double)POLY_FN(norm1)(plane);
    /* Both ends within the reach would send the pair to the flush test: one must stay beyond it. */
    int f0, f1;
    double r0 = POLY_FN(cache_det_room)(&g0, fixed, s0, reach, least, &f0);
    double r1 = POLY_FN(cache_det_room)(&g1, fixed, s1, reach, least, &f1);
    flush = r0 > r1 ? r0 : r1;
    if (!f0 && !f1) return 0.0;
  }
  const int straddles = ok0 && ok1 && ((s0 > 0) != (s1 > 0));
  double margin = gap;
  if (ok0 && ok1 && !straddles) {
    /* Both ends on one side: a miss for as long as they stay there. */
    const double both = m0 < m1 ? m0 : m1;
    margin = both > margin ? both : margin;
    if (margin >= least) return flush < margin ? flush : margin;
  }
  POLY_FN(sub)(p1, p0, d);
  const R *corners[3] = {q0, q1, q2};
  double om[3];
  int sign[3], known[3];
  for (int k = 0; k < 3; k++) {
    /* det(d, q_k - p0, q_k+1 - p0): the edge against the triangle's edge k (the three agree on a crossing). */
    R a[3], b[3];
    POLY_FN(sub)(corners[k], p0, a);
    POLY_FN(sub)(corners[k == 2 ? 0 : k + 1], p0, b);
    const double o = (double)POLY_FN(det)(d, a, b);
    om[k] = POLY_FN(cache_det_margin)(d, a, b, edge_kinds, inv_rb, fixed, o, 0.0, least, &known[k]);
    sign[k] = o > 0;
    /* The first two disagreeing for good: a miss by a margin of at least `least`, whatever the third. */
    if (k == 1 && known[0] && known[1] && sign[0] != sign[1] && om[0] >= least && om[1] >= least)
      return flush < least ? flush : least;
  }
  const int agree = known[0] && known[1] && known[2] && sign[0] == sign[1] && sign[1] == sign[2];
  if (straddles && agree) {
    margin = m0 < m1 ? m0 : m1;
    for (int k = 0; k < 3; k++) margin = om[k] < margin ? om[k] : margin;
  } else {
    /* A miss: the best of its reasons. */
    for (int k = 0; k < 3; k++)
      for (int l = k + 1; l < 3; l++)
        if (known[k] && known[l] && sign[k] != sign[l]) {
          double both = om[k] < om[l] ? om[k] : om[l];
          margin = both > margin ? both : margin;
        }
  }
  return flush < margin ? flush : margin;
}

/* Watches the pair (edge e of the body `of_b`, triangle t of the other) of margin `margin` < `least` (the least
 * margin of the pairs not watched): kept in the cache's watch list by ascending margin; when the list is full the
 * pair of the largest margin is left out, and the certificate's least margin becomes that. Returns the least. */
POLY_INLINE double POLY_FN(cache_watch)(poly_crossing_cache *cache, int e, int t, int of_b, double margin,
                                        double least)
{
  int slot = cache->num_watch;
  if (slot == POLY_CACHE_WATCH) {
    const double largest = cache->watch_margin[slot - 1];
    if (!(margin < largest)) return margin;
    least = largest < least ? largest : least;
    slot--;
  } else {
    cache->num_watch++;
  }
  for (; slot > 0 && cache->watch_margin[slot - 1] > margin; slot--) {
    cache->watch_edge[slot] = cache->watch_edge[slot - 1];
    cache->watch_triangle[slot] = cache->watch_triangle[slot - 1];
    cache->watch_of_b[slot] = cache->watch_of_b[slot - 1];
    cache->watch_margin[slot] = cache->watch_margin[slot - 1];
  }
  cache->watch_edge[slot] = e;
  cache->watch_triangle[slot] = t;
  cache->watch_of_b[slot] = (unsigned char)of_b;
  cache->watch_margin[slot] = margin;
  return least;
}

/* The search's decision on edge e of `mine` against triangle t of `other` (find_crossings' box test, flush reach,
 * sides and crossing test, on the same numbers): 1 a crossing, 0 none, -1 both ends within the flush test's reach
 * (the search decides those; the caller searches). */
POLY_INLINE int POLY_FN(cache_decide)(const POLY_FN(shape_view) *mine, const R *my_vertices, int mine_is_b, int e,
                                      const POLY_FN(shape_view) *other, const R *other_vertices, int t, R tolerance)
{
  const R *p0 = my_vertices + 3 * mine->edges[2 * e], *p1 = my_vertices + 3 * mine->edges[2 * e + 1];
  const int *tri = other->triangles + 3 * t;
  R low[3], high[3], box[6], plane[4];
  POLY_FN(segment_bounds)(p0, p1, low, high);
  POLY_FN(triangle_bounds)(other_vertices, tri, box, box + 3);
  for (int k = 0; k < 3; k++) {
    box[k] -= tolerance;
    box[3 + k] += tolerance;
  }
  if (!POLY_FN(boxes_overlap)(low, high, box)) return 0;
  POLY_FN(triangle_plane)(other_vertices, tri, plane);
  R side0 = POLY_FN(plane_side)(p0, other_vertices, tri, plane);
  R side1 = POLY_FN(plane_side)(p1, other_vertices, tri, plane);
  if (tolerance > 0) {
    R reach = tolerance * POLY_FN(norm1)(plane);
    if (fabs(side0) <= reach && fabs(side1) <= reach) return -1;
  }
  int sign0 = POLY_FN(side_sign)(side0, mine_is_b, other_vertices, tri, plane);
  int sign1 = POLY_FN(side_sign)(side1, mine_is_b, other_vertices, tri, plane);
  if (sign0 == sign1) return 0;
  R lambda;
  return POLY_FN(records_crossing_in_triangle)(p0, p1, mine_is_b, other_vertices, tri, side0, side1, sign0,
                                               &lambda) != 0;
}

/* Watched pairs are decided at the pose evaluated, not along the way to it: every edge then crosses what it
 * crossed at the search, but a body small enough to pass through a face between two evaluations (thinner than
 * the reach) could have gone inside the other with the same crossings. Each body's vertices are inside or not by
 * the parity of the crossings along the mesh's edges from any one vertex (the mesh is connected), so one vertex of
 * each body that stays outside the other throughout the reach fixes them all: a vertex of A farther than r_B +
 * reach from B's centre, one of B farther than r_A + reach from A's (B's points move by at most the motion). */
POLY_INLINE int POLY_FN(cache_outside_vertices)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                                const double *rotation, const double *translation, double reach)
{
  const double ra = (double)a->bounding_radius, rb = (double)b->bounding_radius;
  const double far = 1e-9 * (ra + rb + fabs(translation[0]) + fabs(translation[1]) + fabs(translation[2]));
  const double beyond_b = rb + reach + far, beyond_a = ra + reach + far;
  int found = 0;
  for (int i = 0; i < a->num_vertices && !found; i++) {
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
      const double d = (double)a->vertices[3 * i + k] - translation[k];
      d2 += d * d;
    }
    found = d2 > beyond_b * beyond_b;
  }
  if (!found) return 0;
  for (int j = 0; j < b->num_vertices; j++) {
    const R *v = b->vertices + 3 * j;
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
      const double x = rotation[3 * k] * v[0] + rotation[3 * k + 1] * v[1] + rotation[3 * k + 2] * v[2] + translation[k];
      d2 += x * x;
    }
    if (d2 > beyond_a * beyond_a) return 1;
  }
  return 0;
}

/* The local coordinates' rounding, in the pose of translation T and in any within `reach` of it: 32 units of
 * roundoff of the largest coordinate (the origin lies between the bodies on the centre line). */
POLY_INLINE double POLY_FN(cache_fixed)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                        const double *translation, double reach)
{
  const double distance = sqrt(translation[0] * translation[0] + translation[1] * translation[1] +
                               translation[2] * translation[2]),
               size = (double)a->bounding_radius + (double)b->bounding_radius;
  return 32.0 * (double)POLY_FN(epsilon)() * (2.0 * size + distance + reach);
}

/* The margin of edge p0 p1 (box [low, high]) against triangle `tri` of the other body (box `box`, unpadded): the
 * boxes' gap, beyond the flush test's growth of them, when that is at least `least`, else cache_pair_margin. */
POLY_INLINE double POLY_FN(cache_boxed_margin)(const R *p0, const R *p1, const R *low, const R *high, const R *box,
                                               const R *q, const int *tri, double tolerance, int mine_is_b,
                                               double inv_rb, double fixed, double least)
{
  double gap = 0.0;
  for (int k = 0; k < 3; k++) {
    double g = (double)box[k] - (double)high[k], h = (double)low[k] - (double)box[3 + k];
    g = g > h ? g : h;
    gap = g > gap ? g : gap;
  }
  /* Boxes apart, by more than the flush test's growth of them: a miss for as long as they stay apart. */
  gap = 0.5 * (gap - 4.0 * tolerance);
  if (gap >= least) return gap;
  return POLY_FN(cache_pair_margin)(p0, p1, q, tri, tolerance, gap > 0.0 ? gap : 0.0, mine_is_b, inv_rb, fixed, least);
}

/* Watched pair w's decision at the pose of `va`, `vb` (cache_decide on its edge and triangle). */
POLY_INLINE int POLY_FN(cache_watched_decision)(const POLY_FN(shape_view) *a, const R *va,
                                                const POLY_FN(shape_view) *b, const R *vb,
                                                const poly_crossing_cache *cache, int w, R tolerance)
{
  return cache->watch_of_b[w]
             ? POLY_FN(cache_decide)(b, vb, 1, cache->watch_edge[w], a, va, cache->watch_triangle[w], tolerance)
             : POLY_FN(cache_decide)(a, va, 0, cache->watch_edge[w], b, vb, cache->watch_triangle[w], tolerance);
}

/* How far, along the slab's axis, a point's place against the other body's extreme may move while B moves by d <
 * cap (translation T of B in A's frame): by d itself, and by the axis (the centre line, T / |T|) turning by up to
 * 2 d / |T| at points up to r_A + r_B + |T| from A's centre; twice that, and 2 cap for the two bodies' motion. */
POLY_INLINE double POLY_FN(cache_band)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                       const double *translation, double cap)
{
  const double distance = sqrt(translation[0] * translation[0] + translation[1] * translation[1] +
                               translation[2] * translation[2]);
  const double size = (double)a->bounding_radius + (double)b->bounding_radius;
  if (!(distance > 1e-3 * size)) return 1e300; /* centres nearly together: the axis may turn anywhere */
  return 2.0 * cap + 2.0 * cap * (1.0 + 2.0 * (size + distance) / distance);
}

/* The certificate of one way (edges of `mine` against triangles of `other`) over the pairs the search could test
 * while each body moves by less than cap (their boxes within 2 cap, both within `band` of the slab's other side):
 * those of margin below the least are watched (cache_watch), and the least margin of the others, at most `least`
 * (cap or the other way's), returned; 0 as soon as that is. */
POLY_INLINE double POLY_FN(cache_certificate_way)(const POLY_FN(shape_view) *mine, const R *my_vertices,
                                                  const R *my_along, const POLY_FN(shape_view) *other,
                                                  const R *other_vertices, const R *other_along, int mine_is_b,
                                                  double limit_mine, double limit_other, double tolerance,
                                                  double cap, double band, double inv_rb, double fixed,
                                                  double least, poly_crossing_cache *cache,
                                                  POLY_FN(overlap_workspace) *ws)
{
  /* Along the slab's axis (a unit vector), B lies at >= limit_a and A at <= limit_b: a point of `mine` short of
   * its limit by more than `band`, or of `other` beyond its own, is neither in a later pose's slab (whose axis
   * turns with the centre line: cache_band) nor able to meet the other body, and so is an edge or a triangle all
   * of whose points are: the search tests no pair of them, not even for flush faces. */
  const double sign = mine_is_b ? -1.0 : 1.0, reach_mine = sign * limit_mine - band,
               reach_other = -sign * limit_other - band;
  /* The other's triangles in that band, with their boxes and the box of them all; then my edges in my band, with
   * theirs (the boxes in the convex path's side table, the lists in the grid's: both free here). */
  int *near = ws->grid_candidates, *edges = ws->grid_entries, num_near = 0, num_edges = 0;
  R *boxes = ws->sides, *edge_boxes = ws->sides + 6 * other->num_triangles;
  double other_low[3] = {1e300, 1e300, 1e300}, other_high[3] = {-1e300, -1e300, -1e300};
  double my_low[3] = {1e300, 1e300, 1e300}, my_high[3] = {-1e300, -1e300, -1e300};
  for (int t = 0; t < other->num_triangles; t++) {
    const int *tri = other->triangles + 3 * t;
    if (!(-sign * (double)other_along[tri[0]] >= reach_other || -sign * (double)other_along[tri[1]] >= reach_other ||
          -sign * (double)other_along[tri[2]] >= reach_other))
      continue;
    R *box = boxes + 6 * num_near;
    POLY_FN(triangle_bounds)(other_vertices, tri, box, box + 3);
    for (int k = 0; k < 3; k++) {
      other_low[k] = (double)box[k] < other_low[k] ? (double)box[k] : other_low[k];
      other_high[k] = (double)box[3 + k] > other_high[k] ? (double)box[3 + k] : other_high[k];
    }
    near[num_near++] = t;
  }
  for (int e = 0; e < mine->num_edges; e++) {
    if (!(sign * (double)my_along[mine->edges[2 * e]] >= reach_mine ||
          sign * (double)my_along[mine->edges[2 * e + 1]] >= reach_mine))
      continue;
    R *box = edge_boxes + 6 * num_edges;
    POLY_FN(segment_bounds)(my_vertices + 3 * mine->edges[2 * e], my_vertices + 3 * mine->edges[2 * e + 1], box,
                            box + 3);
    int in = 1;
    for (int k = 0; k < 3; k++) {
      in &= (double)box[3 + k] >= other_low[k] - 2.0 * cap && (double)box[k] <= other_high[k] + 2.0 * cap;
      my_low[k] = (double)box[k] < my_low[k] ? (double)box[k] : my_low[k];
      my_high[k] = (double)box[3 + k] > my_high[k] ? (double)box[3 + k] : my_high[k];
    }
    edges[num_edges] = e;
    num_edges += in;
  }
  /* Only the other's triangles near those edges' box. */
  int kept = 0;
  for (int n = 0; n < num_near; n++) {
    const R *box = boxes + 6 * n;
    int in = 1;
    for (int k = 0; k < 3; k++) in &= (double)box[3 + k] >= my_low[k] - 2.0 * cap && (double)box[k] <= my_high[k] + 2.0 * cap;
    for (int k = 0; k < 6; k++) boxes[6 * kept + k] = box[k];
    near[kept] = near[n];
    kept += in;
  }
  num_near = kept;
  for (int m = 0; m < num_edges; m++) {
    const int e = edges[m];
    const R *p0 = my_vertices + 3 * mine->edges[2 * e], *p1 = my_vertices + 3 * mine->edges[2 * e + 1];
    const R *low = edge_boxes + 6 * m, *high = low + 3;
    for (int n = 0; n < num_near; n++) {
      const double margin = POLY_FN(cache_boxed_margin)(p0, p1, low, high, boxes + 6 * n, other_vertices,
                                                        other->triangles + 3 * near[n], tolerance, mine_is_b, inv_rb,
                                                        fixed, least);
      if (margin < least) {
        least = POLY_FN(cache_watch)(cache, e, near[n], mine_is_b, margin, least);
        if (!(least > 0.0)) return 0.0;
      }
    }
  }
  return least;
}

/* How far B's points have moved in A's body frame since the pose (R0, T0) (the cache's search, or its watched pairs'
 * last recheck), at most: |R - R0|_F r_B + |T - T0|, and the rounding of the local coordinates (both poses'). */
POLY_INLINE double POLY_FN(cache_motion_from)(const double *rotation0, const double *translation0,
                                              const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                              const double *rotation, const double *translation)
{
  double turned = 0.0, moved = 0.0, far = 0.0;
  for (int k = 0; k < 9; k++) turned += (rotation[k] - rotation0[k]) * (rotation[k] - rotation0[k]);
  for (int k = 0; k < 3; k++) {
    moved += (translation[k] - translation0[k]) * (translation[k] - translation0[k]);
    far += translation[k] * translation[k];
  }
  const double size = (double)a->bounding_radius + (double)b->bounding_radius;
  return sqrt(turned) * (double)b->bounding_radius + sqrt(moved) +
         16.0 * (double)POLY_FN(epsilon)() * (2.0 * size + sqrt(far));
}

POLY_INLINE double POLY_FN(cache_motion)(const poly_crossing_cache *cache, const POLY_FN(shape_view) *a,
                                         const POLY_FN(shape_view) *b, const double *rotation,
                                         const double *translation)
{
  return POLY_FN(cache_motion_from)(cache->rotation, cache->translation, a, b, rotation, translation);
}

/* B's motion since the pair's cached search (cache_motion) when the cache was made for these shapes and its
 * certificate holds at this pose (the watched pairs aside); else -1. */
POLY_INLINE double POLY_FN(cache_held_motion)(const poly_crossing_cache *cache, const POLY_FN(shape_view) *a,
                                              const POLY_FN(shape_view) *b, const double *rotation,
                                              const double *translation)
{
  if (!(cache->margin > 0.0) || cache->shape_a != (const void *)a->vertices ||
      cache->shape_b != (const void *)b->vertices)
    return -1.0;
  const double motion = POLY_FN(cache_motion)(cache, a, b, rotation, translation);
  return motion < cache->margin ? motion : -1.0;
}

/* The crossing records of one body's cached crossings [from, to) at the current pose, with a run per cached edge
 * [edge_from, edge_to) (ascending, as the search's runs): each crossing's parameter and side from the search's
 * predicates on the same numbers, inserted along its edge as the search inserts them. 0 when a crossing does not
 * hold (the certificate should have said so), -1 when the records are full; else 1. */
POLY_INLINE int POLY_FN(cache_records)(const POLY_FN(shape_view) *mine, const R *my_vertices, int mine_is_b,
                                       const POLY_FN(shape_view) *other, const R *other_vertices,
                                       const poly_crossing_cache *cache, int from, int to, int edge_from,
                                       int edge_to, POLY_FN(overlap_workspace) *ws, int *num_records, int *runs,
                                       int *num_runs)
{
  int next = from;
  for (int n = edge_from; n < edge_to; n++) {
    const int e = cache->inside_edge[n];
    const R *p0 = my_vertices + 3 * mine->edges[2 * e], *p1 = my_vertices + 3 * mine->edges[2 * e + 1];
    int first = *num_records, count = 0;
    for (; next < to && cache->edge[next] == e; next++) {
      const int t = cache->triangle[next], *tri = other->triangles + 3 * t;
      R plane[4];
      POLY_FN(triangle_plane)(other_vertices, tri, plane);
      R side0 = POLY_FN(plane_side)(p0, other_vertices, tri, plane);
      R side1 = POLY_FN(plane_side)(p1, other_vertices, tri, plane);
      int sign0 = POLY_FN(side_sign)(side0, mine_is_b, other_vertices, tri, plane);
      int sign1 = POLY_FN(side_sign)(side1, mine_is_b, other_vertices, tri, plane);
      if (sign0 == sign1) return 0;
      if (!POLY_FN(insert_record)(ws, first, &count, e, t, POLY_FN(crossing_parameter)(side0, side1), sign0))
        return -1;
    }
    *num_records = first + count;
    int *run = runs + 3 * (*num_runs)++;
    run[0] = e;
    run[1] = first;
    run[2] = count;
  }
  return next == to ? 1 : 0;
}

/* B's facet t for the sums: no apex yet, its normal in A's frame (as overlap_pass turns the kept ones). */
POLY_INLINE void POLY_FN(cache_facet_of_b)(const POLY_FN(shape_view) *b, const double *rotation, int t,
                                           POLY_FN(overlap_workspace) *ws)
{
  ws->apex_b[3 * t] = POLY_NO_APEX;
  POLY_FN(turn_normal)(rotation, b->face_normals + 3 * t, ws->normals_b + 3 * t);
}

/* Adds triangle t to the ascending list of `count` triangles once; returns the new count. */
POLY_INLINE int POLY_FN(cache_add_end)(int *list, int count, int t)
{
  int slot = count;
  while (slot > 0 && list[slot - 1] > t) slot--;
  if (slot > 0 && list[slot - 1] == t) return count;
  for (int m = count; m > slot; m--) list[m] = list[m - 1];
  list[slot] = t;
  return count + 1;
}

/* The end of a recheck's margins (or of a recheck that made none): the backoff of the next. */
POLY_INLINE void POLY_FN(cache_recheck_ended)(poly_crossing_cache *cache, int paid)
{
  cache->recheck_backoff = paid ? 0 : 2 * cache->recheck_backoff + 1;
  if (cache->recheck_backoff > 63) cache->recheck_backoff = 63;
  cache->recheck_wait = cache->recheck_backoff;
  cache->recheck_count = 0;
}

/* The margins from this pose (B's relative pose `rotation`, `translation`) of the first `count` watched pairs, just
 * decided as at the search: cache_certificate_way's for each (its box gap, then cache_pair_margin), and the least of
 * them kept with the pose (0 when one of them has none). */
POLY_INLINE void POLY_FN(cache_recheck)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                        const R *vb, const double *rotation, const double *translation, R tolerance,
                                        int count, poly_crossing_cache *cache)
{
  const double reach = POLY_CACHE_REACH * POLY_CACHE_CAP * ((double)a->bounding_radius + (double)b->bounding_radius);
  const double fixed = POLY_FN(cache_fixed)(a, b, translation, reach), inv_rb = 1.0 / (double)b->bounding_radius;
  double least = reach;
  for (int w = 0; w < count && least > 0.0; w++) {
    const int of_b = cache->watch_of_b[w], e = cache->watch_edge[w], t = cache->watch_triangle[w];
    const POLY_FN(shape_view) *mine = of_b ? b : a, *other = of_b ? a : b;
    const R *my_vertices = of_b ? vb : va, *other_vertices = of_b ? va : vb;
    const R *p0 = my_vertices + 3 * mine->edges[2 * e], *p1 = my_vertices + 3 * mine->edges[2 * e + 1];
    R low[3], high[3], box[6];
    POLY_FN(segment_bounds)(p0, p1, low, high);
    POLY_FN(triangle_bounds)(other_vertices, other->triangles + 3 * t, box, box + 3);
    const double margin = POLY_FN(cache_boxed_margin)(p0, p1, low, high, box, other_vertices,
                                                      other->triangles + 3 * t, (double)tolerance, of_b, inv_rb,
                                                      fixed, least);
    least = margin < least ? margin : least;
  }
  for (int k = 0; k < 9; k++) cache->recheck_rotation[k] = rotation[k];
  for (int k = 0; k < 3; k++) cache->recheck_translation[k] = translation[k];
  cache->recheck_margin = POLY_CACHE_RECHECK_SCALE * (least > 0.0 ? least : 0.0);
  cache->recheck_count = least > 0.0 ? count : 0;
}

/* The pass of a pair whose cache's certificate holds (`motion`, cache_held_motion's, under the margin): the
 * records path's sums (runs' inside parts, chords) over the cached crossings, inside vertices and edges, with the
 * nodes in the search's order. `va`, `vb`: the pass's local vertices. Returns 1 with *out filled, 0 when the pair
 * must be searched (a watched pair decides otherwise, a crossing that does not hold). */
POLY_INLINE int POLY_FN(cache_replay)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                      const R *vb, const double *rotation, const double *translation, double motion,
                                      R tolerance, POLY_FN(overlap_workspace) *ws, POLY_FN(pass) *out)
{
  poly_crossing_cache *cache = ws->crossing_cache;
  /* The watched pairs whose margins B's motion has reached (the first `reached`, by ascending margin): decided again,
   * they must decide as at the search; unless they were so decided at the last recheck and B has since moved by less
   * than their margins from there (a resting contact's watched pairs are reached one after the other, and then
   * would be decided again at every evaluation: a tenth of a settled pile's time). */
  int reached = 0;
  while (POLY_CACHE_WATCH_CHECKS && reached < cache->num_watch && !(motion < cache->watch_margin[reached])) reached++;
  if (reached > 0 && reached <= cache->recheck_count &&
      POLY_FN(cache_motion_from)(cache->recheck_rotation, cache->recheck_translation, a, b, rotation, translation) <
          cache->recheck_margin) {
    cache->recheck_skips += cache->recheck_skips < 4;
  } else if (reached > 0) {
    for (int w = 0; w < reached; w++)
      if (POLY_FN(cache_watched_decision)(a, va, b, vb, cache, w, tolerance) != (int)cache->watch_crosses[w]) return 0;
    /* Their margins from here only once no more pairs are being reached (at rest): while the contact moves on, a
     * new pair each evaluation would end each recheck at once, and the margins cost three times the decisions.
     * Margins that spared fewer than four evaluations, or none made (a pair of margin 0), make the next wait 1, 3,
     * 7 ... 63 rechecks. */
    if (cache->recheck_count > 0) POLY_FN(cache_recheck_ended)(cache, cache->recheck_skips >= 4);
    if (cache->recheck_wait > 0) {
      cache->recheck_wait--;
    } else if (reached == cache->last_reached) {
      POLY_FN(cache_recheck)(a, va, b, vb, rotation, translation, tolerance, reached, cache);
      cache->recheck_skips = 0;
      if (cache->recheck_count == 0) POLY_FN(cache_recheck_ended)(cache, 0);
    }
  }
  cache->last_reached = reached;
  if (cache->num_records == 0 && cache->num_edges == 0 && cache->num_inside == 0) {
    /* A near miss (bodies apart, though no plane of the filter parts them): its search found nothing, and the
     * pass's sums stay empty, as they would. */
    out->num_points = out->num_inconsistent = out->flush = 0;
    out->num_kept_a = cache->num_kept_a;
    out->num_kept_b = cache->num_kept_b;
    ws->cache_hits++;
    cache->hits++;
    return 1;
  }
  int num_records = 0, num_runs_a = 0, num_runs_b = 0;
  int status = POLY_FN(cache_records)(a, va, 0, b, vb, cache, 0, cache->records_b, 0, cache->edges_b, ws,
                                      &num_records, ws->runs, &num_runs_a);
  const int records_b = num_records;
  int *runs_b = ws->runs + 3 * num_runs_a;
  if (status == 1)
    status = POLY_FN(cache_records)(b, vb, 1, a, va, cache, cache->records_b, cache->num_records, cache->edges_b,
                                    cache->num_edges, ws, &num_records, runs_b, &num_runs_b);
  if (status != 1) return 0;
  /* Inside states and their nodes, as settle_inside leaves them. */
  int num_points = 0;
  for (int i = 0; i < a->num_vertices; i++) ws->inside_a[i] = 0;
  for (int j = 0; j < b->num_vertices; j++) ws->inside_b[j] = 0;
  for (int n = 0; n < cache->num_inside; n++) {
    const int of_b = n >= cache->inside_b, v = cache->inside_vertex[n];
    (of_b ? ws->inside_b : ws->inside_a)[v] = 1;
    POLY_FN(add_point)(ws, &num_points, (of_b ? vb : va) + 3 * v);
  }
  /* Facets without apexes and B's normals in A's frame, for the facets the sums touch (the cached edges'
   * triangles and the crossed triangles), and, until the chords are kept, the triangles of A that end chords,
   * ascending. */
  for (int n = 0; n < cache->num_edges; n++) {
    const int of_b = n >= cache->edges_b, e = cache->inside_edge[n];
    for (int j = 0; j < 2; j++) {
      if (of_b) POLY_FN(cache_facet_of_b)(b, rotation, b->edge_triangles[2 * e + j], ws);
      else ws->apex_a[3 * a->edge_triangles[2 * e + j]] = POLY_NO_APEX;
    }
  }
  const int chords_kept = cache->num_chords >= 0;
  int num_ends = 0;
  for (int r = 0; r < num_records; r++) {
    const int e = ws->record_edge[r], t = ws->record_triangle[r];
    if (r < records_b) {
      POLY_FN(cache_facet_of_b)(b, rotation, t, ws);
      if (chords_kept) continue;
      num_ends = POLY_FN(cache_add_end)(ws->kept_list_a, num_ends, a->edge_triangles[2 * e]);
      num_ends = POLY_FN(cache_add_end)(ws->kept_list_a, num_ends, a->edge_triangles[2 * e + 1]);
    } else {
      ws->apex_a[3 * t] = POLY_NO_APEX;
      if (!chords_kept) num_ends = POLY_FN(cache_add_end)(ws->kept_list_a, num_ends, t);
    }
  }
  POLY_FN(accumulator) acc = out->acc;
  POLY_FN(run_inside_parts)(a, va, ws->inside_a, ws->runs, num_runs_a, a->face_normals, ws->apex_a, 0, NULL, ws, &acc,
                            &num_points);
  POLY_FN(run_inside_parts)(b, vb, ws->inside_b, runs_b, num_runs_b, ws->normals_b, ws->apex_b, 1, NULL, ws, &acc,
                            &num_points);
  if (chords_kept) {
    for (int c = 0; c < cache->num_chords; c++)
      POLY_FN(add_chord)(a, va, b, vb, records_b, cache->chord_a[c], cache->chord_b[c], cache->chord_from[c],
                         cache->chord_to[c], ws, &acc);
  } else {
    POLY_FN(group_chord_ends)(a, b, records_b, num_records, ws->kept_list_a, num_ends, 0, ws);
    POLY_FN(add_chords)(a, va, b, vb, records_b, ws->kept_list_a, num_ends, ws, &acc, cache);
  }
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = 0;
  out->flush = 0;
  out->num_kept_a = cache->num_kept_a;
  out->num_kept_b = cache->num_kept_b;
  ws->cache_hits++;
  cache->hits++;
  return 1;
}

/* Keeps records [from, to) (one body's, grouped by edge ascending, along each edge by parameter) in the cache from
 * `at`, ascending by edge and then triangle (the order in which the search meets them, its candidates ascending). */
POLY_INLINE void POLY_FN(cache_keep_records)(poly_crossing_cache *cache, int at, const POLY_FN(overlap_workspace) *ws,
                                             int from, int to)
{
  for (int r = from; r < to; r++) {
    int e = ws->record_edge[r], t = ws->record_triangle[r], slot = at + (r - from);
    while (slot > at && (cache->edge[slot - 1] > e || (cache->edge[slot - 1] == e && cache->triangle[slot - 1] > t))) {
      cache->edge[slot] = cache->edge[slot - 1];
      cache->triangle[slot] = cache->triangle[slot - 1];
      slot--;
    }
    cache->edge[slot] = e;
    cache->triangle[slot] = t;
  }
}

/* After a search with a cache given: the pose, and, for a pair that moved little since its last search (so that
 * a certificate may last), what cache_replay needs and the certificate (none for flush faces, inconsistent edges,
 * convex shapes, which take their own paths, or more than the cache or the nodes hold). */
POLY_INLINE void POLY_FN(cache_after_search)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                             const R *vb, const double *rotation, const double *translation,
                                             const POLY_FN(filtered) *f, const int *runs_a, int num_runs_a,
                                             const int *runs_b, int num_runs_b, int num_records, int records_b,
                                             int num_points, int flush, int inconsistent,
                                             POLY_FN(overlap_workspace) *ws)
{
  poly_crossing_cache *cache = ws->crossing_cache;
  const double cap = POLY_CACHE_CAP * ((double)a->bounding_radius + (double)b->bounding_radius);
  const int known = cache->shape_a == (const void *)a->vertices && cache->shape_b == (const void *)b->vertices;
  /* A pair that moved by less than POLY_CACHE_GATE of the cap since its last search may keep a certificate for a
   * few steps (one cap, with certificates reaching 8 and the tighter margins; a sixteenth of a certificate of at
   * most one cap before; 2 and 8 caps made movingMeshGran's flow slower). A certificate costs about a search, an
   * evaluation from it a quarter of one: a pair whose certificate served fewer than two evaluations waits 1, 2, 4
   * ... 64 searches before the next. */
  const double moved = known ? POLY_FN(cache_motion)(cache, a, b, rotation, translation) : cap;
  const int slow = moved < POLY_CACHE_GATE * cap;
  if (known && cache->margin > 0.0) cache->backoff = cache->hits > 1 ? 0 : (cache->backoff ? 2 * cache->backoff : 1);
  if (cache->backoff > 64) cache->backoff = 64;
  cache->hits = 0;
  cache->num_chords = -1; /* the first replay pairs the chords' ends anew */
  ws->cache_searches++;
  cache->shape_a = (const void *)a->vertices;
  cache->shape_b = (const void *)b->vertices;
  for (int k = 0; k < 9; k++) cache->rotation[k] = rotation[k];
  for (int k = 0; k < 3; k++) cache->translation[k] = translation[k];
  cache->margin = 0.0;
  if (!slow || flush || inconsistent || num_records > POLY_CACHE_RECORDS ||
      num_points > ws->capacity_points || (a->face_of && b->face_of))
    return;
  /* The edges with inside parts (crossings, or an inside first vertex) and the inside vertices. */
  int num_edges = 0, edges_b = 0, num_inside = 0, inside_b = 0;
  for (int body = 0; body < 2; body++) {
    const POLY_FN(shape_view) *mine = body ? b : a;
    const int *runs = body ? runs_b : runs_a, count = body ? num_runs_b : num_runs_a;
    const unsigned char *inside = body ? ws->inside_b : ws->inside_a;
    if (body) edges_b = num_edges, inside_b = num_inside;
    for (int r = 0; r < count; r++) {
      const int *run = runs + 3 * r;
      if (run[2] == 0 && !inside[mine->edges[2 * run[0]]]) continue;
      if (num_edges == POLY_CACHE_EDGES) return;
      cache->inside_edge[num_edges++] = run[0];
    }
    for (int v = 0; v < mine->num_vertices; v++) {
      if (!inside[v]) continue;
      if (num_inside == POLY_CACHE_INSIDE) return;
      cache->inside_vertex[num_inside++] = v;
    }
  }
  if (cache->skip > 0) {
    cache->skip--;
    return;
  }
  cache->skip = cache->backoff;
  const double reach = POLY_CACHE_REACH * cap, band = POLY_FN(cache_band)(a, b, translation, reach);
  const double fixed = POLY_FN(cache_fixed)(a, b, translation, reach), inv_rb = 1.0 / (double)b->bounding_radius;
  cache->num_watch = 0;
  cache->recheck_count = cache->last_reached = cache->recheck_skips = cache->recheck_wait = 0;
  cache->recheck_margin = 0.0;
  double margin = POLY_FN(cache_certificate_way)(a, va, ws->along_a, b, vb, ws->along_b, 0, (double)f->limit_a,
                                                 (double)f->limit_b, (double)f->tolerance, reach, band, inv_rb, fixed,
                                                 reach, cache, ws);
  if (margin > 0.0)
    margin = POLY_FN(cache_certificate_way)(b, vb, ws->along_b, a, va, ws->along_a, 1, (double)f->limit_b,
                                            (double)f->limit_a, (double)f->tolerance, reach, band, inv_rb, fixed,
                                            margin, cache, ws);
  ws->cache_certificates++;
  /* Without an outside vertex of each body the watched pairs cannot be left to their decisions: the certificate
   * ends at the least of their margins (every pair then keeps its decision all the way). */
  if (cache->num_watch > 0 && cache->watch_margin[0] < margin &&
      !(POLY_CACHE_OUTSIDE_CHECKS ? POLY_FN(cache_outside_vertices)(a, b, rotation, translation, reach) : 1)) {
    margin = cache->watch_margin[0];
    cache->num_watch = 0;
  }
  /* The watched pairs' decisions at the search (those of margin beyond the certificate never come up). */
  int watched = 0;
  for (int w = 0; w < cache->num_watch && margin > 0.0 && cache->watch_margin[w] < margin; w++, watched++) {
    const int decision = POLY_FN(cache_watched_decision)(a, va, b, vb, cache, w, f->tolerance);
    if (decision < 0) margin = 0.0;
    cache->watch_crosses[w] = (unsigned char)(decision > 0);
    cache->watch_margin[w] *= POLY_CACHE_MARGIN_SCALE;
  }
  cache->num_watch = watched;
  if (!(margin > 0.0)) return;
  POLY_FN(cache_keep_records)(cache, 0, ws, 0, records_b);
  POLY_FN(cache_keep_records)(cache, records_b, ws, records_b, num_records);
  cache->num_records = num_records;
  cache->records_b = records_b;
  cache->num_edges = num_edges;
  cache->edges_b = edges_b;
  cache->num_inside = num_inside;
  cache->inside_b = inside_b;
  cache->num_kept_a = f->num_kept_a;
  cache->num_kept_b = f->num_kept_b;
  cache->margin = POLY_CACHE_MARGIN_SCALE * margin;
}
