/* pair_style polyhedral/volumetric: volumetric-overlap HM+D contacts between
 * polyhedral particles (CPU reference). Geometry: poly_overlap.h; law:
 * poly_contact.h; this class only moves data between LIGGGHTS and those. */
#ifdef PAIR_CLASS
#else

#ifndef LMP_PAIR_POLYHEDRAL_VOLUMETRIC_H
#define LMP_PAIR_POLYHEDRAL_VOLUMETRIC_H

#include <vector>

#include "pair.h"
#include "poly_contact.h"
#include "poly_overlap.h"
#include "polyhedral_warning.h"

namespace LAMMPS_NS {

// One active contact, as listed by compute pair/polyhedral/local.
struct PolyContactRecord {
  int id_i, id_j;
  int persisting;  // the pair was in contact at the step before (LIGGGHTS' touch flag): not a new overlap
  double volume, depth, normal[3], contact_point[3], normal_force[3], tangential_force[3];
};

class PairPolyhedralVolumetric : public Pair {
 public:
  PairPolyhedralVolumetric(class LAMMPS *);
  ~PairPolyhedralVolumetric();
  void compute(int, int);
  void settings(int, char **);
  void coeff(int, char **);
  void init_style();
  void init_list(int, class NeighList *);
  double init_one(int, int);
  void *extract(const char *, int &);
  void write_restart(FILE *);
  void read_restart(FILE *, const int, const int);
  void write_restart_settings(FILE *);
  void read_restart_settings(FILE *, const int, const int);
  double memory_usage();

  int computeflag;                  // read by the contact-history fix
  class NeighList *listgranhistory; // touch flags and history per neighbour

  // compute pair/polyhedral/local registers itself (NULL: none) and reads the
  // records, which are made only on the steps LIGGGHTS' output invokes it
  // (its timeflag), so the GPU style keeps its fast path on the other steps.
  void record_contacts(class Compute *compute, bool on);
  const std::vector<PolyContactRecord> &recorded_contacts() const { return records; }
  bigint records_step() const { return records_timestep; }

  // Contacts with flush faces, re-evaluated, still inconsistent, on this rank since the style was defined.
  const poly_degenerate_counts &degenerate_counts() const { return degenerate; }

  // What the pair loop did with its neighbour pairs on this rank since the style was defined (compute
  // pair/polyhedral/local's vector 4-8): pairs whose bounding spheres overlap; of them, those the plane that
  // parted them at their last evaluation still parts (not evaluated); and the evaluations that found a contact,
  // that the slab or a parting plane found apart before the whole path, and that found no contact after it (near
  // misses, which cost about what a contact does).
  struct EvaluationCounts {
    double candidates, hinted, contacts, parted, near_misses;
    double from_cache;  // contacts evaluated from their certified crossings (crossing_cache)
    double misses_from_cache;  // near misses evaluated from their certified (empty) search
    double capped;  // contacts whose extent is over 1.001 times their law depth 3 V / A: several spots
  };
  const EvaluationCounts &evaluation_counts() const { return evaluations; }

  // LIGGGHTS' contact-model keywords of pair gran and fix wall/gran, as a converted deck keeps them (model,
  // cohesion, rolling_friction, surface; tangential no_history): accepted where they say what this law does
  // anyway, else an ERROR naming the alternative. Returns whether `key` was one of them.
  static bool liggghts_model_keyword(class LAMMPS *lmp, const char *caller, const char *key, const char *value);

  // For compute contact/polyhedron: adds to count[i] the number of particles each local particle of the group
  // (mask & groupbit) touches, from the contacts of the last force evaluation.
  void count_contacts(double *count, int groupbit);

  // The effective materials of all type pairs (fix wall/polyhedral builds its own with its switches).
  static void material_table(class LAMMPS *lmp, const char *caller, bool with_restitution, bool with_friction,
                             bool with_cohesion, std::vector<poly_material_pair> &table);
  // Cohesion that would sink faces deeper than 20 % of their size (k/E* > 0.15) is an ERROR; beyond 5 % a WARNING.
  static void check_cohesion_depth(class LAMMPS *lmp, const char *caller, int i, int j, double k,
                                   double youngs_effective);
  static constexpr double kCohesionDepthWarning = 0.05, kCohesionDepthError = 0.2;
  const poly_material_pair &material_of(int itype, int jtype) const { return material(itype, jtype); }
  // `cohesion sjkr|off` of a pair_style or fix wall line: 1 or 0 (other values: the ERROR of liggghts_model_keyword).
  static int cohesion_keyword(class LAMMPS *lmp, const char *caller, const char *value);
  bool cohesion_on() const { return cohesion; }

  // For fix wall/polyhedral: the shapes and the switches.
  const poly_shape_view_d &shape_view(int shapetype) const { return views_d[shapetype]; }
  bool tangential_history_on() const { return tangential_history; }
  bool damping_on() const { return damping; }
  bool rocking_damping_on() const { return rocking_damping; }
  int narrow_precision() const { return precision; }  // poly_precision

  // Called by the contact-history fix before LIGGGHTS reads the history in the
  // neighbour list; a style that keeps history elsewhere (the GPU) puts it back.
  virtual void history_to_host() {}

 protected:
  bool tangential_history, damping, rocking_damping, cohesion;
  bool crossing_cache;  // `crossing_cache on` (default): contacts reuse their crossings while certified
  bool skip_apart;      // `skip_apart on` (default): pairs found apart wait until they may have moved their gap
  bool parting_search;  // `parting_search on` (default): the filters by a pair's last evaluation (touching: no
                        // supporting triangles; apart: also the parting search, poly_overlap_parting_impl.h)
  int precision;  // poly_precision
  std::vector<class Compute *> recorders;
  bool recording;               // on this step
  bigint records_timestep;
  std::vector<PolyContactRecord> records;
  poly_degenerate_counts degenerate;
  EvaluationCounts evaluations;
  PolyhedralRankWarning inconsistent_warning, centroid_warning, apart_spots_warning;
  void warn_centroid_outside();
  void warn_spots_facing_apart();
  void share_warnings();
  void count_degenerate(const poly_overlap_result &geometry);
  bool centroid_within(int i, int j, const poly_overlap_result &geometry);

  std::vector<poly_shape_view_d> views_d;  // indexed by shape number
  std::vector<poly_shape_view_f> views_f;
  poly_overlap_workspace_d workspace_d;
  poly_overlap_workspace_f workspace_f;
  bool have_workspace;

  std::vector<poly_material_pair> materials;  // (ntypes+1)^2, effective constants per type pair
  double *maxrad;             // largest bounding radius per type
  class FixContactHistoryPolyhedral *fix_history;

  void allocate();
  void load_materials();
  void build_shape_views();
  void free_shape_views();
  void ensure_history_fix();
  void check_timestep();
  bool begin_compute(int eflag, int vflag);
  void poses(int i, int j, poly_pose *pose_i, poly_pose *pose_j) const;
  void overlap(int i, int j, poly_overlap_result *result, poly_crossing_cache *cache = NULL);
  // Per neighbour pair in contact or a near miss, its crossing cache (poly_crossing_cache): crossing_cache_of, laid
  // out as the hints, indexes the pool (-1: none); entries of pairs that part go to the free list.
  std::vector<int> crossing_cache_of, crossing_cache_free;
  std::vector<poly_crossing_cache> crossing_cache_pool;
  int new_crossing_cache();
  void release_crossing_cache(int slot);
  // Per neighbour pair, the code of the supporting triangle that parted it at its last evaluation (-1: none),
  // laid out as the neighbour list (hint_offset per ii): most pairs that are apart stay apart from one step
  // to the next, and one plane shows it. A code left from another pair after a neighbour-list build is safe
  // (poly_overlap_still_separated tests it on the current pose), merely useless.
  std::vector<int> separating_hint, hint_offset;
  bool still_separated(int i, int j, int hint, double *gap);
  // A pair found apart waits, not evaluated, until its two particles may have moved the gap proved between them
  // (poly_overlap_result's gap): `travel`, per particle (owned and ghost), how far any of its points may have moved
  // since the neighbour-list build, from `last_pose` (x, quaternion) at the last step; `apart_until`, per
  // neighbour pair (laid out as the hints), the sum of the two travels up to which it stays apart (-1: none).
  std::vector<double> travel, last_pose, apart_until;
  void update_travel(size_t num_pairs);
  void start_apart(int slot, int i, int j, double gap);
  void apply_contact(int i, int j, double volume, double depth, const double *normal, const double *centroid,
                     const poly_contact_output &out, bool persisting);
  const poly_material_pair &material(int itype, int jtype) const
  {
    return materials[itype * (atom_ntypes + 1) + jtype];
  }
  int atom_ntypes;
};

}

#endif
#endif
