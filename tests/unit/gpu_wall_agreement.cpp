/* GPU vs CPU agreement of fix wall/polyhedral's mesh narrow phase: for each
 * reference shape, `count` particles in random poses against a mesh with a
 * concave and a convex crease (a 12 x 12 grid, z = (|x| - |y|) / 4 in units of
 * the particle's bounding radius), every prism whose bounding sphere touches
 * the particle's. Each (particle, prism) piece goes through
 * poly_gpu_wall_overlaps and through the host's poly_overlap_d/f/m, and each
 * particle's pieces are combined into its contact with the mesh
 * (poly_mesh_contact_combine) from either side's pieces and nodes. Prints the
 * worst relative difference of the pieces' V and centroid and of the contacts'
 * V, centroid, normal and depth (normal and depth where the contact has one
 * and both sides found the same pieces: see the comment in main; at most
 * 0.5 % of the contacts may have a piece at the round-off floor found by one
 * side only); exits non-zero above 1e-10 (double) or 1e-4
 * (single, mixed). Scales as tests/unit/gpu_agreement.cpp: V against
 * max(V, 1e-3 V_p), centroid against the bounding radius, normal and depth for
 * contacts above 1e-3 V_p. The GPU's pieces per second: the fastest of three
 * calls (the first also allocates). Usage:
 * gpu_wall_agreement SHAPES_DIR COUNT double|single|mixed [SHAPE_FILE]
 * (with SHAPE_FILE, a file of SHAPES_DIR such as one of the eight or
 * rock_1000.obj, only that shape is uploaded and tested, as in a deck of one
 * template: the kernels' choices depend on the uploaded shapes, doc/gpu.md) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <vector>

#include "poly_gpu.h"
#include "poly_mesh_shell.h"
#include "poly_overlap.h"

static double uniform(unsigned long long *state)
{
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) / 9007199254740992.0;
}

static double crease_height(double x, double y)
{
  return 0.25 * (fabs(x) - fabs(y));
}

// The grid's triangles, counter-clockwise seen from +z (the free side).
static std::vector<double> crease_mesh(double radius, int cells)
{
  std::vector<double> corners;
  double width = 6.0 * radius, step = width / cells;
  for (int a = 0; a < cells; a++)
    for (int b = 0; b < cells; b++) {
      double x0 = -0.5 * width + a * step, y0 = -0.5 * width + b * step, x1 = x0 + step, y1 = y0 + step;
      double quad[4][3] = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
      for (int k = 0; k < 4; k++) quad[k][2] = crease_height(quad[k][0], quad[k][1]);
      const int split[2][3] = {{0, 1, 2}, {0, 2, 3}};
      for (int t = 0; t < 2; t++)
        for (int k = 0; k < 3; k++)
          for (int d = 0; d < 3; d++) corners.push_back(quad[split[t][k]][d]);
    }
  return corners;
}

static double seconds_since(const struct timespec &start)
{
  struct timespec stop;
  clock_gettime(CLOCK_MONOTONIC, &stop);
  return (stop.tv_sec - start.tv_sec) + 1e-9 * (stop.tv_nsec - start.tv_nsec);
}

struct Worst {
  double value;
  const char *what;
  int particle;
  void take(double difference, const char *name, int n)
  {
    if (difference > value) {
      value = difference;
      what = name;
      particle = n;
    }
  }
};

static double relative(const double *a, const double *b, int n, double scale)
{
  double d = 0.0;
  for (int k = 0; k < n; k++) d = fmax(d, fabs(a[k] - b[k]));
  return d / scale;
}

int main(int argc, char **argv)
{
  if (argc != 4 && argc != 5) return 2;
  const char *all_names[] = {"schoenhardt.stl", "cube.stl", "tetrahedron.obj", "icosphere_80.off",
                             "icosphere_320.off", "rock_10.obj", "rock_40.obj", "rock_70.obj"};
  std::vector<const char *> names(all_names, all_names + 8);
  if (argc == 5) names.assign(1, argv[4]);
  const int num_shapes = (int)names.size(), count = atoi(argv[2]);
  int precision = strcmp(argv[3], "single") == 0  ? POLY_PRECISION_SINGLE
                  : strcmp(argv[3], "mixed") == 0 ? POLY_PRECISION_MIXED
                                                  : POLY_PRECISION_DOUBLE;
  std::vector<poly_shape> shapes(num_shapes);
  std::vector<const poly_shape *> pointers(num_shapes);
  int max_vertices = 6, max_triangles = 8;
  char message[512];
  for (int s = 0; s < num_shapes; s++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", argv[1], names[s]);
    if (poly_shape_load(path, 0.01, &shapes[s], message, sizeof message) != POLY_OK) {
      printf("FAIL %s\n", message);
      return 1;
    }
    pointers[s] = &shapes[s];
    if (shapes[s].num_vertices > max_vertices) max_vertices = shapes[s].num_vertices;
    if (shapes[s].num_triangles > max_triangles) max_triangles = shapes[s].num_triangles;
  }
  if (poly_gpu_init(0, num_shapes, &pointers[0], message, sizeof message) != 0) {
    printf("FAIL %s\n", message);
    return 1;
  }
  poly_overlap_workspace_d ws_d;
  poly_overlap_workspace_f ws_f;
  poly_overlap_workspace_create_d(&ws_d, max_vertices, max_triangles);
  poly_overlap_workspace_create_f(&ws_f, max_vertices, max_triangles);
  ws_d.want_nodes = 1;  // as the wall asks: the clipping path's corners for the depth
  std::vector<double> node_scratch(3 * (size_t)(ws_d.capacity_corners > ws_f.capacity_corners ? ws_d.capacity_corners
                                                                                                 : ws_f.capacity_corners));
  const double tolerance = precision == POLY_PRECISION_DOUBLE ? 1e-10 : 1e-4;
  int failures = 0;

  for (int s = 0; s < num_shapes; s++) {
    const double radius = shapes[s].bounding_radius, volume_p = shapes[s].volume;
    std::vector<double> corners = crease_mesh(radius, 12);
    poly_mesh_shell shell;
    if (poly_mesh_shell_build(&corners[0], (int)corners.size() / 9, 2.2 * radius, 1e-8, &shell, message,
                              sizeof message) != 0) {
      printf("FAIL %s\n", message);
      return 1;
    }
    std::vector<poly_mesh_prism> prisms(shell.num_triangles);
    std::vector<int> usable(shell.num_triangles);
    for (int t = 0; t < shell.num_triangles; t++) {
      double nodes[3][3];
      for (int k = 0; k < 3; k++)
        for (int d = 0; d < 3; d++) nodes[k][d] = corners[9 * t + 3 * k + d];
      usable[t] = poly_mesh_shell_prism(&shell, t, nodes, &prisms[t]) == 0;  // its view points into prisms[t]
    }
    poly_shape_view_d view_d = poly_shape_view_of(&shapes[s]);
    poly_shape_view_f view_f;
    poly_shape_view_make_f(&shapes[s], &view_f);

    // Candidates: every usable prism whose bounding sphere touches the particle's.
    unsigned long long state = 777 + s;
    std::vector<poly_pose> poses(count);
    std::vector<int> piece_particle, piece_prism;
    for (int n = 0; n < count; n++) {
      poly_pose &pose = poses[n];
      double x = (3.0 * uniform(&state) - 1.5) * radius, y = (3.0 * uniform(&state) - 1.5) * radius;
      pose.position[0] = x;
      pose.position[1] = y;
      pose.position[2] = crease_height(x, y) + (1.5 * uniform(&state) - 0.9) * radius;
      for (int k = 0; k < 4; k++) pose.quaternion[k] = 2.0 * uniform(&state) - 1.0;
      poly_quat_normalize(pose.quaternion);
      for (int t = 0; t < shell.num_triangles; t++) {
        if (!usable[t]) continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += pow(pose.position[k] - prisms[t].origin[k], 2);
        double reach = radius + prisms[t].view.bounding_radius;
        if (d2 >= reach * reach) continue;
        piece_particle.push_back(n);
        piece_prism.push_back(t);
      }
    }
    const int num_pieces = (int)piece_particle.size();
    poly_gpu_wall_piece *buffer = poly_gpu_wall_buffer(num_pieces);
    if (!buffer) {
      printf("FAIL no pinned buffer\n");
      return 1;
    }
    for (int p = 0; p < num_pieces; p++) {
      const poly_pose &pose = poses[piece_particle[p]];
      const poly_mesh_prism &prism = prisms[piece_prism[p]];
      poly_gpu_wall_piece &piece = buffer[p];
      piece.shape = s;
      memcpy(piece.position, pose.position, sizeof piece.position);
      memcpy(piece.quaternion, pose.quaternion, sizeof piece.quaternion);
      poly_gpu_wall_piece_set_prism(&piece, &prism);
    }
    std::vector<poly_gpu_wall_overlap> gpu(num_pieces > 0 ? num_pieces : 1);
    const double *gpu_nodes = NULL;
    struct timespec start;
    double gpu_seconds = 1e300, host_seconds = 0.0;
    const long handed_before = poly_gpu_timings().wall_handed_back;
    for (int call = 0; call < 3; call++) {
      clock_gettime(CLOCK_MONOTONIC, &start);
      if (poly_gpu_wall_overlaps(precision, num_pieces, &gpu[0], &gpu_nodes, message, sizeof message) != 0) {
        printf("FAIL %s\n", message);
        return 1;
      }
      gpu_seconds = fmin(gpu_seconds, seconds_since(start));
    }
    const long handed = (poly_gpu_timings().wall_handed_back - handed_before) / 3;

    // The host's pieces, in the same precision, and both sides' combined contacts per particle.
    Worst worst = {0.0, "-", -1};
    const double floor_volume = (precision == POLY_PRECISION_DOUBLE ? 1e-12 : 1e-6) * volume_p;
    int touching_pieces = 0, contacts = 0, conditioned = 0, ambiguous = 0;
    std::vector<poly_overlap_result> host_pieces, gpu_pieces;
    std::vector<double> host_nodes, gpu_node_copy;
    std::vector<int> host_first, host_count, gpu_first, gpu_count;
    for (int p = 0, first = 0; first < num_pieces; first = p) {
      int n = piece_particle[first];
      host_pieces.clear(); gpu_pieces.clear(); host_nodes.clear(); gpu_node_copy.clear();
      host_first.clear(); host_count.clear(); gpu_first.clear(); gpu_count.clear();
      bool one_sided = false;
      for (; p < num_pieces && piece_particle[p] == n; p++) {
        poly_mesh_prism &prism = prisms[piece_prism[p]];
        poly_pose prism_pose = {{prism.origin[0], prism.origin[1], prism.origin[2]}, {1.0, 0.0, 0.0, 0.0}};
        const poly_shape_view_d *prism_view = poly_mesh_prism_view(&prism, &view_d);  // as the fix chooses
        poly_overlap_result host;
        std::vector<double> &nodes = node_scratch;
        int num_nodes;
        clock_gettime(CLOCK_MONOTONIC, &start);
        if (precision == POLY_PRECISION_DOUBLE) {
          poly_overlap_d(&view_d, &poses[n], prism_view, &prism_pose, &ws_d, &host);
          num_nodes = poly_overlap_nodes_d(&ws_d, &poses[n], &nodes[0], ws_d.capacity_corners);
        } else {
          float vertices[18], normals[24];
          for (int k = 0; k < 18; k++) vertices[k] = (float)prism.vertices[k];
          for (int k = 0; k < 24; k++) normals[k] = (float)prism.face_normals[k];
          poly_shape_view_f prism_f;
          memset(&prism_f, 0, sizeof prism_f);
          prism_f.num_vertices = 6, prism_f.num_triangles = 8, prism_f.num_edges = 12;
          prism_f.vertices = vertices, prism_f.face_normals = normals, prism_f.triangles = prism.triangles;
          prism_f.edges = prism.edges, prism_f.edge_triangles = prism.edge_triangles;
          prism_f.bounding_radius = (float)prism.view.bounding_radius;
          if (precision == POLY_PRECISION_SINGLE)
            poly_overlap_f(&view_f, &poses[n], &prism_f, &prism_pose, &ws_f, &host);
          else
            poly_overlap_m(&view_f, &poses[n], &prism_f, &prism_pose, &ws_f, &host);
          num_nodes = poly_overlap_nodes_f(&ws_f, &poses[n], &nodes[0], ws_f.capacity_corners);
        }
        host_seconds += seconds_since(start);
        const poly_overlap_result &device = gpu[p].geometry;
        double small = 1e-3 * volume_p;
        worst.take(fabs(host.volume - device.volume) / fmax(host.volume, small), "piece volume", n);
        if (host.volume > small) worst.take(relative(host.centroid, device.centroid, 3, radius), "piece centroid", n);
        // A piece may be found by one side only when its volume is at the round-off floor.
        if ((host.volume > 0.0) != (device.volume > 0.0)) {
          if (fmax(host.volume, device.volume) > floor_volume) worst.take(1.0, "piece found by one side", n);
          one_sided = true;
        }
        if (host.volume > 0.0) {
          touching_pieces++;
          host_pieces.push_back(host);
          host_first.push_back((int)host_nodes.size() / 3);
          host_count.push_back(num_nodes);
          if (num_nodes > 0) host_nodes.insert(host_nodes.end(), nodes.begin(), nodes.begin() + 3 * num_nodes);
        }
        if (device.volume > 0.0) {
          gpu_pieces.push_back(device);
          gpu_first.push_back((int)gpu_node_copy.size() / 3);
          int m = gpu[p].first_node < 0 ? -1 : device.num_nodes;
          gpu_count.push_back(m);
          if (m > 0)
            gpu_node_copy.insert(gpu_node_copy.end(), gpu_nodes + 3 * (size_t)gpu[p].first_node,
                                 gpu_nodes + 3 * (size_t)(gpu[p].first_node + m));
        }
      }
      if (host_pieces.empty() || gpu_pieces.empty()) continue;
      poly_overlap_result a, b;
      poly_mesh_contact_combine(&host_pieces[0], host_nodes.empty() ? NULL : &host_nodes[0], &host_first[0],
                                &host_count[0], (int)host_pieces.size(), &a);
      poly_mesh_contact_combine(&gpu_pieces[0], gpu_node_copy.empty() ? NULL : &gpu_node_copy[0], &gpu_first[0],
                                &gpu_count[0], (int)gpu_pieces.size(), &b);
      contacts++;
      double small = 1e-3 * volume_p;
      worst.take(fabs(a.volume - b.volume) / fmax(a.volume, small), "contact volume", n);
      if (a.volume > small) worst.take(relative(a.centroid, b.centroid, 3, radius), "contact centroid", n);
      // The normal is the direction of the summed area vectors of the particle's surface inside the shell,
      // which cancel where the particle is (nearly) wholly inside it; there it carries no information and
      // any difference in the pieces turns it anywhere. Checked where the sum is 5 % of the area or more,
      // and where both sides found the same pieces: a sliver of a particle's face lying in a prism's face has
      // a volume at the round-off floor but may have a large area, and whether it is found is round-off's
      // decision (counted, and bounded below).
      if (one_sided) ambiguous++;
      if (a.volume > small && a.projected_area >= 0.05 * a.area && !one_sided) {
        conditioned++;
        worst.take(relative(a.normal, b.normal, 3, 1.0), "contact normal", n);
        worst.take(fabs(a.depth - b.depth) / fmax(a.depth, 1e-300), "contact depth", n);
      }
    }
    printf("%-20s %s: %5d particles, %6d pieces (%5d touching), %5d contacts (%5d with a normal, %d with a piece at the round-off floor "
           "on one side), worst relative difference %.2e (%s, particle %d); pieces/s: GPU %.3g (pieces up, overlaps and nodes down; "
           "%ld handed to the one-thread kernel), one CPU core %.3g\n", names[s], argv[3], count, num_pieces, touching_pieces,
           contacts, conditioned, ambiguous, worst.value, worst.what, worst.particle, num_pieces / gpu_seconds, handed,
           num_pieces / host_seconds);
    if (worst.value > tolerance || contacts < count / 4 || conditioned < count / 4 || ambiguous > contacts / 200)
      failures++;
    poly_shape_view_free_f(&view_f);
    poly_mesh_shell_free(&shell);
  }
  printf("device memory %.1f MiB\n", poly_gpu_bytes() / 1048576.0);
  poly_gpu_clear();
  printf(failures ? "FAIL\n" : "OK\n");
  return failures ? 1 : 0;
}
