/* dump ID group polyhedron/vtk N file_*.vtp
 * Writes each particle's surface triangles in world coordinates as VTK XML
 * PolyData (one file per snapshot, '*' becomes the timestep), with per-cell
 * id, type, shape, velocity and angular velocity, for ParaView. */
#ifdef DUMP_CLASS
#else

#ifndef LMP_DUMP_POLYHEDRON_VTK_H
#define LMP_DUMP_POLYHEDRON_VTK_H

#include <vector>

#include "dump.h"

namespace LAMMPS_NS {

class DumpPolyhedronVTK : public Dump {
 public:
  DumpPolyhedronVTK(class LAMMPS *, int, char **);
  void write();

 protected:
  void init_style();
  void write_header(bigint) {}
  void pack(int *) {}
  void write_data(int, double *) {}

 private:
  std::vector<double> local_records, all_records;
  void gather_records();
  void write_file(FILE *out);
};

}

#endif
#endif
