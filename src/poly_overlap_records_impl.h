/* The crossing records of one pass of the overlap (overlap_pass in
 * poly_overlap_impl.h). Included by poly_overlap_impl.h once per precision
 * (no include guard).
 *
 * Every crossing of an edge of one body with a kept triangle of the other is
 * decided once, by the exact predicates, and kept as a record (edge, triangle,
 * parameter along the edge, entering or leaving). The records then give all
 * three parts of the boundary sums without another predicate:
 * - the inside state of each vertex: propagated along the edges from a vertex
 *   known to be outside (out of the slab or of the other's box), flipping at
 *   each crossing, instead of a ray's parity per vertex (a ray only where no
 *   edge reaches a decided vertex: a body wholly inside the other);
 * - the inside parts of the edges, from the records of each edge in order;
 * - the chord of every crossing triangle pair (t of A, s of B): its two ends
 *   are exactly the records of t's edges with s and of s's edges with t, so
 *   the pairs are found by grouping the records by (t, s) in a small hash
 *   table rather than by examining every pair of kept triangles.
 * The decisions are those of the reference path (the same predicates on the
 * same numbers) and the sums are taken in the same order, so both paths give
 * the same bits (tests/test_records_path.py). Where the records do not fit the
 * workspace, the pass takes the reference path. */

/* A uniform grid over the boxes of the other body's kept triangles, so that an
 * edge meets only the triangles of the cells its box touches rather than all
 * of them: for large shapes these pairs were most of the cost (rock_1000:
 * 62 %). At most POLY_GRID_SIDE cells a side, about one triangle a cell; each
 * triangle is listed in every cell its box touches. The cell of a coordinate
 * is monotonic in it, so an edge whose box overlaps a triangle's always shares
 * a cell with it. */
#define POLY_GRID_SIDE 16
#define POLY_GRID_MIN_KEPT 64 /* fewer kept triangles: the plain loop is cheaper (rock_70) */
typedef struct POLY_FN(grid) {
  R low[3], scale[3];
  int side;
} POLY_FN(grid);

POLY_INLINE int POLY_FN(grid_cell)(const POLY_FN(grid) *g, int k, R x)
{
  R position = (x - g->low[k]) * g->scale[k];
  if (!(position > 0)) return 0;
  return position >= (R)(g->side - 1) ? g->side - 1 : (int)position;
}

POLY_INLINE void POLY_FN(grid_range)(const POLY_FN(grid) *g, const R *low, const R *high, int from[3], int to[3])
{
  for (int k = 0; k < 3; k++) {
    from[k] = POLY_FN(grid_cell)(g, k, low[k]);
    to[k] = POLY_FN(grid_cell)(g, k, high[k]);
  }
}

/* Builds the grid of `kept_list`'s triangles (cell c lists ws->grid_entries
 * [grid_start[c], grid_start[c + 1])) and clears their bits; 0, or -1 when
 * it does not fit the workspace. */
POLY_INLINE int POLY_FN(grid_build)(POLY_FN(overlap_workspace) *ws, const R *bounds, const int *kept_list, int num_kept,
                                    POLY_FN(grid) *g)
{
  R high[3];
  for (int k = 0; k < 3; k++) {
    g->low[k] = (R)1e30;
    high[k] = (R)-1e30;
  }
  for (int n = 0; n < num_kept; n++) {
    const R *box = bounds + 6 * kept_list[n];
    ws->grid_bits[kept_list[n] >> 5] = 0;
    for (int k = 0; k < 3; k++) {
      if (box[k] < g->low[k]) g->low[k] = box[k];
      if (box[3 + k] > high[k]) high[k] = box[3 + k];
    }
  }
  int side = 1;
  while (side * side * side < num_kept && side < POLY_GRID_SIDE) side++;
  g->side = side;
  for (int k = 0; k < 3; k++) g->scale[k] = high[k] > g->low[k] ? (R)side / (high[k] - g->low[k]) : (R)0;
  int cells = side * side * side, *start = ws->grid_start, *entries = ws->grid_entries;
  for (int c = 0; c <= cells; c++) start[c] = 0;
  for (int pass = 0; pass < 2; pass++) {
    for (int n = 0; n < num_kept; n++) {
      int t = kept_list[n], from[3], to[3];
      POLY_FN(grid_range)(g, bounds + 6 * t, bounds + 6 * t + 3, from, to);
      for (int i = from[0]; i <= to[0]; i++)
        for (int j = from[1]; j <= to[1]; j++)
          for (int l = from[2]; l <= to[2]; l++) {
            int c = (i * side + j) * side + l;
            if (pass == 0) start[c + 1]++;
            else entries[start[c]++] = t;
          }
    }
    if (pass == 0) {
      for (int c = 0; c < cells; c++) start[c + 1] += start[c];
      if (start[cells] > ws->capacity_grid) return -1;
    }
  }
  /* The fill moved each cell's start to its end: shift back. */
  for (int c = cells; c > 0; c--) start[c] = start[c - 1];
  start[0] = 0;
  return 0;
}

/* The kept triangles whose cells the box [low, high] touches, once each and in
 * ascending order (the plain loop's), into ws->grid_candidates; returns how many.
 * A bit per triangle (ws->grid_bits, cleared by grid_build and after each
 * call) rather than sorting them: an edge's cells list a triangle several times,
 * in no common order. */
POLY_INLINE int POLY_FN(grid_candidates)(const POLY_FN(grid) *g, POLY_FN(overlap_workspace) *ws, const R *low,
                                         const R *high)
{
  int from[3], to[3], count = 0, side = g->side, *found = ws->grid_candidates, first = 1 << 30, last = -1;
  unsigned *bits = ws->grid_bits;
  POLY_FN(grid_range)(g, low, high, from, to);
  for (int i = from[0]; i <= to[0]; i++)
    for (int j = from[1]; j <= to[1]; j++)
      for (int l = from[2]; l <= to[2]; l++) {
        int c = (i * side + j) * side + l;
        for (int m = ws->grid_start[c]; m < ws->grid_start[c + 1]; m++) {
          int t = ws->grid_entries[m], w = t >> 5;
          bits[w] |= 1u << (t & 31);
          first = w < first ? w : first;
          last = w > last ? w : last;
        }
      }
  for (int w = first; w <= last; w++) {
    for (unsigned b = bits[w]; b; b &= b - 1) found[count++] = 32 * w + poly_clip_lowest_bit(b);
    bits[w] = 0;
  }
  return count;
}

/* The triangles of `kept_list` whose box meets [low, high], in its order and without a branch per triangle (most
 * miss, unpredictably), into `near_list`; returns how many. In double on a core, each box's six comparisons as
 * three SSE2 pairs (boxes_overlap's comparisons, so the same answers): a fifth to a quarter of the crossing search
 * of rock_40 and rock_70 pairs was this loop. */
POLY_INLINE int POLY_FN(near_triangles)(const R *bounds, const int *kept_list, int num_kept, const R *low,
                                        const R *high, int *near_list)
{
  int count = 0;
#if defined(__SSE2__) && !defined(__CUDACC__)
  if (sizeof(R) == sizeof(double)) {
    const double *lo = (const double *)low, *hi = (const double *)high, *b = (const double *)bounds;
    /* A box misses where box.low > high or low > box.high on some axis: (box.lx, box.ly) > (hx, hy),
     * (box.lz, lx) > (hz, box.hx) and (ly, lz) > (box.hy, box.hz). */
    const __m128d high_xy = _mm_loadu_pd(hi), high_z = _mm_set_sd(hi[2]), low_x = _mm_set1_pd(lo[0]);
    const __m128d low_yz = _mm_loadu_pd(lo + 1);
    for (int n = 0; n < num_kept; n++) {
      const int t = kept_list[n];
      const double *box = b + 6 * t;
      const __m128d low_z_high_x = _mm_loadu_pd(box + 2);
      const __m128d miss = _mm_or_pd(
          _mm_or_pd(_mm_cmpgt_pd(_mm_loadu_pd(box), high_xy),
                    _mm_cmpgt_pd(_mm_move_sd(low_x, low_z_high_x), _mm_move_sd(low_z_high_x, high_z))),
          _mm_cmpgt_pd(low_yz, _mm_loadu_pd(box + 4)));
      near_list[count] = t;
      count += _mm_movemask_pd(miss) == 0;
    }
    return count;
  }
#endif
  for (int n = 0; n < num_kept; n++) {
    int t = kept_list[n];
    near_list[count] = t;
    count += POLY_FN(boxes_overlap)(low, high, bounds + 6 * t);
  }
  return count;
}

/* crossing_in_triangle (poly_overlap_predicates_impl.h) with its three edge
 * orientations sharing their parts: the segment's direction and the corners'
 * offsets from p0, each with its |.|_1, are computed once rather than once per
 * triangle edge (a corner serves two edges); each orientation's fast value and
 * bound are edge_side's expressions on the same numbers, and what the bound
 * cannot decide goes to edge_side itself: the same signs, so the same records.
 * In the non-convex shapes' contacts this test was a fifth of the work. */
POLY_INLINE int POLY_FN(records_crossing_in_triangle)(const R *p0, const R *p1, int segment_in_b, const R *vertices,
                                                      const int *tri, R side0, R side1, int sign0, R *lambda)
{
  R direction[3], corner[3][3], size[3];
  POLY_FN(sub)(p1, p0, direction);
  R scale = (R)32 * POLY_FN(epsilon)() * POLY_FN(norm1)(direction);
  for (int k = 0; k < 3; k++) {
    POLY_FN(sub)(vertices + 3 * tri[k], p0, corner[k]);
    size[k] = POLY_FN(norm1)(corner[k]);
  }
  int common = 0;
  for (int k = 0; k < 3; k++) {
    int next = k == 2 ? 0 : k + 1, from = tri[k], to = tri[next];
    int low = from < to ? k : next, high = from < to ? next : k;
    R orientation = POLY_FN(det)(direction, corner[low], corner[high]);
    R bound = scale * size[low] * size[high];
    if (!(orientation > bound || -orientation > bound)) {
      const R *q0 = vertices + 3 * tri[low], *q1 = vertices + 3 * tri[high];
      orientation = POLY_FN(edge_side)(p0, p1, q0, q1);
      if (orientation == 0) orientation = POLY_FN(edge_tie_break)(p0, p1, q0, q1, segment_in_b);
    }
    int sign = (orientation > 0 ? 1 : -1) * (from < to ? 1 : -1);
    if (k == 0) common = sign;
    else if (sign != common) return 0;
  }
  *lambda = POLY_FN(crossing_parameter)(side0, side1);
  return sign0;
}

/* Appends the record (edge e crossing triangle t at lambda, entering when side > 0) to the edge's records from
 * `first` (count so far *count), in order along the edge; 0 when the records are full. */
POLY_INLINE int POLY_FN(insert_record)(POLY_FN(overlap_workspace) *ws, int first, int *count, int e, int t, R lambda,
                                       int side)
{
  if (first + *count >= ws->capacity_records) return 0;
  /* Insertion sort: an edge crosses a handful of triangles. */
  int slot = first + (*count)++;
  while (slot > first && ws->record_lambda[slot - 1] > lambda) {
    ws->record_lambda[slot] = ws->record_lambda[slot - 1];
    ws->record_entering[slot] = ws->record_entering[slot - 1];
    ws->record_triangle[slot] = ws->record_triangle[slot - 1];
    ws->record_edge[slot] = ws->record_edge[slot - 1];
    slot--;
  }
  ws->record_lambda[slot] = lambda;
  ws->record_entering[slot] = side > 0 ? (R)1 : (R)-1;
  ws->record_triangle[slot] = t;
  ws->record_edge[slot] = e;
  return 1;
}

/* Records of the edges of `mine` in the slab crossing kept triangles of
 * `other`, sorted along each edge: one run (edge, first record, count) per edge
 * tested (not those with both ends short of `slab_limit`, their vertices'
 * places along the axis being `my_along`), appended to `runs`. Flush faces (a
 * face of A and one of B in one plane to within `tolerance`) are looked for
 * where an edge lies within it of a triangle's plane, over the edge's two
 * triangles. Returns 0, or -1 when the records do not fit the workspace. */
POLY_INLINE int POLY_FN(find_crossings)(const POLY_FN(shape_view) *mine, const R *my_vertices, const R *my_along,
                                        const R *my_planes, const R *my_bounds, const R *my_normals, int mine_is_b,
                                        const int *my_kept_list, int my_num_kept,
                                        const POLY_FN(shape_view) *other, const R *other_vertices,
                                        const R *other_planes, const R *other_bounds, const R *other_normals,
                                        const int *other_kept_list, int other_num_kept, R slab_limit,
                                        const R *near_box, R tolerance,
                                        POLY_FN(overlap_workspace) *ws, int *num_records, int *runs, int *num_runs,
                                        int *flush)
{
  POLY_FN(grid) grid = {{0, 0, 0}, {0, 0, 0}, 0};
  int gridded = other_num_kept >= POLY_GRID_MIN_KEPT &&
                POLY_FN(grid_build)(ws, other_bounds, other_kept_list, other_num_kept, &grid) == 0;
  /* An edge in the slab has an end in it, so both its triangles are kept: the edges of the kept triangles, in
   * ascending order as the reference path takes them (rocks: a fifth of the edges), rather than all. */
  const int words = (mine->num_edges + 31) / 32;
  unsigned *mask = ws->edge_mask;
  for (int w = 0; w < words; w++) mask[w] = mine->triangle_edges ? 0u : ~0u;
  if (mine->num_edges % 32) mask[words - 1] &= ~0u >> (32 - mine->num_edges % 32);
  if (mine->triangle_edges)
    for (int n = 0; n < my_num_kept; n++)
      for (int k = 0; k < 3; k++) {
        int e = mine->triangle_edges[3 * my_kept_list[n] + k];
        mask[e >> 5] |= 1u << (e & 31);
      }
  for (int w = 0; w < words; w++)
    for (unsigned bits = mask[w]; bits; bits &= bits - 1) {
      int e = 32 * w + poly_clip_lowest_bit(bits);
      int v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
      const R *p0 = my_vertices + 3 * v0, *p1 = my_vertices + 3 * v1;
      R d0 = my_along[v0], d1 = my_along[v1];
      /* The other body lies beyond slab_limit along +axis (my_along) for A, below it for B. */
      if (!mine_is_b ? (d0 < slab_limit && d1 < slab_limit) : (d0 > slab_limit && d1 > slab_limit)) continue;
      R low[3], high[3];
      POLY_FN(segment_bounds)(p0, p1, low, high);
      /* An edge whose box misses the boxes' common part meets no candidate's box, and both its ends lie outside
       * the other's box: no record, no inside part, nothing for settle_inside to carry. */
      if (!POLY_FN(boxes_overlap)(low, high, near_box)) continue;
      int first = *num_records, count = 0;
      const int *candidates = other_kept_list;
      int num_candidates = other_num_kept;
      if (gridded) {
        num_candidates = POLY_FN(grid_candidates)(&grid, ws, low, high);
        candidates = ws->grid_candidates;
      }
      /* The candidates whose box meets the edge's (four in five miss); then the tests on those. */
      int *passing = ws->box_passing;
      const int num_passing = POLY_FN(near_triangles)(other_bounds, candidates, num_candidates, low, high, passing);
      for (int n = 0; n < num_passing; n++) {
        int t = passing[n];
        const int *tri = other->triangles + 3 * t;
        const R *plane = other_planes + 4 * t;
        R side0 = POLY_FN(plane_side)(p0, other_vertices, tri, plane);
        R side1 = POLY_FN(plane_side)(p1, other_vertices, tri, plane);
        if (tolerance > 0 && !*flush) {
          /* |side| / |plane|_2 is the distance to the plane; |plane|_1 >= |plane|_2, so this only lets more
           * edges on to triangles_flush, which decides as the reference path does. */
          R reach = tolerance * POLY_FN(norm1)(plane);
          if (fabs(side0) <= reach && fabs(side1) <= reach)
            for (int j = 0; j < 2 && !*flush; j++) {
              int m = mine->edge_triangles[2 * e + j];
              const R *box_m = my_bounds + 6 * m, *box_t = other_bounds + 6 * t;
              if (!POLY_FN(boxes_overlap)(box_m, box_m + 3, box_t)) continue;
              *flush = !mine_is_b ? POLY_FN(triangles_flush)(my_vertices, mine->triangles + 3 * m, my_planes + 4 * m,
                                                             my_normals + 3 * m, other_vertices, tri, plane,
                                                             other_normals + 3 * t, tolerance)
                                  : POLY_FN(triangles_flush)(other_vertices, tri, plane, other_normals + 3 * t,
                                                             my_vertices, mine->triangles + 3 * m, my_planes + 4 * m,
                                                             my_normals + 3 * m, tolerance);
            }
        }
        int sign0 = POLY_FN(side_sign)(side0, mine_is_b, other_vertices, tri, plane);
        int sign1 = POLY_FN(side_sign)(side1, mine_is_b, other_vertices, tri, plane);
        if (sign0 == sign1) continue;
        R lambda;
        int side = POLY_FN(records_crossing_in_triangle)(p0, p1, mine_is_b, other_vertices, tri, side0, side1, sign0,
                                                         &lambda);
        if (!side) continue;
        if (!POLY_FN(insert_record)(ws, first, &count, e, t, lambda, side)) return -1;
      }
      *num_records = first + count;
      int *run = runs + 3 * (*num_runs)++;
      run[0] = e;
      run[1] = first;
      run[2] = count;
    }
  return 0;
}

/* Inside states of the vertices of `mine` (see the top of this file): 0 where
 * a vertex cannot be inside the other body (`candidate` 0), else settled along
 * the runs' edges, or by point_inside's ray where no run reaches a settled
 * vertex. Then counts the runs whose parity disagrees with their ends' states
 * (rounding; 0 normally) and adds the inside vertices as nodes. */
POLY_INLINE void POLY_FN(settle_inside)(const POLY_FN(shape_view) *mine, const R *my_vertices, const R *my_along,
                                        int mine_is_b, R slab_limit, const R *other_low, const R *other_high,
                                        const int *runs, int num_runs, const R *ray, R ray_length,
                                        const POLY_FN(shape_view) *other, const R *other_vertices,
                                        const R *other_planes, const R *other_bounds, const int *other_kept_list,
                                        int other_num_kept, unsigned char *inside, POLY_FN(overlap_workspace) *ws,
                                        int *num_points, int *num_inconsistent)
{
  const unsigned char unknown = 2;
  int num_unknown = 0;
  for (int i = 0; i < mine->num_vertices; i++) {
    const R *x = my_vertices + 3 * i;
    R along = my_along[i];
    int candidate = !mine_is_b ? along >= slab_limit : along <= slab_limit;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= other_low[k] && x[k] <= other_high[k];
    inside[i] = candidate ? unknown : 0;
    num_unknown += candidate;
  }
  while (num_unknown > 0) {
    int settled = 0;
    for (int r = 0; r < num_runs; r++) {
      const int *run = runs + 3 * r;
      int v0 = mine->edges[2 * run[0]], v1 = mine->edges[2 * run[0] + 1];
      if ((inside[v0] == unknown) == (inside[v1] == unknown)) continue;
      if (inside[v0] == unknown)
        inside[v0] = (unsigned char)(inside[v1] ^ (run[2] & 1));
      else
        inside[v1] = (unsigned char)(inside[v0] ^ (run[2] & 1));
      settled++;
    }
    num_unknown -= settled;
    if (settled || num_unknown == 0) continue;
    for (int i = 0; i < mine->num_vertices; i++)
      if (inside[i] == unknown) {
        inside[i] = (unsigned char)POLY_FN(point_inside)(my_vertices + 3 * i, ray, ray_length, mine_is_b,
                                                         other_vertices, other->triangles, other_planes,
                                                         other_bounds, other_kept_list, other_num_kept);
        num_unknown--;
        break;
      }
  }
  for (int r = 0; r < num_runs; r++) {
    const int *run = runs + 3 * r;
    int v0 = mine->edges[2 * run[0]], v1 = mine->edges[2 * run[0] + 1];
    if (((inside[v0] + run[2]) & 1) != inside[v1]) (*num_inconsistent)++;
  }
  for (int i = 0; i < mine->num_vertices; i++)
    if (inside[i]) POLY_FN(add_point)(ws, num_points, my_vertices + 3 * i);
}

/* The inside parts of the edges of the runs. */
POLY_INLINE void POLY_FN(run_inside_parts)(const POLY_FN(shape_view) *mine, const R *my_vertices,
                                           const unsigned char *inside, const int *runs, int num_runs,
                                           const R *my_unit_normals, R *my_apexes, int mine_is_b,
                                           const int *face_of, POLY_FN(overlap_workspace) *ws,
                                           POLY_FN(accumulator) *acc, int *num_points)
{
  for (int r = 0; r < num_runs; r++) {
    const int *run = runs + 3 * r;
    int e = run[0], v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
    POLY_FN(edge_inside_parts)(mine, e, my_vertices + 3 * v0, my_vertices + 3 * v1, inside[v0],
                               ws->record_lambda + run[1], ws->record_entering + run[1], run[2], my_unit_normals,
                               my_apexes, mine_is_b, face_of, ws, acc, num_points);
  }
}

/* Point of record r on its edge of `body` (as edge_inside_parts computes it). */
POLY_INLINE void POLY_FN(record_point)(const POLY_FN(shape_view) *body, const R *vertices,
                                       const POLY_FN(overlap_workspace) *ws, int r, R *x)
{
  int e = ws->record_edge[r];
  const R *p0 = vertices + 3 * body->edges[2 * e], *p1 = vertices + 3 * body->edges[2 * e + 1];
  R direction[3];
  POLY_FN(sub)(p1, p0, direction);
  for (int k = 0; k < 3; k++) x[k] = p0[k] + ws->record_lambda[r] * direction[k];
}

/* The two chord ends of record r: triangles of A (t) and of B (s) of each, and
 * (r << 1 | starts). A record of edge e (of A) with triangle s ends the chords
 * (t, s) of both triangles t of e; the chord starts there where the edge, run
 * in t's order, leaves B (it enters A's facet inside B). For an edge of B the
 * roles and the direction swap (see chord_ends). */
POLY_INLINE void POLY_FN(record_ends)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                      const POLY_FN(overlap_workspace) *ws, int r, int of_b, int faces, int t[2],
                                      int s[2], int end[2])
{
  const POLY_FN(shape_view) *body = of_b ? b : a;
  int e = ws->record_edge[r], other = ws->record_triangle[r];
  int enters = ws->record_entering[r] > 0;
  for (int j = 0; j < 2; j++) {
    /* j = 0: the triangle in which the edge runs from its lower vertex. */
    int mine = body->edge_triangles[2 * e + j];
    if (faces) mine = body->face_of[mine];
    t[j] = of_b ? other : mine;
    s[j] = of_b ? mine : other;
    end[j] = r << 1 | (((j == 0) ? !enters : enters) != of_b);
  }
}

/* The ends of the records grouped by triangle pair (t, s): by t (a counting
 * sort over the triangles in `list_a`, ascending, which must hold every t
 * that ends a chord), then by s within each t (insertion: a handful), so the
 * chords come in the order of the pair (t, s), as the reference path adds
 * them: the sums, and so their rounding, are the same on both paths (in
 * single precision a sliver between nearly parallel edges is that sensitive).
 * Records [0, records_b) are A's, [records_b, num_records) B's; `faces`: name
 * facets by their faces (the convex path). Returns the number of pairs with
 * other than two ends (the reference path skips those as not crossing in one
 * chord; to the convex path they are a decision to take again exactly). */
POLY_INLINE int POLY_FN(group_chord_ends)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b, int records_b,
                                          int num_records, const int *list_a, int num_a, int faces,
                                          POLY_FN(overlap_workspace) *ws)
{
  int *bucket = ws->chord_buckets, *ends = ws->chord_ends;
  for (int m = 0; m < num_a; m++) bucket[list_a[m]] = 0;
  for (int r = 0; r < num_records; r++) {
    int t[2], s[2], end[2];
    POLY_FN(record_ends)(a, b, ws, r, r >= records_b, faces, t, s, end);
    bucket[t[0]]++;
    bucket[t[1]]++;
  }
  for (int m = 0, offset = 0; m < num_a; m++) {
    int *slot = bucket + list_a[m];
    int size = *slot;
    *slot = offset;
    offset += size;
  }
  for (int r = 0; r < num_records; r++) {
    int t[2], s[2], end[2];
    POLY_FN(record_ends)(a, b, ws, r, r >= records_b, faces, t, s, end);
    for (int j = 0; j < 2; j++) {
      int position = bucket[t[j]]++;
      ends[2 * position] = s[j];
      ends[2 * position + 1] = end[j];
    }
  }
  int odd = 0;
  for (int m = 0, begin = 0; m < num_a; m++) {
    int stop = bucket[list_a[m]];
    for (int i = begin + 1; i < stop; i++) {
      int key = ends[2 * i], value = ends[2 * i + 1], j = i;
      while (j > begin && ends[2 * (j - 1)] > key) {
        ends[2 * j] = ends[2 * (j - 1)];
        ends[2 * j + 1] = ends[2 * (j - 1) + 1];
        j--;
      }
      ends[2 * j] = key;
      ends[2 * j + 1] = value;
    }
    for (int i = begin; i < stop;) {
      int j = i + 1;
      while (j < stop && ends[2 * j] == ends[2 * i]) j++;
      odd += j - i != 2;
      i = j;
    }
    begin = stop;
  }
  return odd;
}

/* One chord: from the crossing of record `from` to that of record `to` (A's
 * records before records_b, B's after), added to A's triangle t and, reversed,
 * to B's triangle s. */
POLY_INLINE void POLY_FN(add_chord)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                    const R *vb, int records_b, int t, int s, int from, int to,
                                    POLY_FN(overlap_workspace) *ws, POLY_FN(accumulator) *acc)
{
  R first[3], second[3];
  if (from >= records_b) POLY_FN(record_point)(b, vb, ws, from, first);
  else POLY_FN(record_point)(a, va, ws, from, first);
  if (to >= records_b) POLY_FN(record_point)(b, vb, ws, to, second);
  else POLY_FN(record_point)(a, va, ws, to, second);
  POLY_FN(add_segment)(acc, ws->apex_a + 3 * t, a->face_normals + 3 * t, first, second, 1);
  POLY_FN(add_segment)(acc, ws->apex_b + 3 * s, ws->normals_b + 3 * s, second, first, 0);
}

/* The chords of the crossing triangle pairs grouped by group_chord_ends (the
 * pairs with exactly two ends), each added by add_chord. `keep`: a crossing
 * cache that keeps them, in this order, for its later replays (its num_chords
 * left -1 when they do not fit), or NULL. */
POLY_INLINE void POLY_FN(add_chords)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                     const R *vb, int records_b, const int *list_a, int num_a,
                                     POLY_FN(overlap_workspace) *ws, POLY_FN(accumulator) *acc,
                                     poly_crossing_cache *keep)
{
  const int *bucket = ws->chord_buckets, *ends = ws->chord_ends;
  int kept = 0, fits = 1;
  for (int m = 0, begin = 0; m < num_a; m++) {
    int t = list_a[m], stop = bucket[t];
    for (int i = begin; i < stop;) {
      int j = i + 1;
      while (j < stop && ends[2 * j] == ends[2 * i]) j++;
      if (j - i == 2) {
        const int s = ends[2 * i], starts = ends[2 * i + 1] & 1;
        const int from = ends[2 * (i + !starts) + 1] >> 1, to = ends[2 * (i + starts) + 1] >> 1;
        POLY_FN(add_chord)(a, va, b, vb, records_b, t, s, from, to, ws, acc);
        if (keep && kept < POLY_CACHE_RECORDS && t <= 0xffff && s <= 0xffff && from <= 0xff && to <= 0xff) {
          keep->chord_a[kept] = (unsigned short)t;
          keep->chord_b[kept] = (unsigned short)s;
          keep->chord_from[kept] = (unsigned char)from;
          keep->chord_to[kept] = (unsigned char)to;
        } else {
          fits = 0;
        }
        kept++;
      }
      i = j;
    }
    begin = stop;
  }
  if (keep) keep->num_chords = fits ? kept : -1;
}

#include "poly_overlap_cache_impl.h"

/* The records path of one pass (see the top of this file). Returns 0 with the
 * sums, nodes, inconsistent edges and flush faces in *out, or -1 when the
 * records do not fit the workspace. */
POLY_INLINE int POLY_FN(records_path)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                      const R *vb, const double *rotation, const double *translation,
                                      const POLY_FN(filtered) *f, POLY_FN(overlap_workspace) *ws, POLY_FN(pass) *out)
{
  if (a->num_edges + b->num_edges > ws->capacity_runs) return -1;
  const int mask_words = POLY_EDGE_MASK_WORDS(ws->capacity_triangles);
  if ((a->num_edges + 31) / 32 > mask_words || (b->num_edges + 31) / 32 > mask_words) return -1;
  int num_records = 0, num_runs_a = 0, num_runs_b = 0, flush = 0;
  /* Every crossing, and every flush pair of faces (found through the same box tests), lies in both bodies' boxes
   * of kept triangles: an edge of one in the slab is in its kept triangles' box. So the crossings need only the
   * triangles whose box meets the common part (rocks resting on each other: about a third of the kept ones). */
  R near_box[6];
  for (int k = 0; k < 3; k++) {
    near_box[k] = f->box_a_low[k] > f->box_b_low[k] ? f->box_a_low[k] : f->box_b_low[k];
    near_box[3 + k] = f->box_a_high[k] < f->box_b_high[k] ? f->box_a_high[k] : f->box_b_high[k];
  }
  int num_near_a = POLY_FN(near_triangles)(ws->bounds_a, ws->kept_list_a, f->num_kept_a, near_box, near_box + 3,
                                           ws->near_list_a);
  int num_near_b = POLY_FN(near_triangles)(ws->bounds_b, ws->kept_list_b, f->num_kept_b, near_box, near_box + 3,
                                           ws->near_list_b);
  int *runs_a = ws->runs;
  if (POLY_FN(find_crossings)(a, va, ws->along_a, ws->planes_a, ws->bounds_a, a->face_normals, 0, ws->kept_list_a,
                              f->num_kept_a, b, vb,
                              ws->planes_b, ws->bounds_b, ws->normals_b, ws->near_list_b, num_near_b, f->limit_a,
                              near_box, f->tolerance, ws, &num_records, runs_a, &num_runs_a, &flush))
    return -1;
  int records_b = num_records, *runs_b = runs_a + 3 * num_runs_a;
  if (POLY_FN(find_crossings)(b, vb, ws->along_b, ws->planes_b, ws->bounds_b, ws->normals_b, 1, ws->kept_list_b,
                              f->num_kept_b, a, va,
                              ws->planes_a, ws->bounds_a, a->face_normals, ws->near_list_a, num_near_a, f->limit_b,
                              near_box, f->tolerance, ws, &num_records, runs_b, &num_runs_b, &flush))
    return -1;
  int num_points = 0, inconsistent = 0;
  POLY_FN(settle_inside)(a, va, ws->along_a, 0, f->limit_a, f->box_b_low, f->box_b_high, runs_a, num_runs_a,
                         f->ray_a, f->ray_length, b, vb, ws->planes_b, ws->bounds_b, ws->kept_list_b, f->num_kept_b,
                         ws->inside_a, ws, &num_points, &inconsistent);
  POLY_FN(settle_inside)(b, vb, ws->along_b, 1, f->limit_b, f->box_a_low, f->box_a_high, runs_b, num_runs_b,
                         f->ray_b, f->ray_length, a, va, ws->planes_a, ws->bounds_a, ws->kept_list_a, f->num_kept_a,
                         ws->inside_b, ws, &num_points, &inconsistent);
  if (ws->cache_pass && ws->crossing_cache)
    POLY_FN(cache_after_search)(a, va, b, vb, rotation, translation, f, runs_a, num_runs_a, runs_b, num_runs_b,
                                num_records, records_b, num_points, flush, inconsistent, ws);
  POLY_FN(accumulator) acc = out->acc;
  POLY_FN(run_inside_parts)(a, va, ws->inside_a, runs_a, num_runs_a, a->face_normals, ws->apex_a, 0, NULL, ws, &acc,
                            &num_points);
  POLY_FN(run_inside_parts)(b, vb, ws->inside_b, runs_b, num_runs_b, ws->normals_b, ws->apex_b, 1, NULL, ws, &acc,
                            &num_points);
  POLY_FN(group_chord_ends)(a, b, records_b, num_records, ws->kept_list_a, f->num_kept_a, 0, ws);
  POLY_FN(add_chords)(a, va, b, vb, records_b, ws->kept_list_a, f->num_kept_a, ws, &acc, NULL);
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = inconsistent;
  out->flush = flush;
  return 0;
}

/* The gap a supporting triangle's plane must leave to part two bodies: 1e-12
 * of their size (as overlap_slab) and, in single precision, more than the
 * rounding of the stored unit normals (about 6e-8), by which a body could
 * stand in front of its own triangle's plane so rounded. */
POLY_INLINE double POLY_FN(support_reach)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b)
{
  return (1e-12 + 64.0 * (double)POLY_FN(epsilon)()) * ((double)a->bounding_radius + (double)b->bounding_radius);
}

/* Does the `of_b`-th body's supporting triangle number m (of its support
 * list) part the bodies: the other body wholly in front of its plane by more
 * than `reach`? `start`: a vertex of the other body to try first. (Which
 * triangles face the other body, support_separated decides.) When it does,
 * *separation is by how much (the other body's lowest vertex above the plane). */
POLY_INLINE int POLY_FN(support_parts)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                       const double *rotation, const double *translation, int of_b, int m,
                                       double reach, int start, double *separation)
{
  const POLY_FN(shape_view) *faced = of_b ? b : a, *other = of_b ? a : b;
  int t = faced->support[m];
  const R *n = faced->face_normals + 3 * t, *corner = faced->vertices + 3 * faced->triangles[3 * t];
  double normal[3], height;
  if (of_b) {
    /* B's triangle turned into A's frame, against A's vertices. */
    double x[3];
    for (int k = 0; k < 3; k++) normal[k] = rotation[3 * k] * n[0] + rotation[3 * k + 1] * n[1] + rotation[3 * k + 2] * n[2];
    for (int k = 0; k < 3; k++)
      x[k] = rotation[3 * k] * corner[0] + rotation[3 * k + 1] * corner[1] + rotation[3 * k + 2] * corner[2] +
             translation[k];
    height = normal[0] * x[0] + normal[1] * x[1] + normal[2] * x[2];
  } else {
    /* Against B's vertices R v + T: n . (R v + T) = (R^T n) . v + n . T. */
    for (int k = 0; k < 3; k++)
      normal[k] = rotation[k] * (double)n[0] + rotation[3 + k] * (double)n[1] + rotation[6 + k] * (double)n[2];
    height = (double)n[0] * corner[0] + (double)n[1] * corner[1] + (double)n[2] * corner[2] -
             ((double)n[0] * translation[0] + (double)n[1] * translation[1] + (double)n[2] * translation[2]);
  }
  double lowest = 1e300;
  for (int v = -1; v < other->num_vertices && lowest - height > reach; v++) {
    const R *x = other->vertices + 3 * (v < 0 ? start : v);
    double along = normal[0] * x[0] + normal[1] * x[1] + normal[2] * x[2];
    if (along < lowest) lowest = along;
  }
  *separation = lowest - height;
  return lowest - height > reach;
}

/* A separating plane among the supporting triangles of the two shapes (each
 * has every vertex of its shape on or behind its plane): is either body wholly
 * in front of one (support_reach)? For pairs the centre line's slab does not
 * part, before anything else: in a pile of rock_40 more such pairs had no
 * overlap than had one, and each cost the whole general path to find a volume
 * of 0. Only triangles facing the other body are tried (normal within 32
 * degrees of the centre line, towards it; any towards it for a body of at
 * most 12 such triangles), each against the other body's
 * vertices until one is behind, starting from its vertex deepest along the
 * centre line (`extreme_a`, `extreme_b`: overlap_slab_extremes'; when the
 * bodies touch, mostly behind the triangle): a filter, which may miss a
 * separation the general path then finds. Sets *separating to the triangle's
 * code (2 m + of_b, m its place in the support list) and *separation to the
 * gap in front of it when it parts them. */
POLY_INLINE int POLY_FN(support_separated)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                           const double *rotation, const double *translation, const double *axis,
                                           int extreme_a, int extreme_b, int *separating, double *separation)
{
  const double facing = 0.85; /* cos 32 degrees */
  double reach = POLY_FN(support_reach)(a, b);
  /* Which triangles face the other body, from their body-frame normals: B's against the axis turned into B's
   * frame, so that only those tried are turned (in a touching pair of rock_40 most are not: they were 6 % of
   * its general path). */
  double turned[3];
  for (int i = 0; i < 3; i++) turned[i] = rotation[i] * axis[0] + rotation[3 + i] * axis[1] + rotation[6 + i] * axis[2];
  for (int of_b = 1; of_b >= 0; of_b--) {
    const POLY_FN(shape_view) *faced = of_b ? b : a;
    const double *towards = of_b ? turned : axis, sign = of_b ? -1.0 : 1.0;
    /* A body of few supporting triangles (a wall's prism) has them all tried that face the other at all: a
     * rock beside a prism is parted by its top face seen at a slant (the hopper's walls: 40 % less time). */
    double facing_here = faced->num_support <= 12 ? 0.0 : facing;
    for (int m = 0; m < faced->num_support; m++) {
      const R *n = faced->face_normals + 3 * faced->support[m];
      if (sign * ((double)n[0] * towards[0] + (double)n[1] * towards[1] + (double)n[2] * towards[2]) < facing_here)
        continue;
      if (POLY_FN(support_parts)(a, b, rotation, translation, of_b, m, reach, of_b ? extreme_a : extreme_b,
                                 separation)) {
        *separating = 2 * m + of_b;
        return 1;
      }
    }
  }
  return 0;
}

/* Does the supporting triangle of code `separating` (a result's, from these
 * shapes in this order) still part the bodies? Any code is safe to try: one
 * out of range, or a triangle that no longer parts them, gives 0. *gap: the
 * proved gap (proved_gap) when it does, else 0. */
POLY_INLINE int POLY_FN(still_separated)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                         const double *rotation, const double *translation, int separating,
                                         double *gap)
{
  int of_b = separating & 1, m = separating >> 1;
  const POLY_FN(shape_view) *faced = of_b ? b : a;
  double separation = 0.0;
  *gap = 0.0;
  if (separating < 0 || !faced->support || m >= faced->num_support) return 0;
  if (!POLY_FN(support_parts)(a, b, rotation, translation, of_b, m, POLY_FN(support_reach)(a, b), 0, &separation))
    return 0;
  *gap = POLY_FN(proved_gap)(a, b, separation);
  return 1;
}
