/* The solid behind an open triangle-mesh wall, as one prism per triangle, for
 * the volumetric contact of a particle with a LIGGGHTS mesh (fix wall/polyhedral
 * mesh ...).
 *
 * Each oriented triangle's normal points into the free space. Every mesh vertex
 * gets one direction m, the angle-weighted mean of the unit normals of the
 * triangles around it. The prism of a triangle (v0, v1, v2) is the solid
 * between the triangle and its copy pushed back by the shell thickness h along
 * the vertex directions, (v0 - h m0, v1 - h m1, v2 - h m2); its three side
 * faces are the quads over the edges, each split into two triangles along the
 * diagonal chosen from the two vertices' global numbers. Two triangles sharing
 * an edge share the same side quad split the same way, so neighbouring prisms
 * meet face to face: the prisms partition the shell with no volume counted
 * twice and none left out, at shared edges and vertices alike, whatever the
 * angle between the faces (convex or concave). A flat wall tessellated into
 * many triangles gets vertical prisms, whose union is the slab under the plane:
 * the same overlap as one plane. The shell is the mesh's solid only within the
 * thickness h; at a sharp convex edge it reaches h cos(theta/2) behind the edge
 * (theta the angle between the face normals) instead of h. Where triangles
 * next to a sharp edge are narrower than the shell is thick, a full-depth
 * prism would fold over itself or turn inside out; there the vertices' depths
 * shrink (shared by all the triangles around a vertex, so prisms still meet
 * face to face) until every prism is a proper solid: its bottom facing the way
 * its top does, its side quads facing outward, and, certified by a
 * decomposition into tetrahedra that all turn the right way, nowhere inside
 * out. (The prisms' winding numbers always sum to 1 in the shell, shared faces
 * cancelling; but the overlap core returns nothing for a prism's inside-out
 * part while its neighbours count the region it turns over.) Behind such an
 * edge the shell is then exact only as deep as the edge's shrunk vertices
 * reach behind the faces (about a cell's width, less near the mesh's border):
 * deeper, the two faces' prisms overlap (doc/fix_wall_polyhedral.md).
 *
 * Vertex directions are stored per triangle corner as coefficients (a, b, c) of
 * m = a (v1 - v0) + b (v2 - v0) + c n in the triangle's own frame, so they
 * follow rigid motions of the mesh (fix move/mesh) without any bookkeeping. */
#ifndef POLY_MESH_SHELL_H
#define POLY_MESH_SHELL_H

#include <stddef.h>

#include "poly_overlap.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct poly_mesh_shell {
  int num_triangles;
  int num_vertices;          /* after merging coincident corners */
  int *vertex_ids;           /* 3 per triangle */
  double thickness;          /* h */
  double *corner_directions; /* 9 per triangle: (a, b, c) per corner, see above, times the vertex's depth / h */
  int num_open_edges;        /* edges of one triangle only (the mesh's border) */
  int num_misoriented_edges; /* shared edges run the same way in both triangles: flipped normals */
  int num_nonmanifold_edges; /* edges of more than two triangles */
  double min_corner_cosine;  /* smallest m . n over all corners: the steepest prism side */
  double min_depth_fraction; /* smallest vertex depth / h (1: full depth everywhere) */
  int num_folded;            /* triangles whose prism stays folded (then skipped) */
} poly_mesh_shell;

/* corners: 9 doubles per triangle (v0, v1, v2), indexed by the mesh's global
 * triangle number; thickness: h. Corners closer than relative_tolerance times
 * the mesh's bounding-box diagonal are one vertex. Returns 0, or -1 with a
 * message. */
int poly_mesh_shell_build(const double *corners, int num_triangles, double thickness, double relative_tolerance,
                          poly_mesh_shell *shell, char *message, size_t message_size);
void poly_mesh_shell_free(poly_mesh_shell *shell);

/* The mesh's connected surfaces (triangles joined across edges of exactly two triangles), each oriented
 * consistently whatever the triangles' winding in the file: a triangle's canonical corners are (v0, v1, v2)
 * or, where flip is set, (v0, v2, v1). A closed surface (every edge of two triangles) is oriented outward
 * (positive enclosed volume); an open one by its lowest-numbered triangle, whose canonical normal's largest
 * component is positive. Shells built from the canonical corners and from their reverse put the solid
 * behind and in front of the canonical orientation: fix wall/polyhedral takes, per particle and surface,
 * the one away from the particle's centre. */
typedef struct poly_mesh_orientation {
  int num_triangles;
  int num_components;
  int *flip;                 /* per triangle */
  int *component;            /* per triangle */
  int *component_closed;     /* per component: every edge shared by exactly two of its triangles */
  int *component_size;       /* triangles */
  int *component_flipped;    /* triangles flipped from the file's winding */
  int *component_conflicts;  /* edges that no orientation makes consistent (a non-orientable surface) */
  double *component_volume;  /* enclosed by a closed component, canonical orientation (> 0) */
  int num_misoriented_edges; /* shared edges running the same way in both triangles, as wound in the file */
  /* 9 per triangle: the canonical unit normal of the triangle across canonical edge c (corner c -> c + 1) as
   * coefficients (a, b, c) of a e1 + b e2 + c n in the triangle's canonical frame; (0, 0, 1) on open and
   * non-manifold edges. n + that: the edge's pseudo-normal, for the side of a point nearest the edge. */
  double *edge_normals;
} poly_mesh_orientation;

int poly_mesh_orient(const double *corners, int num_triangles, double relative_tolerance,
                     poly_mesh_orientation *orientation, char *message, size_t message_size);
void poly_mesh_orientation_free(poly_mesh_orientation *orientation);

/* Corners 9 per triangle in canonical order (reverse = 1: the canonical reversed, (v0, v2, v1) of it). */
void poly_mesh_canonical_corners(const poly_mesh_orientation *orientation, const double *corners, int reverse,
                                 double *out);

/* The point of triangle (a, b, c) nearest p and which feature it lies on: 0 the face, 1 + k corner k,
 * 4 + k the edge from corner k to corner k + 1. */
int poly_triangle_closest(const double p[3], const double a[3], const double b[3], const double c[3],
                          double closest[3]);

/* One triangle's prism, as a closed shape for poly_overlap_d: 6 vertices,
 * 8 triangles, 12 edges, relative to its own centroid (`origin`, world). */
typedef struct poly_mesh_prism {
  double origin[3];
  double vertices[18];
  double face_normals[24];
  int triangles[24];
  int edges[24];
  int edge_triangles[24];
  int support[8];   /* the triangles whose planes have every corner behind them */
  int face_of[8];   /* when all 8 do (a convex prism): per triangle its face's lowest triangle */
  int ridges[12];   /* and the edges between two faces */
  /* The prism's faces for the clipping path (poly_clip.h; clip_view.clip.num_faces 0 when it has none): per face its
   * plane, its corners in order, a triangle of it, and the convex pieces they bound: a convex prism is one piece
   * of its merged faces, one that is not the three tetrahedra of its split (faces its 8 triangles, planes theirs
   * and the two between the tetrahedra). */
  double clip_planes[40];
  int clip_loop_start[9], clip_loop[24], clip_face_triangle[8], clip_plane_support[10], clip_face_plane[8];
  int clip_piece_point_start[4], clip_piece_points[12], clip_piece_face_start[4], clip_piece_faces[8];
  poly_clip_words clip_piece_front[3], clip_piece_back[3];
  int clip_num_planes, clip_num_pieces;
  int clip_state;    /* 1 once poly_mesh_prism_clip_faces has looked for them */
  int diagonals[3];  /* per side c, 1: its diagonal runs from top corner c to bottom corner c + 1; 2: the other */
  /* Both views point into the prism (use it where it was made: a copy's would point into the original). */
  poly_shape_view_d view;       /* without clip faces: the blocks or general path */
  poly_shape_view_d clip_view;  /* the same with them, once made (clip.num_faces 0 until then, or without) */
  poly_shape_view_d mesh_view;  /* clip_view for the mesh path (poly_clip_mesh.h: clip.facets 1) */
} poly_mesh_prism;

/* The prism's faces for the clipping path (into clip_view; none for a prism whose side diagonals run in a cycle
 * or whose split is not three proper tetrahedra), found once: not made with the prism, as they cost about a
 * third as much again (0.2 us). */
void poly_mesh_prism_clip_faces(poly_mesh_prism *prism);

/* The view of the prism that `particle` meets it by (fix wall/polyhedral), with clip faces (made the first time)
 * where a clipping path takes the pair: mesh_view (the mesh path, poly_clip_mesh.h) for a particle the host's
 * clipping path does not take (rock_70, icospheres), for the mesh walls' pieces (rock_40) and, for other shapes
 * in pieces (Schönhardt, rock_10), when the prism's triangle has an edge of at least 3 of the particle's bounding
 * radii; clip_view (poly_clip.h) for the rest: convex particles and shapes in pieces against a finer mesh, which
 * it clips faster (doc/benchmarks.md, "Mesh walls on the CPU"). Else the view without clip faces. The choice
 * depends on the particle and the prism alone, not on what other particles made. */
const poly_shape_view_d *poly_mesh_prism_view(poly_mesh_prism *prism, const poly_shape_view_d *particle);

/* The prism of global triangle `triangle` whose current corners are `nodes`
 * (world). Returns 0, or -1 for a degenerate triangle or a folded prism. */
int poly_mesh_shell_prism(const poly_mesh_shell *shell, int triangle, const double nodes[3][3],
                          poly_mesh_prism *prism);

/* One contact from a particle's overlaps with several prisms of a shell (poly_overlap_d with the particle
 * as A): volumes, first moments and area vectors add up, as the prisms partition the shell; the normal is
 * the summed area vector's direction (the volume-weighted mean of the pieces' normals when that sums to
 * nothing: a particle wholly inside the shell); the depth is the extent of the union of the pieces' nodes
 * along that normal. Piece k's nodes (poly_overlap_nodes_d, relative to the particle) are
 * nodes[3 * first_node[k] ...], num_nodes[k] of them; num_nodes[k] < 0 (not kept) lets its own depth,
 * projected on the normal, stand in. */
void poly_mesh_contact_combine(const poly_overlap_result *pieces, const double *nodes, const int *first_node,
                               const int *num_nodes, int count, poly_overlap_result *contact);

#ifdef __cplusplus
}
#endif

#endif
