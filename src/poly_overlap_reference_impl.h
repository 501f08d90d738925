/* The reference path of one pass of the overlap (overlap_pass in
 * poly_overlap_impl.h): every predicate evaluated where it is needed, with no
 * memory beyond the per-triangle arrays. The GPU takes it (its threads' local
 * memory holds no crossing records), and the CPU where the records do not
 * fit; tests/test_records_path.py checks that the records path gives its
 * bits. Also node_extent, which finds the nodes again when they did not fit
 * the workspace. Included by poly_overlap_impl.h once per precision (no
 * include guard). */

/* Inside parts of every edge of `mine` (crossing `other`): each adds a segment to
 * both triangles of the edge, in their own orientations. */
POLY_INLINE void POLY_FN(accumulate_edges)(const POLY_FN(shape_view) *mine, const R *my_vertices,
                                           const R *my_unit_normals, R *my_apexes, const unsigned char *my_inside,
                                           int mine_is_b,
                                           const POLY_FN(shape_view) *other, const R *other_vertices,
                                           const R *other_planes, const R *other_bounds,
                                           const int *other_kept_list, int other_num_kept, const R *axis,
                                           R slab_limit, POLY_FN(overlap_workspace) *ws,
                                           POLY_FN(accumulator) *acc, int *num_points, int *num_inconsistent)
{
  for (int e = 0; e < mine->num_edges; e++) {
    int v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
    const R *p0 = my_vertices + 3 * v0, *p1 = my_vertices + 3 * v1;
    R d0 = POLY_FN(dot)(p0, axis), d1 = POLY_FN(dot)(p1, axis);
    /* The other body lies beyond slab_limit along +axis for A, below it for B. */
    if (!mine_is_b ? (d0 < slab_limit && d1 < slab_limit) : (d0 > slab_limit && d1 > slab_limit)) continue;

    int count = 0;
    R *entering = ws->crossings + ws->capacity_triangles; /* +1 where the edge enters the other body */
    R low[3], high[3];
    POLY_FN(segment_bounds)(p0, p1, low, high);
    for (int n = 0; n < other_num_kept; n++) {
      int t = other_kept_list[n];
      if (!POLY_FN(boxes_overlap)(low, high, other_bounds + 6 * t)) continue;
      R lambda;
      int side = POLY_FN(segment_crosses_triangle)(p0, p1, mine_is_b, other_vertices, other->triangles + 3 * t,
                                                   other_planes + 4 * t, &lambda);
      if (side) {
        /* Insertion sort: an edge crosses a handful of triangles. */
        int slot = count++;
        while (slot > 0 && ws->crossings[slot - 1] > lambda) {
          ws->crossings[slot] = ws->crossings[slot - 1];
          entering[slot] = entering[slot - 1];
          slot--;
        }
        ws->crossings[slot] = lambda;
        entering[slot] = side > 0 ? (R)1 : (R)-1;
      }
    }
    int inside = my_inside[v0];
    if (((inside + count) & 1) != my_inside[v1]) {
      (*num_inconsistent)++;
#ifdef POLY_DEBUG_INCONSISTENT
      fprintf(stderr, "inconsistent edge %d (%d,%d) of %s: in0=%d in1=%d count=%d p0=(%g %g %g) p1=(%g %g %g)\n", e, v0, v1, mine_is_b ? "B" : "A", inside, my_inside[v1], count, p0[0], p0[1], p0[2], p1[0], p1[1], p1[2]);
#endif
    }
    POLY_FN(edge_inside_parts)(mine, e, p0, p1, inside, ws->crossings, entering, count, my_unit_normals, my_apexes,
                               mine_is_b, NULL, ws, acc, num_points);
  }
}

/* Where the edges of triangle `mine` (of B when mine_is_b) cross triangle
 * `other`: each crossing is an end of the two triangles' chord, the chord's
 * start when the edge, in its triangle's order, enters the other body (for a
 * triangle of A) or leaves it (for a triangle of B). Counts every crossing in
 * *found (more than two means the triangles do not cross in one chord) and
 * keeps the first two. Edges are tested from their lower vertex index, so both
 * triangles sharing an edge decide alike. */
POLY_INLINE void POLY_FN(chord_ends)(const R *mine_vertices, const int *mine, int mine_is_b, const R *other_vertices,
                                     const int *other, const R *other_plane, R ends[2][3], int starts[2], int *found)
{
  for (int k = 0; k < 3 && *found <= 2; k++) {
    int from = mine[k], to = mine[k == 2 ? 0 : k + 1];
    int low = from < to ? from : to, high = from < to ? to : from;
    const R *p0 = mine_vertices + 3 * low, *p1 = mine_vertices + 3 * high;
    R lambda;
    int side = POLY_FN(segment_crosses_triangle)(p0, p1, mine_is_b, other_vertices, other, other_plane, &lambda);
    if (!side) continue;
    if (*found < 2) {
      for (int i = 0; i < 3; i++) ends[*found][i] = p0[i] + lambda * (p1[i] - p0[i]);
      starts[*found] = ((side > 0) != (from == low)) != mine_is_b;
    }
    (*found)++;
  }
}

/* Intersection segment of triangle t of A with triangle s of B, if they cross. */
POLY_INLINE void POLY_FN(accumulate_triangle_pair)(const POLY_FN(shape_view) *a, const R *va, const R *planes_a,
                                                   const R *normals_a, int t, const POLY_FN(shape_view) *b,
                                                   const R *vb, const R *planes_b, const R *normals_b, int s,
                                                   POLY_FN(overlap_workspace) *ws, POLY_FN(accumulator) *acc)
{
  const int *ta = a->triangles + 3 * t, *tb = b->triangles + 3 * s;
  /* A triangle wholly on one side of the other's plane cannot cross it: the
   * same signs the crossing tests would compute, so the answer is the same. */
  int sides_a = 0, sides_b = 0;
  for (int k = 0; k < 3; k++) {
    const R *corner = va + 3 * ta[k];
    sides_a += POLY_FN(side_sign)(POLY_FN(plane_side)(corner, vb, tb, planes_b + 4 * s), 0, vb, tb, planes_b + 4 * s);
  }
  if (sides_a == 3 || sides_a == -3) return;
  for (int k = 0; k < 3; k++) {
    const R *corner = vb + 3 * tb[k];
    sides_b += POLY_FN(side_sign)(POLY_FN(plane_side)(corner, va, ta, planes_a + 4 * t), 1, va, ta, planes_a + 4 * t);
  }
  if (sides_b == 3 || sides_b == -3) return;
  /* The chord runs along n_t x n_s. Its direction is read from the crossings,
   * not from that cross product, which is noise for nearly coplanar triangles:
   * it ends where an edge of t (in t's order) enters B and starts where an edge
   * of s (in s's order) enters A. */
  R ends[2][3];
  int starts[2] = {0, 0};
  int found = 0;
  POLY_FN(chord_ends)(va, ta, 0, vb, tb, planes_b + 4 * s, ends, starts, &found);
  POLY_FN(chord_ends)(vb, tb, 1, va, ta, planes_a + 4 * t, ends, starts, &found);
  if (found != 2) return;
  const R *na = normals_a + 3 * t;
  const R *first = ends[0], *second = ends[1];
  if (!starts[0]) { first = ends[1]; second = ends[0]; }
  POLY_FN(add_segment)(acc, ws->apex_a + 3 * t, na, first, second, 1);
  POLY_FN(add_segment)(acc, ws->apex_b + 3 * s, normals_b + 3 * s, second, first, 0);
}

/* Extent along `direction` of the vertices of `mine` inside `other` and of the
 * crossings of its edges with `other`'s kept triangles. */
POLY_INLINE void POLY_FN(node_extent)(const POLY_FN(shape_view) *mine, const R *my_vertices,
                                      const unsigned char *my_inside, int mine_is_b,
                                      const POLY_FN(shape_view) *other, const R *other_vertices,
                                      const R *other_planes, const int *other_kept_list, int other_num_kept,
                                      const double *direction, double *low, double *high)
{
  for (int i = 0; i < mine->num_vertices; i++) {
    if (!my_inside[i]) continue;
    const R *x = my_vertices + 3 * i;
    double along = direction[0] * x[0] + direction[1] * x[1] + direction[2] * x[2];
    if (along < *low) *low = along;
    if (along > *high) *high = along;
  }
  for (int e = 0; e < mine->num_edges; e++) {
    const R *p0 = my_vertices + 3 * mine->edges[2 * e], *p1 = my_vertices + 3 * mine->edges[2 * e + 1];
    for (int n = 0; n < other_num_kept; n++) {
      int t = other_kept_list[n];
      R lambda;
      if (!POLY_FN(segment_crosses_triangle)(p0, p1, mine_is_b, other_vertices,
                                                                other->triangles + 3 * t, other_planes + 4 * t,
                                                                &lambda))
        continue;
      double along = 0.0;
      for (int k = 0; k < 3; k++) along += direction[k] * (double)(p0[k] + lambda * (p1[k] - p0[k]));
      if (along < *low) *low = along;
      if (along > *high) *high = along;
    }
  }
}

/* The reference path of one pass: a ray's parity per candidate vertex (only
 * those in the slab and in the other's box of kept triangles can be inside,
 * and rays pointing away from the other body only meet kept triangles,
 * sec. 5.2), every edge tested against the other's kept triangles, and every
 * pair of kept triangles with overlapping boxes examined for a chord. */
POLY_INLINE void POLY_FN(reference_path)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                         const R *vb, const POLY_FN(filtered) *f, POLY_FN(overlap_workspace) *ws,
                                         POLY_FN(pass) *out)
{
  int num_points = 0;
  for (int i = 0; i < a->num_vertices; i++) {
    const R *x = va + 3 * i;
    int candidate = POLY_FN(dot)(x, f->axis) >= f->limit_a;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= f->box_b_low[k] && x[k] <= f->box_b_high[k];
    ws->inside_a[i] = candidate ? (unsigned char)POLY_FN(point_inside)(x, f->ray_a, f->ray_length, 0, vb,
                                                                         b->triangles, ws->planes_b, ws->bounds_b,
                                                                         ws->kept_list_b, f->num_kept_b)
                                : 0;
    if (ws->inside_a[i]) POLY_FN(add_point)(ws, &num_points, x);
  }
  for (int j = 0; j < b->num_vertices; j++) {
    const R *x = vb + 3 * j;
    int candidate = POLY_FN(dot)(x, f->axis) <= f->limit_b;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= f->box_a_low[k] && x[k] <= f->box_a_high[k];
    ws->inside_b[j] = candidate ? (unsigned char)POLY_FN(point_inside)(x, f->ray_b, f->ray_length, 1, va,
                                                                         a->triangles, ws->planes_a, ws->bounds_a,
                                                                         ws->kept_list_a, f->num_kept_a)
                                : 0;
    if (ws->inside_b[j]) POLY_FN(add_point)(ws, &num_points, x);
  }

  POLY_FN(accumulator) acc = out->acc;
  int inconsistent = 0;
  POLY_FN(accumulate_edges)(a, va, a->face_normals, ws->apex_a, ws->inside_a, 0, b, vb, ws->planes_b, ws->bounds_b,
                            ws->kept_list_b, f->num_kept_b, f->axis, f->limit_a, ws, &acc, &num_points,
                            &inconsistent);
  POLY_FN(accumulate_edges)(b, vb, ws->normals_b, ws->apex_b, ws->inside_b, 1, a, va, ws->planes_a, ws->bounds_a,
                            ws->kept_list_a, f->num_kept_a, f->axis, f->limit_b, ws, &acc, &num_points,
                            &inconsistent);
  int flush = 0;
  for (int m = 0; m < f->num_kept_a; m++) {
    int t = ws->kept_list_a[m];
    const R *box_t = ws->bounds_a + 6 * t;
    for (int n = 0; n < f->num_kept_b; n++) {
      int s = ws->kept_list_b[n];
      const R *box_s = ws->bounds_b + 6 * s;
      if (!POLY_FN(boxes_overlap)(box_t, box_t + 3, box_s)) continue;
      if (f->tolerance > 0 && !flush)
        flush = POLY_FN(triangles_flush)(va, a->triangles + 3 * t, ws->planes_a + 4 * t, a->face_normals + 3 * t, vb,
                                         b->triangles + 3 * s, ws->planes_b + 4 * s, ws->normals_b + 3 * s,
                                         f->tolerance);
      POLY_FN(accumulate_triangle_pair)(a, va, ws->planes_a, a->face_normals, t, b, vb, ws->planes_b,
                                        ws->normals_b, s, ws, &acc);
    }
  }
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = inconsistent;
  out->flush = flush;
}
