/* fix particletemplate/polyhedron: a polyhedral shape read from a mesh file.
 * Templates are numbered 1, 2, ... in the order they are defined; that number
 * is the per-particle `shape` of atom_style polyhedron. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_PARTICLETEMPLATE_POLYHEDRON_H
#define LMP_FIX_PARTICLETEMPLATE_POLYHEDRON_H

#include "fix.h"
#include "poly_shape.h"

namespace LAMMPS_NS {

class FixParticletemplatePolyhedron : public Fix {
 public:
  FixParticletemplatePolyhedron(class LAMMPS *, int, char **);
  ~FixParticletemplatePolyhedron();
  int setmask() { return 0; }

  const poly_shape &shape() const { return shape_; }
  int shape_index() const { return shape_index_; }
  int atom_type() const { return atom_type_; }
  double density() const { return density_; }
  const char *file() const { return file_; }

  // The template whose shape number is `shape_index` (1-based), or NULL.
  static FixParticletemplatePolyhedron *find(class LAMMPS *, int shape_index);
  // The template with fix ID `id`, or NULL.
  static FixParticletemplatePolyhedron *find(class LAMMPS *, const char *id);
  static int count(class LAMMPS *);

 private:
  poly_shape shape_;
  int shape_index_;
  int atom_type_;
  double density_;
  double scale_;
  char *file_;
  int seed_;

  void print_summary();
};

}

#endif
#endif
