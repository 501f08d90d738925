/* create_polyhedron TEMPLATE-ID x y z [quat w i j k] [vel vx vy vz] [omega wx wy wz]
 * Places one polyhedral particle; the rank that owns the position creates it. */
#ifdef COMMAND_CLASS
#else

#ifndef LMP_CREATE_POLYHEDRON_H
#define LMP_CREATE_POLYHEDRON_H

#include "pointers.h"

namespace LAMMPS_NS {

class CreatePolyhedron : protected Pointers {
 public:
  CreatePolyhedron(class LAMMPS *);
  void command(int, char **);
};

}

#endif
#endif
