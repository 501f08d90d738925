/* Convex pieces of a shape that is not convex by a binary partition of space
 * with the shape's own face planes (an autopartition), for the clipping path
 * (poly_clip.h). Included by poly_convex.c only.
 *
 * A box around the shape is split by the plane of a triangle that crosses it,
 * each half again, until no triangle crosses a cell's inside; such a cell is
 * then wholly inside the shape or wholly outside (decided by the winding
 * number of its centre). The cells inside are the pieces. Every facet of a
 * piece lies on one of the shape's face planes, so the pieces need no planes
 * but the shape's (8 for a Schoenhardt polyhedron, against the 20 of the cones
 * from the centre of mass), and they are fat: a cut follows the surface
 * instead of fanning from one point. The shape's triangles are cut where the
 * pieces' facets meet on them; each part (a "sub-face") belongs to the one
 * piece it bounds, and its corners, and the pieces' corners, join the shape's
 * vertices as clip vertices.
 *
 * Where the shape needs more pieces, planes, vertices or faces than the
 * clipping path holds, or the pieces do not add up to the shape's volume and
 * surface (a check run on every result), nothing is kept. */

#define PARTITION_MAX_CELL_PLANES 64  /* facets of one cell */
#define PARTITION_MAX_CELL_VERTICES 96
#define PARTITION_MAX_POINTS POLY_CLIP_MAX_VERTICES /* clip vertices: the shape's and the new corners */
#define PARTITION_MAX_CELLS 2048      /* cells visited, inside and outside: a bound on the time a shape takes */

typedef struct partition_cell {
  int count;
  int plane[PARTITION_MAX_CELL_PLANES];
  int behind[PARTITION_MAX_CELL_PLANES]; /* 1: the cell lies behind the plane (n.x <= d) */
} partition_cell;

typedef struct partition {
  const poly_shape *shape;
  double tolerance;
  int num_planes, num_face_planes; /* the shape's face planes first, then the box's 6 */
  double *planes;
  int *triangle_plane;
  /* what the pieces make */
  double *points;
  int num_points;
  int num_pieces, num_cells, failed;
  int max_piece_planes; /* at most POLY_CLIP_MAX_PIECE_PLANES */
  int piece_planes[POLY_CLIP_MAX_PIECES][POLY_CLIP_MAX_PIECE_PLANES];
  int piece_behind[POLY_CLIP_MAX_PIECES][POLY_CLIP_MAX_PIECE_PLANES];
  int piece_num_planes[POLY_CLIP_MAX_PIECES];
  int *piece_points, num_piece_points, piece_point_start[POLY_CLIP_MAX_PIECES + 1];
  int *faces_loop, faces_loop_used, num_faces, *face_loop_start, *face_triangle;
  int piece_face_start[POLY_CLIP_MAX_PIECES + 1];
  double volume, area;
} partition;

static double partition_side(const partition *p, int plane, const double *x)
{
  const double *q = p->planes + 4 * plane;
  return q[0] * x[0] + q[1] * x[1] + q[2] * x[2] - q[3];
}

/* The corners of a cell: every three of its planes that meet in a point on or behind all of them; -1 when it has
 * too many. */
static int partition_cell_vertices(const partition *p, const partition_cell *cell, double *vertices)
{
  int count = 0;
  const double tolerance = p->tolerance;
  for (int i = 0; i < cell->count; i++)
    for (int j = i + 1; j < cell->count; j++)
      for (int k = j + 1; k < cell->count; k++) {
        const double *a = p->planes + 4 * cell->plane[i], *b = p->planes + 4 * cell->plane[j],
                     *c = p->planes + 4 * cell->plane[k];
        double bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
        double det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
        if (fabs(det) < 1e-9) continue;
        double ca[3] = {c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0]};
        double ab[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        double x[3];
        for (int m = 0; m < 3; m++) x[m] = (a[3] * bc[m] + b[3] * ca[m] + c[3] * ab[m]) / det;
        int inside = 1;
        for (int m = 0; m < cell->count && inside; m++) {
          double s = partition_side(p, cell->plane[m], x);
          inside = cell->behind[m] ? s <= tolerance : s >= -tolerance;
        }
        if (!inside) continue;
        int known = 0;
        for (int v = 0; v < count && !known; v++) {
          const double *y = vertices + 3 * v;
          known = fabs(x[0] - y[0]) <= tolerance && fabs(x[1] - y[1]) <= tolerance && fabs(x[2] - y[2]) <= tolerance;
        }
        if (known) continue;
        if (count == PARTITION_MAX_CELL_VERTICES) return -1;
        for (int m = 0; m < 3; m++) vertices[3 * count + m] = x[m];
        count++;
      }
  return count;
}

/* Triangle t clipped by the cell's planes, each moved `inset` into the cell: the polygon's corner count. */
static int partition_clip_triangle(const partition *p, const partition_cell *cell, int t, double inset,
                                   int skip_plane, double *polygon)
{
  double work[3 * POLY_CLIP_MAX_POLYGON * 2];
  double *in = polygon, *out = work;
  const poly_shape *shape = p->shape;
  int n = 3;
  for (int c = 0; c < 3; c++)
    for (int m = 0; m < 3; m++) in[3 * c + m] = shape->vertices[3 * shape->triangles[3 * t + c] + m];
  for (int k = 0; k < cell->count && n >= 3; k++) {
    if (cell->plane[k] == skip_plane) continue;
    const double *q = p->planes + 4 * cell->plane[k];
    double plane[4];
    for (int m = 0; m < 4; m++) plane[m] = cell->behind[k] ? q[m] : -q[m];
    plane[3] -= inset;
    n = poly_clip_polygon(in, n, plane, out, 2 * POLY_CLIP_MAX_POLYGON);
    if (n < 0) return 0;
    double *swap = in;
    in = out;
    out = swap;
  }
  if (in != polygon)
    for (int m = 0; m < 3 * n; m++) polygon[m] = in[m];
  return n >= 3 ? n : 0;
}

static double partition_polygon_area(const double *polygon, int n)
{
  double sum[3] = {0.0, 0.0, 0.0};
  for (int i = 1; i + 1 < n; i++) {
    const double *a = polygon, *b = polygon + 3 * i, *c = polygon + 3 * (i + 1);
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    sum[0] += e1[1] * e2[2] - e1[2] * e2[1];
    sum[1] += e1[2] * e2[0] - e1[0] * e2[2];
    sum[2] += e1[0] * e2[1] - e1[1] * e2[0];
  }
  return 0.5 * sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
}

/* Does triangle t cross the cell's inside (not only touch its boundary)? */
static int partition_crosses(const partition *p, const partition_cell *cell, const double *vertices, int count, int t)
{
  const int plane = p->triangle_plane[t];
  for (int k = 0; k < cell->count; k++)
    if (cell->plane[k] == plane) return 0;
  int ahead = 0, behind = 0;
  for (int v = 0; v < count; v++) {
    double s = partition_side(p, plane, vertices + 3 * v);
    ahead |= s > p->tolerance;
    behind |= s < -p->tolerance;
  }
  if (!ahead || !behind) return 0;
  double polygon[3 * POLY_CLIP_MAX_POLYGON * 2];
  int n = partition_clip_triangle(p, cell, t, p->tolerance, -1, polygon);
  return n >= 3 && partition_polygon_area(polygon, n) > p->tolerance * p->tolerance;
}

/* Winding number of the shape's surface about x (1 inside, 0 outside). */
static double partition_winding(const poly_shape *shape, const double *x)
{
  double solid = 0.0;
  for (int t = 0; t < shape->num_triangles; t++) {
    double r[3][3], length[3];
    for (int c = 0; c < 3; c++) {
      for (int m = 0; m < 3; m++) r[c][m] = shape->vertices[3 * shape->triangles[3 * t + c] + m] - x[m];
      length[c] = sqrt(r[c][0] * r[c][0] + r[c][1] * r[c][1] + r[c][2] * r[c][2]);
    }
    double triple = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                    r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    double dot01 = r[0][0] * r[1][0] + r[0][1] * r[1][1] + r[0][2] * r[1][2];
    double dot12 = r[1][0] * r[2][0] + r[1][1] * r[2][1] + r[1][2] * r[2][2];
    double dot20 = r[2][0] * r[0][0] + r[2][1] * r[0][1] + r[2][2] * r[0][2];
    solid += 2.0 * atan2(triple, length[0] * length[1] * length[2] + dot01 * length[2] + dot12 * length[0] +
                                     dot20 * length[1]);
  }
  return solid / (4.0 * 3.14159265358979323846);
}

/* Index of point x among the clip points, added when new; -1 when they are full. */
static int partition_point(partition *p, const double *x)
{
  for (int v = 0; v < p->num_points; v++) {
    const double *y = p->points + 3 * v;
    if (fabs(x[0] - y[0]) <= p->tolerance && fabs(x[1] - y[1]) <= p->tolerance && fabs(x[2] - y[2]) <= p->tolerance)
      return v;
  }
  if (p->num_points == PARTITION_MAX_POINTS) return -1;
  for (int m = 0; m < 3; m++) p->points[3 * p->num_points + m] = x[m];
  return p->num_points++;
}

/* Points `x` (`count`, 3 each) as clip points into `index`; 0 (and the partition failed) when they are full. */
static int partition_points(partition *p, const double *x, int count, int *index)
{
  for (int v = 0; v < count; v++)
    if ((index[v] = partition_point(p, x + 3 * v)) < 0) {
      p->failed = 1;
      return 0;
    }
  return 1;
}

/* A cell inside the shape (its planes its facets only, as partition_split leaves them) becomes a piece: its
 * planes, its corners, and the parts of the triangles on its facets (the sub-faces) with their area and the
 * volume they enclose. */
static void partition_add_piece(partition *p, const partition_cell *facets, const double *vertices, int count)
{
  if (p->num_pieces == POLY_CLIP_MAX_PIECES || facets->count > p->max_piece_planes) {
    p->failed = 1;
    return;
  }
  const int piece = p->num_pieces, num_planes = facets->count;
  for (int k = 0; k < num_planes; k++) {
    if (facets->plane[k] >= p->num_face_planes) {
      p->failed = 1;  /* a box plane bounds a piece: the box did not hold the shape */
      return;
    }
    p->piece_planes[piece][k] = facets->plane[k];
    p->piece_behind[piece][k] = facets->behind[k];
  }
  p->piece_num_planes[piece] = num_planes;
  if (!partition_points(p, vertices, count, p->piece_points + p->num_piece_points)) return;
  p->num_piece_points += count;
  p->piece_point_start[piece + 1] = p->num_piece_points;
  const poly_shape *shape = p->shape;
  for (int t = 0; t < shape->num_triangles; t++) {
    int on_facet = 0;
    for (int k = 0; k < num_planes; k++) on_facet |= facets->plane[k] == p->triangle_plane[t] && facets->behind[k];
    if (!on_facet) continue;
    double polygon[3 * POLY_CLIP_MAX_POLYGON * 2];
    int n = partition_clip_triangle(p, facets, t, 0.0, p->triangle_plane[t], polygon);
    if (n < 3 || !(partition_polygon_area(polygon, n) > p->tolerance * p->tolerance)) continue;
    if (p->num_faces == POLY_CLIP_MAX_FACES || n > POLY_CLIP_MAX_LOOP) {
      p->failed = 1;
      return;
    }
    p->face_loop_start[p->num_faces] = p->faces_loop_used;
    if (!partition_points(p, polygon, n, p->faces_loop + p->faces_loop_used)) return;
    p->faces_loop_used += n;
    p->face_triangle[p->num_faces++] = t;
    p->area += partition_polygon_area(polygon, n);
    for (int i = 1; i + 1 < n; i++) {
      const double *a = polygon, *b = polygon + 3 * i, *c = polygon + 3 * (i + 1);
      p->volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                    a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
  }
  p->piece_face_start[piece + 1] = p->num_faces;
  p->num_pieces++;
}

/* The cell's plane that crossing triangles' own planes cut the fewest others of the crossing triangles; -1
 * when none crosses. */
static int partition_choose(const partition *p, const partition_cell *cell, const int *crossing, int num_crossing)
{
  int best = -1, best_cuts = 1 << 30, best_on = 0;
  for (int i = 0; i < num_crossing; i++) {
    const int plane = p->triangle_plane[crossing[i]];
    int seen = 0;
    for (int j = 0; j < i && !seen; j++) seen = p->triangle_plane[crossing[j]] == plane;
    if (seen) continue;
    int cuts = 0, on = 0;
    for (int j = 0; j < num_crossing; j++) {
      const int t = crossing[j];
      if (p->triangle_plane[t] == plane) {
        on++;
        continue;
      }
      double polygon[3 * POLY_CLIP_MAX_POLYGON * 2];
      int n = partition_clip_triangle(p, cell, t, 0.0, -1, polygon), ahead = 0, behind = 0;
      for (int c = 0; c < n; c++) {
        double s = partition_side(p, plane, polygon + 3 * c);
        ahead |= s > p->tolerance;
        behind |= s < -p->tolerance;
      }
      cuts += ahead && behind;
    }
    if (cuts < best_cuts || (cuts == best_cuts && on > best_on)) {
      best = plane;
      best_cuts = cuts;
      best_on = on;
    }
  }
  return best;
}

static void partition_split(partition *p, const partition_cell *cell, const int *candidates, int num_candidates)
{
  if (p->failed) return;
  if (++p->num_cells > PARTITION_MAX_CELLS) {
    p->failed = 1;
    return;
  }
  double vertices[3 * PARTITION_MAX_CELL_VERTICES];
  int count = partition_cell_vertices(p, cell, vertices);
  if (count < 0) p->failed = 1;
  if (count < 4) return;  /* empty */
  /* Only the facets' planes go on (the others hold fewer than 3 corners), so that cells deep in the partition stay
   * small; a plane with every corner on it is a flat cell, which is dropped. */
  partition_cell facets;
  facets.count = 0;
  for (int k = 0; k < cell->count; k++) {
    int on = 0;
    for (int v = 0; v < count; v++) on += fabs(partition_side(p, cell->plane[k], vertices + 3 * v)) <= p->tolerance;
    if (on == count) return;
    if (on < 3) continue;
    facets.plane[facets.count] = cell->plane[k];
    facets.behind[facets.count++] = cell->behind[k];
  }
  cell = &facets;
  int crossing[POLY_CLIP_MAX_FACES], num_crossing = 0;
  for (int i = 0; i < num_candidates; i++)
    if (partition_crosses(p, cell, vertices, count, candidates[i])) crossing[num_crossing++] = candidates[i];
  if (num_crossing == 0) {
    double centre[3] = {0.0, 0.0, 0.0};
    for (int v = 0; v < count; v++)
      for (int m = 0; m < 3; m++) centre[m] += vertices[3 * v + m] / count;
    double winding = partition_winding(p->shape, centre);
    if (winding > 0.5) partition_add_piece(p, cell, vertices, count);
    return;
  }
  if (cell->count == PARTITION_MAX_CELL_PLANES) {
    p->failed = 1;
    return;
  }
  const int plane = partition_choose(p, cell, crossing, num_crossing);
  partition_cell half = *cell;
  half.plane[half.count] = plane;
  half.count++;
  for (int side = 1; side >= 0; side--) {
    half.behind[half.count - 1] = side;
    partition_split(p, &half, crossing, num_crossing);
  }
}

/* The partition's pieces into the shape (the fields poly_convex.c's cones fill, and the clip vertices); returns
 * 0, leaving the shape as it was, when it does not give pieces the clipping path takes. */
static int partition_pieces(poly_shape *shape, int max_piece_planes)
{
  const int nt = shape->num_triangles, nv = shape->num_vertices;
  const double radius = shape->bounding_radius;
  if (nt > POLY_CLIP_MAX_FACES || nv > PARTITION_MAX_POINTS) return 0;
  partition p;
  memset(&p, 0, sizeof p);
  p.shape = shape;
  p.max_piece_planes = max_piece_planes < POLY_CLIP_MAX_PIECE_PLANES ? max_piece_planes : POLY_CLIP_MAX_PIECE_PLANES;
  p.tolerance = 1e-12 * radius;
  p.planes = (double *)malloc(sizeof(double) * 4 * (size_t)(nt + 6));
  p.triangle_plane = (int *)malloc(sizeof(int) * (size_t)nt);
  p.points = (double *)malloc(sizeof(double) * 3 * PARTITION_MAX_POINTS);
  p.piece_points = (int *)malloc(sizeof(int) * POLY_CLIP_MAX_PIECES * PARTITION_MAX_CELL_VERTICES);
  p.faces_loop = (int *)malloc(sizeof(int) * POLY_CLIP_MAX_FACES * POLY_CLIP_MAX_LOOP);
  p.face_loop_start = (int *)malloc(sizeof(int) * (POLY_CLIP_MAX_FACES + 1));
  p.face_triangle = (int *)malloc(sizeof(int) * POLY_CLIP_MAX_FACES);
  int ok = p.planes && p.triangle_plane && p.points && p.piece_points && p.faces_loop && p.face_loop_start &&
           p.face_triangle;
  /* The face planes, coplanar triangles of one orientation sharing one. */
  for (int t = 0; ok && t < nt; t++) {
    const double *n = shape->face_normals + 3 * t, *corner = shape->vertices + 3 * shape->triangles[3 * t];
    double plane[4] = {n[0], n[1], n[2], n[0] * corner[0] + n[1] * corner[1] + n[2] * corner[2]};
    int index = -1;
    for (int k = 0; k < p.num_planes && index < 0; k++) {
      const double *q = p.planes + 4 * k;
      if (plane[0] * q[0] + plane[1] * q[1] + plane[2] * q[2] > 1.0 - 1e-12 && fabs(plane[3] - q[3]) <= p.tolerance)
        index = k;
    }
    if (index < 0) {
      index = p.num_planes++;
      for (int m = 0; m < 4; m++) p.planes[4 * index + m] = plane[m];
    }
    p.triangle_plane[t] = index;
  }
  p.num_face_planes = p.num_planes;
  /* The box, a tenth of the size clear of the shape, so that no piece has a facet on it. */
  partition_cell box;
  box.count = 0;
  for (int axis = 0; ok && axis < 3; axis++)
    for (int sign = -1; sign <= 1; sign += 2) {
      double *q = p.planes + 4 * p.num_planes;
      q[0] = q[1] = q[2] = 0.0;
      q[axis] = sign;
      q[3] = -1e300;
      for (int v = 0; v < nv; v++) q[3] = fmax(q[3], sign * shape->vertices[3 * v + axis]);
      q[3] += 0.1 * radius;
      box.plane[box.count] = p.num_planes++;
      box.behind[box.count++] = 1;
    }
  for (int v = 0; ok && v < nv; v++) partition_point(&p, shape->vertices + 3 * v);
  int all[POLY_CLIP_MAX_FACES];
  for (int t = 0; t < nt; t++) all[t] = t;
  if (ok) partition_split(&p, &box, all, nt);
  ok = ok && !p.failed && p.num_pieces > 1;
  /* The check: the sub-faces cover the surface and enclose the shape's volume. */
  double area = 0.0;
  for (int t = 0; ok && t < nt; t++) {
    double corners[9];
    for (int c = 0; c < 3; c++)
      for (int m = 0; m < 3; m++) corners[3 * c + m] = shape->vertices[3 * shape->triangles[3 * t + c] + m];
    area += partition_polygon_area(corners, 3);
  }
  ok = ok && fabs(p.area - area) <= 1e-9 * area && fabs(p.volume - shape->volume) <= 1e-9 * shape->volume;
  /* Only the planes some piece has, renumbered. */
  int *renumber = ok ? (int *)malloc(sizeof(int) * (size_t)p.num_planes) : NULL;
  int num_used = 0;
  ok = ok && renumber;
  for (int k = 0; ok && k < p.num_planes; k++) renumber[k] = -1;
  for (int i = 0; ok && i < p.num_pieces; i++)
    for (int k = 0; k < p.piece_num_planes[i]; k++)
      if (renumber[p.piece_planes[i][k]] < 0) renumber[p.piece_planes[i][k]] = num_used++;
  ok = ok && num_used <= POLY_CLIP_SHAPE_PLANES;
  double *planes = ok ? (double *)malloc(sizeof(double) * 4 * (size_t)num_used) : NULL;
  poly_clip_words *front = ok ? (poly_clip_words *)calloc((size_t)p.num_pieces, sizeof(poly_clip_words)) : NULL;
  poly_clip_words *back = ok ? (poly_clip_words *)calloc((size_t)p.num_pieces, sizeof(poly_clip_words)) : NULL;
  double *points = ok ? (double *)malloc(sizeof(double) * 3 * (size_t)p.num_points) : NULL;
  int *point_start = ok ? (int *)malloc(sizeof(int) * (size_t)(p.num_pieces + 1)) : NULL;
  int *face_start = ok ? (int *)malloc(sizeof(int) * (size_t)(p.num_pieces + 1)) : NULL;
  int *faces = ok ? (int *)malloc(sizeof(int) * (size_t)p.num_faces) : NULL;
  ok = ok && planes && front && back && points && point_start && face_start && faces;
  if (ok) {
    for (int k = 0; k < p.num_planes; k++)
      if (renumber[k] >= 0)
        for (int m = 0; m < 4; m++) planes[4 * renumber[k] + m] = p.planes[4 * k + m];
    for (int i = 0; i < p.num_pieces; i++)
      for (int k = 0; k < p.piece_num_planes[i]; k++) {
        int index = renumber[p.piece_planes[i][k]];
        poly_clip_words *mask = p.piece_behind[i][k] ? front + i : back + i;
        if (index < 64) mask->low |= 1ull << index;
        else mask->high |= 1ull << (index - 64);
      }
    for (int m = 0; m < 3 * p.num_points; m++) points[m] = p.points[m];
    for (int i = 0; i <= p.num_pieces; i++) point_start[i] = p.piece_point_start[i], face_start[i] = p.piece_face_start[i];
    for (int f = 0; f < p.num_faces; f++) faces[f] = f;
    p.face_loop_start[p.num_faces] = p.faces_loop_used;
    shape->clip_planes = planes;
    shape->num_clip_planes = num_used;
    shape->clip_loop_start = p.face_loop_start;
    shape->clip_loop = p.faces_loop;
    shape->clip_face_triangle = p.face_triangle;
    shape->num_clip_faces = p.num_faces;
    shape->clip_piece_front = front;
    shape->clip_piece_back = back;
    shape->clip_piece_point_start = point_start;
    shape->clip_piece_points = p.piece_points;
    shape->clip_piece_face_start = face_start;
    shape->clip_piece_faces = faces;
    shape->num_clip_pieces = p.num_pieces;
    shape->clip_vertices = points;
    shape->num_clip_vertices = p.num_points;
    p.face_loop_start = p.faces_loop = p.face_triangle = p.piece_points = NULL;
  } else {
    free(planes);
    free(front);
    free(back);
    free(points);
    free(point_start);
    free(face_start);
    free(faces);
  }
  free(renumber);
  free(p.planes);
  free(p.triangle_plane);
  free(p.points);
  free(p.piece_points);
  free(p.faces_loop);
  free(p.face_loop_start);
  free(p.face_triangle);
  return ok;
}
