/* fix check/timestep/polyhedral: LIGGGHTS' fix check/timestep/gran for
 * polyhedra, same arguments and output vector, so that a converted deck keeps
 * its thermo columns (doc/fix_check_timestep_polyhedral.md). */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_CHECK_TIMESTEP_POLYHEDRAL_H
#define LMP_FIX_CHECK_TIMESTEP_POLYHEDRAL_H

#include "fix.h"

namespace LAMMPS_NS {

class FixCheckTimestepPolyhedral : public Fix {
 public:
  FixCheckTimestepPolyhedral(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void end_of_step();
  double compute_vector(int);

 private:
  void estimate_times();
  double largest_mesh_speed() const;
  void warn(const char *format, double value, double limit);

  double rayleigh_limit, hertz_limit;  // fractions of the two times above which it warns
  bool warnings;
  double rayleigh_time, hertz_time, speed, smallest_radius;
  double fraction_rayleigh, fraction_hertz, fraction_skin;
};

}

#endif
#endif
