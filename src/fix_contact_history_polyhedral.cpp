#include "fix_contact_history_polyhedral.h"

#include <stdlib.h>
#include <string.h>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "pair.h"

#include "pair_polyhedral_volumetric.h"

using namespace LAMMPS_NS;

// Arguments as for fix contacthistory: ID group style dnum name1 newton1 ...
FixContactHistoryPolyhedral::FixContactHistoryPolyhedral(LAMMPS *lmp, int narg, char **arg)
    : FixContactHistory(lmp, narg, arg)
{
  // The base constructor parses the per-value names and newton flags only for
  // its own style name; with ours it stopped after dnum.
  if (narg - iarg_ < 2 * dnum_) error->fix_error(FLERR, this, "need a name and a newton flag per history value");
  newtonflag_ = new int[dnum_];
  history_id_ = (char **) memory->smalloc(dnum_ * sizeof(char *), "contacthistory/polyhedral:history_id");
  for (int d = 0; d < dnum_; d++) {
    history_id_[d] = new char[strlen(arg[iarg_]) + 1];
    strcpy(history_id_[d], arg[iarg_++]);
    newtonflag_[d] = atoi(arg[iarg_++]);
  }
  delete[] style;
  style = new char[strlen("contacthistory") + 1];
  strcpy(style, "contacthistory");
}

void FixContactHistoryPolyhedral::init()
{
  if (atom->tag_enable == 0) error->all(FLERR, "Contact history requires atoms have IDs");
  PairPolyhedralVolumetric *pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (!pair) error->all(FLERR, "Polyhedral contact history exists without pair polyhedral/volumetric");
  pair_gran_ = pair;
  computeflag_ = &pair->computeflag;
  allocate_pages();
}

void FixContactHistoryPolyhedral::pre_exchange()
{
  PairPolyhedralVolumetric *pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (pair) pair->history_to_host();
  FixContactHistory::pre_exchange();
}
