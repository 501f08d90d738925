/* fix wall/polyhedral: plane walls for polyhedral particles, with the
 * volumetric contact law of pair_style polyhedral/volumetric (the wall is the
 * second body, of infinite mass and at rest). The overlap of a particle with
 * the wall solid is exact (src/poly_halfspace.h). The tangential spring of
 * each particle's wall contact is a per-atom property (fix property/atom), so
 * it migrates with the particle and is written to restart files. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_WALL_POLYHEDRAL_H
#define LMP_FIX_WALL_POLYHEDRAL_H

#include <vector>

#include "fix.h"
#include "poly_contact.h"

namespace LAMMPS_NS {

class FixWallPolyhedral : public Fix {
 public:
  FixWallPolyhedral(class LAMMPS *, int, char **);
  ~FixWallPolyhedral();
  void post_create();
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  double compute_vector(int);

 private:
  void apply_walls(bool advance_history);

  int wall_type;             // atom type of the wall material
  int axis;                  // 0, 1, 2 for xplane, yplane, zplane
  double position;           // of the plane along the axis
  int tangential, damping;   // -1: as the pair style
  char *history_id;
  class FixPropertyAtom *history;
  class PairPolyhedralVolumetric *pair;
  int use_tangential, use_damping;   // this wall's switches, resolved in init()
  std::vector<poly_material_pair> materials;  // (ntypes+1)^2, read with this wall's switches
  double wall_force[4], wall_force_all[4];  // force on the wall (3), contacts
  bool force_summed;
};

}

#endif
#endif
