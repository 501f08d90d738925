/* fix wall/polyhedral, its triangle meshes each step (src/fix_wall_polyhedral.cpp has the rest of the fix):
 * the (particle, prism) candidates from LIGGGHTS' mesh neighbour lists with each particle's side of each
 * connected surface, their overlaps on the CPU or in one GPU call, and one contact per particle and mesh
 * combined from its pieces. */
#include "fix_wall_polyhedral.h"

#include <math.h>
#include <string.h>

#include <algorithm>

#include "atom.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_neighlist_mesh.h"
#include "fix_property_atom.h"
#include "tri_mesh.h"

#include "pair_polyhedral_volumetric.h"
#include "pair_polyhedral_volumetric_gpu.h"

using namespace LAMMPS_NS;

// Kept prisms (about 1.8 kB each) past which they are all forgotten and made again as needed: about 30 MB a rank.
static const size_t kMostKeptPrisms = 16384;

// The (particle, prism) candidates of every mesh and their overlaps, in one batch (one GPU call per step).
void FixWallPolyhedral::compute_mesh_overlaps()
{
  if (prisms.size() > kMostKeptPrisms) forget_prisms();
  candidates.clear();
  mesh_first_candidate.assign(meshes.size() + 1, 0);
  for (size_t m = 0; m < meshes.size(); m++) {
    gather_candidates((int)m);
    mesh_first_candidate[m + 1] = candidates.size();
  }
  compute_overlaps();
}

// The slot of the prism of (mesh m, global triangle, side) over corners `nodes` (canonical order): the kept one
// when it was made from the same corners, else made again in its slot; -1 when the triangle has no prism.
int FixWallPolyhedral::prism_slot(int m, int triangle_id, int side, const double nodes[3][3])
{
  const long long key = ((long long)m << 33) | ((long long)triangle_id << 1) | side;
  std::unordered_map<long long, int>::const_iterator found = prism_slots.find(key);
  int slot;
  if (found != prism_slots.end()) {
    slot = found->second;
    if (memcmp(&prism_corners[9 * (size_t)slot], nodes, 9 * sizeof(double)) == 0) return prism_made[slot] ? slot : -1;
  } else {
    slot = (int)prisms.size();
    prisms.push_back(poly_mesh_prism());
    prism_corners.resize(9 * prisms.size());
    prism_made.push_back(0);
    prism_slots[key] = slot;
  }
  memcpy(&prism_corners[9 * (size_t)slot], nodes, 9 * sizeof(double));
  prism_made[slot] = poly_mesh_shell_prism(side ? &back_shells[m] : &shells[m], triangle_id, nodes, &prisms[slot]) == 0;
  return prism_made[slot] ? slot : -1;
}

void FixWallPolyhedral::forget_prisms()
{
  prisms.clear();
  prism_corners.clear();
  prism_made.clear();
  prism_slots.clear();
}

static bool side_entry_order(const FixWallPolyhedral::SideEntry &a, const FixWallPolyhedral::SideEntry &b)
{
  if (a.particle != b.particle) return a.particle < b.particle;
  if (a.component != b.component) return a.component < b.component;
  if (a.distance2 != b.distance2) return a.distance2 < b.distance2;
  return a.triangle_id < b.triangle_id;
}

// Triangle j's current corners in canonical order (reverse: the canonical reversed, for the back shell).
static void canonical_nodes(TriMesh *mesh, int j, int flip, double nodes[3][3])
{
  const int order[3] = {0, flip ? 2 : 1, flip ? 1 : 2};
  for (int k = 0; k < 3; k++) mesh->node(j, order[k], nodes[k]);
}

// Each (particle, triangle) pair of LIGGGHTS' mesh neighbour list whose bounding spheres can touch, with the
// prism on the far side from the particle: per particle and connected surface, the side of the particle's
// centre at the surface's point nearest it (the sign against the pseudo-normal of the face, edge or vertex
// that point lies on, as for the inside test of a closed surface), so every triangle of the surface near the
// particle puts its prism on the same side.
void FixWallPolyhedral::gather_candidates(int m)
{
  TriMesh *mesh = meshes[m]->triMesh();
  FixNeighlistMesh *list = meshes[m]->meshNeighlist();
  const poly_mesh_orientation &orientation = orientations[m];
  const poly_mesh_shell &front = shells[m];
  double **x = atom->x, *radius = atom->radius;
  int *mask = atom->mask;
  const int nlocal = atom->nlocal, triangles = mesh->size();
  side_entries.clear();
  for (int j = 0; j < triangles; j++) {
    const std::vector<int> &neighbours = list->get_contact_list(j);
    if (neighbours.empty()) continue;
    const int id = mesh->id(j);
    double nodes[3][3], e1[3], e2[3], normal[3];
    canonical_nodes(mesh, j, orientation.flip[id], nodes);
    for (int k = 0; k < 3; k++) {
      e1[k] = nodes[1][k] - nodes[0][k];
      e2[k] = nodes[2][k] - nodes[0][k];
    }
    normal[0] = e1[1] * e2[2] - e1[2] * e2[1];
    normal[1] = e1[2] * e2[0] - e1[0] * e2[2];
    normal[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double length = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(length > 0.0)) continue;
    for (int k = 0; k < 3; k++) normal[k] /= length;
    for (size_t c = 0; c < neighbours.size(); c++) {
      int i = neighbours[c];
      if (i >= nlocal || !(mask[i] & groupbit)) continue;
      // Neither prism reaches a particle this far from the triangle's plane; and if this were the surface's
      // nearest triangle, the particle would not touch the surface (only, at most, the shell's side at an
      // open border, where either side will do).
      double height = (x[i][0] - nodes[0][0]) * normal[0] + (x[i][1] - nodes[0][1]) * normal[1] +
                      (x[i][2] - nodes[0][2]) * normal[2];
      if (!(fabs(height) < radius[i])) continue;
      double closest[3], pseudo[3];
      int feature = poly_triangle_closest(x[i], nodes[0], nodes[1], nodes[2], closest);
      const double *coefficients = NULL;
      if (feature >= 4) coefficients = orientation.edge_normals + 9 * (size_t)id + 3 * (feature - 4);
      else if (feature >= 1) coefficients = front.corner_directions + 9 * (size_t)id + 3 * (feature - 1);
      for (int k = 0; k < 3; k++)
        pseudo[k] = coefficients ? coefficients[0] * e1[k] + coefficients[1] * e2[k] + coefficients[2] * normal[k]
                                 : normal[k];
      if (feature >= 4)
        for (int k = 0; k < 3; k++) pseudo[k] += normal[k];
      double offset[3] = {x[i][0] - closest[0], x[i][1] - closest[1], x[i][2] - closest[2]};
      SideEntry entry;
      entry.particle = i;
      entry.triangle = j;
      entry.component = orientation.component[id];
      entry.triangle_id = id;
      entry.distance2 = offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2];
      entry.side = offset[0] * pseudo[0] + offset[1] * pseudo[1] + offset[2] * pseudo[2] >= 0.0 ? 0 : 1;
      side_entries.push_back(entry);
    }
  }
  // The decision per (particle, surface): its nearest triangle's (ties: the lowest global number).
  std::vector<size_t> &index = side_order;
  index.resize(side_entries.size());
  for (size_t e = 0; e < index.size(); e++) index[e] = e;
  std::sort(index.begin(), index.end(),
            [this](size_t a, size_t b) { return side_entry_order(side_entries[a], side_entries[b]); });
  std::vector<int> decided(side_entries.size());
  for (size_t first = 0; first < index.size();) {
    size_t last = first;
    const SideEntry &head = side_entries[index[first]];
    while (last + 1 < index.size() && side_entries[index[last + 1]].particle == head.particle &&
           side_entries[index[last + 1]].component == head.component)
      last++;
    int side = head.side;
    // closed_side inside|outside: particles inside a closed surface (canonically outward) are behind it.
    if (closed_particles != 0 && orientation.component_closed[head.component]) side = closed_particles > 0 ? 1 : 0;
    for (size_t e = first; e <= last; e++) decided[index[e]] = side;
    first = last + 1;
  }
  // The candidates, with the prism of their side (each triangle's one or two prisms looked up once).
  int current = -1, slot[2] = {-1, -1};
  for (size_t e = 0; e < side_entries.size(); e++) {
    const SideEntry &entry = side_entries[e];
    const int i = entry.particle, j = entry.triangle, side = decided[e];
    if (j != current) {
      current = j;
      slot[0] = slot[1] = -2;
    }
    if (slot[side] == -2) {
      double nodes[3][3];
      canonical_nodes(mesh, j, orientation.flip[entry.triangle_id] ^ side, nodes);
      slot[side] = prism_slot(m, entry.triangle_id, side, nodes);
    }
    if (slot[side] < 0) continue;
    const poly_mesh_prism &p = prisms[slot[side]];
    const double *top_normal = p.face_normals;
    double corner[3];
    mesh->node(j, 0, corner);
    double offset[3] = {x[i][0] - corner[0], x[i][1] - corner[1], x[i][2] - corner[2]};
    if (offset[0] * top_normal[0] + offset[1] * top_normal[1] + offset[2] * top_normal[2] >= radius[i]) continue;
    double to_prism[3] = {x[i][0] - p.origin[0], x[i][1] - p.origin[1], x[i][2] - p.origin[2]};
    double reach = radius[i] + p.view.bounding_radius;
    if (to_prism[0] * to_prism[0] + to_prism[1] * to_prism[1] + to_prism[2] * to_prism[2] >= reach * reach) continue;
    MeshCandidate candidate = {i, j, slot[side]};
    candidates.push_back(candidate);
  }
}

// The angular velocity of a triangle moving rigidly, from its corners' velocities: the least-squares solution
// of (x_b - x_a) x Omega = v_a - v_b over its three edges, exact for a rigid motion (fix move/mesh), and 0 for
// a translation.
static void triangle_angular_velocity(const double corners[3][3], double **velocities, double omega[3])
{
  double matrix[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, right[3] = {0, 0, 0};
  for (int a = 0; a < 3; a++) {
    int b = (a + 1) % 3;
    double e[3], w[3];
    for (int k = 0; k < 3; k++) {
      e[k] = corners[b][k] - corners[a][k];
      w[k] = velocities[b][k] - velocities[a][k];  // = Omega x e
    }
    double length2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    // normal equations: sum (|e|^2 I - e e^T) Omega = sum e x w
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) matrix[3 * r + c] += (r == c ? length2 : 0.0) - e[r] * e[c];
    right[0] += e[1] * w[2] - e[2] * w[1];
    right[1] += e[2] * w[0] - e[0] * w[2];
    right[2] += e[0] * w[1] - e[1] * w[0];
  }
  double det = matrix[0] * (matrix[4] * matrix[8] - matrix[5] * matrix[7]) -
               matrix[1] * (matrix[3] * matrix[8] - matrix[5] * matrix[6]) +
               matrix[2] * (matrix[3] * matrix[7] - matrix[4] * matrix[6]);
  for (int k = 0; k < 3; k++) omega[k] = 0.0;
  if (!(fabs(det) > 0.0)) return;
  for (int k = 0; k < 3; k++) {
    double column[9];
    for (int q = 0; q < 9; q++) column[q] = matrix[q];
    for (int r = 0; r < 3; r++) column[3 * r + k] = right[r];
    omega[k] = (column[0] * (column[4] * column[8] - column[5] * column[7]) -
                column[1] * (column[3] * column[8] - column[5] * column[6]) +
                column[2] * (column[3] * column[7] - column[4] * column[6])) / det;
  }
}

// Mesh m's pieces: its candidates that overlap, with the wall's velocity at each piece's centroid.
void FixWallPolyhedral::collect_pieces(int m)
{
  TriMesh *mesh = meshes[m]->triMesh();
  MultiVectorContainer<double, 3, 3> *velocity_container =
      mesh->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v");
  double ***vertex_velocity = velocity_container ? velocity_container->begin() : NULL;
  pieces.clear();
  for (size_t c = mesh_first_candidate[m]; c < mesh_first_candidate[m + 1]; c++) {
    const poly_overlap_result &geometry = overlaps[c];
    if (!(geometry.volume > 0.0)) continue;
    poly_degenerate_count(&degenerate, &geometry);
    int j = candidates[c].triangle;
    MeshPiece piece;
    piece.particle = candidates[c].particle;
    piece.triangle = j;
    piece.triangle_id = mesh->id(j);
    piece.geometry = geometry;
    piece.first_node = overlap_first_node[c];
    piece.num_nodes = overlap_num_nodes[c];
    for (int k = 0; k < 3; k++) piece.wall_velocity[k] = piece.wall_omega[k] = 0.0;
    if (vertex_velocity) {
      // Barycentric coordinates of the centroid's foot on the triangle's plane (exact for rigid motions within
      // the plane; the offset along the normal is of the order of the overlap depth).
      double corners[3][3], e1[3], e2[3], r[3];
      for (int k = 0; k < 3; k++) mesh->node(j, k, corners[k]);
      for (int k = 0; k < 3; k++) {
        e1[k] = corners[1][k] - corners[0][k];
        e2[k] = corners[2][k] - corners[0][k];
        r[k] = geometry.centroid[k] - corners[0][k];
      }
      double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2],
             g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      double r1 = r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2], r2 = r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2];
      double det = g11 * g22 - g12 * g12;
      double b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det, b0 = 1.0 - b1 - b2;
      for (int k = 0; k < 3; k++)
        piece.wall_velocity[k] = b0 * vertex_velocity[j][0][k] + b1 * vertex_velocity[j][1][k] +
                                 b2 * vertex_velocity[j][2][k];
      triangle_angular_velocity(corners, vertex_velocity[j], piece.wall_omega);
    }
    pieces.push_back(piece);
  }
}

// The overlaps of the candidates, with the nodes of those that touch: on the CPU, or in one batch on the GPU.
void FixWallPolyhedral::compute_overlaps()
{
  const size_t count = candidates.size();
  double **x = atom->x, **quaternion = atom->quaternion;
  int *shapetype = atom->shapetype;
  overlaps.resize(count);
  overlap_first_node.assign(count, -1);
  overlap_num_nodes.assign(count, -1);
  nodes.clear();
  // Fewer pieces than a GPU call is worth (POLY_GPU_MIN_PIECES) stay on the host.
  if (gpu_precision >= 0 && (long)count >= gpu_min_pieces) {
#ifdef POLY_HAVE_CUDA
    char message[512];
    poly_gpu_wall_piece *buffer = poly_gpu_wall_buffer((int)count);
    if (!buffer) error->one(FLERR, "Fix wall/polyhedral: no pinned host memory for the GPU's wall pieces");
    for (size_t c = 0; c < count; c++) {
      int i = candidates[c].particle;
      const poly_mesh_prism &prism = prisms[candidates[c].prism];
      poly_gpu_wall_piece &piece = buffer[c];
      piece.shape = shapetype[i] - 1;
      for (int k = 0; k < 3; k++) piece.position[k] = x[i][k];
      for (int k = 0; k < 4; k++) piece.quaternion[k] = quaternion[i][k];
      poly_gpu_wall_piece_set_prism(&piece, &prism);
    }
    gpu_overlaps.resize(count);
    const double *gpu_nodes = NULL;
    if (poly_gpu_wall_overlaps(gpu_precision, (int)count, count ? &gpu_overlaps[0] : NULL, &gpu_nodes, message,
                               sizeof message) != 0) {
      char text[600];
      snprintf(text, sizeof text, "Fix wall/polyhedral on the GPU: %s", message);
      error->one(FLERR, text);
    }
    for (size_t c = 0; c < count; c++) {
      overlaps[c] = gpu_overlaps[c].geometry;
      if (!(overlaps[c].volume > 0.0) || gpu_overlaps[c].first_node < 0) continue;
      int n = overlaps[c].num_nodes;
      overlap_first_node[c] = (int)nodes.size() / 3;
      overlap_num_nodes[c] = n;
      const double *first = gpu_nodes + 3 * (size_t)gpu_overlaps[c].first_node;
      nodes.insert(nodes.end(), first, first + 3 * (size_t)n);
    }
    return;
#endif
  }
  for (size_t c = 0; c < count; c++) {
    int i = candidates[c].particle;
    poly_mesh_prism &prism = prisms[candidates[c].prism];
    const poly_shape_view_d &particle_view = wall_views[shapetype[i]];  // the walls' pieces (build_wall_views)
    const poly_shape_view_d *prism_view = poly_mesh_prism_view(&prism, &particle_view);
    poly_pose prism_pose = {{prism.origin[0], prism.origin[1], prism.origin[2]}, {1.0, 0.0, 0.0, 0.0}};
    poly_pose particle_pose = {{x[i][0], x[i][1], x[i][2]},
                               {quaternion[i][0], quaternion[i][1], quaternion[i][2], quaternion[i][3]}};
    workspace.want_second_moment = use_rocking;
    workspace.want_nodes = 1;  // the pieces' corners, for the contact's depth (poly_mesh_contact_combine)
    poly_overlap_d(&particle_view, &particle_pose, prism_view, &prism_pose, &workspace,
                   &overlaps[c]);
    int n = poly_overlap_num_nodes_d(&workspace);
    if (!(overlaps[c].volume > 0.0) || n < 0) continue;
    overlap_first_node[c] = (int)nodes.size() / 3;
    overlap_num_nodes[c] = n;
    if (n > 0) {
      nodes.resize(nodes.size() + 3 * (size_t)n);
      poly_overlap_nodes_d(&workspace, &particle_pose, &nodes[3 * (size_t)overlap_first_node[c]], n);
    }
  }
}

static bool piece_order(const FixWallPolyhedral::MeshPiece &a, const FixWallPolyhedral::MeshPiece &b)
{
  if (a.particle != b.particle) return a.particle < b.particle;
  return a.triangle_id < b.triangle_id;
}

// Triangle j's plane from its current corners: unit normal (as the corners run) and offset, into plane[0..3].
static void triangle_plane(TriMesh *mesh, int j, double *plane)
{
  double c[3][3], e1[3], e2[3];
  for (int k = 0; k < 3; k++) mesh->node(j, k, c[k]);
  for (int k = 0; k < 3; k++) e1[k] = c[1][k] - c[0][k], e2[k] = c[2][k] - c[0][k];
  double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; k++) plane[k] = length > 0.0 ? n[k] / length : 0.0;
  plane[3] = plane[0] * c[0][0] + plane[1] * c[0][1] + plane[2] * c[0][2];
}

// Triangles of a mesh whose planes meet at less than this (radians), directly or through others a particle
// touches, are one surface to it: a flat face cut into triangles, a tessellated drum or cone (a cube's impact on
// a drum of 64 to 2000 sides as on the zcylinder primitive). Across a sharper crease each side is a contact.
static const double kCreaseAngle = 20.0 * M_PI / 180.0;

static int surface_root(std::vector<int> &parent, int p)
{
  while (parent[p] != p) p = parent[p] = parent[parent[p]];
  return p;
}

// One contact per particle and surface of the mesh that it touches (poly_mesh_contact_combine over that surface's
// pieces, those within kCreaseAngle of each other), its depth the deepest of its nodes below their triangles:
// a particle against a flat face gets one contact however the face is cut into triangles, and one in a corner or
// a sharp crease one contact a face, as against separate walls. One contact of all its pieces had, in a corner,
// the depth of the spots' spread along their mean normal (tests/test_mesh_walls.py's corner: a cube held 8300 times
// too stiffly); and the extent of its nodes along the normal grew with the normal's tilt times the contact's width
// (a cube whose face ends at a crease or a mesh's border: its side strips tilted the normal by the depth over the
// edge, tripling the depth).
void FixWallPolyhedral::apply_mesh(int m, bool advance_history)
{
  collect_pieces(m);
  // Sorted by particle, then by global triangle: sums independent of the domain decomposition.
  std::sort(pieces.begin(), pieces.end(), piece_order);
  double **springs = history->array_atom;
  const int nlocal = atom->nlocal, base = mesh_history_offset(m);
  TriMesh *mesh = meshes[m]->triMesh();
  const double crease = cos(kCreaseAngle);
  double **x = atom->x;
  std::vector<unsigned> &used = used_slots;  // per local particle, the contact slots of this step
  used.assign(nlocal, 0u);
  std::vector<int> &parent = surface_parent;
  for (size_t first = 0; first < pieces.size();) {
    size_t last = first;
    while (last + 1 < pieces.size() && pieces[last + 1].particle == pieces[first].particle) last++;
    const int i = pieces[first].particle, count = (int)(last - first + 1);
    // The pieces' surfaces: joined where their triangles' planes meet within the crease angle.
    plane_normals.resize(4 * (size_t)count);
    parent.resize(count);
    for (int p = 0; p < count; p++) {
      double *plane = &plane_normals[4 * p];
      triangle_plane(mesh, pieces[first + p].triangle, plane);
      // Turned to face the particle's centre, whichever way the triangle is wound: the two walls of a slot the
      // particle is in face each other, and are two contacts.
      if (plane[0] * x[i][0] + plane[1] * x[i][1] + plane[2] * x[i][2] < plane[3])
        for (int k = 0; k < 4; k++) plane[k] = -plane[k];
      parent[p] = p;
    }
    for (int p = 0; p < count; p++)
      for (int q = p + 1; q < count; q++) {
        const double *np = &plane_normals[4 * p], *nq = &plane_normals[4 * q];
        if (np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2] >= crease) {
          const int rp = surface_root(parent, p), rq = surface_root(parent, q);  // the lower index the root
          if (rp < rq) parent[rq] = rp;
          else parent[rp] = rq;
        }
      }
    // Surfaces numbered in the order of their first piece (global triangle order).
    piece_plane.assign(count, -1);
    int surfaces = 0;
    for (int p = 0; p < count; p++) {
      const int root = surface_root(parent, p);
      piece_plane[p] = root == p ? surfaces++ : piece_plane[root];
    }
    // Each surface keeps the slot that holds one of its triangles (its largest piece's at the step before: a
    // particle moves less than a triangle a step); a new one takes a free slot. By triangle, not by normal: on a
    // convex crease both contacts have the particle's face's normal, and their springs swapped.
    double *slots = springs[i] + base;
    surface_slot.assign(surfaces, -1);
    for (int k = 0; k < kMeshContactSlots; k++) {
      const double stored = slots[kMeshSlotSize * k + POLY_HISTORY_SIZE];
      for (int p = 0; p < count && stored > 0.0; p++)
        if (pieces[first + p].triangle_id + 1 == (int)stored && surface_slot[piece_plane[p]] < 0) {
          surface_slot[piece_plane[p]] = k;
          used[i] |= 1u << k;
          break;
        }
    }
    for (int g = 0; g < surfaces; g++) {
      // A new contact: a slot no surface kept (free, or of a contact that ended), its spring from zero.
      for (int k = 0; k < kMeshContactSlots && surface_slot[g] < 0; k++)
        if (!((used[i] >> k) & 1u)) {
          surface_slot[g] = k;
          used[i] |= 1u << k;
          for (int d = 0; d < kMeshSlotSize; d++) slots[kMeshSlotSize * k + d] = 0.0;
        }
      const bool touches = apply_mesh_plane(m, i, first, last, g,
                                            surface_slot[g] >= 0 ? slots + kMeshSlotSize * surface_slot[g] : NULL,
                                            advance_history);
      if (!touches && surface_slot[g] >= 0) used[i] &= ~(1u << surface_slot[g]);  // too little to touch: no spring
    }
    first = last + 1;
  }
  // Contact slots not used this step: their contacts ended (at set-up too, as a run begins where the last ended).
  for (int i = 0; i < nlocal; i++)
    if (atom->mask[i] & groupbit)
      for (int k = 0; k < kMeshContactSlots; k++)
        if (!((used[i] >> k) & 1u))
          for (int d = 0; d < kMeshSlotSize; d++) springs[i][base + kMeshSlotSize * k + d] = 0.0;
}

// Particle i's contact with surface `plane` of mesh m (its pieces among pieces[first..last]), with the tangential
// spring of its slot `slot` (NULL: none free); false when its overlap is too small to be a contact.
bool FixWallPolyhedral::apply_mesh_plane(int m, int i, size_t first, size_t last, int plane, double *slot,
                                         bool advance_history)
{
  particle_pieces.clear();
  piece_first_node.clear();
  piece_num_nodes.clear();
  double velocity[3] = {0, 0, 0}, spin[3] = {0, 0, 0};
  size_t largest = last + 1;
  for (size_t p = first; p <= last; p++) {
    if (piece_plane[p - first] != plane) continue;
    const MeshPiece &piece = pieces[p];
    particle_pieces.push_back(piece.geometry);
    piece_first_node.push_back(piece.first_node);
    piece_num_nodes.push_back(piece.num_nodes);
    for (int k = 0; k < 3; k++) {
      velocity[k] += piece.geometry.volume * piece.wall_velocity[k];
      spin[k] += piece.geometry.volume * piece.wall_omega[k];
    }
    if (largest > last || piece.geometry.volume > pieces[largest].geometry.volume) largest = p;
  }
  poly_overlap_result contact;
  poly_mesh_contact_combine(&particle_pieces[0], nodes.empty() ? NULL : &nodes[0], &piece_first_node[0],
                            &piece_num_nodes[0], (int)particle_pieces.size(), &contact);
  // The depth: the deepest node below its own triangle's plane (nodes are relative to the particle).
  double deepest = 0.0;
  bool all_kept = true;
  const double *centre = atom->x[i];
  for (size_t p = first; p <= last && all_kept; p++) {
    if (piece_plane[p - first] != plane) continue;
    const MeshPiece &piece = pieces[p];
    if (piece.num_nodes < 0) {
      all_kept = false;
      continue;
    }
    const double *n = &plane_normals[4 * (p - first)];
    const double level = n[0] * centre[0] + n[1] * centre[1] + n[2] * centre[2] - n[3];
    for (int q = 0; q < piece.num_nodes; q++) {
      const double *x = &nodes[3 * (size_t)(piece.first_node + q)];
      deepest = fmax(deepest, fabs(level + n[0] * x[0] + n[1] * x[1] + n[2] * x[2]));
    }
  }
  if (all_kept) contact.depth = deepest;
  const double volume = contact.volume;
  if (!(volume > 1e-12 * atom->rmass[i] / atom->density[i]) || !(contact.depth > 0.0)) return false;
  for (int k = 0; k < 3; k++) {
    velocity[k] /= volume;
    spin[k] /= volume;
  }
  double scratch[kMeshSlotSize] = {0.0};
  double *spring = scratch;
  if (slot) {
    spring = slot;
    spring[POLY_HISTORY_SIZE] = pieces[largest].triangle_id + 1;  // the surface's mark for the next step
  } else if (!slots_warning.raised()) {
    char message[256];
    snprintf(message, sizeof message, "Fix wall/polyhedral %s: a particle touches more than %d surfaces of mesh '%s' "
             "at once; the contacts past them have no tangential spring", id, (int)kMeshContactSlots,
             mesh_ids[m].c_str());
    slots_warning.raise(FLERR, message);
  }
  double force[3], shift[3];
  FixMeshSurface *surface = meshes[m];
  apply_contact(i, surface->atomTypeWall(), spring, advance_history, volume, contact.depth, contact.projected_area,
                contact.normal, contact.centroid, contact.second_moment, velocity, spin, false, force, shift);
  if (recording) record(i, m + 1, pieces[largest].triangle_id, force, contact.centroid, shift, volume);
  if (!advance_history) return true;
  // Each triangle carries its share of the force, by volume, at its piece's centroid moved by the centre of
  // pressure's shift (so the torque on the mesh sums to the whole force at the contact's centre of pressure,
  // as on the particle); LIGGGHTS' stress module turns the sign.
  for (size_t p = first; p <= last; p++) {
    if (piece_plane[p - first] != plane) continue;
    MeshPiece &piece = pieces[p];
    double share = piece.geometry.volume / volume, on_particle[3], arm[3];
    for (int k = 0; k < 3; k++) {
      on_particle[k] = share * force[k];
      arm[k] = piece.geometry.centroid[k] + shift[k] - atom->x[i][k];
    }
    surface->add_particle_contribution(i, on_particle, arm, piece.triangle, piece.wall_velocity);
  }
  return true;
}
