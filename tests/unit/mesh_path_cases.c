/* Hard cases of the mesh walls' mesh path (src/poly_clip_mesh.h): one particle against one triangle's prism by the
 * prism's mesh view, and by the general path (ws.use_clip = 0) for the reference. tests/test_mesh_walls_clip.py
 * runs it.
 *
 *   mesh_path_cases SHAPES_DIR
 *
 * Prints one line per case: its name, whether the mesh path answered (clipped 1) or handed the pair back
 * (clipped 0), the volumes by both paths and the exact one where known (exact -1: not known), relative to the
 * particle's volume, and the largest difference between the paths in volume (against max(V, 1e-3 V_p)), centroid
 * (against the bounding radius) and depth (against the bounding radius).
 *
 * inside:  a small prism wholly inside an icosphere: no cross-section meets a face's edge, so each face is decided
 *          by the cross-section's winding about its corner; the overlap is the prism itself.
 * engulfed: rock_70 wholly inside a large prism: no face's plane crosses it, its whole surface is inside; the
 *          overlap is the particle.
 * flush:   an icosphere resting on a flat triangle with its lowest vertex on the triangle's plane: handed back.
 * far:     rock_70 into a wall 1e4 particle sizes from the origin.
 * tiny, huge: the same at scales 1e-6 and 1e3. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "poly_clip_mesh.h"
#include "poly_mesh_shell.h"
#include "poly_overlap.h"

typedef struct mesh_case {
  const char *name, *shape;
  double scale;         /* of the shape file */
  double triangle[9];   /* the wall's one triangle, counter-clockwise seen from the free side, in radii */
  double thickness;     /* the shell's, in radii */
  double centre[3];     /* the particle's, in radii */
  double offset;        /* added to every coordinate (world units) */
  int rest;             /* 1: the particle's lowest vertex on the triangle's plane z = 0 (centre[2] ignored) */
  int exact;            /* 1: the overlap is the whole prism, 2: the whole particle */
} mesh_case;

static double worst(double current, double difference) { return difference > current ? difference : current; }

/* The volume and centroid of the prism (its 8 triangles as fans from its first corner). */
static double prism_volume(const poly_mesh_prism *prism, double centroid[3])
{
  double volume = 0.0, moment[3] = {0.0, 0.0, 0.0};
  const double *o = prism->vertices;
  for (int t = 0; t < 8; t++) {
    const double *a = prism->vertices + 3 * prism->triangles[3 * t], *b = prism->vertices + 3 * prism->triangles[3 * t + 1],
                 *c = prism->vertices + 3 * prism->triangles[3 * t + 2];
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) u[k] = a[k] - o[k], v[k] = b[k] - o[k], w[k] = c[k] - o[k];
    const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
    volume += det / 6.0;
    for (int k = 0; k < 3; k++) moment[k] += det / 6.0 * (o[k] + a[k] + b[k] + c[k]) / 4.0;
  }
  for (int k = 0; k < 3; k++) centroid[k] = moment[k] / volume + prism->origin[k];
  return volume;
}

static int run_case(const char *shapes, const mesh_case *c)
{
  char path[1024], message[512];
  snprintf(path, sizeof path, "%s/%s", shapes, c->shape);
  poly_shape shape;
  if (poly_shape_load(path, c->scale, &shape, message, sizeof message) != POLY_OK) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  const poly_shape_view_d view = poly_shape_view_of(&shape);
  const double r = shape.bounding_radius;
  double corners[9];
  for (int i = 0; i < 9; i++) corners[i] = c->triangle[i] * r + c->offset;
  poly_mesh_shell shell;
  if (poly_mesh_shell_build(corners, 1, c->thickness * r, 1e-8, &shell, message, sizeof message) != 0) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  poly_mesh_prism prism;
  double nodes[3][3];
  memcpy(nodes, corners, sizeof nodes);
  if (poly_mesh_shell_prism(&shell, 0, nodes, &prism) != 0) {
    fprintf(stderr, "%s: no prism\n", c->name);
    return 1;
  }
  poly_mesh_prism_clip_faces(&prism);
  poly_pose pose = {{c->centre[0] * r + c->offset, c->centre[1] * r + c->offset, c->centre[2] * r + c->offset},
                    {1.0, 0.0, 0.0, 0.0}};
  if (c->rest) {
    double lowest = INFINITY;
    for (int v = 0; v < shape.num_vertices; v++) lowest = fmin(lowest, shape.vertices[3 * v + 2]);
    pose.position[2] = c->offset - lowest;
  }
  const poly_pose prism_pose = {{prism.origin[0], prism.origin[1], prism.origin[2]}, {1.0, 0.0, 0.0, 0.0}};
  poly_overlap_workspace_d ws;
  poly_overlap_workspace_create_d(&ws, shape.num_vertices > 6 ? shape.num_vertices : 6,
                                  shape.num_triangles > 8 ? shape.num_triangles : 8);
  ws.want_nodes = 1;
  ws.want_second_moment = 1;
  poly_overlap_result result[2];
  int clipped = 0;
  for (int by = 0; by < 2; by++) {
    ws.use_clip = by == 0;
    const int fallbacks = ws.clip_fallbacks;
    poly_overlap_d(&view, &pose, by == 0 ? &prism.mesh_view : &prism.view, &prism_pose, &ws, &result[by]);
    if (by == 0) clipped = ws.clip_fallbacks == fallbacks;
  }
  const double vp = shape.volume, scale = fmax(result[1].volume, 1e-3 * vp);
  double exact = -1.0, exact_centroid[3] = {0.0, 0.0, 0.0}, centroid_error = 0.0;
  if (c->exact == 1) exact = prism_volume(&prism, exact_centroid) / vp;
  if (c->exact == 2) { /* the particle, centred on its centre of mass */
    exact = 1.0;
    for (int k = 0; k < 3; k++) exact_centroid[k] = pose.position[k];
  }
  double d_volume = fabs(result[0].volume - result[1].volume) / scale, d_centroid = 0.0;
  for (int k = 0; k < 3; k++) {
    d_centroid = worst(d_centroid, fabs(result[0].centroid[k] - result[1].centroid[k]) / r);
    if (c->exact) centroid_error = worst(centroid_error, fabs(result[0].centroid[k] - exact_centroid[k]) / r);
  }
  printf("case %s clipped %d mesh %.17g general %.17g exact %.17g volume %.3g centroid %.3g depth %.3g "
         "exact_centroid %.3g\n",
         c->name, clipped, result[0].volume / vp, result[1].volume / vp, exact, d_volume, d_centroid,
         fabs(result[0].depth - result[1].depth) / r, centroid_error);
  poly_overlap_workspace_destroy_d(&ws);
  poly_mesh_shell_free(&shell);
  poly_shape_free(&shape);
  return 0;
}

int main(int argc, char **argv)
{
  if (argc < 2) {
    fprintf(stderr, "usage: mesh_path_cases SHAPES_DIR\n");
    return 2;
  }
  const double small[9] = {-0.13, -0.07, 0.0, 0.11, -0.09, 0.0, -0.08, 0.12, 0.0}; /* off the icosphere's symmetries */
  const double floor[9] = {-3.0, -3.0, 0.0, 3.0, -3.0, 0.0, -3.0, 3.0, 0.0};
  const double big[9] = {-6.0, -5.0, 0.0, 7.0, -4.0, 0.0, -5.0, 6.5, 0.0};
  const mesh_case cases[] = {
      {"inside", "icosphere_320.off", 1.0, {0}, 0.2, {0.0, 0.0, -0.05}, 0.0, 0, 1},
      {"engulfed", "rock_70.obj", 0.01, {0}, 5.0, {0.3, -0.2, -2.5}, 0.0, 0, 2},
      {"flush", "icosphere_80.off", 1.0, {0}, 2.2, {0.0, 0.0, 0.0}, 0.0, 1, 0},
      {"far", "rock_70.obj", 0.01, {0}, 2.2, {-1.0, -1.0, 0.3}, 1e4 * 0.01, 0, 0},
      {"tiny", "rock_70.obj", 1e-6, {0}, 2.2, {-1.0, -1.0, 0.3}, 0.0, 0, 0},
      {"huge", "rock_70.obj", 1e3, {0}, 2.2, {-1.0, -1.0, 0.3}, 0.0, 0, 0},
  };
  for (int i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
    mesh_case c = cases[i];
    memcpy(c.triangle, i == 0 ? small : i == 1 ? big : floor, sizeof c.triangle);
    if (run_case(argv[1], &c)) return 1;
  }
  return 0;
}
