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
 * particle's own surface inside the solid only. Each triangle is clipped to the three half-planes of each
 * sector that its part in the solid spans (a convex polygon, Sutherland-Hodgman, no division by the
 * triangle's tilt) and integrated exactly (linear and quadratic integrands over triangles); a vertical
 * triangle adds nothing. Triangles wholly in the solid, and runs of sectors in which a triangle is, are one
 * piece each, so only triangles crossing the circle are cut sector by sector. The contact normal is the
 * direction of the summed area vectors of the particle's surface inside the solid (as for mesh walls; it
 * is minus the cap's, horizontal), the depth the deepest point's radial distance into the exact cylinder. */
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

/* Distance in the xy plane from the axis (the origin) to the projection of triangle p. */
POLY_INLINE double poly_cylinder_axis_distance(const double (*p)[3])
{
  double orientation[3], best = -1.0;
  for (int c = 0; c < 3; c++) {
    const double *a = p[c], *b = p[(c + 1) % 3];
    orientation[c] = a[0] * b[1] - a[1] * b[0];   /* side of the origin relative to edge a->b */
    double ex = b[0] - a[0], ey = b[1] - a[1], length2 = ex * ex + ey * ey;
    double t = length2 > 0.0 ? -(a[0] * ex + a[1] * ey) / length2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double dx = a[0] + t * ex, dy = a[1] + t * ey, distance = sqrt(dx * dx + dy * dy);
    if (best < 0.0 || distance < best) best = distance;
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

/* Adds a planar polygon of the particle's surface (in its own order) to the sums. */
POLY_INLINE void poly_cylinder_add_polygon(const double (*polygon)[3], int corners, poly_cylinder_sums *sums)
{
  for (int m = 1; m + 1 < corners; m++) {
    const double *a = polygon[0], *b = polygon[m], *c = polygon[m + 1];
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

/* shape: double-precision view (body frame). rotation: body to world (row major), position: centre of mass.
 * axis: (CX, CY); facets: of the polygon standing in for the circle (poly_cylinder_facets). On return result
 * has volume, centroid, normal (from the particle into the wall, horizontal), depth, area and projected_area
 * (of the particle's surface inside the wall), world frame; all zero without overlap. */
POLY_INLINE void poly_cylinder_overlap(const poly_shape_view_d *shape, const double rotation[9],
                                       const double position[3], const double axis[2], double radius, int facets,
                                       poly_overlap_result *result)
{
  const double two_pi = 2.0 * 3.14159265358979323846;
  result->volume = result->depth = result->area = result->projected_area = 0.0;
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
  const double step = two_pi / facets, h = poly_cylinder_facet_distance(radius, facets);
  const double corner_radius = h / cos(0.5 * step), side = drum ? 1.0 : -1.0;

  poly_cylinder_sums sums = {0.0, {0.0, 0.0, 0.0}, 0.0, {0.0, 0.0, 0.0}};
  double deepest = 0.0, nearest = -1.0;
  for (int t = 0; t < shape->num_triangles; t++) {
    const int *tri = shape->triangles + 3 * t;
    double p[3][3], r2[3];
    for (int c = 0; c < 3; c++) {
      double world[3];
      poly_matrix_apply(rotation, shape->vertices + 3 * tri[c], world);
      for (int k = 0; k < 3; k++) p[c][k] = world[k] + offset[k];
      r2[c] = p[c][0] * p[c][0] + p[c][1] * p[c][1];
    }
    const double (*corners)[3] = (const double (*)[3])p;
    /* Triangles wholly off the solid of the polygon: inside its inscribed circle (the drum, convex), or
     * farther from the axis than its corners (the pillar). */
    if (drum && r2[0] < h * h && r2[1] < h * h && r2[2] < h * h) continue;
    double distance = poly_cylinder_axis_distance(corners);
    if (!drum) {
      if (nearest < 0.0 || distance < nearest) nearest = distance;
      if (distance >= corner_radius) continue;
    }
    /* Triangles wholly in the polygon's solid: beyond its corner circle (the drum), or inside its inscribed
     * circle (the pillar). */
    if (drum ? distance >= corner_radius : r2[0] <= h * h && r2[1] <= h * h && r2[2] <= h * h) {
      poly_cylinder_add_polygon(corners, 3, &sums);
      continue;
    }
    if (!(distance > 0.0)) {   /* the projection surrounds or touches the axis: every sector */
      poly_cylinder_sector_pieces(corners, 0, facets - 1, facets, h, side, &sums);
      continue;
    }
    /* Only the sectors the triangle's parts in the solid span: those beyond the inscribed circle (drum), or
     * within the corner circle (pillar). Where the triangle is wholly in the solid (its parts within the
     * corner circle, or beyond the inscribed one, span other sectors) whole blocks of sectors are one piece. */
    double ranges[3][2];
    int spans[3][2], partial[3][2];
    int span_count = poly_cylinder_triangle_ranges(corners, drum ? h : corner_radius, drum, ranges);
    span_count = poly_cylinder_sector_intervals(ranges, span_count, step, spans);
    int partial_count = poly_cylinder_triangle_ranges(corners, drum ? corner_radius : h, !drum, ranges);
    partial_count = poly_cylinder_sector_intervals(ranges, partial_count, step, partial);
    for (int r = 0; r < span_count; r++) {
      int block = INT_MIN;   /* first sector of the open block */
      for (int s = spans[r][0]; s <= spans[r][1]; s++) {
        int whole = 1;
        for (int q = 0; q < partial_count; q++) whole = whole && !(s >= partial[q][0] && s <= partial[q][1]);
        if (whole && block == INT_MIN) block = s;
        if (block != INT_MIN && (!whole || s == spans[r][1] || s - block + 1 >= facets / 8)) {
          int last = whole ? s : s - 1;
          if (last >= block) poly_cylinder_block_piece(corners, block, last, facets, &sums);
          block = INT_MIN;
        }
        if (!whole) poly_cylinder_sector_pieces(corners, s, s, facets, h, side, &sums);
      }
    }
  }
  double volume = sums.volume, *moment = sums.moment, *area_vector = sums.area_vector, area = sums.area;
  if (!(volume > 0.0)) return;

  int inside_vertices = 0;
  for (int i = 0; i < shape->num_vertices; i++) {
    double world[3];
    poly_matrix_apply(rotation, shape->vertices + 3 * i, world);
    double x = world[0] + offset[0], y = world[1] + offset[1], r = sqrt(x * x + y * y);
    double into = drum ? r - radius : radius - r;
    if (into > 0.0) {
      inside_vertices++;
      if (drum && into > deepest) deepest = into;
    }
  }
  if (!drum) deepest = nearest >= 0.0 && nearest < radius ? radius - nearest : 0.0;

  double horizontal = sqrt(area_vector[0] * area_vector[0] + area_vector[1] * area_vector[1]);
  if (horizontal > 0.0) {
    result->normal[0] = area_vector[0] / horizontal;
    result->normal[1] = area_vector[1] / horizontal;
  }
  for (int k = 0; k < 3; k++) result->centroid[k] = moment[k] / volume + position[k] - offset[k];
  result->volume = volume;
  result->depth = deepest;
  result->area = area;
  result->projected_area = horizontal;
  result->num_nodes = inside_vertices;
}

#endif
