/* Shape templates: welding, validation, exact mass properties, body frame.
 *
 * The file readers live in poly_mesh_read.c; everything here works on a
 * poly_mesh, whatever format it came from.
 */
#include "poly_shape.h"
#include "poly_message.h"
/* Exact orientation signs; poly_rigid.h, which it includes, is C99/C++ but not pedantic C11. */
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include "poly_exact.h"
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* Below this fraction of size^2 a triangle's doubled area is rounding noise. */
#define POLY_DEGENERATE_AREA_RELATIVE 1e-14
/* Below this fraction of size^3 the enclosed volume is rounding noise. */
#define POLY_ZERO_VOLUME_RELATIVE 1e-12

poly_status poly_fail(char *message, size_t message_size, poly_status status, const char *format, ...)
{
  if (message && message_size > 0) {
    va_list args;
    va_start(args, format);
    vsnprintf(message, message_size, format, args);
    va_end(args);
  }
  return status;
}

static void poly_sub3(const double *a, const double *b, double *out)
{
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}

static void poly_cross3(const double *a, const double *b, double *out)
{
  double x = a[1] * b[2] - a[2] * b[1];
  double y = a[2] * b[0] - a[0] * b[2];
  double z = a[0] * b[1] - a[1] * b[0];
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

static double poly_dot3(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double poly_bounding_box_diagonal(const double *vertices, int num_vertices)
{
  if (num_vertices <= 0) return 0.0;
  double lo[3] = {vertices[0], vertices[1], vertices[2]};
  double hi[3] = {vertices[0], vertices[1], vertices[2]};
  for (int i = 1; i < num_vertices; i++)
    for (int k = 0; k < 3; k++) {
      double x = vertices[3 * i + k];
      lo[k] = x < lo[k] ? x : lo[k];
      hi[k] = x > hi[k] ? x : hi[k];
    }
  double d[3];
  poly_sub3(hi, lo, d);
  return sqrt(poly_dot3(d, d));
}

/* ------------------------------------------------------------------ welding */

typedef struct poly_weld_cell {
  int64_t key[3];
  int head;  /* first representative (new index) in this cell, -1 when the slot is free */
} poly_weld_cell;

static uint64_t poly_weld_hash(const int64_t *key)
{
  uint64_t h = (uint64_t)key[0] * 0x9E3779B97F4A7C15ull;
  h ^= (uint64_t)key[1] * 0xC2B2AE3D27D4EB4Full + (h >> 29);
  h ^= (uint64_t)key[2] * 0x165667B19E3779F9ull + (h >> 31);
  return h ^ (h >> 32);
}

static poly_weld_cell *poly_weld_find(poly_weld_cell *cells, uint64_t mask, const int64_t *key)
{
  for (uint64_t slot = poly_weld_hash(key) & mask;; slot = (slot + 1) & mask) {
    poly_weld_cell *cell = &cells[slot];
    if (cell->head < 0 || (cell->key[0] == key[0] && cell->key[1] == key[1] && cell->key[2] == key[2]))
      return cell;
  }
}

/* Hash grid with cells of the tolerance's size: a partner within tolerance is
 * always in one of the 27 cells around a vertex, so the work stays linear.
 * A vertex joins the earliest representative within tolerance, so the result
 * depends only on vertex order. Returns -1 when memory runs out. */
int poly_mesh_weld(poly_mesh *mesh, double relative_tolerance)
{
  if (!mesh || mesh->num_vertices <= 1 || !mesh->vertices) return 0;
  int n = mesh->num_vertices;
  double *v = mesh->vertices;
  double lo[3] = {v[0], v[1], v[2]};
  for (int i = 1; i < n; i++)
    for (int k = 0; k < 3; k++) lo[k] = v[3 * i + k] < lo[k] ? v[3 * i + k] : lo[k];
  double diagonal = poly_bounding_box_diagonal(v, n);
  double tolerance = relative_tolerance > 0.0 ? relative_tolerance * diagonal : 0.0;
  double cell_size = tolerance > 0.0 ? tolerance : (diagonal > 0.0 ? diagonal * 1e-6 : 1.0);

  uint64_t table_size = 16;
  while (table_size < 2 * (uint64_t)n) table_size *= 2;
  poly_weld_cell *cells = (poly_weld_cell *)malloc(sizeof(poly_weld_cell) * table_size);
  int *next = (int *)malloc(sizeof(int) * (size_t)n);
  int *remap = (int *)malloc(sizeof(int) * (size_t)n);
  if (!cells || !next || !remap) {
    free(cells);
    free(next);
    free(remap);
    return -1;
  }
  for (uint64_t s = 0; s < table_size; s++) cells[s].head = -1;

  int kept = 0;
  for (int i = 0; i < n; i++) {
    double p[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    int64_t key[3];
    for (int k = 0; k < 3; k++) {
      double c = floor((p[k] - lo[k]) / cell_size);
      key[k] = c < 4e15 ? (int64_t)c : (int64_t)4e15;  /* clamping only costs speed */
    }
    int match = -1;
    for (int dx = -1; dx <= 1; dx++)
      for (int dy = -1; dy <= 1; dy++)
        for (int dz = -1; dz <= 1; dz++) {
          int64_t near_key[3] = {key[0] + dx, key[1] + dy, key[2] + dz};
          poly_weld_cell *cell = poly_weld_find(cells, table_size - 1, near_key);
          for (int r = cell->head; r >= 0; r = next[r]) {
            double d[3];
            poly_sub3(p, v + 3 * r, d);
            /* Representatives are compacted to their new index; slots below i hold only them. */
            if (poly_dot3(d, d) <= tolerance * tolerance && (match < 0 || r < match)) match = r;
          }
        }
    if (match >= 0) {
      remap[i] = match;
      continue;
    }
    poly_weld_cell *cell = poly_weld_find(cells, table_size - 1, key);
    if (cell->head < 0) memcpy(cell->key, key, sizeof key);
    next[kept] = cell->head;
    cell->head = kept;
    memcpy(v + 3 * kept, p, sizeof p);
    remap[i] = kept++;
  }
  for (int t = 0; t < 3 * mesh->num_triangles; t++) {
    int index = mesh->triangles[t];
    if (index >= 0 && index < n) mesh->triangles[t] = remap[index];
  }
  free(cells);
  free(next);
  free(remap);
  mesh->num_vertices = kept;
  double *shrunk = (double *)realloc(mesh->vertices, sizeof(double) * 3 * (size_t)kept);
  if (shrunk) mesh->vertices = shrunk;
  return n - kept;
}

/* ------------------------------------------------------------------ mass properties */

/* Each triangle spans a signed tetrahedron with the reference point; the
 * integrals of 1, x and x x^T over a tetrahedron with one corner at the origin
 * are det/6, det/24 (a+b+c) and det/120 (a a^T + b b^T + c c^T + s s^T), s = a+b+c. */
void poly_mass_properties_compute(const double *vertices, const int *triangles, int num_triangles,
                                  poly_mass_properties *out)
{
  memset(out, 0, sizeof *out);
  if (!vertices || !triangles || num_triangles <= 0) return;
  /* Working relative to a mesh vertex keeps the sums O(size), not O(distance from origin). */
  const double *reference = vertices + 3 * (size_t)triangles[0];
  double det_sum = 0.0, first[3] = {0.0, 0.0, 0.0}, second[9] = {0.0};
  for (int t = 0; t < num_triangles; t++) {
    double a[3], b[3], c[3], bc[3], s[3];
    poly_sub3(vertices + 3 * (size_t)triangles[3 * t], reference, a);
    poly_sub3(vertices + 3 * (size_t)triangles[3 * t + 1], reference, b);
    poly_sub3(vertices + 3 * (size_t)triangles[3 * t + 2], reference, c);
    poly_cross3(b, c, bc);
    double det = poly_dot3(a, bc);
    for (int k = 0; k < 3; k++) s[k] = a[k] + b[k] + c[k];
    det_sum += det;
    for (int i = 0; i < 3; i++) {
      first[i] += det * s[i];
      for (int j = i; j < 3; j++)
        second[3 * i + j] += det * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
  }
  double volume = det_sum / 6.0;
  out->volume = volume;
  memcpy(out->centroid, reference, sizeof out->centroid);
  if (volume == 0.0) return;
  double centroid[3], covariance[9];
  for (int i = 0; i < 3; i++) centroid[i] = first[i] / 24.0 / volume;
  for (int i = 0; i < 3; i++)
    for (int j = i; j < 3; j++) {
      covariance[3 * i + j] = second[3 * i + j] / 120.0 - volume * centroid[i] * centroid[j];
      covariance[3 * j + i] = covariance[3 * i + j];
    }
  double trace = covariance[0] + covariance[4] + covariance[8];
  for (int i = 0; i < 9; i++) out->inertia[i] = (i % 4 == 0 ? trace : 0.0) - covariance[i];
  for (int i = 0; i < 3; i++) out->centroid[i] = reference[i] + centroid[i];
}

/* ------------------------------------------------------------------ eigen */

/* Cyclic Jacobi: exact for already-diagonal input (so spheres and cubes keep
 * the coordinate axes) and accurate to rounding for well-separated eigenvalues. */
void poly_symmetric_eigen3(const double matrix[9], double eigenvalues[3], double eigenvectors[9])
{
  double a[9], v[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) a[3 * i + j] = 0.5 * (matrix[3 * i + j] + matrix[3 * j + i]);
  static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 50; sweep++) {
    if (a[1] == 0.0 && a[2] == 0.0 && a[5] == 0.0) break;
    for (int n = 0; n < 3; n++) {
      int p = pairs[n][0], q = pairs[n][1], r = 3 - p - q;
      double apq = a[3 * p + q], app = a[3 * p + p], aqq = a[3 * q + q];
      if (apq == 0.0) continue;
      /* An off-diagonal entry that cannot change either diagonal entry is already converged. */
      if (fabs(apq) <= 1e-18 * (fabs(app) + fabs(aqq))) {
        a[3 * p + q] = a[3 * q + p] = 0.0;
        continue;
      }
      double theta = (aqq - app) / (2.0 * apq);
      double t = fabs(theta) > 1e150 ? 0.5 / theta
                                      : (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
      double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
      a[3 * p + p] = app - t * apq;
      a[3 * q + q] = aqq + t * apq;
      a[3 * p + q] = a[3 * q + p] = 0.0;
      double arp = a[3 * r + p], arq = a[3 * r + q];
      a[3 * r + p] = a[3 * p + r] = c * arp - s * arq;
      a[3 * r + q] = a[3 * q + r] = s * arp + c * arq;
      for (int k = 0; k < 3; k++) {
        double vkp = v[3 * k + p], vkq = v[3 * k + q];
        v[3 * k + p] = c * vkp - s * vkq;
        v[3 * k + q] = s * vkp + c * vkq;
      }
    }
  }
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 3; i++)
    for (int j = i + 1; j < 3; j++)
      if (a[4 * order[j]] < a[4 * order[i]]) {
        int swap = order[i];
        order[i] = order[j];
        order[j] = swap;
      }
  double columns[3][3];
  for (int i = 0; i < 3; i++) {
    eigenvalues[i] = a[4 * order[i]];
    for (int k = 0; k < 3; k++) columns[i][k] = v[3 * k + order[i]];
  }
  /* Fixed signs make the body frame reproducible: the largest component of the
   * first two axes is positive, the third completes a right-handed set. */
  for (int i = 0; i < 2; i++) {
    int largest = 0;
    for (int k = 1; k < 3; k++)
      if (fabs(columns[i][k]) > fabs(columns[i][largest])) largest = k;
    if (columns[i][largest] < 0)
      for (int k = 0; k < 3; k++) columns[i][k] = -columns[i][k];
  }
  poly_cross3(columns[0], columns[1], columns[2]);
  for (int i = 0; i < 3; i++)
    for (int k = 0; k < 3; k++) eigenvectors[3 * k + i] = columns[i][k];
}

/* ------------------------------------------------------------------ validation */

typedef struct poly_half_edge {
  int lo, hi;    /* vertex indices, lo < hi */
  int triangle;
  int corner;    /* the edge runs from corner to corner + 1 of the triangle */
} poly_half_edge;

static int poly_half_edge_compare(const void *pa, const void *pb)
{
  const poly_half_edge *a = (const poly_half_edge *)pa, *b = (const poly_half_edge *)pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  return a->triangle < b->triangle ? -1 : (a->triangle > b->triangle);
}

/* Scratch state of one build; everything is freed in one place. */
typedef struct poly_build {
  const char *name;
  char *message;
  size_t message_size;
  int num_vertices, num_triangles, num_edges;
  double *vertices;           /* compacted, file frame, later scaled */
  int *triangles;
  poly_half_edge *half_edges; /* 3 * num_triangles, sorted */
  int *neighbours;            /* 3 * num_triangles: triangle across the edge from each corner */
  int *edges, *edge_triangles;
  int *vertex_offsets, *vertex_triangles;
} poly_build;

static void poly_build_free(poly_build *b)
{
  free(b->vertices);
  free(b->triangles);
  free(b->half_edges);
  free(b->neighbours);
  free(b->edges);
  free(b->edge_triangles);
  free(b->vertex_offsets);
  free(b->vertex_triangles);
}

static poly_status poly_build_out_of_memory(poly_build *b)
{
  return poly_fail(b->message, b->message_size, POLY_ERROR_MEMORY, "shape mesh '%s': out of memory",
                   b->name);
}

static const double *poly_build_vertex(const poly_build *b, int index)
{
  return b->vertices + 3 * (size_t)index;
}

/* Copies the referenced vertices only: stray unused vertices would otherwise
 * inflate the bounding radius and appear as contact features without faces. */
static poly_status poly_build_copy(poly_build *b, const poly_mesh *mesh)
{
  for (int t = 0; t < 3 * mesh->num_triangles; t++) {
    int index = mesh->triangles[t];
    if (index < 0 || index >= mesh->num_vertices)
      return poly_fail(b->message, b->message_size, POLY_ERROR_PARSE,
                       "shape mesh '%s': triangle %d of %d references vertex %d outside 0..%d",
                       b->name, t / 3 + 1, mesh->num_triangles, index, mesh->num_vertices - 1);
  }
  int *remap = (int *)malloc(sizeof(int) * (size_t)mesh->num_vertices);
  b->triangles = (int *)malloc(sizeof(int) * 3 * (size_t)mesh->num_triangles);
  b->vertices = (double *)malloc(sizeof(double) * 3 * (size_t)mesh->num_vertices);
  if (!remap || !b->triangles || !b->vertices) {
    free(remap);
    return poly_build_out_of_memory(b);
  }
  for (int i = 0; i < mesh->num_vertices; i++) remap[i] = -1;
  b->num_triangles = mesh->num_triangles;
  for (int t = 0; t < 3 * mesh->num_triangles; t++) {
    int index = mesh->triangles[t];
    if (remap[index] < 0) {
      const double *p = mesh->vertices + 3 * (size_t)index;
      if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
        free(remap);
        return poly_fail(b->message, b->message_size, POLY_ERROR_PARSE,
                         "shape mesh '%s': vertex %d has a non-finite coordinate", b->name, index);
      }
      remap[index] = b->num_vertices++;
      memcpy(b->vertices + 3 * (size_t)remap[index], p, 3 * sizeof(double));
    }
    b->triangles[t] = remap[index];
  }
  free(remap);
  return POLY_OK;
}

static poly_status poly_check_degenerate(poly_build *b)
{
  double size = poly_bounding_box_diagonal(b->vertices, b->num_vertices);
  for (int t = 0; t < b->num_triangles; t++) {
    const int *tri = b->triangles + 3 * t;
    const double *p = poly_build_vertex(b, tri[0]), *q = poly_build_vertex(b, tri[1]),
                 *r = poly_build_vertex(b, tri[2]);
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      const double *x = poly_build_vertex(b, tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1]);
      return poly_fail(b->message, b->message_size, POLY_ERROR_DEGENERATE,
                       "shape mesh '%s' has a degenerate triangle %d of %d: it uses vertex "
                       "(%.9g,%.9g,%.9g) twice",
                       b->name, t + 1, b->num_triangles, x[0], x[1], x[2]);
    }
    double u[3], w[3], n[3];
    poly_sub3(q, p, u);
    poly_sub3(r, p, w);
    poly_cross3(u, w, n);
    if (sqrt(poly_dot3(n, n)) <= POLY_DEGENERATE_AREA_RELATIVE * size * size)
      return poly_fail(b->message, b->message_size, POLY_ERROR_DEGENERATE,
                       "shape mesh '%s' has a degenerate triangle %d of %d: (%.9g,%.9g,%.9g)-"
                       "(%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g) has zero area",
                       b->name, t + 1, b->num_triangles, p[0], p[1], p[2], q[0], q[1], q[2], r[0],
                       r[1], r[2]);
  }
  return POLY_OK;
}

/* "(x,y,z)-(x,y,z)" of an edge, for messages. */
static const char *poly_edge_text(const poly_build *b, const poly_half_edge *h, char *text, size_t size)
{
  const double *p = poly_build_vertex(b, h->lo), *q = poly_build_vertex(b, h->hi);
  snprintf(text, size, "(%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g)", p[0], p[1], p[2], q[0], q[1], q[2]);
  return text;
}

/* Sorting the 3F directed edges by their vertex pair groups each edge's uses;
 * the checks then run in the documented order: open, non-manifold, orientation. */
static poly_status poly_check_edges(poly_build *b)
{
  int nh = 3 * b->num_triangles;
  b->half_edges = (poly_half_edge *)malloc(sizeof(poly_half_edge) * (size_t)nh);
  b->neighbours = (int *)malloc(sizeof(int) * (size_t)nh);
  if (!b->half_edges || !b->neighbours) return poly_build_out_of_memory(b);
  for (int t = 0; t < b->num_triangles; t++)
    for (int k = 0; k < 3; k++) {
      int from = b->triangles[3 * t + k], to = b->triangles[3 * t + (k + 1) % 3];
      poly_half_edge h = {from < to ? from : to, from < to ? to : from, t, k};
      b->half_edges[3 * t + k] = h;
    }
  qsort(b->half_edges, (size_t)nh, sizeof(poly_half_edge), poly_half_edge_compare);
  int first_open = -1, first_crowded = -1, crowded_count = 0, first_misoriented = -1;
  b->num_edges = 0;
  for (int i = 0; i < nh;) {
    int j = i + 1;
    while (j < nh && b->half_edges[j].lo == b->half_edges[i].lo && b->half_edges[j].hi == b->half_edges[i].hi) j++;
    if (j - i == 1 && first_open < 0) first_open = i;
    if (j - i > 2 && first_crowded < 0) {
      first_crowded = i;
      crowded_count = j - i;
    }
    if (j - i == 2) {
      const poly_half_edge *h0 = &b->half_edges[i], *h1 = &b->half_edges[i + 1];
      int forward0 = b->triangles[3 * h0->triangle + h0->corner] == h0->lo;
      int forward1 = b->triangles[3 * h1->triangle + h1->corner] == h1->lo;
      if (forward0 == forward1 && first_misoriented < 0) first_misoriented = i;
      b->neighbours[3 * h0->triangle + h0->corner] = h1->triangle;
      b->neighbours[3 * h1->triangle + h1->corner] = h0->triangle;
    }
    b->num_edges++;
    i = j;
  }
  char edge[160];
  if (first_open >= 0)
    return poly_fail(b->message, b->message_size, POLY_ERROR_OPEN,
                     "shape mesh '%s' is open: edge %s belongs to only one triangle (%d of %d)",
                     b->name, poly_edge_text(b, &b->half_edges[first_open], edge, sizeof edge),
                     b->half_edges[first_open].triangle + 1, b->num_triangles);
  if (first_crowded >= 0)
    return poly_fail(b->message, b->message_size, POLY_ERROR_NONMANIFOLD,
                     "shape mesh '%s' is non-manifold: edge %s is shared by %d triangles", b->name,
                     poly_edge_text(b, &b->half_edges[first_crowded], edge, sizeof edge), crowded_count);
  if (first_misoriented >= 0)
    return poly_fail(b->message, b->message_size, POLY_ERROR_ORIENTATION,
                     "shape mesh '%s' has inconsistent orientation: edge %s is traversed in the "
                     "same direction by triangles %d and %d",
                     b->name, poly_edge_text(b, &b->half_edges[first_misoriented], edge, sizeof edge),
                     b->half_edges[first_misoriented].triangle + 1,
                     b->half_edges[first_misoriented + 1].triangle + 1);
  return POLY_OK;
}

/* Counting sort of (vertex, triangle) incidences: each vertex's triangles in ascending order. */
static poly_status poly_build_vertex_triangles(poly_build *b)
{
  b->vertex_offsets = (int *)calloc((size_t)b->num_vertices + 1, sizeof(int));
  b->vertex_triangles = (int *)malloc(sizeof(int) * 3 * (size_t)b->num_triangles);
  if (!b->vertex_offsets || !b->vertex_triangles) return poly_build_out_of_memory(b);
  for (int c = 0; c < 3 * b->num_triangles; c++) b->vertex_offsets[b->triangles[c] + 1]++;
  for (int i = 0; i < b->num_vertices; i++) b->vertex_offsets[i + 1] += b->vertex_offsets[i];
  int *fill = (int *)malloc(sizeof(int) * (size_t)b->num_vertices);
  if (!fill) return poly_build_out_of_memory(b);
  memcpy(fill, b->vertex_offsets, sizeof(int) * (size_t)b->num_vertices);
  for (int c = 0; c < 3 * b->num_triangles; c++) b->vertex_triangles[fill[b->triangles[c]]++] = c / 3;
  free(fill);
  return POLY_OK;
}

static int poly_corner_of(const int *triangle, int vertex)
{
  return triangle[0] == vertex ? 0 : (triangle[1] == vertex ? 1 : 2);
}

/* With manifold, consistently oriented edges, stepping across each triangle's
 * outgoing edge at v walks v's fan; a manifold vertex has exactly one cycle. */
static poly_status poly_check_vertex_fans(poly_build *b)
{
  for (int v = 0; v < b->num_vertices; v++) {
    int begin = b->vertex_offsets[v], valence = b->vertex_offsets[v + 1] - begin;
    int start = b->vertex_triangles[begin], t = start, steps = 0;
    do {
      t = b->neighbours[3 * t + poly_corner_of(b->triangles + 3 * t, v)];
      steps++;
    } while (t != start && steps <= valence);
    if (steps == valence) continue;
    const double *p = poly_build_vertex(b, v);
    return poly_fail(b->message, b->message_size, POLY_ERROR_NONMANIFOLD,
                     "shape mesh '%s' is non-manifold: pinched vertex (%.9g,%.9g,%.9g) has %d "
                     "triangles that do not form a single fan (one cycle covers only %d)",
                     b->name, p[0], p[1], p[2], valence, steps);
  }
  return POLY_OK;
}

static poly_status poly_check_connected(poly_build *b)
{
  int *stack = (int *)malloc(sizeof(int) * (size_t)b->num_triangles);
  unsigned char *seen = (unsigned char *)calloc((size_t)b->num_triangles, 1);
  if (!stack || !seen) {
    free(stack);
    free(seen);
    return poly_build_out_of_memory(b);
  }
  int top = 0, reached = 1;
  stack[top++] = 0;
  seen[0] = 1;
  while (top > 0) {
    int t = stack[--top];
    for (int k = 0; k < 3; k++) {
      int u = b->neighbours[3 * t + k];
      if (!seen[u]) {
        seen[u] = 1;
        reached++;
        stack[top++] = u;
      }
    }
  }
  int stray = 0;
  while (stray < b->num_triangles && seen[stray]) stray++;
  free(stack);
  free(seen);
  if (reached == b->num_triangles) return POLY_OK;
  const double *p = poly_build_vertex(b, b->triangles[3 * stray]);
  return poly_fail(b->message, b->message_size, POLY_ERROR_DISCONNECTED,
                   "shape mesh '%s' has more than one connected component: triangle %d at "
                   "(%.9g,%.9g,%.9g) is not connected to triangle 1 (%d of %d triangles reach it)",
                   b->name, stray + 1, p[0], p[1], p[2], reached, b->num_triangles);
}

/* Unique edges with lo < hi; the first triangle runs lo -> hi, the second hi -> lo. */
static poly_status poly_build_edges(poly_build *b)
{
  b->edges = (int *)malloc(sizeof(int) * 2 * (size_t)b->num_edges);
  b->edge_triangles = (int *)malloc(sizeof(int) * 2 * (size_t)b->num_edges);
  if (!b->edges || !b->edge_triangles) return poly_build_out_of_memory(b);
  for (int e = 0; e < b->num_edges; e++) {
    const poly_half_edge *h = &b->half_edges[2 * e];
    int forward = b->triangles[3 * h->triangle + h->corner] == h->lo;
    b->edges[2 * e] = h->lo;
    b->edges[2 * e + 1] = h->hi;
    b->edge_triangles[2 * e] = forward ? h[0].triangle : h[1].triangle;
    b->edge_triangles[2 * e + 1] = forward ? h[1].triangle : h[0].triangle;
  }
  return POLY_OK;
}

/* ------------------------------------------------------------ self-intersection */

/* A closed, consistently oriented, connected triangulation can still pass
 * through itself (a corner pulled through the opposite face); its divergence-
 * theorem integrals are then meaningless (negative principal moments). Every
 * pair of triangles whose bounding boxes touch is tested with exact orientation
 * signs (poly_exact.h); touching counts as intersecting, as triangles that share
 * no vertex never touch in an embedded surface. Triangles sharing a vertex may
 * meet only there, triangles sharing an edge only along it. */

static int poly_sign(double value) { return (value > 0.0) - (value < 0.0); }

/* Segment pq against triangle abc, the segment not lying in the triangle's plane:
 * 1 if they meet (touching included). */
static int poly_segment_meets_triangle(const double *p, const double *q, const double *a, const double *b,
                                       const double *c)
{
  int sp = poly_sign(poly_orient(a, b, c, p)), sq = poly_sign(poly_orient(a, b, c, q));
  if (sp == sq) return 0; /* both on one side, or both in the plane (coplanar: handled apart) */
  int s1 = poly_sign(poly_orient(p, q, a, b)), s2 = poly_sign(poly_orient(p, q, b, c)),
      s3 = poly_sign(poly_orient(p, q, c, a));
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/* 2-d orientation in the plane of two coplanar triangles (axis `drop` dropped). */
static double poly_orient2(const double *a, const double *b, const double *c, int drop)
{
  int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  return (b[i] - a[i]) * (c[j] - a[j]) - (b[j] - a[j]) * (c[i] - a[i]);
}

/* Two coplanar triangles without a common vertex: 1 if they overlap (an edge of
 * one properly crosses an edge of the other, or a vertex is strictly inside). */
static int poly_coplanar_triangles_meet(const double *const t1[3], const double *const t2[3], int drop)
{
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const double *p = t1[i], *q = t1[(i + 1) % 3], *r = t2[j], *s = t2[(j + 1) % 3];
      double o1 = poly_orient2(p, q, r, drop), o2 = poly_orient2(p, q, s, drop);
      double o3 = poly_orient2(r, s, p, drop), o4 = poly_orient2(r, s, q, drop);
      if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 1;
    }
  for (int pass = 0; pass < 2; pass++) {
    const double *const *inner = pass ? t2 : t1, *const *outer = pass ? t1 : t2;
    for (int i = 0; i < 3; i++) {
      double o1 = poly_orient2(outer[0], outer[1], inner[i], drop), o2 = poly_orient2(outer[1], outer[2], inner[i], drop),
             o3 = poly_orient2(outer[2], outer[0], inner[i], drop);
      if ((o1 > 0 && o2 > 0 && o3 > 0) || (o1 < 0 && o2 < 0 && o3 < 0)) return 1;
    }
  }
  return 0;
}

/* Whether the direction a - v, with a in the plane of triangle (v, c, d), points
 * into that triangle's corner at v (along one of its edges included). */
static int poly_direction_in_corner(const double *v, const double *a, const double *c, const double *d)
{
  double u[3], e[3], f[3], n[3], ue[3], uf[3];
  poly_sub3(a, v, u);
  poly_sub3(c, v, e);
  poly_sub3(d, v, f);
  poly_cross3(e, f, n);
  poly_cross3(e, u, ue);
  poly_cross3(u, f, uf);
  double d1 = poly_dot3(n, ue), d2 = poly_dot3(n, uf);
  double tolerance = 1e-12 * sqrt(poly_dot3(n, n) * poly_dot3(u, u)) *
                     (sqrt(poly_dot3(e, e)) + sqrt(poly_dot3(f, f)));
  return d1 >= -tolerance && d2 >= -tolerance && (d1 > tolerance || d2 > tolerance);
}

static int poly_triangles_intersect(const poly_build *b, int t1, int t2)
{
  const int *i1 = b->triangles + 3 * t1, *i2 = b->triangles + 3 * t2;
  int shared1[3] = {-1, -1, -1}, shared = 0; /* shared1[k]: corner of t2 equal to corner k of t1 */
  for (int k = 0; k < 3; k++)
    for (int l = 0; l < 3; l++)
      if (i1[k] == i2[l]) {
        shared1[k] = l;
        shared++;
      }
  const double *p1[3], *p2[3];
  for (int k = 0; k < 3; k++) {
    p1[k] = poly_build_vertex(b, i1[k]);
    p2[k] = poly_build_vertex(b, i2[k]);
  }
  /* The same triangle twice: in a closed, connected mesh only a two-triangle
   * pillow, which the volume check reports. */
  if (shared >= 3) return 0;
  if (shared == 2) {
    /* Along their common edge v-w only, unless folded flat onto each other. */
    int k = shared1[0] < 0 ? 0 : shared1[1] < 0 ? 1 : 2; /* t1's corner off the edge */
    int l = 3 - shared1[(k + 1) % 3] - shared1[(k + 2) % 3];
    const double *v = p1[(k + 1) % 3], *w = p1[(k + 2) % 3], *a = p1[k], *c = p2[l];
    if (poly_orient(v, w, a, c) != 0.0) return 0;
    double e[3], u[3], x[3], n1[3], n2[3];
    poly_sub3(w, v, e);
    poly_sub3(a, v, u);
    poly_sub3(c, v, x);
    poly_cross3(e, u, n1);
    poly_cross3(e, x, n2);
    return poly_dot3(n1, n2) > 0.0;
  }
  if (shared == 1) {
    int k = shared1[0] >= 0 ? 0 : shared1[1] >= 0 ? 1 : 2, l = shared1[k];
    const double *v = p1[k], *a = p1[(k + 1) % 3], *bb = p1[(k + 2) % 3];
    const double *c = p2[(l + 1) % 3], *d = p2[(l + 2) % 3];
    if (poly_segment_meets_triangle(a, bb, v, c, d) || poly_segment_meets_triangle(c, d, v, a, bb)) return 1;
    /* An edge from v lying in the other triangle's plane, pointing into it. */
    if (poly_orient(v, c, d, a) == 0.0 && poly_direction_in_corner(v, a, c, d)) return 1;
    if (poly_orient(v, c, d, bb) == 0.0 && poly_direction_in_corner(v, bb, c, d)) return 1;
    if (poly_orient(v, a, bb, c) == 0.0 && poly_direction_in_corner(v, c, a, bb)) return 1;
    if (poly_orient(v, a, bb, d) == 0.0 && poly_direction_in_corner(v, d, a, bb)) return 1;
    return 0;
  }
  int coplanar = 1;
  for (int k = 0; k < 3; k++)
    if (poly_orient(p1[0], p1[1], p1[2], p2[k]) != 0.0) coplanar = 0;
  if (coplanar) {
    double u[3], w[3], n[3];
    poly_sub3(p1[1], p1[0], u);
    poly_sub3(p1[2], p1[0], w);
    poly_cross3(u, w, n);
    int drop = fabs(n[0]) >= fabs(n[1]) && fabs(n[0]) >= fabs(n[2]) ? 0 : fabs(n[1]) >= fabs(n[2]) ? 1 : 2;
    return poly_coplanar_triangles_meet(p1, p2, drop);
  }
  for (int k = 0; k < 3; k++) {
    if (poly_segment_meets_triangle(p1[k], p1[(k + 1) % 3], p2[0], p2[1], p2[2])) return 1;
    if (poly_segment_meets_triangle(p2[k], p2[(k + 1) % 3], p1[0], p1[1], p1[2])) return 1;
  }
  return 0;
}

typedef struct poly_box_entry {
  double low[3], high[3];
  int triangle;
} poly_box_entry;

static int poly_box_entry_compare(const void *pa, const void *pb)
{
  const poly_box_entry *a = (const poly_box_entry *)pa, *b = (const poly_box_entry *)pb;
  if (a->low[0] != b->low[0]) return a->low[0] < b->low[0] ? -1 : 1;
  return (a->triangle > b->triangle) - (a->triangle < b->triangle);
}

/* Sweep along x over the triangles' bounding boxes; the exact test for each pair
 * of touching boxes. */
static poly_status poly_check_self_intersection(poly_build *b)
{
  poly_box_entry *boxes = (poly_box_entry *)malloc(sizeof(poly_box_entry) * (size_t)b->num_triangles);
  if (!boxes) return poly_build_out_of_memory(b);
  for (int t = 0; t < b->num_triangles; t++) {
    boxes[t].triangle = t;
    for (int k = 0; k < 3; k++) {
      boxes[t].low[k] = HUGE_VAL;
      boxes[t].high[k] = -HUGE_VAL;
    }
    for (int c = 0; c < 3; c++) {
      const double *p = poly_build_vertex(b, b->triangles[3 * t + c]);
      for (int k = 0; k < 3; k++) {
        if (p[k] < boxes[t].low[k]) boxes[t].low[k] = p[k];
        if (p[k] > boxes[t].high[k]) boxes[t].high[k] = p[k];
      }
    }
  }
  qsort(boxes, (size_t)b->num_triangles, sizeof(poly_box_entry), poly_box_entry_compare);
  int found1 = -1, found2 = -1;
  for (int i = 0; i < b->num_triangles && found1 < 0; i++)
    for (int j = i + 1; j < b->num_triangles && boxes[j].low[0] <= boxes[i].high[0]; j++) {
      if (boxes[j].low[1] > boxes[i].high[1] || boxes[i].low[1] > boxes[j].high[1] ||
          boxes[j].low[2] > boxes[i].high[2] || boxes[i].low[2] > boxes[j].high[2])
        continue;
      int t1 = boxes[i].triangle, t2 = boxes[j].triangle;
      if (poly_triangles_intersect(b, t1, t2)) {
        found1 = t1 < t2 ? t1 : t2;
        found2 = t1 < t2 ? t2 : t1;
        break;
      }
    }
  free(boxes);
  if (found1 < 0) return POLY_OK;
  const double *p[6];
  for (int c = 0; c < 3; c++) {
    p[c] = poly_build_vertex(b, b->triangles[3 * found1 + c]);
    p[3 + c] = poly_build_vertex(b, b->triangles[3 * found2 + c]);
  }
  return poly_fail(b->message, b->message_size, POLY_ERROR_SELF_INTERSECTION,
                   "shape mesh '%s' intersects itself: triangles %d and %d of %d cross "
                   "((%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g) and "
                   "(%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g)-(%.9g,%.9g,%.9g))",
                   b->name, found1 + 1, found2 + 1, b->num_triangles, p[0][0], p[0][1], p[0][2], p[1][0],
                   p[1][1], p[1][2], p[2][0], p[2][1], p[2][2], p[3][0], p[3][1], p[3][2], p[4][0], p[4][1],
                   p[4][2], p[5][0], p[5][1], p[5][2]);
}

static poly_status poly_build_validate(poly_build *b, const poly_mesh *mesh)
{
  poly_status status = poly_build_copy(b, mesh);
  if (status == POLY_OK) status = poly_check_degenerate(b);
  if (status == POLY_OK) status = poly_check_edges(b);
  if (status == POLY_OK) status = poly_build_edges(b);
  if (status == POLY_OK) status = poly_build_vertex_triangles(b);
  if (status == POLY_OK) status = poly_check_vertex_fans(b);
  if (status == POLY_OK) status = poly_check_connected(b);
  if (status == POLY_OK) status = poly_check_self_intersection(b);
  return status;
}

/* Jacobi returns arbitrary axes inside a degenerate eigenspace (cube, tetrahedron,
 * icosphere, square prism), which would leave such a shape turned against its
 * file for no reason. Inside a degenerate eigenspace we therefore take the file
 * axes projected onto it, so a cube stays axis-aligned. `axes` holds the
 * principal axes as columns (row-major), moments ascending. */
static void poly_align_degenerate_axes(const double moments[3], double axes[9])
{
  double tolerance = 1e-9 * fabs(moments[2]);
  int low_pair = fabs(moments[1] - moments[0]) <= tolerance;
  int high_pair = fabs(moments[2] - moments[1]) <= tolerance;
  if (!low_pair && !high_pair) return;
  if (low_pair && high_pair) {
    for (int k = 0; k < 9; k++) axes[k] = (k % 4 == 0) ? 1.0 : 0.0;
    return;
  }
  /* One unique axis u; the other two span the plane normal to it. Columns must
   * stay right-handed (c2 = c0 x c1): for the pair (0,1) take c0 = a, c1 = u x a;
   * for the pair (1,2) take c1 = a, c2 = u x a. */
  int unique = low_pair ? 2 : 0, first = low_pair ? 0 : 1, second = low_pair ? 1 : 2;
  double u[3] = {axes[unique], axes[3 + unique], axes[6 + unique]}, a[3] = {0, 0, 0}, best = -1.0;
  for (int e = 0; e < 3; e++) {
    double projected[3];
    for (int k = 0; k < 3; k++) projected[k] = (k == e ? 1.0 : 0.0) - u[e] * u[k];
    double length = sqrt(poly_dot3(projected, projected));
    if (length > best + 1e-12) {
      best = length;
      for (int k = 0; k < 3; k++) a[k] = projected[k] / length;
    }
  }
  double b[3];
  poly_cross3(u, a, b);
  for (int k = 0; k < 3; k++) {
    axes[3 * k + first] = a[k];
    axes[3 * k + second] = b[k];
  }
}

/* Moves the scaled file-frame mesh into the body frame and hands all arrays to `shape`. */
/* Each triangle's three edges (corners 0-1, 1-2, 2-0), from the edges' triangle pairs. */
static void poly_build_triangle_edges(const poly_build *b, int *triangle_edges)
{
  for (int e = 0; e < b->num_edges; e++)
    for (int j = 0; j < 2; j++) {
      const int t = b->edge_triangles[2 * e + j], *tri = b->triangles + 3 * t;
      for (int k = 0; k < 3; k++) {
        const int from = tri[k], to = tri[k == 2 ? 0 : k + 1];
        if ((from == b->edges[2 * e] && to == b->edges[2 * e + 1]) ||
            (to == b->edges[2 * e] && from == b->edges[2 * e + 1]))
          triangle_edges[3 * t + k] = e;
      }
    }
}

static poly_status poly_build_finish(poly_build *b, const poly_mass_properties *mass, poly_shape *shape)
{
  double *normals = (double *)malloc(sizeof(double) * 3 * (size_t)b->num_triangles);
  int *triangle_edges = (int *)malloc(sizeof(int) * 3 * (size_t)b->num_triangles);
  if (!normals || !triangle_edges) {
    free(normals);
    free(triangle_edges);
    return poly_build_out_of_memory(b);
  }
  poly_build_triangle_edges(b, triangle_edges);
  double moments[3], axes[9];
  poly_symmetric_eigen3(mass->inertia, moments, axes);
  poly_align_degenerate_axes(moments, axes);
  double radius_squared = 0.0;
  for (int i = 0; i < b->num_vertices; i++) {
    double *p = b->vertices + 3 * (size_t)i, d[3];
    poly_sub3(p, mass->centroid, d);
    for (int k = 0; k < 3; k++) p[k] = axes[k] * d[0] + axes[3 + k] * d[1] + axes[6 + k] * d[2];
    double r2 = poly_dot3(p, p);
    radius_squared = r2 > radius_squared ? r2 : radius_squared;
  }
  for (int t = 0; t < b->num_triangles; t++) {
    const int *tri = b->triangles + 3 * t;
    double u[3], w[3], *n = normals + 3 * (size_t)t;
    poly_sub3(poly_build_vertex(b, tri[1]), poly_build_vertex(b, tri[0]), u);
    poly_sub3(poly_build_vertex(b, tri[2]), poly_build_vertex(b, tri[0]), w);
    poly_cross3(u, w, n);
    double length = sqrt(poly_dot3(n, n));
    for (int k = 0; k < 3; k++) n[k] /= length;
  }
  shape->num_vertices = b->num_vertices;
  shape->num_triangles = b->num_triangles;
  shape->num_edges = b->num_edges;
  shape->vertices = b->vertices;
  shape->triangles = b->triangles;
  shape->face_normals = normals;
  shape->edges = b->edges;
  shape->edge_triangles = b->edge_triangles;
  shape->triangle_edges = triangle_edges;
  shape->vertex_triangle_offsets = b->vertex_offsets;
  shape->vertex_triangles = b->vertex_triangles;
  shape->volume = mass->volume;
  shape->bounding_radius = sqrt(radius_squared);
  memcpy(shape->principal_moments, moments, sizeof moments);
  memcpy(shape->centre_of_mass, mass->centroid, sizeof shape->centre_of_mass);
  memcpy(shape->principal_axes, axes, sizeof axes);
  b->vertices = NULL;
  b->triangles = NULL;
  b->edges = b->edge_triangles = b->vertex_offsets = b->vertex_triangles = NULL;
  return POLY_OK;
}

/* Mass properties a rigid body can have: finite, positive, and principal moments
 * that obey the triangle inequality (I1 + I2 >= I3 for every ordering; with
 * ascending moments only the largest needs checking). An extreme scale gives
 * zero (underflow) or non-finite moments; a mesh passing through itself could
 * give negative ones. The shape is freed on failure. */
static poly_status poly_check_mass_properties(poly_shape *shape, double scale, const char *name, char *message,
                                              size_t message_size)
{
  const double *m = shape->principal_moments;
  const char *reason = NULL;
  if (!isfinite(shape->volume) || !(shape->volume > 0.0)) reason = "the volume is not positive and finite";
  else if (!isfinite(m[0]) || !isfinite(m[1]) || !isfinite(m[2])) reason = "a principal moment is not finite";
  else if (!(m[0] > 0.0 && m[1] > 0.0 && m[2] > 0.0)) reason = "a principal moment is not positive";
  else if (m[0] + m[1] < m[2] * (1.0 - 1e-9))
    reason = "the principal moments break the triangle inequality I1 + I2 >= I3";
  else if (!isfinite(shape->bounding_radius) || !(shape->bounding_radius > 0.0))
    reason = "the bounding radius is not positive and finite";
  if (!reason) return POLY_OK;
  poly_status status = poly_fail(message, message_size, POLY_ERROR_MASS,
                                 "shape mesh '%s' (scale %g) has impossible mass properties: %s (volume %g, "
                                 "principal moments/density %g %g %g)",
                                 name, scale, reason, shape->volume, m[0], m[1], m[2]);
  poly_shape_free(shape);
  return status;
}

poly_status poly_shape_build(const poly_mesh *mesh, double scale, const char *name,
                             poly_shape *shape, char *message, size_t message_size)
{
  if (message && message_size > 0) message[0] = '\0';
  if (!shape) return poly_fail(message, message_size, POLY_ERROR_EMPTY, "no shape to build into");
  memset(shape, 0, sizeof *shape);
  const char *by_cones = getenv("POLY_PIECES_BY_CONES");  /* read by poly_shape_find_faces */
  if (by_cones && strcmp(by_cones, "0") != 0 && strcmp(by_cones, "1") != 0)
    return poly_fail(message, message_size, POLY_ERROR_PARSE, "POLY_PIECES_BY_CONES=%s: expected 0 or 1", by_cones);
  poly_build b;
  memset(&b, 0, sizeof b);
  b.name = name ? name : "(unnamed)";
  b.message = message;
  b.message_size = message_size;
  if (!mesh || mesh->num_triangles <= 0 || mesh->num_vertices <= 0 || !mesh->vertices || !mesh->triangles)
    return poly_fail(message, message_size, POLY_ERROR_EMPTY, "shape mesh '%s' is empty: no triangles",
                     b.name);
  if (!(scale > 0.0) || !isfinite(scale))
    return poly_fail(message, message_size, POLY_ERROR_VOLUME,
                     "shape mesh '%s': scale %g must be positive and finite", b.name, scale);
  poly_status status = poly_build_validate(&b, mesh);
  if (status != POLY_OK) {
    poly_build_free(&b);
    return status;
  }
  for (int i = 0; i < 3 * b.num_vertices; i++) {
    b.vertices[i] *= scale;
    if (!isfinite(b.vertices[i])) {
      poly_build_free(&b);
      return poly_fail(message, message_size, POLY_ERROR_MASS,
                       "shape mesh '%s': scale %g makes its coordinates overflow", b.name, scale);
    }
  }
  poly_mass_properties mass;
  poly_mass_properties_compute(b.vertices, b.triangles, b.num_triangles, &mass);
  double size = poly_bounding_box_diagonal(b.vertices, b.num_vertices);
  double size_cubed = size * size * size;
  if (!isfinite(mass.volume) || !isfinite(size_cubed) || !(size_cubed > 0.0)) {
    poly_build_free(&b);
    return poly_fail(message, message_size, POLY_ERROR_MASS,
                     "shape mesh '%s': with scale %g its volume (%g for a bounding-box diagonal of %g) is "
                     "out of the range of double precision",
                     b.name, scale, mass.volume, size);
  }
  if (!(fabs(mass.volume) > POLY_ZERO_VOLUME_RELATIVE * size_cubed)) {
    poly_build_free(&b);
    return poly_fail(message, message_size, POLY_ERROR_VOLUME,
                     "shape mesh '%s' encloses zero volume (%g for a bounding-box diagonal of %g)",
                     b.name, mass.volume, size);
  }
  if (mass.volume < 0.0) {
    /* Reversing every triangle reverses every edge, so each edge's triangle pair swaps too. */
    for (int t = 0; t < b.num_triangles; t++) {
      int swap = b.triangles[3 * t + 1];
      b.triangles[3 * t + 1] = b.triangles[3 * t + 2];
      b.triangles[3 * t + 2] = swap;
    }
    for (int e = 0; e < b.num_edges; e++) {
      int swap = b.edge_triangles[2 * e];
      b.edge_triangles[2 * e] = b.edge_triangles[2 * e + 1];
      b.edge_triangles[2 * e + 1] = swap;
    }
    poly_mass_properties_compute(b.vertices, b.triangles, b.num_triangles, &mass);
    shape->was_flipped = 1;
  }
  status = poly_build_finish(&b, &mass, shape);
  int was_flipped = shape->was_flipped;
  poly_build_free(&b);
  if (status != POLY_OK) {
    poly_shape_free(shape);
    return status;
  }
  shape->was_flipped = was_flipped;
  status = poly_check_mass_properties(shape, scale, b.name, message, message_size);
  if (status == POLY_OK) status = poly_shape_find_faces(shape);
  return status;
}

poly_status poly_shape_load(const char *path, double scale, poly_shape *shape, char *message,
                            size_t message_size)
{
  poly_mesh mesh;
  if (shape) memset(shape, 0, sizeof *shape);
  poly_status status = poly_mesh_read(path, &mesh, message, message_size);
  if (status != POLY_OK) return status;
  int welded = poly_mesh_weld(&mesh, 1e-9);
  if (welded < 0) {
    poly_mesh_free(&mesh);
    return poly_fail(message, message_size, POLY_ERROR_MEMORY,
                     "shape mesh '%s': out of memory while welding", path);
  }
  status = poly_shape_build(&mesh, scale, path, shape, message, message_size);
  poly_mesh_free(&mesh);
  if (status == POLY_OK) shape->num_welded = welded;
  return status;
}

void poly_shape_free(poly_shape *shape)
{
  if (!shape) return;
  free(shape->vertices);
  free(shape->triangles);
  free(shape->face_normals);
  free(shape->edges);
  free(shape->edge_triangles);
  free(shape->triangle_edges);
  free(shape->vertex_triangle_offsets);
  free(shape->vertex_triangles);
  poly_shape_free_faces(shape);
  memset(shape, 0, sizeof *shape);
}
