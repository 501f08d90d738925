/* The blocks path of one pass of the overlap (overlap_pass in
 * poly_overlap_impl.h): two convex shapes of at most POLY_BLOCK_MAX faces and
 * vertices each (cubes, boxes, tetrahedra, coarse crushed-rock hulls), the
 * pairs of a pile of blocks. Included by poly_overlap_impl.h once per
 * precision (no include guard); CPU only, as the convex path.
 *
 * It decides what the convex path (poly_overlap_convex_impl.h) decides, with
 * the same predicates on the same numbers, but without the half-space filter
 * and its per-triangle boxes and planes, which for shapes this small cost
 * more than they spare: one table of every vertex's sides of every face of
 * the other body, kept as a bit mask per vertex (bit c: in front of face c),
 * gives at once
 *   - the separation (every vertex of one body in front of one face of the
 *     other: an AND of the masks),
 *   - the inside vertices (mask 0),
 *   - the ridges that cannot meet the other body (both ends in front of one
 *     face: an AND of two masks), and for the others the faces to clip by (the
 *     faces whose sides differ at the two ends: an XOR).
 * The records, chords and sums are then those of the convex path. Flush faces
 * (nearly parallel faces first, then their triangles as the general path
 * tests them), odd chord groups and a node count over the workspace hand the
 * pass back, as the convex path does. tests/test_convex_path.py compares it
 * with the general path. */

#if POLY_OVERLAP_RECORDS /* the CPU build: the GPU takes the reference path */
#define POLY_BLOCK_MAX 64
#define POLY_BLOCK_CHORD_TABLE 1024 /* pairs of faces (block_chords) */

/* The faces of a convex body, named by their lowest triangles, ascending,
 * and each one's column (by its lowest triangle); returns how many, or -1
 * above POLY_BLOCK_MAX. */
POLY_INLINE int POLY_FN(block_faces)(const POLY_FN(shape_view) *body, int *faces, int *column)
{
  int count = 0;
  for (int t = 0; t < body->num_triangles; t++) {
    if (body->face_of[t] != t) continue;
    if (count == POLY_BLOCK_MAX) return -1;
    column[t] = count;
    faces[count++] = t;
  }
  return count;
}

/* The side table of `mine`'s vertices against `other`'s faces (a row of
 * `stride` >= num_faces per vertex) and their masks: plane_side and
 * side_sign, term for term, on the faces' corners, planes and error bounds
 * gathered first, POLY_BLOCK_LANES faces at a time (SSE2, which every x86-64
 * has: each lane the scalar arithmetic, so the same bits); a side the bound
 * cannot decide goes to plane_side itself, which decides it exactly. One face
 * at a time, this table was a third of the time of a pile of cubes. */
#if defined(__SSE2__) && !defined(__CUDACC__)
#include <emmintrin.h>
#define POLY_BLOCK_LANES (16 / (int)sizeof(R))
#else
#define POLY_BLOCK_LANES 1
#endif

POLY_INLINE int POLY_FN(block_stride)(int num_faces)
{
  return (num_faces + POLY_BLOCK_LANES - 1) / POLY_BLOCK_LANES * POLY_BLOCK_LANES;
}

/* One group of faces (7 rows of POLY_BLOCK_LANES: corner xyz, plane xyz,
 * bound scale) against the point x: the sides into `row`, and bit l of the
 * returns set where lane l is in front (*decided: where the bound decided). */
POLY_INLINE int POLY_FN(block_side_group)(const R *x, const R *group, R *row, int *decided)
{
#if defined(__SSE2__) && !defined(__CUDACC__)
  if (sizeof(R) == sizeof(double)) {
    const double *face = (const double *)group, *point = (const double *)x;
    const __m128d sign = _mm_set1_pd(-0.0);
    __m128d offset0 = _mm_sub_pd(_mm_set1_pd(point[0]), _mm_loadu_pd(face));
    __m128d offset1 = _mm_sub_pd(_mm_set1_pd(point[1]), _mm_loadu_pd(face + 2));
    __m128d offset2 = _mm_sub_pd(_mm_set1_pd(point[2]), _mm_loadu_pd(face + 4));
    __m128d side = _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_loadu_pd(face + 6), offset0),
                                         _mm_mul_pd(_mm_loadu_pd(face + 8), offset1)),
                              _mm_mul_pd(_mm_loadu_pd(face + 10), offset2));
    __m128d size = _mm_add_pd(_mm_add_pd(_mm_andnot_pd(sign, offset0), _mm_andnot_pd(sign, offset1)),
                              _mm_andnot_pd(sign, offset2));
    __m128d bound = _mm_mul_pd(_mm_loadu_pd(face + 12), size);
    *decided = _mm_movemask_pd(_mm_or_pd(_mm_cmpgt_pd(side, bound), _mm_cmpgt_pd(_mm_xor_pd(side, sign), bound)));
    _mm_storeu_pd((double *)row, side);
    return _mm_movemask_pd(_mm_cmpgt_pd(side, _mm_setzero_pd()));
  } else {
    const float *face = (const float *)group, *point = (const float *)x;
    const __m128 sign = _mm_set1_ps(-0.0f);
    __m128 offset0 = _mm_sub_ps(_mm_set1_ps(point[0]), _mm_loadu_ps(face));
    __m128 offset1 = _mm_sub_ps(_mm_set1_ps(point[1]), _mm_loadu_ps(face + 4));
    __m128 offset2 = _mm_sub_ps(_mm_set1_ps(point[2]), _mm_loadu_ps(face + 8));
    __m128 side = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(face + 12), offset0),
                                        _mm_mul_ps(_mm_loadu_ps(face + 16), offset1)),
                             _mm_mul_ps(_mm_loadu_ps(face + 20), offset2));
    __m128 size = _mm_add_ps(_mm_add_ps(_mm_andnot_ps(sign, offset0), _mm_andnot_ps(sign, offset1)),
                             _mm_andnot_ps(sign, offset2));
    __m128 bound = _mm_mul_ps(_mm_loadu_ps(face + 24), size);
    *decided = _mm_movemask_ps(_mm_or_ps(_mm_cmpgt_ps(side, bound), _mm_cmpgt_ps(_mm_xor_ps(side, sign), bound)));
    _mm_storeu_ps((float *)row, side);
    return _mm_movemask_ps(_mm_cmpgt_ps(side, _mm_setzero_ps()));
  }
#else
  R offset[3] = {x[0] - group[0], x[1] - group[1], x[2] - group[2]};
  R side = group[3] * offset[0] + group[4] * offset[1] + group[5] * offset[2];
  R bound = group[6] * (fabs(offset[0]) + fabs(offset[1]) + fabs(offset[2]));
  *decided = side > bound || -side > bound;
  row[0] = side;
  return side > 0;
#endif
}

POLY_INLINE void POLY_FN(block_sides)(const POLY_FN(shape_view) *mine, const R *my_vertices, int mine_is_b,
                                      const POLY_FN(shape_view) *other, const R *other_vertices, const R *other_planes,
                                      const int *faces, int num_faces, int stride, R *sides, unsigned long long *masks)
{
  const int lanes = POLY_BLOCK_LANES, groups = stride / POLY_BLOCK_LANES, all = (1 << POLY_BLOCK_LANES) - 1;
  /* Padding lanes: a plane of zeros, side 0, behind. */
  R table[7 * POLY_BLOCK_MAX + 7 * 4];
  for (int c = 0; c < stride; c++) {
    R *slot = table + 7 * lanes * (c / lanes) + c % lanes;
    if (c >= num_faces) {
      for (int k = 0; k < 6; k++) slot[k * lanes] = 0;
      slot[6 * lanes] = -1;
      continue;
    }
    const int *tri = other->triangles + 3 * faces[c];
    const R *plane = other_planes + 4 * faces[c];
    for (int k = 0; k < 3; k++) {
      slot[k * lanes] = other_vertices[3 * tri[0] + k];
      slot[(3 + k) * lanes] = plane[k];
    }
    slot[6 * lanes] = (R)32 * POLY_FN(epsilon)() * plane[3];
  }
  for (int v = 0; v < mine->num_vertices; v++) {
    const R *x = my_vertices + 3 * v;
    R *row = sides + v * stride;
    unsigned long long mask = 0;
    for (int g = 0; g < groups; g++) {
      int decided, in_front = POLY_FN(block_side_group)(x, table + 7 * lanes * g, row + g * lanes, &decided);
      for (int l = 0; decided != all && l < lanes; l++) {
        int c = g * lanes + l;
        if (decided >> l & 1 || c >= num_faces) continue;
        const int *tri = other->triangles + 3 * faces[c];
        const R *plane = other_planes + 4 * faces[c];
        row[c] = POLY_FN(plane_side)(x, other_vertices, tri, plane);
        in_front &= ~(1 << l);
        in_front |= (POLY_FN(side_sign)(row[c], mine_is_b, other_vertices, tri, plane) > 0) << l;
      }
      mask |= (unsigned long long)in_front << (g * lanes);
    }
    masks[v] = mask;
  }
}

/* The columns of a side table (faces of the other body) that some vertex
 * lies within `reach` (relative to the plane's |.|_1, which bounds its
 * length) of: only these faces can be flush with a face of this body. */
POLY_INLINE unsigned long long POLY_FN(block_near_faces)(const R *sides, int stride, int num_vertices, int num_faces,
                                                         const R *planes, const int *faces, R reach)
{
  unsigned long long near = 0;
  for (int c = 0; c < num_faces; c++) {
    R limit = reach * POLY_FN(norm1)(planes + 4 * faces[c]);
    for (int v = 0; v < num_vertices; v++)
      if (fabs(sides[v * stride + c]) <= limit) {
        near |= 1ull << c;
        break;
      }
  }
  return near;
}

/* Is a face of A flush with a face of B, as the general path would find it
 * (triangles_flush on a pair of their triangles whose boxes, grown by the
 * tolerance, overlap)? A flush pair has the corners of each triangle within
 * the tolerance of the other's plane, so only faces that the other body's
 * vertices come near (the side tables, with twice the tolerance for the
 * rounding of the faces' other triangles) are paired, by their normals
 * first; every pair of their triangles is then tested, kept by the filter or
 * not, so this finds every flush pair the general path finds, and perhaps a
 * few more (which it then evaluates without smoothing: the same answer, more
 * slowly). */
POLY_INLINE int POLY_FN(block_flush)(const POLY_FN(shape_view) *a, const R *va, const int *faces_a,
                                     unsigned long long near_a, const POLY_FN(shape_view) *b, const R *vb,
                                     const int *faces_b, unsigned long long near_b, const double *rotation,
                                     R tolerance)
{
  for (; near_a; near_a &= near_a - 1) {
    int f = faces_a[__builtin_ctzll(near_a)];
    for (unsigned long long candidates = near_b; candidates; candidates &= candidates - 1) {
      int g = faces_b[__builtin_ctzll(candidates)];
      const R *n = b->face_normals + 3 * g;
      R turned[3];
      for (int k = 0; k < 3; k++)
        turned[k] = (R)(rotation[3 * k] * n[0] + rotation[3 * k + 1] * n[1] + rotation[3 * k + 2] * n[2]);
      R cosine = POLY_FN(dot)(a->face_normals + 3 * f, turned);
      /* triangles_flush's own first test, with a margin for the normals of the faces' other triangles. */
      if (cosine * cosine < (R)0.9998) continue;
      for (int t = f; t < a->num_triangles; t++) {
        if (a->face_of[t] != f) continue;
        const int *tri_t = a->triangles + 3 * t;
        R plane_t[4], box_t[6];
        POLY_FN(triangle_plane)(va, tri_t, plane_t);
        POLY_FN(triangle_bounds)(va, tri_t, box_t, box_t + 3);
        for (int k = 0; k < 3; k++) {
          box_t[k] -= tolerance;
          box_t[3 + k] += tolerance;
        }
        for (int u = g; u < b->num_triangles; u++) {
          if (b->face_of[u] != g) continue;
          const int *tri_u = b->triangles + 3 * u;
          R plane_u[4], box_u[6], normal_u[3];
          POLY_FN(triangle_bounds)(vb, tri_u, box_u, box_u + 3);
          for (int k = 0; k < 3; k++) {
            box_u[k] -= tolerance;
            box_u[3 + k] += tolerance;
          }
          if (!POLY_FN(boxes_overlap)(box_t, box_t + 3, box_u)) continue;
          POLY_FN(triangle_plane)(vb, tri_u, plane_u);
          POLY_FN(turn_normal)(rotation, b->face_normals + 3 * u, normal_u);
          if (POLY_FN(triangles_flush)(va, tri_t, plane_t, a->face_normals + 3 * t, vb, tri_u, plane_u, normal_u,
                                       tolerance))
            return 1;
        }
      }
    }
  }
  return 0;
}

/* Records of the ridges of `mine` clipped by the faces of the other body
 * (convex_crossings' decisions, the faces to clip by read from the masks). */
POLY_INLINE int POLY_FN(block_crossings)(const POLY_FN(shape_view) *mine, const R *sides, int stride,
                                         const unsigned long long *masks, const int *other_faces,
                                         POLY_FN(overlap_workspace) *ws,
                                         int *num_records, int *runs, int *num_runs)
{
  for (int q = 0; q < mine->num_ridges; q++) {
    int e = mine->ridges[q], v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
    unsigned long long mask0 = masks[v0], mask1 = masks[v1];
    if (mask0 & mask1) continue; /* both ends in front of one face: no part inside */
    POLY_FN(clip) clip = {0, 1, -1, -1};
    for (unsigned long long differ = mask0 ^ mask1; differ; differ &= differ - 1) {
      int c = __builtin_ctzll(differ);
      POLY_FN(clip_by_face)(&clip, sides[v0 * stride + c], sides[v1 * stride + c], mask0 >> c & 1, other_faces[c]);
    }
    /* Both ends behind every face (masks 0): inside, a run without records. */
    int in0 = !mask0, in1 = !mask1, through = !in0 && !in1 && clip.enter < clip.leave;
    if (POLY_FN(ridge_records)(ws, e, in0, in1, through, &clip, num_records, runs, num_runs)) return -1;
  }
  return 0;
}

/* The chords of the crossing face pairs (f of A, g of B), added to f and,
 * reversed, to g, as add_chords does; the two ends of each pair are found in
 * a table over the pairs of face columns rather than by sorting. Returns -1
 * where a pair does not have exactly two ends (see group_chord_ends). */
POLY_INLINE int POLY_FN(block_chords)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                      const R *vb, int records_b, int num_records, int num_faces_a, int num_faces_b,
                                      POLY_FN(overlap_workspace) *ws, POLY_FN(accumulator) *acc)
{
  int pending[POLY_BLOCK_CHORD_TABLE], pairs[3 * 2 * POLY_BLOCK_MAX], num_pairs = 0, unpaired = 0;
  for (int key = 0; key < num_faces_a * num_faces_b; key++) pending[key] = -1;
  for (int r = 0; r < num_records; r++) {
    int t[2], s[2], end[2];
    POLY_FN(record_ends)(a, b, ws, r, r >= records_b, 1, t, s, end);
    for (int j = 0; j < 2; j++) {
      int key = ws->face_column_a[t[j]] * num_faces_b + ws->face_column_b[s[j]];
      if (pending[key] == -1) {
        pending[key] = end[j];
        unpaired++;
      } else if (pending[key] >= 0 && num_pairs < 2 * POLY_BLOCK_MAX) {
        int *pair = pairs + 3 * num_pairs++;
        pair[0] = key;
        pair[1] = pending[key];
        pair[2] = end[j];
        pending[key] = -2;
        unpaired--;
      } else {
        return -1;
      }
    }
  }
  if (unpaired) return -1;
  for (int p = 0; p < num_pairs; p++) {
    const int *pair = pairs + 3 * p;
    R points[2][3];
    for (int k = 0; k < 2; k++) {
      int r = pair[1 + k] >> 1;
      if (r >= records_b)
        POLY_FN(record_point)(b, vb, ws, r, points[k]);
      else
        POLY_FN(record_point)(a, va, ws, r, points[k]);
    }
    const R *first = points[0], *second = points[1];
    if (!(pair[1] & 1)) {
      first = points[1];
      second = points[0];
    }
    int t = ws->faces_a[pair[0] / num_faces_b], u = ws->faces_b[pair[0] % num_faces_b];
    POLY_FN(add_segment)(acc, ws->apex_a + 3 * t, a->face_normals + 3 * t, first, second, 1);
    POLY_FN(add_segment)(acc, ws->apex_b + 3 * u, b->face_normals + 3 * u, second, first, 0);
  }
  return 0;
}

/* Can the pair take the blocks path? */
POLY_INLINE int POLY_FN(blocks_fit)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                    const POLY_FN(overlap_workspace) *ws)
{
  return a->face_of && b->face_of && a->num_vertices <= POLY_BLOCK_MAX && b->num_vertices <= POLY_BLOCK_MAX &&
         a->num_vertices * POLY_FN(block_stride)(b->num_triangles) +
                 b->num_vertices * POLY_FN(block_stride)(a->num_triangles) <= ws->capacity_sides &&
         a->num_edges + b->num_edges <= ws->capacity_runs &&
         (long)a->num_triangles * b->num_triangles <= POLY_BLOCK_CHORD_TABLE;
}

/* The blocks path of one pass, on the vertices in the local frame (va, vb):
 * 0 with the sums and nodes in *out, 1 when a face separates the bodies, -1
 * where the general path must decide (see the top of this file), -2 for
 * shapes of more than POLY_BLOCK_MAX faces (the convex path takes them). */
POLY_INLINE int POLY_FN(blocks_path)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                     const R *vb, const double *rotation, R tolerance, POLY_FN(overlap_workspace) *ws,
                                     POLY_FN(pass) *out)
{
  /* A separating face is named as support_separated names it: a convex shape's support list is all its
   * triangles, in order. */
  int *faces_a = ws->faces_a, *faces_b = ws->faces_b;
  int num_faces_a = POLY_FN(block_faces)(a, faces_a, ws->face_column_a);
  int num_faces_b = POLY_FN(block_faces)(b, faces_b, ws->face_column_b);
  if (num_faces_a < 0 || num_faces_b < 0) return -2; /* more faces than a mask holds: the convex path's */
  for (int c = 0; c < num_faces_a; c++) {
    int f = faces_a[c];
    POLY_FN(triangle_plane)(va, a->triangles + 3 * f, ws->planes_a + 4 * f);
    ws->apex_a[3 * f] = POLY_NO_APEX;
  }
  for (int c = 0; c < num_faces_b; c++) {
    int g = faces_b[c];
    POLY_FN(triangle_plane)(vb, b->triangles + 3 * g, ws->planes_b + 4 * g);
    ws->apex_b[3 * g] = POLY_NO_APEX;
  }
  unsigned long long masks_a[POLY_BLOCK_MAX], masks_b[POLY_BLOCK_MAX];
  int stride_a = POLY_FN(block_stride)(num_faces_b), stride_b = POLY_FN(block_stride)(num_faces_a);
  R *sides_a = ws->sides, *sides_b = ws->sides + a->num_vertices * stride_a;
  unsigned long long all_a = ~0ull, all_b = ~0ull;
  POLY_FN(block_sides)(a, va, 0, b, vb, ws->planes_b, faces_b, num_faces_b, stride_a, sides_a, masks_a);
  for (int i = 0; i < a->num_vertices; i++) all_a &= masks_a[i];
  if (all_a) {
    out->separating = 2 * faces_b[__builtin_ctzll(all_a)] + 1;
    return 1;
  }
  POLY_FN(block_sides)(b, vb, 1, a, va, ws->planes_a, faces_a, num_faces_a, stride_b, sides_b, masks_b);
  for (int j = 0; j < b->num_vertices; j++) all_b &= masks_b[j];
  if (all_b) {
    out->separating = 2 * faces_a[__builtin_ctzll(all_b)];
    return 1;
  }
  if (tolerance > 0) {
    unsigned long long near_b = POLY_FN(block_near_faces)(sides_a, stride_a, a->num_vertices, num_faces_b,
                                                          ws->planes_b, faces_b, 2 * tolerance);
    unsigned long long near_a = near_b ? POLY_FN(block_near_faces)(sides_b, stride_b, b->num_vertices, num_faces_a,
                                                                   ws->planes_a, faces_a, 2 * tolerance)
                                       : 0;
    if (near_a && POLY_FN(block_flush)(a, va, faces_a, near_a, b, vb, faces_b, near_b, rotation, tolerance))
      return -1;
  }

  int num_records = 0, num_runs_a = 0, num_runs_b = 0;
  int *runs_a = ws->runs;
  if (POLY_FN(block_crossings)(a, sides_a, stride_a, masks_a, faces_b, ws, &num_records, runs_a, &num_runs_a))
    return -1;
  int records_b = num_records, *runs_b = runs_a + 3 * num_runs_a;
  if (POLY_FN(block_crossings)(b, sides_b, stride_b, masks_b, faces_a, ws, &num_records, runs_b, &num_runs_b))
    return -1;

  POLY_FN(accumulator) acc = out->acc;
  int num_points = 0;
  for (int i = 0; i < a->num_vertices; i++) {
    ws->inside_a[i] = !masks_a[i];
    if (!masks_a[i]) POLY_FN(add_point)(ws, &num_points, va + 3 * i);
  }
  for (int j = 0; j < b->num_vertices; j++) {
    ws->inside_b[j] = !masks_b[j];
    if (!masks_b[j]) POLY_FN(add_point)(ws, &num_points, vb + 3 * j);
  }
  POLY_FN(run_inside_parts)(a, va, ws->inside_a, runs_a, num_runs_a, a->face_normals, ws->apex_a, 0, a->face_of, ws,
                            &acc, &num_points);
  /* B's facets count no area, so their normals are not read: B's own stand in for the turned ones. */
  POLY_FN(run_inside_parts)(b, vb, ws->inside_b, runs_b, num_runs_b, b->face_normals, ws->apex_b, 1, b->face_of, ws,
                            &acc, &num_points);
  /* node_extent, which finds nodes again past the workspace, needs the filter's lists (a pass that keeps no
   * nodes has capacity 0). */
  if (num_points > ws->capacity_points && ws->capacity_points > 0) return -1;
  if (POLY_FN(block_chords)(a, va, b, vb, records_b, num_records, num_faces_a, num_faces_b, ws, &acc)) return -1;
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = 0;
  out->flush = 0;
  return 0;
}
#endif
