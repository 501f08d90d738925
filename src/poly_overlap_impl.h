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
#include "poly_extremes.h"

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

/* 32-bit words of a mask of the edges of a closed mesh of `triangles` triangles (3/2 as many edges). */
#ifndef POLY_EDGE_MASK_WORDS
#define POLY_EDGE_MASK_WORDS(triangles) ((3 * (triangles) / 2 + 31) / 32 + 1)
#endif

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
   * by A's triangles. The nodes' array holds on the host at least the clipping path's corners
   * (POLY_CLIP_MAX_NODES), which it hands over there for the mesh walls' depth (want_nodes; capacity_corners):
   * a small shape clipped in pieces against a prism can have more (Schoenhardt: 92 nodes). The general path keeps
   * to np, as on the GPU. */
  size_t np = 2 * nv + 2 * nt + 64;
  size_t ncorners = POLY_OVERLAP_RECORDS && np < POLY_CLIP_MAX_NODES ? POLY_CLIP_MAX_NODES : np;
  size_t nr = POLY_OVERLAP_RECORDS ? np : 0, nruns = POLY_OVERLAP_RECORDS ? 3 * nt : 0;
  size_t nbuckets = POLY_OVERLAP_RECORDS ? nt : 0;
  /* The convex path's side table: rows of the vertices it clips, a column per face. */
  size_t nsides = 2 * (nv * nt < 16 * (nv + nt) + 128 ? nv * nt : 16 * (nv + nt) + 128);
  /* It also holds the crossing cache's certificate boxes: 6 per triangle and per edge (3/2 per triangle). */
  if (nsides < 15 * nt + 64) nsides = 15 * nt + 64;
  if (!POLY_OVERLAP_RECORDS) nsides = 0;
  size_t nfaces = POLY_OVERLAP_RECORDS ? nt : 0;
  size_t nrows = POLY_OVERLAP_RECORDS ? nv : 0;
  size_t nalong = POLY_OVERLAP_RECORDS ? nv : 0;
  size_t reals = 3 * nv + 3 * nv + 4 * nt + 4 * nt + 3 * nt + 6 * nt + 6 * nt + 3 * nt + 3 * nt + 2 * nt + 3 * ncorners +
                 2 * nr + nsides + 2 * nalong;
  /* The grid of kept triangles: its cells' starts, its entries (a triangle in a few cells), and per
   * triangle a stamp and a slot for the candidates of an edge. */
  size_t ncells = POLY_OVERLAP_RECORDS ? 16 * 16 * 16 + 1 : 0, nentries = POLY_OVERLAP_RECORDS ? 8 * nt + 64 : 0;
  size_t ngrid = POLY_OVERLAP_RECORDS ? nt : 0, nnear = POLY_OVERLAP_RECORDS ? nt : 0;
  size_t nmask = POLY_OVERLAP_RECORDS ? POLY_EDGE_MASK_WORDS(nt) : 0;
  size_t ints = 2 * nt + 2 * nnear + nmask + 2 * nr + 3 * nruns + nbuckets + 4 * nr + 4 * nfaces + 2 * nrows + ncells +
                nentries + 3 * ngrid;
  size_t bytes = sizeof(R) * reals + sizeof(int) * ints + 2 * nt + 2 * nv + 2 * nalong;
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
  ws->points = r; r += 3 * ncorners;
  ws->record_lambda = r; r += nr;
  ws->record_entering = r; r += nr;
  ws->sides = r; r += nsides;
  ws->along_a = r; r += nalong;
  ws->along_b = r; r += nalong;
  int *n = (int *)r;
  ws->kept_list_a = n; n += nt;
  ws->kept_list_b = n; n += nt;
  ws->record_triangle = n; n += nr;
  ws->record_edge = n; n += nr;
  ws->runs = n; n += 3 * nruns;
  ws->chord_buckets = n; n += nbuckets;
  ws->chord_ends = n; n += 4 * nr;
  ws->faces_a = n; n += nfaces;
  ws->faces_b = n; n += nfaces;
  ws->face_column_a = n; n += nfaces;
  ws->face_column_b = n; n += nfaces;
  ws->row_of_a = n; n += nrows;
  ws->row_of_b = n; n += nrows;
  ws->grid_start = n; n += ncells;
  ws->grid_entries = n; n += nentries;
  ws->grid_bits = (unsigned *)n; n += ngrid;
  ws->grid_candidates = n; n += ngrid;
  ws->box_passing = n; n += ngrid;
  ws->near_list_a = n; n += nnear;
  ws->near_list_b = n; n += nnear;
  ws->edge_mask = (unsigned *)n; n += nmask;
  unsigned char *c = (unsigned char *)n;
  ws->kept_a = c; c += nt;
  ws->kept_b = c; c += nt;
  ws->inside_a = c; c += nv;
  ws->inside_b = c; c += nv;
  ws->in_slab_a = c; c += nalong;
  ws->in_slab_b = c;
  ws->capacity_vertices = (int)nv;
  ws->capacity_triangles = (int)nt;
  ws->capacity_points = (int)np;
  ws->capacity_corners = (int)ncorners;
  ws->corners_kept = 0;
  ws->capacity_records = (int)nr;
  ws->capacity_runs = (int)nruns;
  ws->use_records = POLY_OVERLAP_RECORDS;
  ws->records_overflows = 0;
  ws->capacity_sides = (int)nsides;
  ws->convex_fallbacks = 0;
  ws->use_convex = POLY_OVERLAP_RECORDS;
  ws->use_clip = 1;
  ws->clip_fallbacks = 0;
  ws->want_nodes = 0;
  ws->capacity_grid = (int)nentries;
  ws->use_filter = 1;
  ws->want_second_moment = 0;
  ws->crossing_cache = NULL;
  ws->cache_pass = 0;
  ws->last_evaluation = POLY_LAST_UNKNOWN;
  ws->cache_hits = ws->cache_searches = ws->cache_certificates = 0;
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
  return !((box[0] > high_a[0]) | (box[1] > high_a[1]) | (box[2] > high_a[2]) | (low_a[0] > box[3]) |
           (low_a[1] > box[4]) | (low_a[2] > box[5]));
}

POLY_INLINE void POLY_FN(segment_bounds)(const R *p0, const R *p1, R *low, R *high)
{
  /* Each bound by one comparison of the form of a minimum or maximum instruction: written as one comparison the
   * compiler made them a branch, mispredicted half the time (a sixth of the crossing search's samples). */
  for (int k = 0; k < 3; k++) {
    const R x = p0[k], y = p1[k];
    low[k] = y < x ? y : x;
    high[k] = x < y ? y : x;
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
  if (apex[0] == POLY_NO_APEX) {
    /* The facet's first segment starts at its apex: a flat tetrahedron, nothing to add (adding its zeros
     * would not change a bit of the sums). */
    for (int k = 0; k < 3; k++) apex[k] = x1[k];
    return;
  }
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
                                            const int *face_of, POLY_FN(overlap_workspace) *ws,
                                            POLY_FN(accumulator) *acc, int *num_points)
{
  if (count == 0 && !inside) return;

  R direction[3];
  POLY_FN(sub)(p1, p0, direction);
  R start = 0;
  int forward = mine->edge_triangles[2 * e], backward = mine->edge_triangles[2 * e + 1];
  if (face_of) {
    /* The convex path: facets are whole faces, named by their lowest triangle. */
    forward = face_of[forward];
    backward = face_of[backward];
  }
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

POLY_INLINE void POLY_FN(triangle_bounds)(const R *vertices, const int *tri, R *low, R *high)
{
  for (int k = 0; k < 3; k++) {
    R x = vertices[3 * tri[0] + k], y = vertices[3 * tri[1] + k], z = vertices[3 * tri[2] + k];
    /* The same selections as x < y ? (x < z ? x : z) : (y < z ? y : z), in a form the compiler makes min/max
     * instructions of rather than branches. */
    R lower = x < y ? x : y, higher = x > y ? x : y;
    low[k] = lower < z ? lower : z;
    high[k] = higher > z ? higher : z;
  }
}

/* The triangles of `body` that reach into the slab (A's: a corner at or beyond `limit` along the axis; B's,
 * `below`: a corner at or below it), into `kept_list` in order without a branch per triangle (whether one reaches
 * it is unpredictable), `kept` set per triangle and their apexes reset. `along`: the vertices' places along the
 * axis, or NULL to project `vertices` on `axis`; `in_slab`: per vertex whether it reaches the slab (the same
 * comparison with `limit`), or NULL. Returns how many are kept. */
POLY_INLINE int POLY_FN(keep_in_slab)(const POLY_FN(shape_view) *body, const R *vertices, const R *along,
                                      const unsigned char *in_slab, const R *axis, R limit, int below,
                                      unsigned char *kept, R *apex, int *kept_list)
{
  int count = 0;
  for (int t = 0; t < body->num_triangles; t++) {
    const int *tri = body->triangles + 3 * t;
    int in;
    if (in_slab) {
      in = in_slab[tri[0]] | in_slab[tri[1]] | in_slab[tri[2]];
    } else {
      R reach = below ? (R)1e30 : -(R)1e30;
      for (int k = 0; k < 3; k++) {
        R x = along ? along[tri[k]] : POLY_FN(dot)(vertices + 3 * tri[k], axis);
        if (below ? x < reach : x > reach) reach = x;
      }
      in = below ? reach <= limit : reach >= limit;
    }
    kept[t] = (unsigned char)in;
    apex[3 * t] = POLY_NO_APEX;
    kept_list[count] = t;
    count += in;
  }
  return count;
}

/* A normal of B turned into A's frame (`rotation`, row major), rounded to R once. */
POLY_INLINE void POLY_FN(turn_normal)(const double *rotation, const R *normal, R *out)
{
  for (int k = 0; k < 3; k++)
    out[k] = (R)(rotation[3 * k] * normal[0] + rotation[3 * k + 1] * normal[1] + rotation[3 * k + 2] * normal[2]);
}

/* The plane of `tri` as the predicates take it: (v1 - v0) x (v2 - v0) and |v1 - v0|_1 |v2 - v0|_1. */
POLY_INLINE void POLY_FN(triangle_plane)(const R *vertices, const int *tri, R *plane)
{
  R e1[3], e2[3];
  POLY_FN(sub)(vertices + 3 * tri[1], vertices + 3 * tri[0], e1);
  POLY_FN(sub)(vertices + 3 * tri[2], vertices + 3 * tri[0], e2);
  POLY_FN(cross)(e1, e2, plane);
  plane[3] = POLY_FN(norm1)(e1) * POLY_FN(norm1)(e2);
}

/* For a triangle that survives the filter: its plane for the predicates
 * ((v1-v0)x(v2-v0) and |v1-v0|_1 |v2-v0|_1), its box grown by `grow` (boxes
 * only cull, so a grown box is safe; grown by the flush tolerance, the pair
 * loop's one box test also finds flush faces a hair apart), and the body's box
 * of kept triangles grown to hold it. */
POLY_INLINE void POLY_FN(prepare_kept_triangle)(const R *vertices, const int *tri, R grow, R *plane, R *bounds,
                                                R *box_low, R *box_high)
{
  POLY_FN(triangle_bounds)(vertices, tri, bounds, bounds + 3);
  for (int k = 0; k < 3; k++) {
    bounds[k] -= grow;
    bounds[3 + k] += grow;
    box_low[k] = bounds[k] < box_low[k] ? bounds[k] : box_low[k]; /* minimum and maximum instructions */
    box_high[k] = bounds[3 + k] > box_high[k] ? bounds[3 + k] : box_high[k];
  }
  POLY_FN(triangle_plane)(vertices, tri, plane);
}

/* The half-space filter's slab (eqs. 5.3-5.4): the filtering direction
 * `axis_d` (the centre line; any direction is valid), the highest extent of A
 * and the lowest of B along it (B's vertices taken to A's body frame in
 * double). Returns 1 when the bodies do not overlap along it, so neither do
 * they: the GPU also uses it to skip such pairs before the overlap kernel. */
POLY_INLINE int POLY_FN(overlap_slab_extremes)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                               const double *rotation, const double *translation, double *axis_d,
                                               double *extent_a, double *extent_b, int *extreme_a, int *extreme_b);

POLY_INLINE int POLY_FN(overlap_slab)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                      const double *rotation, const double *translation, double *axis_d,
                                      double *extent_a, double *extent_b)
{
  int extreme_a, extreme_b;
  return POLY_FN(overlap_slab_extremes)(a, b, rotation, translation, axis_d, extent_a, extent_b, &extreme_a,
                                        &extreme_b);
}

/* The highest place of `body`'s vertices along `direction`, plus `shift`, and the first vertex there (*extreme left
 * as it is when none is above -1e300). Two running maxima, of the even and the odd vertices, without a branch: one
 * chain of comparisons took a branch per vertex, and as long as the vertices (this was a sixteenth of the hopper's
 * rocks). */
POLY_INLINE double POLY_FN(highest_vertex)(const POLY_FN(shape_view) *body, const double *direction, double shift,
                                           int *extreme)
{
  const R *v = body->vertices;
  const int cell = body->extreme_start ? poly_extreme_cell(direction) : -1;
  if (cell >= 0) {
    /* The few that can be highest (poly_extremes.h), in ascending order: the same first highest. */
    double high = -1e300;
    int at = *extreme;
    for (int m = body->extreme_start[cell]; m < body->extreme_start[cell + 1]; m++) {
      const int i = body->extreme_vertices[m];
      const double along = direction[0] * v[3 * i] + direction[1] * v[3 * i + 1] + direction[2] * v[3 * i + 2] + shift;
      at = along > high ? i : at;
      high = along > high ? along : high;
    }
    *extreme = at;
    return high;
  }
  double high0 = -1e300, high1 = -1e300;
  int at0 = *extreme, at1 = *extreme;
  const int n = body->num_vertices;
  for (int i = 0; i < n; i += 2) {
    const int j = i + 1 < n ? i + 1 : i;
    const double along0 = direction[0] * v[3 * i] + direction[1] * v[3 * i + 1] + direction[2] * v[3 * i + 2] + shift;
    const double along1 = direction[0] * v[3 * j] + direction[1] * v[3 * j + 1] + direction[2] * v[3 * j + 2] + shift;
    at0 = along0 > high0 ? i : at0;
    high0 = along0 > high0 ? along0 : high0;
    at1 = along1 > high1 ? j : at1;
    high1 = along1 > high1 ? along1 : high1;
  }
  const int odd = high1 > high0 || (high1 == high0 && at1 < at0);
  *extreme = odd ? at1 : at0;
  return odd ? high1 : high0;
}

/* overlap_slab, which also gives the vertices at A's highest and B's lowest extent. */
POLY_INLINE int POLY_FN(overlap_slab_extremes)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                               const double *rotation, const double *translation, double *axis_d,
                                               double *extent_a, double *extent_b, int *extreme_a, int *extreme_b)
{
  /* Filtering direction (eq. 5.3): the centre line; any direction is valid. */
  double distance = sqrt(translation[0] * translation[0] + translation[1] * translation[1] +
                         translation[2] * translation[2]);
  axis_d[0] = 1.0;
  axis_d[1] = axis_d[2] = 0.0;
  if (distance > 1e-12 * ((double)a->bounding_radius + (double)b->bounding_radius))
    for (int k = 0; k < 3; k++) axis_d[k] = translation[k] / distance;

  /* B's vertices along the axis: axis . (R v + T) = (R^T axis) . v + axis . T, without turning each vertex. */
  double turned[3], shift = axis_d[0] * translation[0] + axis_d[1] * translation[1] + axis_d[2] * translation[2];
  for (int i = 0; i < 3; i++)
    turned[i] = rotation[i] * axis_d[0] + rotation[3 + i] * axis_d[1] + rotation[6 + i] * axis_d[2];
  const double minus_turned[3] = {-turned[0], -turned[1], -turned[2]};
  const double high_a = POLY_FN(highest_vertex)(a, axis_d, -0.0, extreme_a); /* x + -0 is x, bit for bit */
  const double low_b = -POLY_FN(highest_vertex)(b, minus_turned, -shift, extreme_b);
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
  int separating;       /* filtered out by a supporting triangle: its code (support_separated); else -1 */
  double gap;           /* filtered out: the gap proved (proved_gap); else 0 */
} POLY_FN(pass);

/* Length of the finite shift of the flush-face smoothing (see overlap_local),
 * relative to the particles' size: far above the rounding of the local
 * coordinates (about 1e-16 of the size in double, 6e-8 in single), far below
 * any overlap the contact law resolves. */
POLY_INLINE double POLY_FN(smoothing_length)(void) { return sizeof(R) == sizeof(float) ? 0x1p-16 : 0x1p-36; }

/* A separation a filter found (the slab's along the centre line, or a supporting triangle's plane), made a
 * distance the bodies are proved apart by: less the filter's own rounding and its tolerances, the rounding of the
 * local coordinates of any later evaluation in R and the flush faces' tolerance (overlap_local), so that no
 * evaluation of a pair apart by more can find a volume. 0 when nothing is left. The pair style skips a pair
 * while the particles have moved less than this since (poly_overlap_result's gap). */
POLY_INLINE double POLY_FN(proved_gap)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                       double separation)
{
  const double size = (double)a->bounding_radius + (double)b->bounding_radius;
  const double gap =
      separation - (1e-12 + 256.0 * (double)POLY_FN(epsilon)() + 8.0 * POLY_FN(smoothing_length)()) * size;
  return gap > 0.0 ? gap : 0.0;
}

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

/* What the half-space filter of overlap_pass leaves for the paths that make
 * the sums: the centre line and the slab's limits for A's and B's parts, the
 * flush tolerance, the boxes of the kept triangles, and rays along the
 * coordinate axis closest to the centre line pointing away from the other body
 * (axis-aligned rays make the box test reject almost every triangle). */
typedef struct POLY_FN(filtered) {
  R axis[3];
  R limit_a, limit_b; /* B lies at >= limit_a along the axis, A at <= limit_b */
  R tolerance;
  R box_a_low[3], box_a_high[3], box_b_low[3], box_b_high[3];
  R ray_a[3], ray_b[3], ray_length;
  int num_kept_a, num_kept_b;
} POLY_FN(filtered);

#include "poly_overlap_reference_impl.h"
#include "poly_overlap_records_impl.h"
#include "poly_overlap_parting_impl.h"
#include "poly_overlap_convex_impl.h"
#include "poly_overlap_blocks_impl.h"

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
  out->separating = -1;
  out->gap = 0.0;
  out->num_kept_a = out->num_kept_b = 0;
  int capacity_points = ws->capacity_points;

  double axis_d[3], extent_a, extent_b;
#if POLY_OVERLAP_RECORDS
  int extreme_a = 0, extreme_b = 0;
  int separated = POLY_FN(overlap_slab_extremes)(a, b, rotation, translation, axis_d, &extent_a, &extent_b,
                                                 &extreme_a, &extreme_b);
#else
  int separated = POLY_FN(overlap_slab)(a, b, rotation, translation, axis_d, &extent_a, &extent_b);
#endif
  for (int k = 0; k < 3; k++) out->axis[k] = axis_d[k];
  double separation = extent_b - extent_a; /* by the slab; a parting plane's when one parts them */
#if POLY_OVERLAP_RECORDS
  /* A pair whose cache's certificate holds is evaluated from it (cache_replay below). A contact so certified has
   * no parting plane: its boundaries cross, or a vertex of one lies inside the other; its supporting triangles are
   * tried only if the replay does not take it. */
  const poly_crossing_cache *cache = ws->crossing_cache;
  const double cache_motion = !separated && ws->cache_pass && cache && ws->use_records
                                  ? POLY_FN(cache_held_motion)(cache, a, b, rotation, translation)
                                  : -1.0;
  int support_later = 0;
  if (!separated && use_filter && !(a->face_of && b->face_of) && a->support && b->support &&
      ws->last_evaluation != POLY_LAST_TOUCHING) {
    support_later = cache_motion >= 0.0 && (cache->num_records > 0 || cache->num_inside > 0);
    if (!support_later)
      separated = POLY_FN(support_separated)(a, b, rotation, translation, axis_d, extreme_a, extreme_b,
                                             &out->separating, &separation);
  }
  if (!separated && use_filter && ws->last_evaluation == POLY_LAST_APART && ws->cache_pass && !support_later)
    separated = POLY_FN(parting_search)(a, b, rotation, translation, extreme_a, extreme_b, &separation);
#endif
  if (separated && use_filter) {
    out->filtered_out = 1;
    out->gap = POLY_FN(proved_gap)(a, b, separation);
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

#if POLY_OVERLAP_RECORDS
  /* A contact whose crossings are certified since its last search: their sums without the filter and search. */
  if (cache_motion >= 0.0 &&
      POLY_FN(cache_replay)(a, va, b, vb, rotation, translation, cache_motion, tolerance, ws, out)) {
    ws->capacity_points = capacity_points;
    return;
  }
  if (support_later &&
      (POLY_FN(support_separated)(a, b, rotation, translation, axis_d, extreme_a, extreme_b, &out->separating,
                                  &separation) ||
       (ws->last_evaluation == POLY_LAST_APART &&
        POLY_FN(parting_search)(a, b, rotation, translation, extreme_a, extreme_b, &separation)))) {
    out->filtered_out = 1;
    out->gap = POLY_FN(proved_gap)(a, b, separation);
    ws->capacity_points = capacity_points;
    return;
  }
#endif
  /* Small convex shapes: the blocks path needs no filter. */
#if POLY_OVERLAP_RECORDS
  int blocks_failed = 0;
  if (use_filter && ws->use_records && ws->use_convex && POLY_FN(blocks_fit)(a, b, ws)) {
    int status = POLY_FN(blocks_path)(a, va, b, vb, rotation, tolerance, ws, out);
    if (status >= 0) {
      out->filtered_out = status == 1;
      ws->capacity_points = capacity_points;
      return;
    }
    blocks_failed = status == -1;
    ws->convex_fallbacks += blocks_failed;
  }
#endif

  /* Half-space filter (eq. 5.5) and bounding boxes of what survives. */
  R box_a_low[3] = {(R)1e30, (R)1e30, (R)1e30}, box_a_high[3] = {(R)-1e30, (R)-1e30, (R)-1e30};
  R box_b_low[3] = {(R)1e30, (R)1e30, (R)1e30}, box_b_high[3] = {(R)-1e30, (R)-1e30, (R)-1e30};
  const R *along_a = NULL, *along_b = NULL;
  const unsigned char *in_slab_a = NULL, *in_slab_b = NULL;
#if POLY_OVERLAP_RECORDS
  /* Each vertex's place along the axis once, for the filter, the crossings' slab and the inside states (a vertex
   * is in about six edges and six triangles: rock_1000's pairs spent a tenth of their time on these products),
   * and whether it reaches the slab, for the filter's triangles. */
  for (int i = 0; i < a->num_vertices; i++) {
    ws->along_a[i] = POLY_FN(dot)(va + 3 * i, axis);
    ws->in_slab_a[i] = (unsigned char)(ws->along_a[i] >= limit_a);
  }
  for (int j = 0; j < b->num_vertices; j++) {
    ws->along_b[j] = POLY_FN(dot)(vb + 3 * j, axis);
    ws->in_slab_b[j] = (unsigned char)(ws->along_b[j] <= limit_b);
  }
  along_a = ws->along_a;
  along_b = ws->along_b;
  in_slab_a = ws->in_slab_a;
  in_slab_b = ws->in_slab_b;
#endif
  const int num_kept_a = POLY_FN(keep_in_slab)(a, va, along_a, in_slab_a, axis, limit_a, 0, ws->kept_a, ws->apex_a,
                                               ws->kept_list_a);
  const int num_kept_b = POLY_FN(keep_in_slab)(b, vb, along_b, in_slab_b, axis, limit_b, 1, ws->kept_b, ws->apex_b,
                                               ws->kept_list_b);
  for (int n = 0; n < num_kept_a; n++) {
    const int t = ws->kept_list_a[n];
    POLY_FN(prepare_kept_triangle)(va, a->triangles + 3 * t, tolerance, ws->planes_a + 4 * t, ws->bounds_a + 6 * t,
                                   box_a_low, box_a_high);
  }
  for (int n = 0; n < num_kept_b; n++) {
    const int s = ws->kept_list_b[n];
    POLY_FN(prepare_kept_triangle)(vb, b->triangles + 3 * s, tolerance, ws->planes_b + 4 * s, ws->bounds_b + 6 * s,
                                   box_b_low, box_b_high);
    POLY_FN(turn_normal)(rotation, b->face_normals + 3 * s, ws->normals_b + 3 * s);
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
  POLY_FN(filtered) f = {{axis[0], axis[1], axis[2]}, limit_a, limit_b, tolerance,
                         {box_a_low[0], box_a_low[1], box_a_low[2]}, {box_a_high[0], box_a_high[1], box_a_high[2]},
                         {box_b_low[0], box_b_low[1], box_b_low[2]}, {box_b_high[0], box_b_high[1], box_b_high[2]},
                         {ray_a[0], ray_a[1], ray_a[2]}, {ray_b[0], ray_b[1], ray_b[2]}, ray_length,
                         num_kept_a, num_kept_b};
  /* The sums by the cheapest path that can decide them: convex shapes' face
   * table, the crossing records, or the reference path. */
  int done = 0;
#if POLY_OVERLAP_RECORDS
  /* Not compiled for the GPU, which never takes them: their frames and registers would weigh on its one
   * kernel (its double-precision throughput fell by 30 % when they grew). */
  if (ws->use_records && ws->use_convex && use_filter && a->face_of && b->face_of && !blocks_failed) {
    done = POLY_FN(convex_path)(a, va, b, vb, rotation, &f, ws, out) == 0;
    if (!done) ws->convex_fallbacks++;
  }
  if (!done && ws->use_records) {
    done = POLY_FN(records_path)(a, va, b, vb, rotation, translation, &f, ws, out) == 0;
    if (!done) ws->records_overflows++;
  }
#endif
  if (!done) POLY_FN(reference_path)(a, va, b, vb, &f, ws, out);
  out->num_kept_a = num_kept_a;
  out->num_kept_b = num_kept_b;
  ws->capacity_points = capacity_points;
}


#include "poly_overlap_local_impl.h"

#undef POLY_NO_APEX
#undef R
#undef ACC
