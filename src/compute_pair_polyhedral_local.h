/* compute pair/polyhedral/local: the active contacts of pair
 * polyhedral/volumetric, one row each, for dump local (as compute
 * pair/gran/local does for spheres); its scalar is the number of contacts,
 * for thermo output. */
#ifdef COMPUTE_CLASS
#else

#ifndef LMP_COMPUTE_PAIR_POLYHEDRAL_LOCAL_H
#define LMP_COMPUTE_PAIR_POLYHEDRAL_LOCAL_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputePairPolyhedralLocal : public Compute {
 public:
  ComputePairPolyhedralLocal(class LAMMPS *, int &, int, char **);
  ~ComputePairPolyhedralLocal();
  void init();
  void compute_local();
  double compute_scalar();  // number of contacts
  void compute_vector();    // degenerate contacts since pair_style: smoothed, re-evaluated, inconsistent
  double memory_usage();

  enum { kColumns = 16 };

  // Removes computes destroyed since the last init from the pair style's
  // recorders; called from every init that precedes a run (this compute's and
  // atom_style polyhedron's), never from a destructor.
  static void drop_destroyed_recorders(class LAMMPS *);
  // For any recorder (this compute or another) deleted while it may still be
  // registered with the pair style: dropped at the next init.
  static void recorder_destroyed(class LAMMPS *, class Compute *);

 private:
  class PairPolyhedralVolumetric *pair;
  int capacity;
  double statistics[11];
  void require_current_records();
};

}

#endif
#endif
