/* Body of the overlap computation, written once for a scalar type.
 * Include with POLY_REAL (double or float) and POLY_FN(name) (name with a
 * precision suffix) defined, and optionally POLY_ACCUM, the type the volume,
 * moment and area sums are accumulated in (default POLY_REAL; double with
 * float geometry is the "mixed" precision); see poly_overlap.h for the method. Everything is
 * static inline, so the CUDA path can include it too. */
#if !defined(POLY_REAL) || !defined(POLY_FN)
#error "define POLY_REAL and POLY_FN before including poly_overlap_impl.h"
#endif

#include <math.h>
#include <stddef.h>

#include "poly_exact.h"

#ifndef POLY_OVERLAP_IMPL_COMMON
#define POLY_OVERLAP_IMPL_COMMON
/* The crossing records (poly_overlap_records_impl.h) need workspace memory
 * that would push cubes and Schoenhardt polyhedra out of a GPU thread's local
 * array (gpu/poly_gpu.h): the CUDA build lays out no records and takes the
 * reference path, whose results are the same bits. */
#ifndef POLY_OVERLAP_RECORDS
#if defined(__CUDACC__)
#define POLY_OVERLAP_RECORDS 0
#else
#define POLY_OVERLAP_RECORDS 1
#endif
#endif
/* The exact predicates decide only the rare uncertain cases, and each inlined
 * copy of their expansion arithmetic brings its own arrays: on the GPU they
 * stay out of line, so a thread's stack holds one frame of them and the hot
 * path's registers are not spent on code it almost never runs. The CPU build
 * inlines them as before. */
#if defined(__CUDACC__)
#define POLY_COLD static __host__ __device__ __noinline__
#else
#define POLY_COLD POLY_INLINE
#endif

POLY_COLD double poly_overlap_orient(const double *a, const double *b, const double *c, const double *d)
{
  return poly_orient(a, b, c, d);
}

POLY_COLD int poly_overlap_det_sign(const double *const high[3], const double *const low[3])
{
  return poly_det_sign_exact(high, low);
}

/* B's body frame in A's: rotation R_A^T R_B, translation R_A^T (x_B - x_A),
 * with the position difference taken in double before anything else; also
 * A's rotation R_A, which takes results back to the world. */
POLY_INLINE void poly_overlap_relative_pose(const double *position_a, const double *quaternion_a,
                                            const double *position_b, const double *quaternion_b,
                                            double rotation_a[9], double rotation[9], double translation[3])
{
  double rotation_b[9], difference[3];
  poly_quat_to_matrix(quaternion_a, rotation_a);
  poly_quat_to_matrix(quaternion_b, rotation_b);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      rotation[3 * i + j] = rotation_a[i] * rotation_b[j] + rotation_a[3 + i] * rotation_b[3 + j] +
                            rotation_a[6 + i] * rotation_b[6 + j];
  for (int k = 0; k < 3; k++) difference[k] = position_b[k] - position_a[k];
  poly_matrix_apply_transpose(rotation_a, difference, translation);
}
#endif

typedef POLY_REAL POLY_FN(real);
#define R POLY_FN(real)
#ifdef POLY_ACCUM
typedef POLY_ACCUM POLY_FN(accum);
#else
typedef POLY_REAL POLY_FN(accum);
#endif
#define ACC POLY_FN(accum)

/* Fixed generic direction of the symbolic perturbation of B (body frame of A).
 * Irrational-looking components so that no mesh normal or edge of practical
 * interest is orthogonal to it. */
#ifndef POLY_PERTURBATION_SIGN
#define POLY_PERTURBATION_SIGN 1 /* -1: the opposite direction (tests/test_flush_faces.py builds both) */
#endif
POLY_INLINE void POLY_FN(perturbation)(R *direction)
{
  direction[0] = (R)(POLY_PERTURBATION_SIGN * 0.7431448254773942);
  direction[1] = (R)(POLY_PERTURBATION_SIGN * 0.5219894423148289);
  direction[2] = (R)(POLY_PERTURBATION_SIGN * 0.4186764212365043);
}

POLY_INLINE R POLY_FN(dot)(const R *a, const R *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

POLY_INLINE void POLY_FN(sub)(const R *a, const R *b, R *out)
{
  out[0] = a[0] - b[0]; out[1] = a[1] - b[1]; out[2] = a[2] - b[2];
}

POLY_INLINE void POLY_FN(cross)(const R *a, const R *b, R *out)
{
  R x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
  out[0] = x; out[1] = y; out[2] = z;
}

POLY_INLINE R POLY_FN(det)(const R *a, const R *b, const R *c)
{
  return a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/* Sign of (value + epsilon * first_order) for infinitesimal epsilon > 0. */
POLY_INLINE int POLY_FN(perturbed_sign)(R value, R first_order)
{
  if (value > 0) return 1;
  if (value < 0) return -1;
  return first_order > 0 ? 1 : -1;
}

/* Sizes the workspace for shapes of up to max_vertices / max_triangles in one
 * block of memory: returns the bytes needed, and with `ws` and `memory` given
 * points the workspace's arrays into that block. */
POLY_INLINE size_t POLY_FN(overlap_workspace_layout)(POLY_FN(overlap_workspace) *ws, void *memory, int max_vertices,
                                                     int max_triangles)
{
  size_t nv = (size_t)(max_vertices > 0 ? max_vertices : 1);
  size_t nt = (size_t)(max_triangles > 0 ? max_triangles : 1);
  /* Nodes: vertices inside plus edge crossings; a few per triangle covers any
   * realistic overlap, and more are found again rather than lost. (The apexes
   * took 2 nodes' worth per triangle, so the total, and which shapes fit a GPU
   * thread's local memory, did not change.) Crossing records (CPU only, see
   * POLY_OVERLAP_RECORDS): as many as nodes, each crossing being one, and more
   * take the reference path; runs: one per edge of both bodies (a closed mesh
   * has 3/2 as many edges as triangles); chord ends: two per record, bucketed
   * by A's triangles. */
  size_t np = 2 * nv + 2 * nt + 64;
  size_t nr = POLY_OVERLAP_RECORDS ? np : 0, nruns = POLY_OVERLAP_RECORDS ? 3 * nt : 0;
  size_t nbuckets = POLY_OVERLAP_RECORDS ? nt : 0;
  size_t reals = 3 * nv + 3 * nv + 4 * nt + 4 * nt + 3 * nt + 6 * nt + 6 * nt + 3 * nt + 3 * nt + 2 * nt + 3 * np +
                 2 * nr;
  size_t ints = 2 * nt + 2 * nr + 3 * nruns + nbuckets + 4 * nr;
  size_t bytes = sizeof(R) * reals + sizeof(int) * ints + 2 * nt + 2 * nv;
  if (!ws || !memory) return bytes;
  R *r = (R *)memory;
  ws->vertices_a = r; r += 3 * nv;
  ws->vertices_b = r; r += 3 * nv;
  ws->planes_a = r; r += 4 * nt;
  ws->planes_b = r; r += 4 * nt;
  ws->normals_b = r; r += 3 * nt;
  ws->bounds_a = r; r += 6 * nt;
  ws->bounds_b = r; r += 6 * nt;
  ws->apex_a = r; r += 3 * nt;
  ws->apex_b = r; r += 3 * nt;
  ws->crossings = r; r += 2 * nt; /* parameters, then directions */
  ws->points = r; r += 3 * np;
  ws->record_lambda = r; r += nr;
  ws->record_entering = r; r += nr;
  int *n = (int *)r;
  ws->kept_list_a = n; n += nt;
  ws->kept_list_b = n; n += nt;
  ws->record_triangle = n; n += nr;
  ws->record_edge = n; n += nr;
  ws->runs = n; n += 3 * nruns;
  ws->chord_buckets = n; n += nbuckets;
  ws->chord_ends = n; n += 4 * nr;
  unsigned char *c = (unsigned char *)n;
  ws->kept_a = c; c += nt;
  ws->kept_b = c; c += nt;
  ws->inside_a = c; c += nv;
  ws->inside_b = c;
  ws->capacity_vertices = (int)nv;
  ws->capacity_triangles = (int)nt;
  ws->capacity_points = (int)np;
  ws->capacity_records = (int)nr;
  ws->capacity_runs = (int)nruns;
  ws->use_records = POLY_OVERLAP_RECORDS;
  ws->records_overflows = 0;
  ws->use_filter = 1;
  ws->want_second_moment = 0;
  return bytes;
}

/* Unit roundoff of the scalar type: bounds the error of the fast predicates. */
POLY_INLINE R POLY_FN(epsilon)(void) { return sizeof(R) == sizeof(float) ? (R)5.9604645e-8 : (R)1.1102230246251565e-16; }

POLY_INLINE R POLY_FN(norm1)(const R *a) { return fabs(a[0]) + fabs(a[1]) + fabs(a[2]); }

POLY_INLINE void POLY_FN(to_double)(const R *a, double *out) { out[0] = a[0]; out[1] = a[1]; out[2] = a[2]; }

#include "poly_overlap_predicates_impl.h"

/* Do the boxes [low_a, high_a] and the stored triangle box (low xyz, high xyz) overlap? */
POLY_INLINE int POLY_FN(boxes_overlap)(const R *low_a, const R *high_a, const R *box)
{
  return !(box[0] > high_a[0] || box[1] > high_a[1] || box[2] > high_a[2] || low_a[0] > box[3] ||
           low_a[1] > box[4] || low_a[2] > box[5]);
}

POLY_INLINE void POLY_FN(segment_bounds)(const R *p0, const R *p1, R *low, R *high)
{
  for (int k = 0; k < 3; k++) {
    low[k] = p0[k] < p1[k] ? p0[k] : p1[k];
    high[k] = p0[k] < p1[k] ? p1[k] : p0[k];
  }
}

/* Running sums of the signed tetrahedra (O, c, x1, x2). */
typedef struct POLY_FN(accumulator) {
  ACC volume6;     /* 6 V */
  ACC moment24[3]; /* 24 V c */
  ACC area_normal[3]; /* sum of area * unit normal over A's facets (eq. 4.19) */
  ACC area;
  R reference[3];  /* the first node of the boundary: the tetrahedra's common vertex O (local frame) */
  int has_reference;
  int want_second;
  double second120[6]; /* 120 int (x - O)(x - O)^T dV, when want_second (always in double) */
} POLY_FN(accumulator);

/* Marks a facet whose apex is not yet set (an impossible local coordinate). */
#define POLY_NO_APEX ((R)1e30)

/* Segment (x1, x2) of a facet with unit normal `unit_normal`. Its share of the
 * volume and moment is the signed tetrahedron (O, q, x1, x2) (eqs. 5.7-5.11):
 * q, the facet's apex, is the first node met on the facet (stored in `apex`
 * when still POLY_NO_APEX), and O, common to all facets, the first node of the
 * whole boundary. Any points would do in exact arithmetic; these lie on the
 * overlap, so the tetrahedra are the size of the overlap. Points far from it
 * (the foot of the local origin on the facet's plane, a corner of the facet)
 * make tetrahedra R/delta times the overlap for a contact of depth delta away
 * from the centre line, which cancel to its volume: the float nodes' rounding
 * then came out amplified by that factor in single and mixed precision (a
 * vertex 1e-5 D into a face: volumes wrong by 10x, contacts lost). The
 * determinant is det(q - O, x1 - q, x2 - x1): x2 - x1 is short and exact, and
 * two long, nearly parallel sides (q far from the segment, where a facet
 * touches the other body in two places) would leave the rounding of their
 * cross product across the facet. `of_a`: a facet of A, which also counts for
 * the area and eq. 4.19. The tetrahedra are evaluated in the accumulation type
 * (mixed precision promotes the float nodes first). */
POLY_INLINE void POLY_FN(add_segment)(POLY_FN(accumulator) *acc, R *apex, const R *unit_normal, const R *x1,
                                      const R *x2, int of_a)
{
  if (!acc->has_reference) {
    for (int k = 0; k < 3; k++) acc->reference[k] = x1[k];
    acc->has_reference = 1;
  }
  if (apex[0] == POLY_NO_APEX)
    for (int k = 0; k < 3; k++) apex[k] = x1[k];
  ACC q[3], e1[3], side[3];
  for (int k = 0; k < 3; k++) {
    q[k] = (ACC)apex[k] - (ACC)acc->reference[k];
    e1[k] = (ACC)x1[k] - (ACC)apex[k];
    side[k] = (ACC)x2[k] - (ACC)x1[k];
  }
  ACC cross[3] = {e1[1] * side[2] - e1[2] * side[1], e1[2] * side[0] - e1[0] * side[2],
                  e1[0] * side[1] - e1[1] * side[0]};
  ACC n[3] = {unit_normal[0], unit_normal[1], unit_normal[2]};
  ACC twice_area = n[0] * cross[0] + n[1] * cross[1] + n[2] * cross[2];
  ACC v6 = q[0] * cross[0] + q[1] * cross[1] + q[2] * cross[2];
  acc->volume6 += v6;
  for (int k = 0; k < 3; k++) acc->moment24[k] += v6 * ((ACC)3 * q[k] + (ACC)2 * e1[k] + side[k]);
  if (acc->want_second) {
    double corner_q[3], corner_1[3], corner_2[3];
    for (int k = 0; k < 3; k++) {
      corner_q[k] = (double)q[k];
      corner_1[k] = corner_q[k] + (double)e1[k];
      corner_2[k] = corner_1[k] + (double)side[k];
    }
    poly_second_moment_add(acc->second120, (double)v6, corner_q, corner_1, corner_2);
  }
  if (of_a) {
    ACC area = (ACC)0.5 * twice_area;
    acc->area += area;
    for (int k = 0; k < 3; k++) acc->area_normal[k] += area * n[k];
  }
}

POLY_INLINE void POLY_FN(add_point)(POLY_FN(overlap_workspace) *ws, int *count, const R *x)
{
  if (*count < ws->capacity_points) {
    R *slot = ws->points + 3 * *count;
    slot[0] = x[0]; slot[1] = x[1]; slot[2] = x[2];
  }
  (*count)++;
}

/* Parity of crossings of the ray from x along `ray` with the kept triangles of `body`. */
POLY_INLINE int POLY_FN(point_inside)(const R *x, const R *ray, R ray_length, int point_in_b, const R *vertices,
                                      const int *triangles, const R *planes, const R *bounds,
                                      const int *kept_list, int num_kept)
{
  R far_end[3], low[3], high[3];
  for (int k = 0; k < 3; k++) far_end[k] = x[k] + ray_length * ray[k];
  POLY_FN(segment_bounds)(x, far_end, low, high);
  int crossings = 0;
  for (int n = 0; n < num_kept; n++) {
    int t = kept_list[n];
    if (!POLY_FN(boxes_overlap)(low, high, bounds + 6 * t)) continue;
    R lambda;
    crossings += 0 != POLY_FN(segment_crosses_triangle)(x, far_end, point_in_b, vertices, triangles + 3 * t,
                                                   planes + 4 * t, &lambda);
  }
  return crossings & 1;
}

/* The inside parts of edge e of `mine` (p0 -> p1, from its lower vertex; `inside` the state of p0), given its
 * crossings with the other body sorted along it (parameters `lambdas`, +1 in `entering` where it enters):
 * each part adds a segment to both triangles of the edge, in their own orientations, and each crossing a node. */
POLY_INLINE void POLY_FN(edge_inside_parts)(const POLY_FN(shape_view) *mine, int e, const R *p0, const R *p1,
                                            int inside, const R *lambdas, const R *entering, int count,
                                            const R *my_unit_normals, R *my_apexes, int mine_is_b,
                                            POLY_FN(overlap_workspace) *ws, POLY_FN(accumulator) *acc,
                                            int *num_points)
{
  if (count == 0 && !inside) return;

  R direction[3];
  POLY_FN(sub)(p1, p0, direction);
  R start = 0;
  int forward = mine->edge_triangles[2 * e], backward = mine->edge_triangles[2 * e + 1];
  /* Crossings whose rounded positions came out of order (an edge nearly in the
   * plane of a face it crosses) would pair the wrong ends. Then the inside part
   * is written as the chain inside(p0) [p0, p1] + sum over crossings of
   * +-[x_i, p1], whose ends match the chords at every x_i in any order. */
  int ordered = 1;
  for (int c = 0, state = inside; c < count && ordered; c++, state = !state) ordered = (entering[c] > 0) == !state;
  if (!ordered) {
    const R *n_forward = my_unit_normals + 3 * forward, *n_backward = my_unit_normals + 3 * backward;
    R *apex_forward = my_apexes + 3 * forward, *apex_backward = my_apexes + 3 * backward;
    for (int c = 0; c < count; c++) {
      R x[3];
      for (int k = 0; k < 3; k++) x[k] = p0[k] + lambdas[c] * direction[k];
      POLY_FN(add_point)(ws, num_points, x);
      const R *from = entering[c] > 0 ? x : p1, *to = entering[c] > 0 ? p1 : x;
      POLY_FN(add_segment)(acc, apex_forward, n_forward, from, to, !mine_is_b);
      POLY_FN(add_segment)(acc, apex_backward, n_backward, to, from, !mine_is_b);
    }
    if (inside) {
      POLY_FN(add_segment)(acc, apex_forward, n_forward, p0, p1, !mine_is_b);
      POLY_FN(add_segment)(acc, apex_backward, n_backward, p1, p0, !mine_is_b);
    }
    return;
  }
  for (int c = 0; c <= count; c++) {
    R stop = c < count ? lambdas[c] : (R)1;
    if (c < count) {
      R x[3];
      for (int k = 0; k < 3; k++) x[k] = p0[k] + stop * direction[k];
      POLY_FN(add_point)(ws, num_points, x);
    }
    if (inside && stop > start) {
      R x1[3], x2[3];
      for (int k = 0; k < 3; k++) {
        x1[k] = p0[k] + start * direction[k];
        x2[k] = p0[k] + stop * direction[k];
      }
      POLY_FN(add_segment)(acc, my_apexes + 3 * forward, my_unit_normals + 3 * forward, x1, x2, !mine_is_b);
      POLY_FN(add_segment)(acc, my_apexes + 3 * backward, my_unit_normals + 3 * backward, x2, x1, !mine_is_b);
    }
    inside = !inside;
    start = stop;
  }
}

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
                               mine_is_b, ws, acc, num_points);
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

POLY_INLINE void POLY_FN(triangle_bounds)(const R *vertices, const int *tri, R *low, R *high)
{
  for (int k = 0; k < 3; k++) {
    R x = vertices[3 * tri[0] + k], y = vertices[3 * tri[1] + k], z = vertices[3 * tri[2] + k];
    low[k] = x < y ? (x < z ? x : z) : (y < z ? y : z);
    high[k] = x > y ? (x > z ? x : z) : (y > z ? y : z);
  }
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

/* For a triangle that survives the filter: its plane for the predicates
 * ((v1-v0)x(v2-v0) and |v1-v0|_1 |v2-v0|_1), its box grown by `grow` (boxes
 * only cull, so a grown box is safe; grown by the flush tolerance, the pair
 * loop's one box test also finds flush faces a hair apart), and the body's box
 * of kept triangles grown to hold it. */
POLY_INLINE void POLY_FN(prepare_kept_triangle)(const R *vertices, const int *tri, R grow, R *plane, R *bounds,
                                                R *box_low, R *box_high)
{
  R e1[3], e2[3];
  POLY_FN(triangle_bounds)(vertices, tri, bounds, bounds + 3);
  for (int k = 0; k < 3; k++) {
    bounds[k] -= grow;
    bounds[3 + k] += grow;
    if (bounds[k] < box_low[k]) box_low[k] = bounds[k];
    if (bounds[3 + k] > box_high[k]) box_high[k] = bounds[3 + k];
  }
  POLY_FN(sub)(vertices + 3 * tri[1], vertices + 3 * tri[0], e1);
  POLY_FN(sub)(vertices + 3 * tri[2], vertices + 3 * tri[0], e2);
  POLY_FN(cross)(e1, e2, plane);
  plane[3] = POLY_FN(norm1)(e1) * POLY_FN(norm1)(e2);
}

/* The half-space filter's slab (eqs. 5.3-5.4): the filtering direction
 * `axis_d` (the centre line; any direction is valid), the highest extent of A
 * and the lowest of B along it (B's vertices taken to A's body frame in
 * double). Returns 1 when the bodies do not overlap along it, so neither do
 * they: the GPU also uses it to skip such pairs before the overlap kernel. */
POLY_INLINE int POLY_FN(overlap_slab)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                      const double *rotation, const double *translation, double *axis_d,
                                      double *extent_a, double *extent_b)
{
  /* Filtering direction (eq. 5.3): the centre line; any direction is valid. */
  double distance = sqrt(translation[0] * translation[0] + translation[1] * translation[1] +
                         translation[2] * translation[2]);
  axis_d[0] = 1.0;
  axis_d[1] = axis_d[2] = 0.0;
  if (distance > 1e-12 * ((double)a->bounding_radius + (double)b->bounding_radius))
    for (int k = 0; k < 3; k++) axis_d[k] = translation[k] / distance;

  double high_a = -1e300, low_b = 1e300;
  for (int i = 0; i < a->num_vertices; i++) {
    const R *v = a->vertices + 3 * i;
    double along = axis_d[0] * v[0] + axis_d[1] * v[1] + axis_d[2] * v[2];
    if (along > high_a) high_a = along;
  }
  for (int j = 0; j < b->num_vertices; j++) {
    const R *v = b->vertices + 3 * j;
    double along = 0.0;
    for (int k = 0; k < 3; k++) {
      double w = rotation[3 * k] * v[0] + rotation[3 * k + 1] * v[1] + rotation[3 * k + 2] * v[2] + translation[k];
      along += axis_d[k] * w;
    }
    if (along < low_b) low_b = along;
  }
  *extent_a = high_a;
  *extent_b = low_b;
  /* Separated, or touching to within round-off: an overlap at most 1e-12 of
   * the particle size deep has a volume the contact law ignores anyway, and
   * faces touching face to face are the most degenerate, slowest case for the
   * exact predicates (a bed of boxes placed on a grid is full of them). */
  return high_a - low_b <= 1e-12 * ((double)a->bounding_radius + (double)b->bounding_radius);
}

/* What one evaluation of the boundary sums leaves: the sums, the local frame
 * they are in, and what the caller decides on (inconsistent edges, flush faces). */
typedef struct POLY_FN(pass) {
  POLY_FN(accumulator) acc;
  double origin[3];     /* of the local frame, in A's body frame */
  double axis[3];       /* filtering direction (centre line) */
  int num_points, num_inconsistent, filtered_out;
  int num_kept_a, num_kept_b;
  int flush;            /* a kept face of A and one of B lie in one plane to within the smoothing tolerance */
} POLY_FN(pass);

/* Length of the finite shift of the flush-face smoothing (see overlap_local),
 * relative to the particles' size: far above the rounding of the local
 * coordinates (about 1e-16 of the size in double, 6e-8 in single), far below
 * any overlap the contact law resolves. */
POLY_INLINE double POLY_FN(smoothing_length)(void) { return sizeof(R) == sizeof(float) ? 0x1p-16 : 0x1p-36; }

/* Are triangle t of A and triangle s of B flush: every corner of each within
 * `tolerance` of the other's plane (planes as prepare_kept_triangle stores them)?
 * Faces more than 0.8 degrees apart are not, unless smaller than 1e4 tolerances
 * (the unit normals' test first: it is cheap and rejects almost every pair). */
POLY_INLINE int POLY_FN(triangles_flush)(const R *va, const int *ta, const R *plane_a, const R *normal_a,
                                         const R *vb, const int *tb, const R *plane_b, const R *normal_b,
                                         R tolerance)
{
  R cosine = POLY_FN(dot)(normal_a, normal_b);
  if (cosine * cosine < (R)0.9999) return 0;
  R length_a = sqrt(POLY_FN(dot)(plane_a, plane_a)), length_b = sqrt(POLY_FN(dot)(plane_b, plane_b));
  for (int k = 0; k < 3; k++) {
    R offset[3];
    POLY_FN(sub)(vb + 3 * tb[k], va + 3 * ta[0], offset);
    if (fabs(POLY_FN(dot)(plane_a, offset)) > tolerance * length_a) return 0;
    POLY_FN(sub)(va + 3 * ta[k], vb + 3 * tb[0], offset);
    if (fabs(POLY_FN(dot)(plane_b, offset)) > tolerance * length_b) return 0;
  }
  return 1;
}

#include "poly_overlap_records_impl.h"

/* One evaluation of the boundary sums of A n B, B placed by rotation and
 * translation in A's body frame. `use_filter` 0: every triangle, no early exit
 * (the path no slab rounding can touch). `flush_tolerance` > 0: look for flush
 * faces within it (relative to the particles' size). `keep_points` 0: the
 * intersection nodes are not stored (ws->points and ws->origin are left as they are). */
POLY_INLINE void POLY_FN(overlap_pass)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                       const double *rotation, const double *translation, int use_filter,
                                       double flush_tolerance, int keep_points, POLY_FN(overlap_workspace) *ws,
                                       POLY_FN(pass) *out)
{
  POLY_FN(accumulator) empty = {0, {0, 0, 0}, {0, 0, 0}, 0, {0, 0, 0}, 0, 0, {0, 0, 0, 0, 0, 0}};
  out->acc = empty;
  out->acc.want_second = ws->want_second_moment && keep_points;
  out->num_points = out->num_inconsistent = out->filtered_out = out->flush = 0;
  out->num_kept_a = out->num_kept_b = 0;
  int capacity_points = ws->capacity_points;

  double axis_d[3], extent_a, extent_b;
  int separated = POLY_FN(overlap_slab)(a, b, rotation, translation, axis_d, &extent_a, &extent_b);
  for (int k = 0; k < 3; k++) out->axis[k] = axis_d[k];
  if (separated && use_filter) {
    out->filtered_out = 1;
    return;
  }
  if (!use_filter) {
    /* No early exit, and a slab that holds both bodies entirely. */
    extent_a += 4.0 * ((double)a->bounding_radius + (double)b->bounding_radius);
    extent_b -= 4.0 * ((double)a->bounding_radius + (double)b->bounding_radius);
  }
  /* Local origin in the middle of the slab on the centre line: the signed
   * tetrahedra are then the size of the overlap, not of the particles. */
  double middle = 0.5 * (extent_a + extent_b);
  double origin[3] = {axis_d[0] * middle, axis_d[1] * middle, axis_d[2] * middle};
  for (int k = 0; k < 3; k++) out->origin[k] = origin[k];
  if (keep_points)
    for (int k = 0; k < 3; k++) ws->origin[k] = origin[k];
  else
    ws->capacity_points = 0;
  R axis[3] = {(R)axis_d[0], (R)axis_d[1], (R)axis_d[2]};
  R tolerance = (R)(flush_tolerance * ((double)a->bounding_radius + (double)b->bounding_radius));
  /* The slab tests below compare rounded projections (of rounded local
   * coordinates, on a rounded axis) with rounded limits. A vertex or face of
   * one body flush with the other's extreme point would be cut or kept by that
   * rounding, not by the perturbation that decides every other predicate
   * (a cube flush in the corner of a box lost its corner vertex: V 2/3 of the
   * true 1). So the limits are widened by a bound on that rounding: keeping a
   * few more triangles costs little, and the exact predicates decide them. */
  double scale = (double)a->bounding_radius + (double)b->bounding_radius + fabs(middle);
  double margin = 64.0 * (double)POLY_FN(epsilon)() * scale +
                  flush_tolerance * ((double)a->bounding_radius + (double)b->bounding_radius);
  R limit_a = (R)(extent_b - middle - margin); /* B lies at >= limit_a along the axis */
  R limit_b = (R)(extent_a - middle + margin); /* A lies at <= limit_b */

  R *va = ws->vertices_a, *vb = ws->vertices_b;
  for (int i = 0; i < a->num_vertices; i++)
    for (int k = 0; k < 3; k++) va[3 * i + k] = (R)((double)a->vertices[3 * i + k] - origin[k]);
  for (int j = 0; j < b->num_vertices; j++) {
    const R *v = b->vertices + 3 * j;
    for (int k = 0; k < 3; k++)
      vb[3 * j + k] = (R)(rotation[3 * k] * v[0] + rotation[3 * k + 1] * v[1] + rotation[3 * k + 2] * v[2] +
                          translation[k] - origin[k]);
  }

  /* Half-space filter (eq. 5.5) and bounding boxes of what survives. */
  R box_a_low[3] = {(R)1e30, (R)1e30, (R)1e30}, box_a_high[3] = {(R)-1e30, (R)-1e30, (R)-1e30};
  R box_b_low[3] = {(R)1e30, (R)1e30, (R)1e30}, box_b_high[3] = {(R)-1e30, (R)-1e30, (R)-1e30};
  int num_kept_a = 0, num_kept_b = 0;
  for (int t = 0; t < a->num_triangles; t++) {
    const int *tri = a->triangles + 3 * t;
    R high = -(R)1e30;
    for (int k = 0; k < 3; k++) {
      R along = POLY_FN(dot)(va + 3 * tri[k], axis);
      if (along > high) high = along;
    }
    ws->kept_a[t] = high >= limit_a;
    ws->apex_a[3 * t] = POLY_NO_APEX;
    if (!ws->kept_a[t]) continue;
    ws->kept_list_a[num_kept_a++] = t;
    POLY_FN(prepare_kept_triangle)(va, tri, tolerance, ws->planes_a + 4 * t, ws->bounds_a + 6 * t, box_a_low,
                                   box_a_high);
  }
  for (int s = 0; s < b->num_triangles; s++) {
    const int *tri = b->triangles + 3 * s;
    R low = (R)1e30;
    for (int k = 0; k < 3; k++) {
      R along = POLY_FN(dot)(vb + 3 * tri[k], axis);
      if (along < low) low = along;
    }
    ws->kept_b[s] = low <= limit_b;
    ws->apex_b[3 * s] = POLY_NO_APEX;
    if (!ws->kept_b[s]) continue;
    ws->kept_list_b[num_kept_b++] = s;
    POLY_FN(prepare_kept_triangle)(vb, tri, tolerance, ws->planes_b + 4 * s, ws->bounds_b + 6 * s, box_b_low,
                                   box_b_high);
    const R *n = b->face_normals + 3 * s;
    for (int k = 0; k < 3; k++)
      ws->normals_b[3 * s + k] = (R)(rotation[3 * k] * n[0] + rotation[3 * k + 1] * n[1] + rotation[3 * k + 2] * n[2]);
  }
  if (!num_kept_a || !num_kept_b) {
    out->filtered_out = 1;
    ws->capacity_points = capacity_points;
    return;
  }

  /* Vertices inside the other body: only those in the slab and in the other's
   * box can be; rays point away from the other body, so they only meet kept
   * triangles (sec. 5.2). */
  /* Rays along the coordinate axis closest to the centre line, pointing away
   * from the other body: axis-aligned rays make the box test reject almost
   * every triangle. */
  R ray_length = (R)(4.0 * ((double)a->bounding_radius + (double)b->bounding_radius) + (extent_a - extent_b));
  int ray_axis = 0;
  for (int k = 1; k < 3; k++)
    if (fabs(axis_d[k]) > fabs(axis_d[ray_axis])) ray_axis = k;
  R ray_b[3] = {0, 0, 0}, ray_a[3] = {0, 0, 0};
  ray_b[ray_axis] = axis_d[ray_axis] > 0 ? (R)1 : (R)-1;
  ray_a[ray_axis] = -ray_b[ray_axis];
  int num_points = 0;
  if (ws->use_records && a->num_edges + b->num_edges <= ws->capacity_runs) {
    int num_records = 0, num_runs_a = 0, num_runs_b = 0, flush = 0;
    int *runs_a = ws->runs;
    int fits = POLY_FN(find_crossings)(a, va, ws->planes_a, ws->bounds_a, a->face_normals, 0, b, vb, ws->planes_b,
                                       ws->bounds_b, ws->normals_b, ws->kept_list_b, num_kept_b, axis, limit_a,
                                       tolerance, ws, &num_records, runs_a, &num_runs_a, &flush) == 0;
    int records_b = num_records;
    int *runs_b = runs_a + 3 * num_runs_a;
    fits = fits && POLY_FN(find_crossings)(b, vb, ws->planes_b, ws->bounds_b, ws->normals_b, 1, a, va, ws->planes_a,
                                           ws->bounds_a, a->face_normals, ws->kept_list_a, num_kept_a, axis, limit_b,
                                           tolerance, ws, &num_records, runs_b, &num_runs_b, &flush) == 0;
    if (fits) {
      int inconsistent = 0;
      POLY_FN(settle_inside)(a, va, 0, axis, limit_a, box_b_low, box_b_high, runs_a, num_runs_a, ray_a, ray_length, b,
                             vb, ws->planes_b, ws->bounds_b, ws->kept_list_b, num_kept_b, ws->inside_a, ws,
                             &num_points, &inconsistent);
      POLY_FN(settle_inside)(b, vb, 1, axis, limit_b, box_a_low, box_a_high, runs_b, num_runs_b, ray_b, ray_length, a,
                             va, ws->planes_a, ws->bounds_a, ws->kept_list_a, num_kept_a, ws->inside_b, ws,
                             &num_points, &inconsistent);
      POLY_FN(accumulator) acc = out->acc;
      POLY_FN(run_inside_parts)(a, va, ws->inside_a, runs_a, num_runs_a, a->face_normals, ws->apex_a, 0, ws, &acc,
                                &num_points);
      POLY_FN(run_inside_parts)(b, vb, ws->inside_b, runs_b, num_runs_b, ws->normals_b, ws->apex_b, 1, ws, &acc,
                                &num_points);
      POLY_FN(accumulate_chords)(a, va, b, vb, records_b, num_records, num_kept_a, ws, &acc);
      out->acc = acc;
      out->num_points = num_points;
      out->num_inconsistent = inconsistent;
      out->flush = flush;
      out->num_kept_a = num_kept_a;
      out->num_kept_b = num_kept_b;
      ws->capacity_points = capacity_points;
      return;
    }
  }
  if (ws->use_records) ws->records_overflows++;
  /* The reference path: a ray's parity per candidate vertex, every kept
   * triangle pair examined. */
  for (int i = 0; i < a->num_vertices; i++) {
    const R *x = va + 3 * i;
    int candidate = POLY_FN(dot)(x, axis) >= limit_a;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= box_b_low[k] && x[k] <= box_b_high[k];
    ws->inside_a[i] = candidate ? (unsigned char)POLY_FN(point_inside)(x, ray_a, ray_length, 0, vb, b->triangles,
                                                                         ws->planes_b, ws->bounds_b, ws->kept_list_b,
                                                                         num_kept_b)
                                : 0;
    if (ws->inside_a[i]) POLY_FN(add_point)(ws, &num_points, x);
  }
  for (int j = 0; j < b->num_vertices; j++) {
    const R *x = vb + 3 * j;
    int candidate = POLY_FN(dot)(x, axis) <= limit_b;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= box_a_low[k] && x[k] <= box_a_high[k];
    ws->inside_b[j] = candidate ? (unsigned char)POLY_FN(point_inside)(x, ray_b, ray_length, 1, va, a->triangles,
                                                                         ws->planes_a, ws->bounds_a, ws->kept_list_a,
                                                                         num_kept_a)
                                : 0;
    if (ws->inside_b[j]) POLY_FN(add_point)(ws, &num_points, x);
  }

  POLY_FN(accumulator) acc = out->acc;
  int inconsistent = 0;
  POLY_FN(accumulate_edges)(a, va, a->face_normals, ws->apex_a, ws->inside_a, 0, b, vb, ws->planes_b, ws->bounds_b,
                            ws->kept_list_b, num_kept_b, axis, limit_a, ws, &acc, &num_points, &inconsistent);
  POLY_FN(accumulate_edges)(b, vb, ws->normals_b, ws->apex_b, ws->inside_b, 1, a, va, ws->planes_a, ws->bounds_a,
                            ws->kept_list_a, num_kept_a, axis, limit_b, ws, &acc, &num_points, &inconsistent);
  int flush = 0;
  for (int m = 0; m < num_kept_a; m++) {
    int t = ws->kept_list_a[m];
    const R *box_t = ws->bounds_a + 6 * t;
    for (int n = 0; n < num_kept_b; n++) {
      int s = ws->kept_list_b[n];
      const R *box_s = ws->bounds_b + 6 * s;
      if (!POLY_FN(boxes_overlap)(box_t, box_t + 3, box_s)) continue;
      if (tolerance > 0 && !flush)
        flush = POLY_FN(triangles_flush)(va, a->triangles + 3 * t, ws->planes_a + 4 * t, a->face_normals + 3 * t, vb,
                                         b->triangles + 3 * s, ws->planes_b + 4 * s, ws->normals_b + 3 * s,
                                         tolerance);
      POLY_FN(accumulate_triangle_pair)(a, va, ws->planes_a, a->face_normals, t, b, vb, ws->planes_b,
                                        ws->normals_b, s, ws, &acc);
    }
  }
  out->acc = acc;
  out->num_points = num_points;
  out->num_inconsistent = inconsistent;
  out->flush = flush;
  out->num_kept_a = num_kept_a;
  out->num_kept_b = num_kept_b;
  ws->capacity_points = capacity_points;
}


#include "poly_overlap_local_impl.h"

#undef POLY_NO_APEX
#undef R
#undef ACC
