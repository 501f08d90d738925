/* CUDA narrow phase: the CPU code's own overlap geometry and contact law, one
 * thread per touching pair. See poly_gpu.h for the call sequence.
 *
 * Each step: (1) a cheap kernel over all candidate pairs tests the bounding
 * spheres, clears the pairs that do not touch and appends the others to a
 * compact list (warp-aggregated atomics), so the expensive kernel runs on
 * touching pairs only and its warps do not idle on far pairs; (2) the contact
 * kernel evaluates overlap and contact law for the listed pairs, writing a
 * per-pair force and torques (no atomics on particles, so the sums are
 * deterministic); (3) a reduction kernel sums each particle's pair
 * contributions in a fixed order through a CSR index built at set-up.
 *
 * The kernels are instantiated per precision. The pre-filter of (1) also applies
 * the overlap's own half-space slab test (poly_overlap_slab), so pairs whose
 * bounding spheres touch but whose bodies cannot (most of them in a packed bed
 * of elongated shapes) leave no idle lanes in the overlap kernel's warps. Each
 * thread of (2) needs an overlap workspace: when the largest shape's fits in
 * POLY_GPU_LOCAL_WORKSPACE_REALS scalars it is an array in the thread's local
 * memory, which the hardware interleaves across a warp's threads (a warp's
 * accesses to one element of its 32 workspaces fall in one or two cache lines,
 * and the unused tail of the array is never touched); larger shapes get
 * per-thread blocks of a scratch buffer in global memory. */
#include "poly_gpu.h"

#include <stdlib.h>
#include <string.h>

#include <algorithm>
#include <vector>

#include "poly_gpu_device.cuh"
#include "poly_gpu_clip_warp.cuh"

using namespace poly_gpu_detail;

namespace {

// Per pair: what the contact kernel leaves for the reduction.
struct PairForce {
  double force_j[3], torque_i[3], torque_j[3];
};

// Per pair, when the host needs each pair (poly_gpu_result): the rest of it, its forces being in PairForce.
struct PairGeometry {
  int contact, pair;
  double volume, depth, normal[3], centroid[3], normal_force, tangential_force[3];
};

struct State {
  bool ready;
  DeviceShapes shapes;
  int num_particles, num_force_particles, num_pairs, num_types;
  DeviceArray<poly_gpu_particle> particles;
  DeviceArray<poly_gpu_motion> motion;
  DeviceArray<int> pair_i, pair_j;
  DeviceArray<double> history;
  DeviceArray<int> contact;
  DeviceArray<int> touching;        // compact list of pairs whose bounding spheres overlap
  DeviceArray<int> counters;        // [0] touching pairs, [1] contacts, [2] pairs the warp kernel handed back,
                                    // [3] touching pairs of shapes beyond the warp kernel's limits, [4] pairs kept,
                                    // [5] overlaps whose centroid fell outside their particles (no contact),
                                    // [6] contacts at spots facing apart (poly_contact_spots_facing_apart)
  DeviceArray<int> slot;            // per pair: its place in pair_force and results, -1 where the pre-filter
                                    // dropped it (most of a packed bed's pairs: no per-pair arrays for them)
  int num_kept;                     // pairs the last pre-filter kept: the size of pair_force and results
  DeviceArray<int> handed_back;     // the pairs of [2]
  DeviceArray<int> large;           // the pairs of [3]
  DeviceArray<int> handed_large;    // the pairs large_by_warp hands back (counted in [2] again)
  poly_gpu_options options;         // the kernel choices (poly_gpu_environment)
  bool any_clip;                    // some shape has faces for the clipping path (poly_clip.h)
  bool any_pieces;                  // some such shape is not convex (several pieces): the warp clipping kernel
  ClipWarpLimits clip_limits;       // its shared block per warp, for the uploaded shapes
  ClipWarpLimits clip_limits_single;  // the same with the faces clipped in single (mixed precision)
  ClipWarpLimits clip_limits_used;    // those of the last launch (poly_gpu_timings)
  std::vector<int> host_counts;     // per shape: vertices, triangles, edges
  DeviceArray<PairForce> pair_force;
  DeviceArray<PairGeometry> results;
  PinnedArray<PairGeometry> host_results;     // the kept pairs' results and forces, before they go to the
  PinnedArray<PairForce> host_pair_force;     // caller's places
  DeviceArray<int> csr_offsets, csr_entries;  // per force particle: 2 * pair + (0: as i, 1: as j)
  DeviceArray<double> force_torque;
  DeviceArray<poly_material_pair> materials;
  DeviceArray<char> scratch;        // per-thread overlap workspaces
  PinnedArray<poly_gpu_motion> host_motion;
  PinnedArray<double> host_force_torque;
  poly_gpu_timing timing;
};

State state = {};


// Does either shape of the pair exceed the warp kernel's limits?
__device__ inline bool beyond(const DeviceShapes &shapes, int shape_i, int shape_j, const WarpLimits &limits)
{
  return beyond_limits(shapes, shape_i, limits) || beyond_limits(shapes, shape_j, limits);
}

// A place from *counter for each lane where `take` (one atomic per warp), -1 elsewhere.
__device__ inline int reserve(int take, int *__restrict__ counter)
{
  unsigned ballot = __ballot_sync(0xffffffffu, take);
  if (!ballot) return -1;
  int lane = threadIdx.x & 31, leader = __ffs(ballot) - 1, base = 0;
  if (lane == leader) base = atomicAdd(counter, __popc(ballot));
  base = __shfl_sync(0xffffffffu, base, leader);
  return take ? base + __popc(ballot & ((1u << lane) - 1u)) : -1;
}

// Appends p to `list` where `take` (one atomic per warp on *counter).
__device__ inline void append(int take, int p, int *__restrict__ list, int *__restrict__ counter)
{
  int place = reserve(take, counter);
  if (take) list[place] = p;
}

// Pairs whose bounding spheres overlap, and whose bodies overlap along the
// centre line and (`parting_search`, pairs not in contact at their last
// evaluation) are not parted by the host's parting search (src/poly_overlap_parting_impl.h:
// most pairs apart that the centre line does not part, which the contact
// kernels took whole), go to the compact list `touching` (counters[0]), or, when the
// warp kernel runs (limits.bytes > 0) and a shape exceeds its limits, to
// `large` (counters[3]) for the one-thread kernel, and get a slot (counters[4])
// in the per-pair arrays pair_force and results; the others are cleared: no
// contact, no history, no slot (their force is zero).
template <int Precision>
__global__ void __launch_bounds__(kThreads)
    bounding_kernel(DeviceShapes shapes, int num_pairs, const int *__restrict__ pair_i,
                    const int *__restrict__ pair_j, const poly_gpu_particle *__restrict__ particles,
                    const poly_gpu_motion *__restrict__ motion, int *__restrict__ contact,
                    double *__restrict__ history, int *__restrict__ slot, int *__restrict__ touching,
                    int *__restrict__ large, WarpLimits limits, int parting_search, int *__restrict__ counters)
{
  typedef Narrow<Precision> N;
  int p = blockIdx.x * blockDim.x + threadIdx.x;
  int take = 0;
  if (p < num_pairs) {
    int i = pair_i[p], j = pair_j[p];
    const double *xi = motion[i].position, *xj = motion[j].position;
    double dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
    int shape_i = particles[i].shape, shape_j = particles[j].shape;
    double reach = shapes.radius[shape_i] + shapes.radius[shape_j];
    take = dx * dx + dy * dy + dz * dz < reach * reach;
    if (take) {
      double rotation_i[9], rotation[9], translation[3];
      poly_overlap_relative_pose(motion[i].position, motion[i].quaternion, motion[j].position, motion[j].quaternion,
                                 rotation_i, rotation, translation);
      typename N::View a = N::view(shapes, shape_i), b = N::view(shapes, shape_j);
      take = !N::separated(&a, &b, rotation, translation, parting_search && !contact[p]);
    }
    if (!take) {
      contact[p] = 0;
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) history[POLY_HISTORY_SIZE * p + d] = 0.0;
    }
  }
  // Every lane of the warp gets here (blocks are whole warps).
  int place = reserve(take, counters + 4);
  if (p < num_pairs) slot[p] = place;
  int to_large = take && limits.bytes > 0 && beyond(shapes, particles[pair_i[p]].shape, particles[pair_j[p]].shape,
                                                    limits);
  append(take && !to_large, p, touching, counters);
  if (limits.bytes > 0) append(to_large, p, large, counters + 3);
}

// Pair p's two particles and the pose of j in i's body frame, as the host's overlap entry computes it: the one
// start of every contact kernel.
struct PairBodies {
  const poly_gpu_particle *body_i, *body_j;
  const poly_gpu_motion *state_i, *state_j;
  double rotation_i[9], rotation[9], translation[3];
};

__device__ __forceinline__ void pair_bodies(int p, const int *__restrict__ pair_i, const int *__restrict__ pair_j,
                                            const poly_gpu_particle *__restrict__ particles,
                                            const poly_gpu_motion *__restrict__ motion, PairBodies &pair)
{
  const int i = pair_i[p], j = pair_j[p];
  pair.body_i = particles + i, pair.body_j = particles + j;
  pair.state_i = motion + i, pair.state_j = motion + j;
  poly_overlap_relative_pose(pair.state_i->position, pair.state_i->quaternion, pair.state_j->position,
                             pair.state_j->quaternion, pair.rotation_i, pair.rotation, pair.translation);
}

// The contact law for pair p from its overlap (in i's local frame), and what
// the reduction and the host read: the one end of every contact kernel.
__device__ __forceinline__ void finish_pair(int p, const PairBodies &pair, const poly_overlap_result &geometry, const double *local_centroid,
                            const double *local_normal, const poly_material_pair *__restrict__ materials,
                            int num_types, const poly_gpu_settings &settings, int *__restrict__ contact,
                            double *__restrict__ history, const int *__restrict__ slot,
                            PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                            int *__restrict__ counters)
{
  const poly_gpu_particle &body_i = *pair.body_i, &body_j = *pair.body_j;
  const poly_gpu_motion &state_i = *pair.state_i, &state_j = *pair.state_j;
  const double *rotation_i = pair.rotation_i;
  double *pair_history = history + POLY_HISTORY_SIZE * p;
  const int place = slot[p];
  double negligible = body_i.negligible_volume < body_j.negligible_volume ? body_i.negligible_volume
                                                                          : body_j.negligible_volume;
  const bool touches = geometry.volume > negligible && geometry.depth > 0.0;
  if (!touches ||
      !poly_contact_centroid_within(local_centroid, pair.translation, body_i.bounding_radius, body_j.bounding_radius)) {
    if (touches) atomicAdd(counters + 5, 1);  // rounding, dropped; the host warns as for its own (centroid_within)
    contact[p] = 0;
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) pair_history[d] = 0.0;
    PairForce zero = {};
    pair_force[place] = zero;
    return;
  }
  poly_contact_input input;
  input.volume = geometry.volume;
  input.depth = poly_contact_pair_depth(geometry.volume, geometry.depth, geometry.projected_area);
  if (poly_contact_spots_facing_apart(geometry.volume, input.depth, geometry.area)) atomicAdd(counters + 6, 1);
  poly_matrix_apply(rotation_i, local_centroid, input.centroid);
  poly_matrix_apply(rotation_i, local_normal, input.normal);
  for (int k = 0; k < 3; k++) input.centroid[k] += state_i.position[k];
  poly_second_moment_rotate(rotation_i, geometry.second_moment, input.second_moment);
  input.couples = 1;
  input.contact_area = geometry.projected_area;
  poly_contact_input_set_bodies(&input, state_i.position, state_i.velocity, state_i.omega, body_i.mass,
                                state_j.position, state_j.velocity, state_j.omega, body_j.mass, settings.dt);
  double scratch_history[POLY_HISTORY_SIZE];
  double *law_history = pair_history;
  if (!settings.advance_history) {
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) scratch_history[d] = pair_history[d];
    law_history = scratch_history;
  }
  poly_contact_output law;
  poly_contact_evaluate(&input, &materials[body_i.type * (num_types + 1) + body_j.type], settings.tangential,
                        settings.damping, law_history, &law);
  contact[p] = 1;
  atomicAdd(counters + 1, 1);
  PairForce out;
  for (int k = 0; k < 3; k++) {
    out.force_j[k] = law.force_j[k];
    out.torque_i[k] = law.torque_i[k];
    out.torque_j[k] = law.torque_j[k];
  }
  pair_force[place] = out;
  if (results) {
    PairGeometry r;
    r.contact = 1;
    r.pair = p;
    r.volume = geometry.volume;
    r.depth = input.depth;
    r.normal_force = law.normal_force - law.cohesive_force;  // net, as the CPU style records it
    for (int k = 0; k < 3; k++) {
      r.normal[k] = input.normal[k];
      r.centroid[k] = input.centroid[k];
      r.tangential_force[k] = law.tangential_force[k];
    }
    results[place] = r;
  }
}

// One thread per pair of `list`: the whole of overlap_local, for the pairs the
// warp kernel hands back and for shapes too large for its shared memory.
template <int Precision, size_t LocalBytes>
__global__ void __launch_bounds__(kThreads, POLY_GPU_CONTACT_MIN_BLOCKS)
    contact_kernel(DeviceShapes shapes, const int *__restrict__ list, int first, int count,
                   const int *__restrict__ pair_i, const int *__restrict__ pair_j,
                   const poly_gpu_particle *__restrict__ particles, const poly_gpu_motion *__restrict__ motion,
                   const poly_material_pair *__restrict__ materials, int num_types, poly_gpu_settings settings,
                   int *__restrict__ contact, double *__restrict__ history, const int *__restrict__ slot,
                   PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                   int *__restrict__ counters, char *__restrict__ scratch,
                   size_t bytes_per_thread)
{
  typedef Narrow<Precision> N;
  int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= count) return;
  int p = list[first + local];
  PairBodies pair;
  pair_bodies(p, pair_i, pair_j, particles, motion, pair);

  poly_overlap_result geometry;
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  {
    WorkspaceMemory<LocalBytes> memory;
    typename N::Workspace ws;
    N::layout(&ws, memory.get(scratch, local, bytes_per_thread), shapes.max_vertices, shapes.max_triangles);
    ws.want_second_moment = settings.rocking;
    typename N::View a = N::view(shapes, pair.body_i->shape), b = N::view(shapes, pair.body_j->shape);
    N::overlap(&a, &b, pair.rotation, pair.translation, &ws, local_centroid, local_normal, &geometry);
  }
  finish_pair(p, pair, geometry, local_centroid, local_normal, materials,
              num_types, settings, contact, history, slot, pair_force, results, counters);
}

#include "poly_gpu_clip_kernels.cuh"

// One warp per pair of `list` (poly_gpu_warp_impl.cuh), each warp with its
// block of limits.bytes of shared memory, or of `global_blocks` (the pair's
// own, at its place in `list`) for shapes too large for shared memory; pairs it
// cannot finish, and pairs of shapes beyond the limits, go to `handed_back`
// (counted in counters[2]) for contact_kernel.
template <int Precision>
__global__ void __launch_bounds__(kThreads)
    warp_contact_kernel(DeviceShapes shapes, const int *__restrict__ list, int count, const int *__restrict__ pair_i,
                        const int *__restrict__ pair_j, const poly_gpu_particle *__restrict__ particles,
                        const poly_gpu_motion *__restrict__ motion, const poly_material_pair *__restrict__ materials,
                        int num_types, poly_gpu_settings settings, int *__restrict__ contact,
                        double *__restrict__ history, const int *__restrict__ slot,
                        PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                        int *__restrict__ counters,
                        int *__restrict__ handed_back, WarpLimits limits, char *__restrict__ global_blocks)
{
  typedef Narrow<Precision> N;
  extern __shared__ double warp_blocks[];
  const int groups = blockDim.x / limits.lanes, group = threadIdx.x / limits.lanes;
  int local = blockIdx.x * groups + group;
  if (local >= count) return;  // the pair's whole group of lanes
  const poly_lanes lanes = poly_lanes_of(limits.lanes);
  typename N::WarpMemory memory;
  char *block = global_blocks ? global_blocks + (size_t)local * limits.bytes
                              : (char *)warp_blocks + (size_t)group * limits.bytes;
  N::warp_layout(&memory, block, limits.vertices, limits.triangles, limits.edges, limits.records);
  int p = list[local];
  PairBodies pair;
  pair_bodies(p, pair_i, pair_j, particles, motion, pair);
  poly_overlap_result geometry;
  double local_centroid[3] = {0, 0, 0}, local_normal[3] = {0, 0, 0};
  typename N::View a = N::view(shapes, pair.body_i->shape), b = N::view(shapes, pair.body_j->shape);
  // The pre-filter sent pairs beyond the limits elsewhere; kept as a guard of the shared block.
  int handed = beyond(shapes, pair.body_i->shape, pair.body_j->shape, limits);
  if (!handed)
    handed = N::warp_overlap(&a, &b, pair.rotation, pair.translation, settings.rocking, &memory, lanes, local_centroid,
                             local_normal, &geometry, NULL);
  if (lanes.lane != 0) return;
  if (handed) {
    handed_back[atomicAdd(counters + 2, 1)] = p;
    return;
  }
  finish_pair(p, pair, geometry, local_centroid, local_normal, materials,
              num_types, settings, contact, history, slot, pair_force, results, counters);
}

// Force and torque on each force particle: its pairs in a fixed order.
__global__ void reduce_kernel(int num_force_particles, const int *offsets, const int *entries, const int *slot,
                              const PairForce *pair_force, double *force_torque)
{
  int n = blockIdx.x * blockDim.x + threadIdx.x;
  if (n >= num_force_particles) return;
  double sum[6] = {0, 0, 0, 0, 0, 0};
  for (int e = offsets[n]; e < offsets[n + 1]; e++) {
    int entry = entries[e], place = slot[entry >> 1];
    if (place < 0) continue;  // dropped by the pre-filter: no force
    const PairForce &pf = pair_force[place];
    if (entry & 1)
      for (int k = 0; k < 3; k++) {
        sum[k] += pf.force_j[k];
        sum[3 + k] += pf.torque_j[k];
      }
    else
      for (int k = 0; k < 3; k++) {
        sum[k] -= pf.force_j[k];
        sum[3 + k] += pf.torque_i[k];
      }
  }
  for (int k = 0; k < 6; k++) force_torque[6 * n + k] = sum[k];
}

void free_shapes(DeviceShapes &s)
{
  cudaFree(s.offsets); cudaFree(s.counts); cudaFree(s.radius);
  cudaFree(s.vertices_d); cudaFree(s.normals_d); cudaFree(s.vertices_f); cudaFree(s.normals_f);
  cudaFree(s.triangles); cudaFree(s.edges); cudaFree(s.edge_triangles);
  cudaFree(s.clip); cudaFree(s.clip_planes); cudaFree(s.clip_loop_start); cudaFree(s.clip_loop);
  cudaFree(s.clip_triangle); cudaFree(s.clip_piece_front); cudaFree(s.clip_piece_back);
  cudaFree(s.clip_piece_point_start); cudaFree(s.clip_piece_points); cudaFree(s.clip_piece_face_start);
  cudaFree(s.clip_piece_faces); cudaFree(s.clip_vertices); cudaFree(s.clip_face_plane);
  cudaFree(s.clip_vertices_f); cudaFree(s.clip_planes_f);
  memset(&s, 0, sizeof s);
}

template <typename T> bool upload_raw(T **device, const std::vector<T> &host, char *message, size_t size)
{
  if (!check(cudaMalloc((void **)device, sizeof(T) * (host.empty() ? 1 : host.size())), "cudaMalloc", message, size))
    return false;
  if (host.empty()) return true;
  return check(cudaMemcpy(*device, &host[0], sizeof(T) * host.size(), cudaMemcpyHostToDevice), "cudaMemcpy", message,
               size);
}

template <int Precision>
bool large_by_warp(const poly_gpu_settings &settings, const int *list, int count, PairGeometry *device_results,
                   char *message, size_t size);

// contact_kernel over `count` pairs of `list`: in one launch with local-memory
// workspaces, else (`warp_first` false, or POLY_GPU_PAIR_KERNEL=thread) in
// batches of threads whose workspaces fit in a bounded scratch buffer. With
// `warp_first` such pairs take large_by_warp first.
template <int Precision>
bool thread_per_pair(const poly_gpu_settings &settings, const int *list, int count, PairGeometry *device_results,
                     char *message, size_t size, bool warp_first = true)
{
  typedef Narrow<Precision> N;
  const DeviceShapes &s = state.shapes;
  if (count == 0) return true;
  size_t workspace = N::layout(NULL, NULL, s.max_vertices, s.max_triangles);
  if (workspace > LocalWorkspace<Precision>::bytes && warp_first && state.options.pair_kernel != 1)
    return large_by_warp<Precision>(settings, list, count, device_results, message, size);
  if (workspace <= LocalWorkspace<Precision>::bytes) {
    contact_kernel<Precision, LocalWorkspace<Precision>::bytes><<<(count + kThreads - 1) / kThreads, kThreads>>>(
        s, list, 0, count, state.pair_i.data, state.pair_j.data, state.particles.data, state.motion.data,
        state.materials.data, state.num_types, settings, state.contact.data, state.history.data, state.slot.data,
        state.pair_force.data, device_results, state.counters.data, NULL, 0);
    return check(cudaGetLastError(), "contact kernel launch", message, size);
  }
  workspace = (workspace + 255) / 256 * 256;
  size_t batch = (size_t)1 << 18;
  const size_t budget = (size_t)1 << 30;
  while (batch > 256 && batch * workspace > budget) batch /= 2;
  if (!ensure(state.scratch, batch * workspace, message, size)) return false;
  for (size_t first = 0; first < (size_t)count; first += batch) {
    int chunk = (int)((size_t)count - first < batch ? (size_t)count - first : batch);
    contact_kernel<Precision, 0><<<(chunk + kThreads - 1) / kThreads, kThreads>>>(
        s, list, (int)first, chunk, state.pair_i.data, state.pair_j.data, state.particles.data, state.motion.data,
        state.materials.data, state.num_types, settings, state.contact.data, state.history.data, state.slot.data,
        state.pair_force.data, device_results, state.counters.data, state.scratch.data, workspace);
    if (!check(cudaGetLastError(), "contact kernel launch", message, size)) return false;
  }
  return true;
}

// The pairs without clip faces of shapes whose workspaces do not fit a thread's local memory (from about 16
// triangles: rock_70, icosphere_80, rock_1000; or small shapes beside them), a warp per pair as warp_contact_kernel
// does in shared memory, but each warp's block in the scratch buffer: a block per pair rather than an overlap
// workspace per thread, so that the bounded buffer holds enough pairs at once to fill the device (a rock_1000
// workspace of about 350 KB let 2048 threads run at a time, a fraction of one warp per SM), and the lanes share the
// pair's loops. What the warps hand back takes the one-thread kernel.
template <int Precision>
bool large_by_warp(const poly_gpu_settings &settings, const int *list, int count, PairGeometry *device_results,
                   char *message, size_t size)
{
  typedef Narrow<Precision> N;
  WarpLimits limits = largest_shape_limits(0, 0, 0);
  if (state.options.pair_lanes) limits.lanes = state.options.pair_lanes;
  const int groups = kThreads / limits.lanes;
  const size_t bytes =
      (N::warp_layout(NULL, NULL, limits.vertices, limits.triangles, limits.edges, limits.records) + 255) / 256 * 256;
  const size_t budget = (size_t)1 << 30;
  size_t batch = std::min((size_t)count, budget / bytes);
  if (batch == 0) return thread_per_pair<Precision>(settings, list, count, device_results, message, size, false);
  // Blocks for four times the pairs the device runs at once (its resident warps with 32 lanes a pair), at least
  // 4096 (fewer pairs a launch measured no faster from about that many down to 2000, and slower below): a deck of
  // 70-triangle rocks (29 KB a pair) then takes a few hundred MiB of the budget instead of all of it; rock_1000's
  // blocks fill the budget before that.
  int device = 0, sms = 0, blocks_per_sm = 0;
  if (!check(cudaGetDevice(&device), "cudaGetDevice", message, size) ||
      !check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), "cudaDeviceGetAttribute", message,
             size) ||
      !check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks_per_sm, warp_contact_kernel<Precision>, kThreads, 0),
             "cudaOccupancyMaxActiveBlocksPerMultiprocessor", message, size))
    return false;
  batch = std::min(batch, std::max((size_t)4096, (size_t)4 * sms * blocks_per_sm * groups));
  limits.bytes = (int)bytes;
  if (!ensure(state.scratch, batch * bytes, message, size) || !ensure(state.handed_large, count, message, size) ||
      !check(cudaMemset(state.counters.data + 2, 0, sizeof(int)), "cudaMemset", message, size))
    return false;
  for (size_t first = 0; first < (size_t)count; first += batch) {
    const int chunk = (int)std::min(batch, (size_t)count - first);
    warp_contact_kernel<Precision><<<(chunk + groups - 1) / groups, kThreads>>>(
        state.shapes, list + first, chunk, state.pair_i.data, state.pair_j.data, state.particles.data,
        state.motion.data, state.materials.data, state.num_types, settings, state.contact.data, state.history.data,
        state.slot.data, state.pair_force.data, device_results, state.counters.data, state.handed_large.data, limits,
        state.scratch.data);
    if (!check(cudaGetLastError(), "large pairs' warp kernel launch", message, size)) return false;
  }
  int num_handed = 0;
  if (!check(cudaMemcpy(&num_handed, state.counters.data + 2, sizeof(int), cudaMemcpyDeviceToHost),
             "large pairs' warp kernel", message, size) ||
      !check(cudaMemset(state.counters.data + 2, 0, sizeof(int)), "cudaMemset", message, size))
    return false;
  state.timing.handed_back += num_handed;
  return thread_per_pair<Precision>(settings, state.handed_large.data, num_handed, device_results, message, size,
                                    false);
}

// The warp kernels' limits (WarpLimits) for the shapes of poly_gpu_init, each count at least the minimum given.
template <int Precision> WarpLimits warp_limits_of(int min_vertices, int min_triangles, int min_edges)
{
  typedef Narrow<Precision> N;
  WarpLimits w = {0, 0, 0, 0, 0, 32};
  for (size_t n = 0; n + 2 < state.host_counts.size(); n += 3) {
    int nv = state.host_counts[n], nt = state.host_counts[n + 1], ne = state.host_counts[n + 2];
    nv = nv > min_vertices ? nv : min_vertices;
    nt = nt > min_triangles ? nt : min_triangles;
    ne = ne > min_edges ? ne : min_edges;
    if (N::warp_layout(NULL, NULL, nv, nt, ne, 4 * nt + 64) > kWarpBytesLimit) continue;
    w.vertices = nv > w.vertices ? nv : w.vertices;
    w.triangles = nt > w.triangles ? nt : w.triangles;
    w.edges = ne > w.edges ? ne : w.edges;
  }
  if (w.triangles == 0) return w;
  // A pair of small shapes leaves most of a warp's lanes idle: 8 lanes a pair up to 16 triangles (measured faster
  // than 32 for every such reference shape, 32 faster from 40 triangles; doc/benchmarks.md).
  w.lanes = state.options.pair_lanes ? state.options.pair_lanes : (w.triangles <= 16 ? 8 : 32);
  w.records = 4 * w.triangles + 64;
  size_t bytes = N::warp_layout(NULL, NULL, w.vertices, w.triangles, w.edges, w.records);
  w.bytes = bytes <= kWarpBytesLimit ? (int)bytes : 0;
  return w;
}

// The shared-memory warp kernel takes the pairs only when POLY_GPU_PAIR_KERNEL=warp forces it (tests,
// benchmarks). By default, pairs whose one-thread workspaces fit local memory take the one-thread kernel (the
// faster one for them, doc/gpu.md "Contact kernels"), and the others a warp each with its block in global memory
// (large_by_warp): on one H200 that kept more warps on an SM than the shared blocks did (rock_70 1.1-1.25x), and
// with no shared blocks the clipping kernels take every pair with clip faces (doc/benchmarks.md).
bool use_warp_kernel()
{
  return state.options.pair_kernel == 2;
}

// Pre-filter, then overlap and contact law for the pairs that passed: the
// clipping kernels for pairs with clip faces, the one-thread kernel or
// large_by_warp for the rest and for what they hand back (thread_per_pair); with
// POLY_GPU_PAIR_KERNEL=warp the shared-memory warp kernel, then the one-thread
// kernel for what it hands back.
template <int Precision>
bool narrow_phase(const poly_gpu_settings &settings, bool want_results, char *message, size_t size)
{
  const DeviceShapes &s = state.shapes;
  const int num_pairs = state.num_pairs;
  state.num_kept = 0;
  if (num_pairs == 0) return true;
  WarpLimits limits = {0, 0, 0, 0, 0, 32};
  if (use_warp_kernel()) limits = warp_limits_of<Precision>(0, 0, 0);
  if (limits.bytes > 0 && !ensure(state.large, num_pairs, message, size)) return false;
  bounding_kernel<Precision><<<(num_pairs + kThreads - 1) / kThreads, kThreads>>>(
      s, num_pairs, state.pair_i.data, state.pair_j.data, state.particles.data, state.motion.data,
      state.contact.data, state.history.data, state.slot.data, state.touching.data, state.large.data, limits,
      settings.parting_search, state.counters.data);
  int counts[5] = {0, 0, 0, 0, 0};
  if (!check(cudaGetLastError(), "bounding kernel launch", message, size) ||
      !check(cudaMemcpy(counts, state.counters.data, sizeof counts, cudaMemcpyDeviceToHost), "bounding kernel",
             message, size))
    return false;
  const int num_touching = counts[0], num_large = counts[3];
  // The per-pair arrays for the kept pairs only.
  state.num_kept = counts[4];
  state.timing.kept += counts[4];
  PairGeometry *device_results = NULL;
  if (!ensure(state.pair_force, state.num_kept, message, size)) return false;
  if (want_results) {
    if (!ensure(state.results, state.num_kept, message, size) ||
        !check(cudaMemset(state.results.data, 0, sizeof(PairGeometry) * (state.num_kept > 0 ? state.num_kept : 1)),
               "cudaMemset", message, size))
      return false;
    device_results = state.results.data;
  }
  if (Precision != POLY_PRECISION_SINGLE && state.any_clip && num_touching > 0 && !state.options.pair_kernel) {
    // Pairs of shapes with clip faces take the clipping path (in double, in mixed precision too as on the host;
    // POLY_GPU_MIXED_CLIP=single: the warp kernel's faces in single); the rest, and what it hands back,
    // thread_per_pair.
    if (!ensure(state.handed_back, num_touching, message, size)) return false;
    // Pairs of convex shapes run faster one per thread (their few faces leave most of a warp idle); shapes of
    // several pieces one per warp (doc/benchmarks.md, "Clipping kernels").
    const bool by_warp = state.options.clip_kernel ? state.options.clip_kernel == 2 : state.any_pieces;
    if (!by_warp)
      (state.any_pieces ? clip_contact_kernel<true> : clip_contact_kernel<false>)
          <<<(num_touching + kThreads - 1) / kThreads, kThreads>>>(
              s, state.touching.data, num_touching, state.pair_i.data, state.pair_j.data, state.particles.data,
              state.motion.data, state.materials.data, state.num_types, settings, state.contact.data,
              state.history.data, state.slot.data, state.pair_force.data, device_results, state.counters.data,
              state.handed_back.data);
    else {
      // In mixed precision the faces are clipped in double unless POLY_GPU_MIXED_CLIP=single: clipped in single
      // they ran 1.14x faster but injected energy into a packed bed (doc/benchmarks.md).
      const bool single = Precision == POLY_PRECISION_MIXED && state.options.mixed_clip == 1;
      const ClipWarpLimits &limits = single ? state.clip_limits_single : state.clip_limits;
      state.clip_limits_used = limits;
      (single ? clip_warp_kernel<float> : clip_warp_kernel<double>)
          <<<(num_touching + POLY_CLIP_WARPS * limits.pairs - 1) / (POLY_CLIP_WARPS * limits.pairs),
             32 * POLY_CLIP_WARPS, POLY_CLIP_WARPS * limits.bytes>>>(
              s, state.touching.data, num_touching, state.pair_i.data, state.pair_j.data, state.particles.data,
              state.motion.data, state.materials.data, state.num_types, settings, state.contact.data,
              state.history.data, state.slot.data, state.pair_force.data, device_results, state.counters.data,
              state.handed_back.data, limits);
    }
    int num_handed = 0;
    if (!check(cudaGetLastError(), "clip kernel launch", message, size) ||
        !check(cudaMemcpy(&num_handed, state.counters.data + 2, sizeof(int), cudaMemcpyDeviceToHost), "clip kernel",
               message, size))
      return false;
    state.timing.handed_back += num_handed;
    return thread_per_pair<Precision>(settings, state.handed_back.data, num_handed, device_results, message, size);
  }
  if (limits.bytes == 0)
    return thread_per_pair<Precision>(settings, state.touching.data, num_touching, device_results, message, size);
  if (!thread_per_pair<Precision>(settings, state.large.data, num_large, device_results, message, size))
    return false;
  if (num_touching == 0) return true;
  WarpLaunch grid;
  if (!warp_launch(warp_contact_kernel<Precision>, limits, &grid, message, size) ||
      !ensure(state.handed_back, num_touching, message, size))
    return false;
  warp_contact_kernel<Precision><<<(num_touching + grid.groups - 1) / grid.groups, grid.threads, grid.shared>>>(
      s, state.touching.data, num_touching, state.pair_i.data, state.pair_j.data, state.particles.data,
      state.motion.data, state.materials.data, state.num_types, settings, state.contact.data, state.history.data,
      state.slot.data, state.pair_force.data, device_results, state.counters.data, state.handed_back.data, limits,
      NULL);
  int num_handed = 0;
  if (!check(cudaGetLastError(), "warp kernel launch", message, size) ||
      !check(cudaMemcpy(&num_handed, state.counters.data + 2, sizeof(int), cudaMemcpyDeviceToHost), "warp kernel",
             message, size))
    return false;
  state.timing.handed_back += num_handed;
  return thread_per_pair<Precision>(settings, state.handed_back.data, num_handed, device_results, message, size,
                                   false);
}

}  // namespace

const DeviceShapes *poly_gpu_detail::device_shapes()
{
  return state.ready ? &state.shapes : NULL;
}

WarpLimits poly_gpu_detail::largest_shape_limits(int min_vertices, int min_triangles, int min_edges)
{
  WarpLimits limits = {std::max(state.shapes.max_vertices, min_vertices),
                       std::max(state.shapes.max_triangles, min_triangles), min_edges, 0, 0, 32};
  for (size_t n = 2; n < state.host_counts.size(); n += 3) limits.edges = std::max(limits.edges, state.host_counts[n]);
  limits.records = 4 * limits.triangles + 64;
  return limits;
}

WarpLimits poly_gpu_detail::warp_limits(int precision, int min_vertices, int min_triangles, int min_edges)
{
  return precision == POLY_PRECISION_DOUBLE ? warp_limits_of<POLY_PRECISION_DOUBLE>(min_vertices, min_triangles,
                                                                                    min_edges)
         : precision == POLY_PRECISION_MIXED ? warp_limits_of<POLY_PRECISION_MIXED>(min_vertices, min_triangles,
                                                                                   min_edges)
                                             : warp_limits_of<POLY_PRECISION_SINGLE>(min_vertices, min_triangles,
                                                                                    min_edges);
}

int poly_gpu_detail::wall_kernel_choice()
{
  return state.options.wall_kernel;
}

extern "C" int poly_gpu_device_count(void)
{
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

// Where the host's code is cheaper than a GPU call (doc/gpu.md, "Small decks"): a rank's neighbour list whose
// pairs, those in contact counting 32, number fewer than this runs on the host until the next rebuild...
#ifndef POLY_GPU_DEFAULT_MIN_PAIRS
#define POLY_GPU_DEFAULT_MIN_PAIRS 500
#endif
// ...and so do a step's mesh-wall pieces when fewer than this.
#ifndef POLY_GPU_DEFAULT_MIN_PIECES
#define POLY_GPU_DEFAULT_MIN_PIECES 32
#endif

static int read_choice(const char *name, const char *const *words, const int *values, int count, const char *expected,
                       int *out, char *message, size_t message_size)
{
  const char *text = getenv(name);
  *out = 0;
  if (!text || !*text) return 0;
  for (int n = 0; n < count; n++)
    if (strcmp(text, words[n]) == 0) {
      *out = values[n];
      return 0;
    }
  snprintf(message, message_size, "environment variable %s=%s: expected %s", name, text, expected);
  return -1;
}

static int read_count(const char *name, long fallback, long *out, char *message, size_t message_size)
{
  const char *text = getenv(name);
  *out = fallback;
  if (!text || !*text) return 0;
  char *end = NULL;
  long value = strtol(text, &end, 10);
  if (*end != '\0' || value < 0) {
    snprintf(message, message_size, "environment variable %s=%s: expected a whole number, 0 or more", name, text);
    return -1;
  }
  *out = value;
  return 0;
}

extern "C" int poly_gpu_environment(poly_gpu_options *options, char *message, size_t message_size)
{
  const char *kernels[2] = {"thread", "warp"}, *lanes[3] = {"8", "16", "32"};
  const char *clip_precisions[2] = {"single", "double"}, *carveouts[2] = {"tight", "driver"};
  const int kernel_values[2] = {1, 2}, lane_values[3] = {8, 16, 32};
  if (read_choice("POLY_GPU_PAIR_KERNEL", kernels, kernel_values, 2, "thread or warp", &options->pair_kernel, message,
                  message_size) ||
      read_choice("POLY_GPU_PAIR_LANES", lanes, lane_values, 3, "8, 16 or 32", &options->pair_lanes, message,
                  message_size) ||
      read_choice("POLY_GPU_WALL_KERNEL", kernels, kernel_values, 2, "thread or warp", &options->wall_kernel, message,
                  message_size) ||
      read_choice("POLY_GPU_CLIP_KERNEL", kernels, kernel_values, 2, "thread or warp", &options->clip_kernel, message,
                  message_size) ||
      read_choice("POLY_GPU_MIXED_CLIP", clip_precisions, kernel_values, 2, "single or double", &options->mixed_clip,
                  message, message_size) ||
      read_choice("POLY_GPU_CARVEOUT", carveouts, kernel_values, 2, "tight or driver", &options->carveout, message,
                  message_size) ||
      read_count("POLY_GPU_MIN_PAIRS", POLY_GPU_DEFAULT_MIN_PAIRS, &options->min_pairs, message, message_size) ||
      read_count("POLY_GPU_MIN_PIECES", POLY_GPU_DEFAULT_MIN_PIECES, &options->min_pieces, message, message_size))
    return -1;
  return 0;
}

// The shapes' faces and convex pieces for the clipping path (poly_clip.h), and per shape a poly_clip_faces of
// device pointers into them and into the uploaded vertices; shapes without clip faces get num_faces 0.
static bool upload_clip_faces(int num_shapes, const poly_shape *const *shapes, char *message, size_t message_size)
{
  DeviceShapes &s = state.shapes;
  std::vector<double> planes, clip_vertices;
  std::vector<int> loop_start, loop, triangle, point_start, points, face_start, faces, first_vertex, face_plane;
  std::vector<poly_clip_words> front, back;
  std::vector<int> first_plane, first_face, first_start, first_corner, first_piece, first_point_start, first_face_start,
      first_point, first_piece_face;
  state.any_clip = state.any_pieces = false;
  ClipWarpLimits limits = {0, 0, 0, 1, 0, 0};
  for (int i = 0; i < num_shapes; i++) {
    const poly_shape *shape = shapes[i];
    first_plane.push_back((int)planes.size() / 4);
    first_face.push_back((int)triangle.size());
    first_start.push_back((int)loop_start.size());
    first_corner.push_back((int)loop.size());
    first_piece.push_back((int)front.size());
    first_point_start.push_back((int)point_start.size());
    first_face_start.push_back((int)face_start.size());
    first_point.push_back((int)points.size());
    first_piece_face.push_back((int)faces.size());
    first_vertex.push_back((int)clip_vertices.size() / 3);
    if (shape->num_clip_faces == 0) continue;
    state.any_clip = true;
    const int np = shape->num_clip_pieces;
    if (np > 1) state.any_pieces = true;
    const int nv = poly_shape_num_clip_points(shape);
    const double *x = poly_shape_clip_points(shape);
    clip_vertices.insert(clip_vertices.end(), x, x + 3 * nv);
    limits.vertices = std::max(limits.vertices, nv);
    limits.planes = std::max(limits.planes, shape->num_clip_planes);
    limits.pieces = std::max(limits.pieces, np);
    planes.insert(planes.end(), shape->clip_planes, shape->clip_planes + 4 * shape->num_clip_planes);
    loop_start.insert(loop_start.end(), shape->clip_loop_start, shape->clip_loop_start + shape->num_clip_faces + 1);
    loop.insert(loop.end(), shape->clip_loop, shape->clip_loop + shape->clip_loop_start[shape->num_clip_faces]);
    triangle.insert(triangle.end(), shape->clip_face_triangle, shape->clip_face_triangle + shape->num_clip_faces);
    for (int f = 0; f < shape->num_clip_faces; f++) face_plane.push_back(shape->clip_face_plane ? shape->clip_face_plane[f] : -1);
    front.insert(front.end(), shape->clip_piece_front, shape->clip_piece_front + np);
    back.insert(back.end(), shape->clip_piece_back, shape->clip_piece_back + np);
    point_start.insert(point_start.end(), shape->clip_piece_point_start, shape->clip_piece_point_start + np + 1);
    points.insert(points.end(), shape->clip_piece_points, shape->clip_piece_points + shape->clip_piece_point_start[np]);
    face_start.insert(face_start.end(), shape->clip_piece_face_start, shape->clip_piece_face_start + np + 1);
    faces.insert(faces.end(), shape->clip_piece_faces, shape->clip_piece_faces + shape->clip_piece_face_start[np]);
  }
  if (!upload_raw(&s.clip_planes, planes, message, message_size) ||
      !upload_raw(&s.clip_loop_start, loop_start, message, message_size) ||
      !upload_raw(&s.clip_loop, loop, message, message_size) ||
      !upload_raw(&s.clip_triangle, triangle, message, message_size) ||
      !upload_raw(&s.clip_piece_front, front, message, message_size) ||
      !upload_raw(&s.clip_piece_back, back, message, message_size) ||
      !upload_raw(&s.clip_piece_point_start, point_start, message, message_size) ||
      !upload_raw(&s.clip_piece_points, points, message, message_size) ||
      !upload_raw(&s.clip_piece_face_start, face_start, message, message_size) ||
      !upload_raw(&s.clip_piece_faces, faces, message, message_size) ||
      !upload_raw(&s.clip_vertices, clip_vertices, message, message_size) ||
      !upload_raw(&s.clip_face_plane, face_plane, message, message_size) ||
      !upload_raw(&s.clip_vertices_f, std::vector<float>(clip_vertices.begin(), clip_vertices.end()), message,
                  message_size) ||
      !upload_raw(&s.clip_planes_f, std::vector<float>(planes.begin(), planes.end()), message, message_size))
    return false;
  int device = 0, shared_per_sm = 0, reserved_per_block = 0;
  if (!check(cudaGetDevice(&device), "cudaGetDevice", message, message_size) ||
      !check(cudaDeviceGetAttribute(&shared_per_sm, cudaDevAttrMaxSharedMemoryPerMultiprocessor, device),
             "cudaDeviceGetAttribute", message, message_size) ||
      !check(cudaDeviceGetAttribute(&reserved_per_block, cudaDevAttrReservedSharedMemoryPerBlock, device),
             "cudaDeviceGetAttribute", message, message_size))
    return false;
  ClipWarpLimits single = limits;
  single.single = 1;
  clip_warp_pairs(&limits, (size_t)shared_per_sm, (size_t)reserved_per_block);
  clip_warp_pairs(&single, (size_t)shared_per_sm, (size_t)reserved_per_block);
  state.clip_limits = limits;
  state.clip_limits_single = single;
  const ClipWarpLimits none = {0, 0, 0, 0, 0, 0};
  state.clip_limits_used = none;
  if (state.any_pieces &&
      (!check(cudaFuncSetAttribute(clip_warp_kernel<double>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                   (int)(POLY_CLIP_WARPS * limits.bytes)), "cudaFuncSetAttribute", message,
              message_size) ||
       !check(cudaFuncSetAttribute(clip_warp_kernel<float>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                   (int)(POLY_CLIP_WARPS * single.bytes)), "cudaFuncSetAttribute", message,
              message_size)))
    return false;
  if (state.any_pieces && state.options.carveout != 2 &&  // POLY_GPU_CARVEOUT=driver: the driver's choice
      (!clip_warp_carveout(clip_warp_kernel<double>, 32 * POLY_CLIP_WARPS, POLY_CLIP_WARPS * limits.bytes,
                           (size_t)shared_per_sm, (size_t)reserved_per_block, message, message_size) ||
       !clip_warp_carveout(clip_warp_kernel<float>, 32 * POLY_CLIP_WARPS, POLY_CLIP_WARPS * single.bytes,
                           (size_t)shared_per_sm, (size_t)reserved_per_block, message, message_size)))
    return false;
  std::vector<poly_clip_faces> clip(num_shapes);
  for (int i = 0; i < num_shapes; i++) {
    poly_clip_faces &f = clip[i];
    memset(&f, 0, sizeof f);
    f.num_faces = shapes[i]->num_clip_faces;
    f.num_vertices = poly_shape_num_clip_points(shapes[i]);
    f.num_planes = shapes[i]->num_clip_planes;
    f.num_pieces = shapes[i]->num_clip_pieces;
    f.vertices = s.clip_vertices + 3 * first_vertex[i];
    f.face_plane = shapes[i]->clip_face_plane ? s.clip_face_plane + first_face[i] : NULL;
    f.planes = s.clip_planes + 4 * first_plane[i];
    f.loop_start = s.clip_loop_start + first_start[i];
    f.loop = s.clip_loop + first_corner[i];
    f.triangle = s.clip_triangle + first_face[i];
    f.piece_front = s.clip_piece_front + first_piece[i];
    f.piece_back = s.clip_piece_back + first_piece[i];
    f.piece_point_start = s.clip_piece_point_start + first_point_start[i];
    f.piece_points = s.clip_piece_points + first_point[i];
    f.piece_face_start = s.clip_piece_face_start + first_face_start[i];
    f.piece_faces = s.clip_piece_faces + first_piece_face[i];
  }
  return upload_raw(&s.clip, clip, message, message_size);
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

  // Flatten the shapes; vertex indices stay shape-local.
  DeviceShapes &s = state.shapes;
  s.count = num_shapes;
  s.max_vertices = s.max_triangles = 1;
  if (poly_gpu_environment(&state.options, message, message_size) != 0) return -1;
  std::vector<int> offsets, counts, triangles, edges, edge_triangles;
  std::vector<double> radius, vertices_d, normals_d;
  std::vector<float> vertices_f, normals_f;
  int v = 0, t = 0, e = 0;
  for (int i = 0; i < num_shapes; i++) {
    const poly_shape *shape = shapes[i];
    if (shape->num_vertices > s.max_vertices) s.max_vertices = shape->num_vertices;
    if (shape->num_triangles > s.max_triangles) s.max_triangles = shape->num_triangles;
    state.host_counts.push_back(shape->num_vertices);
    state.host_counts.push_back(shape->num_triangles);
    state.host_counts.push_back(shape->num_edges);
    offsets.push_back(v); offsets.push_back(t); offsets.push_back(e);
    counts.push_back(shape->num_vertices); counts.push_back(shape->num_triangles); counts.push_back(shape->num_edges);
    radius.push_back(shape->bounding_radius);
    for (int k = 0; k < 3 * shape->num_vertices; k++) {
      vertices_d.push_back(shape->vertices[k]);
      vertices_f.push_back((float)shape->vertices[k]);
    }
    for (int k = 0; k < 3 * shape->num_triangles; k++) {
      normals_d.push_back(shape->face_normals[k]);
      normals_f.push_back((float)shape->face_normals[k]);
      triangles.push_back(shape->triangles[k]);
    }
    for (int k = 0; k < 2 * shape->num_edges; k++) {
      edges.push_back(shape->edges[k]);
      edge_triangles.push_back(shape->edge_triangles[k]);
    }
    v += shape->num_vertices; t += shape->num_triangles; e += shape->num_edges;
  }
  bool ok = upload_raw(&s.offsets, offsets, message, message_size) &&
            upload_raw(&s.counts, counts, message, message_size) &&
            upload_raw(&s.radius, radius, message, message_size) &&
            upload_raw(&s.vertices_d, vertices_d, message, message_size) &&
            upload_raw(&s.normals_d, normals_d, message, message_size) &&
            upload_raw(&s.vertices_f, vertices_f, message, message_size) &&
            upload_raw(&s.normals_f, normals_f, message, message_size) &&
            upload_raw(&s.triangles, triangles, message, message_size) &&
            upload_raw(&s.edges, edges, message, message_size) &&
            upload_raw(&s.edge_triangles, edge_triangles, message, message_size) &&
            ensure(state.counters, 7, message, message_size) &&
            upload_clip_faces(num_shapes, shapes, message, message_size);
  if (!ok) return -1;
  state.ready = true;
  return 0;
}

extern "C" int poly_gpu_set_pairs(int num_particles, int num_force_particles, const poly_gpu_particle *particles,
                                  int num_pairs, const int *pair_i, const int *pair_j, const double *history,
                                  int num_types, const poly_material_pair *materials, char *message,
                                  size_t message_size)
{
  if (!state.ready) {
    snprintf(message, message_size, "poly_gpu_set_pairs before poly_gpu_init");
    return -1;
  }
  double start = now();
  // Each force particle's pairs, in pair order: counting sort.
  std::vector<int> offsets(num_force_particles + 1, 0), entries;
  for (int p = 0; p < num_pairs; p++) {
    if (pair_i[p] >= num_force_particles) {
      snprintf(message, message_size, "pair %d: first particle %d is not a force particle", p, pair_i[p]);
      return -1;
    }
    offsets[pair_i[p] + 1]++;
    if (pair_j[p] < num_force_particles) offsets[pair_j[p] + 1]++;
  }
  for (int n = 0; n < num_force_particles; n++) offsets[n + 1] += offsets[n];
  entries.resize(offsets[num_force_particles] > 0 ? offsets[num_force_particles] : 1);
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (int p = 0; p < num_pairs; p++) {
    entries[fill[pair_i[p]]++] = 2 * p;
    if (pair_j[p] < num_force_particles) entries[fill[pair_j[p]]++] = 2 * p + 1;
  }
  size_t num_materials = (size_t)(num_types + 1) * (num_types + 1);
  state.num_particles = num_particles;
  state.num_force_particles = num_force_particles;
  state.num_pairs = num_pairs;
  state.num_types = num_types;
  bool ok = upload(state.particles, particles, num_particles, message, message_size) &&
            upload(state.pair_i, pair_i, num_pairs, message, message_size) &&
            upload(state.pair_j, pair_j, num_pairs, message, message_size) &&
            upload(state.history, history, (size_t)POLY_HISTORY_SIZE * num_pairs, message, message_size) &&
            upload(state.csr_offsets, &offsets[0], offsets.size(), message, message_size) &&
            upload(state.csr_entries, &entries[0], entries.size(), message, message_size) &&
            upload(state.materials, materials, num_materials, message, message_size) &&
            ensure(state.contact, num_pairs, message, message_size) &&
            ensure(state.touching, num_pairs, message, message_size) &&
            ensure(state.slot, num_pairs, message, message_size) &&
            ensure(state.motion, num_particles, message, message_size) &&
            ensure(state.force_torque, 6 * (size_t)num_force_particles, message, message_size) &&
            ensure(state.host_motion, num_particles, message, message_size) &&
            ensure(state.host_force_torque, 6 * (size_t)num_force_particles, message, message_size);
  if (!ok) return -1;
  if (num_pairs > 0 && !check(cudaMemset(state.contact.data, 0, sizeof(int) * num_pairs), "cudaMemset", message,
                              message_size))
    return -1;
  state.timing.set_pairs += now() - start;
  state.timing.num_set_pairs++;
  return 0;
}

extern "C" poly_gpu_motion *poly_gpu_motion_buffer(void)
{
  return state.host_motion.data;
}

extern "C" const double *poly_gpu_force_torque(void)
{
  return state.host_force_torque.data;
}

extern "C" int poly_gpu_compute(const poly_gpu_settings *settings, poly_gpu_result *results, int *num_contacts,
                                char *message, size_t message_size)
{
  if (!state.ready || !state.host_motion.data) {
    snprintf(message, message_size, "poly_gpu_compute before poly_gpu_init and poly_gpu_set_pairs");
    return -1;
  }
  const int num_pairs = state.num_pairs;
  double start = now();
  if (!check(cudaMemcpy(state.motion.data, state.host_motion.data, sizeof(poly_gpu_motion) * state.num_particles,
                        cudaMemcpyHostToDevice), "upload motion", message, message_size) ||
      !check(cudaMemset(state.counters.data, 0, 7 * sizeof(int)), "cudaMemset", message, message_size))
    return -1;
  double uploaded = now();

  const int threads = kThreads;
  int counters[7] = {0, 0, 0, 0, 0, 0, 0};
  const bool want_results = results != NULL;
  bool ok = settings->precision == POLY_PRECISION_DOUBLE
                ? narrow_phase<POLY_PRECISION_DOUBLE>(*settings, want_results, message, message_size)
            : settings->precision == POLY_PRECISION_MIXED
                ? narrow_phase<POLY_PRECISION_MIXED>(*settings, want_results, message, message_size)
                : narrow_phase<POLY_PRECISION_SINGLE>(*settings, want_results, message, message_size);
  if (!ok) return -1;
  if (!results && state.num_force_particles > 0) {
    reduce_kernel<<<(state.num_force_particles + threads - 1) / threads, threads>>>(
        state.num_force_particles, state.csr_offsets.data, state.csr_entries.data, state.slot.data,
        state.pair_force.data,
        state.force_torque.data);
    if (!check(cudaGetLastError(), "reduction kernel launch", message, message_size)) return -1;
  }
  if (!check(cudaDeviceSynchronize(), "contact kernel", message, message_size)) return -1;
  double computed = now();
  if (!check(cudaMemcpy(counters, state.counters.data, 7 * sizeof(int), cudaMemcpyDeviceToHost), "download counters",
             message, message_size))
    return -1;
  state.timing.centroid_outside += counters[5];
  state.timing.spots_facing_apart += counters[6];
  if (results) {
    // The kept pairs' results and forces, each to its pair's place; the others have no contact.
    const int kept = state.num_kept;
    if (!ensure(state.host_results, kept > 0 ? kept : 1, message, message_size) ||
        !ensure(state.host_pair_force, kept > 0 ? kept : 1, message, message_size) ||
        (kept > 0 && !check(cudaMemcpy(state.host_results.data, state.results.data, sizeof(PairGeometry) * kept,
                                       cudaMemcpyDeviceToHost), "download results", message, message_size)) ||
        (kept > 0 && !check(cudaMemcpy(state.host_pair_force.data, state.pair_force.data, sizeof(PairForce) * kept,
                                       cudaMemcpyDeviceToHost), "download pair forces", message, message_size)))
      return -1;
    memset(results, 0, sizeof(poly_gpu_result) * (num_pairs > 0 ? num_pairs : 1));
    for (int k = 0; k < kept; k++) {
      const PairGeometry &g = state.host_results.data[k];
      const PairForce &f = state.host_pair_force.data[k];
      if (!g.contact) continue;
      poly_gpu_result &r = results[g.pair];
      r.contact = 1;
      r.pair = g.pair;
      r.volume = g.volume;
      r.depth = g.depth;
      r.normal_force = g.normal_force;
      for (int d = 0; d < 3; d++) {
        r.force_j[d] = f.force_j[d];
        r.torque_i[d] = f.torque_i[d];
        r.torque_j[d] = f.torque_j[d];
        r.normal[d] = g.normal[d];
        r.centroid[d] = g.centroid[d];
        r.tangential_force[d] = g.tangential_force[d];
      }
    }
  } else if (state.num_force_particles > 0 &&
             !check(cudaMemcpy(state.host_force_torque.data, state.force_torque.data,
                               6 * sizeof(double) * state.num_force_particles, cudaMemcpyDeviceToHost),
                    "download forces", message, message_size)) {
    return -1;
  }
  if (num_contacts) *num_contacts = counters[1];
  double done = now();
  state.timing.upload += uploaded - start;
  state.timing.kernels += computed - uploaded;
  state.timing.download += done - computed;
  state.timing.num_compute++;
  state.timing.pairs += num_pairs;
  return 0;
}

extern "C" int poly_gpu_get_history(double *history, int *contact, char *message, size_t message_size)
{
  if (state.num_pairs == 0) return 0;
  if (!check(cudaMemcpy(history, state.history.data, sizeof(double) * POLY_HISTORY_SIZE * state.num_pairs,
                        cudaMemcpyDeviceToHost), "download history", message, message_size) ||
      !check(cudaMemcpy(contact, state.contact.data, sizeof(int) * state.num_pairs, cudaMemcpyDeviceToHost),
             "download contact flags", message, message_size))
    return -1;
  return 0;
}

extern "C" poly_gpu_timing poly_gpu_timings(void)
{
  poly_gpu_timing timing = state.timing;
  wall_timing(&timing);
  const ClipWarpLimits &limits = state.clip_limits_used.bytes ? state.clip_limits_used : state.clip_limits;
  timing.clip_warp_pairs = limits.pairs;
  timing.clip_warp_bytes = (long)limits.bytes;
  return timing;
}

extern "C" size_t poly_gpu_bytes(void)
{
  // Shapes are small; the per-particle and per-pair arrays and the workspaces dominate.
  return bytes_of(state.particles) + bytes_of(state.motion) + bytes_of(state.pair_i) + bytes_of(state.pair_j) +
         bytes_of(state.history) + bytes_of(state.contact) + bytes_of(state.touching) + bytes_of(state.counters) +
         bytes_of(state.handed_back) + bytes_of(state.large) + bytes_of(state.handed_large) +
         bytes_of(state.slot) + bytes_of(state.pair_force) + bytes_of(state.results) + bytes_of(state.csr_offsets) +
         bytes_of(state.csr_entries) + bytes_of(state.force_torque) + bytes_of(state.materials) +
         bytes_of(state.scratch) + wall_bytes();
}

extern "C" void poly_gpu_clear(void)
{
  if (state.ready) free_shapes(state.shapes);
  release(state.particles); release(state.motion); release(state.pair_i); release(state.pair_j);
  release(state.history); release(state.contact); release(state.touching); release(state.counters);
  release(state.handed_back); release(state.large); release(state.handed_large);
  release(state.slot); release(state.pair_force); release(state.results); release(state.host_results);
  release(state.host_pair_force);
  release(state.csr_offsets); release(state.csr_entries);
  release(state.force_torque); release(state.materials); release(state.scratch);
  release(state.host_motion); release(state.host_force_torque);
  wall_clear();
  // A new run re-initialises: the timing summary covers the whole session.
  poly_gpu_timing timing = state.timing;
  state = State();
  state.timing = timing;
}
