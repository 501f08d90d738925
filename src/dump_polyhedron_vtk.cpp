#include "dump_polyhedron_vtk.h"

#include <algorithm>
#include <mpi.h>
#include <stdio.h>
#include <string.h>
#include <string>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"
#include "poly_rigid.h"

using namespace LAMMPS_NS;

// One particle's record: id type shape x(3) quaternion(4) v(3) omega(3).
static const int kRecordSize = 16;

DumpPolyhedronVTK::DumpPolyhedronVTK(LAMMPS *lmp, int narg, char **arg) : Dump(lmp, narg, arg)
{
  if (narg != 5) error->all(FLERR, "Illegal dump polyhedron/vtk command: expected ID group polyhedron/vtk N file_*.vtp");
  if (!strchr(filename, '*'))
    error->all(FLERR, "dump polyhedron/vtk writes one file per snapshot: the file name needs a '*' for the timestep");
  if (multiproc || compressed || binary)
    error->all(FLERR, "dump polyhedron/vtk: '%', '.gz' and '.bin' file names are not supported");
}

void DumpPolyhedronVTK::init_style()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0) error->all(FLERR, "dump polyhedron/vtk requires atom_style polyhedron");
}

void DumpPolyhedronVTK::gather_records()
{
  local_records.clear();
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double record[kRecordSize] = {
        (double) atom->tag[i], (double) atom->type[i], (double) atom->shapetype[i],
        atom->x[i][0], atom->x[i][1], atom->x[i][2],
        atom->quaternion[i][0], atom->quaternion[i][1], atom->quaternion[i][2], atom->quaternion[i][3],
        atom->v[i][0], atom->v[i][1], atom->v[i][2],
        atom->omega[i][0], atom->omega[i][1], atom->omega[i][2]};
    local_records.insert(local_records.end(), record, record + kRecordSize);
  }
  int local_count = (int) local_records.size();
  std::vector<int> counts(comm->nprocs), displacements(comm->nprocs, 0);
  MPI_Gather(&local_count, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  int total = 0;
  if (comm->me == 0)
    for (int p = 0; p < comm->nprocs; p++) {
      displacements[p] = total;
      total += counts[p];
    }
  all_records.resize(comm->me == 0 ? std::max(total, 1) : 1);
  MPI_Gatherv(local_records.empty() ? NULL : &local_records[0], local_count, MPI_DOUBLE, &all_records[0],
              &counts[0], &displacements[0], MPI_DOUBLE, 0, world);
  all_records.resize(comm->me == 0 ? total : 0);
}

void DumpPolyhedronVTK::write()
{
  gather_records();
  std::string path(filename);
  char step[32];
  snprintf(step, sizeof step, BIGINT_FORMAT, update->ntimestep);
  path.replace(path.find('*'), 1, step);

  FILE *out = NULL;
  if (comm->me == 0) out = fopen(path.c_str(), "w");
  int ok = comm->me != 0 || out != NULL;
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  if (!ok) {
    std::string message = "dump polyhedron/vtk cannot open file " + path;
    error->all(FLERR, message.c_str());
  }
  if (comm->me == 0) {
    write_file(out);
    ok = fclose(out) == 0;
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  if (!ok) {
    std::string message = "dump polyhedron/vtk could not write file " + path;
    error->all(FLERR, message.c_str());
  }
}

// VTK XML PolyData, ASCII; particles sorted by id so output is independent of the decomposition.
void DumpPolyhedronVTK::write_file(FILE *out)
{
  int num_particles = (int) all_records.size() / kRecordSize;
  std::vector<int> order(num_particles);
  for (int p = 0; p < num_particles; p++) order[p] = p;
  std::sort(order.begin(), order.end(), [this](int a, int b) {
    return all_records[a * kRecordSize] < all_records[b * kRecordSize];
  });

  std::vector<const poly_shape *> shapes(num_particles);
  long num_points = 0, num_cells = 0;
  for (int p = 0; p < num_particles; p++) {
    int shape_index = (int) all_records[order[p] * kRecordSize + 2];
    FixParticletemplatePolyhedron *shape_template = FixParticletemplatePolyhedron::find(lmp, shape_index);
    if (!shape_template) error->one(FLERR, "dump polyhedron/vtk: a particle has a shape with no template");
    shapes[p] = &shape_template->shape();
    num_points += shapes[p]->num_vertices;
    num_cells += shapes[p]->num_triangles;
  }

  fprintf(out, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
  fprintf(out, "<PolyData>\n<Piece NumberOfPoints=\"%ld\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
               "NumberOfStrips=\"0\" NumberOfPolys=\"%ld\">\n", num_points, num_cells);

  fprintf(out, "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (int p = 0; p < num_particles; p++) {
    const double *record = &all_records[order[p] * kRecordSize];
    double rotation[9];
    poly_quat_to_matrix(record + 6, rotation);
    for (int v = 0; v < shapes[p]->num_vertices; v++) {
      double world[3];
      poly_matrix_apply(rotation, shapes[p]->vertices + 3 * v, world);
      fprintf(out, "%.10g %.10g %.10g\n", world[0] + record[3], world[1] + record[4], world[2] + record[5]);
    }
  }
  fprintf(out, "</DataArray>\n</Points>\n");

  fprintf(out, "<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  long first_point = 0;
  for (int p = 0; p < num_particles; p++) {
    const int *triangles = shapes[p]->triangles;
    for (int t = 0; t < shapes[p]->num_triangles; t++)
      fprintf(out, "%ld %ld %ld\n", first_point + triangles[3 * t], first_point + triangles[3 * t + 1],
              first_point + triangles[3 * t + 2]);
    first_point += shapes[p]->num_vertices;
  }
  fprintf(out, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (long c = 1; c <= num_cells; c++) fprintf(out, "%ld\n", 3 * c);
  fprintf(out, "</DataArray>\n</Polys>\n");

  // Per-triangle copies of each particle's data, so ParaView can colour the surfaces.
  fprintf(out, "<CellData Scalars=\"id\" Vectors=\"v\">\n");
  const struct { const char *name, *type; int offset, components; } fields[] = {
      {"id", "Int32", 0, 1}, {"type", "Int32", 1, 1}, {"shape", "Int32", 2, 1},
      {"v", "Float64", 10, 3}, {"omega", "Float64", 13, 3}};
  for (size_t f = 0; f < sizeof fields / sizeof fields[0]; f++) {
    fprintf(out, "<DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"ascii\">\n", fields[f].type,
            fields[f].name, fields[f].components);
    for (int p = 0; p < num_particles; p++) {
      const double *value = &all_records[order[p] * kRecordSize + fields[f].offset];
      for (int t = 0; t < shapes[p]->num_triangles; t++) {
        if (fields[f].components == 1) fprintf(out, "%d\n", (int) value[0]);
        else fprintf(out, "%.10g %.10g %.10g\n", value[0], value[1], value[2]);
      }
    }
    fprintf(out, "</DataArray>\n");
  }
  fprintf(out, "</CellData>\n</Piece>\n</PolyData>\n</VTKFile>\n");
}
