#include "fix_wall_polyhedral.h"

#include <mpi.h>
#include <math.h>
#include <string.h>

#include <algorithm>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_neighlist_mesh.h"
#include "fix_property_atom.h"
#include "force.h"
#include "modify.h"
#include "neighbor.h"
#include "tri_mesh.h"
#include "update.h"

#include "fix_particletemplate_polyhedron.h"
#include "pair_polyhedral_volumetric.h"
#include "pair_polyhedral_volumetric_gpu.h"
#include "poly_cylinder.h"
#include "polyhedral_input.h"
#include "poly_halfspace.h"

using namespace LAMMPS_NS;
using namespace FixConst;

// fix ID group wall/polyhedral [tangential history|off] [damping on|off] [rocking_damping on|off] [thickness H]
//     [sagitta S] [closed_side auto|inside|outside]
//     primitive type T xplane|yplane|zplane POS  |  primitive type T zcylinder R CX CY  |  mesh n_meshes K meshes MESH-ID ...
FixWallPolyhedral::FixWallPolyhedral(LAMMPS *lmp, int narg, char **arg)
    : Fix(lmp, narg, arg), wall_type(0), axis(-1), position(0.0), cylinder(false), cylinder_radius(0.0),
      sagitta(1e-6), thickness(0.0), shell_thickness(0.0), closed_particles(0),
      have_workspace(false), gpu_precision(-1), gpu_min_pieces(0), tangential(-1), damping(-1), rocking(-1), cohesion(-1), history_id(NULL), history(NULL), pair(NULL),
      force_summed(false), recording(false), records_timestep(-1)
{
  if (strcmp(atom->atom_style, "polyhedron") != 0) error->all(FLERR, "Fix wall/polyhedral requires atom_style polyhedron");
  bool have_plane = false, mesh_only_keyword = false, sagitta_given = false;
  int iarg = 3;
  while (iarg < narg) {
    const char *key = arg[iarg];
    if (strcmp(key, "cohesion") == 0 && iarg + 1 < narg) {
      cohesion = PairPolyhedralVolumetric::cohesion_keyword(lmp, "Fix wall/polyhedral", arg[iarg + 1]);
      iarg += 2;
      continue;
    }
    // LIGGGHTS' fix wall/gran keywords a converted deck keeps (model hertz, ...), before the wall itself.
    if (!have_plane && meshes.empty() &&
        PairPolyhedralVolumetric::liggghts_model_keyword(lmp, "Fix wall/polyhedral", key,
                                                         iarg + 1 < narg ? arg[iarg + 1] : NULL)) {
      iarg += 2;
      continue;
    }
    if ((strcmp(key, "tangential") == 0 || strcmp(key, "damping") == 0 || strcmp(key, "rocking_damping") == 0) &&
        iarg + 1 < narg) {
      const char *value = arg[iarg + 1];
      int *flag = strcmp(key, "tangential") == 0 ? &tangential : (strcmp(key, "damping") == 0 ? &damping : &rocking);
      const char *on = flag == &tangential ? "history" : "on", *off = "off";
      if (strcmp(value, on) == 0) *flag = 1;
      else if (strcmp(value, off) == 0) *flag = 0;
      else {
        char message[256];
        snprintf(message, sizeof message, "Fix wall/polyhedral: invalid value '%s' for '%s' (%s or %s)", value, key,
                 on, off);
        error->all(FLERR, message);
      }
      iarg += 2;
    } else if (strcmp(key, "thickness") == 0 && iarg + 1 < narg) {
      thickness = polyhedral_finite_number(error, "Fix wall/polyhedral", "thickness", arg[iarg + 1]);
      if (!(thickness > 0.0)) error->all(FLERR, "Fix wall/polyhedral: thickness must be positive");
      mesh_only_keyword = true;
      iarg += 2;
    } else if (strcmp(key, "closed_side") == 0 && iarg + 1 < narg) {
      // Where the particles are against a closed surface: decided per particle (auto), or fixed.
      const char *value = arg[iarg + 1];
      if (strcmp(value, "auto") == 0) closed_particles = 0;
      else if (strcmp(value, "inside") == 0) closed_particles = 1;
      else if (strcmp(value, "outside") == 0) closed_particles = -1;
      else {
        char message[256];
        snprintf(message, sizeof message,
                 "Fix wall/polyhedral: invalid value '%s' for 'closed_side' (auto, inside or outside)", value);
        error->all(FLERR, message);
      }
      mesh_only_keyword = true;
      iarg += 2;
    } else if (strcmp(key, "sagitta") == 0 && iarg + 1 < narg) {
      sagitta = polyhedral_finite_number(error, "Fix wall/polyhedral", "sagitta", arg[iarg + 1]);
      sagitta_given = true;
      if (!(sagitta > 0.0 && sagitta < 1.0))
        error->all(FLERR, "Fix wall/polyhedral: sagitta must be between 0 and 1 (a fraction of the bounding radius)");
      iarg += 2;
    } else if (strcmp(key, "primitive") == 0) {
      // One wall a fix, as fix wall/gran: a second would replace the first, or (a plane after a cylinder) not.
      if (have_plane)
        error->all(FLERR, "Fix wall/polyhedral: one 'primitive' a fix (use a fix for each primitive wall)");
      if (iarg + 3 >= narg || strcmp(arg[iarg + 1], "type") != 0)
        error->all(FLERR, "Fix wall/polyhedral: expected 'primitive type T xplane|yplane|zplane POS' or "
                          "'primitive type T zcylinder R CX CY'");
      wall_type = force->inumeric(FLERR, arg[iarg + 2]);
      const char *style = arg[iarg + 3];
      if (strcmp(style, "zcylinder") == 0) {
        if (iarg + 6 >= narg) error->all(FLERR, "Fix wall/polyhedral: expected 'primitive type T zcylinder R CX CY'");
        cylinder = true;
        cylinder_radius = polyhedral_finite_number(error, "Fix wall/polyhedral", "zcylinder R", arg[iarg + 4]);
        cylinder_axis[0] = polyhedral_finite_number(error, "Fix wall/polyhedral", "zcylinder CX", arg[iarg + 5]);
        cylinder_axis[1] = polyhedral_finite_number(error, "Fix wall/polyhedral", "zcylinder CY", arg[iarg + 6]);
        if (!(cylinder_radius > 0.0)) error->all(FLERR, "Fix wall/polyhedral: zcylinder radius R must be positive");
        have_plane = true;
        iarg += 7;
        continue;
      }
      axis = strcmp(style, "xplane") == 0 ? 0 : strcmp(style, "yplane") == 0 ? 1 : strcmp(style, "zplane") == 0 ? 2 : -1;
      if (axis < 0) {
        char message[256];
        snprintf(message, sizeof message,
                 "Fix wall/polyhedral: unknown primitive '%s' (xplane, yplane, zplane and zcylinder are available)",
                 style);
        error->all(FLERR, message);
      }
      if (iarg + 4 >= narg) error->all(FLERR, "Fix wall/polyhedral: expected 'primitive type T xplane|yplane|zplane POS'");
      position = polyhedral_finite_number(error, "Fix wall/polyhedral", style, arg[iarg + 4]);
      have_plane = true;
      iarg += 5;
    } else if (strcmp(key, "mesh") == 0) {
      iarg = parse_mesh(iarg, narg, arg);
    } else {
      // A keyword of ours at the end of the line has no value; LIGGGHTS' model keywords go before the wall.
      static const char *const kValued[] = {"tangential", "damping", "rocking_damping", "thickness", "sagitta",
                                            "closed_side", "cohesion"};
      bool valued = false;
      for (size_t k = 0; k < sizeof kValued / sizeof kValued[0]; k++) valued |= strcmp(key, kValued[k]) == 0;
      char message[320];
      if (valued && iarg + 1 >= narg)
        snprintf(message, sizeof message, "Fix wall/polyhedral: keyword '%s' needs a value", key);
      else if ((have_plane || !meshes.empty()) &&
               (strcmp(key, "model") == 0 || strcmp(key, "rolling_friction") == 0 || strcmp(key, "surface") == 0))
        snprintf(message, sizeof message,
                 "Fix wall/polyhedral: unknown keyword '%s' after the wall (LIGGGHTS' model, rolling_friction and "
                 "surface keywords go before 'primitive' or 'mesh')", key);
      else
        snprintf(message, sizeof message,
                 "Fix wall/polyhedral: unknown keyword '%s' (tangential, damping, rocking_damping, thickness, "
                 "sagitta, closed_side, primitive, mesh; LIGGGHTS' model, cohesion, rolling_friction, surface)", key);
      error->all(FLERR, message);
    }
  }
  if (have_plane && !meshes.empty())
    error->all(FLERR, "Fix wall/polyhedral: either 'primitive' or 'mesh', not both (use two fixes)");
  if (!have_plane && meshes.empty())
    error->all(FLERR, "Fix wall/polyhedral: no wall given ('primitive type T zplane POS' or 'mesh n_meshes 1 meshes ID')");
  if (have_plane && (wall_type < 1 || wall_type > atom->ntypes))
    error->all(FLERR, "Fix wall/polyhedral: wall type out of range");
  if (have_plane && mesh_only_keyword)
    error->all(FLERR, "Fix wall/polyhedral: 'thickness' and 'closed_side' are for mesh walls (a primitive wall is "
                      "a solid half-space or cylinder)");
  if (sagitta_given && !cylinder)
    error->all(FLERR, "Fix wall/polyhedral: 'sagitta' is for 'primitive ... zcylinder' walls");

  vector_flag = 1;
  size_vector = 10;
  global_freq = 1;
  extvector = 1;
  restart_global = 0;
  for (int k = 0; k < 10; k++) wall_force[k] = wall_force_all[k] = 0.0;
  for (int k = 0; k < 3; k++) setup_overlaps[k] = 0.0;
  degenerate.smoothed = degenerate.recomputed = degenerate.inconsistent = 0.0;

  history_id = new char[strlen(id) + 16];
  sprintf(history_id, "%s_history", id);
}

// mesh n_meshes K meshes ID1 ... IDK, the meshes of fix mesh/surface (or mesh/surface/stress).
int FixWallPolyhedral::parse_mesh(int iarg, int narg, char **arg)
{
  if (iarg + 3 >= narg || strcmp(arg[iarg + 1], "n_meshes") != 0 || strcmp(arg[iarg + 3], "meshes") != 0)
    error->all(FLERR, "Fix wall/polyhedral: expected 'mesh n_meshes K meshes MESH-ID ...'");
  int count = force->inumeric(FLERR, arg[iarg + 2]);
  if (count < 1) error->all(FLERR, "Fix wall/polyhedral: 'mesh n_meshes K meshes' needs K >= 1 mesh IDs");
  if (iarg + 4 + count > narg) {
    char message[256];
    snprintf(message, sizeof message, "Fix wall/polyhedral: 'n_meshes %d' but %d mesh ID%s after 'meshes'", count,
             narg - iarg - 4, narg - iarg - 4 == 1 ? "" : "s");
    error->all(FLERR, message);
  }
  for (int k = 0; k < count; k++) {
    const char *mesh_id = arg[iarg + 4 + k];
    int index = modify->find_fix(mesh_id);
    FixMeshSurface *mesh = index >= 0 ? dynamic_cast<FixMeshSurface *>(modify->fix[index]) : NULL;
    char message[512];
    if (index < 0) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s' does not exist (define it with fix ID all "
                                        "mesh/surface file FILE type T before this fix)", mesh_id);
      error->all(FLERR, message);
    }
    if (!mesh) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: fix '%s' is a %s, not a fix mesh/surface", mesh_id,
               modify->fix[index]->style);
      error->all(FLERR, message);
    }
    if (mesh->atomTypeWall() < 1 || mesh->atomTypeWall() > atom->ntypes) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s' has type %d, out of range 1..%d", mesh_id,
               mesh->atomTypeWall(), atom->ntypes);
      error->all(FLERR, message);
    }
    // The same mesh twice would push twice: a doubled wall force.
    for (size_t m = 0; m < mesh_ids.size(); m++)
      if (mesh_ids[m] == mesh_id) {
        snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s' is listed twice", mesh_id);
        error->all(FLERR, message);
      }
    mesh_ids.push_back(mesh_id);
    meshes.push_back(mesh);
  }
  return iarg + 4 + count;
}

FixWallPolyhedral::~FixWallPolyhedral()
{
  if (history && modify->find_fix(history_id) >= 0) modify->delete_fix(history_id);
  delete[] history_id;
  for (size_t m = 0; m < shells.size(); m++) poly_mesh_shell_free(&shells[m]);
  for (size_t m = 0; m < back_shells.size(); m++) poly_mesh_shell_free(&back_shells[m]);
  for (size_t m = 0; m < orientations.size(); m++) poly_mesh_orientation_free(&orientations[m]);
  if (have_workspace) poly_overlap_workspace_destroy_d(&workspace);
  free_wall_views();
}

// Mesh m's contact slots in a particle's history: kMeshContactSlots of kMeshSlotSize each per mesh.
int FixWallPolyhedral::mesh_history_offset(int m) const
{
  return m * kMeshContactSlots * kMeshSlotSize;
}

// The per-atom tangential springs (a primitive's one; a mesh's contact slots), migrating and restarting with the
// atoms; for meshes, LIGGGHTS' triangle-particle neighbour lists (the ones fix wall/gran uses).
void FixWallPolyhedral::post_create()
{
  const int size = meshes.empty() ? POLY_HISTORY_SIZE : mesh_history_offset((int)meshes.size());
  if (modify->find_fix(history_id) < 0) {
    std::vector<const char *> args;
    const char *head[] = {history_id, "all", "property/atom", history_id, size > 1 ? "vector" : "scalar",
                          "yes", "no", "no"};
    args.assign(head, head + 8);
    for (int d = 0; d < size; d++) args.push_back("0.");
    // LIGGGHTS' fix property/atom asks whether more than 20 values are meant (a mesh's contact slots are 32): they
    // are, so its screen and log are away while it is made.
    FILE *screen_kept = screen, *logfile_kept = logfile;
    screen = logfile = NULL;
    modify->add_fix((int)args.size(), const_cast<char **>(&args[0]));
    screen = screen_kept;
    logfile = logfile_kept;
  }
  history = static_cast<FixPropertyAtom *>(modify->fix[modify->find_fix(history_id)]);
  for (size_t m = 0; m < meshes.size(); m++) meshes[m]->createWallNeighList(igroup);
}

void FixWallPolyhedral::pre_delete(bool unfixflag)
{
  if (unfixflag)
    for (size_t m = 0; m < meshes.size(); m++)
      if (modify->find_fix(mesh_ids[m].c_str()) >= 0) meshes[m]->deleteWallNeighList();
}

int FixWallPolyhedral::setmask()
{
  return POST_FORCE;
}

void FixWallPolyhedral::init()
{
  pair = dynamic_cast<PairPolyhedralVolumetric *>(force->pair);
  if (!pair) error->all(FLERR, "Fix wall/polyhedral requires pair_style polyhedral/volumetric (or its /gpu variant)");
  int index = modify->find_fix(history_id);
  if (index < 0) error->all(FLERR, "Fix wall/polyhedral: its history fix was deleted");
  history = static_cast<FixPropertyAtom *>(modify->fix[index]);
  // The wall's own switches decide which materials it needs, whatever the pair style's are.
  use_tangential = tangential < 0 ? pair->tangential_history_on() : tangential;
  use_damping = damping < 0 ? pair->damping_on() : damping;
  use_rocking = use_damping && (rocking < 0 ? pair->rocking_damping_on() : rocking);
  use_cohesion = cohesion < 0 ? pair->cohesion_on() : cohesion;
  PairPolyhedralVolumetric::material_table(lmp, style, use_damping, use_tangential, use_cohesion, materials);
  // With the /gpu pair style the meshes' overlaps run on its GPU, in its precision.
  PairPolyhedralVolumetricGPU *gpu_pair = dynamic_cast<PairPolyhedralVolumetricGPU *>(pair);
  gpu_precision = gpu_pair ? pair->narrow_precision() : -1;
  gpu_min_pieces = gpu_pair ? gpu_pair->wall_pieces_on_gpu_from() : 0;
  if (meshes.empty()) return;

  for (size_t m = 0; m < meshes.size(); m++) {
    int index = modify->find_fix(mesh_ids[m].c_str());
    if (index < 0 || modify->fix[index] != meshes[m]) {
      char message[256];
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s' was deleted", mesh_ids[m].c_str());
      error->all(FLERR, message);
    }
  }
  if (neighbor->style != 1)
    error->all(FLERR, "Fix wall/polyhedral: mesh walls need 'neighbor SKIN bin' (LIGGGHTS' mesh neighbour lists bin)");

  // Shell thickness: the largest particle must not reach through it.
  double largest = 0.0, largest_all = 0.0;
  int max_vertices = 6, max_triangles = 8;
  for (int s = 1; s <= FixParticletemplatePolyhedron::count(lmp); s++) {
    const poly_shape &shape = FixParticletemplatePolyhedron::find(lmp, s)->shape();
    largest = std::max(largest, shape.bounding_radius);
    max_vertices = std::max(max_vertices, shape.num_vertices);
    max_triangles = std::max(max_triangles, shape.num_triangles);
  }
  for (int i = 0; i < atom->nlocal; i++) largest = std::max(largest, atom->radius[i]);
  MPI_Allreduce(&largest, &largest_all, 1, MPI_DOUBLE, MPI_MAX, world);
  shell_thickness = thickness > 0.0 ? thickness : 2.0 * largest_all;
  if (thickness > 0.0 && thickness < 2.0 * largest_all && comm->me == 0) {
    char message[256];
    snprintf(message, sizeof message, "Fix wall/polyhedral: thickness %g is less than the largest particle's bounding "
                                      "diameter %g: a particle may reach through the wall", thickness, 2.0 * largest_all);
    error->warning(FLERR, message);
  }
  if (have_workspace) poly_overlap_workspace_destroy_d(&workspace);
  if (poly_overlap_workspace_create_d(&workspace, max_vertices, max_triangles) != 0)
    error->one(FLERR, "Fix wall/polyhedral: out of memory for the overlap workspace");
  have_workspace = true;
  build_wall_views();
  if (!shells.empty() && shells[0].thickness != shell_thickness) {
    for (size_t m = 0; m < shells.size(); m++) poly_mesh_shell_free(&shells[m]);
    for (size_t m = 0; m < back_shells.size(); m++) poly_mesh_shell_free(&back_shells[m]);
    for (size_t m = 0; m < orientations.size(); m++) poly_mesh_orientation_free(&orientations[m]);
    shells.clear();
    back_shells.clear();
    orientations.clear();
  }
  if (shells.empty()) build_shells();
}

void FixWallPolyhedral::build_wall_views()
{
  const int count = FixParticletemplatePolyhedron::count(lmp);
  for (size_t s = count + 1; s < wall_shapes.size(); s++) poly_shape_free_wall_pieces(&wall_shapes[s]);
  poly_shape empty;
  memset(&empty, 0, sizeof empty);
  wall_shapes.resize(count + 1, empty);
  wall_sources.resize(count + 1, NULL);
  wall_views.assign(count + 1, pair->shape_view(0));
  for (int s = 1; s <= count; s++) {
    const poly_shape *shape = &FixParticletemplatePolyhedron::find(lmp, s)->shape();
    if (wall_sources[s] != shape) {
      poly_shape_free_wall_pieces(&wall_shapes[s]);
      poly_shape_wall_pieces(shape, &wall_shapes[s]);
      wall_sources[s] = shape;
    }
    wall_views[s] = wall_shapes[s].num_clip_pieces > 1 ? poly_shape_view_of(&wall_shapes[s]) : pair->shape_view(s);
  }
}

void FixWallPolyhedral::free_wall_views()
{
  for (size_t s = 0; s < wall_shapes.size(); s++) poly_shape_free_wall_pieces(&wall_shapes[s]);
  wall_shapes.clear();
  wall_sources.clear();
  wall_views.clear();
}

// Every rank builds the shell of every mesh from all its triangles, once: the
// vertex directions need the triangles around each vertex, which a rank's own
// and ghost triangles do not always include.
void FixWallPolyhedral::build_shells()
{
  forget_prisms();  // made from the shells that are being replaced
  for (size_t m = 0; m < meshes.size(); m++) {
    TriMesh *mesh = meshes[m]->triMesh();
    // Before the first run every rank still holds all triangles (LIGGGHTS distributes them at setup), after it
    // its own: either way the union over the ranks has each global number at least once.
    int local = mesh->sizeLocal(), total = 0;
    std::vector<double> mine(10 * (size_t)local);
    for (int j = 0; j < local; j++) {
      mine[10 * j] = mesh->id(j);
      double node[3];
      for (int k = 0; k < 3; k++) {
        mesh->node(j, k, node);
        for (int d = 0; d < 3; d++) mine[10 * j + 1 + 3 * k + d] = node[d];
      }
    }
    int nprocs = comm->nprocs, count = 10 * local;
    std::vector<int> counts(nprocs), offsets(nprocs, 0);
    MPI_Allgather(&count, 1, MPI_INT, &counts[0], 1, MPI_INT, world);
    for (int p = 1; p < nprocs; p++) offsets[p] = offsets[p - 1] + counts[p - 1];
    std::vector<double> all(offsets[nprocs - 1] + counts[nprocs - 1] + 1);
    MPI_Allgatherv(local ? &mine[0] : NULL, count, MPI_DOUBLE, &all[0], &counts[0], &offsets[0], MPI_DOUBLE, world);
    for (size_t e = 0; e + 10 <= all.size(); e += 10) total = std::max(total, (int)all[e] + 1);
    std::vector<double> corners(9 * (size_t)total, 0.0);
    std::vector<char> seen(total, 0);
    for (size_t e = 0; e + 10 <= all.size(); e += 10) {
      int gid = (int)all[e];
      if (gid < 0 || gid >= total) error->one(FLERR, "Fix wall/polyhedral: mesh triangle number out of range");
      seen[gid] = 1;
      for (int d = 0; d < 9; d++) corners[9 * (size_t)gid + d] = all[e + 1 + d];
    }
    char message[512], text[256];
    if (std::count(seen.begin(), seen.end(), 1) != total) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s': triangles missing", mesh_ids[m].c_str());
      error->all(FLERR, message);
    }
    // The connected surfaces, wound consistently and canonically whatever the file's winding; one shell
    // behind and one in front of the canonical orientation.
    poly_mesh_orientation orientation;
    if (poly_mesh_orient(&corners[0], total, 1e-8, &orientation, text, sizeof text) != 0) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s': %s", mesh_ids[m].c_str(), text);
      error->all(FLERR, message);
    }
    orientations.push_back(orientation);
    std::vector<double> canonical(corners.size());
    poly_mesh_shell shell, back;
    for (int reverse = 0; reverse < 2; reverse++) {
      poly_mesh_canonical_corners(&orientation, &corners[0], reverse, &canonical[0]);
      if (poly_mesh_shell_build(&canonical[0], total, shell_thickness, 1e-8, reverse ? &back : &shell, text,
                                sizeof text) != 0) {
        snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s': %s", mesh_ids[m].c_str(), text);
        error->all(FLERR, message);
      }
    }
    shells.push_back(shell);
    back_shells.push_back(back);
    // The shell on the particles' side is the back shell where they are behind the canonical orientation.
    shell.min_depth_fraction = std::min(shell.min_depth_fraction, back.min_depth_fraction);
    shell.num_folded = std::max(shell.num_folded, back.num_folded);
    shell.min_corner_cosine = std::min(shell.min_corner_cosine, back.min_corner_cosine);
    if (comm->me != 0) continue;
    int closed = 0, conflicts = 0, flipped = 0;
    for (int c = 0; c < orientation.num_components; c++) {
      closed += orientation.component_closed[c];
      conflicts += orientation.component_conflicts[c];
      flipped += orientation.component_flipped[c];
    }
    const char *wound = flipped == 0 ? "outward" : flipped == total ? "inward" : "mixed (made consistent)";
    if (closed == orientation.num_components)
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s': closed, %d triangles in %d surface%s, normals %s: %s\n",
               mesh_ids[m].c_str(), total, orientation.num_components, orientation.num_components > 1 ? "s" : "",
               wound, closed_particles > 0 ? "particles inside (closed_side inside): the solid is outside"
                      : closed_particles < 0 ? "particles outside (closed_side outside): the solid is inside"
                                             : "the solid is on the far side from each particle (the body for particles "
                                               "outside, the container for particles inside)");
    else
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: mesh '%s': open, %d triangles in %d connected surface%s (%d closed): the solid "
               "is on the far side of each surface from each particle, whichever way the triangles are wound\n",
               mesh_ids[m].c_str(), total, orientation.num_components, orientation.num_components > 1 ? "s" : "",
               closed);
    if (screen) fputs(message, screen);
    if (logfile) fputs(message, logfile);
    if (orientation.num_misoriented_edges > 0) {
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: mesh '%s': %d shared edges run the same way in both triangles: the triangles' "
               "normals are inconsistent (flipped); they are oriented consistently per connected surface and the "
               "solid taken on the far side from each particle",
               mesh_ids[m].c_str(), orientation.num_misoriented_edges);
      error->warning(FLERR, message);
    }
    if (conflicts > 0) {
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: mesh '%s': %d edges cannot be oriented consistently (a non-orientable surface)",
               mesh_ids[m].c_str(), conflicts);
      error->warning(FLERR, message);
    }
    if (shell.num_nonmanifold_edges > 0) {
      snprintf(message, sizeof message, "Fix wall/polyhedral: mesh '%s': %d edges belong to more than two triangles",
               mesh_ids[m].c_str(), shell.num_nonmanifold_edges);
      error->warning(FLERR, message);
    }
    if (shell.min_depth_fraction < 0.5 || shell.num_folded > 0) {
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: mesh '%s': triangles next to sharp edges are narrow for a shell %g thick: it is "
               "%.2g of that deep there%s%d triangles have no shell (their prisms fold)", mesh_ids[m].c_str(),
               shell_thickness, shell.min_depth_fraction, shell.num_folded ? "; " : "; ", shell.num_folded);
      error->warning(FLERR, message);
    }
    if (shell.min_corner_cosine < 0.2) {
      snprintf(message, sizeof message,
               "Fix wall/polyhedral: mesh '%s' has edges sharper than about 157 degrees between face normals; the "
               "shell behind them is thin there (vertex direction . face normal = %.3g)",
               mesh_ids[m].c_str(), shell.min_corner_cosine);
      error->warning(FLERR, message);
    }
  }
}

void FixWallPolyhedral::setup(int)
{
  force_summed = false;
  records.clear();
  records_timestep = update->ntimestep;
  for (int k = 0; k < 7; k++) wall_force[k] = 0.0;
  for (int k = 0; k < 3; k++) setup_overlaps[k] = 0.0;
  if (meshes.empty()) apply_primitive(false);
  if (!meshes.empty()) compute_mesh_overlaps();
  for (size_t m = 0; m < meshes.size(); m++) apply_mesh((int)m, false);
  warn_initial_overlaps();
  slots_warning.share(lmp);
}

// Particles created or inserted into a wall are pushed out violently; say so at set-up, as the templates do
// for particle pairs (fix particletemplate/polyhedron), with the same 1 % of the bounding diameter (more where
// cohesion holds contacts deeper: poly_initial_overlap_allowance).
void FixWallPolyhedral::warn_initial_overlaps()
{
  double total[2], deepest = 0.0;
  MPI_Allreduce(setup_overlaps, total, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(setup_overlaps + 2, &deepest, 1, MPI_DOUBLE, MPI_MAX, world);
  if (total[1] <= 0.0 || comm->me != 0) return;
  char message[512];
  snprintf(message, sizeof message,
           "Fix wall/polyhedral %s: %.0f of %.0f particle-wall contacts at the start of this run, new (not in "
           "contact at the step before), are deeper than 1%% of the particle's bounding diameter (or than cohesion "
           "holds them), the deepest %.3g%% of it. They will be pushed out violently: check create_polyhedron "
           "positions, insertion regions, or the data file", id, total[1], total[0],
           100.0 * deepest);
  error->warning(FLERR, message);
}

void FixWallPolyhedral::post_force(int)
{
  force_summed = false;
  records.clear();
  records_timestep = update->ntimestep;
  for (int k = 0; k < 7; k++) wall_force[k] = 0.0;
  if (meshes.empty()) apply_primitive(true);
  if (!meshes.empty()) compute_mesh_overlaps();
  for (size_t m = 0; m < meshes.size(); m++) apply_mesh((int)m, true);
  if (PolyhedralRankWarning::due(lmp)) slots_warning.share(lmp);
}

void FixWallPolyhedral::record(int i, int mesh, int triangle, const double *force, const double *centroid,
                               const double *shift, double volume)
{
  const double row[kRecordColumns] = {(double)atom->tag[i], (double)mesh, (double)triangle, force[0], force[1],
                                      force[2], centroid[0] + shift[0], centroid[1] + shift[1],
                                      centroid[2] + shift[2], volume};
  records.insert(records.end(), row, row + kRecordColumns);
}

// The contact law for particle i against a wall of infinite mass moving at wall_velocity at the centroid;
// adds force and torque to the particle and the force to the wall's total. Returns the force on the particle.
void FixWallPolyhedral::apply_contact(int i, int type_of_wall, double *spring, bool advance_history, double volume,
                                      double depth, double contact_area, const double *normal, const double *centroid,
                                      const double *second_moment, const double *wall_velocity,
                                      const double *wall_omega, bool couples, double *force_on_particle,
                                      double *pressure_shift)
{
  double **x = atom->x, **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
  const poly_material_pair *material = &materials[atom->type[i] * (atom->ntypes + 1) + type_of_wall];
  // Set-up: tally for warn_initial_overlaps the contacts that are new, the spring's stiffness (history[3],
  // kept with tangential history) being zero for a particle that did not touch the wall at the step before.
  if (!advance_history && !(spring[3] > 0.0)) {
    double fraction = depth / (2.0 * atom->radius[i]);
    setup_overlaps[0] += 1.0;
    if (fraction > poly_initial_overlap_allowance(material)) setup_overlaps[1] += 1.0;
    if (fraction > setup_overlaps[2]) setup_overlaps[2] = fraction;
  }
  poly_contact_input input;
  poly_contact_input_set_geometry(&input, volume, depth, normal, centroid);
  input.contact_area = contact_area;
  if (use_rocking) poly_contact_input_set_second_moment(&input, second_moment);
  input.couples = couples;
  // The wall: infinite mass (0), its "position" the contact point.
  poly_contact_input_set_bodies(&input, x[i], v[i], omega[i], atom->rmass[i], centroid, wall_velocity, wall_omega,
                                0.0, update->dt);
  double scratch[POLY_HISTORY_SIZE];
  double *law_history = spring;
  if (!advance_history) {
    for (int d = 0; d < POLY_HISTORY_SIZE; d++) scratch[d] = spring[d];
    law_history = scratch;
  }
  poly_contact_output out;
  poly_contact_evaluate(&input, material, use_tangential, use_damping, law_history, &out);
  for (int k = 0; k < 3; k++) {
    f[i][k] -= out.force_j[k];
    torque[i][k] += out.torque_i[k];
    wall_force[k] += out.force_j[k];
    force_on_particle[k] = -out.force_j[k];
    pressure_shift[k] = out.pressure_shift[k];
  }
  wall_force[3] += 1.0;
  // Torque on the wall about the origin: minus the torque the contact puts on the particle.
  const double *p = x[i], *g = force_on_particle;
  double moment[3] = {p[1] * g[2] - p[2] * g[1], p[2] * g[0] - p[0] * g[2], p[0] * g[1] - p[1] * g[0]};
  for (int k = 0; k < 3; k++) wall_force[4 + k] -= moment[k] + out.torque_i[k];
}

// Particle i's overlap with the primitive's solid, which is on the far side of the plane or the cylinder
// from the particle's centre. The cylinder (src/poly_cylinder.h) is replaced by a polygon whose sagitta is
// `sagitta` of the particle's bounding radius, its facet count cached per shape.
void FixWallPolyhedral::primitive_overlap(int i, poly_overlap_result *geometry)
{
  double *x = atom->x[i], radius = atom->radius[i];
  int shapetype = atom->shapetype[i];
  geometry->volume = 0.0;
  double rotation[9];
  if (cylinder) {
    double dx = x[0] - cylinder_axis[0], dy = x[1] - cylinder_axis[1];
    if (!(fabs(sqrt(dx * dx + dy * dy) - cylinder_radius) < radius)) return;
    const poly_shape_view_d &shape = pair->shape_view(shapetype);
    if (shapetype >= (int)cylinder_facets.size()) cylinder_facets.resize(shapetype + 1, 0);
    int &facets = cylinder_facets[shapetype];
    if (facets == 0) facets = poly_cylinder_facets(cylinder_radius, sagitta * shape.bounding_radius);
    poly_quat_to_matrix(atom->quaternion[i], rotation);
    poly_cylinder_overlap(&shape, rotation, x, cylinder_axis, cylinder_radius, facets, geometry);
    return;
  }
  if (!(fabs(x[axis] - position) < radius)) return;
  double side = x[axis] >= position ? 1.0 : -1.0;
  double normal[3] = {0.0, 0.0, 0.0};
  normal[axis] = side;
  poly_quat_to_matrix(atom->quaternion[i], rotation);
  poly_halfspace_overlap(&pair->shape_view(shapetype), rotation, x, normal, side * position, use_rocking,
                         geometry);
}

void FixWallPolyhedral::apply_primitive(bool advance_history)
{
  double **springs = history->array_atom, *rmass = atom->rmass, *density = atom->density;
  const double zero[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    double *spring = springs[i];
    poly_overlap_result geometry;
    primitive_overlap(i, &geometry);
    if (!(geometry.volume > 1e-12 * rmass[i] / density[i]) || !(geometry.depth > 0.0)) {
      for (int d = 0; d < POLY_HISTORY_SIZE; d++) spring[d] = 0.0;
      continue;
    }
    double force[3], shift[3];
    apply_contact(i, wall_type, spring, advance_history, geometry.volume, geometry.depth, geometry.projected_area,
                  geometry.normal,
                  geometry.centroid, geometry.second_moment, zero, zero, true, force, shift);
    if (recording) record(i, 0, -1, force, geometry.centroid, shift, geometry.volume);
  }
}

// 1-3: force on the wall, 4: particle-wall contacts, 5-7: torque on the wall about the origin; 8-10: mesh
// pieces with flush faces, re-evaluated after an inconsistent edge, inconsistent even so, since the fix was
// defined (summed over ranks).
double FixWallPolyhedral::compute_vector(int n)
{
  if (!force_summed) {
    wall_force[7] = degenerate.smoothed;
    wall_force[8] = degenerate.recomputed;
    wall_force[9] = degenerate.inconsistent;
    MPI_Allreduce(wall_force, wall_force_all, 10, MPI_DOUBLE, MPI_SUM, world);
    force_summed = true;
  }
  return wall_force_all[n];
}
