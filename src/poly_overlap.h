/* Exact intersection of two closed triangulated shapes: volume, centroid,
 * contact normal and depth of the overlap, for the volumetric contact law.
 *
 * Method (document 000, sec. 5): the intersection I = A n B is bounded by the
 * part of A's surface inside B and the part of B's surface inside A. By the
 * divergence theorem its volume and first moment are sums over the boundary,
 * and each planar facet's share can be written as a sum over its oriented
 * boundary segments, each independently: a segment (x1, x2) on the plane of
 * triangle t adds the signed tetrahedron (O, c_t, x1, x2), c_t any point of
 * that plane and O any point. Both are taken on the overlap (O its first node,
 * c_t the first node on t), so the tetrahedra are the overlap's size and do
 * not cancel, even for a contact far shallower than the particles are large
 * and away from the centre line. This is the edge-local form of the cusp
 * construction (eqs. 5.7-5.11): no triangulation of I, no convex decomposition, so
 * non-convex shapes are first-class. The boundary segments are
 *   - the parts of each edge of A lying inside B (and of B inside A), found by
 *     sorting the edge's crossings with the other surface and toggling from the
 *     inside/outside state of the edge's first vertex, and
 *   - the intersection segment of every pair of crossing triangles (t of A,
 *     s of B), oriented along n_t x n_s on t and reversed on s.
 * Triangles are first filtered by the two half-spaces along the centre line
 * (eqs. 5.3-5.5); everything runs in the body frame of A, shifted to the
 * middle of that slab, so accuracy does not depend on where the pair is.
 *
 * Degenerate configurations (a vertex on a face, an edge on an edge, coplanar
 * faces, identical shapes in identical poses) are decided as if B were moved
 * by an infinitesimal fixed generic translation (simulation of simplicity):
 * every predicate that evaluates to exactly zero takes the sign of its
 * first-order term in that translation, and every predicate is evaluated on
 * canonically ordered vertices so that neighbouring triangles agree. The
 * result is the limit of the nearby generic configuration: finite, and
 * continuous in the poses.
 *
 * Four paths compute these sums (poly_overlap_impl.h): the reference path,
 * which evaluates each predicate where it needs it (the GPU's); the crossing
 * records, which decide each edge-triangle crossing once and derive the
 * inside states and the chords from those decisions (the same bits); and, for
 * two shapes found convex when built, the convex path (faces' planes, edges
 * clipped by them) or, for convex shapes of few faces, the blocks path (the
 * same clipping from one table of every vertex's sides of every face, no
 * half-space filter), which hand what they cannot decide back.
 *
 * The same code is compiled in double (suffix _d), single (suffix _f) and
 * mixed (suffix _m: single geometry, double sums) precision from
 * poly_overlap_impl.h; poses and results are always double, and the geometry
 * is always relative to A's body frame.
 */
#ifndef POLY_OVERLAP_H
#define POLY_OVERLAP_H

#include <stddef.h>

#include "poly_clip.h"
#include "poly_rigid.h"
#include "poly_shape.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Position of the centre of mass and body-to-world orientation. */
typedef struct poly_pose {
  double position[3];
  double quaternion[4];
} poly_pose;

typedef struct poly_overlap_result {
  double volume;          /* of the intersection */
  double centroid[3];     /* world frame */
  double normal[3];       /* unit, world frame, pointing from particle A towards particle B */
  double depth;           /* extent of the intersection along normal */
  double area;            /* area of A's surface inside B */
  double projected_area;  /* |sum of the area vectors of A's surface inside B|: normal * projected_area is that sum,
                             which adds up over pieces of B (fix wall/polyhedral's mesh prisms) */
  int num_nodes;          /* intersection nodes: vertices inside the other shape + edge-face crossings */
  int num_inconsistent;   /* edges whose crossings disagreed with their end vertices (rounding); 0 normally */
  int filtered_out;       /* 1 when the half-space filter proved there is no overlap */
  int recomputed;         /* 1 when an inconsistent edge made the pair be evaluated again without the filter */
  int smoothed;           /* 1 when flush faces made area and normal the mean of two shifted evaluations */
  double second_moment[6];/* of the overlap's volume about its centroid, world frame (xx yy zz xy xz yz); only
                             when the workspace's want_second_moment is set (the contact law's rocking damping) */
  int separating;         /* filtered out by a supporting triangle of either shape (poly_shape's support): its code,
                             for poly_overlap_still_separated at the next step; else -1 */
  double gap;             /* filtered out: a distance the bodies are proved apart by (the slab's or the parting
                             plane's separation less every rounding and tolerance of this and any later evaluation of
                             the pair): while the points of the two bodies have moved by less than this, summed over
                             both, there is no overlap; 0 when not known */
} poly_overlap_result;

/* What a pair's last crossing search found, kept by the caller from step to step (the pair style, per contact),
 * so that the next evaluations of the pair take the same boundary without the search while B has moved, relative
 * to A, by less than `margin`: below it no edge-triangle decision can change (a certificate from each decision's
 * predicates, poly_overlap_cache_impl.h), so the crossings, the vertices inside and the edges with inside parts
 * are those the search would find, and the sums over them, made by the same functions in the same order, give
 * every result bit it would give. General path (crossing records) only; a caller sets the workspace's
 * crossing_cache (zeroed for a new pair) before each call. */
#define POLY_CACHE_RECORDS 32
#define POLY_CACHE_EDGES 48
#define POLY_CACHE_INSIDE 32
#define POLY_CACHE_WATCH 32
typedef struct poly_crossing_cache {
  const void *shape_a, *shape_b;   /* the shapes it was made for (their vertex arrays) */
  double rotation[9], translation[3]; /* B's pose in A's body frame at that search */
  double margin;                   /* 0: no certificate (the next evaluation searches) */
  int num_records, records_b;      /* crossings of A's edges [0, records_b), of B's [records_b, num_records) */
  int num_edges, edges_b;          /* edges with a part inside the other body: A's [0, edges_b), B's after */
  int num_inside, inside_b;        /* vertices inside the other body: A's [0, inside_b), B's after */
  int num_kept_a, num_kept_b;      /* the search's kept triangles (its pass reports them) */
  int hits;                        /* evaluations that took them since the certificate was made */
  int backoff, skip;               /* searches to make no certificate after one that served no evaluation */
  int edge[POLY_CACHE_RECORDS], triangle[POLY_CACHE_RECORDS]; /* ascending by edge, then triangle */
  int inside_edge[POLY_CACHE_EDGES]; /* ascending within each body */
  int inside_vertex[POLY_CACHE_INSIDE]; /* ascending within each body */
  /* The edge-triangle pairs whose decisions the certificate does not cover (their margins below it), ascending by
   * margin: each decided again, by the search's predicates, once B's motion reaches its margin. */
  int num_watch;
  int watch_edge[POLY_CACHE_WATCH], watch_triangle[POLY_CACHE_WATCH]; /* edge of A (of B when watch_of_b) */
  unsigned char watch_of_b[POLY_CACHE_WATCH], watch_crosses[POLY_CACHE_WATCH];
  double watch_margin[POLY_CACHE_WATCH];
  /* The watched pairs' last check (cache_replay): the first recheck_count of them were decided again at this pose
   * and keep their decisions while B's motion from it stays under recheck_margin (0: none kept). */
  double recheck_rotation[9], recheck_translation[3], recheck_margin;
  int recheck_count;
  int last_reached;                /* the watched pairs reached at the last evaluation from the cache */
  int recheck_skips, recheck_backoff, recheck_wait; /* evaluations the last margins spared; rechecks to wait */
  /* The chords of the crossings as the first replay after the search paired their ends (group_chord_ends): the
   * same for every replay of that search (the crossings, their order along each edge and their directions are
   * what the certificate holds), kept so that the later replays need not pair them again; -1 until then, or when
   * they do not fit. Each from record chord_from to record chord_to, on A's triangle chord_a and B's chord_b. */
  int num_chords;
  unsigned short chord_a[POLY_CACHE_RECORDS], chord_b[POLY_CACHE_RECORDS];
  unsigned char chord_from[POLY_CACHE_RECORDS], chord_to[POLY_CACHE_RECORDS];
} poly_crossing_cache;

/* The workspace's last_evaluation: the pair at its last evaluation, as the pair style knows it. */
enum { POLY_LAST_UNKNOWN = 0, POLY_LAST_TOUCHING = 1, POLY_LAST_APART = 2 };
#define POLY_OVERLAP_DECLARE(REAL, SUFFIX)                                                            \
  typedef struct poly_shape_view##SUFFIX {                                                           \
    int num_vertices, num_triangles, num_edges;                                                     \
    const REAL *vertices;     /* 3 * num_vertices, body frame */                                    \
    const REAL *face_normals; /* 3 * num_triangles, unit outward */                                 \
    const int *triangles;     /* 3 * num_triangles */                                               \
    const int *edges;         /* 2 * num_edges, first < second */                                   \
    const int *edge_triangles;/* 2 * num_edges: first runs first->second, second the reverse */     \
    const int *triangle_edges;/* 3 * num_triangles: edges of corners 0-1, 1-2, 2-0; or NULL */      \
    REAL bounding_radius;                                                                            \
    const int *face_of;       /* convex shapes: per triangle its face's lowest triangle; else NULL */ \
    const int *ridges;        /* convex shapes: the edges between two faces */                      \
    int num_ridges;                                                                                  \
    const int *support;       /* triangles whose planes support the shape, or NULL (none known) */  \
    int num_support;                                                                                 \
    const int *extreme_start, *extreme_vertices; /* poly_extremes.h's table, or NULL (scan them all) */ \
    poly_clip_faces clip;     /* double views of convex shapes of few faces: poly_clip.h; else 0 faces */ \
  } poly_shape_view##SUFFIX;                                                                        \
  /* Scratch memory for one pair at a time, sized once for the largest shapes. */                   \
  typedef struct poly_overlap_workspace##SUFFIX {                                                   \
    int capacity_vertices, capacity_triangles, capacity_points;                                     \
    int use_filter;                    /* 1 (default): half-space filter; 0: all triangles, even of separated pairs */ \
    int want_second_moment;            /* 1: also the result's second_moment (default 0) */              \
    int use_records;                   /* 1 (default): crossings decided once (poly_overlap_records_impl.h); \
                                          0: the reference path (ray parity, every kept triangle pair) */   \
    int capacity_records, capacity_runs;                                                            \
    int records_overflows;             /* passes that took the reference path as the records did not fit */ \
    REAL *record_lambda, *record_entering; /* per crossing record: parameter along the edge, +-1 */  \
    int *record_triangle, *record_edge;    /* the other body's triangle crossed, and the edge */      \
    int *runs;                         /* per edge tested: edge, first record, count */              \
    int *chord_buckets, *chord_ends;   /* per triangle of A; per record end (triangle of B, record) */ \
    int use_convex;                    /* 1 (default): convex shapes take the convex path (poly_overlap_convex_impl.h), with the filter on */ \
    int use_clip;                      /* 1 (default): pairs of shapes with clip faces take poly_clip.h (double entry only) */ \
    int clip_fallbacks;                /* pairs with clip faces it handed to the other paths (flush faces) */ \
    int want_nodes;                    /* 1: the clipping path (double) leaves its corners in `points` too, or hands the \
                                          pair on when they do not fit (the mesh walls' depth); 0 (default): none */ \
    int capacity_corners;              /* room in `points` for those corners (>= capacity_points) */ \
    int corners_kept;                  /* 1: the last overlap's points are those corners, all kept */ \
    int capacity_sides, convex_fallbacks; /* convex path: side table size; passes it left to the general path */ \
    REAL *sides;                       /* convex path: per vertex used, its plane_side for each face */ \
    int *faces_a, *faces_b, *face_column_a, *face_column_b; /* its faces, and their columns per face */ \
    int *row_of_a, *row_of_b;          /* per vertex: its row of the side table, -1 before it is made */ \
    int capacity_grid;                 /* entries of the grid of kept triangles (find_crossings) */    \
    int *grid_start, *grid_entries, *grid_candidates; /* cells; their triangles; an edge's candidates */ \
    unsigned *grid_bits;               /* find_crossings: a bit per triangle, the candidates of an edge */ \
    int *box_passing;                  /* find_crossings: an edge's candidates whose box meets its own */ \
    int *near_list_a, *near_list_b;    /* records path: the kept triangles whose box meets both bodies' boxes */ \
    unsigned *edge_mask;               /* find_crossings: a bit per edge of a kept triangle */          \
    REAL *vertices_a, *vertices_b;     /* local frame, 3 * capacity_vertices each */                \
    REAL *along_a, *along_b;           /* per vertex its place along the slab's axis (host: records path) */ \
    REAL *planes_a, *planes_b;         /* per triangle (v1-v0)x(v2-v0) and |v1-v0|_1 |v2-v0|_1: 4 each */ \
    REAL *normals_b;                   /* B's unit normals in the local frame */                   \
    REAL *bounds_a, *bounds_b;         /* per kept triangle: low xyz, high xyz */                  \
    REAL *apex_a, *apex_b;             /* per kept triangle: apex of its boundary tetrahedra (3 each) */ \
    unsigned char *kept_a, *kept_b;    /* triangles that survive the half-space filter */           \
    int *kept_list_a, *kept_list_b;    /* their indices, so no loop visits the others */            \
    unsigned char *inside_a, *inside_b;/* vertex of A inside B, and vice versa */                   \
    unsigned char *in_slab_a, *in_slab_b; /* per vertex: it reaches the slab (host: records path) */ \
    REAL *crossings;                   /* along one edge: parameters, then directions; 2 * capacity_triangles */ \
    REAL *points;                      /* intersection nodes, 3 * capacity_points */                \
    int num_points;                    /* of the last overlap (may exceed capacity_points) */        \
    double origin[3];                  /* of the local frame of the points, in A's body frame */     \
    poly_crossing_cache *crossing_cache; /* the pair's (see poly_crossing_cache), or NULL (default) */ \
    int cache_pass;                    /* set by overlap_local: the pass that may use or fill it */     \
    int last_evaluation;               /* what the caller knows of the pair, which picks the filters tried after \
                                          the slab: POLY_LAST_UNKNOWN (default) the supporting triangles; \
                                          POLY_LAST_TOUCHING none (they part few such pairs); POLY_LAST_APART \
                                          those and the parting search (poly_overlap_parting_impl.h; the \
                                          clipping path's pairs too, before the clipping) */             \
    long cache_hits, cache_searches, cache_certificates; /* evaluations that took the cached crossings; that \
                                          searched with a cache given; certificates made */           \
  } poly_overlap_workspace##SUFFIX;

POLY_OVERLAP_DECLARE(double, _d)
POLY_OVERLAP_DECLARE(float, _f)
/* Mixed precision works on single-precision shapes and workspaces. */
typedef poly_shape_view_f poly_shape_view_m;
typedef poly_overlap_workspace_f poly_overlap_workspace_m;

/* Running counts of the degenerate evaluations (see overlap_local in
 * poly_overlap_impl.h), for the users' statistics of the pair style and walls. */
typedef struct poly_degenerate_counts {
  double smoothed;      /* contacts with flush faces, area and normal the mean of two shifted evaluations */
  double recomputed;    /* contacts evaluated again without the filter after an inconsistent edge */
  double inconsistent;  /* contacts with an inconsistent edge even so (a bug to report) */
} poly_degenerate_counts;

static inline void poly_degenerate_count(poly_degenerate_counts *counts, const poly_overlap_result *result)
{
  counts->smoothed += result->smoothed > 0;
  counts->recomputed += result->recomputed > 0;
  counts->inconsistent += result->num_inconsistent > 0;
}

/* Precision of the narrow phase, as the pair styles' `precision` keyword names it. */
typedef enum poly_precision { POLY_PRECISION_DOUBLE = 0, POLY_PRECISION_SINGLE = 1, POLY_PRECISION_MIXED = 2 } poly_precision;

/* View of a double-precision shape (no copy). */
poly_shape_view_d poly_shape_view_of(const poly_shape *shape);

/* Single-precision copy of a shape's geometry; free with poly_shape_view_free_f. */
int poly_shape_view_make_f(const poly_shape *shape, poly_shape_view_f *view);
void poly_shape_view_free_f(poly_shape_view_f *view);

/* Workspace for shapes of at most these sizes; 0 on success. (The memory
 * layout is poly_overlap_workspace_layout in poly_overlap_impl.h.) */
int poly_overlap_workspace_create_d(poly_overlap_workspace_d *ws, int max_vertices, int max_triangles);
int poly_overlap_workspace_create_f(poly_overlap_workspace_f *ws, int max_vertices, int max_triangles);
void poly_overlap_workspace_destroy_d(poly_overlap_workspace_d *ws);
void poly_overlap_workspace_destroy_f(poly_overlap_workspace_f *ws);

/* The overlap of shape a at pose_a with shape b at pose_b. The workspace must
 * have been created for shapes at least as large as both. */
void poly_overlap_d(const poly_shape_view_d *a, const poly_pose *pose_a, const poly_shape_view_d *b,
                    const poly_pose *pose_b, poly_overlap_workspace_d *ws, poly_overlap_result *result);
void poly_overlap_f(const poly_shape_view_f *a, const poly_pose *pose_a, const poly_shape_view_f *b,
                    const poly_pose *pose_b, poly_overlap_workspace_f *ws, poly_overlap_result *result);
void poly_overlap_m(const poly_shape_view_m *a, const poly_pose *pose_a, const poly_shape_view_m *b,
                    const poly_pose *pose_b, poly_overlap_workspace_m *ws, poly_overlap_result *result);

/* Whether the pair is still parted by the supporting triangle that parted it before (`separating`, a result's
 * code from these shapes in this order): 1 when the other body lies wholly in front of that triangle's plane
 * (by 1e-12 of their size; in single precision by more than the normals' rounding), so there is no overlap;
 * 0 otherwise, or for a code that fits neither shape. Costs one plane against one body's vertices, so a pair
 * that stays apart from step to step is rejected without the narrow phase. *gap: as poly_overlap_result's. */
int poly_overlap_still_separated_d(const poly_shape_view_d *a, const poly_pose *pose_a, const poly_shape_view_d *b,
                                   const poly_pose *pose_b, int separating, double *gap);
int poly_overlap_still_separated_f(const poly_shape_view_f *a, const poly_pose *pose_a, const poly_shape_view_f *b,
                                   const poly_pose *pose_b, int separating, double *gap);

/* The nodes of the last overlap computed with ws (by poly_overlap_d, A at pose_a; _f: by poly_overlap_f or _m):
 * world frame, relative to A's position. Writes at most `capacity` nodes (3 doubles each) and returns how many
 * there are, or -1 when they did not fit in the workspace (then only the result's own depth is known). */
int poly_overlap_nodes_d(const poly_overlap_workspace_d *ws, const poly_pose *pose_a, double *nodes, int capacity);
int poly_overlap_nodes_f(const poly_overlap_workspace_f *ws, const poly_pose *pose_a, double *nodes, int capacity);

/* How many nodes the last overlap left in ws (what poly_overlap_nodes returns), -1 when they did not fit. */
static inline int poly_overlap_num_nodes_d(const poly_overlap_workspace_d *ws)
{
  return ws->num_points <= (ws->corners_kept ? ws->capacity_corners : ws->capacity_points) ? ws->num_points : -1;
}

#ifdef __cplusplus
}
#endif

#endif
