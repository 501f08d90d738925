/* One polyhedral particle as LIGGGHTS' fix insert styles place it.
 *
 * The insertion fix picks position, velocity, angular velocity and orientation
 * (its `orientation random|template|constant` keyword) and asks the particle,
 * through check_near_set_x_v_omega, whether it may go there. For spheres that
 * is a bounding-sphere test against the fix's neighbour list of nearby
 * particles (existing ones, and those accepted earlier in the same insertion).
 * Here the bounding spheres are only the broad phase: a candidate is rejected
 * when its exact overlap volume (poly_overlap_d) with a nearby polyhedron is
 * positive, and, for fix insert/pack and insert/rate/region, when one of its
 * vertices, at its insertion orientation, is outside the region (all_in) or
 * outside this rank's sub-domain. See doc/fix_particletemplate_polyhedron.md.
 *
 * On insertion the new atom gets its shape, orientation, mass properties and
 * angular momentum. */
#ifndef LMP_PARTICLE_TO_INSERT_POLYHEDRON_H
#define LMP_PARTICLE_TO_INSERT_POLYHEDRON_H

#include "particleToInsert.h"

namespace LAMMPS_NS {

class FixParticletemplatePolyhedron;
class FixTemplateSphere;

// What the insertion fix that is inserting now asks beyond the overlap test.
struct PolyhedronInsertionRules {
  // Positions are sampled with the shape's inner radius, not its bounding
  // radius, as the margin from the region's surface and the sub-domain's
  // borders (r_bound_ins); the vertices are then checked against both here.
  bool vertex_margins;
  class Region *all_in_region;  // all_in: every vertex inside it (NULL: no such check)
  bool inside_subdomain;        // every vertex inside this rank's sub-domain

  // The rules of the insertion fix inserting particles of `shape_template` on
  // this step (call while that fix inserts); none if there is no such fix.
  static PolyhedronInsertionRules of_current_insertion(class LAMMPS *, FixTemplateSphere *shape_template);
};

class ParticleToInsertPolyhedron : public ParticleToInsert {
 public:
  ParticleToInsertPolyhedron(class LAMMPS *, class FixPropertyAtom *fix_release = NULL);

  int insert();
  int check_near_set_x_v_omega(double *x, double *v, double *omega, double *quat,
                               RegionNeighborList<interpolate_no> &neighbours);
  int set_x_v_omega(double *x, double *v, double *omega, double *quat);

  const FixParticletemplatePolyhedron *shape_template;
  int shape_index;        // the template's shape number (atom shapetype)
  double quaternion[4];   // body to world
  PolyhedronInsertionRules rules;

 private:
  bool vertices_fit(const double *x, const double *quat);
};

}

#endif
