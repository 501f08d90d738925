/* Convex shapes and their faces, found once when a shape is built, for the
 * convex path of the overlap (poly_overlap_convex_impl.h), and the supporting
 * triangles of any shape (the separation test of overlap_pass). */
#include <math.h>
#include <stdlib.h>

#include "poly_clip_limits.h"
#include "poly_shape.h"

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
  if (num_faces > POLY_CLIP_MAX_FACES || nv > POLY_CLIP_MAX_VERTICES) return POLY_OK;
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

poly_status poly_shape_find_faces(poly_shape *shape)
{
  free(shape->face_of);
  free(shape->ridges);
  free(shape->support);
  free(shape->clip_planes);
  free(shape->clip_loop_start);
  free(shape->clip_loop);
  free(shape->clip_face_triangle);
  shape->face_of = shape->ridges = shape->support = NULL;
  shape->clip_planes = NULL;
  shape->clip_loop_start = shape->clip_loop = shape->clip_face_triangle = NULL;
  shape->num_ridges = shape->num_support = shape->num_clip_faces = 0;
  const int nt = shape->num_triangles, nv = shape->num_vertices, ne = shape->num_edges;
  /* Convex: every vertex on or behind every face's plane, to 1e-12 of the size (a shape that much from
   * convex differs from the intersection of its faces' half-spaces by less than the rounding of the
   * particles' poses). */
  const double tolerance = 1e-12 * shape->bounding_radius;
  shape->support = (int *)malloc(sizeof(int) * (size_t)(nt > 0 ? nt : 1));
  if (!shape->support) return POLY_ERROR_MEMORY;
  for (int t = 0; t < nt; t++)
    if (supports(shape, t, tolerance)) shape->support[shape->num_support++] = t;
  if (shape->num_support < nt) return POLY_OK;
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
  return find_clip_faces(shape);
}
