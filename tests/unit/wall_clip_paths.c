/* The mesh wall's narrow phase by the clipping path (prisms with clip faces: convex ones, and the others as three
 * tetrahedra; poly_clip.h through the prisms' clip views, or with `mesh` poly_clip_mesh.h through their mesh views,
 * with the corners kept for the
 * depth: ws.want_nodes) against the general path (ws.use_clip = 0), as fix wall/polyhedral combines them: each
 * particle's pieces (one per prism whose bounding sphere touches the particle's) into one contact
 * (poly_mesh_contact_combine, from the pieces' nodes). tests/test_mesh_walls_clip.py runs it.
 *
 *   wall_clip_paths SHAPE_FILE COUNT [flat] [mesh]
 *   wall_clip_paths splits SEEDS
 *
 * The wall: a 10 x 10 height field of 5 bounding radii (random heights up to 0.6 radii: creases of both signs,
 * prisms convex and not), or with `flat` a plane, over which the particles rest as blocks in a pile (one in two at
 * a random turn about z, the rest in random orientations), their centres from 0.9 radii below to 0.6 above the
 * surface. Prints the pieces, the touching ones, the prisms with clip faces and those split into tetrahedra, the
 * pieces offered to the clipping path and those it handed back, and the
 * contacts' worst differences: volume against max(V, 1e-3 V_p), centroid against the bounding radius, second
 * moment against V_p r^2, and for contacts above 1e-3 V_p normal and depth (against the radius) weighed by the
 * summed area vector's length over the area. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_mesh_shell.h"
#include "poly_clip_mesh.h"
#include "poly_overlap.h"

#define CELLS 10

static unsigned long long state = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return (double)(state >> 11) * (1.0 / 9007199254740992.0);
}

static double heights[CELLS + 1][CELLS + 1];

/* The height field's triangles, counter-clockwise seen from +z (the free side); each cell split along the
 * diagonal that alternates, so that creases run both ways. */
static double *height_field(double radius, int *num_triangles)
{
  const double width = 5.0 * radius, step = width / CELLS;
  double *corners = malloc(sizeof(double) * 18 * CELLS * CELLS);
  int t = 0;
  for (int i = 0; i < CELLS; i++)
    for (int j = 0; j < CELLS; j++) {
      double quad[4][3];
      const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
      for (int k = 0; k < 4; k++) {
        quad[k][0] = -0.5 * width + (i + di[k]) * step;
        quad[k][1] = -0.5 * width + (j + dj[k]) * step;
        quad[k][2] = heights[i + di[k]][j + dj[k]];
      }
      const int split[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
      for (int h = 0; h < 2; h++, t++)
        for (int k = 0; k < 3; k++) memcpy(corners + 9 * t + 3 * k, quad[split[(i + j) % 2][h][k]], sizeof(double) * 3);
    }
  *num_triangles = t;
  return corners;
}

/* The surface's height under (x, y): the height field interpolated on the cell's triangle, roughly (the
 * particles' heights are random anyway). */
static double surface(double radius, double x, double y)
{
  const double width = 5.0 * radius, step = width / CELLS;
  int i = (int)floor((x + 0.5 * width) / step), j = (int)floor((y + 0.5 * width) / step);
  i = i < 0 ? 0 : (i >= CELLS ? CELLS - 1 : i);
  j = j < 0 ? 0 : (j >= CELLS ? CELLS - 1 : j);
  return 0.25 * (heights[i][j] + heights[i + 1][j] + heights[i][j + 1] + heights[i + 1][j + 1]);
}

static void random_quaternion(double *q)
{
  double norm = 0.0;
  for (int k = 0; k < 4; k++) {
    q[k] = 2.0 * uniform() - 1.0;
    norm += q[k] * q[k];
  }
  for (int k = 0; k < 4; k++) q[k] /= sqrt(norm);
}

static double worst(double current, double difference) { return difference > current ? difference : current; }

/* Six times the signed volume of the tetrahedron (a, b, c, d). */
static double volume6(const double *a, const double *b, const double *c, const double *d)
{
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/* `splits SEEDS`: steep height fields (cells of 1, heights up to 1, a shell 3 thick), every prism split into
 * tetrahedra must be partitioned by them: the tetrahedra's volumes sum to the prism's (each counted unsigned, so
 * one turned inside out shows). Prints the prisms, those split, and those whose split is not a partition. */
static int check_splits(int seeds)
{
  long prisms_made = 0, split = 0, bad = 0;
  char message[512];
  for (int seed = 0; seed < seeds; seed++) {
    for (int i = 0; i <= CELLS; i++)
      for (int j = 0; j <= CELLS; j++) heights[i][j] = uniform();
    int num_triangles;
    double *corners = height_field(2.0, &num_triangles);  /* 5 x 2 / CELLS: cells of 1 */
    poly_mesh_shell shell;
    if (poly_mesh_shell_build(corners, num_triangles, 3.0, 1e-8, &shell, message, sizeof message) != 0) {
      fprintf(stderr, "%s\n", message);
      return 1;
    }
    for (int t = 0; t < num_triangles; t++) {
      poly_mesh_prism prism;
      double nodes[3][3];
      memcpy(nodes, corners + 9 * t, sizeof nodes);
      if (poly_mesh_shell_prism(&shell, t, nodes, &prism) != 0) continue;
      prisms_made++;
      poly_mesh_prism_clip_faces(&prism);
      if (prism.clip_view.clip.num_pieces != 3) continue;
      split++;
      const double origin[3] = {0.0, 0.0, 0.0};
      double whole = 0.0, parts = 0.0;
      for (int f = 0; f < 8; f++) {
        const int *tri = prism.triangles + 3 * f;
        whole += volume6(origin, prism.vertices + 3 * tri[0], prism.vertices + 3 * tri[1], prism.vertices + 3 * tri[2]);
      }
      for (int p = 0; p < 3; p++) {
        const int *c = prism.clip_piece_points + 4 * p;
        parts += fabs(volume6(prism.vertices + 3 * c[0], prism.vertices + 3 * c[1], prism.vertices + 3 * c[2],
                              prism.vertices + 3 * c[3]));
      }
      bad += fabs(parts - whole) > 1e-9 * fabs(whole);
    }
    poly_mesh_shell_free(&shell);
    free(corners);
  }
  printf("prisms %ld split %ld not_partitions %ld\n", prisms_made, split, bad);
  return 0;
}

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: wall_clip_paths SHAPE_FILE COUNT [flat] [mesh]\n");
    return 2;
  }
  if (!strcmp(argv[1], "splits")) return check_splits(atoi(argv[2]));
  int flat = 0, by_mesh = 0;  /* the prisms' mesh views (the mesh path, poly_clip_mesh.h), else their clip views */
  for (int i = 3; i < argc; i++) {
    flat |= !strcmp(argv[i], "flat");
    by_mesh |= !strcmp(argv[i], "mesh");
  }
  const int count = atoi(argv[2]);
  poly_shape shape;
  char message[512];
  if (poly_shape_load(argv[1], 0.01, &shape, message, sizeof message) != POLY_OK) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  const double radius = shape.bounding_radius, particle_volume = shape.volume;
  for (int i = 0; i <= CELLS; i++)
    for (int j = 0; j <= CELLS; j++) heights[i][j] = flat ? 0.0 : 0.6 * radius * uniform();
  int num_triangles;
  double *corners = height_field(radius, &num_triangles);
  poly_mesh_shell shell;
  if (poly_mesh_shell_build(corners, num_triangles, 2.2 * radius, 1e-8, &shell, message, sizeof message) != 0) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  poly_mesh_prism *prisms = malloc(sizeof(poly_mesh_prism) * (size_t)num_triangles);
  int *usable = malloc(sizeof(int) * (size_t)num_triangles), clip_prisms = 0, split_prisms = 0;
  for (int t = 0; t < num_triangles; t++) {
    double nodes[3][3];
    memcpy(nodes, corners + 9 * t, sizeof nodes);
    usable[t] = poly_mesh_shell_prism(&shell, t, nodes, &prisms[t]) == 0;
    if (usable[t]) poly_mesh_prism_clip_faces(&prisms[t]);  /* for convex particles too (the fix leaves them) */
    clip_prisms += usable[t] && prisms[t].clip_view.clip.num_faces > 0;
    split_prisms += usable[t] && prisms[t].clip_view.clip.num_pieces == 3;
  }

  poly_overlap_workspace_d ws;
  poly_overlap_workspace_create_d(&ws, shape.num_vertices > 6 ? shape.num_vertices : 6,
                                  shape.num_triangles > 8 ? shape.num_triangles : 8);
  ws.want_second_moment = 1;
  ws.want_nodes = 1;
  poly_shape wall_pieces;  /* as fix wall/polyhedral clips prisms: rock_40's partition instead of its cones */
  const int has_wall_pieces = poly_shape_wall_pieces(&shape, &wall_pieces);
  const poly_shape_view_d view = poly_shape_view_of(has_wall_pieces ? &wall_pieces : &shape);
  const int capacity = ws.capacity_corners;
  /* Per path: the pieces, and the nodes of each, laid end to end as the wall lays them. */
  poly_overlap_result *pieces[2];
  int *first_node[2], *num_nodes[2];
  double *nodes[2];
  for (int path = 0; path < 2; path++) {
    pieces[path] = malloc(sizeof(poly_overlap_result) * (size_t)num_triangles);
    first_node[path] = malloc(sizeof(int) * (size_t)num_triangles);
    num_nodes[path] = malloc(sizeof(int) * (size_t)num_triangles);
    nodes[path] = malloc(sizeof(double) * 3 * (size_t)capacity * (size_t)num_triangles);
  }
  long total_pieces = 0, touching = 0, clip_offered = 0, clip_handed_back = 0, contacts = 0;
  double worst_volume = 0, worst_centroid = 0, worst_normal = 0, worst_depth = 0, worst_second = 0;
  for (int n = 0; n < count; n++) {
    poly_pose pose;
    double x = (3.0 * uniform() - 1.5) * radius, y = (3.0 * uniform() - 1.5) * radius;
    pose.position[0] = x;
    pose.position[1] = y;
    pose.position[2] = surface(radius, x, y) + (1.5 * uniform() - 0.9) * radius;
    if (n % 2 == 0) {
      double turn = 2.0 * 3.14159265358979323846 * uniform();
      pose.quaternion[0] = cos(0.5 * turn), pose.quaternion[1] = pose.quaternion[2] = 0.0;
      pose.quaternion[3] = sin(0.5 * turn);
    } else {
      random_quaternion(pose.quaternion);
    }
    int used[2] = {0, 0};
    for (int path = 0; path < 2; path++) {
      ws.use_clip = path == 0;
      for (int t = 0; t < num_triangles; t++) {
        if (!usable[t]) continue;
        const poly_mesh_prism *prism = &prisms[t];
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += (pose.position[k] - prism->origin[k]) * (pose.position[k] - prism->origin[k]);
        const double reach = radius + prism->view.bounding_radius;
        if (d2 >= reach * reach) continue;
        poly_pose prism_pose = {{prism->origin[0], prism->origin[1], prism->origin[2]}, {1.0, 0.0, 0.0, 0.0}};
        const int fallbacks = ws.clip_fallbacks;
        poly_overlap_result result;
        /* The path under test: the prism's clip faces (when it has them) for every particle. */
        const poly_shape_view_d *prism_view = prism->clip_view.clip.num_faces == 0 ? &prism->view
                                              : by_mesh                           ? &prism->mesh_view
                                                                                  : &prism->clip_view;
        poly_overlap_d(&view, &pose, prism_view, &prism_pose, &ws, &result);
        if (path == 0) {
          total_pieces++;
          /* The clipping path proper, or the mesh path (poly_clip_mesh.h). */
          if (prism_view->clip.facets ? poly_clip_mesh_fits(&view)
                                      : poly_clip_takes(&view.clip) && poly_clip_takes(&prism_view->clip)) {
            clip_offered++;
            clip_handed_back += ws.clip_fallbacks > fallbacks;
          }
        }
        if (!(result.volume > 0.0)) continue;
        touching += path == 0;
        const int p = used[path]++;
        pieces[path][p] = result;
        first_node[path][p] = p * capacity;
        num_nodes[path][p] = poly_overlap_nodes_d(&ws, &pose, nodes[path] + 3 * (size_t)p * (size_t)capacity, capacity);
      }
    }
    poly_overlap_result contact[2];
    for (int path = 0; path < 2; path++)
      poly_mesh_contact_combine(pieces[path], nodes[path], first_node[path], num_nodes[path], used[path],
                                &contact[path]);
    if (!(contact[1].volume > 0.0) && !(contact[0].volume > 0.0)) continue;
    contacts++;
    const double scale = fmax(contact[1].volume, 1e-3 * particle_volume);
    worst_volume = worst(worst_volume, fabs(contact[0].volume - contact[1].volume) / scale);
    for (int k = 0; k < 3; k++)
      worst_centroid = worst(worst_centroid, fabs(contact[0].centroid[k] - contact[1].centroid[k]) / radius);
    for (int e = 0; e < 6; e++)
      worst_second = worst(worst_second, fabs(contact[0].second_moment[e] - contact[1].second_moment[e]) /
                                             (particle_volume * radius * radius));
    /* The normal is the summed area vector's direction: weighed by its length against the area (a particle deep
     * in the shell has its surface's area vectors nearly cancel, and a normal known only to rounding / that
     * ratio), the depth likewise (the extent along that normal). */
    if (contact[1].volume > 1e-3 * particle_volume && contact[1].area > 0.0) {
      const double weight = contact[1].projected_area / contact[1].area;
      for (int k = 0; k < 3; k++)
        worst_normal = worst(worst_normal, weight * fabs(contact[0].normal[k] - contact[1].normal[k]));
      worst_depth = worst(worst_depth, weight * fabs(contact[0].depth - contact[1].depth) / radius);
    }
  }
  printf("pieces %ld touching %ld clip_prisms %d of %d split_prisms %d clip_offered %ld clip_handed_back %ld contacts %ld\n",
         total_pieces, touching, clip_prisms, num_triangles, split_prisms, clip_offered, clip_handed_back, contacts);
  printf("worst volume %.3g centroid %.3g normal %.3g depth %.3g second %.3g\n", worst_volume, worst_centroid,
         worst_normal, worst_depth, worst_second);
  for (int path = 0; path < 2; path++) {
    free(pieces[path]);
    free(first_node[path]);
    free(num_nodes[path]);
    free(nodes[path]);
  }
  poly_overlap_workspace_destroy_d(&ws);
  free(prisms);
  free(usable);
  free(corners);
  poly_mesh_shell_free(&shell);
  poly_shape_free_wall_pieces(&wall_pieces);
  poly_shape_free(&shape);
  return 0;
}
