/* Polyhedral shape templates: mesh input, validation and exact mass properties.
 *
 * Host-only C11. A shape is loaded from a surface mesh (STL ascii/binary,
 * Wavefront OBJ, OFF), welded, checked to be a closed, consistently and
 * outward-oriented 2-manifold, and stored in its body frame: centre of mass
 * at the origin, principal axes along x, y, z. Everything the narrow phase
 * needs later (edges, face normals, vertex-triangle adjacency) is built here
 * once, so no hot loop ever has to derive it.
 *
 * Errors never abort: every function that can fail returns a poly_status and
 * writes a one-line message naming the file and the defect into `message`.
 */
#ifndef POLY_SHAPE_H
#define POLY_SHAPE_H

#include <stddef.h>
#include "poly_clip_limits.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum poly_status {
  POLY_OK = 0,
  POLY_ERROR_FILE,          /* missing, unreadable, unknown extension */
  POLY_ERROR_PARSE,         /* malformed content */
  POLY_ERROR_EMPTY,         /* no triangles */
  POLY_ERROR_DEGENERATE,    /* zero-area triangle or repeated vertex */
  POLY_ERROR_OPEN,          /* edge used by one triangle */
  POLY_ERROR_NONMANIFOLD,   /* edge used by >2 triangles, or pinched vertex */
  POLY_ERROR_ORIENTATION,   /* neighbouring triangles disagree on orientation */
  POLY_ERROR_DISCONNECTED,  /* more than one connected component */
  POLY_ERROR_VOLUME,        /* zero enclosed volume */
  POLY_ERROR_MEMORY,
  POLY_ERROR_SELF_INTERSECTION, /* two triangles cross (or touch away from their common vertices) */
  POLY_ERROR_MASS           /* non-finite, non-positive or impossible mass properties (e.g. extreme scale) */
} poly_status;

/* A raw triangle soup as read from a file (file frame, file units). */
typedef struct poly_mesh {
  int num_vertices;
  int num_triangles;
  double *vertices;   /* 3 * num_vertices */
  int *triangles;     /* 3 * num_triangles, vertex indices */
} poly_mesh;

/* Volume, centroid and inertia tensor of a closed triangulation, unit density. */
typedef struct poly_mass_properties {
  double volume;
  double centroid[3];
  double inertia[9];  /* row-major, about the centroid */
} poly_mass_properties;

/* A validated shape in its body frame. */
typedef struct poly_shape {
  int num_vertices;
  int num_triangles;
  int num_edges;
  double *vertices;              /* 3 * num_vertices, body frame */
  int *triangles;                /* 3 * num_triangles, counter-clockwise seen from outside */
  double *face_normals;          /* 3 * num_triangles, unit outward */
  int *edges;                    /* 2 * num_edges, first index < second */
  int *edge_triangles;           /* 2 * num_edges: the two triangles sharing the edge */
  int *triangle_edges;           /* 3 * num_triangles: the edges of corners 0-1, 1-2 and 2-0 */
  int *vertex_triangle_offsets;  /* num_vertices + 1, CSR into vertex_triangles */
  int *vertex_triangles;         /* 3 * num_triangles entries */

  double volume;                 /* after scaling */
  double bounding_radius;        /* max distance of a vertex from the centre of mass */
  double principal_moments[3];   /* unit density, ascending */

  /* Pose of the body frame in the file frame (after scaling):
   * x_file = centre_of_mass + principal_axes * x_body,
   * principal_axes row-major with the principal axes as its columns, det = +1. */
  double centre_of_mass[3];
  double principal_axes[9];

  int was_flipped;               /* 1 if the file's orientation was inward and got inverted */
  int num_welded;                /* vertices merged by welding */

  /* Convex shapes only (NULL, 0 otherwise; poly_shape_find_faces): per triangle the lowest triangle of its
   * face (the coplanar neighbours it is merged with), and the edges between two faces. */
  int *face_of;
  int *ridges;
  int num_ridges;
  /* The triangles whose planes support the shape (every vertex on or behind them, to 1e-12 of its size),
   * so that a body wholly in front of one is apart from the shape (poly_shape_find_faces; all of them
   * for a convex shape). */
  int *support;
  int num_support;
  /* The vertices that can be highest along the directions of each cell of poly_extremes.h (extreme_start: per cell
   * its first entry in extreme_vertices, POLY_EXTREME_CELLS + 1 of them), or NULL for shapes of few vertices
   * (poly_shape_find_faces). */
  int *extreme_start, *extreme_vertices;
  /* The clipping path's shapes (poly_clip.h; NULL, 0 otherwise): convex shapes of at most POLY_CLIP_MAX_PLANES
   * faces, and shapes that are not convex but split into at most POLY_CLIP_MAX_PIECES convex pieces (their
   * faces are their triangles, or the triangles' parts on each piece). Per face its plane (unit outward
   * normal and offset, 4 each) and its corners in order, counter-clockwise seen from outside
   * (clip_loop[clip_loop_start[f] ...], indices into the clip vertices). */
  double *clip_planes;
  int *clip_loop_start;
  int *clip_loop;
  int *clip_face_triangle;  /* per face its lowest triangle */
  int num_clip_faces;
  /* The convex pieces (poly_clip_faces): clip_planes holds num_clip_planes planes, the faces' first for a
   * convex shape (one piece); per piece the masks of the planes it lies behind and in front of, its corners
   * (clip vertex indices; for the cones, num_vertices is the centre of mass) and its faces, each a CSR list. */
  int num_clip_planes, num_clip_pieces;
  poly_clip_words *clip_piece_front, *clip_piece_back;
  int *clip_piece_point_start, *clip_piece_points, *clip_piece_face_start, *clip_piece_faces;
  /* The points the faces' loops and the pieces' corners index when the pieces cut the triangles (the shape's
   * vertices first, then the new corners; poly_convex_partition_impl.h); NULL, 0: the shape's vertices. */
  double *clip_vertices;
  int num_clip_vertices;
  /* Per clip plane of the pieces the index in `support` of a supporting triangle on it, or -1; the mask of those
   * that have one. */
  int *clip_plane_support;
  poly_clip_words clip_support_planes;
  int *clip_face_plane;  /* per clip face the index of its plane among clip_planes (pieces only) */
  int clip_many_faces;   /* 1: the host clips these pieces whatever their faces (poly_shape_wall_pieces) */
} poly_shape;

/* The clipping path's points: the clip vertices where the pieces cut the triangles, else the vertices. */
static inline const double *poly_shape_clip_points(const poly_shape *shape)
{
  return shape->clip_vertices ? shape->clip_vertices : shape->vertices;
}

static inline int poly_shape_num_clip_points(const poly_shape *shape)
{
  return shape->clip_vertices ? shape->num_clip_vertices : shape->num_vertices;
}

/* Reads a mesh; the format is chosen by extension (.stl, .obj, .off, any case).
 * STL: ascii or binary (detected from content, not from the "solid" keyword alone). */
poly_status poly_mesh_read(const char *path, poly_mesh *mesh, char *message, size_t message_size);

/* Merges vertices closer than tolerance * (bounding-box diagonal) and renumbers
 * triangles. Returns the number of vertices removed. */
int poly_mesh_weld(poly_mesh *mesh, double relative_tolerance);

void poly_mesh_free(poly_mesh *mesh);

/* Exact mass properties of a closed, oriented triangulation (divergence theorem). */
void poly_mass_properties_compute(const double *vertices, const int *triangles, int num_triangles,
                                  poly_mass_properties *out);

/* Eigen-decomposition of a symmetric 3x3 matrix (Jacobi). Eigenvalues ascending;
 * eigenvectors are the columns of the row-major `eigenvectors`, a right-handed set. */
void poly_symmetric_eigen3(const double matrix[9], double eigenvalues[3], double eigenvectors[9]);

/* Validates `mesh` (which must already be welded), scales it by `scale`,
 * orients it outward, computes mass properties, and stores it in the body frame.
 * `name` (usually the file path) is used in messages. */
poly_status poly_shape_build(const poly_mesh *mesh, double scale, const char *name,
                             poly_shape *shape, char *message, size_t message_size);

/* Convenience: read + weld + build. */
poly_status poly_shape_load(const char *path, double scale, poly_shape *shape,
                            char *message, size_t message_size);

/* Fills support, and face_of and ridges when the shape is convex (to 1e-12 of its size) and every vertex
 * lies on a ridge (NULL otherwise). Called by poly_shape_build. */
poly_status poly_shape_find_faces(poly_shape *shape);

/* Frees what poly_shape_find_faces made (poly_shape_free does this too). */
void poly_shape_free_faces(poly_shape *shape);

/* The convex pieces fix wall/polyhedral's mesh walls clip on the host, for a shape whose own are cones or none:
 * the partition by its face planes (poly_convex_partition_impl.h) with pieces of up to POLY_CLIP_WALL_PIECE_PLANES
 * planes, which a shape's own pieces may not have (the GPU's polygons), and any number of faces (for pairs of such
 * shapes the general path is faster; against a prism of a few faces the clipping is: rock_40 1.6x). Fills `wall`
 * with the shape's geometry, borrowed (it must outlive `wall`), and pieces of its own, and returns 1; returns 0
 * and leaves `wall` empty when the shape has its own pieces, is convex, or the partition does not fit. Free with
 * poly_shape_free_wall_pieces (either way). */
int poly_shape_wall_pieces(const poly_shape *shape, poly_shape *wall);
void poly_shape_free_wall_pieces(poly_shape *wall);

void poly_shape_free(poly_shape *shape);

#ifdef __cplusplus
}
#endif

#endif
