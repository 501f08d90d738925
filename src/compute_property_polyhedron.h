/* compute property/polyhedron: per-particle orientation, shape and moments,
 * for dump custom, like compute property/atom does for other styles. */
#ifdef COMPUTE_CLASS
#else

#ifndef LMP_COMPUTE_PROPERTY_POLYHEDRON_H
#define LMP_COMPUTE_PROPERTY_POLYHEDRON_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputePropertyPolyhedron : public Compute {
 public:
  ComputePropertyPolyhedron(class LAMMPS *, int &, int, char **);
  ~ComputePropertyPolyhedron();
  void init();
  void compute_peratom();
  double memory_usage();

 private:
  enum Quantity { SHAPE, QUATW, QUATI, QUATJ, QUATK, INERTIAX, INERTIAY, INERTIAZ, BOUNDRADIUS, VOLUME, RADIUS_VOLUME };
  int num_quantities;
  Quantity *quantities;
  int nmax;
  double *values;  // the single column when num_quantities == 1
  double value_of(Quantity, int i) const;
};

}

#endif
#endif
