#include "create_polyhedron.h"

#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "polyhedral_input.h"
#include "force.h"
#include "group.h"

#include "atom_vec_polyhedron.h"
#include "fix_particletemplate_polyhedron.h"
#include "poly_rigid.h"

using namespace LAMMPS_NS;

CreatePolyhedron::CreatePolyhedron(LAMMPS *lmp) : Pointers(lmp) {}

// A finite number, all of `text`, or an error naming what it was for
// (LIGGGHTS' force->numeric says only "Expected floating point parameter").
static double number(Error *error, const char *what, const char *text)
{
  return polyhedral_finite_number(error, "create_polyhedron", what, text);
}

void CreatePolyhedron::command(int narg, char **arg)
{
  if (!domain->box_exist) error->all(FLERR, "create_polyhedron command before simulation box is defined");
  if (strcmp(atom->atom_style, "polyhedron") != 0)
    error->all(FLERR, "create_polyhedron requires atom_style polyhedron");
  if (narg < 4) error->all(FLERR, "Illegal create_polyhedron command: expected TEMPLATE-ID x y z [quat w i j k] [vel vx vy vz] [omega wx wy wz]");

  FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, arg[0]);
  if (!shape_template) {
    char message[256];
    snprintf(message, sizeof message, "create_polyhedron: '%s' is not the ID of a fix particletemplate/polyhedron", arg[0]);
    error->all(FLERR, message);
  }

  double position[3], quat[4] = {1.0, 0.0, 0.0, 0.0}, velocity[3] = {0.0, 0.0, 0.0}, omega[3] = {0.0, 0.0, 0.0};
  static const char *const position_names[3] = {"position x", "position y", "position z"};
  for (int k = 0; k < 3; k++) position[k] = number(error, position_names[k], arg[1 + k]);
  bool given_quat = false, given_vel = false, given_omega = false;
  for (int iarg = 4; iarg < narg;) {
    bool *given = strcmp(arg[iarg], "quat") == 0 ? &given_quat
                  : strcmp(arg[iarg], "vel") == 0 ? &given_vel
                  : strcmp(arg[iarg], "omega") == 0 ? &given_omega : NULL;
    if (given && *given) {
      char message[256];
      snprintf(message, sizeof message, "create_polyhedron: '%s' given twice", arg[iarg]);
      error->all(FLERR, message);
    }
    if (given) *given = true;
    if (strcmp(arg[iarg], "quat") == 0) {
      if (iarg + 5 > narg) error->all(FLERR, "create_polyhedron: 'quat' needs 4 values w i j k");
      double largest = 0.0;
      for (int k = 0; k < 4; k++) {
        quat[k] = number(error, "'quat'", arg[iarg + 1 + k]);
        largest = fmax(largest, fabs(quat[k]));
      }
      if (!(largest > 0.0)) error->all(FLERR, "create_polyhedron: 'quat' must not be zero");
      // Components near the double range's ends would overflow or vanish when squared (1e200 1e200 0 0 came out
      // as the identity): scaled first; other quaternions exactly as before.
      if (largest > 1e150 || largest < 1e-150)
        for (int k = 0; k < 4; k++) quat[k] /= largest;
      poly_quat_normalize(quat);
      iarg += 5;
    } else if (strcmp(arg[iarg], "vel") == 0 || strcmp(arg[iarg], "omega") == 0) {
      double *target = strcmp(arg[iarg], "vel") == 0 ? velocity : omega;
      if (iarg + 4 > narg) error->all(FLERR, "create_polyhedron: 'vel' and 'omega' need 3 values");
      for (int k = 0; k < 3; k++) target[k] = number(error, target == velocity ? "'vel'" : "'omega'", arg[iarg + 1 + k]);
      iarg += 4;
    } else {
      char message[256];
      snprintf(message, sizeof message, "create_polyhedron: unknown keyword '%s'", arg[iarg]);
      error->all(FLERR, message);
    }
  }

  // Periodic positions are wrapped into the box; the owner is the rank whose
  // sub-domain holds the wrapped point (half-open, so exactly one rank).
  tagint image = ((tagint) IMGMAX << IMG2BITS) | ((tagint) IMGMAX << IMGBITS) | IMGMAX;
  domain->remap(position, image);
  double *lo = domain->sublo, *hi = domain->subhi;
  if (domain->triclinic) error->all(FLERR, "create_polyhedron does not support triclinic boxes");
  // Half-open sub-domains, as LIGGGHTS' own exchange keeps them: exactly one
  // owner, and a point on the upper face of a fixed boundary belongs to nobody
  // (LIGGGHTS would drop it silently at the first exchange).
  bool mine = true;
  for (int k = 0; k < 3; k++) mine = mine && position[k] >= lo[k] && position[k] < hi[k];
  int created = 0;
  if (mine) {
    AtomVecPolyhedron *avec = static_cast<AtomVecPolyhedron *>(atom->avec);
    avec->create_atom(shape_template->particle_type(), position);
    int i = atom->nlocal - 1;
    atom->image[i] = image;
    atom->mask[i] = 1 | group->bitmask[group->find("all")];
    atom->shapetype[i] = shape_template->shape_index();
    atom->density[i] = shape_template->density();
    for (int k = 0; k < 4; k++) atom->quaternion[i][k] = quat[k];
    avec->resolve_shape(i);
    for (int k = 0; k < 3; k++) {
      atom->v[i][k] = velocity[k];
      atom->omega[i][k] = omega[k];
    }
    poly_omega_to_angmom(atom->quaternion[i], atom->inertia[i], omega, atom->angmom[i]);
    created = 1;
  }

  int created_total = 0;
  MPI_Allreduce(&created, &created_total, 1, MPI_INT, MPI_SUM, world);
  if (created_total != 1) {
    char message[256];
    snprintf(message, sizeof message,
             "create_polyhedron: position (%g, %g, %g) is outside the simulation box", position[0], position[1],
             position[2]);
    error->all(FLERR, message);
  }

  bigint nlocal = atom->nlocal;
  MPI_Allreduce(&nlocal, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (atom->tag_enable) atom->tag_extend();
  if (atom->map_style) {
    atom->nghost = 0;
    atom->map_init();
    atom->map_set();
  }
}
