/* Convex shapes and their faces, found once when a shape is built, for the
 * convex path of the overlap (poly_overlap_convex_impl.h), the supporting
 * triangles of any shape (the separation test of overlap_pass), and the
 * convex pieces of shapes that are not convex, for the clipping path
 * (poly_clip.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "poly_clip_polygon.h"
#include "poly_extremes.h"
#include "poly_shape.h"
#include "poly_convex_partition_impl.h"

static int face_root(int *parent, int t)
{
  while (parent[t] != t) {
    parent[t] = parent[parent[t]];
    t = parent[t];
  }
  return t;
}

/* Is triangle u's plane the plane of triangle t, to within `tolerance`:
 * normals within 1e-12 of each other and u's corners on t's plane? */
static int same_plane(const poly_shape *shape, int t, int u, double tolerance)
{
  const double *n = shape->face_normals + 3 * t, *m = shape->face_normals + 3 * u;
  if (n[0] * m[0] + n[1] * m[1] + n[2] * m[2] < 1.0 - 1e-12) return 0;
  const double *origin = shape->vertices + 3 * shape->triangles[3 * t];
  for (int c = 0; c < 3; c++) {
    const double *x = shape->vertices + 3 * shape->triangles[3 * u + c];
    double height = n[0] * (x[0] - origin[0]) + n[1] * (x[1] - origin[1]) + n[2] * (x[2] - origin[2]);
    if (fabs(height) > tolerance) return 0;
  }
  return 1;
}

/* Does triangle t's plane support the shape: every vertex on or behind it, to `tolerance`? */
static int supports(const poly_shape *shape, int t, double tolerance)
{
  const double *n = shape->face_normals + 3 * t, *origin = shape->vertices + 3 * shape->triangles[3 * t];
  for (int v = 0; v < shape->num_vertices; v++) {
    const double *x = shape->vertices + 3 * v;
    if (n[0] * (x[0] - origin[0]) + n[1] * (x[1] - origin[1]) + n[2] * (x[2] - origin[2]) > tolerance) return 0;
  }
  return 1;
}

/* The faces as polygons for the clipping path (poly_clip.h): each face's boundary edges, those whose other
 * triangle is of another face, chained in the face's own counter-clockwise order. Leaves the shape without
 * them (not an error) when it has too many faces, vertices or corners per face. */
static poly_status find_clip_faces(poly_shape *shape)
{
  const int nt = shape->num_triangles, nv = shape->num_vertices, ne = shape->num_edges;
  int num_faces = 0;
  for (int t = 0; t < nt; t++) num_faces += shape->face_of[t] == t;
  if (num_faces > POLY_CLIP_MAX_PLANES || nv > POLY_CLIP_MAX_VERTICES) return POLY_OK;
  int *next = (int *)malloc(sizeof(int) * (size_t)nv);
  double *planes = (double *)malloc(sizeof(double) * 4 * (size_t)num_faces);
  int *start = (int *)malloc(sizeof(int) * (size_t)(num_faces + 1)), *loop = (int *)malloc(sizeof(int) * 2 * (size_t)ne);
  int *triangle = (int *)malloc(sizeof(int) * (size_t)num_faces);
  poly_status status = POLY_OK;
  int complete = next && planes && start && loop && triangle;
  if (!complete) status = POLY_ERROR_MEMORY;
  int used = 0;
  for (int f = 0, t = 0; complete && f < num_faces; f++, t++) {
    while (shape->face_of[t] != t) t++;
    triangle[f] = t;
    const double *n = shape->face_normals + 3 * t, *x = shape->vertices + 3 * shape->triangles[3 * t];
    for (int k = 0; k < 3; k++) planes[4 * f + k] = n[k];
    planes[4 * f + 3] = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
    /* Boundary edges of face f, directed as its triangles run them: edge (a, b) runs a->b in its first
     * triangle and b->a in its second. */
    for (int v = 0; v < nv; v++) next[v] = -1;
    int first = -1, count = 0;
    for (int e = 0; e < ne; e++) {
      int t0 = shape->edge_triangles[2 * e], t1 = shape->edge_triangles[2 * e + 1];
      if (shape->face_of[t0] == shape->face_of[t1]) continue;
      int a = shape->edges[2 * e], b = shape->edges[2 * e + 1];
      if (shape->face_of[t0] == t) { next[a] = b; first = a; count++; }
      else if (shape->face_of[t1] == t) { next[b] = a; first = b; count++; }
    }
    start[f] = used;
    int v = first, steps = 0;
    while (v >= 0 && steps < count && count <= POLY_CLIP_MAX_LOOP) {
      loop[used + steps++] = v;
      v = next[v];
      if (v == first) break;
    }
    if (count > POLY_CLIP_MAX_LOOP || steps != count || v != first) complete = 0;  /* not one simple loop */
    used += steps;
  }
  if (complete) {
    start[num_faces] = used;
    shape->clip_planes = planes;
    shape->clip_loop_start = start;
    shape->clip_loop = loop;
    shape->clip_face_triangle = triangle;
    shape->num_clip_faces = num_faces;
  } else {
    free(planes);
    free(start);
    free(loop);
    free(triangle);
  }
  free(next);
  return status;
}

/* The piece of one convex shape for the clipping path: the shape, behind its faces' planes. */
static poly_status single_piece(poly_shape *shape)
{
  const int nf = shape->num_clip_faces, nv = shape->num_vertices;
  shape->clip_piece_front = (poly_clip_words *)malloc(sizeof(poly_clip_words));
  shape->clip_piece_back = (poly_clip_words *)malloc(sizeof(poly_clip_words));
  shape->clip_piece_point_start = (int *)malloc(sizeof(int) * 2);
  shape->clip_piece_points = (int *)malloc(sizeof(int) * (size_t)nv);
  shape->clip_piece_face_start = (int *)malloc(sizeof(int) * 2);
  shape->clip_piece_faces = (int *)malloc(sizeof(int) * (size_t)nf);
  if (!shape->clip_piece_front || !shape->clip_piece_back || !shape->clip_piece_point_start ||
      !shape->clip_piece_points || !shape->clip_piece_face_start || !shape->clip_piece_faces)
    return POLY_ERROR_MEMORY;
  shape->clip_piece_front[0].low = (1ull << nf) - 1ull;
  shape->clip_piece_front[0].high = 0ull;
  shape->clip_piece_back[0].low = shape->clip_piece_back[0].high = 0ull;
  shape->clip_piece_point_start[0] = shape->clip_piece_face_start[0] = 0;
  shape->clip_piece_point_start[1] = nv;
  shape->clip_piece_face_start[1] = nf;
  for (int v = 0; v < nv; v++) shape->clip_piece_points[v] = v;
  for (int f = 0; f < nf; f++) shape->clip_piece_faces[f] = f;
  shape->num_clip_planes = nf;
  shape->num_clip_pieces = 1;
  return POLY_OK;
}

static int add_plane(double *planes, int count, const double *n, double offset)
{
  for (int k = 0; k < count; k++) {
    const double *q = planes + 4 * k;
    if (n[0] * q[0] + n[1] * q[1] + n[2] * q[2] > 1.0 - 1e-14 && fabs(offset - q[3]) < 1e-14 * (1.0 + fabs(offset)))
      return count;  /* the same plane twice (coplanar triangles, or boundary edges in line with the apex) */
  }
  if (count == POLY_CLIP_MAX_PLANES) return count + 1;
  double *q = planes + 4 * count;
  q[0] = n[0], q[1] = n[1], q[2] = n[2], q[3] = offset;
  return count + 1;
}

/* The cone from the origin (the centre of mass) over the triangles with in_patch set: its planes into
 * `planes` (the triangles' planes and one through the origin per boundary edge of the patch), their count
 * returned, or 0 when the cone is not convex to `tolerance` or needs more than POLY_CLIP_MAX_PLANES planes. */
static int cone_planes(const poly_shape *shape, const unsigned char *in_patch, const int *neighbour,
                       double tolerance, double *planes)
{
  const int nt = shape->num_triangles;
  const double *x = shape->vertices;
  int count = 0;
  for (int t = 0; t < nt && count <= POLY_CLIP_MAX_PLANES; t++) {
    if (!in_patch[t]) continue;
    const double *n = shape->face_normals + 3 * t, *corner = x + 3 * shape->triangles[3 * t];
    count = add_plane(planes, count, n, n[0] * corner[0] + n[1] * corner[1] + n[2] * corner[2]);
    for (int c = 0; c < 3 && count <= POLY_CLIP_MAX_PLANES; c++) {
      if (in_patch[neighbour[3 * t + c]]) continue;
      /* Boundary edge u -> v of triangle t: the side (origin, v, u), outward. */
      const double *u = x + 3 * shape->triangles[3 * t + c], *v = x + 3 * shape->triangles[3 * t + (c + 1) % 3];
      double side[3] = {v[1] * u[2] - v[2] * u[1], v[2] * u[0] - v[0] * u[2], v[0] * u[1] - v[1] * u[0]};
      double length = sqrt(side[0] * side[0] + side[1] * side[1] + side[2] * side[2]);
      if (!(length > 1e-9 * shape->bounding_radius * shape->bounding_radius)) return 0;
      for (int k = 0; k < 3; k++) side[k] /= length;
      count = add_plane(planes, count, side, 0.0);
    }
  }
  if (count > POLY_CLIP_MAX_PLANES) return 0;
  /* Convex: the apex and every corner of the patch on or behind every plane. */
  for (int k = 0; k < count; k++) {
    const double *q = planes + 4 * k;
    if (-q[3] > tolerance) return 0;
    for (int t = 0; t < nt; t++) {
      if (!in_patch[t]) continue;
      for (int c = 0; c < 3; c++) {
        const double *p = x + 3 * shape->triangles[3 * t + c];
        if (q[0] * p[0] + q[1] * p[1] + q[2] * p[2] - q[3] > tolerance) return 0;
      }
    }
  }
  return count;
}

/* Index of the plane (n, offset) in the shape's `planes` (count of them), added when new; its side through
 * `opposite` (1 when the stored plane faces the other way); -1 when POLY_CLIP_SHAPE_PLANES are taken. */
static int shape_plane(double *planes, int *count, const double *plane, int *opposite)
{
  for (int k = 0; k < *count; k++) {
    const double *q = planes + 4 * k;
    double cosine = plane[0] * q[0] + plane[1] * q[1] + plane[2] * q[2];
    if (cosine > 1.0 - 1e-14 && fabs(plane[3] - q[3]) < 1e-14 * (1.0 + fabs(q[3]))) {
      *opposite = 0;
      return k;
    }
    if (cosine < -1.0 + 1e-14 && fabs(plane[3] + q[3]) < 1e-14 * (1.0 + fabs(q[3]))) {
      *opposite = 1;
      return k;
    }
  }
  if (*count == POLY_CLIP_SHAPE_PLANES) return -1;
  for (int c = 0; c < 4; c++) planes[4 * *count + c] = plane[c];
  *opposite = 0;
  return (*count)++;
}

/* Per plane of the pieces, a supporting triangle on it (its index in shape->support), for the pieces' separation
 * test, and (with `face_planes`) per face its plane (either way round), so that a face is not clipped by a piece
 * wholly on one side of it (poly_clip_pieces_overlap). The cones go without the latter: their pieces have one face
 * each, few tests skip a clipping, and the GPU warp kernel ran rock_40's cones 6 % slower with them
 * (doc/benchmarks.md). */
static poly_status find_plane_support(poly_shape *shape, int face_planes)
{
  const int np = shape->num_clip_planes, nf = shape->num_clip_faces;
  const double tolerance = 1e-12 * shape->bounding_radius;
  shape->clip_plane_support = (int *)malloc(sizeof(int) * (size_t)(np > 0 ? np : 1));
  shape->clip_face_plane = (int *)malloc(sizeof(int) * (size_t)(nf > 0 ? nf : 1));
  if (!shape->clip_plane_support || !shape->clip_face_plane) return POLY_ERROR_MEMORY;
  int all_found = face_planes;
  for (int f = 0; f < nf && face_planes; f++) {
    const int t = shape->clip_face_triangle[f];
    const double *n = shape->face_normals + 3 * t, *x = shape->vertices + 3 * shape->triangles[3 * t];
    const double offset = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
    shape->clip_face_plane[f] = -1;
    for (int k = 0; k < np && shape->clip_face_plane[f] < 0; k++) {
      const double *q = shape->clip_planes + 4 * k, cosine = n[0] * q[0] + n[1] * q[1] + n[2] * q[2];
      if ((cosine > 1.0 - 1e-12 && fabs(offset - q[3]) <= tolerance) ||
          (cosine < -1.0 + 1e-12 && fabs(offset + q[3]) <= tolerance))
        shape->clip_face_plane[f] = k;
    }
    all_found &= shape->clip_face_plane[f] >= 0;
  }
  if (!all_found) {  /* a face off every plane of the pieces: none is skipped */
    free(shape->clip_face_plane);
    shape->clip_face_plane = NULL;
  }
  for (int k = 0; k < np; k++) {
    const double *q = shape->clip_planes + 4 * k;
    shape->clip_plane_support[k] = -1;
    for (int m = 0; m < shape->num_support && shape->clip_plane_support[k] < 0; m++) {
      const int t = shape->support[m];
      const double *n = shape->face_normals + 3 * t, *x = shape->vertices + 3 * shape->triangles[3 * t];
      if (n[0] * q[0] + n[1] * q[1] + n[2] * q[2] > 1.0 - 1e-12 &&
          fabs(n[0] * x[0] + n[1] * x[1] + n[2] * x[2] - q[3]) <= tolerance)
        shape->clip_plane_support[k] = m;
    }
    if (shape->clip_plane_support[k] < 0) continue;
    if (k < 64) shape->clip_support_planes.low |= 1ull << k;
    else shape->clip_support_planes.high |= 1ull << (k - 64);
  }
  return POLY_OK;
}

/* Convex pieces of a shape that is not convex: first the partition by the shape's own face planes
 * (poly_convex_partition_impl.h: fewer and fatter pieces, no planes but the faces'; Schoenhardt 2.2 us a pair on a
 * core against 3.0 us by the cones below). When that needs more than the path holds (rock_40, rock_70: a piece of
 * more than POLY_CLIP_MAX_PIECE_PLANES planes), and every triangle's plane has the centre of mass (the origin)
 * behind it by a millionth of the size, the cones from it over the triangles tile the shape; neighbouring
 * cones are merged, greedily, while their union stays convex with at most POLY_CLIP_MAX_PLANES planes. The
 * shape's faces for the clipping path are then its triangles. Leaves the shape without pieces (not an error)
 * when neither gives pieces the path takes. POLY_PIECES_BY_CONES=1 in the environment skips the partition (a
 * benchmark's before and after in one build, doc/benchmarks.md). */
static poly_status find_pieces(poly_shape *shape)
{
  const int nt = shape->num_triangles, nv = shape->num_vertices, ne = shape->num_edges;
  const double radius = shape->bounding_radius, tolerance = 1e-12 * radius;
  const char *by_cones = getenv("POLY_PIECES_BY_CONES");  /* 0 or 1 (poly_shape_build checks it) */
  if (!(by_cones && strcmp(by_cones, "1") == 0) && partition_pieces(shape, POLY_CLIP_PIECE_PLANES))
    return find_plane_support(shape, 1);
  if (nt > POLY_CLIP_MAX_FACES || nv >= POLY_CLIP_MAX_VERTICES) return POLY_OK;
  for (int t = 0; t < nt; t++) {
    const double *n = shape->face_normals + 3 * t, *corner = shape->vertices + 3 * shape->triangles[3 * t];
    if (n[0] * corner[0] + n[1] * corner[1] + n[2] * corner[2] < 1e-6 * radius) return POLY_OK;
  }
  double scratch[4 * POLY_CLIP_MAX_PLANES];
  int *neighbour = (int *)malloc(sizeof(int) * 3 * (size_t)nt), *piece_of = (int *)malloc(sizeof(int) * (size_t)nt);
  unsigned char *in_patch = (unsigned char *)calloc((size_t)nt, 1), *seen = (unsigned char *)calloc((size_t)nv, 1);
  double *planes = (double *)malloc(sizeof(double) * 4 * POLY_CLIP_SHAPE_PLANES);
  poly_clip_words *front = (poly_clip_words *)calloc(POLY_CLIP_MAX_PIECES, sizeof(poly_clip_words));
  poly_clip_words *back = (poly_clip_words *)calloc(POLY_CLIP_MAX_PIECES, sizeof(poly_clip_words));
  int *point_start = (int *)malloc(sizeof(int) * (POLY_CLIP_MAX_PIECES + 1));
  int *points = (int *)malloc(sizeof(int) * (size_t)(3 * nt + POLY_CLIP_MAX_PIECES));
  int *face_start = (int *)malloc(sizeof(int) * (POLY_CLIP_MAX_PIECES + 1)), *faces = (int *)malloc(sizeof(int) * (size_t)nt);
  int *loop_start = (int *)malloc(sizeof(int) * ((size_t)nt + 1)), *loop = (int *)malloc(sizeof(int) * 3 * (size_t)nt);
  int *triangle = (int *)malloc(sizeof(int) * (size_t)nt);
  poly_status status = POLY_OK;
  int num_pieces = 0, num_planes = 0, ok = 1;
  if (!neighbour || !piece_of || !in_patch || !seen || !planes || !front || !back || !point_start || !points ||
      !face_start || !faces || !loop_start || !loop || !triangle) {
    status = POLY_ERROR_MEMORY;
    ok = 0;
  }
  /* Across corner c's edge (c -> c + 1) of each triangle, its neighbour. */
  for (int e = 0; ok && e < ne; e++) {
    int a = shape->edges[2 * e], b = shape->edges[2 * e + 1];
    int t0 = shape->edge_triangles[2 * e], t1 = shape->edge_triangles[2 * e + 1];
    for (int side = 0; side < 2; side++) {
      int t = side ? t1 : t0, other = side ? t0 : t1;
      for (int c = 0; c < 3; c++) {
        int u = shape->triangles[3 * t + c], v = shape->triangles[3 * t + (c + 1) % 3];
        if ((u == a && v == b) || (u == b && v == a)) neighbour[3 * t + c] = other;
      }
    }
  }
  for (int t = 0; ok && t < nt; t++) piece_of[t] = -1;
  point_start[0] = face_start[0] = 0;
  for (int seed = 0; ok && seed < nt; seed++) {
    if (piece_of[seed] >= 0) continue;
    if (num_pieces == POLY_CLIP_MAX_PIECES) {
      ok = 0;
      break;
    }
    for (int t = 0; t < nt; t++) in_patch[t] = 0;
    in_patch[seed] = 1;
    piece_of[seed] = num_pieces;
    if (!cone_planes(shape, in_patch, neighbour, tolerance, scratch)) {
      ok = 0;
      break;
    }
    for (int grew = 1; grew;) {
      grew = 0;
      for (int t = 0; t < nt; t++) {
        if (!in_patch[t]) continue;
        for (int c = 0; c < 3; c++) {
          int u = neighbour[3 * t + c];
          if (piece_of[u] >= 0) continue;
          in_patch[u] = 1;
          if (cone_planes(shape, in_patch, neighbour, tolerance, scratch)) {
            piece_of[u] = num_pieces;
            grew = 1;
          } else {
            in_patch[u] = 0;
          }
        }
      }
    }
    /* The piece's planes among the shape's, its corners (the apex first) and its faces. */
    int count = cone_planes(shape, in_patch, neighbour, tolerance, scratch);
    for (int k = 0; k < count && ok; k++) {
      int opposite, index = shape_plane(planes, &num_planes, scratch + 4 * k, &opposite);
      if (index < 0) {
        ok = 0;
      } else {
        poly_clip_words *mask = opposite ? back + num_pieces : front + num_pieces;
        if (index < 64) mask->low |= 1ull << index;
        else mask->high |= 1ull << (index - 64);
      }
    }
    int num_points = point_start[num_pieces], num_faces = face_start[num_pieces];
    points[num_points++] = nv;
    for (int v = 0; v < nv; v++) seen[v] = 0;
    for (int t = 0; t < nt; t++) {
      if (!in_patch[t]) continue;
      faces[num_faces++] = t;
      for (int c = 0; c < 3; c++) {
        int v = shape->triangles[3 * t + c];
        if (!seen[v]) points[num_points++] = v;
        seen[v] = 1;
      }
    }
    point_start[num_pieces + 1] = num_points;
    face_start[num_pieces + 1] = num_faces;
    num_pieces++;
  }
  if (ok && num_pieces > 1) {
    for (int t = 0; t < nt; t++) {
      loop_start[t] = 3 * t;
      for (int c = 0; c < 3; c++) loop[3 * t + c] = shape->triangles[3 * t + c];
      triangle[t] = t;
    }
    loop_start[nt] = 3 * nt;
    shape->clip_planes = planes;
    shape->num_clip_planes = num_planes;
    shape->clip_loop_start = loop_start;
    shape->clip_loop = loop;
    shape->clip_face_triangle = triangle;
    shape->num_clip_faces = nt;
    shape->clip_piece_front = front;
    shape->clip_piece_back = back;
    shape->clip_piece_point_start = point_start;
    shape->clip_piece_points = points;
    shape->clip_piece_face_start = face_start;
    shape->clip_piece_faces = faces;
    shape->num_clip_pieces = num_pieces;
    status = find_plane_support(shape, 0);
  } else {
    free(planes);
    free(loop_start);
    free(loop);
    free(triangle);
    free(front);
    free(back);
    free(point_start);
    free(points);
    free(face_start);
    free(faces);
  }
  free(neighbour);
  free(piece_of);
  free(in_patch);
  free(seen);
  return status;
}

static void forget_faces(poly_shape *shape);

int poly_shape_wall_pieces(const poly_shape *shape, poly_shape *wall)
{
  memset(wall, 0, sizeof *wall);
  /* Convex shapes and those with pieces by the partition have theirs already; cones, or none, may gain. */
  if (shape->face_of || (shape->num_clip_pieces > 1 && shape->clip_vertices) || shape->num_support == 0) return 0;
  *wall = *shape;  /* the geometry borrowed; what poly_shape_find_faces makes, the wall's own */
  forget_faces(wall);
  wall->support = (int *)malloc(sizeof(int) * (size_t)shape->num_support);
  if (!wall->support) {
    memset(wall, 0, sizeof *wall);
    return 0;
  }
  memcpy(wall->support, shape->support, sizeof(int) * (size_t)shape->num_support);
  wall->num_support = shape->num_support;
  if (!partition_pieces(wall, POLY_CLIP_WALL_PIECE_PLANES) || find_plane_support(wall, 1) != POLY_OK ||
      wall->num_clip_planes > POLY_CLIP_MAX_SHAPE_PLANES) {
    poly_shape_free_wall_pieces(wall);
    return 0;
  }
  wall->clip_many_faces = 1;
  return 1;
}

void poly_shape_free_wall_pieces(poly_shape *wall)
{
  poly_shape_free_faces(wall);  /* the geometry is the shape's */
  memset(wall, 0, sizeof *wall);
}

void poly_shape_free_faces(poly_shape *shape)
{
  free(shape->face_of);
  free(shape->ridges);
  free(shape->support);
  free(shape->clip_planes);
  free(shape->clip_loop_start);
  free(shape->clip_loop);
  free(shape->clip_face_triangle);
  free(shape->clip_piece_front);
  free(shape->clip_piece_back);
  free(shape->clip_piece_point_start);
  free(shape->clip_piece_points);
  free(shape->clip_piece_face_start);
  free(shape->clip_piece_faces);
  free(shape->clip_vertices);
  free(shape->clip_plane_support);
  free(shape->clip_face_plane);
  free(shape->extreme_start);
  free(shape->extreme_vertices);
  forget_faces(shape);
}

/* Leaves `shape` without what poly_shape_find_faces makes, freeing nothing. */
static void forget_faces(poly_shape *shape)
{
  shape->clip_plane_support = NULL;
  shape->clip_face_plane = NULL;
  shape->clip_support_planes.low = shape->clip_support_planes.high = 0ull;
  shape->clip_vertices = NULL;
  shape->num_clip_vertices = 0;
  shape->face_of = shape->ridges = shape->support = NULL;
  shape->clip_planes = NULL;
  shape->clip_loop_start = shape->clip_loop = shape->clip_face_triangle = NULL;
  shape->clip_piece_front = shape->clip_piece_back = NULL;
  shape->clip_piece_point_start = shape->clip_piece_points = shape->clip_piece_face_start = shape->clip_piece_faces = NULL;
  shape->num_ridges = shape->num_support = shape->num_clip_faces = shape->num_clip_planes = shape->num_clip_pieces = 0;
  shape->clip_many_faces = 0;
  shape->extreme_start = shape->extreme_vertices = NULL;
}

poly_status poly_shape_find_faces(poly_shape *shape)
{
  poly_shape_free_faces(shape);
  const int nt = shape->num_triangles, nv = shape->num_vertices, ne = shape->num_edges;
  /* Convex: every vertex on or behind every face's plane, to 1e-12 of the size (a shape that much from
   * convex differs from the intersection of its faces' half-spaces by less than the rounding of the
   * particles' poses). */
  const double tolerance = 1e-12 * shape->bounding_radius;
  if (nv > POLY_EXTREME_MIN_VERTICES) {
    const int entries = poly_extreme_table(shape->vertices, nv, shape->bounding_radius, NULL, NULL);
    shape->extreme_start = (int *)malloc(sizeof(int) * (POLY_EXTREME_CELLS + 1));
    shape->extreme_vertices = (int *)malloc(sizeof(int) * (size_t)(entries > 0 ? entries : 1));
    if (!shape->extreme_start || !shape->extreme_vertices) return POLY_ERROR_MEMORY;
    poly_extreme_table(shape->vertices, nv, shape->bounding_radius, shape->extreme_start, shape->extreme_vertices);
  }
  shape->support = (int *)malloc(sizeof(int) * (size_t)(nt > 0 ? nt : 1));
  if (!shape->support) return POLY_ERROR_MEMORY;
  for (int t = 0; t < nt; t++)
    if (supports(shape, t, tolerance)) shape->support[shape->num_support++] = t;
  if (shape->num_support < nt) return find_pieces(shape);
  int *parent = (int *)malloc(sizeof(int) * (size_t)nt), *on_ridge = (int *)calloc((size_t)nv, sizeof(int));
  int *face_of = (int *)malloc(sizeof(int) * (size_t)nt);
  int *ridges = (int *)malloc(sizeof(int) * (size_t)(ne > 0 ? ne : 1));
  if (!parent || !on_ridge || !face_of || !ridges) {
    free(parent);
    free(on_ridge);
    free(face_of);
    free(ridges);
    return POLY_ERROR_MEMORY;
  }
  for (int t = 0; t < nt; t++) parent[t] = t;
  for (int e = 0; e < ne; e++) {
    int t = shape->edge_triangles[2 * e], u = shape->edge_triangles[2 * e + 1];
    if (!same_plane(shape, t, u, tolerance) || !same_plane(shape, u, t, tolerance)) continue;
    int root_t = face_root(parent, t), root_u = face_root(parent, u);
    /* The root is the face's lowest triangle: its representative. */
    if (root_t < root_u) parent[root_u] = root_t;
    else parent[root_t] = root_u;
  }
  for (int t = 0; t < nt; t++) face_of[t] = face_root(parent, t);
  int num_ridges = 0;
  for (int e = 0; e < ne; e++) {
    if (face_of[shape->edge_triangles[2 * e]] == face_of[shape->edge_triangles[2 * e + 1]]) continue;
    ridges[num_ridges++] = e;
    on_ridge[shape->edges[2 * e]] = on_ridge[shape->edges[2 * e + 1]] = 1;
  }
  /* A vertex inside a flat face (on no ridge) would be a node the convex path does not see: such shapes
   * keep the general path. */
  int all_on_ridges = 1;
  for (int v = 0; v < nv; v++) all_on_ridges &= on_ridge[v];
  free(parent);
  free(on_ridge);
  if (!all_on_ridges) {
    free(face_of);
    free(ridges);
    return POLY_OK;
  }
  shape->face_of = face_of;
  shape->ridges = ridges;
  shape->num_ridges = num_ridges;
  poly_status status = find_clip_faces(shape);
  if (status != POLY_OK || shape->num_clip_faces == 0) return status;
  return single_piece(shape);
}
