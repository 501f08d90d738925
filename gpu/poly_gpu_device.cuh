/* Device-side pieces shared by the CUDA sources of gpu/: the shapes in flat
 * device arrays, growable device and pinned host arrays with checked CUDA
 * calls, and the overlap code of each precision with its shape views and
 * per-thread workspaces, for kernel templates. Internal to gpu/: the public
 * boundary is poly_gpu.h. */
#ifndef POLY_GPU_DEVICE_CUH
#define POLY_GPU_DEVICE_CUH

#include <cuda_runtime.h>
#include <stdio.h>

#include <chrono>

#include "poly_overlap.h"

#include "poly_overlap_instances.h"

// The warp-per-pair pass (poly_gpu_warp_impl.cuh), once per precision.
#define POLY_FN(name) poly_##name##_d
#include "poly_gpu_warp_impl.cuh"
#undef POLY_FN
#define POLY_FN(name) poly_##name##_f
#include "poly_gpu_warp_impl.cuh"
#undef POLY_FN
#define POLY_FN(name) poly_##name##_m
#include "poly_gpu_warp_impl.cuh"
#undef POLY_FN

namespace poly_gpu_detail {

// Shapes packed in flat device arrays; per shape the offsets into them.
struct DeviceShapes {
  int count;
  int max_vertices, max_triangles;
  int *offsets;               // 3 per shape: vertex, triangle, edge offset
  int *counts;                // 3 per shape: vertices, triangles, edges
  double *radius;
  double *vertices_d, *normals_d;
  float *vertices_f, *normals_f;
  int *triangles, *edges, *edge_triangles;
  poly_clip_faces *clip;      // per shape its faces for the clipping path (num_faces 0: none), device pointers
  double *clip_planes;
  int *clip_loop_start, *clip_loop, *clip_triangle;
  poly_clip_words *clip_piece_front, *clip_piece_back;  // per piece (poly_clip_faces)
  int *clip_piece_point_start, *clip_piece_points, *clip_piece_face_start, *clip_piece_faces;
  double *clip_vertices;      // per shape its clip vertices (poly_shape's, or its vertices)
  float *clip_vertices_f, *clip_planes_f;  // the same in float (the warp clipping kernel in mixed precision)
  int *clip_face_plane;       // per clip face its plane's index among the shape's clip planes, or -1
};

template <typename T> struct DeviceArray {
  T *data;
  size_t capacity;
};

template <typename T> struct PinnedArray {
  T *data;
  size_t capacity;
};

inline double now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline bool check(cudaError_t status, const char *what, char *message, size_t size)
{
  if (status == cudaSuccess) return true;
  if (message) snprintf(message, size, "CUDA error in %s: %s", what, cudaGetErrorString(status));
  return false;
}

template <typename T> bool ensure(DeviceArray<T> &a, size_t count, char *message, size_t size)
{
  if (count <= a.capacity && a.data) return true;
  cudaFree(a.data);
  a.data = NULL;
  a.capacity = 0;
  size_t grown = count + count / 8 + 64;  // room for the next rebuild's few more, not a quarter more
  if (!check(cudaMalloc((void **)&a.data, sizeof(T) * grown), "cudaMalloc", message, size)) return false;
  a.capacity = grown;
  return true;
}

template <typename T> bool ensure(PinnedArray<T> &a, size_t count, char *message, size_t size)
{
  if (count <= a.capacity && a.data) return true;
  cudaFreeHost(a.data);
  a.data = NULL;
  a.capacity = 0;
  size_t grown = count + count / 8 + 64;  // room for the next rebuild's few more, not a quarter more
  if (!check(cudaMallocHost((void **)&a.data, sizeof(T) * grown), "cudaMallocHost", message, size)) return false;
  a.capacity = grown;
  return true;
}

template <typename T> bool upload(DeviceArray<T> &a, const T *host, size_t count, char *message, size_t size)
{
  if (!ensure(a, count, message, size)) return false;
  if (count == 0) return true;
  return check(cudaMemcpy(a.data, host, sizeof(T) * count, cudaMemcpyHostToDevice), "cudaMemcpy", message, size);
}

template <typename T> void release(DeviceArray<T> &a)
{
  cudaFree(a.data);
  a.data = NULL;
  a.capacity = 0;
}

template <typename T> void release(PinnedArray<T> &a)
{
  cudaFreeHost(a.data);
  a.data = NULL;
  a.capacity = 0;
}

template <typename T> size_t bytes_of(const DeviceArray<T> &a) { return a.capacity * sizeof(T); }

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
  v.triangle_edges = NULL;
  v.face_of = v.ridges = NULL;  // the device takes the reference path (POLY_OVERLAP_RECORDS 0)
  v.num_ridges = 0;
  v.support = NULL;
  v.num_support = 0;
  v.extreme_start = v.extreme_vertices = NULL;
  v.clip.num_faces = 0;  // the clipping path is host-only for now
  v.bounding_radius = (Real)s.radius[shape];
  return v;
}

// The overlap code of one precision (poly_overlap_instances.h): its shape
// views, workspace and functions, for the kernel templates.
template <int Precision> struct Narrow;
#define POLY_GPU_NARROW(PRECISION, REAL, GEOMETRY, SUFFIX)                                                        \
  template <> struct Narrow<PRECISION> {                                                                           \
    typedef REAL Real;                                                                                             \
    typedef poly_shape_view##GEOMETRY View;                                                                        \
    typedef poly_overlap_workspace##GEOMETRY Workspace;                                                            \
    typedef poly_warp_memory##SUFFIX WarpMemory;                                                                   \
    static __device__ View view(const DeviceShapes &s, int shape)                                                  \
    {                                                                                                              \
      return shape_view<View>(s, shape, s.vertices##GEOMETRY, s.normals##GEOMETRY);                              \
    }                                                                                                              \
    static __host__ __device__ size_t layout(Workspace *ws, void *memory, int max_vertices, int max_triangles)    \
    {                                                                                                              \
      return poly_overlap_workspace_layout##SUFFIX(ws, memory, max_vertices, max_triangles);                      \
    }                                                                                                              \
    static __device__ int separated(const View *a, const View *b, const double *rotation, const double *translation, \
                                    int search)                                                                   \
    {                                                                                                              \
      double separation;                                                                                           \
      return poly_slab_or_parting##SUFFIX(a, b, rotation, translation, search, &separation);                      \
    }                                                                                                              \
    static __device__ void overlap(const View *a, const View *b, const double *rotation, const double *translation, \
                                   Workspace *ws, double *centroid, double *normal, poly_overlap_result *result)   \
    {                                                                                                              \
      poly_overlap_local##SUFFIX(a, b, rotation, translation, ws, centroid, normal, result);                      \
    }                                                                                                              \
    static __host__ __device__ size_t warp_layout(WarpMemory *m, char *memory, int nv, int nt, int ne, int nr)     \
    {                                                                                                              \
      return poly_warp_layout##SUFFIX(m, memory, nv, nt, ne, nr);                                                  \
    }                                                                                                              \
    typedef poly_warp_frame##SUFFIX WarpFrame;                                                                     \
    static __device__ int warp_overlap(const View *a, const View *b, const double *rotation,                      \
                                       const double *translation, int want_second, const WarpMemory *m,           \
                                       const poly_lanes &lanes, double *centroid, double *normal,                 \
                                       poly_overlap_result *result, WarpFrame *frame)                             \
    {                                                                                                              \
      return poly_warp_overlap##SUFFIX(a, b, rotation, translation, want_second, m, lanes, centroid, normal,       \
                                       result, frame);                                                             \
    }                                                                                                              \
    static __device__ void warp_nodes(const View *a, const View *b, const WarpMemory *m, const WarpFrame *frame,  \
                                      const double *rotation_a, const poly_lanes &lanes, double *out)             \
    {                                                                                                              \
      poly_warp_nodes##SUFFIX(a, b, m, frame, rotation_a, lanes, out);                                            \
    }                                                                                                              \
  };
POLY_GPU_NARROW(POLY_PRECISION_DOUBLE, double, _d, _d)
POLY_GPU_NARROW(POLY_PRECISION_SINGLE, float, _f, _f)
POLY_GPU_NARROW(POLY_PRECISION_MIXED, float, _f, _m)
#undef POLY_GPU_NARROW

// Where a thread's overlap workspace lives: an array of Bytes in its local
// memory, or (Bytes = 0) its block of the global scratch buffer.
template <size_t Bytes> struct WorkspaceMemory {
  double block[(Bytes + sizeof(double) - 1) / sizeof(double)];
  __device__ char *get(char *, int, size_t) { return (char *)block; }
};
template <> struct WorkspaceMemory<0> {
  __device__ char *get(char *scratch, int local, size_t bytes_per_thread)
  {
    return scratch + (size_t)local * bytes_per_thread;
  }
};

// Bytes of the local-memory workspace of a precision.
template <int Precision> struct LocalWorkspace {
  static const size_t bytes = POLY_GPU_LOCAL_WORKSPACE_REALS * sizeof(typename Narrow<Precision>::Real);
};

const int kThreads = 128;

// The warp kernel takes shapes whose warp block (poly_gpu_warp_impl.cuh) is at most kWarpBytesLimit, and a
// block of up to kThreads / 32 warps whose blocks fit in kWarpBlockBytes of shared memory.
const size_t kWarpBytesLimit = 48 * 1024, kWarpBlockBytes = 96 * 1024;

// Blocks of the contact kernel each SM must be able to hold: 2 leaves ptxas
// all 255 registers (no spills, 8 warps per SM); 3 caps it at 168 and 4 at
// 128, trading spills for occupancy. tools/bench_gpu.sh measures the choices.
#ifndef POLY_GPU_CONTACT_MIN_BLOCKS
#define POLY_GPU_CONTACT_MIN_BLOCKS 2
#endif

// The warp kernels' limits: the largest counts of the shapes whose own warp
// block fits kWarpBytesLimit (larger shapes go to the one-thread kernels),
// their records, and the bytes of a block for them (0: no shape fits).
struct WarpLimits {
  int vertices, triangles, edges, records, bytes;
  int lanes;  // per pair or wall piece: 8, 16 or 32
};

// Does the shape exceed the warp kernels' limits?
__device__ inline bool beyond_limits(const DeviceShapes &shapes, int shape, const WarpLimits &limits)
{
  const int *c = shapes.counts + 3 * shape;
  return c[0] > limits.vertices || c[1] > limits.triangles || c[2] > limits.edges;
}

// A warp kernel's launch: blocks of whole warps, as many groups of limits.lanes lanes as kWarpBlockBytes holds
// (at most kThreads lanes), each group with its block of limits.bytes of shared memory; lets the kernel use
// more than the default 48 KiB where it needs to.
struct WarpLaunch {
  int threads, groups;
  size_t shared;
};
template <typename Kernel>
inline bool warp_launch(Kernel kernel, const WarpLimits &limits, WarpLaunch *launch, char *message, size_t size)
{
  launch->threads = kThreads;
  while (launch->threads > 32 && (size_t)(launch->threads / limits.lanes) * limits.bytes > kWarpBlockBytes)
    launch->threads /= 2;
  launch->groups = launch->threads / limits.lanes;
  launch->shared = (size_t)launch->groups * limits.bytes;
  return launch->shared <= 48 * 1024 ||
         check(cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, (int)launch->shared),
               "warp kernel shared memory", message, size);
}

// The shapes uploaded by poly_gpu_init (NULL before it).
const DeviceShapes *device_shapes();

// The limits of a warp block in global memory for every uploaded shape (each count at least the minimum given):
// the largest counts, their records, 32 lanes; bytes left 0 for the caller's layout.
WarpLimits largest_shape_limits(int min_vertices, int min_triangles, int min_edges);

// For the shapes of poly_gpu_init in a precision: the warp kernels' limits, each count at least the minimum
// given (a wall's prism: 6 vertices, 8 triangles, 12 edges); POLY_GPU_WALL_KERNEL (0 unset, 1 thread, 2 warp).
WarpLimits warp_limits(int precision, int min_vertices, int min_triangles, int min_edges);
int wall_kernel_choice();

// The wall narrow phase's device memory (poly_gpu_wall.cu), for poly_gpu_bytes and poly_gpu_clear.
size_t wall_bytes();
void wall_clear();
void wall_timing(poly_gpu_timing *timing);  // its fields wall_*

}  // namespace poly_gpu_detail

#endif
