#include "dump_polyhedron_vtk.h"

#include <algorithm>
#include <limits.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMPIController.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPPolyDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"
#include "pair_polyhedral_volumetric.h"
#include "poly_rigid.h"

using namespace LAMMPS_NS;

// One particle's record: id type shape x(3) quaternion(4) v(3) omega(3) f(3) contacts.
enum RecordField {
  R_ID = 0, R_TYPE = 1, R_SHAPE = 2, R_X = 3, R_QUAT = 6, R_V = 10, R_OMEGA = 13, R_F = 16, R_CONTACTS = 19,
  RECORD_SIZE = 20
};

static bool ends_with(const char *text, const char *suffix)
{
  size_t n = strlen(text), m = strlen(suffix);
  return n >= m && strcmp(text + n - m, suffix) == 0;
}

static void sort_records_by_id(std::vector<double> &records)
{
  const long count = (long) records.size() / RECORD_SIZE;
  std::vector<long> order(count);
  for (long p = 0; p < count; p++) order[p] = p;
  std::sort(order.begin(), order.end(),
            [&records](long a, long b) { return records[a * RECORD_SIZE] < records[b * RECORD_SIZE]; });
  std::vector<double> sorted(records.size());
  for (long p = 0; p < count; p++)
    std::copy(&records[order[p] * RECORD_SIZE], &records[order[p] * RECORD_SIZE] + RECORD_SIZE,
              &sorted[p * RECORD_SIZE]);
  records.swap(sorted);
}

DumpPolyhedronVTK::DumpPolyhedronVTK(LAMMPS *lmp, int narg, char **arg)
    : Dump(lmp, narg, arg), pieces_per_rank(false), binary_output(true), compressor(COMPRESSOR_ZLIB), compression_level(1),
      write_contacts(false)
{
  if (narg != 5)
    error->all(FLERR, "Illegal dump polyhedron/vtk command: expected ID group polyhedron/vtk N file_*.vtp (or .pvtp)");
  if (!strchr(filename, '*'))
    error->all(FLERR, "dump polyhedron/vtk writes one file per snapshot: the file name needs a '*' for the timestep");
  if (multiproc || compressed || binary)
    error->all(FLERR, "dump polyhedron/vtk: '%', '.gz' and '.bin' file names are not supported "
                      "(a .pvtp file name writes one piece per rank; dump_modify compressor compresses)");
  if (ends_with(filename, ".pvtp")) pieces_per_rank = true;
  else if (!ends_with(filename, ".vtp"))
    error->all(FLERR, "dump polyhedron/vtk: the file name must end in .vtp (one file) or .pvtp (a piece per rank)");
}

void DumpPolyhedronVTK::init_style()
{
  if (strcmp(atom->atom_style, "polyhedron") != 0) error->all(FLERR, "dump polyhedron/vtk requires atom_style polyhedron");
  write_contacts = dynamic_cast<PairPolyhedralVolumetric *>(force->pair) != NULL;
}

// dump_modify ID binary yes|no, compressor zlib|lz4|none (the keywords of LIGGGHTS' dump custom/vtk), and
// compression_level 1-9 for zlib.
int DumpPolyhedronVTK::modify_param(int narg, char **arg)
{
  if (strcmp(arg[0], "binary") == 0) {
    if (narg < 2 || (strcmp(arg[1], "yes") != 0 && strcmp(arg[1], "no") != 0))
      error->all(FLERR, "Illegal dump_modify command: binary yes|no");
    binary_output = strcmp(arg[1], "yes") == 0;
    return 2;
  }
  if (strcmp(arg[0], "compressor") == 0) {
    if (narg < 2) error->all(FLERR, "Illegal dump_modify command: compressor zlib|lz4|none");
    if (strcmp(arg[1], "zlib") == 0) compressor = COMPRESSOR_ZLIB;
    else if (strcmp(arg[1], "lz4") == 0) compressor = COMPRESSOR_LZ4;
    else if (strcmp(arg[1], "none") == 0) compressor = COMPRESSOR_NONE;
    else error->all(FLERR, "Illegal dump_modify command: compressor zlib|lz4|none");
    return 2;
  }
  if (strcmp(arg[0], "compression_level") == 0) {
    char *end = NULL;
    long level = narg < 2 ? 0 : strtol(arg[1], &end, 10);
    if (narg < 2 || *end != '\0' || level < 1 || level > 9)
      error->all(FLERR, "Illegal dump_modify command: compression_level 1-9 (zlib's level)");
    compression_level = (int) level;
    return 2;
  }
  return 0;
}

void DumpPolyhedronVTK::collect_local_records()
{
  const int nlocal = atom->nlocal;
  if (write_contacts) {
    contact_counts.assign(std::max(nlocal, 1), 0.0);
    static_cast<PairPolyhedralVolumetric *>(force->pair)->count_contacts(&contact_counts[0], groupbit);
  }
  local_records.clear();
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double record[RECORD_SIZE] = {
        (double) atom->tag[i], (double) atom->type[i], (double) atom->shapetype[i],
        atom->x[i][0], atom->x[i][1], atom->x[i][2],
        atom->quaternion[i][0], atom->quaternion[i][1], atom->quaternion[i][2], atom->quaternion[i][3],
        atom->v[i][0], atom->v[i][1], atom->v[i][2],
        atom->omega[i][0], atom->omega[i][1], atom->omega[i][2],
        atom->f[i][0], atom->f[i][1], atom->f[i][2],
        write_contacts ? contact_counts[i] : 0.0};
    local_records.insert(local_records.end(), record, record + RECORD_SIZE);
  }
  // A piece in id order, so its layout depends on the decomposition only through which rank holds what (a .vtp's
  // gathered records are put in order on rank 0).
  if (pieces_per_rank) sort_records_by_id(local_records);
}

// Every rank's records on rank 0, in id order.
void DumpPolyhedronVTK::gather_records()
{
  int local_count = (int) local_records.size();
  std::vector<int> counts(comm->nprocs), displacements(comm->nprocs, 0);
  MPI_Gather(&local_count, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  long total = 0;
  if (comm->me == 0)
    for (int p = 0; p < comm->nprocs; p++) {
      if (total > INT_MAX - counts[p])
        error->one(FLERR, "dump polyhedron/vtk: too many particles for one .vtp file: write a .pvtp (a piece per rank)");
      displacements[p] = (int) total;
      total += counts[p];
    }
  all_records.resize(comm->me == 0 ? std::max(total, 1L) : 1);
  MPI_Gatherv(local_records.empty() ? NULL : &local_records[0], local_count, MPI_DOUBLE, &all_records[0],
              &counts[0], &displacements[0], MPI_DOUBLE, 0, world);
  all_records.resize(comm->me == 0 ? total : 0);
  if (comm->me == 0) sort_records_by_id(all_records);
}

std::string DumpPolyhedronVTK::snapshot_path() const
{
  std::string path(filename);
  char step[32];
  snprintf(step, sizeof step, BIGINT_FORMAT, update->ntimestep);
  path.replace(path.find('*'), 1, step);
  return path;
}

static vtkSmartPointer<vtkDoubleArray> double_cell_array(const char *name, int components, vtkIdType cells)
{
  vtkSmartPointer<vtkDoubleArray> array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(cells);
  return array;
}

static vtkSmartPointer<vtkIntArray> int_cell_array(const char *name, vtkIdType cells)
{
  vtkSmartPointer<vtkIntArray> array = vtkSmartPointer<vtkIntArray>::New();
  array->SetName(name);
  array->SetNumberOfTuples(cells);
  return array;
}

// The rank's world communicator as VTK's global controller (LIGGGHTS' dump custom/vtk does the same;
// whichever dump comes first sets it, both on the same communicator).
static vtkMultiProcessController *world_controller(MPI_Comm world)
{
  vtkMultiProcessController *controller = vtkMultiProcessController::GetGlobalController();
  if (controller) return controller;
  vtkMPICommunicatorOpaqueComm opaque(&world);
  vtkMPICommunicator *communicator = vtkMPICommunicator::New();
  communicator->InitializeExternal(&opaque);
  vtkMPIController *mpi_controller = vtkMPIController::New();
  mpi_controller->SetCommunicator(communicator);
  communicator->Delete();
  vtkMultiProcessController::SetGlobalController(mpi_controller);
  return mpi_controller;
}

template <class Writer>
static void configure_writer(Writer *writer, bool binary_output, int compressor, int compression_level)
{
  writer->SetHeaderTypeToUInt64();
  if (!binary_output) {
    writer->SetDataModeToAscii();
    writer->SetCompressorTypeToNone();
    return;
  }
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw bytes, not base64
  if (compressor == 1) {
    writer->SetCompressorTypeToZLib();
    // Default 1: within 3 % of level 5's size on these files at 0.6 of its time (tools/bench_dump_vtk.sh).
    writer->SetCompressionLevel(compression_level);
  }
  else if (compressor == 2) writer->SetCompressorTypeToLZ4();
  else writer->SetCompressorTypeToNone();
}

void DumpPolyhedronVTK::write_polydata(const std::vector<double> &records, const std::string &path)
{
  const long num_particles = (long) records.size() / RECORD_SIZE;
  std::vector<const poly_shape *> shapes(num_particles);
  vtkIdType num_points = 0, num_cells = 0;
  for (long p = 0; p < num_particles; p++) {
    FixParticletemplatePolyhedron *shape_template =
        FixParticletemplatePolyhedron::find(lmp, (int) records[p * RECORD_SIZE + R_SHAPE]);
    if (!shape_template) error->one(FLERR, "dump polyhedron/vtk: a particle has a shape with no template");
    shapes[p] = &shape_template->shape();
    num_points += shapes[p]->num_vertices;
    num_cells += shapes[p]->num_triangles;
  }

  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(num_points);
  double *point = static_cast<vtkDoubleArray *>(points->GetData())->GetPointer(0);
  vtkSmartPointer<vtkIdTypeArray> offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  vtkSmartPointer<vtkIdTypeArray> connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfTuples(num_cells + 1);
  connectivity->SetNumberOfTuples(3 * num_cells);
  vtkIdType *offset = offsets->GetPointer(0), *corner = connectivity->GetPointer(0);

  // Per-triangle copies of each particle's data, so ParaView colours the surfaces by any of them.
  vtkSmartPointer<vtkIntArray> ids = int_cell_array("id", num_cells), types = int_cell_array("type", num_cells),
                               shape_ids = int_cell_array("shape", num_cells),
                               contacts = int_cell_array("contacts", num_cells);
  vtkSmartPointer<vtkDoubleArray> velocities = double_cell_array("v", 3, num_cells),
                                  angular = double_cell_array("omega", 3, num_cells),
                                  forces = double_cell_array("f", 3, num_cells);

  vtkIdType first_point = 0, cell = 0;
  offset[0] = 0;
  for (long p = 0; p < num_particles; p++) {
    const double *record = &records[p * RECORD_SIZE];
    const poly_shape *shape = shapes[p];
    double rotation[9];
    poly_quat_to_matrix(record + R_QUAT, rotation);
    for (int v = 0; v < shape->num_vertices; v++, point += 3) {
      poly_matrix_apply(rotation, shape->vertices + 3 * v, point);
      for (int k = 0; k < 3; k++) point[k] += record[R_X + k];
    }
    for (int t = 0; t < shape->num_triangles; t++, cell++) {
      for (int k = 0; k < 3; k++) *corner++ = first_point + shape->triangles[3 * t + k];
      offset[cell + 1] = 3 * (cell + 1);
      ids->SetValue(cell, (int) record[R_ID]);
      types->SetValue(cell, (int) record[R_TYPE]);
      shape_ids->SetValue(cell, (int) record[R_SHAPE]);
      contacts->SetValue(cell, (int) record[R_CONTACTS]);
      velocities->SetTypedTuple(cell, record + R_V);
      angular->SetTypedTuple(cell, record + R_OMEGA);
      forces->SetTypedTuple(cell, record + R_F);
    }
    first_point += shape->num_vertices;
  }

  vtkSmartPointer<vtkCellArray> triangles = vtkSmartPointer<vtkCellArray>::New();
  triangles->SetData(offsets, connectivity);
  vtkSmartPointer<vtkPolyData> surfaces = vtkSmartPointer<vtkPolyData>::New();
  surfaces->SetPoints(points);
  surfaces->SetPolys(triangles);
  vtkCellData *cell_data = surfaces->GetCellData();
  cell_data->AddArray(ids);
  cell_data->AddArray(types);
  cell_data->AddArray(shape_ids);
  cell_data->AddArray(velocities);
  cell_data->AddArray(angular);
  cell_data->AddArray(forces);
  if (write_contacts) cell_data->AddArray(contacts);
  cell_data->SetActiveScalars("id");
  cell_data->SetActiveVectors("v");

  int written = 0;
  if (pieces_per_rank) {
    vtkSmartPointer<vtkXMLPPolyDataWriter> writer = vtkSmartPointer<vtkXMLPPolyDataWriter>::New();
    configure_writer(writer.GetPointer(), binary_output, compressor, compression_level);
    writer->SetController(world_controller(world));
    writer->SetNumberOfPieces(comm->nprocs);
    writer->SetStartPiece(comm->me);
    writer->SetEndPiece(comm->me);
    writer->SetFileName(path.c_str());
    writer->SetInputData(surfaces);
    written = writer->Write() && writer->GetErrorCode() == 0;
  } else {
    vtkSmartPointer<vtkXMLPolyDataWriter> writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    configure_writer(writer.GetPointer(), binary_output, compressor, compression_level);
    writer->SetFileName(path.c_str());
    writer->SetInputData(surfaces);
    written = writer->Write() && writer->GetErrorCode() == 0;
  }
  if (!written) {
    std::string message = "dump polyhedron/vtk could not write " + path + " (is its directory writable?)";
    error->one(FLERR, message.c_str());
  }
}

void DumpPolyhedronVTK::write()
{
  collect_local_records();
  const std::string path = snapshot_path();
  if (pieces_per_rank) {
    write_polydata(local_records, path);
    return;
  }
  gather_records();
  if (comm->me == 0) write_polydata(all_records, path);
  MPI_Barrier(world);
}
