#include "fix_particletemplate_polyhedron.h"

#include <stdlib.h>
#include <string.h>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "random_park.h"

using namespace LAMMPS_NS;

static const char *const kStyle = "particletemplate/polyhedron";

FixParticletemplatePolyhedron::FixParticletemplatePolyhedron(LAMMPS *lmp, int narg, char **arg)
    : Fix(lmp, narg, arg), shape_index_(0), atom_type_(0), density_(0.0), scale_(1.0), file_(NULL), seed_(0)
{
  memset(&shape_, 0, sizeof shape_);
  if (domain->dimension != 3) error->fix_error(FLERR, this, "requires a 3d simulation");
  if (narg < 4) error->fix_error(FLERR, this, "expected: SEED atom_type T density constant RHO file PATH [scale S]");
  // Validated and kept for random orientations at insertion time.
  RanPark seed_check(lmp, arg[3]);
  seed_ = atoi(arg[3]);

  for (int iarg = 4; iarg < narg;) {
    if (strcmp(arg[iarg], "atom_type") == 0) {
      if (iarg + 2 > narg) error->fix_error(FLERR, this, "missing value after 'atom_type'");
      atom_type_ = force->inumeric(FLERR, arg[iarg + 1]);
      if (atom_type_ < 1) error->fix_error(FLERR, this, "invalid atom type (must be >= 1)");
      iarg += 2;
    } else if (strcmp(arg[iarg], "density") == 0) {
      if (iarg + 3 > narg) error->fix_error(FLERR, this, "expected 'density constant RHO'");
      if (strcmp(arg[iarg + 1], "constant") != 0)
        error->fix_error(FLERR, this, "only 'density constant RHO' is supported");
      density_ = force->numeric(FLERR, arg[iarg + 2]);
      if (!(density_ > 0.0)) error->fix_error(FLERR, this, "density must be > 0");
      iarg += 3;
    } else if (strcmp(arg[iarg], "file") == 0) {
      if (iarg + 2 > narg) error->fix_error(FLERR, this, "missing path after 'file'");
      delete[] file_;
      file_ = new char[strlen(arg[iarg + 1]) + 1];
      strcpy(file_, arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "scale") == 0) {
      if (iarg + 2 > narg) error->fix_error(FLERR, this, "missing value after 'scale'");
      scale_ = force->numeric(FLERR, arg[iarg + 1]);
      if (!(scale_ > 0.0)) error->fix_error(FLERR, this, "scale must be > 0");
      iarg += 2;
    } else {
      error->fix_error(FLERR, this, "unknown keyword", arg[iarg]);
    }
  }
  if (atom_type_ == 0) error->fix_error(FLERR, this, "missing keyword 'atom_type'");
  if (density_ == 0.0) error->fix_error(FLERR, this, "missing keyword 'density'");
  if (!file_) error->fix_error(FLERR, this, "missing keyword 'file'");
  if (atom_type_ > atom->ntypes) error->fix_error(FLERR, this, "atom type exceeds the number of atom types");

  char message[512];
  if (poly_shape_load(file_, scale_, &shape_, message, sizeof message) != POLY_OK) {
    poly_shape_free(&shape_);
    error->fix_error(FLERR, this, message);
  }
  if (shape_.was_flipped) {
    snprintf(message, sizeof message,
             "Fix %s (id %s): shape mesh '%s' is oriented inward; its triangles were flipped", kStyle, id, file_);
    error->warning(FLERR, message);
  }

  // Numbered after the templates that exist already (this fix is not yet in
  // modify->fix); max + 1 rather than count + 1 so an unfix never reuses a number.
  shape_index_ = 1;
  for (int i = 0; i < modify->nfix; i++)
    if (strcmp(modify->fix[i]->style, kStyle) == 0)
      {
      int existing = static_cast<FixParticletemplatePolyhedron *>(modify->fix[i])->shape_index_;
      if (existing >= shape_index_) shape_index_ = existing + 1;
    }
  print_summary();
}

FixParticletemplatePolyhedron::~FixParticletemplatePolyhedron()
{
  poly_shape_free(&shape_);
  delete[] file_;
}

void FixParticletemplatePolyhedron::print_summary()
{
  if (comm->me != 0) return;
  char line[512];
  snprintf(line, sizeof line,
           "Polyhedral template %s: shape %d from %s (scale %g): %d triangles, %d vertices, "
           "volume %.10g, bounding radius %.10g, principal moments/density %.6g %.6g %.6g\n",
           id, shape_index_, file_, scale_, shape_.num_triangles, shape_.num_vertices, shape_.volume,
           shape_.bounding_radius, shape_.principal_moments[0], shape_.principal_moments[1],
           shape_.principal_moments[2]);
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
}

FixParticletemplatePolyhedron *FixParticletemplatePolyhedron::find(LAMMPS *lmp, int shape_index)
{
  for (int i = 0; i < lmp->modify->nfix; i++) {
    Fix *fix = lmp->modify->fix[i];
    if (strcmp(fix->style, kStyle) == 0) {
      FixParticletemplatePolyhedron *candidate = static_cast<FixParticletemplatePolyhedron *>(fix);
      if (candidate->shape_index_ == shape_index) return candidate;
    }
  }
  return NULL;
}

FixParticletemplatePolyhedron *FixParticletemplatePolyhedron::find(LAMMPS *lmp, const char *fix_id)
{
  int ifix = lmp->modify->find_fix(fix_id);
  if (ifix < 0 || strcmp(lmp->modify->fix[ifix]->style, kStyle) != 0) return NULL;
  return static_cast<FixParticletemplatePolyhedron *>(lmp->modify->fix[ifix]);
}

int FixParticletemplatePolyhedron::count(LAMMPS *lmp)
{
  int n = 0;
  for (int i = 0; i < lmp->modify->nfix; i++)
    if (strcmp(lmp->modify->fix[i]->style, kStyle) == 0) n++;
  return n;
}
