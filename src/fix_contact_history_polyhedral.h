/* Per-contact history of pair polyhedral/volumetric, kept by LIGGGHTS' own
 * contact-history machinery.
 *
 * LIGGGHTS' granular neighbour lists restore each pair's history from the
 * partner arrays of FixContactHistory at every rebuild, and that fix carries
 * the arrays through migration and restart files. The neighbour code looks the
 * fix up by the exact style name "contacthistory", and the stock class binds
 * itself to `pair gran` in init(). This subclass therefore renames itself to
 * "contacthistory" on construction (before LIGGGHTS matches per-atom restart
 * data by ID and style) and binds to our pair style in init(). Before the
 * stock pre_exchange copies the history out of the neighbour list (rebuilds,
 * migration, restart files) it lets the pair style bring the list up to date:
 * the GPU style keeps the history on the device. Everything else is the stock
 * implementation. Created by the pair style, not by users. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_CONTACT_HISTORY_POLYHEDRAL_H
#define LMP_FIX_CONTACT_HISTORY_POLYHEDRAL_H

#include "fix_contact_history.h"

namespace LAMMPS_NS {

class FixContactHistoryPolyhedral : public FixContactHistory {
 public:
  FixContactHistoryPolyhedral(class LAMMPS *, int, char **);
  void init();
  void pre_exchange();

  static const char *fix_id() { return "contacthistory_polyhedral"; }
  static const char *creation_style() { return "contacthistory/polyhedral"; }
};

}

#endif
#endif
