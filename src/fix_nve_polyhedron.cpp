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

// Both integrate steps run once per particle and step, so they are written for speed.
// Particles with angular momentum are rotated in blocks of POLY_ROTATION_BLOCK
// (poly_free_rotation_block: the NO_SQUISH splitting in structure-of-arrays form, with
// the inverse moments formed once, polynomial sin/cos of the small sub-rotation angles
// and no rotation matrix for the conjugate momentum); a particle without angular
// momentum (L = 0 exactly: q stays, omega = 0) skips the rotation.
static inline bool zero_vector(const double *a)
{
  return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0;
}

void FixNVEPolyhedron::initial_integrate(int)
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  double **angmom = atom->angmom, **torque = atom->torque, **omega = atom->omega;
  double **quaternion = atom->quaternion, **inertia = atom->inertia;
  const double *rmass = atom->rmass;
  const int *mask = atom->mask;
  int nlocal = atom->nlocal;
  if (igroup == atom->firstgroup) nlocal = atom->nfirst;
  const double dtv = this->dtv, dtf = this->dtf;

  double *block_q[POLY_ROTATION_BLOCK], *block_omega[POLY_ROTATION_BLOCK];
  const double *block_moments[POLY_ROTATION_BLOCK], *block_angmom[POLY_ROTATION_BLOCK];
  int count = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *__restrict xi = x[i], *__restrict vi = v[i], *__restrict li = angmom[i];
    const double *__restrict fi = f[i], *__restrict ti = torque[i];
    const double dtfm = dtf / rmass[i];
    for (int k = 0; k < 3; k++) {
      vi[k] += dtfm * fi[k];
      xi[k] += dtv * vi[k];
      li[k] += dtf * ti[k];
    }
    if (zero_vector(li)) {
      omega[i][0] = omega[i][1] = omega[i][2] = 0.0;
      continue;
    }
    block_q[count] = quaternion[i];
    block_moments[count] = inertia[i];
    block_angmom[count] = li;
    block_omega[count] = omega[i];
    if (++count == POLY_ROTATION_BLOCK) {
      poly_free_rotation_block(count, block_q, block_moments, block_angmom, block_omega, dtv);
      count = 0;
    }
  }
  if (count) poly_free_rotation_block(count, block_q, block_moments, block_angmom, block_omega, dtv);
}

void FixNVEPolyhedron::final_integrate()
{
  double **v = atom->v, **f = atom->f;
  double **angmom = atom->angmom, **torque = atom->torque, **omega = atom->omega;
  double **quaternion = atom->quaternion, **inertia = atom->inertia;
  const double *rmass = atom->rmass;
  const int *mask = atom->mask;
  int nlocal = atom->nlocal;
  if (igroup == atom->firstgroup) nlocal = atom->nfirst;
  const double dtf = this->dtf;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *__restrict vi = v[i], *__restrict li = angmom[i];
    const double *__restrict fi = f[i], *__restrict ti = torque[i];
    double *__restrict wi = omega[i];
    const double dtfm = dtf / rmass[i];
    for (int k = 0; k < 3; k++) vi[k] += dtfm * fi[k];
    // L stays in registers (a vector reload of freshly stored scalars stalls)
    const double l0 = li[0] + dtf * ti[0], l1 = li[1] + dtf * ti[1], l2 = li[2] + dtf * ti[2];
    li[0] = l0; li[1] = l1; li[2] = l2;
    if (l0 == 0.0 && l1 == 0.0 && l2 == 0.0) {
      wi[0] = wi[1] = wi[2] = 0.0;
      continue;
    }
    poly_angmom_to_omega_fast(quaternion[i], inertia[i], l0, l1, l2, wi);
  }
}
