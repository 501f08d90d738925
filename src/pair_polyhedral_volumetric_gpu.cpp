#include "pair_polyhedral_volumetric_gpu.h"

#include <mpi.h>
#include <string.h>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"

#ifdef POLY_HAVE_CUDA
#include "poly_gpu.h"
#endif

using namespace LAMMPS_NS;

#ifndef POLY_HAVE_CUDA
// Built without CUDA: the style exists so that input scripts name it, and says why it cannot run.
struct poly_gpu_result {};
#endif

PairPolyhedralVolumetricGPU::PairPolyhedralVolumetricGPU(LAMMPS *lmp)
    : PairPolyhedralVolumetric(lmp), device_ready(false), min_pairs(0), min_pieces(0), pairs_on_host(false),
      steps_on_host(0), pairs_build(-1), device_history_newer(false), num_force_particles(0), sent_particles(0)
{
}

PairPolyhedralVolumetricGPU::~PairPolyhedralVolumetricGPU()
{
#ifdef POLY_HAVE_CUDA
  if (!device_ready) return;
  // Where the time went, as LAMMPS' GPU package reports it at the end.
  poly_gpu_timing t = poly_gpu_timings();
  double local[12] = {t.set_pairs, t.upload, t.kernels, t.download, poly_gpu_bytes() / 1048576.0, t.wall_seconds,
                      (double)t.handed_back, (double)t.wall_handed_back, (double)steps_on_host, (double)t.pairs,
                      (double)t.wall_pieces, (double)t.wall_calls}, sum[12];
  MPI_Reduce(local, sum, 12, MPI_DOUBLE, MPI_SUM, 0, world);
  if (comm->me == 0 && (t.num_compute > 0 || t.wall_calls > 0 || steps_on_host > 0)) {
    char text[900];
    int length = snprintf(text, sizeof text,
                          "Pair polyhedral/volumetric/gpu (summed over %d ranks): %ld steps on the GPU (%.0f pairs per "
                          "step and rank), %.0f on the host (fewer than %ld pairs), %ld pair uploads; seconds: pair "
                          "upload %.3f, pose upload %.3f, kernels %.3f, force download %.3f; %.0f pairs handed back; "
                          "device memory %.1f MiB\n",
                          comm->nprocs, t.num_compute, t.num_compute ? sum[9] / (comm->nprocs * (double)t.num_compute) : 0.0,
                          sum[8], min_pairs, t.num_set_pairs, sum[0], sum[1], sum[2], sum[3], sum[6], sum[4]);
    if (sum[11] > 0 && length > 0 && length < (int)sizeof text)
      snprintf(text + length, sizeof text - length, "Fix wall/polyhedral meshes on the GPU (summed over ranks): %.0f "
               "calls of %.0f pieces on average (steps of fewer than %ld pieces on the host), %.3f seconds, pieces up, "
               "overlaps and nodes down; %.0f pieces handed back\n", sum[11], sum[10] / sum[11], min_pieces, sum[5],
               sum[7]);
    if (screen) fputs(text, screen);
    if (logfile) fputs(text, logfile);
  }
  poly_gpu_clear();
#endif
}

void PairPolyhedralVolumetricGPU::gpu_error(const char *message)
{
  char text[320];
  snprintf(text, sizeof text, "Pair polyhedral/volumetric/gpu: %s", message);
  error->one(FLERR, text);
}

void PairPolyhedralVolumetricGPU::init_style()
{
#ifndef POLY_HAVE_CUDA
  error->all(FLERR, "Pair polyhedral/volumetric/gpu: this build has no CUDA support (rebuild with nvcc and CUDA=on)");
#else
  PairPolyhedralVolumetric::init_style();
  char message[256];
  poly_gpu_options options;
  if (poly_gpu_environment(&options, message, sizeof message) != 0) {
    char text[320];
    snprintf(text, sizeof text, "Pair polyhedral/volumetric/gpu: %s", message);
    error->all(FLERR, text);
  }
  min_pairs = options.min_pairs;
  min_pieces = options.min_pieces;
  if (options.mixed_clip == 1 && precision == POLY_PRECISION_MIXED && comm->me == 0)
    error->warning(FLERR, "Pair polyhedral/volumetric/gpu: POLY_GPU_MIXED_CLIP=single: the warp clipping kernel clips "
                          "faces in single precision, which injects energy into resting packings (doc/gpu.md); for "
                          "benchmarks only");
  if (poly_gpu_device_count() == 0)
    error->all(FLERR, "Pair polyhedral/volumetric/gpu: no usable CUDA GPU (use pair_style polyhedral/volumetric)");
  // The device keeps history only within one run; a new run starts from LIGGGHTS' lists.
  history_to_host();
  // Ranks on one node share its GPUs round-robin by node-local rank.
  MPI_Comm node;
  int node_rank = 0;
  MPI_Comm_split_type(world, MPI_COMM_TYPE_SHARED, comm->me, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &node_rank);
  MPI_Comm_free(&node);
  int count = (int) views_d.size() - 1;
  std::vector<const poly_shape *> shapes(count > 0 ? count : 1);
  for (int s = 1; s <= count; s++) shapes[s - 1] = &FixParticletemplatePolyhedron::find(lmp, s)->shape();
  if (device_ready) {
    // Shapes may have been added between runs: start the device over (history is back on the host).
    poly_gpu_clear();
    device_ready = false;
  }
  if (poly_gpu_init(node_rank, count, &shapes[0], message, sizeof message) != 0) gpu_error(message);
  device_ready = true;
  pairs_build = -1;
#endif
}

#ifdef POLY_HAVE_CUDA
// The host's work on this rank's neighbour list, in pairs apart: a pair in contact costs the host's code about
// kContactWeight pairs whose bodies are apart (measured, doc/gpu.md "Small decks"), the GPU about the same.
long PairPolyhedralVolumetricGPU::pair_work() const
{
  const long kContactWeight = 32;
  int **first_touch = listgranhistory ? listgranhistory->firstneigh : NULL;
  long pairs = 0, contacts = 0;
  for (int ii = 0; ii < list->inum; ii++) {
    int i = list->ilist[ii], n = list->numneigh[i];
    pairs += n;
    if (first_touch)
      for (int jj = 0; jj < n; jj++) contacts += first_touch[i][jj] != 0;
  }
  return pairs + kContactWeight * contacts;
}

// All pairs of the new neighbour list, with their history from LIGGGHTS.
void PairPolyhedralVolumetricGPU::send_pairs()
{
  double *rmass = atom->rmass, *density = atom->density;
  int *type = atom->type, *shapetype = atom->shapetype;
  const int nall = atom->nlocal + atom->nghost;
  num_force_particles = force->newton_pair ? nall : atom->nlocal;
  std::vector<poly_gpu_particle> particles(nall > 0 ? nall : 1);
  for (int i = 0; i < nall; i++) {
    particles[i].shape = shapetype[i] - 1;
    particles[i].type = type[i];
    particles[i].mass = rmass[i];
    particles[i].negligible_volume = 1e-12 * rmass[i] / density[i];
    particles[i].bounding_radius = atom->radius[i];
  }
  int inum = list->inum, *ilist = list->ilist, *numneigh = list->numneigh, **firstneigh = list->firstneigh;
  double **first_history = listgranhistory ? listgranhistory->firstdouble : NULL;
  pair_i.clear();
  pair_j.clear();
  pair_jj.clear();
  history.clear();
  for (int ii = 0; ii < inum; ii++) {
    int i = ilist[ii];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      pair_i.push_back(i);
      pair_j.push_back(firstneigh[i][jj] & NEIGHMASK);
      pair_jj.push_back(jj);
      for (int d = 0; d < POLY_HISTORY_SIZE; d++)
        history.push_back(first_history ? first_history[i][POLY_HISTORY_SIZE * jj + d] : 0.0);
    }
  }
  int n = (int) pair_i.size();
  if (n == 0) {
    pair_i.push_back(0);
    pair_j.push_back(0);
    history.assign(POLY_HISTORY_SIZE, 0.0);
  }
  char message[256];
  if (poly_gpu_set_pairs(nall, num_force_particles, &particles[0], n, &pair_i[0], &pair_j[0], &history[0],
                         atom->ntypes, &materials[0], message, sizeof message) != 0)
    gpu_error(message);
  pair_i.resize(n);
  pair_j.resize(n);
  history.resize((size_t) POLY_HISTORY_SIZE * n);
  pairs_build = neighbor->ncalls;
  sent_particles = nall;
  device_history_newer = false;
}
#endif

void PairPolyhedralVolumetricGPU::compute(int eflag, int vflag)
{
#ifdef POLY_HAVE_CUDA
  if (pairs_build != neighbor->ncalls) {
    // A new neighbour list, with its history in LIGGGHTS' lists: whichever side computes until the next one.
    pairs_on_host = pair_work() < min_pairs;
    if (pairs_on_host) {
      pairs_build = neighbor->ncalls;
      device_history_newer = false;
    }
  }
  if (pairs_on_host) {
    steps_on_host++;
    PairPolyhedralVolumetric::compute(eflag, vflag);
    return;
  }
  const bool advance_history = begin_compute(eflag, vflag);
  if (pairs_build != neighbor->ncalls) send_pairs();

  double **x = atom->x, **v = atom->v, **omega = atom->omega, **quaternion = atom->quaternion;
  const int nall = atom->nlocal + atom->nghost;
  // LIGGGHTS adds and removes particles only where it rebuilds the lists; anything else would leave
  // the device's pairs pointing at the wrong particles.
  if (nall != sent_particles)
    error->one(FLERR, "Pair polyhedral/volumetric/gpu: the number of particles changed without a neighbour-list "
                      "rebuild");
  poly_gpu_motion *motion = poly_gpu_motion_buffer();
  for (int i = 0; i < nall; i++) {
    for (int k = 0; k < 3; k++) {
      motion[i].position[k] = x[i][k];
      motion[i].velocity[k] = v[i][k];
      motion[i].omega[k] = omega[i][k];
    }
    for (int k = 0; k < 4; k++) motion[i].quaternion[k] = quaternion[i][k];
  }
  poly_gpu_settings settings;
  settings.precision = precision;
  settings.tangential = tangential_history;
  settings.damping = damping;
  settings.rocking = damping && rocking_damping;
  settings.advance_history = advance_history;
  settings.parting_search = parting_search;
  settings.dt = update->dt;

  // The virial and contact records need each pair on the host; otherwise the
  // GPU sums forces and torques per particle.
  const bool per_pair = evflag || recording;
  const int n = (int) pair_i.size();
  if (per_pair) results.resize(n > 0 ? n : 1);
  char message[256];
  int num_contacts = 0;
  const poly_gpu_timing before = poly_gpu_timings();  // counts of the whole process: this call's are the difference
  if (poly_gpu_compute(&settings, per_pair ? &results[0] : NULL, &num_contacts, message, sizeof message) != 0)
    gpu_error(message);
  device_history_newer = true;
  const poly_gpu_timing after = poly_gpu_timings();
  if (after.centroid_outside > before.centroid_outside) warn_centroid_outside();  // the kernels' own, counted
  if (after.spots_facing_apart > before.spots_facing_apart) warn_spots_facing_apart();

  if (per_pair) {
    int **firstneigh = list->firstneigh;
    for (int p = 0; p < n; p++) {
      const poly_gpu_result &r = results[p];
      if (!r.contact) continue;
      poly_contact_output out;
      memset(&out, 0, sizeof out);
      for (int k = 0; k < 3; k++) {
        out.force_j[k] = r.force_j[k];
        out.torque_i[k] = r.torque_i[k];
        out.torque_j[k] = r.torque_j[k];
        out.tangential_force[k] = r.tangential_force[k];
      }
      out.normal_force = r.normal_force;
      // The host's touch flags: the state the pairs were sent with (at set-up, the step before the run).
      const bool persisting = listgranhistory && listgranhistory->firstneigh[pair_i[p]][pair_jj[p]];
      apply_contact(pair_i[p], firstneigh[pair_i[p]][pair_jj[p]] & NEIGHMASK, r.volume, r.depth, r.normal,
                    r.centroid, out, persisting);
    }
  } else {
    const double *sums = poly_gpu_force_torque();
    double **f = atom->f, **torque = atom->torque;
    for (int i = 0; i < num_force_particles; i++)
      for (int k = 0; k < 3; k++) {
        f[i][k] += sums[6 * i + k];
        torque[i][k] += sums[6 * i + 3 + k];
      }
  }
  share_warnings();  // collective: ranks computing on the host share theirs in the host path's compute
#else
  (void) eflag;
  (void) vflag;
  error->all(FLERR, "Pair polyhedral/volumetric/gpu: this build has no CUDA support");
#endif
}

// The device's history and contact flags into LIGGGHTS' neighbour list, which
// still holds the pairs they were sent from.
void PairPolyhedralVolumetricGPU::history_to_host()
{
#ifdef POLY_HAVE_CUDA
  if (!device_ready || !device_history_newer || !listgranhistory || pairs_build != neighbor->ncalls) return;
  const int n = (int) pair_i.size();
  contact.resize(n > 0 ? n : 1);
  history.resize((size_t) POLY_HISTORY_SIZE * (n > 0 ? n : 1));
  char message[256];
  if (poly_gpu_get_history(&history[0], &contact[0], message, sizeof message) != 0) gpu_error(message);
  int **first_touch = listgranhistory->firstneigh;
  double **first_history = listgranhistory->firstdouble;
  for (int p = 0; p < n; p++) {
    int i = pair_i[p], jj = pair_jj[p];
    first_touch[i][jj] = contact[p];
    for (int d = 0; d < POLY_HISTORY_SIZE; d++)
      first_history[i][POLY_HISTORY_SIZE * jj + d] = history[POLY_HISTORY_SIZE * p + d];
  }
  device_history_newer = false;
#endif
}

double PairPolyhedralVolumetricGPU::memory_usage()
{
  double bytes = PairPolyhedralVolumetric::memory_usage();
#ifdef POLY_HAVE_CUDA
  bytes += (double) (pair_i.capacity() + pair_j.capacity() + pair_jj.capacity() + contact.capacity()) * sizeof(int) +
           (double) history.capacity() * sizeof(double) + (double) results.capacity() * sizeof(poly_gpu_result);
  if (device_ready) bytes += (double) poly_gpu_bytes();
#endif
  return bytes;
}
