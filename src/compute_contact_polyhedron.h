/* compute contact/polyhedron: LIGGGHTS' compute contact/atom for polyhedra, the
 * number of particles each particle touches (coordination number), from the
 * contacts pair_style polyhedral/volumetric found. */
#ifdef COMPUTE_CLASS
#else

#ifndef LMP_COMPUTE_CONTACT_POLYHEDRON_H
#define LMP_COMPUTE_CONTACT_POLYHEDRON_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeContactPolyhedron : public Compute {
 public:
  ComputeContactPolyhedron(class LAMMPS *, int &, int, char **);
  ~ComputeContactPolyhedron();
  void init();
  void compute_peratom();
  double memory_usage();

 private:
  int nmax;
  double *contact;
};

}

#endif
#endif
