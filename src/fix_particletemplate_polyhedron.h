/* fix particletemplate/polyhedron: a polyhedral shape read from a mesh file.
 *
 * Templates are numbered 1, 2, ... in the order they are defined; that number
 * is the per-particle `shape` of atom_style polyhedron. The class derives from
 * LIGGGHTS' FixTemplateSphere because fix particledistribution/discrete and
 * the fix insert styles treat every "particletemplate/" style as one; its
 * insertion methods hand them ParticleToInsertPolyhedron objects, which give
 * inserted atoms this template's shape. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_PARTICLETEMPLATE_POLYHEDRON_H
#define LMP_FIX_PARTICLETEMPLATE_POLYHEDRON_H

#include "fix_template_sphere.h"
#include "particle_to_insert_polyhedron.h"
#include "poly_shape.h"

namespace LAMMPS_NS {

class FixParticletemplatePolyhedron : public FixTemplateSphere {
 public:
  FixParticletemplatePolyhedron(class LAMMPS *, int, char **);
  ~FixParticletemplatePolyhedron();
  // The first template checks, at each run's set-up, for overlapping particles.
  void init();
  void setup(int);

  const poly_shape &shape() const { return shape_; }
  // Whether `density` gives this shape a finite positive mass and principal moments with finite inverses (the
  // integrator divides by them).
  bool gives_usable_mass(double density) const;
  int shape_index() const { return shape_index_; }
  int particle_type() const { return atom_type; }
  double density() const { return density_; }
  const char *file() const { return file_; }
  double scale() const { return scale_; }
  // A 52-bit hash of the scaled shape (its body-frame triangles and vertices to
  // 1e-6 of the bounding radius), exact as a double: atom_style polyhedron
  // stores it per particle in restart files, so a restart read with another
  // mesh or scale of the same volume is refused.
  double fingerprint() const { return fingerprint_; }

  // What fix particledistribution/discrete asks of a template.
  double volexpect() { return shape_.volume; }
  double massexpect() { return shape_.volume * density_; }
  double min_rad() { return shape_.bounding_radius; }
  double max_rad() { return shape_.bounding_radius; }
  double max_r_bound() { return shape_.bounding_radius; }
  int number_spheres() { return 1; }
  unsigned int generate_hash();

  // Insertion through fix particledistribution/discrete and fix insert/*.
  void init_ptilist(int, const bool, FixPropertyAtom *const);
  void randomize_single();
  void randomize_ptilist(int, int, int);
  void direct_set_ptlist(const int, const void *const, const int, const int);

  // The template whose shape number is `shape_index` (1-based), or NULL.
  static FixParticletemplatePolyhedron *find(class LAMMPS *, int shape_index);
  // The template with fix ID `id`, or NULL.
  static FixParticletemplatePolyhedron *find(class LAMMPS *, const char *id);
  static int count(class LAMMPS *);

 private:
  poly_shape shape_;
  int shape_index_;
  double density_;
  double scale_;
  double fingerprint_;
  double inner_radius_;  // of a ball about the centre of mass inside the shape (0 if none is found)
  char *file_;

  class Compute *overlap_probe_;               // makes the pair style record the set-up contacts
  class PairPolyhedralVolumetric *probe_pair_;  // where overlap_probe_ is registered, or NULL
  void warn_initial_overlaps();

  void parse_own_keywords(int narg, char **arg);
  void print_summary();
  ParticleToInsertPolyhedron *own_single_;
  void fill(ParticleToInsertPolyhedron *particle, int extra_groupbit, int distorder,
            const PolyhedronInsertionRules &rules);
  ParticleToInsertPolyhedron *single_particle();
};

}

#endif
#endif
