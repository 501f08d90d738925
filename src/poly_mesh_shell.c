#include "poly_mesh_shell.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_clip_mesh.h"
#include "poly_shape.h"

static void shell_sub(const double *a, const double *b, double *out)
{
  for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}

static void shell_cross(const double *a, const double *b, double *out)
{
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static double shell_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double shell_normalize(double *a)
{
  double length = sqrt(shell_dot(a, a));
  if (length > 0.0)
    for (int k = 0; k < 3; k++) a[k] /= length;
  return length;
}

/* Unit normal (v1 - v0) x (v2 - v0) and the two edge vectors; returns the doubled area. */
static double shell_frame(const double *v0, const double *v1, const double *v2, double e1[3], double e2[3],
                          double normal[3])
{
  shell_sub(v1, v0, e1);
  shell_sub(v2, v0, e2);
  shell_cross(e1, e2, normal);
  return shell_normalize(normal);
}

typedef struct shell_edge {
  int low, high;  /* vertex ids, low < high */
  int forward;    /* 1: the triangle runs low -> high */
} shell_edge;

static int shell_edge_order(const void *pa, const void *pb)
{
  const shell_edge *a = (const shell_edge *)pa, *b = (const shell_edge *)pb;
  if (a->low != b->low) return a->low < b->low ? -1 : 1;
  if (a->high != b->high) return a->high < b->high ? -1 : 1;
  return a->forward - b->forward;
}

/* Open, misoriented and non-manifold edges, from the sorted list of all triangle edges. */
static void shell_count_edges(poly_mesh_shell *shell, shell_edge *edges, int count)
{
  qsort(edges, (size_t)count, sizeof(shell_edge), shell_edge_order);
  for (int first = 0; first < count;) {
    int last = first;
    while (last + 1 < count && edges[last + 1].low == edges[first].low && edges[last + 1].high == edges[first].high)
      last++;
    int users = last - first + 1;
    if (users == 1) shell->num_open_edges++;
    else if (users > 2) shell->num_nonmanifold_edges++;
    else if (edges[first].forward == edges[last].forward) shell->num_misoriented_edges++;
    first = last + 1;
  }
}

static int shell_faces_out(const double *p, const double *q, const double *r, const double outward[3])
{
  double f1[3], f2[3], n[3];
  shell_sub(q, p, f1);
  shell_sub(r, p, f2);
  shell_cross(f1, f2, n);
  return shell_dot(n, outward) > 0.0;
}

/* The side quad (b, a, a_low, b_low) over the top edge a -> b, split along the diagonal a - b_low
 * (diagonal 1: triangles (b, a, b_low), (a, a_low, b_low)) or b - a_low (diagonal 2: (b, a, a_low),
 * (b, a_low, b_low)): 1 if both triangles face `outward`. */
static int shell_split_faces_out(const double *b, const double *a, const double *a_low, const double *b_low,
                                 const double outward[3], int diagonal)
{
  if (diagonal == 1) return shell_faces_out(b, a, b_low, outward) && shell_faces_out(a, a_low, b_low, outward);
  return shell_faces_out(b, a, a_low, outward) && shell_faces_out(b, a_low, b_low, outward);
}

/* 1 if that split's two triangles face the same way (the quad does not fold along the diagonal): a test
 * of the four corners alone, so the prisms on both sides of the quad decide alike. */
static int shell_split_flat(const double *b, const double *a, const double *a_low, const double *b_low, int diagonal)
{
  const double *p[2][3] = {{b, a, b_low}, {a, a_low, b_low}}, *q[2][3] = {{b, a, a_low}, {b, a_low, b_low}};
  const double *(*t)[3] = diagonal == 1 ? p : q;
  double n[2][3];
  for (int k = 0; k < 2; k++) {
    double f1[3], f2[3];
    shell_sub(t[k][1], t[k][0], f1);
    shell_sub(t[k][2], t[k][0], f2);
    shell_cross(f1, f2, n[k]);
  }
  return shell_dot(n[0], n[1]) > 0.0;
}

static void shell_edge_outward(const double *a, const double *b, const double normal[3], double outward[3])
{
  double edge[3];
  shell_sub(b, a, edge);
  shell_cross(edge, normal, outward);
}

/* The diagonal (1 or 2, as shell_split_faces_out) that splits the side quad over the top edge c -> c + 1: the one
 * starting at the top vertex of the lower global number, so the prism across this edge splits the shared quad the
 * same way; unless the quad folds along that diagonal (a non-convex quad), then the other, which the prism across
 * decides alike from the same four corners. */
static int shell_side_diagonal(const double v[3][3], const double b[3][3], const int ids[3], int c)
{
  int next = (c + 1) % 3;
  int diagonal = ids[c] < ids[next] ? 1 : 2;
  if (!shell_split_flat(v[next], v[c], b[c], b[next], diagonal)) diagonal = 3 - diagonal;
  return diagonal;
}

/* Six times the signed volume of the tetrahedron (p, q, r, s). */
static double shell_orient(const double *p, const double *q, const double *r, const double *s)
{
  double u[3], w[3], x[3], n[3];
  shell_sub(q, p, u);
  shell_sub(r, p, w);
  shell_sub(s, p, x);
  shell_cross(u, w, n);
  return shell_dot(n, x);
}

/* The radius of the largest ball inside every face's half-space (the faces' outward planes through their corners,
 * degenerate faces left out): > 0 if some point sees every face from inside, i.e. the solid is star-shaped about
 * it. A linear programme in (x, r) over 8 constraints n . x + r <= d, solved by trying every 4 of them as the
 * active set; corners relative to `centre`. */
static double shell_kernel_radius(const double *corner[6], const int faces[8][3], const double centre[3])
{
  double plane[8][4], size = 0.0;
  int count = 0;
  for (int c = 0; c < 6; c++) {
    double y[3];
    shell_sub(corner[c], centre, y);
    if (shell_dot(y, y) > size * size) size = sqrt(shell_dot(y, y));
  }
  for (int f = 0; f < 8; f++) {
    double p[3][3], e1[3], e2[3], n[3];
    for (int c = 0; c < 3; c++) shell_sub(corner[faces[f][c]], centre, p[c]);
    if (!(shell_frame(p[0], p[1], p[2], e1, e2, n) > 0.0)) continue;
    for (int k = 0; k < 3; k++) plane[count][k] = n[k];
    plane[count][3] = shell_dot(n, p[0]) / 3.0 + shell_dot(n, p[1]) / 3.0 + shell_dot(n, p[2]) / 3.0;
    count++;
  }
  double best = -1e300;
  for (int i = 0; i < count; i++)
    for (int j = i + 1; j < count; j++)
      for (int k = j + 1; k < count; k++)
        for (int l = k + 1; l < count; l++) {
          const int rows[4] = {i, j, k, l};
          double a[4][5];
          for (int r = 0; r < 4; r++) {
            for (int q = 0; q < 3; q++) a[r][q] = plane[rows[r]][q];
            a[r][3] = 1.0;
            a[r][4] = plane[rows[r]][3];
          }
          int singular = 0;
          for (int col = 0; col < 4 && !singular; col++) {
            int pivot = col;
            for (int r = col + 1; r < 4; r++)
              if (fabs(a[r][col]) > fabs(a[pivot][col])) pivot = r;
            if (fabs(a[pivot][col]) < 1e-12) {
              singular = 1;
              break;
            }
            for (int q = 0; q < 5; q++) {
              double swap = a[col][q];
              a[col][q] = a[pivot][q];
              a[pivot][q] = swap;
            }
            for (int r = 0; r < 4; r++)
              if (r != col) {
                double factor = a[r][col] / a[col][col];
                for (int q = col; q < 5; q++) a[r][q] -= factor * a[col][q];
              }
          }
          if (singular) continue;
          double x[4];
          for (int r = 0; r < 4; r++) x[r] = a[r][4] / a[r][r];
          if (!(x[3] > best)) continue;
          int feasible = 1;
          for (int r = 0; r < count && feasible; r++)
            feasible =
                plane[r][0] * x[0] + plane[r][1] * x[1] + plane[r][2] * x[2] + x[3] <= plane[r][3] + 1e-12 * size;
          if (feasible) best = x[3];
        }
  return best;
}

/* 1 if the prism's surface, split as poly_mesh_shell_prism splits it, bounds a region of winding number 0 or 1
 * only, never -1 (no part of the prism inside out), with a margin (`margin` relative to the prism's depth). The
 * certificate is a decomposition of the prism into tetrahedra that all turn the right way: their signed
 * indicators sum to the prism's winding number, so it is >= 0 everywhere. First, when the three side diagonals
 * run one way round (each from the top of one vertex to the bottom of the next: s -> m, m -> t and s -> t), the
 * three tetrahedra (s, m, t, t'), (s, m, m', t'), (s, s', m', t'); else (a twisted prism, whose diagonals run in
 * a cycle and which has no such decomposition, or a non-convex one) the eight cones to its faces from a point
 * that sees every face from inside: the mean of the corners, or else the centre of the largest ball in all the
 * faces' inner half-spaces (shell_kernel_radius). The overlap core returns nothing for a prism's inside-out part
 * (a negative volume), so a prism that fails this drops volume while its neighbours, which reach into the region
 * it turns over, count that region as their own. */
static int shell_prism_certified(const double v[3][3], const double b[3][3], const int ids[3], double margin)
{
  const double *corner[6] = {v[0], v[1], v[2], b[0], b[1], b[2]};
  double e1[3], e2[3], normal[3];
  double doubled_area = shell_frame(v[0], v[1], v[2], e1, e2, normal), deepest = 0.0;
  for (int c = 0; c < 3; c++) {
    double d[3];
    shell_sub(v[c], b[c], d);
    double length = sqrt(shell_dot(d, d));
    if (length > deepest) deepest = length;
  }
  const double limit = margin * doubled_area * deepest;
  int out_degree[3] = {0, 0, 0}, in_degree[3] = {0, 0, 0};
  int diagonals[3];
  for (int c = 0; c < 3; c++) {
    int next = (c + 1) % 3;
    diagonals[c] = shell_side_diagonal(v, b, ids, c);
    int from = diagonals[c] == 1 ? c : next, to = diagonals[c] == 1 ? next : c;
    out_degree[from]++;
    in_degree[to]++;
  }
  int s = -1, t = -1;
  for (int c = 0; c < 3; c++) {
    if (out_degree[c] == 2) s = c;
    if (in_degree[c] == 2) t = c;
  }
  if (s >= 0 && t >= 0) {
    int m = 3 - s - t;
    /* +1 if (s, m, t) runs round the top as (0, 1, 2) does; the tetrahedra's signs in a straight prism follow. */
    double parity = (m == (s + 1) % 3) ? 1.0 : -1.0;
    if (-parity * shell_orient(corner[s], corner[m], corner[t], corner[t + 3]) > limit &&
        parity * shell_orient(corner[s], corner[m], corner[m + 3], corner[t + 3]) > limit &&
        -parity * shell_orient(corner[s], corner[s + 3], corner[m + 3], corner[t + 3]) > limit)
      return 1;
  }
  /* The eight faces as poly_mesh_shell_prism orders them. */
  double centre[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < 6; c++)
    for (int k = 0; k < 3; k++) centre[k] += corner[c][k] / 6.0;
  int faces[8][3] = {{0, 1, 2}, {3, 5, 4}}, count = 2;
  for (int c = 0; c < 3; c++) {
    int a = c, n = (c + 1) % 3;
    if (diagonals[c] == 1) {
      faces[count][0] = n, faces[count][1] = a, faces[count][2] = n + 3, count++;
      faces[count][0] = a, faces[count][1] = a + 3, faces[count][2] = n + 3, count++;
    } else {
      faces[count][0] = n, faces[count][1] = a, faces[count][2] = a + 3, count++;
      faces[count][0] = n, faces[count][1] = a + 3, faces[count][2] = n + 3, count++;
    }
  }
  int seen = 1;
  for (int f = 0; f < 8 && seen; f++)
    seen = -shell_orient(corner[faces[f][0]], corner[faces[f][1]], corner[faces[f][2]], centre) > limit;
  return seen || shell_kernel_radius(corner, (const int (*)[3])faces, centre) > margin * deepest;
}

enum { SHELL_PRISM_PROPER = 0, SHELL_PRISM_FOLDED = 1, SHELL_PRISM_INSIDE_OUT = 2 };

/* SHELL_PRISM_PROPER if the prism over top corners v with bottom corners b is a proper solid: the bottom faces
 * the same way as the top and every side quad has a split (a non-convex quad only one) whose triangles face
 * outward (else SHELL_PRISM_FOLDED), and the prism as split is nowhere inside out (shell_prism_certified,
 * tetrahedra at least `margin` in volume; else SHELL_PRISM_INSIDE_OUT). */
static int shell_prism_state(const double v[3][3], const double b[3][3], const int ids[3], double margin)
{
  double e1[3], e2[3], normal[3], bottom_e1[3], bottom_e2[3], bottom[3];
  shell_frame(v[0], v[1], v[2], e1, e2, normal);
  shell_sub(b[1], b[0], bottom_e1);
  shell_sub(b[2], b[0], bottom_e2);
  shell_cross(bottom_e1, bottom_e2, bottom);
  if (!(shell_dot(bottom, normal) > 0.0)) return SHELL_PRISM_FOLDED;
  for (int c = 0; c < 3; c++) {
    int next = (c + 1) % 3;
    double outward[3];
    shell_edge_outward(v[c], v[next], normal, outward);
    if (!shell_split_faces_out(v[next], v[c], b[c], b[next], outward, 1) &&
        !shell_split_faces_out(v[next], v[c], b[c], b[next], outward, 2))
      return SHELL_PRISM_FOLDED;
  }
  return shell_prism_certified(v, b, ids, margin) ? SHELL_PRISM_PROPER : SHELL_PRISM_INSIDE_OUT;
}

/* Triangle t's top and bottom corners at the vertex depths during the build, and its prism's state (with a
 * margin, so that the same prism moved rigidly, rounded differently, is still proper). */
static int shell_build_prism_state(const poly_mesh_shell *shell, const double *corners,
                                   const double *vertex_directions, const double *depth, int t, double v[3][3],
                                   double b[3][3])
{
  const int *ids = shell->vertex_ids + 3 * t;
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 3; k++) {
      v[c][k] = corners[9 * t + 3 * c + k];
      b[c][k] = v[c][k] - shell->thickness * depth[ids[c]] * vertex_directions[3 * ids[c] + k];
    }
  return shell_prism_state((const double (*)[3])v, (const double (*)[3])b, ids, 1e-9);
}

/* Vertex depths (fractions of h): shrunk where a triangle's full-depth prism folds, until none does. */
static void shell_limit_depths(poly_mesh_shell *shell, const double *corners, const double *vertex_directions,
                               double *depth)
{
  for (int i = 0; i < shell->num_vertices; i++) depth[i] = 1.0;
  for (int pass = 0; pass < 200; pass++) {
    int changed = 0;
    for (int t = 0; t < shell->num_triangles; t++) {
      double v[3][3], b[3][3];
      const int *ids = shell->vertex_ids + 3 * t;
      int state = shell_build_prism_state(shell, corners, vertex_directions, depth, t, v, b);
      if (state == SHELL_PRISM_PROPER) continue;
      if (state == SHELL_PRISM_FOLDED) {
        /* Corners whose direction leans away from the face normal push the bottom sideways: they give
         * way most. The others give a little too, which also ends exact coincidences (a bottom corner
         * on the line of a side quad's diagonal) that no shrinking of the leaning corners alone ends. */
        double e1[3], e2[3], normal[3];
        shell_frame(v[0], v[1], v[2], e1, e2, normal);
        for (int c = 0; c < 3; c++)
          depth[ids[c]] *= shell_dot(vertex_directions + 3 * ids[c], normal) < 1.0 - 1e-9 ? 0.9 : 0.97;
      } else {
        /* Inside out: the corner that reaches deepest behind the triangle gives way (next to a sharp
         * convex edge, a corner one cell from the edge goes back along its own face's normal, past the
         * edge's bisecting plane, where the corners on the edge, already shrunk, go back along it). */
        double e1[3], e2[3], normal[3], behind[3], deepest = 0.0;
        shell_frame(v[0], v[1], v[2], e1, e2, normal);
        for (int c = 0; c < 3; c++) {
          behind[c] = depth[ids[c]] * shell_dot(vertex_directions + 3 * ids[c], normal);
          if (behind[c] > deepest) deepest = behind[c];
        }
        for (int c = 0; c < 3; c++)
          if (behind[c] >= (1.0 - 1e-9) * deepest) depth[ids[c]] *= 0.9;
      }
      changed = 1;
    }
    if (!changed) break;
  }
  shell->min_depth_fraction = 1.0;
  for (int i = 0; i < shell->num_vertices; i++)
    if (depth[i] < shell->min_depth_fraction) shell->min_depth_fraction = depth[i];
  shell->num_folded = 0;
  for (int t = 0; t < shell->num_triangles; t++) {
    double v[3][3], b[3][3];
    shell->num_folded +=
        shell_build_prism_state(shell, corners, vertex_directions, depth, t, v, b) != SHELL_PRISM_PROPER;
  }
}

int poly_mesh_shell_build(const double *corners, int num_triangles, double thickness, double relative_tolerance,
                          poly_mesh_shell *shell, char *message, size_t message_size)
{
  memset(shell, 0, sizeof *shell);
  shell->min_corner_cosine = 1.0;
  shell->thickness = thickness;
  double *depth = NULL;
  if (num_triangles <= 0) {
    snprintf(message, message_size, "the mesh has no triangles");
    return -1;
  }
  poly_mesh soup;
  soup.num_vertices = 3 * num_triangles;
  soup.num_triangles = num_triangles;
  soup.vertices = (double *)malloc(sizeof(double) * 9 * (size_t)num_triangles);
  soup.triangles = (int *)malloc(sizeof(int) * 3 * (size_t)num_triangles);
  double *vertex_directions = NULL;
  shell_edge *edges = (shell_edge *)malloc(sizeof(shell_edge) * 3 * (size_t)num_triangles);
  shell->corner_directions = (double *)malloc(sizeof(double) * 9 * (size_t)num_triangles);
  if (!soup.vertices || !soup.triangles || !edges || !shell->corner_directions) goto out_of_memory;
  memcpy(soup.vertices, corners, sizeof(double) * 9 * (size_t)num_triangles);
  for (int c = 0; c < 3 * num_triangles; c++) soup.triangles[c] = c;
  if (poly_mesh_weld(&soup, relative_tolerance) < 0) goto out_of_memory;
  shell->num_triangles = num_triangles;
  shell->num_vertices = soup.num_vertices;
  shell->vertex_ids = soup.triangles;
  soup.triangles = NULL;

  /* Angle-weighted mean normal per vertex. */
  vertex_directions = (double *)calloc(3 * (size_t)soup.num_vertices, sizeof(double));
  if (!vertex_directions) goto out_of_memory;
  for (int t = 0; t < num_triangles; t++) {
    const double *v = corners + 9 * t;
    double e1[3], e2[3], normal[3];
    if (shell_frame(v, v + 3, v + 6, e1, e2, normal) <= 0.0) {
      snprintf(message, message_size, "triangle %d has zero area", t);
      goto failed;
    }
    for (int c = 0; c < 3; c++) {
      double to_next[3], to_previous[3];
      shell_sub(v + 3 * ((c + 1) % 3), v + 3 * c, to_next);
      shell_sub(v + 3 * ((c + 2) % 3), v + 3 * c, to_previous);
      double cosine = shell_dot(to_next, to_previous) / sqrt(shell_dot(to_next, to_next) * shell_dot(to_previous, to_previous));
      double angle = acos(cosine < -1.0 ? -1.0 : cosine > 1.0 ? 1.0 : cosine);
      double *m = vertex_directions + 3 * shell->vertex_ids[3 * t + c];
      for (int k = 0; k < 3; k++) m[k] += angle * normal[k];
    }
    for (int c = 0; c < 3; c++) {
      int a = shell->vertex_ids[3 * t + c], b = shell->vertex_ids[3 * t + (c + 1) % 3];
      if (a == b) {
        snprintf(message, message_size, "triangle %d has two coincident corners", t);
        goto failed;
      }
      shell_edge edge = {a < b ? a : b, a < b ? b : a, a < b};
      edges[3 * t + c] = edge;
    }
  }
  for (int i = 0; i < soup.num_vertices; i++)
    if (shell_normalize(vertex_directions + 3 * i) <= 0.0) {
      /* Normals around the vertex cancel: a fold back onto itself. */
      snprintf(message, message_size, "the normals around a vertex cancel (the mesh folds back at (%g, %g, %g))",
               soup.vertices[3 * i], soup.vertices[3 * i + 1], soup.vertices[3 * i + 2]);
      goto failed;
    }

  depth = (double *)malloc(sizeof(double) * (size_t)soup.num_vertices);
  if (!depth) goto out_of_memory;
  shell_limit_depths(shell, corners, vertex_directions, depth);

  /* Each corner's direction in its triangle's frame, times its depth: m = a e1 + b e2 + c n. */
  for (int t = 0; t < num_triangles; t++) {
    const double *v = corners + 9 * t;
    double e1[3], e2[3], normal[3];
    shell_frame(v, v + 3, v + 6, e1, e2, normal);
    double g11 = shell_dot(e1, e1), g12 = shell_dot(e1, e2), g22 = shell_dot(e2, e2), det = g11 * g22 - g12 * g12;
    for (int c = 0; c < 3; c++) {
      const int id = shell->vertex_ids[3 * t + c];
      const double *unit = vertex_directions + 3 * id;
      if (shell_dot(unit, normal) < shell->min_corner_cosine) shell->min_corner_cosine = shell_dot(unit, normal);
      double m[3] = {depth[id] * unit[0], depth[id] * unit[1], depth[id] * unit[2]};
      double along = shell_dot(m, normal);
      double in_plane[3] = {m[0] - along * normal[0], m[1] - along * normal[1], m[2] - along * normal[2]};
      double r1 = shell_dot(in_plane, e1), r2 = shell_dot(in_plane, e2);
      double *coefficients = shell->corner_directions + 9 * t + 3 * c;
      coefficients[0] = (g22 * r1 - g12 * r2) / det;
      coefficients[1] = (g11 * r2 - g12 * r1) / det;
      coefficients[2] = along;
    }
  }
  shell_count_edges(shell, edges, 3 * num_triangles);
  free(depth);
  free(vertex_directions);
  free(edges);
  free(soup.vertices);
  return 0;

out_of_memory:
  snprintf(message, message_size, "out of memory for a mesh of %d triangles", num_triangles);
failed:
  free(depth);
  free(vertex_directions);
  free(edges);
  free(soup.vertices);
  free(soup.triangles);
  poly_mesh_shell_free(shell);
  return -1;
}

void poly_mesh_shell_free(poly_mesh_shell *shell)
{
  free(shell->vertex_ids);
  free(shell->corner_directions);
  shell->vertex_ids = NULL;
  shell->corner_directions = NULL;
}

/* Vertices 0-2 the triangle, 3-5 behind 0-2. Top and bottom faces, then two
 * triangles per side quad (b, a, a', b') over edge a -> b of the top. */
static int prism_add_triangle(int *triangles, int count, int a, int b, int c)
{
  triangles[3 * count] = a;
  triangles[3 * count + 1] = b;
  triangles[3 * count + 2] = c;
  return count + 1;
}

/* The prism's supporting triangles (every corner on or behind the plane, to 1e-12 of its size: the
 * separation test of the overlap) and, when all 8 support it (a convex prism: side quads planar or folded
 * outwards, as over a flat or convex stretch of wall), its faces (coplanar triangles merged) and ridges, so
 * that a convex particle no clipping path takes and it take the convex path. Otherwise the general path (a side
 * quad folded inwards makes the prism non-convex). */
/* clip_view: the view with its clip pointing at the prism's own clip arrays (num_faces faces found by
 * prism_clip_faces or prism_clip_tetrahedra; their other counts in the prism). */
static void prism_bind_clip(poly_mesh_prism *prism, int num_faces)
{
  prism->clip_view = prism->view;
  poly_clip_faces *clip = &prism->clip_view.clip;
  memset(clip, 0, sizeof *clip);
  clip->num_faces = num_faces;
  clip->num_planes = prism->clip_num_planes;
  clip->num_vertices = 6;
  clip->vertices = prism->vertices;
  clip->planes = prism->clip_planes;
  clip->loop_start = prism->clip_loop_start;
  clip->loop = prism->clip_loop;
  clip->triangle = prism->clip_face_triangle;
  clip->num_pieces = prism->clip_num_pieces;
  clip->piece_front = prism->clip_piece_front;
  clip->piece_back = prism->clip_piece_back;
  clip->piece_point_start = prism->clip_piece_point_start;
  clip->piece_points = prism->clip_piece_points;
  clip->piece_face_start = prism->clip_piece_face_start;
  clip->piece_faces = prism->clip_piece_faces;
  clip->plane_support = prism->clip_plane_support;
  clip->support_planes.low = clip->support_planes.high = 0ull;
  for (int k = 0; k < prism->clip_num_planes; k++)
    if (prism->clip_plane_support[k] >= 0) clip->support_planes.low |= 1ull << k;
  clip->face_plane = prism->clip_face_plane;
  clip->many_faces = 0;
  clip->facets = 0;
  prism->mesh_view = prism->clip_view;
  prism->mesh_view.clip.facets = 1;  /* a convex prism's merged faces, or its split's triangles: whole facets */
}

/* A convex prism's faces as the clipping path takes them (as poly_convex.c's find_clip_faces does for a shape):
 * per face the plane of its lowest triangle and its boundary edges chained in the triangles' order; one piece.
 * Every triangle supports a convex prism, so support[m] = m and a face's supporting triangle is its own. */
static void prism_clip_faces(poly_mesh_prism *prism)
{
  int num_faces = 0, used = 0;
  for (int t = 0; t < 8; t++) {
    if (prism->face_of[t] != t) continue;
    const int f = num_faces++;
    const double *n = prism->face_normals + 3 * t, *x = prism->vertices + 3 * prism->triangles[3 * t];
    for (int k = 0; k < 3; k++) prism->clip_planes[4 * f + k] = n[k];
    prism->clip_planes[4 * f + 3] = shell_dot(n, x);
    prism->clip_face_triangle[f] = prism->clip_plane_support[f] = t;
    prism->clip_face_plane[f] = prism->clip_piece_faces[f] = f;
    int next[6] = {-1, -1, -1, -1, -1, -1}, first = -1, count = 0;
    for (int e = 0; e < prism->view.num_edges; e++) {
      int t0 = prism->edge_triangles[2 * e], t1 = prism->edge_triangles[2 * e + 1];
      if (prism->face_of[t0] == prism->face_of[t1]) continue;
      int a = prism->edges[2 * e], b = prism->edges[2 * e + 1];
      if (prism->face_of[t0] == t) next[a] = b, first = a, count++;
      else if (prism->face_of[t1] == t) next[b] = a, first = b, count++;
    }
    prism->clip_loop_start[f] = used;
    for (int v = first, steps = 0; steps < count; steps++, v = next[v]) {
      if (v < 0) return;  /* not one loop: cannot happen for a proper prism; the other paths take it */
      prism->clip_loop[used++] = v;
    }
  }
  prism->clip_loop_start[num_faces] = used;
  prism->clip_num_planes = num_faces;
  prism->clip_num_pieces = 1;
  prism->clip_piece_front[0].low = (1ull << num_faces) - 1ull;
  prism->clip_piece_front[0].high = prism->clip_piece_back[0].low = prism->clip_piece_back[0].high = 0ull;
  prism->clip_piece_point_start[0] = prism->clip_piece_face_start[0] = 0;
  prism->clip_piece_point_start[1] = 6;
  prism->clip_piece_face_start[1] = num_faces;
  for (int v = 0; v < 6; v++) prism->clip_piece_points[v] = v;
  prism_bind_clip(prism, num_faces);
}

/* Index of plane (n, offset) among the prism's clip planes, added when new (within 1e-12 of the prism's size;
 * -1 when the 10 it holds are taken); *opposite 1 when it is stored facing the other way. */
static int prism_plane(poly_mesh_prism *prism, const double *n, double offset, int *opposite)
{
  const double tolerance = 1e-12 * prism->view.bounding_radius;
  for (int k = 0; k < prism->clip_num_planes; k++) {
    const double *q = prism->clip_planes + 4 * k, cosine = shell_dot(n, q);
    *opposite = cosine < 0.0;
    if (fabs(cosine) > 1.0 - 1e-12 && fabs(*opposite ? offset + q[3] : offset - q[3]) <= tolerance) return k;
  }
  if (prism->clip_num_planes == 10) return -1;
  const int k = prism->clip_num_planes++;
  for (int c = 0; c < 3; c++) prism->clip_planes[4 * k + c] = n[c];
  prism->clip_planes[4 * k + 3] = offset;
  *opposite = 0;
  return k;
}

/* A prism that is not convex as the three tetrahedra of its split, pieces for the clipping path: `diagonals` (per
 * side c, 1 when its diagonal runs from top corner c to bottom corner c + 1, else 2) must run from one top corner
 * s to both others' bottoms and from both others' tops to one bottom t (no cycle: else it keeps the general path),
 * and each tetrahedron must have a volume. The faces are the prism's 8 triangles, each on the tetrahedron that has
 * its corners; the planes theirs (a planar side's two triangles share one) and the two between the tetrahedra. */
static void prism_clip_tetrahedra(poly_mesh_prism *prism, const int diagonals[3])
{
  int out_degree[3] = {0, 0, 0}, in_degree[3] = {0, 0, 0}, s = -1, t = -1;
  for (int c = 0; c < 3; c++) {
    int next = (c + 1) % 3;
    out_degree[diagonals[c] == 1 ? c : next]++;
    in_degree[diagonals[c] == 1 ? next : c]++;
  }
  for (int c = 0; c < 3; c++) {
    if (out_degree[c] == 2) s = c;
    if (in_degree[c] == 2) t = c;
  }
  if (s < 0 || t < 0) return;
  const int m = 3 - s - t;
  const int tetrahedra[3][4] = {{s, m, t, t + 3}, {s, m, m + 3, t + 3}, {s, s + 3, m + 3, t + 3}};
  const double tolerance = 1e-9 * prism->view.bounding_radius;
  prism->clip_num_planes = 0;
  int face_piece[8];
  for (int f = 0; f < 8; f++) {
    const int *tri = prism->triangles + 3 * f;
    const double *n = prism->face_normals + 3 * f;
    int opposite;
    prism->clip_face_plane[f] = prism_plane(prism, n, shell_dot(n, prism->vertices + 3 * tri[0]), &opposite);
    if (prism->clip_face_plane[f] < 0) return;
    face_piece[f] = -1;
    for (int p = 0; p < 3 && face_piece[f] < 0; p++) {
      int found = 0;
      for (int c = 0; c < 3; c++)
        for (int v = 0; v < 4; v++) found += tetrahedra[p][v] == tri[c];
      if (found == 3) face_piece[f] = p;
    }
    if (face_piece[f] < 0 || opposite) return;
    prism->clip_face_triangle[f] = f;
    for (int c = 0; c < 3; c++) prism->clip_loop[3 * f + c] = tri[c];
    prism->clip_loop_start[f] = 3 * f;
  }
  prism->clip_loop_start[8] = 24;
  /* Each tetrahedron behind the planes of its four faces (outward: away from the corner opposite). */
  int used_faces = 0;
  for (int p = 0; p < 3; p++) {
    prism->clip_piece_front[p].low = prism->clip_piece_front[p].high = 0ull;
    prism->clip_piece_back[p].low = prism->clip_piece_back[p].high = 0ull;
    for (int opposite_corner = 0; opposite_corner < 4; opposite_corner++) {
      const double *x[3], *apex = prism->vertices + 3 * tetrahedra[p][opposite_corner];
      for (int c = 0, k = 0; c < 4; c++)
        if (c != opposite_corner) x[k++] = prism->vertices + 3 * tetrahedra[p][c];
      double u[3], w[3], n[3];
      shell_sub(x[1], x[0], u);
      shell_sub(x[2], x[0], w);
      shell_cross(u, w, n);
      if (!(shell_normalize(n) > 0.0)) return;
      double offset = shell_dot(n, x[0]), height = shell_dot(n, apex) - offset;
      if (height > 0.0) {
        for (int k = 0; k < 3; k++) n[k] = -n[k];
        offset = -offset;
        height = -height;
      }
      if (!(-height > tolerance)) return;  /* a flat tetrahedron */
      int opposite, k = prism_plane(prism, n, offset, &opposite);
      if (k < 0) return;
      if (opposite) prism->clip_piece_back[p].low |= 1ull << k;
      else prism->clip_piece_front[p].low |= 1ull << k;
    }
    prism->clip_piece_point_start[p] = 4 * p;
    prism->clip_piece_face_start[p] = used_faces;
    for (int c = 0; c < 4; c++) prism->clip_piece_points[4 * p + c] = tetrahedra[p][c];
    for (int f = 0; f < 8; f++)
      if (face_piece[f] == p) prism->clip_piece_faces[used_faces++] = f;
  }
  prism->clip_piece_point_start[3] = 12;
  prism->clip_piece_face_start[3] = used_faces;
  /* Each triangle's plane must be one its tetrahedron lies behind: a tetrahedron turned inside out (a split that
   * the prism's certification passed by its star-shaped test instead) has its triangles' planes facing into it,
   * and the three would overlap. Such a prism keeps the general path. */
  for (int f = 0; f < 8; f++) {
    const int p = face_piece[f], k = prism->clip_face_plane[f];
    if (!((prism->clip_piece_front[p].low >> k) & 1ull) || ((prism->clip_piece_back[p].low >> k) & 1ull)) return;
  }
  /* A plane supports the prism where one of its supporting triangles lies on it (the separation test). */
  for (int k = 0; k < prism->clip_num_planes; k++) {
    prism->clip_plane_support[k] = -1;
    for (int q = 0; q < prism->view.num_support && prism->clip_plane_support[k] < 0; q++)
      if (prism->clip_face_plane[prism->support[q]] == k) prism->clip_plane_support[k] = q;
  }
  prism->clip_num_pieces = 3;
  prism_bind_clip(prism, 8);
}

static void prism_faces(poly_mesh_prism *prism)
{
  const double tolerance = 1e-12 * prism->view.bounding_radius;
  int num_support = 0;
  for (int t = 0; t < 8; t++) {
    const double *n = prism->face_normals + 3 * t, *origin = prism->vertices + 3 * prism->triangles[3 * t];
    int behind = 1;
    for (int c = 0; c < 6 && behind; c++) {
      double offset[3];
      shell_sub(prism->vertices + 3 * c, origin, offset);
      behind = shell_dot(n, offset) <= tolerance;
    }
    if (behind) prism->support[num_support++] = t;
  }
  prism->view.support = prism->support;
  prism->view.num_support = num_support;
  prism->view.extreme_start = prism->view.extreme_vertices = NULL; /* 6 vertices: scanned */
  prism->view.face_of = prism->view.ridges = NULL;
  prism->view.triangle_edges = NULL;
  prism->view.num_ridges = 0;
  memset(&prism->view.clip, 0, sizeof prism->view.clip);
  memset(&prism->clip_view.clip, 0, sizeof prism->clip_view.clip);  /* until poly_mesh_prism_clip_faces */
  prism->clip_state = 0;
  if (num_support < 8) return;
  for (int t = 0; t < 8; t++) prism->face_of[t] = t;
  /* Merge the two triangles of an edge when they lie in one plane (a planar side quad); a prism's faces are
   * at most such pairs, so one pass names each face by its lower triangle. */
  for (int e = 0; e < prism->view.num_edges; e++) {
    int t = prism->edge_triangles[2 * e], u = prism->edge_triangles[2 * e + 1];
    const double *n = prism->face_normals + 3 * t, *m = prism->face_normals + 3 * u;
    if (shell_dot(n, m) < 1.0 - 1e-12) continue;
    const double *origin = prism->vertices + 3 * prism->triangles[3 * t];
    int flat = 1;
    for (int c = 0; c < 3 && flat; c++) {
      double offset[3];
      shell_sub(prism->vertices + 3 * prism->triangles[3 * u + c], origin, offset);
      flat = fabs(shell_dot(n, offset)) <= tolerance;
    }
    if (!flat) continue;
    int low = t < u ? t : u, high = t < u ? u : t;
    prism->face_of[high] = prism->face_of[low];
  }
  int num_ridges = 0;
  for (int e = 0; e < prism->view.num_edges; e++)
    if (prism->face_of[prism->edge_triangles[2 * e]] != prism->face_of[prism->edge_triangles[2 * e + 1]])
      prism->ridges[num_ridges++] = e;
  prism->view.face_of = prism->face_of;
  prism->view.ridges = prism->ridges;
  prism->view.num_ridges = num_ridges;
}

void poly_mesh_prism_clip_faces(poly_mesh_prism *prism)
{
  if (prism->clip_state) return;
  prism->clip_state = 1;
  if (prism->view.face_of) prism_clip_faces(prism);
  else prism_clip_tetrahedra(prism, prism->diagonals);
}

const poly_shape_view_d *poly_mesh_prism_view(poly_mesh_prism *prism, const poly_shape_view_d *particle)
{
  const int clips = poly_clip_takes(&particle->clip);
  const int meshes = POLY_CLIP_MESH_PATH && poly_clip_mesh_fits(particle);
  if (!clips && !meshes) return &prism->view;
  poly_mesh_prism_clip_faces(prism);
  if (prism->clip_view.clip.num_faces == 0) return &prism->view;
  if (!meshes) return &prism->clip_view;
  if (!clips || POLY_CLIP_MESH_PATH == 2 || particle->clip.many_faces) return &prism->mesh_view;
  if (particle->clip.num_pieces == 1) return &prism->clip_view;
  /* Shapes in pieces: the mesh path where the triangle is larger than the particle (the top's corners 0-2). */
  double longest2 = 0.0;
  for (int c = 0; c < 3; c++) {
    const double *u = prism->vertices + 3 * c, *v = prism->vertices + 3 * ((c + 1) % 3);
    const double d2 = (v[0] - u[0]) * (v[0] - u[0]) + (v[1] - u[1]) * (v[1] - u[1]) + (v[2] - u[2]) * (v[2] - u[2]);
    longest2 = d2 > longest2 ? d2 : longest2;
  }
  const double reach = 3.0 * particle->bounding_radius;
  return longest2 >= reach * reach ? &prism->mesh_view : &prism->clip_view;
}

int poly_mesh_shell_prism(const poly_mesh_shell *shell, int triangle, const double nodes[3][3],
                          poly_mesh_prism *prism)
{
  const double thickness = shell->thickness;
  double e1[3], e2[3], normal[3];
  if (shell_frame(nodes[0], nodes[1], nodes[2], e1, e2, normal) <= 0.0) return -1;
  double corner[6][3];
  for (int c = 0; c < 3; c++) {
    const double *coefficients = shell->corner_directions + 9 * triangle + 3 * c;
    for (int k = 0; k < 3; k++) {
      double m = coefficients[0] * e1[k] + coefficients[1] * e2[k] + coefficients[2] * normal[k];
      corner[c][k] = nodes[c][k];
      corner[c + 3][k] = nodes[c][k] - thickness * m;
    }
  }
  const int *ids = shell->vertex_ids + 3 * triangle;
  const double (*top)[3] = (const double (*)[3])corner, (*bottom)[3] = (const double (*)[3])(corner + 3);
  if (shell_prism_state(top, bottom, ids, 0.0) != SHELL_PRISM_PROPER) return -1;
  for (int k = 0; k < 3; k++) {
    double sum = 0.0;
    for (int c = 0; c < 6; c++) sum += corner[c][k];
    prism->origin[k] = sum / 6.0;
  }
  double radius2 = 0.0;
  for (int c = 0; c < 6; c++) {
    double *y = prism->vertices + 3 * c;
    shell_sub(corner[c], prism->origin, y);
    double r2 = shell_dot(y, y);
    if (r2 > radius2) radius2 = r2;
  }

  int count = 0;
  count = prism_add_triangle(prism->triangles, count, 0, 1, 2);
  count = prism_add_triangle(prism->triangles, count, 3, 5, 4);
  for (int c = 0; c < 3; c++) {
    int a = c, b = (c + 1) % 3;
    int diagonal = prism->diagonals[c] = shell_side_diagonal(top, bottom, ids, c);
    if (diagonal == 1) {
      count = prism_add_triangle(prism->triangles, count, b, a, b + 3);
      count = prism_add_triangle(prism->triangles, count, a, a + 3, b + 3);
    } else {
      count = prism_add_triangle(prism->triangles, count, b, a, a + 3);
      count = prism_add_triangle(prism->triangles, count, b, a + 3, b + 3);
    }
  }

  /* Edges (first < second) and the triangle running first -> second, then the other. */
  int num_edges = 0;
  for (int t = 0; t < 8; t++)
    for (int c = 0; c < 3; c++) {
      int from = prism->triangles[3 * t + c], to = prism->triangles[3 * t + (c + 1) % 3];
      int low = from < to ? from : to, high = from < to ? to : from, e;
      for (e = 0; e < num_edges; e++)
        if (prism->edges[2 * e] == low && prism->edges[2 * e + 1] == high) break;
      if (e == num_edges) {
        prism->edges[2 * e] = low;
        prism->edges[2 * e + 1] = high;
        num_edges++;
      }
      prism->edge_triangles[2 * e + (from < to ? 0 : 1)] = t;
    }
  for (int t = 0; t < 8; t++) {
    const int *tri = prism->triangles + 3 * t;
    double f1[3], f2[3];
    double *n = prism->face_normals + 3 * t;
    if (shell_frame(prism->vertices + 3 * tri[0], prism->vertices + 3 * tri[1], prism->vertices + 3 * tri[2], f1, f2,
                    n) <= 0.0)
      return -1;
  }
  prism->view.num_vertices = 6;
  prism->view.num_triangles = 8;
  prism->view.num_edges = num_edges;
  prism->view.vertices = prism->vertices;
  prism->view.face_normals = prism->face_normals;
  prism->view.triangles = prism->triangles;
  prism->view.edges = prism->edges;
  prism->view.edge_triangles = prism->edge_triangles;
  prism->view.bounding_radius = sqrt(radius2);
  prism_faces(prism);
  return 0;
}

void poly_mesh_contact_combine(const poly_overlap_result *pieces, const double *nodes, const int *first_node,
                               const int *num_nodes, int count, poly_overlap_result *contact)
{
  memset(contact, 0, sizeof *contact);
  double moment[3] = {0, 0, 0}, area[3] = {0, 0, 0}, weighted[3] = {0, 0, 0};
  for (int p = 0; p < count; p++) {
    const poly_overlap_result *piece = pieces + p;
    contact->volume += piece->volume;
    contact->area += piece->area;
    contact->num_nodes += piece->num_nodes;
    contact->num_inconsistent += piece->num_inconsistent;
    contact->recomputed += piece->recomputed;
    contact->smoothed += piece->smoothed;
    for (int k = 0; k < 3; k++) {
      moment[k] += piece->volume * piece->centroid[k];
      area[k] += piece->projected_area * piece->normal[k];
      weighted[k] += piece->volume * piece->normal[k];
    }
  }
  if (!(contact->volume > 0.0)) return;
  double length = sqrt(shell_dot(area, area));
  contact->projected_area = length;
  const double *direction = length > 1e-9 * contact->area && length > 0.0 ? area : weighted;
  length = sqrt(shell_dot(direction, direction));
  for (int k = 0; k < 3; k++) {
    contact->centroid[k] = moment[k] / contact->volume;
    contact->normal[k] = length > 0.0 ? direction[k] / length : 0.0;
  }
  /* Second moments about the contact's centroid: each piece's own plus its parallel-axis term. */
  for (int p = 0; p < count; p++) {
    double offset[3];
    for (int k = 0; k < 3; k++) offset[k] = pieces[p].centroid[k] - contact->centroid[k];
    for (int e = 0; e < 6; e++) contact->second_moment[e] += pieces[p].second_moment[e];
    poly_second_moment_to_centroid(contact->second_moment, -pieces[p].volume, offset);
  }
  double low = 1e300, high = -1e300, fallback = 0.0;
  for (int p = 0; p < count; p++) {
    if (num_nodes[p] < 0) {
      double along = pieces[p].depth * shell_dot(pieces[p].normal, contact->normal);
      if (along > fallback) fallback = along;
      continue;
    }
    for (int q = 0; q < num_nodes[p]; q++) {
      double along = shell_dot(nodes + 3 * (first_node[p] + q), contact->normal);
      if (along < low) low = along;
      if (along > high) high = along;
    }
  }
  contact->depth = high > low ? high - low : 0.0;
  if (fallback > contact->depth) contact->depth = fallback;
}

/* Mesh orientation: connected surfaces, consistent and canonical winding (poly_mesh_shell.h). */

typedef struct orient_edge {
  int low, high, triangle, corner, forward;
} orient_edge;

static int orient_edge_order(const void *pa, const void *pb)
{
  const orient_edge *a = (const orient_edge *)pa, *b = (const orient_edge *)pb;
  if (a->low != b->low) return a->low < b->low ? -1 : 1;
  if (a->high != b->high) return a->high < b->high ? -1 : 1;
  return a->triangle != b->triangle ? (a->triangle < b->triangle ? -1 : 1) : a->corner - b->corner;
}

/* All triangle edges of `ids` (3 per triangle), sorted. */
static void orient_list_edges(const int *ids, int num_triangles, orient_edge *edges)
{
  for (int t = 0; t < num_triangles; t++)
    for (int c = 0; c < 3; c++) {
      int a = ids[3 * t + c], b = ids[3 * t + (c + 1) % 3];
      orient_edge edge = {a < b ? a : b, a < b ? b : a, t, c, a < b};
      edges[3 * t + c] = edge;
    }
  qsort(edges, 3 * (size_t)num_triangles, sizeof(orient_edge), orient_edge_order);
}

void poly_mesh_canonical_corners(const poly_mesh_orientation *orientation, const double *corners, int reverse,
                                 double *out)
{
  for (int t = 0; t < orientation->num_triangles; t++) {
    int swap = orientation->flip[t] ^ (reverse ? 1 : 0);
    const int order[3] = {0, swap ? 2 : 1, swap ? 1 : 2};
    for (int c = 0; c < 3; c++)
      for (int k = 0; k < 3; k++) out[9 * t + 3 * c + k] = corners[9 * t + 3 * order[c] + k];
  }
}

int poly_mesh_orient(const double *corners, int num_triangles, double relative_tolerance,
                     poly_mesh_orientation *o, char *message, size_t message_size)
{
  memset(o, 0, sizeof *o);
  if (num_triangles <= 0) {
    snprintf(message, message_size, "the mesh has no triangles");
    return -1;
  }
  const size_t n = (size_t)num_triangles;
  o->num_triangles = num_triangles;
  poly_mesh soup;
  soup.num_vertices = 3 * num_triangles;
  soup.num_triangles = num_triangles;
  soup.vertices = (double *)malloc(sizeof(double) * 9 * n);
  soup.triangles = (int *)malloc(sizeof(int) * 3 * n);
  orient_edge *edges = (orient_edge *)malloc(sizeof(orient_edge) * 3 * n);
  int *neighbour = (int *)malloc(sizeof(int) * 3 * n), *same = (int *)malloc(sizeof(int) * 3 * n);
  int *queue = (int *)malloc(sizeof(int) * n), *canonical_ids = (int *)malloc(sizeof(int) * 3 * n);
  double *canonical = (double *)malloc(sizeof(double) * 9 * n);
  o->flip = (int *)calloc(n, sizeof(int));
  o->component = (int *)malloc(sizeof(int) * n);
  o->edge_normals = (double *)malloc(sizeof(double) * 9 * n);
  o->component_closed = (int *)calloc(n, sizeof(int));
  o->component_size = (int *)calloc(n, sizeof(int));
  o->component_flipped = (int *)calloc(n, sizeof(int));
  o->component_conflicts = (int *)calloc(n, sizeof(int));
  o->component_volume = (double *)calloc(n, sizeof(double));
  int failed = !soup.vertices || !soup.triangles || !edges || !neighbour || !same || !queue || !canonical_ids ||
               !canonical || !o->flip || !o->component || !o->edge_normals || !o->component_closed ||
               !o->component_size || !o->component_flipped || !o->component_conflicts || !o->component_volume;
  if (!failed) {
    memcpy(soup.vertices, corners, sizeof(double) * 9 * n);
    for (int c = 0; c < 3 * num_triangles; c++) soup.triangles[c] = c;
    failed = poly_mesh_weld(&soup, relative_tolerance) < 0;
  }
  if (failed) {
    snprintf(message, message_size, "out of memory for a mesh of %d triangles", num_triangles);
    free(soup.vertices);
    free(soup.triangles);
    free(edges);
    free(neighbour);
    free(same);
    free(queue);
    free(canonical_ids);
    free(canonical);
    poly_mesh_orientation_free(o);
    return -1;
  }
  /* Neighbours across manifold edges; same[]: the shared edge runs the same way in both (one must flip). */
  for (size_t k = 0; k < 3 * n; k++) neighbour[k] = -1;
  orient_list_edges(soup.triangles, num_triangles, edges);
  int *open = (int *)calloc(n, sizeof(int));  /* per triangle: has an open or non-manifold edge */
  for (int first = 0; first < 3 * num_triangles;) {
    int last = first;
    while (last + 1 < 3 * num_triangles && edges[last + 1].low == edges[first].low &&
           edges[last + 1].high == edges[first].high)
      last++;
    if (last == first + 1 && edges[first].triangle != edges[last].triangle) {
      const orient_edge *a = edges + first, *b = edges + last;
      int flipped = a->forward == b->forward;
      o->num_misoriented_edges += flipped;
      neighbour[3 * a->triangle + a->corner] = b->triangle;
      neighbour[3 * b->triangle + b->corner] = a->triangle;
      same[3 * a->triangle + a->corner] = same[3 * b->triangle + b->corner] = flipped;
    } else if (open) {
      for (int e = first; e <= last; e++) open[edges[e].triangle] = 1;
    }
    first = last + 1;
  }
  /* Components by breadth-first search from the lowest-numbered triangle not yet reached. */
  for (size_t t = 0; t < n; t++) o->component[t] = -1;
  for (int seed = 0; seed < num_triangles; seed++) {
    if (o->component[seed] >= 0) continue;
    int id = o->num_components++, head = 0, tail = 0;
    o->component[seed] = id;
    o->flip[seed] = 0;
    queue[tail++] = seed;
    int closed = 1;
    while (head < tail) {
      int t = queue[head++];
      o->component_size[id]++;
      if (open && open[t]) closed = 0;
      for (int c = 0; c < 3; c++) {
        int u = neighbour[3 * t + c];
        if (u < 0) continue;
        int want = o->flip[t] ^ same[3 * t + c];
        if (o->component[u] < 0) {
          o->component[u] = id;
          o->flip[u] = want;
          queue[tail++] = u;
        } else if (o->flip[u] != want && u > t) {
          o->component_conflicts[id]++;
        }
      }
    }
    o->component_closed[id] = closed && o->component_conflicts[id] == 0;
  }
  free(open);
  /* Canonical orientation per component. */
  double *volume = o->component_volume;
  int *lowest = queue;
  for (int id = 0; id < o->num_components; id++) lowest[id] = -1;
  for (int t = 0; t < num_triangles; t++) {
    int id = o->component[t];
    if (lowest[id] < 0) lowest[id] = t;
    const double *v = corners + 9 * t;
    double cross[3];
    shell_cross(v + 3, v + 6, cross);
    double six = shell_dot(v, cross) / 6.0;
    volume[id] += o->flip[t] ? -six : six;
  }
  for (int id = 0; id < o->num_components; id++) {
    int reverse;
    if (o->component_closed[id]) {
      reverse = volume[id] < 0.0;
    } else {
      const double *v = corners + 9 * lowest[id];
      double e1[3], e2[3], normal[3];
      shell_frame(v, v + 3, v + 6, e1, e2, normal);
      int axis = 0;
      for (int k = 1; k < 3; k++)
        if (fabs(normal[k]) > fabs(normal[axis])) axis = k;
      reverse = (normal[axis] < 0.0) ^ o->flip[lowest[id]];
    }
    if (reverse) volume[id] = -volume[id];
    lowest[id] = reverse;
  }
  for (int t = 0; t < num_triangles; t++) {
    o->flip[t] ^= lowest[o->component[t]];
    o->component_flipped[o->component[t]] += o->flip[t];
  }
  /* Neighbour normals across each canonical edge, in the canonical frame. */
  poly_mesh_canonical_corners(o, corners, 0, canonical);
  for (int t = 0; t < num_triangles; t++) {
    int swap = o->flip[t];
    const int order[3] = {0, swap ? 2 : 1, swap ? 1 : 2};
    for (int c = 0; c < 3; c++) canonical_ids[3 * t + c] = soup.triangles[3 * t + order[c]];
  }
  for (size_t k = 0; k < 3 * n; k++) neighbour[k] = -1;
  orient_list_edges(canonical_ids, num_triangles, edges);
  for (int first = 0; first < 3 * num_triangles;) {
    int last = first;
    while (last + 1 < 3 * num_triangles && edges[last + 1].low == edges[first].low &&
           edges[last + 1].high == edges[first].high)
      last++;
    if (last == first + 1 && edges[first].triangle != edges[last].triangle) {
      neighbour[3 * edges[first].triangle + edges[first].corner] = edges[last].triangle;
      neighbour[3 * edges[last].triangle + edges[last].corner] = edges[first].triangle;
    }
    first = last + 1;
  }
  for (int t = 0; t < num_triangles; t++) {
    const double *v = canonical + 9 * t;
    double e1[3], e2[3], normal[3];
    shell_frame(v, v + 3, v + 6, e1, e2, normal);
    double g11 = shell_dot(e1, e1), g12 = shell_dot(e1, e2), g22 = shell_dot(e2, e2), det = g11 * g22 - g12 * g12;
    for (int c = 0; c < 3; c++) {
      double *coefficients = o->edge_normals + 9 * t + 3 * c;
      int u = neighbour[3 * t + c];
      coefficients[0] = coefficients[1] = 0.0;
      coefficients[2] = 1.0;
      if (u < 0 || !(det > 0.0)) continue;
      const double *w = canonical + 9 * u;
      double f1[3], f2[3], m[3];
      shell_frame(w, w + 3, w + 6, f1, f2, m);
      double along = shell_dot(m, normal);
      double in_plane[3] = {m[0] - along * normal[0], m[1] - along * normal[1], m[2] - along * normal[2]};
      double r1 = shell_dot(in_plane, e1), r2 = shell_dot(in_plane, e2);
      coefficients[0] = (g22 * r1 - g12 * r2) / det;
      coefficients[1] = (g11 * r2 - g12 * r1) / det;
      coefficients[2] = along;
    }
  }
  free(soup.vertices);
  free(soup.triangles);
  free(edges);
  free(neighbour);
  free(same);
  free(queue);
  free(canonical_ids);
  free(canonical);
  return 0;
}

void poly_mesh_orientation_free(poly_mesh_orientation *o)
{
  free(o->flip);
  free(o->component);
  free(o->component_closed);
  free(o->component_size);
  free(o->component_flipped);
  free(o->component_conflicts);
  free(o->component_volume);
  free(o->edge_normals);
  memset(o, 0, sizeof *o);
}

/* Ericson, Real-Time Collision Detection, 5.1.5, with the feature reached. */
int poly_triangle_closest(const double p[3], const double a[3], const double b[3], const double c[3],
                          double closest[3])
{
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  shell_sub(b, a, ab);
  shell_sub(c, a, ac);
  shell_sub(p, a, ap);
  double d1 = shell_dot(ab, ap), d2 = shell_dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    memcpy(closest, a, 3 * sizeof(double));
    return 1;
  }
  shell_sub(p, b, bp);
  double d3 = shell_dot(ab, bp), d4 = shell_dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    memcpy(closest, b, 3 * sizeof(double));
    return 2;
  }
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    double s = d1 / (d1 - d3);
    for (int k = 0; k < 3; k++) closest[k] = a[k] + s * ab[k];
    return 4;
  }
  shell_sub(p, c, cp);
  double d5 = shell_dot(ab, cp), d6 = shell_dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    memcpy(closest, c, 3 * sizeof(double));
    return 3;
  }
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    double s = d2 / (d2 - d6);
    for (int k = 0; k < 3; k++) closest[k] = a[k] + s * ac[k];
    return 6;  /* edge c -> a */
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (int k = 0; k < 3; k++) closest[k] = b[k] + s * (c[k] - b[k]);
    return 5;  /* edge b -> c */
  }
  double denominator = 1.0 / (va + vb + vc), v = vb * denominator, w = vc * denominator;
  for (int k = 0; k < 3; k++) closest[k] = a[k] + ab[k] * v + ac[k] * w;
  return 0;
}
