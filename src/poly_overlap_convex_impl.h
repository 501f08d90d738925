/* The convex path of one pass of the overlap (overlap_pass in
 * poly_overlap_impl.h), for two shapes found convex when they were built
 * (poly_shape_find_faces: per triangle its face, and the ridges between
 * faces). Included by poly_overlap_impl.h once per precision (no include
 * guard).
 *
 * A convex body is the intersection of its faces' half-spaces, so a point is
 * inside it when it is behind every face, and an edge of the other body is
 * inside it between the last face it enters through and the first it leaves
 * through (Cyrus-Beck clipping). Both come from one table of the vertices'
 * sides of the faces (plane_side, exact signs, the perturbation deciding exact
 * zeros), with no test of a crossing against a triangle's edges: that test is
 * most of the cost of the general path. Only the faces holding a triangle kept
 * by the half-space filter are needed: any point of A (which lies below the
 * slab's far limit) behind all of those is inside B, as a segment from B to
 * such a point could only leave B through a face reaching below that limit.
 * The facets are whole faces (coplanar triangles merged, named by their lowest
 * triangle) and only ridges are clipped: the segments of an edge inside a flat
 * face would cancel. The crossings become the records of the general path, so
 * the chords and the sums are built by the same code.
 *
 * The path answers only where its decisions are consistent: where a chord of
 * a pair of faces does not get exactly two ends (a vertex or an edge of one
 * body on an edge of the other, decided by rounding rather than by the
 * perturbation), where faces are flush (the smoothing of overlap_local), or
 * where the table or the records do not fit, the pass returns -1 and the
 * general path decides exactly. tests/test_convex_path.py checks it against
 * the general path. */

/* The faces of `body` holding a kept triangle: their lowest triangles in
 * `faces`, each face's column of the side table in `column` (indexed by the
 * lowest triangle). The plane of a face comes from its lowest triangle, which
 * the filter may not have kept: its plane (and for B its turned normal) is
 * made here, as prepare_kept_triangle makes them. */
POLY_INLINE int POLY_FN(convex_faces)(const POLY_FN(shape_view) *body, const R *vertices, const int *kept_list,
                                      int num_kept, const unsigned char *kept, R *planes, int *faces, int *column,
                                      R *turned_normals, const double *rotation)
{
  for (int m = 0; m < num_kept; m++) column[body->face_of[kept_list[m]]] = -1;
  int num_faces = 0;
  for (int m = 0; m < num_kept; m++) {
    int f = body->face_of[kept_list[m]];
    if (column[f] >= 0) continue;
    column[f] = num_faces;
    faces[num_faces++] = f;
    if (kept[f]) continue;
    const int *tri = body->triangles + 3 * f;
    R e1[3], e2[3], *plane = planes + 4 * f;
    POLY_FN(sub)(vertices + 3 * tri[1], vertices + 3 * tri[0], e1);
    POLY_FN(sub)(vertices + 3 * tri[2], vertices + 3 * tri[0], e2);
    POLY_FN(cross)(e1, e2, plane);
    plane[3] = POLY_FN(norm1)(e1) * POLY_FN(norm1)(e2);
    if (turned_normals) {
      const R *n = body->face_normals + 3 * f;
      for (int k = 0; k < 3; k++)
        turned_normals[3 * f + k] =
            (R)(rotation[3 * k] * n[0] + rotation[3 * k + 1] * n[1] + rotation[3 * k + 2] * n[2]);
    }
  }
  return num_faces;
}

/* Row of the side table for vertex v of `mine` (its plane_side values for the
 * faces of `other`), made on first use; sets inside[v] (behind every face).
 * Returns the row's offset, or -1 when the table is full. */
POLY_INLINE int POLY_FN(convex_row)(int v, const R *my_vertices, int mine_is_b, const POLY_FN(shape_view) *other,
                                    const R *other_vertices, const R *other_planes, const int *faces,
                                    int num_faces, int *row_of, unsigned char *inside,
                                    POLY_FN(overlap_workspace) *ws, int *num_sides)
{
  if (row_of[v] >= 0) return row_of[v];
  if (*num_sides + num_faces > ws->capacity_sides) return -1;
  int row = *num_sides;
  *num_sides += num_faces;
  const R *x = my_vertices + 3 * v;
  int behind = 1;
  for (int c = 0; c < num_faces; c++) {
    const int *tri = other->triangles + 3 * faces[c];
    const R *plane = other_planes + 4 * faces[c];
    R side = POLY_FN(plane_side)(x, other_vertices, tri, plane);
    ws->sides[row + c] = side;
    if (behind && POLY_FN(side_sign)(side, mine_is_b, other_vertices, tri, plane) > 0) behind = 0;
  }
  inside[v] = (unsigned char)behind;
  row_of[v] = row;
  return row;
}

/* Cyrus-Beck clipping of a ridge by the faces of the other body: the last
 * face it enters through and the first it leaves through, with their
 * parameters along it. */
typedef struct POLY_FN(clip) {
  R enter, leave;
  int enter_face, leave_face;
} POLY_FN(clip);

/* The ridge's crossing of one face whose sides (plane_side values side0,
 * side1 at its ends) differ: `entering` where its first end is in front. */
POLY_INLINE void POLY_FN(clip_by_face)(POLY_FN(clip) *clip, R side0, R side1, int entering, int face)
{
  R lambda = POLY_FN(crossing_parameter)(side0, side1);
  if (entering) {
    if (clip->enter_face < 0 || lambda > clip->enter) {
      clip->enter = lambda;
      clip->enter_face = face;
    }
  } else if (clip->leave_face < 0 || lambda < clip->leave) {
    clip->leave = lambda;
    clip->leave_face = face;
  }
}

/* The records of ridge e (its ends inside or not: in0, in1; `through`: both
 * outside, crossing the body) and its run, appended; -1 when they do not fit. */
POLY_INLINE int POLY_FN(ridge_records)(POLY_FN(overlap_workspace) *ws, int e, int in0, int in1, int through,
                                       const POLY_FN(clip) *clip, int *num_records, int *runs, int *num_runs)
{
  int first = *num_records, count = 0;
  if (first + 2 > ws->capacity_records) return -1;
  if ((!in0 && in1) || through) {
    ws->record_lambda[first + count] = clip->enter;
    ws->record_entering[first + count] = (R)1;
    ws->record_triangle[first + count] = clip->enter_face;
    ws->record_edge[first + count++] = e;
  }
  if ((in0 && !in1) || through) {
    ws->record_lambda[first + count] = clip->leave;
    ws->record_entering[first + count] = (R)-1;
    ws->record_triangle[first + count] = clip->leave_face;
    ws->record_edge[first + count++] = e;
  }
  *num_records = first + count;
  int *run = runs + 3 * (*num_runs)++;
  run[0] = e;
  run[1] = first;
  run[2] = count;
  return 0;
}

/* Records of the ridges of `mine` in the slab, clipped by the faces of
 * `other`: the crossing where a ridge enters the other body (the last face it
 * enters through) and where it leaves it (the first it leaves through), with
 * the face as the record's triangle. One run per ridge in the slab, as
 * find_crossings. Returns 0, or -1 when the table or the records are full. */
POLY_INLINE int POLY_FN(convex_crossings)(const POLY_FN(shape_view) *mine, const R *my_vertices, int mine_is_b,
                                          const POLY_FN(shape_view) *other, const R *other_vertices,
                                          const R *other_planes, const int *faces, int num_faces, const R *axis,
                                          R slab_limit, int *row_of, unsigned char *inside,
                                          POLY_FN(overlap_workspace) *ws, int *num_sides, int *num_records,
                                          int *runs, int *num_runs)
{
  for (int q = 0; q < mine->num_ridges; q++) {
    int e = mine->ridges[q], v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
    R d0 = POLY_FN(dot)(my_vertices + 3 * v0, axis), d1 = POLY_FN(dot)(my_vertices + 3 * v1, axis);
    if (!mine_is_b ? (d0 < slab_limit && d1 < slab_limit) : (d0 > slab_limit && d1 > slab_limit)) continue;
    int row0 = POLY_FN(convex_row)(v0, my_vertices, mine_is_b, other, other_vertices, other_planes, faces, num_faces,
                                   row_of, inside, ws, num_sides);
    int row1 = POLY_FN(convex_row)(v1, my_vertices, mine_is_b, other, other_vertices, other_planes, faces, num_faces,
                                   row_of, inside, ws, num_sides);
    if (row0 < 0 || row1 < 0) return -1;
    POLY_FN(clip) clip = {0, 1, -1, -1};
    int missed = 0;
    for (int c = 0; c < num_faces && !missed; c++) {
      const int *tri = other->triangles + 3 * faces[c];
      const R *plane = other_planes + 4 * faces[c];
      R side0 = ws->sides[row0 + c], side1 = ws->sides[row1 + c];
      int sign0 = POLY_FN(side_sign)(side0, mine_is_b, other_vertices, tri, plane);
      int sign1 = POLY_FN(side_sign)(side1, mine_is_b, other_vertices, tri, plane);
      if (sign0 > 0 && sign1 > 0) missed = 1;
      if (sign0 == sign1) continue;
      POLY_FN(clip_by_face)(&clip, side0, side1, sign0 > 0, faces[c]);
    }
    int in0 = inside[v0], in1 = inside[v1];
    int through = !missed && !in0 && !in1 && clip.enter_face >= 0 && clip.leave_face >= 0 && clip.enter < clip.leave;
    if (POLY_FN(ridge_records)(ws, e, in0, in1, through, &clip, num_records, runs, num_runs)) return -1;
  }
  return 0;
}

/* The boundary sums of A n B for two convex shapes, after the filter of
 * overlap_pass (kept triangles with their planes, B's turned normals). Returns
 * 0 with the sums in *acc and the nodes counted in *num_points, or -1 where the
 * general path must decide (see the top of this file). */
POLY_INLINE int POLY_FN(convex_pass)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                     const R *vb, const double *rotation, const R *axis, R limit_a, R limit_b,
                                     R tolerance, int num_kept_a, int num_kept_b, POLY_FN(overlap_workspace) *ws,
                                     POLY_FN(accumulator) *acc, int *num_points)
{
  /* Flush faces: the general path finds them again and smooths. */
  for (int m = 0; m < num_kept_a && tolerance > 0; m++) {
    int t = ws->kept_list_a[m];
    const R *box_t = ws->bounds_a + 6 * t;
    for (int n = 0; n < num_kept_b; n++) {
      int s = ws->kept_list_b[n];
      R cosine = POLY_FN(dot)(a->face_normals + 3 * t, ws->normals_b + 3 * s);
      if (cosine * cosine < (R)0.9999 || !POLY_FN(boxes_overlap)(box_t, box_t + 3, ws->bounds_b + 6 * s)) continue;
      if (POLY_FN(triangles_flush)(va, a->triangles + 3 * t, ws->planes_a + 4 * t, a->face_normals + 3 * t, vb,
                                   b->triangles + 3 * s, ws->planes_b + 4 * s, ws->normals_b + 3 * s, tolerance))
        return -1;
    }
  }
  int *faces_a = ws->faces_a, *faces_b = ws->faces_b;
  int num_faces_a = POLY_FN(convex_faces)(a, va, ws->kept_list_a, num_kept_a, ws->kept_a, ws->planes_a, faces_a,
                                          ws->face_column_a, NULL, rotation);
  int num_faces_b = POLY_FN(convex_faces)(b, vb, ws->kept_list_b, num_kept_b, ws->kept_b, ws->planes_b, faces_b,
                                          ws->face_column_b, ws->normals_b, rotation);
  for (int i = 0; i < a->num_vertices; i++) {
    ws->row_of_a[i] = -1;
    ws->inside_a[i] = 0;
  }
  for (int j = 0; j < b->num_vertices; j++) {
    ws->row_of_b[j] = -1;
    ws->inside_b[j] = 0;
  }
  int num_sides = 0, num_records = 0, num_runs_a = 0, num_runs_b = 0;
  int *runs_a = ws->runs;
  if (POLY_FN(convex_crossings)(a, va, 0, b, vb, ws->planes_b, faces_b, num_faces_b, axis, limit_a, ws->row_of_a,
                                ws->inside_a, ws, &num_sides, &num_records, runs_a, &num_runs_a))
    return -1;
  int records_b = num_records, *runs_b = runs_a + 3 * num_runs_a;
  if (POLY_FN(convex_crossings)(b, vb, 1, a, va, ws->planes_a, faces_a, num_faces_a, axis, limit_b, ws->row_of_b,
                                ws->inside_b, ws, &num_sides, &num_records, runs_b, &num_runs_b))
    return -1;
  if (POLY_FN(group_chord_ends)(a, b, records_b, num_records, faces_a, num_faces_a, 1, ws)) return -1;
  for (int i = 0; i < a->num_vertices; i++)
    if (ws->inside_a[i]) POLY_FN(add_point)(ws, num_points, va + 3 * i);
  for (int j = 0; j < b->num_vertices; j++)
    if (ws->inside_b[j]) POLY_FN(add_point)(ws, num_points, vb + 3 * j);
  POLY_FN(run_inside_parts)(a, va, ws->inside_a, runs_a, num_runs_a, a->face_normals, ws->apex_a, 0, a->face_of, ws,
                            acc, num_points);
  POLY_FN(run_inside_parts)(b, vb, ws->inside_b, runs_b, num_runs_b, ws->normals_b, ws->apex_b, 1, b->face_of, ws,
                            acc, num_points);
  POLY_FN(add_chords)(a, va, b, vb, records_b, faces_a, num_faces_a, ws, acc, NULL);
  return 0;
}

/* The convex path of one pass: 0 with the sums and nodes in *out, or -1 (see
 * the top of this file). */
POLY_INLINE int POLY_FN(convex_path)(const POLY_FN(shape_view) *a, const R *va, const POLY_FN(shape_view) *b,
                                     const R *vb, const double *rotation, const POLY_FN(filtered) *f,
                                     POLY_FN(overlap_workspace) *ws, POLY_FN(pass) *out)
{
  if (a->num_edges + b->num_edges > ws->capacity_runs) return -1;
  POLY_FN(accumulator) acc = out->acc;
  int num_points = 0;
  if (POLY_FN(convex_pass)(a, va, b, vb, rotation, f->axis, f->limit_a, f->limit_b, f->tolerance, f->num_kept_a,
                           f->num_kept_b, ws, &acc, &num_points))
    return -1;
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = 0;
  out->flush = 0;
  return 0;
}
