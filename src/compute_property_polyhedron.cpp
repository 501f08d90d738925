#include "compute_property_polyhedron.h"

#include <math.h>
#include <string.h>

#include "atom.h"
#include "error.h"
#include "memory.h"
#include "update.h"

using namespace LAMMPS_NS;

static const struct { const char *name; int quantity; } kKeywords[] = {
    {"shape", 0},    {"quatw", 1},    {"quati", 2},    {"quatj", 3},       {"quatk", 4},
    {"inertiax", 5}, {"inertiay", 6}, {"inertiaz", 7}, {"boundradius", 8}, {"volume", 9},
    {"radius_volume", 10},
};

ComputePropertyPolyhedron::ComputePropertyPolyhedron(LAMMPS *lmp, int &iarg, int narg, char **arg)
    : Compute(lmp, iarg, narg, arg), num_quantities(0), quantities(NULL), nmax(0), values(NULL)
{
  if (narg <= iarg) error->compute_error(FLERR, this, "expected at least one keyword");
  num_quantities = narg - iarg;
  quantities = new Quantity[num_quantities];
  for (int n = 0; n < num_quantities; n++) {
    int found = -1;
    for (size_t k = 0; k < sizeof kKeywords / sizeof kKeywords[0]; k++)
      if (strcmp(arg[iarg + n], kKeywords[k].name) == 0) found = kKeywords[k].quantity;
    if (found < 0) error->compute_error(FLERR, this, "unknown keyword (shape quatw quati quatj quatk "
                                                     "inertiax inertiay inertiaz boundradius volume radius_volume)");
    quantities[n] = static_cast<Quantity>(found);
  }
  // The LIGGGHTS Compute base leaves these unset.
  vector_atom = NULL;
  array_atom = NULL;
  peratom_flag = 1;
  size_peratom_cols = num_quantities == 1 ? 0 : num_quantities;
}

ComputePropertyPolyhedron::~ComputePropertyPolyhedron()
{
  delete[] quantities;
  memory->destroy(values);
  memory->destroy(array_atom);
}

void ComputePropertyPolyhedron::init()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0)
    error->compute_error(FLERR, this, "requires atom_style polyhedron");
}

double ComputePropertyPolyhedron::value_of(Quantity quantity, int i) const
{
  switch (quantity) {
    case SHAPE: return atom->shapetype[i];
    case QUATW: return atom->quaternion[i][0];
    case QUATI: return atom->quaternion[i][1];
    case QUATJ: return atom->quaternion[i][2];
    case QUATK: return atom->quaternion[i][3];
    case INERTIAX: return atom->inertia[i][0];
    case INERTIAY: return atom->inertia[i][1];
    case INERTIAZ: return atom->inertia[i][2];
    case BOUNDRADIUS: return atom->radius[i];
    case VOLUME: return atom->rmass[i] / atom->density[i];
    // The radius of the sphere of the particle's volume (dump custom's `radius` is the bounding radius).
    case RADIUS_VOLUME: return cbrt(3.0 * atom->rmass[i] / (4.0 * M_PI * atom->density[i]));
  }
  return 0.0;
}

void ComputePropertyPolyhedron::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    if (num_quantities == 1) {
      memory->destroy(values);
      memory->create(values, nmax, "property/polyhedron:vector");
      vector_atom = values;
    } else {
      memory->destroy(array_atom);
      memory->create(array_atom, nmax, num_quantities, "property/polyhedron:array");
    }
  }
  for (int i = 0; i < atom->nlocal; i++) {
    bool in_group = (atom->mask[i] & groupbit) != 0;
    for (int n = 0; n < num_quantities; n++) {
      double value = in_group ? value_of(quantities[n], i) : 0.0;
      if (num_quantities == 1) values[i] = value;
      else array_atom[i][n] = value;
    }
  }
}

double ComputePropertyPolyhedron::memory_usage()
{
  return (double) nmax * num_quantities * sizeof(double);
}
