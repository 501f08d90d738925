#include "pair_polyhedral_volumetric_gpu.h"

#include <mpi.h>
#include <string.h>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"

#ifdef POLY_HAVE_CUDA
#include "poly_gpu.h"
#endif

using namespace LAMMPS_NS;

#ifndef POLY_HAVE_CUDA
// Built without CUDA: the style exists so that input scripts name it, and says why it cannot run.
struct poly_gpu_pair {};
struct poly_gpu_result {};
#endif

PairPolyhedralVolumetricGPU::PairPolyhedralVolumetricGPU(LAMMPS *lmp) : PairPolyhedralVolumetric(lmp), device_ready(false)
{
}

PairPolyhedralVolumetricGPU::~PairPolyhedralVolumetricGPU()
{
#ifdef POLY_HAVE_CUDA
  if (device_ready) poly_gpu_clear();
#endif
}

void PairPolyhedralVolumetricGPU::init_style()
{
#ifndef POLY_HAVE_CUDA
  error->all(FLERR, "Pair polyhedral/volumetric/gpu: this build has no CUDA support (rebuild with nvcc and CUDA=on)");
#else
  PairPolyhedralVolumetric::init_style();
  if (poly_gpu_device_count() == 0)
    error->all(FLERR, "Pair polyhedral/volumetric/gpu: no usable CUDA GPU (use pair_style polyhedral/volumetric)");
  // Ranks on one node share its GPUs round-robin by node-local rank.
  MPI_Comm node;
  int node_rank = 0;
  MPI_Comm_split_type(world, MPI_COMM_TYPE_SHARED, comm->me, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &node_rank);
  MPI_Comm_free(&node);
  int count = (int) views_d.size() - 1;
  std::vector<const poly_shape *> shapes(count > 0 ? count : 1);
  for (int s = 1; s <= count; s++) shapes[s - 1] = &FixParticletemplatePolyhedron::find(lmp, s)->shape();
  char message[256];
  if (poly_gpu_init(node_rank, count, &shapes[0], message, sizeof message) != 0) {
    char text[320];
    snprintf(text, sizeof text, "Pair polyhedral/volumetric/gpu: %s", message);
    error->one(FLERR, text);
  }
  device_ready = true;
#endif
}

void PairPolyhedralVolumetricGPU::compute(int eflag, int vflag)
{
#ifdef POLY_HAVE_CUDA
  const bool advance_history = begin_compute(eflag, vflag);

  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  double **quaternion = atom->quaternion;
  double *radius = atom->radius, *rmass = atom->rmass, *density = atom->density;
  int *type = atom->type, *shapetype = atom->shapetype;
  const int ntypes = atom->ntypes;

  int inum = list->inum, *ilist = list->ilist, *numneigh = list->numneigh, **firstneigh = list->firstneigh;
  int **first_touch = listgranhistory ? listgranhistory->firstneigh : NULL;
  double **first_history = listgranhistory ? listgranhistory->firstdouble : NULL;

  // Candidates: pairs whose bounding spheres overlap; the rest are no contact.
  pairs.clear();
  pair_i.clear();
  pair_jj.clear();
  history.clear();
  for (int ii = 0; ii < inum; ii++) {
    int i = ilist[ii];
    for (int jj = 0; jj < numneigh[i]; jj++) {
      int j = firstneigh[i][jj] & NEIGHMASK;
      double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
      double reach = radius[i] + radius[j];
      if (dx * dx + dy * dy + dz * dz >= reach * reach) {
        if (first_touch) {
          first_touch[i][jj] = 0;
          for (int d = 0; d < POLY_HISTORY_SIZE; d++) first_history[i][POLY_HISTORY_SIZE * jj + d] = 0.0;
        }
        continue;
      }
      poly_gpu_pair pair;
      memset(&pair, 0, sizeof pair);
      pair.shape_i = shapetype[i] - 1;
      pair.shape_j = shapetype[j] - 1;
      pair.material = type[i] * (ntypes + 1) + type[j];
      for (int k = 0; k < 3; k++) {
        pair.position_i[k] = x[i][k];
        pair.position_j[k] = x[j][k];
        pair.velocity_i[k] = v[i][k];
        pair.velocity_j[k] = v[j][k];
        pair.omega_i[k] = omega[i][k];
        pair.omega_j[k] = omega[j][k];
      }
      for (int k = 0; k < 4; k++) {
        pair.quaternion_i[k] = quaternion[i][k];
        pair.quaternion_j[k] = quaternion[j][k];
      }
      pair.mass_i = rmass[i];
      pair.mass_j = rmass[j];
      double volume_i = rmass[i] / density[i], volume_j = rmass[j] / density[j];
      pair.negligible_volume = 1e-12 * (volume_i < volume_j ? volume_i : volume_j);
      pairs.push_back(pair);
      pair_i.push_back(i);
      pair_jj.push_back(jj);
      for (int d = 0; d < POLY_HISTORY_SIZE; d++)
        history.push_back(first_history ? first_history[i][POLY_HISTORY_SIZE * jj + d] : 0.0);
    }
  }

  int n = (int) pairs.size();
  results.resize(n > 0 ? n : 1);
  char message[256];
  if (n > 0 && poly_gpu_compute(n, &pairs[0], &materials[0], (int) materials.size(), single_precision,
                                tangential_history, damping, update->dt, advance_history, &history[0], &results[0],
                                message, sizeof message) != 0) {
    char text[320];
    snprintf(text, sizeof text, "Pair polyhedral/volumetric/gpu: %s", message);
    error->one(FLERR, text);
  }

  for (int p = 0; p < n; p++) {
    int i = pair_i[p], jj = pair_jj[p];
    int j = firstneigh[i][jj] & NEIGHMASK;
    const poly_gpu_result &r = results[p];
    if (first_touch) {
      first_touch[i][jj] = r.contact;
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) first_history[i][POLY_HISTORY_SIZE * jj + d] = history[POLY_HISTORY_SIZE * p + d];
    }
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
    apply_contact(i, j, r.volume, r.depth, r.normal, r.centroid, out);
  }
#else
  (void) eflag;
  (void) vflag;
  error->all(FLERR, "Pair polyhedral/volumetric/gpu: this build has no CUDA support");
#endif
}

double PairPolyhedralVolumetricGPU::memory_usage()
{
  double bytes = PairPolyhedralVolumetric::memory_usage();
#ifdef POLY_HAVE_CUDA
  bytes += (double) pairs.capacity() * sizeof(poly_gpu_pair) + (double) results.capacity() * sizeof(poly_gpu_result);
  if (device_ready) bytes += (double) poly_gpu_bytes();
#endif
  return bytes;
}
