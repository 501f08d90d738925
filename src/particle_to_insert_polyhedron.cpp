#include "particle_to_insert_polyhedron.h"

#include <map>
#include <vector>

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix_insert_pack.h"
#include "fix_particledistribution_discrete.h"
#include "modify.h"
#include "region.h"
#include "update.h"

#include "atom_vec_polyhedron.h"
#include "fix_particletemplate_polyhedron.h"
#include "liggghts_member.h"
#include "poly_overlap.h"
#include "poly_rigid.h"

using namespace LAMMPS_NS;

namespace {

// The insertion settings LIGGGHTS keeps protected in FixInsert and FixInsertPack.
struct CheckOverlapTag { typedef int FixInsert::*Member; friend Member exposed(CheckOverlapTag); };
struct AllInTag { typedef int FixInsert::*Member; friend Member exposed(AllInTag); };
struct InsertRegionTag { typedef Region *FixInsertPack::*Member; friend Member exposed(InsertRegionTag); };
struct SubdomainBorderTag { typedef bool FixInsertPack::*Member; friend Member exposed(SubdomainBorderTag); };
template struct ExposeMember<CheckOverlapTag, &FixInsert::check_ol_flag>;
template struct ExposeMember<AllInTag, &FixInsert::all_in_flag>;
template struct ExposeMember<InsertRegionTag, &FixInsertPack::ins_region>;
template struct ExposeMember<SubdomainBorderTag, &FixInsertPack::check_dist_from_subdomain_border_>;

typedef RegionNeighborList<interpolate_no> NeighbourList;

struct Position {
  double x[3];
  bool operator<(const Position &other) const
  {
    for (int k = 0; k < 3; k++)
      if (x[k] != other.x[k]) return x[k] < other.x[k];
    return false;
  }
  bool same(const double *other) const { return x[0] == other[0] && x[1] == other[1] && x[2] == other[2]; }
};

/* The particles an insertion must not overlap, as the insertion fix's
 * neighbour list holds them. That list keeps a position, a bounding radius and
 * an index per particle; the fix fills it with the existing particles near the
 * insertion volume (local and ghost, index -1), and the particles accepted
 * during this insertion are added to it. Here every particle of the list gets
 * an index into `entries`, which hold its shape and orientation: an existing
 * particle is found in the atom arrays by its position (the fix copied atom->x),
 * an accepted one is recorded as it is accepted. A particle that is not a
 * polyhedron of a known template keeps only its bounding sphere. */
class InsertionNeighbours {
 public:
  InsertionNeighbours()
      : lmp_(NULL), list_(NULL), step_(-1), listed_(0), atoms_mapped_(false), capacity_vertices_(0),
        capacity_triangles_(0)
  {
  }
  ~InsertionNeighbours()
  {
    if (capacity_vertices_ > 0) poly_overlap_workspace_destroy_d(&workspace_);
  }

  // Before the list is used on behalf of a particle: makes every entry of the
  // list one of ours, if the list changed since (a new insertion, or a
  // particle that some other code added).
  void sync(LAMMPS *lmp, NeighbourList &list)
  {
    if (lmp != lmp_ || &list != list_ || lmp->update->ntimestep != step_) {
      lmp_ = lmp;
      list_ = &list;
      step_ = lmp->update->ntimestep;
      entries_.clear();
      atoms_.clear();
      atoms_mapped_ = false;
      listed_ = 0;
      update_views();
    }
    if (list.count() != listed_) reindex();
  }

  // Whether a polyhedron of shape `shape` at `pose` overlaps (positive volume) one in the list.
  bool overlaps(int shape, const poly_pose &pose, double bounding_radius)
  {
    double x[3] = {pose.position[0], pose.position[1], pose.position[2]};
    hits_.clear();
    if (!list_->hasOverlapWith(x, bounding_radius, hits_)) return false;  // broad phase: bounding spheres
    for (size_t h = 0; h < hits_.size(); h++) {
      int index = hits_[h];
      if (index < 0 || index >= (int) entries_.size() || entries_[index].shape == 0) return true;
      const Entry &other = entries_[index];
      poly_overlap_result result;
      poly_overlap_d(&views_[shape], &pose, &views_[other.shape], &other.pose, &workspace_, &result);
      if (result.volume > 0.0) return true;
    }
    return false;
  }

  void add(int shape, const poly_pose &pose, double bounding_radius)
  {
    Entry entry;
    entry.shape = shape;
    entry.pose = pose;
    entries_.push_back(entry);
    double x[3] = {pose.position[0], pose.position[1], pose.position[2]};
    list_->insert(x, bounding_radius, (int) entries_.size() - 1);
    listed_++;
  }

  bool knows_shape(int shape) const { return shape >= 1 && shape < (int) views_.size(); }

 private:
  struct Entry {
    int shape;  // 0: only the bounding sphere is known
    poly_pose pose;
  };

  LAMMPS *lmp_;
  NeighbourList *list_;
  bigint step_;
  size_t listed_;  // particles in the list that have an entry
  std::vector<Entry> entries_;
  std::map<Position, int> atoms_;  // local and ghost atoms in the list's bounding box, by position
  bool atoms_mapped_;
  std::vector<poly_shape_view_d> views_;  // by shape number; [0] unused
  poly_overlap_workspace_d workspace_;
  int capacity_vertices_, capacity_triangles_;
  std::vector<int> hits_;

  void reindex()
  {
    std::vector<Bin<interpolate_no> > bins = list_->getBins();
    list_->clear();
    listed_ = 0;
    for (size_t b = 0; b < bins.size(); b++) {
      const ParticleListNoInterpolate &particles = bins[b].particles;
      for (size_t p = 0; p < particles.size(); p++) {
        Position at;
        for (int k = 0; k < 3; k++) at.x[k] = particles[p].x[k];
        int index = particles[p].index;
        if (index < 0 || index >= (int) entries_.size() || !at.same(entries_[index].pose.position)) {
          entries_.push_back(entry_of_atom_at(at));
          index = (int) entries_.size() - 1;
        }
        list_->insert(at.x, particles[p].radius, index);
        listed_++;
      }
    }
  }

  Entry entry_of_atom_at(const Position &at)
  {
    Atom *atom = lmp_->atom;
    if (!atoms_mapped_) {
      int nall = atom->nlocal + atom->nghost;
      for (int i = 0; i < nall; i++) {
        if (!list_->isInBoundingBox(atom->x[i])) continue;  // the fix lists only particles in there
        Position p;
        for (int k = 0; k < 3; k++) p.x[k] = atom->x[i][k];
        atoms_[p] = i;
      }
      atoms_mapped_ = true;
    }
    Entry entry;
    entry.shape = 0;
    for (int k = 0; k < 3; k++) entry.pose.position[k] = at.x[k];
    entry.pose.quaternion[0] = 1.0;
    entry.pose.quaternion[1] = entry.pose.quaternion[2] = entry.pose.quaternion[3] = 0.0;
    std::map<Position, int>::const_iterator found = atoms_.find(at);
    if (found != atoms_.end() && atom->shapetype && atom->quaternion && knows_shape(atom->shapetype[found->second])) {
      entry.shape = atom->shapetype[found->second];
      for (int k = 0; k < 4; k++) entry.pose.quaternion[k] = atom->quaternion[found->second][k];
    }
    return entry;
  }

  // Views of every template by shape number, and a workspace for the largest.
  void update_views()
  {
    views_.assign(1, poly_shape_view_d());
    int max_vertices = 1, max_triangles = 1;
    for (int s = 1; FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp_, s);
         s++) {
      const poly_shape &shape = shape_template->shape();
      views_.push_back(poly_shape_view_of(&shape));
      if (shape.num_vertices > max_vertices) max_vertices = shape.num_vertices;
      if (shape.num_triangles > max_triangles) max_triangles = shape.num_triangles;
    }
    if (max_vertices <= capacity_vertices_ && max_triangles <= capacity_triangles_) return;
    if (capacity_vertices_ > 0) poly_overlap_workspace_destroy_d(&workspace_);
    capacity_vertices_ = capacity_triangles_ = 0;
    if (poly_overlap_workspace_create_d(&workspace_, max_vertices, max_triangles) != 0)
      lmp_->error->one(FLERR, "Polyhedral insertion: out of memory");
    capacity_vertices_ = max_vertices;
    capacity_triangles_ = max_triangles;
  }
};

InsertionNeighbours &insertion_neighbours()
{
  static InsertionNeighbours neighbours;
  return neighbours;
}

void keep_orientation(const double *quat, double *quaternion)
{
  if (!quat) return;
  for (int k = 0; k < 4; k++) quaternion[k] = quat[k];
  poly_quat_normalize(quaternion);
}

}  // namespace

PolyhedronInsertionRules PolyhedronInsertionRules::of_current_insertion(LAMMPS *lmp, FixTemplateSphere *shape_template)
{
  PolyhedronInsertionRules rules = {false, NULL, false};
  // Insertion fixes run one after the other (pre_exchange, in the order they
  // were defined) and each marks the step at its start: the one inserting now
  // is the last so marked whose distribution has this template.
  FixInsert *inserting = NULL;
  for (int i = 0; i < lmp->modify->nfix; i++) {
    FixInsert *fix = dynamic_cast<FixInsert *>(lmp->modify->fix[i]);
    if (!fix || !fix->has_inserted() || !fix->get_distribution()) continue;
    FixParticledistributionDiscrete *distribution = fix->get_distribution();
    for (int t = 0; t < distribution->n_particletemplates(); t++)
      if (distribution->particletemplates()[t] == shape_template) inserting = fix;
  }
  // insert/pack and insert/rate/region (derived from it) sample positions in a
  // region, keeping r_bound_ins from its surface (all_in) and from the
  // sub-domain's borders; with the overlap check on, particles can refuse a
  // position, so they take over both checks on their vertices.
  FixInsertPack *pack = dynamic_cast<FixInsertPack *>(inserting);
  if (!pack || !(pack->*exposed(CheckOverlapTag()))) return rules;
  rules.vertex_margins = true;
  if (pack->*exposed(AllInTag())) rules.all_in_region = pack->*exposed(InsertRegionTag());
  rules.inside_subdomain = pack->*exposed(SubdomainBorderTag());
  return rules;
}

ParticleToInsertPolyhedron::ParticleToInsertPolyhedron(LAMMPS *lmp, FixPropertyAtom *fix_release)
    : ParticleToInsert(lmp, 1, fix_release), shape_template(NULL), shape_index(0)
{
  quaternion[0] = 1.0;
  quaternion[1] = quaternion[2] = quaternion[3] = 0.0;
  rules.vertex_margins = false;
  rules.all_in_region = NULL;
  rules.inside_subdomain = false;
}

bool ParticleToInsertPolyhedron::vertices_fit(const double *x, const double *quat)
{
  if (!rules.all_in_region && !rules.inside_subdomain) return true;
  const poly_shape &shape = shape_template->shape();
  double rotation[9];
  poly_quat_to_matrix(quat, rotation);
  for (int v = 0; v < shape.num_vertices; v++) {
    double vertex[3];
    poly_matrix_apply(rotation, shape.vertices + 3 * v, vertex);
    for (int k = 0; k < 3; k++) vertex[k] += x[k];
    if (rules.inside_subdomain)
      for (int k = 0; k < 3; k++)
        if (vertex[k] < domain->sublo[k] || vertex[k] > domain->subhi[k]) return false;
    if (rules.all_in_region && !rules.all_in_region->match(vertex[0], vertex[1], vertex[2])) return false;
  }
  return true;
}

int ParticleToInsertPolyhedron::check_near_set_x_v_omega(double *x, double *v, double *omega, double *quat,
                                                        RegionNeighborList<interpolate_no> &neighbours)
{
  InsertionNeighbours &near = insertion_neighbours();
  near.sync(lmp, neighbours);
  if (!shape_template || !near.knows_shape(shape_index)) {
    // Not filled by its template: bounding spheres, as for spheres.
    int placed = ParticleToInsert::check_near_set_x_v_omega(x, v, omega, quat, neighbours);
    if (placed) keep_orientation(quat, quaternion);
    return placed;
  }

  poly_pose pose;
  pose.quaternion[0] = 1.0;
  pose.quaternion[1] = pose.quaternion[2] = pose.quaternion[3] = 0.0;
  keep_orientation(quat, pose.quaternion);
  for (int k = 0; k < 3; k++) pose.position[k] = x[k];
  if (!vertices_fit(x, pose.quaternion)) return 0;
  if (near.overlaps(shape_index, pose, radius_ins[0])) return 0;

  near.add(shape_index, pose, radius_ins[0]);
  for (int k = 0; k < 3; k++) {
    x_ins[0][k] = x[k];
    v_ins[k] = v[k];
    omega_ins[k] = omega[k];
  }
  for (int k = 0; k < 4; k++) quaternion[k] = pose.quaternion[k];
  return 1;
}

int ParticleToInsertPolyhedron::set_x_v_omega(double *x, double *v, double *omega, double *quat)
{
  keep_orientation(quat, quaternion);
  return ParticleToInsert::set_x_v_omega(x, v, omega, quat);
}

int ParticleToInsertPolyhedron::insert()
{
  int inserted = ParticleToInsert::insert();
  if (inserted != 1) return inserted;
  int i = atom->nlocal - 1;
  atom->shapetype[i] = shape_index;
  atom->density[i] = density_ins;
  for (int k = 0; k < 4; k++) atom->quaternion[i][k] = quaternion[k];
  // Mass, bounding radius and principal inertia from the shape.
  static_cast<AtomVecPolyhedron *>(atom->avec)->resolve_shape(i);
  poly_omega_to_angmom(atom->quaternion[i], atom->inertia[i], omega_ins, atom->angmom[i]);
  return inserted;
}
