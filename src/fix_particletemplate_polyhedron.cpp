#include "fix_particletemplate_polyhedron.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <algorithm>
#include <string>
#include <vector>

#include <mpi.h>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "compute_pair_polyhedral_local.h"
#include "pair_polyhedral_volumetric.h"
#include "update.h"
#include "domain.h"
#include "error.h"
#include "polyhedral_input.h"
#include "force.h"
#include "memory.h"
#include "modify.h"

using namespace LAMMPS_NS;

static const char *const kStyle = "particletemplate/polyhedron";

// FixTemplateSphere parses its keywords (atom_type, density, region, ...) until
// the first one it does not know; ours (file, scale) therefore go last.
static bool is_own_keyword(const char *word) { return strcmp(word, "file") == 0 || strcmp(word, "scale") == 0; }

// A finite number, all of `text`; LIGGGHTS' force->numeric would not name the keyword.
static void require_number(LAMMPS *lmp, char **arg, const char *keyword, const char *text)
{
  double value;
  if (polyhedral_parse_finite(text, &value)) return;
  char message[512];
  snprintf(message, sizeof message, "Fix %s (id %s): '%s' needs a finite number, got '%s'", kStyle, arg[0], keyword,
           text);
  lmp->error->all(FLERR, message);
}

// Numbers of our keywords and of `density constant` are checked here, before
// FixTemplateSphere reads them with a message that does not name the keyword.
static void check_numbers(LAMMPS *lmp, int narg, char **arg)
{
  for (int i = 4; i < narg; i++) {
    if (strcmp(arg[i], "scale") == 0 && i + 1 < narg) require_number(lmp, arg, "scale", arg[i + 1]);
    if (strcmp(arg[i], "density") == 0 && i + 2 < narg && strcmp(arg[i + 1], "constant") == 0)
      require_number(lmp, arg, "density constant", arg[i + 2]);
  }
}

static char **base_keywords_first(LAMMPS *lmp, int narg, char **arg)
{
  if (narg >= 1) check_numbers(lmp, narg, arg);
  static std::vector<char *> ordered;
  ordered.assign(arg, arg + (narg < 4 ? narg : 4));
  std::vector<char *> own;
  for (int i = 4; i < narg; i++) {
    bool own_pair = is_own_keyword(arg[i]) && i + 1 < narg;
    (own_pair ? own : ordered).push_back(arg[i]);
    if (own_pair) own.push_back(arg[++i]);
  }
  ordered.insert(ordered.end(), own.begin(), own.end());
  return &ordered[0];
}

// The smallest distance from the centre of mass to a triangle's plane, if the
// centre is on the inner side of every one: then the ball of that radius is
// inside the shape (from a point outside, a ray towards the shape first meets
// a triangle whose outer side the point is on). Otherwise 0.
static double inner_radius_of(const poly_shape &shape)
{
  double radius = shape.bounding_radius;
  for (int t = 0; t < shape.num_triangles; t++) {
    const double *normal = shape.face_normals + 3 * t;
    const double *corner = shape.vertices + 3 * shape.triangles[3 * t];
    double distance = normal[0] * corner[0] + normal[1] * corner[1] + normal[2] * corner[2];
    if (!(distance > 0.0)) return 0.0;
    if (distance < radius) radius = distance;
  }
  return radius;
}

// FNV-1a over the topology and the quantized body-frame vertices and volume.
static double fingerprint_of(const poly_shape &shape)
{
  uint64_t hash = 14695981039346656037ULL;
  const uint64_t prime = 1099511628211ULL;
  std::vector<int64_t> words;
  words.push_back(shape.num_vertices);
  words.push_back(shape.num_triangles);
  for (int k = 0; k < 3 * shape.num_triangles; k++) words.push_back(shape.triangles[k]);
  // 1e-6 of the bounding radius: any real difference of shape or scale shows, while
  // rounding differences between builds almost never cross a quantization step.
  double unit = shape.bounding_radius * 1e-6;
  for (int k = 0; k < 3 * shape.num_vertices; k++) words.push_back((int64_t) llround(shape.vertices[k] / unit));
  // The volume to 1e-6 relative, through its binary exponent and mantissa.
  int exponent = 0;
  double mantissa = frexp(shape.volume, &exponent);
  words.push_back(exponent);
  words.push_back((int64_t) llround(mantissa * 1e6));
  for (size_t w = 0; w < words.size(); w++)
    for (int byte = 0; byte < 8; byte++) {
      hash ^= (uint64_t) ((words[w] >> (8 * byte)) & 0xff);
      hash *= prime;
    }
  return (double) (hash >> 12);  // 52 bits: exact in a double
}

namespace {
// A compute that only has a schedule: registered with the pair style as a
// recorder for the set-up step, so that the pair style keeps that step's
// contacts; never added to modify.
class OverlapProbe : public Compute {
 public:
  OverlapProbe(LAMMPS *lmp, int &iarg, char **arg) : Compute(lmp, iarg, 3, arg) {}
  void init() {}
};

OverlapProbe *new_overlap_probe(LAMMPS *lmp)
{
  char id[] = "poly_initial_overlaps", group[] = "all", style[] = "pair/polyhedral/local";
  char *arg[3] = {id, group, style};
  int iarg = 3;
  return new OverlapProbe(lmp, iarg, arg);
}

// Overlaps deeper than this fraction of the smaller particle's bounding
// diameter are reported at set-up,
const double kInitialOverlapFraction = 0.01;
// if they also hold this fraction of a cube as deep as their depth: a pair of non-convex particles touching at
// spots a particle size apart has one contact (one contact per pair, document 000 sec. 5.4) whose extent along
// its normal is the spots' spread, millimetres for volumes of 3e-16 m^3 in a settled bed of Schoenhardt polyhedra
// (723 of its 5385 overlapping pairs), and is no deep overlap; a cube's corner pushed in that deep holds a sixth
// of such a cube. (The pair style's depth, which the probe records, is now also capped at 3 V / A,
// poly_contact_pair_depth, which leaves none of that bed's contacts above the fraction; spots whose normals
// oppose each other can still have the spread as their depth.)
const double kInitialOverlapFill = 0.01;
}

FixParticletemplatePolyhedron::FixParticletemplatePolyhedron(LAMMPS *lmp, int narg, char **arg)
    : FixTemplateSphere(lmp, narg, base_keywords_first(lmp, narg, arg)),
      shape_index_(0), density_(0.0), scale_(1.0), fingerprint_(0.0), inner_radius_(0.0), file_(NULL),
      overlap_probe_(NULL), probe_pair_(NULL), own_single_(NULL)
{
  memset(&shape_, 0, sizeof shape_);
  parse_own_keywords(narg, arg);

  char message[512];
  if (poly_shape_load(file_, scale_, &shape_, message, sizeof message) != POLY_OK) {
    poly_shape_free(&shape_);
    error->fix_error(FLERR, this, message);
  }
  if (shape_.was_flipped && comm->me == 0) {  // every rank loads the shape; one says so
    snprintf(message, sizeof message,
             "Fix %s (id %s): shape mesh '%s' is oriented inward; its triangles were flipped", kStyle, id, file_);
    error->warning(FLERR, message);
  }
  if (!gives_usable_mass(density_)) {
    snprintf(message, sizeof message, "density %g gives the shape (volume %g) no finite positive mass and inertia",
             density_, shape_.volume);
    error->fix_error(FLERR, this, message);
  }
  inner_radius_ = inner_radius_of(shape_);
  fingerprint_ = fingerprint_of(shape_);

  // Particles refer to a template by number, so a template cannot be replaced
  // in place. Modify::add_fix empties the slot of a fix being redefined
  // before constructing the new one: an empty slot means redefinition.
  for (int i = 0; i < modify->nfix; i++)
    if (!modify->fix[i])
      error->fix_error(FLERR, this, "a template cannot be redefined (particles refer to its shape number); "
                                    "use a new fix ID");

  // Numbered after the templates that exist already (this fix is not yet in
  // modify->fix); max + 1 so an unfix never leads to a reused number.
  shape_index_ = 1;
  for (int i = 0; i < modify->nfix; i++)
    if (strcmp(modify->fix[i]->style, kStyle) == 0) {
      int existing = static_cast<FixParticletemplatePolyhedron *>(modify->fix[i])->shape_index_;
      if (existing >= shape_index_) shape_index_ = existing + 1;
    }
  print_summary();
}

FixParticletemplatePolyhedron::~FixParticletemplatePolyhedron()
{
  // FixTemplateSphere frees its particles to insert only for its own style name.
  delete pti;
  pti = NULL;
  if (pti_list) delete_ptilist();
  poly_shape_free(&shape_);
  delete[] file_;
  // The pair style may be gone already (at exit force goes before modify).
  if (probe_pair_) ComputePairPolyhedralLocal::recorder_destroyed(lmp, overlap_probe_);
  delete overlap_probe_;
}

void FixParticletemplatePolyhedron::init()
{
  FixTemplateSphere::init();
  // One template does it: the first in modify's list.
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i] && strcmp(modify->fix[i]->style, kStyle) == 0) {
      if (modify->fix[i] != this) return;
      break;
    }
  PairPolyhedralVolumetric *pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (!pair) return;
  if (!overlap_probe_) overlap_probe_ = new_overlap_probe(lmp);
  overlap_probe_->clearstep();
  overlap_probe_->addstep(update->ntimestep);
  pair->record_contacts(overlap_probe_, true);
  probe_pair_ = pair;
}

void FixParticletemplatePolyhedron::setup(int)
{
  if (!probe_pair_) return;
  PairPolyhedralVolumetric *pair = probe_pair_;
  pair->record_contacts(overlap_probe_, false);
  probe_pair_ = NULL;
  if (pair == force->pair && pair->records_step() == update->ntimestep) warn_initial_overlaps();
}

// Particles created or inserted overlapping each other start with a large
// elastic energy and fly apart; this says so instead of leaving it silent.
// Pairs that were in contact at the step before (a settled bed at a later
// run, a restart) carry their load already and are left out: with soft
// materials they rest deeper than the allowance.
void FixParticletemplatePolyhedron::warn_initial_overlaps()
{
  // setup() has checked that force->pair is the pair style the probe was registered with.
  const PairPolyhedralVolumetric *pair = static_cast<PairPolyhedralVolumetric *>(force->pair);
  const std::vector<PolyContactRecord> &records = pair->recorded_contacts();
  double largest_allowance = kInitialOverlapFraction;  // without an atom map: the most any type pair allows
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = 1; j <= atom->ntypes; j++)
      largest_allowance = std::max(largest_allowance, poly_initial_overlap_allowance(&pair->material_of(i, j)));
  double smallest_diameter = 0.0;  // without an atom map: the smallest template's
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i] && strcmp(modify->fix[i]->style, kStyle) == 0) {
      double d = 2.0 * static_cast<FixParticletemplatePolyhedron *>(modify->fix[i])->shape_.bounding_radius;
      if (smallest_diameter == 0.0 || d < smallest_diameter) smallest_diameter = d;
    }
  double counts[2] = {0.0, 0.0}, deepest[2] = {0.0, 0.0};  // count, pairs; deepest fraction, its depth
  for (size_t r = 0; r < records.size(); r++) {
    if (records[r].persisting) continue;
    double size = smallest_diameter, allowance = largest_allowance;
    if (atom->map_style) {
      int i = atom->map(records[r].id_i), j = atom->map(records[r].id_j);
      if (i >= 0 && j >= 0) {
        size = 2.0 * (atom->radius[i] < atom->radius[j] ? atom->radius[i] : atom->radius[j]);
        allowance = poly_initial_overlap_allowance(&pair->material_of(atom->type[i], atom->type[j]));
      }
    }
    double fraction = size > 0.0 ? records[r].depth / size : 0.0;
    double deep = allowance * size;
    counts[1] += 1.0;
    if (fraction > allowance && records[r].volume > kInitialOverlapFill * deep * deep * deep) counts[0] += 1.0;
    else continue;
    if (fraction > deepest[0]) {
      deepest[0] = fraction;
      deepest[1] = records[r].depth;
    }
  }
  double total[2];
  MPI_Allreduce(counts, total, 2, MPI_DOUBLE, MPI_SUM, world);
  struct {
    double value;
    int rank;
  } mine = {deepest[0], comm->me}, worst;
  MPI_Allreduce(&mine, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  double depth = deepest[1];
  MPI_Bcast(&depth, 1, MPI_DOUBLE, worst.rank, world);
  if (total[0] <= 0.0 || comm->me != 0) return;
  char message[512];
  snprintf(message, sizeof message,
           "%.0f of %.0f overlapping particle pairs at the start of this run, new (not in contact at the step "
           "before), overlap deeper than %g%% of the smaller particle's bounding diameter (or than cohesion holds "
           "them) and of at least %g%% of a cube that deep; the deepest by %g (%.3g%% of it). They will be pushed apart violently: check create_polyhedron "
           "positions, insertion with overlapcheck yes, or the data file",
           total[0], total[1], 100.0 * kInitialOverlapFraction, 100.0 * kInitialOverlapFill, depth,
           100.0 * worst.value);
  error->warning(FLERR, message);
}

bool FixParticletemplatePolyhedron::gives_usable_mass(double density) const
{
  const double mass = density * shape_.volume;
  bool usable = isfinite(mass) && mass > 0.0 && isfinite(1.0 / mass);
  for (int k = 0; k < 3; k++) {
    const double moment = density * shape_.principal_moments[k];
    usable = usable && isfinite(moment) && moment > 0.0 && isfinite(1.0 / moment);
  }
  return usable;
}

// FixTemplateSphere has checked seed, atom_type, density and region; this
// reads file and scale, the density value, and rejects anything unknown, or
// given twice (FixTemplateSphere would take the last, and so would this).
void FixParticletemplatePolyhedron::parse_own_keywords(int narg, char **arg)
{
  std::vector<std::string> seen;
  for (int i = 4; i < narg;) {
    if (std::find(seen.begin(), seen.end(), arg[i]) != seen.end()) {
      char message[256];
      snprintf(message, sizeof message, "keyword '%s' given twice", arg[i]);
      error->fix_error(FLERR, this, message);
    }
    seen.push_back(arg[i]);
    if (strcmp(arg[i], "atom_type") == 0 || strcmp(arg[i], "region") == 0 || strcmp(arg[i], "relative") == 0 ||
        strcmp(arg[i], "volume_limit") == 0 || strcmp(arg[i], "additional_group") == 0) {
      i += 2;
    } else if (strcmp(arg[i], "density") == 0) {
      if (i + 3 > narg || strcmp(arg[i + 1], "constant") != 0)
        error->fix_error(FLERR, this, "only 'density constant RHO' is supported");
      density_ = force->numeric(FLERR, arg[i + 2]);
      i += 3;
    } else if (strcmp(arg[i], "file") == 0) {
      if (i + 2 > narg) error->fix_error(FLERR, this, "missing path after 'file'");
      delete[] file_;
      file_ = new char[strlen(arg[i + 1]) + 1];
      strcpy(file_, arg[i + 1]);
      i += 2;
    } else if (strcmp(arg[i], "scale") == 0) {
      if (i + 2 > narg) error->fix_error(FLERR, this, "missing value after 'scale'");
      scale_ = force->numeric(FLERR, arg[i + 1]);
      if (!(scale_ > 0.0)) error->fix_error(FLERR, this, "scale must be > 0");
      i += 2;
    } else {
      error->fix_error(FLERR, this, "unknown keyword", arg[i]);
    }
  }
  if (!file_) error->fix_error(FLERR, this, "missing keyword 'file'");
  if (atom_type > atom->ntypes) error->fix_error(FLERR, this, "atom type exceeds the number of atom types");
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

unsigned int FixParticletemplatePolyhedron::generate_hash()
{
  unsigned int hash = 0;
  unsigned int start = seed_orig * 420001;
  add_hash_value(atom_type, start, hash);
  add_hash_value(shape_index_, start, hash);
  add_hash_value(shape_.volume, start, hash);
  add_hash_value(density_, start, hash);
  return hash;
}

// Insertion through fix particledistribution/discrete and fix insert/*: the
// particles to insert carry this template's shape; their orientation comes from
// the insertion fix. r_bound_ins is the margin by which the fix keeps sampled
// positions from the region's surface and the sub-domain's borders: the inner
// radius where the particles check their vertices themselves.
void FixParticletemplatePolyhedron::fill(ParticleToInsertPolyhedron *particle, int extra_groupbit, int distorder,
                                         const PolyhedronInsertionRules &rules)
{
  particle->atom_type = atom_type;
  particle->shape_template = this;
  particle->shape_index = shape_index_;
  particle->rules = rules;
  particle->radius_ins[0] = shape_.bounding_radius;
  particle->r_bound_ins = rules.vertex_margins ? inner_radius_ : shape_.bounding_radius;
  particle->density_ins = density_;
  particle->volume_ins = shape_.volume;
  particle->mass_ins = density_ * shape_.volume;
  for (int k = 0; k < 3; k++) particle->x_ins[0][k] = particle->v_ins[k] = particle->omega_ins[k] = 0.0;
  particle->quaternion[0] = 1.0;
  particle->quaternion[1] = particle->quaternion[2] = particle->quaternion[3] = 0.0;
  particle->groupbit = groupbit | extra_groupbit;
  particle->distorder = distorder;
}

void FixParticletemplatePolyhedron::init_ptilist(int n_random_max, const bool, FixPropertyAtom *const fix_release)
{
  if (pti_list) error->one(FLERR, "Fix particletemplate/polyhedron: insertion list set up twice");
  n_pti_max = n_random_max;
  pti_list = (ParticleToInsert **) memory->smalloc(n_pti_max * sizeof(ParticleToInsert *), "pti_list");
  for (int i = 0; i < n_pti_max; i++) pti_list[i] = new ParticleToInsertPolyhedron(lmp, fix_release);
}

void FixParticletemplatePolyhedron::randomize_single()
{
  PolyhedronInsertionRules none = {false, NULL, false};
  fill(single_particle(), 0, 0, none);
}

void FixParticletemplatePolyhedron::randomize_ptilist(int n_random, int distribution_groupbit, int distorder)
{
  PolyhedronInsertionRules rules = PolyhedronInsertionRules::of_current_insertion(lmp, this);
  for (int i = 0; i < n_random; i++)
    fill(static_cast<ParticleToInsertPolyhedron *>(pti_list[i]), distribution_groupbit, distorder, rules);
}

void FixParticletemplatePolyhedron::direct_set_ptlist(const int, const void *const, const int, const int)
{
  error->fix_error(FLERR, this, "fix insert/stream/predefined and other pre-defined insertion are not available "
                                "for polyhedral particles; use fix insert/pack, insert/stream or insert/rate/region");
}

// FixTemplateSphere made a sphere to insert; replace it once with ours.
ParticleToInsertPolyhedron *FixParticletemplatePolyhedron::single_particle()
{
  if (!own_single_) {
    delete pti;
    pti = own_single_ = new ParticleToInsertPolyhedron(lmp);
  }
  return own_single_;
}

FixParticletemplatePolyhedron *FixParticletemplatePolyhedron::find(LAMMPS *lmp, int shape_index)
{
  for (int i = 0; i < lmp->modify->nfix; i++) {
    Fix *fix = lmp->modify->fix[i];
    if (fix && strcmp(fix->style, kStyle) == 0) {
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
    if (lmp->modify->fix[i] && strcmp(lmp->modify->fix[i]->style, kStyle) == 0) n++;
  return n;
}
