#include "particle_to_insert_polyhedron.h"

#include <math.h>

#include "atom.h"

#include "atom_vec_polyhedron.h"
#include "poly_rigid.h"

using namespace LAMMPS_NS;

ParticleToInsertPolyhedron::ParticleToInsertPolyhedron(LAMMPS *lmp, FixPropertyAtom *fix_release)
    : ParticleToInsert(lmp, 1, fix_release), shape_index(0)
{
  quaternion[0] = 1.0;
  quaternion[1] = quaternion[2] = quaternion[3] = 0.0;
}

static void keep_orientation(const double *quat, double *quaternion)
{
  if (!quat) return;
  for (int k = 0; k < 4; k++) quaternion[k] = quat[k];
  poly_quat_normalize(quaternion);
}

int ParticleToInsertPolyhedron::check_near_set_x_v_omega(double *x, double *v, double *omega, double *quat,
                                                        RegionNeighborList<interpolate_no> &neighbours)
{
  int placed = ParticleToInsert::check_near_set_x_v_omega(x, v, omega, quat, neighbours);
  if (placed) keep_orientation(quat, quaternion);
  return placed;
}

int ParticleToInsertPolyhedron::set_x_v_omega(double *x, double *v, double *omega, double *quat)
{
  keep_orientation(quat, quaternion);
  return ParticleToInsert::set_x_v_omega(x, v, omega, quat);
}

int ParticleToInsertPolyhedron::insert()
{
  int inserted = ParticleToInsert::insert();
  if (inserted != 1) return inserted;
  int i = atom->nlocal - 1;
  atom->shapetype[i] = shape_index;
  atom->density[i] = density_ins;
  for (int k = 0; k < 4; k++) atom->quaternion[i][k] = quaternion[k];
  // Mass, bounding radius and principal inertia from the shape.
  static_cast<AtomVecPolyhedron *>(atom->avec)->resolve_shape(i);
  poly_omega_to_angmom(atom->quaternion[i], atom->inertia[i], omega_ins, atom->angmom[i]);
  return inserted;
}
