/* One polyhedral particle as LIGGGHTS' fix insert styles place it: the
 * insertion fix picks position, velocity, angular velocity and orientation
 * (its `orientation random|template|constant` keyword) and checks overlaps on
 * the bounding sphere, as for spheres; this class remembers the orientation,
 * which the sphere class drops for single particles, and on insertion gives
 * the new atom its shape, orientation, mass properties and angular momentum. */
#ifndef LMP_PARTICLE_TO_INSERT_POLYHEDRON_H
#define LMP_PARTICLE_TO_INSERT_POLYHEDRON_H

#include "particleToInsert.h"

namespace LAMMPS_NS {

class ParticleToInsertPolyhedron : public ParticleToInsert {
 public:
  ParticleToInsertPolyhedron(class LAMMPS *, class FixPropertyAtom *fix_release = NULL);

  int insert();
  int check_near_set_x_v_omega(double *x, double *v, double *omega, double *quat,
                               RegionNeighborList<interpolate_no> &neighbours);
  int set_x_v_omega(double *x, double *v, double *omega, double *quat);

  int shape_index;        // the template's shape number (atom shapetype)
  double quaternion[4];   // body to world
};

}

#endif
