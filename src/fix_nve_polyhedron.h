/* fix nve/polyhedron: velocity Verlet for translation, NO_SQUISH for rotation. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_NVE_POLYHEDRON_H
#define LMP_FIX_NVE_POLYHEDRON_H

#include "fix.h"

namespace LAMMPS_NS {

class FixNVEPolyhedron : public Fix {
 public:
  FixNVEPolyhedron(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void initial_integrate(int);
  void final_integrate();
  void reset_dt();

 private:
  double dtv, dtf;
};

}

#endif
#endif
