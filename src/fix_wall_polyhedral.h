/* fix wall/polyhedral: plane walls and LIGGGHTS triangle-mesh walls for
 * polyhedral particles, with the volumetric contact law of pair_style
 * polyhedral/volumetric (the wall is the second body, of infinite mass).
 *
 * Primitive planes: the overlap of a particle with the wall solid is exact
 * (src/poly_halfspace.h). The zcylinder primitive: exact for a polygonal prism
 * within a stated sagitta of the cylinder (src/poly_cylinder.h). Meshes (fix mesh/surface, mesh/surface/stress, moved
 * by fix move/mesh): each triangle contributes the particle's overlap with its
 * prism of the shell on the far side of the mesh from the particle's centre, per connected surface of the
 * mesh, whichever way its triangles are wound (src/poly_mesh_shell.h, doc/fix_wall_polyhedral.md); the prisms
 * partition the shell, so a particle has one contact per mesh whose volume,
 * centroid and area vector are the sums over the triangles it touches. The
 * force is shared among those triangles by volume for fix mesh/surface/stress.
 * The tangential spring of each particle's contact with each wall is a per-atom
 * property (fix property/atom), so it migrates with the particle and is
 * written to restart files. */
#ifdef FIX_CLASS
#else

#ifndef LMP_FIX_WALL_POLYHEDRAL_H
#define LMP_FIX_WALL_POLYHEDRAL_H

#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

#include "fix.h"
#include "poly_contact.h"
#include "poly_gpu.h"
#include "poly_mesh_shell.h"
#include "poly_overlap.h"
#include "polyhedral_warning.h"

namespace LAMMPS_NS {

class FixWallPolyhedral : public Fix {
 public:
  FixWallPolyhedral(class LAMMPS *, int, char **);
  ~FixWallPolyhedral();
  void post_create();
  void pre_delete(bool unfixflag);
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  double compute_vector(int);
  // The meshes of a `mesh` wall (none for a primitive), e.g. for fix check/timestep/polyhedral.
  const std::vector<class FixMeshSurface *> &wall_meshes() const { return meshes; }

  // compute wall/polyhedral/local: while on, each force evaluation lists its contacts, kRecordColumns values
  // each (particle tag, mesh 1..K or 0 for a primitive, the global id of the mesh triangle with the largest share
  // of the overlap as LIGGGHTS numbers them (-1 for a primitive), force on the particle x y z, contact point x y z,
  // overlap volume).
  enum { kRecordColumns = 10 };
  // A particle touches each surface of a mesh it meets with a contact of its own (apply_mesh): at most
  // kMeshContactSlots at once keep a tangential spring, each slot its history and a triangle of the surface
  // (its global id + 1; 0: free).
  enum { kMeshContactSlots = 4, kMeshSlotSize = POLY_HISTORY_SIZE + 1 };
  void record_contacts(bool on) { recording = on; }
  const std::vector<double> &recorded_contacts() const { return records; }
  bigint records_step() const { return records_timestep; }

  // One triangle's share of a particle's contact with a mesh.
  struct MeshPiece {
    int particle, triangle, triangle_id;  // local atom, local and global triangle
    poly_overlap_result geometry;         // the particle's overlap with the triangle's prism
    double wall_velocity[3];              // at the piece's centroid
    double wall_omega[3];                 // the triangle's angular velocity (a moving mesh's rotation)
    int first_node, num_nodes;            // in `nodes`; num_nodes < 0: not kept
  };

  // A (particle, triangle) pair of the mesh neighbour list, for the side decision.
  struct SideEntry {
    int particle, triangle, component, triangle_id;
    double distance2;                    // from the particle's centre to the triangle
    int side;                            // 0: centre in front of the canonical orientation (solid behind), 1: behind
  };

 private:
  int parse_mesh(int iarg, int narg, char **arg);
  void build_shells();
  void apply_primitive(bool advance_history);
  void primitive_overlap(int i, poly_overlap_result *geometry);
  void apply_mesh(int m, bool advance_history);
  void compute_mesh_overlaps();
  void gather_candidates(int m);
  void collect_pieces(int m);
  void compute_overlaps();
  void apply_contact(int i, int wall_type, double *spring, bool advance_history, double volume, double depth,
                     double contact_area, const double *normal, const double *centroid, const double *second_moment,
                     const double *wall_velocity, const double *wall_omega, bool couples, double *force_on_particle,
                     double *pressure_shift);

  int wall_type;             // atom type of the plane's material
  int axis;                  // 0, 1, 2 for xplane, yplane, zplane; -1: meshes
  double position;           // of the plane along the axis
  bool cylinder;             // zcylinder primitive
  double cylinder_radius, cylinder_axis[2];  // R, (CX, CY)
  double sagitta;            // of the cylinder's polygon, relative to the particle's bounding radius
  std::vector<int> cylinder_facets;  // per shape number, 0 until needed
  std::vector<std::string> mesh_ids;
  std::vector<class FixMeshSurface *> meshes;
  std::vector<poly_mesh_shell> shells;  // per mesh, by global triangle number: solid behind the canonical normals
  std::vector<poly_mesh_shell> back_shells;  // the same with the solid in front (canonical corners reversed)
  std::vector<poly_mesh_orientation> orientations;  // per mesh: connected surfaces, canonical winding
  std::vector<SideEntry> side_entries;
  std::vector<size_t> side_order;
  double thickness;          // of the shell behind the meshes; <= 0: twice the largest bounding radius
  double shell_thickness;    // in use
  int closed_particles;      // closed_side: 0 auto (per particle), 1 inside, -1 outside
  poly_overlap_workspace_d workspace;
  bool have_workspace;
  // Per shape number the view the mesh walls clip prisms with on the host: the pair style's, or for a shape whose
  // own pieces are cones (rock_40) the pieces of poly_shape_wall_pieces, kept in wall_shapes (made from the
  // template's shape in wall_sources, again only when that changes).
  std::vector<poly_shape> wall_shapes;
  std::vector<const poly_shape *> wall_sources;
  std::vector<poly_shape_view_d> wall_views;
  void build_wall_views();
  void free_wall_views();
  // A (particle, prism) pair whose bounding spheres touch, before its overlap is known.
  struct MeshCandidate {
    int particle, triangle, prism;        // local atom, local triangle, slot in `prisms`
  };
  // Prisms kept from step to step, so that a mesh that does not move has each made once (with its clip faces):
  // per (mesh, global triangle, side) a slot of `prisms` (a deque: a prism's view points into it, so it must not
  // move), valid while the triangle's corners are the same to the bit (prism_slot).
  std::deque<poly_mesh_prism> prisms;
  std::vector<double> prism_corners;  // 9 per slot: the corners it was made from
  std::vector<char> prism_made;       // per slot: 0 when the triangle has no prism (degenerate, folded)
  std::unordered_map<long long, int> prism_slots;
  int prism_slot(int m, int triangle_id, int side, const double nodes[3][3]);
  void forget_prisms();
  std::vector<MeshCandidate> candidates;  // of all meshes, mesh by mesh
  std::vector<size_t> mesh_first_candidate;  // mesh m's are [mesh_first_candidate[m], mesh_first_candidate[m + 1])
  std::vector<poly_overlap_result> overlaps;         // per candidate
  std::vector<int> overlap_first_node, overlap_num_nodes;  // per candidate, into `nodes`; < 0: not kept
  std::vector<poly_gpu_wall_overlap> gpu_overlaps;
  int gpu_precision;         // -1: overlaps on the CPU; else on the GPU of the /gpu pair style, in this precision
  long gpu_min_pieces;       // with the GPU: steps with fewer pieces than this compute them on the host
  std::vector<MeshPiece> pieces;
  std::vector<double> nodes;   // of all pieces, world frame relative to their particle
  std::vector<poly_overlap_result> particle_pieces;  // one particle's pieces at a time
  std::vector<int> piece_first_node, piece_num_nodes;
  std::vector<int> piece_plane;  // one particle's pieces: the surface of the mesh each is on (apply_mesh)
  std::vector<double> plane_normals;  // one particle's pieces: their triangles' unit normals (3) and offsets (1)
  int mesh_history_offset(int m) const;  // where mesh m's contact slots start in a particle's history
  bool apply_mesh_plane(int m, int i, size_t first, size_t last, int plane, double *slot, bool advance_history);
  std::vector<unsigned> used_slots;   // per local particle, the contact slots of a mesh this step
  std::vector<int> surface_parent;    // one particle's pieces: union-find of their surfaces
  std::vector<int> surface_slot;      // one particle's surfaces: their contact slots
  int tangential, damping, rocking, cohesion;   // -1: as the pair style
  char *history_id;
  class FixPropertyAtom *history;
  class PairPolyhedralVolumetric *pair;
  int use_tangential, use_damping, use_rocking, use_cohesion;   // this wall's switches, resolved in init()
  std::vector<poly_material_pair> materials;  // (ntypes+1)^2, read with this wall's switches
  double wall_force[10], wall_force_all[10];  // force on the wall (3), contacts, torque on the wall (3),
                                              // then degenerate pieces since the fix was defined (3)
  poly_degenerate_counts degenerate;
  double setup_overlaps[3];  // at set-up: contacts, those deeper than 1 % of the bounding diameter, deepest fraction
  void warn_initial_overlaps();
  bool force_summed;
  bool recording;
  bigint records_timestep;
  PolyhedralRankWarning slots_warning;  // more contacts than slots (fix_wall_polyhedral_mesh.cpp)
  std::vector<double> records;
  void record(int i, int mesh, int triangle, const double *force, const double *centroid, const double *shift,
              double volume);
};

}

#endif
#endif
