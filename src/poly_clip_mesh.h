/* The clipping path for a closed triangle mesh A (any shape: not convex, not in pieces) against a body B in convex
 * pieces whose every face is its piece's whole facet on its plane (a mesh wall's prism: one convex piece, or the
 * three tetrahedra of its split; poly_clip_faces.facets). Host only, double.
 *
 * The intersection's boundary is A's surface inside B and B's surface inside A. The first is A's triangles clipped
 * by each of B's pieces (whose inner planes cut but never make a polygon, as in poly_clip.h). The second needs no
 * pieces of A: B's face on plane P, inside A, is bounded by A's cross-section by P (the segments where A's triangles
 * cross P) cut by the face's edges, and by the parts of the face's edges inside A; each segment is summed on its own
 * as a fan triangle, so a cross-section that is not convex (holes included) needs no bridges. So the particles the
 * clipping path does not take (rock_70, the icospheres) meet prisms 1.5-2.1x faster than by the general path, and
 * shapes in pieces meet triangles larger than themselves faster than by their pieces (doc/benchmarks.md, "Mesh
 * walls on the CPU"; poly_mesh_prism_view chooses).
 *
 * A vertex of A within the flush distance of a plane of B hands the pair back (returns 0), as poly_clip.h does;
 * so do crossings along a face's edges that do not alternate (a degenerate pose) and full buffers. */
#ifndef POLY_CLIP_MESH_H
#define POLY_CLIP_MESH_H

#include "poly_clip.h"
#include "poly_overlap.h"

/* Which (particle, prism) pairs poly_mesh_prism_view gives the mesh path: 1 as it chooses, 0 none, 2 every one
 * whose particle fits (benchmarks' switch: BENCH_DEFINES=-DPOLY_CLIP_MESH_PATH=0|2). */
#ifndef POLY_CLIP_MESH_PATH
#define POLY_CLIP_MESH_PATH 1
#endif
#define POLY_CLIP_MESH_MAX_VERTICES 1024
#define POLY_CLIP_MESH_MAX_TRIANGLES 2048
#define POLY_CLIP_MESH_MAX_PLANES POLY_CLIP_MAX_PLANES /* B's planes (a prism's 5, or its split's 10): side masks */
#define POLY_CLIP_MESH_MAX_THROUGH 128  /* places where A's cross-section crosses one face's edges */

/* A is the particle's double-precision view (poly_shape_view_d): its body-frame vertices, triangles (counter-clockwise
 * seen from outside), edges and the triangles on either side of each, and each triangle's edges. */

/* Does the mesh path take mesh A (small enough for the buffers, its edges known) against such a B? */
POLY_INLINE int poly_clip_mesh_fits(const poly_shape_view_d *a)
{
  return a->triangle_edges && a->num_vertices <= POLY_CLIP_MESH_MAX_VERTICES &&
         a->num_triangles <= POLY_CLIP_MESH_MAX_TRIANGLES && a->num_edges <= 3 * POLY_CLIP_MESH_MAX_TRIANGLES / 2;
}

/* Does the mesh path take this pair: A fits and B is a prism's mesh view (faces its pieces' facets), of few planes? */
POLY_INLINE int poly_clip_mesh_takes(const poly_shape_view_d *a, const poly_clip_faces *b)
{
  return b->facets && b->num_faces > 0 && b->num_planes <= POLY_CLIP_MESH_MAX_PLANES &&
         b->num_vertices <= POLY_CLIP_MAX_VERTICES && poly_clip_mesh_fits(a);
}

/* The point where A's edge `e` crosses `plane`, from its lower end (the same point from either triangle). */
POLY_INLINE void poly_clip_mesh_crossing(const poly_shape_view_d *a, int e, const double *plane, double *point)
{
  const double *p = a->vertices + 3 * a->edges[2 * e], *q = a->vertices + 3 * a->edges[2 * e + 1];
  const double sp = poly_clip_side(plane, p), sq = poly_clip_side(plane, q), t = sp / (sp - sq);
  for (int k = 0; k < 3; k++) point[k] = p[k] + t * (q[k] - p[k]);
}

/* The edges of A's triangle `t` (crossing plane `bit`) its segment in the plane runs from and to, A's inside on its
 * left seen from the plane's front (so that the cross-section winds counter-clockwise about the plane's normal):
 * from the edge leaving a corner alone in front to the one entering it, the other way round for one alone behind. */
POLY_INLINE void poly_clip_mesh_segment(const poly_shape_view_d *a, int t, int bit, const unsigned *ahead, int *from,
                                        int *to)
{
  const int *corner = a->triangles + 3 * t, *edge = a->triangle_edges + 3 * t;
  const int f0 = (ahead[corner[0]] >> bit) & 1, f1 = (ahead[corner[1]] >> bit) & 1, f2 = (ahead[corner[2]] >> bit) & 1;
  const int alone = f0 == f1 ? 2 : (f0 == f2 ? 1 : 0);  /* the corner on its own side */
  const int leaving = edge[alone], entering = edge[(alone + 2) % 3];
  const int in_front = alone == 0 ? f0 : (alone == 1 ? f1 : f2);
  *from = in_front ? leaving : entering;
  *to = in_front ? entering : leaving;
}

/* A corner of the intersection for the depth (relative to the accumulator's reference, set by the first one). */
POLY_INLINE void poly_clip_mesh_keep_point(poly_clip_accumulator *acc, const double *p)
{
  if (acc->num_corners++ == 0)
    for (int k = 0; k < 3; k++) acc->reference[k] = p[k];
  double x[3];
  for (int k = 0; k < 3; k++) x[k] = p[k] - acc->reference[k];
  if (acc->depth_pass) {
    poly_clip_extent(x, 1, acc->direction, &acc->low, &acc->high);
  } else if (acc->num_kept < POLY_CLIP_MAX_NODES) {
    for (int k = 0; k < 3; k++) acc->nodes[3 * acc->num_kept + k] = x[k];
    acc->num_kept++;
  } else {
    acc->overflow = 1;
  }
}

/* One boundary segment (s to e) of B's face inside A, as the fan triangle from the face's point `c` (all relative to
 * the reference), summed as poly_clip_add_polygon sums a triangle (B's side: no area). */
POLY_INLINE void poly_clip_mesh_add_segment(poly_clip_accumulator *acc, const double *c, const double *s,
                                            const double *e)
{
  if (acc->depth_pass) return;
  const double fan[9] = {c[0], c[1], c[2], s[0], s[1], s[2], e[0], e[1], e[2]};
  poly_clip_add_polygon(fan, 3, 0, &acc->sums);
}

/* Per triangle of A, its corners' sides of B's planes: the planes some corner is in front of and all are, and
 * likewise behind. */
typedef struct poly_clip_mesh_sides {
  unsigned any_ahead, all_ahead, any_behind, all_behind;
} poly_clip_mesh_sides;

/* A's cross-section by plane `k`: per triangle of `crossing`, the edges its segment runs from (`start`) and to
 * (`end`), A's inside on its left seen from the plane's front (reversed with `flip`), and each such edge's crossing
 * point in `edge_point` (3 per edge of A). The section is closed and A's triangles share each edge in opposite
 * directions, so every crossing edge starts one segment and ends another: computed once, as the start, the same
 * bits for both segments (each triangle computed both of its ends before, so every point twice). */
POLY_INLINE void poly_clip_mesh_section(const poly_shape_view_d *a, const int *crossing, int num_crossing, int k,
                                        const unsigned *ahead, const double *plane, int flip, int *start, int *end,
                                        double *edge_point)
{
  for (int i = 0; i < num_crossing; i++) {
    int from, to;
    poly_clip_mesh_segment(a, crossing[i], k, ahead, &from, &to);
    start[i] = flip ? to : from;
    end[i] = flip ? from : to;
    poly_clip_mesh_crossing(a, start[i], plane, edge_point + 3 * start[i]);
  }
}

/* What segment s-e of a closed curve in the plane of unit normal `normal` adds to the curve's winding number about
 * point `p` on it (crossings of a ray from p), in the plane's projection on the coordinate plane its normal is most
 * along (the sign may flip: only whether the sum is 0 counts). */
POLY_INLINE int poly_clip_mesh_winding(const double *s, const double *e, const double *normal, const double *p)
{
  const double ax = fabs(normal[0]), ay = fabs(normal[1]), az = fabs(normal[2]);
  const int drop = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2), u = (drop + 1) % 3, w = (drop + 2) % 3;
  const double su = s[u] - p[u], sw = s[w] - p[w], eu = e[u] - p[u], ew = e[w] - p[w];
  const double left = su * ew - sw * eu;
  if (sw <= 0.0 && ew > 0.0 && left > 0.0) return 1;
  if (sw > 0.0 && ew <= 0.0 && left < 0.0) return -1;
  return 0;
}

/* Where a segment of A's cross-section passes through an edge of B's face: the edge, the place along it, the point,
 * and whether the cross-section goes into the face there (1) or out of it (0). */
typedef struct poly_clip_mesh_crossing_point {
  int edge, into;
  double along, point[3];
} poly_clip_mesh_crossing_point;

POLY_INLINE void poly_clip_mesh_add_part(poly_clip_accumulator *acc, double *origin, int *have_origin,
                                         const double *from, const double *to)
{
  double s[3], e[3];
  poly_clip_mesh_keep_point(acc, from);
  for (int k = 0; k < 3; k++) s[k] = from[k] - acc->reference[k], e[k] = to[k] - acc->reference[k];
  if (!*have_origin) {
    for (int k = 0; k < 3; k++) origin[k] = s[k];
    *have_origin = 1;
  }
  poly_clip_mesh_add_segment(acc, origin, s, e);
}

/* B's face `face` on plane `k` of a piece (`out_of`: per triangle of A the planes of the piece all its corners are
 * outside of; `flip`: the face's outward normal is the plane's reversed; `start`, `end`, `edge_point`: A's section
 * by the plane, from poly_clip_mesh_section), inside A, wound about the face's outward normal. Its boundary there
 * is (1) the parts inside the face of A's cross-section by the plane (the segments where A's triangles `crossing`
 * cross it, A's inside on their left), each segment cut by the face's edges, and (2) the parts of the face's edges
 * inside A, which start where the cross-section leaves the face and end where it enters it, or are the whole edges
 * when it crosses none and a corner is inside A (its winding about that corner). Each
 * segment is summed on its own (a fan triangle from the face's first point), so a cross-section that is not convex
 * needs no bridges, and segments of triangles wholly outside a plane of the piece are not made at all; every point
 * summed is a corner of the intersection, kept for the depth. Returns 0 when the crossings along the edges do not
 * alternate (a degenerate pose) or the buffers overflow. */
POLY_INLINE int poly_clip_mesh_face(const poly_clip_faces *b, int face, const double *xb, const unsigned *out_of,
                                    const int *crossing, int num_crossing, const int *start, const int *end,
                                    const double *edge_point, const double *planes, int k, int flip,
                                    poly_clip_accumulator *acc)
{
  poly_clip_mesh_crossing_point through[POLY_CLIP_MESH_MAX_THROUGH];
  int num_through = 0;
  const double *plane = planes + 4 * k;
  /* The face's corners, counter-clockwise seen from outside, and per edge its outward direction in the plane: the
   * segments are cut by the face's own edges, not by the planes of the faces beside it, whose lines in this plane are
   * ill-conditioned where the two are nearly coplanar (a prism's side folded a little): cut by those, the volume
   * strayed from the other paths' by 100 times their rounding. */
  const int *corner = b->loop + b->loop_start[face];
  const int num_corners = b->loop_start[face + 1] - b->loop_start[face];
  const double sign = flip ? -1.0 : 1.0, normal[3] = {sign * plane[0], sign * plane[1], sign * plane[2]};
  double outward[3 * POLY_CLIP_MAX_LOOP];
  for (int c = 0; c < num_corners; c++) {
    const double *u = xb + 3 * corner[c], *v = xb + 3 * corner[c + 1 == num_corners ? 0 : c + 1];
    const double d[3] = {v[0] - u[0], v[1] - u[1], v[2] - u[2]};
    poly_cross3_d(d, normal, outward + 3 * c);
  }
  double origin[3] = {0.0, 0.0, 0.0};
  int have_origin = 0;
  /* (1) The cross-section's segments inside the face. */
  for (int i = 0; i < num_crossing; i++) {
    if (out_of[crossing[i]]) continue;  /* the triangle, and its segment, outside the piece */
    const double *s = edge_point + 3 * start[i], *e = edge_point + 3 * end[i];
    double t0 = 0.0, t1 = 1.0;
    int in_edge = -1, out_edge = -1;
    for (int c = 0; c < num_corners; c++) {
      const double *u = xb + 3 * corner[c], *w = outward + 3 * c;
      const double ds = w[0] * (s[0] - u[0]) + w[1] * (s[1] - u[1]) + w[2] * (s[2] - u[2]);
      const double de = w[0] * (e[0] - u[0]) + w[1] * (e[1] - u[1]) + w[2] * (e[2] - u[2]);
      if ((ds > 0.0 && de >= 0.0) || (de > 0.0 && ds >= 0.0)) { /* outside, or touching it from outside */
        t0 = 2.0;
        break;
      }
      if (ds > 0.0) {
        const double f = ds / (ds - de);
        if (f > t0) t0 = f, in_edge = c;
      } else if (de > 0.0) {
        const double f = ds / (ds - de);
        if (f < t1) t1 = f, out_edge = c;
      }
    }
    if (!(t0 < t1)) continue;
    double p[3], q[3];
    for (int c = 0; c < 3; c++) {
      p[c] = in_edge >= 0 ? s[c] + t0 * (e[c] - s[c]) : s[c];
      q[c] = out_edge >= 0 ? s[c] + t1 * (e[c] - s[c]) : e[c];
    }
    for (int side = 0; side < 2; side++) {
      const int edge = side ? out_edge : in_edge;
      if (edge < 0) continue;
      if (num_through == POLY_CLIP_MESH_MAX_THROUGH) return 0;
      poly_clip_mesh_crossing_point *x = through + num_through++;
      const double *u = xb + 3 * corner[edge], *w = xb + 3 * corner[edge + 1 == num_corners ? 0 : edge + 1];
      const double *at = side ? q : p;
      x->edge = edge;
      x->along = (at[0] - u[0]) * (w[0] - u[0]) + (at[1] - u[1]) * (w[1] - u[1]) + (at[2] - u[2]) * (w[2] - u[2]);
      x->into = !side;
      for (int c = 0; c < 3; c++) x->point[c] = at[c];
    }
    poly_clip_mesh_add_part(acc, origin, &have_origin, p, q);
  }
  /* (2) The face's edges inside A: along each edge (sorted), inside A from where the cross-section leaves the face
   * to where it enters it. The state at corner 0: that before the first crossing (a crossing into the face ends an
   * edge's inside part), or, with none at all, the cross-section's winding about the corner. */
  for (int i = 1; i < num_through; i++) /* by edge, then along it */
    for (int j = i; j > 0; j--) {
      poly_clip_mesh_crossing_point *x = through + j - 1, *y = through + j;
      if (x->edge < y->edge || (x->edge == y->edge && x->along <= y->along)) break;
      const poly_clip_mesh_crossing_point swap = *x;
      *x = *y, *y = swap;
    }
  int inside;
  if (num_through > 0) {
    inside = through[0].into;
  } else {
    int winding = 0;
    for (int i = 0; i < num_crossing; i++)
      winding += poly_clip_mesh_winding(edge_point + 3 * start[i], edge_point + 3 * end[i], plane,
                                        xb + 3 * corner[0]);
    inside = winding != 0;
  }
  for (int c = 0, x = 0; c < num_corners; c++) {
    const double *from = xb + 3 * corner[c], *to = xb + 3 * corner[c + 1 == num_corners ? 0 : c + 1];
    for (; x < num_through && through[x].edge == c; x++) {
      if (through[x].into != inside) return 0; /* the crossings do not alternate: degenerate */
      if (inside) poly_clip_mesh_add_part(acc, origin, &have_origin, from, through[x].point);
      inside = !inside;
      from = through[x].point;
    }
    if (inside) poly_clip_mesh_add_part(acc, origin, &have_origin, from, to);
  }
  return 1;
}

/* A's triangle `t` clipped by the planes of `cuts` (reversed for those of `back`) into `polygon` (room for
 * POLY_CLIP_MAX_POLYGON corners; poly_clip_by_planes); returns the corner count (0: nothing left), or -1 when it
 * outgrows that. */
POLY_INLINE int poly_clip_mesh_clip_triangle(const poly_shape_view_d *a, int t, const double *planes, unsigned cuts,
                                             unsigned back, double *polygon)
{
  double work[3 * POLY_CLIP_MAX_POLYGON], *result = polygon;
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 3; k++) polygon[3 * c + k] = a->vertices[3 * a->triangles[3 * t + c] + k];
  const int n = poly_clip_by_planes(polygon, work, 3, planes, cuts, back, POLY_CLIP_MAX_POLYGON, &result);
  if (n > 0 && result != polygon)
    for (int c = 0; c < 3 * n; c++) polygon[c] = result[c];
  return n;
}

/* A's triangles clipped by the piece (front, back) of B, each surviving polygon accumulated on A's side; per
 * triangle in `out_of` the planes of the piece all its corners are outside of (0 when some part may be inside). */
POLY_INLINE int poly_clip_mesh_triangles(const poly_shape_view_d *a, const poly_clip_mesh_sides *sides,
                                         const double *planes, unsigned front, unsigned back, unsigned *out_of,
                                         poly_clip_accumulator *acc)
{
  double polygon[3 * POLY_CLIP_MAX_POLYGON];
  for (int t = 0; t < a->num_triangles; t++) {
    const poly_clip_mesh_sides *side = sides + t;
    out_of[t] = (side->all_ahead & front) | (side->all_behind & back);
    if (out_of[t]) continue;
    const unsigned some = (side->any_ahead & front) | (side->any_behind & back);
    const int n = poly_clip_mesh_clip_triangle(a, t, planes, some, back, polygon);
    if (n < 0) return 0;
    if (n >= 3) poly_clip_accumulate(acc, polygon, n, 1);
  }
  return 1;
}

/* The overlap of mesh A and B (B's body frame taken to A's by `rotation` and `translation`), as poly_clip_overlap:
 * 1 with `out` filled (volume 0: apart, with a separating plane's code when one of B's supporting planes has all of
 * A in front), 0 for the general path. */
POLY_INLINE int poly_clip_mesh_overlap(const poly_shape_view_d *a, const poly_clip_faces *b, const double *rotation,
                                       const double *translation, double size, int want_second,
                                       poly_clip_result *out, poly_clip_corners *corners)
{
  const double flush = POLY_CLIP_FLUSH * size;
  const int num_planes = b->num_planes;
  double planes[4 * POLY_CLIP_MESH_MAX_PLANES];
  unsigned ahead[POLY_CLIP_MESH_MAX_VERTICES], behind[POLY_CLIP_MESH_MAX_VERTICES];
  unsigned out_of[POLY_CLIP_MESH_MAX_TRIANGLES];
  poly_clip_mesh_sides sides[POLY_CLIP_MESH_MAX_TRIANGLES];
  int crossing[POLY_CLIP_MESH_MAX_TRIANGLES], start[POLY_CLIP_MESH_MAX_TRIANGLES], end[POLY_CLIP_MESH_MAX_TRIANGLES];
  double edge_point[3 * (3 * POLY_CLIP_MESH_MAX_TRIANGLES / 2)];  /* a closed mesh has 3/2 edges a triangle */
  out->volume = out->depth = out->area = out->projected_area = 0.0;
  out->num_nodes = 0;
  out->separating = -1;
  for (int e = 0; e < 6; e++) out->second_moment[e] = 0.0;
  if (corners) corners->count = 0;
  for (int f = 0; f < num_planes; f++) {
    double *plane = planes + 4 * f;
    poly_matrix_apply(rotation, b->planes + 4 * f, plane);
    plane[3] = b->planes[4 * f + 3] + plane[0] * translation[0] + plane[1] * translation[1] + plane[2] * translation[2];
  }
  /* Every vertex's sides (poly_clip_sides: two planes at a time on a core); none is on a plane, so behind is the
   * rest. */
  unsigned all_ahead, all_behind = ~0u, any_ahead = 0u, any_behind = 0u;
  if (!poly_clip_sides(a->vertices, a->num_vertices, planes, num_planes, flush, ahead, &all_ahead)) return 0;
  const unsigned valid = (1u << num_planes) - 1u;
  for (int v = 0; v < a->num_vertices; v++) {
    behind[v] = valid & ~ahead[v];
    all_behind &= behind[v], any_ahead |= ahead[v], any_behind |= behind[v];
  }
  const unsigned supporting = (unsigned)poly_clip_mask_of(&b->support_planes);
  if (all_ahead & supporting) {
    out->separating = (b->plane_support[poly_clip_lowest_bit(all_ahead & supporting)] << 1) | 1;
    return 1;
  }
  for (int t = 0; t < a->num_triangles; t++) {
    const int *c = a->triangles + 3 * t;
    poly_clip_mesh_sides *side = sides + t;
    side->any_ahead = ahead[c[0]] | ahead[c[1]] | ahead[c[2]];
    side->all_ahead = ahead[c[0]] & ahead[c[1]] & ahead[c[2]];
    side->any_behind = behind[c[0]] | behind[c[1]] | behind[c[2]];
    side->all_behind = behind[c[0]] & behind[c[1]] & behind[c[2]];
  }
  double xb[3 * POLY_CLIP_MAX_VERTICES];
  for (int v = 0; v < b->num_vertices; v++) {
    poly_matrix_apply(rotation, b->vertices + 3 * v, xb + 3 * v);
    for (int k = 0; k < 3; k++) xb[3 * v + k] += translation[k];
  }
  poly_clip_accumulator acc;
  poly_clip_accumulator_start(&acc, want_second);
  for (int pass = 0; pass < 2; pass++) {
    for (int j = 0; j < b->num_pieces; j++) {
      const unsigned front = (unsigned)poly_clip_mask_of(b->piece_front + j),
                     back = (unsigned)poly_clip_mask_of(b->piece_back + j);
      /* A plane of the piece with all of A outside it: nothing of the piece is in A. */
      if ((all_ahead & front) | (all_behind & back)) continue;
      if (!poly_clip_mesh_triangles(a, sides, planes, front, back, out_of, &acc)) return 0;
      for (int i = b->piece_face_start[j]; i < b->piece_face_start[j + 1]; i++) {
        const int face = b->piece_faces[i], k = b->face_plane ? b->face_plane[face] : face;
        const unsigned bit = 1u << k;
        if (!(any_ahead & bit) || !(any_behind & bit)) continue;  /* A wholly on one side of the face's plane */
        /* Without a branch per triangle: which ones cross is unpredictable. */
        int num_crossing = 0;
        for (int t = 0; t < a->num_triangles; t++) {
          crossing[num_crossing] = t;
          num_crossing += (int)(((sides[t].any_ahead & ~sides[t].all_ahead) >> k) & 1u);
        }
        poly_clip_mesh_section(a, crossing, num_crossing, k, ahead, planes + 4 * k, (back >> k) & 1, start, end,
                               edge_point);
        if (!poly_clip_mesh_face(b, face, xb, out_of, crossing, num_crossing, start, end, edge_point, planes, k,
                                 (back >> k) & 1, &acc))
          return 0;
      }
    }
    if (pass == 0 && poly_clip_finish(&acc, translation, out)) {
      const double none[3] = {0.0, 0.0, 0.0};
      poly_clip_keep_corners(acc.nodes, acc.num_kept, acc.num_corners ? acc.reference : none, corners);
      return 1;
    }
  }
  poly_clip_finish_depth(&acc, out);
  if (corners) corners->count = -1;
  return 1;
}

#endif
