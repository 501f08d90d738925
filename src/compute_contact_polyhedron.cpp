#include "compute_contact_polyhedron.h"

#include <string.h>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "update.h"

#include "pair_polyhedral_volumetric.h"

using namespace LAMMPS_NS;

ComputeContactPolyhedron::ComputeContactPolyhedron(LAMMPS *lmp, int &iarg, int narg, char **arg)
    : Compute(lmp, iarg, narg, arg), nmax(0), contact(NULL)
{
  if (narg != iarg) error->compute_error(FLERR, this, "takes no arguments");
  peratom_flag = 1;
  size_peratom_cols = 0;
}

ComputeContactPolyhedron::~ComputeContactPolyhedron()
{
  memory->destroy(contact);
}

void ComputeContactPolyhedron::init()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0)
    error->compute_error(FLERR, this, "requires atom_style polyhedron (compute contact/atom counts spheres)");
  if (!dynamic_cast<PairPolyhedralVolumetric *>(force->pair))
    error->compute_error(FLERR, this, "requires pair_style polyhedral/volumetric");
}

void ComputeContactPolyhedron::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    memory->destroy(contact);
    nmax = atom->nmax;
    memory->create(contact, nmax, "contact/polyhedron:contact");
    vector_atom = contact;
  }
  for (int i = 0; i < atom->nlocal; i++) contact[i] = 0.0;
  static_cast<PairPolyhedralVolumetric *>(force->pair)->count_contacts(contact, groupbit);
}

double ComputeContactPolyhedron::memory_usage()
{
  return (double) nmax * sizeof(double);
}
