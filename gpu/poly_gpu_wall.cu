/* The narrow phase of fix wall/polyhedral's mesh walls on the GPU: the host's
 * overlap code (src/poly_overlap_impl.h) in the precision of the pair style,
 * for each (particle, prism) candidate, on a group of lanes per piece (the
 * warp pass of gpu/poly_gpu_warp_impl.cuh, as the pair style's warp kernel)
 * or on one thread per piece (all of overlap_local: the pieces the lanes hand
 * back, flush faces above all, and shapes too large for their shared block).
 * The host keeps what is cheap and needs LIGGGHTS: the mesh neighbour lists,
 * the prisms (src/poly_mesh_shell.c) and combining a particle's pieces into one
 * contact; the overlaps come back with their intersection nodes, which that
 * combination needs for the depth.
 *
 * Nodes go to one array, each piece reserving its run with an atomic; a run's
 * place in the array varies between runs, its content does not, so the host's
 * result is deterministic. When the array is too small the kernel writes what
 * fits and the call runs again with the array grown to the count. */
#include "poly_gpu.h"

#include <string.h>

#include <algorithm>

#include "poly_gpu_device.cuh"

using namespace poly_gpu_detail;

namespace {

struct WallState {
  DeviceArray<poly_gpu_wall_piece> pieces;
  DeviceArray<poly_gpu_wall_overlap> overlaps;
  DeviceArray<double> nodes;
  DeviceArray<int> counters;          // [0] nodes reserved, [1] pieces the lanes handed back
  DeviceArray<int> handed_back;       // the pieces of counters[1]
  DeviceArray<int> handed_large;      // the pieces large_pieces_by_warp hands back (counters[1] again)
  DeviceArray<char> scratch;
  PinnedArray<poly_gpu_wall_piece> host_pieces;
  PinnedArray<double> host_nodes;
  double seconds;
  long calls, num_pieces, handed;     // summed over calls; handed: pieces the lanes left to the one-thread kernel
};

WallState wall = {};

// A prism: 6 vertices, 8 triangles, 12 edges; its vertices and normals in the kernel's precision.
const int kPrismVertices = 6, kPrismTriangles = 8, kPrismEdges = 12, kPrismReals = 18 + 24;

// The piece's prism as the host's view of it, with `reals` holding its vertices then its normals.
template <typename View, typename Real> __device__ inline View prism_view(const poly_gpu_wall_piece &piece, Real *reals)
{
  View prism;
  prism.num_vertices = kPrismVertices;
  prism.num_triangles = kPrismTriangles;
  prism.num_edges = kPrismEdges;
  prism.vertices = reals;
  prism.face_normals = reals + 18;
  prism.triangles = piece.triangles;
  prism.edges = piece.edges;
  prism.edge_triangles = piece.edge_triangles;
  prism.triangle_edges = NULL;
  prism.face_of = prism.ridges = NULL;
  prism.num_ridges = 0;
  prism.support = NULL;
  prism.num_support = 0;
  prism.extreme_start = prism.extreme_vertices = NULL;
  prism.bounding_radius = (Real)piece.bounding_radius;
  return prism;
}

// The prism's vertices then normals into `reals` in the kernel's precision: entries first, first + step, ...
// (one thread: 0, 1; a group of lanes: its lane, its size).
template <typename Real>
__device__ inline void prism_reals_of(const poly_gpu_wall_piece &piece, Real *reals, int first, int step)
{
  for (int k = first; k < 18; k += step) reals[k] = (Real)piece.vertices[k];
  for (int k = first; k < 24; k += step) reals[18 + k] = (Real)piece.face_normals[k];
}

// A piece's result before its overlap is known: no overlap, no nodes.
__device__ inline poly_gpu_wall_overlap no_wall_overlap()
{
  poly_gpu_wall_overlap out;
  memset(&out, 0, sizeof out);
  out.first_node = -1;
  return out;
}

// The particle's rotation and the prism's pose in the particle's body frame, as poly_overlap_d computes them.
__device__ inline void piece_pose(const poly_gpu_wall_piece &piece, double *rotation_a, double *rotation,
                                  double *translation)
{
  const double identity[4] = {1.0, 0.0, 0.0, 0.0};
  poly_overlap_relative_pose(piece.position, piece.quaternion, piece.origin, identity, rotation_a, rotation,
                             translation);
}

// An overlap's centroid, normal and second moment from the particle's body frame to the world's.
__device__ inline void piece_to_world(const poly_gpu_wall_piece &piece, const double *rotation_a,
                                      const double *local_centroid, const double *local_normal,
                                      poly_overlap_result *geometry)
{
  poly_matrix_apply(rotation_a, local_centroid, geometry->centroid);
  for (int k = 0; k < 3; k++) geometry->centroid[k] += piece.position[k];
  poly_matrix_apply(rotation_a, local_normal, geometry->normal);
  double local_second[6];
  for (int e = 0; e < 6; e++) local_second[e] = geometry->second_moment[e];
  poly_second_moment_rotate(rotation_a, local_second, geometry->second_moment);
}

// One thread per piece of `list` (NULL: the pieces first .. first + count - 1): all of overlap_local.
template <int Precision, size_t LocalBytes>
__global__ void __launch_bounds__(kThreads, POLY_GPU_CONTACT_MIN_BLOCKS)
    wall_kernel(DeviceShapes shapes, int max_vertices, int max_triangles, const poly_gpu_wall_piece *__restrict__ pieces,
                const int *__restrict__ list, int first, int count, poly_gpu_wall_overlap *__restrict__ overlaps,
                double *__restrict__ nodes, int node_capacity, int *__restrict__ node_count, char *__restrict__ scratch,
                size_t bytes_per_thread)
{
  typedef Narrow<Precision> N;
  typedef typename N::Real Real;
  int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= count) return;
  const int c = list ? list[first + local] : first + local;
  const poly_gpu_wall_piece &piece = pieces[c];

  Real prism_reals[kPrismReals];
  prism_reals_of(piece, prism_reals, 0, 1);
  typename N::View prism = prism_view<typename N::View>(piece, prism_reals);
  double rotation_a[9], rotation[9], translation[3];
  piece_pose(piece, rotation_a, rotation, translation);

  poly_gpu_wall_overlap out = no_wall_overlap();
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  WorkspaceMemory<LocalBytes> memory;
  typename N::Workspace ws;
  N::layout(&ws, memory.get(scratch, local, bytes_per_thread), max_vertices, max_triangles);
  ws.want_second_moment = 1;  // the host drops it when the wall's rocking damping is off
  typename N::View particle = N::view(shapes, piece.shape);
  N::overlap(&particle, &prism, rotation, translation, &ws, local_centroid, local_normal, &out.geometry);
  if (out.geometry.volume > 0.0) {
    // World frame, as poly_overlap_d and poly_overlap_nodes_d.
    piece_to_world(piece, rotation_a, local_centroid, local_normal, &out.geometry);
    int num_points = ws.num_points;
    if (num_points <= ws.capacity_points) {
      int start = atomicAdd(node_count, num_points);
      out.first_node = start;
      if (start + num_points <= node_capacity)
        for (int p = 0; p < num_points; p++) {
          double point[3];
          for (int k = 0; k < 3; k++) point[k] = (double)ws.points[3 * p + k] + ws.origin[k];
          poly_matrix_apply(rotation_a, point, nodes + 3 * (size_t)(start + p));
        }
    }
  }
  overlaps[c] = out;
}

// A group of limits.lanes lanes per piece of `list` from `first` (NULL: the pieces from `first`;
// gpu/poly_gpu_warp_impl.cuh), each group with its block of limits.bytes of shared memory, or of `global_blocks`
// (the piece's own, at its place in the launch) for shapes too large for shared memory: the prism's reals in its
// first prism_bytes, the warp pass's arrays after them. Pieces the lanes cannot finish (flush faces, inconsistent
// edges, full records), and pieces of shapes beyond the limits, go to `handed_back` (counted in counters[1]) for
// wall_kernel. counters[0] reserves nodes, as wall_kernel's node_count; capacity_points is wall_kernel's
// workspace's, so that both keep the nodes of the same pieces.
template <int Precision>
__global__ void __launch_bounds__(kThreads)
    warp_wall_kernel(DeviceShapes shapes, const poly_gpu_wall_piece *__restrict__ pieces, const int *__restrict__ list,
                     int first, int count, poly_gpu_wall_overlap *__restrict__ overlaps, double *__restrict__ nodes,
                     int node_capacity, int capacity_points, int *__restrict__ counters,
                     int *__restrict__ handed_back, WarpLimits limits, int prism_bytes,
                     char *__restrict__ global_blocks)
{
  typedef Narrow<Precision> N;
  typedef typename N::Real Real;
  extern __shared__ double warp_blocks[];
  const int groups = blockDim.x / limits.lanes, group = threadIdx.x / limits.lanes;
  const int local = blockIdx.x * groups + group;
  if (local >= count) return;  // the piece's whole group of lanes
  const int c = list ? list[first + local] : first + local;
  const poly_lanes lanes = poly_lanes_of(limits.lanes);
  const poly_gpu_wall_piece &piece = pieces[c];
  if (beyond_limits(shapes, piece.shape, limits)) {
    if (lanes.lane == 0) handed_back[atomicAdd(counters + 1, 1)] = c;
    return;
  }
  char *block = global_blocks ? global_blocks + (size_t)local * limits.bytes
                              : (char *)warp_blocks + (size_t)group * limits.bytes;
  Real *prism_reals = (Real *)block;
  prism_reals_of(piece, prism_reals, lanes.lane, lanes.size);
  typename N::WarpMemory memory;
  N::warp_layout(&memory, block + prism_bytes, limits.vertices, limits.triangles, limits.edges, limits.records);
  __syncwarp(lanes.mask);
  typename N::View prism = prism_view<typename N::View>(piece, prism_reals);
  typename N::View particle = N::view(shapes, piece.shape);
  double rotation_a[9], rotation[9], translation[3];
  piece_pose(piece, rotation_a, rotation, translation);

  poly_gpu_wall_overlap out = no_wall_overlap();
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  typename N::WarpFrame frame;
  // want_second 1: the host drops it when the wall's rocking damping is off
  if (N::warp_overlap(&particle, &prism, rotation, translation, 1, &memory, lanes, local_centroid, local_normal,
                      &out.geometry, &frame)) {
    if (lanes.lane == 0) handed_back[atomicAdd(counters + 1, 1)] = c;
    return;
  }
  if (out.geometry.volume > 0.0) {
    piece_to_world(piece, rotation_a, local_centroid, local_normal, &out.geometry);
    const int num_points = out.geometry.num_nodes;
    if (num_points <= capacity_points) {
      int start = 0;
      if (lanes.lane == 0) start = atomicAdd(counters, num_points);
      start = __shfl_sync(lanes.mask, start, lanes.base);
      out.first_node = start;
      if (start + num_points <= node_capacity)
        N::warp_nodes(&particle, &prism, &memory, &frame, rotation_a, lanes, nodes + 3 * (size_t)start);
    }
  }
  if (lanes.lane == 0) overlaps[c] = out;
}

// wall_kernel over `count` pieces of `list` (NULL: all pieces): in one launch with local-memory workspaces,
// else in batches whose workspaces fit a bounded scratch buffer (as the pair kernel does).
template <int Precision>
bool thread_per_piece(const DeviceShapes &shapes, const int *list, int count, int node_capacity, char *message,
                      size_t size)
{
  typedef Narrow<Precision> N;
  if (count == 0) return true;
  // The prisms have 6 vertices and 8 triangles; the host's workspace is sized the same way.
  int max_vertices = shapes.max_vertices > kPrismVertices ? shapes.max_vertices : kPrismVertices;
  int max_triangles = shapes.max_triangles > kPrismTriangles ? shapes.max_triangles : kPrismTriangles;
  size_t workspace = N::layout(NULL, NULL, max_vertices, max_triangles);
  if (workspace <= LocalWorkspace<Precision>::bytes) {
    wall_kernel<Precision, LocalWorkspace<Precision>::bytes><<<(count + kThreads - 1) / kThreads, kThreads>>>(
        shapes, max_vertices, max_triangles, wall.pieces.data, list, 0, count, wall.overlaps.data, wall.nodes.data,
        node_capacity, wall.counters.data, NULL, 0);
    return check(cudaGetLastError(), "wall kernel launch", message, size);
  }
  workspace = (workspace + 255) / 256 * 256;
  size_t batch = (size_t)1 << 16;
  const size_t budget = (size_t)1 << 28;
  while (batch > 256 && batch * workspace > budget) batch /= 2;
  if (!ensure(wall.scratch, batch * workspace, message, size)) return false;
  for (size_t first = 0; first < (size_t)count; first += batch) {
    int chunk = (int)((size_t)count - first < batch ? (size_t)count - first : batch);
    wall_kernel<Precision, 0><<<(chunk + kThreads - 1) / kThreads, kThreads>>>(
        shapes, max_vertices, max_triangles, wall.pieces.data, list, (int)first, chunk, wall.overlaps.data,
        wall.nodes.data, node_capacity, wall.counters.data, wall.scratch.data, workspace);
    if (!check(cudaGetLastError(), "wall kernel launch", message, size)) return false;
  }
  return true;
}

// Which kernel takes the pieces (POLY_GPU_WALL_KERNEL=thread or warp forces one): lanes per piece whenever
// the shapes fit their blocks. Measured on an H100 (doc/benchmarks.md, "Mesh walls on the GPU",
// tools/bench_gpu_walls.sh): 2-5x the one-thread kernel's pieces per second for shapes of 40 triangles and
// more, within 15 % of it either way for the small ones; and a call of few pieces lasts as long as its
// slowest piece, which lanes shorten.
bool use_warp_wall_kernel()
{
  return wall_kernel_choice() != 1;
}

// The pieces of `list` (NULL: all `count` pieces) on a warp each, as warp_wall_kernel does in shared memory, but
// each warp's block in the scratch buffer: for shapes whose one-thread workspaces do not fit local memory (a
// rock_1000 workspace of about 350 KB let 512 pieces run at a time), a block per piece rather than a workspace per
// thread, and the lanes sharing the piece's loops. What the warps hand back takes the one-thread kernel.
template <int Precision>
bool large_pieces_by_warp(const DeviceShapes &shapes, const int *list, int count, int node_capacity,
                          int capacity_points, char *message, size_t size)
{
  typedef typename Narrow<Precision>::Real Real;
  if (count == 0) return true;
  WarpLimits limits = largest_shape_limits(kPrismVertices, kPrismTriangles, kPrismEdges);
  const size_t prism_bytes = (kPrismReals * sizeof(Real) + 15) / 16 * 16;
  const size_t bytes = (Narrow<Precision>::warp_layout(NULL, NULL, limits.vertices, limits.triangles, limits.edges,
                                                       limits.records) + prism_bytes + 255) / 256 * 256;
  const size_t budget = (size_t)1 << 28;
  const size_t batch = std::min((size_t)count, budget / bytes);
  if (batch == 0) return thread_per_piece<Precision>(shapes, list, count, node_capacity, message, size);
  limits.bytes = (int)bytes;
  if (!ensure(wall.scratch, batch * bytes, message, size) || !ensure(wall.handed_large, count, message, size) ||
      !check(cudaMemset(wall.counters.data + 1, 0, sizeof(int)), "cudaMemset", message, size))
    return false;
  const int groups = kThreads / 32;
  for (size_t first = 0; first < (size_t)count; first += batch) {
    const int chunk = (int)std::min(batch, (size_t)count - first);
    warp_wall_kernel<Precision><<<(chunk + groups - 1) / groups, kThreads>>>(
        shapes, wall.pieces.data, list, (int)first, chunk, wall.overlaps.data, wall.nodes.data,
        node_capacity, capacity_points, wall.counters.data, wall.handed_large.data, limits, (int)prism_bytes,
        wall.scratch.data);
    if (!check(cudaGetLastError(), "large pieces' warp wall kernel launch", message, size)) return false;
  }
  int num_handed = 0;
  if (!check(cudaMemcpy(&num_handed, wall.counters.data + 1, sizeof(int), cudaMemcpyDeviceToHost),
             "large pieces' warp wall kernel", message, size))
    return false;
  wall.handed += num_handed;
  return thread_per_piece<Precision>(shapes, wall.handed_large.data, num_handed, node_capacity, message, size);
}

// All pieces: a group of lanes per piece, then a thread per piece for those the lanes handed back (or for
// all, when use_warp_wall_kernel says so or no shape fits the lanes' blocks); where the one-thread workspaces
// would be in global memory, a warp per piece with its block there first (large_pieces_by_warp).
template <int Precision>
bool launch(const DeviceShapes &shapes, int count, int node_capacity, char *message, size_t size)
{
  typedef typename Narrow<Precision>::Real Real;
  // The one-thread kernel's node capacity per piece (overlap_workspace_layout), for the same nodes kept.
  int max_vertices = shapes.max_vertices > kPrismVertices ? shapes.max_vertices : kPrismVertices;
  int max_triangles = shapes.max_triangles > kPrismTriangles ? shapes.max_triangles : kPrismTriangles;
  typename Narrow<Precision>::Workspace probe;
  char dummy;
  const size_t workspace = Narrow<Precision>::layout(&probe, &dummy, max_vertices, max_triangles);  // capacities only
  const bool large_by_warp = use_warp_wall_kernel() && workspace > LocalWorkspace<Precision>::bytes;
  WarpLimits limits = {0, 0, 0, 0, 0, 32};
  if (use_warp_wall_kernel())
    limits = warp_limits(Precision, kPrismVertices, kPrismTriangles, kPrismEdges);
  if (limits.bytes == 0)
    return large_by_warp
               ? large_pieces_by_warp<Precision>(shapes, NULL, count, node_capacity, probe.capacity_points, message,
                                                 size)
               : thread_per_piece<Precision>(shapes, NULL, count, node_capacity, message, size);
  const int prism_bytes = (int)((kPrismReals * sizeof(Real) + 15) / 16 * 16);
  limits.bytes += prism_bytes;
  WarpLaunch grid;
  if (!warp_launch(warp_wall_kernel<Precision>, limits, &grid, message, size) ||
      !ensure(wall.handed_back, count, message, size))
    return false;
  warp_wall_kernel<Precision><<<(count + grid.groups - 1) / grid.groups, grid.threads, grid.shared>>>(
      shapes, wall.pieces.data, NULL, 0, count, wall.overlaps.data, wall.nodes.data, node_capacity,
      probe.capacity_points, wall.counters.data, wall.handed_back.data, limits, prism_bytes, NULL);
  int num_handed = 0;
  if (!check(cudaGetLastError(), "warp wall kernel launch", message, size) ||
      !check(cudaMemcpy(&num_handed, wall.counters.data + 1, sizeof(int), cudaMemcpyDeviceToHost), "warp wall kernel",
             message, size))
    return false;
  if (large_by_warp)
    return large_pieces_by_warp<Precision>(shapes, wall.handed_back.data, num_handed, node_capacity,
                                           probe.capacity_points, message, size);
  wall.handed += num_handed;
  return thread_per_piece<Precision>(shapes, wall.handed_back.data, num_handed, node_capacity, message, size);
}

}  // namespace

extern "C" poly_gpu_wall_piece *poly_gpu_wall_buffer(int count)
{
  if (!ensure(wall.host_pieces, count > 0 ? (size_t)count : 1, NULL, 0)) return NULL;
  return wall.host_pieces.data;
}

extern "C" int poly_gpu_wall_overlaps(int precision, int count, poly_gpu_wall_overlap *overlaps, const double **nodes,
                                      char *message, size_t message_size)
{
  const DeviceShapes *shapes = device_shapes();
  if (!shapes) {
    snprintf(message, message_size, "poly_gpu_wall_overlaps before poly_gpu_init");
    return -1;
  }
  if (count > 0 && (!wall.host_pieces.data || wall.host_pieces.capacity < (size_t)count)) {
    snprintf(message, message_size, "poly_gpu_wall_overlaps: the pieces are not in poly_gpu_wall_buffer(%d)", count);
    return -1;
  }
  *nodes = NULL;
  if (count <= 0) return 0;
  double start = now();
  if (!ensure(wall.pieces, count, message, message_size) || !ensure(wall.overlaps, count, message, message_size) ||
      !ensure(wall.counters, 2, message, message_size) ||
      !check(cudaMemcpy(wall.pieces.data, wall.host_pieces.data, sizeof(poly_gpu_wall_piece) * count,
                        cudaMemcpyHostToDevice), "upload wall pieces", message, message_size))
    return -1;
  // Tens of nodes per touching piece, and most candidates do not touch: the first guess rarely needs a rerun.
  size_t node_capacity = wall.nodes.capacity > 32 * (size_t)count ? wall.nodes.capacity / 3 : 32 * (size_t)count;
  int num_nodes = 0;
  for (int attempt = 0; attempt < 2; attempt++) {
    if (!ensure(wall.nodes, 3 * node_capacity, message, message_size) ||
        !check(cudaMemset(wall.counters.data, 0, 2 * sizeof(int)), "cudaMemset", message, message_size))
      return -1;
    bool ok = precision == POLY_PRECISION_DOUBLE
                  ? launch<POLY_PRECISION_DOUBLE>(*shapes, count, (int)node_capacity, message, message_size)
              : precision == POLY_PRECISION_MIXED
                  ? launch<POLY_PRECISION_MIXED>(*shapes, count, (int)node_capacity, message, message_size)
                  : launch<POLY_PRECISION_SINGLE>(*shapes, count, (int)node_capacity, message, message_size);
    if (!ok || !check(cudaDeviceSynchronize(), "wall kernel", message, message_size) ||
        !check(cudaMemcpy(&num_nodes, wall.counters.data, sizeof(int), cudaMemcpyDeviceToHost), "download node count",
               message, message_size))
      return -1;
    if ((size_t)num_nodes <= node_capacity) break;
    node_capacity = (size_t)num_nodes;
  }
  if (!ensure(wall.host_nodes, 3 * (size_t)num_nodes + 3, message, message_size) ||
      !check(cudaMemcpy(overlaps, wall.overlaps.data, sizeof(poly_gpu_wall_overlap) * count, cudaMemcpyDeviceToHost),
             "download wall overlaps", message, message_size) ||
      (num_nodes > 0 && !check(cudaMemcpy(wall.host_nodes.data, wall.nodes.data, 3 * sizeof(double) * num_nodes,
                                          cudaMemcpyDeviceToHost), "download wall nodes", message, message_size)))
    return -1;
  *nodes = wall.host_nodes.data;
  wall.seconds += now() - start;
  wall.calls++;
  wall.num_pieces += count;
  return 0;
}

void poly_gpu_detail::wall_timing(poly_gpu_timing *timing)
{
  timing->wall_seconds = wall.seconds;
  timing->wall_calls = wall.calls;
  timing->wall_pieces = wall.num_pieces;
  timing->wall_handed_back = wall.handed;
}

size_t poly_gpu_detail::wall_bytes()
{
  return bytes_of(wall.pieces) + bytes_of(wall.overlaps) + bytes_of(wall.nodes) + bytes_of(wall.counters) +
         bytes_of(wall.handed_back) + bytes_of(wall.handed_large) + bytes_of(wall.scratch);
}

void poly_gpu_detail::wall_clear()
{
  release(wall.pieces); release(wall.overlaps); release(wall.nodes); release(wall.counters);
  release(wall.handed_back); release(wall.handed_large); release(wall.scratch);
  release(wall.host_pieces); release(wall.host_nodes);
  // The timing summary covers the whole session.
  WallState kept = wall;
  wall = WallState();
  wall.seconds = kept.seconds;
  wall.calls = kept.calls;
  wall.num_pieces = kept.num_pieces;
  wall.handed = kept.handed;
}
