/* atom_style polyhedron: rigid polyhedral particles.
 *
 * Per particle, beyond the usual id/type/mask/image/x/v/f:
 *   shapetype  1-based index of its fix particletemplate/polyhedron
 *   quaternion orientation, body -> world
 *   angmom     world angular momentum (the integrated state)
 *   omega      world angular velocity (derived, kept for contacts and output)
 *   torque     world torque
 *   density, rmass
 *   radius     bounding-sphere radius about the centre of mass, so the
 *              granular size neighbour lists work unchanged
 *   inertia    body-frame principal moments
 * radius, rmass and inertia follow from shape and density; they are filled
 * from the templates at every init, so data files and restarts need only the
 * shape number and the density.
 */
#ifdef ATOM_CLASS
#else

#ifndef LMP_ATOM_VEC_POLYHEDRON_H
#define LMP_ATOM_VEC_POLYHEDRON_H

#include <map>

#include "atom_vec.h"

namespace LAMMPS_NS {

class AtomVecPolyhedron : public AtomVec {
 public:
  AtomVecPolyhedron(class LAMMPS *);
  void init();
  void grow(int);
  void grow_reset();
  void copy(int, int, int);
  int pack_comm(int, int *, double *, int, int *);
  int pack_comm_vel(int, int *, double *, int, int *);
  void unpack_comm(int, int, double *);
  void unpack_comm_vel(int, int, double *);
  int pack_reverse(int, int, double *);
  void unpack_reverse(int, int *, double *);
  int pack_border(int, int *, double *, int, int *);
  int pack_border_vel(int, int *, double *, int, int *);
  void unpack_border(int, int, double *);
  void unpack_border_vel(int, int, double *);
  int pack_exchange(int, double *);
  int unpack_exchange(double *);
  int size_restart();
  int pack_restart(int, double *);
  int unpack_restart(double *);
  void create_atom(int, double *);
  void data_atom(double *, tagint, char **);
  void data_vel(int, char **);
  void pack_data(double **);
  void pack_data(double **, int);
  void write_data(FILE *, int, double **);
  void pack_vel(double **);
  void pack_vel(double **, int);
  void write_vel(FILE *, int, double **);
  bigint memory_usage();

  // Fills radius, rmass and inertia of local particle i from its template and
  // density; checks a stored mass against the template (restart consistency).
  void resolve_shape(int i);

 private:
  int *tag, *type, *mask;
  tagint *image;
  double **x, **v, **f;
  double *radius, *density, *rmass;
  double **omega, **angmom, **torque, **quaternion, **inertia;
  int *shapetype;

  bool check_restart_masses;  // set by unpack_restart, checked and cleared by init
  // Shape number -> template fingerprint stored in the restart file read (set
  // by unpack_restart, checked against the templates and cleared by init).
  std::map<int, double> restart_fingerprints;
  void check_restart_fingerprints();
  void check_periodic_box();  // ERROR where a template is as wide as a periodic box length

  void shift_for(int pbc_flag, int *pbc, double shift[3]);
  void border_shift_for(int pbc_flag, int *pbc, double shift[3]);
  int pack_state(int i, double *buf);     // everything but x, v, tag/type/mask/image
  int unpack_state(int i, const double *buf);
};

}

#endif
#endif
