/* compute wall/polyhedral/local: the contacts of one fix wall/polyhedral, one
 * row each, for dump local (LIGGGHTS' compute wall/gran/local for polyhedra). */
#ifdef COMPUTE_CLASS
#else

#ifndef LMP_COMPUTE_WALL_POLYHEDRAL_LOCAL_H
#define LMP_COMPUTE_WALL_POLYHEDRAL_LOCAL_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeWallPolyhedralLocal : public Compute {
 public:
  ComputeWallPolyhedralLocal(class LAMMPS *, int &, int, char **);
  ~ComputeWallPolyhedralLocal();
  void init();
  void compute_local();
  double memory_usage();

 private:
  class FixWallPolyhedral *find_wall() const;
  char *wall_id;
  int nmax;
  double **rows;
};

}

#endif
#endif
