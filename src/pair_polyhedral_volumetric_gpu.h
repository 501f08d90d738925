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
  // For fix wall/polyhedral: a step with fewer mesh-wall pieces than this runs them on the host.
  long wall_pieces_on_gpu_from() const { return min_pieces; }

 private:
  void send_pairs();
  long pair_work() const;
  void gpu_error(const char *message);

  bool device_ready;
  // Small work goes to the host's code (doc/gpu.md, "Small decks"): decided at each neighbour-list build from
  // the list's pairs on this rank, those in contact weighted (pair_work, POLY_GPU_MIN_PAIRS), and per step from
  // the mesh-wall pieces (POLY_GPU_MIN_PIECES).
  long min_pairs, min_pieces;
  bool pairs_on_host;
  long steps_on_host;
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
