#include "fix_nve_polyhedron.h"

#include <string.h>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include "poly_rigid.h"

using namespace LAMMPS_NS;
using namespace FixConst;

FixNVEPolyhedron::FixNVEPolyhedron(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg), dtv(0.0), dtf(0.0)
{
  if (narg != 3) error->fix_error(FLERR, this, "takes no arguments");
  time_integrate = 1;
}

int FixNVEPolyhedron::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixNVEPolyhedron::init()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0) error->fix_error(FLERR, this, "requires atom_style polyhedron");
  reset_dt();
  // angmom is the integrated state; omega is derived from it (data files and
  // restarts carry angmom).
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit)
      poly_angmom_to_omega(atom->quaternion[i], atom->inertia[i], atom->angmom[i], atom->omega[i]);
}

void FixNVEPolyhedron::reset_dt()
{
  dtv = update->dt;
  dtf = 0.5 * update->dt * force->ftm2v;
}

void FixNVEPolyhedron::initial_integrate(int)
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  double **angmom = atom->angmom, **torque = atom->torque, **omega = atom->omega;
  double **quaternion = atom->quaternion, **inertia = atom->inertia;
  double *rmass = atom->rmass;
  int *mask = atom->mask;
  int nlocal = atom->nlocal;
  if (igroup == atom->firstgroup) nlocal = atom->nfirst;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double dtfm = dtf / rmass[i];
    for (int k = 0; k < 3; k++) {
      v[i][k] += dtfm * f[i][k];
      x[i][k] += dtv * v[i][k];
      angmom[i][k] += dtf * torque[i][k];
    }
    poly_free_rotation(quaternion[i], inertia[i], angmom[i], dtv);
    poly_angmom_to_omega(quaternion[i], inertia[i], angmom[i], omega[i]);
  }
}

void FixNVEPolyhedron::final_integrate()
{
  double **v = atom->v, **f = atom->f;
  double **angmom = atom->angmom, **torque = atom->torque, **omega = atom->omega;
  double **quaternion = atom->quaternion, **inertia = atom->inertia;
  double *rmass = atom->rmass;
  int *mask = atom->mask;
  int nlocal = atom->nlocal;
  if (igroup == atom->firstgroup) nlocal = atom->nfirst;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double dtfm = dtf / rmass[i];
    for (int k = 0; k < 3; k++) {
      v[i][k] += dtfm * f[i][k];
      angmom[i][k] += dtf * torque[i][k];
    }
    poly_angmom_to_omega(quaternion[i], inertia[i], angmom[i], omega[i]);
  }
}
