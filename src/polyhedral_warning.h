/* A warning that any rank may meet in the middle of a step (a contact's overlap, a wall's contact slots).
 * LIGGGHTS' Error::warning writes to the rank's screen and log file; every rank has stdout as its screen (none
 * with -screen none), but only rank 0 has the log file, so a warning met on another rank never reached the log
 * (and was printed once per rank that met it). Here a rank raises the warning, and share() (collective) says it
 * once, on rank 0's screen and log, whichever rank met it. */
#ifndef POLYHEDRAL_WARNING_H
#define POLYHEDRAL_WARNING_H

#include <mpi.h>
#include <string>

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "neighbor.h"
#include "update.h"

class PolyhedralRankWarning {
 public:
  PolyhedralRankWarning() : pending(0), said(false), line(0) {}

  // Met on this rank, at `file`:`where` (FLERR); `message` the text the warning will have (the lowest such rank's
  // is said, with its site).
  void raise(const char *file, int where, const char *message)
  {
    if (raised()) return;
    pending = 1;
    text = message;
    site = file;
    line = where;
  }

  // Raised here and not yet shared, or already said: a caller may skip making the message.
  bool raised() const { return said || pending; }

  // Whether share() should run at this step: where LIGGGHTS rebuilds the neighbour lists (a step every rank takes
  // together), at set-up and at the run's last step, so that a warning is said within one list's life and before
  // the run ends, at the cost of one small reduction per rebuild.
  static bool due(LAMMPS_NS::LAMMPS *lmp)
  {
    return lmp->update->setupflag || lmp->neighbor->ago == 0 || lmp->update->ntimestep >= lmp->update->laststep;
  }

  // Collective: every rank at the same steps. Says the warning on rank 0 when some rank raised it.
  void share(LAMMPS_NS::LAMMPS *lmp)
  {
    if (said) return;
    int any = 0, me = lmp->comm->me;
    MPI_Allreduce(&pending, &any, 1, MPI_INT, MPI_MAX, lmp->world);
    if (!any) return;
    // The text of the lowest rank that met it.
    int from = pending ? me : 1 << 30, first = 0;
    MPI_Allreduce(&from, &first, 1, MPI_INT, MPI_MIN, lmp->world);
    std::string message = broadcast(lmp, text, first), file = broadcast(lmp, site, first);
    int where = line;
    MPI_Bcast(&where, 1, MPI_INT, first, lmp->world);
    said = true;
    pending = 0;
    if (me == 0) lmp->error->warning(file.c_str(), where, message.c_str());
  }

 private:
  int pending;
  bool said;
  std::string text, site;
  int line;

  static std::string broadcast(LAMMPS_NS::LAMMPS *lmp, const std::string &mine, int root)
  {
    int length = lmp->comm->me == root ? (int)mine.size() : 0;
    MPI_Bcast(&length, 1, MPI_INT, root, lmp->world);
    std::string out(length, ' ');
    if (lmp->comm->me == root) out = mine;
    if (length > 0) MPI_Bcast(&out[0], length, MPI_CHAR, root, lmp->world);
    return out;
  }
};

#endif
