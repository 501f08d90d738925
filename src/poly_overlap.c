/* Double, single and mixed precision instances of the overlap computation
 * (poly_overlap_impl.h), shape views and workspaces. */
#include "poly_overlap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "poly_clip_mesh.h"
#include "poly_overlap_instances.h"

/* The clipping path's faces and pieces (double, whatever the view's precision: mixed precision clips in double). */
static poly_clip_faces clip_faces_of(const poly_shape *shape)
{
  poly_clip_faces clip;
  clip.num_faces = shape->num_clip_faces;
  clip.num_vertices = poly_shape_num_clip_points(shape);
  clip.vertices = poly_shape_clip_points(shape);
  clip.planes = shape->clip_planes;
  clip.loop_start = shape->clip_loop_start;
  clip.loop = shape->clip_loop;
  clip.triangle = shape->clip_face_triangle;
  clip.num_planes = shape->num_clip_planes;
  clip.num_pieces = shape->num_clip_pieces;
  clip.piece_front = shape->clip_piece_front;
  clip.piece_back = shape->clip_piece_back;
  clip.piece_point_start = shape->clip_piece_point_start;
  clip.piece_points = shape->clip_piece_points;
  clip.piece_face_start = shape->clip_piece_face_start;
  clip.piece_faces = shape->clip_piece_faces;
  clip.plane_support = shape->clip_plane_support;
  clip.support_planes = shape->clip_support_planes;
  clip.face_plane = shape->clip_face_plane;
  clip.many_faces = shape->clip_many_faces;
  clip.facets = 0;  /* a shape's pairs keep poly_clip.h's path (the mesh path is the walls': their prisms) */
  return clip;
}

poly_shape_view_d poly_shape_view_of(const poly_shape *shape)
{
  poly_shape_view_d view;
  view.num_vertices = shape->num_vertices;
  view.num_triangles = shape->num_triangles;
  view.num_edges = shape->num_edges;
  view.vertices = shape->vertices;
  view.face_normals = shape->face_normals;
  view.triangles = shape->triangles;
  view.edges = shape->edges;
  view.edge_triangles = shape->edge_triangles;
  view.triangle_edges = shape->triangle_edges;
  view.face_of = shape->face_of;
  view.ridges = shape->ridges;
  view.num_ridges = shape->num_ridges;
  view.support = shape->support;
  view.num_support = shape->num_support;
  view.extreme_start = shape->extreme_start;
  view.extreme_vertices = shape->extreme_vertices;
  view.bounding_radius = shape->bounding_radius;
  view.clip = clip_faces_of(shape);
  return view;
}

int poly_shape_view_make_f(const poly_shape *shape, poly_shape_view_f *view)
{
  memset(view, 0, sizeof *view);
  float *vertices = (float *)malloc(sizeof(float) * 3 * (size_t)shape->num_vertices);
  float *normals = (float *)malloc(sizeof(float) * 3 * (size_t)shape->num_triangles);
  if (!vertices || !normals) {
    free(vertices);
    free(normals);
    return -1;
  }
  for (int i = 0; i < 3 * shape->num_vertices; i++) vertices[i] = (float)shape->vertices[i];
  for (int i = 0; i < 3 * shape->num_triangles; i++) normals[i] = (float)shape->face_normals[i];
  view->num_vertices = shape->num_vertices;
  view->num_triangles = shape->num_triangles;
  view->num_edges = shape->num_edges;
  view->vertices = vertices;
  view->face_normals = normals;
  view->triangles = shape->triangles;
  view->edges = shape->edges;
  view->edge_triangles = shape->edge_triangles;
  view->triangle_edges = shape->triangle_edges;
  view->face_of = shape->face_of;
  view->ridges = shape->ridges;
  view->num_ridges = shape->num_ridges;
  view->support = shape->support;
  view->num_support = shape->num_support;
  view->extreme_start = shape->extreme_start;
  view->extreme_vertices = shape->extreme_vertices;
  view->bounding_radius = (float)shape->bounding_radius;
  view->clip = clip_faces_of(shape);
  return 0;
}

void poly_shape_view_free_f(poly_shape_view_f *view)
{
  free((void *)view->vertices);
  free((void *)view->face_normals);
  memset(view, 0, sizeof *view);
}

/* One allocation per workspace, laid out by poly_overlap_workspace_layout (the
 * GPU carves its per-thread workspaces the same way). */
#define POLY_WORKSPACE_FUNCTIONS(SUFFIX)                                                               \
  void poly_overlap_workspace_destroy##SUFFIX(poly_overlap_workspace##SUFFIX *ws)                     \
  {                                                                                                   \
    free(ws->vertices_a);                                                                             \
    memset(ws, 0, sizeof *ws);                                                                        \
  }                                                                                                   \
  int poly_overlap_workspace_create##SUFFIX(poly_overlap_workspace##SUFFIX *ws, int max_vertices,     \
                                            int max_triangles)                                        \
  {                                                                                                   \
    memset(ws, 0, sizeof *ws);                                                                        \
    size_t bytes = poly_overlap_workspace_layout##SUFFIX(NULL, NULL, max_vertices, max_triangles);     \
    void *memory = malloc(bytes);                                                                     \
    if (!memory) return -1;                                                                           \
    poly_overlap_workspace_layout##SUFFIX(ws, memory, max_vertices, max_triangles);                   \
    return 0;                                                                                         \
  }

POLY_WORKSPACE_FUNCTIONS(_d)
POLY_WORKSPACE_FUNCTIONS(_f)

static void poly_result_to_world(const poly_pose *pose_a, const double rotation_a[9], const double *local_centroid,
                                 const double *local_normal, poly_overlap_result *result)
{
  if (!(result->volume > 0.0)) {
    memset(result->centroid, 0, sizeof result->centroid);
    memset(result->normal, 0, sizeof result->normal);
    memset(result->second_moment, 0, sizeof result->second_moment);
    return;
  }
  poly_matrix_apply(rotation_a, local_centroid, result->centroid);
  for (int k = 0; k < 3; k++) result->centroid[k] += pose_a->position[k];
  poly_matrix_apply(rotation_a, local_normal, result->normal);
  double local_second[6];
  for (int e = 0; e < 6; e++) local_second[e] = result->second_moment[e];
  poly_second_moment_rotate(rotation_a, local_second, result->second_moment);
}

/* The mesh path (poly_clip_mesh.h) for A against B, a mesh wall's prism in its mesh view (poly_mesh_prism_view):
 * whether it takes the pair, and its overlap. Double only: mixed precision's views hold single-precision vertices. */
static int clip_mesh_takes_d(const poly_shape_view_d *a, const poly_shape_view_d *b)
{
  return poly_clip_mesh_takes(a, &b->clip);
}
static int clip_mesh_overlap_d(const poly_shape_view_d *a, const poly_shape_view_d *b, const double *rotation,
                               const double *translation, double size, int want_second, poly_clip_result *out,
                               poly_clip_corners *corners)
{
  return poly_clip_mesh_overlap(a, &b->clip, rotation, translation, size, want_second, out, corners);
}
static int clip_mesh_takes_f(const poly_shape_view_f *a, const poly_shape_view_f *b)
{
  (void)a, (void)b;
  return 0;
}
static int clip_mesh_overlap_f(const poly_shape_view_f *a, const poly_shape_view_f *b, const double *rotation,
                               const double *translation, double size, int want_second, poly_clip_result *out,
                               poly_clip_corners *corners)
{
  (void)a, (void)b, (void)rotation, (void)translation, (void)size, (void)want_second, (void)out, (void)corners;
  return 0;
}

/* The clipping path (poly_clip.h) for two shapes with clip faces, in double (also for mixed precision, whose
 * contact law is in double: the clipping is cheaper than the single-precision general path and exact to double
 * rounding); 1 when it gave the answer. Single precision keeps the general path. POINTS: the workspace's nodes
 * where they are doubles (ws->want_nodes), else NULL. */
#define POLY_OVERLAP_BY_CLIPPING(NAME, SUFFIX, POINTS)                                                  \
  static int NAME(const poly_shape_view##SUFFIX *a, const poly_shape_view##SUFFIX *b,                 \
                                         const double *rotation, const double *translation,           \
                                         poly_overlap_workspace##SUFFIX *ws, double *local_centroid,   \
                                         double *local_normal, poly_overlap_result *result)            \
  {                                                                                                   \
    const int by_mesh = ws->use_clip && clip_mesh_takes##SUFFIX(a, b);                                \
    if (!by_mesh && (!ws->use_clip || !poly_clip_takes(&a->clip) || !poly_clip_takes(&b->clip))) return 0; \
    /* The general path's slab first for pieces (an apart pair of pieces costs a projection, not every piece), \
     * and for a pair apart at its last evaluation its parting search (the general path's filters): the       \
     * clipping finds such a pair apart too, but proves no gap for skip_apart to wait on. */                  \
    const int search = ws->use_filter && ws->last_evaluation == POLY_LAST_APART;                      \
    if (a->clip.num_pieces > 1 || b->clip.num_pieces > 1 || search || by_mesh) {                      \
      double separation;                                                                              \
      if (poly_slab_or_parting##SUFFIX(a, b, rotation, translation, search, &separation)) {           \
        memset(result, 0, sizeof *result);                                                            \
        result->filtered_out = 1;                                                                     \
        result->separating = -1;                                                                      \
        result->gap = poly_proved_gap##SUFFIX(a, b, separation);                                      \
        ws->num_points = 0;                                                                           \
        return 1;                                                                                     \
      }                                                                                               \
    }                                                                                                 \
    poly_clip_result clip;                                                                            \
    double *points = POINTS;                                                                          \
    poly_clip_corners corners = {points, ws->capacity_corners, 0, {0.0, 0.0, 0.0}};                   \
    poly_clip_corners *keep = points && ws->want_nodes ? &corners : NULL;                             \
    const double size = (double)a->bounding_radius + (double)b->bounding_radius;                      \
    if (!(by_mesh ? clip_mesh_overlap##SUFFIX(a, b, rotation, translation, size, ws->want_second_moment, &clip, \
                                              keep)                                                   \
                  : poly_clip_overlap(&a->clip, &b->clip, rotation, translation, size, ws->want_second_moment, \
                                      &clip, keep)) ||                                                \
        (keep && corners.count < 0)) { /* flush faces, or corners the workspace does not hold */      \
      ws->clip_fallbacks++;                                                                           \
      return 0;                                                                                       \
    }                                                                                                 \
    result->volume = clip.volume;                                                                     \
    result->depth = clip.depth;                                                                       \
    result->area = clip.area;                                                                         \
    result->projected_area = clip.projected_area;                                                     \
    result->num_nodes = clip.num_nodes;                                                               \
    result->num_inconsistent = result->recomputed = result->smoothed = 0;                             \
    result->filtered_out = !(clip.volume > 0.0); /* apart, proved by the clipping */                  \
    result->separating = clip.separating;                                                             \
    result->gap = 0.0;                                                                                \
    for (int e = 0; e < 6; e++) result->second_moment[e] = clip.second_moment[e];                     \
    for (int k = 0; k < 3; k++) {                                                                     \
      local_centroid[k] = clip.centroid[k];                                                           \
      local_normal[k] = clip.normal[k];                                                               \
    }                                                                                                 \
    ws->num_points = keep ? corners.count : 0;                                                        \
    ws->corners_kept = keep != NULL;                                                                  \
    for (int k = 0; k < 3; k++) ws->origin[k] = corners.origin[k];                                    \
    return 1;                                                                                         \
  }

POLY_OVERLAP_BY_CLIPPING(overlap_by_clipping_d, _d, ws->points)
POLY_OVERLAP_BY_CLIPPING(overlap_by_clipping_m, _f, (double *)NULL)
static int overlap_by_clipping_f(const poly_shape_view_f *a, const poly_shape_view_f *b, const double *rotation,
                                      const double *translation, poly_overlap_workspace_f *ws, double *local_centroid,
                                      double *local_normal, poly_overlap_result *result)
{
  (void)a, (void)b, (void)rotation, (void)translation, (void)ws, (void)local_centroid, (void)local_normal,
      (void)result;
  return 0;
}

#define POLY_OVERLAP_ENTRY(SUFFIX)                                                                     \
  void poly_overlap##SUFFIX(const poly_shape_view##SUFFIX *a, const poly_pose *pose_a,                \
                            const poly_shape_view##SUFFIX *b, const poly_pose *pose_b,                \
                            poly_overlap_workspace##SUFFIX *ws, poly_overlap_result *result)          \
  {                                                                                                   \
    double rotation_a[9], rotation[9], translation[3], local_centroid[3] = {0, 0, 0},                 \
           local_normal[3] = {0, 0, 0};                                                               \
    poly_overlap_relative_pose(pose_a->position, pose_a->quaternion, pose_b->position, pose_b->quaternion, \
                               rotation_a, rotation, translation);                                    \
    ws->corners_kept = 0;                                                                             \
    if (!overlap_by_clipping##SUFFIX(a, b, rotation, translation, ws, local_centroid, local_normal, result)) \
      poly_overlap_local##SUFFIX(a, b, rotation, translation, ws, local_centroid, local_normal, result); \
    poly_result_to_world(pose_a, rotation_a, local_centroid, local_normal, result);                   \
  }

POLY_OVERLAP_ENTRY(_d)
POLY_OVERLAP_ENTRY(_f)
POLY_OVERLAP_ENTRY(_m)

#define POLY_STILL_SEPARATED(SUFFIX)                                                                   \
  int poly_overlap_still_separated##SUFFIX(const poly_shape_view##SUFFIX *a, const poly_pose *pose_a, \
                                           const poly_shape_view##SUFFIX *b, const poly_pose *pose_b, \
                                           int separating, double *gap)                               \
  {                                                                                                   \
    double rotation_a[9], rotation[9], translation[3];                                                \
    poly_overlap_relative_pose(pose_a->position, pose_a->quaternion, pose_b->position, pose_b->quaternion, \
                               rotation_a, rotation, translation);                                    \
    return poly_still_separated##SUFFIX(a, b, rotation, translation, separating, gap);                \
  }

POLY_STILL_SEPARATED(_d)
POLY_STILL_SEPARATED(_f)

#define POLY_OVERLAP_NODES(SUFFIX)                                                                     \
  int poly_overlap_nodes##SUFFIX(const poly_overlap_workspace##SUFFIX *ws, const poly_pose *pose_a,   \
                                 double *nodes, int capacity)                                        \
  {                                                                                                   \
    if (ws->num_points > (ws->corners_kept ? ws->capacity_corners : ws->capacity_points)) return -1;  \
    double rotation[9];                                                                               \
    poly_quat_to_matrix(pose_a->quaternion, rotation);                                                \
    for (int p = 0; p < ws->num_points && p < capacity; p++) {                                        \
      double local[3];                                                                                \
      for (int k = 0; k < 3; k++) local[k] = (double)ws->points[3 * p + k] + ws->origin[k];           \
      poly_matrix_apply(rotation, local, nodes + 3 * p);                                              \
    }                                                                                                 \
    return ws->num_points;                                                                            \
  }

POLY_OVERLAP_NODES(_d)
POLY_OVERLAP_NODES(_f)
