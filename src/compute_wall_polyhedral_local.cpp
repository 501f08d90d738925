#include "compute_wall_polyhedral_local.h"

#include <stdio.h>
#include <string.h>

#include "atom.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include "fix_wall_polyhedral.h"

using namespace LAMMPS_NS;

// compute ID group wall/polyhedral/local WALL-FIX-ID
ComputeWallPolyhedralLocal::ComputeWallPolyhedralLocal(LAMMPS *lmp, int &iarg, int narg, char **arg)
    : Compute(lmp, iarg, narg, arg), wall_id(NULL), nmax(0), rows(NULL)
{
  if (narg != iarg + 1)
    error->compute_error(FLERR, this, "expected the ID of a fix wall/polyhedral: 'wall/polyhedral/local WALL-ID'");
  wall_id = new char[strlen(arg[iarg]) + 1];
  strcpy(wall_id, arg[iarg]);
  iarg++;
  local_flag = 1;
  size_local_rows = 0;
  size_local_cols = FixWallPolyhedral::kRecordColumns;
}

ComputeWallPolyhedralLocal::~ComputeWallPolyhedralLocal()
{
  FixWallPolyhedral *wall = find_wall();
  if (wall) wall->record_contacts(false);
  delete[] wall_id;
  memory->destroy(rows);
}

FixWallPolyhedral *ComputeWallPolyhedralLocal::find_wall() const
{
  int index = modify->find_fix(wall_id);
  return index >= 0 ? dynamic_cast<FixWallPolyhedral *>(modify->fix[index]) : NULL;
}

void ComputeWallPolyhedralLocal::init()
{
  FixWallPolyhedral *wall = find_wall();
  if (!wall) {
    char message[300];
    snprintf(message, sizeof message, "no fix wall/polyhedral with ID '%s'", wall_id);
    error->compute_error(FLERR, this, message);
  }
  wall->record_contacts(true);
}

void ComputeWallPolyhedralLocal::compute_local()
{
  invoked_local = update->ntimestep;
  FixWallPolyhedral *wall = find_wall();
  if (!wall) error->compute_error(FLERR, this, "its fix wall/polyhedral was deleted");
  if (wall->records_step() != update->ntimestep)
    error->compute_error(FLERR, this, "invoked on a step its wall did not compute (use it from dump local or "
                                      "thermo output during a run)");
  const std::vector<double> &records = wall->recorded_contacts();
  const int columns = FixWallPolyhedral::kRecordColumns;
  const int count = (int)(records.size() / columns);
  if (count > nmax) {
    memory->destroy(rows);
    nmax = count;
    memory->create(rows, nmax, columns, "wall/polyhedral/local:rows");
    array_local = rows;
  }
  int n = 0;
  for (int c = 0; c < count; c++) {
    const double *row = &records[(size_t)c * columns];
    int i = atom->map((int)row[0]);
    if (i < 0 || !(atom->mask[i] & groupbit)) continue;
    for (int k = 0; k < columns; k++) rows[n][k] = row[k];
    n++;
  }
  size_local_rows = n;
  array_local = rows;
}

double ComputeWallPolyhedralLocal::memory_usage()
{
  return (double)nmax * FixWallPolyhedral::kRecordColumns * sizeof(double);
}
