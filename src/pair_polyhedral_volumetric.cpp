#include "pair_polyhedral_volumetric.h"

#include <math.h>
#include <mpi.h>
#include <string.h>
#include <algorithm>
#include <map>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "fix_property_global.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "update.h"

#include "fix_contact_history_polyhedral.h"
#include "fix_particletemplate_polyhedron.h"

using namespace LAMMPS_NS;

// The time step is flagged above these fractions of the Rayleigh and Hertz times.
static const double kRayleighFraction = 0.2;
static const double kHertzFraction = 0.1;

PairPolyhedralVolumetric::PairPolyhedralVolumetric(LAMMPS *lmp)
    : Pair(lmp), computeflag(0), listgranhistory(NULL), tangential_history(true), damping(true),
      rocking_damping(true), cohesion(false), crossing_cache(true), skip_apart(true), parting_search(true),
#ifdef POLY_SINGLE_PRECISION
      precision(POLY_PRECISION_SINGLE),
#else
      precision(POLY_PRECISION_DOUBLE),
#endif
      recording(false), records_timestep(-1), have_workspace(false), maxrad(NULL),
      fix_history(NULL), atom_ntypes(0)
{
  degenerate.smoothed = degenerate.recomputed = degenerate.inconsistent = 0.0;
  evaluations.candidates = evaluations.hinted = evaluations.contacts = evaluations.parted = 0.0;
  evaluations.near_misses = evaluations.from_cache = evaluations.misses_from_cache = evaluations.capped = 0.0;
  single_enable = 0;
  restartinfo = 1;
  no_virial_fdotr_compute = 1;
  memset(&workspace_d, 0, sizeof workspace_d);
  memset(&workspace_f, 0, sizeof workspace_f);
}

PairPolyhedralVolumetric::~PairPolyhedralVolumetric()
{
  free_shape_views();
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(maxrad);
  }
}

void PairPolyhedralVolumetric::allocate()
{
  allocated = 1;
  int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(maxrad, n + 1, "pair:maxrad");
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) setflag[i][j] = 0;
}

// pair_style polyhedral/volumetric [tangential history|off] [damping on|off] [rocking_damping on|off]
//     [precision double|single|mixed]
void PairPolyhedralVolumetric::settings(int narg, char **arg)
{
  for (int iarg = 0; iarg < narg; iarg += 2) {
    if (iarg + 2 > narg) {
      char message[256];
      snprintf(message, sizeof message, "Pair polyhedral/volumetric: keyword '%s' needs a value", arg[iarg]);
      error->all(FLERR, message);
    }
    const char *key = arg[iarg], *value = arg[iarg + 1];
    for (int earlier = 0; earlier < iarg; earlier += 2)
      if (strcmp(arg[earlier], key) == 0) {
        char message[256];
        snprintf(message, sizeof message, "Pair polyhedral/volumetric: keyword '%s' given twice", key);
        error->all(FLERR, message);
      }
    bool ok = true;
    if (strcmp(key, "cohesion") == 0) {
      cohesion = cohesion_keyword(lmp, "Pair polyhedral/volumetric", value);
      continue;
    }
    if (liggghts_model_keyword(lmp, "Pair polyhedral/volumetric", key, value)) continue;
    if (strcmp(key, "tangential") == 0) {
      ok = strcmp(value, "history") == 0 || strcmp(value, "off") == 0;
      tangential_history = strcmp(value, "history") == 0;
    } else if (strcmp(key, "damping") == 0) {
      ok = strcmp(value, "on") == 0 || strcmp(value, "off") == 0;
      damping = strcmp(value, "on") == 0;
    } else if (strcmp(key, "rocking_damping") == 0) {
      ok = strcmp(value, "on") == 0 || strcmp(value, "off") == 0;
      rocking_damping = strcmp(value, "on") == 0;
    } else if (strcmp(key, "crossing_cache") == 0) {
      ok = strcmp(value, "on") == 0 || strcmp(value, "off") == 0;
      crossing_cache = strcmp(value, "on") == 0;
    } else if (strcmp(key, "skip_apart") == 0) {
      ok = strcmp(value, "on") == 0 || strcmp(value, "off") == 0;
      skip_apart = strcmp(value, "on") == 0;
    } else if (strcmp(key, "parting_search") == 0) {
      ok = strcmp(value, "on") == 0 || strcmp(value, "off") == 0;
      parting_search = strcmp(value, "on") == 0;
    } else if (strcmp(key, "precision") == 0) {
      ok = strcmp(value, "double") == 0 || strcmp(value, "single") == 0 || strcmp(value, "mixed") == 0;
      precision = strcmp(value, "single") == 0  ? POLY_PRECISION_SINGLE
                  : strcmp(value, "mixed") == 0 ? POLY_PRECISION_MIXED
                                                : POLY_PRECISION_DOUBLE;
    } else {
      char message[256];
      snprintf(message, sizeof message,
               "Pair polyhedral/volumetric: unknown keyword '%s' (tangential, damping, rocking_damping, precision, "
               "crossing_cache, skip_apart, parting_search; LIGGGHTS' model, cohesion, rolling_friction, surface)",
               key);
      error->all(FLERR, message);
    }
    if (!ok) {
      char message[256];
      snprintf(message, sizeof message, "Pair polyhedral/volumetric: invalid value '%s' for '%s'", value, key);
      error->all(FLERR, message);
    }
  }
}

bool PairPolyhedralVolumetric::liggghts_model_keyword(LAMMPS *lmp, const char *caller, const char *key,
                                                      const char *value)
{
  static const char *const kAccepted[][2] = {
      {"model", "hertz"}, {"cohesion", "off"}, {"rolling_friction", "off"}, {"surface", "default"}};
  const bool known = strcmp(key, "model") == 0 || strcmp(key, "cohesion") == 0 ||
                     strcmp(key, "rolling_friction") == 0 || strcmp(key, "surface") == 0 ||
                     (strcmp(key, "tangential") == 0 && value && strcmp(value, "no_history") == 0);
  if (!known) return false;
  char message[600];
  if (!value) {
    snprintf(message, sizeof message, "%s: keyword '%s' needs a value", caller, key);
    lmp->error->all(FLERR, message);
  }
  for (size_t k = 0; k < sizeof kAccepted / sizeof kAccepted[0]; k++)
    if (strcmp(key, kAccepted[k][0]) == 0 && strcmp(value, kAccepted[k][1]) == 0) return true;
  if (strcmp(key, "model") == 0)
    snprintf(message, sizeof message,
             "%s: model %s: the volumetric law is Hertz-Mindlin generalised to overlap volumes and has no %s "
             "variant; use model hertz (or leave 'model' out)", caller, value,
             strncmp(value, "hooke", 5) == 0 ? "linear (Hooke)" : "such");
  else if (strcmp(key, "tangential") == 0)
    snprintf(message, sizeof message,
             "%s: tangential no_history (a viscous tangential force without a spring) has no counterpart here; use "
             "tangential history (Mindlin-Deresiewicz with its history, the default) or tangential off", caller);
  else if (strcmp(key, "rolling_friction") == 0)
    snprintf(message, sizeof message,
             "%s: rolling_friction %s: polyhedra roll over their edges and vertices, so their shape resists rolling "
             "as a real grain's does (spheres need a rolling-friction model for it); leave the keyword out or use "
             "rolling_friction off", caller, value);
  else if (strcmp(key, "cohesion") == 0)
    snprintf(message, sizeof message,
             "%s: cohesion %s is not available for polyhedra; use cohesion sjkr (LIGGGHTS' simplified JKR over "
             "the overlap's cross-section) or cohesion off", caller, value);
  else
    snprintf(message, sizeof message, "%s: surface %s has no counterpart here; use surface default or leave it out",
             caller, value);
  lmp->error->all(FLERR, message);
  return true;
}

// The touch flags of LIGGGHTS' history list say which pairs the last evaluation found in contact (the GPU
// style brings its flags back first). The half list holds a pair of two local particles once, and a pair of
// a local and a ghost particle on both ranks, so each side counts its local particles only.
void PairPolyhedralVolumetric::count_contacts(double *count, int groupbit)
{
  history_to_host();
  if (!list || !listgranhistory)
    error->all(FLERR, "Compute contact/polyhedron: the pair style has no contact list yet (use it after a run)");
  const int nlocal = atom->nlocal, *mask = atom->mask;
  int **touch = listgranhistory->firstneigh;
  for (int ii = 0; ii < list->inum; ii++) {
    int i = list->ilist[ii];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      if (!touch[i][jj]) continue;
      int j = list->firstneigh[i][jj] & NEIGHMASK;
      if (i < nlocal && (mask[i] & groupbit)) count[i] += 1.0;
      if (j < nlocal && (mask[j] & groupbit)) count[j] += 1.0;
    }
  }
}

// pair_coeff * *: the materials come from fix property/global.
void PairPolyhedralVolumetric::coeff(int narg, char **arg)
{
  if (narg != 2) error->all(FLERR, "Pair polyhedral/volumetric: use 'pair_coeff * *' (materials come from fix property/global)");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  force->bounds(arg[0], atom->ntypes, ilo, ihi);
  force->bounds(arg[1], atom->ntypes, jlo, jhi);
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = (jlo > i ? jlo : i); j <= jhi; j++) {
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients");
}

void PairPolyhedralVolumetric::init_style()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0)
    error->all(FLERR, "Pair polyhedral/volumetric requires atom_style polyhedron");
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "Pair polyhedral/volumetric requires ghost atoms store velocity: use 'communicate single vel yes'");
  if (tangential_history && force->newton_pair)
    error->all(FLERR, "Pair polyhedral/volumetric with tangential history requires newton pair off");
  if (comm->me == 0 && neighbor->delay != 0)
    error->warning(FLERR, "Pair polyhedral/volumetric: use 'neigh_modify delay 0' so contacts are never missed");

  load_materials();
  build_shape_views();
  if (tangential_history) ensure_history_fix();

  int irequest = neighbor->request(this);
  neighbor->requests[irequest]->half = 0;
  neighbor->requests[irequest]->gran = 1;
  if (tangential_history) {
    irequest = neighbor->request(this);
    neighbor->requests[irequest]->id = 1;
    neighbor->requests[irequest]->half = 0;
    neighbor->requests[irequest]->granhistory = 1;
    neighbor->requests[irequest]->dnum = POLY_HISTORY_SIZE;
  }

  // Bounding radius per type, from the particles and from the templates
  // (particles inserted later).
  int n = atom->ntypes;
  std::vector<double> local(n + 1, 0.0);
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->radius[i] > local[atom->type[i]]) local[atom->type[i]] = atom->radius[i];
  for (int s = 1; s < (int) views_d.size(); s++) {
    FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, s);
    int t = shape_template->particle_type();
    if (t <= n && shape_template->shape().bounding_radius > local[t]) local[t] = shape_template->shape().bounding_radius;
  }
  MPI_Allreduce(&local[1], &maxrad[1], n, MPI_DOUBLE, MPI_MAX, world);

  check_timestep();
}

void PairPolyhedralVolumetric::init_list(int id, NeighList *ptr)
{
  if (id == 0) list = ptr;
  else if (id == 1) listgranhistory = ptr;
}

double PairPolyhedralVolumetric::init_one(int i, int j)
{
  if (!allocated) allocate();
  return (maxrad[i] + maxrad[j]) * neighbor->contactDistanceFactor;
}

void *PairPolyhedralVolumetric::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "computeflag") == 0) return (void *) &computeflag;
  return NULL;
}

void PairPolyhedralVolumetric::load_materials()
{
  atom_ntypes = atom->ntypes;
  material_table(lmp, force->pair_style, damping, tangential_history, cohesion, materials);
}

// Effective constants of every type pair from LIGGGHTS' fix property/global
// tables, indexed i * (ntypes+1) + j. Only what the scene needs is read:
// restitution only with damping, friction only with a tangential force (as
// pair gran asks for its materials); the others default to e = 1, mu = 0.
int PairPolyhedralVolumetric::cohesion_keyword(LAMMPS *lmp, const char *caller, const char *value)
{
  if (strcmp(value, "sjkr") == 0) return 1;
  if (strcmp(value, "off") == 0) return 0;
  liggghts_model_keyword(lmp, caller, "cohesion", value);  // stops with the ERROR naming the alternative
  return 0;
}

// Deep cohesive overlaps are outside the volumetric law's shallow-overlap regime (doc/pair_polyhedral_volumetric.md,
// "Cohesion"): an ERROR where particles would half merge, a WARNING (once per value) where faces sink past 5 %.
void PairPolyhedralVolumetric::check_cohesion_depth(LAMMPS *lmp, const char *caller, int i, int j, double k,
                                                    double youngs_effective)
{
  const double ratio = poly_cohesion_face_depth_ratio(k, youngs_effective);
  if (ratio <= kCohesionDepthWarning) return;
  char message[640];
  snprintf(message, sizeof message,
           "%s: cohesionEnergyDensity %g for types %d %d against E* = %g: faces held by cohesion alone sink "
           "%.0f %% of their size into each other (3 sqrt(pi)/4 k/E*), and blunt vertices are drawn in until faces "
           "meet; %s",
           caller, k, i, j, youngs_effective, 100.0 * ratio,
           ratio > kCohesionDepthError ? "keep k/E* below 0.15 (lower cohesionEnergyDensity or raise youngsModulus)"
                                       : "the volumetric law is meant for shallow overlaps");
  if (ratio > kCohesionDepthError) lmp->error->all(FLERR, message);
  static std::map<std::pair<double, double>, bool> warned;
  if (warned[std::make_pair(k, youngs_effective)]) return;
  warned[std::make_pair(k, youngs_effective)] = true;
  if (lmp->comm->me == 0) lmp->error->warning(FLERR, message);
}

void PairPolyhedralVolumetric::material_table(LAMMPS *lmp, const char *caller, bool with_restitution,
                                              bool with_friction, bool with_cohesion,
                                              std::vector<poly_material_pair> &table)
{
  Modify *modify = lmp->modify;
  Error *error = lmp->error;
  const int n = lmp->atom->ntypes;
  FixPropertyGlobal *youngs = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("youngsModulus", "property/global", "peratomtype", n, 0, caller));
  FixPropertyGlobal *poisson = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", n, 0, caller));
  FixPropertyGlobal *restitution = with_restitution ? static_cast<FixPropertyGlobal *>(modify->find_fix_property(
                                                          "coefficientRestitution", "property/global", "peratomtypepair", n, n, caller))
                                                    : NULL;
  FixPropertyGlobal *friction = with_friction ? static_cast<FixPropertyGlobal *>(modify->find_fix_property(
                                                    "coefficientFriction", "property/global", "peratomtypepair", n, n, caller))
                                              : NULL;
  FixPropertyGlobal *cohesion_density = with_cohesion ? static_cast<FixPropertyGlobal *>(modify->find_fix_property(
                                                           "cohesionEnergyDensity", "property/global", "peratomtypepair", n, n, caller))
                                                     : NULL;
  table.assign((n + 1) * (n + 1), poly_material_pair());
  // Kept for the process: every run command and every wall fix calls this, and one beta (a bisection
  // over integrated impacts) took as long as a few hundred steps of a small pile.
  static std::map<double, double> beta_of_restitution;
  for (int i = 1; i <= n; i++) {
    double youngs_i = youngs->compute_vector(i - 1), poisson_i = poisson->compute_vector(i - 1);
    if (!(youngs_i > 0.0 && isfinite(youngs_i)))
      error->all(FLERR, "Pair polyhedral/volumetric: youngsModulus must be a finite number > 0");
    if (!(poisson_i >= 0.0 && poisson_i < 0.5)) error->all(FLERR, "Pair polyhedral/volumetric: poissonsRatio must be in [0, 0.5)");
    for (int j = 1; j <= n; j++) {
      double youngs_j = youngs->compute_vector(j - 1), poisson_j = poisson->compute_vector(j - 1);
      double e = restitution ? restitution->compute_array(i - 1, j - 1) : 1.0;
      double mu = friction ? friction->compute_array(i - 1, j - 1) : 0.0;
      if (!(e > 0.0 && e <= 1.0)) error->all(FLERR, "Pair polyhedral/volumetric: coefficientRestitution must be in (0, 1]");
      if (!(mu >= 0.0 && isfinite(mu)))
        error->all(FLERR, "Pair polyhedral/volumetric: coefficientFriction must be a finite number >= 0");
      if (!beta_of_restitution.count(e)) beta_of_restitution[e] = poly_damping_beta_for_restitution(e);
      poly_material_pair_make(youngs_i, poisson_i, youngs_j, poisson_j, beta_of_restitution[e], mu,
                              &table[i * (n + 1) + j]);
      if (cohesion_density) {
        double k = cohesion_density->compute_array(i - 1, j - 1);
        if (!(k >= 0.0 && isfinite(k)))
          error->all(FLERR, "Pair polyhedral/volumetric: cohesionEnergyDensity must be a finite number >= 0");
        table[i * (n + 1) + j].cohesion = k;
        check_cohesion_depth(lmp, caller, i, j, k, table[i * (n + 1) + j].youngs_effective);
      }
    }
  }
}

void PairPolyhedralVolumetric::free_shape_views()
{
  for (size_t s = 0; s < views_f.size(); s++)
    if (views_f[s].vertices) poly_shape_view_free_f(&views_f[s]);
  views_f.clear();
  views_d.clear();
  if (have_workspace) {
    poly_overlap_workspace_destroy_d(&workspace_d);
    poly_overlap_workspace_destroy_f(&workspace_f);
    have_workspace = false;
  }
}

// Views of every template by shape number, and one workspace for the largest.
void PairPolyhedralVolumetric::build_shape_views()
{
  free_shape_views();
  // The crossing caches name their shapes by the views' vertex arrays, which new views may reuse.
  crossing_cache_of.clear();
  crossing_cache_pool.clear();
  crossing_cache_free.clear();
  int count = 0;
  for (int s = 1; FixParticletemplatePolyhedron::find(lmp, s); s++) count = s;
  if (count != FixParticletemplatePolyhedron::count(lmp))
    error->all(FLERR, "Pair polyhedral/volumetric: polyhedral templates must be numbered 1..N without gaps");
  views_d.assign(count + 1, poly_shape_view_d());
  views_f.assign(count + 1, poly_shape_view_f());
  memset(&views_d[0], 0, sizeof(poly_shape_view_d));
  memset(&views_f[0], 0, sizeof(poly_shape_view_f));
  int max_vertices = 1, max_triangles = 1;
  for (int s = 1; s <= count; s++) {
    const poly_shape &shape = FixParticletemplatePolyhedron::find(lmp, s)->shape();
    views_d[s] = poly_shape_view_of(&shape);
    if (poly_shape_view_make_f(&shape, &views_f[s]) != 0) error->one(FLERR, "Pair polyhedral/volumetric: out of memory");
    if (shape.num_vertices > max_vertices) max_vertices = shape.num_vertices;
    if (shape.num_triangles > max_triangles) max_triangles = shape.num_triangles;
  }
  if (poly_overlap_workspace_create_d(&workspace_d, max_vertices, max_triangles) != 0 ||
      poly_overlap_workspace_create_f(&workspace_f, max_vertices, max_triangles) != 0)
    error->one(FLERR, "Pair polyhedral/volumetric: out of memory");
  have_workspace = true;
}

void PairPolyhedralVolumetric::ensure_history_fix()
{
  int ifix = modify->find_fix(FixContactHistoryPolyhedral::fix_id());
  if (ifix < 0) {
    char dnum[8];
    snprintf(dnum, sizeof dnum, "%d", POLY_HISTORY_SIZE);
    // The elastic tangential force flips sign when the pair is seen from the partner.
    const char *args[4 + 2 * POLY_HISTORY_SIZE] = {
        FixContactHistoryPolyhedral::fix_id(), "all", FixContactHistoryPolyhedral::creation_style(), dnum,
        "elastic_tangential_x", "1", "elastic_tangential_y", "1", "elastic_tangential_z", "1",
        "tangential_stiffness", "0", "normal_force", "0"};
    modify->add_fix(4 + 2 * POLY_HISTORY_SIZE, const_cast<char **>(args));
    ifix = modify->find_fix(FixContactHistoryPolyhedral::fix_id());
  }
  fix_history = dynamic_cast<FixContactHistoryPolyhedral *>(modify->fix[ifix]);
  if (!fix_history || fix_history->get_dnum() != POLY_HISTORY_SIZE)
    error->all(FLERR, "Pair polyhedral/volumetric: contact history of an incompatible model (restart from another pair style?)");
}

// Warns when the time step is a large fraction of the Rayleigh time of the
// smallest particle or of the Hertz contact time at the fastest approach.
void PairPolyhedralVolumetric::check_timestep()
{
  double rayleigh = 1e300, hertz = 1e300, speed = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    double v2 = atom->v[i][0] * atom->v[i][0] + atom->v[i][1] * atom->v[i][1] + atom->v[i][2] * atom->v[i][2];
    if (v2 > speed * speed) speed = sqrt(v2);
  }
  double speed_all;
  MPI_Allreduce(&speed, &speed_all, 1, MPI_DOUBLE, MPI_MAX, world);
  double approach = 2.0 * speed_all;
  FixPropertyGlobal *youngs = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("youngsModulus", "property/global", "peratomtype", atom->ntypes, 0, force->pair_style));
  FixPropertyGlobal *poisson = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", atom->ntypes, 0, force->pair_style));
  for (int i = 0; i < atom->nlocal; i++) {
    int t = atom->type[i];
    double e = youngs->compute_vector(t - 1), nu = poisson->compute_vector(t - 1);
    // From the shape, not rmass: after read_data the masses are set only when
    // atom_style polyhedron initialises, which LIGGGHTS does after the pair style.
    FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, atom->shapetype[i]);
    if (!shape_template) continue;
    double volume = shape_template->shape().volume, mass = atom->density[i] * volume;
    double r = cbrt(3.0 * volume / (4.0 * M_PI));
    double t_rayleigh = poly_rayleigh_time(r, atom->density[i], e, nu);
    if (t_rayleigh < rayleigh) rayleigh = t_rayleigh;
    if (approach > 0.0) {
      // Two equal particles: reduced mass m/2, radius r/2.
      double t_hertz = poly_hertz_time(0.5 * mass, 0.5 * r, e / (2.0 * (1.0 - nu * nu)), approach);
      if (t_hertz < hertz) hertz = t_hertz;
    }
  }
  double local[2] = {rayleigh, hertz}, global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, world);
  if (comm->me != 0) return;
  double dt = update->dt;
  char message[512];
  if (global[0] < 1e300 && dt > kRayleighFraction * global[0]) {
    snprintf(message, sizeof message,
             "Pair polyhedral/volumetric: time step %g is %.0f%% of the Rayleigh time %g of the smallest particle "
             "(keep it below %.0f%%)", dt, 100.0 * dt / global[0], global[0], 100.0 * kRayleighFraction);
    error->warning(FLERR, message);
  }
  if (global[1] < 1e300 && dt > kHertzFraction * global[1]) {
    snprintf(message, sizeof message,
             "Pair polyhedral/volumetric: time step %g is %.0f%% of the Hertz contact time %g at the fastest "
             "approach speed %g (keep it below %.0f%%)", dt, 100.0 * dt / global[1], global[1], approach,
             100.0 * kHertzFraction);
    error->warning(FLERR, message);
  }
}

void PairPolyhedralVolumetric::poses(int i, int j, poly_pose *pose_i, poly_pose *pose_j) const
{
  for (int k = 0; k < 3; k++) {
    pose_i->position[k] = atom->x[i][k];
    pose_j->position[k] = atom->x[j][k];
  }
  for (int k = 0; k < 4; k++) {
    pose_i->quaternion[k] = atom->quaternion[i][k];
    pose_j->quaternion[k] = atom->quaternion[j][k];
  }
}

void PairPolyhedralVolumetric::overlap(int i, int j, poly_overlap_result *result, poly_crossing_cache *cache)
{
  poly_pose pose_i, pose_j;
  poses(i, j, &pose_i, &pose_j);
  int si = atom->shapetype[i], sj = atom->shapetype[j];
  workspace_d.want_second_moment = workspace_f.want_second_moment = damping && rocking_damping;
  workspace_d.crossing_cache = workspace_f.crossing_cache = cache;
  if (precision == POLY_PRECISION_SINGLE)
    poly_overlap_f(&views_f[si], &pose_i, &views_f[sj], &pose_j, &workspace_f, result);
  else if (precision == POLY_PRECISION_MIXED)
    poly_overlap_m(&views_f[si], &pose_i, &views_f[sj], &pose_j, &workspace_f, result);
  else
    poly_overlap_d(&views_d[si], &pose_i, &views_d[sj], &pose_j, &workspace_d, result);
  workspace_d.crossing_cache = workspace_f.crossing_cache = NULL;
}

// A pool entry for a pair's crossing cache, zeroed (no crossings, no certificate).
int PairPolyhedralVolumetric::new_crossing_cache()
{
  int index;
  if (!crossing_cache_free.empty()) {
    index = crossing_cache_free.back();
    crossing_cache_free.pop_back();
  } else {
    index = (int) crossing_cache_pool.size();
    crossing_cache_pool.push_back(poly_crossing_cache());
  }
  // What a new pair's cache must say: made for no shapes, no certificate (the rest is written with them).
  poly_crossing_cache &cache = crossing_cache_pool[index];
  cache.shape_a = cache.shape_b = NULL;
  cache.margin = 0.0;
  cache.hits = cache.backoff = cache.skip = cache.recheck_backoff = cache.recheck_wait = 0;
  return index;
}

void PairPolyhedralVolumetric::release_crossing_cache(int slot)
{
  if (slot < (int) crossing_cache_of.size() && crossing_cache_of[slot] >= 0) {
    crossing_cache_free.push_back(crossing_cache_of[slot]);
    crossing_cache_of[slot] = -1;
  }
}

bool PairPolyhedralVolumetric::still_separated(int i, int j, int hint, double *gap)
{
  poly_pose pose_i, pose_j;
  poses(i, j, &pose_i, &pose_j);
  int si = atom->shapetype[i], sj = atom->shapetype[j];
  if (precision == POLY_PRECISION_DOUBLE)
    return poly_overlap_still_separated_d(&views_d[si], &pose_i, &views_d[sj], &pose_j, hint, gap);
  return poly_overlap_still_separated_f(&views_f[si], &pose_i, &views_f[sj], &pose_j, hint, gap);
}

// Each particle's travel since the neighbour-list build: per step |dx| + 2 r |dq|, r its bounding radius, q of
// the sign nearest the last (a point at distance r from the centre turned by theta runs a chord of
// 2 r sin(theta/2) <= 4 r sin(theta/4) = 2 r |dq|). Between builds atoms keep their index and ghosts their image;
// at a build, or when the count changes (an insertion), every travel and wait starts again.
void PairPolyhedralVolumetric::update_travel(size_t num_pairs)
{
  const int nall = atom->nlocal + atom->nghost;
  double **x = atom->x, **q = atom->quaternion, *radius = atom->radius;
  const bool restart = neighbor->ago == 0 || travel.size() != (size_t) nall || apart_until.size() != num_pairs;
  if (restart) {
    travel.assign(nall, 0.0);
    last_pose.resize(7 * (size_t) nall);
    apart_until.assign(num_pairs, -1.0);
  }
  for (int i = 0; i < nall; i++) {
    double *last = &last_pose[7 * (size_t) i];
    if (!restart) {
      double moved = 0.0, minus = 0.0, plus = 0.0;
      for (int k = 0; k < 3; k++) moved += (x[i][k] - last[k]) * (x[i][k] - last[k]);
      for (int k = 0; k < 4; k++) {
        minus += (q[i][k] - last[3 + k]) * (q[i][k] - last[3 + k]);
        plus += (q[i][k] + last[3 + k]) * (q[i][k] + last[3 + k]);
      }
      travel[i] += sqrt(moved) + 2.0 * radius[i] * sqrt(minus < plus ? minus : plus);
    }
    for (int k = 0; k < 3; k++) last[k] = x[i][k];
    for (int k = 0; k < 4; k++) last[3 + k] = q[i][k];
  }
}

// Pair `slot` (i, j) found apart by `gap`: it waits while i and j travel less than that, less the rounding of
// their relative pose (of the order of their coordinates' rounding) and of the travels' sums.
void PairPolyhedralVolumetric::start_apart(int slot, int i, int j, double gap)
{
  double **x = atom->x, coordinates = 0.0;
  for (int k = 0; k < 3; k++) coordinates += fabs(x[i][k]) + fabs(x[j][k]);
  const double budget = gap * (1.0 - 1e-9) - 1e-14 * coordinates;
  if (budget > 0.0) apart_until[slot] = travel[i] + travel[j] + budget;
}

// The statistics of compute pair/polyhedral/local's vector; an edge still
// inconsistent after the re-evaluation is a wrong answer, so it is said once.
void PairPolyhedralVolumetric::count_degenerate(const poly_overlap_result &geometry)
{
  poly_degenerate_count(&degenerate, &geometry);
  if (geometry.num_inconsistent > 0)
    inconsistent_warning.raise(FLERR, "Pair polyhedral/volumetric: a contact's overlap stayed inconsistent after "
                                      "its re-evaluation (its volume may be wrong); please report the two shapes and "
                                      "poses");
}

// Whether the overlap's centroid lies within both particles' bounding spheres (poly_contact_centroid_within);
// one that does not is rounding, taken as no contact, and said once.
bool PairPolyhedralVolumetric::centroid_within(int i, int j, const poly_overlap_result &geometry)
{
  double **x = atom->x, *radius = atom->radius, centroid[3], j_from_i[3];
  for (int k = 0; k < 3; k++) centroid[k] = geometry.centroid[k] - x[i][k], j_from_i[k] = x[j][k] - x[i][k];
  if (poly_contact_centroid_within(centroid, j_from_i, radius[i], radius[j])) return true;
  warn_centroid_outside();
  return false;
}

void PairPolyhedralVolumetric::warn_centroid_outside()
{
  centroid_warning.raise(FLERR, "Pair polyhedral/volumetric: an overlap's centroid fell outside one of its two "
                                "particles (a sliver thinner than the precision resolves); such overlaps are taken "
                                "as no contact");
}

void PairPolyhedralVolumetric::warn_spots_facing_apart()
{
  apart_spots_warning.raise(FLERR, "Pair polyhedral/volumetric: a pair touches at spots facing apart (a particle "
                                   "wedged across a slot of one that is not convex?): one contact per pair takes "
                                   "their spread as its depth, and its force is far too large there (the pair style's "
                                   "page, Restrictions)");
}

// Called by every rank at the end of each compute (CPU or GPU): the warnings any rank met, said on rank 0.
void PairPolyhedralVolumetric::share_warnings()
{
  if (!PolyhedralRankWarning::due(lmp)) return;
  inconsistent_warning.share(lmp);
  centroid_warning.share(lmp);
  apart_spots_warning.share(lmp);
}

void PairPolyhedralVolumetric::record_contacts(Compute *compute, bool on)
{
  std::vector<Compute *>::iterator found = std::find(recorders.begin(), recorders.end(), compute);
  if (on && found == recorders.end()) recorders.push_back(compute);
  if (!on && found != recorders.end()) recorders.erase(found);
}

// Common start of compute() for the CPU and GPU styles; returns whether the
// tangential springs may advance (not in the set-up force evaluation).
bool PairPolyhedralVolumetric::begin_compute(int eflag, int vflag)
{
  if (eflag || vflag) ev_setup(eflag, vflag);
  else evflag = vflag_fdotr = 0;
  computeflag = 1;
  // Every recorder's schedule is consulted (matchstep also drops its past steps).
  recording = false;
  for (size_t c = 0; c < recorders.size(); c++)
    if (recorders[c]->matchstep(update->ntimestep)) recording = true;
  if (recording) {
    records.clear();
    records_timestep = update->ntimestep;
  }
  return !update->setupflag;
}

void PairPolyhedralVolumetric::compute(int eflag, int vflag)
{
  const bool advance_history = begin_compute(eflag, vflag);

  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  double *radius = atom->radius, *rmass = atom->rmass, *density = atom->density;
  int *type = atom->type;
  const int num_shapes = (int) views_d.size();

  int inum = list->inum, *ilist = list->ilist, *numneigh = list->numneigh, **firstneigh = list->firstneigh;
  int **first_touch = listgranhistory ? listgranhistory->firstneigh : NULL;
  double **first_history = listgranhistory ? listgranhistory->firstdouble : NULL;

  hint_offset.resize(inum);
  size_t num_hints = 0;
  for (int ii = 0; ii < inum; ii++) {
    hint_offset[ii] = (int) num_hints;
    num_hints += numneigh[ilist[ii]];
  }
  if (separating_hint.size() < num_hints) separating_hint.resize(num_hints, -1);
  if (skip_apart) update_travel(num_hints);
  // The contacts' crossing caches, laid out as the hints; started afresh at each neighbour-list build (a cache
  // left to another pair would be safe, its certificate being geometric, but its slot's bookkeeping would not).
  if (crossing_cache && (neighbor->ago == 0 || crossing_cache_of.size() != num_hints)) {
    crossing_cache_of.assign(num_hints, -1);
    crossing_cache_pool.clear();
    crossing_cache_free.clear();
  }

  for (int ii = 0; ii < inum; ii++) {
    int i = ilist[ii];
    int *jlist = firstneigh[i], *touch = first_touch ? first_touch[i] : NULL;
    int *hints = &separating_hint[hint_offset[ii]];
    double *all_history = first_history ? first_history[i] : NULL;
    for (int jj = 0; jj < numneigh[i]; jj++) {
      int j = jlist[jj] & NEIGHMASK;
      double *history = all_history ? &all_history[POLY_HISTORY_SIZE * jj] : NULL;
      double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
      double reach = radius[i] + radius[j];
      bool in_contact = false, near_miss = false;
      poly_overlap_result geometry;
      if (dx * dx + dy * dy + dz * dz < reach * reach) {
        int si = atom->shapetype[i], sj = atom->shapetype[j];
        if (si <= 0 || sj <= 0 || si >= num_shapes || sj >= num_shapes)
          error->one(FLERR, "Pair polyhedral/volumetric: a particle has a shape without template");
        evaluations.candidates++;
        const int slot = hint_offset[ii] + jj;
        double gap = 0.0;
        if (skip_apart && apart_until[slot] > travel[i] + travel[j]) {
          evaluations.hinted++;
        } else if (hints[jj] >= 0 && still_separated(i, j, hints[jj], &gap)) {
          evaluations.hinted++;
          if (skip_apart) start_apart(slot, i, j, gap);
        } else {
          poly_crossing_cache *cache = NULL;
          if (crossing_cache) {
            int &index = crossing_cache_of[slot];
            if (index < 0) index = new_crossing_cache();
            cache = &crossing_cache_pool[index];
          }
          // The filters after the slab by what the pair was at its last evaluation: one touching then is likely
          // touching still, and pays no supporting triangles; one apart then (or new) is likely apart where the
          // filters do not part it, and is searched for a parting plane (parting_search). Without LIGGGHTS' touch
          // flags (`tangential off`: no history list) that is not known, and the former filters stay.
          const int last = !parting_search || !touch ? POLY_LAST_UNKNOWN
                                                     : (touch[jj] ? POLY_LAST_TOUCHING : POLY_LAST_APART);
          workspace_d.last_evaluation = workspace_f.last_evaluation = last;
          const long hits = workspace_d.cache_hits + workspace_f.cache_hits;
          overlap(i, j, &geometry, cache);
          const bool from_cache = workspace_d.cache_hits + workspace_f.cache_hits > hits;
          hints[jj] = geometry.separating;
          if (skip_apart && geometry.filtered_out) start_apart(slot, i, j, geometry.gap);
          count_degenerate(geometry);
          // Faces that touch exactly come out with a round-off volume (the symbolic
          // perturbation may push them together by an infinitesimal amount): below
          // 1e-12 of the smaller particle's volume an overlap is not a contact.
          double volume_i = rmass[i] / density[i], volume_j = rmass[j] / density[j];
          double negligible = 1e-12 * (volume_i < volume_j ? volume_i : volume_j);
          in_contact = geometry.volume > negligible && geometry.depth > 0.0;
          if (in_contact && !centroid_within(i, j, geometry)) in_contact = false;
          near_miss = !in_contact && !geometry.filtered_out;
          if (in_contact && from_cache) evaluations.from_cache++;
          if (near_miss && from_cache) evaluations.misses_from_cache++;
          if (in_contact) evaluations.contacts++;
          else if (geometry.filtered_out) evaluations.parted++;
          else evaluations.near_misses++;
        }
      }
      if (!in_contact) {
        // A near miss keeps its cache: its empty search may be certified as a contact's crossings are.
        if (crossing_cache && !near_miss) release_crossing_cache(hint_offset[ii] + jj);
        // A pair that was not touching has zero history already: LIGGGHTS' lists
        // give new pairs zeros, and a pair leaving contact is cleared here.
        if (history && (!touch || touch[jj]))
          for (int d = 0; d < POLY_HISTORY_SIZE; d++) history[d] = 0.0;
        if (touch) touch[jj] = 0;
        continue;
      }
      const bool persisting = touch && touch[jj];
      if (touch) touch[jj] = 1;

      poly_contact_input input;
      const double depth = poly_contact_pair_depth(geometry.volume, geometry.depth, geometry.projected_area);
      // Several spots: the extent well above the cap (single precision's rounding alone takes up to 1e-4 of it).
      if (geometry.depth > 1.001 * depth) evaluations.capped++;
      if (poly_contact_spots_facing_apart(geometry.volume, depth, geometry.area)) warn_spots_facing_apart();
      poly_contact_input_set_geometry(&input, geometry.volume, depth, geometry.normal, geometry.centroid);
      input.contact_area = geometry.projected_area;
      poly_contact_input_set_second_moment(&input, geometry.second_moment);
      poly_contact_input_set_bodies(&input, x[i], v[i], omega[i], rmass[i], x[j], v[j], omega[j], rmass[j],
                                    update->dt);
      double scratch[POLY_HISTORY_SIZE] = {0.0, 0.0, 0.0, 0.0, 0.0};
      double *state = scratch;
      if (history) {
        if (advance_history) state = history;
        else
          for (int d = 0; d < POLY_HISTORY_SIZE; d++) scratch[d] = history[d];
      }
      poly_contact_output out;
      poly_contact_evaluate(&input, &material(type[i], type[j]), tangential_history, damping, state, &out);

      apply_contact(i, j, geometry.volume, depth, geometry.normal, geometry.centroid, out, persisting);
    }
  }
  share_warnings();
}

// Forces and torques on i (and on j when it is owned here or newton is on),
// virial, and the record for compute pair/polyhedral/local.
void PairPolyhedralVolumetric::apply_contact(int i, int j, double volume, double depth, const double *normal,
                                             const double *centroid, const poly_contact_output &out,
                                             bool persisting)
{
  double **x = atom->x, **f = atom->f, **torque = atom->torque;
  int *tag = atom->tag;
  const int nlocal = atom->nlocal, newton_pair = force->newton_pair;
  for (int k = 0; k < 3; k++) {
    f[i][k] -= out.force_j[k];
    torque[i][k] += out.torque_i[k];
  }
  if (newton_pair || j < nlocal)
    for (int k = 0; k < 3; k++) {
      f[j][k] += out.force_j[k];
      torque[j][k] += out.torque_j[k];
    }
  if (evflag)
    ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, -out.force_j[0], -out.force_j[1], -out.force_j[2],
                 x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]);
  // With newton off a pair with a ghost is computed on both ranks; one records it.
  if (recording && (j < nlocal || tag[i] < tag[j])) {
    PolyContactRecord record;
    record.id_i = tag[i];
    record.id_j = tag[j];
    record.persisting = persisting;
    record.volume = volume;
    record.depth = depth;
    for (int k = 0; k < 3; k++) {
      record.normal[k] = normal[k];
      record.contact_point[k] = centroid[k];
      record.normal_force[k] = (out.normal_force - out.cohesive_force) * normal[k];  // net: repulsion less cohesion
      record.tangential_force[k] = out.tangential_force[k];
    }
    records.push_back(record);
  }
}

void PairPolyhedralVolumetric::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) fwrite(&setflag[i][j], sizeof(int), 1, fp);
}

void PairPolyhedralVolumetric::read_restart(FILE *fp, const int major, const int minor)
{
  read_restart_settings(fp, major, minor);
  allocate();
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      if (comm->me == 0 && fread(&setflag[i][j], sizeof(int), 1, fp) != 1)
        error->one(FLERR, "Pair polyhedral/volumetric: truncated restart file");
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
    }
}

// cohesion rides in the rocking flag's second bit, so files written before it existed read as cohesion off.
void PairPolyhedralVolumetric::write_restart_settings(FILE *fp)
{
  int flags[4] = {tangential_history, damping, precision, (rocking_damping ? 1 : 0) | (cohesion ? 2 : 0)};
  fwrite(flags, sizeof(int), 4, fp);
}

void PairPolyhedralVolumetric::read_restart_settings(FILE *fp, const int, const int)
{
  int flags[4];
  if (comm->me == 0 && fread(flags, sizeof(int), 4, fp) != 4) error->one(FLERR, "Pair polyhedral/volumetric: truncated restart file");
  MPI_Bcast(flags, 4, MPI_INT, 0, world);
  tangential_history = flags[0];
  damping = flags[1];
  precision = flags[2];
  rocking_damping = (flags[3] & 1) != 0;
  cohesion = (flags[3] & 2) != 0;
}

double PairPolyhedralVolumetric::memory_usage()
{
  double bytes = Pair::memory_usage();
  bytes += (double) records.capacity() * sizeof(PolyContactRecord);
  bytes += (double) (separating_hint.capacity() + hint_offset.capacity()) * sizeof(int);
  bytes += (double) (travel.capacity() + last_pose.capacity() + apart_until.capacity()) * sizeof(double);
  return bytes;
}
