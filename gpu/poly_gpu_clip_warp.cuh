/* The clipping path (src/poly_clip.h) with one warp per pair, in double (in
 * mixed precision the faces clipped in single and summed in double, as the
 * general path's mixed precision does): the same pieces, masks, clipping and sums as the host's poly_clip_overlap, with
 * the loops spread over the lanes instead of one thread running them all (the
 * one-thread clip_contact_kernel's warps idle most lanes while one thread
 * clips many polygons; a pair of Schoenhardt polyhedra clips 20-30 faces):
 *
 * 1. B's points and planes into A's frame, and every point's sides of the
 *    other body's planes, a point per lane;
 * 2. the pairs of pieces that no plane of either parts, a pair per lane, and
 *    their faces to clip as one list of items (face, side, other piece),
 *    less those a plane of the piece leaves wholly outside;
 * 3. an item per lane: the face clipped by the other body's piece, its
 *    polygon summed from a common corner (the first item's polygon's first
 *    corner, as on the host) and its corners kept in the warp's block;
 * 4. the lanes' sums added in a fixed tree (runs repeat bit for bit), the
 *    normal, and the depth over the kept corners (or a second clipping pass
 *    for the extent when they did not fit).
 *
 * Pairs it does not take (flush faces, more items than its block holds) go to
 * the one-thread kernel, as from clip_contact_kernel. Included by poly_gpu.cu. */
#ifndef POLY_GPU_CLIP_WARP_CUH
#define POLY_GPU_CLIP_WARP_CUH

#ifndef POLY_CLIP_WARPS
#define POLY_CLIP_WARPS 4          /* warps (pairs) per block */
#endif
#ifndef POLY_CLIP_WARP_MIN_BLOCKS
#define POLY_CLIP_WARP_MIN_BLOCKS 4 /* blocks per SM the registers are sized for (doc/benchmarks.md) */
#endif
#ifndef POLY_CLIP_WARP_PAIRS
#define POLY_CLIP_WARP_PAIRS 16    /* at most this many pairs a warp clips one after the other (ClipWarpLimits) */
#endif
#define POLY_CLIP_WARP_ITEMS 256   /* faces to clip per pair */
#define POLY_CLIP_WARP_NODES 64    /* corners kept for the depth per pair */
#ifndef POLY_CLIP_WARP_POLYGON
#define POLY_CLIP_WARP_POLYGON 12  /* corners of a clipped face (a lane's work buffers are in local memory) */
#endif

/* What one warp's block of shared memory holds, sized for the uploaded shapes. */
struct ClipWarpLimits {
  int vertices, planes, pieces;
  int pairs;  /* pairs a warp clips one after the other, then finishes on as many lanes (clip_warp_pairs) */
  size_t bytes;
  int single; /* the faces clipped in single precision (mixed): B's points and planes in float too */
};

struct ClipWarpMemory {
  double *xb, *planes_b, *nodes;
  float *xb_f, *planes_b_f;   /* with limits.single */
  poly_clip_mask *ahead_a, *behind_a, *ahead_b, *behind_b;
  poly_clip_mask *piece_ahead_a, *piece_behind_a, *piece_ahead_b, *piece_behind_b;
  unsigned short *items;  /* clip_item codes: faces below 128, pieces below POLY_CLIP_MAX_PIECES (32) */
  poly_clip_result *results;  /* the warp's pairs' overlaps, for the contact law on a lane each */
};

/* Bytes of one warp's block for `limits`; with `m` and `memory`, points m's arrays into the block. */
static __host__ __device__ inline size_t clip_warp_layout(ClipWarpMemory *m, char *memory, const ClipWarpLimits &limits)
{
  const size_t points = (size_t)limits.vertices + 1;
  size_t doubles = 3 * points + 4 * (size_t)limits.planes + 3 * POLY_CLIP_WARP_NODES;
  size_t masks = 4 * points + 4 * (size_t)limits.pieces;
  size_t floats = limits.single ? 3 * points + 4 * (size_t)limits.planes : 0;
  size_t bytes = sizeof(double) * doubles + sizeof(poly_clip_mask) * masks + sizeof(float) * floats +
                 sizeof(unsigned short) * POLY_CLIP_WARP_ITEMS;
  bytes = (bytes + 15) / 16 * 16;
  const size_t results_at = bytes;
  bytes += sizeof(poly_clip_result) * limits.pairs;
  bytes = (bytes + 15) / 16 * 16;
  if (!m || !memory) return bytes;
  poly_clip_mask *k = (poly_clip_mask *)memory;  /* first: the masks want 16-byte alignment */
  m->ahead_a = k; k += points;
  m->behind_a = k; k += points;
  m->ahead_b = k; k += points;
  m->behind_b = k; k += points;
  m->piece_ahead_a = k; k += limits.pieces;
  m->piece_behind_a = k; k += limits.pieces;
  m->piece_ahead_b = k; k += limits.pieces;
  m->piece_behind_b = k; k += limits.pieces;
  double *d = (double *)k;
  m->xb = d; d += 3 * points;
  m->planes_b = d; d += 4 * limits.planes;
  m->nodes = d; d += 3 * POLY_CLIP_WARP_NODES;
  float *f = (float *)d;
  m->xb_f = f; f += limits.single ? 3 * points : 0;
  m->planes_b_f = f; f += limits.single ? 4 * (size_t)limits.planes : 0;
  m->items = (unsigned short *)f;
  m->results = (poly_clip_result *)(memory + results_at);
  return bytes;
}

/* Pairs per warp: the most, up to POLY_CLIP_WARP_PAIRS, whose blocks, POLY_CLIP_WARP_MIN_BLOCKS of them (what the
 * registers are sized for), take at most half of the SM's shared memory (`shared_per_sm` and `reserved_per_block`
 * bytes, the device's), the rest staying L1 cache for the lanes' local memory, which the kernel waits on: more
 * pairs a warp run more contact laws at once (Schoenhardt polyhedra 16 pairs 4 % faster than 8, 6 % than 1), but
 * rock_40's larger blocks lose by them (1 pair 2 % faster than 8, 14 % than 16; doc/benchmarks.md). Sets
 * limits->pairs and limits->bytes. */
static inline void clip_warp_pairs(ClipWarpLimits *limits, size_t shared_per_sm, size_t reserved_per_block)
{
  for (limits->pairs = POLY_CLIP_WARP_PAIRS;; limits->pairs /= 2) {
    limits->bytes = clip_warp_layout(NULL, NULL, *limits);
    const size_t block = POLY_CLIP_WARPS * limits->bytes + reserved_per_block;
    if (limits->pairs == 1 || POLY_CLIP_WARP_MIN_BLOCKS * block <= shared_per_sm / 2) return;
  }
}

/* The least of the SM's shared-memory configurations that holds `needed` bytes, as the carveout percent of
 * `shared_per_sm` (the SM's shared memory at most), or -1 where none does: the rest of the SM's memory is L1 cache,
 * which the lanes' local memory goes through (left to the driver, the kernel's blocks got 132 KiB instead of 100 and
 * its pairs ran 5-7 % slower: doc/benchmarks.md). The configurations of compute capability 8.x and 9.0 (CUDA C++
 * Programming Guide), up to the SM's; the percent is rounded down, as the driver takes the smallest configuration at
 * least that share (measured), and no two are within 1 % of 228 KiB. */
static inline int least_carveout(size_t needed, size_t shared_per_sm)
{
  static const int kilobytes[] = {8, 16, 32, 64, 100, 132, 164, 196, 228};
  for (int k = 0; k < (int)(sizeof kilobytes / sizeof kilobytes[0]); k++) {
    const size_t config = (size_t)kilobytes[k] * 1024;
    if (config > shared_per_sm) break;
    if (config >= needed) return (int)(100 * config / shared_per_sm);
  }
  return -1;
}

/* Asks for the least configuration that holds as many blocks of `kernel` (`threads` threads and `shared` bytes of
 * dynamic shared memory each, `reserved_per_block` more the driver's) as an SM runs at once. The occupancy query runs
 * with the most shared memory asked for, so that a carveout left by an earlier upload (of smaller shapes) cannot
 * bound it. Once, when the shapes are uploaded: the pair and wall warp kernels measured no gain from it (their blocks
 * in global memory), and their launches run every step. */
template <typename Kernel>
static bool clip_warp_carveout(Kernel kernel, int threads, size_t shared, size_t shared_per_sm,
                               size_t reserved_per_block, char *message, size_t size)
{
  using poly_gpu_detail::check;  // (poly_gpu.cu's `using namespace` comes after this file)
  int blocks = 0;
  if (!check(cudaFuncSetAttribute(kernel, cudaFuncAttributePreferredSharedMemoryCarveout,
                                  (int)cudaSharedmemCarveoutMaxShared), "cudaFuncSetAttribute", message, size) ||
      !check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, kernel, threads, shared),
             "cudaOccupancyMaxActiveBlocksPerMultiprocessor", message, size))
    return false;
  const int carveout = least_carveout((size_t)blocks * (shared + reserved_per_block), shared_per_sm);
  return carveout < 0 || check(cudaFuncSetAttribute(kernel, cudaFuncAttributePreferredSharedMemoryCarveout, carveout),
                               "cudaFuncSetAttribute", message, size);
}

/* Item: a face of one body, which body (of_a), and the other body's piece that clips it; 16 bits in the warp's
 * block. */
static_assert(POLY_CLIP_MAX_FACES <= 128 && POLY_CLIP_MAX_PIECES <= 256, "clip_item codes must fit 16 bits");
static __device__ __forceinline__ int clip_item(int face, int of_a, int piece)
{
  return (piece << 8) | (of_a << 7) | face;
}

/* The points and planes the faces are clipped with, in A's frame: A's own (the shape's) and B's (the warp's block),
 * in double, or in float for mixed precision. */
template <typename Real> struct ClipWarpCoordinates {
  const Real *a_vertices, *a_planes, *xb, *planes_b;
};

static __device__ __forceinline__ int clip_warp_by_planes(double *in, double *out, int count, const double *planes,
                                                          poly_clip_mask cut, poly_clip_mask back, double **result)
{
  return poly_clip_by_planes(in, out, count, planes, cut, back, POLY_CLIP_WARP_POLYGON, result);
}

static __device__ __forceinline__ int clip_warp_by_planes(float *in, float *out, int count, const float *planes,
                                                          poly_clip_mask cut, poly_clip_mask back, float **result)
{
  return poly_clip_by_planes_f(in, out, count, planes, cut, back, POLY_CLIP_WARP_POLYGON, result);
}

/* Item `item`'s face clipped by its piece (poly_clip_face_by_piece, in Real): the corner count, -1 when the polygon
 * outgrew the lane's work buffers, and in *result the buffer holding the corners. */
template <typename Real>
static __device__ __forceinline__ int clip_warp_item(int item, const poly_clip_faces &a, const poly_clip_faces &b,
                                                     const ClipWarpMemory &m, const ClipWarpCoordinates<Real> &at,
                                                     Real (*work)[3 * POLY_CLIP_WARP_POLYGON], Real **result)
{
  const int face = item & 127, of_a = (item >> 7) & 1, piece = item >> 8;
  const poly_clip_faces &body = of_a ? a : b, &other = of_a ? b : a;
  const poly_clip_mask front = poly_clip_mask_of(other.piece_front + piece),
                       back = poly_clip_mask_of(other.piece_back + piece);
  poly_clip_mask all_out;
  const poly_clip_mask some_out = poly_clip_face_cuts(&body, face, of_a ? m.ahead_a : m.ahead_b,
                                                      of_a ? m.behind_a : m.behind_b, front, back, &all_out);
  if (all_out) return 0;
  const int *loop = body.loop + body.loop_start[face];
  const int count = body.loop_start[face + 1] - body.loop_start[face];
  if (count > POLY_CLIP_WARP_POLYGON) return -1;
  const Real *x = of_a ? at.a_vertices : at.xb;
  for (int c = 0; c < count; c++)
    for (int k = 0; k < 3; k++) work[0][3 * c + k] = x[3 * loop[c] + k];
  return clip_warp_by_planes(work[0], work[1], count, of_a ? at.planes_b : at.a_planes, some_out, back, result);
}

/* Does some of item `item`'s face lie inside its piece's planes (poly_clip_face_cuts)? */
static __device__ __forceinline__ bool clip_warp_item_meets(int item, const poly_clip_faces &a, const poly_clip_faces &b,
                                                            const ClipWarpMemory &m)
{
  const int face = item & 127, of_a = (item >> 7) & 1, piece = item >> 8;
  const poly_clip_faces &other = of_a ? b : a;
  poly_clip_mask all_out;
  poly_clip_face_cuts(of_a ? &a : &b, face, of_a ? m.ahead_a : m.ahead_b, of_a ? m.behind_a : m.behind_b,
                      poly_clip_mask_of(other.piece_front + piece), poly_clip_mask_of(other.piece_back + piece),
                      &all_out);
  return !all_out;
}

/* The overlap of pair (a, b) on the calling warp, its faces clipped in Real (A's points and planes in float at
 * `a_vertices_f` and `a_planes_f` for float) and summed in double; returns 1 when the pair must go to the
 * one-thread kernel. */
template <typename Real>
static __device__ int clip_warp_overlap(const poly_clip_faces &a, const poly_clip_faces &b, const float *a_vertices_f,
                                        const float *a_planes_f, const double *rotation, const double *translation,
                                        double size, int want_second, const ClipWarpMemory &m, poly_clip_result *out)
{
  const bool single = sizeof(Real) == sizeof(float);
  ClipWarpCoordinates<Real> at;
  at.a_vertices = single ? (const Real *)a_vertices_f : (const Real *)a.vertices;
  at.a_planes = single ? (const Real *)a_planes_f : (const Real *)a.planes;
  at.xb = single ? (const Real *)m.xb_f : (const Real *)m.xb;
  at.planes_b = single ? (const Real *)m.planes_b_f : (const Real *)m.planes_b;
  const unsigned full = 0xffffffffu;
  const int lane = threadIdx.x & 31, na = a.num_vertices, nb = b.num_vertices;
  const double flush = POLY_CLIP_FLUSH * size;
  out->volume = out->depth = out->area = out->projected_area = 0.0;
  out->num_nodes = 0;
  out->separating = -1;
  for (int e = 0; e < 6; e++) out->second_moment[e] = 0.0;
  // 1. B's points (its centre last) and planes in A's frame; each point's sides of the other body's planes.
  for (int v = lane; v <= nb; v += 32) {
    double *x = m.xb + 3 * v;
    if (v < nb) poly_matrix_apply(rotation, b.vertices + 3 * v, x);
    else x[0] = x[1] = x[2] = 0.0;
    for (int k = 0; k < 3; k++) x[k] += translation[k];
    if (single)
      for (int k = 0; k < 3; k++) m.xb_f[3 * v + k] = (float)x[k];
  }
  for (int f = lane; f < b.num_planes; f += 32) {
    double *plane = m.planes_b + 4 * f;
    poly_matrix_apply(rotation, b.planes + 4 * f, plane);
    plane[3] = b.planes[4 * f + 3] + plane[0] * translation[0] + plane[1] * translation[1] + plane[2] * translation[2];
    if (single)
      for (int k = 0; k < 4; k++) m.planes_b_f[4 * f + k] = (float)plane[k];
  }
  __syncwarp();
  // A point per lane: its masks of the other body's planes (a plane per lane with ballots measured slower).
  int flush_hit = 0;
  for (int v = lane; v <= nb + 1 + na; v += 32) {
    const int of_a = v > nb, index = of_a ? v - nb - 1 : v, count = of_a ? na : nb;
    const double origin[3] = {0.0, 0.0, 0.0};
    const double *p = of_a ? (index < na ? a.vertices + 3 * index : origin) : m.xb + 3 * index;
    poly_clip_mask front, back;
    if (poly_clip_point_sides(p, of_a ? m.planes_b : a.planes, of_a ? b.num_planes : a.num_planes, flush, &front,
                              &back) &&
        index < count)
      flush_hit = 1;
    (of_a ? m.ahead_a : m.ahead_b)[index] = front;
    (of_a ? m.behind_a : m.behind_b)[index] = back;
  }
  if (__any_sync(full, flush_hit)) return 1;
  __syncwarp();
  for (int i = lane; i < a.num_pieces + b.num_pieces; i += 32) {
    const int of_a = i < a.num_pieces, piece = of_a ? i : i - a.num_pieces;
    const poly_clip_faces &body = of_a ? a : b;
    const poly_clip_mask *ahead = of_a ? m.ahead_a : m.ahead_b, *behind = of_a ? m.behind_a : m.behind_b;
    poly_clip_mask front = ~(poly_clip_mask)0, back = ~(poly_clip_mask)0;
    for (int q = body.piece_point_start[piece]; q < body.piece_point_start[piece + 1]; q++) {
      front &= ahead[body.piece_points[q]];
      back &= behind[body.piece_points[q]];
    }
    (of_a ? m.piece_ahead_a : m.piece_ahead_b)[piece] = front;
    (of_a ? m.piece_behind_a : m.piece_behind_b)[piece] = back;
  }
  __syncwarp();
  // 2. The pairs of pieces no plane parts, in the host's order (A's piece, then B's), and their faces.
  const int num_pairs = a.num_pieces * b.num_pieces;
  int num_items = 0;
  for (int first = 0; first < num_pairs; first += 32) {
    const int q = first + lane, i = q / b.num_pieces, j = q - i * b.num_pieces;
    int faces_b = 0, faces_a = 0;
    const bool meet = q < num_pairs &&
                      !((m.piece_ahead_b[j] & poly_clip_mask_of(a.piece_front + i)) |
                        (m.piece_behind_b[j] & poly_clip_mask_of(a.piece_back + i)) |
                        (m.piece_ahead_a[i] & poly_clip_mask_of(b.piece_front + j)) |
                        (m.piece_behind_a[i] & poly_clip_mask_of(b.piece_back + j)));
    // A face whose plane has the other piece wholly on one side cannot meet it (the host's test).
    const poly_clip_mask aside_of_b = meet ? m.piece_ahead_a[i] | m.piece_behind_a[i] : 0,
                         aside_of_a = meet ? m.piece_ahead_b[j] | m.piece_behind_b[j] : 0;
    if (meet) {
      faces_b = b.piece_face_start[j + 1] - b.piece_face_start[j];
      faces_a = a.piece_face_start[i + 1] - a.piece_face_start[i];
      if (b.face_plane)
        for (int f = b.piece_face_start[j]; f < b.piece_face_start[j + 1]; f++)
          faces_b -= (aside_of_b >> b.face_plane[b.piece_faces[f]]) & 1;
      if (a.face_plane)
        for (int f = a.piece_face_start[i]; f < a.piece_face_start[i + 1]; f++)
          faces_a -= (aside_of_a >> a.face_plane[a.piece_faces[f]]) & 1;
    }
    int before = faces_b + faces_a;
    for (int offset = 1; offset < 32; offset <<= 1) {
      int other = __shfl_up_sync(full, before, offset);
      if (lane >= offset) before += other;
    }
    const int total = __shfl_sync(full, before, 31);
    before -= faces_b + faces_a;
    if (num_items + total > POLY_CLIP_WARP_ITEMS) return 1;
    unsigned short *slot = m.items + num_items + before;
    if (meet && !b.face_plane) {
      for (int t = 0; t < faces_b; t++) slot[t] = clip_item(b.piece_faces[b.piece_face_start[j] + t], 0, i);
      slot += faces_b;
    } else if (meet) {
      for (int f = b.piece_face_start[j]; f < b.piece_face_start[j + 1]; f++)
        if (!((aside_of_b >> b.face_plane[b.piece_faces[f]]) & 1)) *slot++ = clip_item(b.piece_faces[f], 0, i);
    }
    if (meet && !a.face_plane) {
      for (int t = 0; t < faces_a; t++) slot[t] = clip_item(a.piece_faces[a.piece_face_start[i] + t], 1, j);
    } else if (meet) {
      for (int f = a.piece_face_start[i]; f < a.piece_face_start[i + 1]; f++)
        if (!((aside_of_a >> a.face_plane[a.piece_faces[f]]) & 1)) *slot++ = clip_item(a.piece_faces[f], 1, j);
    }
    num_items += total;
  }
  __syncwarp();
  // Only the items some of whose face is inside the piece's planes, in their order: most faces are wholly outside
  // a plane, and with them on lanes of their own the clipping below ran on 8 of the 32 lanes (Nsight Compute).
  int left = 0;
  for (int first = 0; first < num_items; first += 32) {
    const int it = first + lane, item = it < num_items ? m.items[it] : 0;
    const bool meets = it < num_items && clip_warp_item_meets(item, a, b, m);
    const unsigned with = __ballot_sync(full, meets);
    __syncwarp();
    if (meets) m.items[left + __popc(with & ((1u << lane) - 1u))] = item;
    left += __popc(with);
  }
  num_items = left;
  __syncwarp();
  // 3. An item per lane: clipped, summed from the common corner, its corners kept.
  Real work[2][3 * POLY_CLIP_WARP_POLYGON];
  poly_clip_sums sums;
  sums.volume6 = sums.area = 0.0;
  for (int k = 0; k < 3; k++) sums.moment24[k] = sums.area_vector[k] = 0.0;
  for (int e = 0; e < 6; e++) sums.second120[e] = 0.0;
  sums.want_second = want_second;
  double reference[3] = {0.0, 0.0, 0.0};
  int have_reference = 0, corners = 0, kept = 0, overflow = 0;
  for (int first = 0; first < num_items; first += 32) {
    const int it = first + lane;
    Real *polygon = NULL;
    const int n = it < num_items ? clip_warp_item(m.items[it], a, b, m, at, work, &polygon) : 0;
    if (__any_sync(full, n < 0)) return 1;
    const unsigned with = __ballot_sync(full, n > 0);
    if (!with) continue;
    if (!have_reference) {
      const int leader = __ffs(with) - 1;
      for (int k = 0; k < 3; k++) reference[k] = __shfl_sync(full, n > 0 ? (double)polygon[k] : 0.0, leader);
      have_reference = 1;
    }
    // The fan from the polygon's first corner, each corner made relative to the common one in double as it comes
    // (a float polygon stays float; in double the same values as the host's).
    if (n > 0) {
      const int on_a = (m.items[it] >> 7) & 1;
      double p0[3], p1[3], p2[3];
      for (int k = 0; k < 3; k++) p0[k] = (double)polygon[k] - reference[k], p1[k] = (double)polygon[3 + k] - reference[k];
      for (int c = 2; c < n; c++) {
        for (int k = 0; k < 3; k++) p2[k] = (double)polygon[3 * c + k] - reference[k];
        poly_clip_add_triangle(p0, p1, p2, on_a, &sums);
        for (int k = 0; k < 3; k++) p1[k] = p2[k];
      }
    }
    int before = n;
    for (int offset = 1; offset < 32; offset <<= 1) {
      int other = __shfl_up_sync(full, before, offset);
      if (lane >= offset) before += other;
    }
    const int total = __shfl_sync(full, before, 31);
    before -= n;
    if (kept + total <= POLY_CLIP_WARP_NODES) {
      for (int c = 0; c < 3 * n; c++)
        m.nodes[3 * (kept + before) + c] = (double)polygon[c] - reference[c % 3];
      kept += total;
    } else {
      overflow = 1;
    }
    corners += total;
  }
  // 4. Sums over the lanes, then what the host's poly_clip_finish makes of them.
  if (corners == 0) return 0;
  // All 14 sums at once, so the shuffles of one level overlap; a fixed tree, so runs repeat bit for bit.
  double total[14] = {sums.volume6, sums.moment24[0], sums.moment24[1], sums.moment24[2], sums.area_vector[0],
                      sums.area_vector[1], sums.area_vector[2], sums.area, sums.second120[0], sums.second120[1],
                      sums.second120[2], sums.second120[3], sums.second120[4], sums.second120[5]};
  const int terms = want_second ? 14 : 8;
  for (int offset = 16; offset > 0; offset >>= 1)
#pragma unroll
    for (int t = 0; t < 14; t++)
      if (t < terms) total[t] += __shfl_down_sync(full, total[t], offset);
#pragma unroll
  for (int t = 0; t < 14; t++)
    if (t < terms) total[t] = __shfl_sync(full, total[t], 0);
  const double volume = total[0] / 6.0;
  if (!(volume > 0.0)) return 0;
  double moment24[3] = {total[1], total[2], total[3]}, area_vector[3] = {total[4], total[5], total[6]};
  const double area = total[7];
  const double *second = total + 8;
  out->volume = volume;
  out->num_nodes = corners;
  double from_reference[3];
  for (int k = 0; k < 3; k++) {
    from_reference[k] = moment24[k] / (24.0 * volume);
    out->centroid[k] = from_reference[k] + reference[k];
  }
  out->area = area;
  if (want_second) {
    for (int e = 0; e < 6; e++) out->second_moment[e] = second[e] / 120.0;
    poly_second_moment_to_centroid(out->second_moment, volume, from_reference);
  }
  const double length = sqrt(area_vector[0] * area_vector[0] + area_vector[1] * area_vector[1] +
                             area_vector[2] * area_vector[2]);
  out->projected_area = length;
  if (length > 1e-9 * area && length > 0.0) {
    for (int k = 0; k < 3; k++) out->normal[k] = area_vector[k] / length;
  } else {
    double t = sqrt(translation[0] * translation[0] + translation[1] * translation[1] + translation[2] * translation[2]);
    for (int k = 0; k < 3; k++) out->normal[k] = t > 0.0 ? translation[k] / t : (k == 2 ? 1.0 : 0.0);
  }
  double low = 1e300, high = -1e300;
  const double *n3 = out->normal;
  if (!overflow) {
    __syncwarp();
    for (int c = lane; c < kept; c += 32) {
      const double *x = m.nodes + 3 * c;
      double along = n3[0] * x[0] + n3[1] * x[1] + n3[2] * x[2];
      low = fmin(low, along);
      high = fmax(high, along);
    }
  } else {
    for (int first = 0; first < num_items; first += 32) {
      const int it = first + lane;
      Real *polygon = NULL;
      const int n = it < num_items ? clip_warp_item(m.items[it], a, b, m, at, work, &polygon) : 0;
      for (int c = 0; c < n; c++) {
        const Real *x = polygon + 3 * c;
        double along = n3[0] * (x[0] - reference[0]) + n3[1] * (x[1] - reference[1]) + n3[2] * (x[2] - reference[2]);
        low = fmin(low, along);
        high = fmax(high, along);
      }
    }
  }
  for (int offset = 16; offset > 0; offset >>= 1) {
    low = fmin(low, __shfl_xor_sync(full, low, offset));
    high = fmax(high, __shfl_xor_sync(full, high, offset));
  }
  out->depth = high > low ? high - low : 0.0;
  return 0;
}

#endif
