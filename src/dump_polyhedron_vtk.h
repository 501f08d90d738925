/* dump ID group polyhedron/vtk N file_*.vtp | file_*.pvtp
 * Writes each particle's surface triangles in world coordinates as VTK XML
 * PolyData through VTK's own writers (one file per snapshot, '*' becomes the
 * timestep): a .vtp gathered on rank 0 in id order, or a .pvtp index with one
 * .vtp piece per rank. Per-triangle id, type, shape, velocity, angular
 * velocity, force and contact count, for ParaView. */
#ifdef DUMP_CLASS
#else

#ifndef LMP_DUMP_POLYHEDRON_VTK_H
#define LMP_DUMP_POLYHEDRON_VTK_H

#include <string>
#include <vector>

#include "dump.h"

namespace LAMMPS_NS {

class DumpPolyhedronVTK : public Dump {
 public:
  DumpPolyhedronVTK(class LAMMPS *, int, char **);
  void write();

 protected:
  void init_style();
  int modify_param(int, char **);
  void write_header(bigint) {}
  void pack(int *) {}
  void write_data(int, double *) {}

 private:
  enum Compressor { COMPRESSOR_NONE, COMPRESSOR_ZLIB, COMPRESSOR_LZ4 };
  bool pieces_per_rank;  // .pvtp: one piece per rank; .vtp: one file from rank 0
  bool binary_output;
  Compressor compressor;
  int compression_level;  // zlib's, 1 (fastest) to 9
  bool write_contacts;   // the pair style counts contacts (pair_style polyhedral/volumetric)
  std::vector<double> local_records, all_records, contact_counts;
  void collect_local_records();
  void gather_records();
  void write_polydata(const std::vector<double> &records, const std::string &path);
  std::string snapshot_path() const;
};

}

#endif
#endif
