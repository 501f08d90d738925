/* CUDA narrow phase: one thread per candidate pair, running the CPU code's
 * own overlap geometry and contact law. See poly_gpu.h. */
#include "poly_gpu.h"

#include <cuda_runtime.h>
#include <stdio.h>
#include <string.h>

#include "poly_overlap.h"

#define POLY_REAL double
#define POLY_FN(name) poly_##name##_d
#include "poly_overlap_impl.h"
#undef POLY_REAL
#undef POLY_FN

#define POLY_REAL float
#define POLY_FN(name) poly_##name##_f
#include "poly_overlap_impl.h"
#undef POLY_REAL
#undef POLY_FN

namespace {

// Shapes packed in flat device arrays; per shape the offsets into them.
struct DeviceShapes {
  int count;
  int max_vertices, max_triangles;
  int *offsets;               // 5 per shape: vertex, triangle, edge offset; counts follow in `counts`
  int *counts;                // 3 per shape: vertices, triangles, edges
  double *radius;
  double *vertices_d, *normals_d;
  float *vertices_f, *normals_f;
  int *triangles, *edges, *edge_triangles;
};

struct State {
  bool ready;
  DeviceShapes shapes;
  void *scratch;              // per-thread overlap workspaces
  size_t scratch_bytes;
  poly_gpu_pair *pairs;
  poly_gpu_result *results;
  double *history;
  poly_material_pair *materials;
  size_t pair_capacity, result_capacity, history_capacity, material_capacity;
};

State state = {};

bool check(cudaError_t status, const char *what, char *message, size_t size)
{
  if (status == cudaSuccess) return true;
  if (message) snprintf(message, size, "CUDA error in %s: %s", what, cudaGetErrorString(status));
  return false;
}

template <typename T> bool upload(T **device, const T *host, size_t count, char *message, size_t size)
{
  if (!check(cudaMalloc((void **)device, sizeof(T) * (count ? count : 1)), "cudaMalloc", message, size)) return false;
  if (count == 0) return true;
  return check(cudaMemcpy(*device, host, sizeof(T) * count, cudaMemcpyHostToDevice), "cudaMemcpy", message, size);
}

template <typename T> bool ensure(T **device, size_t *capacity, size_t count, char *message, size_t size)
{
  if (count <= *capacity && *device) return true;
  if (*device) cudaFree(*device);
  *device = NULL;
  size_t grown = count + count / 2 + 64;
  if (!check(cudaMalloc((void **)device, sizeof(T) * grown), "cudaMalloc", message, size)) return false;
  *capacity = grown;
  return true;
}

// A view of shape `shape` in the flat device arrays, with vertices and normals
// of the view's scalar type.
template <typename View, typename Real>
__device__ View shape_view(const DeviceShapes &s, int shape, const Real *vertices, const Real *normals)
{
  View v;
  v.num_vertices = s.counts[3 * shape];
  v.num_triangles = s.counts[3 * shape + 1];
  v.num_edges = s.counts[3 * shape + 2];
  v.vertices = vertices + 3 * s.offsets[3 * shape];
  v.face_normals = normals + 3 * s.offsets[3 * shape + 1];
  v.triangles = s.triangles + 3 * s.offsets[3 * shape + 1];
  v.edges = s.edges + 2 * s.offsets[3 * shape + 2];
  v.edge_triangles = s.edge_triangles + 2 * s.offsets[3 * shape + 2];
  v.bounding_radius = (Real)s.radius[shape];
  return v;
}

__global__ void contact_kernel(DeviceShapes shapes, const poly_gpu_pair *pairs, int first, int count,
                               const poly_material_pair *materials, int single_precision, int tangential,
                               int damping, double dt, int advance_history, double *history,
                               poly_gpu_result *results, char *scratch, size_t bytes_per_thread)
{
  int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= count) return;
  int p = first + local;
  const poly_gpu_pair &pair = pairs[p];
  poly_gpu_result out;
  memset(&out, 0, sizeof out);

  // The relative pose, as poly_overlap_d/f compute it on the host.
  double rotation_i[9], rotation_j[9], rotation[9], difference[3], translation[3];
  poly_quat_to_matrix(pair.quaternion_i, rotation_i);
  poly_quat_to_matrix(pair.quaternion_j, rotation_j);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      rotation[3 * a + b] = rotation_i[a] * rotation_j[b] + rotation_i[3 + a] * rotation_j[3 + b] +
                            rotation_i[6 + a] * rotation_j[6 + b];
  for (int k = 0; k < 3; k++) difference[k] = pair.position_j[k] - pair.position_i[k];
  poly_matrix_apply_transpose(rotation_i, difference, translation);

  poly_overlap_result geometry;
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  char *memory = scratch + (size_t)local * bytes_per_thread;
  if (single_precision) {
    poly_overlap_workspace_f ws;
    poly_overlap_workspace_layout_f(&ws, memory, shapes.max_vertices, shapes.max_triangles);
    poly_shape_view_f a = shape_view<poly_shape_view_f>(shapes, pair.shape_i, shapes.vertices_f, shapes.normals_f);
    poly_shape_view_f b = shape_view<poly_shape_view_f>(shapes, pair.shape_j, shapes.vertices_f, shapes.normals_f);
    poly_overlap_local_f(&a, &b, rotation, translation, &ws, local_centroid, local_normal, &geometry);
  } else {
    poly_overlap_workspace_d ws;
    poly_overlap_workspace_layout_d(&ws, memory, shapes.max_vertices, shapes.max_triangles);
    poly_shape_view_d a = shape_view<poly_shape_view_d>(shapes, pair.shape_i, shapes.vertices_d, shapes.normals_d);
    poly_shape_view_d b = shape_view<poly_shape_view_d>(shapes, pair.shape_j, shapes.vertices_d, shapes.normals_d);
    poly_overlap_local_d(&a, &b, rotation, translation, &ws, local_centroid, local_normal, &geometry);
  }
  double *state_history = history + POLY_HISTORY_SIZE * p;
  if (!(geometry.volume > pair.negligible_volume) || !(geometry.depth > 0.0)) {
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) state_history[d] = 0.0;
    results[p] = out;
    return;
  }
  poly_contact_input input;
  input.volume = geometry.volume;
  input.depth = geometry.depth;
  poly_matrix_apply(rotation_i, local_centroid, input.centroid);
  poly_matrix_apply(rotation_i, local_normal, input.normal);
  for (int k = 0; k < 3; k++) input.centroid[k] += pair.position_i[k];
  poly_contact_input_set_bodies(&input, pair.position_i, pair.velocity_i, pair.omega_i, pair.mass_i, pair.position_j,
                                pair.velocity_j, pair.omega_j, pair.mass_j, dt);
  double scratch_history[POLY_HISTORY_SIZE];
  double *law_history = state_history;
  if (!advance_history) {
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) scratch_history[d] = state_history[d];
    law_history = scratch_history;
  }
  poly_contact_output law;
  poly_contact_evaluate(&input, &materials[pair.material], tangential, damping, law_history, &law);
  out.contact = 1;
  out.volume = geometry.volume;
  out.depth = geometry.depth;
  out.normal_force = law.normal_force;
  for (int k = 0; k < 3; k++) {
    out.force_j[k] = law.force_j[k];
    out.torque_i[k] = law.torque_i[k];
    out.torque_j[k] = law.torque_j[k];
    out.normal[k] = input.normal[k];
    out.centroid[k] = input.centroid[k];
    out.tangential_force[k] = law.tangential_force[k];
  }
  results[p] = out;
}

void free_shapes(DeviceShapes &s)
{
  cudaFree(s.offsets); cudaFree(s.counts); cudaFree(s.radius);
  cudaFree(s.vertices_d); cudaFree(s.normals_d); cudaFree(s.vertices_f); cudaFree(s.normals_f);
  cudaFree(s.triangles); cudaFree(s.edges); cudaFree(s.edge_triangles);
  memset(&s, 0, sizeof s);
}

}  // namespace

extern "C" int poly_gpu_device_count(void)
{
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

extern "C" int poly_gpu_init(int device, int num_shapes, const poly_shape *const *shapes, char *message,
                             size_t message_size)
{
  poly_gpu_clear();
  int devices = poly_gpu_device_count();
  if (devices == 0) {
    snprintf(message, message_size, "no CUDA device is available");
    return -1;
  }
  if (!check(cudaSetDevice(device % devices), "cudaSetDevice", message, message_size)) return -1;

  // Flatten the shapes.
  int total_vertices = 0, total_triangles = 0, total_edges = 0;
  DeviceShapes &s = state.shapes;
  s.count = num_shapes;
  s.max_vertices = s.max_triangles = 1;
  for (int i = 0; i < num_shapes; i++) {
    total_vertices += shapes[i]->num_vertices;
    total_triangles += shapes[i]->num_triangles;
    total_edges += shapes[i]->num_edges;
    if (shapes[i]->num_vertices > s.max_vertices) s.max_vertices = shapes[i]->num_vertices;
    if (shapes[i]->num_triangles > s.max_triangles) s.max_triangles = shapes[i]->num_triangles;
  }
  int *offsets = new int[3 * num_shapes], *counts = new int[3 * num_shapes];
  double *radius = new double[num_shapes];
  double *vertices_d = new double[3 * total_vertices], *normals_d = new double[3 * total_triangles];
  float *vertices_f = new float[3 * total_vertices], *normals_f = new float[3 * total_triangles];
  int *triangles = new int[3 * total_triangles], *edges = new int[2 * total_edges];
  int *edge_triangles = new int[2 * total_edges];
  int v = 0, t = 0, e = 0;
  for (int i = 0; i < num_shapes; i++) {
    const poly_shape *shape = shapes[i];
    offsets[3 * i] = v; offsets[3 * i + 1] = t; offsets[3 * i + 2] = e;
    counts[3 * i] = shape->num_vertices; counts[3 * i + 1] = shape->num_triangles; counts[3 * i + 2] = shape->num_edges;
    radius[i] = shape->bounding_radius;
    for (int k = 0; k < 3 * shape->num_vertices; k++) {
      vertices_d[3 * v + k] = shape->vertices[k];
      vertices_f[3 * v + k] = (float)shape->vertices[k];
    }
    for (int k = 0; k < 3 * shape->num_triangles; k++) {
      normals_d[3 * t + k] = shape->face_normals[k];
      normals_f[3 * t + k] = (float)shape->face_normals[k];
      triangles[3 * t + k] = shape->triangles[k];  // vertex indices stay shape-local
    }
    for (int k = 0; k < 2 * shape->num_edges; k++) {
      edges[2 * e + k] = shape->edges[k];
      edge_triangles[2 * e + k] = shape->edge_triangles[k];
    }
    v += shape->num_vertices; t += shape->num_triangles; e += shape->num_edges;
  }
  bool ok = upload(&s.offsets, offsets, 3 * num_shapes, message, message_size) &&
            upload(&s.counts, counts, 3 * num_shapes, message, message_size) &&
            upload(&s.radius, radius, num_shapes, message, message_size) &&
            upload(&s.vertices_d, vertices_d, 3 * total_vertices, message, message_size) &&
            upload(&s.normals_d, normals_d, 3 * total_triangles, message, message_size) &&
            upload(&s.vertices_f, vertices_f, 3 * total_vertices, message, message_size) &&
            upload(&s.normals_f, normals_f, 3 * total_triangles, message, message_size) &&
            upload(&s.triangles, triangles, 3 * total_triangles, message, message_size) &&
            upload(&s.edges, edges, 2 * total_edges, message, message_size) &&
            upload(&s.edge_triangles, edge_triangles, 2 * total_edges, message, message_size);
  delete[] offsets; delete[] counts; delete[] radius; delete[] vertices_d; delete[] normals_d;
  delete[] vertices_f; delete[] normals_f; delete[] triangles; delete[] edges; delete[] edge_triangles;
  if (!ok) return -1;
  state.ready = true;
  return 0;
}

extern "C" int poly_gpu_compute(int num_pairs, const poly_gpu_pair *pairs, const poly_material_pair *materials,
                                int num_materials, int single_precision, int tangential, int damping, double dt,
                                int advance_history, double *history, poly_gpu_result *results, char *message,
                                size_t message_size)
{
  if (!state.ready) {
    snprintf(message, message_size, "poly_gpu_compute before poly_gpu_init");
    return -1;
  }
  if (num_pairs == 0) return 0;
  if (!ensure(&state.pairs, &state.pair_capacity, num_pairs, message, message_size) ||
      !ensure(&state.results, &state.result_capacity, num_pairs, message, message_size) ||
      !ensure(&state.history, &state.history_capacity, (size_t)num_pairs * POLY_HISTORY_SIZE, message, message_size))
    return -1;
  if (!ensure(&state.materials, &state.material_capacity, num_materials, message, message_size)) return -1;
  if (!check(cudaMemcpy(state.pairs, pairs, sizeof(poly_gpu_pair) * num_pairs, cudaMemcpyHostToDevice), "upload pairs",
             message, message_size) ||
      !check(cudaMemcpy(state.history, history, sizeof(double) * POLY_HISTORY_SIZE * num_pairs,
                        cudaMemcpyHostToDevice), "upload history", message, message_size) ||
      !check(cudaMemcpy(state.materials, materials, sizeof(poly_material_pair) * num_materials,
                        cudaMemcpyHostToDevice), "upload materials", message, message_size))
    return -1;

  // Workspaces for a batch of threads at a time: bounded memory for any pair count.
  const DeviceShapes &s = state.shapes;
  size_t workspace = single_precision
                         ? poly_overlap_workspace_layout_f(NULL, NULL, s.max_vertices, s.max_triangles)
                         : poly_overlap_workspace_layout_d(NULL, NULL, s.max_vertices, s.max_triangles);
  workspace = (workspace + 255) / 256 * 256;
  size_t batch = (size_t)1 << 16;
  const size_t budget = (size_t)1 << 30;
  while (batch > 256 && batch * workspace > budget) batch /= 2;
  if (state.scratch_bytes < batch * workspace) {
    cudaFree(state.scratch);
    state.scratch = NULL;
    if (!check(cudaMalloc(&state.scratch, batch * workspace), "cudaMalloc scratch", message, message_size)) return -1;
    state.scratch_bytes = batch * workspace;
  }
  const int threads = 128;
  for (size_t first = 0; first < (size_t)num_pairs; first += batch) {
    int count = (int)((size_t)num_pairs - first < batch ? (size_t)num_pairs - first : batch);
    contact_kernel<<<(count + threads - 1) / threads, threads>>>(
        s, state.pairs, (int)first, count, state.materials, single_precision, tangential, damping, dt,
        advance_history, state.history, state.results, (char *)state.scratch, workspace);
    if (!check(cudaGetLastError(), "contact kernel launch", message, message_size)) return -1;
  }
  if (!check(cudaDeviceSynchronize(), "contact kernel", message, message_size) ||
      !check(cudaMemcpy(results, state.results, sizeof(poly_gpu_result) * num_pairs, cudaMemcpyDeviceToHost),
             "download results", message, message_size) ||
      !check(cudaMemcpy(history, state.history, sizeof(double) * POLY_HISTORY_SIZE * num_pairs,
                        cudaMemcpyDeviceToHost), "download history", message, message_size))
    return -1;
  return 0;
}

extern "C" size_t poly_gpu_bytes(void)
{
  // Shapes are small; report the per-step buffers, which dominate.
  return state.scratch_bytes + state.pair_capacity * sizeof(poly_gpu_pair) +
         state.result_capacity * sizeof(poly_gpu_result) + state.history_capacity * sizeof(double) +
         state.material_capacity * sizeof(poly_material_pair);
}

extern "C" void poly_gpu_clear(void)
{
  if (state.ready) free_shapes(state.shapes);
  cudaFree(state.scratch);
  cudaFree(state.pairs);
  cudaFree(state.results);
  cudaFree(state.history);
  cudaFree(state.materials);
  state = State();
}
