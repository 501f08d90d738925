#include "fix_wall_polyhedral.h"

#include <mpi.h>
#include <math.h>
#include <string.h>

#include "atom.h"
#include "error.h"
#include "fix_property_atom.h"
#include "force.h"
#include "modify.h"
#include "update.h"

#include "pair_polyhedral_volumetric.h"
#include "poly_halfspace.h"

using namespace LAMMPS_NS;
using namespace FixConst;

// fix ID group wall/polyhedral [tangential history|off] [damping on|off] primitive type T xplane|yplane|zplane POS
FixWallPolyhedral::FixWallPolyhedral(LAMMPS *lmp, int narg, char **arg)
    : Fix(lmp, narg, arg), wall_type(0), axis(-1), position(0.0), tangential(-1), damping(-1), history_id(NULL),
      history(NULL), pair(NULL), force_summed(false)
{
  if (strcmp(atom->atom_style, "polyhedron") != 0) error->all(FLERR, "Fix wall/polyhedral requires atom_style polyhedron");
  int iarg = 3;
  while (iarg < narg) {
    const char *key = arg[iarg];
    if ((strcmp(key, "tangential") == 0 || strcmp(key, "damping") == 0) && iarg + 1 < narg) {
      const char *value = arg[iarg + 1];
      int *flag = strcmp(key, "tangential") == 0 ? &tangential : &damping;
      const char *on = flag == &tangential ? "history" : "on", *off = "off";
      if (strcmp(value, on) == 0) *flag = 1;
      else if (strcmp(value, off) == 0) *flag = 0;
      else {
        char message[256];
        snprintf(message, sizeof message, "Fix wall/polyhedral: invalid value '%s' for '%s' (%s or %s)", value, key,
                 on, off);
        error->all(FLERR, message);
      }
      iarg += 2;
    } else if (strcmp(key, "primitive") == 0) {
      if (iarg + 4 >= narg || strcmp(arg[iarg + 1], "type") != 0)
        error->all(FLERR, "Fix wall/polyhedral: expected 'primitive type T xplane|yplane|zplane POS'");
      wall_type = force->inumeric(FLERR, arg[iarg + 2]);
      const char *plane = arg[iarg + 3];
      axis = strcmp(plane, "xplane") == 0 ? 0 : strcmp(plane, "yplane") == 0 ? 1 : strcmp(plane, "zplane") == 0 ? 2 : -1;
      if (axis < 0) {
        char message[256];
        snprintf(message, sizeof message,
                 "Fix wall/polyhedral: unknown primitive '%s' (xplane, yplane and zplane are available)", plane);
        error->all(FLERR, message);
      }
      position = force->numeric(FLERR, arg[iarg + 4]);
      iarg += 5;
    } else if (strcmp(key, "mesh") == 0) {
      error->all(FLERR, "Fix wall/polyhedral: mesh walls are not available yet; use 'primitive type T "
                        "xplane|yplane|zplane POS'");
    } else {
      char message[256];
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: unknown keyword '%s' (tangential, damping, primitive)", key);
      error->all(FLERR, message);
    }
  }
  if (axis < 0) error->all(FLERR, "Fix wall/polyhedral: no wall given ('primitive type T zplane POS')");
  if (wall_type < 1 || wall_type > atom->ntypes) error->all(FLERR, "Fix wall/polyhedral: wall type out of range");

  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = 1;
  restart_global = 0;
  for (int k = 0; k < 4; k++) wall_force[k] = wall_force_all[k] = 0.0;

  history_id = new char[strlen(id) + 16];
  sprintf(history_id, "%s_history", id);
}

FixWallPolyhedral::~FixWallPolyhedral()
{
  if (history && modify->find_fix(history_id) >= 0) modify->delete_fix(history_id);
  delete[] history_id;
}

// The per-atom tangential springs, migrating and restarting with the atoms.
void FixWallPolyhedral::post_create()
{
  if (modify->find_fix(history_id) < 0) {
    const char *args[8 + POLY_HISTORY_SIZE] = {history_id, "all", "property/atom", history_id, "vector", "yes",
                                               "no", "no"};
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) args[8 + d] = "0.";
    modify->add_fix(8 + POLY_HISTORY_SIZE, const_cast<char **>(args));
  }
  history = static_cast<FixPropertyAtom *>(modify->fix[modify->find_fix(history_id)]);
}

int FixWallPolyhedral::setmask()
{
  return POST_FORCE;
}

void FixWallPolyhedral::init()
{
  pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (!pair) error->all(FLERR, "Fix wall/polyhedral requires pair_style polyhedral/volumetric (or its /gpu variant)");
  int index = modify->find_fix(history_id);
  if (index < 0) error->all(FLERR, "Fix wall/polyhedral: its history fix was deleted");
  history = static_cast<FixPropertyAtom *>(modify->fix[index]);
  // The wall's own switches decide which materials it needs, whatever the pair style's are.
  use_tangential = tangential < 0 ? pair->tangential_history_on() : tangential;
  use_damping = damping < 0 ? pair->damping_on() : damping;
  PairPolyhedralVolumetric::material_table(lmp, style, use_damping, use_tangential, materials);
}

void FixWallPolyhedral::setup(int)
{
  apply_walls(false);
}

void FixWallPolyhedral::post_force(int)
{
  apply_walls(true);
}

void FixWallPolyhedral::apply_walls(bool advance_history)
{
  double **x = atom->x, **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
  double **quaternion = atom->quaternion, **springs = history->array_atom;
  double *rmass = atom->rmass, *density = atom->density, *radius = atom->radius;
  int *mask = atom->mask, *type = atom->type, *shapetype = atom->shapetype;
  const int nlocal = atom->nlocal;
  const double zero[3] = {0.0, 0.0, 0.0};
  force_summed = false;
  for (int k = 0; k < 4; k++) wall_force[k] = 0.0;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *spring = springs[i];
    // The wall solid is on the far side of the plane from the particle's centre.
    double side = x[i][axis] >= position ? 1.0 : -1.0;
    if (fabs(x[i][axis] - position) >= radius[i]) {
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) spring[d] = 0.0;
      continue;
    }
    double normal[3] = {0.0, 0.0, 0.0};
    normal[axis] = side;
    double rotation[9];
    poly_quat_to_matrix(quaternion[i], rotation);
    poly_overlap_result geometry;
    poly_halfspace_overlap(&pair->shape_view(shapetype[i]), rotation, x[i], normal, side * position, &geometry);
    if (!(geometry.volume > 1e-12 * rmass[i] / density[i]) || !(geometry.depth > 0.0)) {
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) spring[d] = 0.0;
      continue;
    }
    poly_contact_input input;
    poly_contact_input_set_geometry(&input, geometry.volume, geometry.depth, geometry.normal, geometry.centroid);
    // The wall: at rest, infinite mass (0), its "position" the contact point.
    poly_contact_input_set_bodies(&input, x[i], v[i], omega[i], rmass[i], geometry.centroid, zero, zero, 0.0,
                                  update->dt);
    double scratch[POLY_HISTORY_SIZE];
    double *law_history = spring;
    if (!advance_history) {
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) scratch[d] = spring[d];
      law_history = scratch;
    }
    poly_contact_output out;
    poly_contact_evaluate(&input, &materials[type[i] * (atom->ntypes + 1) + wall_type], use_tangential, use_damping, law_history, &out);
    for (int k = 0; k < 3; k++) {
      f[i][k] -= out.force_j[k];
      torque[i][k] += out.torque_i[k];
      wall_force[k] += out.force_j[k];
    }
    wall_force[3] += 1.0;
  }
}

// 1-3: force on the wall, 4: particles touching it (summed over ranks).
double FixWallPolyhedral::compute_vector(int n)
{
  if (!force_summed) {
    MPI_Allreduce(wall_force, wall_force_all, 4, MPI_DOUBLE, MPI_SUM, world);
    force_summed = true;
  }
  return wall_force_all[n];
}
