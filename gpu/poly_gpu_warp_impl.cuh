/* One pair's overlap on one warp, or on a group of 8 or 16 of its lanes
 * (poly_lanes): the reference path of src/poly_overlap_impl.h (half-space
 * filter, inside tests by ray parity, every edge against the other body's kept
 * triangles, every pair of kept triangles) with its loops spread over the
 * group's lanes and its arrays in the group's block of shared memory,
 * instead of one thread running the whole of it (whose warps ran 5 of 32 lanes
 * on average, tools/bench_gpu.sh's profile in doc/gpu.md). Every predicate is
 * the host's own function on the host's own numbers, so each decision is the
 * same bit; what differs is the order of the sums and the choice of the points
 * the boundary tetrahedra are built on:
 *
 * - a facet's apex is the node of its first crossing record (records are
 *   numbered in edge order, each edge's crossings along it), or its first
 *   corner when no crossing lies on it (then the facet is wholly inside);
 * - the common vertex O is the first record's node, else the first vertex
 *   inside the other body.
 *
 * Both lie on the overlap, as on the host, so the tetrahedra stay its size.
 * The lanes' sums are added in a fixed tree, so runs repeat bit for bit.
 *
 * What the warp does not handle it hands back (returns 1) for the one-thread
 * kernel, which does all of overlap_local: flush faces (smoothing), an edge
 * inconsistent with its ends (re-evaluation), more crossings than the records
 * or an edge's list hold. Included by poly_gpu.cu once per precision, with
 * POLY_FN as for poly_overlap_impl.h (no include guard). */
#define R POLY_FN(real)
#define ACC POLY_FN(accum)

#ifndef POLY_GPU_LANES
#define POLY_GPU_LANES
/* The lanes that share one pair: `size` (8, 16 or 32) consecutive lanes of a warp from `base`; `lane` counts
 * from 0 within them. */
struct poly_lanes {
  int lane, size, base;
  unsigned mask;
};
static __device__ inline poly_lanes poly_lanes_of(int size)
{
  poly_lanes g;
  int warp_lane = threadIdx.x & 31;
  g.size = size;
  g.base = warp_lane & ~(size - 1);
  g.lane = warp_lane - g.base;
  g.mask = size == 32 ? 0xffffffffu : ((1u << size) - 1u) << g.base;
  return g;
}
/* The group's ballot, bit l for its lane l. */
static __device__ inline unsigned poly_lanes_ballot(const poly_lanes &g, int predicate)
{
  unsigned bits = __ballot_sync(g.mask, predicate) >> g.base;
  return g.size == 32 ? bits : bits & ((1u << g.size) - 1u);
}
#endif

/* An edge's crossings with the other body, sorted along it, before they go to the records. */
#ifndef POLY_WARP_EDGE_CROSSINGS
#define POLY_WARP_EDGE_CROSSINGS 16
#endif

/* The warp's shared arrays (pointers into its block). */
typedef struct POLY_FN(warp_memory) {
  R *va, *vb, *planes_a, *planes_b, *normals_b, *bounds_a, *bounds_b, *apex_a, *apex_b;
  R *record_lambda, *record_entering;
  int *kept_list_a, *kept_list_b, *apex_key_a, *apex_key_b, *record_triangle, *record_edge, *run_start, *run_count;
  unsigned char *inside_a, *inside_b;
  int capacity_records;
} POLY_FN(warp_memory);

/* Bytes of one warp's block for shapes of up to nv vertices, nt triangles and ne edges, and nr crossing
 * records; with `m` and `memory` given, points m's arrays into the block. */
static __host__ __device__ inline size_t POLY_FN(warp_layout)(POLY_FN(warp_memory) *m, char *memory, int nv, int nt, int ne, int nr)
{
  size_t reals = 6 * (size_t)nv + 8 * (size_t)nt + 3 * (size_t)nt + 12 * (size_t)nt + 6 * (size_t)nt + 2 * (size_t)nr;
  size_t ints = 4 * (size_t)nt + 2 * (size_t)nr + 4 * (size_t)ne;
  size_t bytes = sizeof(R) * reals + sizeof(int) * ints + 2 * (size_t)nv;
  bytes = (bytes + 15) / 16 * 16;
  if (!m || !memory) return bytes;
  R *r = (R *)memory;
  m->va = r; r += 3 * nv;
  m->vb = r; r += 3 * nv;
  m->planes_a = r; r += 4 * nt;
  m->planes_b = r; r += 4 * nt;
  m->normals_b = r; r += 3 * nt;
  m->bounds_a = r; r += 6 * nt;
  m->bounds_b = r; r += 6 * nt;
  m->apex_a = r; r += 3 * nt;
  m->apex_b = r; r += 3 * nt;
  m->record_lambda = r; r += nr;
  m->record_entering = r; r += nr;
  int *n = (int *)r;
  m->kept_list_a = n; n += nt;
  m->kept_list_b = n; n += nt;
  m->apex_key_a = n; n += nt;
  m->apex_key_b = n; n += nt;
  m->record_triangle = n; n += nr;
  m->record_edge = n; n += nr;
  m->run_start = n; n += 2 * ne;
  m->run_count = n; n += 2 * ne;
  unsigned char *c = (unsigned char *)n;
  m->inside_a = c; c += nv;
  m->inside_b = c;
  m->capacity_records = nr;
  return bytes;
}

/* The pieces of the warp's shared work that its lanes compute each for themselves. */
static __device__ inline double POLY_FN(warp_max)(const poly_lanes &g, double x)
{
  for (int offset = g.size / 2; offset > 0; offset >>= 1) x = fmax(x, __shfl_xor_sync(g.mask, x, offset, g.size));
  return x;
}
static __device__ inline double POLY_FN(warp_min)(const poly_lanes &g, double x)
{
  for (int offset = g.size / 2; offset > 0; offset >>= 1) x = fmin(x, __shfl_xor_sync(g.mask, x, offset, g.size));
  return x;
}
static __device__ inline R POLY_FN(warp_max_r)(const poly_lanes &g, R x)
{
  for (int offset = g.size / 2; offset > 0; offset >>= 1) {
    R y = __shfl_xor_sync(g.mask, x, offset, g.size);
    x = y > x ? y : x;
  }
  return x;
}
static __device__ inline R POLY_FN(warp_min_r)(const poly_lanes &g, R x)
{
  for (int offset = g.size / 2; offset > 0; offset >>= 1) {
    R y = __shfl_xor_sync(g.mask, x, offset, g.size);
    x = y < x ? y : x;
  }
  return x;
}
/* Sum over the group's lanes in a fixed tree, the total in every lane. */
template <typename T> static __device__ inline T POLY_FN(warp_sum)(const poly_lanes &g, T x)
{
  for (int offset = g.size / 2; offset > 0; offset >>= 1) x += __shfl_down_sync(g.mask, x, offset, g.size);
  return __shfl_sync(g.mask, x, 0, g.size);
}

/* The node of record r (edge g of the combined edge list: A's edges, then B's). */
static __device__ inline void POLY_FN(warp_record_node)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                           const POLY_FN(warp_memory) *m, int r, R *x)
{
  int g = m->record_edge[r];
  int of_b = g >= a->num_edges;
  const POLY_FN(shape_view) *mine = of_b ? b : a;
  int e = of_b ? g - a->num_edges : g;
  const R *vertices = of_b ? m->vb : m->va;
  const R *p0 = vertices + 3 * mine->edges[2 * e], *p1 = vertices + 3 * mine->edges[2 * e + 1];
  R direction[3];
  POLY_FN(sub)(p1, p0, direction);
  for (int k = 0; k < 3; k++) x[k] = p0[k] + m->record_lambda[r] * direction[k];
}

/* Kept triangles of one body, their planes and boxes; returns how many (the same on every lane). */
static __device__ inline int POLY_FN(warp_keep)(const POLY_FN(shape_view) *body, const R *vertices, int of_b, const R *axis, R limit,
                                   R tolerance, R *planes, R *bounds, int *kept_list, int *apex_key, R *box_low,
                                   R *box_high, const poly_lanes &g)
{
  int num_kept = 0;
  R low[3] = {(R)1e30, (R)1e30, (R)1e30}, high[3] = {(R)-1e30, (R)-1e30, (R)-1e30};
  for (int base = 0; base < body->num_triangles; base += g.size) {
    int t = base + g.lane, kept = 0;
    if (t < body->num_triangles) {
      const int *tri = body->triangles + 3 * t;
      R extreme = of_b ? (R)1e30 : -(R)1e30;
      for (int k = 0; k < 3; k++) {
        R along = POLY_FN(dot)(vertices + 3 * tri[k], axis);
        if (of_b ? along < extreme : along > extreme) extreme = along;
      }
      kept = of_b ? extreme <= limit : extreme >= limit;
      apex_key[t] = 0x7fffffff;
      if (kept) POLY_FN(prepare_kept_triangle)(vertices, tri, tolerance, planes + 4 * t, bounds + 6 * t, low, high);
    }
    unsigned ballot = poly_lanes_ballot(g, kept);
    if (kept) kept_list[num_kept + __popc(ballot & ((1u << g.lane) - 1u))] = t;
    num_kept += __popc(ballot);
  }
  for (int k = 0; k < 3; k++) {
    box_low[k] = POLY_FN(warp_min_r)(g, low[k]);
    box_high[k] = POLY_FN(warp_max_r)(g, high[k]);
  }
  return num_kept;
}

/* Every edge of both bodies against the other's kept triangles, 32 edges at a
 * time: each lane sorts its edge's crossings, then the warp writes them to the
 * records in edge order. Marks each facet's first record (apex_key). Returns
 * the number of records, or -1 when something must go to the one-thread
 * kernel (an edge with too many crossings or inconsistent with its ends, or
 * the records full). */
static __device__ inline int POLY_FN(warp_edges)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                    const POLY_FN(warp_memory) *m, int num_kept_a, int num_kept_b, const R *axis,
                                    R limit_a, R limit_b, const poly_lanes &g)
{
  int total = 0, trouble = 0;
  const int num_edges = a->num_edges + b->num_edges;
  for (int base = 0; base < num_edges; base += g.size) {
    int edge = base + g.lane, count = 0, skipped = 1;
    R lambdas[POLY_WARP_EDGE_CROSSINGS], entering[POLY_WARP_EDGE_CROSSINGS];
    int crossed[POLY_WARP_EDGE_CROSSINGS];
    if (edge < num_edges) {
      int of_b = edge >= a->num_edges, e = of_b ? edge - a->num_edges : edge;
      const POLY_FN(shape_view) *mine = of_b ? b : a, *other = of_b ? a : b;
      const R *my_vertices = of_b ? m->vb : m->va, *other_vertices = of_b ? m->va : m->vb;
      const R *other_planes = of_b ? m->planes_a : m->planes_b, *other_bounds = of_b ? m->bounds_a : m->bounds_b;
      const int *other_kept = of_b ? m->kept_list_a : m->kept_list_b;
      const unsigned char *my_inside = of_b ? m->inside_b : m->inside_a;
      int other_num_kept = of_b ? num_kept_a : num_kept_b;
      R slab_limit = of_b ? limit_b : limit_a;
      int v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
      const R *p0 = my_vertices + 3 * v0, *p1 = my_vertices + 3 * v1;
      R d0 = POLY_FN(dot)(p0, axis), d1 = POLY_FN(dot)(p1, axis);
      skipped = !of_b ? (d0 < slab_limit && d1 < slab_limit) : (d0 > slab_limit && d1 > slab_limit);
      if (!skipped) {
        R low[3], high[3];
        POLY_FN(segment_bounds)(p0, p1, low, high);
        for (int n = 0; n < other_num_kept; n++) {
          int t = other_kept[n];
          if (!POLY_FN(boxes_overlap)(low, high, other_bounds + 6 * t)) continue;
          R lambda;
          int side = POLY_FN(segment_crosses_triangle)(p0, p1, of_b, other_vertices, other->triangles + 3 * t,
                                                       other_planes + 4 * t, &lambda);
          if (!side) continue;
          if (count == POLY_WARP_EDGE_CROSSINGS) {
            trouble = 1;
            break;
          }
          int slot = count++;
          while (slot > 0 && lambdas[slot - 1] > lambda) {
            lambdas[slot] = lambdas[slot - 1];
            entering[slot] = entering[slot - 1];
            crossed[slot] = crossed[slot - 1];
            slot--;
          }
          lambdas[slot] = lambda;
          entering[slot] = side > 0 ? (R)1 : (R)-1;
          crossed[slot] = t;
        }
        if (((my_inside[v0] + count) & 1) != my_inside[v1]) trouble = 1;
      }
    }
    /* The records of this round's edges, in edge order. */
    int before = count;
    for (int offset = 1; offset < g.size; offset <<= 1) {
      int other = __shfl_up_sync(g.mask, before, offset, g.size);
      if (g.lane >= offset) before += other;
    }
    int round_total = __shfl_sync(g.mask, before, g.size - 1, g.size);
    int start = total + before - count;
    if (total + round_total > m->capacity_records) trouble = 1;
    else if (edge < num_edges) {
      m->run_start[edge] = skipped ? -1 : start;
      m->run_count[edge] = count;
      int of_b = edge >= a->num_edges, e = of_b ? edge - a->num_edges : edge;
      const POLY_FN(shape_view) *mine = of_b ? b : a;
      int *my_keys = of_b ? m->apex_key_b : m->apex_key_a, *other_keys = of_b ? m->apex_key_a : m->apex_key_b;
      for (int c = 0; c < count; c++) {
        int r = start + c;
        m->record_lambda[r] = lambdas[c];
        m->record_entering[r] = entering[c];
        m->record_triangle[r] = crossed[c];
        m->record_edge[r] = edge;
        atomicMin(my_keys + mine->edge_triangles[2 * e], r);
        atomicMin(my_keys + mine->edge_triangles[2 * e + 1], r);
        atomicMin(other_keys + crossed[c], r);
      }
    }
    total += round_total;
    if (__any_sync(g.mask, trouble)) return -1;
  }
  return total;
}

/* Each kept facet's apex: its first record's node, else its first corner. */
static __device__ inline void POLY_FN(warp_apexes)(const POLY_FN(shape_view) *body, const R *vertices, const int *kept_list,
                                      int num_kept, const int *apex_key, R *apex, const POLY_FN(shape_view) *a,
                                      const POLY_FN(shape_view) *b, const POLY_FN(warp_memory) *m,
                                      const poly_lanes &g)
{
  for (int n = g.lane; n < num_kept; n += g.size) {
    int t = kept_list[n];
    R x[3];
    if (apex_key[t] != 0x7fffffff) POLY_FN(warp_record_node)(a, b, m, apex_key[t], x);
    else
      for (int k = 0; k < 3; k++) x[k] = vertices[3 * body->triangles[3 * t] + k];
    for (int k = 0; k < 3; k++) apex[3 * t + k] = x[k];
  }
}

/* The overlap of A and B (B placed by rotation and translation in A's body
 * frame) in the local frame, as overlap_local gives it, computed by the lanes
 * of g (every one calls it with the same arguments). Returns 0 with the
 * result (the same in every lane), or 1: hand the pair to the one-thread kernel.
 * With `frame` given, also where the nodes are (warp_nodes): the local frame's
 * origin in A's body frame and the number of crossing records. */
typedef struct POLY_FN(warp_frame) {
  double origin[3];
  int num_records;
} POLY_FN(warp_frame);

static __device__ inline int POLY_FN(warp_overlap)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b, const double *rotation,
                                      const double *translation, int want_second, const POLY_FN(warp_memory) *m,
                                      const poly_lanes &g, double *local_centroid, double *local_normal,
                                      poly_overlap_result *result, POLY_FN(warp_frame) *frame)
{
  const int lane = g.lane, step = g.size;
  if (frame) frame->num_records = 0;
  result->volume = result->depth = result->area = result->projected_area = 0.0;
  result->num_nodes = result->num_inconsistent = 0;
  result->filtered_out = result->recomputed = result->smoothed = 0;
  result->separating = -1;
  result->gap = 0.0;
  for (int e = 0; e < 6; e++) result->second_moment[e] = 0.0;

  /* The slab (overlap_slab): the extreme vertices, over the lanes. */
  double ra = (double)a->bounding_radius, rb = (double)b->bounding_radius;
  double distance = sqrt(translation[0] * translation[0] + translation[1] * translation[1] +
                         translation[2] * translation[2]);
  double axis_d[3] = {1.0, 0.0, 0.0};
  if (distance > 1e-12 * (ra + rb))
    for (int k = 0; k < 3; k++) axis_d[k] = translation[k] / distance;
  double high_a = -1e300, low_b = 1e300;
  for (int i = lane; i < a->num_vertices; i += step) {
    const R *v = a->vertices + 3 * i;
    double along = axis_d[0] * v[0] + axis_d[1] * v[1] + axis_d[2] * v[2];
    if (along > high_a) high_a = along;
  }
  double turned[3], shift = axis_d[0] * translation[0] + axis_d[1] * translation[1] + axis_d[2] * translation[2];
  for (int i = 0; i < 3; i++)
    turned[i] = rotation[i] * axis_d[0] + rotation[3 + i] * axis_d[1] + rotation[6 + i] * axis_d[2];
  for (int j = lane; j < b->num_vertices; j += step) {
    const R *v = b->vertices + 3 * j;
    double along = turned[0] * v[0] + turned[1] * v[1] + turned[2] * v[2] + shift;
    if (along < low_b) low_b = along;
  }
  double extent_a = POLY_FN(warp_max)(g, high_a), extent_b = POLY_FN(warp_min)(g, low_b);
  if (extent_a - extent_b <= 1e-12 * (ra + rb)) {
    result->filtered_out = 1;
    return 0;
  }

  /* The local frame and the slab's limits, as overlap_pass makes them. */
  double flush_tolerance = 4.0 * POLY_FN(smoothing_length)();
  double middle = 0.5 * (extent_a + extent_b);
  double origin[3] = {axis_d[0] * middle, axis_d[1] * middle, axis_d[2] * middle};
  if (frame)
    for (int k = 0; k < 3; k++) frame->origin[k] = origin[k];
  R axis[3] = {(R)axis_d[0], (R)axis_d[1], (R)axis_d[2]};
  R tolerance = (R)(flush_tolerance * (ra + rb));
  double scale = ra + rb + fabs(middle);
  double margin = 64.0 * (double)POLY_FN(epsilon)() * scale + flush_tolerance * (ra + rb);
  R limit_a = (R)(extent_b - middle - margin), limit_b = (R)(extent_a - middle + margin);
  for (int i = lane; i < a->num_vertices; i += step)
    for (int k = 0; k < 3; k++) m->va[3 * i + k] = (R)((double)a->vertices[3 * i + k] - origin[k]);
  for (int j = lane; j < b->num_vertices; j += step) {
    const R *v = b->vertices + 3 * j;
    for (int k = 0; k < 3; k++)
      m->vb[3 * j + k] = (R)(rotation[3 * k] * v[0] + rotation[3 * k + 1] * v[1] + rotation[3 * k + 2] * v[2] +
                             translation[k] - origin[k]);
  }
  __syncwarp(g.mask);

  /* The half-space filter; B's normals in the local frame. */
  R box_a_low[3], box_a_high[3], box_b_low[3], box_b_high[3];
  int num_kept_a = POLY_FN(warp_keep)(a, m->va, 0, axis, limit_a, tolerance, m->planes_a, m->bounds_a, m->kept_list_a,
                                      m->apex_key_a, box_a_low, box_a_high, g);
  int num_kept_b = POLY_FN(warp_keep)(b, m->vb, 1, axis, limit_b, tolerance, m->planes_b, m->bounds_b, m->kept_list_b,
                                      m->apex_key_b, box_b_low, box_b_high, g);
  if (!num_kept_a || !num_kept_b) {
    result->filtered_out = 1;
    return 0;
  }
  __syncwarp(g.mask);
  for (int n = lane; n < num_kept_b; n += step) {
    int s = m->kept_list_b[n];
    const R *normal = b->face_normals + 3 * s;
    for (int k = 0; k < 3; k++)
      m->normals_b[3 * s + k] = (R)(rotation[3 * k] * normal[0] + rotation[3 * k + 1] * normal[1] +
                                    rotation[3 * k + 2] * normal[2]);
  }

  /* Vertices inside the other body (reference_path): rays along the coordinate axis closest to the centre line. */
  R ray_length = (R)(4.0 * (ra + rb) + (extent_a - extent_b));
  int ray_axis = 0;
  for (int k = 1; k < 3; k++)
    if (fabs(axis_d[k]) > fabs(axis_d[ray_axis])) ray_axis = k;
  R ray_b[3] = {0, 0, 0}, ray_a[3] = {0, 0, 0};
  ray_b[ray_axis] = axis_d[ray_axis] > 0 ? (R)1 : (R)-1;
  ray_a[ray_axis] = -ray_b[ray_axis];
  int num_points = 0;
  for (int i = lane; i < a->num_vertices; i += step) {
    const R *x = m->va + 3 * i;
    int candidate = POLY_FN(dot)(x, axis) >= limit_a;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= box_b_low[k] && x[k] <= box_b_high[k];
    int inside = candidate && POLY_FN(point_inside)(x, ray_a, ray_length, 0, m->vb, b->triangles, m->planes_b,
                                                    m->bounds_b, m->kept_list_b, num_kept_b);
    m->inside_a[i] = (unsigned char)inside;
    num_points += inside;
  }
  for (int j = lane; j < b->num_vertices; j += step) {
    const R *x = m->vb + 3 * j;
    int candidate = POLY_FN(dot)(x, axis) <= limit_b;
    for (int k = 0; k < 3 && candidate; k++) candidate = x[k] >= box_a_low[k] && x[k] <= box_a_high[k];
    int inside = candidate && POLY_FN(point_inside)(x, ray_b, ray_length, 1, m->va, a->triangles, m->planes_a,
                                                    m->bounds_a, m->kept_list_a, num_kept_a);
    m->inside_b[j] = (unsigned char)inside;
    num_points += inside;
  }
  __syncwarp(g.mask);

  int num_records = POLY_FN(warp_edges)(a, b, m, num_kept_a, num_kept_b, axis, limit_a, limit_b, g);
  if (num_records < 0) return 1;
  if (frame) frame->num_records = num_records;
  __syncwarp(g.mask);
  POLY_FN(warp_apexes)(a, m->va, m->kept_list_a, num_kept_a, m->apex_key_a, m->apex_a, a, b, m, g);
  POLY_FN(warp_apexes)(b, m->vb, m->kept_list_b, num_kept_b, m->apex_key_b, m->apex_b, a, b, m, g);
  __syncwarp(g.mask);

  /* O: the first record's node, else the first vertex inside the other body; none: no boundary, no overlap. */
  POLY_FN(accumulator) acc = {0, {0, 0, 0}, {0, 0, 0}, 0, {0, 0, 0}, 1, want_second, {0, 0, 0, 0, 0, 0}};
  if (num_records > 0) POLY_FN(warp_record_node)(a, b, m, 0, acc.reference);
  else {
    int found = 0;
    for (int body = 0; body < 2 && !found; body++) {
      const POLY_FN(shape_view) *mine = body ? b : a;
      const unsigned char *inside = body ? m->inside_b : m->inside_a;
      const R *vertices = body ? m->vb : m->va;
      for (int base = 0; base < mine->num_vertices && !found; base += step) {
        unsigned ballot = poly_lanes_ballot(g, base + lane < mine->num_vertices && inside[base + lane]);
        if (!ballot) continue;
        int first = base + __ffs(ballot) - 1;
        for (int k = 0; k < 3; k++) acc.reference[k] = vertices[3 * first + k];
        found = 1;
      }
    }
    if (!found) return 0;
  }

  /* The boundary segments: inside parts of the edges, then the chords of the triangle pairs. A workspace
   * with no room for nodes, as edge_inside_parts and accumulate_triangle_pair take one: they only count
   * nodes and read the apexes. */
  POLY_FN(overlap_workspace) ws;
  ws.capacity_points = 0;
  ws.apex_a = m->apex_a;
  ws.apex_b = m->apex_b;
  const int num_edges = a->num_edges + b->num_edges;
  for (int edge = lane; edge < num_edges; edge += step) {
    if (m->run_start[edge] < 0) continue;
    int of_b = edge >= a->num_edges, e = of_b ? edge - a->num_edges : edge;
    const POLY_FN(shape_view) *mine = of_b ? b : a;
    const R *vertices = of_b ? m->vb : m->va;
    int v0 = mine->edges[2 * e], v1 = mine->edges[2 * e + 1];
    int start = m->run_start[edge];
    POLY_FN(edge_inside_parts)(mine, e, vertices + 3 * v0, vertices + 3 * v1, (of_b ? m->inside_b : m->inside_a)[v0],
                               m->record_lambda + start, m->record_entering + start, m->run_count[edge],
                               of_b ? m->normals_b : a->face_normals, of_b ? m->apex_b : m->apex_a, of_b, NULL, &ws,
                               &acc, &num_points);
  }
  int flush = 0;
  const int num_pairs = num_kept_a * num_kept_b;
  for (int q = lane; q < num_pairs; q += step) {
    int t = m->kept_list_a[q / num_kept_b], s = m->kept_list_b[q % num_kept_b];
    const R *box_t = m->bounds_a + 6 * t, *box_s = m->bounds_b + 6 * s;
    if (!POLY_FN(boxes_overlap)(box_t, box_t + 3, box_s)) continue;
    if (!flush)
      flush = POLY_FN(triangles_flush)(m->va, a->triangles + 3 * t, m->planes_a + 4 * t, a->face_normals + 3 * t,
                                       m->vb, b->triangles + 3 * s, m->planes_b + 4 * s, m->normals_b + 3 * s,
                                       tolerance);
    POLY_FN(accumulate_triangle_pair)(a, m->va, m->planes_a, a->face_normals, t, b, m->vb, m->planes_b, m->normals_b,
                                      s, &ws, &acc);
  }
  if (__any_sync(g.mask, flush)) return 1;

  /* The lanes' sums, in a fixed order. */
  ACC volume6 = POLY_FN(warp_sum)(g, acc.volume6);
  if (!((double)volume6 > 0.0)) {
    result->num_nodes = POLY_FN(warp_sum)(g, num_points);
    return 0;
  }
  ACC moment24[3], area_normal[3];
  for (int k = 0; k < 3; k++) {
    moment24[k] = POLY_FN(warp_sum)(g, acc.moment24[k]);
    area_normal[k] = POLY_FN(warp_sum)(g, acc.area_normal[k]);
  }
  ACC area = POLY_FN(warp_sum)(g, acc.area);
  result->num_nodes = POLY_FN(warp_sum)(g, num_points);
  double volume = (double)volume6 / 6.0;
  result->volume = volume;
  for (int k = 0; k < 3; k++)
    local_centroid[k] = (double)moment24[k] / (24.0 * volume) + (double)acc.reference[k] + origin[k];
  result->area = (double)area;
  if (want_second) {
    for (int e = 0; e < 6; e++) result->second_moment[e] = POLY_FN(warp_sum)(g, acc.second120[e]) / 120.0;
    double from_reference[3];
    for (int k = 0; k < 3; k++) from_reference[k] = (double)moment24[k] / (24.0 * volume);
    poly_second_moment_to_centroid(result->second_moment, volume, from_reference);
  }
  double normal[3] = {(double)area_normal[0], (double)area_normal[1], (double)area_normal[2]};
  double length = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  result->projected_area = length;
  if (length > 1e-9 * (double)area && length > 0.0)
    for (int k = 0; k < 3; k++) local_normal[k] = normal[k] / length;
  else
    for (int k = 0; k < 3; k++) local_normal[k] = axis_d[k];

  /* Depth: extent of the nodes (vertices inside, crossings) along the normal. */
  double low = 1e300, high = -1e300;
  for (int body = 0; body < 2; body++) {
    const POLY_FN(shape_view) *mine = body ? b : a;
    const unsigned char *inside = body ? m->inside_b : m->inside_a;
    const R *vertices = body ? m->vb : m->va;
    for (int i = lane; i < mine->num_vertices; i += step) {
      if (!inside[i]) continue;
      const R *x = vertices + 3 * i;
      double along = local_normal[0] * x[0] + local_normal[1] * x[1] + local_normal[2] * x[2];
      low = along < low ? along : low;
      high = along > high ? along : high;
    }
  }
  for (int r = lane; r < num_records; r += step) {
    R x[3];
    POLY_FN(warp_record_node)(a, b, m, r, x);
    double along = local_normal[0] * x[0] + local_normal[1] * x[1] + local_normal[2] * x[2];
    low = along < low ? along : low;
    high = along > high ? along : high;
  }
  low = POLY_FN(warp_min)(g, low);
  high = POLY_FN(warp_max)(g, high);
  result->depth = high > low ? high - low : 0.0;
  return 0;
}

/* The nodes of an overlap warp_overlap found (returned 0, `frame` given), as the host's workspace holds them
 * (vertices inside the other body, then the crossings, in the local frame): A's inside vertices in vertex
 * order, then B's, then the records in order, turned by `rotation_a` into out[3 * n] relative to A's
 * position (as poly_overlap_nodes_d gives them). Every lane of g calls it. */
static __device__ inline void POLY_FN(warp_nodes)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                    const POLY_FN(warp_memory) *m, const POLY_FN(warp_frame) *frame,
                                    const double *rotation_a, const poly_lanes &g, double *out)
{
  int written = 0;
  for (int body = 0; body < 2; body++) {
    const POLY_FN(shape_view) *mine = body ? b : a;
    const unsigned char *inside = body ? m->inside_b : m->inside_a;
    const R *vertices = body ? m->vb : m->va;
    for (int base = 0; base < mine->num_vertices; base += g.size) {
      int i = base + g.lane, take = i < mine->num_vertices && inside[i];
      unsigned ballot = poly_lanes_ballot(g, take);
      if (take) {
        double point[3];
        for (int k = 0; k < 3; k++) point[k] = (double)vertices[3 * i + k] + frame->origin[k];
        poly_matrix_apply(rotation_a, point, out + 3 * (size_t)(written + __popc(ballot & ((1u << g.lane) - 1u))));
      }
      written += __popc(ballot);
    }
  }
  for (int r = g.lane; r < frame->num_records; r += g.size) {
    R x[3];
    POLY_FN(warp_record_node)(a, b, m, r, x);
    double point[3];
    for (int k = 0; k < 3; k++) point[k] = (double)x[k] + frame->origin[k];
    poly_matrix_apply(rotation_a, point, out + 3 * (size_t)(written + r));
  }
}

#undef R
#undef ACC
