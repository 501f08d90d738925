/* The clipping path's two contact kernels (src/poly_clip.h; doc/gpu.md, "Contact kernels"): one thread per pair
 * for convex shapes, one warp per pair (poly_gpu_clip_warp.cuh) when some shape has convex pieces. Included by
 * poly_gpu.cu after PairBodies and finish_pair, in its namespace; apart only to keep that file's length. */
#ifndef POLY_GPU_CLIP_KERNELS_CUH
#define POLY_GPU_CLIP_KERNELS_CUH

// finish_pair for a result of the clipping path.
__device__ __forceinline__ void finish_clip_pair(int p, const PairBodies &pair, const poly_clip_result &clip,
                                                 const poly_material_pair *__restrict__ materials, int num_types,
                                                 const poly_gpu_settings &settings, int *__restrict__ contact,
                                                 double *__restrict__ history, const int *__restrict__ slot,
                                                 PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                                                 int *__restrict__ counters)
{
  poly_overlap_result geometry;
  geometry.volume = clip.volume;
  geometry.depth = clip.depth;
  geometry.area = clip.area;
  geometry.projected_area = clip.projected_area;
  for (int e = 0; e < 6; e++) geometry.second_moment[e] = clip.second_moment[e];
  finish_pair(p, pair, geometry, clip.centroid, clip.normal, materials,
              num_types, settings, contact, history, slot, pair_force, results, counters);
}

// One thread per pair of `list` whose shapes both have clip faces, in double: the clipping path (poly_clip.h), the
// host's own for such pairs, with a stack of a few KiB instead of the reference path's workspace. Pairs it
// does not take (another shape, flush faces, more corners than its buffer) go to `handed_back` (counters[2])
// for contact_kernel.
template <bool Pieces>
__global__ void __launch_bounds__(kThreads)
    clip_contact_kernel(DeviceShapes shapes, const int *__restrict__ list, int count, const int *__restrict__ pair_i,
                        const int *__restrict__ pair_j, const poly_gpu_particle *__restrict__ particles,
                        const poly_gpu_motion *__restrict__ motion, const poly_material_pair *__restrict__ materials,
                        int num_types, poly_gpu_settings settings, int *__restrict__ contact,
                        double *__restrict__ history, const int *__restrict__ slot,
                        PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                        int *__restrict__ counters, int *__restrict__ handed_back)
{
  int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= count) return;
  int p = list[local];
  PairBodies pair;
  pair_bodies(p, pair_i, pair_j, particles, motion, pair);
  const poly_clip_faces faces_i = shapes.clip[pair.body_i->shape], faces_j = shapes.clip[pair.body_j->shape];
  poly_clip_result clip;
  if (faces_i.num_faces == 0 || faces_j.num_faces == 0 ||
      !poly_clip_overlap_of(&faces_i, &faces_j, pair.rotation, pair.translation,
                            shapes.radius[pair.body_i->shape] + shapes.radius[pair.body_j->shape], settings.rocking,
                            Pieces, &clip, NULL)) {
    handed_back[atomicAdd(counters + 2, 1)] = p;
    return;
  }
  finish_clip_pair(p, pair, clip, materials, num_types, settings, contact, history, slot, pair_force, results,
                   counters);
}

// A warp per limits.pairs pairs of `list` whose shapes both have clip faces, the faces clipped in Real (float:
// mixed precision, limits.single) and summed in double: each pair's overlap
// by the clipping path spread over the warp's lanes (poly_gpu_clip_warp.cuh), one pair after the other, then the
// contact law of each on a lane of its own (on one lane per pair it held 8 % of the kernel's stall samples, the
// other lanes idle: doc/benchmarks.md); what the warp does not take goes to `handed_back`, as from
// clip_contact_kernel.
template <typename Real>
__global__ void __launch_bounds__(32 * POLY_CLIP_WARPS, POLY_CLIP_WARP_MIN_BLOCKS)
    clip_warp_kernel(DeviceShapes shapes, const int *__restrict__ list, int count, const int *__restrict__ pair_i,
                     const int *__restrict__ pair_j, const poly_gpu_particle *__restrict__ particles,
                     const poly_gpu_motion *__restrict__ motion, const poly_material_pair *__restrict__ materials,
                     int num_types, poly_gpu_settings settings, int *__restrict__ contact,
                     double *__restrict__ history, const int *__restrict__ slot,
                     PairForce *__restrict__ pair_force, PairGeometry *__restrict__ results,
                     int *__restrict__ counters, int *__restrict__ handed_back, ClipWarpLimits limits)
{
  extern __shared__ __align__(16) double clip_blocks[];
  const int warp = threadIdx.x >> 5, lane = threadIdx.x & 31;
  const int first = (blockIdx.x * POLY_CLIP_WARPS + warp) * limits.pairs;
  if (first >= count) return;  // the whole warp
  const int pairs = count - first < limits.pairs ? count - first : limits.pairs;
  ClipWarpMemory memory;
  clip_warp_layout(&memory, (char *)clip_blocks + (size_t)warp * limits.bytes, limits);
  PairBodies pair;
  for (int k = 0; k < pairs; k++) {
    pair_bodies(list[first + k], pair_i, pair_j, particles, motion, pair);
    const poly_clip_faces faces_i = shapes.clip[pair.body_i->shape], faces_j = shapes.clip[pair.body_j->shape];
    poly_clip_result clip;
    const int handed = faces_i.num_faces == 0 || faces_j.num_faces == 0 ||
                       clip_warp_overlap<Real>(faces_i, faces_j,
                                               shapes.clip_vertices_f + (faces_i.vertices - shapes.clip_vertices),
                                               shapes.clip_planes_f + (faces_i.planes - shapes.clip_planes),
                                               pair.rotation, pair.translation,
                                               shapes.radius[pair.body_i->shape] + shapes.radius[pair.body_j->shape],
                                               settings.rocking, memory, &clip);
    __syncwarp();  // the next pair rewrites the warp's block
    if (lane == 0) {
      if (handed) clip.num_nodes = -1;
      memory.results[k] = clip;
    }
  }
  __syncwarp();
  if (lane >= pairs) return;
  const int p = list[first + lane];
  const poly_clip_result &clip = memory.results[lane];
  if (clip.num_nodes < 0) {
    handed_back[atomicAdd(counters + 2, 1)] = p;
    return;
  }
  pair_bodies(p, pair_i, pair_j, particles, motion, pair);
  finish_clip_pair(p, pair, clip, materials, num_types, settings, contact, history, slot, pair_force, results,
                   counters);
}

#endif
