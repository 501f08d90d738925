#include "fix_check_timestep_polyhedral.h"

#include <limits.h>
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vector>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_property_global.h"
#include "force.h"
#include "modify.h"
#include "neighbor.h"
#include "tri_mesh.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"
#include "fix_wall_polyhedral.h"
#include "pair_polyhedral_volumetric.h"
#include "poly_contact.h"

using namespace LAMMPS_NS;
using namespace FixConst;

// fix ID group check/timestep/polyhedral nevery fraction_rayleigh fraction_hertz [warn yes|no]
FixCheckTimestepPolyhedral::FixCheckTimestepPolyhedral(LAMMPS *lmp, int narg, char **arg)
    : Fix(lmp, narg, arg), rayleigh_limit(0.0), hertz_limit(0.0), warnings(true), rayleigh_time(0.0),
      hertz_time(0.0), speed(0.0), smallest_radius(0.0), fraction_rayleigh(0.0), fraction_hertz(0.0),
      fraction_skin(0.0)
{
  if (narg != 6 && narg != 8)
    error->all(FLERR, "Fix check/timestep/polyhedral: expected 'nevery fraction_rayleigh fraction_hertz "
                      "[warn yes|no]', as fix check/timestep/gran");
  char *end = NULL;
  const long every = strtol(arg[3], &end, 10);
  if (*end || end == arg[3] || every <= 0 || every > INT_MAX)
    error->all(FLERR, "Fix check/timestep/polyhedral: nevery must be a positive integer");
  nevery = (int) every;
  rayleigh_limit = strtod(arg[4], &end);
  bool bad = *end || end == arg[4] || !(rayleigh_limit > 0.0 && isfinite(rayleigh_limit));
  hertz_limit = strtod(arg[5], &end);
  if (bad || *end || end == arg[5] || !(hertz_limit > 0.0 && isfinite(hertz_limit)))
    error->all(FLERR, "Fix check/timestep/polyhedral: the two fractions must be finite positive numbers");
  if (narg == 8) {
    if (strcmp(arg[6], "warn") != 0 || (strcmp(arg[7], "yes") != 0 && strcmp(arg[7], "no") != 0))
      error->all(FLERR, "Fix check/timestep/polyhedral: unknown keyword; the only one is 'warn yes|no'");
    warnings = strcmp(arg[7], "yes") == 0;
  }
  vector_flag = 1;
  size_vector = 3;
  global_freq = nevery;
  extvector = 0;
}

int FixCheckTimestepPolyhedral::setmask()
{
  return END_OF_STEP;
}

void FixCheckTimestepPolyhedral::init()
{
  if (!atom->shapetype)
    error->all(FLERR, "Fix check/timestep/polyhedral requires atom_style polyhedron (use fix check/timestep/gran "
                      "for spheres)");
  if (!dynamic_cast<PairPolyhedralVolumetric *>(force->pair))
    error->all(FLERR, "Fix check/timestep/polyhedral requires pair_style polyhedral/volumetric");
  const int n = atom->ntypes;
  if (!modify->find_fix_property("youngsModulus", "property/global", "peratomtype", n, 0, style, false) ||
      !modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", n, 0, style, false))
    error->all(FLERR, "Fix check/timestep/polyhedral needs the materials youngsModulus and poissonsRatio "
                      "(fix property/global ... peratomtype)");
}

void FixCheckTimestepPolyhedral::end_of_step()
{
  estimate_times();
  const double dt = update->dt, skin = neighbor->skin;
  fraction_rayleigh = rayleigh_time > 0.0 ? dt / rayleigh_time : 0.0;
  fraction_hertz = hertz_time > 0.0 ? dt / hertz_time : 0.0;
  fraction_skin = skin > 0.0 ? speed * dt / skin : 0.0;
  if (!warnings) return;
  if (fraction_skin >= 0.5) warn("particles may travel %g per time step, more than half the skin %g", speed * dt,
                                 0.5 * skin);
  if (speed * dt > smallest_radius)
    warn("particles may travel %g per time step, more than the smallest volume-equivalent radius %g", speed * dt,
         smallest_radius);
  if (fraction_rayleigh > rayleigh_limit)
    warn("time step is %g %% of the Rayleigh time (limit %g %%)", 100.0 * fraction_rayleigh, 100.0 * rayleigh_limit);
  if (fraction_hertz > hertz_limit)
    warn("time step is %g %% of the Hertz time (limit %g %%)", 100.0 * fraction_hertz, 100.0 * hertz_limit);
}

void FixCheckTimestepPolyhedral::warn(const char *format, double value, double limit)
{
  if (comm->me != 0) return;
  char text[256], message[300];
  snprintf(text, sizeof text, format, value, limit);
  snprintf(message, sizeof message, "Fix check/timestep/polyhedral: %s", text);
  error->warning(FLERR, message);
}

// The fastest wall: the vertices of the moving meshes of every fix wall/polyhedral.
double FixCheckTimestepPolyhedral::largest_mesh_speed() const
{
  double fastest = 0.0;
  for (int f = 0; f < modify->nfix; f++) {
    FixWallPolyhedral *wall = dynamic_cast<FixWallPolyhedral *>(modify->fix[f]);
    if (!wall) continue;
    for (size_t m = 0; m < wall->wall_meshes().size(); m++) {
      TriMesh *mesh = wall->wall_meshes()[m]->triMesh();
      if (!mesh->isMoving()) continue;
      MultiVectorContainer<double, 3, 3> *velocity =
          mesh->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v");
      if (!velocity) continue;
      double ***v = velocity->begin();
      for (int t = 0; t < mesh->sizeLocal(); t++)
        for (int c = 0; c < 3; c++) fastest = fmax(fastest, sqrt(v[t][c][0] * v[t][c][0] + v[t][c][1] * v[t][c][1] +
                                                                 v[t][c][2] * v[t][c][2]));
    }
  }
  double all = 0.0;
  MPI_Allreduce(&fastest, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  return all;
}

// LIGGGHTS' estimates (fix check/timestep/gran) with each polyhedron's volume-equivalent radius r and mass
// m = density x volume: the Rayleigh time pi r sqrt(rho / G) / (0.1631 nu + 0.8766), and the Hertz time of
// the particle against its own kind, 2.87 (m^2 / (r/2 E*^2 v))^(1/5), with E* = E / (2 (1 - nu^2)) and v the
// larger of twice the fastest particle's speed and its speed plus the fastest wall's.
void FixCheckTimestepPolyhedral::estimate_times()
{
  FixPropertyGlobal *youngs = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("youngsModulus", "property/global", "peratomtype", atom->ntypes, 0, style));
  FixPropertyGlobal *poisson = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", atom->ntypes, 0, style));
  double rayleigh = 1e300, smallest = 1e300, fastest = 0.0;
  const int nlocal = atom->nlocal;
  std::vector<double> radius(nlocal > 0 ? nlocal : 1, 0.0), mass(radius);
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, atom->shapetype[i]);
    if (!shape_template) continue;
    const double volume = shape_template->shape().volume;
    radius[i] = cbrt(3.0 * volume / (4.0 * M_PI));
    mass[i] = atom->density[i] * volume;
    const int t = atom->type[i];
    const double e = youngs->compute_vector(t - 1), nu = poisson->compute_vector(t - 1);
    rayleigh = fmin(rayleigh, poly_rayleigh_time(radius[i], atom->density[i], e, nu));
    smallest = fmin(smallest, radius[i]);
    double *v = atom->v[i];
    fastest = fmax(fastest, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  double local[2] = {rayleigh, smallest}, global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, world);
  double fastest_all = 0.0;
  MPI_Allreduce(&fastest, &fastest_all, 1, MPI_DOUBLE, MPI_MAX, world);
  rayleigh_time = global[0] < 1e300 ? global[0] : 0.0;
  smallest_radius = global[1];
  speed = fmax(2.0 * fastest_all, fastest_all + largest_mesh_speed());

  double hertz = 1e300;
  for (int i = 0; i < nlocal && speed > 0.0; i++) {
    if (!(atom->mask[i] & groupbit) || !(radius[i] > 0.0)) continue;
    const int t = atom->type[i];
    const double e = youngs->compute_vector(t - 1), nu = poisson->compute_vector(t - 1);
    // As LIGGGHTS: the particle's whole mass (not the pair's reduced mass) and half its radius.
    hertz = fmin(hertz, poly_hertz_time(mass[i], 0.5 * radius[i], e / (2.0 * (1.0 - nu * nu)), speed));
  }
  double hertz_all = 1e300;
  MPI_Allreduce(&hertz, &hertz_all, 1, MPI_DOUBLE, MPI_MIN, world);
  hertz_time = hertz_all < 1e300 ? hertz_all : 0.0;
}

double FixCheckTimestepPolyhedral::compute_vector(int n)
{
  if (n == 0) return fraction_rayleigh;
  if (n == 1) return fraction_hertz;
  if (n == 2) return fraction_skin;
  return 0.0;
}
