/* The CUDA narrow phase of pair_style polyhedral/volumetric/gpu: a C-linkage
 * boundary in the manner of LAMMPS' lib/gpu. Shapes are uploaded once
 * (poly_gpu_init); each step the host hands over the candidate pairs with
 * their poses and velocities and gets forces, torques, the updated contact
 * history and the contact geometry back (poly_gpu_compute). Device memory is
 * owned here and grown, never shrunk, between steps. The kernels call the same
 * overlap geometry (src/poly_overlap_impl.h) and contact law
 * (src/poly_contact.h) as the CPU style. */
#ifndef POLY_GPU_H
#define POLY_GPU_H

#include <stddef.h>

#include "poly_contact.h"
#include "poly_shape.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per candidate pair, as the host packs it. */
typedef struct poly_gpu_pair {
  int shape_i, shape_j;          /* index into the shapes given to poly_gpu_init */
  int material;                  /* index into the materials of the call */
  int flags;                     /* reserved, 0 */
  double position_i[3], quaternion_i[4], velocity_i[3], omega_i[3];
  double position_j[3], quaternion_j[4], velocity_j[3], omega_j[3];
  double mass_i, mass_j;
  double negligible_volume;      /* overlaps at most this large are no contact */
} poly_gpu_pair;

/* Per pair, back to the host. contact = 0: no contact (history zeroed). */
typedef struct poly_gpu_result {
  int contact, pad;
  double force_j[3], torque_i[3], torque_j[3];
  double volume, depth, normal[3], centroid[3], normal_force, tangential_force[3];
} poly_gpu_result;

/* Number of CUDA devices usable by this process (0 without a driver or GPU). */
int poly_gpu_device_count(void);

/* Selects device `device` (e.g. node-local rank modulo the device count) and
 * uploads the shapes. 0 on success, else a message. */
int poly_gpu_init(int device, int num_shapes, const poly_shape *const *shapes, char *message, size_t message_size);

/* Overlap and contact law for `num_pairs` pairs. history: POLY_HISTORY_SIZE
 * doubles per pair, read and (with advance_history) written back. */
int poly_gpu_compute(int num_pairs, const poly_gpu_pair *pairs, const poly_material_pair *materials,
                     int num_materials, int single_precision, int tangential, int damping, double dt,
                     int advance_history, double *history, poly_gpu_result *results, char *message,
                     size_t message_size);

/* Bytes of device memory held now. */
size_t poly_gpu_bytes(void);

void poly_gpu_clear(void);

#ifdef __cplusplus
}
#endif

#endif
