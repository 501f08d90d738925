#include "atom_vec_polyhedron.h"
#include "compute_pair_polyhedral_local.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "domain_wedge.h"
#include "error.h"
#include "polyhedral_input.h"
#include "fix.h"
#include "memory.h"
#include "modify.h"

#include "fix_particletemplate_polyhedron.h"

using namespace LAMMPS_NS;

#define DELTA 10000

// Sizes of the communicated records; they must match the pack/unpack pairs below.
static const int kForwardSize = 7;         // x, quaternion
static const int kBorderSize = 17;         // x, tag, type, mask, state
static const int kStateSize = 17;          // radius density rmass omega angmom quat shapetype inertia
static const int kExchangeBaseSize = 1 + 10 + kStateSize;
static const int kRestartExtraSize = 1;     // the template's fingerprint

AtomVecPolyhedron::AtomVecPolyhedron(LAMMPS *lmp) : AtomVec(lmp), check_restart_masses(false)
{
  molecular = 0;
  comm_x_only = 0;  // orientation travels with positions
  comm_f_only = 0;  // torque travels with forces
  size_forward = kForwardSize;
  size_reverse = 6;
  size_border = kBorderSize;
  size_velocity = 9;  // border_vel adds v, omega, angmom
  size_data_atom = 11;
  size_data_vel = 7;
  xcol_data = 5;

  atom->sphere_flag = 0;
  atom->radius_flag = atom->rmass_flag = atom->omega_flag = atom->density_flag = 1;
  atom->torque_flag = atom->angmom_flag = 1;
  // atom->shapetype holds our template number, but shapetype_flag stays 0:
  // LIGGGHTS reads that flag as "superquadric" in fix wall/gran and elsewhere.
  atom->shapetype_flag = 0;
}

void AtomVecPolyhedron::init()
{
  AtomVec::init();
  if (domain->dimension != 3) error->all(FLERR, "atom_style polyhedron requires a 3d simulation");
  if (dynamic_cast<DomainWedge *>(domain)) error->all(FLERR, "atom_style polyhedron does not support wedge domains");
  check_periodic_box();
  check_restart_fingerprints();
  for (int i = 0; i < atom->nlocal; i++) resolve_shape(i);
  check_restart_masses = false;
  // After uncompute, no compute pair/polyhedral/local may be left for init to do this.
  ComputePairPolyhedralLocal::drop_destroyed_recorders(lmp);
}

// A particle at least as wide as a periodic box length overlaps its own image
// (the pair style would push it against itself). The bounding diameter bounds
// the width in every orientation; every template is checked, as insertion may
// use any of them.
void AtomVecPolyhedron::check_periodic_box()
{
  static const char axes[3] = {'x', 'y', 'z'};
  for (int i = 0; i < modify->nfix; i++) {
    Fix *fix = modify->fix[i];
    if (!fix || strcmp(fix->style, "particletemplate/polyhedron") != 0) continue;
    FixParticletemplatePolyhedron *shape_template = static_cast<FixParticletemplatePolyhedron *>(fix);
    double diameter = 2.0 * shape_template->shape().bounding_radius;
    for (int k = 0; k < 3; k++) {
      if (!domain->periodicity[k] || domain->prd[k] > diameter) continue;
      char message[768];
      snprintf(message, sizeof message,
               "Periodic box length %g along %c is not larger than the bounding diameter %g of the shape of "
               "fix particletemplate/polyhedron '%s' (file '%s', scale %g): a particle could touch its own "
               "periodic image; make the box longer or the shape smaller",
               domain->prd[k], axes[k], diameter, shape_template->id, shape_template->file(),
               shape_template->scale());
      error->all(FLERR, message);
    }
  }
}

// A template of the same volume but another mesh or scale passes the mass
// check; the fingerprint stored with each particle does not.
void AtomVecPolyhedron::check_restart_fingerprints()
{
  std::map<int, double> stored;
  stored.swap(restart_fingerprints);
  for (std::map<int, double>::const_iterator s = stored.begin(); s != stored.end(); ++s) {
    FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, s->first);
    if (!shape_template || s->second == 0.0) continue;  // resolve_shape reports a missing template
    if (shape_template->fingerprint() != s->second) {
      char message[768];
      snprintf(message, sizeof message,
               "Restart file: shape %d does not match shape %d of fix particletemplate/polyhedron '%s' "
               "(file '%s', scale %g): the particles were written with another mesh or scale; define the "
               "templates of the run that wrote the restart, with the same files and scales, in the same order",
               s->first, s->first, shape_template->id, shape_template->file(), shape_template->scale());
      error->one(FLERR, message);
    }
  }
}

void AtomVecPolyhedron::resolve_shape(int i)
{
  FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, shapetype[i]);
  if (!shape_template) {
    char message[256];
    snprintf(message, sizeof message,
             "Particle %d has shape %d, but %d fix particletemplate/polyhedron are defined "
             "(define the templates of the run that wrote the data, in the same order)",
             tag[i], shapetype[i], FixParticletemplatePolyhedron::count(lmp));
    error->one(FLERR, message);
  }
  const poly_shape &shape = shape_template->shape();
  if (!shape_template->gives_usable_mass(density[i])) {
    char message[256];
    snprintf(message, sizeof message,
             "Particle %d: density %g gives shape %d (template '%s', volume %g) no finite positive mass and inertia",
             tag[i], density[i], shapetype[i], shape_template->id, shape.volume);
    error->one(FLERR, message);
  }
  double mass = density[i] * shape.volume;
  // Density is authoritative (`set density` may have changed it); a mass read
  // from a restart file must match, or the templates are not those of the run
  // that wrote it.
  if (check_restart_masses && fabs(rmass[i] - mass) > 1e-9 * mass) {
    char message[256];
    snprintf(message, sizeof message,
             "Particle %d: stored mass %g does not match shape %d (template '%s', density %g gives %g); "
             "templates must be defined in the order of the run that wrote the data",
             tag[i], rmass[i], shapetype[i], shape_template->id, density[i], mass);
    error->one(FLERR, message);
  }
  rmass[i] = mass;
  radius[i] = shape.bounding_radius;
  for (int k = 0; k < 3; k++) inertia[i][k] = density[i] * shape.principal_moments[k];
}

void AtomVecPolyhedron::grow(int n)
{
  if (n == 0) nmax += DELTA;
  else nmax = n;
  atom->nmax = nmax;
  if (nmax < 0 || nmax > MAXSMALLINT) error->one(FLERR, "Per-processor system is too big");

  tag = memory->grow(atom->tag, nmax, "atom:tag");
  type = memory->grow(atom->type, nmax, "atom:type");
  mask = memory->grow(atom->mask, nmax, "atom:mask");
  image = memory->grow(atom->image, nmax, "atom:image");
  x = memory->grow(atom->x, nmax, 3, "atom:x");
  v = memory->grow(atom->v, nmax, 3, "atom:v");
  f = memory->grow(atom->f, nmax * comm->nthreads, 3, "atom:f");

  radius = memory->grow(atom->radius, nmax, "atom:radius");
  density = memory->grow(atom->density, nmax, "atom:density");
  rmass = memory->grow(atom->rmass, nmax, "atom:rmass");
  omega = memory->grow(atom->omega, nmax, 3, "atom:omega");
  angmom = memory->grow(atom->angmom, nmax, 3, "atom:angmom");
  torque = memory->grow(atom->torque, nmax * comm->nthreads, 3, "atom:torque");
  quaternion = memory->grow(atom->quaternion, nmax, 4, "atom:quaternion");
  inertia = memory->grow(atom->inertia, nmax, 3, "atom:inertia");
  shapetype = memory->grow(atom->shapetype, nmax, "atom:shapetype");

  for (int iextra = 0; iextra < atom->nextra_grow; iextra++)
    modify->fix[atom->extra_grow[iextra]]->grow_arrays(nmax);
}

void AtomVecPolyhedron::grow_reset()
{
  tag = atom->tag; type = atom->type; mask = atom->mask; image = atom->image;
  x = atom->x; v = atom->v; f = atom->f;
  radius = atom->radius; density = atom->density; rmass = atom->rmass;
  omega = atom->omega; angmom = atom->angmom; torque = atom->torque;
  quaternion = atom->quaternion; inertia = atom->inertia; shapetype = atom->shapetype;
}

void AtomVecPolyhedron::copy(int i, int j, int delflag)
{
  tag[j] = tag[i]; type[j] = type[i]; mask[j] = mask[i]; image[j] = image[i];
  for (int k = 0; k < 3; k++) {
    x[j][k] = x[i][k]; v[j][k] = v[i][k];
    omega[j][k] = omega[i][k]; angmom[j][k] = angmom[i][k]; inertia[j][k] = inertia[i][k];
  }
  for (int k = 0; k < 4; k++) quaternion[j][k] = quaternion[i][k];
  radius[j] = radius[i]; density[j] = density[i]; rmass[j] = rmass[i];
  shapetype[j] = shapetype[i];

  for (int iextra = 0; iextra < atom->nextra_grow; iextra++)
    modify->fix[atom->extra_grow[iextra]]->copy_arrays(i, j, delflag);
}

// Periodic image shift of a ghost copy in forward communication (box coordinates).
void AtomVecPolyhedron::shift_for(int pbc_flag, int *pbc, double shift[3])
{
  shift[0] = shift[1] = shift[2] = 0.0;
  if (!pbc_flag) return;
  if (domain->triclinic == 0) {
    shift[0] = pbc[0] * domain->xprd;
    shift[1] = pbc[1] * domain->yprd;
    shift[2] = pbc[2] * domain->zprd;
  } else {
    shift[0] = pbc[0] * domain->xprd + pbc[5] * domain->xy + pbc[4] * domain->xz;
    shift[1] = pbc[1] * domain->yprd + pbc[3] * domain->yz;
    shift[2] = pbc[2] * domain->zprd;
  }
}

// Comm::borders works in lamda coordinates for triclinic boxes, where an image
// is one unit along each axis.
void AtomVecPolyhedron::border_shift_for(int pbc_flag, int *pbc, double shift[3])
{
  shift[0] = shift[1] = shift[2] = 0.0;
  if (!pbc_flag) return;
  if (domain->triclinic) {
    for (int k = 0; k < 3; k++) shift[k] = pbc[k];
  } else {
    shift[0] = pbc[0] * domain->xprd;
    shift[1] = pbc[1] * domain->yprd;
    shift[2] = pbc[2] * domain->zprd;
  }
}

int AtomVecPolyhedron::pack_state(int i, double *buf)
{
  int m = 0;
  buf[m++] = radius[i];
  buf[m++] = density[i];
  buf[m++] = rmass[i];
  for (int k = 0; k < 3; k++) buf[m++] = omega[i][k];
  for (int k = 0; k < 3; k++) buf[m++] = angmom[i][k];
  for (int k = 0; k < 4; k++) buf[m++] = quaternion[i][k];
  buf[m++] = ubuf(shapetype[i]).d;
  for (int k = 0; k < 3; k++) buf[m++] = inertia[i][k];
  return m;
}

int AtomVecPolyhedron::unpack_state(int i, const double *buf)
{
  int m = 0;
  radius[i] = buf[m++];
  density[i] = buf[m++];
  rmass[i] = buf[m++];
  for (int k = 0; k < 3; k++) omega[i][k] = buf[m++];
  for (int k = 0; k < 3; k++) angmom[i][k] = buf[m++];
  for (int k = 0; k < 4; k++) quaternion[i][k] = buf[m++];
  shapetype[i] = (int) ubuf(buf[m++]).i;
  for (int k = 0; k < 3; k++) inertia[i][k] = buf[m++];
  return m;
}

int AtomVecPolyhedron::pack_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  double shift[3];
  shift_for(pbc_flag, pbc, shift);
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    int j = list[ii];
    for (int k = 0; k < 3; k++) buf[m++] = x[j][k] + shift[k];
    for (int k = 0; k < 4; k++) buf[m++] = quaternion[j][k];
  }
  return m;
}

int AtomVecPolyhedron::pack_comm_vel(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  double shift[3], velocity_shift[3] = {0.0, 0.0, 0.0};
  shift_for(pbc_flag, pbc, shift);
  if (pbc_flag && deform_vremap) {
    velocity_shift[0] = pbc[0] * h_rate[0] + pbc[5] * h_rate[5] + pbc[4] * h_rate[4];
    velocity_shift[1] = pbc[1] * h_rate[1] + pbc[3] * h_rate[3];
    velocity_shift[2] = pbc[2] * h_rate[2];
  }
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    int j = list[ii];
    bool remap = (mask[j] & deform_groupbit) != 0;
    for (int k = 0; k < 3; k++) buf[m++] = x[j][k] + shift[k];
    for (int k = 0; k < 4; k++) buf[m++] = quaternion[j][k];
    for (int k = 0; k < 3; k++) buf[m++] = v[j][k] + (remap ? velocity_shift[k] : 0.0);
    for (int k = 0; k < 3; k++) buf[m++] = omega[j][k];
  }
  return m;
}

void AtomVecPolyhedron::unpack_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int k = 0; k < 3; k++) x[i][k] = buf[m++];
    for (int k = 0; k < 4; k++) quaternion[i][k] = buf[m++];
  }
}

void AtomVecPolyhedron::unpack_comm_vel(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int k = 0; k < 3; k++) x[i][k] = buf[m++];
    for (int k = 0; k < 4; k++) quaternion[i][k] = buf[m++];
    for (int k = 0; k < 3; k++) v[i][k] = buf[m++];
    for (int k = 0; k < 3; k++) omega[i][k] = buf[m++];
  }
}

int AtomVecPolyhedron::pack_reverse(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int k = 0; k < 3; k++) buf[m++] = f[i][k];
    for (int k = 0; k < 3; k++) buf[m++] = torque[i][k];
  }
  return m;
}

void AtomVecPolyhedron::unpack_reverse(int n, int *list, double *buf)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    int j = list[ii];
    for (int k = 0; k < 3; k++) f[j][k] += buf[m++];
    for (int k = 0; k < 3; k++) torque[j][k] += buf[m++];
  }
}

int AtomVecPolyhedron::pack_border(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  double shift[3];
  border_shift_for(pbc_flag, pbc, shift);
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    int j = list[ii];
    for (int k = 0; k < 3; k++) buf[m++] = x[j][k] + shift[k];
    buf[m++] = ubuf(tag[j]).d;
    buf[m++] = ubuf(type[j]).d;
    buf[m++] = ubuf(mask[j]).d;
    buf[m++] = radius[j];
    buf[m++] = density[j];
    buf[m++] = rmass[j];
    for (int k = 0; k < 4; k++) buf[m++] = quaternion[j][k];
    buf[m++] = ubuf(shapetype[j]).d;
    for (int k = 0; k < 3; k++) buf[m++] = inertia[j][k];
  }
  for (int iextra = 0; iextra < atom->nextra_border; iextra++)
    m += modify->fix[atom->extra_border[iextra]]->pack_border(n, list, &buf[m]);
  return m;
}

int AtomVecPolyhedron::pack_border_vel(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  double shift[3], velocity_shift[3] = {0.0, 0.0, 0.0};
  border_shift_for(pbc_flag, pbc, shift);
  if (pbc_flag && deform_vremap) {
    velocity_shift[0] = pbc[0] * h_rate[0] + pbc[5] * h_rate[5] + pbc[4] * h_rate[4];
    velocity_shift[1] = pbc[1] * h_rate[1] + pbc[3] * h_rate[3];
    velocity_shift[2] = pbc[2] * h_rate[2];
  }
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    int j = list[ii];
    bool remap = (mask[j] & deform_groupbit) != 0;
    for (int k = 0; k < 3; k++) buf[m++] = x[j][k] + shift[k];
    buf[m++] = ubuf(tag[j]).d;
    buf[m++] = ubuf(type[j]).d;
    buf[m++] = ubuf(mask[j]).d;
    buf[m++] = radius[j];
    buf[m++] = density[j];
    buf[m++] = rmass[j];
    for (int k = 0; k < 4; k++) buf[m++] = quaternion[j][k];
    buf[m++] = ubuf(shapetype[j]).d;
    for (int k = 0; k < 3; k++) buf[m++] = inertia[j][k];
    for (int k = 0; k < 3; k++) buf[m++] = v[j][k] + (remap ? velocity_shift[k] : 0.0);
    for (int k = 0; k < 3; k++) buf[m++] = omega[j][k];
    for (int k = 0; k < 3; k++) buf[m++] = angmom[j][k];
  }
  for (int iextra = 0; iextra < atom->nextra_border; iextra++)
    m += modify->fix[atom->extra_border[iextra]]->pack_border(n, list, &buf[m]);
  return m;
}

void AtomVecPolyhedron::unpack_border(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    if (i == nmax) grow(0);
    for (int k = 0; k < 3; k++) x[i][k] = buf[m++];
    tag[i] = (int) ubuf(buf[m++]).i;
    type[i] = (int) ubuf(buf[m++]).i;
    mask[i] = (int) ubuf(buf[m++]).i;
    radius[i] = buf[m++];
    density[i] = buf[m++];
    rmass[i] = buf[m++];
    for (int k = 0; k < 4; k++) quaternion[i][k] = buf[m++];
    shapetype[i] = (int) ubuf(buf[m++]).i;
    for (int k = 0; k < 3; k++) inertia[i][k] = buf[m++];
  }
  for (int iextra = 0; iextra < atom->nextra_border; iextra++)
    m += modify->fix[atom->extra_border[iextra]]->unpack_border(n, first, &buf[m]);
}

void AtomVecPolyhedron::unpack_border_vel(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    if (i == nmax) grow(0);
    for (int k = 0; k < 3; k++) x[i][k] = buf[m++];
    tag[i] = (int) ubuf(buf[m++]).i;
    type[i] = (int) ubuf(buf[m++]).i;
    mask[i] = (int) ubuf(buf[m++]).i;
    radius[i] = buf[m++];
    density[i] = buf[m++];
    rmass[i] = buf[m++];
    for (int k = 0; k < 4; k++) quaternion[i][k] = buf[m++];
    shapetype[i] = (int) ubuf(buf[m++]).i;
    for (int k = 0; k < 3; k++) inertia[i][k] = buf[m++];
    for (int k = 0; k < 3; k++) v[i][k] = buf[m++];
    for (int k = 0; k < 3; k++) omega[i][k] = buf[m++];
    for (int k = 0; k < 3; k++) angmom[i][k] = buf[m++];
  }
  for (int iextra = 0; iextra < atom->nextra_border; iextra++)
    m += modify->fix[atom->extra_border[iextra]]->unpack_border(n, first, &buf[m]);
}

int AtomVecPolyhedron::pack_exchange(int i, double *buf)
{
  int m = 1;
  for (int k = 0; k < 3; k++) buf[m++] = x[i][k];
  for (int k = 0; k < 3; k++) buf[m++] = v[i][k];
  buf[m++] = ubuf(tag[i]).d;
  buf[m++] = ubuf(type[i]).d;
  buf[m++] = ubuf(mask[i]).d;
  buf[m++] = ubuf(image[i]).d;
  m += pack_state(i, &buf[m]);
  for (int iextra = 0; iextra < atom->nextra_grow; iextra++)
    m += modify->fix[atom->extra_grow[iextra]]->pack_exchange(i, &buf[m]);
  buf[0] = m;
  return m;
}

int AtomVecPolyhedron::unpack_exchange(double *buf)
{
  int nlocal = atom->nlocal;
  if (nlocal == nmax) grow(0);
  int m = 1;
  for (int k = 0; k < 3; k++) x[nlocal][k] = buf[m++];
  for (int k = 0; k < 3; k++) v[nlocal][k] = buf[m++];
  tag[nlocal] = (int) ubuf(buf[m++]).i;
  type[nlocal] = (int) ubuf(buf[m++]).i;
  mask[nlocal] = (int) ubuf(buf[m++]).i;
  image[nlocal] = (tagint) ubuf(buf[m++]).i;
  m += unpack_state(nlocal, &buf[m]);
  for (int iextra = 0; iextra < atom->nextra_grow; iextra++)
    m += modify->fix[atom->extra_grow[iextra]]->unpack_exchange(nlocal, &buf[m]);
  atom->nlocal++;
  return m;
}

int AtomVecPolyhedron::size_restart()
{
  int nlocal = atom->nlocal;
  int n = (kExchangeBaseSize + kRestartExtraSize) * nlocal;
  for (int iextra = 0; iextra < atom->nextra_restart; iextra++)
    for (int i = 0; i < nlocal; i++) n += modify->fix[atom->extra_restart[iextra]]->size_restart(i);
  return n;
}

int AtomVecPolyhedron::pack_restart(int i, double *buf)
{
  int m = 1;
  for (int k = 0; k < 3; k++) buf[m++] = x[i][k];
  buf[m++] = ubuf(tag[i]).d;
  buf[m++] = ubuf(type[i]).d;
  buf[m++] = ubuf(mask[i]).d;
  buf[m++] = ubuf(image[i]).d;
  for (int k = 0; k < 3; k++) buf[m++] = v[i][k];
  m += pack_state(i, &buf[m]);
  FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, shapetype[i]);
  buf[m++] = shape_template ? shape_template->fingerprint() : 0.0;
  for (int iextra = 0; iextra < atom->nextra_restart; iextra++)
    m += modify->fix[atom->extra_restart[iextra]]->pack_restart(i, &buf[m]);
  buf[0] = m;
  return m;
}

int AtomVecPolyhedron::unpack_restart(double *buf)
{
  int nlocal = atom->nlocal;
  if (nlocal == nmax) {
    grow(0);
    if (atom->nextra_store) memory->grow(atom->extra, nmax, atom->nextra_store, "atom:extra");
  }
  int m = 1;
  for (int k = 0; k < 3; k++) x[nlocal][k] = buf[m++];
  tag[nlocal] = (int) ubuf(buf[m++]).i;
  type[nlocal] = (int) ubuf(buf[m++]).i;
  mask[nlocal] = (int) ubuf(buf[m++]).i;
  image[nlocal] = (tagint) ubuf(buf[m++]).i;
  for (int k = 0; k < 3; k++) v[nlocal][k] = buf[m++];
  m += unpack_state(nlocal, &buf[m]);
  restart_fingerprints[shapetype[nlocal]] = buf[m++];
  check_restart_masses = true;

  double **extra = atom->extra;
  if (atom->nextra_store) {
    int size = static_cast<int>(buf[0]) - m;
    for (int i = 0; i < size; i++) extra[nlocal][i] = buf[m++];
  }
  atom->nlocal++;
  return m;
}

// create_atoms makes particles without a shape; init() then reports them.
void AtomVecPolyhedron::create_atom(int itype, double *coord)
{
  int nlocal = atom->nlocal;
  if (nlocal == nmax) grow(0);
  tag[nlocal] = 0;
  type[nlocal] = itype;
  mask[nlocal] = 1;
  image[nlocal] = ((tagint) IMGMAX << IMG2BITS) | ((tagint) IMGMAX << IMGBITS) | IMGMAX;
  for (int k = 0; k < 3; k++) {
    x[nlocal][k] = coord[k];
    v[nlocal][k] = omega[nlocal][k] = angmom[nlocal][k] = inertia[nlocal][k] = 0.0;
  }
  quaternion[nlocal][0] = 1.0;
  quaternion[nlocal][1] = quaternion[nlocal][2] = quaternion[nlocal][3] = 0.0;
  radius[nlocal] = 0.0;
  density[nlocal] = 1.0;
  rmass[nlocal] = 0.0;
  shapetype[nlocal] = 0;
  atom->nlocal++;
}

// Atoms line: atom-ID atom-type shape density x y z quatw quati quatj quatk
void AtomVecPolyhedron::data_atom(double *coord, tagint imagetmp, char **values)
{
  int nlocal = atom->nlocal;
  create_atom(1, coord);
  tag[nlocal] = atoi(values[0]);
  if (tag[nlocal] <= 0) error->one(FLERR, "Invalid atom ID in Atoms section of data file");
  type[nlocal] = atoi(values[1]);
  if (type[nlocal] <= 0 || type[nlocal] > atom->ntypes)
    error->one(FLERR, "Invalid atom type in Atoms section of data file");
  // Our columns read whole and finite (atof would take "2500x" as 2500, "1e400" as inf, "1.7" as shape 1).
  char *end = NULL;
  const long shape = strtol(values[2], &end, 10);
  if (*end || end == values[2] || shape <= 0 || shape > INT_MAX)
    error->one(FLERR, "Invalid shape in Atoms section of data file (must be an integer >= 1)");
  shapetype[nlocal] = (int) shape;
  if (!polyhedral_parse_finite(values[3], &density[nlocal]) || !(density[nlocal] > 0.0))
    error->one(FLERR, "Invalid density in Atoms section of data file (must be a finite number > 0)");
  double q[4], largest = 0.0;
  for (int k = 0; k < 4; k++) {
    if (!polyhedral_parse_finite(values[7 + k], &q[k]))
      error->one(FLERR, "Invalid quaternion in Atoms section of data file (four finite numbers)");
    largest = fmax(largest, fabs(q[k]));
  }
  if (!(largest > 0.0)) error->one(FLERR, "Invalid quaternion in Atoms section of data file (all zero)");
  // Components near the double range's ends would overflow or vanish when squared: scaled first (other
  // quaternions, write_data's among them, are read exactly as before).
  if (largest > 1e150 || largest < 1e-150)
    for (int k = 0; k < 4; k++) q[k] /= largest;
  double norm = 0.0;
  for (int k = 0; k < 4; k++) norm += q[k] * q[k];
  for (int k = 0; k < 4; k++) quaternion[nlocal][k] = q[k] / sqrt(norm);
  image[nlocal] = imagetmp;
}

// Velocities line: atom-ID vx vy vz Lx Ly Lz (world angular momentum)
void AtomVecPolyhedron::data_vel(int m, char **values)
{
  for (int k = 0; k < 3; k++) {
    v[m][k] = atof(values[k]);
    angmom[m][k] = atof(values[3 + k]);
  }
}

void AtomVecPolyhedron::pack_data(double **buf) { pack_data(buf, 0); }

void AtomVecPolyhedron::pack_data(double **buf, int tag_offset)
{
  for (int i = 0; i < atom->nlocal; i++) {
    buf[i][0] = ubuf(tag[i] + tag_offset).d;
    buf[i][1] = ubuf(type[i]).d;
    buf[i][2] = ubuf(shapetype[i]).d;
    buf[i][3] = density[i];
    for (int k = 0; k < 3; k++) buf[i][4 + k] = x[i][k];
    for (int k = 0; k < 4; k++) buf[i][7 + k] = quaternion[i][k];
    buf[i][11] = ubuf((image[i] & IMGMASK) - IMGMAX).d;
    buf[i][12] = ubuf((image[i] >> IMGBITS & IMGMASK) - IMGMAX).d;
    buf[i][13] = ubuf((image[i] >> IMG2BITS) - IMGMAX).d;
  }
}

void AtomVecPolyhedron::write_data(FILE *fp, int n, double **buf)
{
  for (int i = 0; i < n; i++)
    fprintf(fp, "%d %d %d %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e %d %d %d\n",
            (int) ubuf(buf[i][0]).i, (int) ubuf(buf[i][1]).i, (int) ubuf(buf[i][2]).i, buf[i][3],
            buf[i][4], buf[i][5], buf[i][6], buf[i][7], buf[i][8], buf[i][9], buf[i][10],
            (int) ubuf(buf[i][11]).i, (int) ubuf(buf[i][12]).i, (int) ubuf(buf[i][13]).i);
}

void AtomVecPolyhedron::pack_vel(double **buf) { pack_vel(buf, 0); }

void AtomVecPolyhedron::pack_vel(double **buf, int tag_offset)
{
  for (int i = 0; i < atom->nlocal; i++) {
    buf[i][0] = ubuf(tag[i] + tag_offset).d;
    for (int k = 0; k < 3; k++) {
      buf[i][1 + k] = v[i][k];
      buf[i][4 + k] = angmom[i][k];
    }
  }
}

void AtomVecPolyhedron::write_vel(FILE *fp, int n, double **buf)
{
  for (int i = 0; i < n; i++)
    fprintf(fp, "%d %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e %-1.16e\n", (int) ubuf(buf[i][0]).i,
            buf[i][1], buf[i][2], buf[i][3], buf[i][4], buf[i][5], buf[i][6]);
}

bigint AtomVecPolyhedron::memory_usage()
{
  bigint bytes = 0;
  if (atom->memcheck("tag")) bytes += memory->usage(tag, nmax);
  if (atom->memcheck("type")) bytes += memory->usage(type, nmax);
  if (atom->memcheck("mask")) bytes += memory->usage(mask, nmax);
  if (atom->memcheck("image")) bytes += memory->usage(image, nmax);
  if (atom->memcheck("x")) bytes += memory->usage(x, nmax, 3);
  if (atom->memcheck("v")) bytes += memory->usage(v, nmax, 3);
  if (atom->memcheck("f")) bytes += memory->usage(f, nmax * comm->nthreads, 3);
  if (atom->memcheck("radius")) bytes += memory->usage(radius, nmax);
  if (atom->memcheck("density")) bytes += memory->usage(density, nmax);
  if (atom->memcheck("rmass")) bytes += memory->usage(rmass, nmax);
  if (atom->memcheck("omega")) bytes += memory->usage(omega, nmax, 3);
  if (atom->memcheck("angmom")) bytes += memory->usage(angmom, nmax, 3);
  if (atom->memcheck("torque")) bytes += memory->usage(torque, nmax * comm->nthreads, 3);
  if (atom->memcheck("quaternion")) bytes += memory->usage(quaternion, nmax, 4);
  if (atom->memcheck("inertia")) bytes += memory->usage(inertia, nmax, 3);
  if (atom->memcheck("shapetype")) bytes += memory->usage(shapetype, nmax);
  return bytes;
}
