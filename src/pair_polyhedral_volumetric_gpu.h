/* pair_style polyhedral/volumetric/gpu: the same contacts as
 * polyhedral/volumetric, with the overlap geometry and contact law evaluated
 * on a GPU (gpu/poly_gpu.h). Neighbour lists, history storage, communication
 * and integration stay with LIGGGHTS on the host. */
#ifdef PAIR_CLASS
#else

#ifndef LMP_PAIR_POLYHEDRAL_VOLUMETRIC_GPU_H
#define LMP_PAIR_POLYHEDRAL_VOLUMETRIC_GPU_H

#include <vector>

#include "pair_polyhedral_volumetric.h"

struct poly_gpu_pair;
struct poly_gpu_result;

namespace LAMMPS_NS {

class PairPolyhedralVolumetricGPU : public PairPolyhedralVolumetric {
 public:
  PairPolyhedralVolumetricGPU(class LAMMPS *);
  ~PairPolyhedralVolumetricGPU();
  void init_style();
  void compute(int, int);
  double memory_usage();

 private:
  bool device_ready;
  std::vector<poly_gpu_pair> pairs;
  std::vector<poly_gpu_result> results;
  std::vector<double> history;
  std::vector<int> pair_i, pair_jj;  // where each candidate came from in the neighbour list
};

}

#endif
#endif
