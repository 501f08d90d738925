/* pair_style polyhedral/volumetric/gpu: the same contacts as
 * polyhedral/volumetric, with the overlap geometry and contact law evaluated
 * on a GPU (gpu/poly_gpu.h). Neighbour lists, communication and integration
 * stay with LIGGGHTS on the host. The candidate pairs and their contact
 * history go to the GPU when LIGGGHTS rebuilds its neighbour list, and the
 * history stays there until LIGGGHTS next needs it (the contact-history fix
 * asks for it before migration, restart and the next rebuild); each step only
 * poses and velocities go up and per-particle forces and torques come back. */
#ifdef PAIR_CLASS
#else

#ifndef LMP_PAIR_POLYHEDRAL_VOLUMETRIC_GPU_H
#define LMP_PAIR_POLYHEDRAL_VOLUMETRIC_GPU_H

#include <vector>

#include "lmptype.h"
#include "pair_polyhedral_volumetric.h"

struct poly_gpu_result;

namespace LAMMPS_NS {

class PairPolyhedralVolumetricGPU : public PairPolyhedralVolumetric {
 public:
  PairPolyhedralVolumetricGPU(class LAMMPS *);
  ~PairPolyhedralVolumetricGPU();
  void init_style();
  void compute(int, int);
  void history_to_host();
  double memory_usage();

 private:
  void send_pairs();
  void gpu_error(const char *message);

  bool device_ready;
  bigint pairs_build;                // neighbor->ncalls when the pairs were sent; -1: never
  bool device_history_newer;         // the GPU holds history the neighbour list lacks
  int num_force_particles;
  int sent_particles;                // owned + ghost particles when the pairs were sent
  std::vector<int> pair_i, pair_j, pair_jj;  // where each candidate came from in the neighbour list
  std::vector<double> history;
  std::vector<int> contact;
  std::vector<poly_gpu_result> results;
};

}

#endif
#endif
