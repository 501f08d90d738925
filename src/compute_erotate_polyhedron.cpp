#include "compute_erotate_polyhedron.h"

#include <mpi.h>
#include <string.h>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include "poly_rigid.h"

using namespace LAMMPS_NS;

ComputeERotatePolyhedron::ComputeERotatePolyhedron(LAMMPS *lmp, int &iarg, int narg, char **arg) : Compute(lmp, iarg, narg, arg)
{
  if (narg != iarg) error->compute_error(FLERR, this, "takes no arguments");
  scalar_flag = 1;
  extscalar = 1;
}

void ComputeERotatePolyhedron::init()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0)
    error->compute_error(FLERR, this, "requires atom_style polyhedron");
}

double ComputeERotatePolyhedron::compute_scalar()
{
  invoked_scalar = update->ntimestep;
  double energy = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit)
      energy += poly_rotational_energy(atom->quaternion[i], atom->inertia[i], atom->angmom[i]);
  MPI_Allreduce(&energy, &scalar, 1, MPI_DOUBLE, MPI_SUM, world);
  scalar *= force->mvv2e;
  return scalar;
}
