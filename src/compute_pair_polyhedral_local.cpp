#include "compute_pair_polyhedral_local.h"

#include <mpi.h>
#include <string.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "update.h"

#include "pair_polyhedral_volumetric.h"

using namespace LAMMPS_NS;

// The pair style keeps a pointer to each recording compute. A compute must not
// reach the pair from its destructor: at exit LIGGGHTS deletes force (and the
// pair) before modify (and the computes), so force->pair is freed memory then.
// A destroyed compute is instead remembered here and dropped from the pair's
// list at the next init (record_contacts only compares the pointer), before the
// pair can consult it. A compute constructed at a remembered address takes the
// entry back.
namespace {
std::vector<std::pair<LAMMPS *, Compute *> > destroyed_recorders;

void forget(LAMMPS *lmp, Compute *compute)
{
  destroyed_recorders.erase(std::remove(destroyed_recorders.begin(), destroyed_recorders.end(),
                                        std::make_pair(lmp, compute)),
                            destroyed_recorders.end());
}
}

void ComputePairPolyhedralLocal::recorder_destroyed(LAMMPS *lmp, Compute *compute)
{
  destroyed_recorders.push_back(std::make_pair(lmp, compute));
}

void ComputePairPolyhedralLocal::drop_destroyed_recorders(LAMMPS *lmp)
{
  PairPolyhedralVolumetric *live = dynamic_cast<PairPolyhedralVolumetric *>(lmp->force->pair);
  std::vector<std::pair<LAMMPS *, Compute *> > kept;
  for (size_t k = 0; k < destroyed_recorders.size(); k++) {
    if (destroyed_recorders[k].first != lmp) kept.push_back(destroyed_recorders[k]);
    else if (live) live->record_contacts(destroyed_recorders[k].second, false);
  }
  destroyed_recorders.swap(kept);
}

// Columns: id1 id2 volume depth nx ny nz cx cy cz fnx fny fnz ftx fty ftz
// (n from particle 1 to 2, c the contact point, forces on particle 2).
ComputePairPolyhedralLocal::ComputePairPolyhedralLocal(LAMMPS *lmp, int &iarg, int narg, char **arg)
    : Compute(lmp, iarg, narg, arg), pair(NULL), capacity(0)
{
  if (narg != iarg) error->compute_error(FLERR, this, "takes no arguments");
  local_flag = 1;
  scalar_flag = 1;
  timeflag = 1;  // output schedules the steps; the pair style records contacts only then
  extscalar = 1;
  vector_flag = 1;  // statistics of degenerate contacts and of the pair loop's evaluations, since pair_style
  size_vector = 11;
  extvector = 1;
  vector = statistics;
  size_local_cols = kColumns;
  size_local_rows = 0;
  array_local = NULL;
  vector_local = NULL;
  forget(lmp, this);
}

ComputePairPolyhedralLocal::~ComputePairPolyhedralLocal()
{
  // No force->pair here (see destroyed_recorders above).
  if (pair) destroyed_recorders.push_back(std::make_pair(lmp, (Compute *) this));
  memory->destroy(array_local);
}

void ComputePairPolyhedralLocal::init()
{
  drop_destroyed_recorders(lmp);
  pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (!pair) error->compute_error(FLERR, this, "requires pair_style polyhedral/volumetric");
  pair->record_contacts(this, true);
}

void ComputePairPolyhedralLocal::require_current_records()
{
  if (pair->records_step() != update->ntimestep)
    error->compute_error(FLERR, this, "contacts are recorded on the steps of thermo, dump and fix ave output "
                                      "only; this use asked on another step");
}

void ComputePairPolyhedralLocal::compute_local()
{
  invoked_local = update->ntimestep;
  require_current_records();
  const std::vector<PolyContactRecord> &records = pair->recorded_contacts();
  int rows = (int) records.size();
  if (rows > capacity) {
    memory->destroy(array_local);
    capacity = rows;
    memory->create(array_local, capacity, (int) kColumns, "pair/polyhedral/local:array");
  }
  for (int r = 0; r < rows; r++) {
    const PolyContactRecord &c = records[r];
    double *row = array_local[r];
    row[0] = c.id_i;
    row[1] = c.id_j;
    row[2] = c.volume;
    row[3] = c.depth;
    for (int k = 0; k < 3; k++) {
      row[4 + k] = c.normal[k];
      row[7 + k] = c.contact_point[k];
      row[10 + k] = c.normal_force[k];
      row[13 + k] = c.tangential_force[k];
    }
  }
  size_local_rows = rows;
}

double ComputePairPolyhedralLocal::compute_scalar()
{
  invoked_scalar = update->ntimestep;
  require_current_records();
  double mine = (double) pair->recorded_contacts().size();
  MPI_Allreduce(&mine, &scalar, 1, MPI_DOUBLE, MPI_SUM, world);
  return scalar;
}

// 1: contacts with flush faces (smoothed), 2: re-evaluated after an inconsistent
// edge, 3: inconsistent even so; 4-8: the pair loop's neighbour pairs in reach,
// skipped by their parting plane, and evaluated into a contact, apart by the
// slab or a parting plane, apart after the whole path; 9: of the contacts, those
// evaluated from their certified crossings (crossing_cache); 10: of the near misses,
// those evaluated from their certified empty search; 11: of the contacts, those whose
// extent is over 1.001 times their law depth 3 V / A (several spots); since the pair
// style was defined, summed over ranks.
void ComputePairPolyhedralLocal::compute_vector()
{
  invoked_vector = update->ntimestep;
  const poly_degenerate_counts &counts = pair->degenerate_counts();
  const PairPolyhedralVolumetric::EvaluationCounts &loop = pair->evaluation_counts();
  double mine[11] = {counts.smoothed, counts.recomputed, counts.inconsistent, loop.candidates,  loop.hinted,
                     loop.contacts,   loop.parted,      loop.near_misses,    loop.from_cache, loop.misses_from_cache,
                     loop.capped};
  MPI_Allreduce(mine, statistics, 11, MPI_DOUBLE, MPI_SUM, world);
}

double ComputePairPolyhedralLocal::memory_usage()
{
  return (double) capacity * kColumns * sizeof(double);
}
