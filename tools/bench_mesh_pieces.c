/* CPU cost of fix wall/polyhedral's mesh narrow phase: (particle, prism) pieces per second on one core.
 *
 *   bash tools/bench_mesh_pieces.sh [particles] [repeats] [shape] [cells]     (builds this file and runs it)
 *   bench_mesh_pieces SHAPES_DIR [particles] [repeats] [shape] [cells]
 *
 * `shape`: one file of the list (e.g. rock_40.obj) alone, for a profile of its pieces; `all` (the default) every
 * one. `cells` (default 12): the grid's cells a side, so its triangles' legs are 6 / cells bounding radii (2:
 * triangles larger than the particle, as a hopper's or a chute's CAD mesh has them).
 *
 * The scene of tests/unit/gpu_wall_agreement.cpp, so the figures compare with doc/benchmarks.md's
 * "Mesh walls on the GPU" CPU column: per shape (scale 0.01), a 12 x 12 grid of 6 bounding radii with a
 * concave and a convex crease (z = (|x| - |y|) / 4), its shell 2.2 bounding radii thick; particles in random
 * orientations over it, centres from 0.9 radii below to 0.6 above the surface; every prism whose bounding
 * sphere touches the particle's is a piece. Each piece is one poly_overlap_d call (particle, prism) with the
 * second moment on and, when they touch, its nodes read back (poly_overlap_nodes_d), as the wall computes it; the
 * prism's clip faces are made when its first piece needs them (poly_mesh_prism_view), once per prism and
 * timing, as the wall makes them once per prism and step. Also prints what making a prism costs (each usable
 * triangle's, poly_mesh_shell_prism) and making its clip faces besides (poly_mesh_prism_clip_faces), in us, the
 * fastest of `repeats` passes over the mesh. Prints pieces, touching pieces, and pieces per second (median
 * of `repeats` timings of the whole set); then what a touching piece and an apart piece cost apart (the median of
 * `repeats` passes over each subset, the prisms' clip faces made beforehand), which says where the set's time
 * goes. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "poly_mesh_shell.h"
#include "poly_overlap.h"

static const char *const SHAPE_FILES[] = {"schoenhardt.stl", "cube.stl", "tetrahedron.obj", "icosphere_80.off",
                                          "icosphere_320.off", "rock_10.obj", "rock_40.obj", "rock_70.obj"};
#define NUM_SHAPES (int)(sizeof SHAPE_FILES / sizeof SHAPE_FILES[0])

static unsigned long long rng = 0x853c49e6748fea9bull;
static double uniform(void)
{
  rng = rng * 6364136223846793005ull + 1442695040888963407ull;
  return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

static double surface_height(double x, double y) { return 0.25 * (fabs(x) - fabs(y)); }

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Every triangle's prism (usable[t]: it has one), with its clip faces too when asked; returns how many. */
static int make_prisms(const poly_mesh_shell *shell, const double *corners, int num_triangles, int with_clip,
                       poly_mesh_prism *prisms, int *usable)
{
  int count = 0;
  for (int t = 0; t < num_triangles; t++) {
    double nodes[3][3];
    memcpy(nodes, corners + 9 * t, sizeof nodes);
    usable[t] = poly_mesh_shell_prism(shell, t, nodes, &prisms[t]) == 0;
    if (usable[t] && with_clip) poly_mesh_prism_clip_faces(&prisms[t]);
    count += usable[t];
  }
  return count;
}

int main(int argc, char **argv)
{
  if (argc < 2) {
    fprintf(stderr, "usage: bench_mesh_pieces SHAPES_DIR [particles] [repeats]\n");
    return 2;
  }
  int num_particles = argc > 2 ? atoi(argv[2]) : 2000, repeats = argc > 3 ? atoi(argv[3]) : 5;
  printf("| shape | pieces | touching | pieces/s (double, one core) | prism (us) | its clip faces (us) | a touching "
         "piece (us) | an apart piece (us) |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const char *only = argc > 4 && strcmp(argv[4], "all") != 0 ? argv[4] : NULL;
  const int cells = argc > 5 ? atoi(argv[5]) : 12;
  if (cells < 1) {
    fprintf(stderr, "cells must be at least 1\n");
    return 2;
  }
  int found = 0;
  for (int s = 0; s < NUM_SHAPES; s++) {
    if (only && strcmp(only, SHAPE_FILES[s]) != 0) continue;
    found = 1;
    char path[1024], message[512];
    snprintf(path, sizeof path, "%s/%s", argv[1], SHAPE_FILES[s]);
    poly_shape shape;
    if (poly_shape_load(path, 0.01, &shape, message, sizeof message) != POLY_OK) {
      fprintf(stderr, "%s\n", message);
      return 1;
    }
    double radius = shape.bounding_radius;
    /* The grid, counter-clockwise seen from +z (the free side). */
    double width = 6.0 * radius, step = width / cells;
    int num_triangles = 2 * cells * cells;
    double *corners = malloc(sizeof(double) * 9 * (size_t)num_triangles);
    for (int i = 0, t = 0; i < cells; i++)
      for (int j = 0; j < cells; j++) {
        double x0 = -0.5 * width + i * step, y0 = -0.5 * width + j * step;
        double quad[4][3] = {{x0, y0, 0}, {x0 + step, y0, 0}, {x0 + step, y0 + step, 0}, {x0, y0 + step, 0}};
        for (int k = 0; k < 4; k++) quad[k][2] = surface_height(quad[k][0], quad[k][1]);
        const int halves[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int h = 0; h < 2; h++, t++)
          for (int k = 0; k < 3; k++) memcpy(corners + 9 * t + 3 * k, quad[halves[h][k]], sizeof(double) * 3);
      }
    poly_mesh_shell shell;
    if (poly_mesh_shell_build(corners, num_triangles, 2.2 * radius, 1e-8, &shell, message, sizeof message) != 0) {
      fprintf(stderr, "%s\n", message);
      return 1;
    }
    poly_mesh_prism *prisms = malloc(sizeof(poly_mesh_prism) * (size_t)num_triangles);
    int *usable = malloc(sizeof(int) * (size_t)num_triangles), num_usable = 0;
    double prism_time = 1e30, clip_time = 1e30;
    for (int r = 0; r < repeats; r++)
      for (int with_clip = 0; with_clip < 2; with_clip++) {
        double start = now();
        num_usable = make_prisms(&shell, corners, num_triangles, with_clip, prisms, usable);
        double time = (now() - start) / num_usable;
        if (with_clip) clip_time = time < clip_time ? time : clip_time;
        else prism_time = time < prism_time ? time : prism_time;
      }
    /* Pieces: (particle pose, prism) with touching bounding spheres. */
    int capacity = num_particles * num_triangles, num_pieces = 0;
    poly_pose *particle_poses = malloc(sizeof(poly_pose) * (size_t)capacity);
    int *piece_prism = malloc(sizeof(int) * (size_t)capacity);
    for (int n = 0; n < num_particles; n++) {
      poly_pose pose;
      double x = (3.0 * uniform() - 1.5) * radius, y = (3.0 * uniform() - 1.5) * radius;
      pose.position[0] = x;
      pose.position[1] = y;
      pose.position[2] = surface_height(x, y) + (1.5 * uniform() - 0.9) * radius;
      double norm = 0.0;
      for (int k = 0; k < 4; k++) {
        pose.quaternion[k] = 2.0 * uniform() - 1.0;
        norm += pose.quaternion[k] * pose.quaternion[k];
      }
      for (int k = 0; k < 4; k++) pose.quaternion[k] /= sqrt(norm);
      for (int t = 0; t < num_triangles && num_pieces < capacity; t++) {
        if (!usable[t]) continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += pow(pose.position[k] - prisms[t].origin[k], 2);
        double reach = radius + prisms[t].view.bounding_radius;
        if (d2 >= reach * reach) continue;
        particle_poses[num_pieces] = pose;
        piece_prism[num_pieces++] = t;
      }
    }
    poly_overlap_workspace_d ws;
    int max_vertices = shape.num_vertices > 6 ? shape.num_vertices : 6;
    int max_triangles = shape.num_triangles > 8 ? shape.num_triangles : 8;
    poly_overlap_workspace_create_d(&ws, max_vertices, max_triangles);
    ws.want_second_moment = 1;
    ws.want_nodes = 1;
    double *nodes = malloc(sizeof(double) * 3 * (size_t)ws.capacity_corners);
    poly_shape wall_pieces; /* the pieces the fix clips prisms with, as fix wall/polyhedral takes them */
    const int has_wall_pieces = poly_shape_wall_pieces(&shape, &wall_pieces);
    poly_shape_view_d view = poly_shape_view_of(has_wall_pieces ? &wall_pieces : &shape);
    double *timings = malloc(sizeof(double) * (size_t)repeats);
    unsigned char *touches = calloc((size_t)num_pieces, 1);
    int touching = 0;
    double per_piece[3];  /* median seconds a piece: all (the prisms' clip faces made on the way), touching, apart */
    for (int subset = 0; subset < 3; subset++) {
      for (int r = 0; r < repeats; r++) {
        /* The whole set makes each prism's clip faces when its first piece needs them, as the wall does once per
         * prism and step; the subsets (touching pieces, apart ones) find them made. */
        make_prisms(&shell, corners, num_triangles, subset > 0, prisms, usable);
        int count = 0;
        double start = now();
        for (int p = 0; p < num_pieces; p++) {
          if (subset > 0 && touches[p] != (subset == 1)) continue;
          count++;
          poly_mesh_prism *prism = &prisms[piece_prism[p]];
          const poly_shape_view_d *prism_view = poly_mesh_prism_view(prism, &view);
          poly_pose prism_pose = {{prism->origin[0], prism->origin[1], prism->origin[2]}, {1.0, 0.0, 0.0, 0.0}};
          poly_overlap_result result;
          poly_overlap_d(&view, &particle_poses[p], prism_view, &prism_pose, &ws, &result);
          if (result.volume > 0.0) {
            if (subset == 0) touches[p] = 1;
            poly_overlap_nodes_d(&ws, &particle_poses[p], nodes, ws.capacity_corners);
          }
        }
        timings[r] = (now() - start) / (count > 0 ? count : 1);
        if (subset == 0) touching = 0;
        for (int p = 0; subset == 0 && p < num_pieces; p++) touching += touches[p];
      }
      qsort(timings, (size_t)repeats, sizeof(double), by_value);
      per_piece[subset] = timings[repeats / 2];
    }
    printf("| %s | %d | %d | %.3g | %.2f | %.2f | %.2f | %.2f |\n", SHAPE_FILES[s], num_pieces, touching,
           1.0 / per_piece[0], 1e6 * prism_time, 1e6 * (clip_time - prism_time), 1e6 * per_piece[1],
           1e6 * per_piece[2]);
    fflush(stdout);
    free(touches);
    free(timings);
    free(nodes);
    poly_overlap_workspace_destroy_d(&ws);
    free(particle_poses);
    free(piece_prism);
    free(prisms);
    free(usable);
    free(corners);
    poly_mesh_shell_free(&shell);
    poly_shape_free_wall_pieces(&wall_pieces);
    poly_shape_free(&shape);
  }
  if (only && !found) {
    fprintf(stderr, "bench_mesh_pieces: no shape '%s' in its list\n", only);
    return 2;
  }
  return 0;
}
