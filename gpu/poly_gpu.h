/* The CUDA narrow phase of pair_style polyhedral/volumetric/gpu: a C-linkage
 * boundary in the manner of LAMMPS' lib/gpu.
 *
 *   poly_gpu_init          once: select the device, upload the shapes
 *   poly_gpu_set_pairs     at each neighbour-list rebuild: the candidate pairs
 *                          (all pairs of the list), per-particle constants,
 *                          materials and the contact history from LIGGGHTS
 *   poly_gpu_compute       every step: poses and velocities in (through the
 *                          pinned poly_gpu_motion_buffer), summed forces and
 *                          torques per particle out (poly_gpu_force_torque), or
 *                          per-pair results when the host needs them (virial,
 *                          contact records)
 *   poly_gpu_get_history   before LIGGGHTS migrates or writes history: the
 *                          history lives on the device between rebuilds
 *   poly_gpu_clear         free everything
 *
 * and for the walls of fix wall/polyhedral (gpu/poly_gpu_wall.cu), on the
 * shapes of poly_gpu_init:
 *
 *   poly_gpu_wall_buffer   pinned host buffer of particle-prism candidates
 *   poly_gpu_wall_overlaps their overlaps (volume, centroid, normal, depth,
 *                          area vector and intersection nodes), as the host's
 *                          poly_overlap_d + poly_overlap_nodes_d give them
 *
 * Device memory and the pinned host buffers are owned here and grown, never
 * shrunk. The kernels call the same overlap geometry (src/poly_overlap_impl.h)
 * and contact law (src/poly_contact.h) as the CPU style. */
#ifndef POLY_GPU_H
#define POLY_GPU_H

#include <stddef.h>
#include <string.h>

#include "poly_contact.h"
#include "poly_mesh_shell.h"
#include "poly_overlap.h"
#include "poly_shape.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A GPU thread's overlap workspace is an array in its local memory when the
 * workspace of the largest shape (poly_overlap_workspace_layout) fits in this
 * many scalars of the precision: 6 KiB in double, enough for tetrahedra,
 * Schoenhardt polyhedra, cubes and 10-triangle rocks, and for shapes of up to
 * about 16 triangles in single and mixed precision. Local memory is reserved
 * for every thread the GPU can hold (about 0.27 M on an H100, so ~1.6 GiB per
 * process at 6 KiB); larger shapes use per-thread blocks of a scratch buffer in
 * global memory instead. */
#define POLY_GPU_LOCAL_WORKSPACE_REALS 768

/* Per particle (owned and ghost), constant between neighbour-list rebuilds. */
typedef struct poly_gpu_particle {
  int shape;                     /* index into the shapes given to poly_gpu_init */
  int type;                      /* atom type, 1..num_types */
  double mass;
  double negligible_volume;      /* a pair's overlap at most the smaller of its two is no contact */
  double bounding_radius;        /* an overlap whose centroid lies beyond it is no contact (poly_contact.h) */
} poly_gpu_particle;

/* Per particle, every step. */
typedef struct poly_gpu_motion {
  double position[3], quaternion[4], velocity[3], omega[3];
} poly_gpu_motion;

typedef struct poly_gpu_settings {
  int precision;                 /* poly_precision: double, single or mixed */
  int tangential, damping;       /* the pair style's switches */
  int rocking;                   /* rocking damping: the overlaps' second moments go to the contact law */
  int advance_history;           /* 0 in set-up force evaluations */
  int parting_search;            /* pairs not in contact at their last evaluation are searched for a parting plane */
  double dt;
} poly_gpu_settings;

/* Per pair, when asked for. contact = 0: no contact. */
typedef struct poly_gpu_result {
  int contact, pair;             /* pair: its index among the pairs of poly_gpu_set_pairs */
  double force_j[3], torque_i[3], torque_j[3];
  double volume, depth, normal[3], centroid[3], normal_force, tangential_force[3];
} poly_gpu_result;

/* A particle against one prism of a mesh wall's shell (poly_mesh_prism of
 * src/poly_mesh_shell.h, which this mirrors without its host pointers). */
typedef struct poly_gpu_wall_piece {
  int shape;                     /* the particle's: index into the shapes given to poly_gpu_init */
  int pad;
  double position[3], quaternion[4];  /* the particle's pose */
  double origin[3];              /* the prism's vertices are relative to this point (world) */
  double vertices[18];           /* 6 vertices, world orientation */
  double face_normals[24];       /* 8 triangles */
  double bounding_radius;        /* about origin */
  int triangles[24], edges[24], edge_triangles[24];
} poly_gpu_wall_piece;

/* The prism half of a piece. */
static inline void poly_gpu_wall_piece_set_prism(poly_gpu_wall_piece *piece, const poly_mesh_prism *prism)
{
  memcpy(piece->origin, prism->origin, sizeof piece->origin);
  memcpy(piece->vertices, prism->vertices, sizeof piece->vertices);
  memcpy(piece->face_normals, prism->face_normals, sizeof piece->face_normals);
  piece->bounding_radius = prism->view.bounding_radius;
  memcpy(piece->triangles, prism->triangles, sizeof piece->triangles);
  memcpy(piece->edges, prism->edges, sizeof piece->edges);
  memcpy(piece->edge_triangles, prism->edge_triangles, sizeof piece->edge_triangles);
}

/* A piece's overlap: geometry as poly_overlap_d returns it (world frame, the
 * particle as A); its geometry.num_nodes intersection nodes, relative to the
 * particle's position as poly_overlap_nodes_d gives them, start at
 * nodes[3 * first_node] of poly_gpu_wall_overlaps' node array. num_nodes = -1
 * (first_node -1) where the host would not keep them either (more nodes than
 * the overlap workspace holds). */
typedef struct poly_gpu_wall_overlap {
  poly_overlap_result geometry;
  int first_node, pad;
} poly_gpu_wall_overlap;

/* Accumulated wall-clock seconds of poly_gpu_set_pairs, of the phases of
 * poly_gpu_compute and of poly_gpu_wall_overlaps, how often each ran, and what
 * they computed. */
typedef struct poly_gpu_timing {
  double set_pairs, upload, kernels, download;
  long num_set_pairs, num_compute;
  long pairs;                    /* candidate pairs, summed over the poly_gpu_compute calls */
  long handed_back;              /* pairs the warp kernel left to the one-thread kernel (flush faces, ...) */
  long kept;                     /* of the candidate pairs, those the pre-filter left to the contact kernels */
  long centroid_outside;         /* overlaps dropped as their centroid fell outside a particle (a sliver of rounding,
                                    poly_contact_centroid_within) */
  long spots_facing_apart;       /* contacts at spots facing apart (poly_contact_spots_facing_apart) */
  double wall_seconds;           /* poly_gpu_wall_overlaps: pieces up, overlaps and nodes down */
  long wall_calls, wall_pieces;  /* its calls, and their pieces summed */
  long wall_handed_back;         /* pieces its lanes left to the one-thread kernel */
  int clip_warp_pairs;           /* pairs a warp of the clipping warp kernel takes, for the uploaded shapes */
  long clip_warp_bytes;          /* and that warp's block of shared memory (doc/gpu.md) */
} poly_gpu_timing;

/* Number of CUDA devices usable by this process (0 without a driver or GPU). */
int poly_gpu_device_count(void);

/* Choices read from the environment (doc/gpu.md): which kernels run, and below
 * how much work a rank leaves the GPU idle and runs the host's code instead. */
typedef struct poly_gpu_options {
  int pair_kernel;               /* POLY_GPU_PAIR_KERNEL = thread | warp: 1, 2 (0 unset: chosen from the shapes) */
  int clip_kernel;               /* POLY_GPU_CLIP_KERNEL = thread | warp: 1, 2 (0 unset: warp), for the clipping path */
  int pair_lanes;                /* POLY_GPU_PAIR_LANES = 8 | 16 | 32, pairs and wall pieces (0 unset: from the shapes) */
  int wall_kernel;               /* POLY_GPU_WALL_KERNEL = thread | warp: 1, 2 (0 unset: chosen from the shapes) */
  int mixed_clip;                /* POLY_GPU_MIXED_CLIP = single | double: 1, 2 (0 unset: double), the warp clipping
                                    kernel's faces in mixed precision (single injects energy into packed beds) */
  int carveout;                  /* POLY_GPU_CARVEOUT = tight | driver: 1, 2 (0 unset: tight), the clipping warp
                                    kernel's shared memory: the least configuration that holds its blocks, or the
                                    driver's choice */
  long min_pairs;                /* POLY_GPU_MIN_PAIRS: fewer neighbour-list pairs on a rank (one in contact counting
                                    32): its pairs on the host until the next rebuild */
  long min_pieces;               /* POLY_GPU_MIN_PIECES: fewer mesh-wall pieces in a step: on the host */
} poly_gpu_options;

/* The options from the environment (unset or empty: the defaults), or -1 and a
 * message naming the variable and its value. Needs no device. */
int poly_gpu_environment(poly_gpu_options *options, char *message, size_t message_size);

/* Selects device `device` (modulo the device count) and uploads the shapes.
 * 0 on success, else a message. */
int poly_gpu_init(int device, int num_shapes, const poly_shape *const *shapes, char *message, size_t message_size);

/* The candidate pairs (pair_i[p], pair_j[p]) into the particle arrays, with
 * POLY_HISTORY_SIZE history doubles per pair. Forces are summed for particles
 * 0 .. num_force_particles-1 (owned, or all with newton on); the pair's first
 * particle must be one of them. materials: (num_types+1)^2, indexed
 * type_i * (num_types+1) + type_j. */
int poly_gpu_set_pairs(int num_particles, int num_force_particles, const poly_gpu_particle *particles, int num_pairs,
                       const int *pair_i, const int *pair_j, const double *history, int num_types,
                       const poly_material_pair *materials, char *message, size_t message_size);

/* Pinned host buffer for the motion of the num_particles of poly_gpu_set_pairs,
 * filled by the caller before poly_gpu_compute. NULL when it cannot be had. */
poly_gpu_motion *poly_gpu_motion_buffer(void);

/* One step. With results == NULL: forces and torques summed per particle, read
 * afterwards from poly_gpu_force_torque. Otherwise per-pair results (num_pairs
 * of them) and no sums. num_contacts: pairs in contact. */
int poly_gpu_compute(const poly_gpu_settings *settings, poly_gpu_result *results, int *num_contacts, char *message,
                     size_t message_size);

/* After poly_gpu_compute without results: 6 doubles per force particle, force
 * then torque. Pinned host memory, valid until the next call. */
const double *poly_gpu_force_torque(void);

/* The contact history and contact flags of the pairs of poly_gpu_set_pairs. */
int poly_gpu_get_history(double *history, int *contact, char *message, size_t message_size);

/* Pinned host buffer for count pieces, filled by the caller before
 * poly_gpu_wall_overlaps; valid until the next call. NULL on failure. */
poly_gpu_wall_piece *poly_gpu_wall_buffer(int count);

/* The overlaps of the count pieces of poly_gpu_wall_buffer in precision
 * `precision` (poly_precision), into overlaps[count]; *nodes points to the
 * nodes (pinned host memory, valid until the next call). 0, or -1 with a
 * message. */
int poly_gpu_wall_overlaps(int precision, int count, poly_gpu_wall_overlap *overlaps, const double **nodes,
                           char *message, size_t message_size);

poly_gpu_timing poly_gpu_timings(void);

/* Bytes of device memory held now. */
size_t poly_gpu_bytes(void);

void poly_gpu_clear(void);

#ifdef __cplusplus
}
#endif

#endif
