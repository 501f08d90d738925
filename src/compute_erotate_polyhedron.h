/* compute erotate/polyhedron: rotational kinetic energy of polyhedral particles. */
#ifdef COMPUTE_CLASS
#else

#ifndef LMP_COMPUTE_EROTATE_POLYHEDRON_H
#define LMP_COMPUTE_EROTATE_POLYHEDRON_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeERotatePolyhedron : public Compute {
 public:
  ComputeERotatePolyhedron(class LAMMPS *, int &, int, char **);
  void init();
  double compute_scalar();
};

}

#endif
#endif
