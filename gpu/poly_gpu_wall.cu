/* The narrow phase of fix wall/polyhedral's mesh walls on the GPU: one thread
 * per (particle, prism) candidate, the host's overlap code (src/poly_overlap_impl.h)
 * in the precision of the pair style. The host keeps what is cheap and needs
 * LIGGGHTS: the mesh neighbour lists, the prisms (src/poly_mesh_shell.c) and
 * combining a particle's pieces into one contact; the overlaps come back with
 * their intersection nodes, which that combination needs for the depth.
 *
 * Nodes go to one array, each thread reserving its run with an atomic; a run's
 * place in the array varies between runs, its content does not, so the host's
 * result is deterministic. When the array is too small the kernel writes what
 * fits and the call runs again with the array grown to the count. */
#include "poly_gpu.h"

#include <string.h>

#include "poly_gpu_device.cuh"

using namespace poly_gpu_detail;

namespace {

struct WallState {
  DeviceArray<poly_gpu_wall_piece> pieces;
  DeviceArray<poly_gpu_wall_overlap> overlaps;
  DeviceArray<double> nodes;
  DeviceArray<int> node_count;
  DeviceArray<char> scratch;
  PinnedArray<poly_gpu_wall_piece> host_pieces;
  PinnedArray<double> host_nodes;
  double seconds;
  long calls;
};

WallState wall = {};

template <int Precision, size_t LocalBytes>
__global__ void __launch_bounds__(kThreads, POLY_GPU_CONTACT_MIN_BLOCKS)
    wall_kernel(DeviceShapes shapes, int max_vertices, int max_triangles, const poly_gpu_wall_piece *__restrict__ pieces,
                int first, int count, poly_gpu_wall_overlap *__restrict__ overlaps, double *__restrict__ nodes,
                int node_capacity, int *__restrict__ node_count, char *__restrict__ scratch, size_t bytes_per_thread)
{
  typedef Narrow<Precision> N;
  typedef typename N::Real Real;
  int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= count) return;
  const poly_gpu_wall_piece &piece = pieces[first + local];

  // The prism in the kernel's precision, as the host's view of it.
  Real prism_vertices[18], prism_normals[24];
  for (int k = 0; k < 18; k++) prism_vertices[k] = (Real)piece.vertices[k];
  for (int k = 0; k < 24; k++) prism_normals[k] = (Real)piece.face_normals[k];
  typename N::View prism;
  prism.num_vertices = 6;
  prism.num_triangles = 8;
  prism.num_edges = 12;
  prism.vertices = prism_vertices;
  prism.face_normals = prism_normals;
  prism.triangles = piece.triangles;
  prism.edges = piece.edges;
  prism.edge_triangles = piece.edge_triangles;
  prism.face_of = prism.ridges = NULL;
  prism.num_ridges = 0;
  prism.support = NULL;
  prism.num_support = 0;
  prism.bounding_radius = (Real)piece.bounding_radius;
  const double identity[4] = {1.0, 0.0, 0.0, 0.0};
  double rotation_a[9], rotation[9], translation[3];
  poly_overlap_relative_pose(piece.position, piece.quaternion, piece.origin, identity, rotation_a, rotation,
                             translation);

  poly_gpu_wall_overlap out;
  memset(&out, 0, sizeof out);
  out.first_node = -1;
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  WorkspaceMemory<LocalBytes> memory;
  typename N::Workspace ws;
  N::layout(&ws, memory.get(scratch, local, bytes_per_thread), max_vertices, max_triangles);
  ws.want_second_moment = 1;  // the host drops it when the wall's rocking damping is off
  typename N::View particle = N::view(shapes, piece.shape);
  N::overlap(&particle, &prism, rotation, translation, &ws, local_centroid, local_normal, &out.geometry);
  if (out.geometry.volume > 0.0) {
    // World frame, as poly_overlap_d and poly_overlap_nodes_d.
    poly_matrix_apply(rotation_a, local_centroid, out.geometry.centroid);
    for (int k = 0; k < 3; k++) out.geometry.centroid[k] += piece.position[k];
    poly_matrix_apply(rotation_a, local_normal, out.geometry.normal);
    double local_second[6];
    for (int e = 0; e < 6; e++) local_second[e] = out.geometry.second_moment[e];
    poly_second_moment_rotate(rotation_a, local_second, out.geometry.second_moment);
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
  overlaps[first + local] = out;
}

// All pieces in one launch with local-memory workspaces, else in batches whose
// workspaces fit a bounded scratch buffer (as the pair kernel does).
template <int Precision>
bool launch(const DeviceShapes &shapes, int count, int node_capacity, char *message, size_t size)
{
  typedef Narrow<Precision> N;
  // The prisms have 6 vertices and 8 triangles; the host's workspace is sized the same way.
  int max_vertices = shapes.max_vertices > 6 ? shapes.max_vertices : 6;
  int max_triangles = shapes.max_triangles > 8 ? shapes.max_triangles : 8;
  size_t workspace = N::layout(NULL, NULL, max_vertices, max_triangles);
  if (workspace <= LocalWorkspace<Precision>::bytes) {
    wall_kernel<Precision, LocalWorkspace<Precision>::bytes><<<(count + kThreads - 1) / kThreads, kThreads>>>(
        shapes, max_vertices, max_triangles, wall.pieces.data, 0, count, wall.overlaps.data, wall.nodes.data,
        node_capacity, wall.node_count.data, NULL, 0);
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
        shapes, max_vertices, max_triangles, wall.pieces.data, (int)first, chunk, wall.overlaps.data, wall.nodes.data,
        node_capacity, wall.node_count.data, wall.scratch.data, workspace);
    if (!check(cudaGetLastError(), "wall kernel launch", message, size)) return false;
  }
  return true;
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
      !ensure(wall.node_count, 1, message, message_size) ||
      !check(cudaMemcpy(wall.pieces.data, wall.host_pieces.data, sizeof(poly_gpu_wall_piece) * count,
                        cudaMemcpyHostToDevice), "upload wall pieces", message, message_size))
    return -1;
  // Tens of nodes per touching piece, and most candidates do not touch: the first guess rarely needs a rerun.
  size_t node_capacity = wall.nodes.capacity > 32 * (size_t)count ? wall.nodes.capacity / 3 : 32 * (size_t)count;
  int num_nodes = 0;
  for (int attempt = 0; attempt < 2; attempt++) {
    if (!ensure(wall.nodes, 3 * node_capacity, message, message_size) ||
        !check(cudaMemset(wall.node_count.data, 0, sizeof(int)), "cudaMemset", message, message_size))
      return -1;
    bool ok = precision == POLY_PRECISION_DOUBLE
                  ? launch<POLY_PRECISION_DOUBLE>(*shapes, count, (int)node_capacity, message, message_size)
              : precision == POLY_PRECISION_MIXED
                  ? launch<POLY_PRECISION_MIXED>(*shapes, count, (int)node_capacity, message, message_size)
                  : launch<POLY_PRECISION_SINGLE>(*shapes, count, (int)node_capacity, message, message_size);
    if (!ok || !check(cudaDeviceSynchronize(), "wall kernel", message, message_size) ||
        !check(cudaMemcpy(&num_nodes, wall.node_count.data, sizeof(int), cudaMemcpyDeviceToHost), "download node count",
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
  return 0;
}

extern "C" double poly_gpu_wall_seconds(long *calls)
{
  if (calls) *calls = wall.calls;
  return wall.seconds;
}

size_t poly_gpu_detail::wall_bytes()
{
  return bytes_of(wall.pieces) + bytes_of(wall.overlaps) + bytes_of(wall.nodes) + bytes_of(wall.node_count) +
         bytes_of(wall.scratch);
}

void poly_gpu_detail::wall_clear()
{
  release(wall.pieces); release(wall.overlaps); release(wall.nodes); release(wall.node_count);
  release(wall.scratch); release(wall.host_pieces); release(wall.host_nodes);
  double seconds = wall.seconds;
  long calls = wall.calls;
  wall = WallState();
  wall.seconds = seconds;
  wall.calls = calls;
}
