/* Overlap of a closed triangulated shape with the solid of an infinite cylinder wall about the z axis
 * (fix wall/polyhedral primitive zcylinder R CX CY).
 *
 * Which solid: as LIGGGHTS' zcylinder primitive, the surface holds particles from either side. A particle
 * whose centre is inside the cylinder (a drum) meets the solid r > R; one whose centre is outside meets
 * the filled cylinder r < R (a pillar); r is the distance from the axis through (CX, CY).
 *
 * The approximant. The circle is replaced by a regular polygon of N sides, fixed in space (facet k spans
 * the angles [k, k+1] 2 pi / N), each facet at the distance h = R sqrt((d/2) / tan(d/2)) from the axis,
 * d = 2 pi / N, so that every sector of the polygon has the area of the circle's sector (the volume error
 * of a particle spanning whole facets cancels to leading order). The polygon then departs from the circle
 * radially by at most s = max(R - h, h / cos(d/2) - R) ~ R d^2 / 12, the sagitta bound; N is the fewest
 * sides that keep s below the tolerance (poly_cylinder_facets). The wall solid of the approximant is the
 * union over k of sector k (between the half-planes at its two angles, which meet on the axis) intersected
 * with the solid side of facet k's plane. Every point of the particle whose classification differs from the
 * exact cylinder's lies within s of the circle, so |V - V_exact| <= s * A_cap to first order, A_cap the area
 * of the cylinder surface inside the particle (tests/test_wall_cylinder.py measures it).
 *
 * Exact for the approximant, with no cap: every face of the wall solid is vertical (parallel to z), so by
 * the divergence theorem with the fields (0, 0, z), (0, 0, x z), (0, 0, y z), (0, 0, z^2 / 2), whose flux
 * through vertical faces vanishes, the volume and first moment of (particle n solid) are integrals over the
 * particle's own surface inside the solid only: for each triangle, integrals of linear and quadratic
 * functions over its part in the solid. A vertical triangle adds nothing to them. The contact normal is the
 * direction of the summed area vectors of the particle's surface inside the solid (as for mesh walls; it is
 * minus the cap's, horizontal), the depth the deepest point's radial distance into the exact cylinder.
 *
 * How each triangle's part is found (poly_cylinder_overlap). Triangles wholly off or wholly in the solid are
 * one test each, and most are skipped before they are even turned into the world frame, by a bound on their
 * vertices' distance from the axis along the direction to the particle's centre (one dot product per
 * vertex). A triangle across the polygon's boundary is worked in projection on the xy plane
 * (poly_cylinder_fast_piece): the polygon is convex, so each edge of the projected triangle meets it in one
 * interval, whose ends lie on the facets about where the edge crosses the corner circle; the piece (projected
 * triangle n polygon, or minus it for the drum) is bounded by parts of the triangle's edges and, between
 * them, arcs of the polygon through its corners. Its area and first and second moments follow from its
 * boundary, one term per segment (Green's theorem), and the integrals over the triangle's part from those
 * and the triangle's plane z(x, y); for a nearly vertical triangle, whose plane is ill-conditioned as a
 * function of (x, y), the same boundary is lifted onto the triangle by interpolation and integrated in 3D.
 * A polygon corner inside the triangle thus costs one term. An edge's crossings are found once, by the first of
 * its two triangles met, and the other takes the same points (poly_cylinder_edge_memo).
 *
 * Before (commit 4644296), every crossing triangle was clipped (Sutherland-Hodgman) to the three half-planes
 * of each sector its part spans, a sector at a time, with sines and cosines for each sector, after angular
 * ranges from several atan2 per triangle. At the default sagitta (1e-6 of the particle's bounding radius) in
 * a drum of 10 particle diameters, N is 6000 to 8000 and a contact of 0.1-3 % of the particle's volume
 * spans 100 to 250 sector pieces: 8 to 69 us per contact on one core (tools/bench_cylinder.sh,
 * doc/benchmarks.md); now 1.0 to 10 us (an AMD EPYC core), with the same approximant and the same results to
 * rounding. That
 * computation is kept as poly_cylinder_overlap_reference, which tests/test_wall_cylinder.py compares with
 * poly_cylinder_overlap on random poses; it still does the triangles whose projection reaches the axis
 * (every sector: a particle across the axis of a drum or a pillar thinner than it). */
#ifndef POLY_CYLINDER_H
#define POLY_CYLINDER_H

#include <limits.h>

#include "poly_overlap.h"

#define POLY_CYLINDER_MIN_FACETS 8
#define POLY_CYLINDER_MAX_FACETS (1 << 22)

/* Distance from the axis of the facets of the N-gon standing in for the circle of radius R. */
POLY_INLINE double poly_cylinder_facet_distance(double radius, int facets)
{
  double half = 3.14159265358979323846 / facets;
  return radius * sqrt(half / tan(half));
}

/* The largest radial distance between the N-gon and the circle. */
POLY_INLINE double poly_cylinder_sagitta(double radius, int facets)
{
  double h = poly_cylinder_facet_distance(radius, facets);
  double inward = radius - h, outward = h / cos(3.14159265358979323846 / facets) - radius;
  return inward > outward ? inward : outward;
}

/* The fewest facets whose polygon departs from the circle by at most max_sagitta (capped). */
POLY_INLINE int poly_cylinder_facets(double radius, double max_sagitta)
{
  double step = sqrt(12.0 * max_sagitta / radius);   /* s ~ R d^2 / 12 */
  double estimate = step > 0.0 ? ceil(2.0 * 3.14159265358979323846 / step) : POLY_CYLINDER_MAX_FACETS;
  int facets = estimate < POLY_CYLINDER_MIN_FACETS ? POLY_CYLINDER_MIN_FACETS
               : estimate > POLY_CYLINDER_MAX_FACETS ? POLY_CYLINDER_MAX_FACETS : (int)estimate;
  while (facets > POLY_CYLINDER_MIN_FACETS && poly_cylinder_sagitta(radius, facets - 1) <= max_sagitta) facets--;
  while (facets < POLY_CYLINDER_MAX_FACETS && poly_cylinder_sagitta(radius, facets) > max_sagitta) facets++;
  return facets;
}

/* Keeps the part of a polygon (3D points, xy relative to the axis) where a x + b y + c > 0 (>= 0 when
 * inclusive). Returns the new corner count; out has room for count + 1 corners. */
POLY_INLINE int poly_cylinder_clip(const double (*in)[3], int count, double a, double b, double c, int inclusive,
                                   double (*out)[3])
{
  double value[10];
  for (int i = 0; i < count; i++) value[i] = a * in[i][0] + b * in[i][1] + c;
  int corners = 0;
  for (int i = 0; i < count; i++) {
    int next = (i + 1) % count;
    int keep = inclusive ? value[i] >= 0.0 : value[i] > 0.0;
    int keep_next = inclusive ? value[next] >= 0.0 : value[next] > 0.0;
    if (keep) {
      for (int k = 0; k < 3; k++) out[corners][k] = in[i][k];
      corners++;
    }
    if (keep != keep_next) {
      double w = value[i] / (value[i] - value[next]);
      for (int k = 0; k < 3; k++) out[corners][k] = in[i][k] + w * (in[next][k] - in[i][k]);
      corners++;
    }
  }
  return corners;
}

/* Squared distance in the xy plane from the axis (the origin) to the projection of triangle p (0 when it
 * surrounds or touches the axis). */
POLY_INLINE double poly_cylinder_axis_distance2(const double (*p)[3])
{
  double orientation[3], best = INFINITY;
  for (int c = 0; c < 3; c++) {
    const double *a = p[c], *b = p[(c + 1) % 3];
    orientation[c] = a[0] * b[1] - a[1] * b[0];   /* side of the origin relative to edge a->b */
    double ex = b[0] - a[0], ey = b[1] - a[1], length2 = ex * ex + ey * ey;
    double t = length2 > 0.0 ? -(a[0] * ex + a[1] * ey) / length2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double dx = a[0] + t * ex, dy = a[1] + t * ey, distance2 = dx * dx + dy * dy;
    best = distance2 < best ? distance2 : best;
  }
  if ((orientation[0] >= 0.0 && orientation[1] >= 0.0 && orientation[2] >= 0.0) ||
      (orientation[0] <= 0.0 && orientation[1] <= 0.0 && orientation[2] <= 0.0))
    return 0.0;
  return best;
}

/* Running sums over the pieces of the particle's surface inside the wall solid (relative coordinates). */
typedef struct poly_cylinder_sums {
  double volume, moment[3], area, area_vector[3];
} poly_cylinder_sums;

/* Adds the triangle (a, b, c) of the particle's surface (in its own order) to the sums. */
POLY_INLINE void poly_cylinder_add_triangle(const double a[3], const double b[3], const double c[3],
                                            poly_cylinder_sums *sums)
{
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  double projected = 0.5 * cross[2];   /* n_z dA over the piece */
  double sum_z = a[2] + b[2] + c[2];
  sums->volume += projected * sum_z / 3.0;
  for (int k = 0; k < 2; k++)
    sums->moment[k] += projected * (a[k] * a[2] + b[k] * b[2] + c[k] * c[2] + (a[k] + b[k] + c[k]) * sum_z) / 12.0;
  sums->moment[2] += projected * (a[2] * a[2] + b[2] * b[2] + c[2] * c[2] + sum_z * sum_z) / 24.0;
  for (int k = 0; k < 3; k++) sums->area_vector[k] += 0.5 * cross[k];
  sums->area += 0.5 * sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
}

/* Adds a planar polygon of the particle's surface (in its own order) to the sums. */
POLY_INLINE void poly_cylinder_add_polygon(const double (*polygon)[3], int corners, poly_cylinder_sums *sums)
{
  for (int m = 1; m + 1 < corners; m++) poly_cylinder_add_triangle(polygon[0], polygon[m], polygon[m + 1], sums);
}

/* Triangle p's piece in one sector of the polygon's solid (side +1: beyond the facet, the drum; -1: before
 * it, the pillar), added to the sums. The sector lies left of the ray `start` (unit direction, inclusive)
 * and right of the ray `end` (the next sector's start, so neighbours meet exactly); `middle` is the
 * facet's unit normal, h its distance from the axis. */
POLY_INLINE void poly_cylinder_sector_piece(const double (*p)[3], const double start[2], const double end[2],
                                            const double middle[2], double h, double side, poly_cylinder_sums *sums)
{
  double polygon_a[10][3], polygon_b[10][3];
  int corners = poly_cylinder_clip(p, 3, -start[1], start[0], 0.0, 1, polygon_a);
  if (corners < 3) return;
  corners = poly_cylinder_clip((const double (*)[3])polygon_a, corners, end[1], -end[0], 0.0, 0, polygon_b);
  if (corners < 3) return;
  corners = poly_cylinder_clip((const double (*)[3])polygon_b, corners, side * middle[0], side * middle[1], -side * h, 0,
                               polygon_a);
  poly_cylinder_add_polygon((const double (*)[3])polygon_a, corners, sums);
}

/* Triangle p's pieces in sectors first..last (any integers; taken modulo the facet count). */
POLY_INLINE void poly_cylinder_sector_pieces(const double (*p)[3], int first, int last, int facets, double h,
                                             double side, poly_cylinder_sums *sums)
{
  const double step = 2.0 * 3.14159265358979323846 / facets, to_middle = 0.5 / cos(0.5 * step);
  int sector = ((first % facets) + facets) % facets;
  double start[2] = {cos(sector * step), sin(sector * step)}, end[2], middle[2];
  for (int s = first; s <= last; s++) {
    int next = (sector + 1) % facets;
    end[0] = cos(next * step);
    end[1] = sin(next * step);
    middle[0] = (start[0] + end[0]) * to_middle;
    middle[1] = (start[1] + end[1]) * to_middle;
    poly_cylinder_sector_piece(p, start, end, middle, h, side, sums);
    start[0] = end[0];
    start[1] = end[1];
    sector = next;
  }
}

/* The angular ranges (radians, unwrapped about vertex 0's angle) of the parts of the projection of triangle
 * p beyond the circle of radius `limit` (beyond = 1: r > limit, else r < limit), which must not surround
 * the axis. The angle is monotone along segments and arcs, so a part's range is that of its corners:
 * its vertices and the crossings of the triangle's edges with the circle, taken in runs along the
 * triangle's boundary (one run per part of the triangle outside a disk; inside one, the part is convex and
 * the runs are merged into one range). Returns the number of ranges (0..3). */
POLY_INLINE int poly_cylinder_triangle_ranges(const double (*p)[3], double limit, int beyond, double ranges[3][2])
{
  double point[9][2];
  int count = 0;
  for (int c = 0; c < 3; c++) {
    const double *a = p[c], *b = p[(c + 1) % 3];
    point[count][0] = a[0];
    point[count][1] = a[1];
    count++;
    double ex = b[0] - a[0], ey = b[1] - a[1];
    double qa = ex * ex + ey * ey, qb = 2.0 * (a[0] * ex + a[1] * ey), qc = a[0] * a[0] + a[1] * a[1] - limit * limit;
    double disc = qb * qb - 4.0 * qa * qc;
    if (!(qa > 0.0) || !(disc > 0.0)) continue;
    double root = sqrt(disc), t1 = (-qb - root) / (2.0 * qa), t2 = (-qb + root) / (2.0 * qa);
    for (int k = 0; k < 2; k++) {
      double t = k == 0 ? t1 : t2;
      if (t > 0.0 && t < 1.0) {
        point[count][0] = a[0] + t * ex;
        point[count][1] = a[1] + t * ey;
        count++;
      }
    }
  }
  const double two_pi = 2.0 * 3.14159265358979323846, angle0 = atan2(p[0][1], p[0][0]);
  /* Each piece of the boundary between consecutive points is wholly on one side: test its midpoint. */
  int wall[9], first_off = -1;
  for (int i = 0; i < count; i++) {
    const double *a = point[i], *b = point[(i + 1) % count];
    double mx = 0.5 * (a[0] + b[0]), my = 0.5 * (a[1] + b[1]), r2 = mx * mx + my * my;
    wall[i] = beyond ? r2 > limit * limit : r2 < limit * limit;
    if (!wall[i] && first_off < 0) first_off = i;
  }
  int runs = 0;
  if (first_off < 0) {   /* the whole boundary on the wall side: one part, all the points */
    ranges[0][0] = ranges[0][1] = angle0;
    for (int i = 1; i < count; i++) {
      double angle = angle0 + remainder(atan2(point[i][1], point[i][0]) - angle0, two_pi);
      ranges[0][0] = angle < ranges[0][0] ? angle : ranges[0][0];
      ranges[0][1] = angle > ranges[0][1] ? angle : ranges[0][1];
    }
    return 1;
  }
  /* From just after an off piece once around: piece i runs from point i to point i + 1. */
  int open = 0;
  for (int n = 1; n <= count; n++) {
    int i = (first_off + n) % count;
    if (!wall[i]) {
      open = 0;
      continue;
    }
    if (!open) {
      ranges[runs][0] = ranges[runs][1] = angle0 + remainder(atan2(point[i][1], point[i][0]) - angle0, two_pi);
      runs++;
      open = 1;
    }
    const double *b = point[(i + 1) % count];
    double angle = angle0 + remainder(atan2(b[1], b[0]) - angle0, two_pi);
    double *range = ranges[runs - 1];
    range[0] = angle < range[0] ? angle : range[0];
    range[1] = angle > range[1] ? angle : range[1];
  }
  if (!beyond && runs > 1) {
    for (int r = 1; r < runs; r++) {
      ranges[0][0] = ranges[r][0] < ranges[0][0] ? ranges[r][0] : ranges[0][0];
      ranges[0][1] = ranges[r][1] > ranges[0][1] ? ranges[r][1] : ranges[0][1];
    }
    runs = 1;
  }
  return runs;
}

/* Sorted, merged intervals of sector numbers (any integers, modulo the facet count later) covering the
 * angular ranges, with one spare sector each side for rounding at sector borders. Returns their count. */
POLY_INLINE int poly_cylinder_sector_intervals(const double ranges[3][2], int count, double step, int intervals[3][2])
{
  for (int r = 0; r < count; r++) {
    intervals[r][0] = (int)floor(ranges[r][0] / step) - 1;
    intervals[r][1] = (int)floor(ranges[r][1] / step) + 1;
  }
  for (int r = 0; r < count; r++)
    for (int q = r + 1; q < count; q++)
      if (intervals[q][0] < intervals[r][0]) {
        int first = intervals[q][0], last = intervals[q][1];
        intervals[q][0] = intervals[r][0], intervals[q][1] = intervals[r][1];
        intervals[r][0] = first, intervals[r][1] = last;
      }
  int merged = 0;
  for (int r = 0; r < count; r++) {
    if (merged > 0 && intervals[r][0] <= intervals[merged - 1][1] + 1) {
      if (intervals[r][1] > intervals[merged - 1][1]) intervals[merged - 1][1] = intervals[r][1];
    } else {
      intervals[merged][0] = intervals[r][0];
      intervals[merged][1] = intervals[r][1];
      merged++;
    }
  }
  return merged;
}

/* Triangle p's piece in sectors first..last (fewer than half the facets), where it is wholly in the solid:
 * clipped to the block's two rays only. */
POLY_INLINE void poly_cylinder_block_piece(const double (*p)[3], int first, int last, int facets,
                                           poly_cylinder_sums *sums)
{
  const double step = 2.0 * 3.14159265358979323846 / facets;
  int start = ((first % facets) + facets) % facets, end = (((last + 1) % facets) + facets) % facets;
  double polygon_a[10][3], polygon_b[10][3];
  int corners = poly_cylinder_clip(p, 3, -sin(start * step), cos(start * step), 0.0, 1, polygon_a);
  if (corners < 3) return;
  corners = poly_cylinder_clip((const double (*)[3])polygon_a, corners, sin(end * step), -cos(end * step), 0.0, 0,
                               polygon_b);
  poly_cylinder_add_polygon((const double (*)[3])polygon_b, corners, sums);
}

/* Triangle p (crossing the polygon's boundary, its projection clear of the axis) clipped sector by sector in
 * the sectors its part in the solid spans: those beyond the inscribed circle (drum), or within the corner
 * circle (pillar). Where the triangle is wholly in the solid (its parts within the corner circle, or beyond the
 * inscribed one, span other sectors) whole blocks of sectors are one piece. */
POLY_INLINE void poly_cylinder_crossing_pieces(const double (*p)[3], int facets, double h, int drum,
                                               poly_cylinder_sums *sums)
{
  const double step = 2.0 * 3.14159265358979323846 / facets, corner_radius = h / cos(0.5 * step);
  double ranges[3][2];
  int spans[3][2], partial[3][2];
  int span_count = poly_cylinder_triangle_ranges(p, drum ? h : corner_radius, drum, ranges);
  span_count = poly_cylinder_sector_intervals(ranges, span_count, step, spans);
  int partial_count = poly_cylinder_triangle_ranges(p, drum ? corner_radius : h, !drum, ranges);
  partial_count = poly_cylinder_sector_intervals(ranges, partial_count, step, partial);
  for (int r = 0; r < span_count; r++) {
    int block = INT_MIN;   /* first sector of the open block */
    for (int s = spans[r][0]; s <= spans[r][1]; s++) {
      int whole = 1;
      for (int q = 0; q < partial_count; q++) whole = whole && !(s >= partial[q][0] && s <= partial[q][1]);
      if (whole && block == INT_MIN) block = s;
      if (block != INT_MIN && (!whole || s == spans[r][1] || s - block + 1 >= facets / 8)) {
        int last = whole ? s : s - 1;
        if (last >= block) poly_cylinder_block_piece(p, block, last, facets, sums);
        block = INT_MIN;
      }
      if (!whole) poly_cylinder_sector_pieces(p, s, s, facets, h, drum ? 1.0 : -1.0, sums);
    }
  }
}

/* The directions of the polygon's corners and facet normals a call has needed, by half steps of angle
 * (2 k: corner k; 2 k + 1: facet k's normal), in a few slots by the index's low bits: a crossing edge is met
 * by both its triangles, and an arc's end by the next triangle, so most are needed again; the same cos and sin
 * either way. */
#define POLY_CYLINDER_MEMO 64
/* Turns by 0 .. POLY_CYLINDER_TURNS steps, for an arc's corners: each corner is its block's first turned by
 * one of them, so the corners do not wait on each other as they did when each was the last turned by a step. */
#define POLY_CYLINDER_TURNS 64
/* The polygon of one call: its facet count, angle step, facet distance h, corner radius h / cos(step / 2),
 * and cos and sin of the step (facet normals are stepped through by rotation), and of 0 .. turns - 1 steps
 * (as far as the call's arcs have needed them). */
typedef struct poly_cylinder_polygon {
  int facets;
  double step, h, corner_radius, cos_step, sin_step, cos_half_step, sin_half_step;
  int memo_index[POLY_CYLINDER_MEMO];
  double memo_cos[POLY_CYLINDER_MEMO], memo_sin[POLY_CYLINDER_MEMO];
  int turns;
  double turn_cos[POLY_CYLINDER_TURNS + 1], turn_sin[POLY_CYLINDER_TURNS + 1];
} poly_cylinder_polygon;

POLY_INLINE poly_cylinder_polygon poly_cylinder_polygon_of(double radius, int facets)
{
  poly_cylinder_polygon g;
  g.facets = facets;
  g.step = 2.0 * 3.14159265358979323846 / facets;
  g.h = poly_cylinder_facet_distance(radius, facets);
  g.corner_radius = g.h / cos(0.5 * g.step);
  g.cos_step = cos(g.step);
  g.sin_step = sin(g.step);
  g.cos_half_step = cos(0.5 * g.step);
  g.sin_half_step = sin(0.5 * g.step);
  for (int i = 0; i < POLY_CYLINDER_MEMO; i++) g.memo_index[i] = INT_MIN;
  g.turns = 1;
  g.turn_cos[0] = 1.0, g.turn_sin[0] = 0.0;
  return g;
}

/* Makes g's turns reach `count` steps (at most POLY_CYLINDER_TURNS + 1 of them), each the one before turned by a
 * step and renormalised, as the arcs' corners used to be stepped. */
POLY_INLINE void poly_cylinder_turns(poly_cylinder_polygon *g, int count)
{
  count = count > POLY_CYLINDER_TURNS + 1 ? POLY_CYLINDER_TURNS + 1 : count;
  for (int q = g->turns; q < count; q++) {
    double c = g->turn_cos[q - 1] * g->cos_step - g->turn_sin[q - 1] * g->sin_step;
    double s = g->turn_sin[q - 1] * g->cos_step + g->turn_cos[q - 1] * g->sin_step;
    double renorm = 1.5 - 0.5 * (c * c + s * s);
    g->turn_cos[q] = c * renorm, g->turn_sin[q] = s * renorm;
  }
  if (count > g->turns) g->turns = count;
}

/* cos and sin of `angle`, the direction of half-step index `index` (see poly_cylinder_polygon), as computed for
 * it before if it is still in its slot. */
POLY_INLINE void poly_cylinder_direction(poly_cylinder_polygon *g, int index, double angle, double *c, double *s)
{
  const int slot = index & (POLY_CYLINDER_MEMO - 1);
  if (g->memo_index[slot] != index) {
    g->memo_index[slot] = index;
    g->memo_cos[slot] = cos(angle);
    g->memo_sin[slot] = sin(angle);
  }
  *c = g->memo_cos[slot];
  *s = g->memo_sin[slot];
}

/* The facet (0..N-1) whose sector holds the point (x, y) (relative to the axis). */
POLY_INLINE int poly_cylinder_sector_of(const poly_cylinder_polygon *g, double x, double y)
{
  /* atan2 is within [-pi, pi]: one facet count added or taken back is the remainder's. */
  int facet = (int)floor(atan2(y, x) / g->step);
  facet += facet < 0 ? g->facets : 0;
  return facet >= g->facets ? facet - g->facets : facet;
}

/* Whether the point (x, y) is inside the polygon (its facets' side towards the axis, boundary included). */
POLY_INLINE int poly_cylinder_in_polygon(poly_cylinder_polygon *g, double x, double y)
{
  double r2 = x * x + y * y;
  if (r2 <= g->h * g->h) return 1; /* the inscribed disk */
  if (r2 >= g->corner_radius * g->corner_radius) return 0;
  const int facet = poly_cylinder_sector_of(g, x, y);
  double nx, ny;
  poly_cylinder_direction(g, 2 * facet + 1, (facet + 0.5) * g->step, &nx, &ny);
  return nx * x + ny * y <= g->h;
}

/* Turns below this (radians) take cos and sin from their series (to the 7th power: below 1e-21 there). */
#define POLY_CYLINDER_SERIES_TURN 1e-2

/* Where the line a + t d (relative to the axis) crosses the polygon's boundary inwards (enter = 1: the
 * largest entry parameter over the facets) or outwards (the smallest exit parameter), t0 being where it
 * crosses the corner circle on that side. Between the two crossings the line runs outside the polygon and
 * inside the corner circle, an annulus in which a segment spans at most one step of angle, so the facet
 * sought is within one of t0's sector; the five about it are tried (one more each side for rounding). The
 * first one's normal is the direction of the point at t0 turned by the small angle between them (series),
 * rather than the cosine and sine of the facet's angle (libm, for polygons of few facets). Returns the
 * parameter; *facet gets its facet (0..N-1) and, unless NULL, normal its unit normal. */
POLY_INLINE double poly_cylinder_line_crossing(poly_cylinder_polygon *g, const double a[2], const double d[2],
                                               double t0, int enter, int *facet, double *normal)
{
  const double x = a[0] + t0 * d[0], y = a[1] + t0 * d[1], angle = atan2(y, x);
  const int first = (int)floor(angle / g->step) - 2; /* unwrapped: the facet numbers are taken modulo N below */
  const double turn = (first + 0.5) * g->step - angle;
  double nx, ny;
  if (fabs(turn) < POLY_CYLINDER_SERIES_TURN) {
    const double r = sqrt(x * x + y * y), ux = x / r, uy = y / r, t2 = turn * turn;
    const double c = 1.0 - 0.5 * t2 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0));
    const double s = turn * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0)));
    nx = ux * c - uy * s, ny = uy * c + ux * s;
  } else {
    poly_cylinder_direction(g, 2 * first + 1, (first + 0.5) * g->step, &nx, &ny);
  }
  double best = t0, best_nx = 0.0, best_ny = 0.0;
  int best_facet = first + 2, found = 0;
  for (int m = 0; m < 5; m++) {
    double along = nx * d[0] + ny * d[1];
    if (enter ? along < 0.0 : along > 0.0) {
      double t = (g->h - nx * a[0] - ny * a[1]) / along;
      if (!found || (enter ? t > best : t < best)) best = t, best_facet = first + m, found = 1, best_nx = nx, best_ny = ny;
    }
    if (!found && m == 2) best_nx = nx, best_ny = ny;
    double rotated = nx * g->cos_step - ny * g->sin_step;
    ny = ny * g->cos_step + nx * g->sin_step;
    nx = rotated;
  }
  best_facet %= g->facets;
  *facet = best_facet < 0 ? best_facet + g->facets : best_facet;
  if (normal) normal[0] = best_nx, normal[1] = best_ny;
  return best;
}

/* Where the segment a -> a + d (relative to the axis) crosses the polygon's boundary, given whether its ends
 * are inside (poly_cylinder_in_polygon). The ends decide how many crossings there are (inside to outside: one
 * exit; outside to inside: one entry; outside to outside: none, or an entry and an exit), so that along a
 * closed path entries and exits alternate whatever the rounding; only where the segment passes outside to
 * outside do the parameters decide whether it enters. Returns the count (0..2); t (in [0, 1]), facet and
 * enter (1: into the polygon) of each, in order along the segment. */
POLY_INLINE int poly_cylinder_edge_crossings(poly_cylinder_polygon *g, const double a[2], const double d[2],
                                             int inside_a, int inside_b, double t[2], int facet[2], int enter[2],
                                             double (*normal)[2])
{
  if (inside_a && inside_b) return 0;
  double qa = d[0] * d[0] + d[1] * d[1], qb = a[0] * d[0] + a[1] * d[1];
  double qc = a[0] * a[0] + a[1] * a[1] - g->corner_radius * g->corner_radius, disc = qb * qb - qa * qc;
  if (!(qa > 0.0)) return 0; /* a point in projection: both ends alike */
  if (!(disc > 0.0)) {
    if (inside_a == inside_b) return 0; /* clear of the corner circle */
    disc = 0.0;
  }
  double root = sqrt(disc), t1 = (-qb - root) / qa, t2 = (-qb + root) / qa;
  if (!inside_a && !inside_b && (t2 <= 0.0 || t1 >= 1.0)) return 0;
  double t_in = 0.0, t_out = 1.0;
  int facet_in = 0, facet_out = 0, count = 0;
  double normal_in[2] = {0.0, 0.0}, normal_out[2] = {0.0, 0.0};
  if (!inside_a) t_in = poly_cylinder_line_crossing(g, a, d, t1, 1, &facet_in, normal_in);
  if (!inside_b) t_out = poly_cylinder_line_crossing(g, a, d, t2, 0, &facet_out, normal_out);
  t_in = t_in < 0.0 ? 0.0 : t_in > 1.0 ? 1.0 : t_in;
  t_out = t_out < 0.0 ? 0.0 : t_out > 1.0 ? 1.0 : t_out;
  if (!inside_a && !inside_b && !(t_in < t_out)) return 0; /* through the annulus only */
  if (normal) { /* in the crossings' order */
    const double *first_normal = !inside_a ? normal_in : normal_out;
    normal[0][0] = first_normal[0], normal[0][1] = first_normal[1];
    normal[1][0] = normal_out[0], normal[1][1] = normal_out[1];
  }
  if (!inside_a) t[count] = t_in, facet[count] = facet_in, enter[count++] = 1;
  if (!inside_b) t[count] = t_out, facet[count] = facet_out, enter[count++] = 0;
  return count;
}

/* Twice, six, twelve and twenty-four times the signed area and first and second moments (about the origin)
 * of triangles (origin, u, w) summed over directed segments u -> w: over a closed boundary, those of the
 * region it encloses (Green's theorem), counted positive when the boundary runs counter-clockwise. */
typedef struct poly_cylinder_moments {
  double m0, mx, my, mxx, mxy, myy;
} poly_cylinder_moments;

POLY_INLINE void poly_cylinder_moments_add(poly_cylinder_moments *m, double ux, double uy, double wx, double wy)
{
  double a = ux * wy - uy * wx;
  m->m0 += a;
  m->mx += a * (ux + wx);
  m->my += a * (uy + wy);
  m->mxx += a * (ux * ux + ux * wx + wx * wx);
  m->myy += a * (uy * uy + uy * wy + wy * wy);
  m->mxy += a * (2.0 * (ux * uy + wx * wy) + ux * wy + wx * uy);
}

/* Where a triangle's boundary crosses the polygon's (its projection's). */
typedef struct poly_cylinder_crossing {
  double x[3];      /* relative to the axis (z: to the particle's centre) */
  double normal[2]; /* the facet's unit normal */
  int edge, facet, enter;
} poly_cylinder_crossing;

/* The crossings of a call's edges of the shape, in a few slots by their vertices: a crossing edge is met by
 * both its triangles, the second takes the first's crossings (found along the edge from its lower-numbered
 * vertex to the other), so the two pieces meet at the same points and each edge's crossings are found once. */
#define POLY_CYLINDER_EDGE_MEMO 64
typedef struct poly_cylinder_edge_memo {
  int low[POLY_CYLINDER_EDGE_MEMO], high[POLY_CYLINDER_EDGE_MEMO]; /* the edge's vertices; low -1: empty */
  int count[POLY_CYLINDER_EDGE_MEMO];
  double x[POLY_CYLINDER_EDGE_MEMO][2][3], normal[POLY_CYLINDER_EDGE_MEMO][2][2];
  int facet[POLY_CYLINDER_EDGE_MEMO][2], enter[POLY_CYLINDER_EDGE_MEMO][2];
} poly_cylinder_edge_memo;

/* Empties the memo: a call's first step. */
POLY_INLINE void poly_cylinder_edge_memo_clear(poly_cylinder_edge_memo *memo)
{
  for (int i = 0; i < POLY_CYLINDER_EDGE_MEMO; i++) memo->low[i] = -1;
}

/* Triangles nearer vertical than this (|n_z| of the unit normal below it) have their pieces integrated in 3D
 * (poly_cylinder_fast_piece): in projection the integrals divide by n_z, which magnifies the rounding by up
 * to 1 / POLY_CYLINDER_MIN_TILT. */
#define POLY_CYLINDER_MIN_TILT 1e-2

/* The point of triangle p's plane above rho dir (dir a unit vector, the point inside the triangle's
 * projection), found as the clipping finds points: on the triangle's chord in the vertical plane through the
 * axis along dir (interpolated along two edges), interpolated by the distance from the axis. So it is
 * well defined however steep the triangle; at a point just off the projection (rounding) it is the nearest
 * end of that chord, or the nearest vertex. */
POLY_INLINE void poly_cylinder_lift(const double (*p)[3], const double dir[2], double rho, double out[3])
{
  double side[3], end[2][3];
  int ends = 0, nearest = 0;
  for (int i = 0; i < 3; i++) {
    side[i] = dir[0] * p[i][1] - dir[1] * p[i][0];
    nearest = fabs(side[i]) < fabs(side[nearest]) ? i : nearest;
  }
  for (int i = 0; i < 3 && ends < 2; i++) {
    int j = (i + 1) % 3;
    if ((side[i] <= 0.0) == (side[j] <= 0.0)) continue;
    double w = side[i] / (side[i] - side[j]);
    for (int k = 0; k < 3; k++) end[ends][k] = p[i][k] + w * (p[j][k] - p[i][k]);
    ends++;
  }
  if (ends < 2) {
    for (int k = 0; k < 3; k++) out[k] = p[nearest][k];
    return;
  }
  double r0 = dir[0] * end[0][0] + dir[1] * end[0][1], r1 = dir[0] * end[1][0] + dir[1] * end[1][1];
  double t = r1 != r0 ? (rho - r0) / (r1 - r0) : 0.5;
  t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  for (int k = 0; k < 3; k++) out[k] = end[0][k] + t * (end[1][k] - end[0][k]);
}

/* The fast path: triangle p's part in the polygon's solid (drum: outside the polygon; else inside it),
 * added to the sums, as poly_cylinder_sector_pieces over all sectors would add it. For triangles whose
 * projection is clear of the axis (so that each arc spans less than half a turn). The polygon is convex,
 * so along each edge of the triangle's projection the part inside it is one interval; its ends are found on
 * the facets about where the edge crosses the corner circle. The boundary of (projection n polygon) runs along
 * the triangle's edges inside the polygon and, from each point where the triangle's boundary leaves the
 * polygon to the next one where it enters, along the polygon's boundary (the way the triangle is wound,
 * through the corners in between); that of (projection \ polygon) runs along the edges outside and back along
 * the same arcs. The piece's integrals are sums of one term per segment of that boundary (Green's theorem):
 * area and first and second moments of its projection about a crossing point (poly_cylinder_moments_add; the
 * terms stay of the piece's size), combined with the triangle's plane z(x, y); or, for a nearly vertical
 * triangle, the integrals over the triangles (crossing point, segment) on the triangle's plane, the polygon's
 * corners lifted onto it (poly_cylinder_lift). A vertical triangle's arcs are the vertical segments where it
 * meets the facets' planes. Each corner of the polygon inside the triangle costs one term, with no clipping. */
POLY_INLINE void poly_cylinder_fast_piece(const double (*p)[3], const int *corners_of, poly_cylinder_edge_memo *memo,
                                          poly_cylinder_polygon *g, int drum, poly_cylinder_sums *sums)
{
  double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  double norm2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  const int steep = !(c[2] * c[2] > POLY_CYLINDER_MIN_TILT * POLY_CYLINDER_MIN_TILT * norm2);
  int inside[3];
  for (int i = 0; i < 3; i++) inside[i] = poly_cylinder_in_polygon(g, p[i][0], p[i][1]);

  /* The crossings in order along the triangle's boundary. */
  poly_cylinder_crossing crossing[6];
  int count = 0;
  for (int i = 0; i < 3; i++) {
    int next = (i + 1) % 3;
    /* Along the edge from its lower-numbered vertex, or as its other triangle found it. */
    const int reversed = corners_of[next] < corners_of[i], from = reversed ? next : i, to = reversed ? i : next;
    const int low = corners_of[from], high = corners_of[to];
    const int slot = (int)(((unsigned)low * 40503u + (unsigned)high) & (POLY_CYLINDER_EDGE_MEMO - 1));
    if (memo->low[slot] != low || memo->high[slot] != high) {
      const double a[2] = {p[from][0], p[from][1]}, d[2] = {p[to][0] - p[from][0], p[to][1] - p[from][1]};
      double t[2];
      int *facet = memo->facet[slot], *enter = memo->enter[slot];
      int n = poly_cylinder_edge_crossings(g, a, d, inside[from], inside[to], t, facet, enter, memo->normal[slot]);
      for (int k = 0; k < n; k++) {
        memo->x[slot][k][0] = a[0] + t[k] * d[0];
        memo->x[slot][k][1] = a[1] + t[k] * d[1];
        memo->x[slot][k][2] = p[from][2] + t[k] * (p[to][2] - p[from][2]);
      }
      memo->low[slot] = low, memo->high[slot] = high, memo->count[slot] = n;
    }
    const int n = memo->count[slot];
    for (int k = 0; k < n; k++, count++) {
      const int j = reversed ? n - 1 - k : k;
      for (int axis = 0; axis < 3; axis++) crossing[count].x[axis] = memo->x[slot][j][axis];
      crossing[count].normal[0] = memo->normal[slot][j][0], crossing[count].normal[1] = memo->normal[slot][j][1];
      crossing[count].edge = i;
      crossing[count].facet = memo->facet[slot][j];
      crossing[count].enter = reversed ? !memo->enter[slot][j] : memo->enter[slot][j];
    }
  }
  if (count == 0) { /* wholly on one side */
    if (inside[0] != drum) poly_cylinder_add_polygon(p, 3, sums);
    return;
  }

  /* The boundary's terms about the first crossing o: first the parts of the edges on the solid's side (inside
   * the polygon for the pillar, outside it for the drum), then the arcs, from each exit to the next entry,
   * the way the triangle is wound, subtracted for the drum (its piece runs back along them). The corners are
   * stepped through by rotation, renormalised so that their distance from the axis does not drift. */
  const double *o = crossing[0].x;
  poly_cylinder_moments m = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, arcs = m;
  poly_cylinder_sums piece = {0.0, {0.0, 0.0, 0.0}, 0.0, {0.0, 0.0, 0.0}}, piece_arcs = piece;
  int k = 0;
  for (int i = 0; i < 3; i++) {
    int state = inside[i];
    const double *u = p[i];
    for (; k <= count; k++) {
      const double *w = k < count && crossing[k].edge == i ? crossing[k].x : p[(i + 1) % 3];
      if (state != drum && steep) poly_cylinder_add_triangle(o, u, w, &piece);
      if (state != drum && !steep) poly_cylinder_moments_add(&m, u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
      if (w == p[(i + 1) % 3]) break;
      u = w, state = crossing[k].enter;
    }
  }
  const int facets = g->facets, forward = c[2] > 0.0; /* counter-clockwise in projection */
  for (k = 0; k < count; k++) {
    if (crossing[k].enter) continue;
    const poly_cylinder_crossing *out = &crossing[k], *in = &crossing[(k + 1) % count];
    int corners = ((forward ? in->facet - out->facet : out->facet - in->facet) % facets + facets) % facets;
    /* An arc within a projection clear of the axis spans less than half a turn, at most facets / 2 + 1
     * corners; a count near `facets` is both ends at one corner, each rounded to another side of it. */
    if (corners > facets / 2 + 1) corners = 0;
    const double way = forward ? 1.0 : -1.0;
    double u[3] = {out->x[0], out->x[1], out->x[2]};
    /* The first corner: the exit's facet normal turned by half a step, forward or back. */
    const double half_sin = way * g->sin_half_step;
    double base[2] = {out->normal[0] * g->cos_half_step - out->normal[1] * half_sin,
                      out->normal[1] * g->cos_half_step + out->normal[0] * half_sin};
    poly_cylinder_turns(g, corners + 1);
    for (int q = 0, j = 0; q < corners; q++, j++) {
      if (j == POLY_CYLINDER_TURNS) { /* the next block's first corner */
        double turn_c = g->turn_cos[j], turn_s = way * g->turn_sin[j];
        double rotated = base[0] * turn_c - base[1] * turn_s;
        base[1] = base[1] * turn_c + base[0] * turn_s;
        base[0] = rotated;
        double renorm = 1.5 - 0.5 * (base[0] * base[0] + base[1] * base[1]);
        base[0] *= renorm, base[1] *= renorm;
        j = 0;
      }
      const double turn_c = g->turn_cos[j], turn_s = way * g->turn_sin[j];
      const double dir[2] = {base[0] * turn_c - base[1] * turn_s, base[1] * turn_c + base[0] * turn_s};
      if (steep) {
        double w[3];
        poly_cylinder_lift(p, dir, g->corner_radius, w);
        poly_cylinder_add_triangle(o, u, w, &piece_arcs);
        for (int n = 0; n < 3; n++) u[n] = w[n];
      } else {
        double wx = g->corner_radius * dir[0], wy = g->corner_radius * dir[1];
        poly_cylinder_moments_add(&arcs, u[0] - o[0], u[1] - o[1], wx - o[0], wy - o[1]);
        u[0] = wx, u[1] = wy;
      }
    }
    if (steep) poly_cylinder_add_triangle(o, u, in->x, &piece_arcs);
    else poly_cylinder_moments_add(&arcs, u[0] - o[0], u[1] - o[1], in->x[0] - o[0], in->x[1] - o[1]);
  }
  const double sign = drum ? -1.0 : 1.0;
  if (steep) { /* the piece's area: the length of its area vector (it is planar) */
    sums->volume += piece.volume + sign * piece_arcs.volume;
    for (int n = 0; n < 3; n++) {
      sums->moment[n] += piece.moment[n] + sign * piece_arcs.moment[n];
      piece.area_vector[n] += sign * piece_arcs.area_vector[n];
      sums->area_vector[n] += piece.area_vector[n];
    }
    const double *v = piece.area_vector;
    sums->area += sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return;
  }
  m.m0 += sign * arcs.m0, m.mx += sign * arcs.mx, m.my += sign * arcs.my;
  m.mxx += sign * arcs.mxx, m.mxy += sign * arcs.mxy, m.myy += sign * arcs.myy;

  /* z = oz + beta X + gamma Y on the triangle's plane (X, Y about o). */
  const double ox = o[0], oy = o[1], oz = o[2];
  const double area = m.m0 / 2.0, mx = m.mx / 6.0, my = m.my / 6.0;
  const double mxx = m.mxx / 12.0, myy = m.myy / 12.0, mxy = m.mxy / 24.0;
  const double beta = -c[0] / c[2], gamma = -c[1] / c[2], slope = beta * mx + gamma * my;
  const double volume = oz * area + slope;
  sums->volume += volume;
  sums->moment[0] += ox * volume + oz * mx + beta * mxx + gamma * mxy;
  sums->moment[1] += oy * volume + oz * my + beta * mxy + gamma * myy;
  sums->moment[2] += 0.5 * (oz * oz * area + 2.0 * oz * slope + beta * beta * mxx + 2.0 * beta * gamma * mxy +
                            gamma * gamma * myy);
  const double scale = area / c[2]; /* the piece's area vector: the triangle's, c / 2, times area / (c_z / 2) */
  for (int n = 0; n < 3; n++) sums->area_vector[n] += c[n] * scale;
  sums->area += sqrt(norm2) * fabs(scale);
}

/* Triangle p's part in the polygon's solid (world frame, relative to the axis and the particle's centre's z;
 * corners_of: its vertices' numbers in the shape, for the call's edge memo `memo`),
 * added to the sums: nothing for a triangle wholly off the solid (inside the inscribed circle for the drum,
 * beyond the corner circle for the pillar), the whole triangle when wholly in it, else its pieces: every
 * sector where its projection reaches the axis, the fast path (fast = 1) or the sector-by-sector clipping.
 * Returns the squared distance of its projection from the axis (the pillar's depth), or INFINITY for a drum
 * triangle within the inscribed circle. */
POLY_INLINE double poly_cylinder_triangle(const double (*p)[3], const int *corners_of, poly_cylinder_edge_memo *memo,
                                          poly_cylinder_polygon *g, int drum, int fast, poly_cylinder_sums *sums)
{
  const double h2 = g->h * g->h, corner2 = g->corner_radius * g->corner_radius;
  int within = 1; /* the inscribed circle */
  for (int c = 0; c < 3; c++) within = within && p[c][0] * p[c][0] + p[c][1] * p[c][1] < h2;
  if (drum && within) return INFINITY;
  double distance2 = poly_cylinder_axis_distance2(p);
  if (!drum && distance2 >= corner2) return distance2;
  if (drum ? distance2 >= corner2 : within) poly_cylinder_add_polygon(p, 3, sums);
  else if (!(distance2 > 0.0)) poly_cylinder_sector_pieces(p, 0, g->facets - 1, g->facets, g->h, drum ? 1.0 : -1.0, sums);
  else if (fast) poly_cylinder_fast_piece(p, corners_of, memo, g, drum, sums);
  else poly_cylinder_crossing_pieces(p, g->facets, g->h, drum, sums);
  return distance2;
}

/* Whether a body-frame vertex may reach the polygon's solid: its distance along `toward` (the horizontal
 * direction from the axis to the particle's centre, turned into the body frame) between the bounds of
 * poly_cylinder_overlap. */
POLY_INLINE int poly_cylinder_may_reach(const double toward[3], const double v[3], double above, double below)
{
  double s = toward[0] * v[0] + toward[1] * v[1] + toward[2] * v[2];
  return s > above && s < below;
}

/* Shapes of up to this many vertices have them marked once per call (a byte each, on the stack); larger
 * ones test the bound per triangle. */
#define POLY_CYLINDER_NEAR_VERTICES 4096

/* The overlap (poly_cylinder_overlap) computed the fast way (fast = 1) or the straightforward way (fast = 0:
 * no triangle skipped by the cheap bound, every crossing triangle clipped sector by sector, as before the
 * fast path; the tests compare the two). */
POLY_INLINE void poly_cylinder_overlap_with(const poly_shape_view_d *shape, const double rotation[9],
                                            const double position[3], const double axis[2], double radius,
                                            int facets, int fast, poly_overlap_result *result)
{
  result->volume = result->depth = result->area = result->projected_area = result->gap = 0.0;
  for (int k = 0; k < 3; k++) result->centroid[k] = result->normal[k] = 0.0;
  result->num_nodes = result->num_inconsistent = result->filtered_out = result->recomputed = result->smoothed = 0;
  for (int e = 0; e < 6; e++) result->second_moment[e] = 0.0; /* not computed: no rocking damping on cylinders */

  /* Coordinates relative to (CX, CY, z of the particle's centre). */
  const double offset[3] = {position[0] - axis[0], position[1] - axis[1], 0.0};
  double centre_distance = sqrt(offset[0] * offset[0] + offset[1] * offset[1]);
  const int drum = centre_distance < radius;   /* wall solid r > R; else the filled cylinder r < R */
  double reach = shape->bounding_radius;
  if ((drum && centre_distance + reach <= radius) || (!drum && centre_distance - reach >= radius)) {
    result->filtered_out = 1;
    return;
  }
  poly_cylinder_polygon g = poly_cylinder_polygon_of(radius, facets);
  const double h = g.h, corner_radius = g.corner_radius;

  /* The cheap bound: a body-frame point v at s = u . (rotation v) along the horizontal unit u from the axis
   * to the centre is at r >= centre_distance + s from the axis, and at r^2 <= centre_distance^2 +
   * 2 centre_distance s + reach^2. So nothing with s <= (h^2 - centre_distance^2 - reach^2) /
   * (2 centre_distance) reaches beyond the inscribed circle (the drum's solid), nothing with s >=
   * corner_radius - centre_distance inside the corner circle (the pillar's), nor, R being between the two,
   * into the exact cylinder's solid. Triangles whose three corners are there are skipped without turning
   * them, and so are such vertices when counting those in the solid. The margins cover rounding. With the
   * centre on the axis there is no bound: nothing is skipped. */
  const int cull = fast && centre_distance > 0.0;
  double toward[3] = {0.0, 0.0, 0.0};
  if (cull)
    for (int k = 0; k < 3; k++) toward[k] = (rotation[k] * offset[0] + rotation[3 + k] * offset[1]) / centre_distance;
  const double margin = 1e-12 * (centre_distance + reach), reach2 = reach * reach * (1.0 + 1e-12);
  const double above = cull && drum ? ((h - centre_distance) * (h + centre_distance) - reach2) /
                                          (2.0 * centre_distance) - margin
                                    : -INFINITY;
  const double below = cull && !drum ? corner_radius - centre_distance + margin : INFINITY;
  unsigned char near[POLY_CYLINDER_NEAR_VERTICES];
  const int masked = cull && shape->num_vertices <= POLY_CYLINDER_NEAR_VERTICES;
  if (masked)
    for (int i = 0; i < shape->num_vertices; i++)
      near[i] = poly_cylinder_may_reach(toward, shape->vertices + 3 * i, above, below);

  poly_cylinder_edge_memo memo;
  poly_cylinder_edge_memo_clear(&memo);
  poly_cylinder_sums sums = {0.0, {0.0, 0.0, 0.0}, 0.0, {0.0, 0.0, 0.0}};
  double nearest2 = INFINITY;
  for (int t = 0; t < shape->num_triangles; t++) {
    const int *tri = shape->triangles + 3 * t;
    if (masked && !(near[tri[0]] | near[tri[1]] | near[tri[2]])) continue;
    if (cull && !masked && !poly_cylinder_may_reach(toward, shape->vertices + 3 * tri[0], above, below) &&
        !poly_cylinder_may_reach(toward, shape->vertices + 3 * tri[1], above, below) &&
        !poly_cylinder_may_reach(toward, shape->vertices + 3 * tri[2], above, below))
      continue;
    double p[3][3];
    for (int c = 0; c < 3; c++) {
      double world[3];
      poly_matrix_apply(rotation, shape->vertices + 3 * tri[c], world);
      for (int k = 0; k < 3; k++) p[c][k] = world[k] + offset[k];
    }
    double distance2 = poly_cylinder_triangle((const double (*)[3])p, tri, &memo, &g, drum, fast, &sums);
    nearest2 = distance2 < nearest2 ? distance2 : nearest2;
  }
  if (!(sums.volume > 0.0)) return;

  /* The depth: the deepest vertex's radial distance into the drum's solid, or for the pillar R minus the
   * distance of the particle's projection from the axis. */
  double deepest = 0.0;
  int inside_vertices = 0;
  for (int i = 0; i < shape->num_vertices; i++) {
    const double *v = shape->vertices + 3 * i;
    if (cull && !(masked ? near[i] : poly_cylinder_may_reach(toward, v, above, below))) continue;
    double world[3];
    poly_matrix_apply(rotation, v, world);
    double x = world[0] + offset[0], y = world[1] + offset[1], r = sqrt(x * x + y * y);
    double into = drum ? r - radius : radius - r;
    inside_vertices += into > 0.0;
    deepest = into > deepest ? into : deepest;
  }
  double nearest = sqrt(nearest2);
  if (!drum) deepest = nearest < radius ? radius - nearest : 0.0;

  const double *area_vector = sums.area_vector;
  double horizontal = sqrt(area_vector[0] * area_vector[0] + area_vector[1] * area_vector[1]);
  if (horizontal > 0.0) {
    result->normal[0] = area_vector[0] / horizontal;
    result->normal[1] = area_vector[1] / horizontal;
  }
  for (int k = 0; k < 3; k++) result->centroid[k] = sums.moment[k] / sums.volume + position[k] - offset[k];
  result->volume = sums.volume;
  result->depth = deepest;
  result->area = sums.area;
  result->projected_area = horizontal;
  result->num_nodes = inside_vertices;
}

/* shape: double-precision view (body frame). rotation: body to world (row major), position: centre of mass.
 * axis: (CX, CY); facets: of the polygon standing in for the circle (poly_cylinder_facets). On return result
 * has volume, centroid, normal (from the particle into the wall, horizontal), depth, area and projected_area
 * (of the particle's surface inside the wall), world frame; all zero without overlap. */
POLY_INLINE void poly_cylinder_overlap(const poly_shape_view_d *shape, const double rotation[9],
                                       const double position[3], const double axis[2], double radius, int facets,
                                       poly_overlap_result *result)
{
  poly_cylinder_overlap_with(shape, rotation, position, axis, radius, facets, 1, result);
}

/* The straightforward computation (poly_cylinder_overlap_with, fast = 0), for the tests. */
POLY_INLINE void poly_cylinder_overlap_reference(const poly_shape_view_d *shape, const double rotation[9],
                                                 const double position[3], const double axis[2], double radius,
                                                 int facets, poly_overlap_result *result)
{
  poly_cylinder_overlap_with(shape, rotation, position, axis, radius, facets, 0, result);
}

#endif
